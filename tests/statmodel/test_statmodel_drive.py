"""The contact driven through a spring: drive = delta_T + F_x / k, stick-slip where
dF_x/d delta_T < -k (statmodel.drive)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from asperity import statmodel
from asperity.errors import InputError
from asperity.statmodel.drive import drive_curve, map_to_drive
from tests._helpers import PAPER_MATERIAL

#: The paper's wire (Sahli et al.): the rig of its Fig 6.
WIRE = 9200.0


def _peaked_curve(f_s: float, f_d: float, rise: float, fall: float, d_s: float = 1e-5):
    """F_x(delta_T): linear rise (N/m) to F_s at d_s, linear fall (N/m, > 0) to F_d, plateau."""
    dts = np.linspace(0.0, 4.0 * d_s, 4001)
    up = f_s - rise * (d_s - dts)
    down = np.maximum(f_s - fall * (dts - d_s), f_d)
    return dts, np.where(dts <= d_s, up, down)


def test_rigid_drive_is_the_interface():
    dts, fx = _peaked_curve(0.4, 0.13, 4e4, 5e5)
    curve = map_to_drive(dts, fx, math.inf)
    assert np.array_equal(curve.drive_displacement, dts)
    assert not curve.stick_slip
    assert curve.static_drive_displacement == pytest.approx(1e-5)


def test_series_springs_stiffness():
    """A linear contact k_c in series with the drive's k: F / drive = k k_c / (k + k_c)."""
    k_c = 4.6e4
    dts = np.linspace(0.0, 1e-5, 11)
    curve = map_to_drive(dts, k_c * dts, WIRE)
    slope = np.polyfit(curve.drive_displacement, curve.tangential_force, 1)[0]
    assert slope == pytest.approx(WIRE * k_c / (WIRE + k_c), rel=1e-12)


def test_fall_steeper_than_spring_jumps_at_equal_drive():
    """Fall 5e5 N/m > k: the jump at the peak's drive D* = d_s + F_s/k lands on the plateau
    at delta_T = D* - F_d/k, with the whole drop F_s - F_d."""
    f_s, f_d, d_s = 0.4, 0.13, 1e-5
    dts, fx = _peaked_curve(f_s, f_d, 4e4, 5e5, d_s)
    curve = map_to_drive(dts, fx, WIRE, sliding_friction=f_d)
    (jump,) = curve.jumps
    d_star = d_s + f_s / WIRE
    assert jump.drive_displacement == pytest.approx(d_star, rel=1e-9)
    assert jump.force_drop == pytest.approx(f_s - f_d, rel=1e-9)
    assert jump.tangential_displacement_after == pytest.approx(d_star - f_d / WIRE, rel=1e-9)
    assert curve.static_drive_displacement == pytest.approx(d_star)


def test_fall_gentler_than_spring_no_jump():
    dts, fx = _peaked_curve(0.4, 0.13, 4e4, 0.5 * WIRE)
    curve = map_to_drive(dts, fx, WIRE, sliding_friction=0.13)
    assert not curve.stick_slip
    assert np.all(curve.stable)


def test_followed_path_never_goes_back():
    dts, fx = _peaked_curve(0.4, 0.13, 4e4, 5e5)
    curve = map_to_drive(dts, fx, WIRE, sliding_friction=0.13)
    drive, force = curve.followed_path()
    assert np.all(np.diff(drive) >= 0.0)
    d_star = curve.jumps[0].drive_displacement
    after = curve.force_at_drive([d_star - 1e-9, d_star, d_star + 1e-9])
    assert after[0] == pytest.approx(0.4, rel=1e-3)
    assert after[1] == after[2] == pytest.approx(0.13)


@pytest.fixture(scope="module")
def paper_curve() -> statmodel.ShearCurve:
    mat = PAPER_MATERIAL
    rough = statmodel.Roughness(
        asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3
    )
    return statmodel.shear_curve(mat, rough, 700e-6, 0.56, np.linspace(0.0, 2.6e-5, 801))


def test_model_through_the_wire_sticks_and_slips(paper_curve):
    """The paper's contact through its 9200 N/m wire: the fall after the static peak is
    steeper than -k, so a jump; it starts where the model's slope reaches -k, lands where
    the drive is back at D*, and the peak is seen at drive delta_s + F_s / k."""
    curve = drive_curve(paper_curve, WIRE)
    assert curve.stick_slip
    jump = curve.jumps[0]
    dts, fx = paper_curve.tangential_displacement, paper_curve.tangential_force
    slope = np.interp(jump.tangential_displacement_before, dts[1:], np.diff(fx) / np.diff(dts))
    assert slope == pytest.approx(-WIRE, rel=0.05)
    landed = jump.tangential_displacement_after + jump.force_after / WIRE
    assert landed == pytest.approx(jump.drive_displacement, rel=1e-6)
    assert jump.force_after < paper_curve.static_friction
    assert jump.tangential_displacement_before > paper_curve.static_displacement
    expected = paper_curve.static_displacement + paper_curve.static_friction / WIRE
    assert curve.static_drive_displacement == pytest.approx(expected)
    # the spring's share of the drive at the peak dwarfs the interface's (paper, Section 4)
    assert paper_curve.static_friction / WIRE > 3 * paper_curve.static_displacement


def test_stiff_drive_follows_the_fall(paper_curve):
    """A drive stiffer than the model's steepest fall holds the contact: no jump."""
    dts, fx = paper_curve.tangential_displacement, paper_curve.tangential_force
    steepest = float(-np.min(np.diff(fx) / np.diff(dts)))
    assert not drive_curve(paper_curve, 2.0 * steepest).stick_slip
    assert drive_curve(paper_curve, 0.5 * steepest).stick_slip


@pytest.mark.parametrize("k", [0.0, -1.0, math.nan, "stiff"])
def test_bad_stiffness_is_refused(k):
    dts, fx = _peaked_curve(0.4, 0.13, 4e4, 5e5)
    with pytest.raises(InputError, match="drive_stiffness"):
        map_to_drive(dts, fx, k)


@settings(max_examples=40, deadline=None)
@given(
    rise=st.floats(1e3, 1e6),
    fall=st.floats(1e2, 1e7),
    k=st.floats(1e2, 1e7),
    ratio=st.floats(0.05, 0.95),
)
def test_path_is_stable_and_monotonic(rise, fall, k, ratio):
    """Any peaked curve: the followed path's drive never decreases, a jump happens exactly
    when the fall is steeper than k, and every jump conserves the drive."""
    assume(abs(fall / k - 1.0) > 1e-6)  # a fall exactly as steep as k is neutral
    d_s = 1e-5
    f_s = rise * d_s
    assume((1.0 - ratio) * f_s / fall > 1e-7)  # the fall spans >= 10 steps of the grid
    dts, fx = _peaked_curve(f_s, ratio * f_s, rise, fall, d_s)
    curve = map_to_drive(dts, fx, k, sliding_friction=ratio * f_s)
    drive, _ = curve.followed_path()
    assert np.all(np.diff(drive) >= 0.0)
    assert curve.stick_slip == (fall > k)
    for jump in curve.jumps:
        back = jump.tangential_displacement_after + jump.force_after / k
        assert back == pytest.approx(jump.drive_displacement, rel=1e-9)
