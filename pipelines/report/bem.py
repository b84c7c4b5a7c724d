"""The BEM section of report.md (the BEM stage, Appendix B).

The section states the boundary condition and the seam mismatch, the branch each number lies
on, the refinement curve of the grid check (A_r/A_n and its error against the finest grid
solved, per stride) and the error of the grid used; the ``bem_grid`` figure
(:func:`asperity.pipelines.report.figures.bem_grid_figure`) draws the same curve.
"""

from __future__ import annotations

from asperity.bem.grid_refinement import EDGE_MISMATCH_LIMIT
from asperity.pipelines.report._run import Run
from asperity.pipelines.stages.bem import BemReference

#: The BEM modes, in the order of the second axis of its grid-check arrays.
BEM_MODES = ("non-adhesive", "adhesive")


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def refinement_rows(bem: BemReference, pixel: float) -> list[list[str]]:
    """Rows of the refinement table: stride, pixel (um), A_r/A_n per mode, error, cost."""
    rows = []
    for i, s in enumerate(bem.check_stride):
        used = " (used)" if int(s) == int(bem.stride) else ""
        rows.append(
            [
                f"{int(s)}{used}",
                f"{s * pixel * 1e6:.4g}",
                *(f"{f:.5g}" for f in bem.check_contact_fraction[i]),
                f"{bem.check_error[i]:.2%}",
                f"{int(bem.check_iterations[i].sum())}",
                f"{bem.check_seconds[i].sum():.2f}",
            ]
        )
    return rows


def bem_section(result: Run) -> list[str]:
    """Markdown lines of the report's "BEM reference" section ([] without a BEM)."""
    bem = result.bem_reference
    if bem is None:
        return []
    modes = list(BEM_MODES[: bem.check_contact_fraction.shape[1]])
    branches = {m: sorted(set(row)) for m, row in zip(modes, bem.branch, strict=False)}
    lines = [
        "## BEM reference",
        "",
        f"- Boundary: **{bem.boundary}**; seam mismatch {bem.edge_mismatch:.2f} x the rms height "
        f"(a periodic solve is warned about above {EDGE_MISMATCH_LIMIT}).",
        "- Branch of each number: "
        + "; ".join(f"{m}: {', '.join(b)}" for m, b in branches.items())
        + " (adhesive: the loading branch, from the non-adhesive state at the same load).",
        f"- Grid used: {bem.grid_reason}.",
        f"- Error of the grid used against the finest grid solved: {bem.grid_error:.2%} "
        f"(check load {bem.check_load:.4g} N; its solve is the sweep's solve at that load"
        + (
            "; the grid used is the finest, so this says nothing of its own error)."
            if bem.stride <= int(min(bem.check_stride))
            else ")."
        ),
        f"- Cost: {bem.solves} solves, {bem.total_iterations} iterations, "
        f"{bem.total_convolutions} FFT convolutions (grid check included, nothing solved twice).",
    ]
    lines += discretisation_lines(bem)
    lines += [f"- **Warning:** {w}" for w in bem.warnings]
    header = ["stride", "pixel (um)", *(f"A_r/A_n {m}" for m in modes)]
    header += ["error vs finest", "iterations", "seconds"]
    return [*lines, "", *_table(header, refinement_rows(bem, result.surface.dx)), ""]


def discretisation_lines(bem: BemReference) -> list[str]:
    """Report lines: the grid check's A_r/A_n extrapolated to zero pixel size (Richardson,
    Roache's grid convergence index) and the relative uncertainty applied to every load."""
    if getattr(bem, "check_extrapolated_fraction", None) is None:
        return []
    modes = BEM_MODES[: len(bem.check_extrapolated_fraction)]
    parts = [
        f"{m}: {f0:.4g} +- {u:.2g} (p = {p:.3g}, safety factor {fs:g}); grid used +- {rel:.1%}"
        for m, f0, u, p, fs, rel in zip(
            modes,
            bem.check_extrapolated_fraction,
            bem.check_extrapolation_uncertainty,
            bem.extrapolation_order,
            bem.extrapolation_safety_factor,
            bem.discretisation_relative_uncertainty,
            strict=True,
        )
    ]
    return [
        "- Discretisation error (Richardson extrapolation of the check load's A_r/A_n over "
        f"strides {', '.join(str(int(s)) for s in bem.check_stride)}, grid convergence "
        "index): " + "; ".join(parts) + ". The grid used's relative uncertainty "
        "(|f - f_0| + u) / f is applied to every load of the same grid (the A_r/A_n +- u of the "
        "load table)."
    ]
