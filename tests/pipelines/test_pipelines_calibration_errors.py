"""A calibration error is detected, not absorbed (issue 37, item 3): curves made by a model at
lambda = 0.03 with 2 % noise, clean, with an additive offset (+0.2 A_r(F_x = 0), a threshold
error) or scaled x1.2 (an area calibration error). The clean interval covers 0.03 at its
stated level; the offset gives an interval that covers 0.03 and a warning; x1.2 a warning."""

from __future__ import annotations

import functools
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.stages.calibration_checks import (
    SCALE_TOLERANCE,
    offset_reasons,
    scale_reasons,
)
from asperity.pipelines.stages.fitting import (
    CALIBRATION_SCALE,
    area_up_to_peak,
    fit_mode_mixity,
    interpolate_area,
)
from asperity.pipelines.stages.friction import ModeMixityChoice
from asperity.pipelines.stages.verdict import check_calibration

LOADS = (1.06, 2.08, 3.12)
TRUE_LAMBDA = 0.03


def _toy_model(mode_mixity: float, normal_load: float) -> tuple[np.ndarray, np.ndarray]:
    """A stand-in with the real model's behaviour (probed on the default material): the area
    falls by ~7 % to the static peak at any lambda, and lambda sets the F_x of that peak
    (F_peak ~ lambda^-1/2). (F_x N, A_r m^2) along the stick branch."""
    s = np.linspace(0.0, 1.0, 301)
    peak = 0.55 * normal_load * np.sqrt(TRUE_LAMBDA / mode_mixity)
    area = 2.2e-6 * normal_load**0.9 * (1.0 - 0.05 * s**2 - 0.02 * s**8)
    return peak * (1.5 * s - 0.5 * s**2), area


def _curves(model, kind: str, seed: int, noise: float = 0.02) -> list[ShearAreaCurve]:
    rng = np.random.default_rng(seed)
    curves = []
    for load in LOADS:
        fx, ar = area_up_to_peak(*model(TRUE_LAMBDA, load))
        picks = np.linspace(0.0, 0.9 * fx[-1], 20)
        area = interpolate_area(fx, ar, picks)
        area = {"clean": area, "offset": area + 0.2 * area[0], "x1.2": 1.2 * area}[kind]
        curves.append(ShearAreaCurve(load, picks, area * (1 + rng.normal(0, noise, picks.size))))
    return curves


def _choice(model, kind: str, seed: int = 0) -> ModeMixityChoice:
    curves = _curves(model, kind, seed)
    return ModeMixityChoice.from_fit(fit_mode_mixity(curves, model, bounds=(1e-3, 1.0)), curves)


def _covers(choice: ModeMixityChoice) -> bool:
    return choice.interval_low <= TRUE_LAMBDA <= choice.interval_high


FRICTION = SimpleNamespace(  # the model's A_r at F_x = 0 known to 3 %
    normal_load=np.array(LOADS),
    model_real_area=np.array([2.3e-6, 4.3e-6, 6.3e-6]),
    model_real_area_uncertainty=0.03 * np.array([2.3e-6, 4.3e-6, 6.3e-6]),
)


def test_clean_curves_cover_the_truth_with_no_calibration_reason():
    choice = _choice(_toy_model, "clean")
    assert _covers(choice)
    assert np.all(np.abs(choice.shape_scale - 1) < CALIBRATION_SCALE)
    assert np.isnan(choice.offset_mode_mixity)  # the offset reading was not needed
    assert check_calibration(choice, FRICTION) == []


def test_an_additive_offset_is_covered_and_warned_about():
    """+0.2 A_r(0) on every point flattens the relative drop: read as a scale, lambda is
    biased low; read as an offset it is recovered; the interval holds both readings."""
    choice = _choice(_toy_model, "offset")
    assert choice.mode_mixity < TRUE_LAMBDA  # the scale reading absorbs the flatter drop
    assert abs(choice.offset_mode_mixity - TRUE_LAMBDA) < abs(choice.mode_mixity - TRUE_LAMBDA)
    assert _covers(choice)
    assert choice.interval_low <= choice.shape_interval[0]
    assert choice.interval_high >= choice.offset_interval[1]
    np.testing.assert_allclose(choice.offset_fraction, 0.2, atol=0.03)
    codes = [r.code for r in check_calibration(choice, FRICTION)]
    assert "measured_area_scale" in codes
    (reason,) = [r for r in check_calibration(choice, FRICTION) if r.code == "measured_area_scale"]
    assert reason.severity == "warning" and "contact-detection threshold" in reason.text
    assert "as an offset" in reason.text and "pixel size" in reason.text


def test_a_scale_error_of_twenty_percent_is_a_warning():
    choice = _choice(_toy_model, "x1.2")
    np.testing.assert_allclose(choice.shape_scale, 1.2, atol=0.02)
    assert _covers(choice)
    (reason,) = check_calibration(choice, FRICTION)
    assert reason.code == "measured_area_scale" and "c = 1.2" in reason.text


def test_the_scale_tolerance_is_beyond_the_models_own_uncertainty():
    choice = SimpleNamespace(
        fitted=True,
        fit_mode="shape",
        shape_scale=np.array([1.12]),
        shape_scale_normal_load=np.array([2.08]),
        offset_mode_mixity=float("nan"),
    )
    sure = SimpleNamespace(**{**vars(FRICTION), "model_real_area_uncertainty": np.zeros(3)})
    assert scale_reasons(choice, sure)  # 12 % > 10 % + 0
    loose = SimpleNamespace(
        **{**vars(FRICTION), "model_real_area_uncertainty": FRICTION.model_real_area * 0.05}
    )
    assert 0.12 < SCALE_TOLERANCE + 0.05 and scale_reasons(choice, loose) == []


def test_an_offset_that_fits_better_is_named():
    base = {"shape_scale": np.ones(3), "n_points": 60, "offset_fraction": np.full(3, 0.2)}
    base.update(
        mode_mixity=0.03,
        shape_interval=np.array([0.02, 0.035]),
        offset_mode_mixity=0.031,
        offset_interval=np.array([0.026, 0.036]),
        interval_low=0.02,
        interval_high=0.036,
    )
    better = SimpleNamespace(**base, residual_rms=0.03, offset_residual_rms=0.02)
    ((code, severity, text),) = offset_reasons(better)
    assert code == "measured_area_offset" and severity == "warning" and "20 %" in text
    alike = SimpleNamespace(**base, residual_rms=0.0201, offset_residual_rms=0.02)
    assert offset_reasons(alike) == []


def test_the_clean_interval_covers_at_its_stated_level_over_forty_seeds():
    """A one-sigma profile interval holds the truth in ~68 % of seeds: of 40, the count is
    binomial (mean 27.2, sd 2.95); fewer than 21 happens in 2 % of cases (undercoverage)."""
    covered = sum(_covers(_choice(_toy_model, "clean", seed)) for seed in range(40))
    assert covered >= 21


@pytest.fixture(scope="module")
def real_model():
    """The job's own model curve (the default material, a 256^2 paper-like map at 25 um)."""
    from asperity import topo
    from asperity.pipelines.config import load_preset
    from asperity.pipelines.stages.friction import model_shear_area
    from asperity.statmodel.effective_resolution import roughness_at_resolution

    config = load_preset("default")
    surface = topo.synthetic.paper_like(n=256, pixel_size=10e-6, seed=1)
    return functools.partial(
        model_shear_area,
        material=config.material,
        roughness=roughness_at_resolution(surface, 25e-6),
        nominal_area=config.loading.nominal_area,
        max_tangential_displacement=None,
        steps=201,
        knobs={"nodes": 8, "panels": 4},
    )


@pytest.mark.slow
def test_real_model_clean_interval_covers_over_twenty_seeds(real_model):
    """20 seeds, the statistical model itself: at least 10 intervals of 20 hold 0.03 (a 68 %
    interval gives fewer in 3.5 % of cases). Measured: 16 / 20 (about 2 s a fit)."""
    covered = sum(_covers(_choice(real_model, "clean", seed)) for seed in range(20))
    assert covered >= 10


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["offset", "x1.2"])
def test_real_model_calibration_errors_are_warned_and_covered(real_model, kind):
    choice = _choice(real_model, kind)
    assert _covers(choice)
    assert "measured_area_scale" in [r.code for r in check_calibration(choice, FRICTION)]
