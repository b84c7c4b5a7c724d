"""Publication figures: formats, units from the data, robust colours, marks, clean layouts, and
the data behind every figure as a CSV that matches results.h5."""

from __future__ import annotations

import dataclasses
import math
import struct
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.report import (
    FIGURES,
    draw_figures,
    draw_resolution,
    draw_surface,
    spans_decades,
)
from asperity.pipelines.report.figure_output import FigureOptions, publish, read_figure_csv
from asperity.pipelines.stages.psd import psd_and_persson
from asperity.pipelines.stages.surface import LevelledSurface
from asperity.plotting import layout_problems
from asperity.statmodel import KAPPA_PERSSON


def test_every_figure_has_a_clean_layout(small_run):
    """No overlapping or clipped text in any figure of the job (the layout engine's boxes)."""
    _, _, result = small_run
    figures = draw_figures(result)
    assert set(figures) == set(FIGURES) - {
        "lambda_fit",
        "lambda_residuals",
        "bem_shear_force",
        "bem_shear_area",
    }  # no measured curves, no [bem_shear] in the small job
    for name, (fig, _) in figures.items():
        assert layout_problems(fig) == [], name


def _column(rows, panel, series, column):
    return np.array(
        [float(r[column]) for r in rows if r["panel"] == panel and r["series"] == series]
    )


def test_figure_csvs_match_results_h5(small_run):
    """The CSV beside a figure holds the stored SI values (Fig 12a, 12d Persson, Fig 13)."""
    _, out, _ = small_run
    rows = read_figure_csv(out / "fig12_resolution.csv")
    with h5py.File(out / "results.h5", "r") as f:
        radius = f["resolution_scan/summit_radius"][()]
        resolution = f["resolution_scan/resolution"][()]
        persson = f["psd/persson_real_area"][()]
        a_n = f["statistical_model"].attrs["nominal_area"]
        contact = f["bem_reference/contact_fraction"][()]
        fx = f["friction/tangential_force"][()]
        loads = f["friction/normal_load"][()]
    np.testing.assert_array_equal(_column(rows, "a", "map", "summit radius R (m)"), radius)
    np.testing.assert_array_equal(_column(rows, "a", "map", "resolution (m)"), resolution)
    np.testing.assert_allclose(
        _column(rows, "d", "Persson, non-adhesive", "A_r/A_n (1)"), persson / a_n, rtol=1e-15
    )
    np.testing.assert_array_equal(_column(rows, "d", "BEM, non-adhesive", "A_r/A_n (1)"), contact)
    fig13 = read_figure_csv(out / "fig13_area_vs_force.csv")
    series = f"model F_z = {loads[-1]:.6g} N"
    np.testing.assert_array_equal(_column(fig13, "all", series, "tangential load F_x (N)"), fx[-1])
    header = list(fig13[0])
    assert all(c in ("panel", "series") or c.endswith(")") for c in header), header


def _png_size(path):
    with open(path, "rb") as handle:
        head = handle.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_formats_and_dpi(small_run, tmp_path):
    """A figure in PNG, SVG and PDF with its CSV; the PNG's pixels follow the dpi."""
    _, _, result = small_run
    options = FigureOptions(("png", "svg", "pdf"), dpi=60)
    for name in ("friction_vs_load", "psd"):
        stem = tmp_path / FIGURES[name][0]
        fig, table = FIGURES[name][1](result)
        assert publish(fig, table, stem.with_suffix(".png"), options) == stem.with_suffix(".png")
        assert stem.with_suffix(".pdf").read_bytes()[:5] == b"%PDF-"
        assert b"<svg" in stem.with_suffix(".svg").read_bytes()[:2000]
        assert stem.with_suffix(".csv").exists()
    width, height = _png_size(tmp_path / "friction_vs_load.png")
    assert (width, height) == (round(6.5 * 60), round(4.8 * 60))  # 6.5 x 4.8 in at 60 dpi
    with pytest.raises(InputError, match="formats"):
        FigureOptions(("png", "tiff"))
    with pytest.raises(InputError, match="dpi"):
        FigureOptions(("png",), dpi=5)


def _surface(heights, dx):
    n = heights.shape[0]
    return LevelledSurface(
        x=np.arange(n) * dx,
        y=np.arange(n) * dx,
        heights=heights,
        dx=dx,
        dy=dx,
        periodic=True,
        n_missing=0,
        rms_height=float(heights.std()),
        provenance={},
    )


def test_surface_colour_scale_ignores_a_spike_and_says_so():
    """One spike 1000 x the roughness leaves the colour limits at the percentiles; the AFM-size
    map is drawn in um, its heights in nm."""
    rng = np.random.default_rng(0)
    heights = rng.normal(0, 5e-9, (64, 64))
    heights[10, 10] = 5e-6
    fig, table = draw_surface(SimpleNamespace(surface=_surface(heights, 10e-6 / 64)))
    image = fig.axes[0].images[0]
    low, high = image.get_clim()
    assert high < 20 and low > -20  # nm: the spike (5000 nm) does not set the scale
    assert "(nm)" in fig.axes[1].get_ylabel() and "percentile" in fig.axes[1].get_ylabel()
    assert "(µm)" in fig.axes[0].get_xlabel()
    assert np.nanmax(table.series("map", "heights", "height (m)")) == pytest.approx(5e-6)


def test_fig12_marks_units_and_log_axes(small_run):
    """Effective resolution and the strides left out of the fits are marked in 12a-c; units
    in um; 12d on log axes where the areas span a decade."""
    _, _, result = small_run
    scan = dataclasses.replace(
        result.resolution_scan, n_summits=np.array(result.resolution_scan.n_summits)
    )
    scan.n_summits[-1] = 3  # fewer than 10 summits: left out of the fits
    fig, _ = draw_resolution(dataclasses.replace(result, resolution_scan=scan))
    for ax in fig.axes[:3]:
        assert "(µm)" in ax.get_xlabel()
        labels = {line.get_label(): line for line in ax.get_lines()}
        (name,) = [k for k in labels if k.startswith("effective")]  # "effective, 20 µm"
        effective = labels[name].get_xdata()[0]
        assert effective == pytest.approx(result.statistical_model.effective_resolution * 1e6)
        excluded = labels["not fitted (< 10 summits)"].get_xdata()
        assert list(excluded) == pytest.approx([result.resolution_scan.resolution[-1] * 1e6])
    d = fig.axes[3]
    fractions = np.concatenate([line.get_ydata() for line in d.get_lines()])
    assert d.get_yscale() == ("log" if spans_decades(fractions) else "linear")
    assert any("Persson" in line.get_label() for line in d.get_lines())
    assert layout_problems(fig) == []


def test_psd_stage_recovers_the_hurst_exponent_and_rolloff():
    """On a synthetic self-affine map (H = 0.8, roll-off 300 um) the stage finds both; Persson's
    area at a small load follows its closed form kappa p / (E* h'_rms)."""
    surface = topo.synthetic.self_affine(
        256, 5e-6, rms_height=2e-6, rolloff_wavelength=300e-6, hurst=0.8, seed=1
    )
    levelled = LevelledSurface.from_height_map(surface)
    choice = SimpleNamespace(effective_resolution=20e-6)
    e_star, a_n, loads = 2e6, 1e-4, np.array([1e-4, 1e-3])
    psd = psd_and_persson(levelled, choice, e_star, a_n, loads)
    assert psd.hurst_exponent == pytest.approx(0.8, abs=0.1)
    assert psd.rolloff_wavelength == pytest.approx(300e-6, rel=0.25)
    assert psd.effective_nyquist_wavelength == pytest.approx(40e-6)
    small = KAPPA_PERSSON * (loads[0] / a_n) / (e_star * psd.persson_rms_slope)
    assert psd.persson_real_area[0] / a_n == pytest.approx(small, rel=1e-3)
    # a coarser cut-off removes short-wavelength slopes: more contact at the same load
    assert np.all(psd.persson_real_area_effective > psd.persson_real_area)
    assert math.isfinite(psd.psd_fit_prefactor)


def test_psd_stage_gives_no_hurst_exponent_for_a_smooth_surface():
    """A spectrum steeper than q^-4 (H = 1.36 imposed, the default job's recipe) has no Hurst
    exponent: NaN, the slope kept as psd_fit_exponent (H_slope = -exponent/2 - 1)."""
    surface = topo.synthetic.self_affine(
        256, 5e-6, rms_height=2e-6, rolloff_wavelength=300e-6, hurst=1.36, seed=1
    )
    levelled = LevelledSurface.from_height_map(surface)
    choice = SimpleNamespace(effective_resolution=20e-6)
    psd = psd_and_persson(levelled, choice, 2e6, 1e-4, np.array([1e-4]))
    assert math.isnan(psd.hurst_exponent)
    assert -psd.psd_fit_exponent / 2 - 1 == pytest.approx(1.36, abs=0.15)


def test_lambda_fit_figure_is_not_clipped():
    """The lambda-fit figure (only drawn with measured curves) keeps its labels on the page."""
    from asperity.pipelines.report import draw_lambda_fit
    from asperity.pipelines.stages.friction import ModeMixityChoice

    grid = np.geomspace(1e-3, 1.0, 9)
    choice = ModeMixityChoice(
        mode_mixity=0.1,
        fitted=True,
        lambda_grid=grid,
        grid_residual_rms=0.01 + np.abs(np.log10(grid / 0.1)),
        mode_mixity_std=0.01,
        residual_rms=0.01,
        n_points=50,
        nfev=12,
        success=True,
        message="ok",
    )
    fig, table = draw_lambda_fit(SimpleNamespace(mode_mixity=choice))
    assert layout_problems(fig) == []
    np.testing.assert_array_equal(
        table.series("fit", "coarse scan", "mode mixity lambda (1)"), grid
    )
