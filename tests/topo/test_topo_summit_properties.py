"""Property tests of the Appendix A summit statistics (hypothesis).

Heights are small integers times 2^-20 m, so that adding a constant, scaling by a power of
two, transposing or tiling changes no comparison and no difference through rounding: the
properties then hold exactly (N) or to rounding of the final averages (R, sigma_s).

Speed: maps of 3..10 pixels per side reach every configuration that matters (edges, corners,
NaN beside a summit, wrap-around) and keep the default run short; ``THOROUGH=1`` in the
environment multiplies the number of examples by 5 (``THOROUGH=1 pytest -m slow`` is not
needed: the same tests run, only longer).
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from asperity import topo
from asperity.topo.summits import summit_mask

UNIT = 2.0**-20  # m
SCALE = 5 if os.environ.get("THOROUGH") else 1


def examples(n: int) -> settings:
    """Hypothesis settings with ``n`` examples (times 5 with THOROUGH=1), no deadline."""
    return settings(max_examples=n * SCALE, deadline=None)


maps = arrays(
    np.float64,
    st.tuples(st.integers(3, 10), st.integers(3, 10)),
    elements=st.one_of(st.integers(-40, 40).map(lambda k: k * UNIT), st.just(np.nan)),
).filter(lambda h: not np.isnan(h).all())

spacings = st.sampled_from([0.5e-6, 1e-6, 2e-6, 3e-6])


def same_statistics(a, b, *, radius_factor=1.0, height_factor=1.0):
    assert a.n_summits == b.n_summits and a.n_candidates == b.n_candidates
    if a.n_candidates == 0:  # no pixel could host a summit: eta is undefined
        assert math.isnan(a.asperity_density) and math.isnan(b.asperity_density)
    else:
        assert a.asperity_density == pytest.approx(b.asperity_density, rel=1e-14)
    if a.n_summits == 0:
        assert math.isnan(b.summit_radius) and math.isnan(b.summit_height_rms)
        return
    assert b.summit_radius == pytest.approx(a.summit_radius * radius_factor, rel=1e-12)
    assert b.summit_height_rms == pytest.approx(
        a.summit_height_rms * height_factor, rel=1e-9, abs=1e-9 * UNIT
    )


@examples(40)
@given(
    h=maps,
    dx=spacings,
    dy=spacings,
    periodic=st.booleans(),
    shift=st.integers(-1000, 1000),
    power=st.integers(-6, 6),
)
def test_invariant_under_a_constant_and_a_positive_scale(h, dx, dy, periodic, shift, power):
    base = topo.summit_statistics(topo.HeightMap(h, dx, dy, periodic))
    shifted = topo.summit_statistics(topo.HeightMap(h + shift * UNIT, dx, dy, periodic))
    same_statistics(base, shifted)
    if base.n_summits:
        assert shifted.mean_summit_height == pytest.approx(
            base.mean_summit_height + shift * UNIT, rel=1e-12, abs=1e-12
        )
    factor = 2.0**power  # exact scaling: R scales as 1/factor, sigma_s as factor
    scaled = topo.summit_statistics(topo.HeightMap(h * factor, dx, dy, periodic))
    same_statistics(base, scaled, radius_factor=1 / factor, height_factor=factor)


@examples(30)
@given(h=maps, factor=st.floats(0.1, 10.0))
def test_any_positive_scale_keeps_the_summits_and_scales_r(h, factor):
    base = topo.summit_statistics(topo.HeightMap(h, 1e-6, 1e-6))
    scaled = topo.summit_statistics(topo.HeightMap(h * factor, 1e-6, 1e-6))
    same_statistics(base, scaled, radius_factor=1 / factor, height_factor=factor)


@examples(40)
@given(h=maps, dx=spacings, dy=spacings, periodic=st.booleans(), neighbours=st.sampled_from([4, 8]))
def test_transposition_and_flips(h, dx, dy, periodic, neighbours):
    base = topo.summit_statistics(topo.HeightMap(h, dx, dy, periodic), neighbours=neighbours)
    # transposing swaps the axes, so dx and dy swap with them: nothing changes
    transposed = topo.HeightMap(h.T, dy, dx, periodic)
    same_statistics(base, topo.summit_statistics(transposed, neighbours=neighbours))
    for flipped in (h[::-1], h[:, ::-1]):
        surface = topo.HeightMap(flipped, dx, dy, periodic)
        same_statistics(base, topo.summit_statistics(surface, neighbours=neighbours))


@examples(30)
@given(h=maps, spacing=spacings)
def test_square_pixels_transposition_keeps_eta_and_r(h, spacing):
    a = topo.summit_statistics(topo.HeightMap(h, spacing, spacing))
    b = topo.summit_statistics(topo.HeightMap(h.T, spacing, spacing))
    same_statistics(a, b)


@examples(30)
@given(h=maps, neighbours=st.sampled_from([4, 8]))
def test_periodic_wrap_equals_the_centre_of_a_tiled_open_map(h, neighbours):
    nx, ny = h.shape
    periodic = summit_mask(topo.HeightMap(h, 1e-6, 1e-6, periodic=True), neighbours=neighbours)
    tiled = summit_mask(topo.HeightMap(np.tile(h, (3, 3)), 1e-6, 1e-6), neighbours=neighbours)
    np.testing.assert_array_equal(periodic, tiled[nx : 2 * nx, ny : 2 * ny])
    stats = topo.summit_statistics(
        topo.HeightMap(h, 1e-6, 1e-6, periodic=True), neighbours=neighbours
    )
    assert stats.n_summits == periodic.sum()


@examples(30)
@given(
    h=arrays(
        np.float64,
        st.tuples(st.integers(6, 24), st.integers(6, 24)),
        elements=st.integers(-40, 40).map(lambda k: k * UNIT),
    ),
    a=st.integers(1, 4),
    b=st.integers(1, 4),
    periodic=st.booleans(),
)
def test_decimation_identities(h, a, b, periodic):
    surface = topo.HeightMap(h, 1e-6, 2e-6, periodic)
    twice = topo.decimate(topo.decimate(surface, a), b)
    once = topo.decimate(surface, a * b)
    np.testing.assert_array_equal(twice.heights, once.heights)
    np.testing.assert_array_equal(once.heights, h[:: a * b, :: a * b])
    assert (once.dx, once.dy) == pytest.approx((a * b * 1e-6, a * b * 2e-6), rel=1e-15)
    assert once.periodic == (periodic and h.shape[0] % (a * b) == 0 and h.shape[1] % (a * b) == 0)
    if min(once.heights.shape) >= 3:
        direct = topo.summit_statistics(surface, stride=a * b)
        same_statistics(direct, topo.summit_statistics(once))
        assert direct.stride == a * b and direct.dx == once.dx
