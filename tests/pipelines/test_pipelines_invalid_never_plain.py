"""An invalid run never prints a plain model number (issue 37, item 2): summary.csv (verdict
column, an uncertainty column per predicted quantity, invalid cells marked as text), the
shear BEM table, the assumed-lambda decade column and key rows."""

from __future__ import annotations

import csv
import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.pipelines.batch.summary import summary_values, write_summary_csv
from asperity.pipelines.report.shear import shear_table
from asperity.pipelines.report.text import decade_column, key_numbers
from asperity.pipelines.stages.verdict import Reason, Verdict

INVALID = Verdict.from_reasons([Reason("tabor", "invalid", "mu = 2 < 5")])
STALL = Verdict.from_reasons([Reason("bem_shear_stall", "invalid", "a step did not converge")])


def _rows(path):
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    return list(csv.DictReader(lines))


def test_summary_values_carry_an_uncertainty_per_prediction_and_the_verdict(small_run):
    _, _, result = small_run
    values = summary_values(result)
    predicted = [
        name
        for name in values
        if name.startswith(("A_r/A_n", "static friction", "sliding friction", "mode mixity"))
        and "uncertainty" not in name
        and " written (" not in name
    ]
    assert len(predicted) == 1 + 3 * 3  # lambda, and A_r/A_n, F_s, F_d at three loads
    for name in predicted:
        quantity, _, unit = name.rpartition(" (")
        assert f"{quantity} uncertainty ({unit}" in values
        assert "\u00b1" in values[f"{quantity} written ({unit}"]  # "0.300 ± 0.024"
    static = "static friction at F_z=2 N"
    assert values[f"{static} uncertainty (N)"] == pytest.approx(
        result.friction.static_friction_uncertainty[1]
    )
    assert values["verdict"] == result.verdict.verdict


def test_an_invalid_map_is_written_as_text_a_spreadsheet_cannot_average(small_run, tmp_path):
    _, _, result = small_run
    values = summary_values(result)
    records = [
        {"map": "a.x3p", "folder": "a", "status": "ok", "message": "", "values": values},
        {"map": "b.x3p", "folder": "b", "status": "invalid", "message": "x", "values": values},
    ]
    ok, bad, *_ = _rows(write_summary_csv(records, tmp_path / "summary.csv"))
    static = "static friction at F_z=2 N (N)"
    assert float(ok[static]) == pytest.approx(result.friction.static_friction[1])
    numeric = [k for k, v in bad.items() if k not in ("map", "folder", "status", "message")]
    numeric = [k for k in numeric if k not in ("verdict", "validity") and bad[k]]
    assert numeric and all(bad[k].startswith("invalid: ") for k in numeric)
    for k in numeric:
        with pytest.raises(ValueError):
            float(bad[k])
    assert bad["verdict"] == ok["verdict"]


def test_a_run_stopped_early_has_only_its_verdict_in_the_summary():
    early = SimpleNamespace(
        statistical_model=None, friction=None, mode_mixity=None, verdict=INVALID
    )
    assert summary_values(early) == {"verdict": "invalid", "validity": "mu = 2 < 5"}


def _shear():
    rows = [
        {
            "normal_load": 2.1,
            "bem_static_friction": 647.8,
            "bem_static_friction_error": 3.0,
            "model_static_friction": 4269.0,
            "bem_sliding_friction": 500.0,
            "bem_sliding_friction_error": 2.0,
            "model_sliding_friction": 2244.0,
            "bem_area_drop": 0.9,
            "bem_area_drop_error": 0.01,
            "model_area_drop": 0.8,
        }
    ]
    return SimpleNamespace(table=lambda: rows, stuck_junctions=np.array([[0]]))


def test_the_shear_bem_table_marks_the_model_and_when_it_fails_the_bem():
    _, (row,) = shear_table(_shear(), INVALID)
    model, bem = [row[2], row[4], row[6]], [row[1], row[3], row[5]]
    assert all(c.startswith("invalid: ") for c in model)
    assert not any("invalid" in c for c in bem)  # a reference with its own validity
    _, (row,) = shear_table(_shear(), STALL)
    assert all(row[i].startswith("invalid: ") for i in range(1, 7))
    _, (row,) = shear_table(_shear(), None)
    assert row[2] == "4269"


def test_the_assumed_lambda_decade_column_is_marked_on_an_invalid_run():
    friction = SimpleNamespace(
        static_friction_mode_mixity_decade=np.array([[6610.0], [2090.0]]),
        mode_mixity_decade=(0.02, 0.2),
        static_friction=np.array([3720.0]),
        sliding_friction=np.array([1000.0]),
    )
    run = SimpleNamespace(friction=friction, verdict=INVALID)
    header, rows = decade_column(run, ["F_z (N)"], [["2.1"]])
    assert "lambda assumed" in header[-1] and rows[0][-1].startswith("invalid: ")
    valid = SimpleNamespace(friction=friction, verdict=None)
    assert not decade_column(valid, ["F_z (N)"], [["2.1"]])[1][0][-1].startswith("invalid")


def test_key_rows_of_the_model_are_marked_on_an_invalid_run(small_run):
    _, _, result = small_run
    rows = dict(key_numbers(dataclasses.replace(result, verdict=INVALID)))
    lam = [k for k in rows if k.startswith("mode mixity lambda")]
    assert lam and all(rows[k].startswith("invalid: ") for k in lam)
    assert rows["Tabor parameter mu"].startswith("invalid: ")


def test_figure_legends_mark_model_numbers_on_an_invalid_run(small_run):
    from asperity.pipelines.report.figures import draw_figure

    _, _, result = small_run
    invalid = dataclasses.replace(result, verdict=INVALID)
    fig, _ = draw_figure(invalid, "resolution")
    texts = [
        t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()
    ]
    marked = [t for t in texts if t.startswith("invalid: effective,")]
    assert marked, texts
    fig, _ = draw_figure(result, "resolution")
    texts = [
        t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()
    ]
    assert not any(t.startswith("invalid") for t in texts)
