"""The BEM section of report.md and the ``bem_grid.png`` figure (the BEM stage, Appendix B).

The section states the boundary condition and the seam mismatch, the branch each number lies
on, the refinement curve of the grid check (A_r/A_n and its error against the finest grid
solved, per stride) and the error of the grid used; the figure draws the same curve.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

from asperity.pipelines.report._run import Run
from asperity.pipelines.report.verdict_marks import separate_bem_markers
from asperity.pipelines.stages._bem_grid import EDGE_MISMATCH_LIMIT
from asperity.pipelines.stages.bem import BemReference
from asperity.plotting import display_unit, new_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes

_MODES = ("non-adhesive", "adhesive")


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
    modes = list(_MODES[: bem.check_contact_fraction.shape[1]])
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
    modes = _MODES[: len(bem.check_extrapolated_fraction)]
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


def _draw_extrapolation(ax: Axes, bem: BemReference) -> None:
    """The extrapolated A_r/A_n at zero pixel size with its band, per mode."""
    if getattr(bem, "check_extrapolated_fraction", None) is None:
        return
    for k, (f0, u) in enumerate(
        zip(bem.check_extrapolated_fraction, bem.check_extrapolation_uncertainty, strict=True)
    ):
        if np.isfinite(f0) and np.isfinite(u):
            label = "extrapolated to 0 (GCI band)" if k == 0 else None
            ax.errorbar([0.0], [f0], yerr=[u], fmt="D", color=f"C{k}", capsize=4, label=label)


def bem_grid_figure(result: Run) -> Figure:
    """The refinement curve (A_r/A_n and error against the finest grid per pixel size) and the
    contact mask at the largest load; axis units chosen from the data (um, mm, ...)."""
    bem = result.bem_reference
    fig = new_figure(14, 4.4)
    ax1, ax3, ax2 = fig.subplots(1, 3)
    pixel_m = np.asarray(bem.check_stride) * result.surface.dx
    pu = display_unit(pixel_m, "m")
    pixel, used = pu(pixel_m), pu(bem.stride * result.surface.dx)
    for k in range(bem.check_contact_fraction.shape[1]):
        ax1.plot(pixel, bem.check_contact_fraction[:, k], "o-", label=_MODES[k])
    _draw_extrapolation(ax1, bem)
    ax1.axvline(used, color="k", ls="--", label="used")
    separate_bem_markers(ax1, ("non-adhesive", "adhesive"))
    ax1.set_xlabel(pu.label("BEM pixel size"))
    ax1.set_ylabel(f"$A_r/A_n$ at $F_z$ = {bem.check_load:.3g} N")
    ax1.set_title(f"grid refinement ({bem.boundary} boundary)")
    ax1.legend(fontsize=8)
    _draw_grid_error(ax3, bem, pixel, used, pu.symbol)
    mask = bem.contact_mask
    lengths = (mask.shape[0] * bem.dx, mask.shape[1] * bem.dy)
    xu = display_unit(lengths, "m")
    ax2.imshow(mask.T, origin="lower", cmap="gray_r", extent=(0, xu(lengths[0]), 0, xu(lengths[1])))
    ax2.set_xlabel(xu.label("x"))
    ax2.set_ylabel(xu.label("y"))
    ax2.set_title(f"contact at $F_z$ = {bem.normal_load.max():.3g} N")
    return fig


def _draw_grid_error(
    ax: Axes, bem: BemReference, pixel: np.ndarray, used: float, symbol: str
) -> None:
    """The error of each coarser grid against the finest solved, in %, on log axes."""
    coarse = bem.check_error > 0
    ax.loglog(pixel[coarse], bem.check_error[coarse] * 100, "o-", label="larger of the modes")
    if bem.area_tolerance is not None:  # stored with the stage: redrawn without the config
        ax.axhline(bem.area_tolerance * 100, color="gray", ls=":", label="area_tolerance")
    ax.axvline(used, color="k", ls="--", label="used")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(NullFormatter())
    ax.legend(fontsize=8)
    ax.set_xlabel(f"BEM pixel size ({symbol})")
    ax.set_ylabel("$|A_r - A_r^{finest}| / A_r^{finest}$ (%)")
    finest = float(pixel.min())
    if used <= finest:
        ax.set_title(f"error against {finest:.3g} {symbol}; the grid used is the finest")
    else:
        ax.set_title(f"error against {finest:.3g} {symbol}; grid used: {bem.grid_error:.2%}")
