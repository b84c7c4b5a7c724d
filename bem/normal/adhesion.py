"""Approach/retraction sweeps with Pohrt-Popov adhesion, and the pull-off force.

An element in contact may carry tension down to ``-Sigma`` (the criterion, eq:max_sigma, is in
:mod:`asperity.bem.elastic.pohrt_popov`); where ``p < -Sigma`` it delaminates (p -> 0), and an
element
out of contact comes into contact where its gap closes (g <= 0): a history-dependent
(hysteretic) rule, so the state depends on the loading path, which these drivers follow.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from asperity.bem.elastic.pohrt_popov import critical_tension, pohrt_popov_chi
from asperity.bem.errors import BemInputError
from asperity.bem.normal.contact import solve_contact
from asperity.bem.result import ContactResult

# critical_tension and pohrt_popov_chi are re-exported for code that imported them from here
__all__ = ["approach_retract", "critical_tension", "pohrt_popov_chi", "pull_off_force"]


def approach_retract(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    work_of_adhesion: float,
    separations_in: Sequence[float],
    separations_out: Sequence[float] | None = None,
    **options,
) -> tuple[list[ContactResult], list[ContactResult]]:
    """Separation-driven loading then unloading path with Pohrt-Popov adhesion, warm-started.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights (m), larger = closer to the flat.
    dx, dy, e_star, work_of_adhesion : float
        Pixel sizes (m), the reduced modulus E* (Pa) and the work of adhesion w (J/m^2).
    separations_in : sequence of float
        Separations d (m) on the approach (loading) branch, in the order applied (decreasing).
    separations_out : sequence of float, optional
        Separations d (m) on the retraction (unloading) branch, applied after the last loading
        step (increasing); default: ``separations_in`` reversed.
    **options
        Passed to :func:`bem.solve_contact` (``options`` a :class:`bem.SolverOptions`,
        ``periodic``, ...;
        ``adhesion="maugis"`` with ``adhesion_range`` (m) follows the same path with the
        Maugis-Dugdale law, :mod:`asperity.bem.normal.maugis`).

    Returns
    -------
    loading, unloading : list of ContactResult
        One result per separation on each branch; the branches differ (hysteresis) because
        elements enter contact at g = 0 but leave only where p < -Sigma.
    """
    if separations_out is None:
        separations_out = list(separations_in)[::-1]
    previous = options.pop("initial", None)

    def follow(separations: Sequence[float]) -> list[ContactResult]:
        """Solve each separation in turn, each warm-started from the previous solution."""
        nonlocal previous
        branch: list[ContactResult] = []
        for d in separations:
            previous = solve_contact(
                heights,
                dx,
                dy,
                e_star,
                separation=float(d),
                work_of_adhesion=work_of_adhesion,
                initial=previous,
                **options,
            )
            branch.append(previous)
        return branch

    loading = follow(separations_in)
    unloading = follow(separations_out)
    return loading, unloading


def pull_off_force(unloading: Sequence[ContactResult]) -> float:
    """Pull-off force (N, negative): the most tensile total force on an unloading branch.

    Under displacement control the minimum of F(d) along the stable unloading path is the
    force at which a load-controlled contact would jump off (for JKR: -3/2 pi w R; with the
    Pohrt-Popov criterion and a retraction refined until the minimum converges, +13.0 % at 10
    elements per critical contact radius, +6.6 % at 20, +4.2 % at 40: docs/bem.md). The branch
    is sampled: a coarse step in separation misses the minimum (40 steps: +11.0 / +4.6 /
    +3.1 %).

    Parameters
    ----------
    unloading : sequence of ContactResult
        The retraction branch, e.g. the second list of :func:`approach_retract`.

    Returns
    -------
    float
        min F_z (N) over the branch.
    """
    if len(unloading) == 0:
        raise BemInputError("pull_off_force: the unloading branch is empty")
    return float(min(r.normal_force for r in unloading))
