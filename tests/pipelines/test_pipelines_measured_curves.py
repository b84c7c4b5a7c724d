"""The lambda fit on data shaped like real measurements: a level offset at F_x = 0,
stick-slip tails after the static peak, repeated points, areas in the wrong unit."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from asperity import statmodel
from asperity.errors import InputError
from asperity.pipelines.measured import ShearAreaCurve, read_shear_area
from asperity.statmodel.lambda_fit import (
    area_up_to_peak,
    first_peak_end,
    fit_mode_mixity,
    interpolate_area,
    merge_repeated,
)
from asperity.statmodel.shear_path import model_shear_area

A_N = 700e-6
TRUE_LAMBDA = 0.03  # the paper's Fig 13 value
LOADS = (1.06, 3.12)


@pytest.fixture(scope="module")
def model():
    """The statistical model with the paper's Fig 13 roughness and material (SI), each
    (lambda, F_z) computed once for the module (the fits of its tests ask for many of the same
    points; the model is a pure function, and every caller gets its own copy of the arrays)."""
    shear_area = functools.partial(
        model_shear_area,
        material=statmodel.Material(2.133e6, 0.040, 0.03, 0.13e6, 0.2e-9),
        roughness=statmodel.Roughness(2.25e6, 1.180e-3, 0.0419e-3),
        nominal_area=A_N,
        max_tangential_displacement=None,
        steps=121,
        knobs={},
    )
    computed = functools.cache(shear_area)

    def once_per_point(mode_mixity: float, normal_load: float) -> tuple[np.ndarray, np.ndarray]:
        fx, ar = computed(float(mode_mixity), float(normal_load))
        return fx.copy(), ar.copy()

    return once_per_point


def _measured(model, *, offset=0.2, tail=True, repeat=0, noise=0.005, seed=0):
    """Curves the model made at TRUE_LAMBDA, 20 % above it at F_x = 0 (like Fig 13 at low
    loads), with 1/2 % noise, a stick-slip tail after the peak (F_x saws down and up while
    A_r keeps falling, Fig 6b) and the F_x = 0 point repeated ``repeat`` times."""
    rng = np.random.default_rng(seed)
    curves = []
    for load in LOADS:
        fx, ar = area_up_to_peak(*model(TRUE_LAMBDA, load))
        picks = np.linspace(0, fx[-1], 30)
        area = interpolate_area(fx, ar, picks) * (1 + offset)
        area *= 1 + rng.normal(0, noise, picks.size)
        if tail:
            saw = fx[-1] * (1 - 0.15 * (np.arange(40) % 5) / 4)
            fall = area[-1] * (1 - 0.3 * np.linspace(0.02, 1, 40))
            picks, area = np.concatenate([picks, saw]), np.concatenate([area, fall])
        picks = np.concatenate([np.zeros(repeat), picks])
        area = np.concatenate([np.full(repeat, area[0]), area])
        curves.append(ShearAreaCurve(load, picks, area))
    return curves


def test_first_peak_and_merge():
    fx = np.array([0.0, 1.0, 2.0, 3.0, 2.5, 3.2, 2.0])
    assert first_peak_end(fx) == 4  # up to F_x = 3.0, before the first drop
    assert first_peak_end(np.array([0.0, 1.0, 2.0])) == 3
    f, a = merge_repeated(np.array([0.0, 0.0, 0.0, 1.0]), np.array([3.0, 5.0, 4.0, 2.0]))
    np.testing.assert_array_equal(f, [0.0, 1.0])
    np.testing.assert_array_equal(a, [4.0, 2.0])


def test_shape_fit_recovers_lambda_from_offset_curves_with_tails_and_repeats(model):
    curves = _measured(model, repeat=100)
    fit = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7)
    assert fit.mode == "shape" and not fit.at_bound
    assert abs(fit.mode_mixity - TRUE_LAMBDA) < 3 * fit.mode_mixity_std
    assert fit.mode_mixity_std < 0.5 * TRUE_LAMBDA  # the data do constrain lambda
    assert fit.interval[0] < TRUE_LAMBDA < fit.interval[1] or (
        abs(fit.mode_mixity - TRUE_LAMBDA) < 3 * fit.mode_mixity_std
    )
    np.testing.assert_allclose(fit.scale, 1.2, rtol=0.03)  # the offset, found per curve
    assert fit.n_points == 2 * 30 and fit.n_points_read == 2 * (30 + 40 + 100)


def test_absolute_fit_of_offset_data_is_flagged_not_trusted(model):
    """In mode absolute, the 20 % offset is read as a tougher interface: lambda is pushed to
    its lower bound and the fit says so (the verdict then calls it invalid)."""
    fit = fit_mode_mixity(
        _measured(model, tail=False), model, bounds=(1e-3, 1.0), grid_points=7, mode="absolute"
    )
    assert fit.at_bound and fit.mode_mixity == pytest.approx(1e-3)


def test_repeated_points_do_not_shrink_the_uncertainty(model):
    once = fit_mode_mixity(_measured(model, tail=False), model, bounds=(1e-3, 1.0), grid_points=7)
    many = fit_mode_mixity(
        _measured(model, tail=False, repeat=100), model, bounds=(1e-3, 1.0), grid_points=7
    )
    assert many.mode_mixity_std == pytest.approx(once.mode_mixity_std, rel=0.05)


def test_untrimmed_tail_biases_lambda(model):
    """Without trimming, the stick-slip tail drags lambda away from the truth by more than
    the trimmed fit's uncertainty: the default trim matters."""
    curves = _measured(model)
    trimmed = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7)
    raw = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7, trim=False)
    assert abs(raw.mode_mixity - TRUE_LAMBDA) > 3 * trimmed.mode_mixity_std


def test_mm2_values_under_an_si_header_are_refused(tmp_path, model):
    (curve,) = _measured(model, tail=False, noise=0.0)[:1]
    path = tmp_path / "shear.csv"
    pairs = zip(curve.tangential_force.tolist(), (curve.real_area * 1e6).tolist(), strict=True)
    rows = "".join(f"{f!r},{a!r}\n" for f, a in pairs)
    path.write_text("# areas in mm^2, header says m^2\ntangential_force,real_area\n" + rows)
    with pytest.raises(InputError, match=r"shear\.csv: line 3, column 'real_area'.*mm\^2"):
        read_shear_area(path, 1.06, nominal_area=A_N)
    path.write_text("tangential_force (N);real_area [mm^2]\n" + rows.replace(",", ";"))
    (back,) = read_shear_area(path, 1.06, nominal_area=A_N)
    np.testing.assert_allclose(back.real_area, curve.real_area, rtol=1e-12)


def test_fit_points_stored_and_residual_plot_per_load(tmp_path, model):
    """The fitted (trimmed, merged) points and the model there survive the stage result, and
    the report draws one residual panel per load."""
    from types import SimpleNamespace

    from asperity.pipelines.report import draw_lambda_residuals
    from asperity.pipelines.report.figure_output import FigureOptions, publish
    from asperity.pipelines.stages.friction import ModeMixityChoice

    curves = _measured(model, repeat=3)
    fit = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7)
    choice = ModeMixityChoice.from_fit(fit, curves)
    assert choice.fit.at_bound is False and choice.fit.interval == fit.interval
    assert sorted(np.unique(choice.fitted_normal_load)) == list(LOADS)
    residual = choice.fitted_real_area - choice.fitted_model_area
    assert np.sqrt(np.mean((residual / choice.fitted_real_area.max()) ** 2)) < 0.02
    fig, table = draw_lambda_residuals(SimpleNamespace(mode_mixity=choice))
    assert len([ax for ax in fig.axes if ax.has_data()]) == len(LOADS)
    path = publish(fig, table, tmp_path / "res.png", FigureOptions())
    assert path.stat().st_size > 10_000


def test_lambda_plot_with_an_unbounded_uncertainty(tmp_path, model):
    """An absolute fit of offset data ends at a bound with an infinite sigma: the report's
    lambda plot still draws (no band), it does not crash the report."""
    from types import SimpleNamespace

    from asperity.pipelines.report import draw_lambda_fit
    from asperity.pipelines.report.figure_output import FigureOptions, publish
    from asperity.pipelines.stages.friction import ModeMixityChoice

    curves = _measured(model, tail=False)  # the fit of test_absolute_fit_of_offset_data_...
    fit = fit_mode_mixity(curves, model, bounds=(1e-3, 1.0), grid_points=7, mode="absolute")
    assert fit.at_bound and not np.isfinite(fit.mode_mixity_std)
    choice = ModeMixityChoice.from_fit(fit, curves)
    fig, table = draw_lambda_fit(SimpleNamespace(mode_mixity=choice))
    assert publish(fig, table, tmp_path / "l.png", FigureOptions()).exists()
