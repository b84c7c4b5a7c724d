"""Predictions per load with uncertainties propagated from the roughness and lambda intervals."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from asperity.errors import InputError
from asperity.statmodel.uncertainty import (
    PREDICTIONS,
    largest_excursion,
    propagate_to_predictions,
)
from tests._helpers import PAPER_MATERIAL as MATERIAL
from tests._helpers import PAPER_NOMINAL_AREA as NOMINAL_AREA
from tests._helpers import paper_roughness as _roughness

LOADS = [0.56, 1.58, 3.12]  # N
PATH = np.linspace(0.0, 80e-6, 241)  # m, past full sliding at every load here


def _propagate(half_width: float, lambda_half_width: float):
    return propagate_to_predictions(
        MATERIAL,
        _roughness(25e-6),
        [_roughness(25e-6 - half_width), _roughness(25e-6 + half_width)],
        (0.03 - lambda_half_width, 0.03 + lambda_half_width),
        NOMINAL_AREA,
        LOADS,
        tangential_displacement=PATH,
    )


def _truth(resolution: float, mode_mixity: float):
    """The model at a 'true' resolution (m) and lambda, the same four predictions."""
    material = dataclasses.replace(MATERIAL, mode_mixity=mode_mixity)
    return propagate_to_predictions(
        material,
        _roughness(resolution),
        [_roughness(resolution)] * 2,
        (mode_mixity, mode_mixity),
        NOMINAL_AREA,
        LOADS,
        tangential_displacement=PATH,
    ).value


def test_intervals_cover_a_known_truth():
    """Truths drawn from inside the intervals (resolution 22..28 um, lambda 0.025..0.035):
    every prediction of every load lies within value +- u. One input at a time it must (the
    outputs are monotone in each input); both together, measured 12 of 12 draws too."""
    result = _propagate(3e-6, 0.005)
    assert result.success, result.message
    rng = np.random.default_rng(3)
    draws = [(23e-6, 0.03), (27.5e-6, 0.03), (25e-6, 0.026), (25e-6, 0.034)]
    draws += [(rng.uniform(22e-6, 28e-6), rng.uniform(0.025, 0.035)) for _ in range(8)]
    for resolution, lam in draws:
        truth = _truth(resolution, lam)
        for name in PREDICTIONS:
            error = np.abs(truth[name] - result.value[name])
            assert np.all(error <= result.uncertainty[name] * (1 + 1e-9)), (name, resolution, lam)


def test_uncertainty_vanishes_as_the_intervals_shrink():
    wide, narrow = _propagate(3e-6, 0.005), _propagate(0.3e-6, 0.0005)
    for name in PREDICTIONS:
        ratio = narrow.uncertainty[name] / wide.uncertainty[name]
        assert np.all(ratio < 0.15), (name, ratio)  # first order: about 0.1
        np.testing.assert_allclose(narrow.value[name], wide.value[name])
    point = _propagate(0.0, 0.0)
    for name in PREDICTIONS:
        assert np.all(point.uncertainty[name] == 0.0)


def test_lambda_leaves_area_and_sliding_friction_alone():
    result = _propagate(3e-6, 0.005)
    for name in ("real_area", "sliding_friction"):
        assert np.all(result.parts[name]["mode_mixity"] == 0.0)
        assert np.all(result.parts[name]["roughness"] > 0.0)
    assert np.all(result.parts["static_friction"]["mode_mixity"] > 0.0)


def test_unknown_or_open_intervals_are_stated():
    open_lambda = propagate_to_predictions(
        MATERIAL, _roughness(25e-6), [_roughness(24e-6), _roughness(26e-6)],
        (0.02, math.inf), NOMINAL_AREA, LOADS, tangential_displacement=PATH,
        interval_open=True,
    )  # fmt: skip
    assert open_lambda.status == 1 and open_lambda.lower_bound
    assert np.all(np.isinf(open_lambda.uncertainty["static_friction"]))
    assert np.all(np.isfinite(open_lambda.uncertainty["real_area"]))
    assert "lower bound" in open_lambda.message and "static_friction" in open_lambda.message
    np.testing.assert_array_equal(largest_excursion(np.array([math.inf]), [1.0]), [math.nan])
    with pytest.raises(InputError, match="expected curve= or tangential_displacement="):
        propagate_to_predictions(
            MATERIAL, _roughness(25e-6), [_roughness(25e-6)] * 2, (0.03, 0.03),
            NOMINAL_AREA, LOADS,
        )  # fmt: skip
