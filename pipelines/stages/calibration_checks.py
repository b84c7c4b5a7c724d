"""The measured A_r(F_x) curves' consistency with the model beyond one scale factor.

The lambda fit's shape mode lets each measured curve carry a factor c (A_measured ~ c A_model):
a level 20 % off leaves lambda untouched (paper, Fig 13: the model underestimates the area at
low loads). But an area calibration error (x 1.2 or x 0.9: the image's pixel size or
magnification) and an additive offset (+0.2 A_r(F_x = 0) on every point: the contact-detection
threshold of the image analysis) both show as c ~ 1.2, and the fit absorbs either without a
trace. Two checks, each with its verdict code (warnings; thresholds here):

The numbers are :mod:`asperity.statmodel.calibration_checks`' (for a notebook user as well);
this module words them as the verdict's reasons.

* ``measured_area_scale``: a curve's A_r(F_x = 0), c times the model's, at least
  :data:`SCALE_TOLERANCE` (10 %) from the model beyond the model's own one-sigma relative
  uncertainty at F_x = 0 at that load (``friction.model_real_area_uncertainty``). The file then
  shows either a scale error or an offset; which one the shape cannot tell (the lambda fit tried
  both: :mod:`asperity.statmodel.lambda_fit`), so lambda's interval is widened over both
  readings, and the reason states both lambdas and what to check. Curves the ``shape_scale``
  reason already names (c outside [0.82, 1.22]) are left to it.
* ``measured_area_offset``: the offset reading (A_model + d) fits the curves better than the
  scale reading by more than :data:`OFFSET_DELTA_CHI2` (Delta chi^2, residual variance from the
  better fit): the drop's shape itself points to an additive offset.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.statmodel import calibration_checks as checks
from asperity.statmodel.calibration_checks import (
    OFFSET_DELTA_CHI2,
    SCALE_TOLERANCE,
    SHAPE_SCALE_BAND,
)

__all__ = [
    "OFFSET_DELTA_CHI2",
    "SCALE_TOLERANCE",
    "SHAPE_SCALE_BAND",
    "model_relative_uncertainty",
    "offset_reasons",
    "scale_reasons",
]


def model_relative_uncertainty(friction: object, load: float) -> float:
    """u(A_model)/A_model at F_x = 0 at the configured load nearest ``load`` (N) of the
    friction stage's result (0 when it did not estimate it):
    :func:`asperity.statmodel.calibration_checks.model_relative_uncertainty`."""
    return checks.model_relative_uncertainty(
        getattr(friction, "normal_load", ()),
        getattr(friction, "model_real_area", None),
        getattr(friction, "model_real_area_uncertainty", None),
        load,
    )


def _interval_text(interval: object) -> str:
    low, high = (float(v) for v in np.asarray(interval, dtype=float))
    fmt = lambda v: f"{v:.3g}" if math.isfinite(v) else "unbounded"  # noqa: E731
    return f"[{fmt(low)}, {fmt(high)}]"


def _readings_text(choice: object) -> str:
    """Both readings' lambdas and intervals, and the interval reported."""
    offset = getattr(choice, "offset_mode_mixity", None)
    if offset is None or not math.isfinite(offset):
        return ""
    return (
        f"; lambda read as a scale error {choice.mode_mixity:.3g} "
        f"{_interval_text(choice.shape_interval)}, as an offset {offset:.3g} "
        f"{_interval_text(choice.offset_interval)}: the interval reported, "
        f"[{choice.interval_low:.3g}, {choice.interval_high:.3g}], holds both"
    )


def scale_reasons(choice: object, friction: object) -> list[tuple[str, str, str]]:
    """``measured_area_scale`` (code, severity, text) for the curves whose level is
    :data:`SCALE_TOLERANCE` or more from the model's beyond its uncertainty."""
    scales = getattr(choice, "shape_scale", None)
    loads = getattr(choice, "shape_scale_normal_load", None)
    if not getattr(choice, "fitted", False) or scales is None or loads is None:
        return []
    if getattr(choice, "fit_mode", "shape") != "shape":
        return []
    flagged = [
        f"c = {c:.3g} at F_z = {load:.4g} N (model's own u {100 * u:.2g} %)"
        for c, load, u in checks.scale_outliers(
            scales, loads, lambda f: model_relative_uncertainty(friction, f)
        )
    ]
    if not flagged:
        return []
    text = (
        f"the measured A_r(F_x = 0) is {SCALE_TOLERANCE:.0%} or more from the model's at the "
        f"same load beyond the model's own uncertainty ({'; '.join(flagged)}): the file shows "
        "an area calibration error (x c: check the image's pixel size and magnification) or an "
        "additive offset (+ (c - 1) A_r(0) on every point: check the contact-detection "
        "threshold), which the drop's shape cannot tell apart"
    )
    return [("measured_area_scale", "warning", text + _readings_text(choice))]


def offset_reasons(choice: object) -> list[tuple[str, str, str]]:
    """``measured_area_offset`` when the offset reading fits better by more than
    :data:`OFFSET_DELTA_CHI2`."""
    offset_rms = getattr(choice, "offset_residual_rms", None)
    rms, n = getattr(choice, "residual_rms", None), getattr(choice, "n_points", None)
    if offset_rms is None or rms is None or not n or not math.isfinite(offset_rms):
        return []
    curves = len(np.atleast_1d(choice.shape_scale))
    delta = checks.offset_delta_chi2(rms, offset_rms, n, curves)
    if delta <= OFFSET_DELTA_CHI2:
        return []
    fractions = ", ".join(f"{100 * d:.3g} %" for d in np.atleast_1d(choice.offset_fraction))
    text = (
        f"the measured A_r(F_x) curves fit an additive offset (A_model + d; d = {fractions} of "
        f"the model's A_r(F_x = 0)) better than a scale factor (Delta chi^2 = {delta:.3g} > "
        f"{OFFSET_DELTA_CHI2:g}): the drop is flatter than the model's at any lambda; check "
        "the contact-detection threshold of the image analysis" + _readings_text(choice)
    )
    return [("measured_area_offset", "warning", text)]
