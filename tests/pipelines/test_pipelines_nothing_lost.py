"""Nothing lost, nothing passed off (issue 40, items 5-7 and issue 37's output-folder items).

A reopened run without a well-formed verdict says so; a finished run is never overwritten by a
different job unasked; a report that cannot finish removes what it wrote of itself; a run that
wrote nothing leaves no lock; batch reuses a finished identical run.
"""

from __future__ import annotations

import dataclasses
import shutil
import warnings
from pathlib import Path

import h5py
import pytest

from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.results import VerdictWarning, open_results
from asperity.pipelines.stages.verdict import Verdict


def _run_copy(small_run, tmp_path: Path, name: str = "run") -> Path:
    _, out, _ = small_run
    folder = tmp_path / name
    folder.mkdir()
    shutil.copy(out / "results.h5", folder / "results.h5")
    return folder


def test_a_stored_verdict_reads_back_without_a_warning(small_run, tmp_path):
    folder = _run_copy(small_run, tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error", VerdictWarning)
        results = open_results(folder)
    assert results.verdict is not None and results.verdict_problem is None
    assert not any(line.startswith("verdict") for line in results.problems())


def test_a_missing_verdict_warns_and_is_a_problem(small_run, tmp_path):
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        del f["verdict"]
    with pytest.warns(VerdictWarning, match="verdict: not stored"):
        results = open_results(folder)
    assert results.verdict is None and results.friction is not None  # the numbers still read
    assert any("verdict: not stored" in line for line in results.problems())


def test_a_verdict_milder_than_its_reasons_is_malformed(small_run, tmp_path):
    folder = _run_copy(small_run, tmp_path)
    store = ResultStore(folder / "results.h5")
    stored = store.stored()["verdict"]
    lying = dataclasses.replace(
        store.read("verdict", Verdict),
        verdict="valid",
        reasons=["rms slope 3: outside the model"],
        codes=["slope"],
        severities=["invalid"],
    )
    store.write("verdict", lying, key=stored.key, seconds=stored.seconds)
    with pytest.warns(VerdictWarning, match="malformed"):
        results = open_results(folder)
    assert results.verdict is None  # never presented as the run's judgement
    assert any("'valid' but its reasons make it 'invalid'" in p for p in results.problems())


def test_a_verdict_that_does_not_read_back_warns_instead_of_failing(small_run, tmp_path):
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        f["verdict"].attrs["codes"] = "[not json"  # changed after it was written
    with pytest.warns(VerdictWarning):
        results = open_results(folder)
    assert results.verdict is None and results.friction is not None
    assert any(line.startswith("verdict:") for line in results.problems())
