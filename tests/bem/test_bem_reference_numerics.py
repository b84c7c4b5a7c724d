"""The BEM reference's numerics as public functions (bem.reference: grid_refinement,
adhesion_range, load_sweeps, solve): the seam measure, the grid choice, Richardson extrapolation
of a known power law, the Maugis range search on a sphere against the Maugis-Dugdale closed form,
and a reference whose solves are each made once."""

from __future__ import annotations

import math

import numpy as np
import pytest

from asperity import bem, topo
from asperity.bem.normal.maugis import MIN_ZONE_ELEMENTS
from asperity.bem.reference.adhesion_range import RangeTry, next_range, search_range
from asperity.bem.reference.grid_refinement import (
    EDGE_MISMATCH_LIMIT,
    boundary_warning,
    check_grids,
    choose_stride,
    edge_mismatch,
    grid_extrapolations,
    relative_discretisation_uncertainty,
)
from asperity.bem.reference.load_sweeps import (
    ContactSetup,
    check_load_index,
    decimated_grid,
    load_chains,
    solve_non_adhesive,
)
from asperity.bem.reference.solve import solve_reference
from asperity.statmodel.maugis_dugdale import MaugisDugdale

E_STAR = 2.133e6  # Pa
W = 0.04  # J/m^2


@pytest.fixture(scope="module")
def periodic_map() -> topo.HeightMap:
    """A periodic 64 x 64 synthetic map (50 um pixels)."""
    return topo.synthetic.paper_like(n=64, pixel_size=50e-6, seed=1)


def test_edge_mismatch_tells_a_periodic_map_from_a_window(periodic_map):
    big = topo.synthetic.paper_like(n=160, pixel_size=50e-6, seed=2)
    window = np.array(big.heights[10:74, 30:94])
    assert edge_mismatch(periodic_map.heights) < 0.3  # statistically ~0
    assert edge_mismatch(window) > 0.9  # uncorrelated edges: ~sqrt(2)
    assert not boundary_warning("periodic", edge_mismatch(periodic_map.heights))
    assert not boundary_warning("free", edge_mismatch(window))
    warning = boundary_warning("periodic", edge_mismatch(window))
    assert f"limit {EDGE_MISMATCH_LIMIT}" in warning and "free" in warning


def test_coarsest_grid_within_tolerance_of_the_finest():
    strides, error = [8, 4, 2, 1], np.array([0.30, 0.04, 0.06, 0.0])
    # stride 4 is within 5 % of the finest even though stride 2 is not: the finest decides
    assert choose_stride(strides, error, 0.05, coarsen=True) == 4
    assert choose_stride(strides, error, 0.01, coarsen=True) == 1
    assert choose_stride(strides, error, 0.5, coarsen=False) == 1


def test_check_load_and_chains_cover_every_load_once():
    loads = np.array([3.12, 0.56, 2.08, 1.06, 2.57, 1.58])
    k = check_load_index(loads)
    assert loads[k] == 2.08  # the middle load of the sorted six, one of the loads
    chains = load_chains(loads)
    assert [loads[c].tolist() for c in chains] == [[2.57, 3.12], [1.58, 1.06, 0.56]]
    assert sorted([k, *chains[0], *chains[1]]) == list(range(6))
    assert load_chains(np.array([1.0])) == []


def test_decimated_grid_keeps_one_point_in_stride_and_fills_missing_pixels():
    heights = np.arange(36.0).reshape(6, 6)
    heights[0, 0] = np.nan
    grid = decimated_grid(heights, 1e-6, 2e-6, 2)
    assert (grid.dx, grid.dy) == (2e-6, 4e-6) and grid.heights.shape == (3, 3)
    # the missing pixel takes the lowest valid height of the grid: it never touches
    assert grid.heights[0, 0] == np.nanmin(heights[::2, ::2])
    assert grid.area == pytest.approx(9 * 2e-6 * 4e-6)


def test_richardson_extrapolation_recovers_a_known_power_law():
    """A_r/A_n = f0 + C h^p on strides 4, 2, 1: the extrapolation returns f0 and p, and the
    relative uncertainty of the finest grid holds its distance from f0."""
    f0, c, p, pixel = 0.05, 30.0, 1.0, 10e-6
    strides = np.array([4, 2, 1])
    h = strides * pixel
    fraction = np.column_stack([f0 + c * h**p, f0 + 2 * c * h**p])  # two modes
    extrapolations = grid_extrapolations(strides, fraction, pixel)
    for mode, e in enumerate(extrapolations):
        assert e.value == pytest.approx(f0, rel=1e-9)
        assert e.order == pytest.approx(p, rel=1e-9)
        used = fraction[-1, mode]
        relative = relative_discretisation_uncertainty(e, used)
        assert relative * used >= abs(used - f0)


def test_next_range_hits_the_target_zone_of_a_quadratic_law():
    """On the JKR side the zone grows as h_0^2: from two tries on that law the next range
    puts the zone at 3 elements times the margin's square."""
    zone = lambda h0: 1e12 * h0**2  # elements  # noqa: E731
    tried = [RangeTry(h0, zone(h0), 0.0) for h0 in (1e-6, 1.2e-6)]
    h_next = next_range(tried)
    assert zone(h_next) == pytest.approx(MIN_ZONE_ELEMENTS * 1.05**2, rel=1e-9)


def test_range_search_on_a_sphere_reaches_three_elements_as_the_closed_form_says():
    """A paraboloid (R = 1 cm) loaded to pi w R: the search starts at the JKR-side closed form
    bem.resolving_range and ends at a range whose cohesive zone spans >= 3 elements; the
    zone it reports is the Maugis-Dugdale closed form's at that range within 15 %."""
    radius, e_star, work = 1e-2, 1e6, 0.05
    force = math.pi * work * radius
    jkr_radius = (9 * math.pi * work * radius**2 / (2 * e_star)) ** (1 / 3)
    n, dx = 72, jkr_radius / 16
    x = (np.arange(n) - n // 2) * dx
    grid = bem.Grid(-(x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius), dx, dx)
    setup = ContactSetup(e_star, work, bem.SolverOptions(tol=1e-8), periodic=False)
    plain = solve_non_adhesive(grid, setup, force)
    choice = search_range(grid, setup, plain, force)
    assert choice.tried[0].adhesion_range == bem.resolving_range(work, e_star, dx)
    assert choice.zone_elements >= MIN_ZONE_ELEMENTS and "(reached" in choice.rule
    md = MaugisDugdale(radius, e_star, work, choice.adhesion_range)
    a = md.contact_radius(force)
    c = md.state(a)["zone_radius"]
    assert choice.zone_elements == pytest.approx((c * c - a * a) / (2 * a * dx), rel=0.15)


def test_reference_solves_every_load_once_and_reuses_the_check(periodic_map):
    """solve_reference on a small map: the check's solve at the chosen stride is the check
    load's, every other load is solved once, and the counts add up."""
    calls = []

    def counting_map(function, jobs):
        calls.extend(len(job[2]) for job in jobs)
        return [function(*job) for job in jobs]

    setup = ContactSetup(E_STAR, W, bem.SolverOptions(tol=1e-6))
    loads = [0.5, 1.0, 2.0]
    run = solve_reference(
        periodic_map.heights, periodic_map.dx, periodic_map.dy, setup, loads, 40e-6,
        max_stride=2, area_tolerance=0.05, coarsen=False, adhesion="pohrt-popov",
        adhesion_range=None, map_chains=counting_map,
    )  # fmt: skip
    assert sorted(calls) == [1, 1]  # one load above, one below the check load
    k = run.check_index
    assert loads[k] == 1.0 and run.check.stride == 1
    assert run.solves[0][k] == run.check.solves[-1][0]
    solves, _, _ = run.totals()
    # the interpolated refinement (x2, x4 of the 64^2 grid) adds one solve per level and mode
    assert run.check.refinement.extra_solves == 4
    assert solves == 2 * len(run.check.strides) + 2 * (len(loads) - 1) + 4
    np.testing.assert_allclose(run.map_loads, np.array(loads) * run.grid.area / 40e-6)


def test_grid_check_errors_are_against_the_finest_grid(periodic_map):
    setup = ContactSetup(E_STAR, 0.0, bem.SolverOptions(tol=1e-6))
    check = check_grids(
        periodic_map.heights, periodic_map.dx, periodic_map.dy, setup, 25e3,
        max_stride=4, area_tolerance=0.05, coarsen=True,
    )  # fmt: skip
    f = check.fractions()
    assert list(check.strides) == [4, 2, 1] and f.shape == (3, 1)
    np.testing.assert_allclose(check.error, np.abs(f[:, 0] - f[-1, 0]) / f[-1, 0])
    assert check.error[check.chosen] <= 0.05 or check.stride == 1
