"""The per-load table's static-peak columns: the friction coefficient, A_r at the static peak
and the area drop (the paper's Fig 13 observation), predicted and, with measured A_r(F_x)
curves, measured.

Predicted (stored in ``results.h5``, group ``friction``, and on the friction stage's result,
derived from each shear curve by
:func:`asperity.pipelines.stages.friction.static_peak_quantities`):

* ``static_friction_coefficient`` mu_s = F_s / F_z (1), with
  ``static_friction_coefficient_uncertainty`` = u(F_s) / F_z (F_z is imposed, exact);
* ``static_peak_real_area`` A_r at the static peak (m^2): the curve A_r(delta_T) at the
  peak's delta_T;
* ``real_area_drop`` A_r(peak) / A_r(F_x = 0) (1): 0.938 at 0.56 N on the default job.

Measured (from the stored measured curves, group ``mode_mixity``; nothing new stored): per
curve, its largest F_x (the measured static friction; written ``>= F`` when the curve ends on
its largest point: it never showed its peak), A_r at that point and the area drop
A_r(peak) / A_r(F_x = 0) with its one-sigma uncertainty from a least-squares fit of the stick
branch (:func:`stick_branch_drop`: the points up to the peak, A_r = a0 + a1 F_x + a2 F_x^2,
the quadratic decrease Sahli et al. measured and the paper's Section 5 discusses), not the
ratio of two single noisy points. At 2 % noise on a 0.94 drop the two-point ratio scatters
over 0.89 .. 1.01; the fit's value stays within its stated +- u.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity.pipelines.report._run import Run


@dataclass(frozen=True)
class MeasuredPeak:
    """The static peak of one measured A_r(F_x) curve (SI).

    Attributes
    ----------
    normal_load : float
        F_z of the curve, N.
    static_friction : float
        The largest measured F_x, N.
    peak_real_area : float
        A_r at that point, m^2.
    real_area_drop : float
        A_r(peak) / A_r(F_x = 0) of the stick branch's fit (1; :func:`stick_branch_drop`).
    ends_rising : bool
        The largest F_x is the curve's last point: the peak was not reached, the static
        friction is a lower bound.
    real_area_drop_uncertainty : float
        One-sigma uncertainty of the drop from the fit's covariance (1; NaN with too few
        points to estimate it).
    """

    normal_load: float
    static_friction: float
    peak_real_area: float
    real_area_drop: float
    ends_rising: bool
    real_area_drop_uncertainty: float = math.nan


#: Points of the stick branch from which a quadratic (else a straight line) is fitted.
QUADRATIC_POINTS = 5
LINE_POINTS = 3


def stick_branch_drop(force: np.ndarray, area: np.ndarray) -> tuple[float, float]:
    """The area drop A_r(F_peak) / A_r(0) and its one-sigma uncertainty from a least-squares
    polynomial fit of the stick branch (``force``, N, and ``area``, m^2, from the first point
    to the peak, in acquisition order): degree 2 from :data:`QUADRATIC_POINTS` points, 1 from
    :data:`LINE_POINTS`, else the two-point ratio with NaN uncertainty. The uncertainty is the
    delta method on the coefficients' covariance s^2 (X^T X)^-1, s^2 the residual variance."""
    force, area = np.asarray(force, dtype=float), np.asarray(area, dtype=float)
    n = force.size
    if n < LINE_POINTS or area[0] <= 0:
        ratio = float(area[-1] / area[0]) if area[0] > 0 else math.nan
        return ratio, math.nan
    degree = 2 if n >= QUADRATIC_POINTS else 1
    scale = float(np.max(np.abs(force))) or 1.0  # conditioning: F in units of the peak
    x = np.vander(force / scale, degree + 1, increasing=True)
    beta, *_ = np.linalg.lstsq(x, area, rcond=None)
    residual = area - x @ beta
    variance = float(residual @ residual) / (n - degree - 1)
    cov = variance * np.linalg.pinv(x.T @ x)
    at_peak = np.vander([force[-1] / scale], degree + 1, increasing=True)[0]
    if beta[0] <= 0:
        return math.nan, math.nan
    drop = float(at_peak @ beta / beta[0])
    gradient = at_peak / beta[0]
    gradient[0] -= drop / beta[0]
    return drop, float(math.sqrt(max(float(gradient @ cov @ gradient), 0.0)))


def measured_peaks(result: Run) -> dict[int, MeasuredPeak]:
    """{load index: the measured curve's static peak} for the loads that have a measured
    A_r(F_x) curve (the curve's load matched to the nearest configured load)."""
    fr = result.friction
    loads = np.asarray(fr.normal_load, dtype=float)
    out: dict[int, MeasuredPeak] = {}
    for curve in getattr(result.mode_mixity, "curves", None) or []:
        fx = np.asarray(curve.tangential_force, dtype=float)
        area = np.asarray(curve.real_area, dtype=float)
        keep = np.isfinite(fx) & np.isfinite(area)
        if not keep.any():
            continue
        fx, area = fx[keep], area[keep]
        peak = int(np.argmax(fx))
        drop, drop_u = stick_branch_drop(fx[: peak + 1], area[: peak + 1])
        out[int(np.argmin(np.abs(loads - curve.normal_load)))] = MeasuredPeak(
            float(curve.normal_load),
            float(fx[peak]),
            float(area[peak]),
            drop,
            peak == fx.size - 1 and fx.size > 1,
            drop_u,
        )
    return out
