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

import math
import time
import warnings

import numpy as np
from scipy import ndimage

from asperity.bem.elastic.tangential_influence import check_poisson
from asperity.bem.errors import BemInputError
from asperity.bem.normal.sweep import load_sweep
from asperity.bem.options import SolverOptions
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
    preload_load_factor: float = 4.0,
    collapse_fraction: float = 0.5,
    slide_margin: int = 2,
    load_tolerance: float = 1e-8,
    max_active_set: int = 500,
    normal_options: SolverOptions | None = None,
    options: ShearOptions | None = None,
    stop_when_sliding: bool = False,
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
    preload_load_factor : float
        > 1: the preload loads to this multiple of F_z, then unloads to F_z (Pohrt-Popov,
        :func:`asperity.bem.load_sweep`); doubled while more than :data:`RIM_TOLERANCE` of the
        unloaded contact still lies on the rim of the loaded one (at most 3 times, and not
        past a loaded contact of a quarter of the map, periodic, or 90 %, free: then a warning
        says how much of the preload is on that rim).
    collapse_fraction : float
        In (0, 1): a junction whose area falls below this fraction of its area at the step's
        start has passed its instability.
    slide_margin : int
        >= 0: elements added round a sliding junction's footprint (its Hertz contact may
        spread when the load redistributes).
    load_tolerance : float
        Relative error allowed on F_z (at least 10 times ``options.tol``: the load cannot be
        closer than the conjugate-gradient solves).
    max_active_set : int
        Cap on active-set iterations per step.
    normal_options : SolverOptions, optional
        Options of the non-adhesive 'load' solve of the preload.
    options : ShearOptions, optional
        Tolerance and FFT backend of the conjugate-gradient solves.
    stop_when_sliding : bool
        Stop after the first step in which every junction slides.

    Returns
    -------
    ShearCurve
        Index 0 of the arrays is the first requested delta_T; ``real_area`` is the adhesive
        stick area plus the sliding contact area (it drops as junctions shrink and slide);
        ``stick_area`` the adhesive area; ``slip_area`` the sliding contact; ``junctions`` the
        stick clusters plus the sliding ones in contact; ``converged`` per step; ``nit`` the
        active-set iterations; ``convolutions`` the conjugate-gradient iterations;
        ``normal_seconds`` the preload's wall time (s).
    """
    check_poisson(poisson_ratio)
    opts = options if options is not None else ShearOptions()
    h = np.asarray(heights, dtype=np.float64)
    if h.ndim != 2 or not np.all(np.isfinite(h)):
        raise BemInputError(f"heights: expected a finite 2D array (m), got shape {h.shape}")
    d_t = np.asarray(tangential_displacements, dtype=np.float64).ravel()
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
    if not (preload_load_factor > 1 and math.isfinite(preload_load_factor)):
        raise BemInputError(
            f"preload_load_factor: expected a number > 1, got {preload_load_factor}"
        )
    if not (0.0 < collapse_fraction < 1.0):
        raise BemInputError(f"collapse_fraction: expected in (0, 1), got {collapse_fraction}")
    if not (isinstance(slide_margin, int) and slide_margin >= 0):
        raise BemInputError(f"slide_margin: expected an integer >= 0, got {slide_margin!r}")
    shape = h.shape
    area = dx * dy
    w = law.work_of_adhesion
    chi, _ = law.factors(dx, dy)
    kw = {"periodic": periodic, "fft_backend": opts.fft_backend, "threads": opts.threads}
    op_n = TangentialOperator(shape, dx, dy, e_star, normal=True, **kw)
    op_t = TangentialOperator(shape, dx, dy, e_star, **kw)
    max_iter = opts.max_iterations(shape)
    scale = e_star / math.sqrt(dx * dy)
    normal = _LoadControlled(h, op_n, dx, dy, e_star, normal_force, opts, max_iter)
    inf = np.full(shape, np.inf)

    def mode_one(p: np.ndarray) -> np.ndarray:
        pt = np.minimum(p, 0.0)
        return pt * pt * chi / (area * e_star)

    def sliding_traction(p: np.ndarray, slide_contact: np.ndarray) -> np.ndarray:
        if shear_strength is not None:
            return np.where(slide_contact, float(shear_strength), 0.0)
        return np.where(slide_contact, float(friction_coefficient) * np.maximum(p, 0.0), 0.0)

    t0 = time.perf_counter()
    state: dict = {}

    def settle(delta_t: float, check_junctions: bool) -> dict:
        """One step: the active set at delta_T, junctions checked for instability."""
        c, slide, s = state["c"], state["slide"], state["s"]
        p, q, d = state["p"], state["q"], state["d"]
        labels, n_lab = label_junctions(c, periodic=periodic)
        idx = np.arange(1, n_lab + 1)
        area0 = np.bincount(labels.ravel(), minlength=n_lab + 1)[1:]
        g0 = np.asarray(ndimage.maximum(mode_one(p), labels, idx)) if n_lab else np.zeros(0)
        nit, status, message = 0, 0, "equilibrium"
        cg0 = normal.cg

        def to_sliding(unstable, c, slide, p, q):
            """The junctions ``unstable`` (start-of-step labels) become sliding, for good."""
            foot = np.isin(labels, idx[unstable])
            now_lab, _ = label_junctions(c, periodic=periodic)
            foot |= np.isin(now_lab, np.unique(now_lab[foot & c]))
            slide = slide | (_grow(foot, slide_margin, periodic) & ~(c & ~foot))
            c = c & ~slide
            return c, slide, np.where(c | slide, p, 0.0), np.where(c, q, 0.0)

        normal.failed = ""
        while True:
            nit += 1
            p, d = normal.solve(d, c, slide, p, max(load_tolerance, 10.0 * opts.tol))
            slide_contact = slide & (p > 0.0)
            q_slide = sliding_traction(p, slide_contact)
            q_c = np.where(c, q, 0.0)
            if c.any():
                rhs = delta_t - s - (op_t(q_slide) if slide_contact.any() else 0.0)
                rt = box_conjugate_gradients(
                    op_t,
                    rhs,
                    c,
                    -inf,
                    inf,
                    q_c,
                    norm=op_t.norm,
                    scale=scale,
                    tol=opts.tol,
                    max_iter=max_iter,
                )
                normal.cg += rt.nit
                if rt.status:
                    status, message = 1, f"tangential solve: {rt.message}"
                q_c = rt.x
            q = q_c + q_slide
            rate = law.release_rate(np.where(c, p, 0.0), q_c, dx, dy, e_star)
            detach = c & (rate >= w)
            gap = op_n(p) - h + d
            touching = c | slide_contact
            pen = ~touching & ~slide & (gap < 0.0)
            near = _grow(slide, 1, periodic)
            to_slide = pen & near
            to_bond = pen & ~near
            if not detach.any() and not pen.any():
                if not check_junctions or n_lab == 0:
                    break
                now = np.bincount(labels[c].ravel(), minlength=n_lab + 1)[1:]
                g_now = np.asarray(ndimage.maximum(np.where(c, mode_one(p), 0.0), labels, idx))
                lost = (g0 >= ADHESION_LOST * w) & (g_now < ADHESION_LOST * w)
                unstable = ((now < collapse_fraction * area0) | lost) & (area0 > 0)
                if not unstable.any():
                    break
                c, slide, p, q = to_sliding(unstable, c, slide, p, q)
                area0 = np.where(unstable, 0, area0)
                continue
            c = c & ~detach
            p = np.where(detach, 0.0, p)
            q = np.where(detach, 0.0, q)
            if check_junctions and n_lab:
                # a junction whose detachment cascades (area below collapse_fraction of its start)
                # has passed its fold: it slides at once, before the load is put back on it
                now = np.bincount(labels[c].ravel(), minlength=n_lab + 1)[1:]
                collapsed = (now < collapse_fraction * area0) & (area0 > 0)
                if collapsed.any():
                    c, slide, p, q = to_sliding(collapsed, c, slide, p, q)
                    area0 = np.where(collapsed, 0, area0)
                    near = _grow(slide, 1, periodic)
                    to_slide = pen & near
                    to_bond = pen & ~near
            if to_bond.any():
                u_x = op_t(q)
                s = np.where(to_bond, delta_t - u_x, s)
                c = c | to_bond
            slide = slide | to_slide
            if nit >= max_active_set:
                status, message = 1, "active set did not settle"
                break
        if normal.failed:
            status, message = 1, normal.failed
        slide_contact = slide & (p > 0.0)
        u_x = op_t(q)
        s = np.where(c, s, delta_t - u_x)
        state.update(c=c, slide=slide, p=p, q=q, s=s, d=d)
        _, n_stick = label_junctions(c, periodic=periodic)
        _, n_slide = label_junctions(slide_contact, periodic=periodic)
        return {
            "force": float(q.sum() * area),
            "normal": float(p.sum() * area),
            "stick": float(c.sum() * area),
            "slip": float(slide_contact.sum() * area),
            "n_stick": n_stick,
            "n_slide": n_slide,
            "status": status,
            "message": message,
            "nit": nit,
            "cg": normal.cg - cg0,
        }

    factor = preload_load_factor
    while True:
        # Pohrt-Popov load (to factor F_z) then unload (to F_z), by the normal solver: at
        # delta_T = 0 the mixed-mode criterion is Pohrt-Popov's
        up, down = load_sweep(
            h,
            dx,
            dy,
            e_star,
            [factor * normal_force, normal_force],
            work_of_adhesion=w,
            periodic=periodic,
            options=normal_options,
        )
        for r in (up, down):
            if not r.converged:
                raise BemInputError(f"preload did not converge: {r.message}")
        start = up.contact_mask
        state.update(
            c=down.contact_mask.copy(),
            slide=np.zeros(shape, dtype=bool),
            p=np.where(down.contact_mask, down.pressure, 0.0),
            q=np.zeros(shape),
            s=np.zeros(shape),
            d=float(down.separation),
        )
        # the loaded contact must hold the JKR contact: (almost) none of it on the loaded rim
        rim = start & ~_shrink(start, periodic)
        held = int((state["c"] & rim).sum())
        if held <= RIM_TOLERANCE * max(int(state["c"].sum()), 1):
            break
        # periodic: a bonded set near the whole map has no solution (the zero mode)
        if up.contact_fraction >= (0.25 if periodic else 0.9) or factor >= 8 * preload_load_factor:
            warnings.warn(
                f"preload: {held / state['c'].sum():.1%} of the unloaded contact lies on the rim "
                f"of the contact loaded to {factor:g} F_z (the junctions of a few elements keep "
                "their loaded footprint under Pohrt-Popov's criterion): the preload depends on "
                "the path there",
                stacklevel=2,
            )
            break
        factor *= 2.0
    pre = settle(0.0, check_junctions=False)
    if pre["status"]:
        raise BemInputError(f"preload did not settle under the mixed-mode law: {pre['message']}")
    normal_seconds = time.perf_counter() - t0
    rows = []
    for value in d_t:
        t1 = time.perf_counter()
        r = settle(float(value), check_junctions=True)
        rows.append((r, time.perf_counter() - t1))
        if stop_when_sliding and r["n_stick"] == 0:
            break

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
        final_traction=state["q"].copy(),
    )
