"""The exact case of the Maugis-Dugdale statistical model: sparse identical spherical caps.

Four paraboloids of radius R (the default job's summit radius, E*, w, and its range h_0 = 12.5
um, lambda = 0.024) at heights 0, -4, -8, -20 um on a periodic 2 x 2 lattice of spacing L, in
load control at 2 mN: three touch, the lowest one is only attracted (within h_0, out of
contact). The MD BEM (adhesion="maugis") against the same law summed over the four heights
(statmodel.maugis_rough.maugis_discrete_contact): with no interaction between the caps they
must agree. The caps' contact radii are 17-25 um (17-25 elements at dx = 1 um), the Dugdale
zones 20-45 um wide (cohesive zone 40 elements).

What separates them, measured (per-cap force errors of the BEM for the caps at 0, -4, -8,
-20 um; total area A_r; adhesive gain A_r / A_r(w = 0) - 1, model +2.49 %):

    L = 128 um, dx = 1   : +6.5, -3.0, -18.2, -15.2 %; A_r -0.55 %; gain +2.49 %
    L = 128 um, dx = 0.5 : +6.5, -3.0, -18.2, -15.5 %; A_r -1.06 %; gain +2.40 %
    L = 256 um, dx = 1   : +3.0, -1.2,  -8.6,  -7.3 %; A_r +0.60 %; gain +2.74 %
    L = 256 um, dx = 0.5 : +3.0, -1.2,  -8.6,  -7.4 %; A_r +0.03 %; gain +2.61 %
    L = 512 um, dx = 1   : +1.4, -0.6,  -4.2,  -3.5 %; A_r +0.83 %; gain +2.82 %

The per-cap forces are set by the elastic interaction of the caps, which falls as 1/L (the
deflection F / (pi E* L) of the neighbours' loads) and is untouched by refinement (0.1 %); at
1/L -> 0 (2 F(512) - F(256)) they are -0.2, 0.0, +0.2, +0.3 %: the model's law. The areas
carry the discretisation (pixel counting at 17-25 elements per radius): +-1 % between dx = 1
and 0.5 um, and the gain, a difference of two such areas, +-0.3 points. Tolerances below: 1 %
(force, contacting caps) and 2 % (attracted cap) at 1/L -> 0, 1.5 % on A_r and 0.5 points on
the gain.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from asperity import bem
from asperity.statmodel.maugis_rough import MaugisAsperity, maugis_discrete_contact

R, E_STAR, WORK, H0 = 55.84e-6, 2.133e6, 0.040, 12.5e-6  # m, Pa, J/m^2, m
HEIGHTS = np.array([0.0, -4e-6, -8e-6, -20e-6])  # m
FORCE = 2e-3  # N


def caps(spacing: float, dx: float) -> np.ndarray:
    """Heights (m) of the 2 x 2 periodic lattice of paraboloids, apexes on grid nodes."""
    cell = int(round(spacing / dx))
    x = (np.arange(cell) - cell // 2) * dx
    bump = -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    return np.block(
        [[HEIGHTS[0] + bump, HEIGHTS[1] + bump], [HEIGHTS[2] + bump, HEIGHTS[3] + bump]]
    )


def solve_pair(spacing: float, dx: float):
    """(MD BEM, non-adhesive BEM, per-cap forces of the MD BEM N, per-cap areas m^2)."""
    h = caps(spacing, dx)
    md = bem.solve_contact(
        h,
        dx,
        dx,
        E_STAR,
        normal_force=FORCE,
        work_of_adhesion=WORK,
        adhesion="maugis",
        adhesion_range=H0,
        options=bem.SolverOptions(tol=1e-8),
    )
    plain = bem.solve_contact(
        h, dx, dx, E_STAR, normal_force=FORCE, options=bem.SolverOptions(tol=1e-8)
    )
    assert md.success, md.message
    assert plain.success, plain.message
    half = h.shape[0] // 2
    blocks = [
        (slice(i * half, (i + 1) * half), slice(j * half, (j + 1) * half))
        for i in (0, 1)
        for j in (0, 1)
    ]
    forces = np.array([md.pressure[b].sum() * dx * dx for b in blocks])
    areas = np.array([np.count_nonzero(md.contact_mask[b]) * dx * dx for b in blocks])
    return md, plain, forces, areas


def model():
    """(MD model, GW model, per-cap forces N, per-cap areas m^2) at FORCE."""
    md = maugis_discrete_contact(HEIGHTS, R, E_STAR, WORK, H0, [FORCE])
    gw = maugis_discrete_contact(HEIGHTS, R, E_STAR, 0.0, H0, [FORCE])
    assert md.success.all() and gw.success.all()
    force, radius = MaugisAsperity(R, E_STAR, WORK, H0).loading_state(HEIGHTS - md.separation[0])
    return md, gw, force, math.pi * radius**2


def test_sparse_caps_total_area_and_gain_at_short_spacing():
    """Fast variant, L = 128 um (interaction still 3-18 % per cap, largely cancelling in the
    total): A_r and the adhesive gain agree within the BEM's discretisation; the lowest cap is
    pulled, out of contact, in both."""
    md_model, gw_model, f_model, a_model = model()
    assert md_model.n_contact[0] == 3 and md_model.n_attracted[0] == 4
    md, plain, forces, areas = solve_pair(128e-6, 1e-6)
    assert md.extra["cohesive_zone_elements"] > 3
    assert md.real_area == pytest.approx(md_model.real_area[0], rel=0.015)
    assert plain.real_area == pytest.approx(gw_model.real_area[0], rel=0.015)
    gain_bem = md.real_area / plain.real_area - 1
    gain_model = md_model.real_area[0] / gw_model.real_area[0] - 1
    assert abs(gain_bem - gain_model) < 0.005
    assert areas[3] == 0 and a_model[3] == 0
    assert forces[3] < 0 and f_model[3] < 0
    assert forces.sum() == pytest.approx(FORCE, rel=1e-9)


@pytest.mark.slow
def test_sparse_caps_agree_per_cap_without_interaction():
    """L = 256 and 512 um: each cap's force, extrapolated to no interaction (linear in 1/L),
    is the model's; the total area and the gain agree at both spacings (about 20 s)."""
    md_model, gw_model, f_model, _ = model()
    gain_model = md_model.real_area[0] / gw_model.real_area[0] - 1
    per_spacing = {}
    for spacing in (256e-6, 512e-6):
        md, plain, forces, _ = solve_pair(spacing, 1e-6)
        assert md.real_area == pytest.approx(md_model.real_area[0], rel=0.015)
        assert abs(md.real_area / plain.real_area - 1 - gain_model) < 0.005
        per_spacing[spacing] = forces
    isolated = 2 * per_spacing[512e-6] - per_spacing[256e-6]
    assert isolated[:3] == pytest.approx(f_model[:3], rel=0.01)
    assert isolated[3] == pytest.approx(f_model[3], rel=0.02)
    # the interaction halves with the spacing: it is not the model's law that differs
    err256 = per_spacing[256e-6] / f_model - 1
    err512 = per_spacing[512e-6] / f_model - 1
    assert np.all(np.abs(err512) < 0.65 * np.abs(err256))
