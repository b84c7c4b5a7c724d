"""The effective resolution between the scan's strides, with its interval (statistical-model
stage).

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
(x = ln resolution, the refinement's bracket), takes the scatter s of m^2 about it, and the
resolutions where the parabola lies within s of its least value are equally good:
``delta_x = sqrt(s / a)``. The interval's half-widths on each side (ln resolution) are the
profile's and ``delta_x`` in quadrature (:func:`widen_interval`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TypeAlias

import numpy as np

from asperity import statmodel, topo
from asperity.errors import InputError
from asperity.statmodel.effective_resolution import (
    EffectiveResolution,
    locate_least_misfit,
    roughness_at_resolution,
)

#: The ``optimum_*`` and ``interval_*`` fields of the statistical-model result by name (SI).
OptimumFields: TypeAlias = dict[str, float | int | bool | str | np.ndarray | tuple[float, float]]


def _interpolation(surface: topo.HeightMap) -> str:
    """Fourier resampling; bilinear for a map with missing pixels (the only choice there)."""
    return "bilinear" if np.isnan(np.asarray(surface.heights)).any() else "fourier"


def roughness_between_strides(surface: topo.HeightMap) -> Callable[[float], statmodel.Roughness]:
    """``roughness(resolution_m)``: eta (1/m^2), R (m), sigma_s (m) of the map resampled there."""
    method = _interpolation(surface)

    def roughness(resolution: float) -> statmodel.Roughness:
        return roughness_at_resolution(surface, resolution, interpolation=method)

    return roughness


def misfit_function(
    roughness: Callable[[float], statmodel.Roughness],
    areas: Callable[[statmodel.Roughness], np.ndarray],
    reference: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
) -> Callable[[float], float]:
    """``misfit_at(resolution_m)``: the rms ln(A_model / A_reference) there (NaN when the map
    has no summits there or the model refuses the loads)."""

    def misfit_at(resolution: float) -> float:
        try:
            model = areas(roughness(resolution))
        except InputError:
            return math.nan
        if not np.all(np.isfinite(model)):
            return math.nan
        return log_misfit(model, reference)

    return misfit_at


#: Samples nearest the optimum fitted by :func:`sampling_half_width` (the refinement's bracket).
SAMPLING_FIT_POINTS = 10


def sampling_half_width(located: EffectiveResolution) -> float:
    """Half-width (in ln resolution) of the optimum's ambiguity from the scatter of the sampled
    m^2 about a least-squares parabola (module notes); 0 without a refinement or when the
    samples lie on the parabola, inf when the samples are not convex (no optimum)."""
    if not located.refined:
        return 0.0
    x = np.log(np.asarray(located.sampled_resolution, dtype=float))
    y = np.asarray(located.sampled_misfit, dtype=float) ** 2
    centre = math.log(located.resolution)
    near = np.argsort(np.abs(x - centre))[:SAMPLING_FIT_POINTS]
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


def _ends_roughness(
    interval: np.ndarray, roughness: Callable[[float], statmodel.Roughness]
) -> np.ndarray:
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


def _message(
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


def optimum_fields(
    surface: topo.HeightMap,
    resolution: np.ndarray,
    misfit: np.ndarray,
    n_loads: int,
    areas: Callable[[statmodel.Roughness], np.ndarray],
    reference: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
) -> OptimumFields:
    """The ``optimum_*`` and ``interval_*`` fields of the stage result (SI).

    Parameters
    ----------
    surface : topo.HeightMap
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

    Returns
    -------
    dict
        Empty when the misfit curve has no finite point to start from.
    """
    roughness = roughness_between_strides(surface)
    misfit_at = misfit_function(roughness, areas, reference, log_misfit)
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
    ends = _ends_roughness(interval, roughness)
    status = max(located.status, 1 if open_finer or open_coarser else 0)
    return {
        "optimum_resolution": float(located.resolution),
        "optimum_interval": interval,
        "optimum_profile_interval": np.asarray(located.interval, dtype=float),
        "optimum_sampling_half_width": float(half_width),
        "optimum_misfit": float(located.misfit),
        "optimum_open_finer": open_finer,
        "optimum_open_coarser": open_coarser,
        "optimum_direction": located.direction,
        "optimum_status": int(status),
        "optimum_message": _message(located, interval, (open_finer, open_coarser), half_width),
        "optimum_asperity_density": float(best.asperity_density),
        "optimum_summit_radius": float(best.summit_radius),
        "optimum_summit_height_rms": float(best.summit_height_rms),
        "interval_asperity_density": ends[0],
        "interval_summit_radius": ends[1],
        "interval_summit_height_rms": ends[2],
        "sampled_resolution": np.asarray(located.sampled_resolution, dtype=float),
        "sampled_misfit": np.asarray(located.sampled_misfit, dtype=float),
    }
