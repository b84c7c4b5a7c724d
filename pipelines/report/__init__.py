"""Figures of every stage (PNG, SVG and/or PDF, each with its data as CSV), ``report.md``,
``report.html`` and the one-screen terminal summary.

Laid out as xarray's ``plot/``: :mod:`~asperity.pipelines.report.figures` draws every figure
(on :class:`matplotlib.figure.Figure` objects, never pyplot state; shared styling in
:mod:`asperity.plotting`), :mod:`~asperity.pipelines.report.text` writes the tables and key
numbers, :mod:`~asperity.pipelines.report.html` the HTML page; :func:`write_report` writes all
three. Every function takes the run as :data:`~asperity.pipelines.report._run.Run` (a
``job.JobResult`` or a reopened ``results.Results``).

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

from pathlib import Path

from asperity.atomic import write_text_atomic
from asperity.pipelines.report._run import Run
from asperity.pipelines.report.figure_output import FigureOptions
from asperity.pipelines.report.figures import (
    COLOUR_PERCENTILES,
    FIGURES,
    SURFACE_DRAWN_PIXELS,
    draw_area_vs_force,
    draw_bem_grid,
    draw_figure,
    draw_figures,
    draw_friction_vs_load,
    draw_lambda_fit,
    draw_lambda_residuals,
    draw_misfit,
    draw_psd,
    draw_resolution,
    draw_shear,
    draw_surface,
    figure_options,
    fit_excluded,
    nyquist_marks,
    nyquist_style,
    radius_fit_line,
    write_figures,
)
from asperity.pipelines.report.html import write_html
from asperity.pipelines.report.text import (
    CAPTIONS,
    headline_numbers,
    key_numbers,
    load_table,
    pixel_size_text,
    report_markdown,
    summary_text,
)
from asperity.plotting import log_axis, spans_decades

__all__ = [
    "CAPTIONS",
    "COLOUR_PERCENTILES",
    "FIGURES",
    "SURFACE_DRAWN_PIXELS",
    "FigureOptions",
    "Run",
    "draw_area_vs_force",
    "draw_bem_grid",
    "draw_figure",
    "draw_figures",
    "draw_friction_vs_load",
    "draw_lambda_fit",
    "draw_lambda_residuals",
    "draw_misfit",
    "draw_psd",
    "draw_resolution",
    "draw_shear",
    "draw_surface",
    "figure_options",
    "fit_excluded",
    "headline_numbers",
    "key_numbers",
    "load_table",
    "log_axis",
    "nyquist_marks",
    "nyquist_style",
    "pixel_size_text",
    "radius_fit_line",
    "report_markdown",
    "spans_decades",
    "summary_text",
    "write_figures",
    "write_report",
]


def write_report(result: Run, out_dir: str | Path, options: FigureOptions | None = None) -> Path:
    """Write the figures, ``report.md`` and ``report.html`` (key numbers, per-load table,
    figures) in ``out_dir``; ``options`` (formats, dpi) default to the job's ``[report]``
    section. Returns the path of ``report.md``."""
    out_dir = Path(out_dir)
    figures = write_figures(result, out_dir, options)
    report = out_dir / "report.md"
    write_text_atomic(report, report_markdown(result, figures))
    write_html(result, out_dir, figures, dict(CAPTIONS))
    return report
