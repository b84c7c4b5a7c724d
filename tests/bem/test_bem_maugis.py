"""Maugis-Dugdale adhesion in the BEM (adhesion="maugis"): the sphere against the closed form
(coarse grids; the fine-grid checks are in test_bem_maugis_sphere.py), the cohesive law's
conditions on a rough surface, branches, warnings and input refusals."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from asperity import bem
from asperity.bem.errors import BemInputError
from tests._helpers import (
    MAUGIS_E_STAR,
    MAUGIS_RADIUS,
    MAUGIS_WORK,
    equivalent_radius,
    maugis_sphere_case,
    random_surface,
    retract_to_pull_off,
)

RADIUS, E_STAR, WORK = MAUGIS_RADIUS, MAUGIS_E_STAR, MAUGIS_WORK  # m, Pa, J/m^2
sphere_case = maugis_sphere_case


@pytest.mark.parametrize(
    ("lam", "per_radius", "n", "tol_a"), [(0.3, 16, 96, 0.02), (1.0, 16, 72, 0.03)]
)
def test_sphere_contact_radius_on_loading(lam, per_radius, n, tol_a):
    """Load control at F = pi w R from scratch (jump-in): the contact radius of the closed
    form, and its cohesive zone to 15 %: the attracted area outside the contact per length of
    contact line, pi (c^2 - a^2) / (2 pi a), in elements."""
    md, h, dx, kw = sphere_case(lam, per_radius, n)
    res = bem.solve_contact(h, dx, dx, E_STAR, normal_force=md.force_scale, **kw)
    assert res.success, res.message
    assert res.branch == "loading"
    a = md.contact_radius(md.force_scale)
    assert equivalent_radius(res) == pytest.approx(a, rel=tol_a)
    c = md.state(a)["zone_radius"]
    zone = (c * c - a * a) / (2 * a * dx)
    assert res.extra["cohesive_zone_elements"] == pytest.approx(zone, rel=0.15)
    assert res.normal_force == pytest.approx(md.force_scale, rel=1e-9)


def test_sphere_zero_approach_and_pull_off_dmt_side():
    """lambda = 0.3: the force at zero approach and the pull-off force within 3 % at 16 pixels
    per contact radius."""
    md, h, dx, kw = sphere_case(0.3, 16, 96)
    pull_off, branch = retract_to_pull_off(h, dx, kw, md, steps=16)
    assert branch[0].normal_force == pytest.approx(md.zero_approach()["force"], rel=0.03)
    assert pull_off == pytest.approx(md.pull_off_force(), rel=0.03)
    assert all(r.branch == "unloading" for r in branch[1:])


def test_unresolved_cohesive_zone_warns_with_the_numbers():
    """lambda = 5 on a coarse grid: the zone spans less than an element; the result says so
    (message and extra["warnings"]), and the contact radius is then visibly off."""
    md, h, dx, kw = sphere_case(5.0, 12, 48)
    res = bem.solve_contact(h, dx, dx, E_STAR, normal_force=md.force_scale, **kw)
    assert res.extra["cohesive_zone_elements"] < 3
    assert len(res.extra["warnings"]) == 1
    assert "cohesive zone not resolved" in res.message and "elements" in res.message
    assert f"{md.adhesion_range:.3g}" in res.extra["warnings"][0]


def test_rough_surface_satisfies_the_cohesive_law():
    """On a rough periodic surface under load control: the force is carried exactly, the
    traction is q - sigma_0 on the attractive set {gap <= h_0} and q >= 0 only in contact,
    the gap is >= 0, and the contact exceeds the non-adhesive one at the same load."""
    h = random_surface(64, seed=3) * 1e-6
    dx, h0, w = 1e-6, 2e-8, 2e-3
    force = 0.02 * E_STAR * h.size * dx * dx * 0.05
    plain = bem.solve_contact(h, dx, dx, E_STAR, normal_force=force)
    res = bem.solve_contact(
        h,
        dx,
        dx,
        E_STAR,
        normal_force=force,
        work_of_adhesion=w,
        adhesion="maugis",
        adhesion_range=h0,
        initial=plain,
    )
    assert res.success, res.message
    sigma0 = w / h0
    attractive = res.gap <= h0
    q = res.pressure + sigma0 * attractive
    assert res.normal_force == pytest.approx(force, rel=1e-9)
    assert np.all(q >= -1e-9 * sigma0)
    assert np.all(res.gap >= -1e-6 * h0)
    assert np.all(q[~res.contact_mask] == pytest.approx(0.0, abs=1e-9 * sigma0))
    assert np.all(res.pressure >= -sigma0 * (1 + 1e-12))
    assert res.extra["attractive_area"] == pytest.approx(np.count_nonzero(attractive) * dx * dx)
    assert res.real_area > plain.real_area
    assert res.critical_tension == pytest.approx(sigma0)


def test_vanishing_range_strength_gives_the_non_adhesive_solution():
    """w -> 0 at a fixed range: sigma_0 -> 0, the solution tends to the non-adhesive one."""
    h = random_surface(48, seed=1) * 1e-6
    dx = 1e-6
    force = 1e-3 * E_STAR * h.size * dx * dx
    plain = bem.solve_contact(
        h, dx, dx, E_STAR, normal_force=force, options=bem.SolverOptions(tol=1e-10)
    )
    res = bem.solve_contact(
        h,
        dx,
        dx,
        E_STAR,
        normal_force=force,
        work_of_adhesion=1e-12,
        adhesion="maugis",
        adhesion_range=1e-8,
        options=bem.SolverOptions(tol=1e-10),
    )
    assert np.array_equal(res.contact_mask, plain.contact_mask)
    assert np.linalg.norm(res.pressure - plain.pressure) < 1e-3 * np.linalg.norm(plain.pressure)


def test_loading_then_unloading_shows_hysteresis():
    """Displacement control on a sphere at lambda = 1: approaching then retracting to the
    same separation, the unloading branch holds more contact and more tension."""
    md, h, dx, kw = sphere_case(1.0, 10, 48)
    d_far, d_in = 0.3 * md.approach_scale, -1.0 * md.approach_scale
    loading = bem.solve_contact(h, dx, dx, E_STAR, separation=d_far, **kw)
    deep = bem.solve_contact(h, dx, dx, E_STAR, separation=d_in, initial=loading, **kw)
    back = bem.solve_contact(h, dx, dx, E_STAR, separation=d_far, initial=deep, **kw)
    assert (loading.branch, deep.branch, back.branch) == ("loading", "loading", "unloading")
    assert back.real_area > loading.real_area
    assert back.normal_force < loading.normal_force


def test_load_sweep_with_maugis_continues_the_attractive_set():
    h = random_surface(48, seed=2) * 1e-6
    dx = 1e-6
    nominal = h.size * dx * dx
    forces = [f * E_STAR * nominal for f in (0.005, 0.01, 0.02)]
    kw = dict(work_of_adhesion=2e-3, adhesion="maugis", adhesion_range=2e-8)
    sweep = bem.load_sweep(h, dx, dx, E_STAR, forces, **kw)
    single = bem.solve_contact(h, dx, dx, E_STAR, normal_force=forces[-1], **kw)
    assert all(r.success and r.branch == "loading" for r in sweep)
    areas = [r.real_area for r in sweep]
    assert areas == sorted(areas)
    assert sweep[-1].real_area == pytest.approx(single.real_area, rel=0.01)


def test_pohrt_popov_stays_what_work_of_adhesion_alone_means():
    h = random_surface(32, seed=4) * 1e-6
    args = (h, 1e-6, 1e-6, E_STAR)
    force = 0.01 * E_STAR * h.size * 1e-12
    alone = bem.solve_contact(*args, normal_force=force, work_of_adhesion=0.01)
    named = bem.solve_contact(
        *args, normal_force=force, work_of_adhesion=0.01, adhesion="pohrt-popov"
    )
    assert np.array_equal(alone.pressure, named.pressure)
    assert "adhesion" not in alone.extra


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        (dict(adhesion="dugdale"), "adhesion must be one of"),
        (dict(adhesion="maugis"), "needs adhesion_range"),
        (dict(adhesion="maugis", adhesion_range=-1e-9), "adhesion_range must be a positive"),
        (dict(adhesion="maugis", adhesion_range="1e-9"), "adhesion_range must be a real"),
        (dict(adhesion_range=1e-9), "applies to adhesion='maugis' only"),
    ],
)
def test_bad_adhesion_arguments_are_named(kwargs, words):
    h = random_surface(16, seed=0) * 1e-6
    with pytest.raises(BemInputError, match=words):
        bem.solve_contact(h, 1e-6, 1e-6, E_STAR, normal_force=1e-6, work_of_adhesion=0.01, **kwargs)


def test_tensile_load_from_first_contact_is_refused_by_status():
    md, h, dx, kw = sphere_case(1.0, 8, 32)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = bem.solve_contact(h, dx, dx, E_STAR, normal_force=-10 * md.force_scale, **kw)
    assert res.status == bem.SolverStatus.LOAD_NOT_CARRIED
    assert not res.success and "load not carried" in res.message
