"""The grid check of a BEM reference: one load solved on a sequence of grids, and the choice.

Boundary (``periodic``)
    Periodic: the map is one period of a periodic interface, as in the paper's Appendix B for
    its measured 10 x 10 mm^2 map. The map is a sample of a larger nominal contact, loaded
    around it at the same nominal pressure; periodic images stand in for that surrounding
    interface. Its artefact is the seam where opposite edges meet: for a map that is not
    periodic the heights jump there. Free (``periodic=False``): the map is a finite specimen on
    a half-space with nothing around it (zero-padded doubled grid); right when the map is the
    whole contacting body, otherwise its artefact is global: the loaded patch sinks into a bowl
    (depth of order p L / E*) that pushes its centre out of contact.

    :func:`edge_mismatch` measures the seam: the rms height jump across opposite edges beyond
    the map's own rms pixel-to-pixel step, divided by the rms height. It is about
    sqrt(2) = 1.41 for a map whose opposite edges are uncorrelated (every measured map wider
    than its correlation length) and about 0 for a periodic map. Above
    :data:`EDGE_MISMATCH_LIMIT` = 0.5 (the seam is a cliff of half the rms height, comparable to
    the height differences that decide which summits touch) a periodic solve gets a warning.

Grid (``max_stride``, ``area_tolerance``, ``coarsen``)
    The check load is solved on the map decimated by ``max_stride``, then by each halving down
    to the full map (:func:`check_strides`), each start from the coarser solution. The error of
    a grid is its relative A_r/A_n difference from the finest grid solved (the larger of the
    non-adhesive and adhesive ones, :func:`relative_errors`). With ``coarsen`` the sweeps use
    the coarsest grid whose error is within ``area_tolerance``; otherwise the finest
    (:func:`choose_stride`). Decimation removes roughness with the pixels, so this sequence is
    the resolution dependence (:func:`resolution_dependence`: on the default job A_r moves
    8.9 % from stride 2 to 1), not an error. The chosen grid's discretisation error, the error
    bar, is measured on its Fourier interpolations, same roughness
    (:mod:`asperity.bem.reference.interpolated_refinement`, :func:`discretisation_estimate`; 3.3 %
    from 10 to 5 um on the default job). :func:`grid_extrapolations` (Richardson over the decimated
    grids) is kept for studies; it mixes both.

With Maugis-Dugdale adhesion the range is chosen first
(:mod:`asperity.bem.reference.adhesion_range`),
on the finest check grid of at most :data:`MAX_RANGE_GRID_PIXELS` pixels
(:func:`range_grid_stride`), and every stride's adhesive solve uses it. Its sensitivity is
measured last: 2 h_0 on the range's grid, h_0/2 on the x2 interpolated grid when the range's
grid is the chosen one (its zone resolved), else on the range's grid (flagged a lower bound).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from asperity.bem.progress import expect_solves
from asperity.bem.reference.adhesion_range import (
    RangeChoice,
    given_range,
    measure_sensitivity,
    search_range,
)
from asperity.bem.reference.discretisation import GridExtrapolation, richardson_extrapolation
from asperity.bem.reference.interpolated_refinement import (
    MAX_REFINEMENT,
    REFINEMENT_PIXELS,
    InterpolatedRefinement,
    refine_by_interpolation,
)
from asperity.bem.reference.load_sweeps import (
    ContactSetup,
    Grid,
    SolveSummary,
    decimated_grid,
    solve_adhesive_loading,
    solve_non_adhesive,
    summarise,
    upsample_pressure,
)
from asperity.bem.result import ContactResult

__all__ = [
    "EDGE_MISMATCH_LIMIT",
    "MAX_RANGE_GRID_PIXELS",
    "GridCheck",
    "boundary_warning",
    "check_grids",
    "check_strides",
    "discretisation_estimate",
    "choose_stride",
    "edge_mismatch",
    "grid_extrapolations",
    "grid_reason",
    "range_grid_stride",
    "relative_discretisation_uncertainty",
    "relative_errors",
    "resolution_dependence",
]

#: Above this edge mismatch (rms seam jump / rms height) a periodic solve is warned about.
EDGE_MISMATCH_LIMIT = 0.5
#: Largest grid (pixels) on which the range search and its sensitivity solve: 2500^2, the
#: paper case's 4 um grid (its 2 um grid of 5000^2 would take four more Maugis solves of about a
#: minute each).
MAX_RANGE_GRID_PIXELS = 2500 * 2500


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
    """One report line when a periodic solve wraps a map whose edges do not meet ("" if none);
    ``boundary`` is ``"periodic"`` or ``"free"``, ``mismatch`` the :func:`edge_mismatch` (1)."""
    if boundary != "periodic" or mismatch <= EDGE_MISMATCH_LIMIT:
        return ""
    return (
        f"the BEM wraps the map periodically but its opposite edges do not meet: rms jump "
        f"across the seam {mismatch:.2f} x the rms height (limit {EDGE_MISMATCH_LIMIT}); "
        'the seam adds a height step along two edges. Use [bem] boundary = "free" if the '
        "map is the whole contacting body"
    )


def check_strides(nx: int, ny: int, max_stride: int) -> list[int]:
    """Strides of the grid check of an nx x ny map: ``max_stride`` halved down to 1, coarse to
    fine, keeping grids of at least 8 x 8 pixels."""
    strides, s = [], max(int(max_stride), 1)
    while True:
        if min(nx, ny) // s >= 8:
            strides.append(s)
        if s == 1:
            return strides
        s = max(s // 2, 1)


def range_grid_stride(nx: int, ny: int, strides: list[int]) -> int:
    """The stride of the range search and its sensitivity on an nx x ny map: the finest of the
    check's ``strides`` with at most :data:`MAX_RANGE_GRID_PIXELS` pixels (the coarsest when
    none)."""
    for s in reversed(strides):
        if (nx // s) * (ny // s) <= MAX_RANGE_GRID_PIXELS:
            return s
    return strides[0]


def relative_errors(fraction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per stride (rows of ``fraction``, A_r/A_n per mode, coarse to fine): the largest
    relative difference over modes from the finest row, and from the next finer row (NaN for
    the last)."""

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
    """The coarsest stride whose relative error against the finest is within
    ``area_tolerance`` (1; the finest without ``coarsen``)."""
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
    """One sentence: which grid and why, with its error against the finest grid solved
    (``pixel``: the map's pixel size, m)."""
    um = chosen * pixel * 1e6
    if len(strides) == 1:
        return f"stride {chosen} ({um:.3g} um) only: the grid check solved a single grid"
    finest = strides[-1]
    own = (
        f"the finest grid's A_r/A_n moved {change[-2]:.2%} from stride {strides[-2]}, roughness "
        "the coarser grid does not carry (its discretisation error is measured on its Fourier "
        "interpolations)"
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
        Stride chosen for the sweeps.
    reason : str
        One sentence for a report.
    start : tuple
        (pressure Pa, force N) of the chosen stride's non-adhesive solve: the sweeps' start.
    mask : ndarray of bool
        Contact mask of the chosen stride's last solve (adhesive when run).
    range_choice : RangeChoice or None
        The Maugis range, its rule and sensitivity (None for Pohrt-Popov or w = 0).
    refinement : InterpolatedRefinement or None
        The check load on the chosen grid's Fourier interpolations: its discretisation error
        (None when ``max_refinement`` < 2).
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
    refinement: InterpolatedRefinement | None = None

    def field(self, name: str, dtype: type = float) -> np.ndarray:
        """One :class:`SolveSummary` attribute per (stride, mode)."""
        return np.array([[getattr(s, name) for s in row] for row in self.solves], dtype=dtype)

    def fractions(self) -> np.ndarray:
        """A_r/A_n per (stride, mode)."""
        return self.field("contact_fraction")

    @property
    def chosen(self) -> int:
        """Index of the chosen stride in :attr:`strides`."""
        return list(self.strides).index(self.stride)

    def converged(self, area_tolerance: float) -> bool:
        """The two finest grids agree within ``area_tolerance`` (1); True for a single grid."""
        return bool(len(self.relative_change) < 2 or self.relative_change[-2] <= area_tolerance)


@dataclass
class _StrideSolve:
    """The non-adhesive solve of one stride and its grid (kept until its adhesive solve)."""

    grid: Grid
    plain: ContactResult
    force: float


def _non_adhesive_solves(
    heights: np.ndarray, dx: float, dy: float, setup: ContactSetup, pressure: float, strides
) -> dict[int, _StrideSolve]:
    """The check pressure (Pa) solved without adhesion at every stride, coarse to fine, each
    started from the coarser pressure."""
    solved: dict[int, _StrideSolve] = {}
    previous: tuple[np.ndarray, int] | None = None
    for s in strides:
        grid = decimated_grid(heights, dx, dy, s)
        force = pressure * grid.heights.size * grid.dx * grid.dy
        initial = None
        if previous is not None:
            initial = upsample_pressure(previous[0], grid.heights.shape, previous[1] / s)
        solved[s] = _StrideSolve(grid, solve_non_adhesive(grid, setup, force, initial), force)
        previous = (solved[s].plain.pressure, s)
    return solved


def _range_choice(
    solve: _StrideSolve, setup: ContactSetup, adhesion: str, adhesion_range: float | None
) -> RangeChoice | None:
    """The Maugis range on the grid of ``solve`` (None without Maugis); its sensitivity is
    measured once the refinement is known (:func:`check_grids`)."""
    if adhesion != "maugis" or not setup.adhesive:
        return None
    if adhesion_range is None:
        return search_range(solve.grid, setup, solve.plain, solve.force)
    return given_range(solve.grid, setup, solve.plain, solve.force, adhesion_range)


def _measure_range_sensitivity(
    choice: RangeChoice,
    range_solve: _StrideSolve,
    setup: ContactSetup,
    refinement: InterpolatedRefinement | None,
) -> None:
    """The Maugis range's sensitivity (A_r at h_0 / 2 against h_0) into ``choice``: from the
    refinement's x2 grid where it solved h_0 / 2 (a resolved zone), else on the range grid;
    the range solve's result is then released."""
    resolved = None
    if refinement is not None and np.isfinite(refinement.half_range_fraction):
        ratio = refinement.half_range_fraction / refinement.half_range_reference
        resolved = (ratio, refinement.half_range_zone_elements)
    measure_sensitivity(
        choice, range_solve.grid, setup, range_solve.plain, range_solve.force, resolved
    )
    choice.result = None


def check_grids(
    heights: np.ndarray,
    dx: float,
    dy: float,
    setup: ContactSetup,
    check_pressure: float,
    *,
    max_stride: int,
    area_tolerance: float,
    coarsen: bool,
    adhesion: str = "pohrt-popov",
    adhesion_range: float | None = None,
    max_refinement: int = MAX_REFINEMENT,
    refinement_pixels: int = REFINEMENT_PIXELS,
) -> GridCheck:
    """The grid check (module notes): solves, errors against the finest, the chosen stride.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        The levelled map, m (NaN: missing pixels, never in contact).
    dx, dy : float
        Pixel sizes of the map, m.
    setup : ContactSetup
        E* (Pa), w (J/m^2; 0: non-adhesive only), solver options, boundary (its
        ``adhesion_range`` is ignored: ``adhesion`` and ``adhesion_range`` set the law).
    check_pressure : float
        Nominal pressure of the check load, Pa.
    max_stride : int
        Coarsest decimation tried (halved down to 1).
    area_tolerance : float
        Relative A_r/A_n error allowed against the finest grid solved (1).
    coarsen : bool
        Choose the coarsest grid within ``area_tolerance`` (False: the finest).
    adhesion : {"pohrt-popov", "maugis"}
        Law of the adhesive solves.
    adhesion_range : float or None
        Maugis range h_0 (m); None: chosen by :func:`bem.reference.adhesion_range.search_range`.
    max_refinement, refinement_pixels : int
        The discretisation check on the chosen grid
        (:func:`bem.reference.interpolated_refinement.refine_by_interpolation`): largest Fourier
        interpolation factor (1: none) and largest grid solved, pixels.

    Returns
    -------
    GridCheck
    """
    setup = dataclasses.replace(setup, adhesion_range=None)
    strides = check_strides(heights.shape[0], heights.shape[1], max_stride)
    expect_solves(len(strides))  # the non-adhesive check solves (a progress bar's N)
    plains = _non_adhesive_solves(heights, dx, dy, setup, check_pressure, strides)
    range_stride = range_grid_stride(heights.shape[0], heights.shape[1], strides)
    range_solve = plains[range_stride]
    choice = _range_choice(range_solve, setup, adhesion, adhesion_range)
    if choice is not None:
        setup = dataclasses.replace(setup, adhesion_range=choice.adhesion_range)
    if setup.adhesive:  # the adhesive check solves, the range grid's done by the search
        expect_solves(len(strides) - (choice is not None))
    solves, masks, starts, grids = [], {}, {}, {}
    for s in strides:
        solve = plains.pop(s)
        starts[s], grids[s] = (solve.plain.pressure, solve.force), solve.grid
        row, final = [summarise(solve.plain)], solve.plain
        if setup.adhesive:
            if choice is not None and s == range_stride:
                assert choice.result is not None  # kept until the sensitivity is measured
                final = choice.result
            else:
                final = solve_adhesive_loading(solve.grid, setup, solve.plain, solve.force)
            row.append(summarise(final))
        solves.append(row)
        masks[s] = np.asarray(final.contact_mask, dtype=bool)
        del solve, final
    fraction = np.array([[r.contact_fraction for r in row] for row in solves])
    error, change = relative_errors(fraction)
    chosen = choose_stride(strides, error, area_tolerance, coarsen)
    reason = grid_reason(strides, error, change, chosen, dx, area_tolerance, coarsen)
    refinement = None
    if max_refinement >= 2:
        half = None if choice is None or chosen != range_stride else 0.5 * choice.adhesion_range
        refinement = refine_by_interpolation(
            grids[chosen], setup, check_pressure, starts[chosen][0],
            solves[strides.index(chosen)], max_refinement=max_refinement,
            max_pixels=refinement_pixels, half_range=half,
        )  # fmt: skip
    if choice is not None:
        _measure_range_sensitivity(choice, range_solve, setup, refinement)
    del range_solve
    return GridCheck(
        np.asarray(strides), solves, error, change, chosen, reason, starts[chosen],
        masks[chosen], choice, refinement,
    )  # fmt: skip


def grid_extrapolations(
    strides: np.ndarray, fraction: np.ndarray, pixel: float
) -> list[GridExtrapolation]:
    """Richardson extrapolation (:func:`bem.richardson_extrapolation`, Roache's GCI) of the
    grid check's A_r/A_n per mode (columns of ``fraction``, rows coarse to fine) to zero pixel
    size; ``pixel`` is the map's pixel size (m), a stride's grid has ``stride * pixel``."""
    h = np.asarray(strides, dtype=float) * pixel
    return [richardson_extrapolation(h, fraction[:, m]) for m in range(fraction.shape[1])]


def relative_discretisation_uncertainty(
    extrapolation: GridExtrapolation, used_fraction: float
) -> float:
    """Relative uncertainty (1) of the A_r/A_n of the grid used, from the extrapolation.

    The value shown is the used grid's f (not the extrapolated f_0); the band f +- u_used with
    ``u_used = |f - f_0| + u`` holds the whole GCI band f_0 +- u (and f_0 itself). Its ratio
    ``u_used / f`` applies to every load of the same grid. NaN without an estimate (a single
    grid) or a zero area.
    """
    f0, u = extrapolation.value, extrapolation.uncertainty
    if not (np.isfinite(f0) and np.isfinite(u)) or used_fraction <= 0:
        return float("nan")
    return float((abs(used_fraction - f0) + u) / used_fraction)


def discretisation_estimate(
    check: GridCheck, pixel: float
) -> tuple[list[GridExtrapolation], np.ndarray]:
    """The discretisation error of the chosen grid at the check load, per mode: the Richardson
    extrapolation over its Fourier-interpolated refinements (:attr:`GridCheck.refinement`, same
    roughness; not the decimation sequence, whose movement is :func:`resolution_dependence`)
    and the relative uncertainty ``(|f - f_0| + u) / f`` of the chosen grid (1). Without a
    refinement: single-grid extrapolations (NaN, status 2). ``pixel`` is the map's pixel
    size, m."""
    if check.refinement is not None:
        return check.refinement.extrapolations, check.refinement.relative_uncertainty
    fraction = check.fractions()[check.chosen]
    h = float(check.stride) * pixel
    extrapolations = [richardson_extrapolation([h], [f]) for f in fraction]
    return extrapolations, np.full(len(fraction), np.nan)


def resolution_dependence(check: GridCheck, pixel: float) -> tuple[np.ndarray, str]:
    """How the check load's A_r/A_n moves from the next coarser decimation to the chosen grid,
    per mode (relative, 1; NaN when the chosen grid is the coarsest), and one sentence saying
    what it is: the roughness the coarser grid does not carry (the physics of resolution, not
    a discretisation error; ``pixel`` is the map's pixel size, m)."""
    fraction = check.fractions()
    c = check.chosen
    if c == 0:
        return np.full(fraction.shape[1], np.nan), ""
    coarse, used = fraction[c - 1], fraction[c]
    move = np.where(used > 0, (coarse - used) / np.where(used > 0, used, 1.0), np.nan)
    s_coarse, s_used = int(check.strides[c - 1]), int(check.stride)
    largest = float(np.nanmax(np.abs(move))) if np.isfinite(move).any() else np.nan
    sentence = (
        f"A_r/A_n moves {largest:.1%} from stride {s_coarse} ({s_coarse * pixel * 1e6:.3g} um) "
        f"to stride {s_used} ({s_used * pixel * 1e6:.3g} um): roughness the coarser grid does "
        "not carry (the physics of resolution, which the effective resolution calibrates), not "
        "a discretisation error and not in the error bar"
    )
    return move, sentence
