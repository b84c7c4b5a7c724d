"""The paper's Figs. 1, 2, 4 and 5 from this package, as PNG (150 dpi) plus one HDF5 data file.

Parameters are the captions' (Fig. 1/2: w = 27 mJ/m^2, R = 9.42 mm, E* = 2.133 MPa,
lambda = 0.0023, tau0 = 0.43 MPa; Fig. 4/5 base: w = 40 mJ/m^2, lambda = 0.2, tau0 = 0.13 MPa,
F_z = 3.1 N, A_n = 700 mm^2, eta = 652.1 mm^-2, sigma_s = 0.032 mm, R = 0.041 mm). Values the
captions do not list are chosen here and recorded in the HDF5 file:

* Fig. 1: indentations delta in {0.005, 0.01, 0.02, 0.04, 0.08} mm;
* Fig. 5: w in {15, 25, 40, 60} mJ/m^2, lambda in {0.05, 0.2, 0.3, 0.9},
  tau0 in {0.05, 0.13, 0.3, 0.5} MPa, F_z in {0.5, 1, 3.1, 6, 10} N.

Every HDF5 dataset has a ``units`` attribute. Figures are :class:`matplotlib.figure.Figure`
objects (no pyplot, no backend forced); axis units carry SI prefixes chosen from the data
(:func:`asperity.plotting.display_unit`). :func:`draw_shear_curve` draws Fig. 4 for any
:class:`~asperity.statmodel.shear.ShearCurve` (the main job's report uses it too).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypeAlias

import h5py
import numpy as np

from asperity.h5 import new_file
from asperity.plotting import DisplayUnit, display_unit, new_figure, save_figure
from asperity.statmodel.hertz import (
    hertz_contact_radius,
    hertz_normal_load,
    hertz_sliding_tangential_load,
)
from asperity.statmodel.papangelo_ciavarella import (
    pc_contact_radius,
    pc_fold_radius,
    pc_max_tangential_displacement,
    pc_normal_load,
)
from asperity.statmodel.parameters import Material, Roughness, tabor_parameter
from asperity.statmodel.results_io import write_dataset
from asperity.statmodel.shear import ShearCurve, shear_curve
from asperity.statmodel.status_map import (
    JUMP_OFF_DIMENSIONLESS,
    asperity_status,
    dimensionless_unstable_boundary,
    from_dimensionless,
    scale_factor,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DPI = 150
# Figs. 1-2 (single asperity)
R1, W1, E1, LAM1, TAU1 = 9.42e-3, 0.027, 2.133e6, 0.0023, 0.43e6
FIG1_DELTAS = np.array([0.005, 0.01, 0.02, 0.04, 0.08]) * 1e-3
# Figs. 4-5 (rough surface)
BASE = {"e_star": 2.133e6, "work_of_adhesion": 0.040, "mode_mixity": 0.2, "shear_strength": 0.13e6}
ROUGH = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
AREA, LOAD = 700e-6, 3.1
FIG5_W = [0.015, 0.025, 0.040, 0.060]
FIG5_LAMBDA = [0.05, 0.2, 0.3, 0.9]
FIG5_TAU = [0.05e6, 0.13e6, 0.3e6, 0.5e6]
FIG5_LOAD = [0.5, 1.0, 3.1, 6.0, 10.0]
#: Size of every 2 x 2 figure, inches.
FIGSIZE = (10.0, 8.0)
#: Axis-label quantities (mathtext).
DELTA_T = r"tangential displacement $\delta_T$"
#: One single-asperity curve by series name (SI): arrays along delta_T, ``delta`` a number.
Curve: TypeAlias = dict[str, np.ndarray | float]


def _finish_panel(ax: Axes, tag: str, xlabel: str, ylabel: str, *, legend: bool = True) -> None:
    """Label a panel ``(tag)``, its axes, a light grid and (optionally) its legend."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(f"({tag})")
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=8)


def _pc_state(delta: float, dts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = np.asarray(pc_contact_radius(delta, dts, R1, W1, E1, LAM1))
    p = np.asarray(pc_normal_load(delta, dts, R1, W1, E1, LAM1))
    t = 4.0 / 3.0 * E1 * a * dts
    return a, p, t


def _fig1_data(h5: h5py.Group) -> tuple[list[Curve], Curve]:
    """Fig. 1's curves (one per delta) and its unstable boundary, written to ``h5`` as well."""
    curves = []
    for j, delta in enumerate(FIG1_DELTAS):
        dt_max = pc_max_tangential_displacement(delta, R1, W1, E1, LAM1)
        dts = dt_max * (1.0 - np.linspace(0.0, 1.0, 400) ** 2)[::-1]
        a, p, t = _pc_state(delta, dts)
        curve: Curve = {"delta": delta, "dt": dts, "p": p, "t": t, "area": np.pi * a**2}
        curves.append(curve)
        _write_single_asperity(h5.create_group(f"delta_{j}"), curve)
    # unstable boundary (dash-dotted): the fold state for a sweep of delta
    deltas = np.linspace(FIG1_DELTAS[0] * 0.5, FIG1_DELTAS[-1] * 1.1, 200)
    dtb = pc_max_tangential_displacement(deltas, R1, W1, E1, LAM1)
    ab = pc_fold_radius(dtb, R1, W1, E1, LAM1)
    pb = 4 * E1 * ab**3 / (3 * R1) - np.sqrt(
        np.maximum(8 * np.pi * E1 * ab**3 * W1 - 16 / 9 * LAM1 * E1**2 * ab**2 * dtb**2, 0)
    )
    boundary: Curve = {"delta": deltas, "dt": dtb, "p": pb, "t": 4 / 3 * E1 * ab * dtb}
    boundary["area"] = np.pi * ab**2
    _write_single_asperity(h5.create_group("unstable_boundary"), boundary)
    return curves, boundary


def _write_single_asperity(g: h5py.Group, curve: Curve) -> None:
    write_dataset(g, "indentation", curve["delta"], "m")
    write_dataset(g, "tangential_displacement", curve["dt"], "m")
    write_dataset(g, "normal_load", curve["p"], "N")
    write_dataset(g, "tangential_load", curve["t"], "N")
    write_dataset(g, "contact_area", curve["area"], "m^2")


def _units(curves: Sequence[Curve], key: str, base: str, power: int = 1) -> DisplayUnit:
    """One display unit for ``key`` across all ``curves``."""
    return _panel_unit([c[key] for c in curves], base, power)


def figure_1(h5: h5py.Group) -> Figure:
    """Fig. 1: P, T, A vs delta_T and A vs T for several delta (fixed grip, PC model).

    E:PC_indent..E:PC_T up to the unstable boundary (the fold, E:PC_a_min_1). The plotted data
    go to the new group ``h5["fig1"]`` (SI units); returns the drawn Figure.
    """
    g = h5.create_group("fig1")
    mu = tabor_parameter(R1, W1, E1)
    g.attrs["parameters"] = f"w={W1} J/m^2, R={R1} m, E*={E1} Pa, lambda={LAM1}, mu={mu:.0f}"
    curves, boundary = _fig1_data(g)
    everything = [*curves, boundary]
    u_delta = display_unit(FIG1_DELTAS, "m")
    u_dt = _units(everything, "dt", "m")
    u_p, u_t = _units(everything, "p", "N"), _units(everything, "t", "N")
    u_area = _units(everything, "area", "m", 2)
    fig = new_figure(*FIGSIZE)
    axes = fig.subplots(2, 2)
    panels = [("dt", u_dt, "p", u_p), ("dt", u_dt, "t", u_t), ("dt", u_dt, "area", u_area)]
    panels.append(("t", u_t, "area", u_area))
    for ax, (x, ux, y, uy) in zip(axes.flat, panels, strict=True):
        for c in curves:
            label = rf"$\delta$ = {u_delta(c['delta']):g} {u_delta.symbol}"
            ax.plot(ux(c[x]), uy(c[y]), label=label)
        ax.plot(ux(boundary[x]), uy(boundary[y]), "k-.", label="unstable boundary")
    quantity = {"dt": DELTA_T, "p": "normal load $P$", "t": "tangential load $T$"}
    quantity["area"] = r"contact area $A = \pi a^2$"
    for ax, (x, ux, y, uy), tag in zip(axes.flat, panels, "abcd", strict=True):
        _finish_panel(ax, tag, ux.label(quantity[x]), uy.label(quantity[y]), legend=tag == "a")
    fig.suptitle(
        "Fig. 1: PC model in fixed grip ($w$ = 27 mJ/m$^2$, $R$ = 9.42 mm, $E^*$ = 2.133 MPa, "
        rf"$\lambda$ = 0.0023, $\mu$ = {mu:.0f})"
    )
    return fig


def _asperity_history(delta: float, dts: np.ndarray):
    """a, P, T along delta_T at fixed delta: stick (PC) then slide (Hertz) or out of contact."""
    a, p, t = _pc_state(delta, dts)
    lost = ~np.isfinite(a)
    if delta >= 0:
        a = np.where(lost, hertz_contact_radius(delta, R1), a)
        p = np.where(lost, hertz_normal_load(delta, R1, E1), p)
        t = np.where(lost, hertz_sliding_tangential_load(delta, R1, TAU1), t)
    else:
        a, p, t = (np.where(lost, 0.0, x) for x in (a, p, t))
    return a, p, t


#: Fig. 2's two paths through the status map: dimensionless indentation and colour.
FIG2_PATHS = ((-0.5, "tab:blue"), (3.0, "tab:red"))


def _draw_status_map(ax: Axes, g: h5py.Group) -> None:
    """Fig. 2(a): stick / slide / out-of-contact regions in (delta_T~, delta~), to ``g`` too."""
    dtt = np.linspace(0.0, 100.0, 500)
    bound = dimensionless_unstable_boundary(dtt, LAM1)
    dd, tt = np.meshgrid(np.linspace(-3.0, 8.0, 400), dtt, indexing="ij")
    status = asperity_status(dd, tt, LAM1)
    ax.contourf(
        tt, dd, status, levels=[-0.5, 0.5, 1.5, 2.5], colors=["#dddddd", "#9ecae1", "#fdae6b"]
    )
    ax.plot(dtt, bound, "k-", label=r"$\tilde\delta_{\min}^{\mathrm{PC}}$")
    ax.axhline(0.0, color="k", ls="--", lw=0.8)
    ax.axhline(JUMP_OFF_DIMENSIONLESS, color="k", ls=":", lw=0.8, label="JKR jump-off")
    for tilde, color in FIG2_PATHS:
        ax.axhline(tilde, color=color, lw=1.2, label=rf"path of (b-d), $\tilde\delta$ = {tilde:g}")
    ax.set_xlim(dtt[0], dtt[-1])
    ax.set_ylim(-3.0, 8.0)
    ax.text(5, 1.0, "stick")
    ax.text(88.0, 1.0, "slide")
    ax.text(70, -2.4, "out of contact")
    ax.set_xlabel(r"$\tilde\delta_T$ (dimensionless)")
    ax.set_ylabel(r"$\tilde\delta$ (dimensionless)")
    ax.set_title("(a) status map")
    ax.legend(fontsize=8, loc="upper left")
    write_dataset(g, "map_delta_t_tilde", dtt, "1")
    write_dataset(g, "map_delta_tilde", dd[:, 0], "1")
    write_dataset(g, "map_status", status, "1 (0 out, 1 stick, 2 slide)")
    write_dataset(g, "boundary_delta_tilde", bound, "1")


def _fig2_histories(g: h5py.Group) -> list[Curve]:
    """A, P, T along delta_T on Fig. 2's two paths, written to ``g`` as well."""
    histories = []
    for tilde, _ in FIG2_PATHS:
        delta = float(from_dimensionless(tilde, 0.0, R1, W1, E1)[0])
        dt_max = pc_max_tangential_displacement(delta, R1, W1, E1, LAM1)
        dts = np.linspace(0.0, 1.6 * dt_max, 800)
        a, p, t = _asperity_history(delta, dts)
        histories.append({"dt": dts, "area": np.pi * a**2, "p": p, "t": t})
        s = g.create_group(f"delta_tilde_{tilde:g}")
        write_dataset(s, "indentation", delta, "m")
        write_dataset(s, "tangential_displacement", dts, "m")
        write_dataset(s, "contact_area", np.pi * a**2, "m^2")
        write_dataset(s, "normal_load", p, "N")
        write_dataset(s, "tangential_load", t, "N")
    return histories


def figure_2(h5: h5py.Group) -> Figure:
    """Fig. 2: status map (a) and A, P, T vs delta_T at delta~ = -0.5 and 3 (b-d).

    The plotted data go to the new group ``h5["fig2"]`` (SI units; the map dimensionless);
    returns the drawn Figure.
    """
    g = h5.create_group("fig2")
    g.attrs["parameters"] = f"w={W1} J/m^2, R={R1} m, E*={E1} Pa, lambda={LAM1}, tau0={TAU1} Pa"
    g.attrs["xi"] = scale_factor(R1, W1, E1)
    fig = new_figure(*FIGSIZE)
    axes = fig.subplots(2, 2)
    _draw_status_map(axes[0, 0], g)
    histories = _fig2_histories(g)
    u_dt = _units(histories, "dt", "m")
    panels = [
        (axes[0, 1], "area", _units(histories, "area", "m", 2), r"contact area $A = \pi a^2$"),
        (axes[1, 0], "p", _units(histories, "p", "N"), "normal load $P$"),
        (axes[1, 1], "t", _units(histories, "t", "N"), "tangential load $T$"),
    ]
    for (ax, key, unit, quantity), tag in zip(panels, "bcd", strict=True):
        for h, (tilde, color) in zip(histories, FIG2_PATHS, strict=True):
            ax.plot(u_dt(h["dt"]), unit(h[key]), color=color, label=rf"$\tilde\delta$ = {tilde:g}")
        _finish_panel(ax, tag, u_dt.label(DELTA_T), unit.label(quantity))
    fig.suptitle(
        "Fig. 2: status map and single-asperity histories\n($w$ = 27 mJ/m$^2$, $R$ = 9.42 mm, "
        rf"$E^*$ = 2.133 MPa, $\lambda$ = 0.0023, $\tau_0$ = 0.43 MPa, "
        rf"$\mu$ = {tabor_parameter(R1, W1, E1):.0f})"
    )
    return fig


def _write_curve(g: h5py.Group, c: ShearCurve) -> None:
    for name, unit in (
        ("tangential_displacement", "m"),
        ("tangential_force", "N"),
        ("normal_force", "N"),
        ("real_area", "m^2"),
        ("n_contact", "1"),
        ("n_stick", "1"),
        ("n_slip", "1"),
        ("tangential_force_stick", "N"),
        ("tangential_force_slip", "N"),
        ("normal_force_stick", "N"),
        ("normal_force_slip", "N"),
        ("real_area_stick", "m^2"),
        ("real_area_slip", "m^2"),
        ("separation", "m"),
    ):
        write_dataset(g, name, getattr(c, name), unit)
    write_dataset(g, "static_friction", c.static_friction, "N")
    write_dataset(g, "sliding_friction", c.sliding_friction, "N")
    write_dataset(g, "sliding_displacement", c.sliding_displacement, "m")


#: Fig. 4's panels: (total, stick part, slip part) field names, quantity, SI base unit, power.
SHEAR_PANELS = (
    (("normal_force", "normal_force_stick", "normal_force_slip"), "normal load $F_z$", "N", 1),
    (("n_contact", "n_stick", "n_slip"), "contacting asperities", "", 0),
    (("real_area", "real_area_stick", "real_area_slip"), "real contact area $A_r$", "m", 2),
    (
        ("tangential_force", "tangential_force_stick", "tangential_force_slip"),
        "tangential load $F_x$",
        "N",
        1,
    ),
)


def _panel_unit(arrays: Sequence[np.ndarray | float], base: str, power: int) -> DisplayUnit:
    """The display unit of one panel (identity for counts)."""
    if power == 0:
        return DisplayUnit(1.0, base)
    return display_unit(np.concatenate([np.ravel(a) for a in arrays]), base, power)


def draw_shear_curve(fig: Figure, curve: ShearCurve, *, title: str | None = None) -> Figure:
    """Draw the paper's Fig. 4 for ``curve`` on ``fig``: four panels against delta_T.

    (a) normal load F_z, (b) number of contacting asperities, (c) real contact area A_r,
    (d) tangential load F_x, each as the total (solid) and its stick (dotted) and sliding
    (dashed) parts: the first and second integrals of E:NewFormulation_Fy, E:NewFormulation_Fx
    and E:NewFormulation_Ar (paper, Section 4). Axis units carry the SI prefix that suits the
    data (um, mN, mm^2, ...).

    Parameters
    ----------
    fig : Figure
        A blank :class:`matplotlib.figure.Figure` (for example
        ``asperity.plotting.new_figure(10, 8)`` or ``matplotlib.pyplot.figure()``); a 2 x 2
        grid of axes is added to it.
    curve : ShearCurve
        The shear response (SI units). Any object with the same array attributes will do:
        ``tangential_displacement`` (m), ``normal_force[_stick|_slip]`` (N),
        ``n_contact``/``n_stick``/``n_slip``, ``real_area[_stick|_slip]`` (m^2) and
        ``tangential_force[_stick|_slip]`` (N).
    title : str, optional
        The figure's title.

    Returns
    -------
    Figure
        ``fig``, drawn on (save it with ``fig.savefig`` or :func:`asperity.plotting.save_figure`).
    """
    u_dt = display_unit(curve.tangential_displacement, "m")
    x = u_dt(curve.tangential_displacement)
    axes = fig.subplots(2, 2)
    for ax, (fields, quantity, base, power), tag in zip(
        axes.flat, SHEAR_PANELS, "abcd", strict=True
    ):
        total, stick, slip = (np.asarray(getattr(curve, name), dtype=float) for name in fields)
        unit = _panel_unit([total, stick, slip], base, power)
        ax.plot(x, unit(total), "k-", label="total")
        ax.plot(x, unit(stick), "b:", label="stick")
        ax.plot(x, unit(slip), "r--", label="sliding")
        _finish_panel(ax, tag, u_dt.label(DELTA_T), unit.label(quantity))
    if title:
        fig.suptitle(title)
    return fig


def figure_4(h5: h5py.Group) -> Figure:
    """Fig. 4: F_z, counts, A_r, F_x vs delta_T with stick (dotted) and slip (dashed) parts.

    The caption's parameters through :func:`draw_shear_curve`; the curve goes to the new group
    ``h5["fig4"]`` (SI units); returns the drawn Figure.
    """
    c = shear_curve(Material(**BASE), ROUGH, AREA, LOAD, np.linspace(0.0, 14e-6, 281))
    g = h5.create_group("fig4")
    g.attrs["parameters"] = f"{BASE}, {ROUGH}, A_n={AREA} m^2, F_z={LOAD} N"
    _write_curve(g, c)
    title = (
        r"Fig. 4: $w$ = 40 mJ/m$^2$, $\lambda$ = 0.2, $\tau_0$ = 0.13 MPa, $F_z$ = 3.1 N "
        rf"($\mu$ = {c.tabor_parameter:.0f})"
    )
    return draw_shear_curve(new_figure(*FIGSIZE), c, title=title)


def _full_curve(material: Material, load: float) -> ShearCurve:
    probe = shear_curve(material, ROUGH, AREA, load, np.linspace(0.0, 14e-6, 15))
    end = 1.4 * probe.sliding_displacement if np.isfinite(probe.sliding_displacement) else 14e-6
    return shear_curve(material, ROUGH, AREA, load, np.linspace(0.0, end, 301))


#: Fig. 5(a-c): the parameter varied, its values and its legend entry (value in display units).
FIG5_STUDIES = (
    ("work_of_adhesion", FIG5_W, "$w$ = {:g} mJ/m$^2$", 1e3),
    ("mode_mixity", FIG5_LAMBDA, r"$\lambda$ = {:g}", 1.0),
    ("shear_strength", FIG5_TAU, r"$\tau_0$ = {:g} MPa", 1e-6),
)


def _fig5_studies(g: h5py.Group) -> list[list[tuple[str, ShearCurve]]]:
    """Fig. 5(a-c)'s curves, one list of (legend, curve) per varied parameter, to ``g`` too."""
    studies = []
    for key, values, fmt, k in FIG5_STUDIES:
        sg = g.create_group(key)
        cases = []
        for j, v in enumerate(values):
            c = _full_curve(Material(**{**BASE, key: v}), LOAD)
            cases.append((fmt.format(v * k), c))
            _write_curve(sg.create_group(f"case_{j}"), c)
            sg[f"case_{j}"].attrs[key] = v
        studies.append(cases)
    return studies


def _fig5_loads(g: h5py.Group) -> tuple[list[ShearCurve], list[float]]:
    """Fig. 5(d)'s curves (one per F_z) and relative static peaks, written to ``g`` too."""
    sg = g.create_group("normal_load")
    curves, ratios = [], []
    for j, f in enumerate(FIG5_LOAD):
        c = _full_curve(Material(**BASE), f)
        curves.append(c)
        _write_curve(sg.create_group(f"case_{j}"), c)
        sg[f"case_{j}"].attrs["normal_load"] = f
        ratios.append(c.static_friction / c.sliding_friction - 1.0)
    write_dataset(sg, "normal_loads", FIG5_LOAD, "N")
    write_dataset(sg, "relative_static_peak", ratios, "1")
    return curves, ratios


def _draw_load_study(ax: Axes, curves: list[ShearCurve], ratios: list[float]) -> None:
    """Fig. 5(d): F_x / F_sliding against delta_T per F_z, and the static peak in an inset."""
    u_dt = _panel_unit([c.tangential_displacement for c in curves], "m", 1)
    for c, f in zip(curves, FIG5_LOAD, strict=True):
        ax.plot(
            u_dt(c.tangential_displacement),
            c.tangential_force / c.sliding_friction,
            label=f"$F_z$ = {f:g} N",
        )
    _finish_panel(ax, "d", u_dt.label(DELTA_T), r"$F_x / F_{\mathrm{sliding}}$", legend=False)
    ax.legend(fontsize=8, loc="lower right")
    inset = ax.inset_axes((0.58, 0.45, 0.38, 0.26))
    inset.plot(FIG5_LOAD, ratios, "ko-", ms=3)
    inset.set_xlabel("$F_z$ (N)", fontsize=7, labelpad=1)
    inset.set_ylabel(r"$F_{\mathrm{static}} / F_{\mathrm{sliding}} - 1$", fontsize=7)
    inset.tick_params(labelsize=6)


def figure_5(h5: h5py.Group) -> Figure:
    """Fig. 5: A_r/A_n vs F_x for varying w, lambda, tau0; F_x/F_sliding vs delta_T for F_z.

    Every curve goes to the new group ``h5["fig5"]`` (SI units); returns the drawn Figure.
    """
    g = h5.create_group("fig5")
    g.attrs["parameters"] = (
        f"base {BASE}, {ROUGH}, A_n={AREA} m^2, F_z={LOAD} N; varied: "
        f"w={FIG5_W}, lambda={FIG5_LAMBDA}, tau0={FIG5_TAU}, "
        f"F_z={FIG5_LOAD}"
    )
    fig = new_figure(*FIGSIZE)
    axes = fig.subplots(2, 2)
    studies = _fig5_studies(g)
    u_fx = _panel_unit([c.tangential_force for cases in studies for _, c in cases], "N", 1)
    for ax, cases, tag in zip(axes.flat, studies, "abc", strict=False):
        for label, c in cases:
            ax.plot(u_fx(c.tangential_force), 100.0 * c.real_area / AREA, label=label)
        _finish_panel(ax, tag, u_fx.label("tangential load $F_x$"), "$A_r / A_n$ (%)")
    _draw_load_study(axes[1, 1], *_fig5_loads(g))
    mu_min = tabor_parameter(ROUGH.summit_radius, min(FIG5_W), BASE["e_star"])
    fig.suptitle(
        rf"Fig. 5: effects of $w$, $\lambda$, $\tau_0$ and $F_z$ (other parameters as Fig. 4; "
        rf"min($\mu$) = {mu_min:.0f})"
    )
    return fig


#: The figures of ``asperity figures``: file name (without suffix) and the function drawing it.
FIGURES = {
    "fig1_pc_single_asperity": figure_1,
    "fig2_status_map": figure_2,
    "fig4_shear_curve": figure_4,
    "fig5_parameter_study": figure_5,
}


def write_all_figures(out: str | Path, *, dpi: int = DPI) -> list[Path]:
    """Write Figs. 1, 2, 4, 5 (PNG) and their data, ``statmodel_figures.h5``, into ``out``.

    Parameters
    ----------
    out : str or Path
        Output directory (created if missing).
    dpi : int
        Resolution of the PNG files, dots per inch.

    Returns
    -------
    list of Path
        The four PNG files, then the HDF5 file (every dataset with a ``units`` attribute).
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    h5_path = out / "statmodel_figures.h5"
    paths = []
    with new_file(h5_path) as h5:  # atomic: a full disk leaves nothing partial
        h5.attrs["source"] = "asperity.statmodel.figures (Xu et al. 2022, Figs. 1, 2, 4, 5)"
        for name, draw in FIGURES.items():
            paths.append(save_figure(draw(h5), out / f"{name}.png", dpi=dpi))
    return [*paths, h5_path]
