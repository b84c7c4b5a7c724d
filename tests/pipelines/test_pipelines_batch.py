"""Batch mode: many maps through one job, one folder each (resumable), one summary; a failing
map is reported and does not stop the others; locally or on a dask LocalCluster."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.batch import expand_maps, run_batch
from asperity.pipelines.cli import main
from asperity.schema import dump_toml

#: Seeds of maps whose calibration is bracketed: with seeds 4 and 7 the least misfit lies at the
#: scan's finest stride and the verdict calls the run invalid, which is not this file's subject.
SEEDS = (3, 5)


def _maps_and_job(small, tmp_path, n_maps=2):
    """``n_maps`` 64 x 64 paper-like maps (.npy, heights in m) and the small job reading them."""
    folder = tmp_path / "maps"
    folder.mkdir()
    for index, seed in enumerate(SEEDS[:n_maps]):
        surface = topo.synthetic.paper_like(n=64, pixel_size=40e-6, seed=seed)
        np.save(folder / f"map{index}.npy", surface.heights)
    data = small.data()
    data["surface"] = {"pixel_size": 40e-6, "max_stride": 4, "detrend": "plane"}
    data["loading"]["normal_loads"] = [1.0, 3.0]
    job = tmp_path / "job.toml"
    job.write_text(dump_toml(data), encoding="utf-8")
    return job, folder


def _summary(path):
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


@pytest.mark.slow
def test_batch_summary_failure_and_resume(small, tmp_path):
    """Two good maps and a broken one: the good ones finish, the broken one is named with its
    reason in summary.csv and the exit status; mean and std rows follow; a second run resumes
    every stored stage."""
    job, folder = _maps_and_job(small, tmp_path)
    (folder / "map9.npy").write_bytes(b"not a numpy file")
    out = tmp_path / "out"
    status = main(["batch", str(job), str(folder / "*.npy"), "--out", str(out)])
    assert status == 2  # a map failed
    rows = _summary(out / "summary.csv")
    assert [r["map"] for r in rows] == [str(folder / f"map{i}.npy") for i in (0, 1, 9)] + [
        "mean",
        "std",
    ]
    assert [r["status"] for r in rows[:3]] == ["ok", "ok", "failed"]
    assert "map9.npy" in rows[2]["message"] or "npy" in rows[2]["message"].lower()
    radius = np.array([float(r["summit radius R (m)"]) for r in rows[:2]])
    assert float(rows[3]["summit radius R (m)"]) == pytest.approx(radius.mean())
    assert float(rows[4]["summit radius R (m)"]) == pytest.approx(radius.std(ddof=1))
    assert float(rows[0]["A_r/A_n at F_z=3 N (1)"]) > float(rows[0]["A_r/A_n at F_z=1 N (1)"])
    assert (out / "summary.png").exists()
    for i in (0, 1):
        assert (out / f"map{i}" / "results.h5").exists() and (
            out / f"map{i}" / "report.html"
        ).exists()
    figures = [p for p in (out / "map0").iterdir() if p.suffix in (".md", ".html", ".png", ".csv")]
    drawn = {p.name: p.stat().st_mtime_ns for p in figures}
    again = run_batch(job, [str(folder / "map0.npy")], out)
    assert again.records[0]["status"] == "ok" and again.records[0]["computed"] == []
    # the finished identical run is reused whole: its report and figures are not redrawn
    assert len(drawn) > 4
    assert {p.name: p.stat().st_mtime_ns for p in figures} == drawn


@pytest.mark.slow
def test_batch_on_a_dask_local_cluster(small, tmp_path):
    """One map per task on a LocalCluster with 2 workers gives the serial batch's numbers."""
    distributed = pytest.importorskip("distributed")
    job, folder = _maps_and_job(small, tmp_path)
    serial = run_batch(job, [str(folder / "*.npy")], tmp_path / "serial")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster:
        with distributed.Client(cluster) as client:
            remote = run_batch(job, [str(folder / "*.npy")], tmp_path / "dask", scheduler=client)
    assert [r["status"] for r in remote.records] == ["ok", "ok"]
    for a, b in zip(serial.records, remote.records, strict=True):
        assert a["values"] == pytest.approx(b["values"], nan_ok=True)


def test_map_patterns_are_checked_before_any_run(small, tmp_path):
    job, folder = _maps_and_job(small, tmp_path, n_maps=1)
    assert expand_maps([str(folder / "*.npy"), str(folder / "map0.npy")]) == [folder / "map0.npy"]
    assert main(["batch", str(job), str(folder / "*.x3p"), "--out", str(tmp_path / "o")]) == 2
    assert main(["batch", str(job), str(folder / "missing.npy")]) == 2
    assert not (tmp_path / "o").exists()


def test_a_surface_key_that_is_no_table_is_bad_input_naming_it(tmp_path):
    from asperity.errors import InputError
    from asperity.pipelines.batch import map_config

    with pytest.raises(InputError, match=r"job.toml: \[surface\] expected a table, found str"):
        map_config({"surface": "map.npy"}, tmp_path, "job.toml", tmp_path / "map.npy")


def _record(name, radius, fraction):
    values = {
        "effective resolution (m)": 40e-6,
        "asperity density eta (1/m^2)": 8e6,
        "summit radius R (m)": radius,
        "rms summit height sigma_s (m)": 45e-6,
        "mode mixity lambda (1)": 0.03,
    }
    for load in (1.0, 3.0):
        values[f"A_r/A_n at F_z={load:.6g} N (1)"] = fraction * load
        values[f"static friction at F_z={load:.6g} N (N)"] = 0.4 * load
        values[f"sliding friction at F_z={load:.6g} N (N)"] = 0.3 * load
    values["verdict"] = ""
    return {"map": name, "folder": name, "status": "ok", "message": "", "values": values}


def test_summary_rows_and_figure_layout(tmp_path):
    """mean and std rows over the maps with status ok only; a clean summary figure."""
    from asperity.pipelines.batch.summary import draw_summary_figure, write_summary_csv
    from asperity.plotting import layout_problems

    records = [
        _record("a.x3p", 100e-6, 0.004),
        {"map": "bad.x3p", "folder": "bad", "status": "failed", "message": "bad input: no"},
        _record("b.x3p", 140e-6, 0.006),
    ]
    rows = _summary(write_summary_csv(records, tmp_path / "summary.csv"))
    assert [r["map"] for r in rows] == ["a.x3p", "bad.x3p", "b.x3p", "mean", "std"]
    assert rows[1]["summit radius R (m)"] == "" and rows[1]["message"] == "bad input: no"
    assert float(rows[3]["summit radius R (m)"]) == pytest.approx(120e-6)
    assert float(rows[4]["summit radius R (m)"]) == pytest.approx(np.std([100e-6, 140e-6], ddof=1))
    assert layout_problems(draw_summary_figure(records)) == []


def test_invalid_maps_are_listed_never_averaged_and_set_the_exit_status(tmp_path):
    """A map whose verdict is invalid is a row of its own, left out of the mean and std (no
    confident average over numbers the model cannot stand behind), and the batch exits 3;
    a failed map (2) and an unconverged one (1) take precedence, as for one run."""
    from asperity.pipelines.batch import BatchResult
    from asperity.pipelines.batch.summary import write_summary_csv

    invalid = {**_record("c.x3p", 900e-6, 0.9), "status": "invalid"}
    records = [_record("a.x3p", 100e-6, 0.004), invalid, _record("b.x3p", 140e-6, 0.006)]
    rows = _summary(write_summary_csv(records, tmp_path / "summary.csv"))
    cell = rows[1]["summit radius R (m)"]  # listed, marked: no spreadsheet reads it as a number
    assert cell.startswith("invalid: ") and float(cell.split(": ")[1]) == pytest.approx(900e-6)
    assert float(rows[3]["summit radius R (m)"]) == pytest.approx(120e-6)  # mean of a and b
    assert "1 invalid or unconverged map(s) left out" in rows[3]["message"]
    result = BatchResult(records=records, summary_csv=tmp_path / "summary.csv")
    assert result.status == 3
    unconverged = {**_record("d.x3p", 1e-4, 0.1), "status": "not converged"}
    assert BatchResult(records=[*records, unconverged], summary_csv=tmp_path).status == 1
    failed = {"map": "e", "folder": "e", "status": "failed", "message": "bad input: x"}
    assert BatchResult(records=[*records, unconverged, failed], summary_csv=tmp_path).status == 2
