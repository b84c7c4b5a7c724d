"""The tangential (Cerruti, nu = 1/2) influence operator and the energy factor chi_T."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from asperity.bem.elastic.influence import point_force_multiplier
from asperity.bem.elastic.pohrt_popov import pohrt_popov_chi
from asperity.bem.elastic.tangential_influence import (
    cerruti_patch_displacement,
    check_poisson,
    periodic_cerruti_multiplier,
    tangential_chi,
)
from asperity.bem.errors import BemInputError
from asperity.bem.shear.stick_slip import TangentialOperator, box_conjugate_gradients
from tests._helpers import mirrored_patch_values, modulus_strategy, pixel_size_strategy

sizes, moduli = pixel_size_strategy(), modulus_strategy()


def _cerruti_point(x, y, e_star):
    """Cerruti's u_x of a unit x-force (Johnson eq. 3.86a) with general nu, here nu = 1/2:
    (1 + nu) / (pi E rho) [(1 - nu) + nu x^2 / rho^2], E = (1 - nu^2) E*."""
    nu = 0.5
    e = (1 - nu * nu) * e_star
    rho = math.hypot(x, y)
    return (1 + nu) / (math.pi * e * rho) * ((1 - nu) + nu * x * x / (rho * rho))


@given(nx=st.integers(2, 40), ny=st.integers(2, 40), dx=sizes, e_star=moduli)
@settings(max_examples=40, deadline=None)
def test_periodic_multiplier_properties(nx, ny, dx, e_star):
    dy = 1.5 * dx
    k = periodic_cerruti_multiplier(nx, ny, dx, dy, e_star)
    kn = point_force_multiplier(nx, ny, dx, dy, e_star)
    assert k.shape == (nx, ny // 2 + 1)
    assert k[0, 0] == 0.0
    assert np.all(k.ravel()[1:] > 0)
    # between the mode-II (q along x: as the normal kernel) and mode-III (q along y: twice) limits
    ratio = k.ravel()[1:] / kn.ravel()[1:]
    assert np.all(ratio >= 1 - 1e-12) and np.all(ratio <= 2 + 1e-12)
    assert np.allclose(k[:, 0][1:], kn[:, 0][1:], rtol=1e-12)  # q_y = 0: q parallel to the load
    if ny > 2:
        assert k[0, 1] == pytest.approx(2 * kn[0, 1], rel=1e-12)  # q_x = 0: antiplane
    # even in q_x: the rows for +q_x and -q_x agree
    assert np.allclose(k[1:], k[1:][::-1], rtol=1e-12)


@given(dx=sizes, ratio=st.floats(0.2, 5.0), e_star=moduli)
@settings(max_examples=30, deadline=None)
def test_patch_symmetry_positivity_far_field(dx, ratio, e_star):
    dy = dx * ratio
    u = mirrored_patch_values(cerruti_patch_displacement, dx, dy, e_star)
    assert np.all(u > 0)
    r = 300.0 * max(dx, dy)
    along = cerruti_patch_displacement(np.array(r), np.array(0.0), dx, dy, e_star)
    across = cerruti_patch_displacement(np.array(0.0), np.array(r), dx, dy, e_star)
    # a point force dx dy: u_x = F / (pi E* r) (1 + x^2/r^2): twice as far-reaching along x
    assert along == pytest.approx(2 * dx * dy / (math.pi * e_star * r), rel=1e-4)
    assert across == pytest.approx(dx * dy / (math.pi * e_star * r), rel=1e-4)


@pytest.mark.parametrize("point", [(0.0, 0.0), (0.2, 0.1), (1.3, 0.0), (0.0, 1.3), (2.0, -1.5)])
def test_patch_against_quadrature_of_cerruti(point):
    """The closed form against a numerical integral of Cerruti's point-force solution (written
    with general-nu coefficients, evaluated at nu = 1/2) over the patch."""
    dx, dy, e_star = 1.0, 0.6, 2.0
    x0, y0 = point

    def integrand(y, x):
        return _cerruti_point(x0 - x, y0 - y, e_star)

    # split the patch at the field point (an integrable 1/rho singularity inside)
    xs = sorted({-dx / 2, dx / 2, min(max(x0, -dx / 2), dx / 2)})
    ys = sorted({-dy / 2, dy / 2, min(max(y0, -dy / 2), dy / 2)})
    total = 0.0
    for xa, xb in zip(xs[:-1], xs[1:], strict=True):
        for ya, yb in zip(ys[:-1], ys[1:], strict=True):
            val, _ = integrate.dblquad(integrand, xa, xb, ya, yb, epsabs=1e-11, epsrel=1e-10)
            total += val
    closed = cerruti_patch_displacement(np.array(x0), np.array(y0), dx, dy, e_star)
    assert closed == pytest.approx(total, rel=2e-6)


def test_free_operator_is_the_direct_sum_of_patches():
    rng = np.random.default_rng(3)
    nx, ny, dx, dy, e_star = 9, 7, 1e-6, 2e-6, 3e6
    q = rng.normal(size=(nx, ny))
    op = TangentialOperator((nx, ny), dx, dy, e_star, periodic=False, fft_backend="scipy")
    u = op(q)
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    direct = np.zeros((nx, ny))
    for i in range(nx):
        for j in range(ny):
            g = cerruti_patch_displacement((i - ix) * dx, (j - iy) * dy, dx, dy, e_star)
            direct[i, j] = np.sum(g * q)
    assert np.allclose(u, direct, rtol=1e-10, atol=1e-12 * np.abs(direct).max())
    # and a second call does not see the first one's data (padding stays clean)
    assert np.allclose(op(np.zeros((nx, ny))), 0.0)


def test_chi_t_closed_form_identities():
    for dx, dy in ((1.0, 1.0), (1.0, 0.3), (2e-6, 5e-6)):
        chi = pohrt_popov_chi(dx, dy)
        # I_x + I_y = 2 pi chi: the two directional parts add to the Boussinesq energy
        assert tangential_chi(dx, dy) + tangential_chi(dy, dx) == pytest.approx(3 * chi, rel=1e-12)
    assert tangential_chi(1.0, 1.0) == pytest.approx(1.5 * pohrt_popov_chi(1.0, 1.0), rel=1e-14)
    assert tangential_chi(2.0, 2.0) == pytest.approx(8 * tangential_chi(1.0, 1.0), rel=1e-14)


def test_chi_t_against_quadrature_of_the_patch():
    """chi_T = half the element integral of the patch displacement (E* = 1), by tensor
    Gauss-Legendre quadrature of the closed-form patch (logarithmic edge terms: 240 nodes)."""
    dx, dy = 1.0, 0.4
    t, wt = np.polynomial.legendre.leggauss(240)
    xx, yy = np.meshgrid(0.5 * dx * t, 0.5 * dy * t, indexing="ij")
    u = cerruti_patch_displacement(xx, yy, dx, dy, 1.0)
    val = 0.25 * dx * dy * np.einsum("i,j,ij->", wt, wt, u)
    assert tangential_chi(dx, dy) == pytest.approx(0.5 * val, rel=1e-5)


def test_chi_t_against_the_fft_kernel_self_energy():
    """Subdivide one element into m x m pixels of the FFT operator, load them uniformly: the
    energy 1/2 sum q u dA tends to q^2 chi_T / E* (measured: 2.0, 0.62, 0.18, 0.052 % at
    m = 4, 8, 16, 32, about m^-1.8)."""
    dx, dy, e_star = 1.0, 0.5, 1.0
    energies = {}
    for m in (8, 16):
        op = TangentialOperator((m, m), dx / m, dy / m, e_star, periodic=False, threads=1)
        u = op(np.ones((m, m)))
        energies[m] = 0.5 * u.sum() * (dx / m) * (dy / m)
    err = {m: abs(e / tangential_chi(dx, dy) - 1) for m, e in energies.items()}
    assert err[16] < 3e-3
    assert err[8] > 3 * err[16]


@pytest.mark.parametrize("normal", [False, True])
def test_stuck_circular_punch_stiffness(normal):
    """A rigid circular punch bonded to the half-space: T = 4/3 E* a delta_T (Mindlin, nu = 1/2)
    and P = 2 E* a delta (Boussinesq), with a = sqrt(A / pi) of the pixelated disc."""
    n_per = 30
    dx = 1.0 / n_per
    n = 2 * n_per + 4
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    disc = np.hypot(xx, yy) <= 1.0
    a = math.sqrt(disc.sum() * dx * dx / math.pi)
    op = TangentialOperator((n, n), dx, dx, 1.0, periodic=False, normal=normal, threads=1)
    inf = np.full((n, n), np.inf)
    res = box_conjugate_gradients(
        op,
        np.ones((n, n)),
        disc,
        -inf,
        inf,
        np.zeros((n, n)),
        norm=op.norm,
        scale=1 / dx,
        tol=1e-9,
        max_iter=2000,
    )
    assert res.success
    force = res.x.sum() * dx * dx
    expected = (2.0 if normal else 4.0 / 3.0) * a
    assert force == pytest.approx(expected, rel=5e-3)


def test_poisson_ratio_refused():
    check_poisson(0.5)
    with pytest.raises(BemInputError, match="nu = 0.5"):
        check_poisson(0.3)
