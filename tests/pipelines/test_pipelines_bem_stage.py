"""Stage 3 (BEM reference): boundary chosen and stated, one adhesive loading path, an honest
grid check whose solves are all reused."""

from __future__ import annotations

import numpy as np
import pytest

from asperity import bem, topo
from asperity.bem.reference import load_sweeps
from asperity.bem.reference.load_sweeps import check_load_index, decimated_grid
from asperity.pipelines.config import BemConfig, ConfigError, config_from_dict
from asperity.pipelines.stages.bem import bem_reference

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


@pytest.mark.slow
def test_boundary_is_applied_stated_and_warned(window_map):
    periodic, free = (
        bem_reference(
            window_map, E_STAR, W, LOADS, A_N, BemConfig(max_stride=1, adhesive=False, boundary=b)
        )
        for b in ("periodic", "free")
    )
    assert (periodic.boundary, free.boundary) == ("periodic", "free")
    assert periodic.warnings and "seam" in periodic.warnings[0]
    assert free.warnings == []
    # the free solve is the finite-specimen solve of bem, at every load
    grid = decimated_grid(window_map.heights, window_map.dx, window_map.dy, 1)
    options = bem.SolverOptions(tol=1e-6)
    for i, f in enumerate(free.map_normal_load):
        ref = bem.solve_contact(
            grid.heights, grid.dx, grid.dy, E_STAR, normal_force=f, periodic=False, options=options
        )
        assert free.contact_fraction[i] == pytest.approx(ref.contact_fraction, rel=0.02)
    assert not np.allclose(free.contact_fraction, periodic.contact_fraction)


def test_config_boundary_key():
    cfg = config_from_dict({"surface": {"synthetic": {"n": 64}}, "bem": {"boundary": "free"}})
    assert cfg.bem.boundary == "free" and cfg.bem.coarsen is True
    with pytest.raises(ConfigError, match=r"bem\.boundary: expected one of 'periodic', 'free'"):
        config_from_dict({"surface": {"synthetic": {"n": 64}}, "bem": {"boundary": "open"}})


@pytest.fixture(scope="module")
def counted(periodic_map):
    """bem_reference on the periodic map with Pohrt-Popov adhesion (the paper's Appendix B),
    counting every bem.solve_contact call of its solves
    (:mod:`asperity.bem.reference.load_sweeps`)."""
    calls = []
    real = bem.solve_contact

    def counting(*args, **kwargs):
        calls.append(kwargs.get("work_of_adhesion", 0.0))
        return real(*args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(load_sweeps, "solve_contact", counting)
    settings = BemConfig(max_stride=4, coarsen=False, adhesion="pohrt-popov")
    try:
        ref = bem_reference(periodic_map, E_STAR, W, LOADS, A_N, settings)
    finally:
        mp.undo()
    return ref, calls


def test_every_solve_is_made_once_and_reused(counted):
    ref, calls = counted
    n_check, n_loads = len(ref.check_stride), len(LOADS)
    assert list(ref.check_stride) == [4, 2, 1] and ref.stride == 1
    # the check solves each stride once per mode; the sweeps solve only the other loads; the
    # discretisation check solves the check load once per mode on each interpolated grid
    refined = 2 * (len(ref.refinement_factor) - 1)
    assert list(ref.refinement_factor) == [1, 2, 4]
    assert len(calls) == 2 * n_check + 2 * (n_loads - 1) + refined == ref.solves
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
    assert "discretisation error is measured on its Fourier interpolations" in ref.grid_reason


def test_one_adhesive_loading_path(counted, periodic_map):
    ref, _ = counted
    assert all(b == "unique" for b in ref.branch[0])
    assert all(b == "loading" for b in ref.branch[1])
    assert [row[1] for row in ref.check_branch] == ["loading"] * len(ref.check_stride)
    # the adhesive A_r of the check and of the sweep lie on the branch that bem reaches from
    # scratch (its own loading path), at the check load and at the loads the chains solved
    g = decimated_grid(periodic_map.heights, periodic_map.dx, periodic_map.dy, 1)
    for i, f in enumerate(ref.map_normal_load):
        scratch = bem.solve_contact(
            g.heights, g.dx, g.dy, E_STAR, normal_force=f, work_of_adhesion=W
        )
        assert scratch.branch == "loading"
        assert ref.contact_fraction_adhesive[i] == pytest.approx(scratch.contact_fraction, rel=0.01)
    # the loading branch of Pohrt-Popov adhesion is the non-adhesive contact set (bem.branch)
    np.testing.assert_allclose(ref.contact_fraction_adhesive, ref.contact_fraction, rtol=0.01)


def test_the_keyword_settings_of_0_3_warn_and_mean_the_same(periodic_map):
    """``bem_reference(..., max_stride=2)`` (0.3) still works for one version, warning with the
    BemConfig to pass instead; a keyword that is no setting is refused."""
    settings = BemConfig(max_stride=2, adhesive=False)
    new = bem_reference(periodic_map, E_STAR, W, LOADS, A_N, settings)
    with pytest.warns(DeprecationWarning, match=r"BemConfig\(max_stride=2, adhesive=False\)"):
        old = bem_reference(periodic_map, E_STAR, W, LOADS, A_N, max_stride=2, adhesive=False)
    np.testing.assert_array_equal(old.contact_fraction, new.contact_fraction)
    with pytest.raises(TypeError, match="max_strides"):
        bem_reference(periodic_map, E_STAR, W, LOADS, A_N, max_strides=2)
