"""Uncertainty of the model's predictions per load, propagated from its two calibrated inputs.

The statistical model's A_r (E:Ar_Greenwood), static friction, sliding friction and sliding
displacement (E:NewFormulation_Fx, :func:`statmodel.shear_curve`) at each normal load depend on
two calibrated inputs, each known within an interval:

* the roughness (eta, R, sigma_s) over the effective resolution's interval
  (:func:`statmodel.effective_resolution.locate_least_misfit`, the statistics at its ends from
  :func:`statmodel.effective_resolution.roughness_at_resolution`);
* the mode mixity lambda over its one-sigma profile interval (the lambda fit). A configured
  lambda (an interval of zero width, ends equal to lambda) carries no uncertainty: the message
  says that lambda is assumed and left out of u.

Rule (:func:`propagate_to_predictions`): the model is evaluated at the optimum and at both ends
of each interval, the other input held at its optimum. The part of a source is the largest
excursion from the optimum, ``u_i = max(|f(low) - f(opt)|, |f(high) - f(opt)|)``: for an output
monotone in the input it bounds the output of every input inside the interval, and it equals
half the envelope when the optimum lies midway. The two sources are independent and add in
quadrature, ``u = sqrt(u_roughness^2 + u_lambda^2)`` (GUM); the value is the model at both
optima. A_r at F_x = 0 and the sliding friction (tau0 times the Hertz area of the all-sliding
state) do not depend on lambda: their lambda part is 0.

Non-finite cases are stated, never hidden: an interval end that is not known (NaN or inf)
makes the parts that depend on it infinite; an interval open on a side (the optimum at an end
of the resolution scan) makes u a lower bound (``lower_bound``, status 1); a sliding
displacement that is infinite at the optimum (no full sliding, e.g. lambda = 0) has NaN
uncertainty.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from asperity.errors import InputError
from asperity.statmodel.parameters import Material, Roughness
from asperity.statmodel.preloading import real_area_at_loads
from asperity.statmodel.shear import shear_curve

#: ``curve(material, roughness, normal_load) -> ShearCurve`` (static_friction N,
#: sliding_friction N, sliding_displacement m).
CurveFunction = Callable[[Material, Roughness, float], Any]

#: The predictions with an uncertainty, and their units.
PREDICTIONS: dict[str, str] = {
    "real_area": "m^2",
    "static_friction": "N",
    "sliding_friction": "N",
    "sliding_displacement": "m",
}

#: ``PredictionUncertainty.status`` codes.
PREDICTION_STATUS: dict[int, str] = {
    0: "every uncertainty finite and from closed intervals",
    1: "some uncertainty is a lower bound (an open interval) or not finite",
}


@dataclass(frozen=True)
class PredictionUncertainty:
    """Per-load model predictions with their uncertainties (rule in the module notes).

    Attributes
    ----------
    normal_load : ndarray
        F_z, N.
    value : dict of str to ndarray
        Per :data:`PREDICTIONS` name, the model at both optima: ``real_area`` (m^2),
        ``static_friction`` (N), ``sliding_friction`` (N), ``sliding_displacement`` (m).
    uncertainty : dict of str to ndarray
        Same keys and units: ``sqrt(u_roughness^2 + u_lambda^2)``.
    parts : dict of str to dict of str to ndarray
        Per prediction, ``{"roughness": u, "mode_mixity": u}`` (same units).
    lower_bound : bool
        An interval was open on a side: u is a lower bound.
    success : bool
        Status 0.
    status : int
        One of :data:`PREDICTION_STATUS`.
    message : str
        What limits the uncertainties, in one sentence.
    """

    normal_load: np.ndarray
    value: dict[str, np.ndarray] = field(repr=False)
    uncertainty: dict[str, np.ndarray] = field(repr=False)
    parts: dict[str, dict[str, np.ndarray]] = field(repr=False)
    lower_bound: bool
    success: bool
    status: int
    message: str


def largest_excursion(optimum: np.ndarray, *ends: np.ndarray) -> np.ndarray:
    """``max |f(end) - f(optimum)|`` over the ends, elementwise (the part of one source).

    NaN where the optimum is not finite; inf where it is and an end is not.
    """
    optimum = np.asarray(optimum, dtype=float)
    with np.errstate(invalid="ignore"):
        gaps = [np.abs(np.asarray(e, dtype=float) - optimum) for e in ends]
        part = np.max(np.where(np.isnan(gaps), np.inf, gaps), axis=0)
    return np.where(np.isfinite(optimum), part, np.nan)


def _predictions(
    curve: CurveFunction,
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    loads: np.ndarray,
) -> dict[str, np.ndarray]:
    """The four predictions per load at one (material, roughness)."""
    curves = [curve(material, roughness, float(f)) for f in loads]
    out = {
        name: np.array([float(getattr(c, name)) for c in curves])
        for name in ("static_friction", "sliding_friction", "sliding_displacement")
    }
    out["real_area"] = np.asarray(real_area_at_loads(material, roughness, nominal_area, loads))
    return out


def _lambda_ends(material: Material, interval: tuple[float, float]) -> list[Material | None]:
    """The material at each end of lambda's interval (None where the end is not known)."""
    ends = []
    for end in interval:
        known = end is not None and math.isfinite(end)
        ends.append(dataclasses.replace(material, mode_mixity=float(end)) if known else None)
    return ends


def _check_loads(normal_loads: ArrayLike) -> np.ndarray:
    loads = np.atleast_1d(np.asarray(normal_loads, dtype=float))
    if loads.ndim != 1 or loads.size == 0 or not np.all(np.isfinite(loads)):
        raise InputError(f"normal_loads: expected finite loads in N, got {loads.tolist()}")
    return loads


def _default_curve(nominal_area: float, tangential_displacement: ArrayLike | None) -> CurveFunction:
    """:func:`statmodel.shear_curve` on the given path (m)."""
    if tangential_displacement is None:
        raise InputError(
            "propagate_to_predictions: expected curve= or tangential_displacement= (m), got neither"
        )
    path = np.asarray(tangential_displacement, dtype=float)

    def curve(material: Material, roughness: Roughness, load: float) -> Any:
        return shear_curve(material, roughness, nominal_area, load, path)

    return curve


def propagate_to_predictions(
    material: Material,
    roughness: Roughness,
    roughness_interval: Sequence[Roughness],
    mode_mixity_interval: tuple[float, float],
    nominal_area: float,
    normal_loads: ArrayLike,
    *,
    tangential_displacement: ArrayLike | None = None,
    curve: CurveFunction | None = None,
    interval_open: bool = False,
) -> PredictionUncertainty:
    """The model's A_r, static and sliding friction and sliding displacement per load, +- u.

    Parameters
    ----------
    material : Material
        E* (Pa), w (J/m^2), tau0 (Pa), epsilon (m) and the best lambda (``mode_mixity``).
    roughness : Roughness
        eta (1/m^2), R (m), sigma_s (m) at the effective resolution.
    roughness_interval : sequence of two Roughness
        The statistics at the finer and coarser ends of the effective resolution's interval.
    mode_mixity_interval : (float, float)
        lambda's one-sigma interval (NaN or inf where an end is not known).
    nominal_area : float
        A_n, m^2.
    normal_loads : array_like
        F_z, N.
    tangential_displacement : array_like, optional
        The shear path (m) of :func:`statmodel.shear_curve`, from 0 and past full sliding.
    curve : callable, optional
        ``curve(material, roughness, normal_load)`` giving a shear curve (the pipeline's own
        path choice); replaces ``tangential_displacement``.
    interval_open : bool
        The effective resolution's interval is open on a side (its end is the scan's end).

    Returns
    -------
    PredictionUncertainty
    """
    loads = _check_loads(normal_loads)
    if len(roughness_interval) != 2:
        raise InputError(
            f"roughness_interval: expected the statistics at the two ends of the interval, "
            f"got {len(roughness_interval)}"
        )
    curve = curve or _default_curve(nominal_area, tangential_displacement)
    best = _predictions(curve, material, roughness, nominal_area, loads)
    by_roughness = [
        _predictions(curve, material, r, nominal_area, loads) for r in roughness_interval
    ]
    by_lambda = [
        None if m is None else _predictions(curve, m, roughness, nominal_area, loads)
        for m in _lambda_ends(material, mode_mixity_interval)
    ]
    assumed = all(
        end is not None and float(end) == material.mode_mixity for end in mode_mixity_interval
    )
    return _assemble(loads, best, by_roughness, by_lambda, interval_open, assumed)


def _assemble(
    loads: np.ndarray,
    best: dict[str, np.ndarray],
    by_roughness: list[dict[str, np.ndarray]],
    by_lambda: list[dict[str, np.ndarray] | None],
    interval_open: bool,
    lambda_assumed: bool = False,
) -> PredictionUncertainty:
    """Parts, their quadrature sum and the status."""
    parts: dict[str, dict[str, np.ndarray]] = {}
    for name in PREDICTIONS:
        rough = largest_excursion(best[name], *(r[name] for r in by_roughness))
        if name in ("real_area", "sliding_friction"):
            lam = np.where(np.isfinite(best[name]), 0.0, np.nan)
        else:
            ends = [np.full(loads.shape, np.nan) if e is None else e[name] for e in by_lambda]
            lam = largest_excursion(best[name], *ends)
        parts[name] = {"roughness": rough, "mode_mixity": lam}
    total = {n: np.sqrt(p["roughness"] ** 2 + p["mode_mixity"] ** 2) for n, p in parts.items()}
    notes = [
        f"{name}: {int(np.sum(~np.isfinite(u)))} of {u.size} loads without a finite uncertainty"
        for name, u in total.items()
        if not np.all(np.isfinite(u))
    ]
    if interval_open:
        notes.insert(0, "the effective resolution's interval is open: u is a lower bound")
    status = 1 if notes else 0
    lam_text = (
        "lambda assumed (configured, not fitted: it carries no uncertainty and u leaves it out)"
        if lambda_assumed
        else "lambda over its interval"
    )
    if notes:
        message = "; ".join([*notes, lam_text] if lambda_assumed else notes)
    else:
        message = (
            f"roughness over the effective resolution's interval and {lam_text}, "
            "largest excursion each, in quadrature"
        )
    return PredictionUncertainty(
        normal_load=loads,
        value=best,
        uncertainty=total,
        parts=parts,
        lower_bound=bool(interval_open),
        success=status == 0,
        status=status,
        message=message,
    )
