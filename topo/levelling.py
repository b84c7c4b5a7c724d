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

from asperity.errors import InputError
from asperity.topo.heightmap import HeightMap, require_height_map

METHODS = ("none", "mean", "plane", "quadratic")
_N_TERMS = {"mean": 1, "plane": 3, "quadratic": 6}


@numba.njit(cache=True)
def _row_sums(heights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row i: S[i, b] = sum_j valid v_j^b (b = 0..4), T[i, b] = sum_j z_ij v_j^b (b = 0..2)."""
    nx, ny = heights.shape
    s = np.zeros((nx, 5))
    t = np.zeros((nx, 3))
    sy = 2.0 / max(ny - 1, 1)
    for i in range(nx):
        s0 = s1 = s2 = s3 = s4 = 0.0
        t0 = t1 = t2 = 0.0
        for j in range(ny):
            z = heights[i, j]
            if np.isnan(z):
                continue
            v = j * sy - 1.0
            v2 = v * v
            s0 += 1.0
            s1 += v
            s2 += v2
            s3 += v2 * v
            s4 += v2 * v2
            t0 += z
            t1 += z * v
            t2 += z * v2
        s[i, 0], s[i, 1], s[i, 2], s[i, 3], s[i, 4] = s0, s1, s2, s3, s4
        t[i, 0], t[i, 1], t[i, 2] = t0, t1, t2
    return s, t


@numba.njit(cache=True)
def _subtract(heights: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    nx, ny = heights.shape
    c = np.zeros(6)
    c[: coefficients.size] = coefficients
    out = np.empty((nx, ny))
    sx = 2.0 / max(nx - 1, 1)
    sy = 2.0 / max(ny - 1, 1)
    for i in range(nx):
        u = i * sx - 1.0
        a0 = c[0] + c[1] * u + c[3] * u * u
        a1 = c[2] + c[4] * u
        a2 = c[5]
        for j in range(ny):
            v = j * sy - 1.0
            out[i, j] = heights[i, j] - (a0 + (a1 + a2 * v) * v)
    return out


# exponents (p, q) of u^p v^q for the basis 1, u, v, u^2, u v, v^2
_POWERS = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))


def _normal_equations(heights: np.ndarray, n_terms: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Normal equations of the least-squares form fit over the valid pixels.

    The basis is evaluated on pixel indices scaled to [-1, 1]; the sums are assembled from
    per-row moments (one compiled pass over the map, no design matrix).
    """
    s, t = _row_sums(heights)
    nx = heights.shape[0]
    u = np.linspace(-1.0, 1.0, nx) if nx > 1 else np.array([-1.0])
    powers = _POWERS[:n_terms]
    matrix = np.empty((n_terms, n_terms))
    rhs = np.empty(n_terms)
    for a, (pa, qa) in enumerate(powers):
        rhs[a] = np.dot(u**pa, t[:, qa])
        for b, (pb, qb) in enumerate(powers):
            matrix[a, b] = np.dot(u ** (pa + pb), s[:, qa + qb])
    return matrix, rhs, int(s[:, 0].sum())


def fit_form(surface: HeightMap, method: str = "plane") -> np.ndarray:
    """Least-squares coefficients of the form ``method`` over the valid pixels.

    Parameters
    ----------
    surface : HeightMap
        Heights in m (NaN pixels ignored).
    method : {"mean", "plane", "quadratic"}
        The form: 1, 3 or 6 terms of the basis below.

    Returns
    -------
    ndarray
        Coefficients in m of the basis ``1, u, v, u^2, u v, v^2`` (first 1, 3 or 6), with
        ``u = 2 i/(nx-1) - 1`` and ``v = 2 j/(ny-1) - 1`` (pixel indices scaled to [-1, 1]).
    """
    if method not in _N_TERMS:
        raise InputError(f"levelling method {method!r}: expected one of {METHODS[1:]}")
    surface = require_height_map(surface, "level")
    n_terms = _N_TERMS[method]
    matrix, rhs, count = _normal_equations(surface.heights, n_terms)
    if count < n_terms:
        source = surface.provenance.get("file", "the map")
        raise InputError(
            f"level({method!r}): {source} has {count} valid (non-NaN) pixels; the fit needs "
            f"at least {n_terms}"
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
        raise InputError(f"levelling method {method!r}: expected one of {METHODS}")
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
