"""The first crossing of a load below a start separation: the march of the rough Maugis model.

The rough Maugis-Dugdale model (:mod:`asperity.statmodel.maugis_rough`) carries a load F at the
largest separation d below the non-adhesive one d_0 where F_z(d) reaches it: it marches
d_k = d_0 - k h (k = 0, 1, ...) until F_z(d_k) >= F and refines the root in the last step. Where
F_z is known to be monotone on an interval of d, the march points inside it need not be
evaluated: a monotone function negative at both ends of a run of march points is negative at
every one in between, and if it changes sign there its root in the run is unique, so the root
the full march would bracket in one step is the root of the whole run. This module finds that
bracket with the residual evaluated in batches (one call for many separations), the points in
the interior of each monotone run skipped.

Separations in m; the residual F_z(d) - F in N.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["Crossing", "first_crossing", "monotone_runs"]

#: Batch sizes of the march: small first (most loads cross near d_0), then growing to this.
FIRST_BATCH, LARGEST_BATCH = 2, 256


@dataclass(frozen=True)
class Crossing:
    """Where the march met the load.

    Attributes
    ----------
    lower, upper : float
        Separations (m), lower < upper: the residual is >= 0 at ``lower`` and < 0 at
        ``upper``, and it has one root between them that the full march would find; both
        NaN when the load is not reached above the lowest separation. ``lower == upper ==
        d_0`` when the residual is already >= 0 at the start.
    evaluations : int
        Residual evaluations spent (each separation once).
    """

    lower: float
    upper: float
    evaluations: int

    @property
    def reached(self) -> bool:
        """Whether the residual reached 0 at or above the lowest separation."""
        return math.isfinite(self.lower)


def monotone_runs(d: np.ndarray, monotone: Sequence[tuple[float, float]]) -> np.ndarray:
    """Which march points (m, descending, in march order) must be evaluated: every point
    outside the monotone intervals (closed, disjoint), and the first and last point of each run
    of consecutive points inside one interval (the interior of a run is skipped)."""
    rising = -np.asarray(d, dtype=float)  # ascending, for the bisections
    keep = np.ones(rising.size, dtype=bool)
    for lo, hi in monotone:
        first = int(np.searchsorted(rising, -hi, side="left"))  # first d <= hi
        last = int(np.searchsorted(rising, -lo, side="right")) - 1  # last d >= lo
        if last - first >= 2:
            keep[first + 1 : last] = False
    return np.nonzero(keep)[0]


def _march_points(d0: float, step: float, d_low: float) -> np.ndarray:
    """d_k = d_0 - k h for k = 0 .. K, d_K the first below d_low (m)."""
    last = int(math.floor((d0 - d_low) / step)) + 1
    while d0 - last * step >= d_low:
        last += 1
    return d0 - step * np.arange(last + 1)


def first_crossing(
    residual: Callable[[np.ndarray], np.ndarray],
    d0: float,
    step: float,
    d_low: float,
    monotone: Sequence[tuple[float, float]] = (),
) -> Crossing:
    """The bracket of the first root of ``residual`` met marching down from ``d0`` by ``step``.

    Parameters
    ----------
    residual : callable
        F_z(d) - F (N) at an array of separations d (m), evaluated together.
    d0 : float
        Start of the march, m.
    step : float
        March step h, m (> 0).
    d_low : float
        The march stops at the first point below this separation (m), that point included.
    monotone : sequence of (float, float)
        Disjoint closed intervals of d (m) on which the residual is monotone.

    Returns
    -------
    Crossing
        The bracket [lower, upper] of the march step (or monotone run) where the residual
        first becomes >= 0; NaN when it stays negative down to the last point.
    """
    d = _march_points(d0, step, d_low)
    order = monotone_runs(d, monotone)
    done, batch, previous = 0, FIRST_BATCH, math.nan
    while done < order.size:
        index = order[done : done + batch]
        values = np.asarray(residual(d[index]), dtype=float)
        hit = np.nonzero(values >= 0.0)[0]
        if hit.size:
            k = int(hit[0])
            spent = done + index.size
            if done + k == 0:
                return Crossing(d0, d0, spent)
            upper = float(d[index[k - 1]]) if k > 0 else previous
            return Crossing(float(d[index[k]]), upper, spent)
        previous = float(d[index[-1]])
        done, batch = done + index.size, min(2 * batch, LARGEST_BATCH)
    return Crossing(math.nan, math.nan, done)
