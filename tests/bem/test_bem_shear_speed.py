"""The fast paths of the shear curve: the dense operator on the contact set, the junction
preconditioner, and their agreement with asperity 0.4.0's per-step solver."""

import math

import numpy as np
import pytest

from asperity.bem import solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.shear.rough import label_junctions, shear_curve
from asperity.bem.shear.stick_slip import (
    ContactMatrix,
    JunctionPreconditioner,
    ShearOptions,
    TangentialOperator,
    traction_bound,
)
from tests._helpers import stepped_tangential_path

E_STAR, TAU0 = 2.0e6, 0.1e6


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("normal", [False, True])
def test_contact_matrix_equals_the_fft_operator(periodic, normal):
    # two representations of one operator: kernel lookup by offsets against FFT convolution,
    # on a scattered set, for a dense vector and for one on a few elements (the rows path)
    rng = np.random.default_rng(3)
    op = TangentialOperator((37, 29), 1e-6, 1.3e-6, 2e6, periodic=periodic, normal=normal)
    mask = rng.random((37, 29)) < 0.2
    m = ContactMatrix(op, mask)
    assert np.array_equal(m.matrix, m.matrix.T)
    for v in (rng.normal(size=m.size), np.where(rng.random(m.size) < 0.1, 1.0, 0.0)):
        full = np.zeros(mask.shape)
        full[mask] = v
        ref = op(full)[mask]
        assert np.max(np.abs(m(v) - ref)) <= 1e-12 * np.max(np.abs(ref))


def _caps(n=96, dx=1e-6, radius=2e-4):
    """Four spherical caps (m) of slightly different heights on a periodic n x n map."""
    x = (np.arange(n) - n / 2 + 0.5) * dx
    h = np.full((n, n), -np.inf)
    for cx, cy, dz in (
        (-0.25, -0.25, 0.0),
        (0.25, -0.25, 0.1),
        (-0.25, 0.25, 0.2),
        (0.25, 0.25, 0.05),
    ):
        r2 = (x[:, None] - cx * n * dx) ** 2 + (x[None, :] - cy * n * dx) ** 2
        h = np.maximum(h, -r2 / (2 * radius) - dz * 1e-7)
    return h, dx


@pytest.fixture(scope="module")
def caps_case():
    h, dx = _caps()
    force = 0.002 * E_STAR * (h.shape[0] * dx) ** 2
    pre = solve_contact(h, dx, dx, E_STAR, normal_force=force)
    a = math.sqrt(pre.contact_mask.sum() / 4 * dx * dx / math.pi)
    d_t = np.linspace(0.05, 1.5, 20) * 3 * TAU0 * a / E_STAR
    return h, dx, force, pre, d_t


def _curve(case, **options):
    h, dx, force, pre, d_t = case
    options.setdefault("tol", 1e-8)
    return shear_curve(
        h,
        dx,
        dx,
        E_STAR,
        force,
        d_t,
        shear_strength=TAU0,
        preload=pre,
        options=ShearOptions(**options),
    )


def test_preconditioner_cuts_the_iterations(caps_case):
    # regression guard: four junctions of ~250 elements; at tol 1e-6 the plain MPRGP needed 222
    # iterations over the 20 steps, the junction-preconditioned one 55 (measured)
    plain = _curve(caps_case, tol=1e-6, precondition=False, dense_limit_bytes=0)
    fast = _curve(caps_case, tol=1e-6)
    assert plain.success and fast.success
    assert plain.nit.sum() >= 150
    assert fast.nit.sum() <= 80
    scale = TAU0 * fast.real_area[0]
    assert np.max(np.abs(fast.tangential_force - plain.tangential_force)) < 1e-5 * scale
    assert fast.sliding[-1] and not fast.sliding[0]


@pytest.mark.slow
def test_dense_and_fft_paths_agree_with_the_per_step_solver(caps_case):
    # asperity 0.4.0's curve: solve_tangential per step on the whole grid, warm-started
    h, dx, force, pre, d_t = caps_case
    contact = pre.contact_mask
    bound = traction_bound(contact, shear_strength=TAU0)
    opts = ShearOptions(tol=1e-10)
    path = stepped_tangential_path(contact, bound, dx, E_STAR, d_t, options=opts)
    forces = [r.tangential_force for r in path]
    sticks = [r.stick_area for r in path]
    prev = path[-1]
    scale = TAU0 * pre.real_area
    for options in ({}, {"dense_limit_bytes": 0}):
        c = _curve(caps_case, **options)
        assert np.max(np.abs(c.tangential_force - forces)) < 1e-6 * scale
        # at most one element on the stick/slip border decided differently at the tolerance
        assert np.max(np.abs(c.stick_area - sticks)) <= dx * dx
        assert np.allclose(c.final_traction, prev.traction, atol=1e-6 * TAU0)


def test_junction_preconditioner_inverts_an_isolated_junction():
    # one junction, every element free: M^-1 is the inverse of K on it (Cholesky)
    h, dx = _caps(n=48, radius=1e-4)
    pre = solve_contact(h, dx, dx, E_STAR, normal_force=0.002 * E_STAR * (48 * dx) ** 2)
    labels, n = label_junctions(pre.contact_mask)
    one = labels == 1
    op = TangentialOperator(h.shape, dx, dx, E_STAR)
    m = ContactMatrix(op, one)
    idx = np.flatnonzero(one)
    pc = JunctionPreconditioner(
        op.kernel(), idx, np.ones(idx.size, dtype=int), h.shape, periodic=True
    )
    v = np.random.default_rng(0).normal(size=idx.size) * TAU0
    free = np.ones(idx.size, dtype=bool)
    assert np.allclose(pc(m(v), free), v, rtol=0, atol=1e-9 * TAU0)
    # part of the junction bound: z stays zero there, and the factor is reused on a subset
    free[: idx.size // 10] = False
    phi = np.where(free, m(v), 0.0)
    z = pc(phi, free)
    assert np.all(z[~free] == 0.0) and float(phi @ z) > 0
    assert pc.factorisations == 1


def test_options_are_checked():
    with pytest.raises(BemInputError, match="dense_limit_bytes"):
        ShearOptions(dense_limit_bytes=-1)
    with pytest.raises(BemInputError, match="precondition"):
        ShearOptions(precondition="yes")
    with pytest.raises(BemInputError, match="refactor_fraction"):
        JunctionPreconditioner(
            np.ones((4, 4)),
            np.arange(2),
            np.ones(2, int),
            (4, 4),
            periodic=True,
            refactor_fraction=1.0,
        )
