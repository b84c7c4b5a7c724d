"""Maugis-Dugdale (finite-range) adhesion in the FFT-BEM.

The cohesive law is Dugdale's (Maugis 1992): a constant tension ``sigma_0 = w / h_0`` acts on
every element whose gap g lies in [0, h_0] (contact included), nothing beyond. The net normal
traction (compressive positive) is ``p = q - sigma_0 [g <= h_0]``, where q >= 0 is the hard-wall
contact pressure, complementary to g >= 0 (E:BEM_eq2, E:BEM_eq3), and the load is
``sum p dx dy = F`` (E:BEM_eq4) or the rigid approach d is imposed (E:BEM_eq1).

Algorithm: a fixed point on the attractive set S = {g <= h_0}. For a fixed S the attraction is a
known external traction, so the problem is the non-adhesive one on the effective heights
``h + sigma_0 K * 1_S`` (the surface lifted by the deflection the attraction causes) with the
contact force ``F + sigma_0 |S|``: the preconditioned Polonsky-Keer solver of
:mod:`asperity.bem.normal.polonsky_keer` solves it, warm-started from the previous q. The gap of
that
solution gives the next S. Under displacement control the obstacle problem is monotone (more
tension, smaller gaps everywhere), so from the non-adhesive solution S only grows: the
iteration converges to the smallest fixed point above it, the loading branch with jump-in;
from a loaded state with a larger separation S only shrinks: the unloading branch. The inner
solves run at a loose tolerance (:data:`LOOSE_TOL`) while S changes, then at ``tol`` until S
is unchanged by a solve at ``tol``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from asperity.bem.elastic.operators import influence_operator
from asperity.bem.errors import BemInputError
from asperity.bem.normal.polonsky_keer import solve_problem, solve_started
from asperity.bem.normal.problem import ContactProblem, real_scalar, set_up_problem
from asperity.bem.normal.start import starting_state
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult, SolverStatus

__all__ = [
    "ADHESION_MODELS",
    "MaugisLaw",
    "check_adhesion",
    "cohesive_zone_width",
    "resolving_range",
    "solve_maugis_problem",
]

#: Values of ``adhesion=``: the paper's Pohrt-Popov criterion (default) or Maugis-Dugdale.
ADHESION_MODELS = ("pohrt-popov", "maugis")
#: Tolerance of the inner solves while the attractive set still changes (or ``tol`` if looser).
LOOSE_TOL = 1e-4
#: Cap on the solves of the attractive-set iteration.
MAX_SET_SOLVES = 400
#: A cohesive zone narrower than this (elements) is reported as not resolved by the grid.
MIN_ZONE_ELEMENTS = 3.0


@dataclass(frozen=True)
class MaugisLaw:
    """The Dugdale cohesive law: work of adhesion w (J/m^2) and range h_0 (m)."""

    work_of_adhesion: float
    adhesion_range: float

    @property
    def cohesive_stress(self) -> float:
        """sigma_0 = w / h_0 (Pa), the tension wherever 0 <= gap <= h_0."""
        return self.work_of_adhesion / self.adhesion_range


def check_adhesion(
    adhesion: object, work_of_adhesion: object, adhesion_range: object
) -> MaugisLaw | None:
    """Validate ``adhesion=`` and ``adhesion_range=`` of :func:`bem.solve_contact`: the
    Maugis law (None for Pohrt-Popov or w = 0), or a BemInputError naming the argument."""
    if adhesion not in ADHESION_MODELS:
        raise BemInputError(
            f"solve_contact: adhesion must be one of {', '.join(map(repr, ADHESION_MODELS))}, "
            f"got {adhesion!r}"
        )
    if adhesion == "pohrt-popov":
        if adhesion_range is not None:
            raise BemInputError(
                "solve_contact: adhesion_range (m) applies to adhesion='maugis' only, got "
                f"{adhesion_range!r} with adhesion='pohrt-popov'"
            )
        return None
    if adhesion_range is None:
        raise BemInputError("solve_contact: adhesion='maugis' needs adhesion_range (m), got none")
    h0 = real_scalar("adhesion_range", adhesion_range)
    if not (math.isfinite(h0) and h0 > 0):
        raise BemInputError(
            f"solve_contact: adhesion_range must be a positive finite length (m), got {h0!r}"
        )
    w = real_scalar("work_of_adhesion", work_of_adhesion)
    if not (math.isfinite(w) and w >= 0):
        raise BemInputError(
            f"solve_contact: work_of_adhesion must be >= 0 (J/m^2), got {work_of_adhesion!r}"
        )
    return MaugisLaw(w, h0) if w > 0 else None


def resolving_range(
    work_of_adhesion: float, e_star: float, dx: float, elements: float = MIN_ZONE_ELEMENTS
) -> float:
    """The range h_0 (m) whose cohesive zone at a crack-like contact edge spans ``elements``
    pixels of size dx (m): the Maugis-Dugdale zone length on the JKR side,
    c - a = pi E* w / (4 sigma_0^2) (the lambda -> infinity limit of the closed form,
    :mod:`asperity.single_asperity.maugis_dugdale`; Dugdale's pi/8 (K_I / sigma_0)^2 with
    K_I^2 = 2 E* w), set to ``elements * dx``: ``h_0 = sqrt(4 w elements dx / (pi E*))``.
    w in J/m^2, E* in Pa. Away from the JKR side the zone is narrower than this estimate
    (on a sphere at the load pi w R: 0.94x at lambda = 5, 0.48x at lambda = 1)."""
    return math.sqrt(4.0 * work_of_adhesion * elements * dx / (math.pi * e_star))


class _Case(NamedTuple):
    """One Maugis problem: heights (m), (dx, dy, E*, periodic), the law, and
    (load_control, force N, separation m)."""

    heights: np.ndarray
    grid: tuple
    law: MaugisLaw
    loads: tuple


@dataclass
class _SetIteration:
    """What the attractive-set iteration carries from one inner solve to the next."""

    attractive: np.ndarray
    inner: ContactResult | None
    tol: float
    solves: int = 0
    nit: int = 0
    convolutions: int = 0
    history: list = dataclasses.field(default_factory=list)


def _attraction_lift(
    attractive: np.ndarray,
    sigma0: float,
    dx: float,
    dy: float,
    e_star: float,
    periodic: bool,
    opts: SolverOptions,
) -> np.ndarray:
    """sigma_0 K * 1_S (m): how far the attraction on S lifts the surface towards the flat."""
    op = influence_operator(
        attractive.shape, dx, dy, e_star, opts.kernel, periodic, opts.fft_backend, opts.threads
    )
    field = op.empty()
    np.multiply(attractive, sigma0, out=field)
    # transformed into its own array (the operators' arrays have the map's shape, periodic
    # or not)
    return op(field, out=field)


def _starting_set(
    h: np.ndarray, law: MaugisLaw, initial: object, load_control: bool, force: float
) -> tuple[np.ndarray, ContactResult | None]:
    """The attractive set and warm start of a solve: from a previous result (its gap),
    or empty (the first inner solve is then the non-adhesive solution), or, for a load <= 0
    from scratch, the elements within h_0 of the highest point (first contact)."""
    if isinstance(initial, ContactResult):
        if initial.pressure.shape != h.shape:
            raise BemInputError(
                f"solve_contact: initial shape {initial.pressure.shape} does not match heights "
                f"{h.shape}"
            )
        attractive = initial.gap <= law.adhesion_range
        q = initial.pressure
        if _is_maugis(initial):  # its own law's attraction taken off: the contact pressure
            own = initial.gap <= initial.extra["adhesion_range"]
            q = q + initial.extra["cohesive_stress"] * own
        inner = dataclasses.replace(initial, pressure=np.maximum(q, 0.0), branch="unique")
        return attractive, inner
    if initial is not None:
        raise BemInputError(
            "solve_contact: with adhesion='maugis', initial must be a ContactResult (its gap "
            "defines the attractive set)"
        )
    if load_control and force <= 0:
        return h >= h.max() - law.adhesion_range, None
    return np.zeros(h.shape, dtype=bool), None


def _is_maugis(result: ContactResult) -> bool:
    return result.extra.get("adhesion") == "maugis"


def _branch(initial: object, loads: tuple[bool, float, float]) -> str:
    """Loading (from scratch, a non-adhesive state, or further in from a loading state),
    unloading (back out from a Maugis state) or "from initial"."""
    if not isinstance(initial, ContactResult) or not _is_maugis(initial):
        return "loading"
    load_control, force, separation = loads
    if load_control:
        inward = force > initial.normal_force * (1 + 1e-9 * np.sign(initial.normal_force))
    else:
        inward = separation < initial.separation
    if inward:
        return "loading" if initial.branch == "loading" else "from initial"
    return "unloading"


def _inner_solve(case: _Case, it: _SetIteration, opts: SolverOptions) -> ContactResult | None:
    """The non-adhesive solve for the contact pressure q with the attraction on the current S
    as an external traction; None when a load-controlled S carries the whole force in
    tension (no compressive contact force left)."""
    dx, dy, e_star, periodic = case.grid
    load_control, force, separation = case.loads
    sigma0 = case.law.cohesive_stress
    if load_control:
        contact_force = force + sigma0 * float(np.count_nonzero(it.attractive)) * dx * dy
        if not contact_force > 0:
            return None
        load = {"normal_force": contact_force}
    else:
        load = {"separation": separation}
    started = time.perf_counter()
    if it.inner is not None:
        # the warm start reads the previous solution's pressure and contact set only: its gap
        # (8 B per point; the new attractive set was taken from it) goes before the lift and
        # the next state are allocated
        it.inner = dataclasses.replace(it.inner, gap=None)  # type: ignore[arg-type]
    # h + sigma_0 K * 1_S, summed into the lift's array (addition commutes bit for bit)
    lifted = _attraction_lift(it.attractive, sigma0, dx, dy, e_star, periodic, opts)
    lifted += case.heights
    inner_opts = dataclasses.replace(opts, tol=it.tol)
    # in-place transforms: the inner iteration stores its direction and work arrays in float32
    # (the lifted heights and the attractive set cost 9 B per point more than a plain solve)
    problem = set_up_problem(lifted, dx, dy, e_star, load, 0.0, periodic, inner_opts, in_place=True)
    del lifted
    if it.inner is None:
        return solve_problem(problem, None, inner_opts, started)
    p, c = starting_state(problem, it.inner)
    # the warm start now lives in p and c: drop the previous solution (pressure, gap, mask)
    # before the iteration allocates its arrays
    it.inner = None
    return solve_started(problem, p, c, inner_opts, started)


def _iterate_set(case: _Case, it: _SetIteration, opts: SolverOptions) -> tuple[SolverStatus, str]:
    """Inner solves until S = {gap <= h_0} is unchanged by a solve at ``tol``."""
    seen: set[bytes] = set()
    while it.solves < MAX_SET_SOLVES:
        # the previous solution is held by ``it`` alone (the solve may drop it), and the
        # attractive set by ``it`` alone (a set found equal to it is not held through the
        # next solve: 1 B per point)
        inner = new = None
        inner = _inner_solve(case, it, opts)
        if inner is None:
            return SolverStatus.CONTACT_LOST, (
                f"contact lost: the imposed force {case.loads[1]:.6g} N is beyond what the "
                "attraction can hold (no compressive contact force is left)"
            )
        _count(it, inner)
        it.inner = inner
        if not inner.converged:
            return SolverStatus(inner.status), inner.message
        new = inner.gap <= case.law.adhesion_range
        if np.array_equal(new, it.attractive):
            if it.tol <= opts.tol:
                return SolverStatus.CONVERGED, (
                    f"converged: residual {inner.residual:.3g} < tol {opts.tol:.3g}, attractive "
                    f"set settled after {it.solves} solves"
                )
            it.tol = opts.tol
            continue
        # a digest of the set (a packed copy of every set seen would cost n/8 B per solve)
        key = hashlib.sha256(np.packbits(new).tobytes()).digest()
        if it.tol <= opts.tol and key in seen:
            return SolverStatus.STALLED, (
                "stalled: the attractive set {gap <= h_0} cycles between states (elements "
                f"with a gap at h_0 to the solver's precision), after {it.solves} solves"
            )
        seen.add(key)
        it.attractive = new
    return SolverStatus.ITERATION_CAP, (
        f"iteration cap reached: the attractive set still changed after {MAX_SET_SOLVES} solves"
    )


def _count(it: _SetIteration, inner: ContactResult) -> None:
    """Add one inner solve's iterations, residual history and convolutions."""
    history = inner.residual_history if not it.history else inner.residual_history[1:]
    it.history.extend(np.asarray(history, dtype=float).tolist())
    it.solves += 1
    it.nit += inner.nit
    it.convolutions += int(inner.extra.get("convolutions", 0)) + 1


def cohesive_zone_width(
    contact: np.ndarray, attractive: np.ndarray, periodic: bool
) -> float | None:
    """Mean width (elements) of the cohesive zone, the attracted elements out of contact:
    their number over the length of the contact line in elements, estimated as pi/4 times the
    number of element edges between contact and non-contact (the Manhattan length of an
    isotropic line); None when nothing is in contact (no contact line to measure from)."""
    contact = np.asarray(contact, dtype=bool)
    edges = 0
    for axis in (0, 1):
        if periodic:
            edges += int(np.count_nonzero(contact != np.roll(contact, 1, axis=axis)))
        else:
            edges += int(np.count_nonzero(np.diff(contact, axis=axis)))
    if edges == 0:
        return None
    zone = int(np.count_nonzero(np.asarray(attractive, dtype=bool) & ~contact))
    return zone / (edges * math.pi / 4.0)


def _zone_warning(width: float | None, law: MaugisLaw, dx: float) -> list[str]:
    """The under-resolution warning (a list, empty when the zone is resolved)."""
    if width is None or width >= MIN_ZONE_ELEMENTS:
        return []
    return [
        f"cohesive zone not resolved: it spans {width:.2g} elements on average (< "
        f"{MIN_ZONE_ELEMENTS:g}) with range h_0 = {law.adhesion_range:.3g} m and "
        f"sigma_0 = {law.cohesive_stress:.3g} Pa at dx = {dx:.3g} m; the contact edge is "
        "then JKR-like on the grid and areas and forces carry discretisation errors of "
        "several per cent: refine the grid or lengthen the range"
    ]


def _assemble(
    it: _SetIteration,
    inner: ContactResult,
    law: MaugisLaw,
    grid: tuple,
    stop: tuple[SolverStatus, str],
    branch: str,
    started: float,
) -> ContactResult:
    """The Maugis result from the last inner solve ``inner``: net traction q - sigma_0 1_S,
    force, attraction diagnostics."""
    dx, dy, _, periodic = grid
    attractive = it.attractive
    # p = q - sigma_0 1_S in the inner result's own array (no full-size temporaries)
    pressure = np.subtract(
        inner.pressure, law.cohesive_stress, out=inner.pressure, where=attractive
    )
    force = float(pressure.sum()) * dx * dy
    width = cohesive_zone_width(inner.contact_mask, attractive, periodic)
    warnings = _zone_warning(width, law, dx)
    status, message = stop
    if warnings:
        message = f"{message}; warning: {warnings[0]}"
    n_attr = int(np.count_nonzero(attractive))
    extra = {
        **inner.extra,
        "adhesion": "maugis",
        "adhesion_range": law.adhesion_range,
        "cohesive_stress": law.cohesive_stress,
        "work_of_adhesion": law.work_of_adhesion,
        "attractive_area": n_attr * dx * dy,
        "attractive_fraction": n_attr / attractive.size,
        "cohesive_zone_elements": width,
        "set_solves": it.solves,
        "convolutions": it.convolutions,
        "warnings": warnings,
    }
    return dataclasses.replace(
        inner,
        pressure=pressure,
        normal_force=force,
        mean_pressure=force / (pressure.size * dx * dy),
        nit=it.nit,
        residual_history=np.asarray(it.history),
        status=int(status),
        message=message,
        seconds=time.perf_counter() - started,
        critical_tension=law.cohesive_stress,
        extra=extra,
        branch=branch,
    )


def _empty_result(h: np.ndarray, grid: tuple, law: MaugisLaw, stop, started) -> ContactResult:
    """No inner solve could run (a tensile load from first contact): nothing is carried."""
    dx, dy, _, _ = grid
    gap = h.max() - h
    it = _SetIteration(np.zeros(h.shape, dtype=bool), None, 0.0)
    it.inner = ContactResult(
        pressure=np.zeros_like(h),
        gap=gap,
        contact_mask=gap == 0,
        real_area=float(np.count_nonzero(gap == 0)) * dx * dy,
        contact_fraction=float(np.mean(gap == 0)),
        normal_force=0.0,
        mean_pressure=0.0,
        mean_gap=float(gap.mean()),
        separation=float(h.max()),
        nit=0,
        residual_history=np.zeros(1),
        status=int(stop[0]),
        message=stop[1],
        seconds=0.0,
        dx=dx,
        dy=dy,
    )
    it.history = [0.0]
    status = SolverStatus.LOAD_NOT_CARRIED
    message = (
        "load not carried: the tensile force is beyond what first contact can hold; pull on a "
        "state of the unloading branch instead (initial=..., e.g. the last loaded result)"
    )
    return _assemble(it, it.inner, law, grid, (status, message), "loading", started)


def solve_maugis_problem(
    problem: ContactProblem, law: MaugisLaw, initial: object, options: SolverOptions
) -> ContactResult:
    """Maugis-Dugdale adhesive contact of a rigid flat with the elastic half-space.

    Called by :func:`bem.solve_contact` (:mod:`asperity.bem.normal.contact`) with
    ``adhesion="maugis"`` on its validated problem.

    Parameters
    ----------
    problem : ContactProblem
        Heights (m), pixel sizes (m), E* (Pa), the boundary, and the imposed total force F
        (N, may be <= 0) or separation d (m).
    law : MaugisLaw
        w (J/m^2) and h_0 (m).
    initial : ContactResult, optional
        A previous state (Maugis or non-adhesive): its gap gives the starting attractive set.
    options : SolverOptions
        Tuning of the inner solves; ``tol`` is met by the final one.

    Returns
    -------
    ContactResult
        ``pressure`` is the net traction p = q - sigma_0 [gap <= h_0] (Pa),
        ``critical_tension`` is sigma_0 (Pa, the most tensile traction), ``normal_force`` =
        sum p dx dy (N); ``nit`` sums the inner iterations; ``extra`` adds ``adhesion``
        ("maugis"), ``adhesion_range`` (m), ``cohesive_stress`` (Pa), ``attractive_area``
        (m^2), ``attractive_fraction``, ``cohesive_zone_elements`` (mean width of the
        attracted ring outside contact, elements, None without contact), ``set_solves`` and
        ``warnings`` (also appended to ``message``: a cohesive zone under
        :data:`MIN_ZONE_ELEMENTS` elements).
    """
    started = time.perf_counter()
    h = problem.heights
    grid = (problem.dx, problem.dy, problem.e_star, problem.periodic)
    loads = (problem.load_control, problem.force, problem.separation)
    attractive, inner = _starting_set(h, law, initial, problem.load_control, problem.force)
    it = _SetIteration(attractive, inner, max(options.tol, LOOSE_TOL))
    stop = _iterate_set(_Case(h, grid, law, loads), it, options)
    if it.inner is None:
        return _empty_result(h, grid, law, stop, started)
    return _assemble(it, it.inner, law, grid, stop, _branch(initial, loads), started)
