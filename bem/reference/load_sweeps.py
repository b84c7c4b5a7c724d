"""Load-controlled solves of a BEM reference, each made once and reused.

Every solve here is :func:`bem.solve_contact` (eqs. E:BEM_eq1..E:BEM_eq4, Appendix B) in load
control; forces in N, pressures in Pa, heights and pixel sizes in m, the work of adhesion in
J/m^2.

* One adhesive loading path. With the Pohrt-Popov criterion (eq:max_sigma) an element enters
  the contact set where its gap closes, so on a monotone loading path the adhesive state is the
  non-adhesive solution at the same load (:mod:`asperity.bem.normal.branch`). Every adhesive number
  is therefore the adhesive solve started from the non-adhesive solution at the same load on the
  same grid (:func:`solve_adhesive_loading`): the ``"loading"`` branch that
  ``bem.solve_contact`` reaches from scratch, without solving the non-adhesive problem a second
  time. With Maugis-Dugdale adhesion (attraction within the range h_0 of the surface) the same
  start leads to the loading branch with jump-in: the attractive set only grows from the
  non-adhesive state (:mod:`asperity.bem.normal.maugis`).
* Nested grids. A finer grid's non-adhesive solve may start from a coarser grid's pressure
  repeated onto it (:func:`upsample_pressure`; on the 1000^2 default map 15 instead of 28
  iterations at stride 1 from stride 2).
* Load chains. The loads other than a check load are solved outwards from it
  (:func:`load_chains`): one chain up, one down, each solve started from the secant prediction
  of the two previous ones (:func:`secant_start`) or from the previous one. The two chains are
  independent and may run in parallel (:func:`solve_chain`, one call per chain).

Functions return :class:`SolveSummary` objects (small, picklable) rather than fields, so that
worker processes send back kilobytes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, TypedDict

import numpy as np

from asperity.bem.elastic.fft_backend import crop_to_fast_size
from asperity.bem.normal.contact import solve_contact
from asperity.bem.options import SolverOptions
from asperity.bem.progress import expect_solves
from asperity.bem.result import ContactResult

__all__ = [
    "ContactSetup",
    "Grid",
    "LawKeywords",
    "LoadChain",
    "SolveSummary",
    "check_load_index",
    "decimated_grid",
    "load_chains",
    "secant_start",
    "solve_adhesive_loading",
    "solve_chain",
    "solve_non_adhesive",
    "summarise",
    "upsample_pressure",
]


@dataclass(frozen=True, eq=False)
class Grid:
    """Heights on a BEM grid.

    Attributes
    ----------
    heights : ndarray (nx, ny)
        Heights h (m), larger = closer to the flat, no NaN.
    dx, dy : float
        Pixel sizes, m.
    """

    heights: np.ndarray
    dx: float
    dy: float

    @property
    def area(self) -> float:
        """Projected area nx ny dx dy of the grid, m^2."""
        return self.heights.size * self.dx * self.dy


def decimated_grid(heights: np.ndarray, dx: float, dy: float, stride: int) -> Grid:
    """The BEM grid of a map decimated by ``stride``, cropped to fast FFT sizes.

    One point in ``stride`` along x and y is kept (the paper's resampling, as
    :func:`asperity.topo.decimate`); pixel sizes become ``stride * dx``, ``stride * dy`` (m).
    The crop to sizes with prime factors 2, 3, 5, 7 (:func:`bem.crop_to_fast_size`, e.g.
    5001 -> 5000) removes at most a few trailing rows and columns; loads are to be scaled to the
    area actually solved (:attr:`Grid.area`). Missing pixels (NaN) are set to the lowest valid
    height: they never touch.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Map heights, m (NaN for missing pixels).
    dx, dy : float
        Pixel sizes of the map, m.
    stride : int
        Decimation k >= 1.
    """
    if stride > 1:
        heights, dx, dy = heights[::stride, ::stride], dx * stride, dy * stride
    grid = np.array(crop_to_fast_size(heights, warn=False), dtype=float)
    missing = np.isnan(grid)
    if missing.any():
        grid[missing] = np.nanmin(grid)
    return Grid(grid, dx, dy)


class LawKeywords(TypedDict, total=False):
    """:func:`bem.solve_contact`'s adhesion-law keywords (none: the Pohrt-Popov criterion)."""

    adhesion: str
    #: The Maugis-Dugdale range h_0, m.
    adhesion_range: float


@dataclass(frozen=True)
class ContactSetup:
    """What every solve of a reference shares besides the grid and the load.

    Attributes
    ----------
    e_star : float
        Reduced modulus E*, Pa.
    work_of_adhesion : float
        w, J/m^2; 0: non-adhesive solves only.
    options : SolverOptions
        How the solver iterates (:func:`bem.solve_contact`).
    periodic : bool
        Periodic domain (True) or a finite specimen.
    adhesion_range : float or None
        The Maugis-Dugdale range h_0 (m) of the adhesive solves; None: the Pohrt-Popov
        criterion (eq:max_sigma).
    """

    e_star: float
    work_of_adhesion: float
    options: SolverOptions
    periodic: bool = True
    adhesion_range: float | None = None

    @property
    def adhesive(self) -> bool:
        """Adhesive solves are made (w > 0)."""
        return self.work_of_adhesion > 0

    def law(self) -> LawKeywords:
        """:func:`bem.solve_contact`'s ``adhesion`` and ``adhesion_range`` keywords."""
        if self.adhesion_range is None:
            return {}
        return {"adhesion": "maugis", "adhesion_range": self.adhesion_range}


@dataclass(frozen=True)
class SolveSummary:
    """What a reference keeps of one BEM solve.

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


def summarise(result: ContactResult) -> SolveSummary:
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


def _solve_on(
    grid: Grid,
    setup: ContactSetup,
    force: float,
    initial: ContactResult | np.ndarray | None,
    **adhesion: Any,
) -> ContactResult:
    """:func:`solve_contact` on ``grid`` at ``force`` (N) with ``setup``'s modulus, boundary and
    options; ``adhesion``: the work of adhesion and the law (none: non-adhesive)."""
    return solve_contact(
        grid.heights,
        grid.dx,
        grid.dy,
        setup.e_star,
        normal_force=force,
        initial=initial,
        periodic=setup.periodic,
        options=setup.options,
        **adhesion,
    )


def solve_non_adhesive(
    grid: Grid,
    setup: ContactSetup,
    force: float,
    initial: ContactResult | np.ndarray | None = None,
) -> ContactResult:
    """The non-adhesive solve at ``force`` (N) from ``initial`` (a result, a pressure field in
    Pa, or None for a cold start)."""
    return _solve_on(grid, setup, force, initial)


def solve_adhesive_loading(
    grid: Grid, setup: ContactSetup, plain: ContactResult, force: float
) -> ContactResult:
    """The adhesive solve on the loading branch at ``force`` (N), started from ``plain``, the
    non-adhesive result at the same force on the same grid (the state the loading branch has
    there, :mod:`asperity.bem.normal.branch`), with the law of ``setup``.

    ``plain`` is passed with its force set to the imposed one: its computed force differs from
    it by round-off, which the solver would otherwise read as a (tiny) unloading step.
    """
    start = dataclasses.replace(plain, normal_force=float(force))
    return _solve_on(
        grid, setup, force, start, work_of_adhesion=setup.work_of_adhesion, **setup.law()
    )


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
    """Start (Pa) at ``force`` (N) from the two previous (pressure Pa, force N) solutions: the
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


def check_load_index(loads: np.ndarray) -> int:
    """Index of the check load in ``loads`` (N): the middle one, ``sorted(loads)[n // 2]``."""
    return int(np.argsort(loads, kind="stable")[len(loads) // 2])


def load_chains(loads: np.ndarray) -> list[list[int]]:
    """Indices of the loads (N) other than the check load, in two chains solved outwards from
    it: increasing above it, decreasing below it (empty chains left out)."""
    order = list(np.argsort(loads, kind="stable"))
    k = len(loads) // 2
    chains = [order[k + 1 :], order[:k][::-1]]
    return [[int(i) for i in c] for c in chains if c]


@dataclass
class LoadChain:
    """The solves of one chain of loads.

    Attributes
    ----------
    plain : list of SolveSummary
        Per force: the non-adhesive solve.
    adhesive : list of SolveSummary or None
        Per force: the adhesive loading-branch solve (None without adhesion).
    mask : ndarray of bool or None
        Contact mask of the last force (adhesive when run), when asked for.
    """

    plain: list[SolveSummary]
    adhesive: list[SolveSummary | None]
    mask: np.ndarray | None = None


def solve_chain(
    grid: Grid,
    setup: ContactSetup,
    forces: Sequence[float],
    start: tuple[np.ndarray, float],
    want_mask: bool = False,
) -> LoadChain:
    """Solve ``forces`` (N) in order on ``grid``, starting from ``start`` = (pressure Pa,
    force N) of a converged non-adhesive solve on this grid; adhesive on the loading branch
    at each force too when ``setup`` is adhesive (:func:`solve_adhesive_loading`).

    Each non-adhesive solve starts from :func:`secant_start` of the two previous ones.
    """
    older, last = None, start
    chain = LoadChain([], [])
    expect_solves(len(forces) * (2 if setup.adhesive else 1))  # a progress bar's N
    for i, force in enumerate(forces):
        plain = solve_non_adhesive(grid, setup, force, secant_start(older, last, force))
        final = plain
        adhesive = None
        if setup.adhesive:
            final = solve_adhesive_loading(grid, setup, plain, force)
            adhesive = summarise(final)
        chain.plain.append(summarise(plain))
        chain.adhesive.append(adhesive)
        if want_mask and i == len(forces) - 1:
            chain.mask = np.asarray(final.contact_mask, dtype=bool)
        older = last if plain.converged else None
        last = (plain.pressure, float(force))
        del final, plain
    return chain
