"""The discretisation error of a BEM reference: the same surface on finer grids.

Refining a measured map by decimation (strides 4, 2, 1 of
:mod:`asperity.bem.reference.grid_refinement`)
changes two things at once: the pixel and the roughness the grid carries (a stride-2 grid has no
wavelength below 4 pixels of the map). On the default job the check load's A_r moves 8.9 % from
stride 2 to 1, while halving the pixel of the same map by Fourier interpolation moves it 3.3 %:
the first is the physics of resolution (roughness the coarser grid does not carry), the second
the discretisation error. This module measures the second.

Refinement (``max_refinement``, ``refinement_pixels``)
    The grid the sweeps use (heights h_1 at pixel h, m) is Fourier-interpolated by 2 and, where
    affordable, by 4 (:func:`fourier_upsample`: periodic band-limited interpolation, so the finer
    grids hold exactly the map's Fourier content and its own nodes), and the check load is
    solved again on each at the same nominal pressure, non-adhesive then adhesive with the same
    law and range. Richardson extrapolation with Roache's grid convergence index over the
    sequence h, h/2 (, h/4) (:func:`bem.richardson_extrapolation`: two grids, order 1 assumed
    and safety factor 3; three grids, the observed order bounded to 0.5..4 and the band at least
    the spread of the three values) gives the relative uncertainty of the grid used,
    ``(|f_1 - f_0| + u) / f_1`` (the band f_1 +- that holds the whole GCI band). It is measured
    at the check load only and applied as the same relative part at every load (stated in the
    report).

    A level is solved only if its grid has at most ``refinement_pixels`` pixels. When even the
    x2 grid of the whole map is larger, the sequence is solved on a centred window of the grid
    used whose x2 grid fits (its own level-1 solve included): the window's relative error
    stands for the map's. Its finer levels are cut from the whole map's interpolation
    (:func:`fourier_upsample_window`), not interpolated from the window alone, which would ring
    at the window's edges; each level is wrapped periodically, so all share the same seam.

Adhesion range at a resolved zone (:func:`refine_by_interpolation` ``half_range``)
    The range rule makes the cohesive zone at h_0 span 3 elements of the grid used, so at h_0/2
    it spans about 1.5 there: the sensitivity solve at h_0/2 is made on the x2 grid instead
    (about 3 elements again), compared with the h_0 solve on that same grid.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from asperity.bem.elastic.fft_backend import crop_to_fast_size
from asperity.bem.progress import expect_solves
from asperity.bem.reference.discretisation import GridExtrapolation, richardson_extrapolation
from asperity.bem.reference.load_sweeps import (
    ContactSetup,
    Grid,
    SolveSummary,
    solve_adhesive_loading,
    solve_non_adhesive,
    summarise,
    upsample_pressure,
)
from asperity.errors import InputError

__all__ = [
    "MAX_REFINEMENT",
    "REFINEMENT_PIXELS",
    "InterpolatedRefinement",
    "fourier_upsample",
    "fourier_upsample_window",
    "refine_by_interpolation",
    "refinement_window",
]

#: Largest Fourier-interpolation factor of the refinement (default ``[bem] max_refinement``).
MAX_REFINEMENT = 4
#: Largest grid (pixels) of a refinement solve (default ``[bem] refinement_pixels``): 2048^2,
#: the default job's 1000^2 map at x2 (about 20 s a solve on one core).
REFINEMENT_PIXELS = 2048 * 2048


def fourier_upsample(heights: np.ndarray, factor: int) -> np.ndarray:
    """The periodic band-limited interpolation of a map onto a grid ``factor`` times finer.

    The map's discrete Fourier transform is zero-padded (the Nyquist coefficient of an even
    length split equally between +q_N and -q_N), so the finer grid carries exactly the map's
    Fourier content, no wavelength below two pixels of the map, and passes through the map's
    own nodes (``fine[::factor, ::factor] == heights`` to round-off).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights, m, finite (one period of a periodic surface).
    factor : int
        Refinement factor >= 1; the result has shape (factor nx, factor ny) and pixel sizes
        dx / factor, dy / factor.

    Returns
    -------
    ndarray (factor nx, factor ny)
        Interpolated heights, m.
    """
    heights = np.asarray(heights, dtype=float)
    if heights.ndim != 2 or min(heights.shape) < 2:
        raise InputError(f"heights: expected a 2-D map of at least 2 x 2, got {heights.shape}")
    if not np.all(np.isfinite(heights)):
        raise InputError("heights: expected finite heights (fill missing pixels first)")
    if int(factor) != factor or factor < 1:
        raise InputError(f"factor: expected an integer >= 1, got {factor!r}")
    factor = int(factor)
    if factor == 1:
        return heights.copy()
    out = heights
    for axis in (0, 1):
        out = _upsample_axis(out, factor, axis)
    return out


def _upsample_axis(values: np.ndarray, factor: int, axis: int) -> np.ndarray:
    """Band-limited periodic interpolation along one axis (see :func:`fourier_upsample`)."""
    n = values.shape[axis]
    spectrum = np.fft.rfft(values, axis=axis)
    padded_shape = list(spectrum.shape)
    padded_shape[axis] = factor * n // 2 + 1
    padded = np.zeros(padded_shape, dtype=complex)
    index = [slice(None)] * values.ndim
    index[axis] = slice(0, spectrum.shape[axis])
    padded[tuple(index)] = spectrum
    if n % 2 == 0:  # the Nyquist term is shared by +q_N and -q_N on the finer grid
        index[axis] = n // 2
        padded[tuple(index)] *= 0.5
    return np.fft.irfft(padded, n=factor * n, axis=axis) * factor


def fourier_upsample_window(
    heights: np.ndarray, factor: int, corner: tuple[int, int], shape: tuple[int, int]
) -> np.ndarray:
    """A window of the map's band-limited interpolation ``factor`` times finer, without forming
    the whole finer map (:func:`fourier_upsample` of the whole map, cut to the window).

    Unlike the interpolation of the window alone (which treats the window as one period and
    rings at its edges, where the heights jump), this is the same surface as the whole map's
    interpolation: the window's finer grid adds no content. Rows and columns are processed in
    blocks, so the memory is about ``factor^2`` windows plus ``factor`` times the map.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        The map, m, finite (one period).
    factor : int
        Refinement factor >= 1.
    corner : tuple of int
        First row and column of the window, pixels of the map.
    shape : tuple of int
        Rows and columns of the window, pixels of the map.

    Returns
    -------
    ndarray (factor shape[0], factor shape[1])
        The interpolated heights on the window, m; ``[::factor, ::factor]`` is the map's window.
    """
    heights = np.asarray(heights, dtype=float)
    (x0, y0), (wx, wy) = corner, shape
    if not (0 <= x0 and x0 + wx <= heights.shape[0] and 0 <= y0 and y0 + wy <= heights.shape[1]):
        raise InputError(
            f"window: expected rows {x0}..{x0 + wx} and columns {y0}..{y0 + wy} inside the "
            f"{heights.shape} map"
        )
    factor = int(factor)
    block = 256
    columns = slice(factor * y0, factor * (y0 + wy))
    along_y = np.concatenate(
        [
            _upsample_axis(heights[i : i + block], factor, 1)[:, columns]
            for i in range(0, heights.shape[0], block)
        ],
        axis=0,
    )
    rows = slice(factor * x0, factor * (x0 + wx))
    return np.concatenate(
        [
            _upsample_axis(along_y[:, j : j + block], factor, 0)[rows]
            for j in range(0, along_y.shape[1], block)
        ],
        axis=1,
    )


def refinement_window(shape: tuple[int, int], factor: int, max_pixels: int) -> tuple[int, int]:
    """Side lengths (pixels of the grid used) of the centred window whose ``factor`` x grid has
    at most ``max_pixels`` pixels: the whole grid when it fits, else the largest fast FFT size
    per axis (at least 8)."""
    nx, ny = shape
    if nx * ny * factor**2 <= max_pixels:
        return nx, ny
    side = max(int(math.isqrt(max_pixels // factor**2)), 8)
    probe = np.empty((min(nx, side), min(ny, side)), dtype=np.uint8)
    return crop_to_fast_size(probe, warn=False).shape


@dataclass
class InterpolatedRefinement:
    """The check load solved on the grid used and its Fourier interpolations.

    Attributes
    ----------
    factors : ndarray of int
        Refinement factors solved (1, 2 and 4 where affordable).
    pixel_size : ndarray
        Pixel size of each level along x, m.
    window : tuple of int
        Pixels (nx, ny) of the grid used that were refined: the whole grid, or a centred
        window (:attr:`windowed`).
    windowed : bool
        The sequence was solved on a window (the x2 grid of the whole map was too large).
    solves : list of list of SolveSummary
        Per level: non-adhesive, then adhesive when run (level 1 of the whole grid: the grid
        check's own solves, not repeated).
    extrapolations : list of GridExtrapolation
        Per mode: Richardson extrapolation of A_r/A_n over the levels (GCI band).
    relative_uncertainty : ndarray
        Per mode: ``(|f_1 - f_0| + u) / f_1`` of the level-1 grid (1), NaN without an estimate.
    half_range_fraction : float
        A_r/A_n at h_0 / 2 on the x2 grid (NaN when not solved).
    half_range_reference : float
        A_r/A_n at h_0 on the same x2 grid (NaN when not solved).
    half_range_zone_elements : float
        Cohesive-zone width of the h_0 / 2 solve, elements of the x2 grid (NaN when not solved).
    seconds : float
        Wall time of the refinement's solves, s.
    message : str
        One sentence for a report: levels, window, what was applied.
    """

    factors: np.ndarray
    pixel_size: np.ndarray
    window: tuple[int, int]
    windowed: bool
    solves: list[list[SolveSummary]]
    extrapolations: list[GridExtrapolation]
    relative_uncertainty: np.ndarray
    half_range_fraction: float = math.nan
    half_range_reference: float = math.nan
    half_range_zone_elements: float = math.nan
    seconds: float = 0.0
    message: str = field(default="")

    def fractions(self) -> np.ndarray:
        """A_r/A_n per (level, mode)."""
        return np.array([[s.contact_fraction for s in row] for row in self.solves])

    @property
    def extra_solves(self) -> int:
        """Solves made by the refinement (the whole grid's level 1 is the check's own)."""
        made = sum(len(row) for row in self.solves[0 if self.windowed else 1 :])
        return made + int(np.isfinite(self.half_range_fraction))


def _relative(extrapolation: GridExtrapolation, used: float) -> float:
    f0, u = extrapolation.value, extrapolation.uncertainty
    if not (np.isfinite(f0) and np.isfinite(u)) or used <= 0:
        return math.nan
    return float((abs(used - f0) + u) / used)


def _zone(result) -> float:
    width = result.extra.get("cohesive_zone_elements")
    return math.nan if width is None else float(width)


def _refinement_factors(window_pixels: int, max_refinement: int, max_pixels: int) -> list[int]:
    """The refinement factors solved: 1, then 2 and 4 where allowed and their grid of the
    window (``window_pixels`` pixels) has at most ``max_pixels`` pixels."""
    factors = [1]
    for factor in (2, 4):
        if factor <= max_refinement and window_pixels * factor**2 <= max_pixels:
            factors.append(factor)
    return factors


def _interpolated_grid(
    grid: Grid, factor: int, corner: tuple[int, int], window: tuple[int, int], windowed: bool
) -> Grid:
    """``grid`` (or its window at ``corner``) Fourier-interpolated by ``factor`` (pixel m)."""
    if windowed:
        fine = fourier_upsample_window(grid.heights, factor, corner, window)
    else:
        fine = fourier_upsample(grid.heights, factor)
    return Grid(fine, grid.dx / factor, grid.dy / factor)


def _solve_level(
    level: Grid,
    setup: ContactSetup,
    pressure: float,
    factor: int,
    previous: np.ndarray,
    half_range: float | None,
) -> tuple[list[SolveSummary], tuple[float, float, float] | None, np.ndarray]:
    """The check pressure (Pa) solved on one refinement level: its summaries (non-adhesive,
    then adhesive), the half-range solve's (fraction, reference fraction, zone elements) on the
    x2 level (None elsewhere), and the non-adhesive pressure (Pa) that starts the next level."""
    force = pressure * level.area
    initial = upsample_pressure(previous, level.heights.shape, 2 if factor > 1 else 1)
    plain = solve_non_adhesive(level, setup, force, initial)
    row = [summarise(plain)]
    half = None
    if setup.adhesive:
        adhesive = solve_adhesive_loading(level, setup, plain, force)
        row.append(summarise(adhesive))
        if factor == 2 and half_range is not None:
            at_half = dataclasses.replace(setup, adhesion_range=half_range)
            result = solve_adhesive_loading(level, at_half, plain, force)
            half = (
                float(result.contact_fraction),
                float(adhesive.contact_fraction),
                _zone(result),
            )
            del result
        del adhesive
    return row, half, plain.pressure


def _refinement_message(
    window: tuple[int, int],
    windowed: bool,
    factors: list[int],
    pixel: np.ndarray,
    max_refinement: int,
    max_pixels: int,
) -> str:
    """One sentence: where the check load was solved, by which factors, at which pixels."""
    nx, ny = window
    where = (
        f"a centred {nx} x {ny} window of the grid used (its x2 grid of the whole map exceeds "
        f"{max_pixels} pixels)"
        if windowed
        else "the whole grid used"
    )
    left = [f for f in (2, 4) if f <= max_refinement and f not in factors]
    omitted = "".join(
        f"; x{f} left out ({nx * ny * f**2} pixels > refinement_pixels {max_pixels})" for f in left
    )
    return (
        f"the check load solved on {where} Fourier-interpolated by "
        f"{', '.join(f'x{f}' for f in factors[1:]) or 'nothing (no level fits)'} (same "
        f"roughness, pixel {', '.join(f'{p * 1e6:.3g}' for p in pixel)} um{omitted})"
    )


def refine_by_interpolation(
    grid: Grid,
    setup: ContactSetup,
    pressure: float,
    start: np.ndarray,
    level_one: list[SolveSummary],
    *,
    max_refinement: int = MAX_REFINEMENT,
    max_pixels: int = REFINEMENT_PIXELS,
    half_range: float | None = None,
) -> InterpolatedRefinement:
    """Solve the check pressure on the Fourier-interpolated grids of ``grid`` (module notes).

    Parameters
    ----------
    grid : Grid
        The grid the sweeps use (heights m, pixel sizes m).
    setup : ContactSetup
        E* (Pa), w (J/m^2; 0: non-adhesive only), solver options, boundary and the adhesive
        law (its ``adhesion_range``, m, for Maugis-Dugdale).
    pressure : float
        Nominal pressure of the check load, Pa.
    start : ndarray
        The converged non-adhesive pressure (Pa) on ``grid`` at ``pressure``: the starts.
    level_one : list of SolveSummary
        The check's solves on ``grid`` (non-adhesive, then adhesive): level 1 of the whole grid.
    max_refinement : int
        Largest factor tried (2 or 4); each level only where its grid has at most
        ``max_pixels`` pixels.
    max_pixels : int
        Largest grid of a refinement solve, pixels.
    half_range : float or None
        Also solve the adhesive problem at this range (m; h_0 / 2) on the x2 grid.

    Returns
    -------
    InterpolatedRefinement
    """
    tic = time.perf_counter()
    nx, ny = refinement_window(grid.heights.shape, 2, max_pixels)
    windowed = (nx, ny) != grid.heights.shape
    corner = (grid.heights.shape[0] - nx) // 2, (grid.heights.shape[1] - ny) // 2
    x0, y0 = corner
    previous = np.array(start[x0 : x0 + nx, y0 : y0 + ny]) if windowed else start
    factors = _refinement_factors(nx * ny, max_refinement, max_pixels)
    levels = sum(not (factor == 1 and not windowed) for factor in factors)
    expect_solves(levels * (2 if setup.adhesive else 1))  # a progress bar's N
    solves: list[list[SolveSummary]] = []
    half = (math.nan, math.nan, math.nan)
    for factor in factors:
        if factor == 1 and not windowed:
            solves.append(list(level_one))
            continue
        level = _interpolated_grid(grid, factor, corner, (nx, ny), windowed)
        row, at_half, previous = _solve_level(level, setup, pressure, factor, previous, half_range)
        if at_half is not None:
            half = at_half
        solves.append(row)
        del level
    fraction = np.array([[s.contact_fraction for s in row] for row in solves])
    pixel = grid.dx / np.asarray(factors, dtype=float)
    extrapolations = [
        richardson_extrapolation(pixel, fraction[:, m]) for m in range(fraction.shape[1])
    ]
    relative = np.array([_relative(e, f) for e, f in zip(extrapolations, fraction[0], strict=True)])
    message = _refinement_message((nx, ny), windowed, factors, pixel, max_refinement, max_pixels)
    return InterpolatedRefinement(
        factors=np.asarray(factors),
        pixel_size=pixel,
        window=(nx, ny),
        windowed=windowed,
        solves=solves,
        extrapolations=extrapolations,
        relative_uncertainty=relative,
        half_range_fraction=half[0],
        half_range_reference=half[1],
        half_range_zone_elements=half[2],
        seconds=time.perf_counter() - tic,
        message=message,
    )
