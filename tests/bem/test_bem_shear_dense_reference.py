"""An independent slow reference for the tangential problem: the Cerruti patch compliance by
quadrature of the point kernel, a dense matrix on the contact set and the box-constrained
quadratic program of Kalker's principle solved by scipy's bounded-variable least squares
(BVLS, an active-set method with nothing in common with the MPRGP of
:mod:`asperity.bem.shear.stick_slip`). Small free grids (20 x 20), agreement to 1e-5."""

import math

import numpy as np
import pytest
from scipy import integrate, linalg, optimize

from asperity.bem.shear.stick_slip import (
    ShearOptions,
    TangentialOperator,
    box_conjugate_gradients,
    solve_tangential,
    traction_bound,
)

E_STAR = 1e6  # Pa
DX = 1e-6  # m
N = 20


def _self_term(a: float, b: float) -> float:
    """iint over the 2a x 2b rectangle centred on the point of (1/rho)(1 + cos^2 theta) dA (m):
    in polar coordinates the radial integral is the distance to the rim."""
    corner = math.atan2(b, a)

    def radial(theta):
        reach = min(
            a / abs(math.cos(theta)) if math.cos(theta) else math.inf,
            b / abs(math.sin(theta)) if math.sin(theta) else math.inf,
        )
        return (1.0 + math.cos(theta) ** 2) * reach

    value, _ = integrate.quad(radial, 0.0, math.pi / 2, points=[corner], epsabs=0, epsrel=1e-13)
    return 4.0 * value


def _gauss_patch(x0: float, y0: float, a: float, b: float, split: int) -> float:
    """iint over the rectangle [x0 - a, x0 + a] x [y0 - b, y0 + b] of 1/rho + x^2/rho^3 (m), by
    Gauss-Legendre (10 points) on ``split`` x ``split`` sub-rectangles."""
    nodes, weights = np.polynomial.legendre.leggauss(10)
    edges_x = np.linspace(x0 - a, x0 + a, split + 1)
    edges_y = np.linspace(y0 - b, y0 + b, split + 1)
    cx = 0.5 * (edges_x[:-1, None] + edges_x[1:, None]) + 0.5 * np.diff(edges_x)[:, None] * nodes
    cy = 0.5 * (edges_y[:-1, None] + edges_y[1:, None]) + 0.5 * np.diff(edges_y)[:, None] * nodes
    wx = (0.5 * np.diff(edges_x)[:, None] * weights).ravel()
    wy = (0.5 * np.diff(edges_y)[:, None] * weights).ravel()
    xx, yy = np.meshgrid(cx.ravel(), cy.ravel(), indexing="ij")
    rho = np.hypot(xx, yy)
    return float(np.einsum("i,j,ij->", wx, wy, 1.0 / rho + xx * xx / rho**3))


def _compliance() -> np.ndarray:
    """u_x (m) at offset (i, j) pixels of a unit x-traction (1 Pa) on one element, nu = 1/2:
    ``(1 / (pi E*)) iint (1/rho + x^2/rho^3) dA`` (Johnson 1985, eq. 3.86a)."""
    a = b = DX / 2
    out = np.empty((N, N))
    for i in range(N):
        for j in range(N):
            if i == j == 0:
                val = _self_term(a, b)
            else:
                split = 8 if max(i, j) <= 2 else 2
                val = _gauss_patch(i * DX, j * DX, a, b, split)
            out[i, j] = val / (math.pi * E_STAR)
    return out


@pytest.fixture(scope="module")
def compliance():
    return _compliance()


def _dense(compliance: np.ndarray, contact: np.ndarray) -> np.ndarray:
    """The compliance matrix (m/Pa) on the contact elements (row-major order)."""
    ii, jj = np.nonzero(contact)
    return compliance[np.abs(ii[:, None] - ii[None, :]), np.abs(jj[:, None] - jj[None, :])]


def _reference(compliance, contact, rhs, bound):
    """argmin 1/2 q.K q - q.rhs over -bound <= q <= bound on the contact (Pa), by BVLS on the
    Cholesky factor: 1/2 |L^T q - L^-1 rhs|^2 differs from it by a constant."""
    k = _dense(compliance, contact)
    low = linalg.cholesky(k, lower=True)
    target = linalg.solve_triangular(low, rhs[contact], lower=True)
    if bound is None:
        q_c = linalg.cho_solve((low, True), rhs[contact])
    else:
        res = optimize.lsq_linear(
            low.T,
            target,
            bounds=(-bound[contact], bound[contact]),
            method="bvls",
            tol=1e-15,
            max_iter=10 * contact.sum(),
        )
        q_c = res.x
    q = np.zeros(contact.shape)
    q[contact] = q_c
    return q


def _grid():
    x = (np.arange(N) - (N - 1) / 2) * DX
    return np.meshgrid(x, x, indexing="ij")


def _assert_close(q, ref):
    scale = np.abs(ref).max()
    assert np.abs(q - ref).max() <= 1e-5 * scale
    assert q.sum() == pytest.approx(ref.sum(), rel=1e-6)


@pytest.mark.slow
def test_quadrature_compliance_matches_closed_form_patch(compliance):
    """The quadrature kernel is the operator's: the free operator's response to one unit traction
    equals it to 1e-9 (relative to the self term)."""
    op = TangentialOperator((N, N), DX, DX, E_STAR, periodic=False)
    kernel = op.kernel()
    assert np.abs(kernel - compliance).max() <= 1e-9 * compliance[0, 0]


@pytest.mark.slow
@pytest.mark.parametrize("case", ["coulomb_disc", "tau0_two_blobs"])
def test_partial_slip_matches_dense_bvls(compliance, case):
    """Cattaneo-like partial slip (stick core, slipping rim): solve_tangential (MPRGP, FFT)
    against the dense BVLS reference, max traction error <= 1e-5 of the largest traction."""
    xx, yy = _grid()
    if case == "coulomb_disc":
        r2 = (xx**2 + yy**2) / (8 * DX) ** 2
        contact = r2 < 1.0
        p = np.where(contact, 1e4 * np.sqrt(np.clip(1.0 - r2, 0.0, None)), 0.0)
        bound = traction_bound(contact, pressure=p, friction_coefficient=0.5)
        d_t = 2e-8
    else:
        contact = ((xx + 4 * DX) ** 2 + yy**2 < (4.2 * DX) ** 2) | (
            (xx - 5 * DX) ** 2 + (yy - 3 * DX) ** 2 < (3.5 * DX) ** 2
        )
        bound = traction_bound(contact, shear_strength=2e3)
        d_t = 2e-8
    res = solve_tangential(
        contact, bound, DX, DX, E_STAR, d_t, periodic=False, options=ShearOptions(tol=1e-12)
    )
    ref = _reference(compliance, contact, np.full((N, N), d_t), bound)
    at_bound = np.isclose(np.abs(ref), bound) & contact
    assert 0 < at_bound.sum() < contact.sum()  # partial slip, not full stick nor gross sliding
    _assert_close(res.traction, ref)


@pytest.mark.slow
def test_bonded_contact_matches_dense_solve(compliance):
    """The bonded (adhesive stick) tangential problem of the mixed-mode solvers, with references
    s from earlier steps: box CG without bounds against the dense Cholesky solve."""
    xx, yy = _grid()
    contact = (xx / (9 * DX)) ** 2 + (yy / (6 * DX)) ** 2 < 1.0
    rng = np.random.default_rng(3)
    slip = np.where(contact, rng.uniform(0.0, 1e-9, (N, N)), 0.0)
    rhs = 5e-9 - slip
    op = TangentialOperator((N, N), DX, DX, E_STAR, periodic=False)
    inf = np.full((N, N), np.inf)
    res = box_conjugate_gradients(
        op,
        rhs,
        contact,
        -inf,
        inf,
        np.zeros((N, N)),
        norm=op.norm,
        scale=E_STAR / DX,
        tol=1e-12,
        max_iter=5000,
    )
    assert res.status == 0
    _assert_close(res.x, _reference(compliance, contact, rhs, None))
