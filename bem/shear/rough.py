"""A rough surface under shear in load control: the normal preload at F_z, then the flat displaced
tangentially in steps up to full sliding, stick/slip by
:func:`asperity.bem.shear.stick_slip.solve_tangential`.

Model (nu = 1/2, so the normal problem is exactly independent of the tangential one: F_z, the
pressure and the contact set of the preload hold through the whole sweep):

* the preload is one normal solve at F_z (:func:`asperity.bem.solve_contact`, with or without
  Pohrt-Popov adhesion);
* each contact element sticks (moves with the flat, keeping its slip) or slides carrying its
  bound: the paper's constant shear strength tau_0 (E:Hertz_theory) or Coulomb mu p;
* each step carries the slip history and is warm-started from the tractions extrapolated
  linearly from the two previous steps, the preload (delta_T = 0, q = 0) counting as one (exact
  for elements that keep sticking);
* the contact set is held, so every step works on its elements only: the Cerruti operator as a
  dense matrix there (:class:`asperity.bem.shear.stick_slip.ContactMatrix`, when it fits in
  ``ShearOptions.dense_limit_bytes``; FFT convolutions otherwise), and MPRGP preconditioned by
  junction (:class:`asperity.bem.shear.stick_slip.JunctionPreconditioner`,
  ``ShearOptions.precondition``).
  Both change only the cost: the curve is the one of
  :func:`asperity.bem.shear.stick_slip.solve_tangential`
  step by step, to the tolerance (``tests/bem/test_bem_shear_speed.py``,
  ``benchmarks/bem_shear.py``).

Junctions are the connected clusters of the contact set (4-connected, merged across the periodic
boundary); a junction slides when none of its elements sticks; the interface slides when every
junction does (no stick element left).

What this model leaves out: with adhesion the mixed-mode edge law of the paper
(:mod:`asperity.bem.shear.mixed_mode`) would shrink the junctions under shear; here the contact set
of
the preload is held, so the real area does not drop and the static peak equals the sliding
force tau_0 A_r (the paper's constant-shear-strength reference of Fig 13). The mixed-mode law
junction by junction is :func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields

import numpy as np
from scipy import ndimage

from asperity.bem.elastic.tangential_influence import check_poisson
from asperity.bem.errors import BemInputError
from asperity.bem.normal.contact import solve_contact
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult
from asperity.bem.shear.stick_slip import (
    ContactMatrix,
    JunctionPreconditioner,
    ShearOptions,
    TangentialOperator,
    _mprgp,
    traction_bound,
)

__all__ = ["ShearCurve", "label_junctions", "shear_curve"]


def label_junctions(contact: np.ndarray, *, periodic: bool = True) -> tuple[np.ndarray, int]:
    """Connected clusters (4-connectivity) of a contact mask; merged across the edges if periodic.

    Returns
    -------
    labels : ndarray of int
        0 off contact, 1..n on the clusters.
    n : int
        Number of clusters.
    """
    labels, n = ndimage.label(np.asarray(contact, dtype=bool))
    if not periodic or n == 0:
        return labels, n
    parent = np.arange(n + 1)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in ((labels[0, :], labels[-1, :]), (labels[:, 0], labels[:, -1])):
        for i, j in zip(a[(a > 0) & (b > 0)], b[(a > 0) & (b > 0)], strict=True):
            ri, rj = find(int(i)), find(int(j))
            if ri != rj:
                parent[max(ri, rj)] = min(ri, rj)
    roots = np.array([find(i) for i in range(n + 1)])
    uniq, compact = np.unique(roots, return_inverse=True)
    # root 0 is the background (label 0 is its own root and the smallest)
    return compact.reshape(-1)[labels].reshape(labels.shape), int(uniq.size - 1)


@dataclass
class ShearCurve:
    """A load-controlled shear curve (SI units); one entry per tangential displacement.

    Attributes
    ----------
    tangential_displacement : ndarray
        delta_T (m).
    tangential_force : ndarray
        F_x (N).
    normal_force : ndarray
        F_z (N), held.
    real_area, stick_area, slip_area : ndarray
        A_r and its sticking and slipping parts (m^2).
    junctions, sliding_junctions : ndarray of int
        Number of contact clusters and of those without a stick element.
    sliding : ndarray of bool
        Every junction slides (gross sliding).
    converged : ndarray of bool
        The step's solve converged.
    nit : ndarray of int
        Iterations of each step.
    convolutions : ndarray of int
        Operator products of each step (FFT convolutions, or products by the dense matrix on
        the contact set: ``ShearOptions.dense_limit_bytes``).
    seconds : ndarray
        Wall time of each step (s).
    normal_seconds : float
        Wall time of the normal preload (s).
    final_traction : ndarray
        q_x (Pa) of the last step.
    substeps : ndarray of int or None
        The mixed-mode curve's transactional steps
        (:func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`): the number of
        sub-steps of delta_T each requested step was solved in (1: as asked; 2, 4, ...: the step
        failed, was undone and retried smaller, ``ShearOptions.max_step_halvings``); None for
        the solvers that do not retry.
    separation : ndarray or None
        The mixed-mode curve's rigid-body separation d of each step (m; load control: the
        flat's approach is -d); None for the other solvers.
    elastic_energy : ndarray or None
        The mixed-mode curve's elastic energy ``1/2 sum (p u_z + q u_x) dx dy`` of each step (J);
        with the work of the drive it gives the dissipation along the path (E:failure_locus
        dissipates ``(G - w) dA >= 0``, sliding ``tau_0`` times the slip); None for the others.
    preload_rim_fraction : float or None
        The mixed-mode curve's share of the bonded elements before shear that lie on the rim
        of the overloaded contact of its Pohrt-Popov preload (there the preload depends on the
        path: :data:`asperity.bem.shear.rough_mixed_mode.RIM_TOLERANCE`); 0 for a preload given
        as a monotone loading state (``initial``); None for the other solvers.
    """

    tangential_displacement: np.ndarray
    tangential_force: np.ndarray
    normal_force: np.ndarray
    real_area: np.ndarray
    stick_area: np.ndarray
    slip_area: np.ndarray
    junctions: np.ndarray
    sliding_junctions: np.ndarray
    sliding: np.ndarray
    converged: np.ndarray
    nit: np.ndarray
    convolutions: np.ndarray
    seconds: np.ndarray
    normal_seconds: float
    final_traction: np.ndarray = field(repr=False)
    substeps: np.ndarray | None = None
    separation: np.ndarray | None = None
    elastic_energy: np.ndarray | None = None
    preload_rim_fraction: float | None = None

    @property
    def success(self) -> bool:
        """Every step converged."""
        return bool(np.all(self.converged))


class _Counted:
    """An operator on the contact vectors (tractions in Pa -> displacements in m) that counts
    its products (``calls``, reset by the caller at each step)."""

    def __init__(self, apply: Callable[[np.ndarray], np.ndarray]) -> None:
        self.apply = apply
        self.calls = 0

    def __call__(self, v: np.ndarray) -> np.ndarray:
        self.calls += 1
        return self.apply(v)


class _GatheredConvolution:
    """The operator on the contact vectors by FFT convolutions of the whole grid: the vector
    (Pa) scattered on the grid, convolved, the displacements (m) gathered back."""

    def __init__(self, op: TangentialOperator, idx: np.ndarray) -> None:
        self.op = op
        self.idx = idx
        self.full = np.zeros(op.shape)
        self.flat = self.full.reshape(-1)

    def __call__(self, v: np.ndarray) -> np.ndarray:
        self.flat[self.idx] = v
        return self.op(self.full).reshape(-1)[self.idx]


@dataclass
class _HeldContact:
    """The contact set of the preload, held through the sweep, and the tangential problem on
    its elements (gathered vectors, C order).

    Attributes
    ----------
    idx : ndarray of int
        Flat indices of the contact elements on the height-map grid.
    q_max : ndarray
        Slip threshold (Pa) of each element: tau_0 (E:Hertz_theory) or mu p.
    labels : ndarray of int
        The junction of each element.
    n_junctions : int
        Number of junctions.
    apply : _Counted
        ``q -> u_x`` (Pa -> m) on the elements, counting its products.
    precondition : JunctionPreconditioner or None
        The junction preconditioner of the conjugate-gradient steps.
    norm : float
        ||K|| (m/Pa).
    scale : float
        Pixel stiffness E*/sqrt(dx dy) (Pa/m) of the residual.
    tol : float
        Residual to reach per step.
    max_iter : int
        Iteration cap per step.
    area : float
        Element area dx dy (m^2).
    """

    idx: np.ndarray
    q_max: np.ndarray
    labels: np.ndarray
    n_junctions: int
    apply: _Counted
    precondition: JunctionPreconditioner | None
    norm: float
    scale: float
    tol: float
    max_iter: int
    area: float


@dataclass
class _SweepState:
    """What one displacement step passes to the next, on the contact elements.

    Attributes
    ----------
    q : ndarray
        Tractions q_x (Pa) of the last step.
    u : ndarray
        Displacements u_x = K q (m) of the last step.
    slip : ndarray
        Accumulated slip s (m).
    prev, older : (float, ndarray)
        ``(delta_T, q)`` (m, Pa) of the last two steps, for the warm start; the preload counts
        as the step ``delta_T = 0, q = 0``; ``older`` None before the first step.
    """

    q: np.ndarray
    u: np.ndarray
    slip: np.ndarray
    prev: tuple[float, np.ndarray]
    older: tuple[float, np.ndarray] | None = None

    @classmethod
    def at_preload(cls, n: int) -> _SweepState:
        """The preload on ``n`` elements: delta_T = 0, q = 0, no slip."""
        return cls(np.zeros(n), np.zeros(n), np.zeros(n), (0.0, np.zeros(n)))


@dataclass
class _Step:
    """The observables of one displacement step (the per-step fields of :class:`ShearCurve`,
    SI units)."""

    tangential_displacement: float
    tangential_force: float
    normal_force: float
    real_area: float
    stick_area: float
    slip_area: float
    junctions: int
    sliding_junctions: int
    sliding: bool
    converged: bool
    nit: int
    convolutions: int
    seconds: float


#: dtypes of the :class:`ShearCurve` arrays that are not float64.
_DTYPES = {
    "junctions": int,
    "sliding_junctions": int,
    "sliding": bool,
    "converged": bool,
    "nit": int,
    "convolutions": int,
}


def _checked_displacements(tangential_displacements: np.ndarray, normal_force: float) -> np.ndarray:
    """The displacements delta_T (m) as a flat float64 array; a clear error for none, a NaN or
    a non-positive F_z (N)."""
    d_t = np.asarray(tangential_displacements, dtype=np.float64).ravel()
    if d_t.size == 0 or not np.all(np.isfinite(d_t)):
        raise BemInputError("tangential_displacements: expected finite values (m), got none or NaN")
    if not (math.isfinite(normal_force) and normal_force > 0):
        raise BemInputError(f"normal_force: expected a positive number (N), got {normal_force}")
    return d_t


def _preload(
    h: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_force: float,
    *,
    work_of_adhesion: float,
    periodic: bool,
    normal_options: SolverOptions | None,
    preload: ContactResult | None,
) -> tuple[ContactResult, float]:
    """The normal preload at F_z (N): the normal BEM (E:BEM_eq1 to E:BEM_eq4; with
    w > 0 (J/m^2) Pohrt-Popov's element criterion, eq:PohrtPopov_G), or the given ``preload``
    after checking its shape and F_z. Returns it and its wall time (s; 0 when given)."""
    if preload is None:
        t0 = time.perf_counter()
        normal = solve_contact(
            h,
            dx,
            dy,
            e_star,
            normal_force=normal_force,
            work_of_adhesion=work_of_adhesion,
            periodic=periodic,
            options=normal_options,
        )
        normal_seconds = time.perf_counter() - t0
    else:
        normal, normal_seconds = preload, 0.0
        if normal.pressure.shape != h.shape or not math.isclose(
            normal.normal_force, normal_force, rel_tol=1e-6
        ):
            raise BemInputError(
                f"preload: expected a solve of shape {h.shape} at {normal_force} N, got shape "
                f"{normal.pressure.shape} at {normal.normal_force} N"
            )
    if not normal.converged:
        raise BemInputError(f"normal preload did not converge: {normal.message}")
    return normal, normal_seconds


def _hold_contact(
    normal: ContactResult,
    bound: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    *,
    periodic: bool,
    opts: ShearOptions,
) -> _HeldContact:
    """The tangential problem on the preload's contact set, with slip thresholds ``bound``
    (Pa): the junctions, the Cerruti operator (a dense :class:`ContactMatrix` when it fits in
    ``opts.dense_limit_bytes``, FFT convolutions otherwise) and the junction preconditioner."""
    contact = normal.contact_mask
    shape = contact.shape
    labels, n_junctions = label_junctions(contact, periodic=periodic)
    op = TangentialOperator(
        shape, dx, dy, e_star, periodic=periodic, fft_backend=opts.fft_backend, threads=opts.threads
    )
    idx = np.flatnonzero(contact)
    if periodic and idx.size == contact.size:
        raise BemInputError(
            "contact: covers the whole periodic cell; the periodic tangential operator has no "
            "stiffness for a uniform traction, so the problem is singular: use a free domain"
        )
    if idx.size and ContactMatrix.nbytes(idx.size) <= opts.dense_limit_bytes:
        apply = ContactMatrix(op, contact)
    else:
        apply = _GatheredConvolution(op, idx)
    pre = None
    if opts.precondition and idx.size:
        pre = JunctionPreconditioner(
            op.kernel(), idx, labels.reshape(-1)[idx], shape, periodic=periodic
        )
    return _HeldContact(
        idx=idx,
        q_max=bound.reshape(-1)[idx],
        labels=labels.reshape(-1)[idx],
        n_junctions=n_junctions,
        apply=_Counted(apply),
        precondition=pre,
        norm=op.norm,
        scale=e_star / math.sqrt(dx * dy),
        tol=opts.tol,
        max_iter=opts.max_iterations(shape),
        area=dx * dy,
    )


def _warm_start(held: _HeldContact, state: _SweepState, value: float) -> np.ndarray:
    """The start of the step at delta_T = ``value`` (m): the tractions (Pa) extrapolated
    linearly from the two previous steps (exact for elements that keep sticking, the problem
    being linear while no element changes status), clipped to the bounds."""
    guess = state.q
    if state.older is not None:
        (d1, q1), (d0, q0) = state.prev, state.older
        span = d1 - d0
        if span != 0.0:
            guess = q1 + (value - d1) / span * (q1 - q0)
    return np.clip(guess, -held.q_max, held.q_max)


def _displacement_step(
    held: _HeldContact, state: _SweepState, value: float
) -> tuple[np.ndarray, int, int]:
    """One quasi-static step: the flat at delta_T = ``value`` (m), the stick/slip tractions by
    MPRGP from the warm start; ``state`` moves to the new step. Returns the stick elements
    (|q| < q_max), the solver's status and its iterations."""
    held.apply.calls = 0
    rhs = value - state.slip
    start = _warm_start(held, state, value)
    # the gradient at the start from the last step's displacements and the product of the
    # tractions' change (zero where the elements keep slipping at their bound)
    change = start - state.q
    if change.any():
        state.u = state.u + held.apply(change)
    q, g, status, _, nit, _ = _mprgp(
        held.apply,
        rhs,
        -held.q_max,
        held.q_max,
        start,
        norm=held.norm,
        scale=held.scale,
        tol=held.tol,
        max_iter=held.max_iter,
        precondition=held.precondition,
        g0=state.u - rhs,
        sparse_updates=True,
    )
    state.u = g + rhs
    stick = np.abs(q) < held.q_max
    # slipping elements take their new slip delta_T - u_x, u_x = g + rhs (no convolution)
    state.slip = np.where(stick, state.slip, value - state.u)
    state.older, state.prev, state.q = state.prev, (value, q), q
    return stick, status, nit


def _observe(
    held: _HeldContact,
    normal: ContactResult,
    q: np.ndarray,
    stick: np.ndarray,
    value: float,
    status: int,
    nit: int,
    t0: float,
) -> _Step:
    """A step's observables: F_x = sum q dx dy (N), the stick and slip areas (m^2), the
    junctions that slide (no stick element), convergence and cost (``t0``: its start, s)."""
    n_stick = int(np.count_nonzero(np.unique(held.labels[stick])))
    return _Step(
        tangential_displacement=value,
        tangential_force=float(q.sum() * held.area),
        normal_force=normal.normal_force,
        real_area=normal.real_area,
        stick_area=float(np.count_nonzero(stick)) * held.area,
        slip_area=(held.idx.size - np.count_nonzero(stick)) * held.area,
        junctions=held.n_junctions,
        sliding_junctions=held.n_junctions - n_stick,
        sliding=n_stick == 0,
        converged=status == 0,
        nit=nit,
        convolutions=held.apply.calls,
        seconds=time.perf_counter() - t0,
    )


def _curve(
    steps: list[_Step],
    normal_seconds: float,
    held: _HeldContact,
    q: np.ndarray,
    shape: tuple[int, int],
) -> ShearCurve:
    """The steps as a :class:`ShearCurve`, with the last tractions ``q`` (Pa) on the grid."""
    final = np.zeros(shape)
    final.reshape(-1)[held.idx] = q
    columns = {
        f.name: np.array([getattr(s, f.name) for s in steps], dtype=_DTYPES.get(f.name))
        for f in fields(_Step)
    }
    return ShearCurve(**columns, normal_seconds=normal_seconds, final_traction=final)


def shear_curve(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_force: float,
    tangential_displacements: np.ndarray,
    *,
    shear_strength: float | None = None,
    friction_coefficient: float | None = None,
    work_of_adhesion: float = 0.0,
    periodic: bool = True,
    poisson_ratio: float = 0.5,
    normal_options: SolverOptions | None = None,
    options: ShearOptions | None = None,
    stop_when_sliding: bool = False,
    preload: ContactResult | None = None,
) -> ShearCurve:
    """Normal preload at F_z, then the tangential displacements in order, warm-started.

    The steps: the preload (:func:`_preload`), the problem on its contact set
    (:func:`_hold_contact`), then per displacement one step (:func:`_displacement_step`) and
    its observables (:func:`_observe`).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights h (m), larger = closer to the flat.
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa), nu = 1/2.
    normal_force : float
        F_z (N), held during shear.
    tangential_displacements : array_like
        delta_T values (m), in loading order (any order: the slip history is carried).
    shear_strength, friction_coefficient : float, optional
        Exactly one: tau_0 (Pa, the paper's sliding law, E:Hertz_theory) or mu (Coulomb).
    work_of_adhesion : float
        w (J/m^2) of the preload (Pohrt-Popov, :func:`asperity.bem.solve_contact`).
    periodic : bool
        Periodic domain (default) or free.
    poisson_ratio : float
        Must be 0.5.
    normal_options, options : optional
        Options of the normal preload and of the tangential steps.
    stop_when_sliding : bool
        Stop after the first step in gross sliding (the remaining entries are not computed:
        the arrays are as long as the steps done).
    preload : ContactResult, optional
        A normal solve of these heights at ``normal_force`` to start from (e.g. to shear one
        preload with several laws); then ``work_of_adhesion`` and ``normal_options`` are unused
        and ``normal_seconds`` is 0.

    Returns
    -------
    ShearCurve
    """
    check_poisson(poisson_ratio)
    opts = options if options is not None else ShearOptions()
    d_t = _checked_displacements(tangential_displacements, normal_force)
    h = np.asarray(heights, dtype=np.float64)
    normal, normal_seconds = _preload(
        h,
        dx,
        dy,
        e_star,
        normal_force,
        work_of_adhesion=work_of_adhesion,
        periodic=periodic,
        normal_options=normal_options,
        preload=preload,
    )
    bound = traction_bound(
        normal.contact_mask,
        pressure=normal.pressure,
        friction_coefficient=friction_coefficient,
        shear_strength=shear_strength,
    )
    held = _hold_contact(normal, bound, dx, dy, e_star, periodic=periodic, opts=opts)
    state = _SweepState.at_preload(held.idx.size)
    steps: list[_Step] = []
    for value in d_t:
        t0 = time.perf_counter()
        stick, status, nit = _displacement_step(held, state, float(value))
        steps.append(_observe(held, normal, state.q, stick, float(value), status, nit, t0))
        if stop_when_sliding and steps[-1].sliding:
            break
    return _curve(steps, normal_seconds, held, state.q, h.shape)
