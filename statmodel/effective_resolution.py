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
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

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
    refined = misfit_at is not None and x.size >= 2
    if refined:
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
