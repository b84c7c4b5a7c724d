"""Plain-text height data: a matrix of heights, or ``x y z`` columns on a regular grid.

Both are in metres (SI) unless stated otherwise by the caller; lines starting with ``#``
or ``%`` are comments; separators may be spaces, tabs, commas or semicolons.

* Matrix: read as written, ``heights[i, j]`` is row ``i``, column ``j`` of the file, so the
  row index is axis 0 (x). The pixel size must come from the caller (``pixel_size``).
* ``x y z`` columns: the grid is rebuilt from the distinct x and y values; every grid
  node must appear exactly once; ``dx``, ``dy`` are the (uniform) coordinate steps.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from topo.errors import TopographyFileError
from topo.heightmap import HeightMap, LineProfile
from topo.io._common import make_provenance, read_all_bytes


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
    if pixel_size is None:
        raise ValueError(
            f"{path}: a plain height matrix carries no pixel size; give pixel_size= "
            "(or --pixel-size DX on the command line), in metres"
        )
    if np.ndim(pixel_size) == 0:
        return float(pixel_size), float(pixel_size)  # type: ignore[arg-type]
    dx, dy = pixel_size  # type: ignore[misc]
    return float(dx), float(dy)


def _is_xyz(rows: list[list[float]]) -> bool:
    if any(len(row) != 3 for row in rows) or len(rows) < 4:
        return False
    array = np.asarray(rows)
    n_x, n_y = np.unique(array[:, 0]).size, np.unique(array[:, 1]).size
    return n_x * n_y == len(rows) and n_x > 1 and n_y > 1


def read_text(
    path: str | Path, *, pixel_size: float | tuple[float, float] | None = None
) -> HeightMap | LineProfile:
    """Read a text height matrix (needs ``pixel_size`` in m) or ``x y z`` columns (m).

    A single column (or single row) of numbers is returned as a :class:`LineProfile`.

    Raises
    ------
    TopographyFileError
        Non-numeric lines, ragged rows (e.g. a truncated file), an incomplete or irregular
        x-y grid.
    ValueError
        A matrix without ``pixel_size``.
    """
    path = Path(path)
    rows = _rows(path)
    if _is_xyz(rows):
        array = np.asarray(rows)
        xs, ix = np.unique(array[:, 0], return_inverse=True)
        ys, iy = np.unique(array[:, 1], return_inverse=True)
        steps = [np.diff(xs), np.diff(ys)]
        for name, step in zip(("x", "y"), steps, strict=True):
            if np.ptp(step) > 1e-6 * abs(step.mean()):
                raise TopographyFileError(path, f"{name} column", "is not a uniform grid")
        heights = np.full((xs.size, ys.size), np.nan)
        heights[ix, iy] = array[:, 2]
        provenance = make_provenance(path, "xyz-text", channel="z", units={"all": "m (assumed)"})
        return HeightMap(heights, steps[0].mean(), steps[1].mean(), False, provenance)
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
