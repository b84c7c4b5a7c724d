"""Figures and CSVs that do not mislead: the verdict stamped on every figure and heading every
CSV of a run that is not valid (and redrawn the same by ``asperity report``), the reasons as a
coloured list in report.html, and the figure fixes read back from the Figure objects (Fig 12a's
fit line, the PSD's Nyquist lines, Fig 12d's BEM markers, the verdict's threshold lines)."""

from __future__ import annotations

import dataclasses
import shutil
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.pipelines.report import (
    draw_figures,
    draw_psd,
    draw_resolution,
    key_numbers,
    nyquist_marks,
    radius_fit_line,
    write_report,
)
from asperity.pipelines.report.figure_output import read_csv_header, read_figure_csv
from asperity.pipelines.report.verdict_marks import threshold_lines
from asperity.pipelines.stages import verdict as v
from asperity.plotting import display_unit, layout_problems, new_figure

INVALID = v.Verdict.from_reasons(
    [
        v.Reason("area_fraction", "invalid", "the statistical model's A_r/A_n reaches 9.82"),
        v.Reason("bem_edge_mismatch", "warning", "seam 1.50 x the rms height"),
    ]
)


@pytest.fixture(scope="module")
def invalid_run(small_run, tmp_path_factory):
    """The small job's result with an invalid verdict, and its report written."""
    _, _, result = small_run
    out = tmp_path_factory.mktemp("invalid")
    invalid = dataclasses.replace(result, verdict=INVALID, out_dir=out)
    write_report(invalid, out)
    return invalid, out


def test_every_figure_of_an_invalid_run_says_so(invalid_run):
    result, _ = invalid_run
    for name, (fig, table) in draw_figures(result).items():
        title = fig.get_suptitle()
        assert title.startswith("Verdict: INVALID."), name
        assert "area_fraction" in title and "9.82" in title.replace("\n", " "), name
        assert table.header[0] == "Verdict: INVALID", name
        assert layout_problems(fig) == [], name


def test_every_csv_of_an_invalid_run_says_so(invalid_run):
    _, out = invalid_run
    csvs = sorted(out.glob("*.csv"))
    assert len(csvs) >= 7
    for path in csvs:
        header = read_csv_header(path)
        assert header[0] == "Verdict: INVALID", path.name
        assert header[1].startswith("first reason: INVALID (area_fraction)"), path.name
        assert read_figure_csv(path)[0]["panel"], path.name  # the table reads past the header


def test_a_valid_run_is_not_stamped_but_its_csv_says_valid(small_run):
    _, _, result = small_run
    valid = dataclasses.replace(result, verdict=v.Verdict.from_reasons([]))
    fig, table = draw_figures(valid)["friction_vs_load"]
    assert fig.get_suptitle() == ""
    assert table.header == ["Verdict: valid"]


def test_a_run_valid_with_warnings_is_not_stamped_but_its_csv_says_so(small_run):
    """Only an invalid run's figures carry the banner; warnings head the report and CSVs."""
    _, _, result = small_run
    warned = dataclasses.replace(
        result, verdict=v.Verdict.from_reasons([v.Reason("bem_grid", "warning", "grid 8.9 %")])
    )
    fig, table = draw_figures(warned)["friction_vs_load"]
    assert fig.get_suptitle() == ""
    assert table.header[0] == "Verdict: valid, with warnings"


def test_the_banner_quotes_a_long_first_reason_whole(small_run):
    _, _, result = small_run
    long = "the statistical model's A_r/A_n reaches 9.82; " + "clause, " * 60 + "last words"
    bad = dataclasses.replace(
        result, verdict=v.Verdict.from_reasons([v.Reason("area_fraction", "invalid", long)])
    )
    fig, _ = draw_figures(bad)["friction_vs_load"]
    title = fig.get_suptitle().replace("\n", " ")
    assert "last words" in title and "[...]" not in title
    assert layout_problems(fig) == []


@pytest.mark.slow
def test_report_command_redraws_the_same_stamps(small_run, tmp_path):
    """``asperity report DIR`` reads the stored verdict from results.h5: same CSV headers."""
    from asperity.pipelines.cli import main
    from asperity.pipelines.results import open_results

    _, out, result = small_run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    assert main(["report", str(copy)]) == 0
    for path in out.glob("*.csv"):
        assert read_csv_header(copy / path.name) == read_csv_header(path), path.name
    redrawn = draw_figures(open_results(copy))
    for name, (fig, _) in draw_figures(result).items():
        assert redrawn[name][0].get_suptitle() == fig.get_suptitle(), name


def test_html_lists_the_reasons_with_coloured_severities(invalid_run):
    _, out = invalid_run
    page = (out / "report.html").read_text()
    assert '<p class="verdict-word">Verdict: INVALID</p>' in page
    reasons = page.split('<ul class="reasons">')[1].split("</ul>")[0]
    assert reasons.count("<li") == 2
    assert '<li class="reason severity-invalid"' in reasons
    assert '<li class="reason severity-warning"' in reasons
    assert reasons.index("area_fraction") < reasons.index("bem_edge_mismatch")
    assert ".severity-invalid{color:#b00000}" in page
    report = (out / "report.md").read_text()
    assert "**Verdict: INVALID.**" in report and "- **INVALID** (`area_fraction`)" in report


def test_radius_fit_is_drawn_where_r_is_positive_with_its_unit():
    """x3p-2's fit R = 179 x - 36 um crosses zero inside the scan: never drawn below."""
    scan = SimpleNamespace(radius_slope=179.0, radius_intercept=-36e-6)
    resolution = np.geomspace(0.1e-6, 4e-6, 60)
    line = radius_fit_line(scan, resolution)
    assert np.all(line["fit"] > 0) and line["fit_x"].min() > 36e-6 / 179
    # a pure number (R and the resolution are both lengths): no "m/m" unit
    assert "= 179 " in line["fit_label"] and "m/m" not in line["fit_label"]
    assert "R > 0" in line["fit_label"]
    whole = radius_fit_line(SimpleNamespace(radius_slope=2.68, radius_intercept=1e-6), resolution)
    assert whole["fit"].size == 60 and "R > 0" not in whole["fit_label"]


def _series_line(ax, label):
    """The data line of a series drawn as a plain line or with error bars."""
    for container in ax.containers:
        if container.get_label() == label:
            return container.lines[0]
    (line,) = [line for line in ax.get_lines() if line.get_label() == label]
    return line


def test_fig12a_line_and_fig12d_markers_read_back(small_run):
    _, _, result = small_run
    fig, _ = draw_resolution(result)
    ax_a, ax_d = fig.axes[0], fig.axes[3]
    (fit,) = [line for line in ax_a.get_lines() if "linear fit" in line.get_label()]
    assert "slope dR/d(resolution) = " in fit.get_label() and "m/m" not in fit.get_label()
    assert np.all(fit.get_ydata() > 0)
    plain, adhesive = _series_line(ax_d, "BEM, non-adhesive"), _series_line(ax_d, "BEM, adhesive")
    assert plain.get_markerfacecolor() == "none" and adhesive.get_markerfacecolor() != "none"
    assert plain.get_markersize() > adhesive.get_markersize()
    assert plain.get_zorder() > adhesive.get_zorder()  # open markers drawn over the filled ones


def test_threshold_lines_inside_the_axis_and_named_outside():
    ax = new_figure(4, 3).subplots()
    ax.plot([1, 2], [0.0, 0.2])
    assert threshold_lines(ax, "A_r/A_n", v_thresholds()) == [0.10, 0.15]
    drawn = [line.get_ydata()[0] for line in ax.get_lines() if "(verdict)" in line.get_label()]
    assert drawn == [0.10, 0.15]
    low = new_figure(4, 3).subplots()
    low.plot([1, 2], [0.001, 0.007])
    low.set_title("(d)")
    assert threshold_lines(low, "A_r/A_n", v_thresholds()) == []
    assert "0.1 (warning) and 0.15 (INVALID) above the axis" in low.get_title()
    assert low.get_ylim()[1] < 0.01  # the axis is not stretched to the limits


def v_thresholds():
    return [(v.WARN_AREA_FRACTION, "warning"), (v.MAX_AREA_FRACTION, "invalid")]


def test_misfit_and_area_figures_carry_the_thresholds_in_range(invalid_run):
    result, _ = invalid_run
    figures = draw_figures(result)
    for name, limits in (
        ("misfit", (v.WARN_MISFIT, v.MAX_MISFIT)),
        ("area_vs_force", (v.WARN_AREA_FRACTION, v.MAX_AREA_FRACTION)),
    ):
        ax = figures[name][0].axes[0]
        low, high = sorted(ax.get_ylim())
        drawn = sorted(
            line.get_ydata()[0] for line in ax.get_lines() if "(verdict)" in line.get_label()
        )
        inside = [x for x in limits if low <= x <= high]
        assert drawn == pytest.approx(inside), name
        # a limit outside the axis is drawn nowhere: no subtitle describes it
        assert "verdict limits" not in ax.get_title(), name


def _non_square(result, dx, dy, effective):
    surface = SimpleNamespace(dx=dx, dy=dy)
    psd = dataclasses.replace(result.psd, effective_resolution=effective)
    return SimpleNamespace(surface=surface, psd=psd)


def test_psd_nyquist_lines_at_pi_over_dx_and_dy(small_run):
    """x3p-2's pixels (0.128 x 0.315 um): pi/dx at pi/dx (not pi/dy), and the effective
    resolution's lines within the map's own Nyquist in each direction."""
    _, _, result = small_run
    dx, dy = 0.1277e-6, 0.3146e-6
    fake = _non_square(result, dx, dy, np.sqrt(dx * dy))  # stride 1
    marks = nyquist_marks(fake)
    assert marks["map Nyquist in x, $\\pi/dx$"] == pytest.approx(np.pi / dx)
    assert marks["map Nyquist in y, $\\pi/dy$"] == pytest.approx(np.pi / dy)
    effective = sorted(q for name, q in marks.items() if name.startswith("effective"))
    assert effective == pytest.approx([np.pi / dy, np.pi / dx])  # never beyond the map's
    fig, _ = draw_psd(fake)
    ax = fig.axes[0]
    unit = display_unit(result.psd.wavenumber, "m", -1)  # the axis unit of the figure
    drawn = {line.get_label(): line.get_xdata()[0] for line in ax.get_lines()}
    assert drawn["map Nyquist in x, $\\pi/dx$"] == pytest.approx(unit(np.pi / dx))
    assert drawn["map Nyquist in y, $\\pi/dy$"] == pytest.approx(unit(np.pi / dy))
    coarse = _non_square(result, dx, dy, 3 * np.sqrt(dx * dy))
    assert min(nyquist_marks(coarse).values()) == pytest.approx(np.pi / (3 * dy))


def test_square_pixels_psd_lines(small_run):
    _, _, result = small_run
    fig, _ = draw_psd(result)
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert "map Nyquist $\\pi/dx$" in labels and not any("dy" in x for x in labels)


def test_headline_pixel_size_gives_dy_when_it_differs(small_run):
    _, _, result = small_run
    surface = dataclasses.replace(result.surface, dy=2 * result.surface.dy)
    rows = dict(key_numbers(dataclasses.replace(result, surface=surface)))
    assert "40 x 80 \u00b5m pixels (dx x dy)" in rows["surface"]
    assert "40 \u00b5m pixels" in dict(key_numbers(result))["surface"]


def test_batch_summary_csv_and_figure_name_the_invalid_maps(tmp_path):
    """summary.csv opens with the count per status and each map that is not ok with its first
    reason; summary.png is stamped, and its mean line is over the maps with status ok."""
    from asperity.pipelines.batch.summary import draw_summary_figure, write_summary_csv

    def record(name, radius, status="ok", message=""):
        values = {"summit radius R (m)": radius, "effective resolution (m)": 1e-5}
        values["mode mixity lambda (1)"] = 0.03
        values["A_r/A_n at F_z=1 N (1)"] = 0.01
        values["static friction at F_z=1 N (N)"] = 0.5
        values["sliding friction at F_z=1 N (N)"] = 0.2
        return {"map": name, "folder": name, "status": status, "message": message, "values": values}

    records = [
        record("a.x3p", 1e-4),
        record("x3p-2.x3p", 9e-4, "invalid", "A_r/A_n reaches 9.82 > 0.15; misfit 5.66"),
        record("b.x3p", 3e-4),
    ]
    path = write_summary_csv(records, tmp_path / "summary.csv")
    header = read_csv_header(path)
    assert header[0] == "asperity batch summary of 3 map(s): 2 ok, 1 INVALID"
    assert header[-1] == "x3p-2.x3p: INVALID: A_r/A_n reaches 9.82 > 0.15"
    assert [r["map"] for r in read_figure_csv(path)][:3] == ["a.x3p", "x3p-2.x3p", "b.x3p"]
    fig = draw_summary_figure(records)
    assert fig.get_suptitle().startswith("1 of 3 maps not ok")
    ax = fig.axes[1]  # summit radius (um): the mean line of the ok maps, 200 um
    (mean,) = [line for line in ax.get_lines() if line.get_linestyle() == "-"]
    assert mean.get_ydata()[0] == pytest.approx(200.0)
    assert layout_problems(fig) == []
