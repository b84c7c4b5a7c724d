"""A rough surface under shear in load control: the normal preload at F_z, then the flat displaced
tangentially in steps up to full sliding, stick/slip by :func:`asperity.bem.shear.solve_tangential`.

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
  dense matrix there (:class:`asperity.bem.shear.ContactMatrix`, when it fits in
  ``ShearOptions.dense_limit_bytes``; FFT convolutions otherwise), and MPRGP preconditioned by
  junction (:class:`asperity.bem.shear.JunctionPreconditioner`, ``ShearOptions.precondition``).
  Both change only the cost: the curve is the one of :func:`asperity.bem.shear.solve_tangential`
  step by step, to the tolerance (``tests/bem/test_bem_shear_speed.py``,
  ``benchmarks/bem_shear.py``).

Junctions are the connected clusters of the contact set (4-connected, merged across the periodic
boundary); a junction slides when none of its elements sticks; the interface slides when every
junction does (no stick element left).

What this model leaves out: with adhesion the mixed-mode edge law of the paper
(:mod:`asperity.bem.mixed_mode`) would shrink the junctions under shear; here the contact set of
the preload is held, so the real area does not drop and the static peak equals the sliding
force tau_0 A_r (the paper's constant-shear-strength reference of Fig 13). The mixed-mode law
junction by junction is :func:`asperity.bem.rough_mixed_mode.mixed_mode_shear_curve`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from asperity.bem.contact import solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult
from asperity.bem.shear import (
    ContactMatrix,
    JunctionPreconditioner,
    ShearOptions,
    TangentialOperator,
    _mprgp,
    traction_bound,
)
from asperity.bem.tangential_influence import check_poisson

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

    @property
    def success(self) -> bool:
        """Every step converged."""
        return bool(np.all(self.converged))


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
        Exactly one: tau_0 (Pa, the paper's sliding law) or mu (Coulomb).
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
    d_t = np.asarray(tangential_displacements, dtype=np.float64).ravel()
    if d_t.size == 0 or not np.all(np.isfinite(d_t)):
        raise BemInputError("tangential_displacements: expected finite values (m), got none or NaN")
    if not (math.isfinite(normal_force) and normal_force > 0):
        raise BemInputError(f"normal_force: expected a positive number (N), got {normal_force}")
    h = np.asarray(heights, dtype=np.float64)
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
    contact = normal.contact_mask
    bound = traction_bound(
        contact,
        pressure=normal.pressure,
        friction_coefficient=friction_coefficient,
        shear_strength=shear_strength,
    )
    labels, n_junctions = label_junctions(contact, periodic=periodic)
    op = TangentialOperator(
        h.shape,
        dx,
        dy,
        e_star,
        periodic=periodic,
        fft_backend=opts.fft_backend,
        threads=opts.threads,
    )
    # the contact set is held: every step works on its elements only (gathered vectors), with
    # the operator as a dense matrix on them when it fits (ShearOptions.dense_limit_bytes)
    idx = np.flatnonzero(contact)
    if periodic and idx.size == contact.size:
        raise BemInputError(
            "contact: covers the whole periodic cell; the periodic tangential operator has no "
            "stiffness for a uniform traction, so the problem is singular: use a free domain"
        )
    if idx.size and ContactMatrix.nbytes(idx.size) <= opts.dense_limit_bytes:
        apply = ContactMatrix(op, contact)
    else:
        full = np.zeros(h.shape)
        flat = full.reshape(-1)

        def apply(v: np.ndarray) -> np.ndarray:
            flat[idx] = v
            return op(full).reshape(-1)[idx]

    pre = None
    if opts.precondition and idx.size:
        pre = JunctionPreconditioner(
            op.kernel(), idx, labels.reshape(-1)[idx], h.shape, periodic=periodic
        )
    calls = 0

    def counted(v: np.ndarray) -> np.ndarray:
        nonlocal calls
        calls += 1
        return apply(v)

    q_max = bound.reshape(-1)[idx]
    lab = labels.reshape(-1)[idx]
    scale = e_star / math.sqrt(dx * dy)
    max_iter = opts.max_iterations(h.shape)
    area = dx * dy
    slip = np.zeros(idx.size)
    rows: list[tuple] = []
    # the preload is the state delta_T = 0, q = 0 (no slip): the first step after it extrapolates
    # from there (exact while every element sticks, the problem being linear then)
    prev: tuple[float, np.ndarray] | None = (0.0, np.zeros(idx.size))
    older: tuple[float, np.ndarray] | None = None
    q = np.zeros(idx.size)
    u = np.zeros(idx.size)  # u_x = K q on the contact set (m)
    for value in d_t:
        t0 = time.perf_counter()
        guess = q
        if prev is not None and older is not None:
            # linear extrapolation of the tractions: exact for elements that keep sticking
            # (the problem is linear while no element changes status); clipped to the bounds
            span = prev[0] - older[0]
            if span != 0.0:
                guess = prev[1] + (float(value) - prev[0]) / span * (prev[1] - older[1])
        calls = 0
        rhs = float(value) - slip
        start = np.clip(guess, -q_max, q_max)
        # the gradient at the guess from the last step's displacements and the product of the
        # tractions' change (zero where the elements keep slipping at their bound)
        u = u + counted(start - q) if (start - q).any() else u
        q, g, status, _, nit, _ = _mprgp(
            counted,
            rhs,
            -q_max,
            q_max,
            start,
            norm=op.norm,
            scale=scale,
            tol=opts.tol,
            max_iter=max_iter,
            precondition=pre,
            g0=u - rhs,
            sparse_updates=True,
        )
        u = g + rhs
        stick = np.abs(q) < q_max
        # slipping elements take their new slip delta_T - u_x, u_x = g + rhs (no convolution)
        slip = np.where(stick, slip, float(value) - u)
        n_stick = int(np.count_nonzero(np.unique(lab[stick])))
        stick_area = float(np.count_nonzero(stick)) * area
        rows.append(
            (
                float(value),
                float(q.sum() * area),
                normal.normal_force,
                normal.real_area,
                stick_area,
                (idx.size - np.count_nonzero(stick)) * area,
                n_junctions,
                n_junctions - n_stick,
                n_stick == 0,
                status == 0,
                nit,
                calls,
                time.perf_counter() - t0,
            )
        )
        older, prev = prev, (float(value), q)
        if stop_when_sliding and n_stick == 0:
            break
    final = np.zeros(h.shape)
    final.reshape(-1)[idx] = q
    cols = list(zip(*rows, strict=True))
    return ShearCurve(
        tangential_displacement=np.array(cols[0]),
        tangential_force=np.array(cols[1]),
        normal_force=np.array(cols[2]),
        real_area=np.array(cols[3]),
        stick_area=np.array(cols[4]),
        slip_area=np.array(cols[5]),
        junctions=np.array(cols[6], dtype=int),
        sliding_junctions=np.array(cols[7], dtype=int),
        sliding=np.array(cols[8], dtype=bool),
        converged=np.array(cols[9], dtype=bool),
        nit=np.array(cols[10], dtype=int),
        convolutions=np.array(cols[11], dtype=int),
        seconds=np.array(cols[12]),
        normal_seconds=normal_seconds,
        final_traction=final,
    )
