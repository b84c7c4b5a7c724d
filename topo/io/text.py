"""Plain-text height data: a matrix of heights, or ``x y z`` columns on a regular grid.

Both are in metres (SI) unless stated otherwise by the caller; lines starting with ``#``
or ``%`` are comments; separators may be spaces, tabs, commas or semicolons.

* Matrix: read as written, ``heights[i, j]`` is row ``i``, column ``j`` of the file, so the
  row index is axis 0 (x). The pixel size must come from the caller (``pixel_size``).
* ``x y z`` columns (three columns whose first two repeat like grid coordinates): the grid
  is rebuilt from the distinct x and y values, whose steps must be uniform (within 1e-4 of
  the step: a non-uniform grid is refused, never interpolated); ``dx``, ``dy`` are those
  steps. A node may appear at most once; nodes absent from the file (instruments often
  skip invalid points) become missing pixels (NaN), counted in ``provenance["missing_nodes"]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import caller_pixel_size, make_provenance, read_all_bytes

#: Largest relative deviation of an x or y step from the mean step of an x-y-z grid.
_STEP_TOLERANCE = 1e-4


def _rows(path: Path) -> list[list[float]]:
    rows: list[list[float]] = []
    text = read_all_bytes(path).decode("latin-1")
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped[0] in "#%":
            continue
        fields = stripped.replace(",", " ").replace(";", " ").split()
        try:
            rows.append([float(value) for value in fields])
        except ValueError:
            raise TopographyFileError(
                path, f"line {number}", f"is {stripped[:60]!r}; expected numbers only"
            ) from None
    if not rows:
        raise TopographyFileError(path, "data", "no numeric lines found")
    return rows


def _pixel_sizes(path: Path, pixel_size: float | tuple[float, float] | None) -> tuple[float, float]:
    sizes = caller_pixel_size(path, pixel_size)
    if sizes is None:
        raise InputError(
            f"{path}: a plain height matrix carries no pixel size; give pixel_size= "
            "(or --pixel-size DX on the command line), in metres"
        )
    return sizes


def _looks_like_xyz(rows: list[list[float]]) -> bool:
    """Three columns whose first two repeat like grid coordinates (not a 3-column matrix)."""
    if len(rows) < 4 or any(len(row) != 3 for row in rows):
        return False
    array = np.asarray(rows)
    n_x, n_y = np.unique(array[:, 0]).size, np.unique(array[:, 1]).size
    return 1 < n_x < len(rows) and 1 < n_y < len(rows) and n_x * n_y <= 2 * len(rows)


def _grid_step(path: Path, values: np.ndarray, name: str) -> float:
    """The uniform step (m) of the sorted distinct coordinates ``values``, or refuse."""
    steps = np.diff(values)
    step = float(steps.mean())
    if np.ptp(steps) > _STEP_TOLERANCE * step:
        worst = int(np.argmax(np.abs(steps - step)))
        raise TopographyFileError(
            path,
            f"{name} column",
            f"is not a uniform grid: steps range from {steps.min():.6g} to {steps.max():.6g} "
            f"(e.g. {values[worst]:.6g} -> {values[worst + 1]:.6g}); expected one constant "
            f"step (within {_STEP_TOLERANCE:g} of it); resample the data onto a regular grid",
        )
    return step


def _read_xyz(path: Path, rows: list[list[float]]) -> HeightMap:
    array = np.asarray(rows)
    xs, ix = np.unique(array[:, 0], return_inverse=True)
    ys, iy = np.unique(array[:, 1], return_inverse=True)
    dx = _grid_step(path, xs, "x")
    dy = _grid_step(path, ys, "y")
    node = ix * ys.size + iy
    counts = np.bincount(node, minlength=xs.size * ys.size)
    if counts.max() > 1:
        first = int(np.flatnonzero(counts > 1)[0])
        raise TopographyFileError(
            path,
            "x y columns",
            f"give the node ({xs[first // ys.size]:.6g}, {ys[first % ys.size]:.6g}) "
            f"{counts[first]} times; expected every grid node at most once "
            "(if this is a 3-column height matrix, save it as .npy instead)",
        )
    heights = np.full((xs.size, ys.size), np.nan)
    heights[ix, iy] = array[:, 2]
    missing = int(xs.size * ys.size - len(rows))
    provenance = make_provenance(
        path,
        "xyz-text",
        channel="z",
        units={"all": "m (assumed)"},
        missing_nodes=missing or None,
    )
    return HeightMap(heights, dx, dy, False, provenance)


def read_text(
    path: str | Path, *, pixel_size: float | tuple[float, float] | None = None
) -> HeightMap | LineProfile:
    """Read a text height matrix (needs ``pixel_size`` in m) or ``x y z`` columns (m).

    A single column (or single row) of numbers is returned as a :class:`LineProfile`.

    Parameters
    ----------
    path : str or Path
        The text file (heights and coordinates in m).
    pixel_size : float or (float, float), optional
        ``dx`` or ``(dx, dy)`` in m for a matrix; refused for x-y-z columns.

    Returns
    -------
    HeightMap or LineProfile

    Raises
    ------
    TopographyFileError
        Non-numeric lines, ragged rows (e.g. a truncated file), a non-uniform x-y grid or
        a node given twice.
    ValueError
        A matrix without ``pixel_size``, an invalid ``pixel_size``, or ``pixel_size``
        given for x-y-z columns.
    """
    path = Path(path)
    rows = _rows(path)
    if _looks_like_xyz(rows):
        if pixel_size is not None:
            raise InputError(
                f"{path}: pixel_size given, but x y z columns carry their own coordinates "
                "(the pixel sizes are their steps); leave pixel_size out"
            )
        return _read_xyz(path, rows)
    widths = {len(row) for row in rows}
    if len(widths) != 1:
        lengths = [len(row) for row in rows]
        bad = next(i for i, n in enumerate(lengths) if n != lengths[0])
        raise TopographyFileError(
            path,
            f"data row {bad + 1}",
            f"has {lengths[bad]} values; expected {lengths[0]} like the first row "
            "(ragged or truncated matrix)",
        )
    heights = np.asarray(rows, dtype=np.float64)
    dx, dy = _pixel_sizes(path, pixel_size)
    provenance = make_provenance(
        path, "matrix-text", channel="heights", units={"all": "m (assumed)"}
    )
    if heights.shape[1] == 1 or heights.shape[0] == 1:
        return LineProfile(heights.ravel(), dx, provenance)
    return HeightMap(heights, dx, dy, False, provenance)
