"""A rough surface under shear with the paper's mixed-mode law, in load control, junction by
junction (periodic or free domain).

The problem (nu = 1/2, SI units). The normal force F_z is held; the rigid flat moves along x by
delta_T in steps. Three kinds of element:

* **adhesive stick** (the set ``c``): bonded to the flat in both directions, ``u_z = h - d`` and
  ``u_x = delta_T - s`` (s the element's tangential reference), the normal traction of either
  sign, the tangential one unbounded; an element detaches when the mesh estimate of
  G_I + lambda G_II reaches w (:class:`asperity.bem.shear.mixed_mode.MixedModeLaw`,
  E:failure_locus);
* **sliding** (the set ``slide``, the footprints of junctions past their instability): the
  paper's status map, a sliding junction is non-adhesive (Signorini: p >= 0, gap >= 0,
  E:Hertz_theory) and carries the constant shear strength tau_0 on its contact (or Coulomb
  mu p);
* **free**: no traction; an element that penetrates attaches (Pohrt-Popov: adhesive, bonded
  where it stands), or joins the sliding set when it borders a sliding junction.

Load control: the separation d is the unknown that makes ``sum p dx dy = F_z`` (a secant on
d, each trial a bound-constrained conjugate-gradient solve warm-started from the last; p is
affine in d while the Signorini set holds, so the secant ends in one or two trials). In the
periodic domain d is measured from the mean surface displacement (the kernel's zero mode is 0,
as in :func:`asperity.bem.solve_contact`).

Junctions are the connected clusters of ``c`` at the start of each step
(:func:`asperity.bem.shear.rough.label_junctions`, merged across the periodic edges). A
junction passes its instability (E:max_disp_PC) when, with the active set settled, its
adhesive area has fallen below ``collapse_fraction`` of its area at the step's start, or it
has lost its tension (its largest mode-I release rate below
:data:`asperity.bem.shear.mixed_mode.ADHESION_LOST` w, having been above it at the start): exactly
the
tests of :func:`asperity.bem.shear.mixed_mode.adhesive_shear_solve` for one junction, applied to
each.
The junction's footprint, grown by ``slide_margin`` elements, then becomes sliding, for good.

Preload (the paper's JKR equilibrium before shear): Pohrt-Popov load then unload, by the normal
solver (:func:`asperity.bem.load_sweep` to ``preload_load_factor`` F_z and back to F_z; at
delta_T = 0 the mixed-mode criterion is Pohrt-Popov's). The loaded contact must contain the JKR
contact at F_z: where more than :data:`RIM_TOLERANCE` of the unloaded contact still lies on the
loaded contact's rim the factor is doubled (a warning where it cannot be: junctions of a few
elements keep their loaded footprint, and their preload depends on the path).

Limits: the edge law is mesh-dependent like Pohrt-Popov's (docs/bem_shear.md); quasi-static;
linear elasticity; loading along x only (q_y = 0).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from asperity.bem.elastic.tangential_influence import check_poisson
from asperity.bem.errors import BemInputError
from asperity.bem.normal.sweep import load_sweep
from asperity.bem.options import SolverOptions
from asperity.bem.result import ContactResult
from asperity.bem.shear.mixed_mode import ADHESION_LOST, MixedModeLaw
from asperity.bem.shear.rough import ShearCurve, label_junctions
from asperity.bem.shear.stick_slip import ShearOptions, TangentialOperator, box_conjugate_gradients

__all__ = ["RIM_TOLERANCE", "mixed_mode_shear_curve"]

#: The preload's loaded contact holds the JKR contact when the bonded elements left on
#: its rim are at most this fraction of the bonded area (junctions of a few elements may keep
#: their whole loaded footprint: their edge is the mesh's).
RIM_TOLERANCE = 0.02


def _shrink(mask: np.ndarray, periodic: bool) -> np.ndarray:
    """``mask`` less its rim (elements with a 4-neighbour outside; outside the grid counts as
    outside when not periodic)."""
    return (
        ~_grow(~mask, 1, periodic) if periodic else ~_grow(~np.pad(mask, 1), 1, False)[1:-1, 1:-1]
    )


def _grow(mask: np.ndarray, steps: int, periodic: bool) -> np.ndarray:
    """``mask`` grown by ``steps`` elements (4-connectivity), wrapping round if periodic."""
    out = mask.copy()
    for _ in range(steps):
        grown = out.copy()
        for axis in (0, 1):
            for shift in (1, -1):
                moved = np.roll(out, shift, axis=axis)
                if not periodic:
                    edge = [slice(None)] * 2
                    edge[axis] = 0 if shift == 1 else -1
                    moved[tuple(edge)] = False
                grown |= moved
        out = grown
    return out


class _LoadControlled:
    """The normal problem at fixed sets and fixed F_z: d by a secant, p by box CG."""

    def __init__(self, heights, op, dx, dy, e_star, force, opts, max_iter):
        self.h = heights
        self.op = op
        self.area = dx * dy
        self.scale = e_star / math.sqrt(dx * dy)
        self.force = force
        self.opts = opts
        self.max_iter = max_iter
        self.slope: float | None = None  # dF/dd (N/m), < 0
        self.cg = 0
        self.failed = ""

    def _at(self, d, mask, lower, p0):
        r = box_conjugate_gradients(
            self.op,
            self.h - d,
            mask,
            lower,
            np.full(mask.shape, np.inf),
            p0,
            norm=self.op.norm,
            scale=self.scale,
            tol=self.opts.tol,
            max_iter=self.max_iter,
        )
        self.cg += r.nit
        if r.status:
            self.failed = f"normal solve: {r.message}"
        return r.x, float(r.x.sum() * self.area) - self.force

    def solve(self, d, c, slide, p0, rel_tol):
        """p (Pa) and d (m) with ``sum p dx dy = F_z``; ``c`` adhesive, ``slide`` Signorini."""
        mask = c | slide
        if not mask.any():
            raise BemInputError(
                "normal_force: no element can carry it (the contact was lost under shear)"
            )
        lower = np.where(c, -np.inf, 0.0)
        if self.slope is None:
            # dF/dd of the bonded set: the load of a unit separation change (superposition)
            unit, _ = self._at(0.0, mask, np.full(mask.shape, -np.inf), np.zeros(mask.shape))
            zero, _ = self._at(1.0, mask, np.full(mask.shape, -np.inf), np.zeros(mask.shape))
            self.slope = float((zero - unit).sum() * self.area)
            if not self.slope < 0:
                self.slope = -self.force / max(float(np.ptp(self.h)), 1e-300)
        tol = rel_tol * abs(self.force)
        p, f = self._at(d, mask, lower, p0)
        d_prev, f_prev = None, None
        for _ in range(60):
            if abs(f) <= tol:
                break
            if d_prev is not None and f != f_prev:
                slope = (f - f_prev) / (d - d_prev)
                if slope < 0:
                    self.slope = slope
            d_prev, f_prev = d, f
            d = d - f / self.slope
            p, f = self._at(d, mask, lower, p)
        else:
            self.failed = f"load not reached: F error {f:.3g} N"
        return p, d


_DEPRECATED_KNOBS = (
    "preload_load_factor",
    "collapse_fraction",
    "slide_margin",
    "load_tolerance",
    "max_active_set",
)


@dataclass
class _State:
    """The contact state between steps (SI units): the sets, the tractions, the references."""

    c: np.ndarray  # adhesive stick elements
    slide: np.ndarray  # sliding-junction elements (Signorini, tau_0 or mu p)
    p: np.ndarray  # normal traction (Pa), tension < 0
    q: np.ndarray  # tangential traction (Pa)
    s: np.ndarray  # tangential reference (m): u_x = delta_T - s on c
    d: float  # separation (m)

    def copy(self) -> _State:
        """An independent copy (a step's transaction restores it when the step fails)."""
        return _State(
            self.c.copy(), self.slide.copy(), self.p.copy(), self.q.copy(), self.s.copy(), self.d
        )


@dataclass
class _Problem:
    """What does not change along the path: the surface, the law, the operators, the knobs."""

    h: np.ndarray
    dx: float
    dy: float
    e_star: float
    law: MixedModeLaw
    periodic: bool
    opts: ShearOptions
    shear_strength: float | None
    friction_coefficient: float | None
    op_n: TangentialOperator
    op_t: TangentialOperator
    normal: _LoadControlled

    @property
    def area(self) -> float:
        """Element area dx dy (m^2)."""
        return self.dx * self.dy

    @property
    def scale(self) -> float:
        """Pixel stiffness E* / sqrt(dx dy) (Pa/m)."""
        return self.e_star / math.sqrt(self.dx * self.dy)

    def mode_one(self, p: np.ndarray) -> np.ndarray:
        """Element mode-I release rate ``min(p, 0)^2 chi / (dx dy E*)`` (J/m^2)."""
        chi, _ = self.law.factors(self.dx, self.dy)
        pt = np.minimum(p, 0.0)
        return pt * pt * chi / (self.area * self.e_star)

    def sliding_traction(self, p: np.ndarray, slide_contact: np.ndarray) -> np.ndarray:
        """q (Pa) of the sliding contact: tau_0, or Coulomb mu p."""
        if self.shear_strength is not None:
            return np.where(slide_contact, float(self.shear_strength), 0.0)
        return np.where(slide_contact, float(self.friction_coefficient) * np.maximum(p, 0.0), 0.0)


@dataclass
class _Junctions:
    """The stick clusters at a step's start: labels, their areas (elements, zeroed once a
    junction has gone to sliding) and their largest mode-I release rates (J/m^2)."""

    labels: np.ndarray
    count: int
    area0: np.ndarray
    g0: np.ndarray
    gone: np.ndarray | None = None  # elements detached during the step

    def __post_init__(self) -> None:
        if self.gone is None:
            self.gone = np.zeros(self.labels.shape, dtype=bool)

    @property
    def ids(self) -> np.ndarray:
        """The labels 1..count."""
        return np.arange(1, self.count + 1)


@dataclass
class _StepLog:
    """What a step reports of its own iteration."""

    nit: int = 0
    status: int = 0
    message: str = "equilibrium"


def _check_curve_inputs(h, d_t, normal_force, shear_strength, friction_coefficient) -> None:
    """BemInputError naming the argument that is not as documented."""
    if h.ndim != 2 or not np.all(np.isfinite(h)):
        raise BemInputError(f"heights: expected a finite 2D array (m), got shape {h.shape}")
    if d_t.size == 0 or np.any(~np.isfinite(d_t)) or np.any(d_t < 0) or np.any(np.diff(d_t) < 0):
        raise BemInputError(
            "tangential_displacements: expected finite, non-negative, non-decreasing values (m)"
        )
    if not (math.isfinite(normal_force) and normal_force > 0):
        raise BemInputError(f"normal_force: expected a positive number (N), got {normal_force}")
    if (shear_strength is None) == (friction_coefficient is None):
        raise BemInputError(
            "give exactly one of shear_strength (tau_0, Pa) or friction_coefficient (mu), got "
            f"{shear_strength!r} and {friction_coefficient!r}"
        )
    for name, val in (
        ("shear_strength", shear_strength),
        ("friction_coefficient", friction_coefficient),
    ):
        if val is not None and not (math.isfinite(val) and val >= 0):
            raise BemInputError(f"{name}: expected a finite number >= 0, got {val}")


def _options_with_knobs(options: ShearOptions | None, knobs: dict) -> ShearOptions:
    """``options`` (default ShearOptions()) with the deprecated loose keywords given folded in
    (a DeprecationWarning names them); the knobs are checked by ShearOptions."""
    opts = options if options is not None else ShearOptions()
    given = {k: v for k, v in knobs.items() if v is not None}
    if given:
        warnings.warn(
            f"mixed_mode_shear_curve: the keywords {', '.join(sorted(given))} are deprecated; "
            "pass them in ShearOptions (options=ShearOptions(...))",
            DeprecationWarning,
            stacklevel=3,
        )
        opts = dataclasses.replace(opts, **given)
    return opts


def _problem(h, dx, dy, e_star, normal_force, law, periodic, opts, strength, mu) -> _Problem:
    """The operators and the load-controlled normal solver of the grid."""
    shape = h.shape
    kw = {"periodic": periodic, "fft_backend": opts.fft_backend, "threads": opts.threads}
    op_n = TangentialOperator(shape, dx, dy, e_star, normal=True, **kw)
    op_t = TangentialOperator(shape, dx, dy, e_star, **kw)
    normal = _LoadControlled(
        h, op_n, dx, dy, e_star, normal_force, opts, opts.max_iterations(shape)
    )
    return _Problem(h, dx, dy, e_star, law, periodic, opts, strength, mu, op_n, op_t, normal)


def _junctions_at_start(prob: _Problem, st: _State) -> _Junctions:
    """Label the stick clusters of ``st`` and record their areas and mode-I peaks."""
    labels, n_lab = label_junctions(st.c, periodic=prob.periodic)
    idx = np.arange(1, n_lab + 1)
    area0 = np.bincount(labels.ravel(), minlength=n_lab + 1)[1:]
    g0 = np.asarray(ndimage.maximum(prob.mode_one(st.p), labels, idx)) if n_lab else np.zeros(0)
    return _Junctions(labels, n_lab, area0, g0)


def _to_sliding(prob: _Problem, st: _State, junc: _Junctions, unstable: np.ndarray) -> None:
    """The junctions ``unstable`` (start-of-step labels) become sliding, for good (in place);
    their start areas are zeroed."""
    foot = np.isin(junc.labels, junc.ids[unstable])
    now_lab, _ = label_junctions(st.c, periodic=prob.periodic)
    foot |= np.isin(now_lab, np.unique(now_lab[foot & st.c]))
    st.slide = st.slide | (_grow(foot, prob.opts.slide_margin, prob.periodic) & ~(st.c & ~foot))
    st.c = st.c & ~st.slide
    st.p = np.where(st.c | st.slide, st.p, 0.0)
    st.q = np.where(st.c, st.q, 0.0)
    junc.area0 = np.where(unstable, 0, junc.area0)


def _equilibrium(
    prob: _Problem, st: _State, delta_t: float, log: _StepLog
) -> tuple[np.ndarray, np.ndarray]:
    """At fixed sets: p and d at F_z, then q on the stick set (in place). Returns the sliding
    contact (sliding elements in compression) and the stick part of q (Pa)."""
    opts = prob.opts
    st.p, st.d = prob.normal.solve(
        st.d, st.c, st.slide, st.p, max(opts.load_tolerance, 10.0 * opts.tol)
    )
    slide_contact = st.slide & (st.p > 0.0)
    q_slide = prob.sliding_traction(st.p, slide_contact)
    q_c = np.where(st.c, st.q, 0.0)
    if st.c.any():
        op_t = prob.op_t
        rhs = delta_t - st.s - (op_t(q_slide) if slide_contact.any() else 0.0)
        inf = np.full(st.c.shape, np.inf)
        rt = box_conjugate_gradients(
            op_t,
            rhs,
            st.c,
            -inf,
            inf,
            q_c,
            norm=op_t.norm,
            scale=prob.scale,
            tol=opts.tol,
            max_iter=opts.max_iterations(st.c.shape),
        )
        prob.normal.cg += rt.nit
        if rt.status:
            log.status, log.message = 1, f"tangential solve: {rt.message}"
        q_c = rt.x
    st.q = q_c + q_slide
    return slide_contact, q_c


def _unstable_junctions(prob: _Problem, st: _State, junc: _Junctions) -> np.ndarray:
    """Junctions past their instability with the sets settled (E:max_disp_PC): area below
    ``collapse_fraction`` of the start, or their tension lost (ADHESION_LOST)."""
    w = prob.law.work_of_adhesion
    now = np.bincount(junc.labels[st.c].ravel(), minlength=junc.count + 1)[1:]
    g_now = np.asarray(
        ndimage.maximum(np.where(st.c, prob.mode_one(st.p), 0.0), junc.labels, junc.ids)
    )
    lost = (junc.g0 >= ADHESION_LOST * w) & (g_now < ADHESION_LOST * w)
    return ((now < prob.opts.collapse_fraction * junc.area0) | lost) & (junc.area0 > 0)


def _collapsed_junctions(prob: _Problem, st: _State, junc: _Junctions) -> np.ndarray:
    """Junctions whose detachment cascades: area below ``collapse_fraction`` of the start."""
    now = np.bincount(junc.labels[st.c].ravel(), minlength=junc.count + 1)[1:]
    return (now < prob.opts.collapse_fraction * junc.area0) & (junc.area0 > 0)


def _change_sets(
    prob: _Problem,
    st: _State,
    delta_t: float,
    detach: np.ndarray,
    pen: np.ndarray,
    junc: _Junctions | None,
) -> None:
    """Detach ``detach``; collapsed junctions slide at once (before the load is put back on
    them); penetrating elements ``pen`` bond where they stand, or slide beside a sliding
    junction (in place)."""
    st.c = st.c & ~detach
    st.p = np.where(detach, 0.0, st.p)
    st.q = np.where(detach, 0.0, st.q)
    if junc is not None:
        collapsed = _collapsed_junctions(prob, st, junc)
        if collapsed.any():
            _to_sliding(prob, st, junc, collapsed)
    near = _grow(st.slide, 1, prob.periodic)
    if junc is not None and prob.opts.rebond_slides and delta_t > 0:
        junc.gone |= detach
        rebond = pen & ~near & junc.gone
        if rebond.any():
            # the junction's receding edge overshot into penetration: the cascade through its
            # fold (mixed_mode's docstring), no stick state; it slides
            through = np.isin(junc.ids, np.unique(junc.labels[rebond])) & (junc.area0 > 0)
            if through.any():
                _to_sliding(prob, st, junc, through)
                near = _grow(st.slide, 1, prob.periodic)
    to_bond = pen & ~near
    if to_bond.any():
        u_x = prob.op_t(st.q)
        st.s = np.where(to_bond, delta_t - u_x, st.s)
        st.c = st.c | to_bond
    st.slide = st.slide | (pen & near)


def _settle(prob: _Problem, st: _State, delta_t: float, check_junctions: bool) -> dict:
    """One step at delta_T (in place): the active set settled, the junctions checked for
    their instability; the step's row (forces N, areas m^2, counts, status)."""
    junc = _junctions_at_start(prob, st)
    checked = junc if check_junctions and junc.count else None
    log = _StepLog()
    cg0 = prob.normal.cg
    prob.normal.failed = ""
    w = prob.law.work_of_adhesion
    while True:
        log.nit += 1
        slide_contact, q_c = _equilibrium(prob, st, delta_t, log)
        rate = prob.law.release_rate(np.where(st.c, st.p, 0.0), q_c, prob.dx, prob.dy, prob.e_star)
        detach = st.c & (rate >= w)
        gap = prob.op_n(st.p) - prob.h + st.d
        pen = ~(st.c | slide_contact) & ~st.slide & (gap < 0.0)
        if not detach.any() and not pen.any():
            if checked is None:
                break
            unstable = _unstable_junctions(prob, st, checked)
            if not unstable.any():
                break
            _to_sliding(prob, st, checked, unstable)
            continue
        _change_sets(prob, st, delta_t, detach, pen, checked)
        if log.nit >= prob.opts.max_active_set:
            log.status, log.message = 1, "active set did not settle"
            break
    if prob.normal.failed:
        log.status, log.message = 1, prob.normal.failed
    return _step_row(prob, st, delta_t, log, prob.normal.cg - cg0)


def _step_row(prob: _Problem, st: _State, delta_t: float, log: _StepLog, cg: int) -> dict:
    """Close a step: references of the non-stick elements reset; the step's row."""
    slide_contact = st.slide & (st.p > 0.0)
    u_x = prob.op_t(st.q)
    st.s = np.where(st.c, st.s, delta_t - u_x)
    area = prob.area
    energy = 0.5 * area * float(np.sum(st.p * prob.op_n(st.p)) + np.sum(st.q * u_x))
    _, n_stick = label_junctions(st.c, periodic=prob.periodic)
    _, n_slide = label_junctions(slide_contact, periodic=prob.periodic)
    return {
        "force": float(st.q.sum() * area),
        "normal": float(st.p.sum() * area),
        "stick": float(st.c.sum() * area),
        "slip": float(slide_contact.sum() * area),
        "n_stick": n_stick,
        "n_slide": n_slide,
        "status": log.status,
        "message": log.message,
        "nit": log.nit,
        "cg": cg,
        "separation": st.d,
        "energy": energy,
    }


def _preload(prob: _Problem, normal_options: SolverOptions | None) -> tuple[_State, float]:
    """Pohrt-Popov load (to a multiple of F_z) then unload (to F_z) by the normal solver (at
    delta_T = 0 the mixed-mode criterion is Pohrt-Popov's); the factor is doubled while the
    loaded contact's rim holds more than RIM_TOLERANCE of the unloaded contact. Returns the
    state and that rim fraction (bonded elements on the loaded rim / bonded elements)."""
    h, periodic, opts = prob.h, prob.periodic, prob.opts
    force = prob.normal.force
    factor = opts.preload_load_factor
    while True:
        up, down = load_sweep(
            h,
            prob.dx,
            prob.dy,
            prob.e_star,
            [factor * force, force],
            work_of_adhesion=prob.law.work_of_adhesion,
            periodic=periodic,
            options=normal_options,
        )
        for r in (up, down):
            if not r.converged:
                raise BemInputError(f"preload did not converge: {r.message}")
        st = _bonded_state(down)
        # the loaded contact must hold the JKR contact: (almost) none of it on the loaded rim
        start = up.contact_mask
        held = int((st.c & (start & ~_shrink(start, periodic))).sum())
        rim = held / max(int(st.c.sum()), 1)
        if rim <= RIM_TOLERANCE:
            return st, rim
        # periodic: a bonded set near the whole map has no solution (the zero mode)
        if (
            up.contact_fraction >= (0.25 if periodic else 0.9)
            or factor >= 8 * opts.preload_load_factor
        ):
            warnings.warn(
                f"preload: {rim:.1%} of the unloaded contact lies on the rim "
                f"of the contact loaded to {factor:g} F_z (the junctions of a few elements keep "
                "their loaded footprint under Pohrt-Popov's criterion): the preload depends on "
                "the path there",
                stacklevel=3,
            )
            return st, rim
        factor *= 2.0


def _bonded_state(normal: ContactResult) -> _State:
    """The state before shear of a normal solution: its contact set bonded (adhesive stick),
    its pressure there (Pa; a Maugis-Dugdale law's cohesive tension outside the contact is
    dropped: the mixed-mode law has no cohesive zone), its separation d (m); no shear yet."""
    zeros = np.zeros(normal.contact_mask.shape)
    return _State(
        normal.contact_mask.copy(),
        np.zeros(zeros.shape, dtype=bool),
        np.where(normal.contact_mask, normal.pressure, 0.0),
        zeros,
        zeros.copy(),
        float(normal.separation),
    )


def _given_preload(prob: _Problem, initial: ContactResult) -> tuple[_State, float]:
    """The caller's normal state at F_z on this grid as the state before shear (a monotone
    loading path: no loaded rim, fraction 0); a BemInputError where its grid or load differ."""
    if initial.contact_mask.shape != prob.h.shape:
        raise BemInputError(
            f"initial: expected a normal solution on the {prob.h.shape} grid of heights, got "
            f"{initial.contact_mask.shape}"
        )
    force = prob.normal.force
    if not abs(float(initial.normal_force) - force) <= 1e-3 * abs(force):
        raise BemInputError(
            f"initial: expected a normal solution at F_z = {force:.6g} N, got "
            f"{float(initial.normal_force):.6g} N"
        )
    if not initial.contact_mask.any():
        raise BemInputError("initial: the normal solution has no contact to shear")
    return _bonded_state(initial), 0.0


def _restore(prob: _Problem, st: _State, saved: _State, slope: float | None) -> None:
    """Put ``st`` (in place) and the load controller's slope back as they were."""
    st.c, st.slide, st.p, st.q, st.s, st.d = (
        saved.c.copy(),
        saved.slide.copy(),
        saved.p.copy(),
        saved.q.copy(),
        saved.s.copy(),
        saved.d,
    )
    prob.normal.slope = slope


def _transactional_step(prob: _Problem, st: _State, start: float, end: float) -> dict:
    """The step from delta_T = ``start`` to ``end`` (m) as a transaction: solved at once; if it
    fails (status != 0) the state is put back as it was and the step is retried as 2, 4, ...
    equal sub-steps, at most ``2**max_step_halvings``. The row is the last sub-step's, with the
    iterations of every attempt summed and ``substeps`` the count that was kept; where even the
    finest retry fails its state is kept and the row says so (status 1, its message, and
    "after n sub-steps")."""
    saved, slope = st.copy(), prob.normal.slope
    nit = cg = 0
    for halvings in range(prob.opts.max_step_halvings + 1):
        if halvings:
            _restore(prob, st, saved, slope)
        n = 2**halvings
        for k in range(1, n + 1):
            value = end if k == n else start + (end - start) * k / n
            row = _settle(prob, st, value, check_junctions=True)
            nit, cg = nit + row["nit"], cg + row["cg"]
            if row["status"]:
                break
        if not row["status"]:
            break
    if row["status"] and n > 1:
        row["message"] = f"{row['message']} (after {n} sub-steps)"
    row.update(nit=nit, cg=cg, substeps=n)
    return row


def _curve(
    d_t: np.ndarray, rows: list, normal_seconds: float, st: _State, rim: float
) -> ShearCurve:
    """The ShearCurve of the step rows ``(row, seconds)``."""

    def col(key: str, dtype=float) -> np.ndarray:
        return np.array([r[key] for r, _ in rows], dtype=dtype)

    stick = col("stick")
    slip = col("slip")
    n_stick = col("n_stick", int)
    n_slide = col("n_slide", int)
    return ShearCurve(
        tangential_displacement=d_t[: len(rows)].copy(),
        tangential_force=col("force"),
        normal_force=col("normal"),
        real_area=stick + slip,
        stick_area=stick,
        slip_area=slip,
        junctions=n_stick + n_slide,
        sliding_junctions=n_slide,
        sliding=n_stick == 0,
        converged=col("status", int) == 0,
        nit=col("nit", int),
        convolutions=col("cg", int),
        seconds=np.array([t for _, t in rows]),
        normal_seconds=normal_seconds,
        final_traction=st.q.copy(),
        substeps=col("substeps", int),
        separation=col("separation"),
        elastic_energy=col("energy"),
        preload_rim_fraction=rim,
    )


def mixed_mode_shear_curve(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_force: float,
    tangential_displacements: np.ndarray,
    law: MixedModeLaw,
    *,
    shear_strength: float | None = None,
    friction_coefficient: float | None = None,
    periodic: bool = True,
    poisson_ratio: float = 0.5,
    normal_options: SolverOptions | None = None,
    options: ShearOptions | None = None,
    stop_when_sliding: bool = False,
    initial: ContactResult | None = None,
    preload_load_factor: float | None = None,
    collapse_fraction: float | None = None,
    slide_margin: int | None = None,
    load_tolerance: float | None = None,
    max_active_set: int | None = None,
) -> ShearCurve:
    """Load-controlled shear curve of a rough surface with the mixed-mode law (module docstring).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights h (m), larger = closer to the flat.
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa), nu = 1/2.
    normal_force : float
        F_z (N) > 0, held during shear.
    tangential_displacements : array_like
        delta_T values (m), non-negative and non-decreasing (the law is irreversible: a path).
    law : MixedModeLaw
        w (J/m^2), lambda and chi_T (E:failure_locus on the mesh).
    shear_strength, friction_coefficient : float, optional
        Exactly one: the shear traction of a sliding junction, tau_0 (Pa, the paper's law) on
        its contact, or Coulomb mu p.
    periodic : bool
        Periodic domain (default) or free.
    poisson_ratio : float
        Must be 0.5.
    normal_options : SolverOptions, optional
        Options of the non-adhesive 'load' solve of the preload.
    options : ShearOptions, optional
        Tolerance and FFT backend of the conjugate-gradient solves, and the curve's knobs
        (:class:`asperity.bem.shear.stick_slip.ShearOptions`): ``preload_load_factor`` (the
        preload loads to this multiple of F_z, then unloads; doubled while more than
        :data:`RIM_TOLERANCE` of the unloaded contact lies on the loaded rim, at most 3 times
        and not past a loaded contact of a quarter of the map, periodic, or 90 %, free: then a
        warning says how much of the preload is on that rim), ``collapse_fraction``,
        ``slide_margin``, ``load_tolerance``, ``max_active_set``.
    stop_when_sliding : bool
        Stop after the first step in which every junction slides.
    initial : ContactResult, optional
        The normal state before shear, at ``normal_force`` on this grid: its contact set is
        bonded and settled under the mixed-mode law at delta_T = 0 (its pressure, Pa, and
        separation, m, the start). For example the BEM reference's adhesive solve at F_z
        (the Maugis-Dugdale loading branch, :func:`asperity.bem.solve_contact` with
        ``adhesion="maugis"``), so that the shear starts from the state the reference and the
        model calibrated on it describe. None: the Pohrt-Popov preload (``options``).
    preload_load_factor, collapse_fraction, slide_margin, load_tolerance, max_active_set
        Deprecated (a DeprecationWarning): the same knobs given loose; they override
        ``options``.

    Returns
    -------
    ShearCurve
        Index 0 of the arrays is the first requested delta_T; ``real_area`` is the adhesive
        stick area plus the sliding contact area (it drops as junctions shrink and slide);
        ``stick_area`` the adhesive area; ``slip_area`` the sliding contact; ``junctions`` the
        stick clusters plus the sliding ones in contact; ``converged`` per step; ``nit`` the
        active-set iterations; ``convolutions`` the conjugate-gradient iterations;
        ``normal_seconds`` the preload's wall time (s); ``substeps`` the sub-steps each step
        was solved in (a failed step is undone and retried in 2, 4, ... sub-steps, up to
        ``2**options.max_step_halvings``; a step that fails even then is kept, not converged).
    """
    check_poisson(poisson_ratio)
    knobs = dict(
        zip(
            _DEPRECATED_KNOBS,
            (preload_load_factor, collapse_fraction, slide_margin, load_tolerance, max_active_set),
            strict=True,
        )
    )
    opts = _options_with_knobs(options, knobs)
    h = np.asarray(heights, dtype=np.float64)
    d_t = np.asarray(tangential_displacements, dtype=np.float64).ravel()
    _check_curve_inputs(h, d_t, normal_force, shear_strength, friction_coefficient)
    prob = _problem(
        h, dx, dy, e_star, normal_force, law, periodic, opts, shear_strength, friction_coefficient
    )
    t0 = time.perf_counter()
    st, rim = _preload(prob, normal_options) if initial is None else _given_preload(prob, initial)
    pre = _settle(prob, st, 0.0, check_junctions=False)
    if pre["status"]:
        raise BemInputError(f"preload did not settle under the mixed-mode law: {pre['message']}")
    normal_seconds = time.perf_counter() - t0
    rows = []
    previous = 0.0
    for value in d_t:
        t1 = time.perf_counter()
        r = _transactional_step(prob, st, previous, float(value))
        rows.append((r, time.perf_counter() - t1))
        previous = float(value)
        if stop_when_sliding and r["n_stick"] == 0:
            break
    return _curve(d_t, rows, normal_seconds, st, rim)
