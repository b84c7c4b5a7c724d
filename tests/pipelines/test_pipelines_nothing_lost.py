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


def test_a_different_job_into_a_finished_folder_is_refused_naming_both(small_run, small, tmp_path):
    from asperity.pipelines.config import config_from_dict
    from asperity.pipelines.engine.outdir import DifferentJobError
    from asperity.pipelines.job import run_job

    folder = _run_copy(small_run, tmp_path)
    before = (folder / "results.h5").read_bytes()
    data = small.data(normal_loads=[1.0, 2.5, 3.0])
    other = config_from_dict(data, source="other.toml", base_dir=tmp_path)
    with pytest.raises(DifferentJobError) as info:
        run_job(other, folder)
    message = str(info.value)
    assert "another job (small)" in message and "this job (other.toml)" in message
    assert "loading.normal_loads" in message and "--force" in message
    assert (folder / "results.h5").read_bytes() == before  # nothing recomputed or written
    assert not [p for p in folder.iterdir() if p.name.endswith(".tmp")]
    again = run_job(small(tmp_path), folder)  # the identical job resumes as before
    assert all(stage.status != "computed" for stage in again.stages)


def test_an_exit_2_run_into_an_empty_folder_leaves_it_empty(tmp_path, capsys):
    from asperity.pipelines.cli import main

    bad = tmp_path / "bad.x3p"
    bad.write_bytes(b"PK\x03\x04 not really a zip")
    job = tmp_path / "job.toml"
    job.write_text('[surface]\nfile = "bad.x3p"\n', encoding="utf-8")
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["run", str(job), "--out", str(empty)]) == 2
    assert list(empty.iterdir()) == []  # no .asperity.lock left behind
    new = tmp_path / "new"
    assert main(["run", str(job), "--out", str(new)]) == 2
    assert not new.exists()  # a folder this run created and wrote nothing in goes too
    capsys.readouterr()


def test_a_report_that_cannot_finish_removes_what_it_wrote(
    small_run, tmp_path, monkeypatch, capsys
):
    import errno

    from asperity.atomic import atomic_output, write_text_atomic
    from asperity.pipelines import report as report_module
    from asperity.pipelines.cli import main

    folder = _run_copy(small_run, tmp_path)
    (folder / "notes.txt").write_text("the user's own file")

    def disk_fills_on_the_fourth_figure(result, out_dir, options=None):
        for name in ("fig1.png", "fig1.csv", "fig2.png"):
            write_text_atomic(Path(out_dir) / name, "drawn")
        with atomic_output(Path(out_dir) / "fig2.csv"):
            raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(report_module, "write_figures", disk_fills_on_the_fourth_figure)
    assert main(["report", str(folder)]) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "unfinished report (3 new files) was removed" in err
    assert sorted(p.name for p in folder.iterdir() if p.name != ".asperity.lock") == [
        "notes.txt",
        "results.h5",
    ]


def _gzip_bomb(path: Path, group: str, name: str, chunks: int = 2048) -> None:
    """A dataset of ``chunks`` MiB of zeros stored as ~1 kB gzip chunks (within deflate's
    ratio chunk by chunk, 2 GiB in all), written directly without compressing anything."""
    import zlib

    import numpy as np

    packed = zlib.compress(np.zeros((1024, 128)).tobytes(), 9)
    with h5py.File(path, "a") as f:
        if name in f[group]:
            del f[group][name]
        bomb = f[group].create_dataset(
            name, shape=(1024 * chunks, 128), dtype="f8", chunks=(1024, 128), compression="gzip"
        )
        for i in range(chunks):
            bomb.id.write_direct_chunk((i * 1024, 0), packed)


@pytest.mark.parametrize(("group", "name"), [("friction", "extra"), ("surface", "heights")])
def test_a_gzip_bomb_results_file_is_refused_within_seconds(small_run, tmp_path, group, name):
    import time

    from asperity.h5 import UntrustedContentError

    folder = _run_copy(small_run, tmp_path)
    _gzip_bomb(folder / "results.h5", group, name)
    assert (folder / "results.h5").stat().st_size < 4 * 1024**2
    began = time.perf_counter()
    with pytest.raises(UntrustedContentError, match="compression bomb") as info:
        open_results(folder)
    assert time.perf_counter() - began < 2.0
    assert f"/{group}/{name}" in str(info.value)


def test_a_fifo_results_file_is_named_first_even_with_force(small, tmp_path):
    import os

    from asperity.files import SpecialFileError
    from asperity.pipelines.job import run_job

    if not hasattr(os, "mkfifo"):  # pragma: no cover
        pytest.skip("POSIX FIFOs only")
    os.mkfifo(tmp_path / "results.h5")
    with pytest.raises(SpecialFileError) as info:
        run_job(small(tmp_path), tmp_path, force=True)
    assert "configuration keys" not in str(info.value) and "FIFO" in str(info.value)
    assert len(str(info.value)) < 200
