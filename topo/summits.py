"""Summit (asperity) statistics of a height map, as in the paper's Appendix A.

A summit is a valid pixel strictly higher than its 4 nearest neighbours (``neighbours=4``,
the paper's rule) or its 8 neighbours (``neighbours=8``). Pixels next to a missing (NaN)
pixel cannot be summits, nor can edge pixels of a non-periodic map (they lack neighbours);
a periodic map wraps around. From the N summits of a map:

* asperity density ``eta = N / A_n`` (1/m^2), with ``A_n`` the sampling area as in
  Appendix A (``A_n = 10 x 10 mm^2`` for the paper's map): ``A_n = n_a dx dy``, where
  ``n_a`` counts the valid pixels none of whose 4 (or 8) compared neighbours is missing.
  A complete map has ``A_n = nx dx ny dy``, its whole area, edge rows and columns
  included (they cannot host a summit, as in the paper). Holes (missing pixels) and the
  pixels around them are left out of the count and of the area alike, so that eta of a
  map with holes estimates the eta of the complete map. (asperity 0.3 and earlier also
  left out the edge rows and columns of a non-periodic map: ``(nx-2)(ny-2) dx dy`` for a
  complete map, which raised eta by ``nx ny / ((nx-2)(ny-2))``, +11 % on a 39 x 39 grid,
  the paper's map at 260 um; periodic maps are unchanged. That interior area is still
  ``n_candidates dx dy``);
* rms summit height ``sigma_s = sqrt(<(z - <z>)^2>)`` over the summits, about the mean
  summit height (m);
* mean summit radius ``R = 1/2 <|z_xx|^-1 + |z_yy|^-1>`` (m), with the central differences
  ``z_xx = (z[i+1,j] - 2 z[i,j] + z[i-1,j]) / dx^2`` and
  ``z_yy = (z[i,j+1] - 2 z[i,j] + z[i,j-1]) / dy^2``.

Everything is computed in one pass of a compiled kernel that never copies the map; the
decimated maps of the resolution scan are strided views of the original.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from asperity.errors import InputError
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.resampling import decimate


@numba.njit(cache=True, inline="always")
def _is_summit(h, i, j, im, ip, jm, jp, eight):
    z = h[i, j]
    if not (z > h[im, j] and z > h[ip, j] and z > h[i, jm] and z > h[i, jp]):
        return False
    if eight:
        if not (z > h[im, jm] and z > h[im, jp] and z > h[ip, jm] and z > h[ip, jp]):
            return False
    return True


@numba.njit(cache=True)
def _row_moments(h, i, im, ip, j, jm, jp, inv_dx2, inv_dy2, eight, acc):
    """Add pixel (i, j) to ``acc`` = [count, mean, m2, radius_sum] if it is a summit."""
    z = h[i, j]
    left = h[i, jm]
    right = h[i, jp]
    if not (z > left and z > right):
        return
    up = h[im, j]
    down = h[ip, j]
    if not (z > up and z > down):
        return
    if eight:
        if not (z > h[im, jm] and z > h[im, jp] and z > h[ip, jm] and z > h[ip, jp]):
            return
    z_xx = (down - 2.0 * z + up) * inv_dx2
    z_yy = (right - 2.0 * z + left) * inv_dy2
    acc[3] += 0.5 * (1.0 / abs(z_xx) + 1.0 / abs(z_yy))
    acc[0] += 1.0
    delta = z - acc[1]
    acc[1] += delta / acc[0]
    acc[2] += delta * (z - acc[1])


@numba.njit(cache=True)
def _summit_moments(h, dx, dy, periodic, eight):
    """Count, mean height, sum of squared deviations and sum of radii of the summits.

    One pass over the map; interior columns need no wrap-around test, the two edge
    columns (periodic maps only) are handled separately. NaN compares False, so a NaN
    pixel or a NaN neighbour never makes a summit.
    """
    nx, ny = h.shape
    acc = np.zeros(4)
    if nx < 3 or ny < 3:
        return 0, 0.0, 0.0, 0.0
    inv_dx2 = 1.0 / (dx * dx)
    inv_dy2 = 1.0 / (dy * dy)
    i_start, i_stop = (0, nx) if periodic else (1, nx - 1)
    for i in range(i_start, i_stop):
        im = i - 1 if i > 0 else nx - 1
        ip = i + 1 if i < nx - 1 else 0
        if periodic:
            _row_moments(h, i, im, ip, 0, ny - 1, 1, inv_dx2, inv_dy2, eight, acc)
        for j in range(1, ny - 1):
            z = h[i, j]
            if z > h[i, j + 1] and z > h[i, j - 1]:
                _row_moments(h, i, im, ip, j, j - 1, j + 1, inv_dx2, inv_dy2, eight, acc)
        if periodic:
            _row_moments(h, i, im, ip, ny - 1, ny - 2, 0, inv_dx2, inv_dy2, eight, acc)
    return int(acc[0]), acc[1], acc[2], acc[3]


@numba.njit(cache=True, inline="always")
def _nan_at(h, i, j, periodic):
    """True if (i, j) is a missing pixel; an index off a non-periodic map is not missing."""
    nx, ny = h.shape
    if periodic:
        return np.isnan(h[i % nx, j % ny])
    if i < 0 or i >= nx or j < 0 or j >= ny:
        return False
    return np.isnan(h[i, j])


@numba.njit(cache=True)
def _count_pixels(h, periodic, eight):
    """Pixels that could host a summit, and pixels of the nominal area ``A_n``.

    A candidate is valid with every compared neighbour present and valid: edge pixels of a
    non-periodic map lack a neighbour, a periodic map wraps around; with ``eight`` the
    diagonal neighbours must be valid too. The area pixels are the valid pixels with no
    compared neighbour missing (NaN): the edge of the map belongs to ``A_n`` (Appendix A:
    ``A_n`` is the whole sampling area), the rim of a hole does not.
    """
    nx, ny = h.shape
    if nx < 3 or ny < 3:
        return 0, 0
    candidates = 0
    area = 0
    for i in range(nx):
        edge_i = not periodic and (i == 0 or i == nx - 1)
        for j in range(ny):
            if np.isnan(h[i, j]):
                continue
            if (
                _nan_at(h, i - 1, j, periodic)
                or _nan_at(h, i + 1, j, periodic)
                or _nan_at(h, i, j - 1, periodic)
                or _nan_at(h, i, j + 1, periodic)
            ):
                continue
            if eight and (
                _nan_at(h, i - 1, j - 1, periodic)
                or _nan_at(h, i - 1, j + 1, periodic)
                or _nan_at(h, i + 1, j - 1, periodic)
                or _nan_at(h, i + 1, j + 1, periodic)
            ):
                continue
            area += 1
            if not (edge_i or (not periodic and (j == 0 or j == ny - 1))):
                candidates += 1
    return candidates, area


@numba.njit(cache=True)
def _summit_mask(h, periodic, eight):
    nx, ny = h.shape
    mask = np.zeros((nx, ny), dtype=np.bool_)
    if nx < 3 or ny < 3:
        return mask
    i_start, i_stop = (0, nx) if periodic else (1, nx - 1)
    j_start, j_stop = (0, ny) if periodic else (1, ny - 1)
    for i in range(i_start, i_stop):
        im = i - 1 if i > 0 else nx - 1
        ip = i + 1 if i < nx - 1 else 0
        for j in range(j_start, j_stop):
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            mask[i, j] = _is_summit(h, i, j, im, ip, jm, jp, eight)
    return mask


def _check_analysable(surface: HeightMap, grid: HeightMap, stride: int) -> None:
    """Refuse a grid on which no pixel can have a neighbour on each side."""
    source = surface.provenance.get("file", "the map")
    if grid.nx < 3 or grid.ny < 3:
        grid_text = (
            f"has {grid.nx} x {grid.ny} pixels"
            if grid is surface
            else f"({surface.nx} x {surface.ny} pixels) decimated by stride {stride} "
            f"leaves {grid.nx} x {grid.ny} pixels"
        )
        raise InputError(
            f"summit_statistics: {source} {grid_text}; a summit needs a neighbour on each "
            "side, so at least 3 x 3 pixels are required"
        )


def _check_not_all_missing(surface: HeightMap, grid: HeightMap, stride: int) -> None:
    """Refuse a grid without valid pixels (called only when no summit was found)."""
    source = surface.provenance.get("file", "the map")
    if grid.n_missing == grid.nx * grid.ny:
        raise InputError(
            f"summit_statistics: every pixel of {source} (stride {stride}) is missing (NaN); "
            "there is nothing to analyse"
        )


def _check_neighbours(neighbours: int) -> bool:
    if neighbours not in (4, 8):
        raise InputError(f"neighbours: expected 4 (the paper's rule) or 8, got {neighbours!r}")
    return neighbours == 8


@dataclass(frozen=True)
class SummitStatistics:
    """The three roughness inputs of the statistical model (Appendix A), SI units.

    Attributes
    ----------
    n_summits : int
        Number of summits N.
    asperity_density : float
        ``eta = N / A_n`` (1/m^2).
    summit_radius : float
        Mean summit radius R (m); NaN without summits.
    summit_height_rms : float
        ``sigma_s``, rms summit height about the mean summit height (m); NaN without summits.
    dx, dy : float
        Pixel sizes of the analysed (decimated) grid (m).
    nominal_area : float
        ``A_n`` over which the summits are counted (m^2): the valid area, ``nx*dx*ny*dy``
        for a complete map (the rule of the module docstring, Appendix A).
    stride : int
        Decimation applied before the analysis.
    neighbours : int
        4 or 8.
    mean_summit_height : float
        Mean summit height (m), relative to the map's height datum.
    n_candidates : int
        Pixels that could host a summit (valid, with every compared neighbour present and
        valid: not the edge of a non-periodic map).
    grid_area : float
        Area of the whole analysed grid, ``nx*dx*ny*dy`` (m^2), holes included.
    """

    n_summits: int
    asperity_density: float
    summit_radius: float
    summit_height_rms: float
    dx: float
    dy: float
    nominal_area: float
    stride: int
    neighbours: int = 4
    mean_summit_height: float = float("nan")
    n_candidates: int = 0
    grid_area: float = float("nan")

    @property
    def valid_fraction(self) -> float:
        """``nominal_area / grid_area``: the valid fraction of the grid (1 without holes)."""
        return self.nominal_area / self.grid_area

    def as_dict(self) -> dict:
        """The statistics as a plain dict of Python numbers."""
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


def summit_statistics(
    surface: HeightMap, *, stride: int = 1, neighbours: int = 4
) -> SummitStatistics:
    """Asperity density, mean summit radius and rms summit height (paper, Appendix A).

    Parameters
    ----------
    surface : HeightMap
        Heights in m (level it first, e.g. ``topo.level(surface, "plane")``; summits are
        found on the heights as given). A LineProfile is refused.
    stride : int
        Analyse ``decimate(surface, stride)`` (keep one point in ``stride``; a view).
    neighbours : {4, 8}
        Summit rule: strictly higher than the 4 (paper) or 8 nearest neighbours.

    Returns
    -------
    SummitStatistics
        ``eta`` in 1/m^2, ``R`` and ``sigma_s`` in m (NaN when there is no summit; eta NaN
        when no pixel could host one). ``eta = N / A_n`` with ``A_n`` the sampling area of
        Appendix A: ``nx dx ny dy`` for a complete map, edges included; with holes, the
        area of the valid pixels none of whose compared neighbours is missing. Missing
        pixels therefore lower N and A_n together: on a map with holes eta estimates the
        hole-free eta instead of being diluted by the holes' area.

    Raises
    ------
    InputError
        A LineProfile; an analysed grid smaller than 3 x 3 pixels (e.g. a stride larger
        than a third of the map) or without any valid pixel; ``neighbours`` not 4 or 8.

    Notes
    -----
    Appendix A of the paper: N summits by the 4-nearest-neighbour rule over the sampling
    area ``A_n`` (the whole 10 x 10 mm^2 map; for a decimated map the ``nx x ny`` grid of
    pixels ``stride*dx`` wide) give ``eta = N/A_n`` (652.1 mm^-2 for the paper's map at 2 um),
    ``sigma_s = sqrt(<z^2>)`` about the mean summit height (0.032 mm) and
    ``R = 1/2 <|z_xx|^-1 + |z_yy|^-1>`` by central differences (0.041 mm).
    """
    surface = require_height_map(surface, "summit_statistics")
    eight = _check_neighbours(neighbours)
    grid = decimate(surface, stride)
    _check_analysable(surface, grid, stride)
    count, mean, m2, radius_sum = _summit_moments(
        grid.heights, grid.dx, grid.dy, grid.periodic, eight
    )
    candidates, area_pixels = _count_pixels(grid.heights, grid.periodic, eight)
    candidates = int(candidates)
    area = int(area_pixels) * grid.dx * grid.dy
    if count == 0:
        _check_not_all_missing(surface, grid, stride)
        radius = rms = mean_height = float("nan")
    else:
        radius = radius_sum / count
        rms = float(np.sqrt(m2 / count))
        mean_height = mean
    return SummitStatistics(
        n_summits=int(count),
        asperity_density=count / area if candidates else float("nan"),
        summit_radius=float(radius),
        summit_height_rms=float(rms),
        dx=grid.dx,
        dy=grid.dy,
        nominal_area=area,
        stride=int(stride),
        neighbours=int(neighbours),
        mean_summit_height=float(mean_height),
        n_candidates=candidates,
        grid_area=grid.nominal_area,
    )


def summit_mask(surface: HeightMap, *, neighbours: int = 4) -> np.ndarray:
    """Where the summits are (the rule of :func:`summit_statistics`, paper's Appendix A).

    Parameters
    ----------
    surface : HeightMap
        Heights in m.
    neighbours : {4, 8}
        Strictly higher than the 4 (paper) or 8 nearest neighbours.

    Returns
    -------
    ndarray of bool, shape (nx, ny)
        True at the summits; edge pixels of a non-periodic map and pixels next to a
        missing pixel are False.
    """
    surface = require_height_map(surface, "summit_mask")
    return _summit_mask(surface.heights, surface.periodic, _check_neighbours(neighbours))
