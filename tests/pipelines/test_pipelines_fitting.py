"""The lambda fit: recovery of a known lambda from noisy curves, within its uncertainty."""

from __future__ import annotations

import numpy as np
import pytest

from asperity.errors import InputError
from asperity.pipelines.measured import ShearAreaCurve
from asperity.statmodel.lambda_fit import area_up_to_peak, fit_mode_mixity, interpolate_area
from tests._helpers import area_to_peak, sampled_area_curves, shear_area_model

A_N = 700e-6


def _toy_model(mode_mixity: float, normal_load: float) -> tuple[np.ndarray, np.ndarray]:
    """A smooth stand-in with the shape of Fig 5b: area falls faster for larger lambda,
    the tangential force peaks then drops to a sliding plateau."""
    s = np.linspace(0.0, 1.0, 301)
    a0 = 2e-6 * normal_load**0.9
    area = a0 * (1.0 - 0.6 * np.sqrt(mode_mixity) * s**2)
    force = 0.3 * normal_load * (1.5 * s - 0.75 * s**2) * (1 + (s > 0.8) * (0.8 - s))
    return force, area


def _noisy_curves(model, lam, loads, noise, rng):
    return sampled_area_curves(area_to_peak(model, lam, loads), loads, 25, 0.9, noise, rng)


def test_area_up_to_peak_keeps_stick_branch():
    fx = np.array([0.0, 1.0, 2.0, 2.0, 3.0, 2.5, 2.6])
    ar = np.array([5.0, 4.0, 3.0, 3.0, 2.0, 1.9, 1.8])
    f, a = area_up_to_peak(fx, ar)
    np.testing.assert_array_equal(f, [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(a, [5.0, 4.0, 3.0, 2.0])
    # beyond the peak the area is held at its peak value
    assert interpolate_area(fx, ar, np.array([10.0]))[0] == 2.0


@pytest.mark.parametrize("true_lambda", [0.01, 0.08, 0.4])
def test_toy_model_recovery_within_uncertainty(true_lambda):
    rng = np.random.default_rng(1)
    curves = _noisy_curves(_toy_model, true_lambda, [0.5, 1.5, 3.0], 0.005, rng)
    fit = fit_mode_mixity(curves, _toy_model)
    assert fit.success
    assert abs(fit.mode_mixity - true_lambda) < 3 * fit.mode_mixity_std
    assert fit.mode_mixity_std < 0.2 * true_lambda  # the data do constrain lambda
    assert fit.residual_rms == pytest.approx(0.005, rel=0.3)  # residual ~ the noise level


def test_more_noise_gives_larger_uncertainty():
    stds = []
    for noise in (0.001, 0.01):
        rng = np.random.default_rng(3)
        curves = _noisy_curves(_toy_model, 0.05, [1.0, 2.0], noise, rng)
        stds.append(fit_mode_mixity(curves, _toy_model).mode_mixity_std)
    assert stds[1] > 3 * stds[0]


def test_bad_inputs_refused():
    with pytest.raises(InputError, match="no measured curves"):
        fit_mode_mixity([], _toy_model)
    curves = [ShearAreaCurve(1.0, np.array([0.0, 0.1]), np.array([1e-6, 1e-6]))]
    with pytest.raises(InputError, match="bounds"):
        fit_mode_mixity(curves, _toy_model, bounds=(0.5, 0.1))


def test_recovers_lambda_from_statistical_model_curves():
    """Curves made by the statistical model itself (Fig 13 roughness) with 1 % noise: the fit
    finds the lambda that made them within its own uncertainty."""
    from asperity import statmodel

    material = statmodel.Material(2.133e6, 0.040, 0.03, 0.13e6, 0.2e-9)
    roughness = statmodel.Roughness(2.25e6, 1.180e-3, 0.0419e-3)
    model = shear_area_model(material, roughness, A_N, 121)
    true_lambda = 0.05
    rng = np.random.default_rng(7)
    loads = (1.06, 2.08, 3.12)
    peaks = area_to_peak(model, true_lambda, loads)
    curves = sampled_area_curves(peaks, loads, 30, 0.95, noise=0.01, rng=rng)
    fit = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7)
    assert fit.success
    assert abs(fit.mode_mixity - true_lambda) < 3 * fit.mode_mixity_std
    assert fit.mode_mixity_std < 0.3 * true_lambda


@pytest.mark.slow
def test_fit_in_worker_processes_matches_serial():
    from asperity.pipelines.engine.parallel import make_executor

    rng = np.random.default_rng(5)
    curves = _noisy_curves(_toy_model, 0.05, [1.0, 2.0], 0.005, rng)
    serial = fit_mode_mixity(curves, _toy_model)
    with make_executor(2) as ex:
        pooled = fit_mode_mixity(curves, _toy_model, map_fn=ex.map)
    assert pooled.mode_mixity == serial.mode_mixity
    assert pooled.mode_mixity_std == serial.mode_mixity_std
