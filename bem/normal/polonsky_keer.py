"""Constrained conjugate gradients (Polonsky & Keer 1999) for eqs. E:BEM_eq1..E:BEM_eq4.

Unknown: the pressure p on every pixel and the contact set Omega_c (an explicit mask). The
solve is a short sequence of named steps: :func:`~asperity.bem.normal.problem.set_up_problem` (input
checks, heights on the FFT grid, the influence operator), :func:`~asperity.bem.normal.start.
starting_state` (warm, coarse-grid or cold start), :func:`~asperity.bem.normal.iteration.iterate`
(one function per iteration variant, plain or preconditioned Polonsky-Keer, on an
:class:`~asperity.bem.normal.iteration.IterationState`), :func:`~asperity.bem.normal.assembly.
assemble_result`. One iteration is a short sequence of fused numba kernels
(:mod:`asperity.bem.normal.kernels`) around FFT convolutions ``K * (.)`` (see
:mod:`asperity.bem.elastic.influence`); the array ``w`` holds the gap u - h without the rigid-body
term:

1. ``deflection_to_gap_stats`` (only after a full convolution u = K p): w = u - h, the mean
   gap on Omega_c (load control: the rigid-body term d) and the squared gap residual
   G = sum_c (g - g_mean)^2;
2. ``update_direction``: conjugate direction t = g_c + beta t on Omega_c (beta = G/G_old, reset
   to 0 after elements entered the contact set, as in Polonsky & Keer), penetration outside;
3. ``r = K t`` (one FFT convolution) with ``sum t r`` fused into the Fourier-space
   multiplication (Parseval): step tau = sum g t / sum r t;
4. ``step_pressure``: p -= tau t on Omega_c; elements whose pressure falls below the lower
   bound (0, or -Sigma with Pohrt-Popov adhesion) leave the contact set with p = 0; elements
   outside with g < 0 enter with p = -tau g (plain) or p = 0 (preconditioned); then
   ``gap_step`` updates the gap as w -= tau r and accumulates the next iteration's gap
   statistics (or, when the contact set changed, u = K p is recomputed and the inverse
   transform of K t is skipped). The tests hold the two to a plain numpy reference of the step.

Preconditioned (default): step 2 becomes ``residual_field`` (s = g on Omega_c), a convolution
z = K^-1 s with the stiffness E*|q|/2 (sum s z fused), ``masked_sum`` (mean of z on Omega_c)
and ``update_direction_preconditioned`` (t = z - z_mean + beta t).

When elements left the contact set (or entered it with a pressure), load control restores the
imposed force (multiplicative rescale without adhesion, as Polonsky & Keer; a uniform shift on
Omega_c with adhesion, since the total force may be zero or tensile) and u = K p is recomputed.
Otherwise w is exact up to round-off (t vanishes outside Omega_c), so that iteration saves a
convolution; u is recomputed every ``refresh`` iterations to bound round-off drift.

With adhesion the contact set is frozen while the conjugate gradients solve the linear problem
on it (until its gap residual fell 100-fold), then elements delaminate (p < -Sigma) or attach
(g < 0) in one step: the Pohrt-Popov active-set iteration, which keeps the history dependence
(elements enter at g = 0 but leave only at p < -Sigma).

Convergence residual (the ``tol`` knob)
    ``residual = sqrt(sum_{Omega_c} (g - g_mean)^2 + sum_{outside} min(g, 0)^2)
    / sqrt(sum p^2) * E* / sqrt(dx dy)``: the rms violation of the contact conditions
    E:BEM_eq2 (g = 0 in contact) and E:BEM_eq3 (no penetration outside), converted to a pressure
    with the stiffness E*/sqrt(dx dy) of a pixel-sized wavelength (where the slowest-converging
    error sits) and divided by the rms pressure: an estimate of the relative rms pressure error.
    Measured on the benchmark surface (512^2 .. 2048^2), tol = 1e-8 gives pressures within
    1.2e-9 .. 1.7e-9 (relative L2) of a tol = 1e-12 solution. The pressure bound (p >= 0,
    or p >= -Sigma) holds exactly at every iterate; the force balance E:BEM_eq4 to round-off
    in load control.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from asperity.bem.normal.assembly import COST_COUNTERS, assemble_result, first_contact_result
from asperity.bem.normal.branch import solve_branch
from asperity.bem.normal.iteration import iterate, new_state
from asperity.bem.normal.problem import ContactProblem, set_up_problem
from asperity.bem.normal.start import starting_state
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult

__all__ = ["solve_polonsky_keer", "solve_problem", "solve_started"]

#: Tolerance of the coarse-grid solves of ``coarse_start`` (or ``tol`` if looser): their
#: solution differs from the fine one by the discretisation anyway.
COARSE_TOL = 1e-2


def solve_polonsky_keer(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    loads: dict[str, float | None],
    *,
    initial: object = None,
    periodic: bool = True,
    options: SolverOptions,
) -> ContactResult:
    """A non-adhesive contact problem set up and solved by constrained conjugate gradients:
    the inner solve of :mod:`asperity.bem.normal.maugis` and of the coarse start.

    ``loads`` maps ``normal_force`` (N), ``mean_pressure`` (Pa) and ``separation`` (m) to their
    values, exactly one not None; heights and pixel sizes in m, E* in Pa. The public entry is
    :func:`asperity.bem.solve_contact`.
    """
    started = time.perf_counter()
    problem = set_up_problem(heights, dx, dy, e_star, loads, 0.0, periodic, options)
    return solve_problem(problem, initial, options, started)


def solve_problem(
    problem: ContactProblem, initial: object, opts: SolverOptions, started: float
) -> ContactResult:
    """Solve one validated problem (:func:`~asperity.bem.normal.problem.set_up_problem`) by
    constrained conjugate gradients on the branch its start implies
    (:mod:`asperity.bem.normal.branch`);
    ``started`` is the :func:`time.perf_counter` of the call, for the result's wall time (s)."""
    branch = solve_branch(problem, initial)
    if branch == "loading":
        return _solve_on_loading_branch(problem, initial, opts, started)
    return _iterate_from(problem, initial, opts, started, branch, {})


def _solve_on_loading_branch(
    problem: ContactProblem, initial: object, opts: SolverOptions, started: float
) -> ContactResult:
    """Adhesive loading branch: the non-adhesive solution at this load (warm-started from a
    previous loading-branch state), then the adhesive iteration from it as the check."""
    if problem.load_control and problem.force <= 0:
        return first_contact_result(problem, started)
    warm = initial if isinstance(initial, ContactResult) else None
    if _is_solution_here(warm, problem, opts):
        # the non-adhesive solution at this load was given (e.g. by load_sweep): nothing to do
        contact, extra = warm, {"loading_iterations": 0, "loading_message": "given"}
    else:
        plain = dataclasses.replace(problem, work_of_adhesion=0.0, critical_tension=0.0)
        contact = _iterate_from(plain, warm, opts, time.perf_counter(), "unique", {})
        extra = {
            "loading_iterations": contact.nit,
            "loading_message": contact.message,
            **{f"loading_{k}": contact.extra[k] for k in COST_COUNTERS},
        }
    return _iterate_from(problem, contact, opts, started, "loading", extra)


def _is_solution_here(
    result: ContactResult | None, problem: ContactProblem, opts: SolverOptions
) -> bool:
    """A converged non-adhesive result at this problem's force (to round-off) and grid, within
    this solve's tolerance: the loading-branch state itself, nothing left to iterate."""
    return (
        result is not None
        and result.branch == "unique"
        and result.converged
        and result.residual <= opts.tol
        and result.pressure.shape == problem.heights.shape
        and (result.dx, result.dy) == (problem.dx, problem.dy)
        and abs(result.normal_force - problem.force) <= 1e-9 * abs(problem.force)
    )


def _iterate_from(
    problem: ContactProblem,
    initial: object,
    opts: SolverOptions,
    started: float,
    branch: str,
    extra: dict,
) -> ContactResult:
    """Start (warm, coarse-grid or cold), iterate and assemble one validated problem."""
    counters = {
        "calls": problem.op.calls,
        "seconds": problem.op.seconds,
        "transforms": problem.op.transforms,
    }
    coarse = None
    if initial is None and _coarse_start_applies(problem, opts):
        coarse, coarse_info = _coarse_start(problem, opts)
        extra = {**extra, **coarse_info}
    p, c = starting_state(problem, initial, coarse)
    del coarse
    return solve_started(
        problem, p, c, opts, started, branch=branch, extra=extra, counters=counters
    )


def solve_started(
    problem: ContactProblem,
    p: np.ndarray,
    c: np.ndarray,
    opts: SolverOptions,
    started: float,
    *,
    branch: str = "unique",
    extra: dict | None = None,
    counters: dict | None = None,
) -> ContactResult:
    """Iterate and assemble one validated problem from its starting pressure ``p`` (Pa) and
    int8 contact set ``c`` on the FFT grid (:func:`~asperity.bem.normal.start.starting_state`); the
    arrays become the iteration's (and, on a periodic grid, the result's). A caller that
    built them from a warm start may drop the warm start first (the Maugis iteration does:
    its previous inner solution is then not held through the next one)."""
    if counters is None:
        counters = {
            "calls": problem.op.calls,
            "seconds": problem.op.seconds,
            "transforms": problem.op.transforms,
        }
    state = new_state(problem, p, c, opts)
    del p, c
    stop = iterate(state, problem, opts)
    return assemble_result(
        problem,
        state,
        stop,
        opts,
        started=started,
        counters=counters,
        extra=extra or {},
        branch=branch,
    )


def _coarse_start_applies(problem: ContactProblem, opts: SolverOptions) -> bool:
    nx, ny = problem.heights.shape
    return (
        opts.coarse_start
        and problem.load_control
        and not problem.adhesive
        and problem.periodic
        and nx % 2 == 0
        and ny % 2 == 0
        and nx >= 64
        and ny >= 64
    )


def _coarse_start(problem: ContactProblem, opts: SolverOptions) -> tuple[np.ndarray, dict]:
    """The pressure (Pa) of the solve on the grid coarsened 2x (2x2 block means, recursively),
    repeated onto the fine grid, and the coarse solve's counters."""
    nx, ny = problem.heights.shape
    coarse_h = problem.heights.reshape(nx // 2, 2, ny // 2, 2).mean(axis=(1, 3))
    coarse = solve_polonsky_keer(
        coarse_h,
        2 * problem.dx,
        2 * problem.dy,
        problem.e_star,
        {"normal_force": None, "mean_pressure": problem.force / problem.nominal_area},
        options=SolverOptions(
            tol=max(opts.tol, COARSE_TOL),
            max_iter=opts.max_iterations((nx, ny)),
            kernel=opts.kernel,
            fft_backend=opts.fft_backend,
            threads=opts.threads,
            coarse_start=True,
        ),
    )
    info = {
        "coarse_iterations": coarse.nit + coarse.extra.get("coarse_iterations", 0),
        "coarse_convolutions": coarse.extra.get("convolutions", 0)
        + coarse.extra.get("coarse_convolutions", 0),
        "coarse_seconds": coarse.seconds,
    }
    return np.repeat(np.repeat(coarse.pressure, 2, axis=0), 2, axis=1), info
