"""The calibration checks' numbers (statmodel.calibration_checks): which curves' levels are off
beyond the model's own uncertainty, and when the offset reading fits better."""

from __future__ import annotations

import math

import numpy as np
import pytest

from asperity.statmodel.calibration_checks import (
    SCALE_TOLERANCE,
    SHAPE_SCALE_BAND,
    model_relative_uncertainty,
    offset_delta_chi2,
    scale_outliers,
)


def test_a_level_off_by_more_than_the_tolerance_plus_the_model_uncertainty_is_flagged():
    scales, loads = [1.0, 1.15, 0.88, 1.3], [1.0, 2.0, 3.0, 4.0]
    flagged = scale_outliers(scales, loads, lambda f: 0.0)
    # 1.3 lies outside the band the fit's own reason names; 1.0 is on the model
    assert [(c, f) for c, f, _ in flagged] == [(1.15, 2.0), (0.88, 3.0)]
    assert SHAPE_SCALE_BAND[1] < 1.3
    # the model's own 10 % uncertainty at 2 N absorbs the 15 % there, not the 12 % at 3 N
    flagged = scale_outliers(scales, loads, lambda f: 0.1 if f == 2.0 else 0.0)
    assert [f for _, f, _ in flagged] == [3.0]
    assert 1.0 + SCALE_TOLERANCE < 1.15


def test_the_model_uncertainty_is_read_at_the_nearest_load_and_zero_when_absent():
    loads, area, u = [1.0, 2.0, 3.0], [2e-6, 4e-6, 6e-6], [2e-7, 2e-7, 0.0]
    assert model_relative_uncertainty(loads, area, u, 2.2) == pytest.approx(0.05)
    assert model_relative_uncertainty(loads, area, u, 0.1) == pytest.approx(0.1)
    assert model_relative_uncertainty(loads, None, u, 2.0) == 0.0
    assert model_relative_uncertainty(loads, [0.0, 0.0, 0.0], u, 2.0) == 0.0  # not finite


@pytest.mark.parametrize("rms, offset_rms", [(0.02, 0.01), (0.01, 0.02), (0.015, 0.015)])
def test_delta_chi2_is_n_times_the_variance_drop_over_the_better_fit(rms, offset_rms):
    n, curves = 40, 3
    delta = offset_delta_chi2(rms, offset_rms, n, curves)
    # chi^2 = n rms^2 / s^2 with s^2 the better reading's variance per degree of freedom
    s2 = min(rms, offset_rms) ** 2 * n / (n - 1 - curves)
    assert delta == pytest.approx(n * rms**2 / s2 - n * offset_rms**2 / s2)
    assert math.copysign(1.0, delta) == math.copysign(1.0, rms - offset_rms) or delta == 0.0
    assert offset_delta_chi2(0.0, 0.0, n, curves) == 0.0
    assert np.isfinite(offset_delta_chi2(rms, offset_rms, 3, curves))  # too few points: dof 1
