"""The paper's Figs. 1, 2, 4 and 5 from this package, as PNG (150 dpi) plus one HDF5 data file.

Parameters are the captions' (Fig. 1/2: w = 27 mJ/m^2, R = 9.42 mm, E* = 2.133 MPa,
lambda = 0.0023, tau0 = 0.43 MPa; Fig. 4/5 base: w = 40 mJ/m^2, lambda = 0.2, tau0 = 0.13 MPa,
F_z = 3.1 N, A_n = 700 mm^2, eta = 652.1 mm^-2, sigma_s = 0.032 mm, R = 0.041 mm). Values the
captions do not list are chosen here and recorded in the HDF5 file:

* Fig. 1: indentations delta in {0.005, 0.01, 0.02, 0.04, 0.08} mm;
* Fig. 5: w in {15, 25, 40, 60} mJ/m^2, lambda in {0.05, 0.2, 0.3, 0.9},
  tau0 in {0.05, 0.13, 0.3, 0.5} MPa, F_z in {0.5, 1, 3.1, 6, 10} N.

Every HDF5 dataset has a ``units`` attribute.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from asperity.statmodel.hertz import (  # noqa: E402
    hertz_contact_radius,
    hertz_normal_load,
    hertz_sliding_tangential_load,
)
from asperity.statmodel.papangelo_ciavarella import (  # noqa: E402
    pc_contact_radius,
    pc_fold_radius,
    pc_max_tangential_displacement,
    pc_normal_load,
)
from asperity.statmodel.parameters import Material, Roughness, tabor_parameter  # noqa: E402
from asperity.statmodel.results_io import write_dataset  # noqa: E402
from asperity.statmodel.shear import shear_curve  # noqa: E402
from asperity.statmodel.status_map import (  # noqa: E402
    JUMP_OFF_DIMENSIONLESS,
    asperity_status,
    dimensionless_unstable_boundary,
    from_dimensionless,
    scale_factor,
)

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


def _pc_state(delta: float, dts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = pc_contact_radius(delta, dts, R1, W1, E1, LAM1)
    p = pc_normal_load(delta, dts, R1, W1, E1, LAM1)
    t = 4.0 / 3.0 * E1 * a * dts
    return a, p, t


def _save(fig: plt.Figure, path: Path) -> Path:
    """Lay out, write at DPI (PNG) and close a figure; returns its path."""
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def figure_1(out: Path, h5: h5py.File) -> Path:
    """Fig. 1: P, T, A vs delta_T and A vs T for several delta (fixed grip, PC model)."""
    g = h5.create_group("fig1")
    g.attrs["parameters"] = (
        f"w={W1} J/m^2, R={R1} m, E*={E1} Pa, lambda={LAM1}, mu={tabor_parameter(R1, W1, E1):.0f}"
    )
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    for j, delta in enumerate(FIG1_DELTAS):
        dt_max = pc_max_tangential_displacement(delta, R1, W1, E1, LAM1)
        dts = dt_max * (1.0 - np.linspace(0.0, 1.0, 400) ** 2)[::-1]
        a, p, t = _pc_state(delta, dts)
        area = np.pi * a**2
        lab = f"delta = {delta * 1e3:g} mm"
        axes[0, 0].plot(dts * 1e3, p * 1e3, label=lab)
        axes[0, 1].plot(dts * 1e3, t * 1e3, label=lab)
        axes[1, 0].plot(dts * 1e3, area * 1e6, label=lab)
        axes[1, 1].plot(t * 1e3, area * 1e6, label=lab)
        s = g.create_group(f"delta_{j}")
        write_dataset(s, "indentation", delta, "m")
        write_dataset(s, "tangential_displacement", dts, "m")
        write_dataset(s, "normal_load", p, "N")
        write_dataset(s, "tangential_load", t, "N")
        write_dataset(s, "contact_area", area, "m^2")
    # unstable boundary (dash-dotted): the fold state for a sweep of delta
    deltas = np.linspace(FIG1_DELTAS[0] * 0.5, FIG1_DELTAS[-1] * 1.1, 200)
    dtb = pc_max_tangential_displacement(deltas, R1, W1, E1, LAM1)
    ab = pc_fold_radius(dtb, R1, W1, E1, LAM1)
    pb = 4 * E1 * ab**3 / (3 * R1) - np.sqrt(
        np.maximum(8 * np.pi * E1 * ab**3 * W1 - 16 / 9 * LAM1 * E1**2 * ab**2 * dtb**2, 0)
    )
    tb = 4 / 3 * E1 * ab * dtb
    axes[0, 0].plot(dtb * 1e3, pb * 1e3, "k-.", label="unstable boundary")
    axes[0, 1].plot(dtb * 1e3, tb * 1e3, "k-.", label="unstable boundary")
    axes[1, 0].plot(dtb * 1e3, np.pi * ab**2 * 1e6, "k-.", label="unstable boundary")
    axes[1, 1].plot(tb * 1e3, np.pi * ab**2 * 1e6, "k-.", label="unstable boundary")
    b = g.create_group("unstable_boundary")
    write_dataset(b, "indentation", deltas, "m")
    write_dataset(b, "tangential_displacement", dtb, "m")
    write_dataset(b, "normal_load", pb, "N")
    write_dataset(b, "tangential_load", tb, "N")
    write_dataset(b, "contact_area", np.pi * ab**2, "m^2")
    for ax, (xl, yl), tag in zip(
        axes.flat,
        [
            ("delta_T (mm)", "P (mN)"),
            ("delta_T (mm)", "T (mN)"),
            ("delta_T (mm)", "A = pi a^2 (mm^2)"),
            ("T (mN)", "A (mm^2)"),
        ],
        "abcd",
        strict=False,
    ):
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_title(f"({tag})")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(
        "Fig. 1: PC model in fixed grip (w = 27 mJ/m^2, R = 9.42 mm, E* = 2.133 MPa, "
        f"lambda = 0.0023, mu = {tabor_parameter(R1, W1, E1):.0f})"
    )
    return _save(fig, out / "fig1_pc_single_asperity.png")


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


def figure_2(out: Path, h5: h5py.File) -> Path:
    """Fig. 2: status map (a) and A, P, T vs delta_T at delta~ = -0.5 and 3 (b-d)."""
    g = h5.create_group("fig2")
    g.attrs["parameters"] = f"w={W1} J/m^2, R={R1} m, E*={E1} Pa, lambda={LAM1}, tau0={TAU1} Pa"
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    ax = axes[0, 0]
    dtt = np.linspace(0.0, 100.0, 500)
    bound = dimensionless_unstable_boundary(dtt, LAM1)
    dd, tt = np.meshgrid(np.linspace(-3.0, 8.0, 400), dtt, indexing="ij")
    status = asperity_status(dd, tt, LAM1)
    ax.contourf(
        tt, dd, status, levels=[-0.5, 0.5, 1.5, 2.5], colors=["#dddddd", "#9ecae1", "#fdae6b"]
    )
    ax.plot(dtt, bound, "k-", label="delta~_min^PC")
    ax.axhline(0.0, color="k", ls="--", lw=0.8)
    ax.axhline(JUMP_OFF_DIMENSIONLESS, color="k", ls=":", lw=0.8, label="JKR jump-off")
    for tilde, color in ((-0.5, "tab:blue"), (3.0, "tab:red")):
        ax.axhline(tilde, color=color, lw=1.2, label=f"path of (b-d), delta~ = {tilde:g}")
    ax.set_xlim(dtt[0], dtt[-1])
    ax.set_ylim(-3.0, 8.0)
    ax.text(5, 4.5, "stick")
    ax.text(88.0, 1.0, "slide")
    ax.text(70, -2.4, "out of contact")
    ax.set_xlabel("delta_T~ (dimensionless)")
    ax.set_ylabel("delta~ (dimensionless)")
    ax.set_title("(a) status map")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.18, 1.0))
    write_dataset(g, "map_delta_t_tilde", dtt, "1")
    write_dataset(g, "map_delta_tilde", dd[:, 0], "1")
    write_dataset(g, "map_status", status, "1 (0 out, 1 stick, 2 slide)")
    write_dataset(g, "boundary_delta_tilde", bound, "1")
    xi = scale_factor(R1, W1, E1)
    for tilde, color in ((-0.5, "tab:blue"), (3.0, "tab:red")):
        delta = float(from_dimensionless(tilde, 0.0, R1, W1, E1)[0])
        dt_max = pc_max_tangential_displacement(delta, R1, W1, E1, LAM1)
        dts = np.linspace(0.0, 1.6 * dt_max, 800)
        a, p, t = _asperity_history(delta, dts)
        lab = f"delta~ = {tilde:g}"
        axes[0, 1].plot(dts * 1e3, np.pi * a**2 * 1e6, color=color, label=lab)
        axes[1, 0].plot(dts * 1e3, p * 1e3, color=color, label=lab)
        axes[1, 1].plot(dts * 1e3, t * 1e3, color=color, label=lab)
        s = g.create_group(f"delta_tilde_{tilde:g}")
        write_dataset(s, "indentation", delta, "m")
        write_dataset(s, "tangential_displacement", dts, "m")
        write_dataset(s, "contact_area", np.pi * a**2, "m^2")
        write_dataset(s, "normal_load", p, "N")
        write_dataset(s, "tangential_load", t, "N")
    g.attrs["xi"] = xi
    for ax, yl, tag in zip(
        [axes[0, 1], axes[1, 0], axes[1, 1]],
        ["A = pi a^2 (mm^2)", "P (mN)", "T (mN)"],
        "bcd",
        strict=False,
    ):
        ax.set_xlabel("delta_T (mm)")
        ax.set_ylabel(yl)
        ax.set_title(f"({tag})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(
        "Fig. 2: status map and single-asperity histories\n(w = 27 mJ/m^2, R = 9.42 mm, "
        f"E* = 2.133 MPa, lambda = 0.0023, tau0 = 0.43 MPa, mu = {tabor_parameter(R1, W1, E1):.0f})"
    )
    return _save(fig, out / "fig2_status_map.png")


def _write_curve(g: h5py.Group, c) -> None:
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


def figure_4(out: Path, h5: h5py.File) -> Path:
    """Fig. 4: F_z, counts, A_r, F_x vs delta_T with stick (dotted) and slip (dashed) parts."""
    c = shear_curve(Material(**BASE), ROUGH, AREA, LOAD, np.linspace(0.0, 14e-6, 281))
    g = h5.create_group("fig4")
    g.attrs["parameters"] = f"{BASE}, {ROUGH}, A_n={AREA} m^2, F_z={LOAD} N"
    _write_curve(g, c)
    x = c.tangential_displacement * 1e6
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    panels = [
        (axes[0, 0], c.normal_force, c.normal_force_stick, c.normal_force_slip, 1.0, "F_z (N)"),
        (axes[0, 1], c.n_contact, c.n_stick, c.n_slip, 1.0, "number of asperities"),
        (axes[1, 0], c.real_area, c.real_area_stick, c.real_area_slip, 1e6, "A_r (mm^2)"),
        (
            axes[1, 1],
            c.tangential_force,
            c.tangential_force_stick,
            c.tangential_force_slip,
            1.0,
            "F_x (N)",
        ),
    ]
    for (ax, tot, st, sl, k, yl), tag in zip(panels, "abcd", strict=False):
        ax.plot(x, tot * k, "k-", label="total")
        ax.plot(x, st * k, "b:", label="stick")
        ax.plot(x, sl * k, "r--", label="slide")
        ax.set_xlabel("delta_T (um)")
        ax.set_ylabel(yl)
        ax.set_title(f"({tag})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(
        f"Fig. 4: w = 40 mJ/m^2, lambda = 0.2, tau0 = 0.13 MPa, F_z = 3.1 N "
        f"(mu = {c.tabor_parameter:.0f})"
    )
    return _save(fig, out / "fig4_shear_curve.png")


def _full_curve(material: Material, load: float):
    probe = shear_curve(material, ROUGH, AREA, load, np.linspace(0.0, 14e-6, 15))
    end = 1.4 * probe.sliding_displacement if np.isfinite(probe.sliding_displacement) else 14e-6
    return shear_curve(material, ROUGH, AREA, load, np.linspace(0.0, end, 301))


def figure_5(out: Path, h5: h5py.File) -> Path:
    """Fig. 5: A_r/A_n vs F_x for varying w, lambda, tau0; F_x/F_sliding vs delta_T for F_z."""
    g = h5.create_group("fig5")
    g.attrs["parameters"] = (
        f"base {BASE}, {ROUGH}, A_n={AREA} m^2, F_z={LOAD} N; varied: "
        f"w={FIG5_W}, lambda={FIG5_LAMBDA}, tau0={FIG5_TAU}, "
        f"F_z={FIG5_LOAD}"
    )
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    studies = [
        (axes[0, 0], "work_of_adhesion", FIG5_W, "w = {:g} mJ/m^2", 1e3),
        (axes[0, 1], "mode_mixity", FIG5_LAMBDA, "lambda = {:g}", 1.0),
        (axes[1, 0], "shear_strength", FIG5_TAU, "tau0 = {:g} MPa", 1e-6),
    ]
    for (ax, key, values, fmt, k), tag in zip(studies, "abc", strict=False):
        sg = g.create_group(key)
        for j, v in enumerate(values):
            c = _full_curve(Material(**{**BASE, key: v}), LOAD)
            ax.plot(c.tangential_force, c.real_area / AREA, label=fmt.format(v * k))
            _write_curve(sg.create_group(f"case_{j}"), c)
            sg[f"case_{j}"].attrs[key] = v
        ax.set_xlabel("F_x (N)")
        ax.set_ylabel("A_r / A_n")
        ax.set_title(f"({tag})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    ax = axes[1, 1]
    sg = g.create_group("normal_load")
    ratios = []
    for j, f in enumerate(FIG5_LOAD):
        c = _full_curve(Material(**BASE), f)
        ax.plot(
            c.tangential_displacement * 1e6,
            c.tangential_force / c.sliding_friction,
            label=f"F_z = {f:g} N",
        )
        _write_curve(sg.create_group(f"case_{j}"), c)
        sg[f"case_{j}"].attrs["normal_load"] = f
        ratios.append(c.static_friction / c.sliding_friction - 1.0)
    write_dataset(sg, "normal_loads", FIG5_LOAD, "N")
    write_dataset(sg, "relative_static_peak", ratios, "1")
    ax.set_xlabel("delta_T (um)")
    ax.set_ylabel("F_x / F_sliding")
    ax.set_title("(d)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    inset = ax.inset_axes([0.56, 0.47, 0.39, 0.24])
    inset.plot(FIG5_LOAD, ratios, "ko-", ms=3)
    inset.set_xlabel("F_z (N)", fontsize=7)
    inset.set_ylabel("F_static/F_sliding - 1", fontsize=7)
    inset.tick_params(labelsize=6)
    mu_min = tabor_parameter(ROUGH.summit_radius, min(FIG5_W), BASE["e_star"])
    fig.suptitle(
        f"Fig. 5: effects of w, lambda, tau0 and F_z (other parameters as Fig. 4; "
        f"min(mu) = {mu_min:.0f})"
    )
    return _save(fig, out / "fig5_parameter_study.png")


def write_all_figures(out: Path) -> list[Path]:
    """Write Figs. 1, 2, 4, 5 (PNG) and ``statmodel_figures.h5`` into directory ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    h5_path = out / "statmodel_figures.h5"
    with h5py.File(h5_path, "w") as h5:
        h5.attrs["source"] = "asperity.statmodel.figures (Xu et al. 2022, Figs. 1, 2, 4, 5)"
        paths = [figure_1(out, h5), figure_2(out, h5), figure_4(out, h5), figure_5(out, h5)]
    return [*paths, h5_path]
