"""The safeguarded Newton solver shared by the single-asperity kernels, tested on its own."""

import math

import numpy as np
import pytest
from numba import njit

from asperity.statmodel import jkr
from asperity.statmodel.newton import (
    CONVERGED,
    MAX_ITERATIONS,
    MAX_ITERATIONS_REACHED,
    MESSAGES,
    NOT_A_NUMBER,
    newton_solver,
)


@njit
def _square_minus(x, params):
    (target,) = params
    return x * x - target, 2.0 * x


@njit
def _double_root(x, params):
    return x * x, 2.0 * x


@njit
def _nan_slope(x, params):
    return 1.0, math.nan


_sqrt = newton_solver(_square_minus)
_double = newton_solver(_double_root)
_nan = newton_solver(_nan_slope)


@njit
def _sqrt_in_compiled_code(target):
    x, status, nit = _sqrt(target + 1.0, -math.inf, (target,))
    return x


@pytest.mark.parametrize("target", [2.0, 1e-20, 3.0, 1e30])
def test_simple_root_converges_quadratically_to_the_last_ulps(target):
    x, status, nit = _sqrt(target + 1.0, -math.inf, (target,))
    assert status == CONVERGED
    assert abs(x - math.sqrt(target)) <= 4 * np.spacing(math.sqrt(target))
    # far from the root Newton halves x (one step per factor 2 of x0/root), then converges
    # quadratically (about 6 steps from 2 digits to 16): tens of steps, never the cap
    assert nit <= 8 + math.log2((target + 1.0) / math.sqrt(target))


def test_monotone_decrease_from_the_right_never_undershoots_the_root():
    for target in np.geomspace(1e-6, 1e6, 50):
        x, status, _ = _sqrt(10.0 * (target + 1.0), -math.inf, (target,))
        assert status == CONVERGED
        assert x * x - target >= -4 * np.spacing(target)  # the root, or right of it in round-off


def test_clamp_returns_the_lower_bound_exactly():
    # the root sqrt(2) lies below the clamp 1.5: the iterate stops at the clamp, exactly
    x, status, nit = _sqrt(3.0, 1.5, (2.0,))
    assert status == CONVERGED
    assert x == 1.5


def test_double_root_reports_the_iteration_cap():
    # f = x^2 has a double root at 0: Newton only halves x, never within 4e-16 of it
    x, status, nit = _double(1.0, -math.inf, ())
    assert status == MAX_ITERATIONS_REACHED
    assert nit == MAX_ITERATIONS == 200
    assert x == 2.0**-200
    assert "200" in MESSAGES[status]


def test_nan_iterate_is_reported_at_once():
    x, status, nit = _nan(1.0, -math.inf, ())
    assert math.isnan(x)
    assert status == NOT_A_NUMBER
    assert nit == 1


def test_solver_runs_inside_compiled_code():
    assert _sqrt_in_compiled_code(2.0) == pytest.approx(math.sqrt(2.0), rel=1e-15)


def test_jkr_radius_is_the_closed_form_root():
    # E:JKR_indent at a = t^2: delta = t^4/R - k t, so the solver must give back t^2
    R, w, E = 1e-4, 0.04, 2e6
    k = math.sqrt(2 * math.pi * w / E)
    t = np.linspace(1.2, 40.0, 50) * (k * R / 4) ** (1 / 3)
    delta = t**4 / R - k * t
    a = jkr.jkr_contact_radius(delta, R, w, E)
    np.testing.assert_allclose(a, t * t, rtol=1e-14)
