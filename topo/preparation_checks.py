"""Warnings of a surface preparation: where one step dominates what the statistics will mean."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from asperity.topo.levelling import order_name

if TYPE_CHECKING:
    from asperity.topo.preparation import PreparationRecord

#: Limits above which a preparation step is said to dominate (fractions and ratios).
WARN_LIMITS = {
    # missing pixels: beyond 10 % the statistics describe a part of the map only
    "missing_fraction": 0.10,
    # form rms over roughness rms: the form, not the roughness, sets the heights
    "form_to_roughness": 10.0,
    # outliers changed: 0.1 % of the valid pixels is more than artefacts (real roughness)
    "outlier_fraction": 1e-3,
    # |ln(rms after / rms before)| of the outlier rule: beyond 5 % the rule, not the surface,
    # sets the rms height, and with it eta, R and sigma_s (code "outlier_effect")
    "outlier_rms_change": 0.05,
    # |dx/dy - 1|: non-square pixels make the 4-neighbour rule anisotropic
    "pixel_aspect": 0.01,
    # the next polynomial order leaves less than half the rms: form taken as roughness
    "next_order_rms_ratio": 0.5,
    # neighbour decorrelation along one axis above this while the other is smooth: the
    # lines do not continue each other (a grid declared with the wrong line length)
    "line_decorrelation": 0.5,
    # ... and the other axis below this fraction of it
    "smooth_axis_ratio": 0.05,
}


def neighbour_decorrelation(heights: np.ndarray) -> tuple[float, float]:
    """Mean squared neighbour difference over twice the variance, along x and along y.

    0 for a smooth map, about 1 when neighbours are unrelated (white noise), per axis.

    Parameters
    ----------
    heights : ndarray
        Levelled heights in m, shape (nx, ny); NaN pixels are ignored.

    Returns
    -------
    (float, float)
        Along axis 0 (x) and axis 1 (y); NaN when undefined (a flat map, a single line).
    """
    if min(heights.shape) < 2:
        return math.nan, math.nan
    variance = float(np.nanvar(heights))
    if not variance > 0:
        return math.nan, math.nan
    with np.errstate(invalid="ignore"):
        along_x = float(np.nanmean(np.diff(heights, axis=0) ** 2)) / (2 * variance)
        along_y = float(np.nanmean(np.diff(heights, axis=1) ** 2)) / (2 * variance)
    return along_x, along_y


def grid_warnings(heights: np.ndarray) -> list[str]:
    """A warning when the lines of the map do not continue each other.

    A file whose header declares the wrong line length (e.g. 256 x 1024 for a 512 x 512
    map: same number of points) puts unrelated points side by side along one axis: their
    differences are as large as between random points, while along the other axis the map
    stays smooth. Refusing is left to the user (a strongly anisotropic surface sampled
    coarsely across its lay can look alike); the warning names the grid fields to check.

    Parameters
    ----------
    heights : ndarray
        Levelled heights in m, shape (nx, ny).

    Returns
    -------
    list of str
    """
    along_x, along_y = neighbour_decorrelation(heights)
    if not (math.isfinite(along_x) and math.isfinite(along_y)):
        return []
    rough, smooth = max(along_x, along_y), min(along_x, along_y)
    limit, ratio = WARN_LIMITS["line_decorrelation"], WARN_LIMITS["smooth_axis_ratio"]
    if rough <= limit or smooth >= ratio * rough:
        return []
    axis = "y (between lines)" if along_y > along_x else "x (along the lines)"
    return [
        f"neighbouring pixels along {axis} differ as much as unrelated points "
        f"(mean squared difference / 2 variance = {rough:.3g}, above {limit:g}) while the "
        f"other axis is smooth ({smooth:.3g}): the grid (points per line, number of lines) "
        "declared by the file may be wrong; check the map's image before trusting its "
        "statistics"
    ]


def _missing(record: PreparationRecord) -> list[str]:
    if record.missing_fraction <= WARN_LIMITS["missing_fraction"]:
        return []
    treated = {
        "keep": "statistics use the valid pixels only and describe the measured part",
        "fill-lowest": "a large part of the map is a flat floor, not measured roughness",
        "interpolate": "a large part of the map is a smooth fill, not measured roughness",
        "refuse": "",
    }[record.missing_policy]
    return [
        f"{100 * record.missing_fraction:.1f} % of the pixels are missing (more than "
        f"{100 * WARN_LIMITS['missing_fraction']:.0f} %): {treated}; consider cropping to "
        "the measured region"
    ]


def _form(record: PreparationRecord) -> list[str]:
    messages = []
    ratio = record.form_to_roughness
    if ratio > WARN_LIMITS["form_to_roughness"]:
        messages.append(
            f"the removed form ({record.levelling}, rms {record.form_rms:.3g} m) is "
            f"{ratio:.3g} times the remaining roughness (rms {record.roughness_rms:.3g} m; "
            f"limit {WARN_LIMITS['form_to_roughness']:g}): the result depends on the form "
            "model; check that the form order suits the part's shape"
        )
    if record.next_order is not None and record.roughness_rms > 0:
        left = record.next_order_rms / record.roughness_rms
        if left < WARN_LIMITS["next_order_rms_ratio"]:
            shape = "tilt" if record.next_order == 1 else "curvature"
            messages.append(
                f"a {order_name(record.next_order)} fit would remove {100 * (1 - left):.0f} % "
                f"of the rms left after levelling '{record.levelling}' (rms "
                f"{record.roughness_rms:.3g} m -> {record.next_order_rms:.3g} m): a {shape} "
                f"is taken as roughness; use detrend {order_name(record.next_order)} or a "
                "higher form order"
            )
    return messages


def _outliers(record: PreparationRecord, scale: float) -> list[str]:
    messages = []
    ratio = record.outlier_rms_ratio
    if record.n_outliers and abs(math.log(ratio)) > WARN_LIMITS["outlier_rms_change"]:
        messages.append(
            f"outlier_effect: the outlier rule ({record.outlier_rule}) changed "
            f"{record.n_outliers} pixels ({100 * record.outlier_fraction:.3g} % of the valid "
            f"ones) and the rms height by a factor {ratio:.3g} "
            f"({record.rms_before_outliers:.4g} m -> {record.roughness_rms:.4g} m): the rule "
            "decides the statistics (sigma_s scales with the heights, R inversely); compare "
            'with --outliers none (or [surface] outliers = "none") before trusting them'
        )
    if record.outlier_fraction > WARN_LIMITS["outlier_fraction"]:
        messages.append(
            f"the outlier rule ({record.outlier_rule}) changed {record.n_outliers} pixels, "
            f"{100 * record.outlier_fraction:.3g} % of the valid ones (more than "
            f"{100 * WARN_LIMITS['outlier_fraction']:g} %): it is removing roughness, not "
            "only artefacts; use a larger threshold or none"
        )
    if scale == 0.0:
        messages.append(
            "the outlier rule was not applied: the MAD of the levelled heights is zero (more "
            "than half the pixels share one height)"
        )
    return messages


def _pixels(record: PreparationRecord) -> list[str]:
    aspect = record.dx / record.dy
    if abs(aspect - 1.0) <= WARN_LIMITS["pixel_aspect"]:
        return []
    return [
        f"non-square pixels: dx = {record.dx:.4g} m, dy = {record.dy:.4g} m (dx/dy = "
        f"{aspect:.3g}): the 4-neighbour summit rule compares neighbours at different "
        "distances, so eta and R depend on the orientation; consider resampling to square "
        "pixels"
    ]


def preparation_warnings(record: PreparationRecord, outlier_scale: float = math.nan) -> list[str]:
    """Every warning of ``record``, each one sentence with its reason and the limit crossed.

    Parameters
    ----------
    record : PreparationRecord
        What was done.
    outlier_scale : float
        Robust standard deviation used by the MAD rule (m); 0 means the rule could not act.

    Returns
    -------
    list of str
        Missing fraction > 10 %, form/roughness > 10, a next-order form that would remove
        more than half of the remaining rms (a tilt or curvature taken as roughness),
        outliers > 0.1 % of the valid pixels, a MAD of zero, dx/dy off by more than 1 %.
    """
    return _missing(record) + _form(record) + _outliers(record, outlier_scale) + _pixels(record)
