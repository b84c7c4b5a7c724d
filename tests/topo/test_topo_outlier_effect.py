"""The outlier rule's effect is recorded on the rms height and warned by effect, not count."""

from __future__ import annotations

import numpy as np
import pytest

from asperity import topo


def _map(spikes: int, seed: int = 0) -> topo.HeightMap:
    rng = np.random.default_rng(seed)
    heights = rng.normal(size=(64, 64)) * 1e-7
    flat = heights.ravel()
    flat[rng.choice(flat.size, spikes, replace=False)] = 5e-6  # 50 sigma spikes
    return topo.HeightMap(heights, dx=1e-6, dy=1e-6)


def test_few_spikes_dominating_the_rms_are_warned_by_effect():
    # 2 pixels of 4096 (0.05 %, under the pixel-count warning) carry most of the variance
    record = topo.prepare_surface(_map(2)).record
    expected_before = np.std(_map(2).heights - _map(2).heights.mean())
    assert record.n_outliers == 2 and record.outlier_fraction < 1e-3
    assert record.rms_before_outliers == pytest.approx(expected_before, rel=0.02)
    # variance before = 1e-14 + 2 * (5e-6)^2 / 4096 m^2: the ratio is 1 / sqrt(1 + 1.22)
    assert record.outlier_rms_ratio == pytest.approx(
        1 / np.sqrt(1 + 2 * 25e-12 / 4096e-14), rel=0.05
    )
    assert any(w.startswith("outlier_effect") for w in record.warnings)


def test_gaussian_map_has_no_outlier_effect():
    record = topo.prepare_surface(_map(0)).record
    assert record.n_outliers == 0 and record.outlier_rms_ratio == 1.0
    assert not any(w.startswith("outlier_effect") for w in record.warnings)
