"""The lambda and friction stages: calibrate lambda on measured A_r(F_x), then predict friction at
each load.

The lambda stage (:func:`calibrate_mode_mixity`) fits the mode mixity lambda to the user's measured
A_r(F_x) curves with :func:`statmodel.lambda_fit.fit_mode_mixity` (Section 5, Fig 13); without
measurements the configured lambda is used.

The friction stage (:func:`friction_prediction`) runs :func:`statmodel.shear_curve` at every normal
load: F_x(delta_T), A_r(F_x) with their stick and slip parts (E:NewFormulation_Fy..Ar), static and
sliding friction (Figs 4, 13), and the constant-shear-strength line F_x = tau0 A_r of Fig 13.

The shear path and the quadrature are chosen by :mod:`asperity.statmodel.shear_path`
(:func:`~asperity.statmodel.shear_path.shear_curve_auto`,
:func:`~asperity.statmodel.shear_path.choose_quadrature`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from asperity import statmodel
from asperity.fields import array, document_fields, scalar, stacked, text
from asperity.pipelines.engine.parallel import run_map
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.measured_friction import FrictionCurve
from asperity.pipelines.stages.statistical_model import STATISTICAL_MODEL
from asperity.statmodel.lambda_fit import LambdaFit, fit_mode_mixity, interpolate_area
from asperity.statmodel.lambda_fit_friction import SourceFits, fit_sources
from asperity.statmodel.results_io import ARRAY_UNITS, SCALAR_UNITS
from asperity.statmodel.shear_path import (
    QuadratureChoice,
    choose_quadrature,
    model_drive_curve,
    model_shear_area,
    shear_curve_auto,
)
from asperity.statmodel.uncertainty import propagate_to_predictions

#: Per-step arrays and per-load scalars of :class:`statmodel.ShearCurve` kept by the friction stage,
#: with their units: the tables the ``asperity friction`` output uses, less ``normal_load``, which
#: is the stage's dimension coordinate.
CURVE_FIELDS: dict[str, str] = dict(ARRAY_UNITS)
#: A shear curve as plain values (arrays and scalars in SI, "converged", "message").
CurveSummary: TypeAlias = dict[str, np.ndarray | float | bool | str]
#: The uncertainty fields of :class:`FrictionPrediction` by name (arrays in SI, flags, text).
UncertaintyFields: TypeAlias = dict[str, np.ndarray | float | bool | int | str]
CURVE_SCALARS: dict[str, str] = {k: v for k, v in SCALAR_UNITS.items() if k != "normal_load"}

#: Fewest delta_T steps of the model curves the lambda fit interpolates (their discretisation
#: must not bias the fit).
MIN_FIT_STEPS = 201


def curve_summary(curve: statmodel.ShearCurve) -> CurveSummary:
    """Arrays and scalars of a shear curve as a picklable dict (SI)."""
    out: CurveSummary = {
        name: np.asarray(getattr(curve, name), dtype=float) for name in CURVE_FIELDS
    }
    for name in CURVE_SCALARS:
        out[name] = float(getattr(curve, name))
    out["converged"] = bool(curve.converged)
    out["message"] = str(curve.message)
    return out


def _curve_job(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_load: float,
    max_dt: float | None,
    steps: int,
    knobs: Mapping[str, float],
) -> CurveSummary:
    return curve_summary(
        shear_curve_auto(
            material,
            roughness,
            nominal_area,
            normal_load,
            max_tangential_displacement=max_dt,
            steps=steps,
            knobs=knobs,
        )
    )


@document_fields
@dataclass
class ModeMixityChoice:
    """Stage-5 result: the lambda used downstream and, when fitted, the fit and its data.

    Attributes
    ----------
    mode_mixity : float
        lambda used by the friction stage.
    fitted : bool
        Fitted to measured A_r(F_x) (else the configured value).
    lambda_grid, grid_residual_rms : ndarray or None
        The fit's coarse scan: lambda and the rms relative residual.
    measured_normal_load, measured_tangential_force, measured_real_area : ndarray or None
        The measured points (N, N, m^2).
    mode_mixity_std, residual_rms : float or None
        One-sigma uncertainty of lambda; rms relative residual at the optimum.
    n_points, nfev : int or None
        Points fitted; model evaluations of the optimiser.
    success : bool or None
        The optimiser reported success.
    message : str or None
        The optimiser's message.
    model_real_area_at_measured : ndarray or None
        The model's A_r (m^2) at each measured (F_z, F_x) point with the fitted lambda
        (beside ``measured_real_area``).
    profile_interval : ndarray or None
        The fit's own one-sigma profile interval (low, high) at the effective resolution's
        statistics (``interval_low`` / ``interval_high`` unite it with
        ``mode_mixity_roughness_shift``).
    mode_mixity_roughness_shift : ndarray or None
        lambda fitted at the statistics of the effective resolution's interval ends (finer,
        coarser; NaN where unknown): the roughness's uncertainty carried into lambda's
        interval, so that it covers a lambda fitted to another resolution inside it.
    shape_scale, shape_scale_normal_load : ndarray or None
        The shape fit's least-squares factor c of each measured curve (A_measured ~ c
        A_model, dimensionless; 1 in mode ``absolute``) and that curve's F_z (N). A factor
        far from 1 means the measured level disagrees with the model at that load (a wrong
        unit, another load): the verdict's ``shape_scale`` reason.
    shape_interval : ndarray or None
        lambda's profile interval under the scale reading (the fit's own; ``profile_interval``
        and ``interval_low`` / ``interval_high`` unite it with the offset reading's).
    offset_mode_mixity, offset_residual_rms : float or None
        lambda and the rms relative residual under the additive-offset reading
        (A_measured ~ A_model + d), fitted when a factor c is 10 % or more from 1
        (:mod:`statmodel.lambda_fit`); NaN when not tested.
    offset_interval : ndarray or None
        lambda's profile interval under that reading.
    offset_fraction : ndarray or None
        Per curve, d over the model's A_r at F_x = 0 under that reading.
    """

    mode_mixity: float = scalar("1", "mode mixity lambda used downstream")
    fitted: bool = scalar("1", "lambda fitted to measured A_r(F_x)")
    lambda_grid: np.ndarray | None = array(
        "1", ("lambda_grid",), "lambda of the coarse scan", optional=True
    )
    grid_residual_rms: np.ndarray | None = array(
        "1",
        ("lambda_grid",),
        "rms of (A_model - A_measured) / max(A_measured)",
        optional=True,
    )
    measured_normal_load: np.ndarray | None = array("N", ("point",), "normal load", optional=True)
    measured_tangential_force: np.ndarray | None = array(
        "N", ("point",), "measured tangential force", optional=True
    )
    measured_real_area: np.ndarray | None = array(
        "m^2", ("point",), "measured real contact area", optional=True
    )
    mode_mixity_std: float | None = scalar("1", "one-sigma uncertainty of lambda", optional=True)
    residual_rms: float | None = scalar("1", "rms relative residual", optional=True)
    n_points: int | None = scalar("1", "measured points fitted", optional=True)
    nfev: int | None = scalar("1", "model evaluations of the optimiser", optional=True)
    success: bool | None = scalar("1", "the optimiser reported success", optional=True)
    message: str | None = text("the optimiser's message", optional=True)
    model_real_area_at_measured: np.ndarray | None = array(
        "m^2", ("point",), "model A_r at the measured points, fitted lambda", optional=True
    )
    fit_mode: str | None = text("shape (A_r/A_r(F_x=0)) or absolute", optional=True)
    at_bound: bool | None = scalar("1", "lambda on a bound of the search interval", optional=True)
    interval_low: float | None = scalar("1", "one-sigma profile interval, low end", optional=True)
    interval_high: float | None = scalar("1", "one-sigma profile interval, high end", optional=True)
    n_points_read: int | None = scalar("1", "measured points before trim/merge", optional=True)
    fitted_normal_load: np.ndarray | None = array(
        "N", ("fitted_point",), "normal load of the fitted points", optional=True
    )
    fitted_tangential_force: np.ndarray | None = array(
        "N", ("fitted_point",), "F_x of the fitted (trimmed, merged) points", optional=True
    )
    fitted_real_area: np.ndarray | None = array(
        "m^2", ("fitted_point",), "measured A_r of the fitted points", optional=True
    )
    fitted_model_area: np.ndarray | None = array(
        "m^2", ("fitted_point",), "model A_r (times the curve's factor) there", optional=True
    )
    shape_scale: np.ndarray | None = array(
        "1",
        ("measured_curve",),
        "shape fit's factor c per measured curve (A_measured ~ c A_model; 1 in mode absolute)",
        optional=True,
    )
    shape_scale_normal_load: np.ndarray | None = array(
        "N", ("measured_curve",), "normal load of each measured curve", optional=True
    )
    profile_interval: np.ndarray | None = array(
        "1", ("interval_end",), "the fit's own profile interval of lambda", optional=True
    )
    mode_mixity_roughness_shift: np.ndarray | None = array(
        "1", ("interval_end",), "lambda fitted at the resolution interval's ends", optional=True
    )
    shape_interval: np.ndarray | None = array(
        "1", ("interval_end",), "profile interval of lambda under the scale reading", optional=True
    )
    offset_mode_mixity: float | None = scalar(
        "1", "lambda under the additive-offset reading (NaN: not tested)", optional=True
    )
    offset_interval: np.ndarray | None = array(
        "1", ("interval_end",), "profile interval of lambda under the offset reading", optional=True
    )
    offset_fraction: np.ndarray | None = array(
        "1",
        ("measured_curve",),
        "offset d over the model's A_r at F_x = 0 per curve, offset reading",
        optional=True,
    )
    offset_residual_rms: float | None = scalar(
        "1", "rms relative residual under the offset reading", optional=True
    )
    fit_source: str | None = text(
        "what lambda was fitted to: area, friction or joint (fit.source)", optional=True
    )
    area_mode_mixity: float | None = scalar("1", "lambda fitted to A_r(F_x) alone", optional=True)
    area_interval: np.ndarray | None = array(
        "1", ("interval_end",), "its one-sigma profile interval", optional=True
    )
    friction_mode_mixity: float | None = scalar(
        "1", "lambda fitted to the friction tests F_x(drive) alone", optional=True
    )
    friction_interval: np.ndarray | None = array(
        "1", ("interval_end",), "its one-sigma profile interval", optional=True
    )
    friction_residual_rms: float | None = scalar(
        "1", "rms of (F_model - F_measured) / max(F_measured), friction fit", optional=True
    )
    friction_n_points: int | None = scalar("1", "friction-test points fitted", optional=True)
    friction_at_bound: bool | None = scalar(
        "1", "the friction-only lambda lies on a bound", optional=True
    )
    lambda_sources_disagree: bool | None = scalar(
        "1", "area-only and friction-only lambdas differ by > 2 combined sigma", optional=True
    )
    lambda_sources_comparison: str | None = text(
        "the two single-source lambdas compared", optional=True
    )

    @classmethod
    def from_fit(cls, fit: LambdaFit, curves: Sequence[ShearAreaCurve]) -> ModeMixityChoice:
        """A fitted lambda with its fit and the measured curves."""
        return cls(
            mode_mixity=fit.mode_mixity,
            fitted=True,
            lambda_grid=np.asarray(fit.grid_mode_mixity, dtype=float),
            grid_residual_rms=np.asarray(fit.grid_residual_rms, dtype=float),
            measured_normal_load=np.concatenate(
                [np.full(len(c.real_area), c.normal_load) for c in curves]
            ),
            measured_tangential_force=np.concatenate([c.tangential_force for c in curves]),
            measured_real_area=np.concatenate([c.real_area for c in curves]),
            mode_mixity_std=fit.mode_mixity_std,
            residual_rms=fit.residual_rms,
            n_points=fit.n_points,
            nfev=fit.nfev,
            success=fit.success,
            message=fit.message,
            fit_mode=fit.mode,
            at_bound=fit.at_bound,
            interval_low=float(fit.interval[0]),
            interval_high=float(fit.interval[1]),
            n_points_read=fit.n_points_read,
            fitted_normal_load=fit.points.get("normal_load"),
            fitted_tangential_force=fit.points.get("tangential_force"),
            fitted_real_area=fit.points.get("real_area"),
            fitted_model_area=fit.points.get("model_area"),
            shape_scale=np.asarray(fit.scale, dtype=float),
            shape_scale_normal_load=np.array([c.normal_load for c in curves], dtype=float),
            shape_interval=np.asarray(fit.shape_interval, dtype=float),
            offset_mode_mixity=float(fit.offset_mode_mixity),
            offset_interval=np.asarray(fit.offset_interval, dtype=float),
            offset_fraction=np.asarray(fit.offset_fraction, dtype=float),
            offset_residual_rms=float(fit.offset_residual_rms),
        )

    @property
    def fit(self) -> LambdaFit | None:
        """The lambda fit, when fitted."""
        if not self.fitted:
            return None
        return LambdaFit(
            self.mode_mixity,
            self.mode_mixity_std,
            self.residual_rms,
            self.n_points,
            self.lambda_grid,
            self.grid_residual_rms,
            self.success,
            self.message,
            self.nfev,
            mode=self.fit_mode or "absolute",
            at_bound=bool(self.at_bound),
            interval=(
                math.nan if self.interval_low is None else self.interval_low,
                math.nan if self.interval_high is None else self.interval_high,
            ),
            n_points_read=self.n_points_read or self.n_points,
            scale=np.ones(0) if self.shape_scale is None else self.shape_scale,
            points={}
            if self.fitted_model_area is None
            else {
                "normal_load": self.fitted_normal_load,
                "tangential_force": self.fitted_tangential_force,
                "real_area": self.fitted_real_area,
                "model_area": self.fitted_model_area,
            },
        )

    @property
    def curves(self) -> list[ShearAreaCurve]:
        """The measured A_r(F_x) curves fitted (empty when not fitted)."""
        if not self.fitted or self.measured_normal_load is None:
            return []
        loads = self.measured_normal_load
        return [
            ShearAreaCurve(
                float(f),
                self.measured_tangential_force[loads == f],
                self.measured_real_area[loads == f],
                "stored",
            )
            for f in np.unique(loads)
        ]


def calibrate_mode_mixity(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    curves: Sequence[ShearAreaCurve],
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    knobs: Mapping[str, float] | None = None,
    executor: Executor | None = None,
    mode: str = "shape",
    trim: bool = True,
    roughness_interval: Sequence[statmodel.Roughness | None] | None = None,
    friction_curves: Sequence[FrictionCurve] = (),
    source: str = "area",
    drive_stiffness: float | None = None,
) -> ModeMixityChoice:
    """The lambda stage: fit lambda to measured A_r(F_x) curves and/or friction tests, or keep
    ``material.mode_mixity``.

    Parameters
    ----------
    material : statmodel.Material
        Its ``mode_mixity`` is used when no curves are given.
    roughness : statmodel.Roughness
        At the effective resolution.
    nominal_area : float
        A_n, m^2.
    curves : sequence of ShearAreaCurve
        Measured A_r(F_x), F_x in N, A_r in m^2.
    bounds : (float, float)
        Search interval of lambda.
    max_tangential_displacement, steps, knobs
        Shear path and quadrature of the model curves (at least :data:`MIN_FIT_STEPS` steps).
    executor : Executor, optional
        Evaluates the loads in parallel.
    mode, trim
        Fit mode and trimming of :func:`statmodel.lambda_fit.fit_mode_mixity`.
    roughness_interval : sequence of two statmodel.Roughness (None for an unknown end), optional
        The statistics at the effective resolution's interval ends: lambda is fitted there too
        and its interval is the union of the profile interval with those two fits (the
        roughness's uncertainty reaches lambda; ``mode_mixity_roughness_shift``). Area fit
        only: a friction or joint lambda keeps its own profile interval.
    friction_curves : sequence of FrictionCurve
        Measured friction tests F_x(drive) (m, N): fitted alone whenever given (the
        comparison of the two single-source lambdas), and used downstream when ``source``
        says so (:func:`statmodel.lambda_fit_friction.fit_sources`); with source "area" and
        no A_r(F_x) curves the configured lambda is used, the friction fit recorded beside it.
    source : {"area", "friction", "joint"}
        Which fit's lambda is used downstream (``[fit] source``).
    drive_stiffness : float or None
        The loading system's k, N/m (None: rigid), between the drive and the contact.
    """
    if not curves and not friction_curves:
        return ModeMixityChoice(mode_mixity=material.mode_mixity, fitted=False)
    map_fn = map if executor is None else executor.map
    quad = dict(knobs or {})
    area_model = functools.partial(
        model_shear_area,
        material=material,
        nominal_area=nominal_area,
        max_tangential_displacement=max_tangential_displacement,
        steps=max(steps, MIN_FIT_STEPS),
        knobs=quad,
    )
    choice, area_fit = None, None
    if curves:
        choice, area_fit = _area_choice(
            area_model, roughness, curves, bounds, map_fn, mode, trim, roughness_interval
        )
    if not friction_curves:
        return choice
    drive_model = _drive_model(
        material, roughness, nominal_area, drive_stiffness, max_tangential_displacement, steps, quad
    )
    fits = fit_sources(
        source,
        area_curves=list(curves),
        friction_curves=list(friction_curves),
        area_model=functools.partial(area_model, roughness=roughness),
        drive_model=drive_model,
        bounds=bounds,
        map_fn=map_fn,
        mode=mode,
        trim=trim,
        area_fit=area_fit,
    )
    if choice is None:  # friction tests only: fitted to them, or (source "area") configured
        choice = _friction_only_choice(material, fits.chosen)
    _record_sources(choice, fits)
    return choice


def _drive_model(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    drive_stiffness: float | None,
    max_tangential_displacement: float | None,
    steps: int,
    knobs: dict,
) -> functools.partial:
    """``model(lam, f_z) -> (drive (m), F_x (N))``: the model's friction test through the
    loading system's stiffness (N/m; None: rigid), on half the fit's steps."""
    return functools.partial(
        model_drive_curve,
        material=material,
        roughness=roughness,
        nominal_area=nominal_area,
        drive_stiffness=drive_stiffness,
        max_tangential_displacement=max_tangential_displacement,
        steps=max(steps, MIN_FIT_STEPS) // 2 + 1,
        knobs=knobs,
    )


def _friction_only_choice(
    material: statmodel.Material, chosen: LambdaFit | None
) -> ModeMixityChoice:
    """The lambda of friction tests alone: their fit's when ``chosen``, else the configured one."""
    return ModeMixityChoice(
        mode_mixity=material.mode_mixity if chosen is None else chosen.mode_mixity,
        fitted=chosen is not None,
    )


def _area_choice(
    area_model: functools.partial,
    roughness: statmodel.Roughness,
    curves: Sequence[ShearAreaCurve],
    bounds: tuple[float, float],
    map_fn: Callable,
    mode: str,
    trim: bool,
    roughness_interval: Sequence[statmodel.Roughness | None] | None,
) -> tuple[ModeMixityChoice, LambdaFit]:
    """lambda fitted to the A_r(F_x) curves (the profile interval united with the fits at the
    resolution interval's ends), with the model's A_r at the measured points; and the fit."""

    def fitted_at(rough: statmodel.Roughness) -> LambdaFit:
        return fit_mode_mixity(
            list(curves),
            functools.partial(area_model, roughness=rough),
            bounds=bounds,
            map_fn=map_fn,
            mode=mode,
            trim=trim,
        )

    fit = fitted_at(roughness)
    choice = ModeMixityChoice.from_fit(fit, curves)
    choice.profile_interval = np.asarray(fit.interval, dtype=float)
    if roughness_interval is not None:
        _unite_with_roughness(
            choice, [fitted_at(r) if _known(r) else None for r in roughness_interval]
        )
    model = functools.partial(area_model, roughness=roughness)
    outputs = map_fn(model, [fit.mode_mixity] * len(curves), [c.normal_load for c in curves])
    choice.model_real_area_at_measured = np.concatenate(
        [
            interpolate_area(fx, ar, c.tangential_force)
            for c, (fx, ar) in zip(curves, outputs, strict=True)
        ]
    )
    return choice, fit


def _record_sources(choice: ModeMixityChoice, fits: SourceFits) -> None:
    """The single-source lambdas and their comparison on ``choice``; with source "friction"
    or "joint", that fit's lambda, interval and scan replace the area fit's."""
    choice.fit_source = fits.source
    if fits.area is not None:
        choice.area_mode_mixity = fits.area.mode_mixity
        choice.area_interval = np.asarray(fits.area.interval, dtype=float)
    friction = fits.friction
    choice.friction_mode_mixity = friction.mode_mixity
    choice.friction_interval = np.asarray(friction.interval, dtype=float)
    choice.friction_residual_rms = friction.residual_rms
    choice.friction_n_points = friction.n_points
    choice.friction_at_bound = friction.at_bound
    choice.lambda_sources_disagree = fits.disagree
    choice.lambda_sources_comparison = fits.comparison or None
    if fits.source == "area":
        return
    chosen = fits.chosen
    choice.mode_mixity = chosen.mode_mixity
    choice.mode_mixity_std = chosen.mode_mixity_std
    choice.interval_low, choice.interval_high = (float(v) for v in chosen.interval)
    choice.profile_interval = np.asarray(chosen.interval, dtype=float)
    choice.mode_mixity_roughness_shift = None
    choice.at_bound = chosen.at_bound
    choice.lambda_grid = np.asarray(chosen.grid_mode_mixity, dtype=float)
    choice.grid_residual_rms = np.asarray(chosen.grid_residual_rms, dtype=float)
    choice.residual_rms = chosen.residual_rms
    choice.n_points = chosen.n_points
    choice.nfev, choice.success, choice.message = chosen.nfev, chosen.success, chosen.message


def _known(roughness: statmodel.Roughness | None) -> bool:
    """eta, R, sigma_s all finite (an interval end that is known; None: unknown)."""
    if roughness is None:
        return False
    values = (roughness.asperity_density, roughness.summit_radius, roughness.summit_height_rms)
    return bool(np.all(np.isfinite(values)))


def _unite_with_roughness(choice: ModeMixityChoice, fits: list[LambdaFit | None]) -> None:
    """lambda's interval united with the lambdas fitted at the resolution interval's ends (an
    unknown end leaves that side as it is); ``mode_mixity_std`` half the new width."""
    shift = np.array([math.nan if f is None else f.mode_mixity for f in fits], dtype=float)
    choice.mode_mixity_roughness_shift = shift
    low, high = float(choice.interval_low), float(choice.interval_high)
    known = shift[np.isfinite(shift)]
    if known.size and math.isfinite(low) and math.isfinite(high):
        low, high = min(low, float(known.min())), max(high, float(known.max()))
    choice.interval_low, choice.interval_high = low, high
    choice.mode_mixity_std = (
        0.5 * (high - low) if math.isfinite(low) and math.isfinite(high) else math.inf
    )


@document_fields
@dataclass
@stacked(statmodel.ShearCurve, (*CURVE_FIELDS, *CURVE_SCALARS), "normal_load", after="normal_load")
class FrictionPrediction:
    """Stage-6 result: the shear curve (:class:`statmodel.ShearCurve`) at every normal load.

    Every per-step array of a shear curve has shape (n_load, steps) and every per-curve
    scalar shape (n_load,), with the unit and description :class:`statmodel.ShearCurve`
    declares (the fields of the ``asperity friction`` output,
    :mod:`asperity.statmodel.results_io`; added by :func:`asperity.fields.stacked`), with
    stick and slip parts (E:NewFormulation_Fy..Ar).

    Attributes
    ----------
    normal_load : ndarray
        F_z, N.
    converged : ndarray of bool
        Per load.
    quadrature_relative_change, quadrature_seconds : ndarray
        The quadrature refinement check per setting (relative change, s per curve).
    mode_mixity, shear_strength, nominal_area : float
        lambda, tau0 (Pa) and A_n (m^2) used.
    messages : list of str
        Per load.
    quadrature_knobs : dict
        The chosen knobs of :func:`statmodel.shear_curve`.
    quadrature_ladder : list of dict
        The settings tried, coarse to fine.
    quadrature_reason : str
        One sentence for the report.
    constant_shear_strength_force : ndarray
        tau0 A_r, N: the constant-shear-strength model of Fig 13 (derived).
    all_converged : bool
        Every shear curve converged (derived).
    model_real_area, model_real_area_uncertainty : ndarray or None
        The model's A_r at F_x = 0 (E:Ar_Greenwood) per load and its uncertainty, m^2.
    static_friction_uncertainty, sliding_friction_uncertainty : ndarray or None
        Per load, N.
    sliding_displacement_uncertainty : ndarray or None
        Per load, m (NaN where the model never fully slides).
    uncertainty_lower_bound : bool or None
        The effective resolution's interval is open on a side: the uncertainties are lower
        bounds.
    uncertainty_status : int or None
        0 every uncertainty finite from closed intervals, 1 otherwise.
    uncertainty_message : str or None
        What limits the uncertainties, one sentence.
    mode_mixity_assumed : bool or None
        lambda is the configured value, not fitted to measured A_r(F_x): it carries no
        uncertainty, and the error bars leave it out.
    mode_mixity_decade : ndarray or None
        With an assumed lambda: lambda / sqrt(10) and lambda x sqrt(10) (a decade about it).
    static_friction_mode_mixity_decade : ndarray or None
        The static friction (N) at those two lambdas, shape (2, n_load): what a decade of the
        assumed lambda does to the prediction.

    The uncertainties come from :func:`statmodel.uncertainty.propagate_to_predictions`: the
    model at the roughness of both ends of the effective resolution's interval and at both ends
    of lambda's interval (zero width when lambda is configured), the largest excursion per
    source, in quadrature (one sigma, docs/uncertainty.md).
    """

    normal_load: np.ndarray = array("N", ("normal_load",), "normal load")
    converged: np.ndarray = array("1", ("normal_load",), "shear curve converged")
    quadrature_relative_change: np.ndarray = array(
        "1", ("quadrature_setting",), "change of F_x, A_r to the next finer setting"
    )
    quadrature_seconds: np.ndarray = array("s", ("quadrature_setting",), "time per curve")
    mode_mixity: float = scalar("1", "mode mixity lambda used")
    shear_strength: float = scalar("Pa", "shear strength tau0 used")
    nominal_area: float = scalar("m^2", "nominal contact area A_n")
    messages: list[str] = text("solver message per load")
    quadrature_knobs: dict[str, int] = text("chosen knobs of statmodel.shear_curve")
    quadrature_ladder: list[dict[str, int]] = text("quadrature settings tried, coarse to fine")
    quadrature_reason: str = text("why this quadrature")
    constant_shear_strength_force: np.ndarray = array(
        "N",
        ("normal_load", "step"),
        "tau0 A_r: the constant-shear-strength model of Fig 13",
        init=False,
    )
    all_converged: bool = scalar("1", "every shear curve converged", init=False)
    model_real_area: np.ndarray | None = array(
        "m^2", ("normal_load",), "model A_r at F_x = 0", optional=True
    )
    model_real_area_uncertainty: np.ndarray | None = array(
        "m^2", ("normal_load",), "uncertainty of the model A_r at F_x = 0", optional=True
    )
    static_friction_uncertainty: np.ndarray | None = array(
        "N", ("normal_load",), "uncertainty of the static friction", optional=True
    )
    sliding_friction_uncertainty: np.ndarray | None = array(
        "N", ("normal_load",), "uncertainty of the sliding friction", optional=True
    )
    sliding_displacement_uncertainty: np.ndarray | None = array(
        "m", ("normal_load",), "uncertainty of the sliding displacement", optional=True
    )
    uncertainty_lower_bound: bool | None = scalar(
        "1", "the uncertainties are lower bounds (an open interval)", optional=True
    )
    uncertainty_status: int | None = scalar("1", "status of the uncertainties", optional=True)
    uncertainty_message: str | None = text("what limits the uncertainties", optional=True)
    mode_mixity_assumed: bool | None = scalar(
        "1", "lambda configured, not fitted (no uncertainty)", optional=True
    )
    mode_mixity_decade: np.ndarray | None = array(
        "1", ("mode_mixity_end",), "lambda / sqrt(10) and lambda x sqrt(10)", optional=True
    )
    static_friction_mode_mixity_decade: np.ndarray | None = array(
        "N",
        ("mode_mixity_end", "normal_load"),
        "static friction at lambda / sqrt(10) and x sqrt(10)",
        optional=True,
    )

    static_friction_coefficient: np.ndarray = array(
        "1", ("normal_load",), "static friction coefficient mu_s = F_s / F_z", init=False
    )
    static_friction_coefficient_uncertainty: np.ndarray | None = array(
        "1", ("normal_load",), "uncertainty of mu_s (F_s's / F_z)", optional=True, init=False
    )
    static_peak_real_area: np.ndarray = array(
        "m^2", ("normal_load",), "A_r at the static peak", init=False
    )
    real_area_drop: np.ndarray = array(
        "1", ("normal_load",), "A_r at the static peak / A_r at F_x = 0 (Fig 13)", init=False
    )

    def __post_init__(self) -> None:
        self.constant_shear_strength_force = self.shear_strength * np.asarray(self.real_area)
        self.all_converged = bool(np.all(self.converged))
        self.__dict__.update(static_peak_quantities(self))

    def curve_arrays(self, index: int) -> dict[str, np.ndarray]:
        """The per-step arrays of the shear curve at load ``index``, by name (SI)."""
        return {name: getattr(self, name)[index] for name in CURVE_FIELDS}


def static_peak_quantities(fr: FrictionPrediction) -> dict[str, np.ndarray | None]:
    """Per load: mu_s = F_s / F_z (1) and its uncertainty, A_r at the static peak (m^2) and the
    area drop A_r(peak) / A_r(delta_T = 0) (1), the paper's Fig 13 observation. A_r(peak) is
    the stored curve's A_r(delta_T) at the peak of F_x(delta_T): the parabola through the
    largest F_x step and its neighbours locates the peak, the parabola through the same three
    steps' A_r gives the area there."""
    load = np.asarray(fr.normal_load, dtype=float)
    area = np.atleast_2d(np.asarray(fr.real_area, dtype=float))
    force = np.atleast_2d(np.asarray(fr.tangential_force, dtype=float))
    peak = np.array([area_at_force_peak(f, a) for f, a in zip(force, area, strict=True)])
    u = fr.static_friction_uncertainty
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            "static_friction_coefficient": np.asarray(fr.static_friction, float) / load,
            "static_friction_coefficient_uncertainty": None if u is None else np.asarray(u) / load,
            "static_peak_real_area": peak,
            "real_area_drop": peak / area[:, 0],
        }


def area_at_force_peak(force: np.ndarray, area: np.ndarray) -> float:
    """A_r at the peak of F_x over equal delta_T steps: the vertex t of the parabola through
    the largest F_x and its two neighbours (in steps, -1/2 <= t <= 1/2), and A_r's parabola
    through the same steps at t; the step's own A_r at an end of the path; NaN if no finite
    F_x."""
    if not np.isfinite(force).any():
        return float("nan")
    k = int(np.nanargmax(force))
    if k == 0 or k == force.size - 1 or not np.all(np.isfinite(force[k - 1 : k + 2])):
        return float(area[k])
    f0, f1, f2 = force[k - 1 : k + 2]
    curvature = f0 - 2 * f1 + f2
    t = 0.0 if curvature >= 0 else float(np.clip(0.5 * (f0 - f2) / curvature, -0.5, 0.5))
    a0, a1, a2 = area[k - 1 : k + 2]
    return float(a1 + 0.5 * t * (a2 - a0) + 0.5 * t * t * (a0 - 2 * a1 + a2))


def friction_prediction(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_loads: Sequence[float],
    *,
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    quadrature_tolerance: float = 1e-4,
    roughness_interval: Sequence[statmodel.Roughness | None] | None = None,
    mode_mixity_interval: tuple[float, float] | None = None,
    interval_open: bool = False,
    mode_mixity_assumed: bool = False,
    executor: Executor | None = None,
    progress: bool = False,
) -> FrictionPrediction:
    """The friction stage: F_x(delta_T), A_r(F_x) with stick/slip parts, static and sliding
    friction.

    Parameters
    ----------
    material : statmodel.Material
        With the calibrated lambda.
    roughness : statmodel.Roughness
        At the effective resolution.
    nominal_area : float
        A_n, m^2.
    normal_loads : sequence of float
        F_z, N.
    max_tangential_displacement : float or None
        Largest delta_T, m (None: automatic, per load).
    steps : int
        delta_T steps.
    quadrature_tolerance : float
        Relative accuracy asked of the quadrature (:func:`choose_quadrature`).
    roughness_interval : sequence of two statmodel.Roughness (None for an unknown end), optional
        eta, R, sigma_s at the (finer, coarser) ends of the effective resolution's interval;
        with it the predictions get their uncertainties (:func:`prediction_uncertainty`).
    mode_mixity_interval : (float, float), optional
        lambda's one-sigma interval (default: lambda itself, no lambda part).
    interval_open : bool
        The effective resolution's interval is open on a side (uncertainties: lower bounds).
    mode_mixity_assumed : bool
        lambda is configured, not fitted: the static friction is also computed at a decade
        about it (lambda / sqrt(10), lambda x sqrt(10)) and stored beside the predictions.
    executor : Executor, optional
        Runs the loads in parallel.
    """
    loads = np.asarray(normal_loads, dtype=float)
    quad = choose_quadrature(
        material,
        roughness,
        nominal_area,
        float(loads.max()),
        tolerance=quadrature_tolerance,
        max_tangential_displacement=max_tangential_displacement,
        steps=steps,
    )
    max_dt = max_tangential_displacement
    jobs = [(material, roughness, nominal_area, float(f), max_dt, steps, quad.knobs) for f in loads]
    results = run_map(_curve_job, jobs, executor, desc="shear curves", progress=progress)
    decade = (
        _mode_mixity_decade(material, jobs, executor)
        if mode_mixity_assumed and material.mode_mixity > 0
        else {}
    )
    names = (*CURVE_FIELDS, *CURVE_SCALARS)
    per_load = {name: np.array([r[name] for r in results]) for name in names}
    curve_at = functools.partial(
        _shear_curve_at, nominal_area=nominal_area, max_dt=max_dt, steps=steps, knobs=quad.knobs
    )
    return FrictionPrediction(
        normal_load=loads,
        converged=np.array([r["converged"] for r in results], dtype=bool),
        mode_mixity=material.mode_mixity,
        shear_strength=material.shear_strength,
        nominal_area=float(nominal_area),
        messages=[r["message"] for r in results],
        **_quadrature_fields(quad),
        **decade,
        **per_load,
        **prediction_uncertainty(
            material,
            roughness,
            nominal_area,
            loads,
            roughness_interval,
            mode_mixity_interval,
            interval_open,
            curve_at,
        ),  # fmt: skip
    )


def _quadrature_fields(quad: QuadratureChoice) -> dict:
    """The quadrature choice's fields of :class:`FrictionPrediction`."""
    return {
        "quadrature_relative_change": quad.relative_change,
        "quadrature_seconds": quad.seconds,
        "quadrature_knobs": quad.knobs,
        "quadrature_ladder": quad.ladder,
        "quadrature_reason": quad.reason,
    }


#: The factor about an assumed lambda shown in the report (a decade: sqrt(10) each way).
DECADE_FACTOR = math.sqrt(10.0)


def _mode_mixity_decade(
    material: statmodel.Material, jobs: list[tuple], executor: Executor | None
) -> dict[str, np.ndarray | bool]:
    """The static friction (N) per load at lambda / sqrt(10) and lambda x sqrt(10) (the
    friction stage's own path and quadrature), with those lambdas and the assumed flag."""
    lams = np.array([material.mode_mixity / DECADE_FACTOR, material.mode_mixity * DECADE_FACTOR])
    rows = []
    for lam in lams:
        changed = dataclasses.replace(material, mode_mixity=float(lam))
        moved = [(changed, *job[1:]) for job in jobs]
        rows.append([r["static_friction"] for r in run_map(_curve_job, moved, executor)])
    return {
        "mode_mixity_assumed": True,
        "mode_mixity_decade": lams,
        "static_friction_mode_mixity_decade": np.array(rows, dtype=float),
    }


def _shear_curve_at(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    normal_load: float,
    *,
    nominal_area: float,
    max_dt: float | None,
    steps: int,
    knobs: Mapping[str, float],
) -> statmodel.ShearCurve:
    """The friction stage's own shear curve (path and quadrature) at one input."""
    return shear_curve_auto(
        material,
        roughness,
        nominal_area,
        normal_load,
        max_tangential_displacement=max_dt,
        steps=steps,
        knobs=knobs,
    )


def _unknown_uncertainty(loads: np.ndarray, message: str) -> UncertaintyFields:
    nan = np.full(loads.shape, np.nan)
    return {
        "model_real_area_uncertainty": nan,
        "static_friction_uncertainty": nan,
        "sliding_friction_uncertainty": nan,
        "sliding_displacement_uncertainty": nan,
        "uncertainty_lower_bound": False,
        "uncertainty_status": 1,
        "uncertainty_message": message,
    }


def prediction_uncertainty(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    loads: np.ndarray,
    roughness_interval: Sequence[statmodel.Roughness | None] | None,
    mode_mixity_interval: tuple[float, float] | None,
    interval_open: bool,
    curve: statmodel.ShearCurve,
) -> UncertaintyFields:
    """The uncertainty fields of :class:`FrictionPrediction` (SI; empty without an interval).

    :func:`statmodel.uncertainty.propagate_to_predictions` with the stage's own ``curve``;
    an interval end with unknown statistics makes every uncertainty NaN, stated.
    """
    if roughness_interval is None:
        return {}
    model_area = np.asarray(
        statmodel.real_area_at_loads(material, roughness, nominal_area, loads), dtype=float
    )
    if not all(_known(r) for r in roughness_interval):
        return {
            "model_real_area": model_area,
            **_unknown_uncertainty(
                loads, "no interval of the effective resolution: no uncertainty estimated"
            ),
        }
    lam = mode_mixity_interval or (material.mode_mixity, material.mode_mixity)
    out = propagate_to_predictions(
        material,
        roughness,
        list(roughness_interval),
        lam,
        nominal_area,
        loads,
        curve=curve,
        interval_open=interval_open,
    )
    return {
        "model_real_area": out.value["real_area"],
        "model_real_area_uncertainty": out.uncertainty["real_area"],
        "static_friction_uncertainty": out.uncertainty["static_friction"],
        "sliding_friction_uncertainty": out.uncertainty["sliding_friction"],
        "sliding_displacement_uncertainty": out.uncertainty["sliding_displacement"],
        "uncertainty_lower_bound": bool(out.lower_bound),
        "uncertainty_status": int(out.status),
        "uncertainty_message": out.message,
    }


def compute_mode_mixity(context: StageContext) -> ModeMixityChoice:
    """The job's lambda stage: :func:`calibrate_mode_mixity` on the measured A_r(F_x) curves."""
    config = context.config
    return calibrate_mode_mixity(
        config.material,
        context.result(STATISTICAL_MODEL).roughness,
        config.loading.nominal_area,
        context.measured.shear_area,
        bounds=config.fit.mode_mixity_bounds,
        max_tangential_displacement=config.loading.max_tangential_displacement,
        steps=config.loading.steps,
        executor=context.executor,
        mode=config.fit.mode,
        trim=config.fit.trim_after_first_peak,
        roughness_interval=context.result(STATISTICAL_MODEL).roughness_interval,
        friction_curves=context.measured.friction_curves,
        source=config.fit.source,
        drive_stiffness=config.loading.drive_stiffness,
    )


def compute_friction(context: StageContext) -> FrictionPrediction:
    """The job's friction stage: :func:`friction_prediction` with the calibrated lambda."""
    config = context.config
    lam = context.result(MODE_MIXITY)
    material = dataclasses.replace(config.material, mode_mixity=lam.mode_mixity)
    res = context.result(STATISTICAL_MODEL)
    return friction_prediction(
        material,
        res.roughness,
        config.loading.nominal_area,
        config.loading.normal_loads,
        max_tangential_displacement=config.loading.max_tangential_displacement,
        steps=config.loading.steps,
        quadrature_tolerance=config.statmodel.area_tolerance,
        roughness_interval=res.roughness_interval,
        mode_mixity_interval=mode_mixity_interval(lam),
        interval_open=res.interval_open,
        mode_mixity_assumed=not lam.fitted,
        executor=context.executor,
        progress=context.progress,
    )


def mode_mixity_interval(choice: ModeMixityChoice) -> tuple[float, float]:
    """lambda's one-sigma profile interval when fitted (NaN ends where the profile did not
    close); the configured lambda itself (zero width) otherwise."""
    if not choice.fitted:
        return (choice.mode_mixity, choice.mode_mixity)
    low, high = choice.interval_low, choice.interval_high
    return (
        math.nan if low is None else float(low),
        math.nan if high is None else float(high),
    )


MODE_MIXITY = Stage(
    name="mode_mixity",
    title="lambda",
    result=ModeMixityChoice,
    config=(
        "material",
        "loading.nominal_area",
        "loading.max_tangential_displacement",
        "loading.steps",
        "loading.drive_stiffness",
        "measured.shear_area",
        "measured.friction_curves",
        "fit",
    ),
    inputs=(STATISTICAL_MODEL,),
    compute=compute_mode_mixity,
)

FRICTION = Stage(
    name="friction",
    title="friction prediction",
    result=FrictionPrediction,
    config=("material", "loading", "statmodel"),
    inputs=(STATISTICAL_MODEL, MODE_MIXITY),
    compute=compute_friction,
)
