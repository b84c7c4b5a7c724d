"""Every bound from the one table, every error one bounded line, a closed pipe ends quietly."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

import asperity.pipelines.batch as batch_module
from asperity.pipelines.cli import MAX_LINE, main
from asperity.pipelines.engine.outdir import OutputDirError, OutputLock
from asperity.quantities import quantity

DATA = Path(__file__).parent / "data"


def _run(capsys, *argv) -> tuple[int, str]:
    status = main([str(a) for a in argv])
    return status, capsys.readouterr().err


@pytest.mark.parametrize(
    "options, key",
    [
        (["--load", "1", "--adhesion", "maugis", "--adhesion-range", "1e300"], "--adhesion-range"),
        (["--load", "1", "--adhesion", "maugis", "--adhesion-range", "1e-300"], "--adhesion-range"),
        (["--load", "1e-300"], "--load"),
        (["--mean-pressure", "-1e-300"], "--mean-pressure"),
    ],
)
def test_bem_options_take_the_registry_bounds(options, key, capsys):
    status, err = _run(capsys, "bem", DATA / "sur-3.sur", "--e-star", "1e9", *options)
    assert status == 2 and err.count("\n") == 1, err
    assert f"{key}: expected a number in" in err, err


def test_the_load_floor_keeps_zero_and_real_loads():
    load = quantity("loading.normal_load")
    assert load.check(0.0, "x") == 0.0 and load.check(-1e-12, "x") == -1e-12
    with pytest.raises(ValueError, match="magnitude >= 1e-12"):
        load.check(1e-13, "x")


@pytest.mark.parametrize("opening, closing", [("[", "]"), ("{a=", "}")])
def test_a_toml_nested_500_levels_is_exit_2(opening, closing, tmp_path, capsys):
    job = tmp_path / "deep.toml"
    job.write_text(f"x = {opening * 500}{'1' if opening != '[' else ''}{closing * 500}\n")
    status, err = _run(capsys, "run", job, "--out", tmp_path / "out")
    assert status == 2 and "nested more than" in err and str(job) in err, err


def test_a_10_mb_unknown_key_gives_a_short_line_with_an_ellipsis(tmp_path, capsys):
    job = tmp_path / "big.toml"
    job.write_text("[surface]\n" + "k" * 10_000_000 + " = 1\n")
    status, err = _run(capsys, "run", job, "--out", tmp_path / "out")
    assert status == 2 and "..." in err and "characters)" in err
    assert len(err) < MAX_LINE + 200 and err.count("\n") == 1


@pytest.mark.slow  # a real process: 2 s alone, 10 s on a busy machine
def test_a_closed_stdout_pipe_ends_quietly_with_the_commands_status(tmp_path):
    command = [sys.executable, "-m", "asperity", "scan", str(DATA / "sur-3.sur")]
    child = subprocess.Popen(
        [*command, "--max-stride", "3"], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    child.stdout.close()  # the reader is gone before the first line (``| head -0``)
    err = child.stderr.read().decode()
    assert child.wait(timeout=120) == 0, err
    assert err == "" or ("Broken" not in err and "error" not in err), err


def test_scan_refuses_an_empty_figure_name(capsys):
    status, err = _run(capsys, "scan", DATA / "sur-3.sur", "--max-stride", "3", "--figure", "")
    assert status == 2 and "--figure" in err and "empty" in err, err


def test_a_full_disk_while_writing_the_lock_names_the_lock_file(tmp_path, monkeypatch):
    def full(self):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(OutputLock, "_write_record", full)
    with pytest.raises(OutputDirError, match="No space left on device") as refused:
        with OutputLock(tmp_path / "out"):
            pass  # pragma: no cover
    assert ".asperity.lock" in str(refused.value)
    monkeypatch.undo()
    with OutputLock(tmp_path / "out"):  # nothing was left held
        pass


def test_batch_refuses_a_directory_and_a_fifo_entry_and_runs_the_rest(
    tmp_path, capsys, monkeypatch
):
    job = tmp_path / "job.toml"
    job.write_text("[surface]\n")
    folder, fifo = tmp_path / "folder", tmp_path / "fifo"
    folder.mkdir()
    os.mkfifo(fifo)
    ran = []

    def run_batch(job_path, maps, out, **options):
        ran.extend(maps)
        return SimpleNamespace(records=[], summary_csv=Path(out) / "summary.csv", status=0)

    monkeypatch.setattr(batch_module, "run_batch", run_batch)
    map_file = DATA / "sur-3.sur"
    status, err = _run(capsys, "batch", job, folder, fifo, map_file, "--out", tmp_path / "o")
    assert ran == [str(map_file)]
    assert status == 2 and err.count("REFUSED") == 2, err
    assert "a directory" in err and "FIFO" in err, err


def test_scan_out_on_a_full_disk_leaves_neither_file(tmp_path, capsys, monkeypatch):
    import asperity.topo.scan as scan_module

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp_path / "scan.png"))

    monkeypatch.setattr(scan_module, "plot_resolution_scan", full)
    out = tmp_path / "scan.h5"
    status, err = _run(capsys, "scan", DATA / "sur-3.sur", "--max-stride", "3", "--out", out)
    assert status == 2 and "No space left" in err, err
    assert list(tmp_path.iterdir()) == []


def test_a_bad_map_error_names_the_file(tmp_path, capsys):
    import h5py
    import numpy as np

    single = tmp_path / "one.txt"
    single.write_text("1.5e-6\n")
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w") as f:
        f.create_dataset("heights", data=np.zeros((0, 0)))
        attrs = {"format": "asperity-heightmap", "version": 1, "dx": 1e-6, "dy": 1e-6}
        f.attrs.update(attrs | {"periodic": True, "units": "m", "provenance": "{}"})
    for argv in (["stats", single, "--pixel-size", "1e-6"], ["scan", empty, "--max-stride", "2"]):
        status, err = _run(capsys, *argv)
        assert status == 2 and str(argv[1]) in err and err.count("\n") == 1, err
