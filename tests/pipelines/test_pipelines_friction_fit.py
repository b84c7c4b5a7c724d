"""lambda fitted to friction tests F_x(drive) through the loading system's spring
(statmodel.lambda_fit_friction): the interval covers the true lambda, at its stated level over
seeds."""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest

from asperity import statmodel
from asperity.errors import InputError
from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.measured_friction import FrictionCurve
from asperity.statmodel.lambda_fit import LambdaFit, interpolate_area
from asperity.statmodel.lambda_fit_friction import (
    compare_sources,
    fit_mode_mixity_friction,
    fit_sources,
)
from asperity.statmodel.shear_path import model_drive_curve
from tests._helpers import shear_area_model

WIRE = 9200.0  # N/m, the paper's loading wire
TRUE_LAMBDA = 0.03
MATERIAL = statmodel.Material(
    e_star=2.133e6,
    work_of_adhesion=0.040,
    mode_mixity=TRUE_LAMBDA,
    shear_strength=0.13e6,
    equilibrium_distance=0.2e-9,
)
ROUGHNESS = statmodel.Roughness(
    asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3
)
MODEL = functools.partial(
    model_drive_curve,
    material=MATERIAL,
    roughness=ROUGHNESS,
    nominal_area=700e-6,
    drive_stiffness=WIRE,
    max_tangential_displacement=None,
    steps=61,
    knobs={},
)


@functools.cache
def _truth(load: float) -> statmodel.DriveCurve:
    return MODEL(TRUE_LAMBDA, load)


def _test(load: float, seed: int, noise: float = 0.01, n: int = 60) -> FrictionCurve:
    """A friction test made from the model at lambda 0.03 through the 9200 N/m wire: the drive
    from 0 to 1.6 times the peak's, F_x as the drive follows it (the jump included), plus white
    noise of ``noise`` times F_s."""
    truth = _truth(load)
    drive = np.linspace(0.0, 1.6 * truth.static_drive_displacement, n)
    rng = np.random.default_rng(seed)
    force = truth.force_at_drive(drive) + noise * truth.static_friction * rng.standard_normal(n)
    return FrictionCurve(load, drive, force, f"synthetic seed {seed}")


@functools.cache
def _fit_seed(seed: int) -> LambdaFit:
    return fit_mode_mixity_friction([_test(0.56, seed)], MODEL)


def test_friction_interval_covers_the_true_lambda():
    fit = _fit_seed(0)
    low, high = fit.interval
    assert low <= TRUE_LAMBDA <= high
    assert high / low < 1.5  # and it says something: 1 % noise pins lambda to tens of percent
    assert not fit.at_bound and fit.mode == "friction"
    assert fit.residual_rms == pytest.approx(0.01, rel=0.35)  # the noise, in units of F_s


def test_trimmed_tail_does_not_move_lambda():
    """The points after the jump (the all-sliding plateau) are cut: moving them far away
    leaves lambda where it was."""
    test = _test(0.56, seed=0)
    tail = test.drive_displacement > _truth(0.56).static_drive_displacement * 1.05
    moved = FrictionCurve(
        0.56, test.drive_displacement, np.where(tail, 0.01, test.tangential_force)
    )
    a = _fit_seed(0).mode_mixity
    b = fit_mode_mixity_friction([moved], MODEL).mode_mixity
    assert b == pytest.approx(a, rel=1e-6)


@pytest.mark.slow
def test_friction_interval_covers_at_its_stated_level():
    """Over 40 noise seeds the one-sigma profile interval covers lambda = 0.03 in a fraction
    consistent with 68.3 % (binomial, 99 % two-sided: 19..35 of 40). Measured: 29 of 40."""
    seeds = range(100, 140)
    covered = 0
    for seed in seeds:
        low, high = fit_mode_mixity_friction([_test(0.56, seed)], MODEL).interval
        covered += low <= TRUE_LAMBDA <= high
    assert 19 <= covered <= 35, covered


def _lambda_fit(lam: float, low: float, high: float) -> LambdaFit:
    return LambdaFit(
        lam, 0.5 * (high - low), 0.01, 10, np.ones(1), np.ones(1), True, "", 1, interval=(low, high)
    )


def test_sources_compared_by_their_intervals():
    """sigma 0.003 each way: 0.03 against 0.038 is 1.9 combined sigma (agree), against 0.039
    2.1 (disagree); an open side of an interval never disagrees."""
    base = _lambda_fit(0.03, 0.027, 0.033)
    agree, _ = compare_sources(base, _lambda_fit(0.038, 0.035, 0.041))
    assert agree is False
    disagree, text = compare_sources(base, _lambda_fit(0.0385, 0.0355, 0.0415))
    assert disagree is True and "disagree" in text
    assert not compare_sources(_lambda_fit(0.03, 0.027, math.nan), _lambda_fit(0.5, 0.4, 0.6))[0]


@pytest.mark.slow
def test_joint_fit_sits_between_and_narrows():
    """A_r(F_x) made at lambda 0.03 and a friction test: the joint interval covers 0.03 and is
    no wider than the narrower single-source one, up to the profile's bisection."""
    area_model = shear_area_model(MATERIAL, ROUGHNESS, 700e-6, 201)
    fine_fx, fine_ar = area_model(TRUE_LAMBDA, 0.56, steps=801)  # not the fit's own nodes
    fx = np.linspace(0.0, 0.98 * fine_fx.max(), 40)
    ar = interpolate_area(fine_fx, fine_ar, fx)
    rng = np.random.default_rng(3)
    area = ShearAreaCurve(0.56, fx, ar * (1 + 0.01 * rng.standard_normal(40)))
    fits = fit_sources(
        "joint",
        area_curves=[area],
        friction_curves=[_test(0.56, seed=2)],
        area_model=area_model,
        drive_model=MODEL,
    )
    assert fits.disagree is False
    low, high = fits.joint.interval
    assert low <= TRUE_LAMBDA <= high
    widths = [f.interval[1] - f.interval[0] for f in (fits.area, fits.friction)]
    assert high - low <= 1.05 * min(widths)
    with pytest.raises(InputError, match="fit.source"):
        fit_sources(
            "friction",
            area_curves=[area],
            friction_curves=[],
            area_model=area_model,
            drive_model=MODEL,
        )


def test_configured_lambda_kept_with_source_area_and_the_friction_fit_recorded():
    """Friction tests without A_r(F_x) curves and fit.source = "area": lambda stays the
    configured one (not fitted), the friction-only lambda is recorded beside it."""
    from asperity.pipelines.stages.friction import calibrate_mode_mixity

    configured = dataclasses.replace(MATERIAL, mode_mixity=0.1)
    choice = calibrate_mode_mixity(
        configured,
        ROUGHNESS,
        700e-6,
        [],
        friction_curves=[_test(0.56, seed=0)],
        source="area",
        drive_stiffness=WIRE,
    )
    assert not choice.fitted and choice.mode_mixity == 0.1
    low, high = choice.friction_interval
    assert low <= TRUE_LAMBDA <= high and choice.fit_source == "area"
    assert choice.lambda_sources_disagree is None


def test_disagreeing_sources_are_a_verdict_warning():
    from asperity.pipelines.stages.friction import ModeMixityChoice
    from asperity.pipelines.stages.verdict import check_lambda_sources

    choice = ModeMixityChoice(mode_mixity=0.03, fitted=True)
    assert check_lambda_sources(choice) == []
    disagree, text = compare_sources(_lambda_fit(0.03, 0.028, 0.032), _lambda_fit(0.1, 0.09, 0.11))
    choice.lambda_sources_disagree, choice.lambda_sources_comparison = disagree, text
    choice.fit_source = "joint"
    (reason,) = check_lambda_sources(choice)
    assert (reason.code, reason.severity) == ("lambda_sources_disagree", "warning")
    assert "drive_stiffness" in reason.text


def test_fit_source_needs_its_curves(tmp_path):
    from asperity.pipelines.config import ConfigError, config_from_dict

    base = {"surface": {"synthetic": {"n": 64}}}
    with pytest.raises(ConfigError, match="fit.source.*measured.friction_curves"):
        config_from_dict({**base, "fit": {"source": "friction"}})
    with pytest.raises(ConfigError, match="fit.source"):
        config_from_dict({**base, "fit": {"source": "both"}})
