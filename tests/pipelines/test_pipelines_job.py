"""The whole job end to end on a small surface: outputs, units, resume, CLI exit status."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import asperity.pipelines.stages.bem as bem_module
import asperity.pipelines.stages.statistical_model as resolution_module
import asperity.pipelines.stages.surface as surface_module
from asperity.pipelines.config import config_from_dict
from asperity.pipelines.job import STAGE_NAMES, run_job
from asperity.pipelines.report import write_report

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


def _cached_first(n: int) -> list[bool]:
    """The stages' ``cached`` flags when the first ``n`` of the 11 are reused: the others run,
    or are disabled on a map (the line-profile realisations; the shear BEM without
    [bem_shear]; the friction tests without [measured] friction_curves), never cached."""
    return [k < n for k in range(11)]


def test_all_stages_ran_and_converged(small_run):
    _, out, result = small_run
    assert [s.name for s in result.stages] == list(STAGE_NAMES)
    assert not any(s.cached for s in result.stages)
    assert result.converged, result.problems()
    for name in (
        "report.md",
        "fig12_resolution.png",
        "fig13_area_vs_force.png",
        "fig4_shear.png",
        "surface.png",
        "bem_grid.png",
        "fig12d_misfit.png",
    ):
        assert (out / name).stat().st_size > 0
    report = (out / "report.md").read_text()
    assert "effective resolution" in report and "![" in report


def test_physics_of_the_outputs(small_run):
    _, _, result = small_run
    fr, bem, res = result.friction, result.bem_reference, result.statistical_model
    # real area grows with load, in the BEM and in the model at every resolution
    assert np.all(np.diff(bem.contact_fraction) > 0)
    finite = np.all(np.isfinite(res.real_area), axis=1)
    assert np.all(np.diff(res.real_area[finite], axis=1) > 0)
    # adhesion adds contact area at equal load
    assert np.all(bem.contact_fraction_adhesive >= bem.contact_fraction)
    # shear at constant normal load: F_z held, A_r shrinks, the static peak lies above
    # sliding, and both friction forces grow with the normal load
    np.testing.assert_allclose(
        fr.normal_force, np.broadcast_to(fr.normal_load[:, None], (3, 41)), rtol=1e-6
    )
    assert np.all(fr.real_area[:, -1] < fr.real_area[:, 0])
    assert np.all(fr.static_friction > fr.sliding_friction)
    assert np.all(np.diff(fr.static_friction) > 0) and np.all(np.diff(fr.sliding_friction) > 0)
    # the static friction is the continuous peak of F_x(delta_T): at or above every grid point,
    # and close to the grid maximum on this 41-step curve
    grid_peak = np.nanmax(fr.tangential_force, axis=1)
    assert np.all(fr.static_friction >= grid_peak * (1 - 1e-12))
    assert np.all(fr.static_friction <= grid_peak * 1.01)
    # stick and slip parts add up to the totals
    for name in ("tangential_force", "normal_force", "real_area"):
        np.testing.assert_allclose(
            getattr(fr, name + "_stick") + getattr(fr, name + "_slip"),
            getattr(fr, name),
            rtol=1e-9,
            atol=1e-12,
        )
    # at full sliding every junction carries tau0 times its area (E:Hertz_theory): the curve
    # ends on the constant-shear-strength line of Fig 13, at the sliding friction
    tau0 = result.config.material.shear_strength
    np.testing.assert_allclose(fr.tangential_force[:, -1], tau0 * fr.real_area[:, -1], rtol=1e-5)
    np.testing.assert_allclose(fr.sliding_friction, fr.tangential_force[:, -1], rtol=1e-5)
    # the effective resolution is the least misfit one
    assert res.index == int(np.nanargmin(res.misfit_bem))


def test_results_file_has_units_dims_and_provenance(small_run):
    cfg, out, result = small_run
    with h5py.File(out / "results.h5", "r") as f:
        ran = {s.name for s in result.stages if s.status != "disabled"}
        assert ran <= set(f) and ran >= set(STAGE_NAMES) - {
            "realisations",
            "bem_shear",
            "friction_tests",
        }
        assert f.attrs["input_sha256"] == result.input_sha256
        assert "[material]" in f.attrs["config_toml"]
        assert f.attrs["asperity_version"]
        n_datasets = 0

        def check(name, obj):
            nonlocal n_datasets
            if isinstance(obj, h5py.Dataset):
                n_datasets += 1
                assert "units" in obj.attrs, name
                assert "DIMENSION_LABELS" not in obj.attrs, name
                for axis in range(obj.ndim):
                    assert len(obj.dims[axis]) == 1 or obj.is_scale, (name, axis)

        f.visititems(check)
        assert n_datasets > 40
        fr = f["friction"]
        n_loads, steps = len(cfg.loading.normal_loads), cfg.loading.steps
        assert fr["tangential_force"].shape == (n_loads, steps)
        assert fr["tangential_force"].attrs["units"] == "N"
        assert fr["real_area"].attrs["units"] == "m^2"
        assert fr["tangential_displacement"].attrs["units"] == "m"
        assert f["surface/heights"].shape == (64, 64)
        assert f["surface/heights"].attrs["units"] == "m"
        scan = f["resolution_scan"]
        assert scan["summit_radius"].attrs["units"] == "m"
        assert scan["asperity_density"].attrs["units"] == "1/m^2"
        assert f["statistical_model/real_area"].shape == (len(scan["stride"]), n_loads)


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_resume_after_interruption_skips_finished_stages(tmp_path, monkeypatch, small):
    cfg = small(tmp_path)
    out = tmp_path / "out"
    calls = {"surface": 0, "bem": 0}
    real_read, real_bem = surface_module.prepare, bem_module.bem_reference

    def counting_read(*a, **k):
        calls["surface"] += 1
        return real_read(*a, **k)

    def counting_bem(*a, **k):
        calls["bem"] += 1
        return real_bem(*a, **k)

    def crash(*a, **k):
        raise KeyboardInterrupt("simulated interruption in stage 4")

    monkeypatch.setattr(surface_module, "prepare", counting_read)
    monkeypatch.setattr(bem_module, "bem_reference", counting_bem)
    monkeypatch.setattr(resolution_module, "statistical_model_scan", crash)
    with pytest.raises(KeyboardInterrupt):
        run_job(cfg, out)
    with h5py.File(out / "results.h5", "r") as f:  # readable, holding stages 1-3 only
        assert set(f) == {"surface", "resolution_scan", "bem_reference"}
    assert calls == {"surface": 1, "bem": 1}

    monkeypatch.undo()
    monkeypatch.setattr(surface_module, "prepare", counting_read)
    monkeypatch.setattr(bem_module, "bem_reference", counting_bem)
    result = run_job(cfg, out)
    assert calls == {"surface": 1, "bem": 1}  # not recomputed
    assert [s.cached for s in result.stages] == _cached_first(3)

    # a change of the loads recomputes the BEM and what follows, not the surface (the finished
    # run of the first loads is replaced on purpose: unasked it is refused)
    changed = config_from_dict(
        {
            **tomllib.loads(cfg.to_toml()),
            "loading": {
                **cfg.to_dict()["loading"],
                "normal_loads": [1.5, 2.5],
                "max_tangential_displacement": "auto",
            },
        },
        base_dir=tmp_path,
    )
    result = run_job(changed, out, replace_run=True)
    assert [s.cached for s in result.stages] == _cached_first(2)
    assert calls == {"surface": 1, "bem": 2}
    # --force recomputes everything
    result = run_job(changed, out, force=True)
    assert not any(s.cached for s in result.stages)
    assert calls == {"surface": 2, "bem": 3}


@pytest.mark.slow
def test_real_afm_file_through_the_job(tmp_path):
    """A real instrument file (Agilent PicoView .mi, 20 um AFM map, tests/data) runs through
    every stage; at the paper's loads its dense nm-scale asperities put the independent-
    asperity model outside its validity, which the job reports instead of hiding."""
    from pathlib import Path

    from asperity.pipelines.stages.surface import file_sha256

    path = Path(__file__).resolve().parents[1] / "data" / "mi-1.mi"
    data = {
        "surface": {"file": str(path), "max_stride": 4},
        "bem": {"max_stride": 2},
        "loading": {"steps": 21, "normal_loads": [1.0, 3.0]},
        "run": {"compute_all": True},  # PDMS on AFM is full contact: the early verdict would stop
    }
    cfg = config_from_dict(data, base_dir=tmp_path)
    result = run_job(cfg, tmp_path / "out")  # no Python warning: the verdict says it
    assert result.converged, result.problems()
    assert result.surface.lx == pytest.approx(20e-6, rel=0.02)
    assert result.input_sha256 == file_sha256(path)
    assert result.statistical_model.validity
    # PDMS on an AFM map: the elastic energy to flatten it is below w (Persson-Tosatti), so the
    # adhesion regime is the reason, in place of the junction coalescence it causes
    codes = result.verdict.codes
    assert result.verdict.verdict == "invalid" and "adhesion_full_contact" in codes
    assert "area_fraction" not in codes
    report = write_report(result, tmp_path / "out").read_text()
    assert "**Verdict: INVALID.**" in report
