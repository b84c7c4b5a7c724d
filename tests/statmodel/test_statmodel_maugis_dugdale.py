"""The Maugis-Dugdale sphere closed form against its JKR and DMT limits and an independent fit."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.statmodel.maugis_dugdale import MaugisDugdale, dimensionless_state

RADIUS, E_STAR, WORK = 1e-2, 1e6, 0.05  # m, Pa, J/m^2
K = 4 * E_STAR / 3


def sphere(lam: float) -> MaugisDugdale:
    """The sphere whose Maugis parameter is ``lam`` (the range h_0 = w / sigma_0 set by it)."""
    sigma0 = lam / 2 * (math.pi * WORK * K**2 / RADIUS) ** (1 / 3)
    return MaugisDugdale(RADIUS, E_STAR, WORK, WORK / sigma0)


def test_the_parameter_is_the_one_asked_for():
    assert sphere(0.7).lam == pytest.approx(0.7, rel=1e-12)


def test_jkr_limit():
    """lambda -> infinity: a^3 K / R = F + 3 pi w R + sqrt(6 pi w R F + (3 pi w R)^2), pull-off
    -3/2 pi w R, and at zero approach F = -4/3 pi w R (JKR: delta = a^2/R - sqrt(8 pi w a/3K))."""
    md = sphere(300.0)
    f = 2.5 * md.force_scale
    w_r = 3 * math.pi * WORK * RADIUS
    a_jkr = ((f + w_r + math.sqrt(2 * w_r * f + w_r**2)) * RADIUS / K) ** (1 / 3)
    assert md.contact_radius(f) == pytest.approx(a_jkr, rel=2e-3)
    assert md.pull_off_force() == pytest.approx(-1.5 * md.force_scale, rel=1e-3)
    assert md.zero_approach()["force"] == pytest.approx(-4 / 3 * md.force_scale, rel=2e-3)


def test_dmt_limit():
    """lambda -> 0: Hertz at the load F + 2 pi w R, pull-off -2 pi w R."""
    md = sphere(1e-3)
    f = 1.5 * md.force_scale
    a_dmt = ((f + 2 * md.force_scale) * RADIUS / K) ** (1 / 3)
    assert md.contact_radius(f) == pytest.approx(a_dmt, rel=1e-2)
    assert md.pull_off_force() == pytest.approx(-2 * md.force_scale, rel=1e-3)


def test_pull_off_moves_monotonically_from_dmt_to_jkr():
    values = [sphere(lam).pull_off_force() / sphere(lam).force_scale for lam in (0.05, 0.3, 1, 3)]
    assert all(b > a for a, b in zip(values, values[1:], strict=False))
    assert -2.0 < values[0] and values[-1] < -1.5


@settings(max_examples=40, deadline=None)
@given(lam=st.floats(0.05, 20.0), a_bar=st.floats(0.2, 5.0))
def test_a_state_is_a_zero_of_the_force_search(lam, a_bar):
    """contact_radius inverts the force on the stable branch: the state at a radius above the
    pull-off radius gives back that radius from its force."""
    md = sphere(lam)
    a = a_bar * md.length_scale
    state = md.state(a)
    a_min = md._minimum_force_radius() * md.length_scale
    if a > a_min * 1.01:
        assert md.contact_radius(state["force"]) == pytest.approx(a, rel=1e-8)
    assert state["zone_radius"] >= a


def test_zero_approach_is_a_zero_of_the_approach():
    md = sphere(1.0)
    za = md.zero_approach()
    assert md.state(za["contact_radius"])["approach"] == pytest.approx(0.0, abs=1e-9)
    m, p, delta = dimensionless_state(za["contact_radius"] / md.length_scale, md.lam)
    assert m > 1 and p * md.force_scale == pytest.approx(za["force"], rel=1e-9)


def test_the_dugdale_zone_is_wide_on_the_dmt_side_and_narrow_on_the_jkr_side():
    """c / a at the load pi w R: the zone reaches far out for small lambda and closes onto the
    contact edge as lambda grows, with c - a -> pi E* w / (4 sigma_0^2) (Dugdale's crack-tip
    zone with K_I^2 = 2 E* w) on the JKR side."""
    ratios = []
    for lam in (0.05, 1.0, 50.0):
        md = sphere(lam)
        a = md.contact_radius(md.force_scale)
        ratios.append(md.state(a)["zone_radius"] / a)
    assert ratios[0] > 2.0 > ratios[1] > ratios[2] > 1.0
    md = sphere(50.0)
    a = md.contact_radius(md.force_scale)
    sigma0 = WORK / md.adhesion_range
    zone = md.state(a)["zone_radius"] - a
    assert zone == pytest.approx(math.pi * E_STAR * WORK / (4 * sigma0**2), rel=2e-3)
