"""Hostile input and status consistency: every bad argument is refused with its name, every
solve either satisfies the contact conditions or says that it did not converge."""

import json
import math

import numpy as np
import pytest

from asperity.bem import SolverOptions, SolverStatus, critical_tension, load_sweep, solve_contact
from asperity.bem.elastic.influence import love_patch_deflection
from asperity.bem.elastic.pohrt_popov import pohrt_popov_chi
from asperity.bem.normal.validity import BemWarning
from asperity.pipelines.cli import main


def _bump(n=8):
    h = np.zeros((n, n))
    h[n // 2, n // 2] = 1.0
    return h


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        ((1.0, 1.0, float("nan")), dict(mean_pressure=1.0), "e_star"),
        ((1.0, 1.0, 0.0), dict(mean_pressure=1.0), "e_star"),
        ((1.0, 1.0, -1.0), dict(mean_pressure=1.0), "e_star"),
        ((1.0, 1.0, math.inf), dict(mean_pressure=1.0), "e_star"),
        ((0.0, 1.0, 1.0), dict(mean_pressure=1.0), "dx"),
        ((math.inf, 1.0, 1.0), dict(mean_pressure=1.0), "dx"),
        ((True, 1.0, 1.0), dict(mean_pressure=1.0), "dx"),
        ((1.0, float("nan"), 1.0), dict(mean_pressure=1.0), "dy"),
        ((1.0, -2.0, 1.0), dict(mean_pressure=1.0), "dy"),
        ((1.0, 1.0, 1.0), dict(mean_pressure=float("nan")), "mean_pressure"),
        ((1.0, 1.0, 1.0), dict(normal_force=math.inf), "normal_force"),
        ((1.0, 1.0, 1.0), dict(normal_force="1"), "normal_force"),
        ((1.0, 1.0, 1.0), dict(normal_force=np.array([1.0, 2.0])), "normal_force"),
        ((1.0, 1.0, 1.0), dict(normal_force=0.0), "must be > 0"),
        ((1.0, 1.0, 1.0), dict(normal_force=-1.0), "must be > 0"),
        ((1.0, 1.0, 1.0), dict(separation=float("nan")), "separation"),
        ((1.0, 1.0, 1.0), dict(normal_force=1.0, separation=1.0), "exactly one"),
        ((1.0, 1.0, 1.0), dict(normal_force=1.0, mean_pressure=1.0, separation=1.0), "exactly one"),
        ((1.0, 1.0, 1.0), dict(normal_force=1.0, work_of_adhesion=None), "work_of_adhesion"),
        ((1.0, 1.0, 1.0), dict(normal_force=1.0, work_of_adhesion=math.nan), "work_of_adhesion"),
    ],
)
def test_bad_scalar_arguments_are_named(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        solve_contact(_bump(), *args, **kwargs)


@pytest.mark.parametrize(
    "knobs, match",
    [
        (dict(tol=math.inf), "tol"),
        (dict(tol=float("nan")), "tol"),
        (dict(max_iter=0), "max_iter"),
        (dict(max_iter=2.5), "max_iter"),
        (dict(stall_window=0), "stall_window"),
        (dict(refresh=0), "refresh"),
    ],
)
def test_bad_solver_options_are_named(knobs, match):
    with pytest.raises(ValueError, match=match):
        solve_contact(_bump(), 1.0, 1.0, 1.0, normal_force=1.0, options=SolverOptions(**knobs))


@pytest.mark.parametrize(
    "heights, match",
    [
        (np.zeros(8), "2D"),
        (np.zeros((2, 2, 2)), "2D"),
        (np.zeros((1, 1)), "at least 2 x 2"),
        (np.zeros((1, 8)), "at least 2 x 2"),
        (np.zeros((4, 4)) + 0j, "real"),
        (np.array([["a", "b"], ["c", "d"]]), "heights"),
        (np.where(np.eye(4) > 0, np.inf, 0.0), "non-finite"),
    ],
)
def test_bad_heights_are_refused(heights, match):
    with pytest.raises(ValueError, match=match):
        solve_contact(heights, 1.0, 1.0, 1.0, normal_force=1.0)


def test_periodic_separation_below_mean_height_is_refused(rough, contact_ok):
    """Periodic kernels have K(q=0) = 0, so mean(g) = d - mean(h) for any pressure: d <= mean(h)
    has no finite solution (the solver used to report convergence at F ~ 1e31 with open gaps)."""
    h = rough(64, seed=2) + 0.5  # mean height 0.5
    for d in (0.5 - 0.1, 0.5):
        with pytest.raises(ValueError, match="separation .* mean height"):
            solve_contact(h, 1.0, 1.0, 1.0, separation=d)
    # just above: nearly full contact at a large but finite force, a valid solution
    res = solve_contact(h, 1.0, 1.0, 1.0, separation=0.5 + 1e-3)
    assert res.converged, res.message
    contact_ok(res, h)
    assert res.contact_fraction > 0.95
    assert res.mean_gap == pytest.approx(1e-3, rel=1e-6)
    # a finite specimen has a solution at any separation
    free = solve_contact(h[:16, :16], 1.0, 1.0, 1.0, separation=0.0, periodic=False)
    assert free.converged, free.message
    contact_ok(free, h[:16, :16])


@pytest.mark.parametrize("periodic", [True, False])
def test_two_by_two_grid(periodic, contact_ok):
    h = np.array([[0.0, 1.0], [0.5, 0.2]])
    res = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.3, periodic=periodic)
    assert res.converged, res.message
    contact_ok(res, h, force=0.3)
    assert res.contact_mask[0, 1]


def test_initial_pressure_checked():
    h = _bump()
    with pytest.raises(ValueError, match="initial"):
        solve_contact(h, 1.0, 1.0, 1.0, normal_force=1.0, initial=np.full((8, 8), np.nan))
    with pytest.raises(ValueError, match="initial"):
        solve_contact(h, 1.0, 1.0, 1.0, normal_force=1.0, initial=np.ones((4, 4)))
    # a warm start with nothing compressive used to divide by zero; now it starts cold
    cold = solve_contact(h, 1.0, 1.0, 1.0, normal_force=1.0)
    warm = solve_contact(h, 1.0, 1.0, 1.0, normal_force=1.0, initial=-np.ones((8, 8)))
    assert warm.converged, warm.message
    np.testing.assert_allclose(warm.pressure, cold.pressure, atol=1e-9)


def test_status_fields_consistent_in_every_outcome(rough):
    """residual_history has nit + 1 entries (the start, then one per step) and ends with the
    returned state's residual, whether converged, capped or stalled."""
    h = rough(64, seed=1)
    outcomes = {
        "converged": solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.04),
        "iteration cap": solve_contact(
            h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(max_iter=3)
        ),
        "stalled": solve_contact(
            h + 1e3,
            1.0,
            1.0,
            1.0,
            mean_pressure=0.04,
            options=SolverOptions(tol=1e-14, stall_window=20, max_iter=5000),
        ),
    }
    for kind, res in outcomes.items():
        assert res.message.startswith(kind), res.message
        assert res.converged is res.success is (kind == "converged")
        assert res.nit == res.iterations
        assert len(res.residual_history) == res.nit + 1
        assert res.residual == res.residual_history[-1]
        tol = 1e-14 if kind == "stalled" else 1e-8
        assert (res.residual < tol) is res.converged
        assert res.seconds > 0
        assert res.summary()["converged"] is res.converged
    # the capped state's residual is that of the returned pressure, below the previous one
    hist = outcomes["iteration cap"].residual_history
    assert hist[-1] < hist[-2]


def test_cold_tensile_load_is_not_reported_as_converged(contact_ok):
    """An adhesive load-controlled solve from scratch cannot carry a tension: reported, and the
    message says why, even when the iteration stops for another reason first."""
    h = _bump()
    res = solve_contact(h, 1.0, 1.0, 1.0, normal_force=-1.0, work_of_adhesion=0.1)
    assert not res.converged
    assert res.status == SolverStatus.LOAD_NOT_CARRIED and res.branch == "loading"
    assert "loading branch" in res.message and "initial=" in res.message


def test_sweep_into_full_contact(rough, contact_ok):
    """Loads up to full contact: each step converges to a valid state or reports a stall."""
    h = rough(64, seed=2)
    forces = np.array([0.5, 2.0, 10.0, 100.0]) * h.size
    fractions = []
    with pytest.warns(BemWarning, match="full contact"):
        sweep = load_sweep(h, 1.0, 1.0, 1.0, forces, options=SolverOptions(tol=1e-10))
    for res, f in zip(sweep, forces, strict=True):
        if res.converged:
            contact_ok(res, h, force=f)
        else:
            assert res.message.startswith(("stalled", "iteration cap"))
        fractions.append(res.contact_fraction)
    assert fractions == sorted(fractions) and fractions[-1] == 1.0


def test_chi_equals_half_the_mean_love_deflection_of_the_element():
    """eq:PohrtPopov_G independently: the energy released by removing a uniform pressure p from
    a dx x dy element is (p/2) * integral of its own Love deflection, so
    chi = (1/2) * integral over the element of u(x, y) E*/p (m^3)."""
    n = 400
    for dx, dy in ((1.0, 1.0), (1.0, 0.4), (0.3, 2.0)):
        x = ((np.arange(n) + 0.5) / n - 0.5) * dx
        y = ((np.arange(n) + 0.5) / n - 0.5) * dy
        u = love_patch_deflection(x[:, None], y[None, :], dx, dy, 1.0)
        assert pohrt_popov_chi(dx, dy) == pytest.approx(0.5 * u.mean() * dx * dy, rel=2e-5)
        assert pohrt_popov_chi(dx, dy) == pytest.approx(pohrt_popov_chi(dy, dx), rel=1e-14)
    # square element, closed form: chi / dx^3 = (2 - 2 sqrt 2) / (3 pi) + 2 asinh(1) / pi
    exact = (2 - 2 * math.sqrt(2)) / (3 * math.pi) + 2 * math.asinh(1.0) / math.pi
    assert pohrt_popov_chi(2e-6, 2e-6) == pytest.approx(exact * 8e-18, rel=1e-13)
    assert exact == pytest.approx(0.473201, abs=1e-6)
    # eq:max_sigma, the paper's parameters (w = 27 mJ/m^2, 2 um pixels) and symmetry
    s = critical_tension(0.027, 1e9, 2e-6, 2e-6)
    assert s == pytest.approx(math.sqrt(0.027 * 1e9 / (exact * 2e-6)), rel=1e-13)
    assert critical_tension(0.027, 1e9, 1e-6, 3e-6) == pytest.approx(
        critical_tension(0.027, 1e9, 3e-6, 1e-6), rel=1e-14
    )
    for bad in ((0.027, 1e9, -1e-6, 1e-6), (0.027, 1e9, 1e-6, math.nan)):
        with pytest.raises(ValueError, match="dx and dy"):
            critical_tension(*bad)


def _cli(capsys, argv):
    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def test_cli_line_profile_and_bad_lists(capsys, tmp_path, rough):
    line = tmp_path / "line.npy"
    np.save(line, np.linspace(0.0, 1e-6, 50))
    status, _, err = _cli(
        capsys, ["bem", str(line), "--e-star", "1e9", "--load", "1", "--pixel-size", "1e-6"]
    )
    assert status == 2 and "line.npy" in err and "line profile" in err
    surf = tmp_path / "s.npy"
    np.save(surf, rough(32, seed=1) * 1e-6)
    base = ["bem", str(surf), "--e-star", "1e9", "--pixel-size", "1e-6"]
    for extra, name in (
        (["--load", "0.5,abc"], "--load"),
        (["--load", "0.5,,1"], "--load"),
        (["--load", "nan"], "--load"),
        (["--mean-pressure", "0"], "--mean-pressure"),
        (["--load", "1", "--max-iter", "0"], "--max-iter"),
        (["--load", "1", "--work-of-adhesion", "-0.1"], "--work-of-adhesion"),
        (["--load", "1", "--pixel-size", "0"], "--pixel-size"),
    ):
        status, out, err = _cli(capsys, base + extra)
        assert status == 2, (extra, err)
        assert name in err and out == "" and len(err.splitlines()) == 1


def test_cli_sweep_with_a_non_converged_step_exits_1(capsys, tmp_path, rough):
    surf = tmp_path / "s.npy"
    np.save(surf, rough(32, seed=1) * 1e-6)
    status, out, err = _cli(
        capsys,
        ["bem", str(surf), "--e-star", "1e9", "--pixel-size", "1e-6", "--load", "0.01,0.02"]
        + ["--max-iter", "1", "--tol", "1e-12", "--json"],
    )
    data = json.loads(out)
    assert status == 1
    assert data["converged"] == [False, False]
    assert "did not converge" in err


def test_no_contact_outcomes_have_consistent_status(sphere, contact_ok):
    """Displacement control beyond the highest point: converged, zero force, one residual;
    an adhesive load beyond pull-off: 'contact lost', not converged."""
    h, dx = sphere(32, 1.0, 1.0)
    res = solve_contact(h, dx, dx, 1.0, separation=1e-3, periodic=False)
    assert res.converged and res.message.startswith("no element in contact")
    assert res.normal_force == 0.0 and res.contact_fraction == 0.0 and res.mean_gap > 0
    assert res.nit == 0 and list(res.residual_history) == [0.0] and res.residual == 0.0
    contact_ok(res, h)
    start = solve_contact(h, dx, dx, 1.0, normal_force=1e-4, periodic=False, work_of_adhesion=1e-4)
    contact_ok(start, h, force=1e-4, rel_force=1e-6)
    lost = solve_contact(
        h, dx, dx, 1.0, normal_force=-1.0, periodic=False, work_of_adhesion=1e-4, initial=start
    )
    assert not lost.converged and not lost.success
    assert lost.message.startswith("contact lost")
    assert len(lost.residual_history) == lost.nit + 1
    assert lost.residual == lost.residual_history[-1] == math.inf
