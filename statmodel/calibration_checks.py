"""Is a measured A_r(F_x) set consistent with the model beyond one scale factor per curve?

The lambda fit's shape mode (:mod:`asperity.statmodel.lambda_fit`) lets each measured curve
carry a factor c (A_measured ~ c A_model, the model's A_r from E:PC_indent's stick population):
a level 20 % off leaves lambda untouched (paper, Fig 13: the model underestimates the area at
low loads). But an area calibration error (x 1.2 or x 0.9: the image's pixel size or
magnification) and an additive offset (+0.2 A_r(F_x = 0) on every point: the contact-detection
threshold of the image analysis) both show as c ~ 1.2, and the fit absorbs either without a
trace. The two tests here (the numbers; the verdict's wording is in
:mod:`asperity.pipelines.stages.calibration_checks`):

* :func:`scale_outliers`: the curves whose factor c lies :data:`SCALE_TOLERANCE` (10 %) or more
  from 1 beyond the model's own one-sigma relative uncertainty of A_r at F_x = 0 at that load,
  inside the band :data:`SHAPE_SCALE_BAND` (farther factors are named by the fit itself).
* :func:`offset_delta_chi2`: by how much the offset reading (A_model + d) fits the curves
  better than the scale reading, Delta chi^2 with the residual variance of the better fit;
  above :data:`OFFSET_DELTA_CHI2` the drop's shape itself points to an additive offset.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "OFFSET_DELTA_CHI2",
    "SCALE_TOLERANCE",
    "SHAPE_SCALE_BAND",
    "model_relative_uncertainty",
    "offset_delta_chi2",
    "scale_outliers",
]

#: A measured level this far from the model (|c - 1|, beyond the model's own uncertainty).
SCALE_TOLERANCE = 0.10
#: Delta chi^2 by which the offset reading must fit better to be named (two sigma).
OFFSET_DELTA_CHI2 = 4.0
#: The band of c the fit's own ``shape_scale`` reason leaves silent (exp(+-0.2)).
SHAPE_SCALE_BAND = (math.exp(-0.2), math.exp(0.2))


def model_relative_uncertainty(
    normal_load: ArrayLike,
    model_area: ArrayLike | None,
    model_area_uncertainty: ArrayLike | None,
    load: float,
) -> float:
    """u(A_model) / A_model at F_x = 0 at the load of ``normal_load`` (N) nearest ``load`` (N).

    Parameters
    ----------
    normal_load : array
        The loads F_z (N) the model's A_r at F_x = 0 is known at.
    model_area, model_area_uncertainty : array or None
        That A_r (m^2) and its one-sigma uncertainty (m^2) per load; None: not estimated.
    load : float
        The measured curve's F_z, N.

    Returns
    -------
    float
        The relative uncertainty (1); 0 when not estimated or not finite.
    """
    if model_area is None or model_area_uncertainty is None:
        return 0.0
    area = np.asarray(model_area, dtype=float)
    band = np.asarray(model_area_uncertainty, dtype=float)
    i = int(np.argmin(np.abs(np.asarray(normal_load, dtype=float) - load)))
    value = float(band[i]) / float(area[i]) if float(area[i]) > 0 else math.nan
    return value if math.isfinite(value) else 0.0


def scale_outliers(
    scales: ArrayLike, loads: ArrayLike, relative_uncertainty: Callable[[float], float]
) -> list[tuple[float, float, float]]:
    """The curves whose shape-fit factor c is :data:`SCALE_TOLERANCE` or more from 1 beyond
    the model's own relative uncertainty, within :data:`SHAPE_SCALE_BAND`.

    Parameters
    ----------
    scales : array
        The factor c per measured curve (1).
    loads : array
        Each curve's F_z, N.
    relative_uncertainty : callable
        ``u(load)``: the model's relative uncertainty of A_r at F_x = 0 at a load (N), 1.

    Returns
    -------
    list of (c, F_z, u)
        The flagged curves in their order: factor (1), load (N), the model's u there (1).
    """
    low, high = SHAPE_SCALE_BAND
    flagged = []
    for c, load in zip(np.asarray(scales, float), np.asarray(loads, float), strict=True):
        u = relative_uncertainty(load)
        if low <= c <= high and abs(c - 1.0) >= SCALE_TOLERANCE + u:
            flagged.append((float(c), float(load), float(u)))
    return flagged


def offset_delta_chi2(
    residual_rms: float, offset_residual_rms: float, n_points: int, n_curves: int
) -> float:
    """Delta chi^2 of the scale reading over the offset reading of one lambda fit.

    chi^2 of each reading is n rms^2 over the residual variance of the better one, with
    n - 1 - n_curves degrees of freedom (lambda and a factor or offset per curve).

    Parameters
    ----------
    residual_rms, offset_residual_rms : float
        The rms relative residuals (1) of the scale and of the offset reading.
    n_points : int
        Measured points fitted.
    n_curves : int
        Measured curves (one factor or offset each).

    Returns
    -------
    float
        Delta chi^2 (positive: the offset reading fits better); 0 for a zero variance.
    """
    n = n_points
    variance = min(residual_rms, offset_residual_rms) ** 2 * n / max(n - 1 - n_curves, 1)
    return n * (residual_rms**2 - offset_residual_rms**2) / variance if variance > 0 else 0.0
