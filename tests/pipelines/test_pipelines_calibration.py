"""The job against measurements: effective resolution and lambda recovered from data the
model made; loads below pull-off refused before the BEM; CLI exit status; parallel runs."""

from __future__ import annotations

import numpy as np
import pytest

import asperity.pipelines.stages.bem as bem_module
from asperity import statmodel
from asperity.pipelines.cli import main
from asperity.pipelines.config import ConfigError, config_from_dict, preset_text
from asperity.pipelines.job import run_job
from asperity.pipelines.measured import NormalAreaCurve, write_shear_area
from asperity.pipelines.stages._pull_off import roughness_from_scan
from asperity.pipelines.stages.statistical_model import material_from_config
from asperity.pipelines.stages.surface import read_and_level, scan_resolutions
from tests._helpers import area_to_peak, sampled_area_curves, shear_area_model, small_data


def _measured_areas_at_stride_3(data: dict, tmp_path) -> tuple:
    """area.csv in ``tmp_path``: A_r(F_z) (m^2 at N) the model makes at the roughness of
    stride 3 of the job's map; the material, that roughness and A_n (m^2)."""
    cfg = config_from_dict(data, base_dir=tmp_path)
    scan = scan_resolutions(read_and_level(cfg.surface), cfg.surface.max_stride)
    truth = roughness_from_scan(scan, 2)  # stride 3
    material = material_from_config(cfg.material)
    a_n = cfg.loading.nominal_area
    loads = np.array([0.8, 1.6, 2.4, 3.2])
    area = statmodel.real_area_at_loads(material, truth, a_n, loads)
    (tmp_path / "area.csv").write_text(
        "normal_load,real_area\n"
        + "".join(f"{float(f)!r},{float(a)!r}\n" for f, a in zip(loads, area, strict=True))
    )
    return material, truth, a_n


def _calibrated_on_stride_3(data: dict, tmp_path):
    """The job on the measurements of ``data`` alone (no BEM): it picks stride 3 and the model
    reproduces its own data there; returns the job's result."""
    data["bem"]["enabled"] = False  # the measurement alone calibrates (no BEM needed)
    result = run_job(config_from_dict(data, base_dir=tmp_path), tmp_path / "out")
    res = result.statistical_model
    assert res.basis == "measured"
    assert res.effective_stride == 3
    assert res.misfit_measured[2] < 1e-6  # the model reproduces its own data
    return result


def test_effective_resolution_recovered_from_measured_areas(tmp_path):
    """Measured A_r(F_z) made by the model at stride 3 (no shear curves: lambda configured):
    the job picks stride 3 and reproduces its own data (the default-run share of the slow
    test below; the lambda recovery itself: tests/pipelines/test_pipelines_measured_curves)."""
    data = small_data()
    _measured_areas_at_stride_3(data, tmp_path)
    data["measured"] = {"normal_area": "area.csv"}
    result = _calibrated_on_stride_3(data, tmp_path)
    lam = result.mode_mixity
    assert not lam.fitted and lam.mode_mixity == data["material"]["mode_mixity"]


@pytest.mark.slow  # about 5 s (three lambda fits in the job); the default run stays < 3 min
def test_effective_resolution_and_lambda_recovered_from_measurements(tmp_path):
    """Measured A_r(F_z) made by the model at stride 3 and A_r(F_x) made with lambda = 0.1
    (1 % noise): the job picks stride 3 and fits lambda within its uncertainty."""
    data = small_data()
    material, truth, a_n = _measured_areas_at_stride_3(data, tmp_path)
    rng = np.random.default_rng(0)
    peaks = area_to_peak(shear_area_model(material, truth, a_n, 81), 0.1, (1.0, 3.0))
    curves = sampled_area_curves(peaks, (1.0, 3.0), 25, 0.95, noise=0.01, rng=rng)
    write_shear_area(tmp_path / "shear.csv", curves)
    data["measured"] = {"normal_area": "area.csv", "shear_area": "shear.csv"}
    data["fit"] = {"mode_mixity_bounds": [1e-3, 1.0]}
    result = _calibrated_on_stride_3(data, tmp_path)
    lam = result.mode_mixity
    assert lam.fitted and lam.fit.success
    # this draw (seed 0) lies 3.0 profile-sigma off in both fit modes (seeds 1, 2: 0.7, 0.1)
    assert abs(lam.mode_mixity - 0.1) < 4 * lam.fit.mode_mixity_std
    assert lam.fit.mode_mixity_std < 0.03
    assert result.friction.mode_mixity == lam.mode_mixity


def test_load_below_pull_off_refused_before_bem(tmp_path, monkeypatch):
    # with the BEM a load <= 0 is refused at validation (its non-adhesive sweep needs a
    # compressive load); without it, the pull-off bound is checked after the resolution scan
    with pytest.raises(ConfigError, match=r"loading\.normal_loads: expected loads > 0 N"):
        config_from_dict(small_data(normal_loads=[-1e3, 1.0]), base_dir=tmp_path)
    (tmp_path / "area.csv").write_text("normal_load,real_area\n1.0,1e-6\n2.0,2e-6\n")
    data = small_data(normal_loads=[-1e3, 1.0])
    data["bem"]["enabled"] = False
    data["measured"] = {"normal_area": "area.csv"}
    cfg = config_from_dict(data, base_dir=tmp_path)

    def no_bem(*a, **k):
        raise AssertionError("the BEM must not run")

    monkeypatch.setattr(bem_module, "bem_reference", no_bem)
    refused = r"loading\.normal_loads: expected .* pull-off .*got -1000 N"
    with pytest.raises(ConfigError, match=refused):
        run_job(cfg, tmp_path / "out")
    assert not (tmp_path / "out" / "results.h5").exists()  # a refused config writes nothing


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_cli_exit_1_when_a_solver_did_not_converge(tmp_path, capsys):
    data = small_data()
    data["bem"]["max_iter"] = 1  # the BEM cannot converge in one iteration
    text = preset_text("default")
    path = tmp_path / "job.toml"
    path.write_text(
        text.replace("[bem]\n", "[bem]\nmax_iter = 1\n")
        .replace("n = 1000 ", "n = 64 ")
        .replace("pixel_size = 10e-6 ", "pixel_size = 40e-6 ")
        .replace("max_stride = 26 ", "max_stride = 4 ")
        .replace("steps = 201", "steps = 21")
    )
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert status == 1
    assert "NOT CONVERGED" in out
    assert (tmp_path / "out" / "report.md").exists()  # everything still written
    assert "Not converged" in (tmp_path / "out" / "report.md").read_text()


def _compare(a, b):
    np.testing.assert_allclose(
        a.bem_reference.contact_fraction, b.bem_reference.contact_fraction, rtol=1e-12
    )
    np.testing.assert_allclose(
        a.statistical_model.real_area, b.statistical_model.real_area, rtol=1e-12
    )
    for name in ("tangential_force", "real_area"):
        np.testing.assert_allclose(getattr(a.friction, name), getattr(b.friction, name), rtol=1e-12)


@pytest.mark.slow
def test_parallel_runs_match_serial(tmp_path):
    """Two worker processes, and a dask.distributed cluster, give the serial numbers."""
    distributed = pytest.importorskip("distributed")
    cfg = config_from_dict(small_data(), base_dir=tmp_path)
    serial = run_job(cfg, tmp_path / "serial")
    pooled = run_job(cfg, tmp_path / "pool", workers=2)
    _compare(serial, pooled)
    # two threads in one worker process: the BEM lock keeps concurrent solves correct
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        with distributed.Client(cluster) as client:
            on_dask = run_job(cfg, tmp_path / "dask", scheduler=client)
    _compare(serial, on_dask)


def test_model_outside_validity_warns():
    """Dense, blunt asperities (an AFM-scale map under the paper's loads) give A_r/A_n > 1 in
    the independent-asperity model: the stage warns and the result says why."""
    from types import SimpleNamespace

    from asperity.pipelines.stages.statistical_model import (
        ModelValidityWarning,
        statistical_model_scan,
    )

    scan = SimpleNamespace(
        stride=np.array([1, 2]),
        resolution=np.array([2e-7, 4e-7]),
        asperity_density=np.array([2e12, 6e11]),
        summit_radius=np.array([1.5e-5, 3e-5]),
        summit_height_rms=np.array([6e-9, 5e-9]),
    )
    material = statmodel.Material(2.133e6, 0.040, 0.03, 0.13e6, 0.2e-9)
    measured = NormalAreaCurve(np.array([1.0, 2.0]), np.array([1e-4, 2e-4]))
    with pytest.warns(ModelValidityWarning, match="outside its validity"):
        choice = statistical_model_scan(scan, material, 700e-6, [1.0, 2.0], measured=measured)
    assert choice.validity and "A_r/A_n up to" in choice.validity[0]
    assert np.nanmax(choice.real_area[choice.index]) / 700e-6 > 1
