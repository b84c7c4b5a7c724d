"""Single-asperity laws: JKR, Papangelo-Ciavarella, Hertz (paper Section 2)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from asperity.statmodel import (
    hertz_contact_radius,
    hertz_normal_load,
    jkr_contact_radius,
    jkr_jump_in_distance,
    jkr_jump_off_distance,
    jkr_normal_load,
    jkr_pull_off_force_fixed_grip,
    jkr_pull_off_force_load_control,
    pc_contact_radius,
    pc_fold_radius,
    pc_max_tangential_displacement,
    pc_min_indentation,
    pc_normal_load,
    pc_tangential_load,
    tabor_parameter,
)
from asperity.statmodel.jkr import jkr_load_from_radius

# Fig. 1/2 parameters (Mergel et al. as extracted by Papangelo & Ciavarella)
R, W, E, LAM = 9.42e-3, 0.027, 2.133e6, 0.0023
K = math.sqrt(2 * math.pi * W / E)


def jkr_indent(a, r=R, w=W, e=E):
    """E:JKR_indent as written in the paper."""
    return a**2 / r - np.sqrt(2 * np.pi * w * a / e)


def pc_indent(a, dt, lam=LAM, r=R, w=W, e=E):
    """E:PC_indent as written in the paper."""
    return a**2 / r - np.sqrt(2 * np.pi * a * w / e - 4.0 / 9.0 * lam * dt**2)


def test_tabor_parameter_matches_paper_captions():
    assert tabor_parameter(R, W, E, 0.2e-9) == pytest.approx(5736, rel=1e-3)  # Fig. 1
    assert tabor_parameter(0.041e-3, 0.040, E, 0.2e-9) == pytest.approx(1217, rel=1e-3)  # Fig. 4


def test_jkr_root_solves_the_indentation_equation_on_the_stable_branch():
    delta = np.linspace(jkr_jump_off_distance(R, W, E), 5e-5, 200)
    a = jkr_contact_radius(delta, R, W, E)
    np.testing.assert_allclose(jkr_indent(a), delta, rtol=0, atol=1e-15 * 5e-5)
    # stable branch: d delta / d a > 0 (a increases with delta)
    assert np.all(np.diff(a) > 0)
    assert np.all(2 * a / R - 0.5 * K / np.sqrt(a) >= -1e-12 * 2 * a / R)


def test_jkr_jump_off_is_the_fold_and_matches_closed_form():
    mu, eps = tabor_parameter(R, W, E, 0.2e-9), 0.2e-9
    d_off = jkr_jump_off_distance(R, W, E)
    assert d_off == pytest.approx(-0.75 * math.pi ** (2 / 3) * mu * eps, rel=1e-13)
    a_c = (math.pi * W * R**2 / (8 * E)) ** (1 / 3)
    assert jkr_contact_radius(d_off, R, W, E) == pytest.approx(a_c, rel=1e-14)
    assert math.isnan(jkr_contact_radius(d_off * (1 + 1e-12), R, W, E))
    # the fold is the minimum of delta(a): no lower indentation on any branch
    res = minimize_scalar(
        jkr_indent, bounds=(1e-7, 1e-3), method="bounded", options={"xatol": 1e-14}
    )
    assert res.fun == pytest.approx(d_off, rel=1e-10)


def test_jkr_pull_off_in_load_control_is_minus_three_halves_pi_w_r():
    # minimum of E:JKR_load over the contact radius (load control)
    res = minimize_scalar(
        lambda a: jkr_load_from_radius(a, R, W, E),
        bounds=(1e-6, 1e-3),
        method="bounded",
        options={"xatol": 1e-15},
    )
    assert res.fun == pytest.approx(jkr_pull_off_force_load_control(R, W), rel=1e-9)
    assert res.fun == pytest.approx(-1.5 * math.pi * W * R, rel=1e-9)
    assert res.x == pytest.approx((9 * math.pi * W * R**2 / (8 * E)) ** (1 / 3), rel=1e-5)


def test_jkr_fixed_grip_limits():
    d_off = jkr_jump_off_distance(R, W, E)
    # force at the fixed-grip jump-off point is -5/6 pi w R, and P(delta) is the load there
    assert jkr_normal_load(d_off, R, W, E) == pytest.approx(
        jkr_pull_off_force_fixed_grip(R, W), rel=1e-12
    )
    assert jkr_pull_off_force_fixed_grip(R, W) == pytest.approx(-5 / 6 * math.pi * W * R)
    # zero indentation: a^3 = 2 pi w R^2 / E*, P = -2/3 E* a^3 / R
    a0 = (2 * math.pi * W * R**2 / E) ** (1 / 3)
    assert jkr_contact_radius(0.0, R, W, E) == pytest.approx(a0, rel=1e-14)
    assert jkr_normal_load(0.0, R, W, E) == pytest.approx(-2 / 3 * E * a0**3 / R, rel=1e-12)
    # zero load: the classical JKR a^3 = 6 pi w R^2 / K with K = 4/3 E*
    a_p0 = (6 * math.pi * W * R**2 / (4 / 3 * E)) ** (1 / 3)
    assert jkr_normal_load(jkr_indent(a_p0), R, W, E) == pytest.approx(0.0, abs=1e-12 * W * R)


def test_jkr_reduces_to_hertz_as_w_vanishes():
    delta = np.array([1e-7, 1e-6, 1e-5])
    np.testing.assert_allclose(
        jkr_contact_radius(delta, R, 0.0, E), hertz_contact_radius(delta, R), rtol=4.5e-16
    )
    np.testing.assert_allclose(
        jkr_normal_load(delta, R, 0.0, E), hertz_normal_load(delta, R, E), rtol=1e-15
    )
    assert jkr_jump_off_distance(R, 0.0, E) == 0.0
    errs = [
        abs(jkr_normal_load(1e-5, R, w, E) / hertz_normal_load(1e-5, R, E) - 1)
        for w in (1e-3, 1e-5, 1e-7)
    ]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 1e-2


def test_wu_jump_in_lies_between_jump_off_and_zero_for_jkr_range():
    for r in (1e-5, 4.1e-5, 1e-3, R):
        mu = tabor_parameter(r, W, E, 0.2e-9)
        assert mu > 5
        d_in = jkr_jump_in_distance(mu, 0.2e-9)
        assert jkr_jump_off_distance(r, W, E) < d_in < 0.0
    assert jkr_jump_in_distance(0.0, 0.2e-9) == 0.0
    assert jkr_jump_in_distance(100.0, 1e-9) == pytest.approx(
        -2.641 * 100 ** (3 / 7) * math.exp(-0.05) * 1e-9
    )


def test_pc_equals_jkr_without_shear_or_without_coupling():
    delta = np.linspace(jkr_jump_off_distance(R, W, E), 3e-5, 50)
    a_jkr = jkr_contact_radius(delta, R, W, E)
    np.testing.assert_allclose(pc_contact_radius(delta, 0.0, R, W, E, LAM), a_jkr, rtol=1e-14)
    np.testing.assert_allclose(pc_contact_radius(delta, 1e-3, R, W, E, 0.0), a_jkr, rtol=1e-14)
    np.testing.assert_allclose(
        pc_normal_load(delta, 1e-3, R, W, E, 0.0),
        jkr_normal_load(delta, R, W, E),
        rtol=1e-12,
        atol=1e-15,
    )
    assert pc_min_indentation(0.0, R, W, E, LAM) == jkr_jump_off_distance(R, W, E)
    assert pc_min_indentation(5e-4, R, W, E, 0.0) == jkr_jump_off_distance(R, W, E)
    assert math.isinf(pc_max_tangential_displacement(1e-5, R, W, E, 0.0))


def test_pc_converges_to_jkr_as_lambda_vanishes():
    delta, dt = 1e-5, 3e-5
    a_jkr = jkr_contact_radius(delta, R, W, E)
    errs = [
        abs(pc_contact_radius(delta, dt, R, W, E, lam) / a_jkr - 1)
        for lam in (1e-2, 1e-3, 1e-4, 1e-5)
    ]
    # first order in lambda: each decade of lambda gains a decade of accuracy
    for e1, e2 in zip(errs, errs[1:], strict=False):
        assert e2 == pytest.approx(e1 / 10, rel=0.05)


def test_pc_root_satisfies_equations_and_loads():
    delta = np.linspace(-1e-6, 4e-5, 40)
    dt = 5e-5
    a = pc_contact_radius(delta, dt, R, W, E, LAM)
    ok = np.isfinite(a)
    assert ok.sum() > 30
    np.testing.assert_allclose(pc_indent(a[ok], dt), delta[ok], rtol=0, atol=1e-16 * 4e-5 * 100)
    p = pc_normal_load(delta, dt, R, W, E, LAM)[ok]
    p_paper = 4 * E * a[ok] ** 3 / (3 * R) - np.sqrt(
        8 * np.pi * E * a[ok] ** 3 * W - 16 / 9 * LAM * E**2 * a[ok] ** 2 * dt**2
    )
    np.testing.assert_allclose(p, p_paper, rtol=1e-13)
    # on the root, E:PC_P equals 2 E* a delta - 2/3 E* a^3 / R
    np.testing.assert_allclose(
        p,
        2 * E * a[ok] * delta[ok] - 2 / 3 * E * a[ok] ** 3 / R,
        rtol=1e-9,
        atol=1e-9 * np.abs(p).max(),
    )
    np.testing.assert_allclose(
        pc_tangential_load(delta, dt, R, W, E, LAM)[ok], 4 / 3 * E * a[ok] * dt, rtol=1e-15
    )


@pytest.mark.parametrize("lam", [LAM, 0.2, 1.0])
@pytest.mark.parametrize("delta", [-1.0e-6, 0.0, 1e-6, 1e-5, 1e-4])
def test_delta_t_max_is_where_the_stable_root_disappears(lam, delta):
    dt_max = pc_max_tangential_displacement(delta, R, W, E, lam)
    assert 0 < dt_max < math.inf
    assert np.isfinite(pc_contact_radius(delta, dt_max * (1 - 1e-9), R, W, E, lam))
    assert np.isnan(pc_contact_radius(delta, dt_max * (1 + 1e-9), R, W, E, lam))
    # the point (delta, dt_max) lies on the unstable boundary delta = delta_PC^min(dt)
    assert pc_min_indentation(dt_max, R, W, E, lam) == pytest.approx(delta, abs=1e-12 * R)
    # and there the fold radius is the E:PC_a_min_1 root a_min
    a_f = pc_fold_radius(dt_max, R, W, E, lam)
    assert a_f**3 - delta * R * a_f - math.pi * W * R**2 / (2 * E) == pytest.approx(
        0.0, abs=1e-10 * a_f**3
    )


def test_savkoor_briggs_lambda_one_griffith_criterion():
    # lambda = 1: the failure locus is G = w, i.e. (K_I^2 + K_II^2)/(2E*) = w; check the
    # E:PC_indent solution satisfies delta = a^2/R - sqrt(2 pi w a/E* - 4/9 dt^2) exactly
    delta = 5e-6
    dt = 0.5 * pc_max_tangential_displacement(delta, R, W, E, 1.0)
    a = pc_contact_radius(delta, dt, R, W, E, 1.0)
    assert pc_indent(a, dt, lam=1.0) == pytest.approx(delta, abs=1e-18)
    assert pc_max_tangential_displacement(delta, R, W, E, 1.0) < pc_max_tangential_displacement(
        delta, R, W, E, 0.1
    )


def test_points_on_the_unstable_boundary_are_exact():
    for dt in (0.0, 1e-4, 1e-3):
        d_min = pc_min_indentation(dt, R, W, E, LAM)
        a_f = pc_fold_radius(dt, R, W, E, LAM)
        assert pc_contact_radius(d_min, dt, R, W, E, LAM) == a_f
        assert np.isnan(pc_contact_radius(np.nextafter(d_min, -1.0), dt, R, W, E, LAM))


def test_no_stick_without_adhesion_under_shear():
    assert math.isinf(pc_min_indentation(1e-6, R, 0.0, E, 0.2))
    assert np.isnan(pc_contact_radius(1e-5, 1e-6, R, 0.0, E, 0.2))
    assert pc_max_tangential_displacement(1e-5, R, 0.0, E, 0.2) == 0.0
    assert pc_contact_radius(1e-5, 0.0, R, 0.0, E, 0.2) == pytest.approx(math.sqrt(R * 1e-5))


def test_below_jkr_jump_off_there_is_no_state():
    d = jkr_jump_off_distance(R, W, E) * 1.01
    assert np.isnan(pc_max_tangential_displacement(d, R, W, E, LAM))
    assert np.isnan(jkr_contact_radius(d, R, W, E))


_dt = st.floats(min_value=0.0, max_value=3e-3)
_delta = st.floats(min_value=-5e-6, max_value=1e-4)
_lam = st.floats(min_value=0.0, max_value=1.0)


@settings(max_examples=300, deadline=None)
@given(delta=_delta, dt=_dt, lam=_lam)
def test_property_stable_root_exists_iff_above_min_indentation(delta, dt, lam):
    a = pc_contact_radius(delta, dt, R, W, E, lam)
    d_min = pc_min_indentation(dt, R, W, E, lam)
    assert np.isfinite(a) == (delta >= d_min)
    if np.isfinite(a):
        # a root of E:PC_indent on the stable side of the fold
        assert pc_indent(a, dt, lam=lam) == pytest.approx(delta, abs=1e-9 * max(abs(delta), 1e-6))
        assert a >= pc_fold_radius(dt, R, W, E, lam)


@settings(max_examples=200, deadline=None)
@given(
    delta=st.floats(min_value=-1.5e-6, max_value=1e-4),
    f1=st.floats(min_value=0.0, max_value=1.0),
    f2=st.floats(min_value=0.0, max_value=1.0),
    lam=st.floats(min_value=1e-4, max_value=1.0),
)
def test_property_contact_radius_decreases_with_delta_t(delta, f1, f2, lam):
    # both delta_T inside the stick range [0, delta_T^max(delta)], so every example is a check
    dt_max = pc_max_tangential_displacement(delta, R, W, E, lam)
    lo, hi = sorted((f1 * dt_max, f2 * dt_max))
    a_lo = pc_contact_radius(delta, lo, R, W, E, lam)
    a_hi = pc_contact_radius(delta, hi, R, W, E, lam)
    assert np.isfinite(a_lo) and np.isfinite(a_hi)
    assert a_hi <= a_lo * (1 + 1e-12)
    if hi > lo * (1 + 1e-6) and hi > 1e-3 * dt_max:
        assert a_hi < a_lo


@settings(max_examples=200, deadline=None)
@given(dt1=_dt, dt2=_dt, lam=st.floats(min_value=1e-4, max_value=1.0))
def test_property_min_indentation_increases_with_delta_t(dt1, dt2, lam):
    lo, hi = sorted((dt1, dt2))
    assert pc_min_indentation(lo, R, W, E, lam) <= pc_min_indentation(hi, R, W, E, lam)


@settings(max_examples=40, deadline=None)
@given(
    radius=st.floats(1e-6, 1e-2),
    work=st.floats(1e-3, 1.0),
    e_star=st.floats(1e5, 1e11),
)
def test_jkr_zero_load_radius_carries_no_load(radius: float, work: float, e_star: float) -> None:
    """a0 is where E:JKR_load crosses zero: P(a0) = 0 against the load's own scale (the
    Hertz and adhesive terms, each 4 E* a0^3 / (3 R) there), and P < 0 just inside it."""
    from asperity.statmodel import jkr_zero_load_radius

    a0 = float(jkr_zero_load_radius(radius, work, e_star))
    scale = 4 * e_star * a0**3 / (3 * radius)
    assert abs(jkr_load_from_radius(a0, radius, work, e_star)) <= 1e-9 * scale
    assert jkr_load_from_radius(0.99 * a0, radius, work, e_star) < 0
