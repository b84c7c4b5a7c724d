"""Figures of every stage (PNG, SVG and/or PDF, each with its data as CSV), ``report.md``,
``report.html`` and the one-screen terminal summary.

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
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from asperity.atomic import write_text_atomic
from asperity.pipelines.report import verdict_marks
from asperity.pipelines.report.bem import bem_grid_figure, bem_section
from asperity.pipelines.report.figure_output import FigureOptions, FigureTable, publish
from asperity.pipelines.report.measured import shape_scale_key_numbers
from asperity.pipelines.report.profile import (
    profile_key_numbers,
    profile_section,
    scan_label,
    surface_title,
)
from asperity.pipelines.report.uncertainty import (
    bem_cells,
    bem_error_bars,
    draw_fig13_error_bars,
    draw_model_band,
    draw_resolution_interval,
    friction_error_bars,
    misfit_text,
    model_cells,
    resolution_text,
    uncertainty_rows,
)
from asperity.pipelines.stages import stage_number
from asperity.pipelines.stages.verdict import (
    mark,
    verdict_lines,
    verdict_markdown,
    verdict_wording,
)
from asperity.plotting import DisplayUnit, display_unit, new_figure
from asperity.statmodel.figures import draw_shear_curve

#: Percentiles of the heights that bound the colour scale of the surface figure.
COLOUR_PERCENTILES = (0.5, 99.5)
#: Largest number of pixels per side drawn (and written to surface.csv).
SURFACE_DRAWN_PIXELS = 400
#: Data spanning at least this ratio are drawn on a log axis.
LOG_SPAN = 10.0


def figure_options(result: Any, options: FigureOptions | None = None) -> FigureOptions:
    """``options``, else the job's ``[report]`` section, else PNG at 150 dpi."""
    if options is not None:
        return options
    report = getattr(getattr(result, "config", None), "report", None)
    if report is None:
        return FigureOptions()
    return FigureOptions(tuple(report.formats), int(report.dpi))


def spans_decades(values: Any) -> bool:
    """Positive finite data whose largest and smallest differ by :data:`LOG_SPAN` or more."""
    v = np.asarray(values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    return v.size > 1 and bool(np.all(v > 0)) and v.max() >= LOG_SPAN * v.min()


def log_axis(ax: Any, which: str, values: Any = None) -> None:
    """A log axis labelled at 1, 2, 5 x 10^k (1 x 10^k beyond 3 decades) in plain numbers;
    no minor tick labels (they overprint)."""
    getattr(ax, f"set_{which}scale")("log")
    v = np.asarray(values if values is not None else [1.0, 1e6], dtype=float).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    decades = np.log10(v.max() / v.min()) if v.size else 6.0
    axis = getattr(ax, f"{which}axis")
    axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0) if decades < 3 else (1.0,)))
    axis.set_major_formatter(FuncFormatter(_tick_text))
    axis.set_minor_formatter(NullFormatter())


def _tick_text(value: float, _position: Any) -> str:
    """A log-axis tick as a short number (0.002, 50, 1e+06)."""
    return f"{value:g}"


def _auto_scale(ax: Any, x: Any, y: Any) -> None:
    """Log axes where the plotted data span decades."""
    if spans_decades(x):
        log_axis(ax, "x", x)
    if spans_decades(y):
        log_axis(ax, "y", y)


def draw_surface(result: Any) -> tuple[Figure, FigureTable]:
    """The read-and-level stage: the levelled height map, robust colour limits (percentiles,
    stated)."""
    s = result.surface
    step = max(1, -(-max(s.nx, s.ny) // SURFACE_DRAWN_PIXELS))
    h = np.asarray(s.heights)[::step, ::step]
    low, high = np.nanpercentile(h, COLOUR_PERCENTILES)
    hu = display_unit([low, high], "m")
    xu = display_unit([s.lx, s.ly], "m")
    fig = new_figure(5.8, 4.6)
    ax = fig.subplots()
    image = ax.imshow(
        hu(h).T,
        origin="lower",
        cmap="viridis",
        extent=(0, xu(s.lx), 0, xu(s.ly)),
        vmin=hu(low),
        vmax=hu(high),
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
    ax.set_title(f"{surface_title(s)}, {s.nx} x {s.ny} px of {size} {pixel.symbol}")
    ix, iy = np.meshgrid(np.arange(h.shape[0]) * step, np.arange(h.shape[1]) * step, indexing="ij")
    table = FigureTable()
    table.add(
        "map",
        f"heights, every {step} px" if step > 1 else "heights",
        {"x (m)": ix * s.dx, "y (m)": iy * s.dy, "height (m)": h},
    )
    return fig, table


def _min_summits() -> int:
    from asperity.topo.scan import resolution_scan

    return int(inspect.signature(resolution_scan).parameters["min_summits"].default)


def fit_excluded(scan: Any) -> np.ndarray:
    """Strides left out of the paper's fits: too few summits or no finite density."""
    return (np.asarray(scan.n_summits) < _min_summits()) | ~np.isfinite(
        np.asarray(scan.asperity_density, dtype=float)
    )


def _mark_resolution(ax: Any, xu: DisplayUnit, res: Any, scan: Any, y: np.ndarray) -> None:
    """The effective resolution (dashed) and the strides left out of the fits (grey)."""
    ax.axvline(xu(res.effective_resolution), color="k", ls="--", lw=1, label="effective")
    out = fit_excluded(scan)
    if out.any():
        ax.plot(
            xu(np.asarray(scan.resolution)[out]),
            y[out],
            "x",
            color="0.5",
            label=f"not fitted (< {_min_summits()} summits)",
        )


def _draw_scan_panel(ax: Any, xu: DisplayUnit, result: Any, spec: dict[str, Any]) -> None:
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
    ax.legend(fontsize=7)


def _scan_panels(scan: Any) -> list[dict[str, Any]]:
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


def radius_fit_line(scan: Any, resolution: np.ndarray) -> dict[str, Any]:
    """Fig 12a's linear fit R = intercept + slope x over ``resolution`` (m), drawn only where
    R > 0 (a radius is positive; the straight line may cross zero inside the scan), with its
    slope dR/dx in m/m (R and the resolution are both lengths)."""
    fit = scan.radius_intercept + scan.radius_slope * np.asarray(resolution, dtype=float)
    keep = np.isfinite(fit) & (fit > 0)
    label = f"linear fit, dR/d(resolution) = {scan.radius_slope:.3g} m/m"
    if not keep.all() and keep.any():
        label += " (drawn where R > 0)"
    if not keep.any():
        return {"fit": None}
    return {"fit": fit[keep], "fit_x": np.asarray(resolution)[keep], "fit_label": label}


def _persson_fraction(result: Any) -> np.ndarray | None:
    psd = getattr(result, "psd", None)
    if psd is None:
        return None
    return np.asarray(psd.persson_real_area) / result.statistical_model.nominal_area


def _draw_area_vs_load(ax: Any, result: Any, table: FigureTable) -> None:
    """Fig 12d: A_r/A_n against F_z from BEM, the statistical model, Persson, measurement."""
    res, bem = result.statistical_model, result.bem_reference
    a_n = res.nominal_area
    loads = np.asarray(res.normal_load, dtype=float)
    fu = display_unit(loads, "N")
    x_col, y_col = "normal load F_z (N)", "A_r/A_n (1)"
    plotted: list[np.ndarray] = []

    def series(name: str, f: Any, fraction: Any, style: str, u: Any = None, **kw: Any) -> None:
        fraction = np.asarray(fraction, dtype=float)
        columns = {x_col: f, y_col: fraction}
        if u is None:
            ax.plot(fu(f), fraction, style, label=name, **kw)
        else:
            ax.errorbar(fu(f), fraction, yerr=u, fmt=style, label=name, capsize=3, **kw)
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
    draw_model_band(ax, fu, result, table, (x_col, y_col))
    for i in sorted({0, res.index, len(res.stride) - 1}):
        if np.all(np.isfinite(res.real_area[i])):
            ru = display_unit(res.resolution[i], "m")
            name = f"model, {ru(res.resolution[i]):.3g} {ru.symbol}"
            name += " (stride of least misfit)" if i == res.index else ""
            series(name, loads, res.real_area[i] / a_n, "-" if i == res.index else ":")
    persson = _persson_fraction(result)
    if persson is not None:
        series("Persson, non-adhesive", result.psd.normal_load, persson, "-.", color="C4")
    if res.measured is not None:
        series("measured", res.measured.normal_load, res.measured.real_area / a_n, "o", color="k")
    verdict_marks.separate_bem_markers(ax)
    _auto_scale(ax, loads, np.concatenate(plotted))
    ax.set_xlabel(fu.label("normal load $F_z$"))
    ax.set_ylabel("$A_r / A_n$")
    ax.set_title("(d)")
    verdict_marks.threshold_lines(ax, "A_r/A_n", verdict_marks.AREA_FRACTION_THRESHOLDS)
    ax.legend(fontsize=7)


def non_adhesive_series(series: Any, res: Any) -> None:
    """Fig 12d's non-adhesive pair: the model at w -> 0 (Greenwood-Williamson) at that pair's
    least-misfit resolution, a grey dashed line with open triangles beside the open markers
    of the non-adhesive BEM (the adhesive pair: the filled markers and the effective model)."""
    index = getattr(res, "effective_index_non_adhesive", None)
    if index is None or res.real_area_non_adhesive is None:
        return
    ru = display_unit(res.resolution[index], "m")
    name = f"model w=0 (GW), {ru(res.resolution[index]):.3g} {ru.symbol} (non-adhesive pair)"
    fraction = res.real_area_non_adhesive[index] / res.nominal_area
    series(name, res.normal_load, fraction, "v--", color="0.4", mfc="none")


def draw_resolution(result: Any) -> tuple[Figure, FigureTable]:
    """Fig 12a-d with the data table (SI)."""
    scan = result.resolution_scan
    xu = display_unit(scan.resolution, "m")
    fig = new_figure(10.5, 8.2)
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
    _draw_area_vs_load(axes[1, 1], result, table)
    return fig, table


def draw_misfit(result: Any) -> tuple[Figure, FigureTable]:
    """The statistical-model stage: the misfit curve that chose the effective resolution."""
    res = result.statistical_model
    xu = display_unit(res.resolution, "m")
    fig = new_figure(6, 4)
    ax = fig.subplots()
    table = FigureTable()
    curves = [("against BEM", res.misfit_bem, "o-")]
    if res.misfit_measured is not None:
        curves.append(("against measured A_r(F_z)", res.misfit_measured, "s-"))
    for name, misfit, style in curves:
        if np.isfinite(misfit).any():
            ax.plot(xu(res.resolution), misfit, style, label=name)
            table.add("misfit", name, {"resolution (m)": res.resolution, "misfit (1)": misfit})
    ax.axvline(
        xu(res.effective_resolution),
        color="k",
        ls="--",
        label=f"stride of least misfit {xu(res.effective_resolution):.3g} {xu.symbol}",
    )
    draw_resolution_interval(ax, xu, res, table)
    ax.set_xlabel(xu.label("resolution"))
    ax.set_ylabel("rms of ln($A_{model}$ / $A_{reference}$)")
    log_axis(ax, "y", [m for _, m, _ in curves])
    verdict_marks.threshold_lines(ax, "misfit", verdict_marks.MISFIT_THRESHOLDS)
    ax.legend(fontsize=8)
    return fig, table


def draw_bem_grid(result: Any) -> tuple[Figure, FigureTable]:
    """The BEM stage: the refinement curve, its error against the finest grid, the contact mask."""
    bem = result.bem_reference
    table = FigureTable()
    pixel = np.asarray(bem.check_stride) * result.surface.dx
    for k, mode in enumerate(("non-adhesive", "adhesive")[: bem.check_contact_fraction.shape[1]]):
        table.add(
            "refinement",
            mode,
            {"BEM pixel size (m)": pixel, "A_r/A_n (1)": bem.check_contact_fraction[:, k]},
        )
    table.add(
        "error",
        "larger of the modes",
        {"BEM pixel size (m)": pixel, "error against the finest grid (1)": bem.check_error},
    )
    return bem_grid_figure(result), table


def draw_lambda_fit(result: Any) -> tuple[Figure, FigureTable]:
    """The lambda stage: the misfit of the coarse lambda scan and the fitted value."""
    fit = result.mode_mixity.fit
    fig = new_figure(6, 4)
    ax = fig.subplots()
    ax.loglog(fit.grid_mode_mixity, fit.grid_residual_rms, "o-", label="coarse scan")
    ax.axvline(
        fit.mode_mixity,
        color="k",
        ls="--",
        label=f"fit {fit.mode_mixity:.3g} +/- {fit.mode_mixity_std:.2g}",
    )
    if np.isfinite(fit.mode_mixity_std):  # an unbounded uncertainty has no band to draw
        ax.axvspan(
            max(fit.mode_mixity - fit.mode_mixity_std, 1e-12),
            fit.mode_mixity + fit.mode_mixity_std,
            color="0.85",
        )
    ax.set_xlabel("mode mixity $\\lambda$")
    ax.set_ylabel("rms of ($A_{model}$ - $A_{measured}$) / max $A_{measured}$")
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


def draw_lambda_residuals(result: Any) -> tuple[Figure, FigureTable]:
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


def draw_shear(result: Any) -> tuple[Figure, FigureTable]:
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


def _model_at_measured(lam: Any, a_n: float, table: FigureTable, x_col: str, y_col: str) -> None:
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


def draw_area_vs_force(result: Any) -> tuple[Figure, FigureTable]:
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
    ax.set_ylim(0, 1.15 * np.nanmax(fr.real_area) / a_n)
    ax.set_xlabel(fu.label("tangential load $F_x$"))
    ax.set_ylabel("$A_r / A_n$")
    verdict_marks.threshold_lines(ax, "A_r/A_n", verdict_marks.AREA_FRACTION_THRESHOLDS)
    ax.legend(fontsize=7)
    return fig, table


def draw_friction_vs_load(result: Any) -> tuple[Figure, FigureTable]:
    """Static and sliding friction against normal load."""
    fr = result.friction
    fu = display_unit(fr.normal_load, "N")
    yu = display_unit([fr.static_friction, fr.sliding_friction], "N")
    fig = new_figure(6, 4)
    ax = fig.subplots()
    table = FigureTable()
    x_col = "normal load F_z (N)"
    bars = friction_error_bars(fr)
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
            ax.errorbar(x, yu(values), yerr=yu(u), fmt=style, capsize=3, label=name)
            columns["friction force uncertainty (N)"] = u
        table.add("all", name, columns)
    _auto_scale(ax, fr.normal_load, [fr.static_friction, fr.sliding_friction])
    ax.set_xlabel(fu.label("normal load $F_z$"))
    ax.set_ylabel(yu.label("friction force"))
    ax.legend(fontsize=8)
    return fig, table


def nyquist_style(name: str) -> dict[str, Any]:
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


def nyquist_marks(result: Any) -> dict[str, float]:
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


def draw_psd(result: Any) -> tuple[Figure, FigureTable]:
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
        ax.loglog(
            qu(line), cu(fit), "-", color="C1", label=f"power law, H = {psd.hurst_exponent:.3g}"
        )
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
            "Hurst exponent (1)": psd.hurst_exponent,
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


#: Figure name -> (file stem, drawing function, whether the result has it).
FIGURES: dict[str, tuple[str, Any, Any]] = {
    "surface": ("surface", draw_surface, lambda r: True),
    "resolution": ("fig12_resolution", draw_resolution, lambda r: True),
    "misfit": ("fig12d_misfit", draw_misfit, lambda r: True),
    "shear": ("fig4_shear", draw_shear, lambda r: True),
    "area_vs_force": ("fig13_area_vs_force", draw_area_vs_force, lambda r: True),
    "friction_vs_load": ("friction_vs_load", draw_friction_vs_load, lambda r: True),
    "bem_grid": ("bem_grid", draw_bem_grid, lambda r: r.bem_reference is not None),
    "lambda_fit": ("lambda_fit", draw_lambda_fit, lambda r: r.mode_mixity.fit is not None),
    "lambda_residuals": (
        "lambda_residuals",
        draw_lambda_residuals,
        lambda r: getattr(r.mode_mixity, "fitted_model_area", None) is not None,
    ),
    "psd": ("psd", draw_psd, lambda r: getattr(r, "psd", None) is not None),
}


def draw_figure(result: Any, name: str) -> tuple[Figure, FigureTable]:
    """One figure of :data:`FIGURES` drawn, stamped with the run's verdict unless it is valid,
    its table headed by the verdict (:mod:`pipelines.report.verdict_marks`)."""
    fig, table = FIGURES[name][1](result)
    verdict = getattr(result, "verdict", None)
    verdict_marks.stamp_verdict(fig, verdict)
    table.header = verdict_marks.csv_header(verdict)
    return fig, table


def draw_figures(result: Any) -> dict[str, tuple[Figure, FigureTable]]:
    """Every figure the result has, drawn (nothing written): {name: (figure, data table)}."""
    return {
        name: draw_figure(result, name)
        for name, (_, _, present) in FIGURES.items()
        if present(result)
    }


def write_figures(
    result: Any, out_dir: Path, options: FigureOptions | None = None
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


def _grid_error_text(bem: Any) -> str:
    """The grid used against the finest grid solved; the finest grid's own error is unknown."""
    if bem.stride <= int(np.min(bem.check_stride)):
        return "the finest grid solved (its own error is not known)"
    return f"A_r {bem.grid_error:.2%} from the finest grid solved"


def pixel_size_text(surface: Any) -> str:
    """``"10 um pixels"``, or ``"0.1277 x 0.3146 um pixels (dx x dy)"`` when dy differs."""
    if np.isclose(surface.dx, surface.dy, rtol=1e-9, atol=0.0):
        return f"{surface.dx * 1e6:.4g} um pixels"
    return f"{surface.dx * 1e6:.4g} x {surface.dy * 1e6:.4g} um pixels (dx x dy)"


def key_numbers(result: Any) -> list[tuple[str, str]]:
    """(quantity, value with unit) rows of the report's headline table."""
    res, fr, bem, lam = (
        result.statistical_model,
        result.friction,
        result.bem_reference,
        result.mode_mixity,
    )
    r = res.roughness
    rows = [
        (
            "surface",
            f"{result.surface.nx} x {result.surface.ny} px, {pixel_size_text(result.surface)}",
        ),
        ("effective resolution", f"{resolution_text(res)}; chosen against {res.basis}"),
        ("summit radius R", f"{r.summit_radius * 1e3:.4g} mm"),
        ("asperity density eta", f"{r.asperity_density * 1e-6:.4g} 1/mm^2"),
        ("rms summit height sigma_s", f"{r.summit_height_rms * 1e3:.4g} mm"),
        ("Tabor parameter mu", f"{res.tabor_parameter:.4g}"),
        ("misfit at effective resolution", misfit_text(res)),
    ]
    if lam.fitted:
        rows.append(
            (
                "mode mixity lambda (fitted)",
                f"{lam.mode_mixity:.4g} +/- {lam.mode_mixity_std:.2g} "
                f"(rms relative residual {lam.residual_rms:.3g}, "
                f"{lam.n_points} points)",
            )
        )
    else:
        rows.append(("mode mixity lambda (configured)", f"{lam.mode_mixity:.4g}"))
    rows += shape_scale_key_numbers(result)
    if bem is None:
        rows.append(("BEM", "not run ([bem] enabled = false): calibrated on the measurement"))
    else:
        rows += [
            (
                "BEM grid",
                f"stride {bem.stride} ({bem.dx * 1e6:.4g} um), {_grid_error_text(bem)}; "
                f"{bem.boundary} boundary",
            ),
            ("BEM solves converged", f"{int(np.sum(bem.converged))} / {bem.converged.size}"),
        ]
        rows += adhesion_key_numbers(result)
    rows += psd_key_numbers(result)
    rows += uncertainty_rows(result)
    rows += profile_key_numbers(result)
    rows += [
        ("statmodel quadrature", fr.quadrature_reason),
        ("shear curves converged", f"{int(np.sum(fr.converged))} / {fr.converged.size}"),
    ]
    verdict = getattr(result, "verdict", None)
    judged = (
        "effective resolution",
        "summit",
        "asperity",
        "rms summit",
        "Tabor",
        "misfit",
        "mode mixity lambda (fitted)",
    )
    return [(k, mark(v, verdict) if k.startswith(judged) else v) for k, v in rows]


def adhesion_key_numbers(result: Any) -> list[tuple[str, str]]:
    """Rows of the adhesive BEM's law and range, the non-adhesive pair's resolution, and the
    adhesion regime (Persson-Tosatti, Pastewka-Robbins, Tabor); empty where not run."""
    bem, res = result.bem_reference, result.statistical_model
    rows = []
    law = getattr(bem, "adhesion", None)
    if law == "maugis":
        rows.append(("BEM adhesion", f"Maugis-Dugdale (adhesive on loading); {bem.range_rule}"))
        spread = bem.range_sensitivity
        rows.append(
            (
                "BEM range uncertainty",
                f"A_r/A_n +/- {bem.area_range_uncertainty:.3g} (half spread over h_0/2, h_0, "
                f"2 h_0: {spread[0]:.4g}, {spread[1]:.4g}, {spread[2]:.4g} at "
                f"{bem.check_load:.4g} N on the range search's grid)",
            )
        )
    elif law == "pohrt-popov":
        rows.append(("BEM adhesion", "Pohrt-Popov (Appendix B): no adhesion on loading"))
    index = getattr(res, "effective_index_non_adhesive", None)
    if index is not None:
        rows.append(
            (
                "effective resolution, non-adhesive pair",
                f"{res.resolution[index] * 1e6:.4g} um (w=0 model against the non-adhesive "
                f"BEM, misfit {res.misfit_bem_non_adhesive[index]:.3g}; not used: the "
                "adhesive pair chooses)",
            )
        )
    return rows + regime_key_numbers(getattr(result, "verdict", None))


def regime_key_numbers(verdict: Any) -> list[tuple[str, str]]:
    """The adhesion regime's row (empty without one)."""
    ratio = getattr(verdict, "adhesion_energy_ratio", None)
    if ratio is None:
        return []
    full = "full contact expected" if ratio < 1 else "partial contact"
    return [
        (
            "adhesion regime",
            f"U_el/(A0 w) = {ratio:.3g} ({full}; Persson-Tosatti, threshold 1); "
            f"stickiness S_PR = {verdict.stickiness:.3g} (Pastewka-Robbins, sticky below 1); "
            f"Tabor mu = {verdict.regime_tabor_parameter:.3g}",
        )
    ]


def psd_key_numbers(result: Any) -> list[tuple[str, str]]:
    """Rows of the PSD stage (empty when the result has none)."""
    psd = getattr(result, "psd", None)
    if psd is None:
        return []
    return [
        ("PSD roll-off wavelength", f"{psd.rolloff_wavelength * 1e6:.4g} um"),
        ("Hurst exponent H (PSD above roll-off)", f"{psd.hurst_exponent:.3g}"),
        (
            "effective Nyquist wavelength 2x",
            f"{psd.effective_nyquist_wavelength * 1e6:.4g} um",
        ),
        ("rms slope h' (Persson)", f"{psd.persson_rms_slope:.4g}"),
    ]


def load_table(result: Any) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the per-load table."""
    fr, bem = result.friction, result.bem_reference
    header = [
        "F_z (N)",
        "A_r/A_n BEM",
        "A_r/A_n BEM adh.",
        "A_r/A_n model",
        "static F_x (N)",
        "sliding F_x (N)",
        "delta_T slide (um)",
    ]
    persson = _persson_fraction(result)
    if persson is not None:
        header.append("A_r/A_n Persson")
    rows = []
    for i, f in enumerate(fr.normal_load):
        rows.append([f"{f:.4g}", *bem_cells(bem, i), *model_cells(result, i)])
        if persson is not None:
            rows[-1].append(f"{persson[i]:.4g}")
    verdict = getattr(result, "verdict", None)
    # the statistical model's columns carry the verdict; BEM and Persson are references
    rows = [[*row[:3], *(mark(cell, verdict) for cell in row[3:7]), *row[7:]] for row in rows]
    return non_adhesive_column(result, header, rows)


def non_adhesive_column(
    result: Any, header: list[str], rows: list[list[str]]
) -> tuple[list[str], list[list[str]]]:
    """The load table with the non-adhesive pair's model column (w = 0, Greenwood-Williamson,
    at that pair's least-misfit resolution) appended: its partner is "A_r/A_n BEM"; the
    adhesive pair is "A_r/A_n BEM adh." and "A_r/A_n model"."""
    res = result.statistical_model
    index = getattr(res, "effective_index_non_adhesive", None)
    if index is None or res.real_area_non_adhesive is None:
        return header, rows
    fraction = res.real_area_non_adhesive[index] / res.nominal_area
    verdict = getattr(result, "verdict", None)
    header = [*header, f"A_r/A_n model w=0 ({res.resolution[index] * 1e6:.3g} um)"]
    return header, [
        [*row, mark(f"{f:.4g}", verdict)] for row, f in zip(rows, fraction, strict=True)
    ]


def surface_section(result: Any) -> list[str]:
    """The report's "Surface" section: how the map was prepared, with its warnings."""
    surface = result.surface
    record = getattr(surface, "preparation", None) or {}
    rows = [
        ["grid", f"{surface.nx} x {surface.ny} px"],
        ["pixel size dx, dy", f"{surface.dx * 1e6:.4g} um, {surface.dy * 1e6:.4g} um"],
    ]
    if record:
        ratio = record.get("form_to_roughness")
        rows += [
            ["crop", str(record.get("crop") or "none")],
            ["levelling (form removed)", str(record.get("levelling"))],
            ["form-to-roughness rms ratio", "-" if ratio is None else f"{ratio:.3g}"],
            [
                "missing pixels",
                f"{record['n_missing']} ({100 * record['missing_fraction']:.3g} %), policy "
                f"{record['missing_policy']}; {record['n_filled']} filled",
            ],
            [
                "outliers changed",
                f"{record['n_outliers']} ({100 * record['outlier_fraction']:.3g} % of the valid "
                f"pixels, {record['outlier_action']}): {record['outlier_rule']}",
            ],
            ["rms roughness after preparation", f"{record['roughness_rms'] * 1e6:.4g} um"],
        ]
    rows = [[key, value.replace("|", "\\|")] for key, value in rows]  # a pipe ends a cell
    lines = ["## Surface", "", _md_table(["step", "value"], rows), ""]
    warnings = record.get("warnings") or []
    lines += [f"- **Warning:** {w}" for w in warnings]
    return [*lines, ""] if warnings else lines


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _source(result: Any) -> str:
    """Where the configuration came from (a job's config, or a reopened file's record)."""
    config = getattr(result, "config", None)
    return config.source if config is not None else getattr(result, "source", "results.h5")


#: Figure name -> caption in report.md and report.html.
CAPTIONS: dict[str, str] = {
    "surface": f"Stage {stage_number('surface')}: levelled surface.",
    "resolution": "Fig 12: summit statistics against resolution (a-c) and A_r/A_n against "
    "F_z (d). Persson's theory (dash-dot) is non-adhesive: a lower bound.",
    "misfit": f"Stage {stage_number('statistical_model')}: misfit of the statistical model "
    "against resolution.",
    "bem_grid": f"Stage {stage_number('bem_reference')}: BEM grid refinement (A_r/A_n and its "
    "error against the finest grid solved) and contact at the largest load.",
    "lambda_fit": f"Stage {stage_number('mode_mixity')}: lambda fit.",
    "lambda_residuals": f"Stage {stage_number('mode_mixity')}: measured minus fitted A_r at each "
    "load (the points fitted: trimmed after the first static peak, repeated points merged).",
    "shear": "Fig 4: shear response at the heaviest load, with stick and slip parts.",
    "area_vs_force": "Fig 13: A_r/A_n against F_x (dashed: model; dotted: constant shear "
    "strength).",
    "friction_vs_load": "Static and sliding friction against normal load.",
    "psd": f"Stage {stage_number('psd')}: radially averaged PSD with the roll-off, the power-law "
    "(Hurst) fit and "
    "the Nyquist wavenumbers of the map and of the effective resolution.",
}


def refusals_section(result: Any) -> list[str]:
    """Markdown lines listing the resolutions where the statistical model gave no value."""
    messages = list(getattr(result.statistical_model, "messages", None) or [])
    if not messages:
        return []
    return [
        "## Statistical model refusals",
        "",
        "No value at these resolutions (NaN in `results.h5`, group `statistical_model`):",
        "",
        *(f"- {m}" for m in messages),
        "",
    ]


def write_report(result: Any, out_dir: str | Path, options: FigureOptions | None = None) -> Path:
    """Write the figures, ``report.md`` and ``report.html`` (key numbers, per-load table,
    figures); ``options`` (formats, dpi) default to the job's ``[report]`` section."""
    from asperity.pipelines.report.html import write_html

    out_dir = Path(out_dir)
    figures = write_figures(result, out_dir, options)
    header, rows = load_table(result)
    status = {"stored": "stored (skipped)", "computed": "computed", "disabled": "disabled"}
    stage_rows = [
        [s.name, status[s.status] + (f" ({s.note})" if s.note else ""), f"{s.seconds:.2f}"]
        for s in result.stages
    ]
    problems = result.problems()
    verdict = getattr(result, "verdict", None)
    text = [
        "# asperity run report",
        "",
        *([] if verdict is None else verdict_markdown(verdict)),
        f"Configuration: `{_source(result)}`; input SHA-256 `{result.input_sha256[:16]}...`;"
        " all data in `results.h5` (SI units).",
        "",
        "## Key numbers",
        "",
        _md_table(["quantity", "value"], [list(r) for r in key_numbers(result)]),
        "",
        "## Per normal load",
        "",
        _md_table(header, rows),
        "",
        *surface_section(result),
        *profile_section(result),
        *bem_section(result),
        "## Validity",
        "",
        f"**{verdict_wording(verdict)}** (reasons at the top)."
        if verdict is not None
        else "The statistical model is within its assumptions."
        if not result.statistical_model.validity
        else "\n".join(f"- **Warning:** {note}" for note in result.statistical_model.validity),
        "",
        *refusals_section(result),
        "## Convergence",
        "",
        "All solvers converged."
        if not problems
        else "**Not converged:**\n\n" + "\n".join(f"- {p}" for p in problems),
        "",
        "## Stages",
        "",
        _md_table(["stage", "status", "seconds"], stage_rows),
        "",
        "## Figures",
        "",
    ]
    captions = dict(CAPTIONS)
    for name, path in figures.items():
        text += [f"![{captions[name]}]({path.name})", "", f"*{captions[name]}*", ""]
    report = out_dir / "report.md"
    write_text_atomic(report, "\n".join(text))
    write_html(result, out_dir, figures, captions)
    return report


def summary_text(result: Any) -> str:
    """The one-screen terminal summary."""
    lines = ["asperity run: summary", ""]
    if getattr(result, "verdict", None) is not None:
        lines += [*verdict_lines(result.verdict), ""]
    width = max(len(k) for k, _ in key_numbers(result))
    for key, value in key_numbers(result):
        lines.append(f"  {key:<{width}}  {value}")
    header, rows = load_table(result)
    widths = [max(len(h), *(len(r[j]) for r in rows)) for j, h in enumerate(header)]
    lines += ["", "  " + "  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True))]
    for row in rows:
        lines.append("  " + "  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)))
    computed = sum(s.seconds for s in result.stages if not s.cached)
    cached = [s.name for s in result.stages if s.cached]
    lines += [
        "",
        f"  stages computed in {computed:.1f} s"
        + (f"; stored stages skipped: {', '.join(cached)}" if cached else "")
        + f"; total {result.total_seconds:.1f} s",
    ]
    if getattr(result, "verdict", None) is None:
        lines += [f"  WARNING: {note}" for note in result.statistical_model.validity]
    for note in [] if result.bem_reference is None else result.bem_reference.warnings:
        lines.append(f"  WARNING: {note}")
    problems = result.problems()
    if problems:
        lines.append("  NOT CONVERGED:")
        lines += [f"    {p}" for p in problems[:8]]
    lines.append(f"  outputs: {result.out_dir / 'results.h5'}, {result.out_dir / 'report.md'}")
    return "\n".join(lines)
