"""Warnings of a surface preparation: where one step dominates what the statistics will mean."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

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
    # |dx/dy - 1|: non-square pixels make the 4-neighbour rule anisotropic
    "pixel_aspect": 0.01,
    # the next polynomial order leaves less than half the rms: form taken as roughness
    "next_order_rms_ratio": 0.5,
}


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
