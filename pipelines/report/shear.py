"""The shear BEM's part of the report (stage ``bem_shear``): its markdown and HTML section, the
BEM-vs-model table and its two figures, a BEM version of Fig 4 (F_x against delta_T) and of
Fig 13 (A_r/A_n against F_x), each beside the model's curves.

Everything here reads the stored results (:class:`~asperity.pipelines.stages.bem_shear.
BemShearComparison` and the friction stage's curves), so ``asperity report`` redraws it from
``results.h5``; each figure's data is written beside it as CSV, and is in ``results.h5``
(groups ``bem_shear`` and ``friction``). Nothing is shown when the stage did not run.
"""

from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING

import numpy as np
from matplotlib import colormaps

from asperity.pipelines.report.figure_output import FigureTable
from asperity.pipelines.report.numbers import format_number, format_quantity, plain_text
from asperity.pipelines.stages import stage_number
from asperity.pipelines.stages.bem_shear import BemShearComparison
from asperity.plotting import display_unit, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from asperity.pipelines.report._run import Run

__all__ = [
    "SHEAR_CAPTIONS",
    "SHEAR_FIGURES",
    "comparison_line",
    "draw_bem_shear_area",
    "draw_bem_shear_force",
    "model_judgement",
    "shear_html",
    "shear_section",
    "shear_key_numbers",
    "shear_table",
]


def _shear(result: Run) -> BemShearComparison | None:
    return getattr(result, "bem_shear", None)


def _pm(value: float, error: float, digits: int = 4) -> str:
    """A BEM value +- its grid error, with the digits the error supports ("not reached" for
    a NaN value; the value alone to ``digits`` significant digits where the error is unknown)."""
    if not math.isfinite(value):
        return "not reached"
    return format_number(value, error if math.isfinite(error) else None, digits=digits)


def _bem_invalid(verdict: object) -> bool:
    """The verdict's invalid reasons reach the BEM's own numbers too: a shear BEM that did
    not converge, or a full-contact regime in which a loading-branch BEM does not apply."""
    codes = getattr(verdict, "codes", []) or []
    pairs = zip(codes, getattr(verdict, "severities", []) or [], strict=True)
    return any(
        severity == "invalid" and (code.startswith("bem") or code == "adhesion_full_contact")
        for code, severity in pairs
    )


def shear_table(
    shear: BemShearComparison, verdict: object = None
) -> tuple[list[str], list[list[str]]]:
    """The BEM-vs-model table: per load, static friction, sliding friction and area drop of
    the BEM (grid used, +- its grid error) and of the model, with the junctions still
    sticking at the end of the BEM's path. With an invalid ``verdict`` the model's cells read
    ``invalid: ...`` (:func:`~asperity.pipelines.stages.verdict.mark`), and the BEM's too when
    an invalid reason concerns the BEM (:func:`_bem_invalid`)."""
    from asperity.pipelines.stages.verdict import mark

    def bem(cell: str) -> str:
        return mark(cell, verdict) if _bem_invalid(verdict) else cell

    header = [
        "F_z (N)",
        "F_s BEM (N)",
        "F_s model (N)",
        "F_d BEM (N)",
        "F_d model (N)",
        "A_r(peak)/A_r(0) BEM",
        "A_r(peak)/A_r(0) model",
        "stuck at end",
    ]
    rows = []
    for i, row in enumerate(shear.table()):
        rows.append(
            [
                f"{row['normal_load']:.4g}",
                bem(_pm(row["bem_static_friction"], row["bem_static_friction_error"])),
                mark(f"{row['model_static_friction']:.4g}", verdict),
                bem(_pm(row["bem_sliding_friction"], row["bem_sliding_friction_error"])),
                mark(f"{row['model_sliding_friction']:.4g}", verdict),
                bem(_pm(row["bem_area_drop"], row["bem_area_drop_error"], 3)),
                mark(f"{row['model_area_drop']:.3g}", verdict),
                str(int(shear.stuck_junctions[0, i])),
            ]
        )
    return header, rows


def model_judgement(shear: BemShearComparison, model_area: np.ndarray) -> str:
    """What the comparison says about the model, in one paragraph of numbers: the model over
    the BEM (grid used) for F_s, its delta_T, F_d and A_r(F_x = 0) (``model_area``, m^2 per
    load sheared), and the area drops side by side (ranges over the loads)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        static = shear.model_static_friction / shear.static_friction[0]
        sliding = shear.model_sliding_friction / shear.sliding_friction[0]
        shift = shear.model_static_displacement / shear.static_displacement[0]
        area = model_area / shear.real_area[0, :, 0]
    drop_bem, drop_model = shear.area_drop[0], shear.model_area_drop
    bem_ratio = shear.static_friction[0] / shear.sliding_friction[0]
    model_ratio = shear.model_static_friction / shear.model_sliding_friction
    return (
        f"Model over BEM: static friction x {_span(static)}, its delta_T x {_span(shift)}, "
        f"sliding friction x {_span(sliding)}, A_r(F_x = 0) x {_span(area)}; F_s/F_d BEM "
        f"{_span(bem_ratio)}, model {_span(model_ratio)}; area drop A_r(peak)/A_r(0) BEM "
        f"{_span(drop_bem)}, model {_span(drop_model)}."
    )


def comparison_line(result: Run, shear: BemShearComparison) -> str:
    """One line: what the shear judgement compares with what, and whether it is like for like
    with the normal BEM reference the model was calibrated on: the same grid (stride) and,
    before shear, the same state (the reference's adhesive solve at F_z), with the numbers
    (A_r(F_x = 0) of the shear BEM over the reference's, per load)."""
    used = f"stride {int(shear.grid_stride[0])} ({shear.grid_pixel_size[0] * 1e6:.3g} µm)"
    preload = getattr(shear, "preload", "pohrt-popov overload-unload")
    head = (
        f"Compared: the shear BEM on {used}, preloaded by {preload}, against the model at the "
        "effective resolution"
    )
    ref = getattr(result, "bem_reference", None)
    if ref is None:
        return f"{head}; no normal BEM reference in this run to match it with."
    law = ref.adhesion or "none"
    gaps = _unlike(ref, shear)
    verdict = "like for like" if not gaps else "not like for like: " + "; ".join(gaps)
    ratio = _start_area_ratio(shear)
    numbers = f" (A_r(F_x = 0) / reference A_r: {ratio[0]})" if ratio else ""
    return (
        f"{head}; the model was calibrated on the normal BEM reference at stride "
        f"{int(ref.stride)} ({ref.dx * 1e6:.3g} µm, adhesion {law}): {verdict}{numbers}."
    )


def _unlike(ref: object, shear: BemShearComparison) -> list[str]:
    """What differs between the shear BEM and the normal reference ``ref`` (empty: like for
    like): the grid, the state before shear, A_r(F_x = 0) beyond 5 %."""
    gaps = []
    if int(ref.stride) != int(shear.grid_stride[0]):
        gaps.append(f"its pixel {shear.grid_pixel_size[0] / ref.dx:.3g}x the reference's")
    preload = getattr(shear, "preload", "pohrt-popov overload-unload")
    if not preload.startswith("the reference's"):
        law = ref.adhesion or "none"
        gaps.append(f"its preload is {preload}, not the reference's adhesive state ({law})")
    ratio = _start_area_ratio(shear)
    if ratio and ratio[1] > 0.05:
        gaps.append(f"A_r(F_x = 0) {ratio[0]} the reference's")
    return gaps


def _start_area_ratio(shear: BemShearComparison) -> tuple[str, float] | None:
    """The shear BEM's A_r(F_x = 0) over the reference's per load (text, "x a-b") and the
    largest |ratio - 1|; None without reference areas."""
    reference = getattr(shear, "reference_area", None)
    if reference is None or not np.any(np.isfinite(reference)):
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(shear.real_area[0, :, 0]) / np.asarray(reference)
    ratio = ratio[np.isfinite(ratio)]
    if not ratio.size:
        return None
    return "x " + _span(ratio, ".3f", 5e-4), float(np.max(np.abs(ratio - 1.0)))


def shear_key_numbers(result: Run) -> list[tuple[str, str]]:
    """The headline rows of the shear BEM (none when the stage did not run): what it was
    compared with (like for like or not, :func:`comparison_line`'s test), the model over the
    BEM for F_s and F_d, and the loads that reached full sliding."""
    shear = _shear(result)
    if shear is None:
        return []
    ratio = _start_area_ratio(shear)
    ref = getattr(result, "bem_reference", None)
    like = "like for like" if ref is not None and not _unlike(ref, shear) else "not like for like"
    grid = f"{shear.grid_pixel_size[0] * 1e6:.3g} µm grid"
    start = f", A_r(F_x = 0) / reference {ratio[0]}" if ratio else ""
    with np.errstate(divide="ignore", invalid="ignore"):
        static = shear.model_static_friction / shear.static_friction[0]
        sliding = shear.model_sliding_friction / shear.sliding_friction[0]
    slid = int(np.sum(shear.stuck_junctions[0] == 0))
    return [
        ("shear BEM, compared", f"{like} ({grid}{start})"),
        (
            "shear BEM, model over BEM",
            f"F_s x {_span(static)}, F_d x {_span(sliding)}; full sliding at {slid} / "
            f"{shear.normal_load.size} loads (report: the table with the BEM's grid error)",
        ),
    ]


def _span(values: np.ndarray, form: str = ".3g", rel_tol: float = 5e-3) -> str:
    """'a' or 'a-b' over the finite values (in ``form``; one value where the ends agree within
    ``rel_tol``), 'n/a' without any."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if not values.size:
        return "n/a"
    low, high = float(values.min()), float(values.max())
    if math.isclose(low, high, rel_tol=rel_tol):
        return format(low, form)
    return f"{format(low, form)}-{format(high, form)}"


def _grid_text(shear: BemShearComparison) -> str:
    grids = ", ".join(
        f"stride {int(s)} ({p * 1e6:.3g} µm)"
        for s, p in zip(shear.grid_stride, shear.grid_pixel_size, strict=True)
    )
    if shear.grid_stride.size > 2:
        check = (
            "the ± is the grid error of the grid used from the three grids (Richardson with "
            "the observed order, bounded, and Roache's grid convergence index: safety 1.25 "
            "where the order is the formal one, else 3; the band holds the extrapolated value "
            "and the spread of the grids)"
        )
    elif shear.grid_stride.size == 2:
        check = (
            "the ± is the grid error from two grids (first order assumed, Roache's safety "
            "factor 3: four times their difference)"
        )
    else:
        check = (
            "no check grid ([bem_shear] grid_check = false): the discretisation error is unknown"
        )
    return f"grids {grids}; {check}"


def _cost_text(shear: BemShearComparison) -> str:
    total = float(np.sum(shear.preload_seconds) + np.sum(shear.curve_seconds))
    return (
        f"{total:.1f} s in all ({np.sum(shear.steps_solved)} steps, "
        f"{int(np.sum(shear.convolutions))} conjugate-gradient iterations; grid used: preloads "
        f"{float(np.sum(shear.preload_seconds[0])):.1f} s, curves "
        f"{float(np.sum(shear.curve_seconds[0])):.1f} s)"
    )


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _intro(shear: BemShearComparison) -> str:
    preload = getattr(shear, "preload", "pohrt-popov")
    return (
        f"The paper's shear experiment solved by the BEM on the map (F_z held, the flat "
        f"displaced along x; preload: {preload}; the mixed-mode edge law G_I + lambda G_II = w "
        f"with lambda = {shear.mode_mixity:.3g} and chi_T = {shear.law}, a junction past its "
        f"instability slides with tau_0 = {format_quantity(shear.shear_strength, 'Pa')}; "
        f"{shear.boundary} boundary), beside the statistical model at the effective resolution. "
        f"Forces scaled to A_n = {format_quantity(shear.nominal_area, 'm', power=2)}."
    )


def shear_section(result: Run) -> list[str]:
    """The report.md section of the shear BEM (empty when the stage did not run)."""
    shear = _shear(result)
    if shear is None:
        return []
    header, rows = shear_table(shear, getattr(result, "verdict", None))
    lines = [
        f"## Shear BEM against the model (stage {stage_number('bem_shear')})",
        "",
        _intro(shear),
        "",
        _md_table(header, rows),
        "",
        f"- {comparison_line(result, shear)}",
        f"- {model_judgement(shear, _model_area(result, shear))}",
        f"- Discretisation: {_grid_text(shear)}.",
        f"- Cost: {_cost_text(shear)}.",
        "- Limits: linear elasticity, quasi-static, the mesh-dependent edge law "
        "(docs/bem_shear.md).",
    ]
    lines += [f"- **Warning:** {w}" for w in shear.warnings]
    lines += [f"- **Not converged:** {m}" for m in shear.messages]
    return [*lines, ""]


def _html_table(header: list[str], rows: list[list[str]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def shear_html(result: Run) -> str:
    """The report.html section of the shear BEM ("" when the stage did not run)."""
    shear = _shear(result)
    if shear is None:
        return ""
    items = [
        model_judgement(shear, _model_area(result, shear)),
        comparison_line(result, shear),
        f"Discretisation: {_grid_text(shear)}.",
        _cost_text(shear),
    ]
    items += [f"Warning: {w}" for w in shear.warnings]
    items += [f"Not converged: {m}" for m in shear.messages]
    listed = "".join(f"<li>{html.escape(plain_text(i))}</li>" for i in items)
    table = _html_table(*shear_table(shear, getattr(result, "verdict", None)))
    return (
        f'<h2 id="bem-shear">Shear BEM against the model (stage {stage_number("bem_shear")})</h2>'
        f"<p>{html.escape(plain_text(_intro(shear)))}</p>{table}<ul>{listed}</ul>"
    )


def _colours(n: int) -> np.ndarray:
    return colormaps["viridis"](np.linspace(0, 0.9, n))


def _model_index(result: Run, load: float) -> int:
    return int(np.argmin(np.abs(np.asarray(result.friction.normal_load) - load)))


def _model_area(result: Run, shear: BemShearComparison) -> np.ndarray:
    """The model's A_r at F_x = 0 (m^2) at each load sheared (the friction stage's curves)."""
    return np.array(
        [result.friction.real_area[_model_index(result, f)][0] for f in shear.normal_load]
    )


def draw_bem_shear_force(result: Run) -> tuple[Figure, FigureTable]:
    """Fig 4 by the BEM: F_x against delta_T per load (grid used solid, check grid thin),
    the model's dashed."""
    shear, fr = _shear(result), result.friction
    table = FigureTable()
    fu = display_unit(np.nanmax(fr.tangential_force), "N")
    du = display_unit(np.nanmax(shear.tangential_displacement), "m")
    fig = new_figure(7, 5)
    ax = fig.subplots()
    x_col, y_col = "tangential displacement delta_T (m)", "tangential force F_x (N)"
    colours = _colours(shear.normal_load.size)
    for j, (f, colour) in enumerate(zip(shear.normal_load, colours, strict=True)):
        path = shear.tangential_displacement[j]
        for g, stride in enumerate(shear.grid_stride):
            fx = shear.tangential_force[g, j]
            style = {"lw": 1.8} if g == 0 else {"lw": 0.8, "alpha": 0.7}
            label = f"BEM $F_z$ = {f:.3g} N" if g == 0 else None
            if g < 2:  # the coarser check grids are in the CSV
                ax.plot(du(path), fu(fx), "-", color=colour, label=label, **style)
            table.add("all", f"BEM stride {int(stride)} F_z = {f:.6g} N", {x_col: path, y_col: fx})
        i = _model_index(result, f)
        ax.plot(du(fr.tangential_displacement[i]), fu(fr.tangential_force[i]), "--", color=colour)
        table.add(
            "all",
            f"model F_z = {f:.6g} N",
            {x_col: fr.tangential_displacement[i], y_col: fr.tangential_force[i]},
        )
    ax.plot([], [], "k--", label="model")
    if shear.grid_stride.size > 1:
        ax.plot([], [], "k-", lw=0.8, alpha=0.7, label=f"BEM stride {int(shear.grid_stride[1])}")
    ax.set_title(grid_title(shear), fontsize=9)
    ax.set_xlim(0, du(_shown_displacement(shear, fr, result)))
    ax.set_xlabel(du.label("tangential displacement $\\delta_T$"))
    ax.set_ylabel(fu.label("tangential force $F_x$"))
    ax.legend(fontsize=7)
    return fig, table


def _shown_displacement(shear: BemShearComparison, fr, result: Run) -> float:
    """The delta_T (m) the force figure spans: the last step any BEM curve solved (a path
    extends past its plan only while junctions stick) and the model's curves shown."""
    solved = np.isfinite(shear.tangential_force).any(axis=0)  # (load, step)
    ends = [
        float(shear.tangential_displacement[j][solved[j]].max())
        for j in range(shear.normal_load.size)
        if solved[j].any()
    ]
    model = [
        float(np.nanmax(fr.tangential_displacement[_model_index(result, f)]))
        for f in shear.normal_load
    ]
    return max(ends + model)


def grid_title(shear: BemShearComparison) -> str:
    """Which grid the BEM curves were solved on, and the check grid beside it."""
    used = display_unit(shear.grid_pixel_size[0], "m")
    text = (
        f"BEM on the {used(shear.grid_pixel_size[0]):.3g} {used.symbol} grid "
        f"(the map at stride {int(shear.grid_stride[0])})"
    )
    if shear.grid_stride.size > 1:
        check = display_unit(shear.grid_pixel_size[-1], "m")
        sizes = ", ".join(f"{check(p):.3g}" for p in shear.grid_pixel_size[1:])
        strides = ", ".join(str(int(s)) for s in shear.grid_stride[1:])
        grids = "grid" if shear.grid_stride.size == 2 else "grids"
        text += f"; check {grids} {sizes} {check.symbol} (stride {strides})"
    return text


def _grid_error_bars(ax, shear: BemShearComparison, j: int, fu, colour) -> bool:
    """Error bars of one load's BEM curve on the grid used: A_r/A_n at F_x = 0 (the normal
    reference's stated uncertainty where the shear starts from its state, else the check
    grid's difference) and the static peak (F_s and the area there, with the stage's grid
    errors). False when the stage has no second grid."""
    if shear.grid_stride.size < 2:
        return False
    a_n = shear.nominal_area
    fx, ar = shear.tangential_force[0, j], shear.real_area[0, j] / a_n
    band = getattr(shear, "reference_area_uncertainty", None)
    if band is not None and np.isfinite(band[j]):
        zero = float(band[j]) / a_n
    else:
        zero = abs(ar[0] - shear.real_area[1, j][0] / a_n)
    ax.errorbar(fu(fx[0]), ar[0], yerr=zero, fmt="none", ecolor=colour, capsize=3, lw=1)
    if not np.isfinite(fx).any():
        return True
    k = int(np.nanargmax(fx))
    peak_error = getattr(shear, "static_friction_error", None)
    drop_error = getattr(shear, "area_drop_error", None)
    xerr = None if peak_error is None else fu(float(peak_error[j]))
    yerr = None if drop_error is None else float(drop_error[j]) * ar[0]
    ax.errorbar(fu(fx[k]), ar[k], xerr=xerr, yerr=yerr, fmt="none", ecolor=colour, capsize=3,
                lw=1)  # fmt: skip
    return True


def draw_bem_shear_area(result: Run) -> tuple[Figure, FigureTable]:
    """Fig 13 by the BEM: A_r/A_n against F_x per load on the grid used (solid, with error
    bars from the check grid at F_x = 0 and at the static peak), the model's dashed, the stick
    part dotted; the check grid's curves are in the CSV."""
    shear, fr = _shear(result), result.friction
    a_n = shear.nominal_area
    table = FigureTable()
    fu = display_unit(np.nanmax(fr.tangential_force), "N")
    fig = new_figure(7, 5)
    ax = fig.subplots()
    x_col, y_col = "tangential load F_x (N)", "A_r/A_n (1)"
    colours = _colours(shear.normal_load.size)
    for j, (f, colour) in enumerate(zip(shear.normal_load, colours, strict=True)):
        for g, stride in enumerate(shear.grid_stride):
            fx, ar = shear.tangential_force[g, j], shear.real_area[g, j] / a_n
            if g == 0:
                ax.plot(fu(fx), ar, "-", color=colour, lw=1.8, label=f"BEM $F_z$ = {f:.3g} N")
            table.add("all", f"BEM stride {int(stride)} F_z = {f:.6g} N", {x_col: fx, y_col: ar})
        bars = _grid_error_bars(ax, shear, j, fu, colour)
        stick = shear.stick_area[0, j] / a_n
        ax.plot(fu(shear.tangential_force[0, j]), stick, ":", color=colour, lw=1)
        table.add(
            "all",
            f"BEM stick area stride {int(shear.grid_stride[0])} F_z = {f:.6g} N",
            {x_col: shear.tangential_force[0, j], y_col: stick},
        )
        reference = getattr(shear, "reference_area", None)
        if reference is not None and np.isfinite(reference[j]):
            ax.plot(0.0, reference[j] / a_n, "x", color=colour, ms=8, mew=1.5)
        i = _model_index(result, f)
        model = fr.real_area[i] / a_n
        ax.plot(fu(fr.tangential_force[i]), model, "--", color=colour)
        table.add("all", f"model F_z = {f:.6g} N", {x_col: fr.tangential_force[i], y_col: model})
    ax.plot([], [], "k--", label="model")
    ax.plot([], [], "k:", lw=1, label="BEM stick (adhesive) part")
    reference = getattr(shear, "reference_area", None)
    if reference is not None and np.isfinite(reference).any():
        ax.plot([], [], "kx", ms=8, mew=1.5, label="normal BEM reference, $F_x$ = 0")
    if bars:
        label = "BEM ± its error: the reference's at $F_x$ = 0, grid error at the static peak"
        ax.errorbar([], [], yerr=[], fmt="none", ecolor="k", capsize=3, lw=1, label=label)
    ax.set_title(grid_title(shear), fontsize=9)
    ax.set_ylim(0, None)
    ax.set_xlabel(fu.label("tangential load $F_x$"))
    ax.set_ylabel("$A_r / A_n$")
    ax.legend(fontsize=7)
    return fig, table


def _present(result: Run) -> bool:
    return _shear(result) is not None


#: The shear BEM's figures: name -> (file stem, drawing function, whether the run has it), the
#: form of :data:`asperity.pipelines.report.figures.FIGURES`.
SHEAR_FIGURES = {
    "bem_shear_force": ("fig4_bem_shear", draw_bem_shear_force, _present),
    "bem_shear_area": ("fig13_bem_shear", draw_bem_shear_area, _present),
}

#: Their captions (the form of :data:`asperity.pipelines.report.text.CAPTIONS`).
SHEAR_CAPTIONS: dict[str, str] = {
    "bem_shear_force": f"Stage {stage_number('bem_shear')}: Fig 4 by the BEM, F_x against "
    "delta_T at each load sheared (solid: grid used; thin: the check grid twice as coarse, "
    "the coarser ones in the CSV; dashed: the statistical model).",
    "bem_shear_area": f"Stage {stage_number('bem_shear')}: Fig 13 by the BEM, A_r/A_n against "
    "F_x (solid: grid used, with its error bars; crosses: the normal BEM reference's A_r/A_n "
    "at the load; dotted: the BEM's sticking adhesive part; dashed: the statistical model).",
}
