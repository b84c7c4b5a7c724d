"""Every paper equation label cited in the code and docs exists in the paper and in docs/paper.md.

The paper's LaTeX source is read from ``../shared/paper/`` relative to the repository root (the
workspace layout); set ``ASPERITY_PAPER_TEX`` to its path elsewhere.
"""

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAPER_NAME = "xu2022_adhesive_friction_model.tex"
LABEL = re.compile(r"\b(?:E|eq):[A-Za-z][A-Za-z0-9_]*")
SOURCE_DIRS = ("asperity", "topo", "bem", "statmodel", "pipelines", "docs", "benchmarks")


def _paper_tex() -> str:
    path = Path(os.environ.get("ASPERITY_PAPER_TEX", ROOT.parent / "shared" / "paper" / PAPER_NAME))
    if not path.is_file():
        pytest.skip(f"the paper's LaTeX source is not at {path} (set ASPERITY_PAPER_TEX)")
    return path.read_text(encoding="utf-8")


def printed_numbers(tex: str) -> dict[str, str]:
    """Label -> printed equation number: each `equation` and each `align` line without
    \\nonumber is numbered; `\\setcounter{equation}{0}` restarts the count and
    `\\renewcommand{\\theequation}{A.\\arabic{equation}}` sets the appendix prefix."""
    token = re.compile(
        r"\\begin\{(equation|align)\}(.*?)\\end\{\1\}"
        r"|\\setcounter\{equation\}\{0\}"
        r"|\\renewcommand\{\\theequation\}\{([A-Z])\.\\arabic\{equation\}\}",
        re.S,
    )
    counter, prefix, numbers = 0, "", {}
    for match in token.finditer(tex):
        if match.group(0).startswith("\\setcounter"):
            counter = 0
        elif match.group(3):
            prefix = f"{match.group(3)}."
        else:
            body = match.group(2)
            rows = [body] if match.group(1) == "equation" else body.split("\\\\")
            for row in rows:
                if not row.strip() or "\\nonumber" in row or "\\notag" in row:
                    continue
                counter += 1
                for label in re.findall(r"\\label\{([^}]*)\}", row):
                    numbers[label] = f"{prefix}{counter}"
    return numbers


def _cited_labels() -> dict[str, list[str]]:
    cited: dict[str, list[str]] = {}
    files = [ROOT / "README.md"]
    for folder in SOURCE_DIRS:
        files += sorted((ROOT / folder).rglob("*.py")) + sorted((ROOT / folder).rglob("*.md"))
    for path in files:
        if not path.is_file() or path.name == "paper.md":
            continue
        for label in set(LABEL.findall(path.read_text(encoding="utf-8"))):
            cited.setdefault(label, []).append(str(path.relative_to(ROOT)))
    return cited


def _table() -> dict[str, str]:
    text = (ROOT / "docs" / "paper.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `((?:E|eq):[^`]+)` \| \(([^)]+)\) \|", text, re.M)
    return dict(rows)


def test_counting_rule_on_a_known_sample():
    tex = (
        "\\begin{equation}\\label{a}x\\end{equation}"
        "\\begin{align}y \\label{b}\\\\ z \\nonumber \\\\ w \\label{c}\\end{align}"
        "\\begin{equation*}v\\end{equation*}"
        "\\setcounter{equation}{0}\\renewcommand{\\theequation}{B.\\arabic{equation}}"
        "\\begin{equation}\\label{d}u\\end{equation}"
    )
    assert printed_numbers(tex) == {"a": "1", "b": "2", "c": "3", "d": "B.1"}


def test_every_cited_label_is_in_the_paper_and_in_the_table():
    numbers = printed_numbers(_paper_tex())
    cited = _cited_labels()
    assert cited, "no equation label found in the code: the scan is broken"
    missing = {label: files for label, files in cited.items() if label not in numbers}
    assert not missing, f"labels cited but absent from the paper: {missing}"
    table = _table()
    untabled = sorted(set(cited) - set(table))
    assert not untabled, f"labels cited but missing from docs/paper.md's table: {untabled}"
    wrong = {k: (v, numbers.get(k)) for k, v in table.items() if numbers.get(k) != v}
    assert not wrong, f"docs/paper.md numbers that differ from the paper (table, paper): {wrong}"
