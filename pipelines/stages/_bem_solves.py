"""The BEM solves of the BEM stage, each made once and reused: the grid check and the load chains.

Every solve here is :func:`bem.solve_contact` (eqs. E:BEM_eq1..E:BEM_eq4, Appendix B) in load
control; forces in N, pressures in Pa, heights and pixel sizes in m, ``work_of_adhesion`` in
J/m^2.

* One adhesive loading path. With the Pohrt-Popov criterion (eq:max_sigma) an element enters
  the contact set where its gap closes, so on a monotone loading path the adhesive state is the
  non-adhesive solution at the same load (:mod:`asperity.bem.branch`). Every adhesive number of
  the stage is therefore the adhesive solve started from the non-adhesive solution at the same
  load on the same grid: the ``"loading"`` branch that ``bem.solve_contact`` reaches from
  scratch, without solving the non-adhesive problem a second time. The grid check and the
  sweeps use this one path. With Maugis-Dugdale adhesion (attraction within the range h_0 of
  the surface) the same start leads to the loading branch with jump-in: the attractive set
  only grows from the non-adhesive state (:mod:`asperity.bem.maugis`).
* Nested grids. The grid check solves the check load from the coarsest stride to the finest;
  each finer non-adhesive solve starts from the coarser pressure, repeated onto the finer grid
  (measured on the 1000^2 default map: 15 instead of 28 iterations at stride 1 from stride 2).
* Load chains. The other loads are solved outwards from the check load: one chain up, one
  down, each solve started from the secant prediction of the two previous ones (the pressure
  extrapolated linearly in the load, clipped at 0) or from the previous one. The two chains
  are independent, so they run in parallel on two workers.

Functions return :class:`SolveSummary` objects (small, picklable) rather than fields, so that
worker processes send back kilobytes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from asperity import bem
from asperity.pipelines.engine.parallel import worker_threads


@dataclass(frozen=True)
class SolveSummary:
    """What the stage keeps of one BEM solve.

    Attributes
    ----------
    contact_fraction : float
        A_r / A_map (1).
    normal_force : float
        Force carried, N.
    iterations, convolutions : int
        Solver iterations and FFT convolutions, the non-adhesive start included for an
        adhesive solve.
    seconds : float
        Wall time, s.
    converged : bool
        The solver met its tolerance.
    message : str
        The solver's message.
    branch : str
        ``"unique"`` (non-adhesive) or the adhesive branch (``"loading"``, ...).
    """

    contact_fraction: float
    normal_force: float
    iterations: int
    convolutions: int
    seconds: float
    converged: bool
    message: str
    branch: str


def summarise(result: Any) -> SolveSummary:
    """The :class:`SolveSummary` of a :class:`bem.ContactResult`."""
    extra = result.extra
    return SolveSummary(
        contact_fraction=float(result.contact_fraction),
        normal_force=float(result.normal_force),
        iterations=int(result.nit) + int(extra.get("coarse_iterations", 0)),
        convolutions=int(extra.get("convolutions", 0)) + int(extra.get("coarse_convolutions", 0)),
        seconds=float(result.seconds),
        converged=bool(result.converged),
        message=str(result.message),
        branch=str(result.branch),
    )


def solve_plain(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    force: float,
    solver: dict,
    initial: Any = None,
) -> Any:
    """The non-adhesive solve at ``force`` (N) from ``initial`` (a pressure field, Pa, or None)."""
    return bem.solve_contact(
        heights, dx, dy, e_star, normal_force=force, initial=initial, **_with_threads(solver)
    )


def solve_adhesive_loading(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    plain: Any,
    force: float,
    work_of_adhesion: float,
    solver: dict,
    law: dict | None = None,
) -> Any:
    """The adhesive solve on the loading branch, started from ``plain``, the non-adhesive
    result at the same ``force`` (N) on the same grid (the state the loading branch has there,
    :mod:`asperity.bem.branch`). ``law`` holds :func:`bem.solve_contact`'s ``adhesion`` and
    ``adhesion_range`` (m); None: Pohrt-Popov.

    ``plain`` is passed with its force set to the imposed one: its computed force differs from
    it by round-off, which the solver would otherwise read as a (tiny) unloading step.
    """
    start = dataclasses.replace(plain, normal_force=float(force))
    return bem.solve_contact(
        heights,
        dx,
        dy,
        e_star,
        normal_force=force,
        work_of_adhesion=work_of_adhesion,
        initial=start,
        **(law or {}),
        **_with_threads(solver),
    )


def _with_threads(solver: dict) -> dict:
    threads = worker_threads()
    return solver if threads is None or "threads" in solver else {**solver, "threads": threads}


def upsample_pressure(pressure: np.ndarray, shape: tuple[int, int], ratio: float) -> np.ndarray:
    """A coarse pressure field (Pa) on a grid ``ratio`` times finer, of ``shape``: each fine
    pixel takes the value of the nearest coarse pixel (the decimated grids share the points
    ``i * ratio``); the solver rescales the start to the imposed force."""
    rows = np.minimum(np.rint(np.arange(shape[0]) / ratio).astype(int), pressure.shape[0] - 1)
    cols = np.minimum(np.rint(np.arange(shape[1]) / ratio).astype(int), pressure.shape[1] - 1)
    return pressure[np.ix_(rows, cols)]


def secant_start(
    older: tuple[np.ndarray, float] | None, last: tuple[np.ndarray, float], force: float
) -> np.ndarray:
    """Start (Pa) at ``force`` (N) from the two previous (pressure, force) solutions: the
    pressure extrapolated linearly in the load and clipped at 0 (the last pressure when there
    is one solution, or the step is reversed or more than twice the previous one)."""
    p_last, f_last = last
    if older is None or older[1] == f_last:
        return p_last
    ratio = (force - f_last) / (f_last - older[1])
    if not 0.0 < ratio <= 2.0:
        return p_last
    predicted = np.subtract(p_last, older[0])
    predicted *= ratio
    predicted += p_last
    np.maximum(predicted, 0.0, out=predicted)
    return predicted if predicted.sum() > 0 else p_last


def solve_chain(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    forces: Sequence[float],
    work_of_adhesion: float,
    solver: dict,
    start: tuple[np.ndarray, float],
    want_mask: bool,
    law: dict | None = None,
) -> tuple[list[tuple[SolveSummary, SolveSummary | None]], np.ndarray | None]:
    """Solve ``forces`` (N) in order, starting from ``start`` = (pressure Pa, force N) of a
    converged non-adhesive solve on this grid; adhesive on the loading branch at each force
    when ``work_of_adhesion`` > 0, with the adhesion ``law`` (see
    :func:`solve_adhesive_loading`).

    Returns
    -------
    list of (SolveSummary, SolveSummary or None)
        Per force: non-adhesive, adhesive (None without adhesion).
    ndarray of bool or None
        Contact mask of the last force (adhesive when run), when ``want_mask``.
    """
    older, last = None, start
    out: list[tuple[SolveSummary, SolveSummary | None]] = []
    mask = None
    for i, force in enumerate(forces):
        plain = solve_plain(
            heights, dx, dy, e_star, force, solver, secant_start(older, last, force)
        )
        final = plain
        adhesive = None
        if work_of_adhesion > 0:
            final = solve_adhesive_loading(
                heights, dx, dy, e_star, plain, force, work_of_adhesion, solver, law
            )
            adhesive = summarise(final)
        out.append((summarise(plain), adhesive))
        if want_mask and i == len(forces) - 1:
            mask = np.asarray(final.contact_mask, dtype=bool)
        older = last if plain.converged else None
        last = (plain.pressure, float(force))
        del final, plain
    return out, mask
