"""Which branch of the history-dependent adhesive problem a solve lies on.

With the Pohrt-Popov criterion an element enters the contact set where its gap closes and
leaves only where its pressure falls below -Sigma (eq:max_sigma), so the state depends on the
loading path. Without adhesion the solution is unique ("unique").

The loading branch (the load, or the approach, increasing from first contact) is the
non-adhesive solution at the same load. Reason: the pressure of the frictionless contact of a
rigid flat with an elastic half-space rises everywhere when the flat advances (a comparison
principle of the obstacle problem: the half-space stiffness, the inverse of the influence
kernel, has non-positive off-diagonal entries, so the solution of the complementarity problem
is monotone in the load), hence no element in contact ever goes into tension on a monotone
loading path, the criterion p < -Sigma never fires, and elements enter where the gap closes
exactly as without adhesion. Measured on a 128^2 rough surface (w = 0.02 E* dx, 11 % contact):
warm-started adhesive load ramps from 0.1 % of the load reach a contact fraction of 0.147 in 4
steps, 0.126 in 16, 0.112 in 64, converging to the non-adhesive 0.111; a coarse ramp (or the
former cold start from the highest 1 % of the points) lands on an unphysical branch with
elements held in tension that the loading never brought into contact.

So an adhesive solve on the loading branch is: the non-adhesive solve at the imposed load
(warm-started from a previous loading-branch state if given), then the adhesive solve started
from it, which checks the state (it converges at once). Unloading (the load decreasing, the flat
retracting) is the adhesive solve warm-started from the previous state: there the history
matters and tension holds the contact.
"""

from __future__ import annotations

import numpy as np

from asperity.bem.normal.problem import ContactProblem
from asperity.bem.result import ContactResult

__all__ = ["solve_branch"]


def initial_pressure(initial: object) -> np.ndarray:
    """The pressure field (Pa) of a warm start (a ContactResult or an array)."""
    if isinstance(initial, ContactResult):
        return initial.pressure if initial.contact_mask.any() else np.zeros(1)
    return np.asarray(initial, dtype=np.float64)


def _moves_in(problem: ContactProblem, previous: ContactResult) -> bool | None:
    """True when the imposed load is beyond ``previous``'s (more force, or a smaller
    separation), False when below, None when the same."""
    if problem.load_control:
        new, old = problem.force, previous.normal_force
        return None if _same(new, old) else new > old
    new, old = problem.separation, previous.separation
    return None if _same(new, old) else new < old


def _same(a: float, b: float) -> bool:
    """Equal up to the round-off of a force summed over the map (relative 1e-9): a result's
    ``normal_force`` is sum p dx dy, which differs from the imposed force in the last digits."""
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b))


def solve_branch(problem: ContactProblem, initial: object) -> str:
    """The branch the solve of ``problem`` from ``initial`` lies on (see
    :data:`asperity.bem.result.BRANCHES`)."""
    if not problem.adhesive:
        return "unique"
    if initial is None or not np.any(initial_pressure(initial)):
        return "loading"  # nothing in contact to hold: the loading branch from first contact
    if not isinstance(initial, ContactResult):
        return "from initial"
    inward = _moves_in(problem, initial)
    if inward is None:
        return initial.branch if initial.branch != "unique" else "loading"
    if inward:
        return "loading" if initial.branch in ("loading", "unique") else "from initial"
    return "unloading"
