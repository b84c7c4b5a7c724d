"""The starting pressure and contact set of a Polonsky-Keer iteration.

A warm start (a previous :class:`~asperity.bem.result.ContactResult` or a pressure field, Pa)
is clipped to the pressure bound (0, or -Sigma with adhesion); otherwise the cold start is a
uniform pressure on the whole map (load control) or the penetrating elements (displacement
control). An adhesive solve never starts cold: from scratch it starts from the non-adhesive
solution, its loading branch (:mod:`asperity.bem.normal.branch`). Under load control the start
carries the
imposed force exactly: rescaled without adhesion (Polonsky & Keer), shifted uniformly on the
contact set with adhesion (where the force may be zero or tensile).
"""

from __future__ import annotations

import numpy as np

from asperity.bem.errors import BemInputError
from asperity.bem.normal.kernels import shift_on_contact
from asperity.bem.normal.problem import ContactProblem
from asperity.bem.result import ContactResult

__all__ = ["starting_state"]


def _initial_fields(initial: object, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Pressure (Pa) and contact mask of a warm start, checked against the heights' shape."""
    if isinstance(initial, ContactResult):
        pressure, mask = initial.pressure, initial.contact_mask
    else:
        pressure, mask = np.asarray(initial, dtype=np.float64), None
    if pressure.shape != shape:
        raise BemInputError(
            f"solve_contact: initial pressure shape {pressure.shape} does not match heights {shape}"
        )
    if not np.all(np.isfinite(pressure)):
        raise BemInputError(
            "solve_contact: initial pressure contains non-finite values (NaN or inf)"
        )
    return pressure, (pressure != 0 if mask is None else mask)


def _warm_start(p: np.ndarray, c: np.ndarray, problem: ContactProblem, initial: object) -> None:
    nx, ny = problem.heights.shape
    pressure, mask = _initial_fields(initial, (nx, ny))
    p[:nx, :ny] = pressure
    c[:nx, :ny] = mask
    # p >= -Sigma on the contact set, 0 outside (without a full-size temporary)
    in_c = c.view(bool) if c.dtype == np.int8 and c.max(initial=0) <= 1 else c != 0
    np.maximum(p, -problem.critical_tension, out=p, where=in_c)
    p[~in_c] = 0.0
    if problem.load_control and not problem.adhesive and not p.sum() > 0:
        # nothing compressive to rescale to the imposed force: start cold instead
        p[...] = 0.0
        c[...] = 0


#: Starting contact fraction over the small-load estimate p0 / (E* h'_rms) (see
#: :func:`start_fraction`). Measured on the paper-like surface at 1024^2 (2.8 % contact, tol
#: 1e-6): 1 -> 38 iterations, 2 -> 34, 4 -> 32, 8 -> 32; the whole map (the former start) 46.
START_FRACTION_FACTOR = 4.0


def _mean_square_diff(heights: np.ndarray, axis: int, scratch: np.ndarray | None) -> float:
    """<(h[i+1] - h[i])^2> along ``axis`` (m^2): the differences (np.diff's, laid out as it
    lays them out) squared in place, in the head of ``scratch`` (a float64 array of at least
    the heights' size) or in a new array."""
    nx, ny = heights.shape
    shape = (nx - 1, ny) if axis == 0 else (nx, ny - 1)
    if scratch is None:
        d = np.empty(shape)
    else:
        d = scratch.reshape(-1)[: shape[0] * shape[1]].reshape(shape)
    lo, hi = (heights[:-1], heights[1:]) if axis == 0 else (heights[:, :-1], heights[:, 1:])
    np.subtract(hi, lo, out=d)
    np.square(d, out=d)
    return float(np.mean(d))


def rms_slope(
    heights: np.ndarray, dx: float, dy: float, scratch: np.ndarray | None = None
) -> float:
    """sqrt(<|grad h|^2>) (dimensionless) from forward differences of the heights (m); pixel
    sizes dx, dy in m. ``scratch``: a C-contiguous float64 array of at least the heights'
    size whose values may be overwritten (the cold start's pressure array: no temporary of
    the map's size)."""
    sx = _mean_square_diff(heights, 0, scratch) / dx**2 if heights.shape[0] > 1 else 0.0
    sy = _mean_square_diff(heights, 1, scratch) / dy**2 if heights.shape[1] > 1 else 0.0
    return float(np.sqrt(sx + sy))


def start_fraction(problem: ContactProblem, scratch: np.ndarray | None = None) -> float:
    """The contact fraction a cold load-controlled solve starts from: ``START_FRACTION_FACTOR``
    times p0 / (E* h'_rms), the small-load contact fraction of a rough surface up to a factor of
    order 1-2 (Persson 2001; Bush, Gibson & Thomas 1975), within [1/N, 1]; the whole map when
    the slope is zero (flat or constant heights)."""
    slope = rms_slope(problem.heights, problem.dx, problem.dy, scratch)
    p0 = abs(problem.force) / problem.nominal_area
    if not slope > 0:
        return 1.0
    return float(min(1.0, START_FRACTION_FACTOR * p0 / (problem.e_star * slope)))


def _cold_start(p: np.ndarray, c: np.ndarray, problem: ContactProblem) -> None:
    """Load control: a uniform pressure on the highest :func:`start_fraction` of the map (the
    contact set then shrinks or grows to the solution in a few iterations instead of the ~15 a
    start on the whole map takes at a few per cent contact). Displacement control: the
    penetrating elements."""
    h0 = problem.heights
    nx, ny = h0.shape
    if problem.load_control:
        # p (of the heights' shape, overwritten below) is the scratch of the slope and of the
        # partition: no temporary of the map's size besides the 1 B set ``top``
        size = h0.size
        k = int(min(size, max(1, np.ceil(start_fraction(problem, p) * size))))
        flat = p.reshape(-1)
        np.copyto(flat, h0.reshape(-1))
        flat.partition(size - k)
        top = h0 >= flat[size - k]
        # top * p0: p0 where top, 0.0 elsewhere (as np.where(top, p0, 0.0))
        np.multiply(top, problem.force / problem.nominal_area, out=p)
        c[:nx, :ny] = top
    else:
        c[:nx, :ny] = (h0 - problem.separation) > 0


def impose_force(p: np.ndarray, c: np.ndarray, problem: ContactProblem) -> None:
    """Make sum p dx dy the imposed force: rescale (no adhesion) or shift on the contact set."""
    target_sum = problem.target_pressure_sum
    psum = float(p.sum())
    if not problem.adhesive:
        p *= target_sum / psum
        return
    n_c = int(np.count_nonzero(c))
    if n_c:
        shift_on_contact(p.ravel(), c.ravel(), (target_sum - psum) / n_c)


def starting_state(
    problem: ContactProblem, initial: object = None, coarse: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Pressure (Pa) and int8 contact set on the FFT grid to start the iteration from.

    ``initial``: a warm start (ContactResult or pressure field); ``coarse``: a pressure field
    (Pa) on the heights' grid interpolated from a coarse-grid solve.
    """
    p = problem.op.zeros()
    c = np.zeros(problem.op.shape, dtype=np.int8)
    if initial is not None:
        _warm_start(p, c, problem, initial)
    elif coarse is not None:
        p[...] = coarse
        c[...] = p > 0
    if not c.any():
        _cold_start(p, c, problem)
    if problem.load_control:
        impose_force(p, c, problem)
    return p, c
