"""The BEM reference A_r(F_z) of a map (Appendix B; squares of Fig 12d), each solve made once.

:func:`solve_reference` chains the pieces: the grid check at the check load (the middle load,
:func:`~asperity.bem.reference.load_sweeps.check_load_index`) with the Maugis range rule
(:func:`~asperity.bem.reference.grid_refinement.check_grids`), then the other loads in two chains
outwards
from it on the chosen grid (:func:`~asperity.bem.reference.load_sweeps.solve_chain`). The check
load is
also solved on the chosen grid's Fourier interpolations (x2, x4 where affordable), whose
Richardson extrapolation is the discretisation error of every load
(:mod:`~asperity.bem.reference.interpolated_refinement`). The check's solve at
the chosen stride is the sweep's solve at the check load. The map covers only part of the
experiment's nominal area A_n, so each load is scaled to the solved grid at equal nominal
pressure, F_map = F_z A_map / A_n; A_r / A_map is then the A_r / A_n of the experiment.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from asperity.bem.reference.grid_refinement import GridCheck, check_grids
from asperity.bem.reference.interpolated_refinement import MAX_REFINEMENT, REFINEMENT_PIXELS
from asperity.bem.reference.load_sweeps import (
    ContactSetup,
    Grid,
    LoadChain,
    SolveSummary,
    check_load_index,
    decimated_grid,
    load_chains,
    solve_chain,
)

__all__ = ["ReferenceSolves", "serial_map", "solve_reference"]

#: How the load chains are run: ``map_chains(solve_chain, jobs)`` returns one
#: :class:`LoadChain` per job, each job the arguments of :func:`solve_chain`.
ChainMap = Callable[[Callable[..., LoadChain], list[tuple]], Sequence[LoadChain]]


def serial_map(function: Callable[..., LoadChain], jobs: list[tuple]) -> list[LoadChain]:
    """The chains one after the other in this process (the default of :func:`solve_reference`)."""
    return [function(*job) for job in jobs]


@dataclass
class ReferenceSolves:
    """The solves of a BEM reference.

    Attributes
    ----------
    check : GridCheck
        The grid check at the check load, with the Maugis range choice.
    grid : Grid
        The grid of the chosen stride (heights m, dx, dy m).
    map_loads : ndarray
        Loads on the grid, F_z A_map / A_n, N.
    check_index : int
        Index of the check load.
    solves : list of list of SolveSummary
        Per mode (non-adhesive, then adhesive when run) and load.
    mask : ndarray of bool
        Contact at the largest load (adhesive when run).
    """

    check: GridCheck
    grid: Grid
    map_loads: np.ndarray
    check_index: int
    solves: list[list[SolveSummary]]
    mask: np.ndarray

    def field(self, name: str, dtype: type = float) -> np.ndarray:
        """One :class:`SolveSummary` attribute per (mode, load)."""
        return np.array([[getattr(s, name) for s in row] for row in self.solves], dtype=dtype)

    def messages(self, loads: np.ndarray) -> list[str]:
        """The solver's message of every solve that did not converge, with its load (N)."""
        return [
            f"{'adhesive' if m else 'non-adhesive'} F_z={loads[i]:.4g} N: {s.message}"
            for m, row in enumerate(self.solves)
            for i, s in enumerate(row)
            if not s.converged
        ]

    def totals(self) -> tuple[int, int, int]:
        """Solves made (each once: the check's at the chosen stride is the check load's; the
        range search's, sensitivity's and interpolated refinement's included), their iterations
        and FFT convolutions (the last two without the range solves)."""
        k = self.check_index
        refinement = self.check.refinement
        extra = [] if refinement is None else refinement.solves[0 if refinement.windowed else 1 :]
        counts = []
        for name in ("iterations", "convolutions"):
            sweep = self.field(name, int)
            check = self.check.field(name, int)
            refined = sum(getattr(s, name) for row in extra for s in row)
            counts.append(int(check.sum() + sweep.sum() - sweep[:, k].sum() + refined))
        sweep_size = self.field("iterations", int).size
        check_size = sum(len(row) for row in self.check.solves)
        choice = self.check.range_choice
        solves = check_size + sweep_size - len(self.solves) + (choice.solves if choice else 0)
        solves += 0 if refinement is None else refinement.extra_solves
        return solves, counts[0], counts[1]


def solve_reference(
    heights: np.ndarray,
    dx: float,
    dy: float,
    setup: ContactSetup,
    normal_loads: Sequence[float],
    nominal_area: float,
    *,
    max_stride: int,
    area_tolerance: float,
    coarsen: bool,
    adhesion: str,
    adhesion_range: float | None,
    max_refinement: int = MAX_REFINEMENT,
    refinement_pixels: int = REFINEMENT_PIXELS,
    map_chains: ChainMap = serial_map,
) -> ReferenceSolves:
    """Solve a map's BEM reference: the grid check, then every load once (module notes).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        The levelled map, m (NaN: missing pixels, never in contact).
    dx, dy : float
        Pixel sizes, m.
    setup : ContactSetup
        E* (Pa), w (J/m^2; 0: non-adhesive only), solver options and boundary.
    normal_loads : sequence of float
        Experiment loads F_z on the nominal area, N.
    nominal_area : float
        A_n of the experiment, m^2.
    max_stride, area_tolerance, coarsen, adhesion, adhesion_range
        The grid check and the adhesive law (:func:`bem.reference.grid_refinement.check_grids`).
    max_refinement, refinement_pixels
        The discretisation check at the check load on the chosen grid's Fourier
        interpolations (:mod:`bem.reference.interpolated_refinement`).
    map_chains : callable
        Runs the (at most two) load chains: ``map_chains(solve_chain, jobs)``, e.g. on two
        worker processes; default :func:`serial_map`.
    """
    loads = np.asarray(normal_loads, dtype=float)
    k = check_load_index(loads)
    check = check_grids(
        heights, dx, dy, setup, float(loads[k]) / nominal_area, max_stride=max_stride,
        area_tolerance=area_tolerance, coarsen=coarsen, adhesion=adhesion,
        adhesion_range=adhesion_range, max_refinement=max_refinement,
        refinement_pixels=refinement_pixels,
    )  # fmt: skip
    if check.range_choice is not None:
        setup = dataclasses.replace(setup, adhesion_range=check.range_choice.adhesion_range)
    grid = decimated_grid(heights, dx, dy, check.stride)
    map_loads = loads * grid.area / nominal_area
    per_load: dict[int, tuple[SolveSummary, ...]] = {k: tuple(check.solves[check.chosen])}
    mask = check.mask  # the check's own when the check load is the largest
    chains = load_chains(map_loads)
    largest = int(np.argmax(map_loads))
    jobs = [
        (grid, setup, [float(map_loads[i]) for i in c], check.start, largest in c) for c in chains
    ]
    for indices, chain in zip(chains, map_chains(solve_chain, jobs) if jobs else [], strict=True):
        for i, plain, adhesive in zip(indices, chain.plain, chain.adhesive, strict=True):
            per_load[i] = (plain,) if adhesive is None else (plain, adhesive)
        mask = chain.mask if chain.mask is not None else mask
    modes = range(len(per_load[k]))
    solves = [[per_load[i][m] for i in range(len(loads))] for m in modes]
    return ReferenceSolves(check, grid, map_loads, k, solves, mask)
