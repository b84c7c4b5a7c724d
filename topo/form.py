"""Polynomial form of a height map: least squares over the valid (non-NaN) pixels.

The form of order ``n`` is ``f(u, v) = sum_{p + q <= n} c_pq P_p(u) P_q(v)`` with the pixel
indices scaled to ``u = 2 i/(nx - 1) - 1`` and ``v = 2 j/(ny - 1) - 1`` (both in [-1, 1]) and
``P_k`` the Legendre polynomials, which keep the normal equations well conditioned up to
:data:`MAX_ORDER`. Order 0 is the mean height, 1 the best plane, 2 the best quadratic. The
normal equations are assembled from per-row Gram sums in one compiled pass (no design matrix is
built), and the form is subtracted in a second pass that never materialises it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from numpy.polynomial import legendre

from asperity.errors import InputError

#: Highest polynomial order accepted (the Legendre normal equations stay well conditioned).
MAX_ORDER = 8


@numba.njit(cache=True)
def _row_gram(heights, pv):
    """Per row i: ``gram[i, a, b] = sum_j P_a(v_j) P_b(v_j)`` and ``rhs[i, a] = sum_j z_ij
    P_a(v_j)`` over the valid pixels j of the row, and their number ``count[i]``."""
    nx, ny = heights.shape
    m = pv.shape[1]
    gram = np.zeros((nx, m, m))
    rhs = np.zeros((nx, m))
    count = np.zeros(nx)
    for i in range(nx):
        for j in range(ny):
            z = heights[i, j]
            if np.isnan(z):
                continue
            count[i] += 1.0
            for a in range(m):
                va = pv[j, a]
                rhs[i, a] += z * va
                for b in range(a, m):
                    gram[i, a, b] += va * pv[j, b]
        for a in range(m):
            for b in range(a):
                gram[i, a, b] = gram[i, b, a]
    return gram, rhs, count


@numba.njit(cache=True)
def _subtract_form(heights, row_factors, pv):
    """``heights - form`` with ``form[i, j] = sum_q row_factors[i, q] * pv[j, q]``; also the
    number, sum and sum of squares of the form over the valid pixels (for its rms)."""
    nx, ny = heights.shape
    m = pv.shape[1]
    out = np.empty((nx, ny))
    n = 0.0
    total = 0.0
    squares = 0.0
    for i in range(nx):
        for j in range(ny):
            f = 0.0
            for q in range(m):
                f += row_factors[i, q] * pv[j, q]
            z = heights[i, j]
            out[i, j] = z - f
            if not np.isnan(z):
                n += 1.0
                total += f
                squares += f * f
    return out, n, total, squares


def _scaled_axis(n: int) -> np.ndarray:
    """Pixel indices 0..n-1 scaled to [-1, 1] (a single pixel sits at -1)."""
    return np.linspace(-1.0, 1.0, n) if n > 1 else np.array([-1.0])


def _terms(order: int) -> list[tuple[int, int]]:
    """Exponent pairs (p, q) of the basis ``P_p(u) P_q(v)``, ``p + q <= order``."""
    return [(p, total - p) for total in range(order + 1) for p in range(total, -1, -1)]


def check_order(order: object) -> int:
    """Return ``order`` as an int in 0..:data:`MAX_ORDER`, or raise :class:`InputError`."""
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
        raise InputError(f"form order: expected an integer 0..{MAX_ORDER}, got {order!r}")
    if not 0 <= order <= MAX_ORDER:
        raise InputError(f"form order: expected an integer 0..{MAX_ORDER}, got {order}")
    return int(order)


@dataclass(frozen=True, eq=False)
class PolynomialForm:
    """A fitted polynomial form (heights in m).

    Attributes
    ----------
    order : int
        Total polynomial order n (0 mean, 1 plane, 2 quadratic, ...).
    coefficients : ndarray, shape (n + 1, n + 1)
        ``c[p, q]`` (m) of ``P_p(u) P_q(v)``; zero where ``p + q > n``.
    n_valid : int
        Valid pixels the fit used.
    rank : int
        Rank of the normal equations: below the number of terms the valid pixels do not
        determine the form (e.g. all on one line) and the minimum-norm solution was taken.
    """

    order: int
    coefficients: np.ndarray
    n_valid: int
    rank: int = -1

    def at(self, shape: tuple[int, int], i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """The form (m) at pixels ``(i, j)`` of a map of ``shape`` (the grid it was fitted on)."""
        pu = legendre.legvander(_scaled_axis(shape[0])[i], self.order)
        pv = legendre.legvander(_scaled_axis(shape[1])[j], self.order)
        return np.einsum("kp,pq,kq->k", pu, self.coefficients, pv)


def fit_polynomial(heights: np.ndarray, order: int) -> PolynomialForm:
    """Least-squares polynomial form of total order ``order`` over the non-NaN pixels.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights in m; NaN pixels are ignored.
    order : int
        0..:data:`MAX_ORDER`.

    Returns
    -------
    PolynomialForm
        The Legendre coefficients (m). Where the valid pixels do not determine every term
        (too few of them, or all on one line), the minimum-norm least-squares solution.

    Raises
    ------
    InputError
        An order outside 0..:data:`MAX_ORDER`, or no valid pixel at all.
    """
    order = check_order(order)
    nx, ny = heights.shape
    pu = legendre.legvander(_scaled_axis(nx), order)
    pv = legendre.legvander(_scaled_axis(ny), order)
    gram, rhs_rows, count = _row_gram(np.asarray(heights, dtype=np.float64), pv)
    n_valid = int(count.sum())
    if n_valid == 0:
        raise InputError("form fit: every pixel is missing (NaN); there is nothing to fit")
    terms = _terms(order)
    full = np.einsum("ip,ir,iqs->pqrs", pu, pu, gram)
    matrix = np.array([[full[p, q, r, s] for r, s in terms] for p, q in terms])
    rhs_full = pu.T @ rhs_rows
    rhs = np.array([rhs_full[p, q] for p, q in terms])
    solution, _, rank, _ = np.linalg.lstsq(matrix, rhs, rcond=1e-12)
    coefficients = np.zeros((order + 1, order + 1))
    for (p, q), value in zip(terms, solution, strict=True):
        coefficients[p, q] = value
    return PolynomialForm(order, coefficients, n_valid, int(rank))


@dataclass(frozen=True, eq=False)
class FormRemoval:
    """Heights with a polynomial form removed, and the size of what was removed.

    Attributes
    ----------
    heights : ndarray
        ``heights - form`` (m); NaN pixels stay NaN.
    form : PolynomialForm
        The fitted form.
    form_rms : float
        rms of the removed form over the valid pixels, about its own mean (m): the size
        of the tilt / curvature taken away (0 for order 0, a constant).
    """

    heights: np.ndarray
    form: PolynomialForm
    form_rms: float


def subtract_polynomial(heights: np.ndarray, order: int) -> FormRemoval:
    """Fit the form of order ``order`` over the valid pixels and subtract it everywhere.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights in m (NaN = missing; they stay NaN).
    order : int
        0..:data:`MAX_ORDER`.

    Returns
    -------
    FormRemoval
        The levelled heights (m), the form and its rms about its mean (m).
    """
    form = fit_polynomial(heights, order)
    nx, ny = heights.shape
    pu = legendre.legvander(_scaled_axis(nx), form.order)
    pv = legendre.legvander(_scaled_axis(ny), form.order)
    out, n, total, squares = _subtract_form(
        np.asarray(heights, dtype=np.float64), pu @ form.coefficients, pv
    )
    mean = total / n
    form_rms = float(np.sqrt(max(squares / n - mean * mean, 0.0)))
    if form.order == 0:
        form_rms = 0.0
    return FormRemoval(out, form, form_rms)


def legendre_to_monomial(coefficients: np.ndarray) -> np.ndarray:
    """Coefficients of ``1, u, v, u^2, u v, v^2`` (m) from a Legendre form of order <= 2.

    Parameters
    ----------
    coefficients : ndarray, shape (n + 1, n + 1), n <= 2
        ``c[p, q]`` of ``P_p(u) P_q(v)`` (m).

    Returns
    -------
    ndarray
        The first 1, 3 or 6 monomial coefficients (order 0, 1, 2), in m.
    """
    order = coefficients.shape[0] - 1
    c = np.zeros((3, 3))
    c[: order + 1, : order + 1] = coefficients
    # P_0 = 1, P_1(x) = x, P_2(x) = (3 x^2 - 1) / 2
    monomial = np.array(
        [
            c[0, 0] - 0.5 * c[2, 0] - 0.5 * c[0, 2],
            c[1, 0],
            c[0, 1],
            1.5 * c[2, 0],
            c[1, 1],
            1.5 * c[0, 2],
        ]
    )
    return monomial[: {0: 1, 1: 3, 2: 6}[order]]
