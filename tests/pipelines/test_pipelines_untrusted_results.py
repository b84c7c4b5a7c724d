"""results.h5 is untrusted input: hand-made hostile files give exit 2 naming the object (report)
or a clean recompute (run), and nothing outside the named file is ever read."""

from __future__ import annotations

import dataclasses
import os
import shutil
import subprocess
import sys
import tracemalloc
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity.h5 import UntrustedContentError
from asperity.pipelines.cli import main
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.job import run_job
from asperity.pipelines.stages.verdict import Verdict

#: A file outside the run folder that a hostile results.h5 points at.
SECRET = b"root:x:0:0:secret outside the named file\n"


@pytest.fixture
def outside(tmp_path):
    """A plain file and an HDF5 file outside the run folder (the targets of the links)."""
    secret = tmp_path / "secret.txt"
    secret.write_bytes(SECRET)
    planted = tmp_path / "outside.h5"
    with h5py.File(planted, "w") as f:
        f["verdict"] = np.arange(4.0)
        f.create_group("friction").attrs["finished"] = True
    return secret, planted


def _run_copy(small_run, tmp_path, name="run") -> Path:
    """A copy of the small run's folder (results.h5 only) to tamper with."""
    _, out, _ = small_run
    folder = tmp_path / name
    folder.mkdir()
    shutil.copy(out / "results.h5", folder / "results.h5")
    return folder


def _report(folder, capsys) -> tuple[int, str]:
    status = main(["report", str(folder)])
    return status, capsys.readouterr().err


def _external_link(f, secret, planted):
    f["friction/extra"] = h5py.ExternalLink(str(planted), "/verdict")
    return "/friction/extra"


def _external_storage(f, secret, planted):
    f["friction"].create_dataset(
        "planted", shape=(len(SECRET),), dtype="u1", external=[(str(secret), 0, len(SECRET))]
    )
    return "/friction/planted"


def _virtual(f, secret, planted):
    layout = h5py.VirtualLayout(shape=(4,), dtype="f8")
    layout[:] = h5py.VirtualSource(str(planted), "verdict", shape=(4,))
    f["surface"].create_virtual_dataset("virtual", layout)
    return "/surface/virtual"


def _soft_loop(f, secret, planted):
    f["resolution_scan"]["a"] = h5py.SoftLink("/resolution_scan/b")
    f["resolution_scan"]["b"] = h5py.SoftLink("/resolution_scan/a")
    return "/resolution_scan/a"


def _huge_chunked(f, secret, planted):
    f["bem_reference"].create_dataset("huge", shape=(10**12,), dtype="f8", chunks=(1024,))
    return "/bem_reference/huge"


@pytest.mark.parametrize(
    "plant",
    [_external_link, _external_storage, _virtual, _soft_loop, _huge_chunked],
    ids=["external link", "external storage", "virtual dataset", "soft-link loop", "1e12 chunked"],
)
def test_report_refuses_a_file_that_reads_outside_itself_naming_the_object(
    plant, small_run, tmp_path, outside, capsys
):
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        name = plant(f, *outside)
    status, err = _report(folder, capsys)
    assert status == 2, err
    assert name.rsplit("/", 1)[-1] in err and "refused" in err, err
    assert len(err.strip().splitlines()) == 1, err
    assert not (folder / "report.md").exists()  # nothing built from it


def test_report_of_a_fifo_is_one_line_and_never_blocks(tmp_path, capsys):
    os.mkfifo(tmp_path / "results.h5")
    status, err = _report(tmp_path, capsys)
    assert status == 2 and "FIFO" in err and len(err.strip().splitlines()) == 1, err


def test_run_refuses_a_fifo_results_file_at_once(small, tmp_path, capsys):
    os.mkfifo(tmp_path / "results.h5")
    cfg = small(tmp_path)
    with pytest.raises(Exception, match="FIFO|not a regular file"):
        run_job(cfg, tmp_path)


def test_report_without_a_stored_verdict_shows_no_number(small_run, tmp_path, capsys):
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        del f["verdict"]
    status, err = _report(folder, capsys)
    assert status == 2 and "verdict" in err, err
    assert not (folder / "report.md").exists()


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_report_of_an_invalid_run_exits_3_as_run_does(small_run, tmp_path, capsys):
    folder = _run_copy(small_run, tmp_path)
    store = ResultStore(folder / "results.h5")
    verdict = store.read("verdict", Verdict)
    stored = store.stored()["verdict"]
    invalid = dataclasses.replace(verdict, verdict="invalid")
    store.write("verdict", invalid, key=stored.key, seconds=stored.seconds)
    status = main(["report", str(folder)])
    out = capsys.readouterr().out
    assert status == 3 and "Verdict: INVALID" in out, out
    assert (folder / "report.md").exists()


@pytest.mark.parametrize("kind", [np.void, np.bytes_])
def test_random_bytes_as_the_stored_configuration_exit_2_naming_it(
    kind, small_run, tmp_path, capsys
):
    folder = _run_copy(small_run, tmp_path)
    rng = np.random.default_rng(7)
    with h5py.File(folder / "results.h5", "a") as f:
        f.attrs["config_toml"] = kind(b"\xff" + rng.bytes(3000))
    status, err = _report(folder, capsys)
    assert status == 2 and "config_toml" in err, err


def test_run_sets_a_hostile_file_aside_and_recomputes_the_same_numbers(
    small, small_run, tmp_path, outside
):
    _, _, reference = small_run
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        _external_link(f, *outside)
    cfg = small(folder)
    with pytest.warns(RuntimeWarning, match="external link"):
        result = run_job(cfg, folder)
    assert (folder / "results.h5.unreadable").exists()
    assert not any(run.cached for run in result.stages)
    np.testing.assert_array_equal(
        result.friction.tangential_force, reference.friction.tangential_force
    )


def test_a_sparse_tail_is_never_read_to_update_the_file(small_run, tmp_path):
    """A valid file padded with a 2 GiB hole: a write copies only what the superblock holds."""
    folder = _run_copy(small_run, tmp_path)
    path = folder / "results.h5"
    size = path.stat().st_size
    with open(path, "r+b") as handle:
        handle.truncate(size + 2 * 1024**3)
    store = ResultStore(path)
    verdict = store.read("verdict", Verdict)
    tracemalloc.start()
    try:
        store.write("verdict", verdict, key="k")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 20 * size
    assert path.stat().st_size < 2 * size
    assert store.read("verdict", Verdict) == verdict


def test_a_file_declaring_more_than_the_budget_is_refused_before_reading(tmp_path):
    path = tmp_path / "results.h5"
    with h5py.File(path, "w") as f:
        f.create_group("a").create_dataset("x", data=np.zeros(10_000))
    store = ResultStore(path, max_bytes=40_000)
    with pytest.raises(UntrustedContentError, match="/a/x"):
        store.stored()
    assert path.exists()  # a reader never moves the file


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("strace") is None, reason="needs strace")
def test_strace_report_of_a_hostile_file_opens_nothing_outside(small_run, tmp_path, outside):
    """``asperity report`` on a file with an external link, external storage and a virtual
    dataset: the process never opens the targets (nor any path outside the folder that is not
    Python's, the package's or the system's)."""
    secret, planted = outside
    folder = _run_copy(small_run, tmp_path)
    with h5py.File(folder / "results.h5", "a") as f:
        _external_storage(f, secret, planted)
    trace = tmp_path / "trace"
    command = [sys.executable, "-m", "asperity", "report", str(folder)]
    strace = ["strace", "-f", "-qq", "-e", "trace=open,openat,openat2", "-o", str(trace)]
    done = subprocess.run(strace + command, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    opened = trace.read_text()
    assert str(secret) not in opened and str(planted) not in opened
    paths = [line.split('"')[1] for line in opened.splitlines() if '"' in line]
    assert {p for p in paths if p.startswith(str(tmp_path))} == {str(folder / "results.h5")}


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("strace") is None, reason="needs strace")
def test_strace_report_of_a_valid_run_opens_only_the_folder_and_the_packages(small_run, tmp_path):
    """Every file ``asperity report`` opens is in the run folder, or belongs to Python, the
    installed packages, asperity itself or the system's libraries and configuration."""
    import asperity

    folder = _run_copy(small_run, tmp_path)
    trace = tmp_path / "trace"
    command = [sys.executable, "-m", "asperity", "report", str(folder)]
    strace = ["strace", "-f", "-qq", "-e", "trace=open,openat,openat2", "-o", str(trace)]
    done = subprocess.run(strace + command, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    opened = {
        line.split('"')[1]
        for line in trace.read_text().splitlines()
        if '"' in line and "= -1" not in line
    }
    allowed = (
        str(folder),
        sys.prefix,
        sys.base_prefix,
        str(Path(asperity.__file__).resolve().parents[1]),
        os.path.expanduser("~/.config/matplotlib"),
        os.path.expanduser("~/.cache"),
        "/usr/",
        "/lib",
        "/etc/ld.so",
        "/etc/localtime",
        "/etc/ssl/",  # a CA bundle named by the environment (SSL_CERT_FILE)
        "/etc/matplotlibrc",
        "/proc/",
        "/sys/",
        "/dev/",
        "/tmp/matplotlib",
        "/tmp/numba",
    )
    outside = sorted(
        p
        for p in opened
        if not any(os.path.realpath(p).startswith(a) or p.startswith(a) for a in allowed)
        and p not in (".", "")
    )
    assert outside == [], outside
