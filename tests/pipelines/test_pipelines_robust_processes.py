"""Real processes: `asperity run` killed with its workers, and a real write failure of libhdf5's
output (a file-size limit: the kernel refuses the write as a full disk would). Slow: each starts
a fresh interpreter."""

from __future__ import annotations

import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity.pipelines.job import run_job

psutil = pytest.importorskip("psutil")

pytestmark = pytest.mark.slow

ASPERITY = [sys.executable, "-m", "asperity.pipelines"]


def _spawned_workers(parent: psutil.Process) -> list[psutil.Process]:
    workers = []
    for child in parent.children(recursive=True):
        try:
            if "spawn_main" in " ".join(child.cmdline()):
                workers.append(child)
        except psutil.NoSuchProcess:
            continue
    return workers


def _running(process: psutil.Process) -> bool:
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _wait_until(predicate, timeout: float, step: float = 0.1) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return predicate()


@pytest.mark.parametrize("signal_number", [signal.SIGKILL, signal.SIGTERM])
def test_workers_die_with_a_killed_run_and_the_run_resumes(
    small, small_run, tmp_path, signal_number
):
    config = tmp_path / "job.toml"
    config.write_text(small(tmp_path).to_toml())
    out = tmp_path / "out"
    run = subprocess.Popen(
        [*ASPERITY, "run", str(config), "--out", str(out), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        parent = psutil.Process(run.pid)
        assert _wait_until(lambda: len(_spawned_workers(parent)) >= 2, timeout=120), (
            "the run never started its two workers"
        )
        workers = _spawned_workers(parent)
        os.kill(run.pid, signal_number)
        run.wait(timeout=30)
        assert _wait_until(lambda: not any(_running(w) for w in workers), timeout=15), [
            w.pid for w in workers if _running(w)
        ]
    finally:
        if run.poll() is None:
            run.kill()
    # the next run takes the lock over and finishes with the uninterrupted numbers
    resumed = run_job(small(tmp_path), out)
    _, _, reference = small_run
    np.testing.assert_array_equal(
        resumed.friction.static_friction, reference.friction.static_friction
    )
    assert not list(out.glob(".*.tmp"))


def _limit_file_size(n_bytes: int):
    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # the write fails with EFBIG instead
        resource.setrlimit(resource.RLIMIT_FSIZE, (n_bytes, n_bytes))

    return limit


def _run_limited(config: Path, out: Path, n_bytes: int, *extra: str):
    return subprocess.run(
        [*ASPERITY, "run", str(config), "--out", str(out), *extra],
        capture_output=True,
        text=True,
        preexec_fn=_limit_file_size(n_bytes),
        timeout=300,
    )


def test_a_real_failed_write_is_one_line_exit_2_and_no_crash(small, small_run, tmp_path):
    """The kernel refuses the bytes (EFBIG under RLIMIT_FSIZE, as ENOSPC on a full disk): before
    the store built files in memory this was an h5py RuntimeError and then a libhdf5 segfault
    at exit (status 139)."""
    config = tmp_path / "job.toml"
    config.write_text(small(tmp_path).to_toml())
    first = _run_limited(config, tmp_path / "new", 16_000)  # the first write fails
    assert first.returncode == 2, first.stderr
    errors = [line for line in first.stderr.splitlines() if "error" in line]
    assert len(errors) == 1 and "File too large" in errors[0], first.stderr
    assert "nothing was written" in errors[0]
    assert "Traceback" not in first.stderr
    assert not (tmp_path / "new" / "results.h5").exists()
    assert not list((tmp_path / "new").glob(".*.tmp"))

    _, reference_out, _ = small_run
    out = tmp_path / "old"
    out.mkdir()
    (out / "results.h5").write_bytes((reference_out / "results.h5").read_bytes())
    before = (out / "results.h5").read_bytes()
    again = _run_limited(config, out, len(before) // 2, "--force")
    assert again.returncode == 2, again.stderr
    assert "unchanged" in again.stderr and "Traceback" not in again.stderr
    assert (out / "results.h5").read_bytes() == before
    assert not list(out.glob(".*.tmp"))
    with h5py.File(out / "results.h5", "r") as f:
        assert "friction" in f


def _sleep(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def test_a_pool_left_by_an_exception_terminates_its_workers_at_once():
    from asperity.pipelines.engine.parallel import make_executor

    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt), make_executor(2) as pool:
        futures = [pool.submit(_sleep, 30.0) for _ in range(4)]
        assert _wait_until(lambda: any(f.running() for f in futures), timeout=60)
        workers = [psutil.Process(p.pid) for p in pool._processes.values()]
        raise KeyboardInterrupt
    assert time.perf_counter() - t0 < 20  # not the 60 s the queued calls would take
    assert not any(_running(w) for w in workers)
    # queued calls are cancelled; running ones end as BrokenProcessPool (the pool's thread)
    assert _wait_until(lambda: all(f.done() for f in futures), timeout=10)
    assert not any(f.done() and not f.cancelled() and f.exception() is None for f in futures)
