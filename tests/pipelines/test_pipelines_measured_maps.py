"""[surface] preparation keys on real instrument files (tests/data, SurfaceTopography MIT
licence): the job's stage 1 is topo.prepare_surface, stated in the record the report shows."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from asperity.pipelines.config import ConfigError, config_from_dict
from asperity.pipelines.stages.surface import LevelledSurface, prepare

DATA = Path(__file__).resolve().parents[1] / "data"


def _surface(name, tmp_path, **keys):
    return config_from_dict({"surface": {"file": str(DATA / name), **keys}}, base_dir=tmp_path)


def test_metropro_spike_is_masked_and_filled_by_default(tmp_path):
    """metropro-1.dat holds one 638 nm spike in +-30 nm of roughness: the default 10 x MAD rule
    masks it and the harmonic fill closes the hole, so the map handed to the BEM is complete."""
    prepared = prepare(_surface("metropro-1.dat", tmp_path).surface)
    record = prepared.record
    assert record.n_outliers >= 1 and record.outlier_fraction < 1e-3
    assert record.missing_policy == "interpolate"
    assert not np.isnan(prepared.surface.heights).any()
    assert np.nanmax(prepared.surface.heights) < 0.2e-6  # the spike is gone
    stored = LevelledSurface.from_height_map(prepared.surface)
    assert stored.preparation["n_outliers"] == record.n_outliers


def test_form_order_wins_over_detrend_and_crop_is_applied(tmp_path):
    cfg = _surface("plu-1.plu", tmp_path, detrend="plane", form_order=2, crop=[10, 138, 0, 64])
    record = prepare(cfg.surface).record
    assert record.levelling == "quadratic" and record.form_order == 2
    assert (record.nx, record.ny) == (128, 64)
    # plu-1 is curved: a quadratic leaves less rms than a plane
    plane = prepare(_surface("plu-1.plu", tmp_path, crop=[10, 138, 0, 64]).surface).record
    assert record.roughness_rms < plane.roughness_rms


def test_refuse_names_the_key_on_a_map_with_holes(tmp_path):
    with pytest.raises(ConfigError, match=r"^surface\.missing: .*missing"):
        prepare(_surface("opd-1.opd", tmp_path, missing="refuse").surface)


def test_non_square_pixels_reach_the_record(tmp_path):
    record = prepare(_surface("x3p-2.x3p", tmp_path, crop=[0, 64, 0, 64]).surface).record
    assert record.dx == pytest.approx(1.277e-7, rel=1e-3)
    assert record.dy == pytest.approx(3.146e-7, rel=1e-3)
    assert any("non-square" in w for w in record.warnings)


def test_bad_surface_keys_refused_by_name(tmp_path):
    with pytest.raises(ConfigError, match=r"surface\.crop: expected \[x0, x1, y0, y1\]"):
        _surface("mi-1.mi", tmp_path, crop=[5, 5, 0, 10])
    with pytest.raises(ConfigError, match=r"surface\.outlier_threshold: expected a percentile"):
        _surface("mi-1.mi", tmp_path, outliers="percentile", outlier_threshold=60.0)
    with pytest.raises(ConfigError, match=r"surface\.missing: expected one of"):
        _surface("mi-1.mi", tmp_path, missing="keep")


@pytest.mark.slow
def test_scan_counts_summits_over_measured_pixels_only(tmp_path):
    """sur-3.sur is 89 % missing: the BEM gets the harmonic fill, but the resolution scan
    sees the filled pixels as missing again, so eta is per measured area, several times the
    value diluted over the smooth fill."""
    from asperity import topo

    stored = LevelledSurface.from_prepared(prepare(_surface("sur-3.sur", tmp_path).surface))
    assert stored.filled is not None and stored.filled.mean() > 0.85
    assert not np.isnan(stored.heights).any()  # complete for the BEM
    measured = stored.measured_height_map()
    assert np.isnan(measured.heights).mean() == pytest.approx(stored.filled.mean())
    valid = topo.resolution_scan(measured, 2).asperity_density[0]
    diluted = topo.resolution_scan(stored.height_map(), 2).asperity_density[0]
    assert valid > 3 * diluted
