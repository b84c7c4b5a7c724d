"""The effective resolution as a continuous quantity, with an interval.

The effective resolution (paper, Section 5, Fig 12d) is the pixel size whose summit statistics
make the statistical model's A_r(F_z) closest to a reference (measured, or the BEM). The misfit
is m(Delta) = sqrt(mean over the n loads of ln^2(A_model/A_reference)). Scanned at integer
strides it moves in factor-2 steps at the fine end; :func:`locate_least_misfit` places it
between them by these rules:

1. **Parabola.** Near its minimum every ln ratio is close to linear in x = ln(Delta), so m^2 is
   a parabola in x. The parabola through the least sampled m^2 and its two neighbours gives
   the optimum x* (its vertex, which lies between the neighbours since the middle point is the
   least).
2. **Refinement** (when ``misfit_at`` is given): m is evaluated at :data:`REFINE_POINTS` more
   resolutions spaced evenly in x between those neighbours (summit statistics of the map
   resampled at non-integer steps, :mod:`topo.fractional_resampling`), and step 1 is repeated
   on all the points. When the least sampled misfit is at an end of the scan, the points go
   between that end and its neighbour: the optimum may lie between the first two strides
   (the default job's mean log ratio changes sign between 10 and 20 um). The least misfit
   m_min is then the model's own misfit evaluated at the vertex, never the parabola's value
   there (the summit statistics are jagged between strides, and a parabola through three
   jagged points can dip to 0 where no resolution fits perfectly). **Never worse than a point
   measured:** when that misfit exceeds the least misfit sampled (a stride or a refined
   resolution), the vertex is dropped and the sampled resolution is the optimum
   (``kept_sample`` says so, with both misfits).
3. **Interval** (the profile rule of the lambda fit, :mod:`pipelines.fitting`): with
   S = n m^2 the residual sum of squares and s^2 = S_min/(n - 1) its one-parameter estimate of
   the residual variance, the one-sigma interval is where S <= S_min + s^2, i.e.
   ``m^2 <= m_min^2 (1 + 1/(n - 1))``. Its ends are where the sampled m^2, interpolated
   linearly in x, first crosses that threshold on each side of the optimum. It assumes
   independent residuals across loads; a perfect match (m_min = 0) gives a zero-width interval.
4. **Open sides.** An optimum still at the finest (coarsest) resolution scanned after the
   refinement cannot be placed between neighbours: the optimum is that end, the interval is
   open on that side (``open_finer`` / ``open_coarser``) and ``direction`` says where the
   data point: ``"finer"`` (a finer measurement might fit better) or ``"coarser"`` (scan
   coarser strides). An interval whose threshold is not crossed before an end of the scan is
   open on that side too; its end is then the scanned end, a lower bound on its width. One
   load gives no residual variance: no interval (NaN, status 2).

**Between strides, and the interval's other parts** (the statistical-model stage's optimum:
:func:`optimum_fields`).

After the integer-stride scan, :func:`statmodel.effective_resolution.locate_least_misfit`
places the least misfit between the strides (a parabola in ln resolution, refined on the map
resampled at non-integer steps, :func:`statmodel.effective_resolution.roughness_at_resolution`)
and gives its one-sigma interval, open flags and the direction the data point to
(docs/uncertainty.md). The misfit at a resolution between strides is the stage's own
(:func:`~asperity.pipelines.stages.statistical_model.log_misfit` of the model's A_r at the
reference's loads). The roughness at the optimum feeds the lambda and friction stages; the
roughness at the interval's ends feeds the uncertainty of their predictions.

**The misfit's jaggedness between strides.** The summit statistics of a map resampled at
neighbouring non-integer steps scatter (summit-count noise: on a 256^2 map sigma_s moves 10 %
between 25 and 25.05 um), so the sampled m^2 scatters about its parabola. The profile interval
of ``locate_least_misfit`` holds only the residual variance over the loads; on its own it missed
a known optimum (a reference made by the model at 25 um) by 3 % on a 1000^2 map and 12 % on a
512^2 map, with a zero-width interval. :func:`sampling_half_width` therefore fits a parabola
``m^2 = a (x - x*)^2 + c`` by least squares to the samples nearest the optimum
(x = ln resolution; every sample within a factor 1.28 of the optimum, strides and the
refinement's points, and at least the ten nearest), takes the scatter s of m^2 about it, and the
resolutions where the parabola lies within s of its least value are equally good:
``delta_x = sqrt(s / a)``. The interval's half-widths on each side (ln resolution) are the
profile's and ``delta_x`` in quadrature (:func:`widen_interval`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from asperity.errors import InputError
from asperity.statmodel.parameters import Roughness
from asperity.topo.fractional_resampling import fractional_summit_statistics
from asperity.topo.heightmap import HeightMap

#: Resolutions added between the least misfit's neighbours by the refinement.
REFINE_POINTS = 8

#: ``EffectiveResolution.status`` codes.
RESOLUTION_STATUS: dict[int, str] = {
    0: "optimum between neighbours, interval closed on both sides",
    1: "optimum at an end of the scan, or interval open on a side",
    2: "no interval: a single load leaves no residual variance",
}


@dataclass(frozen=True)
class EffectiveResolution:
    """The least-misfit resolution with its one-sigma interval (rules in the module notes).

    Attributes
    ----------
    resolution : float
        Effective resolution, m.
    interval : tuple of float
        (finer end, coarser end), m; on an open side the scanned end; NaN without interval.
    misfit : float
        Least misfit m_min (rms ln ratio, 1).
    threshold : float
        m at the interval's ends, ``m_min sqrt(1 + 1/(n - 1))`` (1).
    n_loads : int
        Loads in the misfit.
    open_finer, open_coarser : bool
        The interval reaches the scan's finest / coarsest end without closing.
    direction : str
        ``"finer"`` or ``"coarser"`` when the optimum is at that end of the scan, else "".
    refined : bool
        The optimum was refined on resolutions between the strides.
    sampled_resolution, sampled_misfit : ndarray
        Every resolution used (m, ascending) and its misfit (1).
    success : bool
        Status 0.
    status : int
        One of :data:`RESOLUTION_STATUS`.
    message : str
        One sentence: the optimum, the interval and any open side.
    kept_sample : str
        Empty, or the sentence saying that the parabola's vertex fitted worse than a sampled
        resolution, which is reported instead (rule 2).
    """

    resolution: float
    interval: tuple[float, float]
    misfit: float
    threshold: float
    n_loads: int
    open_finer: bool
    open_coarser: bool
    direction: str
    refined: bool
    sampled_resolution: np.ndarray = field(repr=False)
    sampled_misfit: np.ndarray = field(repr=False)
    success: bool
    status: int
    message: str
    kept_sample: str = ""

    @property
    def half_width(self) -> float:
        """Half the interval, m (NaN without interval)."""
        return 0.5 * (self.interval[1] - self.interval[0])


def _check_curve(resolution: ArrayLike, misfit: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Finite points of the misfit curve, sorted by resolution, or InputError."""
    x = np.atleast_1d(np.asarray(resolution, dtype=float))
    y = np.atleast_1d(np.asarray(misfit, dtype=float))
    if x.ndim != 1 or x.shape != y.shape:
        raise InputError(
            f"locate_least_misfit: expected resolution and misfit of one length, got shapes "
            f"{x.shape} and {y.shape}"
        )
    keep = np.isfinite(x) & np.isfinite(y) & (x > 0)
    if keep.sum() < 1:
        raise InputError("misfit: expected a finite misfit at some resolution, got none")
    if np.any(y[keep] < 0):
        raise InputError("misfit: expected rms ln ratios >= 0, got a negative one")
    order = np.argsort(x[keep])
    return x[keep][order], y[keep][order]


def parabola_vertex(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Vertex (x*, y*) of the parabola through three points with the middle one the least.

    Falls back to the middle point when the three are collinear (flat).
    """
    (x0, x1, x2), (y0, y1, y2) = x, y
    d01, d12 = (y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1)
    curvature = (d12 - d01) / (x2 - x0)
    if curvature <= 0:
        return float(x1), float(y1)
    vertex = 0.5 * (x0 + x1) - d01 / (2 * curvature)
    vertex = min(max(vertex, x0), x2)
    value = y1 + d01 * (vertex - x1) + curvature * (vertex - x0) * (vertex - x1)
    return float(vertex), float(max(value, 0.0))


def _refine(
    x: np.ndarray, y: np.ndarray, low: int, high: int, misfit_at: Callable[[float], float]
) -> tuple[np.ndarray, np.ndarray]:
    """The curve (ln resolution, misfit^2) with REFINE_POINTS more points, evenly spaced in
    ln resolution, strictly between indices ``low`` and ``high``."""
    fine = np.linspace(x[low], x[high], REFINE_POINTS + 2)[1:-1]
    fine = fine[~np.isin(np.round(fine, 12), np.round(x, 12))]
    values = np.array([float(misfit_at(float(np.exp(v)))) ** 2 for v in fine])
    ok = np.isfinite(values)
    xs, ys = np.concatenate([x, fine[ok]]), np.concatenate([y, values[ok]])
    order = np.argsort(xs)
    return xs[order], ys[order]


def _crossing(
    x: np.ndarray, y2: np.ndarray, start: tuple[float, float], level: float, step: int
) -> float:
    """ln resolution where the sampled m^2 (linear between samples) first reaches ``level``,
    walking from the optimum ``start`` = (x*, m*^2) coarser (step +1) or finer (-1); NaN when
    it does not before the end of the scan."""
    inner_x, inner_y = start
    if inner_y >= level:
        return inner_x
    beyond = np.flatnonzero(x > inner_x) if step > 0 else np.flatnonzero(x < inner_x)[::-1]
    for j in beyond:
        if y2[j] >= level:
            return float(inner_x + (level - inner_y) * (x[j] - inner_x) / (y2[j] - inner_y))
        inner_x, inner_y = float(x[j]), float(y2[j])
    return math.nan


def _interval(
    x: np.ndarray, y2: np.ndarray, vertex: tuple[float, float], n_loads: int
) -> tuple[float, float, float, bool, bool]:
    """(finer end, coarser end) in ln m, the threshold misfit, and the open flags."""
    if n_loads < 2:
        return math.nan, math.nan, math.nan, False, False
    level = vertex[1] * (1.0 + 1.0 / (n_loads - 1))
    low, high = _crossing(x, y2, vertex, level, -1), _crossing(x, y2, vertex, level, +1)
    open_low, open_high = math.isnan(low), math.isnan(high)
    return (
        float(x[0]) if open_low else low,
        float(x[-1]) if open_high else high,
        math.sqrt(level),
        open_low,
        open_high,
    )


def _optimum(
    x: np.ndarray, y2: np.ndarray, misfit_at: Callable[[float], float] | None
) -> tuple[np.ndarray, np.ndarray, tuple[float, float], str, bool]:
    """(ln resolutions, m^2, vertex (x*, m*^2), direction, refined) of rules 1, 2 and 4."""
    i, last = int(np.argmin(y2)), x.size - 1
    refined = False
    if misfit_at is not None and x.size >= 2:
        refined = True
        if i in (0, last):  # the optimum may lie between the end and its neighbour
            x, y2 = _refine(x, y2, i, 1 if i == 0 else last - 1, misfit_at)
        else:
            x, y2 = _refine(x, y2, i - 1, i + 1, misfit_at)
        i, last = int(np.argmin(y2)), x.size - 1
    if x.size < 3 or i in (0, last):
        return x, y2, (float(x[i]), float(y2[i])), "finer" if i == 0 else "coarser", refined
    return x, y2, parabola_vertex(x[i - 1 : i + 2], y2[i - 1 : i + 2]), "", refined


def _message(
    resolution: float, ends: tuple[float, float], opens: tuple[bool, bool], direction: str
) -> str:
    """One sentence: optimum, interval, open sides and the direction the data point to."""
    text = f"effective resolution {resolution * 1e6:.4g} um"
    if math.isfinite(ends[0]):
        text += f", one-sigma interval {ends[0] * 1e6:.4g}..{ends[1] * 1e6:.4g} um"
    else:
        text += ", no interval (one load: no residual variance)"
    if direction == "finer":
        text += (
            "; the least misfit is at the finest resolution scanned, so the data point to a "
            "finer one (a finer measurement may fit better)"
        )
    elif direction == "coarser":
        text += (
            "; the least misfit is at the coarsest resolution scanned, so the data point to a "
            "coarser one (scan coarser strides)"
        )
    for is_open, side in zip(opens, ("finer", "coarser"), strict=True):
        if is_open and side != direction:
            text += f"; the interval is open on the {side} side (its end is the scan's end)"
    return text


def locate_least_misfit(
    resolution: ArrayLike,
    misfit: ArrayLike,
    n_loads: int,
    *,
    misfit_at: Callable[[float], float] | None = None,
) -> EffectiveResolution:
    """The least-misfit resolution between the scanned ones, and its interval.

    Parameters
    ----------
    resolution : array_like
        Scanned resolutions (pixel sizes), m; non-finite misfits are left out.
    misfit : array_like
        rms ln(A_model/A_reference) over the loads at each resolution (1).
    n_loads : int
        Number of loads in the misfit (>= 1; the interval needs 2).
    misfit_at : callable, optional
        ``misfit_at(resolution_m) -> misfit`` at any resolution in the scanned range (e.g. the
        model on :func:`roughness_at_resolution`); refines the optimum (rule 2).

    Returns
    -------
    EffectiveResolution
        Rules in the module notes.
    """
    if isinstance(n_loads, bool) or int(n_loads) != n_loads or n_loads < 1:
        raise InputError(f"n_loads: expected an integer >= 1, got {n_loads!r}")
    res, m = _check_curve(resolution, misfit)
    x, y2, vertex, direction, refined = _optimum(np.log(res), m**2, misfit_at)
    kept = ""
    if misfit_at is not None and not direction:  # the model's own misfit there, not the
        own = float(misfit_at(math.exp(vertex[0]))) ** 2  # parabola's floor
        best = int(np.argmin(y2))
        if own <= y2[best]:
            vertex = (vertex[0], own)
        else:  # never report a worse point than one measured (NaN: the vertex has no value)
            kept = (
                f"the parabola's vertex {math.exp(vertex[0]) * 1e6:.4g} um fits worse (misfit "
                f"{math.sqrt(own):.3g}) than the resolution {math.exp(x[best]) * 1e6:.4g} um "
                f"measured (misfit {math.sqrt(y2[best]):.3g}), which is reported instead"
            )
            vertex = (float(x[best]), float(y2[best]))
    low, high, threshold, open_low, open_high = _interval(x, y2, vertex, int(n_loads))
    open_low = open_low or (direction == "finer" and n_loads > 1)
    open_high = open_high or (direction == "coarser" and n_loads > 1)
    ends = (math.exp(low), math.exp(high)) if math.isfinite(low) else (math.nan, math.nan)
    status = 2 if n_loads < 2 else (1 if direction or open_low or open_high else 0)
    ends_of_scan = {"finer": float(res[0]), "coarser": float(res[-1])}
    optimum = ends_of_scan.get(direction, math.exp(vertex[0]))
    on_stride = np.isclose(res, optimum, rtol=1e-12, atol=0.0)
    if on_stride.any():  # a stride kept (rule 2): its own value, not exp(log(value))
        optimum = float(res[np.argmax(on_stride)])
    return EffectiveResolution(
        resolution=optimum,
        interval=ends,
        misfit=math.sqrt(vertex[1]),
        threshold=threshold,
        n_loads=int(n_loads),
        open_finer=open_low,
        open_coarser=open_high,
        direction=direction,
        refined=refined,
        sampled_resolution=np.exp(x),
        sampled_misfit=np.sqrt(y2),
        success=status == 0,
        status=status,
        message=_message(optimum, ends, (open_low, open_high), direction)
        + (f"; {kept}" if kept else ""),
        kept_sample=kept,
    )


def roughness_at_resolution(
    surface: HeightMap,
    resolution: float,
    *,
    interpolation: str = "fourier",
    neighbours: int = 4,
) -> Roughness:
    """eta (1/m^2), R (m), sigma_s (m) of the map at any resolution >= its own (m).

    The map is resampled at the step ``resolution / sqrt(dx dy)`` (the scan's definition of
    resolution, :mod:`topo.scan`) by :func:`topo.fractional_resampling.fractional_resample`
    and analysed by the Appendix A rule; at an integer step (within 1e-9 relative, round-off)
    it is the scan's stride.

    Raises
    ------
    InputError
        A resolution finer than the map's, or a resampled map without summits.
    """
    pixel = math.sqrt(surface.dx * surface.dy)
    step = float(resolution) / pixel
    if abs(step - round(step)) < 1e-9 * step:  # a stride up to round-off (e.g. exp(log(x)))
        step = float(round(step))
    stats = fractional_summit_statistics(
        surface, step, interpolation=interpolation, neighbours=neighbours
    )
    if stats.n_summits == 0:
        raise InputError(
            f"resolution: the map resampled at {resolution:.4g} m has no summit; expected "
            "a resolution at which the scan found summits"
        )
    return Roughness(stats.asperity_density, stats.summit_radius, stats.summit_height_rms)


#: The ``optimum_*`` and ``interval_*`` fields of the statistical-model result by name (SI).
OptimumFields: TypeAlias = dict[str, float | int | bool | str | np.ndarray | tuple[float, float]]


def _interpolation(surface: HeightMap) -> str:
    """Fourier resampling; bilinear for a map with missing pixels (the only choice there)."""
    return "bilinear" if np.isnan(np.asarray(surface.heights)).any() else "fourier"


def roughness_between_strides(surface: HeightMap) -> Callable[[float], Roughness]:
    """``roughness(resolution_m)``: eta (1/m^2), R (m), sigma_s (m) of the map resampled there."""
    method = _interpolation(surface)

    def roughness(resolution: float) -> Roughness:
        return roughness_at_resolution(surface, resolution, interpolation=method)

    return roughness


def model_function(
    roughness: Callable[[float], Roughness],
    areas: Callable[[Roughness], np.ndarray],
) -> Callable[[float], np.ndarray | None]:
    """``model_at(resolution_m)``: the model's A_r (m^2) at the reference's loads there (None
    when the map has no summits there), each resolution evaluated once (every reference the
    stage tries reuses it)."""
    cache: dict[float, np.ndarray | None] = {}

    def model_at(resolution: float) -> np.ndarray | None:
        key = float(resolution)
        if key not in cache:
            try:
                cache[key] = np.asarray(areas(roughness(key)), dtype=float)
            except InputError:
                cache[key] = None
        return cache[key]

    return model_at


def misfit_function(
    model_at: Callable[[float], np.ndarray | None],
    reference: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
) -> Callable[[float], float]:
    """``misfit_at(resolution_m)``: the rms ln(A_model / A_reference) there (NaN when the map
    has no summits there or the model refuses the loads)."""

    def misfit_at(resolution: float) -> float:
        model = model_at(resolution)
        if model is None or not np.all(np.isfinite(model)):
            return math.nan
        return log_misfit(model, reference)

    return misfit_at


#: Fewest samples nearest the optimum fitted by :func:`sampling_half_width`.
SAMPLING_FIT_POINTS = 10
#: Half-width (ln resolution) of the window :func:`sampling_half_width` fits: every sample
#: within a factor exp(0.25) = 1.28 of the optimum, and at least the
#: :data:`SAMPLING_FIT_POINTS` nearest. The refinement's own bracket lies within one stride of
#: the optimum; on a fine scan (the two-step job: 2 um strides at 234 um, a bracket of 1.7 %)
#: its points hold one draw of the summit-count noise, not its scatter, and no parabola fits
#: them. The window reaches across strides whose statistics scatter independently enough to
#: show that noise, while m^2 stays close to its parabola (the ln ratios are close to linear
#: in ln resolution over a factor 1.28).
SAMPLING_WINDOW = 0.25


def sampling_half_width(located: EffectiveResolution) -> float:
    """Half-width (in ln resolution) of the optimum's ambiguity from the scatter of the sampled
    m^2 about a least-squares parabola over :data:`SAMPLING_WINDOW` (module notes); 0 without
    a refinement or when the samples lie on the parabola, inf when the samples are not convex
    (no optimum)."""
    if not located.refined:
        return 0.0
    x = np.log(np.asarray(located.sampled_resolution, dtype=float))
    y = np.asarray(located.sampled_misfit, dtype=float) ** 2
    centre = math.log(located.resolution)
    distance = np.abs(x - centre)
    order = np.argsort(distance)
    near = order[: max(SAMPLING_FIT_POINTS, int(np.sum(distance <= SAMPLING_WINDOW)))]
    if near.size < 4:
        return 0.0
    coefficients, residuals, *_ = np.polyfit(x[near] - centre, y[near], 2, full=True)
    a = float(coefficients[0])
    if a <= 0:
        return math.inf
    scatter = math.sqrt(float(residuals[0]) / (near.size - 3)) if residuals.size else 0.0
    return math.sqrt(scatter / a)


def widen_interval(
    located: EffectiveResolution, half_width: float, scan_ends: tuple[float, float]
) -> tuple[np.ndarray, bool, bool]:
    """The interval (finer, coarser) in m with ``half_width`` (ln resolution) added in quadrature
    on each side, clipped to the scan's ends (m; a clipped side is open), and the open flags."""
    low, high = located.interval
    if not (math.isfinite(low) and math.isfinite(high)):
        return np.array([low, high]), located.open_finer, located.open_coarser
    centre = math.log(located.resolution)
    down = math.hypot(centre - math.log(low), half_width)
    up = math.hypot(math.log(high) - centre, half_width)
    new_low, new_high = math.exp(centre - down), math.exp(centre + up)
    open_finer = located.open_finer or new_low < scan_ends[0]
    open_coarser = located.open_coarser or new_high > scan_ends[1]
    ends = np.array([max(new_low, scan_ends[0]), min(new_high, scan_ends[1])])
    return ends, bool(open_finer), bool(open_coarser)


def _ends_roughness(interval: np.ndarray, roughness: Callable[[float], Roughness]) -> np.ndarray:
    """eta, R, sigma_s at the interval's (finer, coarser) ends, shape (3, 2); NaN unknown."""
    out = np.full((3, 2), np.nan)
    for j, end in enumerate(interval):
        if not math.isfinite(end):
            continue
        try:
            r = roughness(end)
        except InputError:
            continue
        out[:, j] = (r.asperity_density, r.summit_radius, r.summit_height_rms)
    return out


def _interval_message(
    located: EffectiveResolution,
    interval: np.ndarray,
    opens: tuple[bool, bool],
    half_width: float,
) -> str:
    """One sentence: the optimum, its interval (um) and what widened it, any open side."""
    if not np.all(np.isfinite(interval)):
        return located.message
    text = (
        f"effective resolution {located.resolution * 1e6:.4g} um, one-sigma interval "
        f"{interval[0] * 1e6:.4g}..{interval[1] * 1e6:.4g} um (loads' residuals, and the "
        f"misfit's scatter between strides: a factor {math.exp(half_width):.3g} in resolution)"
    )
    sides = [name for name, is_open in zip(("finer", "coarser"), opens, strict=True) if is_open]
    if sides:
        text += f"; open on the {' and '.join(sides)} side"
    if located.direction:
        text += f"; the data point {located.direction}"
    return text


def _shifted_optima(
    located: EffectiveResolution,
    resolution: np.ndarray,
    stride_areas: np.ndarray,
    n_loads: int,
    model_at: Callable[[float], np.ndarray | None],
    reference: np.ndarray,
    relative: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
) -> list[EffectiveResolution | None]:
    """The optimum located against the reference times (1 - u) and (1 + u) (u relative, per
    load; a factor below 0.1 is held at 0.1); None where it fails.

    The misfit against each shifted reference is taken at every resolution already sampled
    (the strides' A_r and the refinement's, cached) and its least value placed by the parabola
    of rule 1 of :func:`statmodel.effective_resolution.locate_least_misfit`; only when that
    least value is at an end of the samples is the model evaluated again, between the end and
    its neighbour (rule 2: the optimum may lie there).
    """
    strides = np.asarray(resolution, dtype=float)
    extra = [r for r in np.asarray(located.sampled_resolution, float) if not np.isclose(
        r, strides, rtol=1e-9, atol=0.0).any()]  # fmt: skip
    points = np.concatenate([strides, extra])
    tables = [np.asarray(row, dtype=float) for row in stride_areas]
    for r in extra:
        model = model_at(float(r))
        tables.append(np.full(len(reference), np.nan) if model is None else model)
    out: list[EffectiveResolution | None] = []
    for sign in (-1.0, 1.0):
        factor = np.maximum(1.0 + sign * np.nan_to_num(relative, nan=0.0), 0.1)
        shifted = np.asarray(reference, dtype=float) * factor
        misfit = np.array(
            [log_misfit(row, shifted) if np.all(np.isfinite(row)) else np.nan for row in tables]
        )
        try:
            found = locate_least_misfit(points, misfit, n_loads)
            if found.direction:
                found = locate_least_misfit(
                    points,
                    misfit,
                    n_loads,
                    misfit_at=misfit_function(model_at, shifted, log_misfit),
                )
            out.append(found)
        except InputError:
            out.append(None)
    return out


def unite_with_reference(
    interval: np.ndarray,
    opens: tuple[bool, bool],
    shifted: list[EffectiveResolution | None],
) -> tuple[np.ndarray, bool, bool, np.ndarray]:
    """The interval (finer, coarser; m) united with the optima against the reference's band,
    the open flags (a shifted optimum at an end of the scan opens that side; one not found
    opens both), and those optima (m; NaN where not found)."""
    low, high = (float(v) for v in interval)
    open_finer, open_coarser = opens
    points = np.full(2, np.nan)
    for j, located in enumerate(shifted):
        if located is None:
            open_finer = open_coarser = True
            continue
        points[j] = located.resolution
        if math.isfinite(low):
            low, high = min(low, located.resolution), max(high, located.resolution)
        open_finer = open_finer or located.direction == "finer"
        open_coarser = open_coarser or located.direction == "coarser"
    return np.array([low, high]), bool(open_finer), bool(open_coarser), points


def _optimum_dict(
    located: EffectiveResolution,
    best: Roughness,
    interval: np.ndarray,
    opens: tuple[bool, bool],
    half_width: float,
    extra: OptimumFields,
    roughness: Callable[[float], Roughness],
) -> OptimumFields:
    """The ``optimum_*`` and ``interval_*`` fields (SI) from the located optimum, its
    roughness ``best``, the final interval (m) with its open flags, the sampling half-width
    (ln resolution) and the fields already gathered (``extra``)."""
    open_finer, open_coarser = opens
    ends = _ends_roughness(interval, roughness)
    status = max(located.status, 1 if open_finer or open_coarser else 0)
    message = _interval_message(located, interval, (open_finer, open_coarser), half_width)
    if "optimum_reference_shift" in extra:
        points = np.asarray(extra["optimum_reference_shift"], dtype=float) * 1e6
        message += (
            f"; united with the optima against the reference's band, times (1 - u): "
            f"{points[0]:.4g} um and (1 + u): {points[1]:.4g} um"
        )
    if located.kept_sample:
        message += "; " + located.kept_sample
    return {
        **extra,
        "optimum_kept_sample": bool(located.kept_sample),
        "optimum_resolution": float(located.resolution),
        "optimum_interval": interval,
        "optimum_profile_interval": np.asarray(located.interval, dtype=float),
        "optimum_sampling_half_width": float(half_width),
        "optimum_misfit": float(located.misfit),
        "optimum_open_finer": open_finer,
        "optimum_open_coarser": open_coarser,
        "optimum_direction": located.direction,
        "optimum_status": int(status),
        "optimum_message": message,
        "optimum_asperity_density": float(best.asperity_density),
        "optimum_summit_radius": float(best.summit_radius),
        "optimum_summit_height_rms": float(best.summit_height_rms),
        "interval_asperity_density": ends[0],
        "interval_summit_radius": ends[1],
        "interval_summit_height_rms": ends[2],
        "sampled_resolution": np.asarray(located.sampled_resolution, dtype=float),
        "sampled_misfit": np.asarray(located.sampled_misfit, dtype=float),
    }


def optimum_fields(
    surface: HeightMap,
    resolution: np.ndarray,
    misfit: np.ndarray,
    n_loads: int,
    areas: Callable[[Roughness], np.ndarray],
    reference: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
    *,
    stride_areas: np.ndarray | None = None,
    reference_relative_uncertainty: np.ndarray | None = None,
) -> OptimumFields:
    """The ``optimum_*`` and ``interval_*`` fields of the stage result (SI).

    Parameters
    ----------
    surface : HeightMap
        The levelled map (m) the scan decimated.
    resolution, misfit : ndarray
        The scan's pixel sizes (m) and their misfits (1).
    n_loads : int
        Loads of the reference in the misfit.
    areas : callable
        ``areas(roughness) -> A_r`` (m^2) of the model at the reference's loads.
    reference : ndarray
        The reference A_r (m^2) at those loads.
    log_misfit : callable
        The stage's misfit rule.
    stride_areas : ndarray, optional
        The model's A_r (m^2) at the reference's loads per stride, shape (n_stride, n_loads):
        with ``reference_relative_uncertainty`` the strides' misfits against the shifted
        references.
    reference_relative_uncertainty : ndarray, optional
        The reference's relative one-sigma uncertainty per load (1): the optimum is also
        located against the reference times (1 - u) and (1 + u) and the interval united with
        those two optima (``optimum_reference_shift``; the misfit's own interval is
        ``optimum_misfit_interval``).

    Returns
    -------
    dict
        Empty when the misfit curve has no finite point to start from.
    """
    roughness = roughness_between_strides(surface)
    model_at = model_function(roughness, areas)
    misfit_at = misfit_function(model_at, reference, log_misfit)
    try:
        located = locate_least_misfit(resolution, misfit, n_loads, misfit_at=misfit_at)
        best = roughness(located.resolution)
    except InputError:
        return {}
    half_width = sampling_half_width(located)
    finite = np.asarray(resolution)[np.isfinite(misfit)]
    interval, open_finer, open_coarser = widen_interval(
        located, half_width, (float(finite.min()), float(finite.max()))
    )
    extra: OptimumFields = {"optimum_misfit_interval": interval.copy()}
    relative = reference_relative_uncertainty
    if relative is not None and stride_areas is not None and np.any(np.nan_to_num(relative) > 0):
        shifted = _shifted_optima(
            located, resolution, stride_areas, n_loads, model_at, reference, relative, log_misfit
        )
        interval, open_finer, open_coarser, points = unite_with_reference(
            interval, (open_finer, open_coarser), shifted
        )
        extra["optimum_reference_shift"] = points
    return _optimum_dict(
        located, best, interval, (open_finer, open_coarser), half_width, extra, roughness
    )
