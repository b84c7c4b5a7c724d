"""The shape fit's scale factor c per measured curve: stored with its load, judged by the
verdict (``shape_scale``: invalid outside [0.50, 2.01], a warning outside [0.82, 1.22])."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.stages.friction import ModeMixityChoice
from asperity.pipelines.stages.verdict import MAX_MISFIT, WARN_MISFIT, check_shape_scale
from asperity.statmodel.lambda_fit import area_up_to_peak, fit_mode_mixity, interpolate_area

LOADS = (0.56, 1.58, 3.12)
TRUE_LAMBDA = 0.3


def _toy_model(mode_mixity: float, normal_load: float) -> tuple[np.ndarray, np.ndarray]:
    """A smooth stand-in with the shape of Fig 5b (area falls faster for larger lambda, F_x
    peaks then drops), A_r growing with the load: (F_x N, A_r m^2)."""
    s = np.linspace(0.0, 1.0, 301)
    area = 2e-6 * normal_load**0.9 * (1.0 - 0.6 * np.sqrt(mode_mixity) * s**2)
    force = 0.3 * normal_load * (1.5 * s - 0.75 * s**2) * (1 + (s > 0.8) * (0.8 - s))
    return force, area


def _curves(levels, seed=0):
    """Curves of the toy model at TRUE_LAMBDA, the measured level times ``levels[i]``."""
    rng = np.random.default_rng(seed)
    curves = []
    for load, level in zip(LOADS, levels, strict=True):
        fx, ar = area_up_to_peak(*_toy_model(TRUE_LAMBDA, load))
        picks = np.linspace(0, 0.9 * fx[-1], 25)
        area = interpolate_area(fx, ar, picks) * level * (1 + rng.normal(0, 0.003, 25))
        curves.append(ShearAreaCurve(load, picks, area))
    return curves


def _choice(levels):
    curves = _curves(levels)
    fit = fit_mode_mixity(curves, _toy_model, bounds=(1e-3, 1.0), grid_points=7)
    return fit, ModeMixityChoice.from_fit(fit, curves)


def test_scale_factors_recover_the_level_and_are_stored_with_units():
    levels = (1.2, 1.0, 0.9)  # Fig 13: 20 % above the model at the lowest load
    fit, choice = _choice(levels)
    np.testing.assert_allclose(fit.scale, levels, rtol=0.01)
    np.testing.assert_allclose(choice.shape_scale, levels, rtol=0.01)
    np.testing.assert_array_equal(choice.shape_scale_normal_load, LOADS)
    specs = {f.name: f.metadata for f in ModeMixityChoice.__dataclass_fields__.values()}
    assert "measured_curve" in str(specs["shape_scale"]) and "'N'" in str(
        specs["shape_scale_normal_load"]
    )
    assert abs(choice.mode_mixity - TRUE_LAMBDA) < 0.1 * TRUE_LAMBDA  # the level left lambda be
    assert check_shape_scale(choice) == []  # within [0.82, 1.22]
    np.testing.assert_allclose(choice.fit.scale, levels, rtol=0.01)  # round trip


def test_a_curve_three_times_the_model_makes_the_verdict_invalid():
    """A curve whose areas are 3x the model at its load (another specimen, a unit slip): the
    shape fit absorbs it into c; lambda may look fine, but the verdict says why it is not."""
    _, choice = _choice((1.0, 3.0, 1.0))
    (reason,) = check_shape_scale(choice)
    assert reason.code == "shape_scale" and reason.severity == "invalid"
    assert "c = 3" in reason.text and "F_z = 1.58 N" in reason.text
    assert f"[{math.exp(-MAX_MISFIT):.2f}, {math.exp(MAX_MISFIT):.2f}]" in reason.text


def test_a_level_30_percent_off_is_a_warning():
    _, choice = _choice((1.0, 1.0, 1.3))
    (reason,) = check_shape_scale(choice)
    assert reason.severity == "warning" and math.log(1.3) > WARN_MISFIT
    assert "at 3.12 N" in reason.text


@pytest.mark.parametrize("fitted", [False, True])
def test_no_reason_without_a_shape_fit(fitted):
    if not fitted:
        assert check_shape_scale(ModeMixityChoice(mode_mixity=0.03, fitted=False)) == []
        return
    curves = _curves((3.0, 3.0, 3.0))
    fit = fit_mode_mixity(curves, _toy_model, bounds=(1e-3, 1.0), grid_points=5, mode="absolute")
    choice = ModeMixityChoice.from_fit(fit, curves)
    np.testing.assert_array_equal(choice.shape_scale, [1.0, 1.0, 1.0])
    assert check_shape_scale(choice) == []  # c = 1 by definition; the level is lambda's


@pytest.mark.slow
def test_job_stores_reports_and_judges_the_scale_factors(small_run, small, tmp_path, capsys):
    """The small job calibrated on curves the statistical model made at lambda = 0.03 (its
    own roughness at the effective resolution), the 2 N curve's areas 3x too large: lambda is
    still recovered, c is stored in results.h5 with its units and shown in report.md, and the
    run ends invalid (exit 3) with ``shape_scale``."""
    import functools

    import h5py

    from asperity.pipelines.cli import main
    from asperity.pipelines.config import DEFAULT_MATERIAL, dump_toml
    from asperity.pipelines.measured import write_shear_area
    from asperity.statmodel.shear_path import model_shear_area

    _, out, result = small_run
    model = functools.partial(
        model_shear_area,
        material=DEFAULT_MATERIAL,
        roughness=result.statistical_model.roughness,
        nominal_area=700e-6,
        max_tangential_displacement=None,
        steps=201,
        knobs={},
    )
    rng = np.random.default_rng(1)
    curves = []
    for load, level in zip((1.0, 2.0, 3.0), (1.1, 3.0, 1.1), strict=True):
        fx, ar = area_up_to_peak(*model(0.03, load))
        picks = np.linspace(0, fx[-1], 30)
        area = interpolate_area(fx, ar, picks) * level * (1 + rng.normal(0, 0.005, 30))
        curves.append(ShearAreaCurve(load, picks, area))
    write_shear_area(tmp_path / "curves.csv", curves)
    data = small.data()
    data["measured"] = {"shear_area": str(tmp_path / "curves.csv")}
    (tmp_path / "job.toml").write_text(dump_toml(data))
    run = tmp_path / "run"
    run.mkdir()
    shutil.copy(out / "results.h5", run / "results.h5")  # stages 1-4 reused: --replace
    status = main(["run", str(tmp_path / "job.toml"), "--out", str(run), "--replace"])
    printed = capsys.readouterr().out
    assert status == 3
    assert "INVALID (shape_scale): the shape fit scales the model's A_r(F_x) by c = 3" in printed
    with h5py.File(run / "results.h5") as f:
        group = f["mode_mixity"]
        lam, std = float(group.attrs["mode_mixity"]), float(group.attrs["mode_mixity_std"])
        np.testing.assert_allclose(group["shape_scale"][()], [1.1, 3.0, 1.1], rtol=0.02)
        assert group["shape_scale"].attrs["units"] == "1"
        assert group["shape_scale_normal_load"].attrs["units"] == "N"
    assert abs(lam - 0.03) < 3 * std
    report = (run / "report.md").read_text()
    assert "shape-fit scale factor c (measured / model)" in report and "3 at 2 N" in report
    # the measured static peak beside the predicted one (report.static_peak)
    assert "| measured F_s (N) | measured A_r/A_n at peak | measured A_r drop |" in report
