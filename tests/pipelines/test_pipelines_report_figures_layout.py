"""Figures a scientist can send: legends that hide nothing, every labelled mark in a legend,
every grid of the BEM check named on its axis, a non-square map filling its figure, the
verdict banner wrapped and never cut, A_r = A_n drawn where the model exceeds it, and the PSD
fit called a Hurst exponent only inside (0, 1)."""

from __future__ import annotations

import dataclasses

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg

from asperity import topo
from asperity.pipelines.report import (
    draw_area_vs_force,
    draw_bem_grid,
    draw_misfit,
    draw_resolution,
    draw_surface,
)
from asperity.pipelines.report.figures import psd_fit_label
from asperity.plotting import display_unit, layout_problems, new_figure, stamp


def _drawn(fig):
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    return renderer


def test_scan_figure_legends_sit_under_their_axes():
    """`asperity scan --figure`: each panel's legend lies below its axes (it hides no point
    or tick), and the figure's texts neither overlap nor get clipped."""
    surface = topo.synthetic.paper_like(n=200, pixel_size=10e-6, seed=5)
    scan = topo.resolution_scan(surface, max_stride=6)
    fig = topo.draw_resolution_scan(new_figure(13, 4.8), scan, title="map")
    renderer = _drawn(fig)
    for ax in fig.axes:
        legend = ax.get_legend().get_window_extent(renderer)
        assert legend.y1 < ax.get_window_extent(renderer).y0
    assert layout_problems(fig) == []


def test_fig12d_legend_outside_and_stride_curves_distinct(small_run):
    _, _, result = small_run
    fig, _ = draw_resolution(result)
    d = fig.axes[3]
    assert d.get_legend() is None and fig.legends  # (d)'s legend under the figure
    jkr = [line for line in d.get_lines() if line.get_label().startswith("JKR model,")]
    styles = {(line.get_marker(), str(line.get_linestyle()), line.get_color()) for line in jkr}
    assert len(styles) == len(jkr) >= 2
    assert layout_problems(fig) == []


def test_misfit_markers_have_a_legend_entry(small_run):
    _, _, result = small_run
    fig, _ = draw_misfit(result)
    ax = fig.axes[0]
    legend = set(ax.get_legend_handles_labels()[1])
    for line in ax.get_lines():
        if line.get_marker() not in ("None", None, "") and len(line.get_xdata()):
            assert line.get_label() in legend, line.get_label()
    assert layout_problems(fig) == []


def test_bem_grid_names_every_grid_on_its_log_axis(small_run):
    """The movement panel's log x-axis labels every pixel size solved (the 40 um point of the
    default job was unlabelled), in plain words."""
    _, _, result = small_run
    fig, _ = draw_bem_grid(result)
    ax = fig.axes[1]
    _drawn(fig)
    bem = result.bem_reference
    pixel = np.asarray(bem.check_stride) * result.surface.dx
    unit = display_unit(np.concatenate([pixel, bem.refinement_pixel_size]), "m")
    labels = {t.get_text() for t in ax.get_xticklabels()}
    assert {f"{v:.3g}" for v in unit(pixel)} <= labels
    assert "larger of the modes" not in ax.get_title()
    assert layout_problems(fig) == []


def test_non_square_map_fills_its_figure(small_run):
    """A map four times as tall as wide: drawn to scale, its image takes a good part of the
    figure (before, a fixed landscape figure left half of it empty)."""
    _, _, result = small_run
    surface = dataclasses.replace(result.surface, dy=4 * result.surface.dy)
    fig, _ = draw_surface(dataclasses.replace(result, surface=surface))
    renderer = _drawn(fig)
    image = fig.axes[0].get_window_extent(renderer)
    assert np.isclose(image.height / image.width, 4, rtol=0.05)
    assert image.width * image.height > 0.3 * fig.bbox.width * fig.bbox.height
    assert layout_problems(fig) == []


def test_verdict_banner_wraps_and_never_cuts_a_word():
    words = " ".join(f"word{i}" for i in range(60)) + " its A_r/A_n reaches 9.82"
    fig = stamp(new_figure(6, 4), words)
    assert fig.get_suptitle().split() == words.split()


def test_full_contact_line_where_the_model_exceeds_it(small_run):
    _, _, result = small_run
    fr = result.friction
    scale = 2 * fr.nominal_area / np.max(fr.real_area)  # the model's A_r reaches 2 A_n
    big = dataclasses.replace(fr, real_area=np.asarray(fr.real_area) * scale)
    fig, _ = draw_area_vs_force(dataclasses.replace(result, friction=big))
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("$A_r = A_n$")]
    assert len(lines) == 1 and lines[0].get_ydata()[0] == 1.0
    fig, _ = draw_area_vs_force(result)  # the small job stays far below A_n: no line
    assert not [ln for ln in fig.axes[0].get_lines() if "A_r = A_n" in ln.get_label()]
    renderer = _drawn(fig)  # the legend under the axes, covering no curve
    legend = fig.axes[0].get_legend().get_window_extent(renderer)
    assert not fig.legends and legend.y1 < fig.axes[0].get_window_extent(renderer).y0


def test_psd_fit_is_a_hurst_exponent_only_inside_0_1():
    class Psd:
        psd_fit_exponent = -4.7
        hurst_exponent = 1.35

    assert "no Hurst exponent" in psd_fit_label(Psd) and "H = 1.35" not in psd_fit_label(Psd)
    Psd.psd_fit_exponent, Psd.hurst_exponent = -3.6, 0.8
    assert psd_fit_label(Psd).endswith("H = 0.8")
