"""Stick/slip under tangential displacement: Cattaneo-Mindlin for a Hertz sphere (Coulomb), the
constant shear strength limit, history through the slip only, warm starts, input errors."""

import functools
import math

import numpy as np
import pytest

from asperity.bem import SolverOptions, solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.reference_solutions import (
    cattaneo_mindlin_displacement,
    cattaneo_mindlin_force,
    cattaneo_mindlin_stick_radius,
)
from asperity.bem.shear.stick_slip import (
    ShearOptions,
    TangentialOperator,
    solve_tangential,
    traction_bound,
)
from tests._helpers import stepped_tangential_path

R, E_STAR, A_H, MU = 1.0, 1.0e6, 0.01, 0.3
P_H = 4 * E_STAR * A_H**3 / (3 * R)


@pytest.fixture(scope="module")
def hertz():
    """A Hertz sphere at 40 elements per contact radius, free domain."""
    n_per = 40
    dx = A_H / n_per
    n = int(2.5 * n_per)
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    h = -(xx**2 + yy**2) / (2 * R)
    res = solve_contact(
        h, dx, dx, E_STAR, normal_force=P_H, periodic=False, options=SolverOptions(tol=1e-10)
    )
    assert res.converged
    op = TangentialOperator(h.shape, dx, dx, E_STAR, periodic=False)
    return res, dx, op


def _shear(hertz, bound, d_t, **kw):
    """solve_tangential on the Hertz contact of the fixture (free boundary, its operator) at
    delta_T = ``d_t`` (m) with the slip threshold ``bound`` (Pa)."""
    res, dx, op = hertz
    return solve_tangential(
        res.contact_mask, bound, dx, dx, E_STAR, d_t, periodic=False, operator=op, **kw
    )


@pytest.mark.parametrize("ratio", [0.3, 0.6, 0.9])
def test_cattaneo_mindlin(hertz, ratio):
    """delta_T from Cattaneo-Mindlin at T = ratio mu P: the BEM's T and stick radius agree."""
    res, dx, op = hertz
    t_ref = ratio * MU * P_H
    d_t = cattaneo_mindlin_displacement(t_ref, MU, P_H, A_H, E_STAR)
    bound = traction_bound(res.contact_mask, pressure=res.pressure, friction_coefficient=MU)
    tr = _shear(hertz, bound, d_t, options=ShearOptions(tol=1e-8))
    assert tr.success and tr.status == 0 and tr.nit > 0
    # the compliance: T(delta_T) within 0.2 % (measured 5e-5 .. 1e-5)
    assert tr.tangential_force == pytest.approx(t_ref, rel=2e-3)
    # the stick radius within 2 % (measured 0.5, 0.4, 1.0 %; pixel counting of the stick disc)
    c = math.sqrt(tr.stick_area / math.pi)
    assert c == pytest.approx(cattaneo_mindlin_stick_radius(t_ref, MU, P_H, A_H), rel=0.02)
    # the slip annulus carries mu p with the sign of the load; the stick zone less
    slip = res.contact_mask & ~tr.stick
    assert np.allclose(tr.traction[slip], MU * res.pressure[slip], rtol=1e-12)
    assert np.all(np.abs(tr.traction[tr.stick]) < bound[tr.stick])
    assert tr.stick_area + tr.slip_area == pytest.approx(res.real_area, rel=1e-12)


def test_monotonic_history_and_warm_start(hertz):
    """Monotonic loading in steps reaches the one-step state (history only through slip), and a
    warm start needs fewer iterations than a cold one."""
    res, dx, op = hertz
    bound = traction_bound(res.contact_mask, pressure=res.pressure, friction_coefficient=MU)
    d_end = cattaneo_mindlin_displacement(0.7 * MU * P_H, MU, P_H, A_H, E_STAR)
    one = _shear(hertz, bound, d_end)
    steps = np.linspace(0.25, 1.0, 4) * d_end
    path = stepped_tangential_path(
        res.contact_mask, bound, dx, E_STAR, steps, periodic=False, operator=op
    )
    assert all(r.success for r in path)
    prev = path[-1]
    assert np.allclose(prev.traction, one.traction, atol=1e-6 * np.abs(one.traction).max())
    next_step = functools.partial(_shear, hertz, bound, 1.02 * d_end, slip=one.slip)
    cold = next_step()
    warm = next_step(initial=one)
    assert warm.nit < cold.nit
    assert np.allclose(warm.traction, cold.traction, atol=1e-6 * np.abs(one.traction).max())


def test_unloading_is_not_reloading(hertz):
    """History: after loading to delta_1 and returning to 0 the tractions do not vanish (the
    slip annulus reverses), unlike a fresh contact at delta_T = 0."""
    res, dx, op = hertz
    bound = traction_bound(res.contact_mask, pressure=res.pressure, friction_coefficient=MU)
    d_1 = cattaneo_mindlin_displacement(0.8 * MU * P_H, MU, P_H, A_H, E_STAR)
    up = solve_tangential(res.contact_mask, bound, dx, dx, E_STAR, d_1, periodic=False, operator=op)
    back = solve_tangential(
        res.contact_mask,
        bound,
        dx,
        dx,
        E_STAR,
        0.0,
        periodic=False,
        operator=op,
        slip=up.slip,
        initial=up,
    )
    assert back.success
    # Mindlin-Deresiewicz: at delta_T = 0 after the excursion the force is negative (residual)
    assert back.tangential_force < -0.05 * MU * P_H
    assert np.abs(back.traction).max() > 0


def test_gross_sliding_constant_shear_strength(hertz):
    """tau_0 bound, delta_T past gross sliding: every element slips, T = tau_0 A exactly."""
    res, dx, op = hertz
    tau0 = 0.2 * P_H / res.real_area
    bound = traction_bound(res.contact_mask, shear_strength=tau0)
    big = 10 * cattaneo_mindlin_displacement(MU * P_H, MU, P_H, A_H, E_STAR)
    tr = solve_tangential(res.contact_mask, bound, dx, dx, E_STAR, big, periodic=False, operator=op)
    assert tr.success
    assert tr.stick_area == 0.0
    assert tr.tangential_force == pytest.approx(tau0 * res.real_area, rel=1e-12)
    # and the Cattaneo-Mindlin inverse saturates at mu P past gross slip
    assert cattaneo_mindlin_force(big, MU, P_H, A_H, E_STAR) == pytest.approx(MU * P_H)


def test_full_stick_is_mindlin(hertz):
    """No bound: T = 4/3 E* a delta_T (E:PC_T, Mindlin's full stick) within 1 %."""
    res, dx, op = hertz
    tr = solve_tangential(res.contact_mask, None, dx, dx, E_STAR, 1e-6, periodic=False, operator=op)
    a = math.sqrt(res.real_area / math.pi)
    assert tr.tangential_force == pytest.approx(4 / 3 * E_STAR * a * 1e-6, rel=1e-2)
    assert tr.slip_area == 0.0


def test_periodic_rough_patch_converges():
    """A periodic rough contact set: converged, bounded, stick + slip = contact, and the
    tractions respect the bound everywhere."""
    rng = np.random.default_rng(5)
    n, dx = 64, 1e-6
    h = rng.normal(size=(n, n))
    h = np.real(
        np.fft.ifft2(
            np.fft.fft2(h)
            * np.exp(-0.05 * np.add.outer(np.fft.fftfreq(n) ** 2, np.fft.fftfreq(n) ** 2) * n * n)
        )
    )
    h *= 2e-6 / h.std()
    res = solve_contact(h, dx, dx, E_STAR, mean_pressure=0.02 * E_STAR)
    assert 0.05 < res.contact_fraction < 0.6
    bound = traction_bound(res.contact_mask, pressure=res.pressure, friction_coefficient=0.5)
    tr = solve_tangential(res.contact_mask, bound, dx, dx, E_STAR, 2e-8)
    assert tr.success
    assert np.all(np.abs(tr.traction) <= bound + 1e-12)
    assert tr.stick_area > 0 and tr.slip_area > 0
    assert tr.stick_area + tr.slip_area == pytest.approx(res.real_area, rel=1e-12)
    assert 0 < tr.tangential_force < 0.5 * res.normal_force


def test_bad_input():
    c = np.ones((4, 4), dtype=bool)
    with pytest.raises(BemInputError, match="nu = 0.5"):
        solve_tangential(c, None, 1.0, 1.0, 1.0, 0.1, poisson_ratio=0.3)
    with pytest.raises(BemInputError, match="bound"):
        solve_tangential(c, -np.ones((4, 4)), 1.0, 1.0, 1.0, 0.1, periodic=False)
    with pytest.raises(BemInputError, match="tangential_displacement"):
        solve_tangential(c, None, 1.0, 1.0, 1.0, math.nan, periodic=False)
    with pytest.raises(BemInputError, match="whole periodic cell"):
        solve_tangential(c, None, 1.0, 1.0, 1.0, 0.1)
    with pytest.raises(BemInputError, match="exactly one"):
        traction_bound(c)
    with pytest.raises(BemInputError, match="tol"):
        ShearOptions(tol=1.0)
