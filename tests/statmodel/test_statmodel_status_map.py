"""The dimensionless status map (Fig. 2a) against closed forms and the dimensional laws."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.statmodel import (
    OUT_OF_CONTACT,
    SLIDE,
    STICK,
    asperity_status,
    pc_contact_radius,
    pc_min_indentation,
)
from asperity.statmodel.status_map import (
    JUMP_OFF_DIMENSIONLESS,
    dimensionless_fold_radius,
    dimensionless_unstable_boundary,
    from_dimensionless,
    to_dimensionless,
)

R, W, E = 9.42e-3, 0.027, 2.133e6


def test_boundary_starts_at_the_dimensionless_jkr_jump_off():
    assert JUMP_OFF_DIMENSIONLESS == pytest.approx(-0.75 * math.pi ** (2 / 3))
    for lam in (0.0, 0.0023, 0.5, 1.0):
        assert dimensionless_unstable_boundary(0.0, lam) == pytest.approx(
            -0.75 * math.pi ** (2 / 3), rel=1e-14
        )


@pytest.mark.parametrize("lam", [0.0023, 0.2, 1.0])
def test_boundary_matches_its_parametric_closed_form(lam):
    # On the boundary: lambda dT~^2 = 2 pi a - pi^2/(4 a^2) and delta~ = a^2 - pi/(2 a)
    a = np.linspace((math.pi / 8) ** (1 / 3), 5.0, 60)
    dt = np.sqrt((2 * np.pi * a - np.pi**2 / (4 * a**2)).clip(0) / lam)
    np.testing.assert_allclose(dimensionless_fold_radius(dt, lam), a, rtol=1e-12)
    np.testing.assert_allclose(
        dimensionless_unstable_boundary(dt, lam), a**2 - np.pi / (2 * a), rtol=1e-11, atol=1e-12
    )


@pytest.mark.parametrize("lam", [0.0023, 0.2, 1.0])
def test_triple_point_where_the_boundary_crosses_zero(lam):
    a_star = (math.pi / 2) ** (1 / 3)
    dt_star = math.sqrt((2 * math.pi * a_star - math.pi**2 / (4 * a_star**2)) / lam)
    assert dimensionless_unstable_boundary(dt_star, lam) == pytest.approx(0.0, abs=1e-12)
    assert asperity_status(-1e-9, dt_star * 1.001, lam) == OUT_OF_CONTACT
    assert asperity_status(1e-9, dt_star * 1.001, lam) == SLIDE
    assert asperity_status(1e-9, dt_star * 0.999, lam) == STICK


def test_dimensionless_boundary_equals_the_dimensional_law():
    lam = 0.0023
    dts = np.linspace(0.0, 2e-3, 30)
    d_min = pc_min_indentation(dts, R, W, E, lam)
    d_t, dt_t = to_dimensionless(d_min, dts, R, W, E)
    np.testing.assert_allclose(
        dimensionless_unstable_boundary(dt_t, lam), d_t, rtol=1e-11, atol=1e-12
    )
    back = from_dimensionless(d_t, dt_t, R, W, E)
    np.testing.assert_allclose(back[0], d_min, rtol=1e-14)
    np.testing.assert_allclose(back[1], dts, rtol=1e-14, atol=1e-30)


def test_status_regions():
    lam = 0.0023
    # below the JKR jump-off: out of contact whatever the shear
    for dt in (0.0, 1.0, 100.0):
        assert asperity_status(JUMP_OFF_DIMENSIONLESS - 1e-6, dt, lam) == OUT_OF_CONTACT
    # negative indentation above jump-off: stick at zero shear, out of contact at large shear
    assert asperity_status(-0.5, 0.0, lam) == STICK
    assert asperity_status(-0.5, 200.0, lam) == OUT_OF_CONTACT
    # positive indentation: stick then slide
    assert asperity_status(3.0, 0.0, lam) == STICK
    assert asperity_status(3.0, 500.0, lam) == SLIDE
    # lambda = 0: never leaves the stick state above jump-off
    assert asperity_status(3.0, 1e6, 0.0) == STICK
    grid = asperity_status(np.array([[-3.0], [-0.5], [3.0]]), np.array([0.0, 1e3]), lam)
    np.testing.assert_array_equal(grid, [[0, 0], [1, 0], [1, 2]])


@settings(max_examples=300, deadline=None)
@given(
    delta_tilde=st.floats(min_value=-3.0, max_value=8.0),
    dt_tilde=st.floats(min_value=0.0, max_value=80.0),
    lam=st.floats(min_value=0.0, max_value=1.0),
)
def test_property_status_agrees_with_the_dimensional_pc_solver(delta_tilde, dt_tilde, lam):
    delta, dt = from_dimensionless(delta_tilde, dt_tilde, R, W, E)
    a = pc_contact_radius(delta, dt, R, W, E, lam)
    code = asperity_status(delta_tilde, dt_tilde, lam)
    boundary = dimensionless_unstable_boundary(dt_tilde, lam)
    if abs(delta_tilde - boundary) > 1e-9 * (1 + abs(boundary)):  # off the boundary itself
        assert (code == STICK) == bool(np.isfinite(a))
    if code != STICK:
        assert code == (SLIDE if delta_tilde >= 0 else OUT_OF_CONTACT)


def test_scalar_and_array_inputs_broadcast():
    d = np.linspace(0.0, 1e-5, 6).reshape(2, 3)
    a = pc_contact_radius(d, np.array([0.0, 1e-5, 2e-5]), R, W, E, 0.2)
    assert a.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            np.testing.assert_equal(
                pc_contact_radius(d[i, j], [0.0, 1e-5, 2e-5][j], R, W, E, 0.2), a[i, j]
            )
    assert np.ndim(pc_contact_radius(1e-5, 1e-5, R, W, E, 0.2)) == 0
