"""Stages declared once: every result through the store, keys that depend on exactly what a
stage reads (and the package version), checksums on reuse, and the BEM switched off."""

from __future__ import annotations

import shutil

import h5py
import numpy as np
import pytest

import asperity
from asperity import statmodel
from asperity.fields import field_specs
from asperity.pipelines.engine.stage import DISABLED
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.job import STAGES, run_job
from asperity.pipelines.report import write_report
from asperity.statmodel.results_io import ARRAY_UNITS, SCALAR_UNITS
from tests._helpers import copied_run, planned_keys


def _assert_same(a, b, cls):
    for spec in field_specs(cls):
        x, y = getattr(a, spec.name), getattr(b, spec.name)
        if spec.kind == "array" and x is not None:
            x = np.asarray(x)
            np.testing.assert_array_equal(x, y, err_msg=spec.name)
            assert x.dtype == y.dtype, spec.name
        elif isinstance(x, float) and np.isnan(x):  # a NaN stored (no Hurst exponent) stays NaN
            assert isinstance(y, float) and np.isnan(y), spec.name
        else:
            assert x == y, spec.name


def test_every_stage_result_round_trips_with_units_and_dims(small_run):
    _, out, result = small_run
    store = ResultStore(out / "results.h5")
    results = {
        "surface": result.surface,
        "resolution_scan": result.resolution_scan,
        "bem_reference": result.bem_reference,
        "statistical_model": result.statistical_model,
        "mode_mixity": result.mode_mixity,
        "friction": result.friction,
        "psd": result.psd,
        "verdict": result.verdict,
    }
    with h5py.File(store.path, "r") as f:
        for stage in STAGES:
            if stage.name not in results:  # the line-profile realisations: disabled for a map
                continue
            _assert_same(results[stage.name], store.read(stage.name, stage.result), stage.result)
            group = f[stage.name]
            for spec in field_specs(stage.result):
                if spec.kind != "array" or getattr(results[stage.name], spec.name) is None:
                    continue
                ds = group[spec.name]
                assert ds.attrs["units"] == spec.units, (stage.name, spec.name)
                if ds.is_scale:
                    dims = (spec.name,)
                else:
                    dims = tuple(
                        h5py.h5ds.get_scale_name(ds.dims[i][0].id).decode() for i in range(ds.ndim)
                    )
                assert dims == spec.dims, (stage.name, spec.name)
    assert result.bem_reference.converged.dtype == bool


def test_friction_result_declares_every_shear_curve_field_with_its_units():
    """Stage 6 stores the ``asperity friction`` outputs under the same names and units."""
    from asperity.pipelines.stages.friction import FrictionPrediction

    specs = {s.name: s for s in field_specs(FrictionPrediction)}
    for name, units in ARRAY_UNITS.items():
        assert specs[name].units == units and specs[name].dims == ("normal_load", "step")
    for name, units in SCALAR_UNITS.items():
        assert specs[name].units == units and specs[name].dims == ("normal_load",)


_keys = planned_keys


def _changed(before, after):
    return {name for name in before if before[name] != after[name]}


def _edit(small, tmp_path, section, **values):
    data = small.data()
    data[section].update(values)
    return small(tmp_path, data)


ALL = {"surface", "resolution_scan", "bem_reference", "statistical_model", "mode_mixity"}
ALL = ALL | {"friction", "psd", "verdict"}


@pytest.mark.parametrize(
    ("section", "values", "changed"),
    [
        ("run", {"workers": 2}, set()),
        ("material", {"shear_strength": 0.2e6}, {"mode_mixity", "friction", "verdict"}),
        ("loading", {"steps": 61}, {"mode_mixity", "friction", "verdict"}),
        ("statmodel", {"area_tolerance": 1e-3}, {"friction", "verdict"}),
        ("bem", {"tol": 1e-7}, ALL - {"surface", "resolution_scan"}),
        ("surface", {"max_stride": 3}, ALL - {"surface", "bem_reference"}),
        ("loading", {"normal_loads": [1.0, 2.5]}, ALL - {"surface", "resolution_scan"}),
        (
            "material",
            {"equilibrium_distance": 0.3e-9},
            ALL - {"surface", "resolution_scan", "bem_reference"},
        ),
    ],
)
def test_a_key_changes_exactly_with_what_the_stage_reads(small, tmp_path, section, values, changed):
    assert _changed(_keys(small(tmp_path)), _keys(_edit(small, tmp_path, section, **values))) == (
        changed
    )


def test_the_lower_case_spelling_keys_the_same_stages(small, tmp_path):
    data = small.data()
    data["material"]["e_star"] = data["material"].pop("E_star")
    assert _keys(small(tmp_path, data)) == _keys(small(tmp_path))


def test_a_new_package_version_invalidates_every_stage(small, tmp_path):
    cfg = small(tmp_path)
    assert _changed(_keys(cfg, "1.0"), _keys(cfg, "1.1")) == ALL


def test_a_changed_measured_file_invalidates_the_stages_that_read_it(small, tmp_path):
    area = tmp_path / "area.csv"
    area.write_text("normal_load,real_area\n1,1e-6\n2,2e-6\n")
    data = small.data()
    data["measured"] = {"normal_area": "area.csv"}
    before = _keys(small(tmp_path, data))
    area.write_text("normal_load,real_area\n1,1e-6\n2,2.1e-6\n")
    after = _keys(small(tmp_path, data))
    assert _changed(before, after) == {
        "statistical_model",
        "mode_mixity",
        "friction",
        "psd",
        "verdict",
    }


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_version_change_recomputes_and_a_corrupted_stage_is_not_reused(
    small_run, tmp_path, monkeypatch
):
    cfg, out, _ = small_run
    copy = copied_run(out, tmp_path / "copy")
    with h5py.File(copy / "results.h5", "a") as f:
        f["friction/static_friction"][0] = 1e3  # a flipped value on disk
    again = run_job(cfg, copy)
    status = {s.name: s.status for s in again.stages}
    assert status == {
        **dict.fromkeys(ALL, "stored"),
        "friction": "computed",
        "realisations": "disabled",  # a line-profile stage; the small job is a map
        "bem_shear": "disabled",  # off without [bem_shear]
        "friction_tests": "disabled",  # the new stage 10, off without its section
    }
    assert "checksum" in next(s for s in again.stages if s.name == "friction").note
    assert again.friction.static_friction[0] < 10.0
    monkeypatch.setattr(asperity, "__version__", asperity.__version__ + ".post1")
    newer = run_job(cfg, copy)
    assert {s.status for s in newer.stages} == {"computed", "disabled"}


def _measured_area_csv(path, result, loads):
    """A measured A_r(F_z) the model makes at the small job's stride-2 statistics."""
    res = result.statistical_model
    roughness = statmodel.Roughness(
        float(result.resolution_scan.asperity_density[1]),
        float(result.resolution_scan.summit_radius[1]),
        float(result.resolution_scan.summit_height_rms[1]),
    )
    area = statmodel.real_area_at_loads(
        result.config.material, roughness, res.nominal_area, np.asarray(loads)
    )
    rows = "".join(f"{f!r},{float(a)!r}\n" for f, a in zip(loads, area, strict=True))
    path.write_text("normal_load,real_area\n" + rows)


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_bem_disabled_calibrates_on_the_measurement_alone(small, small_run, tmp_path):
    _, out, reference = small_run
    shutil.copytree(out, tmp_path / "out")
    _measured_area_csv(tmp_path / "area.csv", reference, [0.8, 1.6, 2.4, 3.2])
    data = small.data()
    data["bem"]["enabled"] = False
    data["measured"] = {"normal_area": "area.csv"}
    # replaces the finished small run in the folder, reusing its surface stages
    result = run_job(small(tmp_path, data), tmp_path / "out", replace_run=True)
    status = {s.name: s.status for s in result.stages}
    assert status["bem_reference"] == "disabled" and result.bem_reference is None
    assert status["surface"] == status["resolution_scan"] == "stored"
    res = result.statistical_model
    assert res.basis == "measured" and res.effective_stride == 2
    assert np.all(np.isnan(res.misfit_bem)) and res.misfit_measured[1] < 1e-6
    assert np.all(result.friction.converged)
    with h5py.File(tmp_path / "out" / "results.h5", "r") as f:
        assert "bem_reference" not in f  # the previous run's BEM is not left beside it
        assert "enabled = false" in f.attrs["config_toml"]
    report = write_report(result, tmp_path / "out").read_text()
    assert "enabled = false" in report and "| bem_reference | disabled |" in report
    assert "bem_grid.png" not in report


def test_disabled_key_is_not_a_hash(small, tmp_path):
    (tmp_path / "area.csv").write_text("normal_load,real_area\n1,1e-6\n2,2e-6\n")
    data = small.data()
    data["bem"]["enabled"] = False
    data["measured"] = {"normal_area": "area.csv"}
    keys = _keys(small(tmp_path, data))
    assert keys["bem_reference"] == DISABLED
    assert _keys(small(tmp_path))["bem_reference"] != DISABLED
