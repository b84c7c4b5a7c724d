"""The shear BEM's grid error bounds the true error of the grid used (issue 34 part 2).

The stage's error of a feature (:func:`asperity.pipelines.stages.bem_shear._grid_errors`) is
Richardson's extrapolation with Roache's grid convergence index over the grid used and two
coarser decimations (strides x2, x4), ``|f - f_extrapolated| + GCI``. Its truth here is the
same map solved at half the pixel (Fourier interpolation: the same roughness, finer elements),
as the normal reference's band is tested, and for a sphere array the same caps at twice the
elements per radius. Each case starts from the reference's state (the Maugis-Dugdale loading
branch at F_z, range fixed across the grids as the reference keeps it) and shears to full
sliding. The stated error must cover the true error of the grid used in >= 90 % of the cases.
"""

from __future__ import annotations

import numpy as np
import pytest

from asperity import statmodel, topo
from asperity.bem.options import SolverOptions
from asperity.bem.reference.interpolated_refinement import fourier_upsample
from asperity.bem.reference.load_sweeps import ContactSetup, Grid
from asperity.pipelines.stages.bem_shear import _grid_errors, _solve_curve, curve_features
from asperity.statmodel.jkr import jkr_contact_radius, jkr_normal_load

E_STAR, W, LAMBDA, TAU0 = 2.133e6, 0.040, 0.03, 0.13e6
RANGE = 12.5e-6  # m, the default job's Maugis-Dugdale range
MATERIAL = statmodel.Material(E_STAR, W, LAMBDA, TAU0)
#: The reference's solve set-up the preload is made with (periodic, Maugis-Dugdale at RANGE).
PRELOAD = ContactSetup(E_STAR, W, SolverOptions(tol=1e-6), True, adhesion_range=RANGE)


def _features(grid: Grid, load: float, path: np.ndarray) -> dict[str, float]:
    """F_s (N), F_d (N) and the area drop of one curve solved as the stage solves it."""
    out = _solve_curve(grid, load, path, MATERIAL, "pc", 1e-6, True, PRELOAD)
    c = out["curve"]
    return curve_features(c.tangential_displacement, c.tangential_force, c.real_area, c.sliding)


def _case(heights: np.ndarray, dx: float, pressure: float, path: np.ndarray):
    """(stated error of the grid used, its true error, value) per feature: grids at strides
    1, 2, 4 of ``heights`` (pixel dx, m) and the truth on its x2 Fourier interpolation, at the
    nominal ``pressure`` (Pa)."""
    grids = [Grid(heights[::s, ::s].copy(), dx * s, dx * s) for s in (1, 2, 4)]
    fine = Grid(fourier_upsample(heights, 2), dx / 2, dx / 2)
    solved = [_features(g, pressure * g.area, path) for g in grids]
    truth = _features(fine, pressure * fine.area, path)
    names = ("static_friction", "area_drop")
    fields = {name: np.array([[f[name]] for f in solved]) for name in names}
    fields["sliding_friction"] = np.array([[f["sliding_friction"]] for f in solved])
    fields["preload_rim_fraction"] = np.zeros((3, 1))
    errors = _grid_errors(fields, np.array([g.dx for g in grids]))
    return {
        name: (float(errors[f"{name}_error"][0]), abs(solved[0][name] - truth[name]))
        for name in names
    }


def _rough_cases() -> list[dict]:
    out = []
    for seed in range(5):
        surface = topo.synthetic.paper_like(n=48, pixel_size=20e-6, seed=seed)
        h = np.asarray(surface.heights, dtype=float)
        path = np.linspace(0.0, 60e-6, 31)
        for pressure in (800.0, 3000.0):  # Pa: the paper's lightest and a middle load
            out.append(_case(h - h.mean(), 20e-6, pressure, path))
    return out


def _sphere_cases() -> list[dict]:
    """2 x 2 identical caps (R = 1 mm) in periodic cells of 5 JKR radii, 8 and 12 elements
    per radius on the grid used."""
    radius = 1e-3
    xi = (E_STAR * radius / W) ** (1 / 3)
    delta = 3 * radius / xi**2
    a_jkr = jkr_contact_radius(delta, radius, W, E_STAR)
    load = jkr_normal_load(delta, radius, W, E_STAR)
    out = []
    for per in (8, 12):
        dx = float(a_jkr) / per
        n1 = 5 * per
        x = (np.arange(n1) - n1 / 2) * dx
        h = np.tile(-(x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius), (2, 2))
        pressure = 4 * float(load) / ((2 * n1 * dx) ** 2)
        path = np.linspace(0.0, 4 * TAU0 * float(a_jkr) / E_STAR, 31)
        out.append(_case(h, dx, pressure, path))
    return out


@pytest.mark.slow
def test_stated_shear_grid_error_covers_the_half_pixel_truth():
    """>= 90 % of 12 cases (10 rough patches, 2 sphere arrays): |f_used - f_truth| <= the
    stated error, for the static friction F_s and the area drop A_r(peak)/A_r(0) (round-off
    allowed: a patch whose junctions do not shrink has a drop of 1 on every grid).

    Measured: F_s covered in 12 of 12, the stated error 5-96 times the true one (median 14):
    conservative, as the coarser decimations carry less roughness as well as larger elements
    (the stage's notes); the area drop in 12 of 12."""
    cases = _rough_cases() + _sphere_cases()
    assert len(cases) >= 10
    for name, slack in (("static_friction", 1e-12), ("area_drop", 1e-9)):
        stated = np.array([c[name][0] for c in cases])
        true = np.array([c[name][1] for c in cases])
        assert np.all(np.isfinite(stated)), name
        covered = float(np.mean(true <= stated + slack))
        assert covered >= 0.9, (name, stated, true)
