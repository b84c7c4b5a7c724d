"""Asperity statistics from line profiles (Nayak's theory) against closed forms, counted
peaks, and the 2D summit statistics of the isotropic maps the profiles are cut from."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.topo.heightmap import LineProfile
from asperity.topo.nayak import (
    ISOTROPY_WARNING,
    SpectralMoments,
    count_peaks,
    nayak_statistics,
    profile_statistics,
    spectral_moments,
    summit_averages,
)
from asperity.topo.synthetic import self_affine


@pytest.mark.parametrize("alpha", [5.0, 20.0, 100.0])
def test_summit_averages_reproduce_nayaks_closed_forms(alpha):
    averages = summit_averages(alpha)
    # Nayak's D_sum: E[|det H|; summit] = 1/(3 sqrt 3) in units of m4 (the Monte Carlo's
    # noisiest average: measured within 0.7 %; eta itself uses the closed form)
    assert averages["density"] == pytest.approx(1 / (3 * math.sqrt(3)), rel=1.5e-2)
    # mean summit curvature (8/3) sqrt(m4/pi), independent of alpha
    assert averages["mean_curvature"] == pytest.approx(8 / (3 * math.sqrt(math.pi)), rel=5e-3)
    # McCool's summit-height variance (1 - 0.8968/alpha) m0 (his fit of Nayak's result)
    assert averages["height_rms"] ** 2 == pytest.approx(1 - 0.8968 / alpha, rel=1e-2)
    # mean summit height 4 sqrt(m0 / (pi alpha)) for large alpha
    if alpha >= 20:
        expected = 4 / math.sqrt(math.pi * alpha)
        assert averages["mean_height"] == pytest.approx(expected, rel=0.05)


def test_bandwidth_below_the_gaussian_bound_is_refused():
    with pytest.raises(InputError, match="alpha"):
        summit_averages(1.2)


@functools.cache
def isotropic_map(seed=3, cutoff=8e-6):
    return self_affine(
        1024,
        1e-6,
        rms_height=1e-6,
        rolloff_wavelength=200e-6,
        hurst=0.8,
        short_cutoff=cutoff,
        seed=seed,
    )


def map_profiles_moments(surface, stride=1):
    """Moments averaged over every 4th row and column of a map (its profiles)."""
    heights = np.asarray(surface.heights)
    moments = [
        spectral_moments(LineProfile(line, surface.dx), stride=stride)
        for grid in (heights, heights.T)
        for line in grid.T[::4]
    ]
    mean = {key: np.mean([getattr(m, key) for m in moments]) for key in ("m0", "m2", "m4")}
    return SpectralMoments(**mean, spacing=moments[0].spacing, n_slopes=0, n_curvatures=0)


@pytest.mark.parametrize("stride", [1, 2])
def test_profiles_cut_from_an_isotropic_map_give_its_8_neighbour_summit_statistics(stride):
    # measured on this map (alpha about 30): eta within 1 %, R within 2 %, sigma_s within 4 %
    surface = isotropic_map()
    nayak = nayak_statistics(map_profiles_moments(surface, stride))
    summits = topo.summit_statistics(surface, stride=stride, neighbours=8)
    assert nayak["asperity_density"] == pytest.approx(summits.asperity_density, rel=0.03)
    assert nayak["summit_radius"] == pytest.approx(summits.summit_radius, rel=0.04)
    assert nayak["summit_height_rms"] == pytest.approx(summits.summit_height_rms, rel=0.06)


def test_the_papers_4_neighbour_rule_counts_more_summits_than_the_theory():
    # the 4-neighbour rule also counts saddles whose descending directions are diagonal:
    # measured 1.31-1.36 times Nayak's density and R 1.15-1.19 times on these maps
    surface = isotropic_map()
    nayak = nayak_statistics(map_profiles_moments(surface))
    summits = topo.summit_statistics(surface, neighbours=4)
    assert 1.2 < summits.asperity_density / nayak["asperity_density"] < 1.45
    assert 1.05 < summits.summit_radius / nayak["summit_radius"] < 1.3


def test_peaks_counted_on_a_profile_follow_nayaks_peak_density():
    surface = isotropic_map(seed=8)
    heights = np.asarray(surface.heights)
    counted = expected = 0.0
    for line in heights.T[::8]:
        profile = LineProfile(line, surface.dx)
        moments = spectral_moments(profile)
        counted += count_peaks(profile)
        expected += math.sqrt(moments.m4 / moments.m2) / (2 * math.pi) * profile.lx
    assert counted == pytest.approx(expected, rel=0.03)


def test_every_result_states_the_isotropy_assumption_and_its_status():
    line = np.asarray(isotropic_map().heights)[:, 0]
    stats = profile_statistics(LineProfile(line, 1e-6))
    assert stats.warnings[0] == ISOTROPY_WARNING
    assert stats.method == "nayak-profile"
    assert (stats.success, stats.status, stats.message) == (True, 0, "valid")


def test_white_noise_is_flagged_and_an_alternating_profile_has_no_summit_statistics():
    noise = LineProfile(np.random.default_rng(1).normal(size=20000) * 1e-7, 1e-6)
    stats = profile_statistics(noise)
    assert stats.bandwidth == pytest.approx(1.5, rel=0.03)  # m0 m4 / m2^2 of white noise
    assert stats.status >= 1 and "alpha" in stats.message
    zigzag = LineProfile(np.tile([1e-7, -1e-7], 50), 1e-6)
    stats = profile_statistics(zigzag)
    assert stats.status == 2 and not stats.success
    assert math.isnan(stats.summit_radius) and math.isnan(stats.summit_height_rms)


def test_flat_profile_and_too_large_stride_are_refused():
    with pytest.raises(InputError, match="flat"):
        profile_statistics(LineProfile(np.zeros(50), 1e-6))
    with pytest.raises(InputError, match="stride 30"):
        profile_statistics(LineProfile(np.arange(50.0) * 1e-9, 1e-6), stride=30)


def test_missing_points_leave_the_moments_of_the_rest():
    line = np.asarray(isotropic_map().heights)[:, 5].copy()
    full = spectral_moments(LineProfile(line, 1e-6))
    line[100:110] = np.nan
    holes = spectral_moments(LineProfile(line, 1e-6))
    assert holes.n_curvatures == full.n_curvatures - 12
    assert holes.m4 == pytest.approx(full.m4, rel=0.05)
