"""Stage 3 (BEM reference): boundary chosen and stated, one adhesive loading path, an honest
grid check whose solves are all reused."""

from __future__ import annotations

import numpy as np
import pytest

from asperity import bem, topo
from asperity.pipelines.config import ConfigError, config_from_dict
from asperity.pipelines.stages import _bem_grid as bem_grid
from asperity.pipelines.stages._bem_grid import EDGE_MISMATCH_LIMIT, choose_stride, edge_mismatch
from asperity.pipelines.stages.bem import bem_reference, check_load_index, load_chains

E_STAR = 2.133e6  # Pa
W = 0.04  # J/m^2
A_N = 40e-6  # m^2: a few % contact on the small maps below
LOADS = [0.5, 1.0, 2.0]  # N


@pytest.fixture(scope="module")
def periodic_map() -> topo.HeightMap:
    """A periodic 64 x 64 synthetic map (50 um pixels)."""
    return topo.synthetic.paper_like(n=64, pixel_size=50e-6, seed=1)


@pytest.fixture(scope="module")
def window_map(periodic_map) -> topo.HeightMap:
    """A 64 x 64 window of a larger synthetic map: opposite edges do not meet (a measured map)."""
    big = topo.synthetic.paper_like(n=160, pixel_size=50e-6, seed=2)
    return topo.HeightMap(np.array(big.heights[10:74, 30:94]), big.dx, big.dy, periodic=False)


def test_edge_mismatch_tells_a_periodic_map_from_a_window(periodic_map, window_map):
    assert edge_mismatch(periodic_map.heights) < 0.3  # statistically ~0
    assert edge_mismatch(window_map.heights) > 0.9  # uncorrelated edges: ~sqrt(2)
    assert not bem_grid.boundary_warning("periodic", edge_mismatch(periodic_map.heights))
    assert not bem_grid.boundary_warning("free", edge_mismatch(window_map.heights))
    warning = bem_grid.boundary_warning("periodic", edge_mismatch(window_map.heights))
    assert f"limit {EDGE_MISMATCH_LIMIT}" in warning and "free" in warning


@pytest.mark.slow
def test_boundary_is_applied_stated_and_warned(window_map):
    kwargs = dict(max_stride=1, adhesive=False)
    periodic = bem_reference(window_map, E_STAR, W, LOADS, A_N, boundary="periodic", **kwargs)
    free = bem_reference(window_map, E_STAR, W, LOADS, A_N, boundary="free", **kwargs)
    assert (periodic.boundary, free.boundary) == ("periodic", "free")
    assert periodic.warnings and "seam" in periodic.warnings[0]
    assert free.warnings == []
    # the free solve is the finite-specimen solve of bem, at every load
    h, dx, dy = bem_grid.solver_grid(window_map, 1)
    for i, f in enumerate(free.map_normal_load):
        ref = bem.solve_contact(h, dx, dy, E_STAR, normal_force=f, periodic=False, tol=1e-6)
        assert free.contact_fraction[i] == pytest.approx(ref.contact_fraction, rel=0.02)
    assert not np.allclose(free.contact_fraction, periodic.contact_fraction)


def test_config_boundary_key():
    cfg = config_from_dict({"surface": {"synthetic": {"n": 64}}, "bem": {"boundary": "free"}})
    assert cfg.bem.boundary == "free" and cfg.bem.coarsen is True
    with pytest.raises(ConfigError, match=r"bem\.boundary: expected one of 'periodic', 'free'"):
        config_from_dict({"surface": {"synthetic": {"n": 64}}, "bem": {"boundary": "open"}})


def test_check_load_and_chains_cover_every_load_once():
    loads = np.array([3.12, 0.56, 2.08, 1.06, 2.57, 1.58])
    k = check_load_index(loads)
    assert loads[k] == 2.08  # the middle load of the sorted six, one of the loads
    chains = load_chains(loads)
    assert [loads[c].tolist() for c in chains] == [[2.57, 3.12], [1.58, 1.06, 0.56]]
    assert sorted([k, *chains[0], *chains[1]]) == list(range(6))
    assert load_chains(np.array([1.0])) == []


def test_coarsest_grid_within_tolerance_of_the_finest():
    strides, error = [8, 4, 2, 1], np.array([0.30, 0.04, 0.06, 0.0])
    # stride 4 is within 5 % of the finest even though stride 2 is not: the finest decides
    assert choose_stride(strides, error, 0.05, coarsen=True) == 4
    assert choose_stride(strides, error, 0.01, coarsen=True) == 1
    assert choose_stride(strides, error, 0.5, coarsen=False) == 1


@pytest.fixture(scope="module")
def counted(periodic_map):
    """bem_reference on the periodic map with Pohrt-Popov adhesion (the paper's Appendix B),
    counting every bem.solve_contact call."""
    calls = []
    real = bem.solve_contact

    def counting(*args, **kwargs):
        calls.append(kwargs.get("work_of_adhesion", 0.0))
        return real(*args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(bem, "solve_contact", counting)
    try:
        ref = bem_reference(
            periodic_map, E_STAR, W, LOADS, A_N, max_stride=4, coarsen=False, adhesion="pohrt-popov"
        )
    finally:
        mp.undo()
    return ref, calls


def test_every_solve_is_made_once_and_reused(counted):
    ref, calls = counted
    n_check, n_loads = len(ref.check_stride), len(LOADS)
    assert list(ref.check_stride) == [4, 2, 1] and ref.stride == 1
    # the check solves each stride once per mode; the sweeps solve only the other loads
    assert len(calls) == 2 * n_check + 2 * (n_loads - 1) == ref.solves
    assert sum(w > 0 for w in calls) == len(calls) // 2
    k = check_load_index(np.array(LOADS))
    np.testing.assert_array_equal(ref.check_contact_fraction[-1, 0], ref.contact_fraction[k])
    np.testing.assert_array_equal(
        ref.check_contact_fraction[-1, 1], ref.contact_fraction_adhesive[k]
    )
    assert ref.check_iterations[-1, 0] == ref.iterations[0, k]


def test_grid_error_is_against_the_finest_grid(counted):
    ref, _ = counted
    f = ref.check_contact_fraction
    expected = np.max(np.abs(f - f[-1]) / f[-1], axis=1)
    np.testing.assert_allclose(ref.check_error, expected)
    assert ref.grid_error == 0.0 and "coarsen = false" in ref.grid_reason
    assert "finest grid's own error is not known" in ref.grid_reason


def test_one_adhesive_loading_path(counted, periodic_map):
    ref, _ = counted
    assert all(b == "unique" for b in ref.branch[0])
    assert all(b == "loading" for b in ref.branch[1])
    assert [row[1] for row in ref.check_branch] == ["loading"] * len(ref.check_stride)
    # the adhesive A_r of the check and of the sweep lie on the branch that bem reaches from
    # scratch (its own loading path), at the check load and at the loads the chains solved
    h, dx, dy = bem_grid.solver_grid(periodic_map, 1)
    for i, f in enumerate(ref.map_normal_load):
        scratch = bem.solve_contact(h, dx, dy, E_STAR, normal_force=f, work_of_adhesion=W)
        assert scratch.branch == "loading"
        assert ref.contact_fraction_adhesive[i] == pytest.approx(scratch.contact_fraction, rel=0.01)
    # the loading branch of Pohrt-Popov adhesion is the non-adhesive contact set (bem.branch)
    np.testing.assert_allclose(ref.contact_fraction_adhesive, ref.contact_fraction, rtol=0.01)
