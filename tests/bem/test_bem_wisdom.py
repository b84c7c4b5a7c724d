"""FFTW wisdom is cached on disk as raw bytes (an .npz read with allow_pickle=False) and reused."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyfftw")

PLAN = (
    "import numpy as np; from asperity.bem.elastic.fft_backend import Convolution; "
    "c = Convolution(np.ones((96, 49)), (96, 96), backend='pyfftw', threads=1); "
    "import pyfftw; print(sum(len(w) for w in pyfftw.export_wisdom()))"
)


def _run(cache: Path, code: str) -> str:
    env = dict(os.environ, ASPERITY_CACHE_DIR=str(cache))
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True
    )
    return done.stdout.strip()


@pytest.mark.slow  # two fresh interpreters (numba and pyFFTW imports): 4-10 s
def test_wisdom_is_stored_without_pickle_and_loaded_by_a_second_process(tmp_path: Path) -> None:
    _run(tmp_path, PLAN)
    files = list(tmp_path.glob("fftw_wisdom_*.npz"))
    assert len(files) == 1
    with np.load(files[0], allow_pickle=False) as stored:  # raw bytes, no objects
        assert all(stored[name].dtype == np.uint8 for name in stored.files)
        stored_bytes = sum(stored[name].size for name in stored.files if name.startswith("w"))
    assert stored_bytes > 0
    # a second process imports the wisdom before planning: it knows at least what was stored
    loaded = _run(
        tmp_path,
        "import pyfftw; from asperity.bem.elastic import fftw_wisdom; "
        # whatever the machine's load now (a file planned busy is set aside on a quiet one)
        "fftw_wisdom.machine_is_quiet = lambda seconds=0.3: False; fftw_wisdom.load(); "
        "print(sum(len(w) for w in pyfftw.export_wisdom()))",
    )
    assert int(loaded) >= stored_bytes - 3  # export appends a terminator per precision


def test_a_corrupt_wisdom_file_is_ignored(tmp_path: Path, monkeypatch) -> None:
    """In this process: loading a corrupt cache file neither raises nor imports anything, and a
    plan made afterwards still works (and saves wisdom that can be read back)."""
    import pyfftw

    from asperity.bem.elastic import fftw_wisdom
    from asperity.bem.elastic.fft_backend import Convolution

    monkeypatch.setenv("ASPERITY_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(fftw_wisdom, "_STATE", fftw_wisdom._State())
    corrupt = tmp_path / f"fftw_wisdom_{pyfftw.__version__}.npz"
    corrupt.write_bytes(b"not an npz file")
    fftw_wisdom.load()  # ignored, no exception
    conv = Convolution(np.ones((40, 21)), (40, 40), backend="pyfftw", threads=1)
    x = np.zeros((40, 40))
    x[3, 4] = 1.0
    y = conv.empty()
    conv(x, y)
    np.testing.assert_allclose(y, x, atol=1e-12)  # multiplier 1 everywhere: the identity


def _fresh_wisdom_state(monkeypatch, cache: Path):
    from asperity.bem.elastic import fftw_wisdom

    monkeypatch.setenv("ASPERITY_CACHE_DIR", str(cache))
    monkeypatch.setattr(fftw_wisdom, "_STATE", fftw_wisdom._State())
    return fftw_wisdom


def _stored_flag(fftw_wisdom) -> bool:
    with np.load(fftw_wisdom.wisdom_file(), allow_pickle=False) as stored:
        return bool(stored["planned_quiet"][0])


@pytest.mark.parametrize(("share", "quiet"), [(0.0, True), (0.9, False)])
def test_a_plan_made_while_others_hold_the_cpus_is_flagged_busy(
    tmp_path: Path, monkeypatch, share: float, quiet: bool
) -> None:
    """The saved file says whether its plans were timed on a quiet machine (the other
    processes' CPU share during the planning, here imposed)."""
    import pyfftw

    from asperity.bem.elastic.fft_backend import Convolution

    fftw_wisdom = _fresh_wisdom_state(monkeypatch, tmp_path)
    monkeypatch.setattr(fftw_wisdom, "others_share", lambda before, after: share)
    pyfftw.forget_wisdom()  # the planner must time this grid (later tests plan theirs afresh)
    shape = (44, 36)
    Convolution(np.ones((shape[0], 19)), shape, backend="pyfftw", threads=1)
    assert _stored_flag(fftw_wisdom) is quiet


@pytest.mark.parametrize(
    ("flag", "quiet_now", "imported"),
    [(True, True, True), (True, False, True), (False, False, True), (False, True, False)],
)
def test_a_busy_file_is_set_aside_only_on_a_quiet_machine(
    tmp_path: Path, monkeypatch, flag: bool, quiet_now: bool, imported: bool
) -> None:
    """Wisdom planned busy (or by an older version: no flag) is not imported when the machine is
    quiet now, so that its plans are timed again; otherwise the file is imported as it is."""
    import pyfftw

    fftw_wisdom = _fresh_wisdom_state(monkeypatch, tmp_path)
    fftw_wisdom._STATE.file_quiet = flag
    fftw_wisdom.save()
    fftw_wisdom._STATE = fftw_wisdom._State()
    calls: list[tuple] = []
    monkeypatch.setattr(pyfftw, "import_wisdom", lambda w: calls.append(w))
    probes: list[float] = []

    def probe(seconds: float = 0.3) -> bool:
        probes.append(seconds)
        return quiet_now

    monkeypatch.setattr(fftw_wisdom, "machine_is_quiet", probe)
    fftw_wisdom.load()
    assert bool(calls) is imported
    assert bool(probes) is (not flag)  # a quiet file is imported without looking
    fftw_wisdom.load()  # once per process
    assert len(calls) == int(imported)


def test_an_older_file_without_the_flag_counts_as_busy(tmp_path: Path, monkeypatch) -> None:
    fftw_wisdom = _fresh_wisdom_state(monkeypatch, tmp_path)
    path = fftw_wisdom.wisdom_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, w0=np.frombuffer(b"(fftw-3.3.10 fftw_wisdom)", dtype=np.uint8))
    stored = fftw_wisdom._read()
    assert stored is not None and stored[1] is False


@pytest.mark.skipif(not Path("/proc/stat").exists(), reason="reads /proc/stat")
def test_another_process_spinning_is_seen_as_its_share_of_the_cpus() -> None:
    """A busy loop in a second process holds one CPU: its share is at least about 1 / CPUs."""
    from asperity.bem.elastic import fftw_wisdom

    hog = subprocess.Popen(
        [sys.executable, "-c", "import time\nt = time.time()\nwhile time.time() - t < 5: pass"]
    )
    try:
        time.sleep(0.5)  # the hog is running
        before = fftw_wisdom.cpu_sample()
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < 1.0:  # this process busy too: not the others' share
            pass
        share = fftw_wisdom.others_share(before, fftw_wisdom.cpu_sample())
    finally:
        hog.kill()
    cpus = before.cpus
    assert share is not None
    assert 0.6 / cpus < share <= 1.0  # the hog is seen (anything else running adds to it)
