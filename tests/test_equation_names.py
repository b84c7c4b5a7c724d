"""The paper's labels by name (asperity.equations): every label of the paper is named, with
the number docs/paper.md's table gives it, and text a user reads names each bare label."""

from __future__ import annotations

import re
from pathlib import Path

from asperity.equations import EQUATIONS, equation_name, name_equations

ROOT = Path(__file__).resolve().parents[1]


def test_each_named_label_has_the_number_of_docs_paper_table():
    """docs/paper.md's "Equation numbers" table (label | (number) | what it is) gives each
    label of EQUATIONS the same printed number, and lists no label EQUATIONS lacks."""
    table = (ROOT / "docs" / "paper.md").read_text(encoding="utf-8")
    rows = dict(re.findall(r"^\| `((?:E|eq):[A-Za-z0-9_]+)` \| \(([A-Z]?[\d.]+)\) \|", table, re.M))
    assert rows, "docs/paper.md: no equation-number table found"
    assert set(rows) == set(EQUATIONS)
    assert {label: number for label, (number, _) in EQUATIONS.items()} == rows


def test_bare_labels_are_named_once_and_named_ones_are_left():
    text = "laws (E:JKR_indent, E:PC_indent) hold; area (Eq. 16, E:Ar_Greenwood); E:unknown_x"
    named = name_equations(text)
    assert "JKR indentation (Eq. 1, E:JKR_indent)" in named
    assert "PC indentation under shear (Eq. 6, E:PC_indent)" in named
    assert "area (Eq. 16, E:Ar_Greenwood);" in named and "E:unknown_x" in named
    assert name_equations(named) == named  # named once: a second pass changes nothing
    assert (
        equation_name("E:NewFormulation_Fy")
        == "normal force under shear (Eq. 17, E:NewFormulation_Fy)"
    )
