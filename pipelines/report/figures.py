"""Every figure of the report (PNG, SVG and/or PDF, each with its data as CSV), drawn on
:class:`matplotlib.figure.Figure` objects (never pyplot state); the text is in
:mod:`~asperity.pipelines.report.text`, the shared styling in :mod:`asperity.plotting`.

The data behind every figure is in ``results.h5`` (same names as the stage records) and, as
plotted, in ``<figure>.csv`` beside it (:mod:`pipelines.report.figure_output`: one tidy table per
figure, SI values, units in the column headers). Units on the axes are SI-prefixed from the
data (:func:`asperity.plotting.display_unit`); an axis whose data span a decade or more is
logarithmic. Formats and dpi come from ``[report]`` (``formats = ["png", "svg", "pdf"]``,
``dpi = 150``) or from ``asperity report OUT_DIR --formats ... --dpi ...``.

Figures written in the output directory (stem; one file per format):

* ``surface`` - the read-and-level stage: the levelled height map; colour limits at the 0.5th
  and 99.5th percentiles of the heights (stated on the colour bar), so one spike does not set
  the scale.
* ``fig12_resolution`` - the resolution-scan to statistical-model stages: R, eta, sigma_s against
  resolution with the paper's fits (Fig 12a-c; the effective resolution and the strides left out of
  the fits marked) and A_r/A_n against F_z from the BEM, the statistical model, Persson's theory and
  the measurement (Fig 12d).
* ``fig12d_misfit`` - the statistical-model stage: misfit of the statistical model against
  resolution.
* ``bem_grid`` - the BEM stage: the grid refinement check and the contact mask.
* ``lambda_fit`` - the lambda stage (when measured curves are given): misfit against lambda.
* ``lambda_residuals`` - the lambda stage: measured minus fitted A_r against F_x, one panel per
  load.
* ``fig4_shear`` - the friction stage: F_z, contact counts, A_r and F_x against delta_T with their
  stick and slip parts, at the heaviest load (Fig 4).
* ``fig13_area_vs_force`` - the friction stage: A_r/A_n against F_x at every load, the measured
  curves and the constant-shear-strength line F_x = tau0 A_r (Fig 13).
* ``friction_vs_load`` - the friction stage: static and sliding friction against F_z.
* ``psd`` - the PSD stage: the radially averaged PSD, its roll-off and power-law (Hurst) fit, the
  map's and the effective resolution's Nyquist wavenumbers (the paper's Section 5 argument).
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace
from typing import TYPE_CHECKING, TypedDict

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator
from numpy.typing import ArrayLike

from asperity.pipelines.report import verdict_marks
from asperity.pipelines.report._run import Run, persson_fraction
from asperity.pipelines.report.bem import BEM_MODES
from asperity.pipelines.report.figure_output import FigureOptions, FigureTable, publish
from asperity.pipelines.report.friction_curves import FRICTION_TEST_FIGURES
from asperity.pipelines.report.numbers import format_number
from asperity.pipelines.report.profile import (
    scan_label,
    surface_title,
)
from asperity.pipelines.report.shear import SHEAR_FIGURES
from asperity.pipelines.report.uncertainty import (
    bem_error_bars,
    friction_error_bars,
)
from asperity.pipelines.report.verdict_marks import separate_bem_markers
from asperity.pipelines.stages.bem import BemReference
from asperity.pipelines.stages.friction import FrictionPrediction, ModeMixityChoice
from asperity.pipelines.stages.statistical_model import ResolutionChoice
from asperity.pipelines.stages.surface import ScanResult
from asperity.plotting import (
    DisplayUnit,
    auto_log_scale,
    display_unit,
    legend_below,
    log_axis,
    new_figure,
    spans_decades,
)
from asperity.statmodel.figures import draw_shear_curve

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: Percentiles of the heights that bound the colour scale of the surface figure.
COLOUR_PERCENTILES = (0.5, 99.5)


#: Largest number of pixels per side drawn (and written to surface.csv).
SURFACE_DRAWN_PIXELS = 400


class FitLine(TypedDict, total=False):
    """A fit drawn on a panel of Fig 12a-c: values (None: nothing to draw), abscissae (m),
    legend."""

    fit: np.ndarray | None
    fit_x: np.ndarray
    fit_label: str


class ScanPanel(FitLine, total=False):
    """One panel of Fig 12a-c: title, quantity, CSV column, values and their display unit,
    the fit and whether the axes are logarithmic."""

    title: str
    quantity: str
    column: str
    values: np.ndarray
    unit: DisplayUnit
    log: bool


def figure_options(result: Run, options: FigureOptions | None = None) -> FigureOptions:
    """``options``, else the job's ``[report]`` section, else PNG at 150 dpi."""
    if options is not None:
        return options
    report = getattr(getattr(result, "config", None), "report", None)
    if report is None:
        return FigureOptions()
    return FigureOptions(tuple(report.formats), int(report.dpi))


def draw_surface(result: Run) -> tuple[Figure, FigureTable]:
    """The read-and-level stage: the levelled height map, robust colour limits (percentiles,
    stated)."""
    s = result.surface
    step = max(1, -(-max(s.nx, s.ny) // SURFACE_DRAWN_PIXELS))
    h = np.asarray(s.heights)[::step, ::step]
    low, high = np.nanpercentile(h, COLOUR_PERCENTILES)
    hu = display_unit([low, high], "m")
    xu = display_unit([s.lx, s.ly], "m")
    tall = float(s.ly / s.lx)  # the map's aspect (height / width)
    to_scale = 1 / SURFACE_MAX_ASPECT <= tall <= SURFACE_MAX_ASPECT
    box = surface_axes_size(tall if to_scale else 1.0)
    fig = new_figure(box[0] + 2.2, box[1] + 1.6)  # room for the colour bar, labels, title
    ax = fig.subplots()
    image = ax.imshow(
        hu(h).T,
        origin="lower",
        cmap="viridis",
        extent=(0, xu(s.lx), 0, xu(s.ly)),
        vmin=hu(low),
        vmax=hu(high),
        aspect="equal" if to_scale else "auto",
    )
    p_low, p_high = COLOUR_PERCENTILES
    fig.colorbar(
        image,
        ax=ax,
        extend="both",
        label=hu.label("height") + f"\ncolour limits: {p_low:g}th-{p_high:g}th percentile",
    )
    ax.set_xlabel(xu.label("x"))
    ax.set_ylabel(xu.label("y"))
    pixel = display_unit([s.dx, s.dy], "m")
    size = f"{pixel(s.dx):.3g}" if s.dx == s.dy else f"{pixel(s.dx):.3g} x {pixel(s.dy):.3g}"
    scale = "" if to_scale else f"\naxes not to scale: the map is {tall:.3g} x as tall as wide"
    ax.set_title(f"{surface_title(s)}, {s.nx} x {s.ny} px of {size} {pixel.symbol}{scale}")
    ix, iy = np.meshgrid(np.arange(h.shape[0]) * step, np.arange(h.shape[1]) * step, indexing="ij")
    table = FigureTable()
    table.add(
        "map",
        f"heights, every {step} px" if step > 1 else "heights",
        {"x (m)": ix * s.dx, "y (m)": iy * s.dy, "height (m)": h},
    )
    return fig, table


#: A map up to this many times taller than wide (or wider than tall) is drawn to scale; beyond
#: it the axes are stretched (and the title says so), so that the picture is not a sliver.
SURFACE_MAX_ASPECT = 4.0


def surface_axes_size(tall: float, area: float = 16.0) -> tuple[float, float]:
    """(width, height) in inches of the surface figure's image for a map ``tall`` times as
    tall as wide: about ``area`` square inches, each side between 2.5 and 7 inches, so that
    a non-square map fills its figure instead of leaving half of it empty."""
    width = min(7.0, max(2.5, math.sqrt(area / tall)))
    return width, min(7.0, max(2.5, width * tall))


def _min_summits() -> int:
    from asperity.topo.scan import resolution_scan

    return int(inspect.signature(resolution_scan).parameters["min_summits"].default)


def fit_excluded(scan: ScanResult) -> np.ndarray:
    """Strides left out of the paper's fits: too few summits or no finite density."""
    return (np.asarray(scan.n_summits) < _min_summits()) | ~np.isfinite(
        np.asarray(scan.asperity_density, dtype=float)
    )


def _mark_resolution(
    ax: Axes, xu: DisplayUnit, res: ResolutionChoice | None, scan: ScanResult, y: np.ndarray
) -> None:
    """The effective resolution (dashed; the located one, whose statistics the model uses) and
    the strides left out of the fits (grey)."""
    if res is not None:  # None: a run stopped at its early verdict has no effective resolution
        at = xu(res.effective_resolution)
        ax.axvline(at, color="k", ls="--", lw=1, label=f"effective, {at:.3g} {xu.symbol}")
    out = fit_excluded(scan)
    if out.any():
        ax.plot(
            xu(np.asarray(scan.resolution)[out]),
            y[out],
            "x",
            color="0.5",
            label=f"not fitted (< {_min_summits()} summits)",
        )


def _draw_scan_panel(ax: Axes, xu: DisplayUnit, result: Run, spec: ScanPanel) -> None:
    """One of Fig 12a-c: the map's points, the fit, the marks."""
    scan = result.resolution_scan
    yu = spec["unit"]
    values = np.asarray(spec["values"], dtype=float)
    ax.plot(xu(scan.resolution), yu(values), "o", ms=4, label=scan_label(scan))
    if spec.get("fit") is not None:
        ax.plot(xu(spec["fit_x"]), yu(spec["fit"]), "-", label=spec["fit_label"])
    _mark_resolution(ax, xu, result.statistical_model, scan, yu(values))
    if spec.get("log"):
        log_axis(ax, "x", xu(scan.resolution))
        log_axis(ax, "y", yu(values))
    ax.set_xlabel(xu.label("resolution"))
    ax.set_ylabel(yu.label(spec["quantity"]))
    ax.set_title(spec["title"])
    legend_below(ax, fontsize=8)  # under the panel: it hides no point


def _scan_panels(scan: ScanResult) -> list[ScanPanel]:
    res = np.asarray(scan.resolution, dtype=float)
    dense = np.geomspace(res.min(), res.max(), 60)
    eta = np.asarray(scan.asperity_density, dtype=float)
    return [
        {
            "title": "(a)",
            "quantity": "mean summit radius $R$",
            "column": "summit radius R (m)",
            "values": scan.summit_radius,
            "unit": display_unit(scan.summit_radius, "m"),
            **radius_fit_line(scan, dense),
        },
        {
            "title": "(b)",
            "quantity": "asperity density $\\eta$",
            "column": "asperity density eta (1/m^2)",
            "values": eta,
            "unit": display_unit(eta, "m", -2),
            "fit": scan.density_prefactor * dense**scan.density_exponent,
            "fit_x": dense,
            "fit_label": f"power law, exponent {scan.density_exponent:.3g}",
            "log": spans_decades(res) or spans_decades(eta),
        },
        {
            "title": "(c)",
            "quantity": "rms summit height $\\sigma_s$",
            "column": "rms summit height sigma_s (m)",
            "values": scan.summit_height_rms,
            "unit": display_unit(scan.summit_height_rms, "m"),
        },
    ]


def radius_fit_line(scan: ScanResult, resolution: np.ndarray) -> FitLine:
    """Fig 12a's linear fit R = intercept + slope x over ``resolution`` (m), drawn only where
    R > 0 (a radius is positive; the straight line may cross zero inside the scan), with its
    slope dR/dx, a pure number (R and the resolution are both lengths)."""
    fit = scan.radius_intercept + scan.radius_slope * np.asarray(resolution, dtype=float)
    keep = np.isfinite(fit) & (fit > 0)
    label = f"linear fit, slope dR/d(resolution) = {scan.radius_slope:.3g}"
    if not keep.all() and keep.any():
        label += " (drawn where R > 0)"
    if not keep.any():
        return {"fit": None}
    return {"fit": fit[keep], "fit_x": np.asarray(resolution)[keep], "fit_label": label}


def _draw_stride_curves(series: Callable[..., None], res, drawn: bool) -> None:
    """Fig 12d's JKR model curves at the finest and coarsest strides (and at the stride of
    least misfit when no effective band is ``drawn``), through ``series``: each its own colour,
    marker and dash, so that neither hides under the effective curves it may lie on."""
    loads = np.asarray(res.normal_load, dtype=float)
    strides = {0, len(res.stride) - 1} | (set() if drawn else {res.index})
    styles = {0: ("d:", "C9"), len(res.stride) - 1: ("x-.", "C6")}
    for i in sorted(strides):
        if drawn and np.isclose(res.resolution[i], res.effective_resolution, rtol=1e-9):
            continue  # the effective curve (drawn with its band) is this one
        if np.all(np.isfinite(res.real_area[i])):
            ru = display_unit(res.resolution[i], "m")
            name = f"JKR model, {ru(res.resolution[i]):.3g} {ru.symbol}"
            name += " (stride of least misfit)" if i == res.index else ""
            style, color = ("-", "C3") if i == res.index else styles.get(i, (":", "C3"))
            series(name, loads, res.real_area[i] / res.nominal_area, style, color=color, ms=5)


def _draw_area_vs_load(ax: Axes, result: Run, table: FigureTable) -> None:
    """Fig 12d: A_r/A_n against F_z from BEM, the statistical model, Persson, measurement."""
    res, bem = result.statistical_model, result.bem_reference
    a_n = res.nominal_area
    loads = np.asarray(res.normal_load, dtype=float)
    fu = display_unit(loads, "N")
    x_col, y_col = "normal load F_z (N)", "A_r/A_n (1)"
    plotted: list[np.ndarray] = []

    def series(
        name: str,
        f: ArrayLike,
        fraction: ArrayLike,
        style: str,
        u: np.ndarray | None = None,
        **kw: str | float,
    ) -> None:
        fraction = np.asarray(fraction, dtype=float)
        columns = {x_col: f, y_col: fraction}
        if u is None:
            ax.plot(fu(f), fraction, style, label=name, **kw)
        else:
            bars, clipped = nonnegative_bars(fraction, u)
            name += CLIPPED_NOTE if clipped else ""
            ax.errorbar(fu(f), fraction, yerr=bars, fmt=style, label=name, capsize=3, **kw)
            columns["A_r/A_n uncertainty (1)"] = u
            # the bars count in the choice of a log axis (none when a bar reaches 0)
            plotted.append(np.concatenate([fraction - u, fraction + u]))
        table.add("d", name, columns)
        plotted.append(fraction)

    if bem is not None:
        bars = bem_error_bars(bem)
        series("BEM, non-adhesive", bem.normal_load, bem.contact_fraction, "s", bars[0], mfc="none")
        if bem.contact_fraction_adhesive is not None:
            series("BEM, adhesive", bem.normal_load, bem.contact_fraction_adhesive, "s", bars[1])
        non_adhesive_series(series, res)
    drawn = draw_model_band(ax, fu, result, table, (x_col, y_col))
    _draw_stride_curves(series, res, drawn)
    persson = persson_fraction(result)
    if persson is not None:
        series("Persson, non-adhesive", result.psd.normal_load, persson, "-.", color="C4")
    if res.measured is not None:
        series("measured", res.measured.normal_load, res.measured.real_area / a_n, "o", color="k")
    verdict_marks.separate_bem_markers(ax)
    auto_log_scale(ax, loads, np.concatenate(plotted))
    full_contact_line(ax, np.concatenate(plotted))
    ax.set_xlabel(fu.label("normal load $F_z$"))
    ax.set_ylabel("$A_r / A_n$")
    ax.set_title("(d)")
    verdict_limit_lines(ax, "A_r/A_n", verdict_marks.AREA_FRACTION_THRESHOLDS)
    # (d)'s many entries: under the whole figure, in two columns, so none covers a curve
    handles, labels = ax.get_legend_handles_labels()
    ax.get_figure().legend(
        handles, labels, loc="outside lower center", ncols=2, fontsize=8, title="(d)"
    )


#: Appended to a legend entry whose error bars were cut at zero.
CLIPPED_NOTE = " (bars clipped at 0)"


def verdict_limit_lines(ax: Axes, quantity: str, thresholds) -> list[float]:
    """The verdict's limits of ``quantity`` drawn as lines where they fall inside the y-axis
    (:func:`verdict_marks.threshold_lines`); a limit outside it is drawn nowhere, so the axis
    title does not describe it (the limits are in report.md)."""
    title, size = ax.get_title(), ax.title.get_fontsize()
    drawn = verdict_marks.threshold_lines(ax, quantity, thresholds)
    ax.set_title(title, fontsize=size)
    return drawn


def nonnegative_bars(value: ArrayLike, u: ArrayLike) -> tuple[np.ndarray, bool]:
    """Error bars (2, n) for ``value`` +- ``u`` whose lower arm stops at 0 (a force or an area
    is never negative), and whether any arm was cut."""
    value = np.asarray(value, dtype=float)
    u = np.broadcast_to(np.asarray(u, dtype=float), value.shape)
    lower = np.minimum(u, np.maximum(value, 0.0))
    clipped = bool(np.any(np.isfinite(u) & (u > lower)))
    return np.vstack([lower, u]), clipped


def full_contact_line(ax: Axes, fractions: ArrayLike) -> bool:
    """A line at A_r/A_n = 1 (labelled) where the plotted A_r/A_n exceed it: an independent-
    asperity model that does so is outside its assumptions (the area cannot exceed A_n)."""
    values = np.asarray(fractions, dtype=float)
    if not np.any(values[np.isfinite(values)] > 1):
        return False
    ax.axhline(1.0, color="k", lw=1.2, ls=(0, (8, 2)), zorder=1.5,
               label="$A_r = A_n$ (full contact: the model exceeds it)")  # fmt: skip
    return True


def non_adhesive_series(series: Callable[..., None], res: ResolutionChoice) -> None:
    """Fig 12d's like-for-like pairs at the effective resolution: Greenwood-Williamson (w = 0;
    a wide light grey line, open triangles) beside the open markers of the non-adhesive BEM, and
    with a Maugis-Dugdale BEM the Maugis-Dugdale model at its h_0 (dashed, filled triangles, on
    top of the grey: the two differ by a few per cent) beside the filled markers. A run stored
    before these fields: the w = 0 model at the non-adhesive
    pair's least-misfit stride."""
    plain = getattr(res, "effective_real_area_non_adhesive", None)
    if plain is not None:
        ru = display_unit(res.effective_resolution, "m")
        at = f"{ru(res.effective_resolution):.3g} {ru.symbol}"
        name = f"GW model (w=0), {at} (pair of the non-adhesive BEM; wide grey)"
        # wide and light under the MD model's dashes: the two lie within a few per cent
        series(name, res.normal_load, plain / res.nominal_area, "v-", color="0.55", lw=5,
               alpha=0.5, ms=9, mfc="none", zorder=1.8)  # fmt: skip
        if getattr(res, "bem_law", None) == "maugis-dugdale":
            hu = display_unit(res.bem_law_adhesion_range, "m")
            h0 = f"{hu(res.bem_law_adhesion_range):.3g} {hu.symbol}"
            name = f"MD model, h_0 = {h0}, {at} (pair of the adhesive BEM)"
            md = res.effective_real_area_bem_law / res.nominal_area
            series(name, res.normal_load, md, "^--", color="C2", zorder=2.2)
        return
    index = getattr(res, "effective_index_non_adhesive", None)
    if index is None or res.real_area_non_adhesive is None:
        return
    ru = display_unit(res.resolution[index], "m")
    name = f"model w=0 (GW), {ru(res.resolution[index]):.3g} {ru.symbol} (non-adhesive pair)"
    fraction = res.real_area_non_adhesive[index] / res.nominal_area
    series(name, res.normal_load, fraction, "v--", color="0.4", mfc="none")


def draw_resolution(result: Run) -> tuple[Figure, FigureTable]:
    """Fig 12a-d with the data table (SI)."""
    scan = result.resolution_scan
    xu = display_unit(scan.resolution, "m")
    fig = new_figure(11, 11)
    axes = fig.subplots(2, 2)
    table = FigureTable()
    used = (~fit_excluded(scan)).astype(float)
    for ax, spec in zip(axes.flat[:3], _scan_panels(scan), strict=True):
        _draw_scan_panel(ax, xu, result, spec)
        columns = {
            "stride (1)": scan.stride,
            "resolution (m)": scan.resolution,
            spec["column"]: spec["values"],
            "used in fit (1)": used,
        }
        table.add(spec["title"].strip("()"), "map", columns)
        if spec.get("fit") is not None:
            table.add(
                spec["title"].strip("()"),
                "fit",
                {"resolution (m)": spec["fit_x"], spec["column"]: spec["fit"]},
            )
    if result.statistical_model is not None:
        _draw_area_vs_load(axes[1, 1], result, table)
    else:  # the run stopped at its early verdict: no model stage to draw (run.compute_all)
        axes[1, 1].set_axis_off()
        axes[1, 1].text(0.5, 0.5, "model stages not computed\n(run.compute_all)", ha="center")
    return fig, table


def draw_misfit(result: Run) -> tuple[Figure, FigureTable]:
    """The statistical-model stage: the misfit curve that chose the effective resolution."""
    res = result.statistical_model
    xu = display_unit(res.resolution, "m")
    fig = new_figure(6.5, 5.6)
    ax = fig.subplots()
    table = FigureTable()
    law = getattr(res, "bem_law", None)
    partner = {"maugis-dugdale": "MD model", "greenwood-williamson": "GW model"}.get(law, "model")
    curves = [(f"{partner} against BEM", res.misfit_bem, "o-")]
    if res.misfit_measured is not None:
        curves.append(("against measured A_r(F_z)", res.misfit_measured, "s-"))
    for name, misfit, style in curves:
        if np.isfinite(misfit).any():
            ax.plot(xu(res.resolution), misfit, style, label=name)
            table.add("misfit", name, {"resolution (m)": res.resolution, "misfit (1)": misfit})
    at_stride = res.resolution[res.effective_index]
    ax.axvline(
        xu(at_stride),
        color="k",
        ls=(0, (4, 3)),
        lw=1.2,
        zorder=3,  # dashed over the located optimum's wide line: both show where they coincide
        label=f"stride of least misfit {xu(at_stride):.3g} {xu.symbol}",
    )
    draw_resolution_interval(ax, xu, res, table)
    ax.set_xlabel(xu.label("resolution"))
    ax.set_ylabel("rms of ln($A_{model}$ / $A_{reference}$)")
    log_axis(ax, "y", [m for _, m, _ in curves])
    verdict_limit_lines(ax, "misfit", verdict_marks.MISFIT_THRESHOLDS)
    legend_below(ax, fontsize=8, ncols=2)
    return fig, table


def draw_bem_grid(result: Run) -> tuple[Figure, FigureTable]:
    """The BEM stage: the decimation sequence (resolution dependence) and the interpolated
    refinement (discretisation error) of the check load, their movement from the grid used, the
    contact mask."""
    bem = result.bem_reference
    table = FigureTable()
    pixel = np.asarray(bem.check_stride) * result.surface.dx
    refined = _refinement(bem)
    for k, mode in enumerate(BEM_MODES[: bem.check_contact_fraction.shape[1]]):
        table.add(
            "refinement",
            mode,
            {"BEM pixel size (m)": pixel, "A_r/A_n (1)": bem.check_contact_fraction[:, k]},
        )
        if refined is not None:
            table.add(
                "interpolated refinement",
                mode,
                {"BEM pixel size (m)": refined[0], "A_r/A_n (1)": refined[1][:, k]},
            )
    table.add(
        "error",
        "the mode (non-adhesive or adhesive) that moves more",
        {"BEM pixel size (m)": pixel, "error against the finest grid (1)": bem.check_error},
    )
    return bem_grid_figure(result), table


#: The lambda scan's misfit axis per fit source (``[fit] source``).
LAMBDA_FIT_LABELS: dict[str, str] = {
    "area": "rms of ($A_{model}$ - $A_{measured}$) / max $A_{measured}$",
    "friction": "rms of ($F_{model}$ - $F_{measured}$) / max $F_{measured}$",
    "joint": "$\\sqrt{\\chi^2 / m}$, both sources",
}


def draw_lambda_fit(result: Run) -> tuple[Figure, FigureTable]:
    """The lambda stage: the misfit of the coarse lambda scan and the fitted value."""
    fit = result.mode_mixity.fit
    fig = new_figure(6, 4)
    ax = fig.subplots()
    ax.loglog(fit.grid_mode_mixity, fit.grid_residual_rms, "o-", label="coarse scan")
    ax.axvline(
        fit.mode_mixity,
        color="k",
        ls="--",
        label=f"fit {format_number(fit.mode_mixity, fit.mode_mixity_std)}",
    )
    if np.isfinite(fit.mode_mixity_std):  # an unbounded uncertainty has no band to draw
        ax.axvspan(
            max(fit.mode_mixity - fit.mode_mixity_std, 1e-12),
            fit.mode_mixity + fit.mode_mixity_std,
            color="0.85",
        )
    ax.set_xlabel("mode mixity $\\lambda$")
    ax.set_ylabel(LAMBDA_FIT_LABELS[getattr(result.mode_mixity, "fit_source", None) or "area"])
    ax.legend(fontsize=8)
    table = FigureTable()
    table.add(
        "fit",
        "coarse scan",
        {"mode mixity lambda (1)": fit.grid_mode_mixity, "residual rms (1)": fit.grid_residual_rms},
    )
    table.add(
        "fit",
        "fitted",
        {"mode mixity lambda (1)": fit.mode_mixity, "lambda std (1)": fit.mode_mixity_std},
    )
    return fig, table


def draw_lambda_residuals(result: Run) -> tuple[Figure, FigureTable]:
    """The lambda stage: measured minus fitted A_r against F_x, one panel per load (fitted
    points)."""
    lam = result.mode_mixity
    loads = np.unique(lam.fitted_normal_load)
    fig = new_figure(6, 2.2 * len(loads) + 0.6)
    axes = fig.subplots(len(loads), 1, squeeze=False)[:, 0]
    fu = display_unit(lam.fitted_tangential_force, "N")
    table = FigureTable()
    for ax, load in zip(axes, loads, strict=True):
        pick = lam.fitted_normal_load == load
        fx = lam.fitted_tangential_force[pick]
        measured, model = lam.fitted_real_area[pick], lam.fitted_model_area[pick]
        residual = (measured - model) / np.max(measured)
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.plot(fu(fx), 100 * residual, "o-", ms=3)
        ax.set_ylabel("residual (% of max $A_r$)")
        ax.set_title(f"$F_z$ = {load:.4g} N ({lam.fit_mode} fit)", fontsize=9)
        table.add(
            f"F_z = {load:.4g} N",
            "residual",
            {
                "tangential force F_x (N)": fx,
                "measured A_r (m^2)": measured,
                "fitted model A_r (m^2)": model,
                "residual / max measured A_r (1)": residual,
            },
        )
    axes[-1].set_xlabel(fu.label("tangential force $F_x$"))
    return fig, table


def draw_shear(result: Run) -> tuple[Figure, FigureTable]:
    """Fig 4 at the heaviest load, drawn by the one Fig-4 plotter, statmodel.draw_shear_curve."""
    from asperity.pipelines.stages.friction import CURVE_FIELDS

    fr = result.friction
    i = int(np.argmax(fr.normal_load))
    arrays = fr.curve_arrays(i)  # the per-step arrays (SI) at that load
    title = f"$F_z$ = {fr.normal_load[i]:.3g} N, $\\lambda$ = {fr.mode_mixity:.3g}"
    fig = draw_shear_curve(new_figure(10, 7.5), SimpleNamespace(**arrays), title=title)
    table = FigureTable()
    table.add(
        "all",
        f"F_z = {fr.normal_load[i]:.6g} N",
        {f"{name} ({CURVE_FIELDS[name]})": values for name, values in arrays.items()},
    )
    return fig, table


def _model_at_measured(
    lam: ModeMixityChoice, a_n: float, table: FigureTable, x_col: str, y_col: str
) -> None:
    """The fitted model at the measured points (data only: the curves show it)."""
    model_at = getattr(lam, "model_real_area_at_measured", None)
    if model_at is None:
        return
    for f in np.unique(lam.measured_normal_load):
        mask = lam.measured_normal_load == f
        table.add(
            "all",
            f"model at measured points F_z = {f:.6g} N",
            {x_col: lam.measured_tangential_force[mask], y_col: model_at[mask] / a_n},
        )


def draw_area_vs_force(result: Run) -> tuple[Figure, FigureTable]:
    """Fig 13: A_r/A_n against F_x at each load, measured curves, and tau0 A_r."""
    fr = result.friction
    a_n = fr.nominal_area
    fu = display_unit(np.nanmax(fr.tangential_force), "N")
    x_col, y_col = "tangential load F_x (N)", "A_r/A_n (1)"
    fig = new_figure(7, 5)
    ax = fig.subplots()
    table = FigureTable()
    colors = colormaps["viridis"](np.linspace(0, 0.9, len(fr.normal_load)))
    for i, f in enumerate(fr.normal_load):
        fx, ar = fr.tangential_force[i], fr.real_area[i] / a_n
        ax.plot(fu(fx), ar, "--", color=colors[i], label=f"model $F_z$ = {f:.3g} N")
        table.add("all", f"model F_z = {f:.6g} N", {x_col: fx, y_col: ar})
    for curve in result.mode_mixity.curves:
        j = int(np.argmin(np.abs(fr.normal_load - curve.normal_load)))
        ar = curve.real_area / a_n
        ax.plot(fu(curve.tangential_force), ar, "-", color=colors[j], lw=1)
        table.add(
            "all",
            f"measured F_z = {curve.normal_load:.6g} N",
            {x_col: curve.tangential_force, y_col: ar},
        )
    if result.mode_mixity.curves:
        ax.plot([], [], "k-", lw=1, label="measured")
    draw_fig13_error_bars(ax, fu, fr, colors, table)
    _model_at_measured(result.mode_mixity, a_n, table, x_col, y_col)
    line = np.linspace(0, np.nanmax(fr.tangential_force), 50)
    tau_line = line / max(fr.shear_strength, 1e-300) / a_n
    ax.plot(fu(line), tau_line, "k:", lw=1, label="$F_x = \\tau_0 A_r$ (constant shear strength)")
    table.add("all", "F_x = tau0 A_r", {x_col: line, y_col: tau_line})
    ax.set_ylim(0, 1.15 * _fig13_top(fr))
    full_contact_line(ax, np.asarray(fr.real_area) / a_n)
    ax.set_xlabel(fu.label("tangential load $F_x$"))
    ax.set_ylabel("$A_r / A_n$")
    verdict_limit_lines(ax, "A_r/A_n", verdict_marks.AREA_FRACTION_THRESHOLDS)
    legend_below(ax, fontsize=8, ncols=2)  # under the axis: it covers no curve
    return fig, table


def draw_friction_vs_load(result: Run) -> tuple[Figure, FigureTable]:
    """Static and sliding friction against normal load."""
    fr = result.friction
    fu = display_unit(fr.normal_load, "N")
    yu = display_unit([fr.static_friction, fr.sliding_friction], "N")
    fig = new_figure(6.5, 4.8)
    ax = fig.subplots()
    table = FigureTable()
    x_col = "normal load F_z (N)"
    bars = friction_error_bars(fr)
    lower_bound = bool(getattr(fr, "uncertainty_lower_bound", False))
    for name, values, style in (
        ("static (peak)", fr.static_friction, "o-"),
        ("sliding", fr.sliding_friction, "s--"),
    ):
        columns = {x_col: fr.normal_load, "friction force (N)": values}
        u = bars[name]
        if u is None:
            ax.plot(fu(fr.normal_load), yu(values), style, label=name)
        else:
            x = fu(fr.normal_load)
            arms, clipped = nonnegative_bars(values, u)
            label = name + " ± u" + (", a lower bound" if lower_bound else "")
            label += CLIPPED_NOTE if clipped else ""
            if lower_bound:  # open-ended: the true bar is at least this long
                (line,) = ax.plot(x, yu(values), style, label=label)
                _lower_bound_arrows(ax, x, yu(values), np.zeros_like(arms), yu(arms),
                                    line.get_color())  # fmt: skip
            else:
                ax.errorbar(x, yu(values), yerr=yu(arms), fmt=style, capsize=3, label=label)
            columns["friction force uncertainty (N)"] = u
        table.add("all", name, columns)
    auto_log_scale(ax, fr.normal_load, [fr.static_friction, fr.sliding_friction])
    ax.set_xlabel(fu.label("normal load $F_z$"))
    ax.set_ylabel(yu.label("friction force"))
    legend_below(ax, fontsize=8, ncols=2)  # under the axis: it hides no bar
    return fig, table


def nyquist_style(name: str) -> dict[str, str | float | tuple[float, tuple[float, ...]]]:
    """Line style of a Nyquist mark: the map's wide and light grey, the effective resolution's
    thin, red and on top (at stride 1 both coincide and both stay visible); solid or
    dash-dot in x, dashed or dash-dot-dot in y."""
    in_y = "dy" in name
    if name.startswith("effective"):
        return {
            "color": "C3",
            "lw": 1.2,
            "zorder": 3,
            "ls": (0, (6, 2, 1, 2, 1, 2)) if in_y else "-.",
        }
    return {
        "color": "0.6",
        "lw": 3.5,
        "alpha": 0.6,
        "zorder": 2,
        "ls": (0, (3, 1)) if in_y else "-",
    }


def nyquist_marks(result: Run) -> dict[str, float]:
    """Labelled Nyquist wavenumbers (rad/m) of the PSD figure (styles: :func:`nyquist_style`).

    The map's own: pi/dx and, when the pixels are not square, pi/dy. The effective
    resolution x (the scan's pixel size, stride k times sqrt(dx dy)) decimates both axes by
    the same stride, so its Nyquist wavenumbers are pi/(k dx) and pi/(k dy): each within the
    map's own in its direction (one line when the pixels are square).
    """
    surface, x = result.surface, float(result.psd.effective_resolution)
    dx, dy = float(surface.dx), float(surface.dy)
    xu = display_unit(x, "m")
    effective = f"effective resolution {xu(x):.3g} {xu.symbol}"
    if np.isclose(dx, dy, rtol=1e-9, atol=0.0):
        return {"map Nyquist $\\pi/dx$": np.pi / dx, f"{effective}: $\\pi/x$": np.pi / x}
    k = x / np.sqrt(dx * dy)  # the stride (the decimation of both axes)
    return {
        "map Nyquist in x, $\\pi/dx$": np.pi / dx,
        "map Nyquist in y, $\\pi/dy$": np.pi / dy,
        f"{effective}: $\\pi/(k\\,dx)$, k = {k:.3g}": np.pi / (k * dx),
        f"{effective}: $\\pi/(k\\,dy)$": np.pi / (k * dy),
    }


def psd_fit_label(psd: object) -> str:
    """The PSD fit's legend: C ~ q^exponent, and the Hurst exponent only where it is one
    (H = -exponent/2 - 1 inside (0, 1); docs/topo.md)."""
    text = f"power law, $C \\propto q^{{{psd.psd_fit_exponent:.3g}}}$"
    hurst = -float(psd.psd_fit_exponent) / 2 - 1  # the slope's H, whatever its range
    if math.isfinite(hurst) and 0 < hurst < 1:
        return f"{text}, H = {hurst:.3g}"
    return f"{text} (no Hurst exponent: H would be {hurst:.3g}, outside (0, 1))"


def draw_psd(result: Run) -> tuple[Figure, FigureTable]:
    """The PSD stage: the radial PSD with the roll-off, the Hurst fit and the Nyquist
    wavenumbers."""
    psd = result.psd
    q, c = np.asarray(psd.wavenumber), np.asarray(psd.psd)
    qu = display_unit(q, "m", -1)
    cu = display_unit(c, "m", 4)
    fig = new_figure(6.5, 4.6)
    ax = fig.subplots()
    table = FigureTable()
    q_col, c_col = "wavenumber q (rad/m)", "PSD C (m^4)"
    ax.loglog(qu(q), cu(c), ".", ms=3, color="0.4", label="radial average")
    table.add("all", "radial average", {q_col: q, c_col: c})
    q_r = 2 * np.pi / psd.rolloff_wavelength
    wl = display_unit(psd.rolloff_wavelength, "m")
    ax.axvline(
        qu(q_r),
        color="C0",
        ls="--",
        label=f"roll-off, {wl(psd.rolloff_wavelength):.3g} {wl.symbol}",
    )
    if np.isfinite(psd.psd_fit_exponent):
        line = np.geomspace(q_r, psd.nyquist_wavenumber, 30)
        fit = psd.psd_fit_prefactor * line**psd.psd_fit_exponent
        ax.loglog(qu(line), cu(fit), "-", color="C1", label=psd_fit_label(psd))
        table.add("all", "power-law fit", {q_col: line, c_col: fit})
    marks = nyquist_marks(result)
    for name, wavenumber in marks.items():
        ax.axvline(qu(wavenumber), label=name, **nyquist_style(name))
    table.add(
        "all",
        "marks",
        {
            "roll-off wavenumber (rad/m)": q_r,
            "map Nyquist wavenumber (rad/m)": psd.nyquist_wavenumber,
            "effective Nyquist wavenumber (rad/m)": np.pi / psd.effective_resolution,
            "Hurst exponent (1)": psd.hurst_exponent,  # NaN outside (0, 1): not one
            "PSD slope's H = -exponent/2 - 1 (1)": -float(psd.psd_fit_exponent) / 2 - 1,
        },
    )
    for name, wavenumber in marks.items():  # each line drawn, named as in the legend
        plain = name.replace("$", "").replace("\\pi", "pi").replace("\\,", " ")
        table.add("all", f"line: {plain}", {q_col: wavenumber})
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(f"wavenumber $q$ (rad {qu.symbol})")
    ax.set_ylabel(cu.label("PSD $C(q)$"))
    ax.legend(fontsize=7)
    return fig, table


def _refinement(bem: BemReference) -> tuple[np.ndarray, np.ndarray] | None:
    """(pixel sizes m, A_r/A_n per level and mode) of the interpolated refinement, or None."""
    factors = getattr(bem, "refinement_factor", None)
    if factors is None:
        return None
    return np.asarray(bem.refinement_pixel_size), np.asarray(bem.refinement_contact_fraction)


def bem_grid_figure(result: Run) -> Figure:
    """The check load's A_r/A_n against pixel size on the decimated grids (roughness lost with
    the pixels) and on the Fourier-interpolated grid used (same roughness: the discretisation
    error), their movement from the grid used, and the contact mask at the largest load; axis
    units chosen from the data (um, mm, ...)."""
    bem = result.bem_reference
    # 12 inches wide with 9-10 pt text: about 12 px text once the page scales it to 1100 px
    fig = new_figure(12, 5.6)
    ax1, ax3, ax2 = fig.subplots(1, 3, width_ratios=(1.15, 1.15, 1))
    pixel_m = np.asarray(bem.check_stride) * result.surface.dx
    refined = _refinement(bem)
    every = pixel_m if refined is None else np.concatenate([pixel_m, refined[0]])
    pu = display_unit(every, "m")
    pixel, used = pu(pixel_m), pu(bem.stride * result.surface.dx)
    for k in range(bem.check_contact_fraction.shape[1]):
        ax1.plot(pixel, bem.check_contact_fraction[:, k], "o-", color=f"C{k}", label=BEM_MODES[k])
        if refined is not None:
            label = "interpolated, same roughness (^)" if k == 0 else None
            ax1.plot(pu(refined[0]), refined[1][:, k], "^--", color=f"C{k}",
                     mfc="none" if k == 0 else None, label=label)  # fmt: skip
    _draw_extrapolation(ax1, bem)
    ax1.axvline(used, color="k", ls="--", label="used")
    separate_bem_markers(ax1, ("non-adhesive", "adhesive"))
    ax1.set_xlabel(pu.label("BEM pixel size"))
    ax1.set_ylabel(f"$A_r/A_n$ at $F_z$ = {bem.check_load:.3g} N")
    ax1.set_title(
        f"decimated (solid) and interpolated\n(dashed) grids ({bem.boundary})", fontsize=10
    )
    legend_below(ax1, fontsize=8)
    _draw_grid_error(ax3, bem, pixel_m, refined, pu)
    mask = bem.contact_mask
    lengths = (mask.shape[0] * bem.dx, mask.shape[1] * bem.dy)
    xu = display_unit(lengths, "m")
    ax2.imshow(mask.T, origin="lower", cmap="gray_r", extent=(0, xu(lengths[0]), 0, xu(lengths[1])))
    ax2.set_xlabel(xu.label("x"))
    ax2.set_ylabel(xu.label("y"))
    ax2.set_title(f"contact at $F_z$ = {bem.normal_load.max():.3g} N", fontsize=10)
    return fig


def _tick_text(value: float, _position: float | None) -> str:
    """A log-axis tick as a short plain number to 3 significant digits (5, 40, 0.5, 128)."""
    return f"{value:.3g}"


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


def _draw_grid_error(
    ax: Axes,
    bem: BemReference,
    pixel_m: np.ndarray,
    refined: tuple[np.ndarray, np.ndarray] | None,
    pu: DisplayUnit,
) -> None:
    """How far A_r/A_n moves from the grid used (%, the mode that moves more), on log axes: on the
    decimated grids (roughness lost) and on the interpolated ones (discretisation), with the
    error bar applied (the discretisation band of the grid used)."""
    used_m = float(pixel_m[list(np.asarray(bem.check_stride)).index(int(bem.stride))])
    fraction = np.asarray(bem.check_contact_fraction)
    chosen = list(np.asarray(bem.check_stride)).index(int(bem.stride))
    base = fraction[chosen]

    def move(rows: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.nanmax(np.abs(rows - base) / base, axis=1)

    coarse = pixel_m > used_m * (1 + 1e-9)
    if coarse.any():
        ax.loglog(pu(pixel_m[coarse]), move(fraction[coarse]) * 100, "o-",
                  label="decimated: roughness lost")  # fmt: skip
    if refined is not None and len(refined[0]) > 1:
        # the window's own level 1 when windowed: the movement is within the window
        level = np.asarray(refined[1])
        with np.errstate(divide="ignore", invalid="ignore"):
            inner = np.nanmax(np.abs(level[1:] - level[0]) / level[0], axis=1)
        ax.loglog(pu(refined[0][1:]), inner * 100, "^--", label="interpolated: discretisation")
    rel = getattr(bem, "discretisation_relative_uncertainty", None)
    if rel is not None and np.isfinite(rel).any():
        ax.axhline(
            float(np.nanmax(rel)) * 100, color="C3", ls="-.", label="error bar of the grid used"
        )
    if bem.area_tolerance is not None:  # stored with the stage: redrawn without the config
        ax.axhline(bem.area_tolerance * 100, color="gray", ls=":", label="area_tolerance")
    ax.axvline(pu(used_m), color="k", ls="--", label="used")
    ticks = np.concatenate([pixel_m, [] if refined is None else refined[0][1:]])
    ax.set_xticks(np.unique(pu(ticks[np.isfinite(ticks) & (ticks > 0)])))  # every grid named
    ax.xaxis.set_major_formatter(FuncFormatter(_tick_text))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(FuncFormatter(_tick_text))
    ax.yaxis.set_minor_formatter(NullFormatter())
    legend_below(ax, fontsize=8)
    ax.set_xlabel(pu.label("BEM pixel size"))
    ax.set_ylabel("$|A_r - A_r^{used}| / A_r^{used}$ (%)")
    ax.set_title(
        "how far $A_r$ moves from the grid used\n(the mode, adhesive or not, that moves more)",
        fontsize=10,
    )


def draw_resolution_interval(
    ax: Axes, xu: DisplayUnit, res: ResolutionChoice, table: FigureTable
) -> None:
    """The misfit figure: the located optimum, its interval (band) and the refined samples."""
    if getattr(res, "optimum_resolution", None) is None:
        return
    low, high = np.asarray(res.optimum_interval, dtype=float)
    if math.isfinite(low) and math.isfinite(high):
        ax.axvspan(xu(low), xu(high), color="C2", alpha=0.2, label="one-sigma interval")
    shift = getattr(res, "optimum_reference_shift", None)
    if shift is not None:
        own = np.asarray(res.optimum_misfit_interval, dtype=float)
        if np.all(np.isfinite(own)):
            ax.axvspan(xu(own[0]), xu(own[1]), color="C2", alpha=0.25, label="misfit's own")
        for j, end in enumerate(shift):
            if math.isfinite(end):
                label = "optimum against BEM x (1 -/+ u)" if j == 0 else None
                ax.axvline(xu(end), color="C2", ls=":", lw=1.2, label=label)
        table.add(
            "misfit",
            "reference band",
            {
                "misfit interval low (m)": own[0],
                "misfit interval high (m)": own[1],
                "optimum against reference x (1 - u) (m)": shift[0],
                "optimum against reference x (1 + u) (m)": shift[1],
            },
        )
    if res.sampled_resolution is not None:
        ax.plot(xu(res.sampled_resolution), res.sampled_misfit, "x", color="C2", ms=5,
                label="sampled to locate the optimum")  # fmt: skip
        table.add(
            "misfit",
            "located (strides and refinement)",
            {"resolution (m)": res.sampled_resolution, "misfit (1)": res.sampled_misfit},
        )
    table.add(
        "misfit",
        "located optimum",
        {
            "resolution (m)": res.optimum_resolution,
            "misfit (1)": res.optimum_misfit,
            "resolution interval low (m)": low,
            "resolution interval high (m)": high,
        },
    )
    ax.axvline(
        xu(res.optimum_resolution),
        color="C2",
        lw=4.0,
        alpha=0.6,
        zorder=2,
        label=f"located {xu(res.optimum_resolution):.3g} {xu.symbol} (wide line)",
    )


def draw_model_band(
    ax: Axes, fu: DisplayUnit, result: Run, table: FigureTable, columns: tuple
) -> bool:
    """Fig 12d: the model at the located optimum with its A_r/A_n band (True when drawn)."""
    fr = result.friction
    if getattr(fr, "model_real_area", None) is None:
        return False
    x_col, y_col = columns
    a_n = fr.nominal_area
    value = np.asarray(fr.model_real_area, dtype=float) / a_n
    u = np.asarray(fr.model_real_area_uncertainty, dtype=float) / a_n
    at = result.statistical_model.effective_resolution
    ru = display_unit(at, "m")
    lower_bound = bool(getattr(fr, "uncertainty_lower_bound", False))
    clipped = bool(np.any(value - u < 0))
    name = f"JKR model ± u, {ru(at):.3g} {ru.symbol} (effective: the predictions)"
    (line,) = ax.plot(fu(fr.normal_load), value, "-", color="C3", label=name)
    low = np.maximum(value - u, 0.0)  # an area is never negative
    note = " (clipped at 0)" if clipped else ""
    if lower_bound:  # only a lower bound: the band is at least this wide, drawn open (hatched)
        ax.fill_between(fu(fr.normal_load), low, value + u, facecolor="none",
                        edgecolor=line.get_color(), hatch="///", lw=0.8, ls="--",
                        label=f"u a lower bound: the band is at least this wide{note}")  # fmt: skip
    else:
        ax.fill_between(fu(fr.normal_load), low, value + u, color=line.get_color(), alpha=0.25,
                        label=f"model ± u (one sigma){note}")  # fmt: skip
    table.add("d", name, {x_col: fr.normal_load, y_col: value, "A_r/A_n uncertainty (1)": u})
    return True


def _fig13_top(fr: FrictionPrediction) -> float:
    """The largest A_r/A_n Fig 13 must show: every curve, and the top of every error bar that
    is a value (a lower-bound bar is open-ended and may run off the axes)."""
    top = float(np.nanmax(fr.real_area) / fr.nominal_area)
    u = getattr(fr, "model_real_area_uncertainty", None)
    if u is not None and not getattr(fr, "uncertainty_lower_bound", False):
        bars = (np.asarray(fr.model_real_area) + np.asarray(u)) / fr.nominal_area
        if np.any(np.isfinite(bars)):
            top = max(top, float(np.nanmax(bars)))
    return top


def draw_fig13_error_bars(
    ax: Axes, fu: DisplayUnit, fr: FrictionPrediction, colors: np.ndarray, table: FigureTable
) -> None:
    """Fig 13: at each load, the model's A_r/A_n at F_x = 0 (vertical bar) and the static
    friction at the peak (horizontal bar, at A_r of the static peak), with their CSV rows.

    Bars stop at zero (the legend says where one was cut). When the uncertainties are only
    lower bounds (the effective resolution's interval is open), each arm ends in an outward
    arrow instead of a cap, and the legend says "lower bound": the true bar is at least this
    long."""
    if getattr(fr, "static_friction_uncertainty", None) is None:
        return
    a_n = fr.nominal_area
    lower_bound = bool(getattr(fr, "uncertainty_lower_bound", False))
    x_col, y_col = "tangential load F_x (N)", "A_r/A_n (1)"
    clipped_any = False
    for i, f in enumerate(fr.normal_load):
        x = np.array([0.0, fr.static_friction[i]])
        y = np.array([fr.model_real_area[i], fr.static_peak_real_area[i]]) / a_n
        xerr = np.array([0.0, fr.static_friction_uncertainty[i]])
        yerr = np.array([fr.model_real_area_uncertainty[i] / a_n, 0.0])
        xbars, x_cut = nonnegative_bars(x, xerr)
        ybars, y_cut = nonnegative_bars(y, yerr)
        clipped_any |= x_cut or y_cut
        if lower_bound:
            _lower_bound_arrows(ax, fu(x), y, fu(xbars), ybars, colors[i])
        else:
            ax.errorbar(fu(x), y, xerr=fu(xbars), yerr=ybars, fmt="none", ecolor=colors[i],
                        capsize=3)  # fmt: skip
        table.add(
            "all",
            f"model uncertainty F_z = {f:.6g} N",
            {
                x_col: x,
                y_col: y,
                "tangential load F_x uncertainty (N)": xerr,
                "A_r/A_n uncertainty (1)": yerr,
            },
        )
    note = CLIPPED_NOTE if clipped_any else ""
    if lower_bound:
        ax.plot([], [], color="0.3", marker=r"$\leftrightarrow$", ms=12, ls="none",
                label=f"model ± u, a lower bound: at least this wide{note}")  # fmt: skip
    else:
        ax.errorbar([], [], xerr=[], yerr=[], fmt="none", ecolor="0.3", capsize=3,
                    label=f"model ± u (A_r at $F_x$ = 0; static peak){note}")  # fmt: skip


def _lower_bound_arrows(
    ax: Axes, x: np.ndarray, y: np.ndarray, xbars: np.ndarray, ybars: np.ndarray, color: object
) -> None:
    """Open-ended bars: from each point, an arrow along each non-zero arm (the uncertainty is
    at least that long; an arm beyond the axes runs off their edge)."""
    style = {"arrowstyle": "->", "color": color, "lw": 1.2, "shrinkA": 0, "shrinkB": 0}
    for j in range(x.size):
        arms = [
            (x[j] - xbars[0, j], y[j]),
            (x[j] + xbars[1, j], y[j]),
            (x[j], y[j] - ybars[0, j]),
            (x[j], y[j] + ybars[1, j]),
        ]
        for end in arms:
            if np.all(np.isfinite(end)) and (end[0] != x[j] or end[1] != y[j]):
                # drawn even when it ends beyond the axes (then cut at their edge: open-ended)
                note = ax.annotate(
                    "", xy=end, xytext=(x[j], y[j]), arrowprops=style, annotation_clip=False
                )
                note.arrow_patch.set_clip_path(ax.patch)


def _modelled(result: Run) -> bool:
    """The run computed the model stages (not stopped where its verdict was known)."""
    return result.statistical_model is not None and result.friction is not None


#: How a figure is drawn: the run in, the figure and its data table out.
Drawer = Callable[[Run], tuple[Figure, FigureTable]]

#: Figure name -> (file stem, drawing function, whether the result has it).
FIGURES: dict[str, tuple[str, Drawer, Callable[[Run], bool]]] = {
    "surface": ("surface", draw_surface, lambda r: True),
    "resolution": ("fig12_resolution", draw_resolution, _modelled),
    "misfit": ("fig12d_misfit", draw_misfit, _modelled),
    "shear": ("fig4_shear", draw_shear, _modelled),
    "area_vs_force": ("fig13_area_vs_force", draw_area_vs_force, _modelled),
    "friction_vs_load": ("friction_vs_load", draw_friction_vs_load, _modelled),
    "bem_grid": ("bem_grid", draw_bem_grid, lambda r: r.bem_reference is not None),
    "lambda_fit": (
        "lambda_fit",
        draw_lambda_fit,
        lambda r: r.mode_mixity is not None and r.mode_mixity.fit is not None,
    ),
    "lambda_residuals": (
        "lambda_residuals",
        draw_lambda_residuals,
        lambda r: getattr(r.mode_mixity, "fitted_model_area", None) is not None,
    ),
    "psd": ("psd", draw_psd, lambda r: getattr(r, "psd", None) is not None),
    **SHEAR_FIGURES,
    **FRICTION_TEST_FIGURES,
}


def draw_figure(result: Run, name: str) -> tuple[Figure, FigureTable]:
    """One figure of :data:`FIGURES` drawn, stamped with the run's verdict when it is invalid
    (:func:`~asperity.pipelines.report.verdict_marks.stamp_verdict`), its table headed by the
    verdict (:mod:`pipelines.report.verdict_marks`)."""
    fig, table = FIGURES[name][1](result)
    verdict = getattr(result, "verdict", None)
    verdict_marks.stamp_verdict(fig, verdict)
    verdict_marks.mark_model_labels(fig, verdict)
    table.header = verdict_marks.csv_header(verdict)
    return fig, table


def draw_figures(result: Run) -> dict[str, tuple[Figure, FigureTable]]:
    """Every figure the result has, drawn (nothing written): {name: (figure, data table)}."""
    return {
        name: draw_figure(result, name)
        for name, (_, _, present) in FIGURES.items()
        if present(result)
    }


def write_figures(
    result: Run, out_dir: Path, options: FigureOptions | None = None
) -> dict[str, Path]:
    """Write every figure of the job in each format, with its CSV; returns {name: path} of
    the first format (PNG when written)."""
    out_dir = Path(out_dir)
    options = figure_options(result, options)
    first = "png" if "png" in options.formats else options.formats[0]
    return {
        name: publish(fig, table, out_dir / f"{FIGURES[name][0]}.{first}", options)
        for name, (fig, table) in draw_figures(result).items()
    }
