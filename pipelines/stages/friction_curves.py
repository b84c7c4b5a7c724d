"""The friction-test stage: measured F_x(drive) against the model seen through the drive's spring.

For each measured friction test (``measured.friction_curves``) the friction stage's shear curve
at that load (E:NewFormulation_Fx, the lambda of the lambda stage) is mapped to the drive,
drive = delta_T + F_x / k with k = ``loading.drive_stiffness`` (absent: rigid), and its
stick-slip jumps found where dF_x/d delta_T < -k (:func:`asperity.statmodel.drive_curve`). The
comparison, per test, with uncertainties (one sigma):

* the static friction F_s: measured, the largest F_x up to the first static peak (where F_x
  first falls below its running maximum by six noise levels,
  :func:`asperity.statmodel.lambda_fit_friction.peak_end`), its uncertainty the test's noise
  (:func:`asperity.statmodel.lambda_fit_friction.noise_level`); predicted, the model's peak
  with the friction stage's uncertainty (the roughness's and lambda's intervals) or, without
  it, the spread over lambda's interval;
* the drive displacement at the peak: measured, from the test's first point (the drive's
  origin, :attr:`asperity.pipelines.measured_friction.FrictionCurve.drive_from_start`), its
  uncertainty half the drive span of the points within the noise of F_s, at least the drive
  step to the next point (the peak may lie anywhere before it); predicted,
  delta_s + F_s / k, its uncertainty the spread over lambda's interval (the model re-run at
  the interval's ends: half the difference);
* the sliding friction F_d where the test slides: measured, the mean F_x of the points after
  the first peak (stick-slip cycles included), its uncertainty their standard deviation (NaN
  when the test stops at its peak); predicted, tau0 A_r^Hertz, the all-sliding limit, with
  the friction stage's uncertainty.

Where the job runs the shear BEM (``[bem_shear]``) at a test's load, the BEM's F_x(delta_T) (the
grid used) is mapped to the drive the same way, with its own jumps.

SI units throughout: m, N, N/m.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from asperity import statmodel
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.measured_friction import FrictionCurve
from asperity.pipelines.stages.bem_shear import BEM_SHEAR, BemShearComparison
from asperity.pipelines.stages.friction import (
    FRICTION,
    MODE_MIXITY,
    FrictionPrediction,
    mode_mixity_interval,
)
from asperity.pipelines.stages.statistical_model import STATISTICAL_MODEL
from asperity.statmodel.lambda_fit_friction import noise_level, peak_end
from asperity.statmodel.shear_path import model_drive_curve


@document_fields
@dataclass
class FrictionTestComparison:
    """Stage result: measured friction tests F_x(drive) against the model through the spring.

    Per test (dimension ``friction_test``): the load, the measured and predicted static
    friction, drive at the peak and sliding friction with their one-sigma uncertainties
    (module docstring), and the predicted first stick-slip jump. Per measured point
    (``friction_point``): the test it belongs to, the drive from the test's start, the measured
    and the predicted F_x (the drive-controlled path, jumps included). Per test and model point
    (``model_point``, NaN-padded): the model's whole quasi-static curve seen from the drive,
    unstable parts included (``model_stable`` 0 there). With the shear BEM (stage ``bem_shear``)
    at a test's load, its curve (grid used) mapped the same way (``bem_*``; NaN elsewhere).
    """

    drive_stiffness: float = scalar("N/m", "loading system's stiffness k (inf: rigid)")
    mode_mixity: float = scalar("1", "lambda of the prediction")
    normal_load: np.ndarray = array("N", ("friction_test",), "normal load of the test")
    measured_static_friction: np.ndarray = array("N", ("friction_test",), "measured F_s")
    measured_static_friction_uncertainty: np.ndarray = array(
        "N", ("friction_test",), "its uncertainty (the test's noise)"
    )
    predicted_static_friction: np.ndarray = array("N", ("friction_test",), "model F_s")
    predicted_static_friction_uncertainty: np.ndarray = array(
        "N", ("friction_test",), "its uncertainty"
    )
    measured_static_drive: np.ndarray = array(
        "m", ("friction_test",), "measured drive at the peak, from the test's start"
    )
    measured_static_drive_uncertainty: np.ndarray = array(
        "m", ("friction_test",), "its uncertainty"
    )
    predicted_static_drive: np.ndarray = array(
        "m", ("friction_test",), "model drive at the peak, delta_s + F_s / k"
    )
    predicted_static_drive_uncertainty: np.ndarray = array(
        "m", ("friction_test",), "its uncertainty (lambda's interval)"
    )
    measured_sliding_friction: np.ndarray = array(
        "N", ("friction_test",), "measured F_d: mean F_x after the first peak (NaN: none)"
    )
    measured_sliding_friction_uncertainty: np.ndarray = array(
        "N", ("friction_test",), "standard deviation of those points"
    )
    predicted_sliding_friction: np.ndarray = array("N", ("friction_test",), "model F_d")
    predicted_sliding_friction_uncertainty: np.ndarray = array(
        "N", ("friction_test",), "its uncertainty"
    )
    measured_noise: np.ndarray = array("N", ("friction_test",), "noise of the measured F_x")
    predicted_stick_slip: np.ndarray = array(
        "1", ("friction_test",), "the model predicts a stick-slip jump"
    )
    predicted_jump_drive: np.ndarray = array(
        "m", ("friction_test",), "drive of the first jump (NaN: none)"
    )
    predicted_jump_force_drop: np.ndarray = array(
        "N", ("friction_test",), "F_x drop of the first jump (NaN: none)"
    )
    predicted_jump_force_after: np.ndarray = array(
        "N", ("friction_test",), "F_x after the first jump (NaN: none)"
    )
    point_test: np.ndarray = array("1", ("friction_point",), "index of the point's test")
    point_drive: np.ndarray = array("m", ("friction_point",), "drive from the test's start")
    point_force: np.ndarray = array("N", ("friction_point",), "measured F_x")
    point_predicted_force: np.ndarray = array(
        "N", ("friction_point",), "model F_x on the drive-controlled path"
    )
    model_drive: np.ndarray = array("m", ("friction_test", "model_point"), "model drive")
    model_force: np.ndarray = array("N", ("friction_test", "model_point"), "model F_x")
    model_stable: np.ndarray = array(
        "1", ("friction_test", "model_point"), "stable under drive control (1), else 0"
    )
    sources: list[str] = text("file of each test")
    uncertainty_message: str = text("what the uncertainties hold")
    bem_drive: np.ndarray | None = array(
        "m", ("friction_test", "bem_step"), "shear BEM's curve: drive (NaN: none)", optional=True
    )
    bem_force: np.ndarray | None = array(
        "N", ("friction_test", "bem_step"), "shear BEM's curve: F_x", optional=True
    )
    bem_static_drive: np.ndarray | None = array(
        "m", ("friction_test",), "shear BEM's drive at its peak (NaN: none)", optional=True
    )
    bem_stick_slip: np.ndarray | None = array(
        "1", ("friction_test",), "the BEM's curve jumps through the spring", optional=True
    )
    bem_jump_drive: np.ndarray | None = array(
        "m", ("friction_test",), "drive of the BEM's first jump (NaN: none)", optional=True
    )
    bem_jump_force_drop: np.ndarray | None = array(
        "N", ("friction_test",), "F_x drop of the BEM's first jump (NaN: none)", optional=True
    )


def measured_peak(curve: FrictionCurve) -> dict[str, float]:
    """F_s (N), the drive at it (m, from the start), their uncertainties, the noise (N), and
    the sliding friction after the peak (N) with its spread (module docstring)."""
    force, drive = np.asarray(curve.tangential_force, float), curve.drive_from_start
    end = peak_end(force)
    i = int(np.argmax(force[:end]))
    noise = noise_level(force)
    near = np.flatnonzero(force[:end] >= force[i] - (noise if math.isfinite(noise) else 0.0))
    # the peak lies anywhere up to the next sample (after which F_x may have dropped)
    step = float(drive[i + 1] - drive[i]) if i + 1 < drive.size else 0.0
    drive_u = max(0.5 * float(drive[near].max() - drive[near].min()), step)
    tail = force[end:]
    return {
        "static_friction": float(force[i]),
        "static_friction_uncertainty": noise,
        "static_drive": float(drive[i]),
        "static_drive_uncertainty": drive_u,
        "noise": noise,
        "sliding_friction": float(np.mean(tail)) if tail.size >= 3 else math.nan,
        "sliding_friction_uncertainty": float(np.std(tail)) if tail.size >= 3 else math.nan,
    }


def peak_displacement(dts: np.ndarray, force: np.ndarray) -> float:
    """delta_T (m) of the peak of F_x (N) sampled on equal steps: the vertex of the parabola
    through the largest F_x and its neighbours (within half a step of it), the step itself at
    an end of the path (the friction stage stores the refined F_s, not its delta_T)."""
    finite = np.isfinite(force)
    k = int(np.nanargmax(np.where(finite, force, -np.inf)))
    if k == 0 or k == force.size - 1 or not np.all(finite[k - 1 : k + 2]):
        return float(dts[k])
    f0, f1, f2 = force[k - 1 : k + 2]
    curvature = f0 - 2 * f1 + f2
    t = 0.0 if curvature >= 0 else float(np.clip(0.5 * (f0 - f2) / curvature, -0.5, 0.5))
    step = dts[k + 1] - dts[k] if t > 0 else dts[k] - dts[k - 1]
    return float(dts[k] + t * step)


def stacked_field(friction: FrictionPrediction, name: str) -> np.ndarray:
    """A per-load field of the friction stage that :func:`asperity.fields.stacked` adds from
    :class:`statmodel.ShearCurve` (``tangential_force``, ``static_friction``, ...), SI."""
    return np.asarray(getattr(friction, name), dtype=np.float64)


def _stored_curve(friction: FrictionPrediction, index: int, k: float) -> statmodel.DriveCurve:
    """The friction stage's shear curve at load ``index`` seen from the drive (k in N/m)."""
    dts = stacked_field(friction, "tangential_displacement")[index]
    force = stacked_field(friction, "tangential_force")[index]
    sliding = float(stacked_field(friction, "sliding_displacement")[index])
    ends_sliding = math.isfinite(sliding) and sliding <= dts[np.isfinite(dts)][-1]
    f_d = float(stacked_field(friction, "sliding_friction")[index])
    return statmodel.map_to_drive(
        dts,
        force,
        k,
        sliding_friction=f_d if ends_sliding else math.nan,
        static_friction=float(stacked_field(friction, "static_friction")[index]),
        static_displacement=peak_displacement(dts, force),
    )


def _bem_curve(shear: BemShearComparison, load: float, k: float) -> statmodel.DriveCurve | None:
    """The shear BEM's curve (grid used) at ``load`` (N) seen from the drive (k N/m), continued
    at its sliding friction when it reached full sliding; None when the BEM did not shear that
    load (or solved fewer than two steps)."""
    loads = np.asarray(shear.normal_load, dtype=float)
    match = np.flatnonzero(np.isclose(loads, load, rtol=1e-9))
    if not match.size:
        return None
    j = int(match[0])
    dts = np.asarray(shear.tangential_displacement[j], dtype=float)
    force = np.asarray(shear.tangential_force[0, j], dtype=float)
    if np.count_nonzero(np.isfinite(force)) < 2:
        return None
    sliding = float(shear.sliding_displacement[0, j])
    slides = math.isfinite(sliding) and sliding <= np.nanmax(dts)
    return statmodel.map_to_drive(
        dts,
        force,
        k,
        sliding_friction=float(shear.sliding_friction[0, j]) if slides else math.nan,
        static_friction=float(shear.static_friction[0, j]),
        static_displacement=float(shear.static_displacement[0, j]),
    )


def _bem_fields(
    shear: BemShearComparison | None, curves: Sequence[FrictionCurve], k: float
) -> dict[str, np.ndarray]:
    """The shear BEM's curves mapped to the drive at each test's load (empty without the
    stage, or when it sheared none of the tests' loads)."""
    if shear is None:
        return {}
    mapped = [_bem_curve(shear, c.normal_load, k) for c in curves]
    if all(m is None for m in mapped):
        return {}
    nan = math.nan
    jumps = [m.jumps[0] if m is not None and m.jumps else None for m in mapped]
    return {
        "bem_drive": _padded(
            [np.full(1, nan) if m is None else m.drive_displacement for m in mapped]
        ),
        "bem_force": _padded(
            [np.full(1, nan) if m is None else m.tangential_force for m in mapped]
        ),
        "bem_static_drive": np.array(
            [nan if m is None else m.static_drive_displacement for m in mapped]
        ),
        "bem_stick_slip": np.array([nan if m is None else float(m.stick_slip) for m in mapped]),
        "bem_jump_drive": np.array([nan if j is None else j.drive_displacement for j in jumps]),
        "bem_jump_force_drop": np.array([nan if j is None else j.force_drop for j in jumps]),
    }


def _at(values: np.ndarray | None, index: int) -> float:
    return math.nan if values is None else float(np.asarray(values, dtype=float)[index])


def _padded(rows: Sequence[np.ndarray]) -> np.ndarray:
    width = max(len(r) for r in rows)
    out = np.full((len(rows), width), np.nan)
    for i, row in enumerate(rows):
        out[i, : len(row)] = row
    return out


def _lambda_spread(context: StageContext, lam: tuple[float, float], load: float, k: float):
    """(F_s N, drive at the peak m) of the model at lambda's interval ends; NaN where an end is
    unknown or equals the lambda used (a configured lambda)."""
    config = context.config
    ends = []
    for value in lam:
        if not math.isfinite(value):
            ends.append((math.nan, math.nan))
            continue
        curve = model_drive_curve(
            value,
            load,
            material=config.material,
            roughness=context.result(STATISTICAL_MODEL).roughness,
            nominal_area=config.loading.nominal_area,
            drive_stiffness=None if math.isinf(k) else k,
            max_tangential_displacement=config.loading.max_tangential_displacement,
            steps=101,
            knobs={},
        )
        ends.append((curve.static_friction, curve.static_drive_displacement))
    return ends


def compare_friction_tests(context: StageContext) -> FrictionTestComparison:
    """The stage: every measured test against the model through the spring (SI)."""
    config = context.config
    friction = context.result(FRICTION)
    choice = context.result(MODE_MIXITY)
    k = config.loading.drive_stiffness
    k = math.inf if k is None else float(k)
    lam = mode_mixity_interval(choice)
    rows: dict[str, list] = {name: [] for name in _PER_TEST}
    points: dict[str, list] = {"test": [], "drive": [], "force": [], "predicted": []}
    model_rows: dict[str, list] = {"drive": [], "force": [], "stable": []}
    for t, curve in enumerate(context.measured.friction_curves):
        j = int(np.argmin(np.abs(np.asarray(friction.normal_load) - curve.normal_load)))
        model = _stored_curve(friction, j, k)
        _test_row(
            rows, curve, model, friction, j, _lambda_spread(context, lam, curve.normal_load, k)
        )
        points["test"].append(np.full(curve.tangential_force.size, t))
        points["drive"].append(curve.drive_from_start)
        points["force"].append(curve.tangential_force)
        points["predicted"].append(model.force_at_drive(curve.drive_from_start))
        model_rows["drive"].append(model.drive_displacement)
        model_rows["force"].append(model.tangential_force)
        model_rows["stable"].append(model.stable.astype(float))
    return FrictionTestComparison(
        drive_stiffness=k,
        mode_mixity=float(choice.mode_mixity),
        **{name: np.asarray(values, dtype=float) for name, values in rows.items()},
        point_test=np.concatenate(points["test"]).astype(float),
        point_drive=np.concatenate(points["drive"]),
        point_force=np.concatenate(points["force"]),
        point_predicted_force=np.concatenate(points["predicted"]),
        model_drive=_padded(model_rows["drive"]),
        model_force=_padded(model_rows["force"]),
        model_stable=_padded(model_rows["stable"]),
        **_bem_fields(context.result(BEM_SHEAR), context.measured.friction_curves, k),
        sources=[c.source for c in context.measured.friction_curves],
        uncertainty_message=_uncertainty_message(friction, choice),
    )


_PER_TEST = (
    "normal_load",
    "measured_static_friction",
    "measured_static_friction_uncertainty",
    "predicted_static_friction",
    "predicted_static_friction_uncertainty",
    "measured_static_drive",
    "measured_static_drive_uncertainty",
    "predicted_static_drive",
    "predicted_static_drive_uncertainty",
    "measured_sliding_friction",
    "measured_sliding_friction_uncertainty",
    "predicted_sliding_friction",
    "predicted_sliding_friction_uncertainty",
    "measured_noise",
    "predicted_stick_slip",
    "predicted_jump_drive",
    "predicted_jump_force_drop",
    "predicted_jump_force_after",
)


def _half_spread(values: Sequence[float], centre: float) -> float:
    """Half the spread of ``values`` about ``centre`` (the largest excursion when one end is
    unknown); NaN when none is known."""
    known = [v for v in values if math.isfinite(v)]
    if not known:
        return math.nan
    if len(known) == 1:
        return abs(known[0] - centre)
    return 0.5 * abs(known[1] - known[0])


def _test_row(
    rows: dict[str, list],
    curve: FrictionCurve,
    model: statmodel.DriveCurve,
    friction: FrictionPrediction,
    j: int,
    ends: list[tuple[float, float]],
) -> None:
    measured = measured_peak(curve)
    spread_fs = _half_spread([e[0] for e in ends], model.static_friction)
    stage_fs = _at(friction.static_friction_uncertainty, j)
    jump = model.jumps[0] if model.jumps else None
    values = {
        "normal_load": curve.normal_load,
        "measured_static_friction": measured["static_friction"],
        "measured_static_friction_uncertainty": measured["static_friction_uncertainty"],
        "predicted_static_friction": model.static_friction,
        "predicted_static_friction_uncertainty": stage_fs if math.isfinite(stage_fs) else spread_fs,
        "measured_static_drive": measured["static_drive"],
        "measured_static_drive_uncertainty": measured["static_drive_uncertainty"],
        "predicted_static_drive": model.static_drive_displacement,
        "predicted_static_drive_uncertainty": _half_spread(
            [e[1] for e in ends], model.static_drive_displacement
        ),
        "measured_sliding_friction": measured["sliding_friction"],
        "measured_sliding_friction_uncertainty": measured["sliding_friction_uncertainty"],
        "predicted_sliding_friction": float(stacked_field(friction, "sliding_friction")[j]),
        "predicted_sliding_friction_uncertainty": _at(friction.sliding_friction_uncertainty, j),
        "measured_noise": measured["noise"],
        "predicted_stick_slip": float(model.stick_slip),
        "predicted_jump_drive": math.nan if jump is None else jump.drive_displacement,
        "predicted_jump_force_drop": math.nan if jump is None else jump.force_drop,
        "predicted_jump_force_after": math.nan if jump is None else jump.force_after,
    }
    for name, value in values.items():
        rows[name].append(value)


def _uncertainty_message(friction: FrictionPrediction, choice) -> str:
    stage = friction.static_friction_uncertainty is not None
    lam = "fitted" if choice.fitted else "configured (no interval: a zero spread)"
    return (
        "one sigma; measured F_s: the test's noise (second differences), drive at the peak: "
        "half the span within that noise (at least the step to the next point), F_d: the "
        "spread after the peak (stick-slip included); predicted F_s and F_d: "
        + (
            "the friction stage's (roughness and lambda intervals)"
            if stage
            else "lambda's interval"
        )
        + f", drive at the peak: lambda's interval only (lambda {lam})"
    )


def _has_friction_tests(config) -> bool:
    return bool(config.measured.friction_curves)


FRICTION_CURVES = Stage(
    name="friction_tests",
    title="friction tests compared",
    result=FrictionTestComparison,
    config=(
        "material",
        "loading",
        "measured.friction_curves",
    ),
    inputs=(STATISTICAL_MODEL, MODE_MIXITY, FRICTION, BEM_SHEAR),
    compute=compare_friction_tests,
    enabled=_has_friction_tests,
)

__all__ = ["FRICTION_CURVES", "FrictionTestComparison", "compare_friction_tests"]
