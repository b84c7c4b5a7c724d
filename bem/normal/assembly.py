"""The result of a solve, assembled from the final iteration state on the heights' grid.

The gap is recomputed exactly (u = K p, the loop's gap may carry incremental updates), the
rigid-body term under load control is the mean gap on the contact set, and the load is checked:
a load-controlled solve whose force is not carried, or an adhesive one that ends with elements
below -Sigma, is reported with status 4 (:class:`~asperity.bem.result.SolverStatus`).
"""

from __future__ import annotations

import math
import time

import numpy as np

from asperity.bem.normal import kernels as kr
from asperity.bem.normal.diagnosis import residual_floor, stall_causes
from asperity.bem.normal.iteration import IterationState, Stop
from asperity.bem.normal.problem import ContactProblem
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult, SolverStatus

__all__ = ["assemble_result", "first_contact_result"]


def _returned_state_residual(s: IterationState, problem: ContactProblem, offset: float) -> float:
    """The residual of the state as returned (after the last step; ``s.w`` is the exact gap
    without the rigid-body term)."""
    g_all = s.w - offset
    in_c = s.c.astype(bool)
    viol = float(np.sum(g_all[in_c] ** 2) + np.sum(np.minimum(g_all[~in_c], 0.0) ** 2))
    p_sq = kr.dot(s.pf, s.pf)
    return math.sqrt(viol / p_sq) * problem.stiffness if p_sq > 0 else math.inf


def _iteration_cap(
    s: IterationState, problem: ContactProblem, options: SolverOptions, offset: float
) -> Stop:
    """The loop ran out of iterations: its last residual belongs to the state before the last
    step, so evaluate the returned one (``residual_history`` then has nit + 1 entries)."""
    s.residual = _returned_state_residual(s, problem, offset)
    s.history.append(s.residual)
    cap = options.max_iterations(problem.heights.shape)
    return Stop(
        SolverStatus.ITERATION_CAP,
        f"iteration cap reached: max_iter={cap} with residual {s.residual:.3g} "
        f"(tol {options.tol:.3g})",
    )


def _abs_sum(a: np.ndarray, block: int = 1 << 12) -> float:
    """sum |a| over a 2D array, about ``block`` values at a time: the temporary |a| of a block
    of rows, not of the whole map (8 B per point at the end of every solve, the peak of a
    Maugis solve once the iteration's own arrays were cut)."""
    rows = max(1, block // max(1, a.shape[1]))
    return float(sum(np.abs(a[i : i + rows]).sum() for i in range(0, a.shape[0], rows)))


def _load_check(problem: ContactProblem, stop: Stop, pressure: np.ndarray, force: float) -> Stop:
    """Status 4 when the imposed force was not reached, or elements in contact end below
    -Sigma (a tensile load this contact cannot carry). The force is compared relative to the
    larger of |F| and sum |p| dx dy, so that a zero imposed load is checked against the
    pressures that cancel in it."""
    force_scale = max(abs(problem.force), _abs_sum(pressure) * problem.pixel_area)
    if (
        problem.load_control
        and stop.status == SolverStatus.CONVERGED
        and abs(force - problem.force) > 1e-8 * force_scale
    ):
        stop = Stop(
            SolverStatus.LOAD_NOT_CARRIED,
            f"imposed force {problem.force:.6g} N not reached (total {force:.6g} N): beyond the "
            "pull-off force of the remaining contact",
        )
    sigma = problem.critical_tension
    if problem.adhesive and np.any(pressure < -sigma * (1 + 1e-12)):
        stop = Stop(
            SolverStatus.LOAD_NOT_CARRIED,
            f"elements in contact below -Sigma = {-sigma:.6g} Pa at the end of the iteration "
            f"(imposed force not carried by this contact; a tensile load needs a warm start "
            f"from a state on the unloading branch, initial=...): {stop.message}",
        )
    return stop


def _name_stall_causes(
    s: IterationState,
    problem: ContactProblem,
    options: SolverOptions,
    stop: Stop,
    contact_fraction: float,
    extra: dict,
) -> tuple[Stop, dict]:
    """Append the likely causes of a stall (:mod:`asperity.bem.normal.diagnosis`) to its message."""
    floor = residual_floor(problem, int(np.count_nonzero(s.c)), s.offset, s.psq)
    causes = stall_causes(problem, contact_fraction, floor, options.tol)
    if causes:
        text = "; likely cause: " + "; ".join(sentence for _, sentence in causes)
    else:
        text = "; no cause detected (checked: outlier pixels, near-full contact, tol vs precision)"
    extra = {**extra, "stall_causes": [code for code, _ in causes]}
    return Stop(stop.status, stop.message + text), extra


#: The cost counters of a solve's ``extra`` (:func:`_diagnostics`) that a solve made on the way
#: to another one (a non-adhesive start) reports beside its own.
COST_COUNTERS = (
    "convolutions",
    "single_precision_convolutions",
    "fft_seconds",
    "fft_transforms",
    "single_precision_transforms",
)


def _diagnostics(s: IterationState, problem: ContactProblem, counters: dict) -> dict:
    """FFT counters since the start of the solve, the preconditioner fallback and the end of
    the single-precision phase (``precision_switched_at``: the iteration, None when the solve
    ran in double precision throughout)."""
    op = problem.op
    other_calls, other_seconds, other_transforms = s.convolutions(exclude=op)
    single = sum(
        conv.calls - calls0
        for conv, calls0, _, _ in s.counted.values()
        if conv.precision == "single"
    )
    single_transforms = sum(
        conv.transforms - transforms0
        for conv, _, _, transforms0 in s.counted.values()
        if conv.precision == "single"
    )
    return {
        "convolutions": op.calls - counters["calls"] + other_calls,
        "fft_transforms": op.transforms - counters["transforms"] + other_transforms,
        "fft_seconds": op.seconds - counters["seconds"] + other_seconds,
        "single_precision_convolutions": single,
        "single_precision_transforms": single_transforms,
        "precision_switched_at": s.switched_at,
        "preconditioner_dropped_at": s.dropped_at,
        "fft_backend": op.backend,
        "fft_threads": op.threads,
        # where the transforms beyond the search direction's two went (issue 36): exact
        # gaps u = K p after a contact-set change with a pressure jump, and the periodic
        # refreshes (each 2 transforms, the direction's pending inverse then skipped)
        "set_change_recomputations": s.set_change_recomputations,
        "refresh_recomputations": s.refresh_recomputations,
    }


def assemble_result(
    problem: ContactProblem,
    s: IterationState,
    stop: Stop | None,
    options: SolverOptions,
    *,
    started: float,
    counters: dict,
    extra: dict,
    branch: str,
) -> ContactResult:
    """The :class:`ContactResult` of the final state ``s`` (``stop`` None: iteration cap).

    ``started``: ``time.perf_counter()`` at the start of the solve; ``counters``: the
    operator's ``calls`` and ``seconds`` at the start of the solve;
    ``extra``: further diagnostics (coarse start, loading ramp).
    """
    s.release_work()
    problem.op(s.p, out=s.w)
    s.w -= problem.grid_heights
    # the state's arrays (on the map, whatever the boundary) become the result's: no copies
    # at the peak
    pressure = s.p
    mask = s.c.view(bool)
    offset = s.offset
    if problem.load_control and mask.any():
        offset = float(s.w[mask].mean())
    if stop is None:
        stop = _iteration_cap(s, problem, options, offset)
    gap = np.subtract(s.w, offset, out=s.w)
    total_force = float(pressure.sum()) * problem.pixel_area
    stop = _load_check(problem, stop, pressure, total_force)
    n_contact = int(np.count_nonzero(mask))
    if stop.status == SolverStatus.STALLED:
        stop, extra = _name_stall_causes(s, problem, options, stop, n_contact / mask.size, extra)
    return ContactResult(
        pressure=pressure,
        gap=gap,
        contact_mask=mask,
        real_area=n_contact * problem.pixel_area,
        contact_fraction=n_contact / mask.size,
        normal_force=total_force,
        mean_pressure=total_force / problem.nominal_area,
        mean_gap=float(gap.mean()),
        separation=-offset,
        nit=s.steps,
        residual_history=np.asarray(s.history),
        status=int(stop.status),
        message=stop.message,
        seconds=time.perf_counter() - started,
        dx=problem.dx,
        dy=problem.dy,
        critical_tension=problem.critical_tension,
        residual=s.residual,
        extra={**_diagnostics(s, problem, counters), **extra},
        branch=branch,
    )


def first_contact_result(problem: ContactProblem, started: float) -> ContactResult:
    """The loading branch at an imposed force <= 0 (N): it starts at first contact, the flat
    touching the highest point with no pressure, at F = 0 (converged); a tensile force is not
    on it (status 4)."""
    h = problem.heights
    top = float(h.max())
    mask = h == top
    if problem.force == 0:
        status, message = (
            SolverStatus.CONVERGED,
            (
                "converged: zero load on the loading branch is first contact (the flat touches the "
                "highest point, no pressure)"
            ),
        )
    else:
        status, message = (
            SolverStatus.LOAD_NOT_CARRIED,
            (
                f"load not carried: a tensile force ({problem.force:.6g} N) is not on the loading "
                "branch, which starts at first contact with F = 0; pull on a state of the "
                "unloading branch instead (initial=..., e.g. the last result of a load_sweep)"
            ),
        )
    gap = top - h
    return ContactResult(
        pressure=np.zeros_like(h),
        gap=gap,
        contact_mask=mask,
        real_area=int(mask.sum()) * problem.pixel_area,
        contact_fraction=float(mask.mean()),
        normal_force=0.0,
        mean_pressure=0.0,
        mean_gap=float(gap.mean()),
        separation=top,
        nit=0,
        residual_history=np.zeros(1),
        status=int(status),
        message=message,
        seconds=time.perf_counter() - started,
        dx=problem.dx,
        dy=problem.dy,
        critical_tension=problem.critical_tension,
        residual=0.0,
        branch="loading",
    )
