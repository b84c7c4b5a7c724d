"""Form removal by least squares over the valid (non-NaN) pixels.

Methods: ``"none"`` (unchanged), ``"mean"`` (subtract the mean height), ``"plane"``
(subtract the least-squares plane ``a + b x + c y``) and ``"quadratic"`` (second-order
form, ``a + b x + c y + d x^2 + e x y + f y^2``). The fit is over valid pixels only and
is computed from normal equations accumulated in one pass (no design matrix is built),
with coordinates scaled to [-1, 1] so the system stays well conditioned.
"""

from __future__ import annotations

import numba
import numpy as np

from topo.heightmap import HeightMap, require_height_map

METHODS = ("none", "mean", "plane", "quadratic")
_N_TERMS = {"mean": 1, "plane": 3, "quadratic": 6}


@numba.njit(cache=True)
def _basis(u: float, v: float, n_terms: int, out: np.ndarray) -> None:
    out[0] = 1.0
    if n_terms > 1:
        out[1] = u
        out[2] = v
    if n_terms > 3:
        out[3] = u * u
        out[4] = u * v
        out[5] = v * v


@numba.njit(cache=True)
def _normal_equations(heights: np.ndarray, n_terms: int) -> tuple[np.ndarray, np.ndarray, int]:
    nx, ny = heights.shape
    matrix = np.zeros((n_terms, n_terms))
    rhs = np.zeros(n_terms)
    phi = np.zeros(n_terms)
    sx = 2.0 / max(nx - 1, 1)
    sy = 2.0 / max(ny - 1, 1)
    count = 0
    for i in range(nx):
        u = i * sx - 1.0
        for j in range(ny):
            z = heights[i, j]
            if np.isnan(z):
                continue
            count += 1
            _basis(u, j * sy - 1.0, n_terms, phi)
            for a in range(n_terms):
                rhs[a] += phi[a] * z
                for b in range(a, n_terms):
                    matrix[a, b] += phi[a] * phi[b]
    for a in range(n_terms):
        for b in range(a):
            matrix[a, b] = matrix[b, a]
    return matrix, rhs, count


@numba.njit(cache=True)
def _subtract(heights: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    nx, ny = heights.shape
    n_terms = coefficients.size
    out = np.empty((nx, ny))
    phi = np.zeros(n_terms)
    sx = 2.0 / max(nx - 1, 1)
    sy = 2.0 / max(ny - 1, 1)
    for i in range(nx):
        u = i * sx - 1.0
        for j in range(ny):
            _basis(u, j * sy - 1.0, n_terms, phi)
            form = 0.0
            for a in range(n_terms):
                form += coefficients[a] * phi[a]
            out[i, j] = heights[i, j] - form
    return out


def fit_form(surface: HeightMap, method: str = "plane") -> np.ndarray:
    """Least-squares coefficients of the form ``method`` over the valid pixels.

    The basis is ``1, u, v, u^2, u v, v^2`` with ``u = 2 i/(nx-1) - 1`` and
    ``v = 2 j/(ny-1) - 1`` (pixel indices scaled to [-1, 1]); coefficients are in m.
    """
    if method not in _N_TERMS:
        raise ValueError(f"levelling method {method!r}: expected one of {METHODS[1:]}")
    surface = require_height_map(surface, "level")
    n_terms = _N_TERMS[method]
    matrix, rhs, count = _normal_equations(surface.heights, n_terms)
    if count < n_terms:
        raise ValueError(
            f"level({method!r}): {count} valid pixels, need at least {n_terms} for the fit"
        )
    try:
        return np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(matrix, rhs, rcond=None)[0]


def level(surface: HeightMap, method: str = "plane") -> HeightMap:
    """Remove the mean, the best plane or the best quadratic form (heights in m).

    Parameters
    ----------
    surface : HeightMap
        Heights in m; NaN pixels are ignored by the fit and stay NaN.
    method : {"none", "mean", "plane", "quadratic"}
        The form removed (least squares over the valid pixels).

    Returns
    -------
    HeightMap
        Same grid and provenance (with ``levelling`` recorded); ``"none"`` returns the input.

    Notes
    -----
    A periodic map has no tilt or form to remove (a plane is not periodic): for
    ``periodic=True`` maps ``"plane"`` and ``"quadratic"`` subtract the mean only, so the
    map stays periodic; the provenance records ``"mean (periodic map)"``.
    """
    if method not in METHODS:
        raise ValueError(f"levelling method {method!r}: expected one of {METHODS}")
    surface = require_height_map(surface, "level")
    if method == "none":
        return surface
    applied = method
    if surface.periodic and method != "mean":
        method, applied = "mean", "mean (periodic map)"
    coefficients = fit_form(surface, method)
    heights = _subtract(surface.heights, coefficients)
    provenance = dict(surface.provenance)
    provenance["levelling"] = applied
    return surface.with_heights(heights, provenance=provenance)
