"""The readers' memory budget and physical bounds, and the checks that enforce them.

Every reader checks a file's declared sizes and scale factors against these limits *before*
it allocates or decompresses anything, and refuses a file outside them with a
:class:`~asperity.topo.errors.TopographyFileError` subclass naming the file and field:

* memory: one map holds at most :data:`MAX_MAP_BYTES` (2 GiB) of float64 heights, i.e.
  :data:`MAX_MAP_POINTS` points (:class:`~asperity.topo.errors.OverBudgetError`); a file is
  read whole only up to :data:`MAX_FILE_BYTES`; a compressed member (zip, HDF5 chunk) may
  not claim more than :data:`MAX_DEFLATE_RATIO` bytes per stored byte (deflate's limit).
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
from pathlib import Path

from asperity.topo.errors import OverBudgetError, PhysicalBoundsError

#: Largest map a reader builds: float64 heights, bytes (2 GiB).
MAX_MAP_BYTES = 2 * 1024**3
#: Largest number of points of one map (``MAX_MAP_BYTES / 8``).
MAX_MAP_POINTS = MAX_MAP_BYTES // 8
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


def check_map_points(path: str | Path, field: str, *dims: int) -> int:
    """Refuse a map whose declared dimensions exceed the memory budget.

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
        If ``prod(dims) * 8 bytes > MAX_MAP_BYTES``.
    """
    count = math.prod(int(d) for d in dims)
    if count > MAX_MAP_POINTS:
        raise OverBudgetError(
            path,
            field,
            f"declare {' x '.join(str(d) for d in dims)} = {count} points "
            f"({count * 8} bytes of float64); the readers' memory budget is "
            f"{MAX_MAP_BYTES} bytes per map",
            expected=MAX_MAP_POINTS,
            found=count,
        )
    return count


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
