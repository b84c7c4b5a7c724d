"""Every accuracy knob and parameter is bounded with its reason; results speak scipy's status."""

import math

import numpy as np
import pytest

from asperity.errors import InputError
from asperity.statmodel import Material, QuadratureOptions, Roughness
from asperity.statmodel.checks import StatmodelWarning
from asperity.statmodel.preloading import PRELOAD_STATUS, preload, pull_off_force
from asperity.statmodel.shear import MAX_STEPS, SHEAR_STATUS, shear_curve
from tests._helpers import FIG4_AREA, FIG4_LOAD, FIG4_MATERIAL, FIG4_ROUGHNESS

MAT, ROUGH, AREA, LOAD = FIG4_MATERIAL, FIG4_ROUGHNESS, FIG4_AREA, FIG4_LOAD
DTS = np.linspace(0.0, 14e-6, 29)


@pytest.mark.parametrize(
    "knob, value, reason",
    [
        # each of these used to run and report "converged" (or exhaust the memory)
        ("cutoff_sigma", 1e300, "underflows"),  # gave 1479 N of static friction (true 0.8235 N)
        ("cutoff_sigma", 6.0, "truncated Gaussian tail"),  # 3e-4 low
        ("load_rtol", 1.0, "not resolved"),  # gave 2.9e-14 N
        ("load_rtol", 1e-16, "round-off"),
        ("nodes", 1e6, "gain nothing"),  # MemoryError / minutes
        ("nodes", 0, "integer in"),
        ("nodes", 2.5, "integer in"),
        ("nodes", True, "integer in"),
        ("panels", 10**9, "gain nothing"),
        ("max_iter", 2**63 - 1, "Brent iterations"),
        ("cutoff_sigma", math.nan, "got nan"),
        ("load_rtol", "tight", "got .tight."),
    ],
)
def test_absurd_accuracy_knobs_are_refused_with_the_reason(knob, value, reason):
    with pytest.raises(InputError, match=rf"{knob}: expected .*{reason}"):
        QuadratureOptions(**{knob: value})
    with pytest.raises(InputError, match=knob):
        shear_curve(MAT, ROUGH, AREA, LOAD, DTS, **{knob: value})


def test_the_knob_range_ends_give_the_same_friction():
    # every accepted setting resolves the model: the ends of the ranges agree with the defaults
    default = shear_curve(MAT, ROUGH, AREA, LOAD, DTS).static_friction
    for knobs in (
        {"cutoff_sigma": 8.0},
        {"cutoff_sigma": 40.0},
        {"load_rtol": 1e-6},
        {"load_rtol": 1e-14},
        {"nodes": 128, "panels": 64},
    ):
        c = shear_curve(MAT, ROUGH, AREA, LOAD, DTS, **knobs)
        assert c.success, knobs
        assert c.static_friction == pytest.approx(default, rel=1e-8), knobs


@pytest.mark.parametrize(
    "build, field",
    [
        (lambda: Material(1e308, 0.04, 0.2, 0.13e6), "Material.e_star"),  # MemoryError before
        (lambda: Material(1.0, 0.04, 0.2, 0.13e6), "Material.e_star"),
        (lambda: Material(2e6, 100.0, 0.2, 0.13e6), "Material.work_of_adhesion"),
        (lambda: Material(2e6, 0.04, 0.2, 1e15), "Material.shear_strength"),
        (lambda: Material(2e6, 0.04, 0.2, 0.13e6, 1e-3), "Material.equilibrium_distance"),
        (lambda: Roughness(1e30, 4e-5, 3e-5), "Roughness.asperity_density"),
        (lambda: Roughness(6e8, 1e5, 3e-5), "Roughness.summit_radius"),
        (lambda: Roughness(6e8, 4e-5, 10.0), "Roughness.summit_height_rms"),
    ],
)
def test_unphysical_parameters_are_refused_naming_the_field_and_range(build, field):
    with pytest.raises(InputError, match=rf"{field}: expected a number in \[.*\] .* \(.+\), got"):
        build()


def test_a_history_longer_than_the_step_limit_is_refused_before_any_work():
    with pytest.raises(InputError, match=f"at most {MAX_STEPS} steps"):
        shear_curve(MAT, ROUGH, AREA, LOAD, np.zeros(MAX_STEPS + 1))


def test_a_converged_curve_and_preload_report_status_zero():
    c = shear_curve(MAT, ROUGH, AREA, LOAD, DTS)
    assert (c.success, c.status, c.converged) == (True, 0, True)
    assert c.message == "converged" and c.status in SHEAR_STATUS
    pre = preload(MAT, ROUGH, AREA, LOAD)
    assert (pre.success, pre.status, pre.converged) == (True, 0, True)
    assert pre.message == PRELOAD_STATUS[0] and pre.nit > 0


def test_a_tensile_load_lost_under_shear_is_status_two_and_nan_after():
    # smooth adhesive surface held at half its pull-off force: shear weakens the junctions
    # (E:PC_indent) until the tension can no longer be carried
    mat = Material(1e6, 0.05, 0.2, 1e5)
    rough = Roughness(1e9, 1e-4, 3e-8)
    load = 0.5 * pull_off_force(mat, rough, 1e-4)
    with pytest.warns(StatmodelWarning, match="A_r/A_n"):  # a smooth surface: near-full contact
        c = shear_curve(mat, rough, 1e-4, load, np.linspace(0.0, 5e-6, 21))
    assert (c.success, c.converged, c.status) == (False, False, 2)
    assert "area_fraction" in c.validity_codes  # said beside the solver's own failure
    assert "cannot be carried" in c.message
    failed = np.flatnonzero(np.isnan(c.tangential_force))
    assert failed.size and np.all(np.isnan(c.tangential_force[failed[0] :]))
    np.testing.assert_allclose(c.normal_force[: failed[0]], load, rtol=1e-9)
    # the static friction is the peak of the solved part, not NaN
    assert c.static_friction == pytest.approx(np.nanmax(c.tangential_force), rel=1e-3)
    assert c.static_friction >= np.nanmax(c.tangential_force)
