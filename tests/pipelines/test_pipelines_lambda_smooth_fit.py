"""The lambda fit between its grid points: an optimum off the coarse grid is found (not the
grid point it started from), the model curve the job fits is smooth in lambda, and the result
is never worse than the best grid point."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from asperity import statmodel
from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.stages.fitting import (
    _Objective,
    area_up_to_peak,
    fit_mode_mixity,
    interpolate_area,
    prepare_curve,
)
from asperity.statmodel.shear_path import model_shear_area

MATERIAL = statmodel.Material(2.133e6, 0.040, 0.03, 0.13e6, 0.2e-9)
ROUGH = statmodel.Roughness(67.87e6, 0.05584e-3, 0.04872e-3)  # the default job's statistics
A_N = 4.9e-3
TRUE = 0.094  # between the default grid's 0.0316 and 0.1 (9 points over 1e-4 .. 1)


def _model(steps: int = 121):
    return functools.partial(
        model_shear_area,
        material=MATERIAL,
        roughness=ROUGH,
        nominal_area=A_N,
        max_tangential_displacement=None,
        steps=steps,
        knobs={"nodes": 8, "panels": 4},
    )


def _curves(lam: float, loads, noise: float, seed: int, reach: float = 0.95):
    """Measured A_r(F_x) made by the model at ``lam`` (a finer curve), relative noise."""
    rng = np.random.default_rng(seed)
    fine = _model(401)
    out = []
    for f in loads:
        fx, ar = area_up_to_peak(*fine(lam, f))
        picks = np.linspace(0.0, reach * fx[-1], 25)
        truth = interpolate_area(fx, ar, picks)
        out.append(ShearAreaCurve(f, picks, truth * (1 + rng.normal(0, noise, picks.size))))
    return out


def test_optimum_between_grid_points_is_found_not_the_start():
    """Curves made at lambda = 0.094 (0.3 % noise): the fit starts from the grid point 0.1 and
    must move to 0.094, within its interval, and fit better than 0.1 does."""
    curves = _curves(TRUE, (1.06, 3.12), 0.003, seed=2)
    model = _model()
    fit = fit_mode_mixity(curves, model)
    assert fit.success
    assert 0.1 in np.round(fit.grid_mode_mixity, 12)  # the grid point it starts from
    assert fit.interval[0] <= TRUE <= fit.interval[1]
    assert fit.mode_mixity == pytest.approx(TRUE, rel=0.02)
    assert abs(fit.mode_mixity - 0.1) > 0.003
    objective = _Objective([prepare_curve(c) for c in curves], model, map, "shape")
    best = objective.ssr(math.log10(fit.mode_mixity))
    assert best <= objective.ssr(-1.0)  # never worse than the grid point


def test_model_curve_is_smooth_in_lambda():
    """The job's fit model (nodes at fixed fractions of the static peak): its last point is the
    static peak, and A_r interpolated at F_x = 0.9 N near the peak (2.08 N; peak ~0.96 N)
    follows a parabola in lambda to 1e-3 of its variation over lambda 0.098 .. 0.102 (on a
    path of nodes fixed in delta_T it departs by 45 %: the nodes near the peak jump)."""
    model = _model()
    lams = np.linspace(0.098, 0.102, 9)
    values = []
    for lam in lams:
        fx, ar = model(lam, 2.08)
        assert int(np.argmax(fx)) == fx.size - 1
        values.append(interpolate_area(fx, ar, np.array([0.9]))[0])
    values = np.array(values)
    parabola = np.polyval(np.polyfit(lams - 0.1, values, 2), lams - 0.1)
    assert np.max(np.abs(values - parabola)) < 1e-3 * np.ptp(values)


def _jagged_toy(mode_mixity: float, normal_load: float) -> tuple[np.ndarray, np.ndarray]:
    """A toy A_r(F_x) whose fit objective is jagged: a sawtooth in lambda of 1e-3 of the area
    (period 0.002 in lambda) on a smooth dependence."""
    s = np.linspace(0.0, 1.0, 301)
    a0 = 2e-6 * normal_load
    saw = 1e-3 * ((mode_mixity / 0.002) % 1.0)
    area = a0 * (1.0 - 0.6 * np.sqrt(mode_mixity) * s**2) * (1 + saw)
    force = 0.3 * normal_load * (1.5 * s - 0.75 * s**2)
    return force, area


def test_jagged_objective_does_not_stop_on_the_start():
    """On a sawtooth objective a gradient step from the grid point 0.1 stops there; the
    bounded search reaches the true 0.094 within the sawtooth's period."""
    rng = np.random.default_rng(0)
    curves = []
    for f in (1.0, 2.0):
        fx, ar = area_up_to_peak(*_jagged_toy(TRUE, f))
        picks = np.linspace(0, 0.9 * fx[-1], 25)
        area = interpolate_area(fx, ar, picks) * (1 + rng.normal(0, 1e-4, picks.size))
        curves.append(ShearAreaCurve(f, picks, area))
    fit = fit_mode_mixity(curves, _jagged_toy, mode="absolute")
    assert abs(fit.mode_mixity - TRUE) < 0.003
    assert fit.interval[0] <= TRUE <= fit.interval[1]
