"""Surface preparation: form removal, harmonic fill, outlier rule, crop, record and warnings."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity import topo
from asperity.errors import InputError
from asperity.topo.form import subtract_polynomial

DATA = Path(__file__).resolve().parents[1] / "data"
REAL_MAPS = [
    "di-3.di",
    "metropro-1.dat",
    "mi-1.mi",
    "opd-1.opd",
    "plu-1.plu",
    "sur-3.sur",
    "x3p-2.x3p",
]


def coordinates(nx, ny, dx=1e-6, dy=2.5e-6):
    return np.arange(nx)[:, None] * dx, np.arange(ny)[None, :] * dy


@settings(max_examples=25, deadline=None)
@given(
    shape=st.tuples(st.integers(3, 30), st.integers(3, 30)),
    fraction=st.floats(0.0, 0.9),
    slope=st.tuples(st.floats(-1, 1), st.floats(-1, 1)),
    seed=st.integers(0, 2**16),
)
def test_harmonic_fill_is_exact_on_planes(shape, fraction, slope, seed):
    x, y = coordinates(*shape)
    plane = 2e-6 + slope[0] * x + slope[1] * y
    holes = np.random.default_rng(seed).random(shape) < fraction
    holes[0, 0] = holes[0, -1] = holes[-1, 0] = False  # the valid pixels determine the plane
    filled = topo.harmonic_fill(np.where(holes, np.nan, plane), 1e-6, 2.5e-6)
    scale = np.abs(plane).max()
    np.testing.assert_allclose(filled, plane, rtol=0, atol=1e-12 * scale)
    line = np.full(shape, np.nan)
    line[1, :2] = 3e-6  # two valid pixels determine no plane: the fill is their mean
    np.testing.assert_allclose(topo.harmonic_fill(line, 1e-6, 1e-6), 3e-6, rtol=1e-12)


def test_harmonic_fill_obeys_the_maximum_principle_and_keeps_valid_pixels():
    rough = topo.synthetic.paper_like(n=128, pixel_size=20e-6, seed=2).heights
    heights = np.array(rough)
    heights[40:70, 50:90] = np.nan  # one interior hole
    heights[:5, :12] = np.nan  # one at the corner
    filled = topo.harmonic_fill(heights, 20e-6, 20e-6)
    valid = ~np.isnan(heights)
    np.testing.assert_array_equal(filled[valid], heights[valid])
    rim = np.concatenate(
        [heights[39, 49:91], heights[70, 49:91], heights[39:71, 49], heights[39:71, 90]]
    )
    inside = filled[40:70, 50:90]
    assert rim.min() - 1e-18 <= inside.min() and inside.max() <= rim.max() + 1e-18
    # a harmonic fill of the hole holds no summit strictly inside it
    inner = topo.HeightMap(filled[41:69, 51:89], 20e-6, 20e-6)
    assert topo.summit_statistics(inner).n_summits == 0


def test_polynomial_form_removes_polynomials_of_its_order_exactly_over_valid_pixels():
    u, v = np.meshgrid(np.linspace(-1, 1, 50), np.linspace(-1, 1, 40), indexing="ij")
    rng = np.random.default_rng(3)
    rough = rng.normal(scale=1e-8, size=u.shape)
    rough[rng.random(u.shape) < 0.1] = np.nan
    for order in range(5):
        form = sum(
            rng.normal(scale=1e-6) * u**p * v**q
            for p in range(order + 1)
            for q in range(order + 1 - p)
        )
        base = subtract_polynomial(rough, order).heights
        formed = subtract_polynomial(rough + form, order).heights
        np.testing.assert_allclose(formed, base, atol=1e-15)
        if order:
            assert subtract_polynomial(rough + form, order).form_rms > 1e-8
    quadratic = topo.level(topo.HeightMap(rough, 1e-6, 1e-6), "quadratic").heights
    np.testing.assert_allclose(topo.level(topo.HeightMap(rough, 1e-6, 1e-6), 2).heights, quadratic)
    with pytest.raises(InputError, match="order"):
        topo.level(topo.HeightMap(rough, 1e-6, 1e-6), 9)


def real(name):
    return topo.read_surface(DATA / name)


def test_default_outlier_rule_catches_the_metropro_spike():
    surface = real("metropro-1.dat")
    levelled = topo.level(surface, "plane").heights
    spike = np.unravel_index(
        np.nanargmax(np.abs(levelled - np.nanmedian(levelled))), levelled.shape
    )
    assert abs(levelled[spike]) > 500e-9  # the 638 nm spike, everything else within +-60 nm
    prepared = topo.prepare_surface(surface)
    assert prepared.outlier_mask[spike] and 1 <= prepared.record.n_outliers <= 20
    assert np.nanmax(np.abs(prepared.surface.heights)) < 100e-9
    clipped = topo.prepare_surface(
        surface, topo.PreparationOptions(outliers=topo.OutlierRule("mad", 10, "clip"))
    )
    record = clipped.record
    bound = record.outlier_low if levelled[spike] < 0 else record.outlier_high
    assert clipped.surface.heights[spike] == pytest.approx(bound, rel=1e-6)
    assert record.n_outliers == prepared.record.n_outliers and clipped.surface.n_missing == 0


@pytest.mark.parametrize("name", REAL_MAPS)
def test_default_outlier_rule_changes_well_under_a_thousandth_of_every_real_map(name):
    record = topo.prepare_surface(real(name)).record
    assert record.outlier_fraction < 5e-4
    assert not any("outlier" in w for w in record.warnings)


def test_outlier_rule_leaves_a_gaussian_map_alone_and_percentiles_change_their_share():
    surface = topo.HeightMap(np.random.default_rng(1).normal(size=(300, 300)) * 1e-7, 1e-6, 1e-6)
    assert topo.find_outliers(surface.heights, topo.OutlierRule()).count == 0
    found = topo.find_outliers(surface.heights, topo.OutlierRule("percentile", 0.5))
    assert found.count == pytest.approx(0.01 * surface.heights.size, rel=0.02)
    flat = np.zeros((20, 20))
    flat[5, 5] = 1e-6
    unlevelled = topo.PreparationOptions(form_order=None)
    record = topo.prepare_surface(topo.HeightMap(flat, 1e-6, 1e-6), unlevelled).record
    assert record.n_outliers == 0 and any("MAD" in w for w in record.warnings)
    for bad in ("mad:-1", "percentile", "percentile:60", "median:3"):
        with pytest.raises(InputError, match="outlier|--outliers"):
            topo.OutlierRule.parse(bad)


def test_missing_policies_and_their_record():
    surface = real("opd-1.opd")
    n_missing = surface.n_missing
    assert 0 < n_missing < 1000
    with pytest.raises(InputError, match=r"opd-1.opd: \d+ of 307200 pixels .* 'refuse'"):
        topo.prepare_surface(surface, topo.PreparationOptions(missing="refuse"))
    kept = topo.prepare_surface(surface).record
    assert (kept.n_missing, kept.n_filled) == (n_missing, 0)
    assert kept.n_missing_left == n_missing + kept.n_outliers
    assert kept.missing_fraction == pytest.approx(n_missing / 307200)
    for policy in ("fill-lowest", "interpolate"):
        prepared = topo.prepare_surface(surface, topo.PreparationOptions(missing=policy))
        assert prepared.surface.n_missing == 0
        assert prepared.record.n_filled == n_missing + prepared.record.n_outliers
        assert prepared.filled_mask.sum() == prepared.record.n_filled
    lowest = topo.prepare_surface(surface, topo.PreparationOptions(missing="fill-lowest"))
    heights = lowest.surface.heights
    assert np.all(heights[lowest.filled_mask] == heights.min())


def test_crop_in_pixels_and_metres_and_refusals():
    surface = topo.synthetic.paper_like(n=64, pixel_size=10e-6, seed=1)
    by_pixels = topo.crop_surface(surface, topo.CropWindow.parse("10:50,:40"))
    by_metres = topo.crop_surface(surface, topo.CropWindow.parse("100e-6:500e-6,0:400e-6", "m"))
    np.testing.assert_array_equal(by_pixels.heights, surface.heights[10:50, :40])
    np.testing.assert_array_equal(by_metres.heights, by_pixels.heights)
    assert not by_pixels.periodic and by_pixels.provenance["crop"] == [10, 50, 0, 40]
    for text, unit in (
        ("0:65,0:10", "px"),
        ("5:5,0:10", "px"),
        ("0:2,0:10", "px"),
        ("0:1e-3,:", "m"),
    ):
        with pytest.raises(InputError, match="crop"):
            topo.crop_surface(surface, topo.CropWindow.parse(text, unit))
    record = topo.prepare_surface(
        surface, topo.PreparationOptions(crop=topo.CropWindow.parse("10:50,:40"))
    ).record
    assert record.crop == (10, 50, 0, 40) and (record.nx, record.ny) == (40, 40)


def rough_open_map(n=200, seed=4):
    surface = topo.synthetic.paper_like(n=n, pixel_size=20e-6, seed=seed)
    return topo.HeightMap(np.array(surface.heights), 20e-6, 20e-6)


def test_warnings_name_what_dominates():
    surface = rough_open_map(100)
    x, y = coordinates(100, 100, 20e-6, 20e-6)
    tilted = surface.with_heights(surface.heights + 2.0 * x + 1.0 * y)
    record = topo.prepare_surface(tilted, topo.PreparationOptions(form_order=None)).record
    assert any("a plane fit would remove" in w and "tilt" in w for w in record.warnings)
    record = topo.prepare_surface(tilted).record
    assert record.form_to_roughness > 10 and any(
        "times the remaining" in w for w in record.warnings
    )
    assert not any("tilt" in w for w in record.warnings)
    holes = np.array(surface.heights)
    holes[:30] = np.nan
    non_square = topo.HeightMap(holes, 20e-6, 25e-6)
    messages = " ".join(topo.prepare_surface(non_square).record.warnings)
    assert "30.0 % of the pixels are missing" in messages and "non-square pixels" in messages
    assert topo.prepare_surface(surface).record.warnings == ()


def punch_disks(heights, fraction, radius, seed):
    rng = np.random.default_rng(seed)
    out = np.array(heights)
    i, j = np.indices(out.shape)
    while np.isnan(out).mean() < fraction:
        ci, cj = rng.integers(0, out.shape[0]), rng.integers(0, out.shape[1])
        out[(i - ci) ** 2 + (j - cj) ** 2 <= radius**2] = np.nan
    return out


@pytest.mark.parametrize("fraction", [0.1, 0.3])
def test_eta_with_holes_stays_within_sampling_error_of_the_complete_map(fraction):
    surface = rough_open_map(400)
    complete = topo.summit_statistics(surface)
    holed = topo.summit_statistics(
        surface.with_heights(punch_disks(surface.heights, fraction, 8, 1))
    )
    sampling = 3 / math.sqrt(holed.n_summits)  # 3 sigma of a Poisson count
    assert holed.asperity_density == pytest.approx(complete.asperity_density, rel=sampling)
    assert holed.valid_fraction < 1 - fraction  # the holes and their rims are left out
    # the whole-area rule would have been off by about the missing fraction
    whole_area = holed.n_summits / holed.grid_area
    assert abs(whole_area / complete.asperity_density - 1) > 2 * sampling


def test_eta_of_sur3_is_over_its_measured_area():
    surface = topo.level(real("sur-3.sur"), "plane")
    assert surface.n_missing / (surface.nx * surface.ny) > 0.88
    stats = topo.summit_statistics(surface)
    assert stats.valid_fraction < 0.11
    assert stats.asperity_density == pytest.approx(stats.n_summits / stats.nominal_area)
    assert stats.asperity_density > 8 * stats.n_summits / stats.grid_area
    scan = topo.resolution_scan(surface, 3)
    np.testing.assert_allclose(scan.asperity_density, scan.n_summits / scan.nominal_area)
