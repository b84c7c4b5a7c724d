"""The per-load table's static-peak columns (mu_s, A_r at the static peak, the area drop),
stored in results.h5; measured peaks beside them; the report's text free of reprs and of a
second spelling of micro; lower-bound uncertainties drawn open-ended; bars never below zero;
the html page's order."""

from __future__ import annotations

import dataclasses
import html
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

from asperity.pipelines.report import (
    draw_area_vs_force,
    draw_friction_vs_load,
    headline_numbers,
    load_table,
    summary_text,
)
from asperity.pipelines.report.figures import nonnegative_bars
from asperity.pipelines.report.static_peak import measured_peaks
from asperity.pipelines.report.text import measured_cells
from asperity.pipelines.stages.friction import area_at_force_peak
from asperity.plotting import DisplayUnit


def test_area_at_force_peak_is_exact_on_parabolas():
    """F_x(d) a parabola peaking between steps and A_r(d) a parabola: the area at the peak is
    A_r(d*) exactly; at the path's end the end step's area."""
    d = np.linspace(0.0, 1.0, 21)
    peak = 0.4237
    force = 1.0 - (d - peak) ** 2
    area = 3.0 - 0.5 * d + 0.7 * d**2
    assert area_at_force_peak(force, area) == pytest.approx(3.0 - 0.5 * peak + 0.7 * peak**2)
    rising = d.copy()
    assert area_at_force_peak(rising, area) == area[-1]
    assert np.isnan(area_at_force_peak(np.full(5, np.nan), np.ones(5)))


def test_static_peak_quantities_stored_with_units(small_run):
    """mu_s = F_s / F_z and the area drop are in results.h5 (group friction) with their
    units; the drop is A_r at the peak over A_r at delta_T = 0 of the stored curves, below 1
    (the area shrinks under shear: the paper's Fig 13) and between the ratios of the steps
    around the largest F_x."""
    _, out, result = small_run
    with h5py.File(out / "results.h5", "r") as f:
        g = f["friction"]
        loads, fs = g["normal_load"][()], g["static_friction"][()]
        fx, area = g["tangential_force"][()], g["real_area"][()]
        mu, drop = g["static_friction_coefficient"], g["real_area_drop"]
        assert mu.attrs["units"] == "1" and drop.attrs["units"] == "1"
        assert g["static_peak_real_area"].attrs["units"] == "m^2"
        np.testing.assert_allclose(mu[()], fs / loads, rtol=1e-12)
        drops = drop[()]
    assert np.all(drops < 1) and np.all(drops > 0.5)
    for i in range(loads.size):
        k = int(np.argmax(fx[i]))
        neighbours = area[i, k - 1 : k + 2] / area[i, 0]
        assert neighbours.min() - 1e-12 <= drops[i] <= neighbours.max() + 1e-12
    np.testing.assert_array_equal(result.friction.real_area_drop, drops)


def test_load_table_has_the_static_peak_columns(small_run):
    _, out, result = small_run
    header, rows = load_table(result)
    fr = result.friction
    for name in ("static F_s (N)", "mu_s = F_s/F_z", "A_r/A_n at static peak", "A_r drop peak/0"):
        assert name in header
    drop = header.index("A_r drop peak/0")
    peak = header.index("A_r/A_n at static peak")
    for i, row in enumerate(rows):
        assert float(row[drop]) == pytest.approx(fr.real_area_drop[i], rel=5e-4)
        assert float(row[peak]) == pytest.approx(
            fr.static_peak_real_area[i] / fr.nominal_area, rel=5e-4
        )
        mu = row[header.index("mu_s = F_s/F_z")]
        assert "±" in mu  # the friction stage estimated u(F_s): mu_s carries it
    report = (out / "report.md").read_text(encoding="utf-8")
    assert "| A_r drop peak/0 |" in report


def test_report_text_has_no_repr_and_one_micro(small_run):
    """No Python dict or list repr and no "um" in report.md, report.html or the terminal
    summary: µm everywhere."""
    _, out, result = small_run
    texts = {
        "report.md": (out / "report.md").read_text(encoding="utf-8"),
        "report.html": (out / "report.html").read_text(encoding="utf-8"),
        "summary": summary_text(result),
    }
    for name, text in texts.items():
        if name == "report.html":  # the page's own CSS braces and the embedded figures aside
            text = text.split("</style>", 1)[1]
            text = text[: text.find("<h2>Figures</h2>")]
        assert "{" not in text and "}" not in text, name
        assert "{'" not in text, name
        words = text.replace("(", " ").replace(")", " ").replace(",", " ").split()
        assert "um" not in words, name
        assert "\u00b5m" in text, name


def test_html_key_numbers_first_then_table_then_details(small_run):
    _, out, result = small_run
    page = (out / "report.html").read_text(encoding="utf-8")
    order = [page.index(h) for h in ("Key numbers", "Per normal load", "Details", "Figures")]
    assert order == sorted(order)
    head = page[order[0] : order[1]]
    for quantity, value in headline_numbers(result):
        shown = html.escape(value).replace(" ± ", "\u00a0±\u00a0")  # one line, "±"
        assert html.escape(quantity) in head and shown in head, quantity
    assert "+-" not in head
    assert len(headline_numbers(result)) <= 12
    assert "max-width:100%" in page


def _lower_bound(result):
    """The run with its uncertainties declared lower bounds (an open interval)."""
    return dataclasses.replace(
        result, friction=dataclasses.replace(result.friction, uncertainty_lower_bound=True)
    )


def test_lower_bound_uncertainties_are_written_and_drawn_open(small_run):
    """A lower-bound u reads "± >u" in the table and is drawn as outward arrows (no capped
    bar) labelled "lower bound" in Fig 13 and in the friction figure."""
    _, _, result = small_run
    run = _lower_bound(result)
    header, rows = load_table(run)
    static = header.index("static F_s (N)")
    assert all("± >" in row[static] for row in rows)
    for draw in (draw_area_vs_force, draw_friction_vs_load):
        fig, _ = draw(run)
        ax = fig.axes[0]
        arrows = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
        assert len(arrows) >= len(result.friction.normal_load), draw.__name__
        labels = ax.get_legend_handles_labels()[1]
        assert any("lower bound" in label for label in labels), draw.__name__
        assert not ax.containers, draw.__name__  # no ordinary (closed) error bars
    fig, _ = draw_area_vs_force(result)
    assert not [t for t in fig.axes[0].texts if getattr(t, "arrow_patch", None) is not None]


def test_bars_stop_at_zero():
    bars, clipped = nonnegative_bars([0.5, 2.0, 0.0], [1.0, 0.5, 0.2])
    np.testing.assert_array_equal(bars, [[0.5, 0.5, 0.0], [1.0, 0.5, 0.2]])
    assert clipped
    assert not nonnegative_bars([3.0], [1.0])[1]


def test_friction_figure_clips_bars_at_zero_and_says_so(small_run):
    _, _, result = small_run
    fr = result.friction
    wide = dataclasses.replace(fr, static_friction_uncertainty=3 * np.asarray(fr.static_friction))
    fig, _ = draw_friction_vs_load(dataclasses.replace(result, friction=wide))
    ax = fig.axes[0]
    (static,) = [c for c in ax.containers if c.get_label().startswith("static")]
    assert "clipped at 0" in static.get_label()
    low = min(seg[:, 1].min() for seg in static.lines[2][0].get_segments())
    assert low >= 0.0


def test_measured_peaks_beside_the_predicted():
    """A measured curve rising to a peak and falling gives its largest F_x and the area drop
    there; one that ends on its largest F_x never showed its peak: written ">= F"."""
    fx = np.array([0.0, 0.2, 0.4, 0.5, 0.45, 0.3])
    area = np.array([10.0, 9.8, 9.5, 9.3, 8.0, 7.0]) * 1e-6
    curves = [
        SimpleNamespace(normal_load=1.0, tangential_force=fx, real_area=area),
        SimpleNamespace(normal_load=2.0, tangential_force=fx[:4], real_area=area[:4]),
    ]
    run = SimpleNamespace(
        friction=SimpleNamespace(normal_load=np.array([1.0, 2.0, 3.0])),
        mode_mixity=SimpleNamespace(curves=curves),
    )
    peaks = measured_peaks(run)
    assert sorted(peaks) == [0, 1]
    # the drop from a straight-line fit of the four stick points (0.931), not 9.3 / 10 alone
    assert peaks[0].static_friction == 0.5 and peaks[0].real_area_drop == pytest.approx(
        0.931, abs=1e-3
    )
    assert 0 < peaks[0].real_area_drop_uncertainty < 0.02
    assert not peaks[0].ends_rising and peaks[1].ends_rising
    newton = DisplayUnit(1.0, "N")
    assert measured_cells(peaks[1], newton, 1e-4) == [">= 0.5", "0.093", "0.9307 ± 0.0063"]
    assert measured_cells(None, newton, 1e-4) == ["-", "-", "-"]
