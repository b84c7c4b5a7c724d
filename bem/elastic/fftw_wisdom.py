"""FFTW wisdom on disk, kept only when it was planned on a quiet machine.

``FFTW_MEASURE`` picks each transform's algorithm by timing the candidates. Timed while other
processes hold the cores, the candidates' ranking is the load's, not the machine's, and the
wisdom file hands that plan to every later process: measured on a 2-core machine at 5000^2, a
double-precision two-thread convolution planned from such a file took 0.39 s, against 0.134 s
once re-planned on the quiet machine (one thread: 0.28 s, so ``"auto"`` fell back to one thread
and the solve ran at half speed for good).

The file therefore records whether every plan in it was made while the machine was quiet (the
other processes' share of the CPUs during the planning, from ``/proc/stat``; a plan made in
under 0.2 s, or where ``/proc/stat`` cannot be read, is not judged: this process's own threads
would count in a load average, and such a plan is cheap to make again). A process that finds
a file not known to be quiet (planned busy, or written by an older version) on a quiet machine
does not import it: it plans afresh, and its save replaces the file. On a busy machine the
file is imported as it is (planning anew there would be no better). Nothing here changes a
transform's result, only which algorithm computes it.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

__all__ = ["cache_dir", "machine_is_quiet", "planning", "wisdom_file"]

QUIET_SHARE = 0.2  # the other processes' share of all CPUs below which the machine is quiet
_MIN_WINDOW = 0.2  # s: shorter windows are not judged (the kernel counts CPU time in 10 ms)
_PROBE_SECONDS = 0.3  # s: the look at the machine before a busy file is imported or not
_QUIET_KEY = "planned_quiet"


class _State:
    """The process's view of the wisdom (one per process, guarded by the backend's lock)."""

    loaded = False  # the file has been considered (imported or set aside)
    file_quiet = True  # every plan in the process's wisdom was made on a quiet machine


_STATE = _State()


class CpuSample(NamedTuple):
    """Clocks read together: wall time, this process's CPU time (all threads) and the CPU time
    of the whole machine (``None`` where ``/proc/stat`` is not readable), all in seconds."""

    wall: float
    own: float
    machine: float | None
    cpus: int


def _machine_busy_seconds() -> tuple[float | None, int]:
    """CPU seconds spent busy by all processes since boot, and the CPUs they are summed over."""
    try:
        with open("/proc/stat", encoding="ascii") as fh:
            lines = fh.read().splitlines()
    except OSError:
        return None, os.cpu_count() or 1
    fields = [int(v) for v in lines[0].split()[1:]]
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    cpus = sum(1 for line in lines if line.startswith("cpu") and line[3:4].isdigit())
    return (sum(fields[:8]) - idle) / os.sysconf("SC_CLK_TCK"), max(cpus, 1)


def cpu_sample() -> CpuSample:
    """The clocks of :class:`CpuSample`, now."""
    machine, cpus = _machine_busy_seconds()
    return CpuSample(time.perf_counter(), time.process_time(), machine, cpus)


def others_share(before: CpuSample, after: CpuSample) -> float | None:
    """Fraction of all the machine's CPU time that other processes used between two samples
    (0 = they used none, 1 = every CPU all the time), or ``None`` where it cannot be told
    (no ``/proc/stat``, or a window shorter than 0.2 s)."""
    wall = after.wall - before.wall
    if before.machine is None or after.machine is None or wall < _MIN_WINDOW:
        return None
    others = (after.machine - before.machine) - (after.own - before.own)
    return max(0.0, others) / (wall * after.cpus)


def machine_is_quiet(seconds: float = _PROBE_SECONDS) -> bool:
    """Whether other processes use under 20 % of the CPUs, watched for ``seconds`` (s); False
    where that cannot be told (no ``/proc/stat``): the file is then imported as it is."""
    before = cpu_sample()
    time.sleep(seconds)
    share = others_share(before, cpu_sample())
    return share is not None and share < QUIET_SHARE


def cache_dir() -> Path:
    """Directory for the FFTW wisdom and the backend choices (created on demand)."""
    root = os.environ.get("ASPERITY_CACHE_DIR")
    if root:
        path = Path(root)
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        path = Path(base) / "asperity"
    return path


def wisdom_file() -> Path:
    """The wisdom file of this pyFFTW version in the cache directory (:func:`cache_dir`)."""
    import pyfftw

    return cache_dir() / f"fftw_wisdom_{pyfftw.__version__}.npz"


def _read() -> tuple[tuple[bytes, ...], bool] | None:
    """The stored wisdom and whether it is known to be quiet; ``None`` if there is none that
    can be read (missing, unreadable, foreign: wisdom only saves planning time)."""
    try:
        with np.load(wisdom_file(), allow_pickle=False) as stored:
            count = sum(1 for name in stored.files if name.startswith("w"))
            wisdom = tuple(stored[f"w{i}"].tobytes() for i in range(count))
            quiet = _QUIET_KEY in stored.files and bool(stored[_QUIET_KEY].any())
    except (OSError, ValueError, KeyError, TypeError, ImportError):
        return None
    return wisdom, quiet


def load() -> None:
    """Import the wisdom cached on disk, once per process (never unpickled: raw bytes in an
    .npz), unless it is not known to be quiet and the machine is quiet now."""
    if _STATE.loaded:
        return
    _STATE.loaded = True
    stored = _read()
    if stored is None:
        return
    wisdom, quiet = stored
    if not quiet and machine_is_quiet():
        return  # planned busy (or by an older version): plan afresh, the save replaces it
    import pyfftw

    try:
        pyfftw.import_wisdom(wisdom)
    except (ValueError, TypeError):
        return
    _STATE.file_quiet = quiet


def save() -> None:
    """Write the process's wisdom with its quiet flag (atomically; a read-only home is
    silently skipped: it must not break a solve)."""
    try:
        import pyfftw

        path = wisdom_file()
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".tmp{os.getpid()}")
        arrays: dict[str, Any] = {
            f"w{i}": np.frombuffer(w, dtype=np.uint8) for i, w in enumerate(pyfftw.export_wisdom())
        }
        arrays[_QUIET_KEY] = np.array([_STATE.file_quiet], dtype=np.uint8)
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    except OSError:
        pass


@contextmanager
def planning() -> Iterator[None]:
    """Make FFTW plans inside this block: the wisdom on disk is imported first (:func:`load`),
    and if the block planned anything, the process's wisdom is saved, flagged busy for good if
    other processes held the CPUs while it planned. Call with the backend's lock held."""
    import pyfftw

    load()
    before_wisdom = pyfftw.export_wisdom()
    before = cpu_sample()
    yield
    if pyfftw.export_wisdom() == before_wisdom:
        return  # every plan came from wisdom: nothing was timed, nothing to judge
    share = others_share(before, cpu_sample())
    if share is not None and share >= QUIET_SHARE:  # unjudged (None) plans keep the flag
        _STATE.file_quiet = False
    save()
