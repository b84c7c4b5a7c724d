"""Adhesive contact under shear with the paper's mode-mixity law (E:failure_locus), in the BEM.

The law. With G_I = K_I^2 / (2 E*) and G_II = K_II^2 / (2 E*), E:failure_locus,
``(K_I^2 + K_II^2) / (2 E*) = w f(psi)`` with ``f = [1 + (lambda - 1) sin^2 psi]^-1`` and
``sin^2 psi = K_II^2 / (K_I^2 + K_II^2)``, reads

    (G_I + G_II) [1 + (lambda - 1) G_II / (G_I + G_II)] = G_I + lambda G_II = w,

exactly. The edge advances (the element detaches) where G_I + lambda G_II >= w.

Mesh-dependent criterion (the generalisation of Pohrt & Popov 2015, Appendix B,
eq:PohrtPopov_G). An element in contact detaches when

    (min(p, 0)^2 chi + lambda q^2 chi_T) / (dx dy E*) >= w,

p the normal traction (tension < 0; a compressed element has no mode-I release), q the
tangential one (Pa), chi Pohrt-Popov's factor
(:func:`asperity.bem.elastic.pohrt_popov.pohrt_popov_chi`).
Two choices of chi_T, the :class:`MixedModeLaw` field ``tangential_energy``:

``"pc"`` (default): chi_T = chi.
    The tangential term is calibrated as the normal one: the edge traction of a crack tip,
    ``q ~ K_II / sqrt(2 pi r)``, has the same form as ``p ~ K_I / sqrt(2 pi r)``, so
    ``q^2 chi / (dx dy E*)`` estimates K_II^2 / (2 E*) exactly as Pohrt-Popov's estimates
    K_I^2 / (2 E*). This is the law of the paper and of Papangelo-Ciavarella, whose K_II is the
    nominal ``T / (2 a sqrt(pi a))`` all round the edge (Savkoor-Briggs), mode III included.
    E:PC_indent..E:PC_T are reproduced with it (``tests/bem/test_bem_shear_pc_sphere.py``).
``"cerruti"``: chi_T = :func:`asperity.bem.elastic.tangential_influence.tangential_chi`
    (1.5 chi on a square element), the energy actually released by removing the element's tangential
    traction. Where the edge runs along x the tangential field is mode III, whose release
    rate for an incompressible body on a rigid flat is ``K_III^2 / (4 G) = K_III^2 / E*``, twice
    the mode-II one: averaged round a circular edge the energy release of a tangential load is
    ``3/2 K_II^2 / (2 E*)`` (it equals ``T^2/2 dC/dA`` with the compliance ``C = 3 / (4 E* a)``).
    With this choice the BEM follows the energy and sits near PC with lambda replaced by
    1.5 lambda; it is offered to show what PC's nominal K_II leaves out, not as the paper's law.

Both are mesh-dependent in the way Pohrt-Popov's criterion is (the element energy estimates
the release rate of a crack-tip field resolved over one element); their error against the
closed forms falls as the mesh is refined (measured in the tests).

Domain: free (non-periodic, zero-padded FFT), for isolated junctions such as the sphere of
Section 2; periodic rough surfaces under this law are not covered here. The state (nu = 1/2:
normal and tangential elasticity uncoupled, coupled only through the contact set): on Omega_c
the flat sticks in both directions, ``u_z = h - d`` and ``u_x = delta_T - s``; elements outside
carry nothing. One solve at given (d, delta_T) is an
active-set iteration (Pohrt-Popov's): with Omega_c frozen, the two linear problems are solved by
conjugate gradients (:func:`asperity.bem.shear.stick_slip.box_conjugate_gradients` without bounds,
warm
started); then every element meeting the criterion detaches and every element outside that
penetrates (gap < 0) attaches, bonding tangentially where it stands (its slip set to
``delta_T - u_x``: no misfit); repeat until the set stops changing. Detachment is irreversible
within a step, so the state depends on the path: reach a state by increasing delta_T in steps
from the preload (:func:`tangential_sweep`).

Preload (the paper's JKR equilibrium before shear). Pohrt-Popov load then unload in one go:
start from the contact set of a deeper approach (:func:`overlap_contact`) and let the criterion
(at delta_T = 0 it is Pohrt-Popov's) detach the excess; the edge stops where G_I = w, the JKR
unloading branch (checked against E:JKR_indent, E:JKR_load).

Instability and sliding. Past delta_T^max (E:max_disp_PC) no stick state exists: the detachment
cascades. At delta < 0 the contact collapses to nothing; at delta > 0 it recedes in one step to
the Hertz contact, where the mode-I ring is gone (K_I = 0) and the mode-II term alone cannot
detach the compressed edge (Pohrt-Popov attach only on penetration, so the contact cannot
spread back). A step is declared unstable when its area falls below ``collapse_fraction`` of
the area at the step's start, when the contact no longer carries tension
(:data:`ADHESION_LOST`), or when, under shear (delta_T > 0), an element that the step detached
penetrates again: the receding edge has overshot to the Hertz contact, which is how the cascade
past the fold shows on a mesh (issue 34: at 48 and 64 elements per JKR radius the
simultaneous detachments of the cascade passed a_H, 284 of 3544 elements bonded again where
they stood, with no tangential misfit, and that relaxed rim held a stick state with every
element below w up to 1.09-1.12 delta_T^max, where PC's G is 3-11 % above w; docs/bem_shear.md);
the junction then slides (the paper's status map): its contact becomes
non-adhesive (w = 0, E:Hertz_theory) and carries the constant shear strength tau_0
(:func:`sliding_state`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from asperity.bem.elastic.pohrt_popov import pohrt_popov_chi
from asperity.bem.elastic.tangential_influence import check_poisson, tangential_chi
from asperity.bem.errors import BemInputError
from asperity.bem.shear.stick_slip import ShearOptions, TangentialOperator, box_conjugate_gradients

#: A contact whose largest element mode-I release rate is below this fraction of w has lost its
#: adhesive ring (K_I = 0 all round): past the fold of E:max_disp_PC the Pohrt-Popov criterion,
#: which attaches only on penetration, leaves the non-adhesive (Hertz) contact stuck instead of
#: collapsing it; by the paper's status map that junction slides.
ADHESION_LOST = 0.01

__all__ = [
    "AdhesiveShearState",
    "MixedModeLaw",
    "ShearSweep",
    "adhesive_shear_solve",
    "overlap_contact",
    "sliding_state",
    "tangential_sweep",
]


@dataclass(frozen=True)
class MixedModeLaw:
    """The mixed-mode edge law G_I + lambda G_II = w (E:failure_locus) on a mesh.

    Attributes
    ----------
    work_of_adhesion : float
        w (J/m^2), > 0.
    mode_mixity : float
        lambda in [0, 1] (0: mode I only, JKR; 1: Griffith, Savkoor-Briggs).
    tangential_energy : {"pc", "cerruti"}
        chi_T = chi (the paper's nominal K_II) or the Cerruti patch energy (module docstring).
    """

    work_of_adhesion: float
    mode_mixity: float
    tangential_energy: str = "pc"

    def __post_init__(self) -> None:
        w = self.work_of_adhesion
        if not (isinstance(w, (int, float)) and math.isfinite(w) and w > 0):
            raise BemInputError(f"work_of_adhesion: expected a positive number (J/m^2), got {w!r}")
        lam = self.mode_mixity
        if not (isinstance(lam, (int, float)) and 0.0 <= lam <= 1.0):
            raise BemInputError(f"mode_mixity: expected lambda in [0, 1], got {lam!r}")
        if self.tangential_energy not in ("pc", "cerruti"):
            raise BemInputError(
                f"tangential_energy: expected 'pc' or 'cerruti', got {self.tangential_energy!r}"
            )

    def factors(self, dx: float, dy: float) -> tuple[float, float]:
        """(chi, chi_T) in m^3 for dx x dy elements."""
        chi = pohrt_popov_chi(dx, dy)
        chi_t = chi if self.tangential_energy == "pc" else tangential_chi(dx, dy)
        return chi, chi_t

    def release_rate(
        self, pressure: np.ndarray, traction: np.ndarray, dx: float, dy: float, e_star: float
    ) -> np.ndarray:
        """Element estimate of G_I + lambda G_II (J/m^2):
        ``(min(p, 0)^2 chi + lambda q^2 chi_T) / (dx dy E*)``."""
        chi, chi_t = self.factors(dx, dy)
        pt = np.minimum(pressure, 0.0)
        return (pt * pt * chi + self.mode_mixity * traction * traction * chi_t) / (dx * dy * e_star)


@dataclass
class AdhesiveShearState:
    """One equilibrium (or collapse) of the adhesive contact under shear (SI units).

    Attributes
    ----------
    pressure, traction : ndarray
        Normal (tension < 0) and tangential tractions (Pa); 0 off the contact set.
    contact : ndarray of bool
        The contact set.
    slip : ndarray
        Tangential reference s (m) of each element: ``u_x = delta_T - s`` where stuck.
    gap : ndarray
        Normal gap ``u_z - h + d`` (m); 0 on the contact set.
    separation, tangential_displacement : float
        d and delta_T (m).
    normal_force, tangential_force : float
        P = sum p dx dy and T = sum q dx dy (N).
    real_area : float
        Contact area (m^2).
    stable : bool
        False when the step's contact collapsed (below ``collapse_fraction`` of its starting
        area, or lost): no stick state at this delta_T.
    success, status, message, nit
        scipy-like: status 0 an equilibrium (stable or not: a collapse is a result, not a
        failure), 1 a linear solve hit its iteration cap or the active set did not settle,
        2 numerical failure; ``nit`` active-set iterations.
    cg_iterations : int
        Conjugate-gradient iterations of both problems, summed.
    seconds : float
        Wall time (s).
    """

    pressure: np.ndarray
    traction: np.ndarray
    contact: np.ndarray
    slip: np.ndarray
    gap: np.ndarray
    separation: float
    tangential_displacement: float
    normal_force: float
    tangential_force: float
    real_area: float
    stable: bool
    success: bool
    status: int
    message: str
    nit: int
    cg_iterations: int
    seconds: float

    @property
    def contact_radius(self) -> float:
        """sqrt(A / pi) (m): the radius of a disc of the contact's area."""
        return math.sqrt(self.real_area / math.pi)


@dataclass
class _Operators:
    normal: TangentialOperator
    tangential: TangentialOperator


def _operators(
    shape: tuple[int, int],
    dx: float,
    dy: float,
    e_star: float,
    opts: ShearOptions,
) -> _Operators:
    kw = {"periodic": False, "fft_backend": opts.fft_backend, "threads": opts.threads}
    return _Operators(
        TangentialOperator(shape, dx, dy, e_star, normal=True, **kw),
        TangentialOperator(shape, dx, dy, e_star, **kw),
    )


def overlap_contact(heights: np.ndarray, separation: float) -> np.ndarray:
    """The contact set of the rigid approach: elements with ``h - d >= 0`` (bool array).

    With ``separation`` below the target's d this is the 'load' half of Pohrt-Popov's load then
    unload: the preload solve detaches what the adhesion cannot hold.
    """
    return np.asarray(heights) - separation >= 0.0


def adhesive_shear_solve(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    separation: float,
    tangential_displacement: float,
    law: MixedModeLaw,
    *,
    contact: np.ndarray | AdhesiveShearState,
    slip: np.ndarray | None = None,
    poisson_ratio: float = 0.5,
    collapse_fraction: float = 0.5,
    max_active_set: int = 500,
    options: ShearOptions | None = None,
    operators: _Operators | None = None,
) -> AdhesiveShearState:
    """The stick state at (d, delta_T) reached from ``contact`` under the mixed-mode law.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Surface heights h (m), larger = closer to the flat (a sphere: ``-r^2 / (2 R)``).
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa), nu = 1/2.
    separation : float
        Rigid-body distance d (m), displacement control: ``gap = u_z - h + d`` (for a sphere
        with apex at h = 0 the indentation is ``delta = -d``).
    tangential_displacement : float
        delta_T (m) of the flat along x.
    law : MixedModeLaw
        w, lambda and the choice of chi_T.
    contact : ndarray of bool or AdhesiveShearState
        Starting contact set: the previous state (its tractions warm-start the solves and its
        slip is used), or a set such as :func:`overlap_contact` for the preload.
    slip : ndarray, optional
        Tangential references s (m); default: the previous state's, or zero.
    poisson_ratio : float
        Must be 0.5.
    collapse_fraction : float
        In (0, 1): the step is unstable when the area falls below this fraction of its start.
    max_active_set : int
        Cap on the active-set iterations.
    options : ShearOptions, optional
        Tolerance of the linear solves, FFT backend.
    operators
        Internal: the normal and tangential FFT operators of this grid, passed by
        :func:`tangential_sweep` so that its steps share one FFT plan; None builds them.

    Returns
    -------
    AdhesiveShearState
    """
    t0 = time.perf_counter()
    check_poisson(poisson_ratio)
    opts = options if options is not None else ShearOptions()
    h = np.asarray(heights, dtype=np.float64)
    _check_solve_inputs(h, collapse_fraction, separation, tangential_displacement)
    it = _starting_iterate(contact, slip, h.shape)
    ops = operators if operators is not None else _operators(h.shape, dx, dy, e_star, opts)
    fixed = _Fixed(h, dx, dy, e_star, float(separation), float(tangential_displacement), law, ops)
    max_iter = opts.max_iterations(h.shape)
    while True:
        it.nit += 1
        if not it.c.any():
            it.stable = it.area0 == 0
            it.message = "contact lost"
            it.p[...] = 0.0
            it.q[...] = 0.0
            break
        if _solve_fixed_set(it, fixed, opts.tol, max_iter):
            break
        if _update_sets(it, fixed, collapse_fraction):
            break
        if it.nit >= max_active_set:
            it.status, it.message = 1, "active set did not settle"
            break
    return _closed_state(it, fixed, time.perf_counter() - t0)


@dataclass
class _Fixed:
    """What one solve holds fixed: the surface, d and delta_T (m), the law, the operators."""

    h: np.ndarray
    dx: float
    dy: float
    e_star: float
    separation: float
    tangential_displacement: float
    law: MixedModeLaw
    ops: _Operators


@dataclass
class _Iterate:
    """The active-set iteration of :func:`adhesive_shear_solve` (SI units)."""

    c: np.ndarray  # contact (bonded) set
    p: np.ndarray  # normal traction (Pa)
    q: np.ndarray  # tangential traction (Pa)
    s: np.ndarray  # tangential reference (m)
    area0: int  # elements at the start
    gap: np.ndarray = None  # normal gap (m) of the last iteration
    gone: np.ndarray = None  # elements detached in this solve
    nit: int = 0
    cg: int = 0
    status: int = 0
    message: str = "equilibrium"
    stable: bool = True


def _check_solve_inputs(h, collapse_fraction, separation, tangential_displacement) -> None:
    """BemInputError naming the argument of :func:`adhesive_shear_solve` that is not valid."""
    if h.ndim != 2 or not np.all(np.isfinite(h)):
        raise BemInputError(f"heights: expected a finite 2D array (m), got shape {h.shape}")
    if not (0.0 < collapse_fraction < 1.0):
        raise BemInputError(f"collapse_fraction: expected in (0, 1), got {collapse_fraction}")
    for name, val in (
        ("separation", separation),
        ("tangential_displacement", tangential_displacement),
    ):
        if not math.isfinite(val):
            raise BemInputError(f"{name}: expected a finite number (m), got {val}")


def _starting_iterate(contact, slip, shape) -> _Iterate:
    """The iteration's start: a previous state (its tractions and slip) or a contact set."""
    p = np.zeros(shape)
    q = np.zeros(shape)
    if isinstance(contact, AdhesiveShearState):
        prev = contact
        c = prev.contact.copy()
        p[...] = prev.pressure
        q[...] = prev.traction
        s = prev.slip.copy() if slip is None else np.asarray(slip, dtype=np.float64).copy()
    else:
        c = np.asarray(contact, dtype=bool).copy()
        s = np.zeros(shape) if slip is None else np.asarray(slip, dtype=np.float64).copy()
    if c.shape != shape or s.shape != shape:
        raise BemInputError(f"contact/slip: expected shape {shape}, got {c.shape} and {s.shape}")
    return _Iterate(c, p, q, s, int(c.sum()), np.zeros(shape), np.zeros(shape, dtype=bool))


def _solve_fixed_set(it: _Iterate, fixed: _Fixed, tol: float, max_iter: int) -> bool:
    """p and q on the frozen set by conjugate gradients, warm-started (in place). True when a
    solve failed numerically (status 2): the iteration stops."""
    ops = fixed.ops
    inf = np.full(it.c.shape, np.inf)
    kw = {"scale": fixed.e_star / math.sqrt(fixed.dx * fixed.dy), "tol": tol, "max_iter": max_iter}
    rn = box_conjugate_gradients(
        ops.normal, fixed.h - fixed.separation, it.c, -inf, inf, it.p, norm=ops.normal.norm, **kw
    )
    rt = box_conjugate_gradients(
        ops.tangential,
        fixed.tangential_displacement - it.s,
        it.c,
        -inf,
        inf,
        it.q,
        norm=ops.tangential.norm,
        **kw,
    )
    it.cg += rn.nit + rt.nit
    it.p, it.q = rn.x, rt.x
    if rn.status == 2 or rt.status == 2:
        it.status = 2
        it.message = f"linear solve failed: {rn.message if rn.status else rt.message}"
        return True
    if rn.status or rt.status:
        it.status, it.message = 1, "a linear solve reached its iteration cap"
    return False


def _update_sets(it: _Iterate, fixed: _Fixed, collapse_fraction: float) -> bool:
    """Detach where G_I + lambda G_II >= w, attach where the gap closes (in place). True when
    the iteration ends: the sets settled (with the adhesion-lost test), or no stick state (the
    cascade overshot into penetration under shear, or the area collapsed)."""
    law, w = fixed.law, fixed.law.work_of_adhesion
    g_rate = law.release_rate(it.p, it.q, fixed.dx, fixed.dy, fixed.e_star)
    detach = it.c & (g_rate >= w)
    it.gap = fixed.ops.normal(it.p) - fixed.h + fixed.separation
    attach = ~it.c & (it.gap < 0.0)
    if not detach.any() and not attach.any():
        g_one = law.release_rate(it.p, np.zeros(it.c.shape), fixed.dx, fixed.dy, fixed.e_star)
        if it.area0 > 0 and float(g_one.max()) < ADHESION_LOST * w:
            it.stable = False
            it.message = "adhesion lost: the contact carries no tension (K_I = 0), it slides"
        return True
    it.c &= ~detach
    it.p[detach] = 0.0
    it.q[detach] = 0.0
    it.gone |= detach
    if fixed.tangential_displacement > 0 and it.area0 > 0 and (attach & it.gone).any():
        it.stable = False
        it.message = (
            "collapsed through the fold: the receding edge overshot into penetration "
            "(the Hertz contact), no stick state"
        )
        return True
    if attach.any():
        u_x = fixed.ops.tangential(it.q)
        it.s[attach] = fixed.tangential_displacement - u_x[attach]
        it.c |= attach
    if it.area0 > 0 and it.c.sum() < collapse_fraction * it.area0:
        it.stable = False
        it.message = "collapsed: no stick state (the junction slides or separates)"
        return True
    return False


def _closed_state(it: _Iterate, fixed: _Fixed, seconds: float) -> AdhesiveShearState:
    """The AdhesiveShearState of a finished iteration (references reset off the contact)."""
    delta_t = fixed.tangential_displacement
    u_x = fixed.ops.tangential(it.q)
    area = fixed.dx * fixed.dy
    return AdhesiveShearState(
        pressure=it.p,
        traction=it.q,
        contact=it.c,
        slip=np.where(it.c, it.s, delta_t - u_x),
        gap=np.where(it.c, 0.0, it.gap),
        separation=fixed.separation,
        tangential_displacement=delta_t,
        normal_force=float(it.p.sum() * area),
        tangential_force=float(it.q.sum() * area),
        real_area=float(it.c.sum() * area),
        stable=it.stable,
        success=it.status == 0,
        status=it.status,
        message=it.message,
        nit=it.nit,
        cg_iterations=it.cg,
        seconds=seconds,
    )


def sliding_state(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    separation: float,
    tangential_displacement: float,
    shear_strength: float,
    *,
    options: ShearOptions | None = None,
    operators: _Operators | None = None,
) -> AdhesiveShearState:
    """The sliding state of the paper's status map (E:Hertz_theory): the non-adhesive contact at d
    carrying the constant shear strength tau_0 (Pa) on every contact element.

    The normal problem ``minimise 1/2 p.K p - p.(h - d)`` over p >= 0 (the Signorini conditions:
    gap >= 0, p >= 0, p gap = 0) is solved with the bound-constrained conjugate gradients on the
    whole grid; nu = 1/2, so the traction tau_0 does not change it. Parameters as
    :func:`adhesive_shear_solve`; ``slip`` of the result is ``delta_T - u_x`` everywhere.
    """
    t0 = time.perf_counter()
    opts = options if options is not None else ShearOptions()
    h = np.asarray(heights, dtype=np.float64)
    if not (math.isfinite(shear_strength) and shear_strength >= 0):
        raise BemInputError(
            f"shear_strength: expected a finite number >= 0 (Pa), got {shear_strength}"
        )
    shape = h.shape
    ops = operators if operators is not None else _operators(shape, dx, dy, e_star, opts)
    everywhere = np.ones(shape, dtype=bool)
    rn = box_conjugate_gradients(
        ops.normal,
        h - separation,
        everywhere,
        np.zeros(shape),
        np.full(shape, np.inf),
        np.maximum(h - separation, 0.0) * e_star / math.sqrt(dx * dy),
        norm=ops.normal.norm,
        scale=e_star / math.sqrt(dx * dy),
        tol=opts.tol,
        max_iter=opts.max_iterations(shape),
    )
    p = rn.x
    c = p > 0.0
    q = np.where(c, float(shear_strength), 0.0)
    u_x = ops.tangential(q)
    area = dx * dy
    return AdhesiveShearState(
        pressure=p,
        traction=q,
        contact=c,
        slip=tangential_displacement - u_x,
        gap=rn.gradient,
        separation=float(separation),
        tangential_displacement=float(tangential_displacement),
        normal_force=float(p.sum() * area),
        tangential_force=float(q.sum() * area),
        real_area=float(c.sum() * area),
        stable=True,
        success=rn.success,
        status=rn.status,
        message="sliding: " + rn.message,
        nit=1,
        cg_iterations=rn.nit,
        seconds=time.perf_counter() - t0,
    )


@dataclass
class ShearSweep:
    """A fixed-grip tangential sweep (:func:`tangential_sweep`), SI units.

    Attributes
    ----------
    preload : AdhesiveShearState
        The JKR-equilibrium state at delta_T = 0.
    states : list of AdhesiveShearState
        One per requested delta_T: stick states, then (after the jump, when tau_0 was given)
        sliding states.
    jump_index : int or None
        Index in ``states`` of the first step without a stick state; None if none.
    max_stick_displacement : float
        The last delta_T with a stick state (m).
    """

    preload: AdhesiveShearState
    states: list[AdhesiveShearState]
    jump_index: int | None
    max_stick_displacement: float

    def fold_displacement(self) -> float:
        """The BEM's delta_T^max (m): the start of the stick step with the steepest recession,
        the largest ``-d ln A / d ln delta_T`` (at the fold of E:max_disp_PC it is infinite).

        Past the fold the Pohrt-Popov criterion, which attaches only on penetration, lets the
        contact recede towards the Hertz contact over a few steps instead of jumping at once (at
        delta > 0 the stuck, nearly non-adhesive contact that is left keeps sticking until its
        tension is gone: ``jump_index``); the steepest recession marks the fold itself. NaN with
        fewer than two steps.
        """
        end = len(self.states) if self.jump_index is None else self.jump_index + 1
        seq = self.states[:end]
        best, where = -math.inf, math.nan
        for before, after in zip(seq[:-1], seq[1:], strict=True):
            t0, t1 = before.tangential_displacement, after.tangential_displacement
            if t0 <= 0 or t1 <= t0 or before.real_area <= 0:
                continue
            if after.real_area <= 0:
                slope = math.inf
            else:
                slope = -math.log(after.real_area / before.real_area) / math.log(t1 / t0)
            if slope > best:
                best, where = slope, t0
        return where

    @property
    def success(self) -> bool:
        """Every solve converged."""
        return self.preload.success and all(s.success for s in self.states)


def tangential_sweep(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    separation: float,
    tangential_displacements: np.ndarray,
    law: MixedModeLaw,
    *,
    preload_separation: float,
    shear_strength: float | None = None,
    poisson_ratio: float = 0.5,
    options: ShearOptions | None = None,
) -> ShearSweep:
    """Preload at d, then increase delta_T through ``tangential_displacements`` at fixed d.

    Parameters
    ----------
    heights, dx, dy, e_star, separation, law, poisson_ratio, options
        As :func:`adhesive_shear_solve`.
    tangential_displacements : array_like
        Increasing delta_T values (m), >= 0.
    preload_separation : float
        d' < d (m) of the 'load' half of Pohrt-Popov's load then unload: its overlap contact
        (:func:`overlap_contact`) must contain the JKR contact at d (for a sphere of radius R:
        ``d' = -(1.1 a_JKR)^2 / R``).
    shear_strength : float, optional
        tau_0 (Pa): after the jump the states are :func:`sliding_state`; without it the sweep
        stops at the jump.

    Returns
    -------
    ShearSweep
    """
    check_poisson(poisson_ratio)
    opts = options if options is not None else ShearOptions()
    h = np.asarray(heights, dtype=np.float64)
    d_t = np.asarray(tangential_displacements, dtype=np.float64).ravel()
    if d_t.size == 0 or np.any(~np.isfinite(d_t)) or np.any(d_t < 0) or np.any(np.diff(d_t) < 0):
        raise BemInputError(
            "tangential_displacements: expected finite, non-negative, non-decreasing values (m)"
        )
    if not preload_separation < separation:
        raise BemInputError(
            f"preload_separation: expected d' < d = {separation} m, got {preload_separation}"
        )
    ops = _operators(h.shape, dx, dy, e_star, opts)
    kw = {"options": opts, "operators": ops}
    state = adhesive_shear_solve(
        h,
        dx,
        dy,
        e_star,
        separation,
        0.0,
        law,
        contact=overlap_contact(h, preload_separation),
        collapse_fraction=1e-6,
        **kw,
    )
    preload, states, jump, last = state, [], None, 0.0
    for value in d_t:
        if jump is None:
            state = adhesive_shear_solve(
                h, dx, dy, e_star, separation, float(value), law, contact=state, **kw
            )
            if state.stable:
                last = float(value)
                states.append(state)
                continue
            jump = len(states)
            if shear_strength is None:
                states.append(state)
                break
        states.append(
            sliding_state(h, dx, dy, e_star, separation, float(value), shear_strength, **kw)
        )
    return ShearSweep(preload, states, jump, last)
