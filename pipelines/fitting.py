"""Fit the mode-mixity lambda to measured A_r(F_x) curves, jointly over all normal loads.

The paper (Section 5, Fig 13) calibrates lambda so that the statistical model's real contact
area under shear matches the measured shear-induced area reduction. Here the model curve
A_r(F_x) at each load is taken from delta_T = 0 up to the static friction peak (the stick
part, where F_x grows with delta_T and A_r(F_x) is single-valued), and evaluated at the
measured tangential forces by linear interpolation; measured points beyond the model's peak
are compared with the area at the peak. The residuals are relative to each curve's largest
measured area, r = (A_model - A_measured) / max(A_measured) (so every load weighs the same and
a measurement error proportional to the area gives residuals of equal variance); those of all
loads are minimised together over log10(lambda)
with :func:`scipy.optimize.least_squares`, started from the best point of a coarse log grid so
that a local minimum is not mistaken for the answer.

Uncertainty: the standard error from the Jacobian at the optimum,
sigma_q^2 = s^2 / (J^T J) with s^2 = sum(r^2) / (m - 1) and q = log10(lambda), carried to
lambda as sigma_lambda = lambda ln(10) sigma_q (one standard deviation; it assumes independent
residuals of equal variance, so it is a lower bound when the measurement errors are correlated).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from asperity.errors import InputError
from asperity.pipelines.measured import ShearAreaCurve

#: ``model(mode_mixity, normal_load) -> (tangential_force N, real_area m^2)`` along delta_T.
ShearAreaModel = Callable[[float, float], tuple[np.ndarray, np.ndarray]]
#: ``map``-like callable (builtin map or an executor's map).
MapFunction = Callable[..., Iterable]


@dataclass(frozen=True)
class LambdaFit:
    """Result of :func:`fit_mode_mixity`.

    Attributes
    ----------
    mode_mixity : float
        Best lambda.
    mode_mixity_std : float
        One-standard-deviation uncertainty of lambda (Jacobian estimate).
    residual_rms : float
        Root mean square of the relative residuals (fraction of each curve's largest area).
    n_points : int
        Number of measured points used.
    grid_mode_mixity, grid_residual_rms : ndarray
        The coarse scan: lambda values and their residual rms (fraction of A_n).
    success : bool
        The optimiser reported success.
    message : str
        The optimiser's message.
    nfev : int
        Model evaluations (each one curve per load) by the optimiser, excluding the scan.
    """

    mode_mixity: float
    mode_mixity_std: float
    residual_rms: float
    n_points: int
    grid_mode_mixity: np.ndarray
    grid_residual_rms: np.ndarray
    success: bool
    message: str
    nfev: int


def area_up_to_peak(
    tangential_force: np.ndarray, real_area: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The stick branch of a model A_r(F_x) curve: from the start up to the static peak.

    Parameters
    ----------
    tangential_force : ndarray
        F_x along delta_T, N.
    real_area : ndarray
        A_r along delta_T, m^2.

    Returns
    -------
    (ndarray, ndarray)
        F_x strictly increasing (N) and the matching A_r (m^2).
    """
    fx = np.asarray(tangential_force, dtype=float)
    ar = np.asarray(real_area, dtype=float)
    peak = int(np.nanargmax(fx))
    fx, ar = fx[: peak + 1], ar[: peak + 1]
    keep = np.concatenate([[True], np.diff(fx) > 0])
    keep &= np.concatenate([[True], fx[1:] > np.maximum.accumulate(fx)[:-1]])
    return fx[keep], ar[keep]


def interpolate_area(
    fx_model: np.ndarray, ar_model: np.ndarray, fx_measured: np.ndarray
) -> np.ndarray:
    """Model A_r (m^2) at measured tangential forces (N), held at the end values outside."""
    fx, ar = area_up_to_peak(fx_model, ar_model)
    return np.interp(fx_measured, fx, ar)


def _model_residuals(
    mode_mixity: float, curves: Sequence[ShearAreaCurve], model: ShearAreaModel, map_fn: MapFunction
) -> np.ndarray:
    loads = [c.normal_load for c in curves]
    outputs = list(map_fn(model, [mode_mixity] * len(curves), loads))
    parts = []
    for curve, (fx, ar) in zip(curves, outputs, strict=True):
        scale = float(np.max(curve.real_area)) or 1.0
        parts.append((interpolate_area(fx, ar, curve.tangential_force) - curve.real_area) / scale)
    return np.concatenate(parts)


def fit_mode_mixity(
    curves: Sequence[ShearAreaCurve],
    model: ShearAreaModel,
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    grid_points: int = 9,
    map_fn: MapFunction = map,
) -> LambdaFit:
    """Fit lambda jointly to measured A_r(F_x) curves (least squares, with uncertainty).

    Parameters
    ----------
    curves : sequence of ShearAreaCurve
        Measured curves (F_x in N, A_r in m^2), one per normal load.
    model : callable
        ``model(mode_mixity, normal_load) -> (F_x N, A_r m^2)`` along the shear path (the
        statistical model, E:NewFormulation_Fx and E:NewFormulation_Ar); must be picklable when
        ``map_fn`` is a process pool's map.
    bounds : (float, float)
        Search interval of lambda, 0 < low < high <= 1.
    grid_points : int
        Points of the coarse log-spaced scan that picks the starting value.
    map_fn : callable
        ``map``-like function used to evaluate the loads (builtin ``map``, or
        ``executor.map`` to run them in parallel).

    Returns
    -------
    LambdaFit
    """
    if not curves:
        raise InputError("fit_mode_mixity: no measured curves")
    low, high = bounds
    if not 0 < low < high <= 1:
        raise InputError(f"fit_mode_mixity: bounds must satisfy 0 < low < high <= 1, got {bounds}")
    n_points = sum(len(c.real_area) for c in curves)
    if n_points < 2:
        raise InputError("fit_mode_mixity: need at least two measured points")

    grid = np.logspace(math.log10(low), math.log10(high), grid_points)
    grid_rms = np.array(
        [float(np.sqrt(np.mean(_model_residuals(lam, curves, model, map_fn) ** 2))) for lam in grid]
    )
    start = math.log10(grid[int(np.argmin(grid_rms))])
    step = (math.log10(high) - math.log10(low)) / max(grid_points - 1, 1)
    q_low = max(math.log10(low), start - step)
    q_high = min(math.log10(high), start + step)
    start = min(max(start, q_low + 1e-9), q_high - 1e-9)

    def residuals(q: np.ndarray) -> np.ndarray:
        return _model_residuals(10.0 ** q[0], curves, model, map_fn)

    result = least_squares(
        residuals,
        x0=[start],
        bounds=([q_low], [q_high]),
        diff_step=[1e-3],
        x_scale=[0.1],
        xtol=1e-10,
        ftol=1e-12,
        gtol=1e-12,
    )
    q_best = float(result.x[0])
    lam = 10.0**q_best
    r = result.fun
    dof = max(n_points - 1, 1)
    s2 = float(np.sum(r**2)) / dof
    jtj = float(result.jac[:, 0] @ result.jac[:, 0])
    sigma_q = math.sqrt(s2 / jtj) if jtj > 0 else math.inf
    return LambdaFit(
        mode_mixity=lam,
        mode_mixity_std=lam * math.log(10.0) * sigma_q,
        residual_rms=float(np.sqrt(np.mean(r**2))),
        n_points=n_points,
        grid_mode_mixity=grid,
        grid_residual_rms=grid_rms,
        success=bool(result.success),
        message=str(result.message),
        nfev=int(result.nfev),
    )
