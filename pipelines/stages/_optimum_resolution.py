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
(x = ln resolution; every sample within a factor 1.28 of the optimum, strides and the
refinement's points, and at least the ten nearest), takes the scatter s of m^2 about it, and the
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


def model_function(
    roughness: Callable[[float], statmodel.Roughness],
    areas: Callable[[statmodel.Roughness], np.ndarray],
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


def optimum_fields(
    surface: topo.HeightMap,
    resolution: np.ndarray,
    misfit: np.ndarray,
    n_loads: int,
    areas: Callable[[statmodel.Roughness], np.ndarray],
    reference: np.ndarray,
    log_misfit: Callable[[np.ndarray, np.ndarray], float],
    *,
    stride_areas: np.ndarray | None = None,
    reference_relative_uncertainty: np.ndarray | None = None,
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
    ends = _ends_roughness(interval, roughness)
    status = max(located.status, 1 if open_finer or open_coarser else 0)
    message = _message(located, interval, (open_finer, open_coarser), half_width)
    if "optimum_reference_shift" in extra:
        points = extra["optimum_reference_shift"] * 1e6
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
