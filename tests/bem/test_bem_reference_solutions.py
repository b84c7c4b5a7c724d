"""The reference solutions against facts independent of the formulas they implement: the load
as the integral of the pressure field, the limits that join two solutions, inverse laws."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from asperity.bem import reference_solutions as ref
from asperity.statmodel.jkr import jkr_contact_radius as jkr_radius_at_approach

R, E_STAR, W = 2e-3, 3e6, 0.04  # m, Pa, J/m^2
LOADS = np.array([1e-4, 1e-3, 2e-2])  # N


@pytest.mark.parametrize("force", LOADS)
def test_hertz_pressure_integrates_to_the_load(force):
    a = ref.hertz_sphere_contact_radius(force, R, E_STAR)
    load, _ = quad(
        lambda r: 2 * math.pi * r * ref.hertz_sphere_pressure(r, force, R, E_STAR), 0, a, limit=200
    )
    assert load == pytest.approx(force, rel=1e-6)  # quad near the square-root edge
    assert ref.hertz_sphere_pressure(1.001 * a, force, R, E_STAR) == 0.0
    assert ref.hertz_sphere_pressure(0.0, force, R, E_STAR) == ref.hertz_sphere_peak_pressure(
        force, R, E_STAR
    )
    assert ref.hertz_sphere_mean_pressure(force, R, E_STAR) * math.pi * a**2 == pytest.approx(
        force, rel=1e-14
    )


def test_hertz_approach_and_force_are_inverse():
    """The approach from the load, fed to the displacement law, gives the load back; and the
    contact radius is sqrt(R delta) (the two routes of E:Hertz_theory)."""
    delta = ref.hertz_sphere_approach(LOADS, R, E_STAR)
    np.testing.assert_allclose(ref.hertz_sphere_force(delta, R, E_STAR), LOADS, rtol=1e-13)
    np.testing.assert_allclose(
        ref.hertz_sphere_contact_radius(LOADS, R, E_STAR), np.sqrt(R * delta), rtol=1e-14
    )
    assert ref.hertz_sphere_force(-1e-9, R, E_STAR) == 0.0


def test_jkr_without_adhesion_is_hertz():
    np.testing.assert_allclose(
        ref.jkr_sphere_contact_radius(LOADS, R, 0.0, E_STAR),
        ref.hertz_sphere_contact_radius(LOADS, R, E_STAR),
        rtol=1e-14,
    )
    a = ref.hertz_sphere_contact_radius(LOADS, R, E_STAR)
    np.testing.assert_allclose(ref.jkr_sphere_approach(a, R, 0.0, E_STAR), a**2 / R, rtol=1e-14)
    np.testing.assert_allclose(ref.jkr_sphere_force(a, R, 0.0, E_STAR), LOADS, rtol=1e-13)


def test_jkr_laws_are_consistent():
    """a(P) inverts P(a); delta(a) inverts the fixed-grip branch a(delta) solved by Newton;
    a(P) exists down to the load-controlled pull-off and not below; the fixed-grip jump-off
    is where the approach is smallest."""
    forces = np.array([-1e-4, 0.0, 1e-3, 1e-2])
    a = ref.jkr_sphere_contact_radius(forces, R, W, E_STAR)
    np.testing.assert_allclose(ref.jkr_sphere_force(a, R, W, E_STAR), forces, atol=1e-15)
    delta = ref.jkr_sphere_approach(a, R, W, E_STAR)
    np.testing.assert_allclose(jkr_radius_at_approach(delta, R, W, E_STAR), a, rtol=1e-10)
    pull_off = ref.jkr_pull_off_force_load_control(R, W)
    assert pull_off == pytest.approx(-1.5 * math.pi * W * R, rel=1e-15)
    assert np.isfinite(ref.jkr_sphere_contact_radius(pull_off, R, W, E_STAR))
    assert np.isnan(ref.jkr_sphere_contact_radius(1.01 * pull_off, R, W, E_STAR))
    radii = np.linspace(0.2, 3.0, 20001) * ref.jkr_sphere_contact_radius(0.0, R, W, E_STAR)
    approach = ref.jkr_sphere_approach(radii, R, W, E_STAR)
    jump_off = ref.jkr_jump_off_distance(R, W, E_STAR)
    assert approach.min() == pytest.approx(jump_off, rel=1e-6)
    at_jump = radii[np.argmin(approach)]
    assert ref.jkr_sphere_force(at_jump, R, W, E_STAR) == pytest.approx(
        ref.jkr_pull_off_force_fixed_grip(R, W), rel=1e-3
    )


def test_maugis_dugdale_towards_jkr():
    """A short Dugdale range (large Maugis parameter) approaches the JKR sphere."""
    sphere = ref.MaugisDugdale(R, E_STAR, W, 1e-10)
    assert sphere.lam > 30
    force = 1e-3
    assert sphere.contact_radius(force) == pytest.approx(
        ref.jkr_sphere_contact_radius(force, R, W, E_STAR), rel=0.02
    )
    assert sphere.pull_off_force() == pytest.approx(
        ref.jkr_pull_off_force_load_control(R, W), rel=0.03
    )


AMPLITUDE, WAVELENGTH = 1e-6, 1e-4  # m


@pytest.mark.parametrize("ratio", [0.05, 0.3, 0.7, 0.99, 1.0, 1.5])
def test_westergaard_pressure_averages_to_the_mean(ratio):
    """The pressure field carries the load: its mean over a period is p_mean, partial or full."""
    p_star = ref.westergaard_full_contact_pressure(AMPLITUDE, WAVELENGTH, E_STAR)
    p_mean = ratio * p_star
    a = ref.westergaard_contact_half_width(p_mean, AMPLITUDE, WAVELENGTH, E_STAR)
    field = lambda x: ref.westergaard_pressure(x, p_mean, AMPLITUDE, WAVELENGTH, E_STAR)  # noqa: E731
    integral, _ = quad(field, -a, a, limit=200)
    assert integral / WAVELENGTH == pytest.approx(p_mean, rel=1e-8)
    assert ref.westergaard_mean_pressure(a, AMPLITUDE, WAVELENGTH, E_STAR) == pytest.approx(
        min(p_mean, p_star), rel=1e-12
    )


def test_westergaard_full_contact_at_p_star():
    """At p* the contact closes (a = lambda / 2), the pressure at the trough falls to zero and
    the partial-contact field equals the full-contact one."""
    p_star = ref.westergaard_full_contact_pressure(AMPLITUDE, WAVELENGTH, E_STAR)
    assert p_star == pytest.approx(math.pi * E_STAR * AMPLITUDE / WAVELENGTH, rel=1e-15)
    a = ref.westergaard_contact_half_width(p_star, AMPLITUDE, WAVELENGTH, E_STAR)
    assert a == pytest.approx(WAVELENGTH / 2, rel=1e-12)
    x = np.linspace(-WAVELENGTH / 2, WAVELENGTH / 2, 101)
    below = ref.westergaard_pressure(x, p_star * (1 - 1e-12), AMPLITUDE, WAVELENGTH, E_STAR)
    at = ref.westergaard_pressure(x, p_star, AMPLITUDE, WAVELENGTH, E_STAR)
    np.testing.assert_allclose(below, at, atol=1e-5 * p_star)
    assert at[0] == pytest.approx(0.0, abs=1e-9 * p_star)
    assert at[50] == pytest.approx(2 * p_star, rel=1e-14)
