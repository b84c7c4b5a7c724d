"""The BEM section of report.md (the BEM stage, Appendix B).

The section states the boundary condition and the seam mismatch, the branch each number lies
on, the decimation sequence of the grid check (A_r/A_n per stride: the resolution dependence,
roughness each grid carries, which chooses the grid), the discretisation error of the grid used
(the check load on its Fourier interpolations, same roughness: the error bar) and the adhesion
range's sensitivity; the ``bem_grid`` figure
(:func:`asperity.pipelines.report.figures.bem_grid_figure`) draws both sequences.
"""

from __future__ import annotations

from asperity.bem.reference.grid_refinement import EDGE_MISMATCH_LIMIT
from asperity.pipelines.report._run import Run
from asperity.pipelines.report.numbers import format_number, format_uncertainty
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
            "; the grid used is the finest: its own error is the discretisation error below)."
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
    """Report lines: the resolution dependence (decimation), the discretisation error of the
    grid used (Richardson extrapolation over its Fourier interpolations, Roache's grid
    convergence index) applied to every load, and where the range's sensitivity was solved."""
    lines = []
    message = getattr(bem, "resolution_message", None)
    if message:
        lines.append(f"- Resolution dependence (decimation sequence): {message}.")
    if getattr(bem, "check_extrapolated_fraction", None) is None:
        return lines
    modes = BEM_MODES[: len(bem.check_extrapolated_fraction)]
    parts = [
        f"{m}: {format_number(f0, u)} (p = {p:.3g}, safety factor {fs:g}); grid used "
        f"{format_uncertainty(rel, percent=True)}"
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
    refined = getattr(bem, "refinement_message", None)
    seconds = getattr(bem, "refinement_seconds", None)
    cost = f", {seconds:.1f} s" if seconds is not None else ""
    source = (
        f"{refined}{cost}; Richardson extrapolation to zero pixel size, grid convergence index"
        if refined
        else "Richardson extrapolation of the check load's A_r/A_n over strides "
        f"{', '.join(str(int(s)) for s in bem.check_stride)}, grid convergence index"
    )
    lines.append(
        f"- Discretisation error, the BEM's error bar ({source}): " + "; ".join(parts) + ". "
        "The grid used's relative uncertainty (|f - f_0| + u) / f, measured at the check load "
        f"({bem.check_load:.4g} N), is applied to every load of the same grid (the A_r/A_n ± u "
        "of the load table), with the adhesion range's part in quadrature for the adhesive one."
    )
    if refined:
        header = ["factor", "pixel (um)", *(f"A_r/A_n {m}" for m in modes)]
        rows = [
            [f"x{int(k)}", f"{h * 1e6:.4g}", *(f"{f:.5g}" for f in row)]
            for k, h, row in zip(
                bem.refinement_factor,
                bem.refinement_pixel_size,
                bem.refinement_contact_fraction,
                strict=True,
            )
        ]
        lines += ["", *_table(header, rows), ""]
    note = getattr(bem, "range_sensitivity_note", None)
    if note and bem.range_sensitivity is not None:
        flag = getattr(bem, "range_sensitivity_resolved", None)
        lines.append(
            "- Adhesion range's sensitivity (A_r/A_n at h_0/2, h_0, 2 h_0: "
            + ", ".join(f"{f:.4g}" for f in bem.range_sensitivity)
            + f"): {note}"
            + ("." if flag else "; **a lower bound** of the range's effect.")
        )
    return lines
