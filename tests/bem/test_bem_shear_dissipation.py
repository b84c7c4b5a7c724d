"""The second law along every shear path: the work done by the drive minus the increase of the
stored energy (elastic energy minus the adhesion energy w A of the bonded area) is >= 0 at every
step. The mixed-mode law dissipates ``(G_I + G_II - w) dA >= 0`` where the edge recedes
(E:failure_locus with lambda <= 1), sliding ``tau_0`` times the slip; the trapezoid of T over a
step uses the force after the step's detachments, a lower bound of the work in displacement
control, so the check is on the safe side. It can fail: charging 3 w per bonded area (a
criterion that let the edge go at a third of the energy it needs) gives -0.08 to -0.28 w A_0 at
a step of these paths (measured), where the law's own steps give >= -6e-12 w A_0."""

import numpy as np
import pytest

from asperity.bem.reference_solutions import pc_sphere
from asperity.bem.shear.mixed_mode import MixedModeLaw, tangential_sweep
from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
from asperity.bem.shear.stick_slip import ShearOptions
from asperity.statmodel.jkr import jkr_contact_radius, jkr_normal_load

R, E_STAR, W = 1.0, 1.0, 1e-6
DELTA = 3.0 * R / 100**2
A_JKR = float(jkr_contact_radius(DELTA, R, W, E_STAR))
P_JKR = float(jkr_normal_load(DELTA, R, W, E_STAR))
TAU0 = 1e-3 * E_STAR


def _sphere(n_per: int, size: float):
    dx = A_JKR / n_per
    n = int(size * n_per) + 2
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    return -(xx**2 + yy**2) / (2 * R), dx


def _work(d_t: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Work (J) of each step by the trapezoid of the force (N) over the displacement (m)."""
    return 0.5 * (force[1:] + force[:-1]) * np.diff(d_t)


def _stored(state, heights, dx) -> float:
    """Elastic energy minus adhesion energy (J) of one fixed-grip state: u_z = h - d + gap,
    u_x = delta_T - s; a sliding state is non-adhesive."""
    u_z = heights - state.separation + state.gap
    u_x = state.tangential_displacement - state.slip
    elastic = 0.5 * dx * dx * float(np.sum(state.pressure * u_z + state.traction * u_x))
    bonded = 0.0 if state.message.startswith("sliding") else state.real_area
    return elastic - W * bonded


@pytest.mark.parametrize(("n_per", "lam"), [(10, 0.03), (12, 0.2), (12, 1.0)])
def test_fixed_grip_sphere_dissipates(n_per, lam):
    """Papangelo-Ciavarella's sphere in fixed grip, through the fold into sliding."""
    h, dx = _sphere(n_per, 2.25)
    d_max = pc_sphere(DELTA, 0.0, R, W, E_STAR, lam).max_tangential_displacement
    d_t = np.r_[0.0, np.linspace(0.1, 1.4, 14) * d_max]
    sweep = tangential_sweep(
        h,
        dx,
        dx,
        E_STAR,
        -DELTA,
        d_t[1:],
        MixedModeLaw(W, lam),
        preload_separation=-((1.1 * A_JKR) ** 2) / R,
        shear_strength=TAU0,
        options=ShearOptions(tol=1e-9),
    )
    assert sweep.success and sweep.jump_index is not None
    states = [sweep.preload, *sweep.states]
    force = np.array([s.tangential_force for s in states])
    stored = np.array([_stored(s, h, dx) for s in states])
    dissipated = _work(d_t, force) - np.diff(stored)
    scale = W * sweep.preload.real_area
    assert np.all(dissipated >= -1e-6 * scale)
    assert dissipated.sum() > 0.01 * scale  # the fold and the sliding dissipate


def test_load_controlled_cap_dissipates():
    """One cap in the free domain at fixed F_z (the drive also works through the approach -d),
    through its instability into sliding."""
    h, dx = _sphere(8, 3.5)
    d_t = np.linspace(0.0, 2.5e-3, 12)
    curve = mixed_mode_shear_curve(
        h,
        dx,
        dx,
        E_STAR,
        P_JKR,
        d_t,
        MixedModeLaw(W, 0.2),
        shear_strength=TAU0,
        periodic=False,
        options=ShearOptions(tol=1e-9, load_tolerance=1e-9),
    )
    assert curve.success and curve.sliding[-1] and not curve.sliding[0]
    work = _work(d_t, curve.tangential_force) - P_JKR * np.diff(curve.separation)
    stored = curve.elastic_energy - W * curve.stick_area
    dissipated = work - np.diff(stored)
    scale = W * curve.stick_area[0]
    assert np.all(dissipated >= -1e-6 * scale)
    assert dissipated.sum() > 0.01 * scale
