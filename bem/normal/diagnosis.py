"""The likely cause of a stall, from what the solver can see.

Three causes are detected (each a short code in ``ContactResult.extra["stall_causes"]`` and a
sentence appended to the message):

``outlier_pixels``
    a few pixels (at most 0.1 % of the map) more than 10 robust standard deviations
    (1.4826 x the median absolute deviation) from the median height: a spike carries a
    concentrated load whose pressure field the iteration resolves slowly; clip or remove them.
``near_full_contact``
    at least 90 % of the elements in contact: the remaining gaps are tiny compared with the
    heights and the residual reaches its round-off floor.
``tolerance_below_precision``
    ``tol`` below 10x the round-off floor of the residual for this problem, i.e. of
    2.2e-16 x (max |h| + |rigid-body term|) in the gaps: heights far from their datum (an
    offset much larger than the roughness) raise it; subtract the mean height or raise ``tol``.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.bem.normal.problem import ContactProblem

__all__ = ["stall_causes"]

EPS = 2.2e-16
OUTLIER_MADS = 10.0
OUTLIER_MAX_FRACTION = 1e-3
FULL_CONTACT = 0.9


def _outliers(h: np.ndarray) -> str | None:
    med = float(np.median(h))
    spread = 1.4826 * float(np.median(np.abs(h - med)))
    if not spread > 0:
        return None
    far = np.abs(h - med) > OUTLIER_MADS * spread
    n_far = int(np.count_nonzero(far))
    if not 0 < n_far <= max(1, OUTLIER_MAX_FRACTION * h.size):
        return None
    worst = float(np.abs(h - med).max())
    return (
        f"{n_far} outlier pixel(s) more than {OUTLIER_MADS:g} robust standard deviations from "
        f"the median height (worst {worst:.3g} m from it, robust std {spread:.3g} m): clip or "
        "remove them before the solve"
    )


def residual_floor(problem: ContactProblem, n_contact: int, offset: float, psq: float) -> float:
    """The residual that round-off of the gaps alone produces (dimensionless, as ``tol``)."""
    if psq <= 0 or n_contact == 0:
        return math.inf
    gap_noise = EPS * (problem.height_scale + abs(offset))
    return math.sqrt(n_contact) * gap_noise * problem.stiffness / math.sqrt(psq)


def stall_causes(
    problem: ContactProblem, contact_fraction: float, floor: float, tol: float
) -> list[tuple[str, str]]:
    """(code, sentence) for each cause detected; empty when none is."""
    causes = []
    outliers = _outliers(problem.heights)
    if outliers:
        causes.append(("outlier_pixels", outliers))
    if contact_fraction >= FULL_CONTACT:
        causes.append(
            (
                "near_full_contact",
                f"near-full contact ({contact_fraction:.1%} of the elements): the remaining "
                "gaps are at the round-off of the heights",
            )
        )
    if tol < 10 * floor:
        causes.append(
            (
                "tolerance_below_precision",
                f"tol {tol:.3g} is below the attainable precision of this problem (round-off "
                f"floor of the residual ~{floor:.2g}, from heights up to "
                f"{problem.height_scale:.3g} m from their datum): subtract the mean height or "
                "raise tol",
            )
        )
    return causes
