"""Harmonic (Laplace) filling of missing pixels, exact on linear height fields.

The least-squares plane of the valid pixels is removed first (the mean only, for a periodic
map or when the valid pixels lie on one line and determine no plane), the missing pixels of the
remainder are the unknowns of the discrete Laplace equation
``sum over neighbours n of w_n (h[n] - h[p]) = 0`` with ``w = 1/dx^2`` along axis 0 and
``1/dy^2`` along axis 1, the valid pixels being the Dirichlet data, and the plane is added
back. Each hole is thus filled by the smoothest surface that meets its rim (a harmonic
function has no interior maximum: filling creates no summit inside a hole). At the edge of a
non-periodic map only the neighbours that exist enter (a zero normal slope of the remainder,
the natural boundary condition); a periodic map wraps around. A linear field ``a + b x + c y``
leaves a zero remainder and is reproduced exactly. The system is symmetric, five non-zeros per
row, non-singular as soon as one pixel is valid; it is solved directly (SuperLU): a
1000 x 1000 map with 3 % missing takes about 0.1 s.
"""

from __future__ import annotations

import numpy as np

from asperity.errors import InputError
from asperity.topo.form import subtract_polynomial


def _neighbour_couplings(
    missing: np.ndarray, periodic: bool, weights: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For every missing pixel p and each existing neighbour n: (p_i, p_j, n_i, n_j, w)."""
    nx, ny = missing.shape
    pi, pj = np.nonzero(missing)
    rows_i, rows_j, nb_i, nb_j, w = [], [], [], [], []
    for axis, step in ((0, -1), (0, 1), (1, -1), (1, 1)):
        size = (nx, ny)[axis]
        position = pi if axis == 0 else pj
        moved = position + step
        exists = np.ones(pi.size, dtype=bool) if periodic else (moved >= 0) & (moved < size)
        moved = moved % size
        rows_i.append(pi[exists])
        rows_j.append(pj[exists])
        nb_i.append(moved[exists] if axis == 0 else pi[exists])
        nb_j.append(pj[exists] if axis == 0 else moved[exists])
        w.append(np.full(int(exists.sum()), weights[axis]))
    return (
        np.concatenate(rows_i),
        np.concatenate(rows_j),
        np.concatenate(nb_i),
        np.concatenate(nb_j),
        np.concatenate(w),
    )


def _solve_laplace(
    remainder: np.ndarray, missing: np.ndarray, periodic: bool, dx: float, dy: float
):
    """Values of the missing pixels of ``remainder`` by the discrete Laplace equation."""
    import scipy.sparse
    import scipy.sparse.linalg

    n = int(missing.sum())
    index = np.full(missing.shape, -1, dtype=np.int64)
    index[missing] = np.arange(n)
    pi, pj, ni, nj, w = _neighbour_couplings(missing, periodic, (1.0 / dx**2, 1.0 / dy**2))
    row = index[pi, pj]
    column = index[ni, nj]
    unknown = column >= 0
    diagonal = np.bincount(row, weights=w, minlength=n)
    rhs = np.bincount(
        row[~unknown], weights=w[~unknown] * remainder[ni[~unknown], nj[~unknown]], minlength=n
    )
    matrix = scipy.sparse.csc_matrix(
        (
            np.concatenate([diagonal, -w[unknown]]),
            (
                np.concatenate([np.arange(n), row[unknown]]),
                np.concatenate([np.arange(n), column[unknown]]),
            ),
        ),
        shape=(n, n),
    )
    solution = scipy.sparse.linalg.spsolve(matrix, rhs)
    if not np.all(np.isfinite(solution)):
        raise InputError(
            f"missing='interpolate': the Laplace fill of {n} missing pixels failed (singular "
            "system); crop to the measured region or use 'fill-lowest'"
        )
    return solution


def harmonic_fill(
    heights: np.ndarray, dx: float, dy: float, *, periodic: bool = False
) -> np.ndarray:
    """Fill the NaN pixels of ``heights`` harmonically (module doc); exact on planes.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights in m; NaN marks the pixels to fill.
    dx, dy : float
        Pixel sizes in m along axis 0 and axis 1 (weights ``1/dx^2`` and ``1/dy^2``).
    periodic : bool
        Wrap around the edges (a periodic map) instead of the open-edge rule.

    Returns
    -------
    ndarray
        A new array: the valid pixels unchanged, the missing ones filled (m).

    Raises
    ------
    InputError
        Every pixel missing.
    """
    filled = np.array(heights, dtype=np.float64)
    missing = np.isnan(filled)
    if not missing.any():
        return filled
    if missing.all():
        raise InputError("missing='interpolate': every pixel is missing; nothing to fill from")
    removal = subtract_polynomial(filled, 0 if periodic else 1)
    order = removal.form.order
    if removal.form.rank < (order + 1) * (order + 2) // 2:
        removal = subtract_polynomial(filled, 0)  # valid pixels on a line: no plane to keep
    values = _solve_laplace(removal.heights, missing, periodic, dx, dy)
    pi, pj = np.nonzero(missing)
    filled[pi, pj] = values + removal.form.at(filled.shape, pi, pj)
    return filled
