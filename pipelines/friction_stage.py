"""Stages 5 and 6: calibrate lambda on measured A_r(F_x), then predict friction at each load.

Stage 5 (:func:`calibrate_mode_mixity`) fits the mode mixity lambda to the user's measured
A_r(F_x) curves with :func:`pipelines.fitting.fit_mode_mixity` (Section 5, Fig 13); without
measurements the configured lambda is used.

Stage 6 (:func:`friction_prediction`) runs :func:`statmodel.shear_curve` at every normal load:
F_x(delta_T), A_r(F_x) with their stick and slip parts (E:NewFormulation_Fy..Ar), static and
sliding friction (Figs 4, 13), and the constant-shear-strength line F_x = tau0 A_r of Fig 13.

The shear path delta_T = 0..max is given, or found automatically ("auto"): a first curve on a
guessed path gives the model's sliding displacement (the statistical model finds it even
beyond the path), and the path is then set to 1.25 times it, so that the steps resolve the
stick part, the static peak and the start of full sliding. When sliding never completes
(lambda = 0) the guessed path is kept.

Quadrature ("model no more than a scene needs"): :func:`choose_quadrature` evaluates the
heaviest load's curve with each setting of :data:`QUADRATURE_LADDER` (coarse to fine) and keeps
the coarsest whose F_x and A_r differ from the next finer one by less than the requested
relative tolerance (relative to the curve's maximum).
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from asperity import statmodel
from asperity.pipelines.fitting import LambdaFit, fit_mode_mixity
from asperity.pipelines.measured import ShearAreaCurve
from asperity.pipelines.parallel import run_map
from asperity.pipelines.store import StageRecord, Variable
from asperity.statmodel.results_io import ARRAY_UNITS, SCALAR_UNITS

#: Per-step arrays and per-load scalars of :class:`statmodel.ShearCurve` kept by stage 6, with
#: their units: the tables the ``asperity friction`` output uses, less ``normal_load``, which is
#: the stage's dimension coordinate.
CURVE_FIELDS: dict[str, str] = dict(ARRAY_UNITS)
CURVE_SCALARS: dict[str, str] = {k: v for k, v in SCALAR_UNITS.items() if k != "normal_load"}

#: Quadrature settings of :func:`statmodel.shear_curve` (its ``nodes`` Gauss-Legendre nodes per
#: panel and ``panels`` per population range), coarse to fine; the fourth is the model's default.
QUADRATURE_LADDER: tuple[dict[str, Any], ...] = (
    {"nodes": 4, "panels": 1},
    {"nodes": 6, "panels": 2},
    {"nodes": 8, "panels": 4},
    {"nodes": 16, "panels": 4},
    {"nodes": 24, "panels": 8},
)

#: Fewest delta_T steps of the model curves the lambda fit interpolates (their discretisation
#: must not bias the fit).
MIN_FIT_STEPS = 201

#: The automatic shear path ends at this multiple of the sliding displacement.
SLIDING_MARGIN = 1.25


def initial_displacement_guess(
    material: statmodel.Material, roughness: statmodel.Roughness
) -> float:
    """A first guess of the shear path length, m.

    Four times tau0 a0 / E*, with a0 = (9 pi w R^2 / (2 E*))^(1/3) the JKR contact radius at
    zero load (E:JKR_indent, E:JKR_load); at least 1e-7 m. Only a starting point: the path is
    then extended or trimmed by :func:`shear_curve_auto`.
    """
    r, w, e = roughness.summit_radius, material.work_of_adhesion, material.e_star
    a0 = (9 * math.pi * max(w, 1e-6) * r**2 / (2 * e)) ** (1 / 3)
    tau = max(material.shear_strength, 1e-3 * e)
    return max(4 * tau * a0 / e, 1e-7)


def shear_curve_auto(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_load: float,
    *,
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    knobs: Mapping[str, Any] | None = None,
) -> Any:
    """:func:`statmodel.shear_curve` on a given or automatically found shear path.

    Parameters
    ----------
    material, roughness : statmodel.Material, statmodel.Roughness
        Model inputs (SI).
    nominal_area : float
        A_n, m^2.
    normal_load : float
        F_z, N.
    max_tangential_displacement : float or None
        Largest delta_T, m; None finds it (see module docstring).
    steps : int
        Number of delta_T steps, the first at delta_T = 0.
    knobs : mapping, optional
        Accuracy knobs passed to :func:`statmodel.shear_curve`.

    Returns
    -------
    statmodel.ShearCurve
    """
    knobs = dict(knobs or {})

    def run(max_dt: float) -> Any:
        path = np.linspace(0.0, max_dt, steps)
        return statmodel.shear_curve(material, roughness, nominal_area, normal_load, path, **knobs)

    if max_tangential_displacement is not None:
        return run(float(max_tangential_displacement))
    max_dt = initial_displacement_guess(material, roughness)
    curve = run(max_dt)
    sliding = float(curve.sliding_displacement)  # found by the model even beyond the path
    if math.isfinite(sliding) and sliding > 0 and not 0.6 * max_dt <= sliding <= max_dt:
        curve = run(SLIDING_MARGIN * sliding)
    return curve


def curve_summary(curve: Any) -> dict[str, Any]:
    """Arrays and scalars of a shear curve as a picklable dict (SI)."""
    out: dict[str, Any] = {
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
    knobs: Mapping[str, Any],
) -> dict[str, Any]:
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


def model_shear_area(
    mode_mixity: float,
    normal_load: float,
    *,
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    max_tangential_displacement: float | None,
    steps: int,
    knobs: Mapping[str, Any],
) -> tuple[np.ndarray, np.ndarray]:
    """Model A_r(F_x) along the shear path for one lambda and load: (F_x N, A_r m^2)."""
    curve = shear_curve_auto(
        dataclasses.replace(material, mode_mixity=float(mode_mixity)),
        roughness,
        nominal_area,
        normal_load,
        max_tangential_displacement=max_tangential_displacement,
        steps=steps,
        knobs=knobs,
    )
    return np.asarray(curve.tangential_force, float), np.asarray(curve.real_area, float)


@dataclass
class QuadratureChoice:
    """Outcome of the statistical model's refinement check.

    Attributes
    ----------
    knobs : dict
        The chosen accuracy knobs of :func:`statmodel.shear_curve`.
    ladder : list of dict
        Settings tried, coarse to fine.
    relative_change : ndarray
        Largest relative change of F_x and A_r from each setting to the next finer one.
    seconds : ndarray
        Time of each setting's curve, s.
    reason : str
        One sentence for the report.
    """

    knobs: dict[str, Any]
    ladder: list[dict[str, Any]]
    relative_change: np.ndarray
    seconds: np.ndarray
    reason: str


def choose_quadrature(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_load: float,
    *,
    tolerance: float,
    max_tangential_displacement: float | None,
    steps: int,
    ladder: Sequence[Mapping[str, Any]] = QUADRATURE_LADDER,
) -> QuadratureChoice:
    """The coarsest quadrature setting whose curve agrees with the next finer one.

    Parameters
    ----------
    material, roughness, nominal_area, normal_load
        The heaviest case of the job (SI).
    tolerance : float
        Allowed relative change of F_x and A_r (relative to each curve's maximum).
    max_tangential_displacement, steps
        The shear path (see :func:`shear_curve_auto`).
    ladder : sequence of dict
        Knob settings, coarse to fine.
    """
    ladder = [dict(k) for k in ladder]
    if len(ladder) == 1:
        return QuadratureChoice(
            ladder[0],
            ladder,
            np.array([np.nan]),
            np.array([np.nan]),
            "statmodel's default quadrature (no coarser setting offered)",
        )
    curves, seconds = [], []
    max_dt = max_tangential_displacement
    for knobs in ladder[::-1]:  # finest first: it fixes the shear path for the others
        t0 = time.perf_counter()
        curve = shear_curve_auto(
            material,
            roughness,
            nominal_area,
            normal_load,
            max_tangential_displacement=max_dt,
            steps=steps,
            knobs=knobs,
        )
        seconds.append(time.perf_counter() - t0)
        if max_dt is None:
            max_dt = float(np.asarray(curve.tangential_displacement)[-1])
        curves.append(curve)
    curves, seconds = curves[::-1], np.array(seconds[::-1])
    change = np.full(len(ladder), np.nan)
    for i in range(len(ladder) - 1):
        worst = 0.0
        for name in ("tangential_force", "real_area"):
            a = np.asarray(getattr(curves[i], name), float)
            b = np.asarray(getattr(curves[i + 1], name), float)
            scale = np.max(np.abs(b)) or 1.0
            worst = max(worst, float(np.max(np.abs(a - b)) / scale))
        change[i] = worst
    for i in range(len(ladder) - 1):
        if change[i] <= tolerance:
            return QuadratureChoice(
                ladder[i],
                ladder,
                change,
                seconds,
                f"setting {ladder[i] or 'default'}: F_x and A_r change by "
                f"{change[i]:.2g} (relative) on refinement, within "
                f"{tolerance:.2g}; {seconds[i]:.3g} s per curve",
            )
    return QuadratureChoice(
        ladder[-1],
        ladder,
        change,
        seconds,
        f"no coarser setting met {tolerance:.2g}: the finest ({ladder[-1] or 'default'}) is used",
    )


@dataclass
class ModeMixityChoice:
    """Stage-5 result: the lambda used downstream and how it was obtained."""

    mode_mixity: float
    fitted: bool
    fit: LambdaFit | None = None
    curves: list[ShearAreaCurve] = field(default_factory=list)


def calibrate_mode_mixity(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    curves: Sequence[ShearAreaCurve],
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    knobs: Mapping[str, Any] | None = None,
    executor: Executor | None = None,
) -> ModeMixityChoice:
    """Stage 5: fit lambda to measured A_r(F_x) curves, or keep ``material.mode_mixity``.

    Parameters
    ----------
    material : statmodel.Material
        Its ``mode_mixity`` is used when ``curves`` is empty.
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
    """
    if not curves:
        return ModeMixityChoice(material.mode_mixity, False)
    model = functools.partial(
        model_shear_area,
        material=material,
        roughness=roughness,
        nominal_area=nominal_area,
        max_tangential_displacement=max_tangential_displacement,
        steps=max(steps, MIN_FIT_STEPS),
        knobs=dict(knobs or {}),
    )
    fit = fit_mode_mixity(
        list(curves), model, bounds=bounds, map_fn=map if executor is None else executor.map
    )
    return ModeMixityChoice(fit.mode_mixity, True, fit, list(curves))


@dataclass
class FrictionPrediction:
    """Stage-6 result: shear curves at every normal load.

    Attributes
    ----------
    normal_load : ndarray
        F_z, N.
    curves : dict of str to ndarray
        Each of :data:`CURVE_FIELDS`, shape (n_load, steps), SI.
    scalars : dict of str to ndarray
        Each of :data:`CURVE_SCALARS`, one per load, SI.
    converged : ndarray of bool
        Per load.
    messages : list of str
        Per load.
    mode_mixity, shear_strength, nominal_area : float
        lambda, tau0 (Pa) and A_n (m^2) used.
    quadrature : QuadratureChoice
        The refinement check.
    """

    normal_load: np.ndarray
    curves: dict[str, np.ndarray]
    scalars: dict[str, np.ndarray]
    converged: np.ndarray
    messages: list[str]
    mode_mixity: float
    shear_strength: float
    nominal_area: float
    quadrature: QuadratureChoice

    @property
    def all_converged(self) -> bool:
        """Every shear curve converged."""
        return bool(np.all(self.converged))


def friction_prediction(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_loads: Sequence[float],
    *,
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    quadrature_tolerance: float = 1e-4,
    executor: Executor | None = None,
    progress: bool = False,
) -> FrictionPrediction:
    """Stage 6: F_x(delta_T), A_r(F_x) with stick/slip parts, static and sliding friction.

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
    jobs = [
        (
            material,
            roughness,
            nominal_area,
            float(f),
            max_tangential_displacement,
            steps,
            quad.knobs,
        )
        for f in loads
    ]
    results = run_map(_curve_job, jobs, executor, desc="shear curves", progress=progress)
    curves = {name: np.array([r[name] for r in results]) for name in CURVE_FIELDS}
    scalars = {name: np.array([r[name] for r in results]) for name in CURVE_SCALARS}
    return FrictionPrediction(
        normal_load=loads,
        curves=curves,
        scalars=scalars,
        converged=np.array([r["converged"] for r in results]),
        messages=[r["message"] for r in results],
        mode_mixity=material.mode_mixity,
        shear_strength=material.shear_strength,
        nominal_area=nominal_area,
        quadrature=quad,
    )


def lambda_record(choice: ModeMixityChoice, nominal_area: float) -> StageRecord:
    """Stage-5 record (the fit's scan and the measured curves when fitted)."""
    record = StageRecord(attrs={"mode_mixity": choice.mode_mixity, "fitted": choice.fitted})
    if choice.fit is None:
        return record
    fit = choice.fit
    record.coords["lambda_grid"] = Variable(
        fit.grid_mode_mixity, "1", ("lambda_grid",), "lambda of the coarse scan"
    )
    record.variables["grid_residual_rms"] = Variable(
        fit.grid_residual_rms,
        "1",
        ("lambda_grid",),
        "rms of (A_model - A_measured) / max(A_measured)",
    )
    loads = np.concatenate([np.full(len(c.real_area), c.normal_load) for c in choice.curves])
    record.coords["point"] = Variable(np.arange(len(loads)), "1", ("point",), "measured point")
    record.variables["measured_normal_load"] = Variable(loads, "N", ("point",), "normal load")
    record.variables["measured_tangential_force"] = Variable(
        np.concatenate([c.tangential_force for c in choice.curves]),
        "N",
        ("point",),
        "measured tangential force",
    )
    record.variables["measured_real_area"] = Variable(
        np.concatenate([c.real_area for c in choice.curves]),
        "m^2",
        ("point",),
        "measured real contact area",
    )
    record.attrs.update(
        mode_mixity_std=fit.mode_mixity_std,
        residual_rms=fit.residual_rms,
        n_points=fit.n_points,
        success=fit.success,
        message=fit.message,
        nfev=fit.nfev,
        nominal_area=nominal_area,
    )
    return record


def lambda_from_record(record: StageRecord) -> ModeMixityChoice:
    """Rebuild the stage-5 result from its stored record."""
    a, v = record.attrs, record.variables
    if not a.get("fitted"):
        return ModeMixityChoice(float(a["mode_mixity"]), False)
    loads = v["measured_normal_load"].data
    curves = [
        ShearAreaCurve(
            float(f),
            v["measured_tangential_force"].data[loads == f],
            v["measured_real_area"].data[loads == f],
            "stored",
        )
        for f in np.unique(loads)
    ]
    fit = LambdaFit(
        float(a["mode_mixity"]),
        float(a["mode_mixity_std"]),
        float(a["residual_rms"]),
        int(a["n_points"]),
        record.coords["lambda_grid"].data,
        v["grid_residual_rms"].data,
        bool(a["success"]),
        str(a["message"]),
        int(a["nfev"]),
    )
    return ModeMixityChoice(fit.mode_mixity, True, fit, curves)


def friction_record(pred: FrictionPrediction) -> StageRecord:
    """Stage-6 record: curves over (normal_load, step), scalars over normal_load."""
    steps = pred.curves["tangential_force"].shape[1]
    record = StageRecord(
        coords={
            "normal_load": Variable(pred.normal_load, "N", ("normal_load",), "normal load"),
            "step": Variable(np.arange(steps), "1", ("step",), "shear step (0: delta_T = 0)"),
            "quadrature_setting": Variable(
                np.arange(len(pred.quadrature.ladder)),
                "1",
                ("quadrature_setting",),
                "quadrature ladder index",
            ),
        }
    )
    for name, units in CURVE_FIELDS.items():
        record.variables[name] = Variable(
            pred.curves[name], units, ("normal_load", "step"), name.replace("_", " ")
        )
    for name, units in CURVE_SCALARS.items():
        record.variables[name] = Variable(
            pred.scalars[name], units, ("normal_load",), name.replace("_", " ")
        )
    record.variables["converged"] = Variable(
        pred.converged, "1", ("normal_load",), "shear curve converged"
    )
    record.variables["constant_shear_strength_force"] = Variable(
        pred.shear_strength * pred.curves["real_area"],
        "N",
        ("normal_load", "step"),
        "tau0 A_r: the constant-shear-strength model of Fig 13",
    )
    record.variables["quadrature_relative_change"] = Variable(
        pred.quadrature.relative_change,
        "1",
        ("quadrature_setting",),
        "change of F_x, A_r to the next finer setting",
    )
    record.variables["quadrature_seconds"] = Variable(
        pred.quadrature.seconds, "s", ("quadrature_setting",), "time per curve"
    )
    record.attrs.update(
        mode_mixity=pred.mode_mixity,
        shear_strength=pred.shear_strength,
        nominal_area=pred.nominal_area,
        messages="\n".join(pred.messages),
        quadrature_knobs=json.dumps(pred.quadrature.knobs),
        quadrature_ladder=json.dumps(pred.quadrature.ladder),
        quadrature_reason=pred.quadrature.reason,
        all_converged=pred.all_converged,
    )
    return record


def friction_from_record(record: StageRecord) -> FrictionPrediction:
    """Rebuild the stage-6 result from its stored record."""
    v, a = record.variables, record.attrs
    quad = QuadratureChoice(
        json.loads(a["quadrature_knobs"]),
        json.loads(a["quadrature_ladder"]),
        v["quadrature_relative_change"].data,
        v["quadrature_seconds"].data,
        str(a["quadrature_reason"]),
    )
    return FrictionPrediction(
        normal_load=record.coords["normal_load"].data,
        curves={name: v[name].data for name in CURVE_FIELDS},
        scalars={name: v[name].data for name in CURVE_SCALARS},
        converged=v["converged"].data.astype(bool),
        messages=str(a.get("messages", "")).split("\n"),
        mode_mixity=float(a["mode_mixity"]),
        shear_strength=float(a["shear_strength"]),
        nominal_area=float(a["nominal_area"]),
        quadrature=quad,
    )
