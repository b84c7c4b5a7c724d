"""Figures (PNG, 150 dpi) of every stage, ``report.md`` and the one-screen terminal summary.

The data behind every figure is in ``results.h5`` (same names as the stage records).

Figures written in the output directory:

* ``surface.png`` - stage 1: the levelled height map.
* ``fig12_resolution.png`` - stages 2-4: R, eta, sigma_s against resolution with the paper's
  fits (Fig 12a-c) and A_r/A_n against F_z from the BEM, the statistical model and the
  measurement (Fig 12d).
* ``fig12d_misfit.png`` - stage 4: misfit of the statistical model against resolution.
* ``bem_grid.png`` - stage 3: the grid refinement check and the contact mask.
* ``lambda_fit.png`` - stage 5 (when measured curves are given): misfit against lambda.
* ``fig4_shear.png`` - stage 6: F_z, contact counts, A_r and F_x against delta_T with their
  stick and slip parts, at the heaviest load (Fig 4).
* ``fig13_area_vs_force.png`` - stage 6: A_r/A_n against F_x at every load, the measured
  curves and the constant-shear-strength line F_x = tau0 A_r (Fig 13).
* ``friction_vs_load.png`` - stage 6: static and sliding friction against F_z.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from asperity.pipelines.bem_report import bem_grid_figure, bem_section
from asperity.statmodel.figures import draw_shear_curve

DPI = 150


def _save(fig: Figure, path: Path) -> Path:
    """Lay out and write a figure (no pyplot: nothing global to close)."""
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    return path


def plot_surface(result: Any, path: Path) -> Path:
    """Stage 1: the levelled height map (um) over x, y (mm)."""
    s = result.surface
    fig = Figure(figsize=(5.2, 4.4))
    ax = fig.subplots()
    step = max(1, max(s.nx, s.ny) // 800)
    image = ax.imshow(
        s.heights[::step, ::step].T * 1e6,
        origin="lower",
        cmap="viridis",
        extent=(0, s.lx * 1e3, 0, s.ly * 1e3),
    )
    fig.colorbar(image, ax=ax, label="height (um)")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"levelled surface, {s.nx} x {s.ny} px, {s.dx * 1e6:.3g} um")
    return _save(fig, path)


def plot_resolution(result: Any, path: Path) -> Path:
    """Fig 12: R, eta, sigma_s against resolution with fits; A_r/A_n against F_z."""
    scan, res, bem = result.scan, result.resolution, result.bem
    a_n = result.config.loading.nominal_area
    um = np.asarray(scan.resolution) * 1e6
    fig = Figure(figsize=(10, 8))
    axes = fig.subplots(2, 2)
    ax = axes[0, 0]
    ax.plot(um, np.asarray(scan.summit_radius) * 1e3, "o", label="map")
    fit_r = scan.radius_intercept + scan.radius_slope * np.asarray(scan.resolution)
    ax.plot(um, fit_r * 1e3, "-", label=f"linear fit, slope {scan.radius_slope:.3g}")
    ax.set_xlabel("resolution (um)")
    ax.set_ylabel("mean summit radius R (mm)")
    ax.set_title("(a)")
    ax.legend()
    ax = axes[0, 1]
    ax.loglog(um, np.asarray(scan.asperity_density) * 1e-6, "o", label="map")
    fit_eta = scan.density_prefactor * np.asarray(scan.resolution) ** scan.density_exponent
    ax.loglog(um, fit_eta * 1e-6, "-", label=f"power law, exponent {scan.density_exponent:.3g}")
    ax.set_xlabel("resolution (um)")
    ax.set_ylabel("asperity density eta (1/mm^2)")
    ax.set_title("(b)")
    ax.legend()
    ax = axes[1, 0]
    ax.plot(um, np.asarray(scan.summit_height_rms) * 1e3, "o")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("resolution (um)")
    ax.set_ylabel("rms summit height sigma_s (mm)")
    ax.set_title("(c)")
    ax = axes[1, 1]
    loads = res.normal_load
    if bem is not None:
        ax.plot(loads, bem.contact_fraction, "s", mfc="none", label="BEM, non-adhesive")
        if bem.contact_fraction_adhesive is not None:
            ax.plot(loads, bem.contact_fraction_adhesive, "s", label="BEM, adhesive")
    n = len(res.stride)
    picks = sorted({0, res.index, n - 1})
    for i in picks:
        if np.all(np.isfinite(res.real_area[i])):
            style = "-" if i == res.index else ":"
            label = f"model, {res.resolution[i] * 1e6:.3g} um"
            if i == res.index:
                label += " (effective)"
            ax.plot(loads, res.real_area[i] / a_n, style, label=label)
    if res.measured is not None:
        ax.plot(res.measured.normal_load, res.measured.real_area / a_n, "o", label="measured")
    ax.set_xlabel("normal load F_z (N)")
    ax.set_ylabel("A_r / A_n")
    ax.set_title("(d)")
    ax.legend(fontsize=8)
    return _save(fig, path)


def plot_misfit(result: Any, path: Path) -> Path:
    """Stage 4: the misfit curve that chose the effective resolution."""
    res = result.resolution
    fig = Figure(figsize=(6, 4))
    ax = fig.subplots()
    um = res.resolution * 1e6
    if np.isfinite(res.misfit_bem).any():
        ax.plot(um, res.misfit_bem, "o-", label="against BEM")
    if res.misfit_measured is not None:
        ax.plot(um, res.misfit_measured, "s-", label="against measured A_r(F_z)")
    ax.axvline(
        res.effective_resolution * 1e6,
        color="k",
        ls="--",
        label=f"effective {res.effective_resolution * 1e6:.3g} um",
    )
    ax.set_xlabel("resolution (um)")
    ax.set_ylabel("rms of ln(A_model / A_reference)")
    ax.set_yscale("log")
    ax.legend()
    return _save(fig, path)


def plot_bem_grid(result: Any, path: Path) -> Path:
    """Stage 3: the refinement curve, its error against the finest grid, the contact mask."""
    return _save(bem_grid_figure(result), path)


def plot_lambda_fit(result: Any, path: Path) -> Path:
    """Stage 5: the misfit of the coarse lambda scan and the fitted value."""
    fit = result.mode_mixity.fit
    fig = Figure(figsize=(6, 4))
    ax = fig.subplots()
    ax.loglog(fit.grid_mode_mixity, fit.grid_residual_rms, "o-", label="coarse scan")
    ax.axvline(
        fit.mode_mixity,
        color="k",
        ls="--",
        label=f"fit {fit.mode_mixity:.3g} +/- {fit.mode_mixity_std:.2g}",
    )
    ax.axvspan(
        max(fit.mode_mixity - fit.mode_mixity_std, 1e-12),
        fit.mode_mixity + fit.mode_mixity_std,
        color="0.85",
    )
    ax.set_xlabel("mode mixity lambda")
    ax.set_ylabel("rms of (A_model - A_measured) / max A_measured")
    ax.legend()
    return _save(fig, path)


def plot_shear(result: Any, path: Path) -> Path:
    """Fig 4 at the heaviest load, drawn by the one Fig-4 plotter, statmodel.draw_shear_curve."""
    fr = result.friction
    i = int(np.argmax(fr.normal_load))
    curve = SimpleNamespace(**fr.curve_arrays(i))  # the per-step arrays (SI) at that load
    title = f"$F_z$ = {fr.normal_load[i]:.3g} N, $\\lambda$ = {fr.mode_mixity:.3g}"
    fig = draw_shear_curve(Figure(figsize=(10, 7.5)), curve, title=title)
    return _save(fig, path)


def plot_area_vs_force(result: Any, path: Path) -> Path:
    """Fig 13: A_r/A_n against F_x at each load, measured curves, and tau0 A_r."""
    fr = result.friction
    a_n = fr.nominal_area
    fig = Figure(figsize=(7, 5))
    ax = fig.subplots()
    colors = colormaps["viridis"](np.linspace(0, 0.9, len(fr.normal_load)))
    for i, f in enumerate(fr.normal_load):
        fx, ar = fr.tangential_force[i], fr.real_area[i]
        ax.plot(fx, ar / a_n, "--", color=colors[i], label=f"model F_z = {f:.3g} N")
    for curve in result.mode_mixity.curves:
        j = int(np.argmin(np.abs(fr.normal_load - curve.normal_load)))
        ax.plot(curve.tangential_force, curve.real_area / a_n, "-", color=colors[j], lw=1)
    if result.mode_mixity.curves:
        ax.plot([], [], "k-", lw=1, label="measured")
    fmax = np.nanmax(fr.tangential_force)
    line = np.linspace(0, fmax, 50)
    ax.plot(
        line,
        line / max(fr.shear_strength, 1e-300) / a_n,
        "k:",
        lw=1,
        label="F_x = tau0 A_r (constant shear strength)",
    )
    top = np.nanmax(fr.real_area) / a_n
    ax.set_ylim(0, 1.15 * top)
    ax.set_xlabel("tangential load F_x (N)")
    ax.set_ylabel("A_r / A_n")
    ax.legend(fontsize=7)
    return _save(fig, path)


def plot_friction_vs_load(result: Any, path: Path) -> Path:
    """Static and sliding friction against normal load."""
    fr = result.friction
    fig = Figure(figsize=(6, 4))
    ax = fig.subplots()
    ax.plot(fr.normal_load, fr.static_friction, "o-", label="static (peak)")
    ax.plot(fr.normal_load, fr.sliding_friction, "s--", label="sliding")
    ax.set_xlabel("normal load F_z (N)")
    ax.set_ylabel("friction force (N)")
    ax.legend()
    return _save(fig, path)


def write_figures(result: Any, out_dir: Path) -> dict[str, Path]:
    """Write every figure of the job; returns {name: path}."""
    out_dir = Path(out_dir)
    figures = {
        "surface": plot_surface(result, out_dir / "surface.png"),
        "resolution": plot_resolution(result, out_dir / "fig12_resolution.png"),
        "misfit": plot_misfit(result, out_dir / "fig12d_misfit.png"),
        "shear": plot_shear(result, out_dir / "fig4_shear.png"),
        "area_vs_force": plot_area_vs_force(result, out_dir / "fig13_area_vs_force.png"),
        "friction_vs_load": plot_friction_vs_load(result, out_dir / "friction_vs_load.png"),
    }
    if result.bem is not None:
        figures["bem_grid"] = plot_bem_grid(result, out_dir / "bem_grid.png")
    if result.mode_mixity.fit is not None:
        figures["lambda_fit"] = plot_lambda_fit(result, out_dir / "lambda_fit.png")
    return figures


def key_numbers(result: Any) -> list[tuple[str, str]]:
    """(quantity, value with unit) rows of the report's headline table."""
    res, fr, bem, lam = result.resolution, result.friction, result.bem, result.mode_mixity
    r = res.roughness
    rows = [
        (
            "surface",
            f"{result.surface.nx} x {result.surface.ny} px, "
            f"{result.surface.dx * 1e6:.4g} um pixels",
        ),
        (
            "effective resolution",
            f"{res.effective_resolution * 1e6:.4g} um "
            f"(stride {res.effective_stride}, chosen against {res.basis})",
        ),
        ("summit radius R", f"{r.summit_radius * 1e3:.4g} mm"),
        ("asperity density eta", f"{r.asperity_density * 1e-6:.4g} 1/mm^2"),
        ("rms summit height sigma_s", f"{r.summit_height_rms * 1e3:.4g} mm"),
        ("Tabor parameter mu", f"{res.tabor_parameter:.4g}"),
        ("misfit at effective resolution", f"{res.misfit[res.index]:.3g} (rms ln ratio)"),
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
    if bem is None:
        rows.append(("BEM", "not run ([bem] enabled = false): calibrated on the measurement"))
    else:
        rows += [
            (
                "BEM grid",
                f"stride {bem.stride} ({bem.dx * 1e6:.4g} um), A_r {bem.grid_error:.2%} from the "
                f"finest grid solved; {bem.boundary} boundary",
            ),
            ("BEM solves converged", f"{int(np.sum(bem.converged))} / {bem.converged.size}"),
        ]
    rows += [
        ("statmodel quadrature", fr.quadrature_reason),
        ("shear curves converged", f"{int(np.sum(fr.converged))} / {fr.converged.size}"),
    ]
    return rows


def load_table(result: Any) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the per-load table."""
    fr, bem, res = result.friction, result.bem, result.resolution
    a_n = fr.nominal_area
    header = [
        "F_z (N)",
        "A_r/A_n BEM",
        "A_r/A_n BEM adh.",
        "A_r/A_n model",
        "static F_x (N)",
        "sliding F_x (N)",
        "delta_T slide (um)",
    ]
    rows = []
    plain = None if bem is None else bem.contact_fraction
    adh = None if bem is None else bem.contact_fraction_adhesive
    for i, f in enumerate(fr.normal_load):
        rows.append(
            [
                f"{f:.4g}",
                "-" if plain is None else f"{plain[i]:.4g}",
                "-" if adh is None else f"{adh[i]:.4g}",
                f"{res.real_area[res.index, i] / a_n:.4g}",
                f"{fr.static_friction[i]:.4g}",
                f"{fr.sliding_friction[i]:.4g}",
                f"{fr.sliding_displacement[i] * 1e6:.4g}",
            ]
        )
    return header, rows


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def write_report(result: Any, out_dir: str | Path) -> Path:
    """Write the figures and ``report.md`` (key numbers, per-load table, figures inline)."""
    out_dir = Path(out_dir)
    figures = write_figures(result, out_dir)
    header, rows = load_table(result)
    status = {"stored": "stored (skipped)", "computed": "computed", "disabled": "disabled"}
    stage_rows = [[s.name, status[s.status], f"{s.seconds:.2f}"] for s in result.stages]
    problems = result.problems()
    text = [
        "# asperity run report",
        "",
        f"Configuration: `{result.config.source}`; input SHA-256 `{result.input_sha256[:16]}...`;"
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
        *bem_section(result),
        "## Validity",
        "",
        "The statistical model is within its assumptions."
        if not result.resolution.validity
        else "\n".join(f"- **Warning:** {note}" for note in result.resolution.validity),
        "",
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
    captions = {
        "surface": "Stage 1: levelled surface.",
        "resolution": "Fig 12: summit statistics against resolution (a-c) and A_r/A_n against "
        "F_z (d).",
        "misfit": "Stage 4: misfit of the statistical model against resolution.",
        "bem_grid": "Stage 3: BEM grid refinement (A_r/A_n and its error against the finest "
        "grid solved) and contact at the largest load.",
        "lambda_fit": "Stage 5: lambda fit.",
        "shear": "Fig 4: shear response at the heaviest load, with stick and slip parts.",
        "area_vs_force": "Fig 13: A_r/A_n against F_x (dashed: model; dotted: constant shear "
        "strength).",
        "friction_vs_load": "Static and sliding friction against normal load.",
    }
    for name, path in figures.items():
        text += [f"![{captions[name]}]({path.name})", "", f"*{captions[name]}*", ""]
    report = out_dir / "report.md"
    report.write_text("\n".join(text), encoding="utf-8")
    return report


def summary_text(result: Any) -> str:
    """The one-screen terminal summary."""
    lines = ["asperity run: summary", ""]
    width = max(len(k) for k, _ in key_numbers(result))
    for key, value in key_numbers(result):
        if len(value) > 90:
            value = value[:87] + "..."
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
    for note in result.resolution.validity:
        lines.append(f"  WARNING: {note}")
    for note in [] if result.bem is None else result.bem.warnings:
        lines.append(f"  WARNING: {note}")
    problems = result.problems()
    if problems:
        lines.append("  NOT CONVERGED:")
        lines += [f"    {p}" for p in problems[:8]]
    lines.append(f"  outputs: {result.out_dir / 'results.h5'}, {result.out_dir / 'report.md'}")
    return "\n".join(lines)
