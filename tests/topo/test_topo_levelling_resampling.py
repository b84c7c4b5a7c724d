"""Levelling invariants and resampling identities."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity import topo
from asperity.topo.levelling import fit_form

RNG = np.random.default_rng(7)


def grid(nx=40, ny=30, dx=1e-6, dy=2e-6):
    x = np.arange(nx)[:, None] * dx
    y = np.arange(ny)[None, :] * dy
    return x, y


@settings(max_examples=40, deadline=None)
@given(a=st.floats(-1e-3, 1e-3), b=st.floats(-1, 1), c=st.floats(-1, 1))
def test_plane_levelling_removes_any_plane_exactly(a, b, c):
    x, y = grid()
    roughness = RNG.normal(scale=1e-7, size=x.shape[:1] + y.shape[1:])
    base = topo.level(topo.HeightMap(roughness, 1e-6, 2e-6), "plane").heights
    tilted = topo.level(topo.HeightMap(roughness + a + b * x + c * y, 1e-6, 2e-6), "plane").heights
    np.testing.assert_allclose(tilted, base, atol=1e-14)


def test_levelled_map_is_orthogonal_to_the_basis_and_keeps_nan():
    x, y = grid()
    h = 3e-6 + 1e-3 * x - 2e-3 * y + 50 * x * y + RNG.normal(scale=1e-7, size=(40, 30))
    h[5, 7] = np.nan
    h[20:23, 3] = np.nan
    surface = topo.HeightMap(h, 1e-6, 2e-6)
    for method, n_terms in (("mean", 1), ("plane", 3), ("quadratic", 6)):
        out = topo.level(surface, method).heights
        assert np.array_equal(np.isnan(out), np.isnan(h))
        assert np.nanmean(out) == pytest.approx(0.0, abs=1e-18)
        residual_form = fit_form(topo.HeightMap(out, 1e-6, 2e-6), method)
        assert residual_form.shape == (n_terms,)
        assert np.allclose(residual_form, 0.0, atol=1e-18)
        assert out.shape == h.shape
    quad = topo.level(
        topo.HeightMap(1 + x**2 * 1e6 + x * y * 3e5 - y**2 * 1e5, 1e-6, 2e-6), "quadratic"
    )
    np.testing.assert_allclose(quad.heights, 0.0, atol=1e-12)
    assert topo.level(surface, "none") is surface
    with pytest.raises(ValueError, match="levelling method"):
        topo.level(surface, "cubic")


def test_periodic_map_keeps_periodicity():
    surface = topo.synthetic.paper_like(n=64, pixel_size=50e-6)
    levelled = topo.level(surface, "plane")
    assert levelled.periodic
    assert levelled.provenance["levelling"] == "mean (periodic map)"


def test_decimate_identities_and_views():
    surface = topo.synthetic.paper_like(n=120, pixel_size=20e-6, seed=2)
    assert topo.decimate(surface, 1) is surface
    d6 = topo.decimate(surface, 6)
    d23 = topo.decimate(topo.decimate(surface, 2), 3)
    np.testing.assert_array_equal(d6.heights, d23.heights)
    assert (d6.dx, d6.dy) == pytest.approx((d23.dx, d23.dy))
    assert np.shares_memory(d6.heights, surface.heights)  # a view, no copy
    assert d6.periodic and not topo.decimate(surface, 7).periodic  # 120 % 7 != 0
    assert not d6.heights.flags.writeable
    with pytest.raises(ValueError, match="stride"):
        topo.decimate(surface, 0)


def test_block_mean_identities():
    constant = topo.HeightMap(np.full((12, 9), 2.5e-6), 1e-6, 1e-6)
    np.testing.assert_allclose(topo.block_mean(constant, 3).heights, 2.5e-6)
    surface = topo.synthetic.paper_like(n=60, pixel_size=20e-6, seed=3)
    coarse = topo.block_mean(surface, 4)
    assert coarse.heights.shape == (15, 15)
    assert coarse.heights.mean() == pytest.approx(surface.heights.mean(), abs=1e-18)
    assert coarse.dx == pytest.approx(4 * surface.dx)
    holes = np.array(surface.heights)
    holes[:4, :4] = np.nan
    holes[4, 4] = np.nan
    blocked = topo.block_mean(topo.HeightMap(holes, 1e-6, 1e-6), 4).heights
    assert np.isnan(blocked[0, 0])
    assert blocked[1, 1] == pytest.approx(np.nanmean(holes[4:8, 4:8]))


def test_fourier_resample_exact_for_band_limited_maps():
    n, dx = 64, 1e-6
    x = np.arange(n) * dx
    wave = (
        1e-6
        * np.cos(2 * np.pi * 3 * x / (n * dx))[:, None]
        * np.sin(2 * np.pi * 5 * x / (n * dx))[None, :]
    )
    surface = topo.HeightMap(wave, dx, dx, periodic=True)
    coarse = topo.fourier_resample(surface, 4)
    np.testing.assert_allclose(coarse.heights, wave[::4, ::4], atol=1e-18)
    # and it removes what decimation would alias: a wave at the fine Nyquist/2 vanishes
    short = topo.HeightMap(np.cos(np.pi * np.arange(n) / 2)[:, None] * np.ones(n), dx, dx, True)
    np.testing.assert_allclose(topo.fourier_resample(short, 4).heights, 0.0, atol=1e-12)
    assert not np.allclose(topo.decimate(short, 4).heights, 0.0)
