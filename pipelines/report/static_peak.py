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
its largest point: it never showed its peak), A_r at that point and A_r there over A_r at the
curve's first point.
"""

from __future__ import annotations

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
        A_r there / A_r at the curve's first point (1).
    ends_rising : bool
        The largest F_x is the curve's last point: the peak was not reached, the static
        friction is a lower bound.
    """

    normal_load: float
    static_friction: float
    peak_real_area: float
    real_area_drop: float
    ends_rising: bool


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
        out[int(np.argmin(np.abs(loads - curve.normal_load)))] = MeasuredPeak(
            float(curve.normal_load),
            float(fx[peak]),
            float(area[peak]),
            float(area[peak] / area[0]) if area[0] > 0 else float("nan"),
            peak == fx.size - 1 and fx.size > 1,
        )
    return out
