"""The exact case of issue 25: a sparse periodic array of identical spherical caps under load
control, BEM with the mixed-mode law (chi_T = chi, the paper's PC law) against the
independent-asperity model summed over the caps (E:PC_indent, E:PC_P, E:PC_T at the common
load F_z / N; past the load-control fold, E:Hertz_theory with tau_0).

The comparison is made in force terms (the tangential force T per cap, the contact radius at
given T, the static peak, the sliding force, the area drop A(peak)/A(0)): PC's law is a relation
between a, P and T, independent of where delta_T is measured from, while the periodic BEM
measures delta_T from the mean surface displacement, which for cells a few contact radii wide
adds the images' elastic interaction (the initial stiffness is 1.9 times 4/3 E* a at a 5 a cell;
docs/bem_shear.md).

Refinement (lambda = 0.2, delta~ = 3, 2 x 2 caps, 5 a cells, 121 steps): peak T +6.0 % at 12 and
+3.0 % at 20 elements per JKR radius; a(T) within 6.8 % and 4.2 %; sliding T +1.0 % and +0.6 %;
area drop 0.60 and 0.68 against the model's 0.64 (the area falls steeply just before the peak,
so it is sampled coarsely by the steps).
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from asperity.bem import solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.shear.mixed_mode import MixedModeLaw
from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
from asperity.statmodel import papangelo_ciavarella as pc
from asperity.statmodel.jkr import jkr_contact_radius, jkr_normal_load
from asperity.statmodel.maugis_dugdale import MaugisDugdale

R, E_STAR, W = 1.0, 1.0, 1e-6
XI = (E_STAR * R / W) ** (1 / 3)
DELTA = 3.0 * R / XI**2
A_JKR = float(jkr_contact_radius(DELTA, R, W, E_STAR))
P_CAP = float(jkr_normal_load(DELTA, R, W, E_STAR))
TAU0 = 1e-3 * E_STAR
LAM = 0.2
CAPS = 2  # per side


def _model_curve(lam: float) -> np.ndarray:
    """(delta_T, a, T) of one cap at the fixed load P_CAP up to the load-control fold (the
    independent-asperity model: every cap carries F_z / N)."""
    args = (R, W, E_STAR, lam)
    d_end = 3.0 * float(pc.pc_max_tangential_displacement(DELTA, *args))
    rows = []
    for dt in np.linspace(0.0, d_end, 1201):
        d_min = float(pc.pc_min_indentation(dt, *args))
        low = d_min + abs(d_min) * 1e-9
        best = minimize_scalar(
            lambda d, dt=dt: float(pc.pc_normal_load(d, dt, *args)),
            bounds=(low, 10 * DELTA),
            method="bounded",
        )
        if best.fun > P_CAP:  # no stick state carries the load: the cap slides
            break
        d = brentq(lambda d, dt=dt: pc.pc_normal_load(d, dt, *args) - P_CAP, best.x, 20 * DELTA)
        a = float(pc.pc_contact_radius(d, dt, *args))
        rows.append((dt, a, float(pc.pc_tangential_load(d, dt, *args))))
    return np.array(rows)


def _array_curve(n_per: int, steps: int):
    dx = A_JKR / n_per
    n1 = int(round(5 * A_JKR / dx))
    x = (np.arange(n1) - (n1 - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    h = np.tile(-(xx**2 + yy**2) / (2 * R), (CAPS, CAPS))
    model = _model_curve(LAM)
    d_t = np.linspace(0.0, 4.8 * model[-1, 0], steps)
    curve = mixed_mode_shear_curve(
        h, dx, dx, E_STAR, CAPS**2 * P_CAP, d_t, MixedModeLaw(W, LAM), shear_strength=TAU0
    )
    return curve, model


def _compare(curve, model):
    n = CAPS**2
    t = curve.tangential_force / n
    a = np.sqrt(curve.real_area / n / math.pi)
    peak = int(np.argmax(np.where(curve.stick_area > 0, t, -np.inf)))
    i_pk = int(np.argmax(model[:, 2]))
    rise = model[: i_pk + 1]
    a_err = [
        a[i] / np.interp(t[i], rise[:, 2], rise[:, 1]) - 1
        for i in range(1, peak + 1)
        if t[i] < rise[-1, 2]
    ]
    a_hertz = (3 * P_CAP * R / (4 * E_STAR)) ** (1 / 3)
    return {
        "preload": a[0] / model[0, 1] - 1,
        "peak": t[peak] / model[i_pk, 2] - 1,
        "a_of_t": float(np.max(np.abs(a_err))),
        "sliding": t[-1] / (TAU0 * math.pi * a_hertz**2) - 1,
        "drop": (a[peak] / a[0]) ** 2 - (model[i_pk, 1] / model[0, 1]) ** 2,
        "load": float(np.max(np.abs(curve.normal_force / (n * P_CAP) - 1))),
    }


def test_sphere_array_fast():
    """12 elements per radius, 41 steps: the model within the mesh error of this resolution."""
    curve, model = _array_curve(12, 41)
    assert curve.success
    assert curve.sliding[-1] and not curve.sliding[0]
    assert np.all(curve.junctions[curve.stick_area > 0] == CAPS**2)
    err = _compare(curve, model)
    assert err["load"] < 1e-6
    assert abs(err["preload"]) < 0.03
    assert abs(err["peak"]) < 0.08
    assert abs(err["sliding"]) < 0.02


@pytest.mark.slow
def test_sphere_array_refined():
    """20 elements per radius, 121 steps: within 4 % (peak), 5 % (a at given T), 1 % (sliding)."""
    curve, model = _array_curve(20, 121)
    assert curve.success
    err = _compare(curve, model)
    assert abs(err["preload"]) < 0.015
    assert abs(err["peak"]) < 0.04
    assert err["a_of_t"] < 0.05
    assert abs(err["sliding"]) < 0.01
    assert abs(err["drop"]) < 0.06


def _two_height_model(z: np.ndarray, d_t: np.ndarray) -> np.ndarray:
    """(delta_T, T, A_r, caps sliding) of the independent-asperity model for caps at heights z:
    a common approach holds sum P_i = F_z; a cap slides (for good) where its indentation falls
    below delta_PC^min(delta_T) (the status map), then carries Hertz's load and tau_0 pi R delta."""
    args = (R, W, E_STAR, LAM)
    force = z.size * P_CAP
    sliding = np.zeros(z.size, dtype=bool)
    rows = []
    for dt in d_t:
        d_min = float(pc.pc_min_indentation(dt, *args))
        p_min = float(pc.pc_normal_load(d_min, dt, *args))
        while True:

            def total(d0, dt=dt, sliding=sliding, d_min=d_min, p_min=p_min):
                out = 0.0
                for zi, slid in zip(z, sliding, strict=True):
                    di = d0 + zi
                    if slid:
                        out += 4 / 3 * E_STAR * math.sqrt(R) * max(di, 0.0) ** 1.5
                    else:
                        out += float(pc.pc_normal_load(di, dt, *args)) if di >= d_min else p_min
                return out - force

            d0 = brentq(total, -3 * DELTA, 5 * DELTA)
            new = ~sliding & (d0 + z < d_min)
            if not new.any():
                break
            sliding = sliding | new
        t = a2 = 0.0
        for zi, slid in zip(z, sliding, strict=True):
            di = d0 + zi
            if slid:
                t += TAU0 * math.pi * R * max(di, 0.0)
                a2 += R * max(di, 0.0)
            else:
                t += float(pc.pc_tangential_load(di, dt, *args))
                a2 += float(pc.pc_contact_radius(di, dt, *args)) ** 2
        rows.append((dt, t, math.pi * a2, int(sliding.sum())))
        if sliding.all():
            break
    return np.array(rows)


@pytest.mark.slow
def test_sphere_array_two_heights():
    """Two caps 0.3 delta higher than the other two: the load shifts as caps slide, in the
    model's order (the low pair first, then the high one); static peak within 4 % and the
    preload area within 8 % at 12 elements per radius (measured: +3.0 % and +6.9 %; at 20:
    +2.0 % and +2.0 %). The sliding force differs by +4.2 % (12) and +4.5 % (20): not a
    discretisation error but the caps' elastic interaction, which shifts load between unequal
    caps (identical caps share it equally whatever the interaction) and which the
    independent-asperity model leaves out."""
    z = np.array([0.3, 0.0, 0.0, 0.3]) * DELTA
    d_max = float(pc.pc_max_tangential_displacement(DELTA, R, W, E_STAR, LAM))
    model = _two_height_model(z, np.linspace(0.0, 6 * d_max, 4001))
    dx = A_JKR / 12
    n1 = int(round(5 * A_JKR / dx))
    x = (np.arange(n1) - (n1 - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    cap = -(xx**2 + yy**2) / (2 * R)
    h = np.block([[cap + z[0], cap + z[1]], [cap + z[2], cap + z[3]]])
    curve = mixed_mode_shear_curve(
        h,
        dx,
        dx,
        E_STAR,
        4 * P_CAP,
        np.linspace(0.0, 2.5 * model[-1, 0], 61),
        MixedModeLaw(W, LAM),
        shear_strength=TAU0,
    )
    assert curve.success and curve.sliding[-1]
    counts = np.unique(curve.sliding_junctions)
    assert list(counts) == list(np.unique(model[:, 3])) == [0, 2, 4]
    peak = int(np.argmax(np.where(curve.stick_area > 0, curve.tangential_force, -np.inf)))
    i_pk = int(np.argmax(model[:, 1]))
    assert curve.real_area[0] == pytest.approx(model[0, 2], rel=0.08)
    assert curve.tangential_force[peak] == pytest.approx(model[i_pk, 1], rel=0.04)
    assert curve.tangential_force[-1] == pytest.approx(model[-1, 1], rel=0.06)


@pytest.mark.slow
def test_free_single_cap_follows_pc_in_delta_t():
    """One cap in the free domain (delta_T from the far field, no images): T(delta_T) and
    a(delta_T) follow the fixed-load PC curve within 7 % up to 0.95 of its fold at 12 elements
    per radius (measured 5.4 % and 4.5 %, the largest near the fold; 1-2 % below half of it);
    it slides between 1.0 and 1.05 of the fold, then T = tau_0 pi a_H^2 within 2 % (measured
    +1.0 %)."""
    model = _model_curve(LAM)
    fold = model[-1, 0]
    dx = A_JKR / 12
    n = int(3.5 * 12) + 2
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    d_t = np.linspace(0.0, 1.3 * fold, 27)
    curve = mixed_mode_shear_curve(
        -(xx**2 + yy**2) / (2 * R),
        dx,
        dx,
        E_STAR,
        P_CAP,
        d_t,
        MixedModeLaw(W, LAM),
        shear_strength=TAU0,
        periodic=False,
    )
    assert curve.success
    stick = d_t <= 0.95 * fold
    t_model = np.interp(d_t[stick], model[:, 0], model[:, 2])
    a_model = np.interp(d_t[stick], model[:, 0], model[:, 1])
    a_bem = np.sqrt(curve.real_area[stick] / math.pi)
    t_err = np.abs(curve.tangential_force[stick][1:] / t_model[1:] - 1)
    a_err = np.abs(a_bem / a_model - 1)
    assert t_err.max() < 0.07 and a_err.max() < 0.07, (t_err.max(), a_err.max())
    assert not curve.sliding[d_t <= fold].any() and curve.sliding[d_t >= 1.05 * fold].all()
    a_hertz = (3 * P_CAP * R / (4 * E_STAR)) ** (1 / 3)
    assert curve.tangential_force[-1] == pytest.approx(TAU0 * math.pi * a_hertz**2, rel=0.02)


def test_periodic_delta_t_is_measured_from_the_mean_surface():
    """The periodic kernels' zero mode is 0: delta_T is measured from the mean surface
    displacement, so a full-stick disc in a cell of a few radii is stiffer than 4/3 E* a (its
    images), tending to it as the cell grows (1.31 and 1.13 at cells of 10 a and 20 a); the free
    domain gives 4/3 E* a within 1 %. Why the sphere-array tests compare force-based numbers."""
    from asperity.bem.shear.stick_slip import solve_tangential

    ratios = {}
    for periodic, cell in ((True, 10), (True, 20), (False, 10)):
        dx = 1.0 / 12
        n = int(cell * 12)
        x = (np.arange(n) - (n - 1) / 2) * dx
        xx, yy = np.meshgrid(x, x, indexing="ij")
        disc = xx**2 + yy**2 <= 1.0
        r = solve_tangential(disc, None, dx, dx, 1.0, 1e-3, periodic=periodic)
        a = math.sqrt(disc.sum() * dx * dx / math.pi)
        ratios[(periodic, cell)] = r.tangential_force / (4 / 3 * a * 1e-3)
    assert ratios[(True, 10)] == pytest.approx(1.31, abs=0.02)
    assert ratios[(True, 20)] == pytest.approx(1.13, abs=0.02)
    assert ratios[(False, 10)] == pytest.approx(1.0, abs=0.01)


def _maugis_loading_state(h, dx, force, maugis_parameter):
    """The Maugis-Dugdale loading branch of the caps at ``force`` (N), as the BEM reference
    solves it (the adhesive solve started from the non-adhesive one at the same load), with
    the range h_0 of Maugis parameter ``maugis_parameter``; and the closed form."""
    k = 4 * E_STAR / 3
    sigma0 = maugis_parameter / 2 * (math.pi * W * k**2 / R) ** (1 / 3)
    closed = MaugisDugdale(R, E_STAR, W, W / sigma0)
    plain = solve_contact(h, dx, dx, E_STAR, normal_force=force)
    state = solve_contact(
        h,
        dx,
        dx,
        E_STAR,
        normal_force=force,
        work_of_adhesion=W,
        initial=dataclasses.replace(plain, normal_force=force),
        adhesion="maugis",
        adhesion_range=closed.adhesion_range,
    )
    return state, closed


def test_sphere_array_sheared_from_the_maugis_loading_branch():
    """The shear BEM started from the normal reference's own state (the Maugis-Dugdale loading
    branch at F_z, Maugis parameter 0.5, its cohesive zone resolved at 12 elements per JKR
    radius) keeps that state's contact at delta_T = 0 (like for like: A_r(F_x = 0) is the
    reference's A_r), which is the Maugis-Dugdale closed form's contact radius at the cap load
    (measured +0.5 %; 14 % below JKR's, the finite range); under shear the edge reaches the
    mixed-mode criterion and the caps follow PC to the same static peak (measured +0.7 %) and
    slide at tau_0 pi a_H^2 (+1.0 %)."""
    dx = A_JKR / 12
    n1 = int(round(5 * A_JKR / dx))
    x = (np.arange(n1) - (n1 - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    h = np.tile(-(xx**2 + yy**2) / (2 * R), (CAPS, CAPS))
    force = CAPS**2 * P_CAP
    state, closed = _maugis_loading_state(h, dx, force, 0.5)
    model = _model_curve(LAM)
    d_t = np.linspace(0.0, 4.8 * model[-1, 0], 41)
    curve = mixed_mode_shear_curve(
        h, dx, dx, E_STAR, force, d_t, MixedModeLaw(W, LAM), shear_strength=TAU0, initial=state
    )
    assert curve.success and curve.preload_rim_fraction == 0.0
    assert curve.real_area[0] == pytest.approx(state.real_area, rel=1e-12)
    a0 = math.sqrt(curve.real_area[0] / CAPS**2 / math.pi)
    assert a0 == pytest.approx(closed.contact_radius(P_CAP), rel=0.02)
    err = _compare(curve, model)
    assert abs(err["peak"]) < 0.05
    assert abs(err["sliding"]) < 0.02
    assert curve.sliding[-1] and not curve.sliding[0]


def test_initial_state_on_another_grid_or_load_is_refused():
    """A normal state of another load or grid is not a preload of this curve: a clear error."""
    dx = A_JKR / 6
    n1 = int(round(5 * A_JKR / dx))
    x = (np.arange(n1) - (n1 - 1) / 2) * dx
    h = -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    state = solve_contact(h, dx, dx, E_STAR, normal_force=P_CAP)
    law = MixedModeLaw(W, LAM)
    with pytest.raises(BemInputError, match="F_z"):
        mixed_mode_shear_curve(
            h, dx, dx, E_STAR, 2 * P_CAP, [0.0], law, shear_strength=TAU0, initial=state
        )
    with pytest.raises(BemInputError, match="grid"):
        mixed_mode_shear_curve(
            h[:-2, :-2], dx, dx, E_STAR, P_CAP, [0.0], law, shear_strength=TAU0, initial=state
        )
