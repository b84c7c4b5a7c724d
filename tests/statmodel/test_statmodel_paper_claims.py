"""The paper's formulas written out term by term, and its numerical claims (Sections 2-4)."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.statmodel import (
    OUT_OF_CONTACT,
    SLIDE,
    STICK,
    TaborWarning,
    asperity_status,
    dimensionless_unstable_boundary,
    hertz_contact_radius,
    hertz_normal_load,
    hertz_sliding_tangential_load,
    jkr_contact_radius,
    jkr_jump_in_distance,
    jkr_jump_off_distance,
    jkr_normal_load,
    pc_contact_radius,
    pc_fold_radius,
    pc_max_tangential_displacement,
    pc_min_indentation,
    pc_normal_load,
    tabor_parameter,
)

E_STAR, EPS = 2.133e6, 0.2e-9
R, W, LAM = 9.42e-3, 0.027, 0.0023  # Figs. 1-2


@pytest.mark.parametrize(
    "radius, work, expected",
    [
        (9.42e-3, 0.027, 5736),  # Figs. 1 and 2
        (0.041e-3, 0.040, 1217),  # Fig. 4
        (0.041e-3, 0.015, 633),  # Fig. 5, min(mu) at its smallest w = 15 mJ/m^2
        # Fig. 13 (R = 1.180 mm): the caption's mu ~ 1939 is reproduced with w = 15 mJ/m^2, the
        # smallest w of Fig. 5 (as its min(mu)); with w = 40 mJ/m^2 it would be ~3729.
        (1.180e-3, 0.015, 1939),
        (1.180e-3, 0.040, 3729),
    ],
)
def test_tabor_parameter_of_the_captions(radius, work, expected):
    mu = tabor_parameter(radius, work, E_STAR, EPS)
    assert mu == pytest.approx(expected, rel=1e-3)
    # mu = (R w^2 / (E*^2 eps^3))^(1/3) written out
    assert mu == pytest.approx((radius * work**2 / (E_STAR**2 * EPS**3)) ** (1 / 3), rel=1e-15)


@settings(max_examples=200, deadline=None)
@given(mu=st.floats(min_value=5.0, max_value=1e7), eps=st.floats(min_value=1e-10, max_value=1e-9))
def test_property_jump_off_below_jump_in_below_zero_for_mu_above_5(mu, eps):
    # paper, Section 2.1: "Because mu > 5 ... delta_JKR^unloading < delta_JKR^loading < 0"
    d_in = jkr_jump_in_distance(mu, eps)
    assert d_in == pytest.approx(-2.641 * mu ** (3 / 7) * math.exp(-1 / (2 * math.sqrt(mu))) * eps)
    assert -0.75 * math.pi ** (2 / 3) * mu * eps < d_in < 0.0


def test_jump_in_fit_outside_the_jkr_range_warns_and_can_cross_the_jump_off():
    with pytest.warns(TaborWarning, match="jump-in"):
        d_in = jkr_jump_in_distance(0.5, EPS)
    # for mu < ~1 Wu's fit falls below the jump-off distance: why the paper needs mu > 5
    assert d_in < -0.75 * math.pi ** (2 / 3) * 0.5 * EPS


def test_jump_in_distance_bad_inputs_are_nan_not_zero():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert jkr_jump_in_distance(0.0, EPS) == 0.0  # no adhesion: Fuller-Tabor limit
        assert math.isnan(jkr_jump_in_distance(math.nan, EPS))
        assert math.isnan(jkr_jump_in_distance(-3.0, EPS))
        assert math.isnan(jkr_jump_in_distance(100.0, 0.0))


def test_jump_off_distance_is_the_paper_closed_form_for_several_materials():
    for r, w, e in [(R, W, E_STAR), (4.1e-5, 0.04, E_STAR), (1e-6, 0.1, 1e9)]:
        mu = tabor_parameter(r, w, e, EPS, warn=False)
        expected = -0.75 * math.pi ** (2 / 3) * mu * EPS  # E:JKR_delta_min_unloading
        assert jkr_jump_off_distance(r, w, e) == pytest.approx(expected, rel=1e-13)
        # "delta_PC^min = delta_JKR^unloading when delta_T = 0" (Section 2.2)
        assert pc_min_indentation(0.0, r, w, e, 0.3) == pytest.approx(expected, rel=1e-13)


def test_jkr_laws_term_by_term():
    # E:JKR_indent and E:JKR_load as printed, at the solver's radius
    for delta in (-1e-6, 0.0, 1e-6, 3e-5):
        a = jkr_contact_radius(delta, R, W, E_STAR)
        assert a**2 / R - math.sqrt(2 * math.pi * W * a / E_STAR) == pytest.approx(
            delta, abs=1e-12 * R
        )
        p = 4 * E_STAR * a**3 / (3 * R) - math.sqrt(8 * math.pi * E_STAR * a**3 * W)
        assert jkr_normal_load(delta, R, W, E_STAR) == pytest.approx(p, rel=1e-13)


def test_hertz_sliding_law_term_by_term():
    # E:Hertz_theory: a = sqrt(R delta), P = 4/3 E* sqrt(R) delta^(3/2), T = pi a^2 tau0
    tau0 = 0.43e6
    for delta in (1e-7, 1e-5):
        a = math.sqrt(R * delta)
        assert hertz_contact_radius(delta, R) == pytest.approx(a, rel=1e-15)
        assert hertz_normal_load(delta, R, E_STAR) == pytest.approx(
            4 / 3 * E_STAR * math.sqrt(R) * delta**1.5, rel=1e-15
        )
        assert hertz_sliding_tangential_load(delta, R, tau0) == pytest.approx(
            math.pi * a**2 * tau0, rel=1e-15
        )
    assert hertz_normal_load(-1e-6, R, E_STAR) == 0.0


@pytest.mark.parametrize("lam", [0.0023, 0.2, 1.0])
@pytest.mark.parametrize("delta", [-5e-7, 0.0, 2e-6, 4e-5])
def test_delta_t_max_is_the_printed_cubic_and_formula(lam, delta):
    # E:PC_a_min_1: a^3 - delta R a - pi w R^2 / (2 E*) = 0, its unique positive real root
    roots = np.roots([1.0, 0.0, -delta * R, -math.pi * W * R**2 / (2 * E_STAR)])
    a_min = max(r.real for r in roots if abs(r.imag) < 1e-12 * abs(r) and r.real > 0)
    # E:max_disp_PC as printed
    dt_max = math.sqrt(
        9 / (4 * lam) * (2 * math.pi * W * a_min / E_STAR - (a_min**2 / R - delta) ** 2)
    )
    assert pc_max_tangential_displacement(delta, R, W, E_STAR, lam) == pytest.approx(
        dt_max, rel=1e-8
    )


@pytest.mark.parametrize("lam", [0.0023, 0.2, 1.0])
@pytest.mark.parametrize("dt", [1e-5, 1e-4, 1e-3])
def test_unstable_boundary_is_the_printed_cubic(lam, dt):
    a = pc_fold_radius(dt, R, W, E_STAR, lam)
    # E:Instable_boundary as printed
    terms = [
        2 * math.pi * W / E_STAR * a**3,
        -4 / 9 * lam * dt**2 * a**2,
        -((math.pi * W * R / (2 * E_STAR)) ** 2),
    ]
    assert sum(terms) == pytest.approx(0.0, abs=1e-14 * max(abs(t) for t in terms))
    # delta_PC^min is E:PC_indent at a'_min, and it exceeds the JKR jump-off for delta_T > 0
    d_min = a**2 / R - math.sqrt(2 * math.pi * a * W / E_STAR - 4 / 9 * lam * dt**2)
    assert pc_min_indentation(dt, R, W, E_STAR, lam) == pytest.approx(d_min, rel=1e-10)
    assert d_min > jkr_jump_off_distance(R, W, E_STAR)
    # dimensionless form: a~^3 - lambda/(2 pi) dT~^2 a~^2 - pi/8 = 0 with the paper's scaling
    xi = (E_STAR * R / W) ** (1 / 3)
    dt_tilde = 2 * xi**2 / (3 * R) * dt
    a_tilde = xi / R * a
    terms = [a_tilde**3, -lam / (2 * math.pi) * dt_tilde**2 * a_tilde**2, -math.pi / 8]
    assert sum(terms) == pytest.approx(0.0, abs=1e-13 * max(abs(t) for t in terms))
    assert dimensionless_unstable_boundary(dt_tilde, lam) == pytest.approx(
        xi**2 / R * d_min, rel=1e-9
    )


def test_lambda_zero_is_jkr_even_at_infinite_shear():
    delta = 1e-5
    a_jkr = jkr_contact_radius(delta, R, W, E_STAR)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no 0 * inf: no RuntimeWarning either
        assert pc_contact_radius(delta, math.inf, R, W, E_STAR, 0.0) == pytest.approx(
            a_jkr, rel=1e-14
        )
        assert pc_normal_load(delta, math.inf, R, W, E_STAR, 0.0) == pytest.approx(
            jkr_normal_load(delta, R, W, E_STAR), rel=1e-12
        )
        assert pc_min_indentation(math.inf, R, W, E_STAR, 0.0) == jkr_jump_off_distance(
            R, W, E_STAR
        )
        assert asperity_status(3.0, math.inf, 0.0) == STICK
        assert dimensionless_unstable_boundary(math.inf, 0.0) == pytest.approx(
            -0.75 * math.pi ** (2 / 3), rel=1e-14
        )


def test_infinite_shear_with_coupling_leaves_no_stick_state():
    assert pc_min_indentation(math.inf, R, W, E_STAR, 0.2) == math.inf
    assert math.isnan(pc_contact_radius(1e-3, math.inf, R, W, E_STAR, 0.2))
    assert dimensionless_unstable_boundary(math.inf, 0.2) == math.inf
    assert asperity_status(3.0, math.inf, 0.2) == SLIDE
    assert asperity_status(-0.5, math.inf, 0.2) == OUT_OF_CONTACT


def test_invalid_single_asperity_inputs_give_nan_or_a_clear_error():
    assert math.isnan(pc_contact_radius(1e-5, 1e-5, R, W, E_STAR, -0.5))  # lambda < 0
    assert math.isnan(pc_contact_radius(1e-5, 1e-5, R, W, E_STAR, 1.5))  # lambda > 1
    assert math.isnan(pc_min_indentation(1e-5, R, W, E_STAR, math.nan))
    assert math.isnan(pc_max_tangential_displacement(1e-5, R, W, E_STAR, -0.1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert math.isnan(jkr_contact_radius(1e-5, R, -W, E_STAR))  # w < 0
        assert math.isnan(jkr_contact_radius(1e-5, -R, W, E_STAR))  # R < 0
        assert math.isnan(jkr_jump_off_distance(R, W, 0.0))  # E* = 0
        assert math.isnan(pc_contact_radius(math.nan, 0.0, R, W, E_STAR, 0.2))
        assert math.isnan(pc_contact_radius(1e-5, math.nan, R, W, E_STAR, 0.2))
    with pytest.raises(ValueError, match="delta_tilde contains NaN"):
        asperity_status(math.nan, 1.0, 0.2)
    with pytest.raises(ValueError, match="mode_mixity"):
        asperity_status(1.0, 1.0, 1.2)


@settings(max_examples=200, deadline=None)
@given(
    dt_tilde=st.floats(min_value=0.0, max_value=1e3),
    lam=st.floats(min_value=0.0, max_value=1.0),
)
def test_property_status_on_the_boundary_is_stick(dt_tilde, lam):
    # a point exactly on the unstable boundary is the fold state itself: it exists (stick)
    boundary = dimensionless_unstable_boundary(dt_tilde, lam)
    assert asperity_status(boundary, dt_tilde, lam) == STICK
    below = np.nextafter(boundary, -math.inf)
    assert asperity_status(below, dt_tilde, lam) == (SLIDE if below >= 0 else OUT_OF_CONTACT)


@settings(max_examples=300, deadline=None)
@given(
    delta=st.floats(min_value=-1.5e-6, max_value=1e-4),
    lam=st.floats(min_value=1e-4, max_value=1.0),
)
def test_property_delta_t_max_is_the_last_stick_point_to_round_off(delta, lam):
    # E:max_disp_PC (fixed delta) and E:Instable_boundary (fixed delta_T) describe the same fold;
    # at delta_T^max itself the stick state exists, 1e-12 beyond it no longer
    dt_max = pc_max_tangential_displacement(delta, R, W, E_STAR, lam)
    assert np.isfinite(pc_contact_radius(delta, dt_max, R, W, E_STAR, lam))
    assert pc_min_indentation(dt_max, R, W, E_STAR, lam) <= delta
    assert np.isnan(pc_contact_radius(delta, dt_max * (1 + 1e-12), R, W, E_STAR, lam))


@settings(max_examples=300, deadline=None)
@given(
    dt=st.floats(min_value=0.0, max_value=5e-4),
    lam=st.floats(min_value=0.0, max_value=1.0),
    ulps=st.integers(min_value=-4, max_value=4),
)
def test_property_stable_root_exists_iff_above_the_boundary_to_the_ulp(dt, lam, ulps):
    # delta within a few ulps of delta_PC^min(delta_T): the existence test is exact, and on the
    # boundary itself the root is the fold radius a'_min
    d_min = pc_min_indentation(dt, R, W, E_STAR, lam)
    delta = d_min
    for _ in range(abs(ulps)):
        delta = np.nextafter(delta, math.copysign(math.inf, ulps))
    a = pc_contact_radius(delta, dt, R, W, E_STAR, lam)
    assert np.isfinite(a) == (delta >= d_min)
    if ulps == 0:
        assert a == pc_fold_radius(dt, R, W, E_STAR, lam)
    if np.isfinite(a):
        assert a >= pc_fold_radius(dt, R, W, E_STAR, lam)
