"""Warm-started load sweeps: each solve starts from a prediction built from the previous ones.

Without adhesion, from the third load on, the start is the secant predictor in the load: the
pressure extrapolated linearly from the two previous solutions, p = p_k + r (p_k - p_{k-1}),
r = (F - F_k) / (F_k - F_{k-1}), clipped at 0 (its positive part is the predicted contact set;
:func:`bem.solve_contact` rescales it to the imposed force exactly). Otherwise (the second load,
a reversed or very uneven step, a previous solve that did not converge, adhesion, where the
contact set depends on the path) the start is the previous solution.

With adhesion, a load above the previous one on the loading branch is solved as on the loading
branch from scratch (:mod:`asperity.bem.normal.branch`): the non-adhesive solution at that load,
then
the adhesive check from it. The non-adhesive part is itself warm-started by the secant
predictor of the previous non-adhesive solutions, or taken from ``non_adhesive=`` (the results
of a non-adhesive sweep at the same forces), which leaves only the checks to do.

Measured (benchmarks/bem_sweep.py, 256^2 periodic self-affine surface, 4-5 % contact, tol 1e-8):
the secant start lowers the initial residual 20x at 2.5 % load steps (6x at 20 %), which saves
about 3 of the 16-17 iterations of a warm-started solve. The preconditioned conjugate gradients
then converge at a fixed rate (about 2.2 iterations per decade of the residual), so a warm start
can only save the decades it begins closer to the solution; see docs/bem.md for the table.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from asperity.bem.errors import BemInputError
from asperity.bem.normal.assembly import COST_COUNTERS
from asperity.bem.normal.contact import solve_contact
from asperity.bem.result import ContactResult

__all__ = ["load_sweep"]


def load_sweep(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_forces: Sequence[float],
    *,
    non_adhesive: Sequence[ContactResult] | None = None,
    **options,
) -> list[ContactResult]:
    """Solve at several imposed total forces (N), each warm-started from the previous ones.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights (m), larger = closer to the flat.
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa).
    normal_forces : sequence of float
        Imposed forces F_z (N), solved in the given order (an increasing sequence is the
        natural loading path; with adhesion the order defines the branch).
    non_adhesive : sequence of ContactResult, optional
        With adhesion: converged non-adhesive results at the same forces (e.g. a previous
        ``load_sweep`` without ``work_of_adhesion``). On the loading branch the adhesive state
        is the non-adhesive one, so each loading step starts from it and costs only the
        adhesive check. Ignored without adhesion.
    **options
        Any keyword of :func:`bem.solve_contact` except the loads (``options`` a
        :class:`bem.SolverOptions`, ``work_of_adhesion``, ``periodic``, ``initial`` for the
        first solve, ...).

    Returns
    -------
    list of ContactResult
        One per force, in the given order.

    With ``adhesion="maugis"`` (and ``adhesion_range``) every solve starts from the previous
    result: its gap gives the attractive set, which grows on loading and shrinks on
    unloading (:mod:`asperity.bem.normal.maugis`); ``non_adhesive`` is not used.

    Notes
    -----
    Each solve starts from the secant prediction of the two previous solutions (see the
    module docstring; not with adhesion) or from the previous solution. The start changes only
    the number of iterations: every result meets the same ``tol`` as a cold solve.
    """
    for key in ("normal_force", "mean_pressure", "separation"):
        if key in options:
            raise BemInputError(f"load_sweep: pass the loads as normal_forces, not {key}=")
    forces = [float(f) for f in normal_forces]
    if not forces:
        raise BemInputError("load_sweep: normal_forces is empty")
    previous = options.pop("initial", None)
    # the secant start only without adhesion (solve_contact validates the value itself)
    adhesive = not (
        isinstance(options.get("work_of_adhesion", 0.0), (int, float))
        and not (options.get("work_of_adhesion", 0.0) > 0)
    )
    given = _checked_non_adhesive(non_adhesive, forces) if adhesive else None
    plain_options = {k: v for k, v in options.items() if k != "work_of_adhesion"}
    results: list[ContactResult] = []
    loading: list[ContactResult] = []  # the non-adhesive solutions of the loading steps
    for k, f in enumerate(forces):
        start = previous
        if not adhesive and len(results) >= 2:
            start = _secant_prediction(results[-2], results[-1], f)
        elif adhesive and options.get("adhesion") == "maugis":
            pass  # Maugis-Dugdale: the attractive set continues from the previous state
        elif adhesive and _on_loading_branch(previous, f):
            if given is not None:
                start = given[k]
            else:
                # the same starts as a non-adhesive sweep: its results are then bit-identical
                guess = loading[-1] if loading else previous
                if len(loading) >= 2:
                    guess = _secant_prediction(loading[-2], loading[-1], f)
                start = solve_contact(
                    heights, dx, dy, e_star, normal_force=f, initial=guess, **plain_options
                )
            loading.append(start)
        res = solve_contact(heights, dx, dy, e_star, normal_force=f, initial=start, **options)
        if adhesive and given is None and start is not previous:
            # the cost of the non-adhesive start solved here, for the caller's accounting
            res.extra["loading_start"] = _counters(start)
        results.append(res)
        previous = res
    return results


def _on_loading_branch(previous: object, force: float) -> bool:
    """An adhesive step that continues the loading branch: from scratch, or a larger force than
    a converged loading-branch (or non-adhesive) result."""
    if previous is None:
        return True
    return (
        isinstance(previous, ContactResult)
        and previous.converged
        and previous.branch in ("loading", "unique")
        and force - previous.normal_force > 1e-9 * abs(previous.normal_force)
    )


def _checked_non_adhesive(
    non_adhesive: Sequence[ContactResult] | None, forces: list[float]
) -> list[ContactResult] | None:
    """The given non-adhesive results, checked: one converged result per force, at that force
    (relative 1e-9), without adhesion."""
    if non_adhesive is None:
        return None
    given = list(non_adhesive)
    if len(given) != len(forces):
        raise BemInputError(
            f"load_sweep: non_adhesive has {len(given)} results for {len(forces)} forces"
        )
    for f, res in zip(forces, given, strict=True):
        if not isinstance(res, ContactResult) or res.branch != "unique" or not res.converged:
            raise BemInputError(
                "load_sweep: non_adhesive must hold converged non-adhesive ContactResults"
            )
        if abs(res.normal_force - f) > 1e-9 * abs(f):
            raise BemInputError(
                f"load_sweep: non_adhesive result at {res.normal_force:.6g} N for the force "
                f"{f:.6g} N (give them in the order of normal_forces)"
            )
    return given


def _counters(res: ContactResult) -> dict:
    """The cost of a non-adhesive start solved inside the sweep (for the result's extra)."""
    counters = {k: res.extra.get(k, 0) for k in COST_COUNTERS}
    return {"nit": res.nit, "seconds": res.seconds, **counters}


# widest step ratio r = (F - F_k) / (F_k - F_{k-1}) extrapolated; beyond it (or for r <= 0,
# a reversed step) the previous solution is the start
_MAX_STEP_RATIO = 2.0


def _secant_prediction(
    older: ContactResult, last: ContactResult, force: float
) -> ContactResult | np.ndarray:
    """Pressure (Pa) at ``force`` (N) extrapolated linearly in the load from two solutions,
    clipped at 0; ``last`` itself when the extrapolation is not trusted."""
    if not (older.converged and last.converged):
        return last
    df = last.normal_force - older.normal_force
    if df == 0.0:
        return last
    ratio = (force - last.normal_force) / df
    if not (0.0 < ratio <= _MAX_STEP_RATIO):
        return last
    predicted = np.subtract(last.pressure, older.pressure)  # in place below: one array
    predicted *= ratio
    predicted += last.pressure
    np.maximum(predicted, 0.0, out=predicted)
    if not predicted.sum() > 0:
        return last
    return predicted
