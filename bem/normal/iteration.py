"""One Polonsky-Keer iteration as named steps on a small state object.

An iteration (Polonsky & Keer 1999, with the preconditioner of Vollebregt 2014 and the
Pohrt-Popov active set for adhesion) is:

1. :func:`measure_gap`: the gap statistics on the contact set Omega_c (under load control the
   rigid-body term is the mean gap there) and the squared gap residual G;
2. the direction: :func:`plain_pk_iteration` uses t = g + beta t (beta = G / G_old);
   :func:`preconditioned_pk_iteration` t = z - mean(z) + beta t, z = K^-1 g on Omega_c;
3. :func:`check_progress`: the convergence residual, the Pohrt-Popov schedule
   (:func:`pohrt_popov_schedule`: when the contact set may change), stall detection;
4. :func:`step_length`: tau = sum g t / sum t K t;
5. :func:`apply_step`: p -= tau t, the active-set update (elements leave where p < -Sigma, or
   p < 0 without adhesion; enter where g < 0), the gap update, and the force restoration
   (:func:`restore_force`) or the cheap incremental gap (:func:`advance_gap`).

Each step reads and writes an :class:`IterationState`; a step that ends the iteration returns
a :class:`Stop`. The loop itself is :func:`iterate`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from asperity.bem.cancel import check_cancelled
from asperity.bem.elastic.fft_backend import Convolution, NumbaThreads
from asperity.bem.elastic.operators import (
    PaddedConvolution,
    influence_operator,
    stiffness_preconditioner,
)
from asperity.bem.normal import kernels as kr
from asperity.bem.normal.problem import ContactProblem
from asperity.bem.options import SolverOptions
from asperity.bem.result import SolverStatus

__all__ = ["IterationState", "Stop", "iterate", "new_state"]

#: Relative round-off of float64 (used for the floor of the gap residual).
EPS = 2.2e-16
#: Relative round-off of float32 (the floor of the residual with single-precision transforms).
EPS_SINGLE = 6.0e-8
#: Mixed precision: the single-precision phase ends when the residual is below this multiple of
#: ``tol`` (the double phase then has a few decades left) ...
SWITCH_TOL_FACTOR = 100.0
#: ... or below this multiple of the single-precision floor of the residual ...
SWITCH_FLOOR_FACTOR = 30.0
#: ... or has not decreased for this many iterations.
SINGLE_PATIENCE = 4


class Stop(NamedTuple):
    """Why the iteration ended: a :class:`SolverStatus` and a message."""

    status: SolverStatus
    message: str


class GapMeasure(NamedTuple):
    """Contact-set size and squared gap residual G (m^2) of the current state."""

    n_contact: int
    g_sq: float


#: Returned by :func:`check_progress` when the preconditioned iteration stopped progressing.
FALL_BACK = "fall back to plain Polonsky-Keer"
#: Returned by :func:`check_progress` when the single-precision phase is over.
SWITCH = "switch to double precision"


@dataclass(eq=False)
class IterationState:
    """The arrays and scalars a Polonsky-Keer iteration carries from one step to the next.

    Arrays live on the FFT grid; the ``*f`` attributes are flat views for the kernels. ``w``
    holds the gap u - h without the rigid-body term (m), or a fresh deflection K p while
    ``stats`` is None; ``offset`` is the rigid-body term (the mean gap on Omega_c under load
    control, -d under displacement control), ``shift`` the reference the gap statistics are
    taken about.
    """

    p: np.ndarray
    c: np.ndarray
    w: np.ndarray
    t: np.ndarray
    r: np.ndarray
    op: Convolution | PaddedConvolution
    pre: Convolution | PaddedConvolution | None
    s_arr: np.ndarray | None
    z_arr: np.ndarray | None
    psq: float
    offset: float
    shift: float
    last_allowed: bool
    stats: kr.GapStats | None = None
    g_old: float = 0.0
    gz_old: float = 0.0
    reset: bool = True
    best: float = math.inf
    best_it: int = 0
    steps: int = 0
    since_refresh: int = 0
    residual: float = math.inf
    allow_change: bool = True
    frozen_its: int = 0
    inner_target: float = 0.0
    dropped_at: int | None = None
    single: bool = False
    switched_at: int | None = None
    n_contact: int = 0
    t_copied: bool = False
    set_change_recomputations: int = 0
    refresh_recomputations: int = 0
    history: list[float] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.pf, self.cf, self.wf, self.tf, self.rf = (
            a.ravel() for a in (self.p, self.c, self.w, self.t, self.r)
        )
        self.sf = self.s_arr.ravel() if self.s_arr is not None else None
        self.zf = self.z_arr.ravel() if self.z_arr is not None else None
        # operators other than the problem's, with their counters at first use (the problem's
        # operator is counted by the caller)
        self.counted: dict[int, tuple[Convolution | PaddedConvolution, int, float, int]] = {}
        for conv in (self.op, self.pre):
            self.count(conv)

    def release_work(self) -> None:
        """Drop the direction and the work array (the state then only describes p, c, w):
        called once the iteration ended, before the result is assembled."""
        self.t = self.r = self.s_arr = self.z_arr = None  # type: ignore[assignment]
        self.tf = self.rf = self.sf = self.zf = None  # type: ignore[assignment]

    def count(self, conv: Convolution | PaddedConvolution | None) -> None:
        """Count the convolutions ``conv`` does from now on in this solve's diagnostics."""
        if conv is not None and id(conv) not in self.counted:
            self.counted[id(conv)] = (conv, conv.calls, conv.seconds, conv.transforms)

    def convolutions(self, exclude: Convolution | PaddedConvolution) -> tuple[int, float, int]:
        """Convolutions started, seconds spent in them and FFTs done by the counted operators
        but ``exclude``."""
        calls, seconds, transforms = 0, 0.0, 0
        for conv, calls0, seconds0, transforms0 in self.counted.values():
            if conv is not exclude:
                calls += conv.calls - calls0
                seconds += conv.seconds - seconds0
                transforms += conv.transforms - transforms0
        return calls, seconds, transforms


def new_state(
    problem: ContactProblem, p: np.ndarray, c: np.ndarray, options: SolverOptions
) -> IterationState:
    """The state at the starting pressure ``p`` (Pa) and contact set ``c``: u = K p computed
    (in single precision when the solve starts mixed, :meth:`SolverOptions.mixed_precision`).

    With an in-place operator (:class:`~asperity.bem.elastic.operators.PaddedConvolution`: a finite
    specimen, or the Maugis iteration's inner solves) the conjugate direction t and the work
    array (r = K t, the preconditioner's s and z) are stored in float32 (8 B per point less):
    t is only a search direction (p -= tau t and w -= tau K t use the same stored t, so p and
    the gap stay consistent in double precision), and r carries the float32 round-off of one
    step's gap change, which the exact refresh of u = K p (every ``refresh`` iterations and at
    the end) removes. The work array is then the head of the transform workspace
    (:meth:`~asperity.bem.elastic.operators.PaddedConvolution.work_array`, no memory of its own, 4 B
    per point less): each of its values is consumed before the next transform overwrites
    it (s -> z by the preconditioner, z by the direction update, r = K t by the gap step)."""
    single = options.mixed_precision(problem.op.shape)
    op = single_precision_operator(problem, options) if single else problem.op
    pre = None
    if options.precondition:
        # every operator of the solve exists before its arrays do: planning one allocates
        # two real grids for a moment (the double preconditioner of a mixed solve would
        # otherwise be planned at the switch, on top of the whole state)
        if single:
            stiffness_preconditioner(problem.op, problem.dx, problem.dy, problem.e_star)
        pre = stiffness_preconditioner(op, problem.dx, problem.dy, problem.e_star)
    compact = isinstance(problem.op, PaddedConvolution)
    w = op.empty()
    op(p, out=w)
    load = problem.load_control
    offset = 0.0 if load else -problem.separation
    shift, stats = offset, None
    if load:
        # w = K p - h in place (no full-size temporary), the mean gap about which the first
        # statistics are taken, and those statistics (as the first measure_gap would compute
        # them from the deflection)
        np.subtract(w, problem.grid_heights, out=w)
        shift = float(np.mean(w))
        stats = kr.gap_stats(w.ravel(), c.ravel(), shift)
    # one work array holds r = K t, the preconditioner's input s and its output z: their
    # lifetimes within an iteration do not overlap (s -> z in place, z is consumed by the
    # direction update before r = K t is transformed back)
    store = np.float32 if compact else np.float64
    work = problem.op.work_array() if isinstance(problem.op, PaddedConvolution) else op.empty()
    return IterationState(
        p=p,
        c=c,
        w=w,
        t=np.zeros(p.shape, dtype=store) if compact else op.zeros(),
        r=work,
        op=op,
        pre=pre,
        s_arr=work if pre is not None else None,
        z_arr=work if pre is not None else None,
        psq=kr.dot(p.ravel(), p.ravel()),
        offset=offset,
        shift=shift,
        stats=stats,
        last_allowed=not problem.adhesive,
        single=single,
    )


def single_precision_operator(
    problem: ContactProblem, options: SolverOptions
) -> Convolution | PaddedConvolution:
    """The problem's influence operator with single-precision transforms (same backend and
    threads as the double one)."""
    op = problem.op
    return influence_operator(
        problem.heights.shape,
        problem.dx,
        problem.dy,
        problem.e_star,
        options.kernel,
        problem.periodic,
        op.backend,
        op.threads,
        precision="single",
        in_place=isinstance(op, PaddedConvolution),
    )


def switch_to_double(s: IterationState, problem: ContactProblem) -> None:
    """End the single-precision phase: double-precision operators, u = K p recomputed exactly,
    the conjugacy restarted. The residual of this state is measured again by the next
    iteration (the single-precision one is dropped from the history)."""
    s.single = False
    s.switched_at = s.steps
    s.op = problem.op
    if s.pre is not None:
        s.pre = stiffness_preconditioner(problem.op, problem.dx, problem.dy, problem.e_star)
        s.count(s.pre)
    problem.op(s.p, out=s.w)
    s.stats = None
    s.since_refresh = 0
    s.reset = True
    s.history.pop()
    s.best, s.best_it = math.inf, s.steps


def lost_contact(s: IterationState, problem: ContactProblem) -> Stop:
    """No element remains in contact: converged only under displacement control with the flat
    beyond the highest point (p = 0 everywhere is then the exact solution)."""
    s.residual = math.inf
    status, message = (
        SolverStatus.CONTACT_LOST,
        (
            "contact lost: no element remains in contact (the imposed load is below the "
            "pull-off force, or the separation exceeds the highest point)"
            if problem.adhesive or not problem.load_control
            else "no contact"
        ),
    )
    if not problem.load_control:
        top = float(problem.heights.max())
        if top <= problem.separation:
            s.residual = 0.0
            status, message = SolverStatus.CONVERGED, "no element in contact at this separation"
        else:
            status, message = (
                SolverStatus.STALLED,
                (
                    f"stalled: every element left the contact set but the flat at separation "
                    f"{problem.separation:.6g} m penetrates the highest point ({top:.6g} m)"
                ),
            )
    s.history.append(s.residual)
    return Stop(status, message)


def measure_gap(s: IterationState, problem: ContactProblem) -> GapMeasure | Stop:
    """Step 1: gap statistics on Omega_c (from w = K p if fresh), the rigid-body term under load
    control, and G = sum_c (g - g_mean)^2 floored at the round-off of the gaps."""
    if s.stats is None:
        s.stats = kr.deflection_to_gap_stats(s.wf, problem.grid_heights.ravel(), s.cf, s.shift)
    n_c, s1, s2 = s.stats
    s.stats = None
    s.n_contact = n_c
    if n_c == 0:
        return lost_contact(s, problem)
    if not problem.load_control:
        return GapMeasure(n_c, s2)
    mean_c = s1 / n_c
    s.offset = s.shift + mean_c
    # below the round-off floor of the gaps the difference carries no information
    floor = n_c * (EPS * (problem.height_scale + abs(s.offset))) ** 2
    s.shift = s.offset
    return GapMeasure(n_c, max(s2 - s1 * mean_c, floor))


def pohrt_popov_schedule(s: IterationState, problem: ContactProblem, g_sq: float, tol: float):
    """The Pohrt-Popov active-set iteration: the contact set stays frozen while the conjugate
    gradients solve on it, until its gap residual dropped 100-fold (or reached ``tol``, or 100
    iterations passed); then elements delaminate (p < -Sigma) or attach (g < 0) in one step."""
    gap_res = math.sqrt(g_sq / s.psq) * problem.stiffness if s.psq > 0 else math.inf
    if s.frozen_its == 0:
        s.inner_target = max(tol, 1e-2 * gap_res)
    s.allow_change = gap_res <= s.inner_target or s.frozen_its >= 100


def check_progress(
    s: IterationState, problem: ContactProblem, options: SolverOptions, g_sq: float, pen: float
) -> Stop | str | None:
    """Step 3: the residual (rms gap violation x E*/sqrt(dx dy) over the rms pressure), its
    history, convergence, the preconditioner fallback (:data:`FALL_BACK`) and stalls."""
    residual = math.sqrt((g_sq + pen) / s.psq) * problem.stiffness if s.psq > 0 else math.inf
    s.residual = residual
    s.history.append(residual)
    if problem.adhesive:
        pohrt_popov_schedule(s, problem, g_sq, options.tol)
    if residual < options.tol and s.last_allowed:
        if s.single:
            return SWITCH
        return Stop(
            SolverStatus.CONVERGED, f"converged: residual {residual:.3g} < tol {options.tol:.3g}"
        )
    if residual < options.tol:
        s.allow_change = True
    it = s.steps
    improved = residual < s.best * (1 - 1e-3)
    if improved:
        s.best, s.best_it = residual, it
    if s.single and (
        residual < single_phase_end(s, problem, options.tol) or it - s.best_it >= SINGLE_PATIENCE
    ):
        return SWITCH
    if improved:
        return None
    if (
        s.pre is not None
        and not problem.adhesive  # there the residual jumps at every delamination step
        and (it - s.best_it >= options.stall_window // 2 or residual > 1e3 * s.best)
    ):
        return FALL_BACK
    if it - s.best_it >= options.stall_window:
        return Stop(
            SolverStatus.STALLED,
            f"stalled: the residual ({residual:.3g}, best {s.best:.3g}) has not decreased for "
            f"{options.stall_window} iterations (tol {options.tol:.3g})",
        )
    return None


def single_phase_end(s: IterationState, problem: ContactProblem, tol: float) -> float:
    """The residual below which single-precision transforms stop paying:
    ``SWITCH_TOL_FACTOR`` x tol, or ``SWITCH_FLOOR_FACTOR`` x the residual of a gap error of
    the float32 round-off of the heights and the rigid-body term on every contact element."""
    if not s.psq > 0:
        return math.inf
    gap_floor = EPS_SINGLE * (problem.height_scale + abs(s.offset)) * math.sqrt(s.n_contact)
    floor = gap_floor / math.sqrt(s.psq) * problem.stiffness
    return max(SWITCH_TOL_FACTOR * tol, SWITCH_FLOOR_FACTOR * floor)


def step_length(
    s: IterationState, problem: ContactProblem, options: SolverOptions, sgt: float, npen: int
) -> float | Stop:
    """Step 4: r = K t (with sum t r fused in Fourier space) and tau = sum g t / sum t r."""
    direct = s.op.direct_input()
    # t was also written into the single-precision transform's own input (transform_input)
    rt = s.op.forward_with_energy(direct if s.t_copied and direct is not None else s.t)
    s.t_copied = False
    if rt > 0:
        return sgt / rt
    below = problem.adhesive and bool(np.any((s.pf < -problem.critical_tension) & (s.cf != 0)))
    if s.allow_change and (npen > 0 or below):
        # the linear problem on the current contact set is solved exactly (t = 0), but the set
        # itself is wrong: penetrating elements must enter, or (adhesion) elements below
        # -Sigma delaminate. Take the set-change step alone (tau = 0) instead of stopping
        # before it (seen on a single-element adhesive contact under tension)
        return 0.0
    if s.residual < options.tol:
        # the linear problem on the set is solved exactly and the set is settled (nothing
        # penetrates, nothing below -Sigma): a converged state, e.g. a flat map in full contact
        return Stop(
            SolverStatus.CONVERGED,
            f"converged: residual {s.residual:.3g} < tol {options.tol:.3g} and the contact set "
            "is settled",
        )
    return Stop(
        SolverStatus.STALLED,
        f"stalled: the search direction vanished (curvature {rt:.3g}) at residual "
        f"{s.residual:.3g} > tol {options.tol:.3g}",
    )


def entering_gain(s: IterationState, problem: ContactProblem, tau: float) -> float:
    """Pressure per gap (Pa/m) of elements entering the contact set: Polonsky-Keer's p = -tau g;
    preconditioned they enter with p = 0 and are loaded by the next step (any entering pressure
    made a rough 5000^2 map cycle between contact sets), except with adhesion, where the set
    changes only in the Pohrt-Popov steps and -tau g E*/sqrt(dx dy) is kept (zero made a
    near-jump-off state stall)."""
    if s.pre is None:
        return tau
    return tau * problem.stiffness if problem.adhesive else 0.0


def restore_force(s: IterationState, problem: ContactProblem, psum: float) -> None:
    """After the contact set changed: restore the imposed force (Polonsky & Keer's rescale
    without adhesion, a uniform shift on Omega_c with adhesion) and recompute u = K p."""
    if problem.load_control:
        target_sum = problem.target_pressure_sum
        if not problem.adhesive:
            if psum > 0:
                s.p *= target_sum / psum
                s.psq *= (target_sum / psum) ** 2
        else:
            n_c = int(np.count_nonzero(s.cf))
            if n_c:
                kr.shift_on_contact(s.pf, s.cf, (target_sum - psum) / n_c)
                s.psq = kr.dot(s.pf, s.pf)
    s.op(s.p, out=s.w)
    s.since_refresh = 0
    s.set_change_recomputations += 1


def advance_gap(
    s: IterationState,
    problem: ContactProblem,
    options: SolverOptions,
    upd: kr.PressureStep,
    tau: float,
) -> None:
    """The contact set did not change: keep the incremental gap w -= tau r (exact up to
    round-off since t vanishes outside Omega_c; r = K t from the pending product of
    :func:`step_length`), recomputing u = K p every ``refresh`` iterations instead; without
    adhesion restore the force by rescaling p (u scales with it)."""
    psum = upd.pressure_sum
    rescale = problem.load_control and not problem.adhesive and psum > 0
    alpha = problem.target_pressure_sum / psum if rescale else 1.0
    if s.since_refresh >= options.refresh:
        if rescale:
            s.p *= alpha
            s.psq *= alpha**2
        s.op(s.p, out=s.w)
        s.since_refresh = 0
        s.refresh_recomputations += 1
        return
    # single precision: r = K t read from the transform's own float32 output (no cast)
    direct = s.op.direct_input()
    r = s.op.inverse(direct) if direct is not None else s.op.inverse(s.r)
    stats = kr.gap_step(s.wf, r.ravel(), s.cf, tau, s.shift)
    if rescale and abs(alpha - 1.0) > 1e-14:
        # after elements left without a restart, t is not zero-mean on the contact set
        s.stats = kr.scale_with_stats(
            s.pf, s.wf, problem.grid_heights.ravel(), s.cf, alpha, s.shift
        )
        s.psq *= alpha * alpha
    else:
        s.stats = stats


#: Preconditioned, without adhesion: the conjugacy survives a contact-set change of at most
#: this fraction of the contact set. On the paper-like surface (tol 1e-6) the iteration then
#: stops alternating between an element entering (at zero pressure) and leaving, each
#: restarting the conjugate gradients: 1024^2: 32 -> 26 iterations (1e-4: 29, 1e-2: 48, 0.1:
#: 33); 2048^2: 43 -> 32 (3e-3: 30).
KEEP_CONJUGACY_FRACTION = 1e-3


def restart_conjugacy(s: IterationState, problem: ContactProblem, upd: kr.PressureStep) -> bool:
    """Whether the next direction starts afresh (beta = 0): Polonsky & Keer restart when
    elements enter; with adhesion also when they leave; preconditioned without adhesion when
    more than ``KEEP_CONJUGACY_FRACTION`` of the contact set changed (a direction that is no
    longer a descent direction is restarted where it is built)."""
    changed = upd.n_entered + upd.n_left
    if s.pre is not None and not problem.adhesive:
        return changed > KEEP_CONJUGACY_FRACTION * upd.n_contact
    return upd.n_entered > 0 or (problem.adhesive and upd.n_left > 0)


def apply_step(
    s: IterationState,
    problem: ContactProblem,
    options: SolverOptions,
    g_sq: float,
    tau: float,
) -> None:
    """Step 5: pressure step and active-set update in one pass, the bookkeeping of the
    conjugacy (:func:`restart_conjugacy`), then the gap: when the contact set changed with a
    pressure jump (elements left, or entered with a pressure) u = K p is recomputed
    (:func:`restore_force`) and the pending K t is never transformed back (one inverse FFT
    saved), otherwise the incremental update (:func:`advance_gap`)."""
    gain = entering_gain(s, problem, tau)
    upd = kr.step_pressure(
        s.pf,
        s.tf,
        s.wf,
        s.cf,
        tau,
        s.offset,
        problem.critical_tension,
        s.allow_change,
        gain,
    )
    s.psq = upd.pressure_sq
    s.last_allowed = s.allow_change
    s.frozen_its = 0 if s.allow_change else s.frozen_its + 1
    s.g_old = g_sq
    s.steps += 1
    s.since_refresh += 1
    s.reset = restart_conjugacy(s, problem, upd)
    if upd.n_left or (upd.n_entered and gain != 0.0):
        restore_force(s, problem, upd.pressure_sum)
    else:
        advance_gap(s, problem, options, upd, tau)


def transform_input(s: IterationState, keep: np.ndarray | None = None) -> np.ndarray:
    """Where a direction kernel writes its copy of t (flat): the float32 input of the
    single-precision operator (the forward transform of t then casts nothing), else t itself
    (the copy is the same write again). Marks the copy made for :func:`step_length`.

    Not where it would overwrite ``keep`` (the preconditioned gap z, which the periodic
    operators hold in the same workspace: the direction may be rebuilt from z)."""
    direct = s.op.direct_input()
    if direct is not None and keep is not None and np.shares_memory(direct, keep):
        direct = None
    s.t_copied = direct is not None
    return direct.ravel() if direct is not None else s.tf


def _progress(
    s: IterationState, problem: ContactProblem, options: SolverOptions, g_sq: float, pen: float
) -> Stop | str | None:
    """:func:`check_progress`'s verdict, the switch to double precision made on :data:`SWITCH`
    (the iteration then ends: the next one starts in double precision)."""
    verdict = check_progress(s, problem, options, g_sq, pen)
    if verdict == SWITCH:
        switch_to_double(s, problem)
    return verdict


def _ended(verdict: Stop | str) -> Stop | None:
    """What an iteration that ends at ``verdict`` returns: the Stop, or None after a switch."""
    return verdict if isinstance(verdict, Stop) else None


def plain_pk_iteration(
    s: IterationState, problem: ContactProblem, options: SolverOptions
) -> Stop | None:
    """One iteration of plain Polonsky-Keer (conjugate gradients on the contact set)."""
    gap = measure_gap(s, problem)
    if isinstance(gap, Stop):
        return gap
    beta = 0.0 if s.reset or s.g_old <= 0 else gap.g_sq / s.g_old
    d = kr.update_direction_into(s.wf, s.cf, s.tf, transform_input(s), s.offset, beta)
    verdict = _progress(s, problem, options, gap.g_sq, d.penetration_sq)
    if isinstance(verdict, Stop) or verdict == SWITCH:
        return _ended(verdict)
    return _take_step(s, problem, options, gap.g_sq, d.sum_gt, d.n_penetrating)


def _take_step(
    s: IterationState,
    problem: ContactProblem,
    options: SolverOptions,
    g_sq: float,
    sgt: float,
    npen: int,
) -> Stop | None:
    tau = step_length(s, problem, options, sgt, npen)
    if isinstance(tau, Stop):
        return tau
    apply_step(s, problem, options, g_sq, tau)
    return None


def drop_preconditioner(s: IterationState) -> None:
    """The preconditioned iteration stopped making progress (seen once, on a rough 5001^2 map
    from a cold start): go on with plain Polonsky-Keer from this state."""
    s.pre = None
    s.dropped_at = s.steps
    s.best = s.residual
    s.best_it = s.steps
    s.reset = True


def _preconditioner(
    s: IterationState,
) -> tuple[Convolution | PaddedConvolution, np.ndarray, np.ndarray]:
    """The state's preconditioner and its input and output arrays s and z (a preconditioned
    iteration runs only while the state has all three)."""
    if s.pre is None or s.s_arr is None or s.z_arr is None:
        raise RuntimeError("preconditioned iteration on a state without its preconditioner")
    return s.pre, s.s_arr, s.z_arr


def preconditioned_pk_iteration(
    s: IterationState, problem: ContactProblem, options: SolverOptions
) -> Stop | None:
    """One preconditioned iteration: direction from z = P_c K^-1 P_c g (the stiffness E*|q|/2
    on the contact-set residual), zero-mean on Omega_c under load control, beta = (g.z) /
    (g.z)_old."""
    gap = measure_gap(s, problem)
    if isinstance(gap, Stop):
        return gap
    # single precision: the residual is written straight into the preconditioner's float32
    # input and z read from its output (no cast passes; the same bits)
    pre, s_work, z_work = _preconditioner(s)
    direct = pre.direct_input()
    s_arr = direct if direct is not None else s_work
    res = kr.residual_field(s.wf, s.cf, s_arr.ravel(), s.offset)
    verdict = _progress(s, problem, options, gap.g_sq, res.penetration_sq)
    if isinstance(verdict, Stop) or verdict == SWITCH:
        return _ended(verdict)
    if verdict == FALL_BACK:
        drop_preconditioner(s)
        d = kr.update_direction(s.wf, s.cf, s.tf, s.offset, 0.0)
        return _take_step(s, problem, options, gap.g_sq, d.sum_gt, d.n_penetrating)
    z_arr = s_arr if direct is not None else z_work
    gz = pre.with_energy(s_arr, z_arr)
    zf = z_arr.ravel()
    zbar = kr.masked_sum(zf, s.cf) / gap.n_contact if problem.load_control else 0.0
    beta = 0.0 if s.reset or s.gz_old <= 0 else gz / s.gz_old
    s.gz_old = gz
    tc = transform_input(s, keep=z_arr)
    sgt = kr.update_direction_preconditioned_into(s.wf, s.cf, s.tf, tc, zf, s.offset, zbar, beta)
    if beta != 0.0 and not sgt > 0:
        sgt = kr.update_direction_preconditioned_into(s.wf, s.cf, s.tf, tc, zf, s.offset, zbar, 0.0)
    return _take_step(s, problem, options, gap.g_sq, sgt, res.n_penetrating)


def iterate(s: IterationState, problem: ContactProblem, options: SolverOptions) -> Stop | None:
    """Iterate until a step stops the loop; None when the iteration cap was reached.

    Raises
    ------
    asperity.bem.cancel.Cancelled
        A cancellation (Ctrl-C) was requested: checked before every iteration, between the
        compiled kernels, never inside one.
    """
    # the pointwise kernels run on the FFT operator's threads (numba's thread mask; the
    # blocks' sums do not depend on it)
    with NumbaThreads(problem.op.threads):
        for _ in range(options.max_iterations(problem.heights.shape)):
            check_cancelled()
            step = plain_pk_iteration if s.pre is None else preconditioned_pk_iteration
            stop = step(s, problem, options)
            if stop is not None:
                return stop
    return None
