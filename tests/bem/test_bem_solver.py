"""Rough-surface solves: balance, complementarity, warm start, caps, stalls, bad input."""

import numpy as np
import pytest

from asperity.bem import ContactResult, SolverOptions, load_sweep, solve_contact
from asperity.bem.normal.validity import BemWarning

N = 128


def _h(rough):
    return rough(N, seed=3)


def test_load_control_balance_and_complementarity(rough, contact_ok):
    h = _h(rough) * 1e-6  # m, pixel 1 um, rms slope 1
    res = solve_contact(
        h, 1e-6, 1e-6, 1000000000.0, mean_pressure=40000000.0, options=SolverOptions(tol=1e-9)
    )
    assert isinstance(res, ContactResult)
    assert res.converged and res.success and res.nit == res.iterations > 0
    assert len(res.residual_history) == res.nit + 1
    assert res.residual_history[-1] < 1e-9
    contact_ok(res, h, force=0.04e9 * h.size * 1e-12)
    assert res.mean_pressure == pytest.approx(0.04e9, rel=1e-9)
    assert 0.02 < res.contact_fraction < 0.2
    assert res.mean_gap > 0


def test_displacement_control_reproduces_load_control(rough, contact_ok):
    h = _h(rough)
    ref = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.03, options=SolverOptions(tol=1e-11))
    res = solve_contact(
        h, 1.0, 1.0, 1.0, separation=ref.separation, options=SolverOptions(tol=1e-11)
    )
    assert ref.converged and res.converged, res.message
    contact_ok(ref, h, force=0.03 * h.size)
    contact_ok(res, h)
    assert res.mean_pressure == pytest.approx(0.03, rel=1e-6)
    np.testing.assert_array_equal(res.contact_mask, ref.contact_mask)
    np.testing.assert_allclose(res.pressure, ref.pressure, atol=1e-7 * ref.pressure.max())


def test_pixel_size_scaling(rough, contact_ok):
    """Heights and pixel sizes in m, E* in Pa: a uniformly scaled problem has the same fraction."""
    h = _h(rough)
    a = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.05, options=SolverOptions(tol=1e-10))
    b = solve_contact(
        h * 2e-6,
        2e-6,
        2e-6,
        3000000000.0,
        mean_pressure=0.05 * 3000000000.0,
        options=SolverOptions(tol=1e-10),
    )
    contact_ok(a, h, force=0.05 * h.size)
    contact_ok(b, h * 2e-6, force=0.05 * 3e9 * h.size * 4e-12)
    assert b.contact_fraction == pytest.approx(a.contact_fraction, abs=1.0 / h.size)
    assert b.mean_gap == pytest.approx(a.mean_gap * 2e-6, rel=1e-6)


def test_warm_start_sweep_costs_fewer_iterations(rough, contact_ok):
    h = _h(rough)
    forces = np.array([0.039, 0.040, 0.041, 0.042]) * h.size
    sweep = load_sweep(
        h, 1.0, 1.0, 1.0, forces, options=SolverOptions(tol=1e-9, coarse_start=False)
    )
    cold = [
        solve_contact(
            h, 1.0, 1.0, 1.0, normal_force=f, options=SolverOptions(tol=1e-9, coarse_start=False)
        )
        for f in forces
    ]
    for s, c, f in zip(sweep, cold, forces, strict=True):
        assert s.converged and c.converged
        contact_ok(s, h, force=f)
        assert s.contact_fraction == pytest.approx(c.contact_fraction, abs=2.0 / h.size)
        np.testing.assert_allclose(s.pressure, c.pressure, atol=1e-6 * c.pressure.max())
    for s, c in zip(sweep[1:], cold[1:], strict=True):
        # the warm start begins more than an order of magnitude closer to the solution than
        # the cold start from the highest points (68x on this surface)
        assert s.residual_history[0] < 1e-1 * c.residual_history[0]
        assert s.nit < c.nit
    assert sum(s.nit for s in sweep[1:]) < 0.9 * sum(c.nit for c in cold[1:])


@pytest.mark.parametrize("precondition", [True, False])
def test_coarse_start_and_preconditioner_same_answer(rough, contact_ok, precondition):
    h = rough(256, seed=5)
    a = solve_contact(
        h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(tol=1e-10, coarse_start=False)
    )
    b = solve_contact(
        h,
        1.0,
        1.0,
        1.0,
        mean_pressure=0.04,
        options=SolverOptions(tol=1e-10, coarse_start=True, precondition=precondition),
    )
    assert a.converged and b.converged
    contact_ok(a, h, force=0.04 * h.size)
    contact_ok(b, h, force=0.04 * h.size)
    assert b.contact_fraction == pytest.approx(a.contact_fraction, abs=3.0 / h.size)
    assert np.abs(a.pressure - b.pressure).max() < 1e-5 * a.pressure.max()


def test_iteration_cap_reports_non_convergence(rough):
    h = _h(rough)
    res = solve_contact(
        h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(tol=1e-9, max_iter=3)
    )
    assert not res.converged and not res.success
    assert res.nit == 3
    assert "iteration cap" in res.message
    assert res.residual_history[-1] > 1e-9
    # the state is still a valid load-balanced pressure field
    assert res.normal_force == pytest.approx(0.04 * h.size, rel=1e-9)


def test_unreachable_tolerance_stalls_or_caps(rough):
    """Heights 1e5 rms above their datum: the gaps' round-off (2.2e-16 x 1e5) is far above what
    tol = 1e-14 asks; the solve says so instead of looping."""
    h = rough(64, seed=1) + 1e5
    res = solve_contact(
        h,
        1.0,
        1.0,
        1.0,
        mean_pressure=0.04,
        options=SolverOptions(tol=1e-14, stall_window=30, max_iter=2000),
    )
    assert not res.converged
    assert res.message.startswith(("stalled", "iteration cap"))


def test_high_load_near_full_contact(rough, contact_ok):
    """Up to nearly full contact: either a converged, valid answer or a reported stall."""
    h = rough(64, seed=2)
    fractions = []
    for p in (0.3, 0.6, 1.0):
        res = solve_contact(
            h, 1.0, 1.0, 1.0, mean_pressure=p, options=SolverOptions(tol=1e-8, stall_window=100)
        )
        if res.converged:
            contact_ok(res, h, force=p * h.size)
        else:
            assert res.message.startswith(("stalled", "iteration cap"))
        fractions.append(res.contact_fraction)
    assert fractions == sorted(fractions)
    assert fractions[-1] > 0.9


def test_full_contact_reached(rough, contact_ok):
    h = rough(32, seed=4)
    with pytest.warns(BemWarning, match="full contact"):
        res = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=20.0, options=SolverOptions(tol=1e-10))
    assert res.converged, res.message
    assert res.contact_fraction == 1.0 and res.extra["validity_codes"] == ["bem_full_contact"]
    contact_ok(res, h, force=20.0 * h.size)


def test_nonperiodic_domain_isolated_bump_matches_periodic_large_box(sphere, contact_ok):
    """A bump far from the edges: zero-padded and periodic (large box) solutions agree."""
    h, dx = sphere(64, 1.0, 1.0)
    per = solve_contact(
        h, dx, dx, 1.0, normal_force=1e-5, options=SolverOptions(kernel="love", tol=1e-10)
    )
    free = solve_contact(
        h, dx, dx, 1.0, normal_force=1e-5, periodic=False, options=SolverOptions(tol=1e-10)
    )
    assert free.converged and per.converged
    contact_ok(per, h, force=1e-5)
    contact_ok(free, h, force=1e-5)
    np.testing.assert_array_equal(free.contact_mask, per.contact_mask)
    assert np.abs(free.pressure - per.pressure).max() < 0.02 * per.pressure.max()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(mean_pressure=1.0, normal_force=1.0), "exactly one"),
        (dict(), "exactly one"),
        (dict(mean_pressure=-1.0), "must be > 0"),
        (dict(mean_pressure=1.0, adhesion="jkr"), "adhesion"),
        (dict(mean_pressure=1.0, work_of_adhesion=-1.0), "work_of_adhesion"),
    ],
)
def test_bad_input_is_refused(kwargs, match):
    h = np.zeros((8, 8))
    h[4, 4] = 1.0
    with pytest.raises(ValueError, match=match):
        solve_contact(h, 1.0, 1.0, 1.0, **kwargs)


def test_nan_heights_are_refused():
    h = np.zeros((8, 8))
    h[1, 2] = np.nan
    with pytest.raises(ValueError, match="1 missing"):
        solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=1.0)
    with pytest.raises(ValueError, match="dx"):
        solve_contact(np.zeros((8, 8)), -1.0, 1.0, 1.0, mean_pressure=1.0)


def test_adhesion_enlarges_contact_on_unloading_only(rough, contact_ok):
    """Same rough surface and force. Loading from first contact (Pohrt-Popov: elements enter
    only where the gap closes) gives the non-adhesive contact; unloading from a higher force
    keeps elements in tension (down to -Sigma), so the contact is larger: hysteresis."""
    h = rough(64, seed=1) * 1e-6
    plain = solve_contact(h, 1e-6, 1e-6, 1e9, normal_force=0.1)
    loading = solve_contact(h, 1e-6, 1e-6, 1e9, normal_force=0.1, work_of_adhesion=0.05)
    assert plain.converged and loading.converged, loading.message
    assert loading.branch == "loading" and plain.branch == "unique"
    np.testing.assert_array_equal(loading.contact_mask, plain.contact_mask)
    top = solve_contact(h, 1e-6, 1e-6, 1e9, normal_force=0.4, work_of_adhesion=0.05)
    unloading = solve_contact(
        h, 1e-6, 1e-6, 1e9, normal_force=0.1, work_of_adhesion=0.05, initial=top
    )
    assert unloading.converged and unloading.branch == "unloading", unloading.message
    contact_ok(unloading, h, force=0.1)
    assert unloading.critical_tension > 0 and unloading.pressure.min() < 0
    assert unloading.contact_fraction > plain.contact_fraction
