"""The readers' memory budget and physical bounds, and the checks that enforce them.

Every reader checks a file's declared sizes and scale factors against these limits *before*
it allocates or decompresses anything, and refuses a file outside them with a
:class:`~asperity.topo.errors.TopographyFileError` subclass naming the file and field:

* memory: a map is refused (:class:`~asperity.topo.errors.OverBudgetError`) from its
  declared grid, before anything is read or decompressed, when what the pipeline does with
  it would not fit the memory budget: :data:`PIPELINE_BYTES_PER_PIXEL` (128) bytes a pixel
  plus :data:`PIPELINE_BASE_BYTES` (0.5 GiB) must fit in the budget, i.e. at most
  :func:`max_map_points` points (about 11,400^2 by default). The budget
  (:func:`memory_budget`) is the smallest of the configured budget, 16 GiB unless the
  environment variable ``ASPERITY_MEMORY_BUDGET`` says otherwise (bytes, or a number with
  ``KiB``/``MiB``/``GiB``/``TiB`` or ``kB``/``MB``/``GB``/``TB``), and the ceilings the
  system sets (:func:`system_memory_ceilings`): ``RLIMIT_AS`` / ``RLIMIT_DATA`` (``ulimit
  -v`` / ``-d``), the control group's memory limit (a batch system's ``memory.max``) and the
  memory available now; the refusal names the one that refuses. The bytes a pixel were measured:
  the peak resident memory of ``asperity run`` (the default job: resolution scan, BEM,
  calibration, PSD) on maps of 500^2 .. 3000^2 pixels, measured with ``/usr/bin/time -v``,
  fitted 171 bytes a pixel + 0.48 GiB (scatter 8 %), rounded up to 200; since the BEM's
  memory work (issue 28: one shared transform workspace, no stored |q| multipliers, results
  taken from the solver's state) the default job on a 2000^2 map (5 um pixels) peaks at
  0.856 GiB, 101 bytes a pixel above the same 0.48 GiB, rounded up to 128. A file is read whole
  only up to :data:`MAX_FILE_BYTES`; a compressed member (zip, HDF5 chunk) may not claim
  more than :data:`MAX_DEFLATE_RATIO` bytes per stored byte (deflate's limit).
* lateral pixel size: finite, in :data:`PIXEL_SIZE_BOUNDS_M` (1 pm .. 1 m)
  (:class:`~asperity.topo.errors.PhysicalBoundsError`).
* height scale factor of integer data (m per raw count): finite, nonzero, with magnitude in
  :data:`HEIGHT_STEP_BOUNDS_M` (1e-24 m .. 1 m); negative only where the format defines an
  inversion (MetroPro's ``sign``), refused elsewhere.
* heights: no infinite value (in every format: infinity is never a missing-point marker);
  finite heights within :data:`MAX_ABS_HEIGHT_M` (1 m) of zero. Heights that vary, but by
  less than :data:`MIN_HEIGHT_SPREAD_M` (1 fm), are read as stored and refused by the
  preparation (:func:`asperity.topo.preparation.check_height_spread`) before any statistic:
  a wrong unit or scale, whose rms no instrument resolves and whose squares underflow.
"""

from __future__ import annotations

import math
import os
import re
import time
from pathlib import Path

from asperity.errors import InputError, cut
from asperity.topo.errors import OverBudgetError, PhysicalBoundsError

_BYTE_UNITS = {
    "": 1,
    "b": 1,
    "kib": 1024,
    "mib": 1024**2,
    "gib": 1024**3,
    "tib": 1024**4,
    "kb": 1000,
    "mb": 1000**2,
    "gb": 1000**3,
    "tb": 1000**4,
}

#: Peak memory of the pipeline per pixel of the map, bytes (measured: see the module notes).
PIPELINE_BYTES_PER_PIXEL = 128
#: Memory of the pipeline that does not grow with the map (interpreter, libraries), bytes.
PIPELINE_BASE_BYTES = 512 * 1024**2
#: Memory budget when ``ASPERITY_MEMORY_BUDGET`` is not set, bytes (16 GiB).
DEFAULT_MEMORY_BUDGET_BYTES = 16 * 1024**3
#: The environment variable that sets the memory budget.
MEMORY_BUDGET_ENV = "ASPERITY_MEMORY_BUDGET"
#: Largest number of points of one map under the default budget.
MAX_MAP_POINTS = (DEFAULT_MEMORY_BUDGET_BYTES - PIPELINE_BASE_BYTES) // PIPELINE_BYTES_PER_PIXEL
#: float64 bytes of the largest map under the default budget (``MAX_MAP_POINTS * 8``).
MAX_MAP_BYTES = MAX_MAP_POINTS * 8
#: Largest file read whole into memory, bytes (4 GiB).
MAX_FILE_BYTES = 4 * 1024**3
#: Deflate cannot expand more than about 1032 bytes per compressed byte.
MAX_DEFLATE_RATIO = 1100
#: Lateral pixel sizes accepted, m (inclusive).
PIXEL_SIZE_BOUNDS_M = (1e-12, 1.0)
#: Magnitudes of the height step of integer data accepted, m per count (inclusive).
HEIGHT_STEP_BOUNDS_M = (1e-24, 1.0)
#: Largest magnitude of a height, m.
MAX_ABS_HEIGHT_M = 1.0
#: Smallest nonzero spread (max - min) of a map's heights, m: a femtometre, far below any
#: instrument's resolution (and well above 1e-154 m, where squares underflow to zero).
MIN_HEIGHT_SPREAD_M = 1e-15


def configured_memory_budget_bytes() -> int:
    """The configured memory budget, bytes: ``ASPERITY_MEMORY_BUDGET``, or 16 GiB.

    Returns
    -------
    int

    Raises
    ------
    InputError
        ``ASPERITY_MEMORY_BUDGET`` set to something other than a positive size (``64GiB``,
        ``8e9``), or one too small for the pipeline's base memory.
    """
    text = os.environ.get(MEMORY_BUDGET_ENV, "").strip()
    if not text:
        return DEFAULT_MEMORY_BUDGET_BYTES
    match = re.fullmatch(r"(\d+(?:\.\d*)?(?:[eE]\d+)?)\s*([A-Za-z]*)", text[:100])
    unit = match.group(2).lower() if match else ""
    if match is None or unit not in _BYTE_UNITS:
        raise InputError(
            f"{MEMORY_BUDGET_ENV}: is {cut(repr(text))}; expected a size such as 64GiB, 8GB or "
            "8e9 (bytes)"
        )
    budget = int(float(match.group(1)) * _BYTE_UNITS[unit])
    if budget <= PIPELINE_BASE_BYTES:
        raise InputError(
            f"{MEMORY_BUDGET_ENV}: is {cut(repr(text))}; expected more than the pipeline's base "
            f"memory of {PIPELINE_BASE_BYTES / 1024**3:g} GiB"
        )
    return budget


#: How long the system's memory ceilings are reused before they are read again, s (the
#: text reader judges its budget line by line).
_CEILINGS_TTL_S = 1.0
_ceilings_cache: list = [float("-inf"), {}]


def system_memory_ceilings() -> dict[str, int]:
    """The ceilings the system puts on this process's memory, bytes, each by its name.

    ``RLIMIT_AS`` (the address-space limit, ``ulimit -v``) and ``RLIMIT_DATA`` (``ulimit
    -d``), when set; the memory limit of the process's control group (cgroup v2
    ``memory.max`` of its group and the groups above it, or cgroup v1
    ``memory.limit_in_bytes``), when set; and the memory available now (``MemAvailable`` of
    ``/proc/meminfo``, plus this process's own resident memory, which the pipeline's base
    memory already counts). A ceiling the system does not report is left out. Read at most
    once a second (the values are reused in between).

    Returns
    -------
    dict
        ``{description: bytes}``, the description naming where the ceiling comes from.
    """
    now = time.monotonic()
    if now - _ceilings_cache[0] > _CEILINGS_TTL_S:
        ceilings = {**_rlimits(), **_cgroup_limits(), **_available_memory()}
        _ceilings_cache[:] = [now, ceilings]
    return dict(_ceilings_cache[1])


def _rlimits() -> dict[str, int]:
    """RLIMIT_AS and RLIMIT_DATA's soft limits, where set (POSIX; none elsewhere)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not POSIX
        return {}
    found = {}
    for name, words in (("RLIMIT_AS", "ulimit -v"), ("RLIMIT_DATA", "ulimit -d")):
        which = getattr(resource, name, None)
        if which is None:  # pragma: no cover
            continue
        soft, _hard = resource.getrlimit(which)
        if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
            found[f"the process limit {name} ({words})"] = int(soft)
    return found


def _read_bytes_value(path: Path) -> int | None:
    """A byte count stored in a cgroup file, or None (absent, unreadable, ``max``)."""
    try:
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    if not text.isdigit() or int(text) >= 2**60:  # "max", or v1's "no limit" (~2^63)
        return None
    return int(text)


def _cgroup_limits(
    proc: Path = Path("/proc/self/cgroup"), root: Path = Path("/sys/fs/cgroup")
) -> dict[str, int]:
    """The smallest memory limit of this process's control group and those above it.

    Parameters
    ----------
    proc : Path
        The process's list of groups (``/proc/self/cgroup``).
    root : Path
        Where the control groups are mounted (``/sys/fs/cgroup``).
    """
    try:
        lines = proc.read_text(encoding="utf-8").splitlines()
    except OSError:
        return {}
    limits = []
    for line in lines:
        hierarchy, _, rest = line.partition(":")
        controllers, _, group = rest.partition(":")
        if hierarchy == "0" and controllers == "":  # cgroup v2: memory.max up the tree
            folder = root / group.lstrip("/")
            for level in (folder, *folder.parents):
                limits.append((_read_bytes_value(level / "memory.max"), level / "memory.max"))
                if level == root:
                    break
        elif "memory" in controllers.split(","):  # cgroup v1
            for base in (root / "memory" / group.lstrip("/"), root / "memory"):
                file = base / "memory.limit_in_bytes"
                limits.append((_read_bytes_value(file), file))
    known = [(value, file) for value, file in limits if value is not None]
    if not known:
        return {}
    value, file = min(known)
    return {f"the control group's memory limit ({file})": value}


def _meminfo_bytes(path: Path, field: str) -> int | None:
    """A ``field: N kB`` line of a /proc file, bytes (None when absent)."""
    try:
        text = path.read_text(encoding="ascii", errors="replace")
    except OSError:
        return None
    match = re.search(rf"^{field}:\s+(\d+)\s*kB", text, re.MULTILINE)
    return int(match.group(1)) * 1024 if match else None


def _available_memory() -> dict[str, int]:
    """MemAvailable plus this process's resident memory (Linux; none elsewhere)."""
    available = _meminfo_bytes(Path("/proc/meminfo"), "MemAvailable")
    if available is None:
        return {}
    resident = _meminfo_bytes(Path("/proc/self/status"), "VmRSS") or 0
    return {
        "the memory available now (MemAvailable + this process's resident memory)": (
            available + resident
        )
    }


def memory_budget() -> tuple[int, str]:
    """The memory budget of one map's pipeline, bytes, and what sets it.

    The smallest of the configured budget (:func:`configured_memory_budget_bytes`) and the
    system's ceilings (:func:`system_memory_ceilings`): a map that fits 16 GiB but not the
    6 GiB a batch system grants is refused before its first allocation, naming the ceiling,
    instead of failing with a MemoryError minutes later.

    Returns
    -------
    (int, str)
        The budget in bytes, and the words naming where it comes from.
    """
    configured = configured_memory_budget_bytes()
    source = f"the configured budget ({MEMORY_BUDGET_ENV} or its default of 16 GiB)"
    if MEMORY_BUDGET_ENV in os.environ and os.environ[MEMORY_BUDGET_ENV].strip():
        source = f"the configured budget ({MEMORY_BUDGET_ENV})"
    budget = (configured, source)
    for words, value in system_memory_ceilings().items():
        if value < budget[0]:
            budget = (value, words)
    return budget


def memory_budget_bytes() -> int:
    """The memory budget of one map's pipeline, bytes (:func:`memory_budget`).

    Returns
    -------
    int

    Raises
    ------
    InputError
        ``ASPERITY_MEMORY_BUDGET`` set to something other than a positive size (``64GiB``,
        ``8e9``), or one too small for the pipeline's base memory.
    """
    return memory_budget()[0]


def max_map_points() -> int:
    """Largest number of points of one map under the memory budget (:func:`memory_budget`);
    zero when the budget does not even hold the pipeline's base memory."""
    return max((memory_budget_bytes() - PIPELINE_BASE_BYTES) // PIPELINE_BYTES_PER_PIXEL, 0)


def check_map_points(path: str | Path, field: str, *dims: int) -> int:
    """Refuse a map whose declared dimensions need more memory than the budget.

    Parameters
    ----------
    path : str or Path
        The file (for the message).
    field : str
        The size fields that declare ``dims``.
    *dims : int
        The declared dimensions (counts of points).

    Returns
    -------
    int
        The number of points, ``prod(dims)``.

    Raises
    ------
    OverBudgetError
        If the pipeline's peak memory for ``prod(dims)`` points
        (``PIPELINE_BYTES_PER_PIXEL`` bytes a point + ``PIPELINE_BASE_BYTES``) exceeds the
        budget; the message names the size, the budget and how to raise it.
    """
    count = math.prod(int(d) for d in dims)
    configured_memory_budget_bytes()  # a malformed ASPERITY_MEMORY_BUDGET is refused always
    if count <= _SMALL_MAP_POINTS:  # a small map, or a text file's first lines: no system call
        return count
    budget, source = memory_budget()
    limit = max((budget - PIPELINE_BASE_BYTES) // PIPELINE_BYTES_PER_PIXEL, 0)
    if count > limit:
        need = count * PIPELINE_BYTES_PER_PIXEL + PIPELINE_BASE_BYTES
        raise OverBudgetError(
            path,
            field,
            f"declare {' x '.join(str(d) for d in dims)} = {count} points; the pipeline "
            f"needs about {PIPELINE_BYTES_PER_PIXEL} bytes a point ({need / 1024**3:.3g} GiB "
            f"for this map), over the memory budget of {budget / 1024**3:.3g} GiB set by "
            f"{source} (at most {limit} points); {_remedy(source)}",
            expected=limit,
            found=count,
        )
    return count


#: Maps of at most this many points fit any budget that holds the base memory (1 M points,
#: 128 MiB): judged without reading the system's ceilings.
_SMALL_MAP_POINTS = 2**20


def _remedy(source: str) -> str:
    """What the user can do about the budget ``source`` sets."""
    if source.startswith("the configured budget"):
        return (
            "crop or resample the map, or raise the budget with the environment variable "
            f"{MEMORY_BUDGET_ENV} (e.g. {MEMORY_BUDGET_ENV}=64GiB)"
        )
    return (
        "crop or resample the map, or run where more memory is granted (raising "
        f"{MEMORY_BUDGET_ENV} does not lift this ceiling)"
    )


def check_pixel_size(path: str | Path, field: str, value: float) -> float:
    """Return ``value`` (a lateral pixel size, m) if it is within the physical bounds.

    Parameters
    ----------
    path : str or Path
        The file (for the message).
    field : str
        The header field the pixel size comes from.
    value : float
        Pixel size in m.

    Returns
    -------
    float

    Raises
    ------
    PhysicalBoundsError
        Not finite or outside :data:`PIXEL_SIZE_BOUNDS_M`.
    """
    low, high = PIXEL_SIZE_BOUNDS_M
    size = float(value)
    if not (low <= size <= high):
        raise PhysicalBoundsError(
            path,
            field,
            f"gives a pixel size of {size!r} m; expected {low:g} m .. {high:g} m",
            expected=PIXEL_SIZE_BOUNDS_M,
            found=size,
        )
    return size


def check_height_step(
    path: str | Path, field: str, value: float, *, inversion_defined: bool = False
) -> float:
    """Return ``value`` (a height scale factor, m per count) if it is physically sensible.

    Parameters
    ----------
    path : str or Path
        The file (for the message).
    field : str
        The header field(s) the factor comes from.
    value : float
        Metres per raw count (for a factor without unit: the factor applied to metres).
    inversion_defined : bool
        Whether the format defines a negative factor as an inverted height axis.

    Returns
    -------
    float

    Raises
    ------
    PhysicalBoundsError
        Zero, not finite, negative where no inversion is defined, or a magnitude outside
        :data:`HEIGHT_STEP_BOUNDS_M`.
    """
    low, high = HEIGHT_STEP_BOUNDS_M
    step = float(value)
    if step < 0 and not inversion_defined:
        raise PhysicalBoundsError(
            path,
            field,
            f"is {step!r} m per count; a negative step would invert the surface and this "
            "format defines no inversion; expected > 0",
            expected="> 0",
            found=step,
        )
    if not (low <= abs(step) <= high):
        raise PhysicalBoundsError(
            path,
            field,
            f"is {step!r} m per count; expected a finite magnitude in {low:g} .. {high:g} m "
            "(a zero factor would make every height 0)",
            expected=HEIGHT_STEP_BOUNDS_M,
            found=step,
        )
    return step
