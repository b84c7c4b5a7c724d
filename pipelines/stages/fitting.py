"""Fit the mode-mixity lambda to measured A_r(F_x) curves, jointly over all normal loads.

The paper (Section 5, Fig 13) calibrates lambda so that the statistical model "recreates
quantitatively the shear-induced reduction of the real contact area": the *shape* of
A_r(F_x)/A_r(F_x = 0), after the normal-contact step has fixed the resolution. Here:

1. **Trim** (default): each measured curve, in acquisition (file) order, is cut after its first
   static peak of F_x, the first maximum after which F_x drops by more than
   :data:`PEAK_DROP` of the curve's largest F_x. Beyond it the paper's Fig 6b shows stick-slip:
   F_x saws up and down while A_r keeps falling, a path the quasi-static model does not
   describe; left in, those points drag lambda up (0.18 for a true 0.03).
2. **Merge**: points with equal F_x become one point (their mean A_r), so a point repeated
   100 times counts once and does not shrink the uncertainty.
3. **Mode** ``shape`` (default): every measured curve is compared with the model curve times
   its own least-squares factor c (closed form, one per curve): the fit sees
   A_r/A_r(F_x = 0) with A_r(F_x = 0) estimated from the whole curve, not from one noisy point.
   A measured A_r 20 % above the model at F_x = 0 (the normal case at low loads, Fig 13) then
   leaves lambda untouched; in mode ``absolute`` (c = 1) that offset drives lambda to its
   lower bound. ``absolute`` is for data whose level the model already matches. The factors
   are returned (:attr:`LambdaFit.scale`, one per curve); the job stores them and its verdict
   calls a c outside [0.50, 2.01] invalid (``shape_scale``): a free factor would otherwise
   absorb areas or loads in a wrong unit without a trace.
4. The model curve A_r(F_x) at each load is its stick branch (delta_T = 0 up to the static
   peak), interpolated at the measured F_x and held at the peak value beyond it. Residuals are
   r = (c A_model - A_measured) / max(A_measured) (every load weighs the same), minimised
   together over q = log10(lambda): a coarse log grid picks the best point (so that a local
   minimum elsewhere is not mistaken for the answer), and a bounded Brent search
   (:func:`scipy.optimize.minimize_scalar`, ``method="bounded"``) of the residual sum of
   squares between that point's neighbours places the optimum between grid points; the result
   is never worse than the best grid point. The objective must be smooth in lambda for this:
   the job's model curve has its nodes at fixed fractions of the static peak's displacement
   (:func:`statmodel.shear_path.model_shear_area`), so the interpolated areas move
   smoothly with lambda (a curve on nodes fixed in delta_T gave a jagged objective, on which a
   gradient step stopped at its starting grid point).

Uncertainty (profile likelihood): with S(q) the residual sum of squares and
s^2 = S_min / (m - 1 - k) (m merged points, k fitted scale factors), the one-sigma interval is
where S(q) <= S_min + s^2 (Delta chi^2 = 1), found by stepping out from the optimum and
bisecting with the model itself, not a linearisation. ``mode_mixity_std`` is half the width of
that interval in lambda; it is infinite when S does not rise by s^2 before a bound (the data
do not constrain lambda on that side). ``at_bound`` flags an optimum on a bound of the search
interval: then the bound, not the data, chose lambda. The interval assumes independent
residuals; correlated measurement errors along a curve make it a lower bound.

**A calibration error is tested, not absorbed.** A free factor c per curve absorbs an area
scale error (x 1.2: the image's pixel size) without a trace, and an additive offset (+0.2
A_r(F_x = 0) on every point: a contact-detection threshold) shows as the same c ~ 1.2 while it
flattens the relative drop, which lambda then absorbs (0.0268 for a true 0.03, its interval
missing the truth). The shape alone cannot tell the two readings apart: lambda acts mainly
through the F_x at which the area falls (the model's drop to the static peak is ~0.93 at any
lambda), and an offset rescales the relative drop. So when a curve's c is
:data:`CALIBRATION_SCALE` (10 %) or more from 1 in mode ``shape``, lambda is fitted again under
the other reading, mode ``offset`` (A_measured ~ A_model + d, one d per curve, c = 1), and
:attr:`LambdaFit.interval` is the union of both profile intervals (the shape reading's own is
:attr:`LambdaFit.shape_interval`): the interval is widened by what the data cannot separate.
The verdict names what the file shows and what to check (``measured_area_scale``,
``measured_area_offset``: :func:`asperity.pipelines.stages.verdict.check_calibration`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import OptimizeResult, minimize_scalar

from asperity.errors import InputError
from asperity.pipelines.measured import ShearAreaCurve

#: ``model(mode_mixity, normal_load) -> (tangential_force N, real_area m^2)`` along delta_T.
ShearAreaModel = Callable[[float, float], tuple[np.ndarray, np.ndarray]]
#: ``map``-like callable (builtin map or an executor's map).
MapFunction = Callable[..., Iterable]
#: The fit modes (:func:`fit_mode_mixity`); the first is the default.
FIT_MODES: tuple[str, ...] = ("shape", "absolute")
#: A drop of F_x by this fraction of the curve's largest F_x marks the first static peak.
PEAK_DROP = 0.02
#: An optimum within this many decades of a bound counts as "at the bound".
BOUND_MARGIN = 1e-3
#: A shape factor this far from 1 (|c - 1|) makes the fit test the offset reading too.
CALIBRATION_SCALE = 0.10
#: The internal reading of the level: an additive offset per curve (A_model + d), c = 1.
OFFSET_MODE = "offset"


@dataclass(frozen=True)
class LambdaFit:
    """Result of :func:`fit_mode_mixity`.

    Attributes
    ----------
    mode_mixity : float
        Best lambda.
    mode_mixity_std : float
        One-sigma uncertainty of lambda: half the profile-likelihood interval (inf when the
        data do not bound lambda on one side).
    residual_rms : float
        Root mean square of the relative residuals (fraction of each curve's largest area).
    n_points : int
        Number of measured points used (after trimming and merging).
    grid_mode_mixity, grid_residual_rms : ndarray
        The coarse scan: lambda values and their residual rms.
    success : bool
        The optimiser reported success.
    message : str
        The optimiser's message.
    nfev : int
        Model evaluations (each one curve per load) by the optimiser, excluding the scan.
    mode : str
        ``shape`` or ``absolute``.
    at_bound : bool
        The optimum lies on a bound of the search interval.
    interval : tuple of float
        The one-sigma profile interval (lambda_low, lambda_high).
    n_points_read : int
        Points in the measured curves before trimming and merging.
    scale : ndarray
        The factor c per curve (1 in mode ``absolute``).
    points : dict of ndarray
        The points fitted (trimmed, merged): ``normal_load`` (N), ``tangential_force`` (N),
        ``real_area`` (m^2) and ``model_area`` (m^2, c A_model at the fitted lambda).
    shape_interval : tuple of float
        The profile interval of the reading the fit was asked for (``interval`` unites it with
        the offset reading's when that was tested).
    offset_mode_mixity : float
        lambda fitted under the offset reading (NaN when not tested: every c within
        :data:`CALIBRATION_SCALE` of 1).
    offset_interval : tuple of float
        Its profile interval.
    offset_fraction : ndarray
        Per curve, the offset d over the model's A_r at F_x = 0 under that reading (1).
    offset_residual_rms : float
        The rms relative residual under the offset reading (NaN when not tested).
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
    mode: str = "shape"
    at_bound: bool = False
    interval: tuple[float, float] = (math.nan, math.nan)
    n_points_read: int = 0
    scale: np.ndarray = field(default_factory=lambda: np.ones(0))
    points: dict[str, np.ndarray] = field(default_factory=dict)
    shape_interval: tuple[float, float] = (math.nan, math.nan)
    offset_mode_mixity: float = math.nan
    offset_interval: tuple[float, float] = (math.nan, math.nan)
    offset_fraction: np.ndarray = field(default_factory=lambda: np.ones(0))
    offset_residual_rms: float = math.nan

    @property
    def offset_tested(self) -> bool:
        """The offset reading was fitted (a factor c at least 10 % from 1)."""
        return math.isfinite(self.offset_mode_mixity)


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
    """Model A_r (m^2) at measured tangential forces (N) on the stick branch, held at the end
    values outside.

    Linear in s = sqrt(F_peak - F_x), not in F_x: near the static peak F_x is quadratic in
    delta_T, so A_r(F_x) has a square-root end point, on which linear interpolation in F_x
    errs by up to a node's change of A_r (and the error jumps as the nodes move with lambda:
    a jagged fit objective), while A_r is smooth in s (s is linear in delta_T there).
    """
    fx, ar = area_up_to_peak(fx_model, ar_model)
    peak = float(fx[-1])
    s_model = np.sqrt(np.maximum(peak - fx, 0.0))[::-1]  # increasing
    s_measured = np.sqrt(np.maximum(peak - np.asarray(fx_measured, dtype=float), 0.0))
    return np.interp(s_measured, s_model, ar[::-1])


def first_peak_end(tangential_force: np.ndarray, drop: float = PEAK_DROP) -> int:
    """Number of points up to and including the first static peak of F_x (acquisition order).

    The peak is the running maximum just before F_x first falls below it by more than
    ``drop`` times the curve's largest |F_x|; without such a fall every point is kept.
    """
    fx = np.asarray(tangential_force, dtype=float)
    running = np.maximum.accumulate(fx)
    fallen = np.flatnonzero(fx < running - drop * float(np.max(np.abs(fx))))
    if not fallen.size:
        return fx.size
    return int(np.argmax(fx[: fallen[0]])) + 1


def merge_repeated(
    tangential_force: np.ndarray, real_area: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Points of equal F_x (N) merged into one: F_x sorted, mean A_r (m^2)."""
    fx, inverse = np.unique(np.asarray(tangential_force, float), return_inverse=True)
    area = np.bincount(inverse, weights=np.asarray(real_area, float)) / np.bincount(inverse)
    return fx, area


def prepare_curve(curve: ShearAreaCurve, *, trim: bool = True) -> ShearAreaCurve:
    """A measured curve trimmed after its first static peak (optional) and merged."""
    end = first_peak_end(curve.tangential_force) if trim else len(curve.tangential_force)
    fx, ar = merge_repeated(curve.tangential_force[:end], curve.real_area[:end])
    return ShearAreaCurve(curve.normal_load, fx, ar, curve.source)


def _scale(model_area: np.ndarray, measured: np.ndarray, mode: str) -> float:
    """Least-squares factor c of ``c model = measured`` (1 in mode ``absolute`` or
    ``offset``)."""
    if mode in ("absolute", OFFSET_MODE):
        return 1.0
    denominator = float(model_area @ model_area)
    return float(model_area @ measured) / denominator if denominator > 0 else 1.0


def _level(model_area: np.ndarray, measured: np.ndarray, mode: str) -> tuple[float, float]:
    """(c, d) of ``c model + d = measured`` in least squares: d = 0 except in mode
    ``offset`` (c = 1, d the mean difference, m^2)."""
    if mode == OFFSET_MODE:
        return 1.0, float(np.mean(measured - model_area))
    return _scale(model_area, measured, mode), 0.0


class _Objective:
    """Residuals of the curves at a lambda; model curves cached per lambda."""

    def __init__(
        self,
        curves: Sequence[ShearAreaCurve],
        model: ShearAreaModel,
        map_fn: MapFunction,
        mode: str,
    ) -> None:
        self.curves, self.model, self.map_fn, self.mode = curves, model, map_fn, mode
        self.cache: dict[float, list[tuple[np.ndarray, np.ndarray]]] = {}

    def reading(self, mode: str) -> _Objective:
        """The same curves and model under another reading of the level, sharing the cache
        of model curves (no model curve is computed twice)."""
        other = _Objective(self.curves, self.model, self.map_fn, mode)
        other.cache = self.cache
        return other

    def model_curves(self, lam: float) -> list[tuple[np.ndarray, np.ndarray]]:
        if lam not in self.cache:
            loads = [c.normal_load for c in self.curves]
            self.cache[lam] = list(self.map_fn(self.model, [lam] * len(loads), loads))
        return self.cache[lam]

    def parts(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(residuals, model area at the points times c plus d, c per curve)."""
        residuals, fitted, scales, _ = self.levels(lam)
        return residuals, fitted, scales

    def levels(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`parts` and, per curve, the offset d over the model's A_r at F_x = 0."""
        residuals, fitted, scales, offsets = [], [], [], []
        for curve, (fx, ar) in zip(self.curves, self.model_curves(lam), strict=True):
            model_area = interpolate_area(fx, ar, curve.tangential_force)
            c, d = _level(model_area, curve.real_area, self.mode)
            top = float(np.max(curve.real_area)) or 1.0
            residuals.append((c * model_area + d - curve.real_area) / top)
            fitted.append(c * model_area + d)
            scales.append(c)
            at_rest = float(interpolate_area(fx, ar, np.zeros(1))[0])
            offsets.append(d / at_rest if at_rest > 0 else math.nan)
        return (
            np.concatenate(residuals),
            np.concatenate(fitted),
            np.array(scales),
            np.array(offsets),
        )

    def residuals(self, lam: float) -> np.ndarray:
        return self.parts(lam)[0]

    @property
    def n_residuals(self) -> int:
        """Number of residuals (merged points over all curves)."""
        return sum(len(c.real_area) for c in self.curves)

    def ssr(self, q: float) -> float:
        return float(np.sum(self.residuals(10.0**q) ** 2))


def _profile_side(objective: _Objective, q_best: float, target: float, limit: float) -> float:
    """q where the residual sum of squares reaches ``target`` between q_best and ``limit``.

    Returns nan when it does not before the limit.
    """
    direction = 1.0 if limit > q_best else -1.0
    step, inner = 0.005, q_best
    while True:
        outer = q_best + direction * step
        if direction * (outer - limit) >= 0:
            outer = limit
        if objective.ssr(outer) >= target:
            break
        if outer == limit:
            return math.nan
        inner, step = outer, step * 2.0
    for _ in range(30):
        middle = 0.5 * (inner + outer)
        if objective.ssr(middle) >= target:
            outer = middle
        else:
            inner = middle
        if abs(outer - inner) < 1e-4:
            break
    return 0.5 * (inner + outer)


def _check_inputs(curves: Sequence[ShearAreaCurve], bounds: tuple, mode: str) -> None:
    if not curves:
        raise InputError("fit_mode_mixity: no measured curves")
    low, high = bounds
    if not 0 < low < high <= 1:
        raise InputError(f"fit_mode_mixity: bounds must satisfy 0 < low < high <= 1, got {bounds}")
    if mode not in (*FIT_MODES, OFFSET_MODE):
        raise InputError(f"fit_mode_mixity: mode: expected one of {FIT_MODES}, got {mode!r}")


def fit_mode_mixity(
    curves: Sequence[ShearAreaCurve],
    model: ShearAreaModel,
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    grid_points: int = 9,
    map_fn: MapFunction = map,
    mode: str = "shape",
    trim: bool = True,
) -> LambdaFit:
    """Fit lambda jointly to measured A_r(F_x) curves (least squares, profile uncertainty).

    Parameters
    ----------
    curves : sequence of ShearAreaCurve
        Measured curves (F_x in N, A_r in m^2, in acquisition order), one per normal load.
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
    mode : {"shape", "absolute"}
        Fit the shape A_r/A_r(F_x=0) (a free factor per curve, default) or A_r itself.
    trim : bool
        Cut each curve after its first static peak of F_x (default).

    Returns
    -------
    LambdaFit
    """
    _check_inputs(curves, bounds, mode)
    n_read = sum(len(c.real_area) for c in curves)
    prepared = [prepare_curve(c, trim=trim) for c in curves]
    n_points = sum(len(c.real_area) for c in prepared)
    n_scales = len(prepared) if mode == "shape" else 0
    if n_points < 2 + n_scales:
        raise InputError(
            f"fit_mode_mixity: need at least {2 + n_scales} distinct measured points "
            f"(mode {mode!r}), got {n_points} after trimming and merging"
        )
    objective = _Objective(prepared, model, map_fn, mode)
    log_bounds = (math.log10(bounds[0]), math.log10(bounds[1]))
    found = _fit_reading(objective, log_bounds, grid_points, n_points, n_scales)
    grid, grid_rms, result, residuals, fitted, scales, interval = found
    q_best = math.log10(float(result.x[0]))
    offset = _offset_reading(objective, log_bounds, grid_points, n_points, scales)
    tested = math.isfinite(offset["offset_mode_mixity"])
    united = _union(interval, offset["offset_interval"], tested)
    return LambdaFit(
        mode_mixity=float(result.x[0]),
        mode_mixity_std=0.5 * (united[1] - united[0]) if np.all(np.isfinite(united)) else math.inf,
        residual_rms=float(np.sqrt(np.mean(residuals**2))),
        n_points=n_points,
        grid_mode_mixity=grid,
        grid_residual_rms=grid_rms,
        success=bool(result.success),
        message=str(result.message),
        nfev=int(result.nfev),
        mode=mode,
        at_bound=min(q_best - log_bounds[0], log_bounds[1] - q_best) < BOUND_MARGIN,
        interval=united,
        n_points_read=n_read,
        scale=scales,
        points=_fitted_points(prepared, fitted),
        shape_interval=interval,
        **offset,
    )


def _fit_reading(
    objective: _Objective, log_bounds: tuple, grid_points: int, n_points: int, n_levels: int
) -> tuple:
    """One reading's least-squares lambda: the coarse grid, the refined optimum (``x`` its
    lambda), the residuals, fitted areas and factors there, and the profile interval."""
    q_low, q_high = log_bounds
    grid = np.logspace(q_low, q_high, grid_points)
    grid_rms = np.array([float(np.sqrt(np.mean(objective.residuals(g) ** 2))) for g in grid])
    result = _refine(objective, grid, grid_rms, log_bounds)
    q_best = float(result.x[0])
    residuals, fitted, scales = objective.parts(10.0**q_best)
    ssr = float(np.sum(residuals**2))
    target = ssr * (1.0 + 1.0 / max(n_points - 1 - n_levels, 1))
    q_down = _profile_side(objective, q_best, target, q_low)
    q_up = _profile_side(objective, q_best, target, q_high)
    result.x = np.array([10.0**q_best])
    return grid, grid_rms, result, residuals, fitted, scales, (10.0**q_down, 10.0**q_up)


def _offset_reading(
    objective: _Objective, log_bounds: tuple, grid_points: int, n_points: int, scales: np.ndarray
) -> dict:
    """The offset reading's lambda, interval, offsets and rms residual (LambdaFit's
    ``offset_*`` fields), fitted when a shape factor is :data:`CALIBRATION_SCALE` or more
    from 1; NaN fields otherwise."""
    untested = {
        "offset_mode_mixity": math.nan,
        "offset_interval": (math.nan, math.nan),
        "offset_fraction": np.full(len(scales), math.nan),
        "offset_residual_rms": math.nan,
    }
    if objective.mode != "shape" or not np.any(np.abs(scales - 1.0) >= CALIBRATION_SCALE):
        return untested
    offset = objective.reading(OFFSET_MODE)
    found = _fit_reading(offset, log_bounds, grid_points, n_points, len(scales))
    lam, residuals, interval = float(found[2].x[0]), found[3], found[6]
    return {
        "offset_mode_mixity": lam,
        "offset_interval": interval,
        "offset_fraction": offset.levels(lam)[3],
        "offset_residual_rms": float(np.sqrt(np.mean(residuals**2))),
    }


def _union(
    interval: tuple[float, float], other: tuple[float, float], tested: bool
) -> tuple[float, float]:
    """The smallest interval holding both profile intervals; NaN (the side the data do not
    bound) on either side stays NaN. ``other`` not ``tested``: ``interval`` unchanged."""
    if not tested:
        return interval
    low = min(interval[0], other[0]) if np.all(np.isfinite([interval[0], other[0]])) else math.nan
    high = max(interval[1], other[1]) if np.all(np.isfinite([interval[1], other[1]])) else math.nan
    return (low, high)


def _refine(
    objective: _Objective, grid: np.ndarray, grid_rms: np.ndarray, log_bounds: tuple
) -> OptimizeResult:
    """Bounded Brent search of the residual sum of squares in q = log10(lambda) between the
    best grid point's neighbours (``x`` a one-element array); the best grid point when the
    search ends above it (never worse than a point evaluated)."""
    q_low, q_high = log_bounds
    best = int(np.argmin(grid_rms))
    start = math.log10(grid[best])
    step = (q_high - q_low) / max(len(grid) - 1, 1)
    lo, hi = max(q_low, start - step), min(q_high, start + step)
    result = minimize_scalar(
        objective.ssr, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6}
    )
    grid_ssr = float(grid_rms[best]) ** 2 * objective.n_residuals
    if not float(result.fun) <= grid_ssr:
        result.x, result.fun = start, grid_ssr
        result.message = f"{result.message}; the best grid point kept (the search ended above it)"
    result.x = np.array([float(result.x)])
    return result


def _fitted_points(prepared: Sequence[ShearAreaCurve], fitted: np.ndarray) -> dict:
    """The points fitted (N, N, m^2) and the model's A_r there (m^2), flattened over curves."""
    return {
        "normal_load": np.concatenate([np.full(len(c.real_area), c.normal_load) for c in prepared]),
        "tangential_force": np.concatenate([c.tangential_force for c in prepared]),
        "real_area": np.concatenate([c.real_area for c in prepared]),
        "model_area": fitted,
    }
