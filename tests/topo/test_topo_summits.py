"""Summit statistics (paper, Appendix A) on surfaces with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from asperity import topo
from asperity.topo.summits import summit_mask


def egg_crate(n_cells_x, n_cells_y, px_per_cell_x, px_per_cell_y, dx, dy, amplitude, periodic=True):
    """h = A cos(kx x) cos(ky y) on a grid that holds whole periods."""
    nx, ny = n_cells_x * px_per_cell_x, n_cells_y * px_per_cell_y
    x = np.arange(nx) * dx
    y = np.arange(ny) * dy
    kx, ky = 2 * np.pi / (px_per_cell_x * dx), 2 * np.pi / (px_per_cell_y * dy)
    heights = amplitude * np.cos(kx * x)[:, None] * np.cos(ky * y)[None, :]
    return topo.HeightMap(heights, dx, dy, periodic), kx, ky


@pytest.mark.parametrize("neighbours", [4, 8])
def test_egg_crate_eta_r_sigma_exact(neighbours):
    cells_x, cells_y, px, py, dx, dy, amp = 6, 4, 16, 12, 2e-6, 3e-6, 5e-6
    surface, kx, ky = egg_crate(cells_x, cells_y, px, py, dx, dy, amp)
    stats = topo.summit_statistics(surface, neighbours=neighbours)
    # maxima at (0, 0) and (half, half) of every cell: two per cell
    n_expected = 2 * cells_x * cells_y
    assert stats.n_summits == n_expected
    assert stats.asperity_density == pytest.approx(
        n_expected / (surface.lx * surface.ly), rel=1e-14
    )
    # central differences of A cos(k x) at a crest: |z_xx| = 2A (1 - cos(k dx)) / dx^2
    zxx = 2 * amp * (1 - math.cos(kx * dx)) / dx**2
    zyy = 2 * amp * (1 - math.cos(ky * dy)) / dy**2
    assert stats.summit_radius == pytest.approx(0.5 * (1 / zxx + 1 / zyy), rel=1e-12)
    # every summit has height A: sigma_s about the mean summit height is zero
    assert stats.summit_height_rms == pytest.approx(0.0, abs=1e-12 * amp)
    assert stats.mean_summit_height == pytest.approx(amp, rel=1e-12)
    # the continuum limit is R -> 1/(A k^2) when the pixels are small
    fine, kx, _ = egg_crate(2, 2, 400, 400, 1e-6, 1e-6, amp)
    assert topo.summit_statistics(fine).summit_radius == pytest.approx(1 / (amp * kx**2), rel=1e-4)


def test_spikes_give_sigma_s_about_the_mean_and_their_radius():
    dx, dy = 1e-6, 2e-6
    heights = np.zeros((20, 30))
    spikes = {(3, 4): 1e-6, (10, 10): 2e-6, (15, 25): 4e-6, (7, 20): 3e-6}
    for (i, j), z in spikes.items():
        heights[i, j] = z
    stats = topo.summit_statistics(topo.HeightMap(heights, dx, dy))
    z = np.array(list(spikes.values()))
    assert stats.n_summits == 4
    assert stats.summit_height_rms == pytest.approx(np.std(z), rel=1e-12)
    radius = np.mean(0.5 * (dx**2 / (2 * z) + dy**2 / (2 * z)))
    assert stats.summit_radius == pytest.approx(radius, rel=1e-12)


def test_plane_and_ties_have_no_summit():
    i, j = np.meshgrid(np.arange(40), np.arange(30), indexing="ij")
    plane = topo.HeightMap(1e-6 * i + 2e-6 * j, 1e-6, 1e-6)
    assert topo.summit_statistics(plane).n_summits == 0
    assert math.isnan(topo.summit_statistics(plane).summit_radius)
    assert topo.summit_statistics(plane).asperity_density == 0.0
    flat_top = np.zeros((10, 10))
    flat_top[4:6, 4] = 1.0  # two equal neighbours: strict inequality, no summit
    assert topo.summit_statistics(topo.HeightMap(flat_top, 1.0, 1.0)).n_summits == 0


def test_four_versus_eight_neighbours():
    heights = np.zeros((9, 9))
    heights[4, 4] = 2.0
    heights[5, 5] = 3.0  # diagonal neighbour higher: a 4- but not an 8-neighbour summit at (4, 4)
    surface = topo.HeightMap(heights, 1.0, 1.0)
    assert topo.summit_statistics(surface, neighbours=4).n_summits == 2
    assert topo.summit_statistics(surface, neighbours=8).n_summits == 1
    with pytest.raises(ValueError, match="neighbours"):
        topo.summit_statistics(surface, neighbours=6)


def test_missing_pixels_and_edges_excluded_periodic_wraps():
    heights = np.zeros((10, 12))
    heights[0, 5] = 1.0  # on the edge
    heights[5, 5] = 1.0
    heights[5, 6 + 1] = 1.0
    heights[5, 8] = np.nan  # beside the spike at (5, 7)
    open_map = topo.HeightMap(heights, 1.0, 1.0, periodic=False)
    assert topo.summit_statistics(open_map).n_summits == 1
    closed = topo.HeightMap(heights, 1.0, 1.0, periodic=True)
    assert topo.summit_statistics(closed).n_summits == 2


def test_stride_is_the_statistics_of_the_decimated_map():
    surface = topo.synthetic.paper_like(n=300, pixel_size=20e-6, seed=4)
    for stride in (1, 2, 3, 7):
        a = topo.summit_statistics(surface, stride=stride)
        b = topo.summit_statistics(topo.decimate(surface, stride))
        c = topo.summit_statistics(
            topo.HeightMap(
                np.array(surface.heights[::stride, ::stride]),
                a.dx,
                a.dy,
                periodic=300 % stride == 0,
            )
        )
        assert (
            a.as_dict() | {"stride": 1}
            == b.as_dict() | {"stride": 1}
            == c.as_dict() | {"stride": 1}
        )
        assert a.dx == stride * surface.dx


def reference_summits(h: np.ndarray) -> np.ndarray:
    """Plain numpy 4-neighbour rule, interior only (NaN compares False)."""
    c = h[1:-1, 1:-1]
    with np.errstate(invalid="ignore"):
        inner = (c > h[:-2, 1:-1]) & (c > h[2:, 1:-1]) & (c > h[1:-1, :-2]) & (c > h[1:-1, 2:])
    return np.pad(inner, 1)


heights_strategy = arrays(
    np.float64,
    st.tuples(st.integers(1, 9), st.integers(1, 9)),
    elements=st.one_of(st.integers(-3, 3).map(float), st.just(np.nan)),
)


@settings(max_examples=60, deadline=None)
@given(heights_strategy)
def test_kernel_matches_numpy_reference_and_symmetries(h):
    surface = topo.HeightMap(h, 1.0, 1.0)
    mask = summit_mask(surface)
    np.testing.assert_array_equal(
        mask, reference_summits(h) if min(h.shape) >= 3 else np.zeros_like(mask)
    )
    if min(h.shape) < 3 or np.isnan(h).all():
        with pytest.raises(ValueError, match="3 x 3 pixels|every pixel"):
            topo.summit_statistics(surface)
        return
    stats = topo.summit_statistics(surface)
    assert stats.n_summits == mask.sum()
    if min(h.shape) >= 3:  # periodic: compare with np.roll in the four directions
        with np.errstate(invalid="ignore"):
            rolled = np.ones(h.shape, dtype=bool)
            for shift, axis in ((1, 0), (-1, 0), (1, 1), (-1, 1)):
                rolled &= h > np.roll(h, shift, axis)
        periodic = topo.HeightMap(h, 1.0, 1.0, periodic=True)
        np.testing.assert_array_equal(summit_mask(periodic), rolled)
        assert topo.summit_statistics(periodic).n_summits == rolled.sum()
    for transformed in (h[::-1], h[:, ::-1], h.T):
        assert topo.summit_statistics(topo.HeightMap(transformed, 1.0, 1.0)).n_summits == mask.sum()


def test_line_profile_refused():
    with pytest.raises(ValueError, match="line profile"):
        topo.summit_statistics(topo.LineProfile(np.arange(10.0), 1e-6))


def candidate_pixels(h: np.ndarray, periodic: bool, neighbours: int) -> np.ndarray:
    """Pixels that could host a summit, by np.roll: valid with every neighbour valid."""
    valid = ~np.isnan(h)
    shifts = [(1, 0), (-1, 0), (1, 1), (-1, 1)]
    ok = valid.copy()
    for shift, axis in shifts:
        ok &= np.roll(valid, shift, axis)
    if neighbours == 8:
        for sx in (1, -1):
            for sy in (1, -1):
                ok &= np.roll(valid, (sx, sy), (0, 1))
    if not periodic:
        ok[[0, -1], :] = False
        ok[:, [0, -1]] = False
    return ok


def area_pixels(h: np.ndarray, periodic: bool, neighbours: int) -> np.ndarray:
    """Pixels of A_n, by padding: valid, no compared neighbour missing; off the map is fine."""
    valid = ~np.isnan(h)
    if periodic:
        padded = np.pad(valid, 1, mode="wrap")
    else:
        padded = np.pad(valid, 1, mode="constant", constant_values=True)
    nx, ny = h.shape
    offsets = [(1, 0), (-1, 0), (0, 1), (0, -1)]
    if neighbours == 8:
        offsets += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    ok = valid.copy()
    for di, dj in offsets:
        ok &= padded[1 + di : 1 + di + nx, 1 + dj : 1 + dj + ny]
    return ok


@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("neighbours", [4, 8])
def test_statistics_match_a_direct_numpy_evaluation(periodic, neighbours):
    rng = np.random.default_rng(11)
    h = rng.normal(size=(53, 41)) * 1e-6
    h[rng.random(h.shape) < 0.02] = np.nan
    dx, dy = 1.5e-6, 2.5e-6
    surface = topo.HeightMap(h, dx, dy, periodic=periodic)
    i, j = np.nonzero(summit_mask(surface, neighbours=neighbours))
    nx, ny = h.shape
    z = h[i, j]
    zxx = (h[(i + 1) % nx, j] - 2 * z + h[(i - 1) % nx, j]) / dx**2
    zyy = (h[i, (j + 1) % ny] - 2 * z + h[i, (j - 1) % ny]) / dy**2
    stats = topo.summit_statistics(surface, neighbours=neighbours)
    assert stats.n_summits == z.size > 50
    candidates = candidate_pixels(h, periodic, neighbours)
    assert stats.n_candidates == candidates.sum() < nx * ny
    area = area_pixels(h, periodic, neighbours)
    assert candidates.sum() <= area.sum() < nx * ny
    assert stats.nominal_area == pytest.approx(area.sum() * dx * dy, rel=1e-14)
    assert stats.grid_area == pytest.approx(nx * dx * ny * dy, rel=1e-14)
    assert stats.asperity_density == pytest.approx(z.size / (area.sum() * dx * dy))
    assert stats.summit_height_rms == pytest.approx(np.std(z), rel=1e-10)
    assert stats.summit_radius == pytest.approx(
        np.mean(0.5 * (1 / np.abs(zxx) + 1 / np.abs(zyy))), rel=1e-12
    )
