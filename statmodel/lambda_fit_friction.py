"""Fit the mode mixity lambda to measured friction tests F_x(drive), alone or jointly with the
measured A_r(F_x) curves, and compare the two single-source estimates.

**Friction only** (:func:`fit_mode_mixity_friction`). Each measured test (drive from its first
point, m; F_x, N) is trimmed after its first static peak (the stick-slip tail follows it, as in
the area fit; the peak is where F_x first falls below its running maximum by six noise levels,
:func:`peak_end`) and points of equal drive are merged. The model curve at a lambda is the
statistical model's F_x(delta_T) (E:NewFormulation_Fx) seen from the drive through the loading
system's spring, drive = delta_T + F_x / k (:func:`asperity.statmodel.drive.drive_curve`); its
stable rising branch, up to the static peak at drive delta_s + F_s / k, is interpolated at the
measured drive and held at F_s beyond it. Residuals r = (F_model - F_measured) / max(F_measured)
(each test weighs the same), absolute (no free factor: the level of F_x is what lambda sets,
through the static peak); q = log10(lambda) is scanned on a coarse log grid and refined by a
bounded Brent search between the best point's neighbours, exactly as the area fit
(:func:`asperity.statmodel.lambda_fit.fit_mode_mixity`). With a rigid drive, drive =
delta_T.

**Interval** (profile likelihood): s^2 = S_min / (m - 1) with m merged points; the one-sigma
interval is where S(q) <= S_min + s^2 (Delta chi^2 = 1), stepped out and bisected on the model
itself. It assumes independent residuals (1 % white noise on F_x: tested to cover the true
lambda at its stated level over seeds); correlated errors along a test make it a lower bound.

**Joint** (:func:`fit_mode_mixity_joint`): the sum of the two sources' residual sums of squares,
each divided by its own variance s^2 from its single-source fit, so that each source weighs by
its own noise; the interval is where that chi^2 rises by 1.

**Comparison** (:func:`compare_sources`): the two single-source estimates disagree when they
differ by more than two combined standard deviations (their one-sigma half-intervals facing
each other, in quadrature); the lambda stage stores it and the verdict warns
(``lambda_sources_disagree``).

SI units throughout: m, N, N/m; lambda is dimensionless.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Protocol, cast

import numpy as np

from asperity.errors import InputError
from asperity.statmodel.drive import DriveCurve
from asperity.statmodel.lambda_fit import (
    BOUND_MARGIN,
    PEAK_DROP,
    LambdaFit,
    ShearAreaModel,
    _Objective,
    _profile_side,
    _refine,
    first_peak_end,
    fit_mode_mixity,
    merge_repeated,
    prepare_curve,
)
from asperity.statmodel.measured_curves import FIT_SOURCES, FrictionCurve, ShearAreaCurve

#: ``model(mode_mixity, normal_load) -> DriveCurve``: the model's F_x seen from the drive.
DriveModel = Callable[[float, float], DriveCurve]
#: ``map``-like callable (builtin map or an executor's map).
MapFunction = Callable[..., Iterable]


@dataclass(frozen=True)
class PreparedTest:
    """A measured test ready to fit: drive from its first point (m, increasing), F_x (N)."""

    normal_load: float
    drive_displacement: np.ndarray
    tangential_force: np.ndarray


#: A fall of F_x below its running maximum by this many noise levels (:func:`noise_level`)
#: marks the first static peak of a friction test (and at least
#: :data:`asperity.statmodel.lambda_fit.PEAK_DROP` of its largest F_x): a noise dip on the
#: rising branch must not be taken for the peak (with 1 % noise the 2 % rule alone cut one test
#: in five there).
PEAK_NOISE_LEVELS = 6.0


def noise_level(force: np.ndarray) -> float:
    """White-noise standard deviation (N) of a sampled F_x, robust to its jumps: the median
    absolute second difference / (0.6745 sqrt 6) (a smooth curve's second differences are
    small on a fine sampling, a white noise's have variance 6 sigma^2, and a few stick-slip
    drops do not move the median). NaN with fewer than three points."""
    force = np.asarray(force, dtype=float)
    if force.size < 3:
        return math.nan
    second = force[2:] - 2.0 * force[1:-1] + force[:-2]
    return float(np.median(np.abs(second)) / (0.6745 * math.sqrt(6.0)))


def peak_end(force: np.ndarray) -> int:
    """Points up to and including a friction test's first static peak: the first fall below
    the running maximum by :data:`PEAK_NOISE_LEVELS` noise levels and at least
    :data:`asperity.statmodel.lambda_fit.PEAK_DROP` of max |F_x|
    (:func:`asperity.statmodel.lambda_fit.first_peak_end`)."""
    force = np.asarray(force, dtype=float)
    top = float(np.max(np.abs(force))) or 1.0
    noise = noise_level(force)
    drop = max(PEAK_DROP, PEAK_NOISE_LEVELS * noise / top if math.isfinite(noise) else 0.0)
    return first_peak_end(force, drop)


def prepare_test(curve: FrictionCurve, *, trim: bool = True) -> PreparedTest:
    """A measured test trimmed after its first static peak (optional, :func:`peak_end`), equal
    drives merged."""
    force = np.asarray(curve.tangential_force, dtype=float)
    end = peak_end(force) if trim else force.size
    drive, merged = merge_repeated(curve.drive_from_start[:end], force[:end])
    return PreparedTest(curve.normal_load, drive, merged)


def rising_branch_force(model: DriveCurve, drive_displacement: np.ndarray) -> np.ndarray:
    """The model's F_x (N) at drive positions (m) on its rising branch, held at F_s beyond.

    The branch is the model's points up to its static peak, ending at the refined peak
    (drive delta_s + F_s / k, F_s); F_x and the drive both increase along it.
    """
    dts = model.tangential_displacement
    upto = dts <= model.static_displacement
    drive = np.append(model.drive_displacement[upto], model.static_drive_displacement)
    force = np.append(model.tangential_force[upto], model.static_friction)
    keep = np.concatenate([np.diff(drive) > 0, [True]])
    return np.interp(drive_displacement, drive[keep], force[keep])


class FrictionObjective:
    """Residuals of measured tests against the model at a lambda (model curves cached)."""

    def __init__(self, tests: Sequence[PreparedTest], model: DriveModel, map_fn: MapFunction):
        self.tests, self.model, self.map_fn = list(tests), model, map_fn
        self.cache: dict[float, list[DriveCurve]] = {}

    def model_curves(self, lam: float) -> list[DriveCurve]:
        """The model's drive curve at each test's load, lambda ``lam``."""
        if lam not in self.cache:
            loads = [t.normal_load for t in self.tests]
            self.cache[lam] = list(self.map_fn(self.model, [lam] * len(loads), loads))
        return self.cache[lam]

    def fitted(self, lam: float) -> np.ndarray:
        """The model's F_x (N) at every measured drive, tests concatenated."""
        return np.concatenate(
            [
                rising_branch_force(m, t.drive_displacement)
                for t, m in zip(self.tests, self.model_curves(lam), strict=True)
            ]
        )

    def residuals(self, lam: float) -> np.ndarray:
        """(F_model - F_measured) / max(F_measured) of each test, concatenated."""
        out = []
        for test, model in zip(self.tests, self.model_curves(lam), strict=True):
            top = float(np.max(np.abs(test.tangential_force))) or 1.0
            model_force = rising_branch_force(model, test.drive_displacement)
            out.append((model_force - test.tangential_force) / top)
        return np.concatenate(out)

    @property
    def n_residuals(self) -> int:
        """Number of residuals (merged points over all tests)."""
        return sum(t.tangential_force.size for t in self.tests)

    def ssr(self, q: float) -> float:
        """Residual sum of squares at lambda = 10**q."""
        return float(np.sum(self.residuals(10.0**q) ** 2))


class Objective(Protocol):
    """What the scan, the refinement and the profile read of an objective."""

    @property
    def n_residuals(self) -> int: ...

    def ssr(self, q: float) -> float: ...


class JointObjective:
    """Several sources' residual sums of squares, each divided by its own variance s^2."""

    def __init__(self, parts: Sequence[tuple[Objective, float]]):
        self.parts = list(parts)

    @property
    def n_residuals(self) -> int:
        """Residuals of all sources."""
        return sum(objective.n_residuals for objective, _ in self.parts)

    def ssr(self, q: float) -> float:
        """chi^2 = sum S_i(q) / s_i^2."""
        return float(sum(objective.ssr(q) / var for objective, var in self.parts))


def _check(bounds: tuple[float, float], n_points: int, what: str) -> None:
    low, high = bounds
    if not 0 < low < high <= 1:
        raise InputError(f"{what}: bounds must satisfy 0 < low < high <= 1, got {bounds}")
    if n_points < 3:
        raise InputError(
            f"{what}: need at least 3 distinct measured points up to the first static peak, "
            f"got {n_points} after trimming and merging"
        )


def _profile_fit(
    objective: Objective,
    bounds: tuple[float, float],
    grid_points: int,
    delta: Callable[[float], float],
) -> dict:
    """Scan, refine and profile ``objective`` over q = log10(lambda); ``delta(S_min)`` is the
    rise of S that bounds the one-sigma interval. The area fit's helpers read only ``ssr`` and
    ``n_residuals`` of it (typed for the area objective: cast)."""
    area_like = cast(_Objective, objective)
    q_low, q_high = math.log10(bounds[0]), math.log10(bounds[1])
    grid = np.logspace(q_low, q_high, grid_points)
    n = objective.n_residuals
    grid_rms = np.array([math.sqrt(objective.ssr(math.log10(g)) / n) for g in grid])
    result = _refine(area_like, grid, grid_rms, (q_low, q_high))
    q_best = float(result.x[0])
    s_min = objective.ssr(q_best)
    target = s_min + delta(s_min)
    interval = (
        10.0 ** _profile_side(area_like, q_best, target, q_low),
        10.0 ** _profile_side(area_like, q_best, target, q_high),
    )
    return {
        "mode_mixity": 10.0**q_best,
        "mode_mixity_std": 0.5 * (interval[1] - interval[0])
        if all(math.isfinite(v) for v in interval)
        else math.inf,
        "residual_rms": math.sqrt(s_min / n),
        "n_points": n,
        "grid_mode_mixity": grid,
        "grid_residual_rms": grid_rms,
        "success": bool(result.success),
        "message": str(result.message),
        "nfev": int(result.nfev),
        "at_bound": min(q_best - q_low, q_high - q_best) < BOUND_MARGIN,
        "interval": interval,
    }


def fit_mode_mixity_friction(
    curves: Sequence[FrictionCurve],
    model: DriveModel,
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    grid_points: int = 9,
    map_fn: MapFunction = map,
    trim: bool = True,
) -> LambdaFit:
    """Fit lambda to measured friction tests F_x(drive) alone (least squares, profile interval).

    Parameters
    ----------
    curves : sequence of FrictionCurve
        Measured tests (drive m, F_x N, acquisition order), one per normal load.
    model : callable
        ``model(mode_mixity, normal_load) -> DriveCurve``: the statistical model's F_x through
        the drive's spring (:func:`asperity.statmodel.drive.drive_curve`); picklable when
        ``map_fn`` is a process pool's map.
    bounds : (float, float)
        Search interval of lambda, 0 < low < high <= 1.
    grid_points : int
        Points of the coarse log-spaced scan.
    map_fn : callable
        ``map``-like function evaluating the loads.
    trim : bool
        Cut each test after its first static peak of F_x (default).

    Returns
    -------
    LambdaFit
        ``mode`` ``"friction"``; ``points``: ``normal_load`` (N), ``drive_displacement`` (m),
        ``tangential_force`` (N, measured) and ``model_force`` (N, at the fitted lambda).
    """
    if not curves:
        raise InputError("fit_mode_mixity_friction: no measured friction tests")
    tests = [prepare_test(c, trim=trim) for c in curves]
    objective = FrictionObjective(tests, model, map_fn)
    _check(bounds, objective.n_residuals, "fit_mode_mixity_friction")
    fit = _profile_fit(
        objective, bounds, grid_points, lambda s: s / max(objective.n_residuals - 1, 1)
    )
    return LambdaFit(
        **fit,
        mode="friction",
        n_points_read=sum(len(c.tangential_force) for c in curves),
        scale=np.ones(len(tests)),
        points=_fitted_points(tests, objective.fitted(fit["mode_mixity"])),
    )


def _fitted_points(tests: Sequence[PreparedTest], model_force: np.ndarray) -> dict:
    """The points fitted (N, m, N) and the model's F_x there (N), flattened over tests."""
    return {
        "normal_load": np.concatenate(
            [np.full(t.tangential_force.size, t.normal_load) for t in tests]
        ),
        "drive_displacement": np.concatenate([t.drive_displacement for t in tests]),
        "tangential_force": np.concatenate([t.tangential_force for t in tests]),
        "model_force": model_force,
    }


def source_variance(fit: LambdaFit, n_free: int) -> float:
    """s^2 = S_min / (m - 1 - k) of a single-source fit (k free factors besides lambda)."""
    s_min = fit.residual_rms**2 * fit.n_points
    return max(s_min / max(fit.n_points - 1 - n_free, 1), 1e-300)


def fit_mode_mixity_joint(
    parts: Sequence[tuple[Objective, float]],
    *,
    bounds: tuple[float, float] = (1e-4, 1.0),
    grid_points: int = 9,
) -> LambdaFit:
    """Fit lambda to several sources at once: chi^2(q) = sum S_i(q) / s_i^2.

    Parameters
    ----------
    parts : sequence of (objective, variance)
        Each source's objective (``ssr(q)`` and ``n_residuals``: :class:`FrictionObjective`,
        or the area fit's) and its residual variance s^2 (:func:`source_variance` of its own
        fit).
    bounds, grid_points
        As :func:`fit_mode_mixity_friction`.

    Returns
    -------
    LambdaFit
        ``mode`` ``"joint"``; ``residual_rms`` is sqrt(chi^2_min / m); the interval is where
        chi^2 rises by 1.
    """
    objective = JointObjective(parts)
    _check(bounds, objective.n_residuals, "fit_mode_mixity_joint")
    fit = _profile_fit(objective, bounds, grid_points, lambda s: 1.0)
    return LambdaFit(**fit, mode="joint", n_points_read=objective.n_residuals)


#: Two single-source lambdas disagree when they differ by more than this many combined
#: standard deviations (two: a false alarm about 5 % of the time for consistent data; the
#: one-sigma intervals themselves fail to overlap for a fifth of consistent pairs).
DISAGREEMENT_SIGMAS = 2.0


def _side(fit: LambdaFit, towards: float) -> float:
    """The half-width of ``fit``'s one-sigma interval on the side facing ``towards`` (inf when
    that end is open: the data do not bound lambda there)."""
    end = fit.interval[1] if towards >= fit.mode_mixity else fit.interval[0]
    return abs(end - fit.mode_mixity) if math.isfinite(end) else math.inf


def compare_sources(area: LambdaFit, friction: LambdaFit) -> tuple[bool, str]:
    """(disagree, sentence): the area-only and friction-only lambdas with their one-sigma
    intervals. They disagree when |lambda_a - lambda_f| exceeds :data:`DISAGREEMENT_SIGMAS`
    times sqrt(s_a^2 + s_f^2), each s the half-interval on the side facing the other lambda
    (asymmetric intervals); an open side never disagrees."""
    a, f = area.mode_mixity, friction.mode_mixity
    combined = math.hypot(_side(area, f), _side(friction, a))
    sigmas = abs(a - f) / combined if combined > 0 else math.inf
    disagree = bool(sigmas > DISAGREEMENT_SIGMAS)
    text = (
        f"lambda from A_r(F_x) {a:.4g} (interval {area.interval[0]:.4g}..{area.interval[1]:.4g}),"
        f" from the friction tests {f:.4g} (interval {friction.interval[0]:.4g}.."
        f"{friction.interval[1]:.4g}): {sigmas:.2g} combined sigma apart"
    )
    if disagree:
        return True, text + f", beyond {DISAGREEMENT_SIGMAS:g}: the two measurements disagree"
    return False, text + f", within {DISAGREEMENT_SIGMAS:g}"


@dataclass(frozen=True)
class SourceFits:
    """The lambda fits of a job with measured curves of either or both kinds.

    Attributes
    ----------
    source : str
        The chosen source (:data:`asperity.pipelines.config.FIT_SOURCES`).
    chosen : LambdaFit or None
        The fit whose lambda is used downstream (None: source "area" without A_r(F_x) curves,
        the configured lambda is used and the friction fit only compared).
    area, friction, joint : LambdaFit or None
        Each fit made (None: that source's curves are absent; joint only when chosen).
    disagree : bool or None
        The two single-source intervals do not overlap (None: one source absent).
    comparison : str
        One sentence comparing them ("" with one source).
    """

    source: str
    chosen: LambdaFit | None
    area: LambdaFit | None
    friction: LambdaFit | None
    joint: LambdaFit | None
    disagree: bool | None
    comparison: str


def fit_sources(
    source: str,
    *,
    area_curves: Sequence[ShearAreaCurve],
    friction_curves: Sequence[FrictionCurve],
    area_model: ShearAreaModel,
    drive_model: DriveModel,
    bounds: tuple[float, float] = (1e-4, 1.0),
    map_fn: MapFunction = map,
    mode: str = "shape",
    trim: bool = True,
    area_fit: LambdaFit | None = None,
) -> SourceFits:
    """Fit lambda to each measured source present, jointly when asked, and compare them.

    Parameters
    ----------
    source : {"area", "friction", "joint"}
        Which fit's lambda is used downstream (``[fit] source``).
    area_curves, friction_curves : sequences
        Measured A_r(F_x) curves (N, m^2) and friction tests F_x(drive) (m, N).
    area_model, drive_model : callables
        ``area_model(lambda, F_z) -> (F_x N, A_r m^2)`` and ``drive_model(lambda, F_z) ->
        DriveCurve``.
    bounds, map_fn, mode, trim
        As :func:`asperity.statmodel.lambda_fit.fit_mode_mixity` (``mode`` applies to the
        area fit; the friction fit is absolute).
    area_fit : LambdaFit, optional
        The area-only fit when already made (not fitted again).

    Raises
    ------
    InputError
        An unknown source, or the chosen source's curves absent ("friction": the friction
        tests; "joint": both; "area" without A_r(F_x) curves chooses no fit).
    """
    if source not in FIT_SOURCES:
        raise InputError(f"fit.source: expected one of {', '.join(FIT_SOURCES)}, got {source!r}")
    needed = {"area": (), "friction": (friction_curves,)}
    if not all(needed.get(source, (area_curves, friction_curves))):
        raise InputError(f"fit.source = {source!r}: the measured curves it fits are not given")
    area, friction, joint = area_fit, None, None
    if area_curves and area is None:
        area = fit_mode_mixity(
            area_curves, area_model, bounds=bounds, map_fn=map_fn, mode=mode, trim=trim
        )
    if friction_curves:
        friction = fit_mode_mixity_friction(
            friction_curves, drive_model, bounds=bounds, map_fn=map_fn, trim=trim
        )
    if source == "joint":
        if area is None or friction is None:  # both given (checked above): both fitted
            raise InputError("fit.source = 'joint': both measured sources are needed")
        area_objective = _Objective(
            [prepare_curve(c, trim=trim) for c in area_curves], area_model, map_fn, mode
        )
        tests = [prepare_test(c, trim=trim) for c in friction_curves]
        n_scales = len(area_curves) if mode == "shape" else 0
        joint = fit_mode_mixity_joint(
            [
                (area_objective, source_variance(area, n_scales)),
                (FrictionObjective(tests, drive_model, map_fn), source_variance(friction, 0)),
            ],
            bounds=bounds,
        )
    disagree, comparison = (None, "")
    if area is not None and friction is not None:
        disagree, comparison = compare_sources(area, friction)
    chosen = {"area": area, "friction": friction, "joint": joint}[source]
    return SourceFits(source, chosen, area, friction, joint, disagree, comparison)
