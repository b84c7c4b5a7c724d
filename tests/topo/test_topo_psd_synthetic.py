"""PSD normalisation (Parseval), rms descriptors and the synthetic generator."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity import topo
from asperity.topo.psd import psd_2d, radial_psd


@settings(max_examples=25, deadline=None)
@given(
    nx=st.integers(2, 33),
    ny=st.integers(2, 33),
    seed=st.integers(0, 2**16),
    dx=st.floats(1e-7, 1e-3),
    dy=st.floats(1e-7, 1e-3),
)
def test_parseval(nx, ny, seed, dx, dy):
    h = np.random.default_rng(seed).normal(size=(nx, ny)) * 1e-6
    surface = topo.HeightMap(h, dx, dy)
    _, _, psd = psd_2d(surface)
    area = nx * dx * ny * dy
    assert psd.sum() / area == pytest.approx(np.var(h), rel=1e-10)


def test_psd_of_a_single_wave_and_rms_descriptors():
    n, dx, amplitude, m = 128, 1e-6, 2e-6, 8
    x = np.arange(n) * dx
    k = 2 * math.pi * m / (n * dx)
    surface = topo.HeightMap(amplitude * np.sin(k * x)[:, None] * np.ones(n), dx, dx, True)
    radial = radial_psd(surface)
    peak = radial.q[np.argmax(radial.psd)]
    assert peak == pytest.approx(k, abs=0.5 * 2 * math.pi / (n * dx))  # within the bin
    assert topo.rms_height(surface) == pytest.approx(amplitude / math.sqrt(2), rel=1e-12)
    # forward differences of a sine: rms = A * 2 sin(k dx / 2) / dx / sqrt(2)
    slope = amplitude * 2 * math.sin(k * dx / 2) / dx / math.sqrt(2)
    assert topo.rms_slope(surface) == pytest.approx(slope, rel=1e-12)
    # central second differences: |h_xx| = A 4 sin^2(k dx/2)/dx^2; mean curvature halves it
    curvature = 0.5 * amplitude * 4 * math.sin(k * dx / 2) ** 2 / dx**2 / math.sqrt(2)
    assert topo.rms_curvature(surface) == pytest.approx(curvature, rel=1e-12)
    holes = np.array(surface.heights)
    holes[3, 3] = np.nan
    with pytest.raises(ValueError, match="missing"):
        radial_psd(topo.HeightMap(holes, dx, dx))


def test_synthetic_is_seeded_periodic_and_has_the_requested_spectrum():
    kwargs = dict(rms_height=3e-6, rolloff_wavelength=100e-6, hurst=0.7, seed=11)
    a = topo.synthetic.self_affine(256, 2e-6, **kwargs)
    b = topo.synthetic.self_affine(256, 2e-6, **kwargs)
    np.testing.assert_array_equal(a.heights, b.heights)
    assert a.periodic
    assert np.sqrt(np.mean(a.heights**2)) == pytest.approx(3e-6, rel=1e-12)
    assert not np.array_equal(
        a.heights, topo.synthetic.self_affine(256, 2e-6, **{**kwargs, "seed": 12}).heights
    )
    radial = radial_psd(a)
    power_law = (radial.q > 3 * 2 * math.pi / 100e-6) & (radial.q < 0.5 * math.pi / 2e-6)
    slope = np.polyfit(np.log(radial.q[power_law]), np.log(radial.psd[power_law]), 1)[0]
    assert slope == pytest.approx(-2 * (1 + 0.7), abs=0.15)
    assert topo.rolloff_wavelength(a) == pytest.approx(100e-6, rel=0.3)


def test_short_cutoff_removes_short_wavelengths():
    surface = topo.synthetic.self_affine(
        128, 1e-6, rms_height=1e-6, rolloff_wavelength=40e-6, short_cutoff=10e-6, seed=1
    )
    qx, qy, psd = psd_2d(surface)
    q = np.hypot(qx[:, None], qy[None, :])
    assert psd[q > 2 * math.pi / 10e-6 * 1.0001].max() < 1e-20 * psd.max()


def test_paper_like_keeps_physical_parameters_independent_of_n():
    small = topo.synthetic.paper_like(n=200, pixel_size=50e-6, seed=0)
    assert small.periodic and small.heights.shape == (200, 200)
    assert small.lx == pytest.approx(10e-3)
    assert np.sqrt(np.mean(small.heights**2)) == pytest.approx(50e-6, rel=1e-12)
    assert small.provenance["rolloff_wavelength"] == 600e-6
    assert topo.rolloff_wavelength(small) == pytest.approx(600e-6, rel=0.35)
    with pytest.raises(ValueError, match="hurst"):
        topo.synthetic.self_affine(16, 1e-6, rms_height=1e-6, rolloff_wavelength=1e-5, hurst=2.5)
    # the same physical surface on a finer grid: same roll-off and rms, cut-off 4 um kept
    fine = topo.synthetic.paper_like(n=256, pixel_size=1e-6, seed=0)
    assert fine.provenance["short_cutoff"] == 4e-6 and fine.lx == pytest.approx(256e-6)


def test_paper_like_reproduces_the_papers_density_and_its_scan_exponent():
    """Appendix A at 2 um and Fig 12(b) on a 5 mm patch of the preset (seed 0).

    Paper: eta = 652.1 mm^-2, R = 0.041 mm, eta ~ resolution^-1.12, R linear. The preset
    matches eta and the exponent; R is within a factor 2.6 (the best a Gaussian surface of
    rms 50 um and roll-off 600 um allows, see topo.synthetic.paper_like).
    """
    surface = topo.synthetic.paper_like(n=2500, seed=0)
    stats = topo.summit_statistics(surface)
    assert stats.asperity_density == pytest.approx(652.1e6, rel=0.1)
    assert 14e-6 < stats.summit_radius < 41e-6
    assert stats.summit_height_rms == pytest.approx(50e-6, rel=0.1)
    scan = topo.resolution_scan(surface, 130)
    assert scan.density_exponent == pytest.approx(-1.12, abs=0.15)
    fitted = scan.radius_slope * scan.resolution + scan.radius_intercept
    assert np.max(np.abs(fitted - scan.summit_radius)) < 0.25 * scan.summit_radius.max()
    assert scan.radius_slope > 2 and scan.height_rms_relative_spread < 0.2


def test_rms_slope_and_curvature_skip_missing_pixels_on_open_maps():
    rng = np.random.default_rng(3)
    h = rng.normal(size=(30, 20)) * 1e-6
    h[4, 5] = np.nan
    dx, dy = 1e-6, 2e-6
    surface = topo.HeightMap(h, dx, dy)
    gx = np.diff(h, axis=0)[:, :-1] / dx
    gy = np.diff(h, axis=1)[:-1, :] / dy
    assert topo.rms_slope(surface) == pytest.approx(np.sqrt(np.nanmean(gx**2 + gy**2)), rel=1e-12)
    c = h[1:-1, 1:-1]
    hxx = (h[2:, 1:-1] - 2 * c + h[:-2, 1:-1]) / dx**2
    hyy = (h[1:-1, 2:] - 2 * c + h[1:-1, :-2]) / dy**2
    expected = np.sqrt(np.nanmean((0.5 * (hxx + hyy)) ** 2))
    assert topo.rms_curvature(surface) == pytest.approx(expected, rel=1e-12)
    assert topo.rms_height(surface) == pytest.approx(np.nanstd(h), rel=1e-12)
    assert topo.rms_height(surface, about_mean=False) == pytest.approx(
        np.sqrt(np.nanmean(h**2)), rel=1e-12
    )
