"""Plausibility checks: plasticity index, contact pressure, static peak and junction shear."""

from __future__ import annotations

import math

import numpy as np
import pytest

from asperity.errors import InputError
from asperity.statmodel import (
    Material,
    Roughness,
    contact_pressure_check,
    junction_shear_check,
    plasticity_index,
    plasticity_index_check,
    shear_curve,
    static_to_sliding_check,
)


def test_plasticity_index_hand_computed():
    # E* = 4 GPa, H = 200 MPa, sigma_s = 1 um, R = 100 um: psi = 20 sqrt(0.01) = 2
    assert plasticity_index(4e9, 2e8, 1e-6, 1e-4) == pytest.approx(2.0, rel=1e-15)
    # the paper's PDMS with a hypothetical H = 10 MPa at 260 um: sqrt(0.0419 / 1.180) / 4.69
    psi = plasticity_index(2.133e6, 10e6, 0.0419e-3, 1.180e-3)
    assert psi == pytest.approx(0.2133 * math.sqrt(0.0419 / 1.180), rel=1e-12)


@pytest.mark.parametrize(
    ("sigma", "level", "threshold"),
    [
        (0.25e-6, "ok", 0.6),
        (0.64e-6, "warning", 0.6),
        (1e-6, "warning", 0.6),
        (4e-6, "invalid", 1.0),
    ],
)
def test_plasticity_levels_follow_greenwood_williamson(sigma, level, threshold):
    # E*/H = 10, R = 100 um: psi = 10 sqrt(sigma / R) = 0.5, 0.8, 1.0, 2.0
    check = plasticity_index_check(1e9, 1e8, sigma, 1e-4)
    assert check.level == level and check.threshold == threshold
    assert check.code == "plastic_asperities"
    if level != "ok":
        assert "material.hardness" in check.parameters and "hardness" in check.message


def test_contact_pressure_against_hardness():
    loads, areas = [0.5, 1.0], [1e-5, 1e-5]  # the largest F_z / A_r is 1e5 Pa
    assert contact_pressure_check(loads, areas, 1e6).level == "ok"
    warning = contact_pressure_check(loads, areas, 2e5)  # 0.5 H, past first yield (0.39 H)
    assert warning.level == "warning" and warning.value == pytest.approx(0.5)
    invalid = contact_pressure_check(loads, areas, 5e4)  # 2 H: no elastic contact carries that
    assert invalid.level == "invalid" and invalid.threshold == 1.0
    assert "load index 1" in invalid.message


def test_friction_ratio_of_the_default_job_is_ok_and_a_glassy_polymer_is_invalid():
    # the default job's static and sliding friction at 0.56 and 3.12 N (report, 2026-11-25)
    ok = static_to_sliding_check([0.2753, 1.374], [0.105, 0.5437])
    assert ok.level == "ok" and ok.value == pytest.approx(0.2753 / 0.105)
    glassy = static_to_sliding_check([2.4], [2.4 / 700])  # x3p-2 with E* = 4 GPa: ~700
    assert glassy.level == "invalid" and glassy.invalid_threshold == 100.0  # issue 24, sec. 5
    assert glassy.parameters == ("material.shear_strength", "material.mode_mixity")
    assert "tau_0" in glassy.message and "lambda" in glassy.message


def test_junctions_in_full_sliding_carry_exactly_tau_0():
    """Once every junction slides, F_x = tau_0 A_r (Hertz sliding): the shear ratio is 1."""
    material = Material(
        e_star=2.133e6, work_of_adhesion=0.040, mode_mixity=0.2, shear_strength=0.13e6
    )
    rough = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
    curve = shear_curve(material, rough, 700e-6, 3.1, np.linspace(0.0, 40e-6, 81))
    assert curve.success and curve.n_stick[-1] == 0
    sliding = junction_shear_check([curve.tangential_force[-1]], [curve.real_area[-1]], 0.13e6)
    assert sliding.value == pytest.approx(1.0, rel=1e-9) and sliding.level == "ok"
    peak = int(np.argmax(curve.tangential_force))
    at_peak = junction_shear_check([curve.tangential_force[peak]], [curve.real_area[peak]], 0.13e6)
    assert 1.0 < at_peak.value < 10.0 and at_peak.level == "ok"
    # x3p-2 with a glassy polymer: 78 MPa of junction shear against tau_0 = 0.13 MPa
    glassy = junction_shear_check([78e6 * 1e-8], [1e-8], 0.13e6)
    assert glassy.level == "warning" and glassy.value == pytest.approx(600.0)


def test_loads_not_computed_are_left_out_and_none_computed_is_a_warning():
    partial = static_to_sliding_check([1.0, math.nan, 3.0], [0.5, 0.2, math.nan])
    assert partial.level == "ok" and partial.value == pytest.approx(2.0)
    nothing = junction_shear_check([math.nan], [1e-6], 0.13e6)
    assert math.isnan(nothing.value) and nothing.level == "warning"
    assert "not computed" in nothing.message and "far beyond" not in nothing.message


@pytest.mark.parametrize(
    ("call", "named"),
    [
        (lambda: plasticity_index(2e6, 0.0, 1e-6, 1e-4), "hardness"),
        (lambda: contact_pressure_check([1.0, 2.0], [1e-5], 1e6), "same length"),
        (lambda: contact_pressure_check([1.0], [0.0], 1e6), "real_area"),
        (lambda: static_to_sliding_check([1.0], [math.inf]), "sliding_friction"),
        (lambda: static_to_sliding_check([-1.0], [1.0]), "static_friction"),
        (lambda: junction_shear_check([1.0], [1e-6], -1.0), "shear_strength"),
    ],
)
def test_bad_input_names_the_argument(call, named):
    with pytest.raises(InputError, match=named):
        call()
