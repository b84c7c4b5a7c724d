"""The report of a job that stopped where its verdict was known (the full-contact limit).

When the adhesion regime judged before the BEM made the verdict invalid, the job skipped the
BEM and the model stages (:mod:`asperity.pipelines.stages.early_verdict`): there is no
effective resolution, no lambda and no model friction to show. The key numbers and the per-load
table then hold what the regime does predict, each row saying it is the full-contact limit
(A_r/A_n -> 1, F_d -> tau_0 A_n), never a plain model number.
"""

from __future__ import annotations

import numpy as np

from asperity.pipelines.report._run import Run
from asperity.pipelines.report.numbers import format_number, format_quantity, plain_text, text_unit
from asperity.pipelines.stages.early_verdict import limit_lines

#: The words every full-contact-limit cell carries, so that no one reads it as the model's.
LIMIT = "full-contact limit"


def is_early(result: Run) -> bool:
    """The run stopped where its verdict was known: a verdict with the full-contact limit
    and no statistical model."""
    verdict = getattr(result, "verdict", None)
    return (
        result.statistical_model is None
        and verdict is not None
        and getattr(verdict, "full_contact_real_area", None) is not None
    )


def early_key_numbers(result: Run, pixels: str) -> list[tuple[str, str]]:
    """(quantity, value) rows: the surface (``pixels``: its pixel size in words), the regime's
    numbers and the full-contact limit."""
    verdict, surface = result.verdict, result.surface
    rows = [
        ("surface", f"{surface.nx} x {surface.ny} px, {pixels}"),
        ("adhesion regime", "full contact expected at any load (Persson-Tosatti)"),
    ]
    if verdict.adhesion_energy_ratio is not None:
        ratio = f"{verdict.adhesion_energy_ratio:.3g} (full contact below 1)"
        rows.append(("elastic energy to flatten over adhesion U_el/(A0 w)", ratio))
    if verdict.stickiness is not None:
        rows.append(("Pastewka-Robbins stickiness S_PR", f"{verdict.stickiness:.3g}"))
    rows += [
        (
            f"real area A_r ({LIMIT})",
            f"-> A_n = {format_quantity(verdict.full_contact_real_area, 'm', power=2)}",
        ),
        (
            f"sliding friction F_d ({LIMIT})",
            f"-> tau_0 A_n = {format_quantity(verdict.full_contact_sliding_friction, 'N')} "
            "at every load; static peak not predicted",
        ),
        ("test of the limit", str(verdict.full_contact_test)),
        ("stages not computed", ", ".join(verdict.stages_skipped or []) + " (run.compute_all)"),
    ]
    return [(plain_text(k), plain_text(val)) for k, val in rows]


def early_load_table(result: Run) -> tuple[list[str], list[list[str]]]:
    """Header and rows per load: F_z, and the full-contact limit's A_r/A_n, F_d and
    mu_d = F_d/F_z, each cell marked with :data:`LIMIT`."""
    verdict = result.verdict
    loads = np.atleast_1d(np.asarray(verdict.full_contact_normal_load, dtype=float))
    load_unit = text_unit(loads, "N")
    sliding = float(verdict.full_contact_sliding_friction)
    force = text_unit([sliding], "N")
    header = [
        f"F_z ({load_unit.text})",
        "A_r/A_n",
        f"sliding F_d ({force.text})",
        "mu_d = F_d/F_z",
    ]
    rows = [
        [
            format_number(load_unit(f)),
            f"{LIMIT}: 1",
            f"{LIMIT}: {format_number(force(sliding))}",
            f"{LIMIT}: {format_number(sliding / f)}" if f > 0 else f"{LIMIT}: -",
        ]
        for f in loads
    ]
    return [plain_text(h) for h in header], [[plain_text(c) for c in row] for row in rows]


def early_markdown(result: Run) -> list[str]:
    """The report.md section stating the full-contact limit and what was not computed."""
    lines = limit_lines(result.verdict)
    if not lines:
        return []
    return ["## Full-contact limit", "", *(f"- {plain_text(line)}" for line in lines), ""]
