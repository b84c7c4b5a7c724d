"""The BEM stage's choices, stated: the boundary condition of the BEM and the grid it solves on.

Boundary (``[bem] boundary``)
    ``"periodic"`` (default): the map is one period of a periodic interface, as in the paper's
    Appendix B for its measured 10 x 10 mm^2 map. The map is a sample of a nominal contact
    seven times larger, loaded around it at the same nominal pressure; periodic images stand in
    for that surrounding interface. Its artefact is the seam where opposite edges meet: for a
    map that is not periodic the heights jump there. ``"free"``: the map is a finite specimen
    on a half-space with nothing around it (zero-padded doubled grid); right when the map is
    the whole contacting body, otherwise its artefact is global: the loaded patch sinks into a
    bowl (depth of order p L / E*) that pushes its centre out of contact.

    :func:`edge_mismatch` measures the seam: the rms height jump across opposite edges of the
    solved grid beyond the map's own rms pixel-to-pixel step, divided by the rms height. It is
    about sqrt(2) = 1.41 for a map whose opposite edges are uncorrelated (every measured map
    wider than its correlation length) and about 0 for a periodic map. Above
    :data:`EDGE_MISMATCH_LIMIT` = 0.5 (the seam is a cliff of half the rms height, comparable
    to the height differences that decide which summits touch) a periodic solve gets a warning.

Grid (``[bem] max_stride``, ``area_tolerance``, ``coarsen``)
    The check load (the middle configured load, ``sorted(loads)[n // 2]``, one of the sweep's
    loads) is solved on the map decimated by ``max_stride``, then by each halving down to the
    full map, each start from the coarser solution. The error of a grid is its relative
    A_r/A_n difference from the finest grid solved (the larger of the non-adhesive and
    adhesive ones). With ``coarsen = true`` the sweeps use the coarsest grid whose error is
    within ``area_tolerance``; with ``coarsen = false`` the finest. The finest grid's own
    discretisation error is not known; the change from the next coarser grid to it is
    reported beside it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from asperity import bem, topo
from asperity.pipelines.stages._bem_range import (
    RangeChoice,
    given_range,
    measure_sensitivity,
    search_range,
)
from asperity.pipelines.stages._bem_solves import (
    SolveSummary,
    solve_adhesive_loading,
    solve_plain,
    summarise,
    upsample_pressure,
)

#: Above this edge mismatch (rms seam jump / rms height) a periodic solve is warned about.
EDGE_MISMATCH_LIMIT = 0.5

#: Values of ``[bem] boundary``.
BOUNDARIES = ("periodic", "free")


def solver_grid(surface: topo.HeightMap, stride: int) -> tuple[np.ndarray, float, float]:
    """The BEM grid of a stride: decimated heights (m), cropped to fast FFT sizes, and dx, dy.

    Missing pixels are set to the lowest valid height (they never touch). The crop to sizes
    with prime factors 2, 3, 5, 7 (:func:`bem.crop_to_fast_size`; e.g. 5001 -> 5000) removes at
    most a few trailing rows and columns; loads are scaled to the area actually solved.
    """
    grid = topo.decimate(surface, stride) if stride > 1 else surface
    heights = np.array(bem.crop_to_fast_size(grid.heights, warn=False), dtype=float)
    missing = np.isnan(heights)
    if missing.any():
        heights[missing] = np.nanmin(heights)
    return heights, grid.dx, grid.dy


def edge_mismatch(heights: np.ndarray) -> float:
    """The height jump across the periodic seam beyond the surface's own pixel-to-pixel steps,
    over the rms height (1; see the module notes).

    ``sqrt(max(<seam jump^2> - <neighbour step^2>, 0)) / rms``: the seams are the jumps from the
    last row to the first and the last column to the first; the neighbour steps are those
    between adjacent rows and columns inside the map. A periodic map gives about 0, a map
    whose opposite edges are uncorrelated about sqrt(2).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights of the solved grid, m.
    """
    rms = float(np.std(heights))
    if rms == 0:
        return 0.0
    seam_x = np.mean((heights[0, :] - heights[-1, :]) ** 2)
    seam_y = np.mean((heights[:, 0] - heights[:, -1]) ** 2)
    step_x = np.mean(np.diff(heights, axis=0) ** 2)
    step_y = np.mean(np.diff(heights, axis=1) ** 2)
    excess = 0.5 * (seam_x - step_x + seam_y - step_y)
    return float(np.sqrt(max(excess, 0.0)) / rms)


def boundary_warning(boundary: str, mismatch: float) -> str:
    """One report line when a periodic solve wraps a map whose edges do not meet ("" if none)."""
    if boundary != "periodic" or mismatch <= EDGE_MISMATCH_LIMIT:
        return ""
    return (
        f"the BEM wraps the map periodically but its opposite edges do not meet: rms jump "
        f"across the seam {mismatch:.2f} x the rms height (limit {EDGE_MISMATCH_LIMIT}); "
        'the seam adds a height step along two edges. Use [bem] boundary = "free" if the '
        "map is the whole contacting body"
    )


def check_strides(nx: int, ny: int, max_stride: int) -> list[int]:
    """Strides of the grid check: ``max_stride`` halved down to 1, coarse to fine, keeping
    grids of at least 8 x 8 pixels."""
    strides, s = [], max(int(max_stride), 1)
    while True:
        if min(nx, ny) // s >= 8:
            strides.append(s)
        if s == 1:
            return strides
        s = max(s // 2, 1)


@dataclass
class GridCheck:
    """The grid check's solves at the check load, coarse to fine, and the grid chosen.

    Attributes
    ----------
    strides : ndarray
        Strides solved, coarse to fine.
    solves : list of list of SolveSummary
        Per stride: non-adhesive, then adhesive (loading branch) when run.
    error : ndarray
        Per stride: largest relative A_r/A_n difference from the finest stride (0 there).
    relative_change : ndarray
        Per stride: largest relative difference from the next finer stride (NaN for the finest).
    stride : int
        Stride the sweeps use.
    reason : str
        One sentence for the report.
    start : tuple
        (pressure Pa, map force N) of the chosen stride's non-adhesive solve: the sweeps'
        start (not stored).
    mask : ndarray of bool
        Contact mask of the chosen stride's last solve (adhesive when run; not stored).
    range_choice : RangeChoice or None
        The Maugis range, its rule and sensitivity (None for Pohrt-Popov or w = 0).
    """

    strides: np.ndarray
    solves: list[list[SolveSummary]]
    error: np.ndarray
    relative_change: np.ndarray
    stride: int
    reason: str
    start: tuple[np.ndarray, float] = field(repr=False)
    mask: np.ndarray = field(repr=False)
    range_choice: RangeChoice | None = None

    def fractions(self) -> np.ndarray:
        """A_r/A_n per (stride, mode)."""
        return np.array([[s.contact_fraction for s in row] for row in self.solves])


def run_grid_check(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    check_pressure: float,
    strides: list[int],
    solver: dict,
    adhesion: tuple[str, float | None] = ("pohrt-popov", None),
) -> tuple[list[list[SolveSummary]], dict[int, tuple[np.ndarray, float]], dict, RangeChoice | None]:
    """Solve the check pressure (Pa) at every stride, coarse to fine, each from the coarser.

    ``adhesion`` is ([bem] adhesion, [bem] adhesion_range m or None for the rule); with
    Maugis the range is chosen first, on the grid of :func:`range_grid_stride`
    (:mod:`._bem_range`), and every
    stride's adhesive solve uses it. Returns the summaries per stride, the (pressure, force)
    of each stride's non-adhesive solve, each stride's last contact mask, and the range choice.
    """
    plains, starts = {}, {}
    previous: tuple[np.ndarray, int] | None = None
    for s in strides:
        h, dx, dy = solver_grid(surface, s)
        force = check_pressure * h.size * dx * dy
        initial = None
        if previous is not None:
            initial = upsample_pressure(previous[0], h.shape, previous[1] / s)
        plains[s] = (solve_plain(h, dx, dy, e_star, force, solver, initial), force)
        starts[s] = (plains[s][0].pressure, force)
        previous = (plains[s][0].pressure, s)
    range_stride = range_grid_stride(surface, strides)
    choice = _range_choice(
        surface, e_star, work_of_adhesion, range_stride, plains, solver, adhesion
    )
    solves, masks = [], {}
    for s in strides:
        plain, force = plains.pop(s)
        row, final = [summarise(plain)], plain
        if work_of_adhesion > 0:
            final = _adhesive_check_solve(
                surface, s, e_star, plain, force, work_of_adhesion, solver, choice, range_stride
            )
            row.append(summarise(final))
        solves.append(row)
        masks[s] = np.asarray(final.contact_mask, dtype=bool)
    if choice is not None:
        choice.result = None
    return solves, starts, masks, choice


#: Largest grid (pixels) on which the range search and its sensitivity solve: 2500^2, the
#: paper case's 4 um grid (its 2 um grid of 5000^2 would take four more Maugis solves of about a
#: minute each).
MAX_RANGE_GRID_PIXELS = 2500 * 2500


def range_grid_stride(surface: topo.HeightMap, strides: list[int]) -> int:
    """The stride of the range search and its sensitivity: the finest of the check's
    ``strides`` with at most :data:`MAX_RANGE_GRID_PIXELS` pixels (the coarsest when none)."""
    for s in reversed(strides):
        if (surface.nx // s) * (surface.ny // s) <= MAX_RANGE_GRID_PIXELS:
            return s
    return strides[0]


def _range_choice(
    surface: topo.HeightMap,
    e_star: float,
    w: float,
    finest: int,
    plains: dict,
    solver: dict,
    adhesion: tuple[str, float | None],
) -> RangeChoice | None:
    """The Maugis range on the grid of stride ``finest`` with its sensitivity (None without
    Maugis)."""
    law, h0 = adhesion
    if law != "maugis" or w <= 0:
        return None
    grid = solver_grid(surface, finest)
    plain, force = plains[finest]
    if h0 is None:
        choice = search_range(grid, e_star, plain, force, w, solver)
    else:
        choice = given_range(grid, e_star, plain, force, w, solver, h0)
    return measure_sensitivity(choice, grid, e_star, plain, force, w, solver)


def _adhesive_check_solve(
    surface: topo.HeightMap,
    stride: int,
    e_star: float,
    plain: object,
    force: float,
    w: float,
    solver: dict,
    choice: RangeChoice | None,
    finest: int,
) -> object:
    """The check's adhesive solve at ``stride``: the range search's own solve on its grid
    (stride ``finest``), else a loading-branch solve from ``plain`` (Pohrt-Popov when
    ``choice`` is None)."""
    if choice is not None and stride == finest:
        return choice.result
    h, dx, dy = solver_grid(surface, stride)
    law = None if choice is None else choice.law
    return solve_adhesive_loading(h, dx, dy, e_star, plain, force, w, solver, law)


def relative_errors(fraction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per stride (rows of ``fraction``, coarse to fine): the largest relative difference over
    modes from the finest row, and from the next finer row (NaN for the last)."""

    def rel(a: np.ndarray, b: np.ndarray) -> float:
        ref = np.where(b > 0, b, np.nan)
        d = np.abs(a - b) / ref
        return float(np.nanmax(d)) if np.isfinite(d).any() else np.nan

    error = np.array([rel(row, fraction[-1]) for row in fraction])
    change = np.full(len(fraction), np.nan)
    for i in range(len(fraction) - 1):
        change[i] = rel(fraction[i], fraction[i + 1])
    return error, change


def choose_stride(
    strides: list[int], error: np.ndarray, area_tolerance: float, coarsen: bool
) -> int:
    """The coarsest stride whose error against the finest is within ``area_tolerance`` (the
    finest without ``coarsen``)."""
    if coarsen:
        for s, e in zip(strides, error, strict=True):
            if e <= area_tolerance:
                return s
    return strides[-1]


def grid_reason(
    strides: list[int],
    error: np.ndarray,
    change: np.ndarray,
    chosen: int,
    pixel: float,
    area_tolerance: float,
    coarsen: bool,
) -> str:
    """One sentence: which grid and why, with its error against the finest grid solved."""
    um = chosen * pixel * 1e6
    if len(strides) == 1:
        return f"stride {chosen} ({um:.3g} um) only: the grid check solved a single grid"
    finest = strides[-1]
    last_change = change[-2]
    own = (
        f"the finest grid's own error is not known (its A_r/A_n moved {last_change:.2%} from "
        f"stride {strides[-2]})"
    )
    if chosen != finest:
        i = strides.index(chosen)
        return (
            f"stride {chosen} ({um:.3g} um): A_r/A_n within {error[i]:.2%} of the finest grid "
            f"solved (stride {finest}), requested {area_tolerance:.2%}; {own}"
        )
    if not coarsen:
        return (
            f"stride {chosen} ({um:.3g} um), the map's own resolution ([bem] coarsen = false); "
            f"coarser grids served as starts; {own}"
        )
    return (
        f"stride {chosen} ({um:.3g} um), the finest solved: no coarser grid within "
        f"{area_tolerance:.2%} of it (stride {strides[-2]}: {error[-2]:.2%}); {own}"
    )


def check_grids(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    check_pressure: float,
    *,
    max_stride: int,
    area_tolerance: float,
    coarsen: bool,
    solver: dict,
    adhesion: tuple[str, float | None] = ("pohrt-popov", None),
) -> GridCheck:
    """The grid check (module notes): solves, errors against the finest, the chosen stride.

    Parameters
    ----------
    surface : topo.HeightMap
        The levelled map (m).
    e_star, work_of_adhesion : float
        E* (Pa) and w (J/m^2; 0: non-adhesive only).
    check_pressure : float
        Nominal pressure of the check load, Pa.
    max_stride, area_tolerance, coarsen
        ``[bem]`` keys of the same names.
    solver : dict
        Keywords of :func:`bem.solve_contact` (tol, max_iter, periodic).
    adhesion : tuple
        ([bem] adhesion, [bem] adhesion_range in m or None for the range rule).
    """
    strides = check_strides(surface.nx, surface.ny, max_stride)
    solves, starts, masks, choice = run_grid_check(
        surface, e_star, work_of_adhesion, check_pressure, strides, solver, adhesion
    )
    fraction = np.array([[s.contact_fraction for s in row] for row in solves])
    error, change = relative_errors(fraction)
    chosen = choose_stride(strides, error, area_tolerance, coarsen)
    reason = grid_reason(strides, error, change, chosen, surface.dx, area_tolerance, coarsen)
    return GridCheck(
        np.asarray(strides),
        solves,
        error,
        change,
        chosen,
        reason,
        starts[chosen],
        masks[chosen],
        choice,
    )


def grid_extrapolations(
    strides: np.ndarray, fraction: np.ndarray, pixel: float
) -> list[bem.GridExtrapolation]:
    """Richardson extrapolation (:func:`bem.richardson_extrapolation`, Roache's GCI) of the
    grid check's A_r/A_n per mode (columns of ``fraction``, rows coarse to fine) to zero pixel
    size; ``pixel`` is the map's pixel size (m), a stride's grid has ``stride * pixel``."""
    h = np.asarray(strides, dtype=float) * pixel
    return [bem.richardson_extrapolation(h, fraction[:, m]) for m in range(fraction.shape[1])]


def relative_discretisation_uncertainty(
    extrapolation: bem.GridExtrapolation, used_fraction: float
) -> float:
    """Relative uncertainty (1) of the A_r/A_n of the grid the sweeps use, from the extrapolation.

    The value shown is the used grid's f (not the extrapolated f_0); the band f +- u_used with
    ``u_used = |f - f_0| + u`` holds the whole GCI band f_0 +- u (and f_0 itself). Its ratio
    ``u_used / f`` applies to every load of the same grid. NaN without an estimate (a single
    grid) or a zero area.
    """
    f0, u = extrapolation.value, extrapolation.uncertainty
    if not (np.isfinite(f0) and np.isfinite(u)) or used_fraction <= 0:
        return float("nan")
    return float((abs(used_fraction - f0) + u) / used_fraction)
