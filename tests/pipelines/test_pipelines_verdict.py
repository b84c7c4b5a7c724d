"""The validity verdict: each code triggered by a minimal case; a real map ends invalid with
exit status 3; the report and the summary say so at the top and mark the numbers."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.errors import ExitStatus
from asperity.pipelines.stages import verdict as v

DATA = Path(__file__).resolve().parents[1] / "data"


def _codes(reasons):
    return {(r.code, r.severity) for r in reasons}


def test_area_fraction_thresholds():
    assert v.check_area_fraction(np.array([0.01, 0.05]), "model") == []
    assert _codes(v.check_area_fraction(np.array([0.02, 0.12]), "model")) == {
        ("area_fraction", "warning")
    }
    (reason,) = v.check_area_fraction(np.array([0.3, np.nan]), "the measured")
    assert reason.severity == "invalid"
    assert "0.3 > 0.15" in reason.text and "Section 5" in reason.text


def test_tabor_below_five_is_invalid():
    assert v.check_tabor(5.0) == []
    (reason,) = v.check_tabor(2.6)
    assert (reason.code, reason.severity) == ("tabor", "invalid")
    assert "2.6 < 5" in reason.text


def test_resolution_misfit_and_edge():
    interior_good = np.array([0.5, 0.1, 0.4])
    assert v.check_resolution(interior_good, 1, "measured") == []
    # best at the finest end with a small misfit: a warning (optimum not bracketed)
    assert _codes(v.check_resolution(np.array([0.1, 0.3]), 0, "bem")) == {
        ("resolution_at_edge", "warning")
    }
    # best at the coarsest scored stride (NaN beyond) with a large misfit: nothing fits
    codes = _codes(v.check_resolution(np.array([9.0, 6.0, 5.0, np.nan]), 2, "bem"))
    assert codes == {("misfit", "invalid"), ("resolution_at_edge", "invalid")}
    # one scored stride (inf: no area where the reference has one), as on sur-3.sur
    lonely = v.check_resolution(np.array([0.33, np.inf, np.nan, np.inf]), 0, "bem")
    assert ("resolution_at_edge", "invalid") in _codes(lonely)
    assert _codes(v.check_resolution(np.array([0.5, 0.3, 0.6]), 1, "bem")) == {
        ("misfit", "warning")
    }


def _fit(**changes):
    base = dict(fitted=True, mode_mixity=0.03, mode_mixity_std=0.002, at_bound=False, success=True)
    return SimpleNamespace(**{**base, "message": "", **changes})


def test_lambda_checks():
    assert v.check_lambda(_fit()) == []
    assert v.check_lambda(SimpleNamespace(fitted=False)) == []
    assert _codes(v.check_lambda(_fit(at_bound=True, mode_mixity=1e-4))) == {
        ("lambda_at_bound", "invalid")
    }
    assert _codes(v.check_lambda(_fit(mode_mixity_std=math.inf))) == {
        ("lambda_uncertainty", "invalid")
    }
    assert _codes(v.check_lambda(_fit(success=False, message="max nfev"))) == {
        ("lambda_fit", "warning")
    }


def test_measured_area_above_nominal_and_unmatched_loads():
    (reason,) = v.check_measured_area(np.array([1e-6, 2e-3]), 700e-6, "A_r(F_z)")
    assert (reason.code, reason.severity) == ("measured_area_above_nominal", "invalid")
    assert v.check_measured_area(np.array([1e-6]), 700e-6, "x") == []
    reasons = v.check_measured_loads([1.0, 2.5], [1.01, 2.0, 3.0])
    assert _codes(reasons) == {("measured_load_unmatched", "warning")}
    assert len(reasons) == 1 and "2.5 N" in reasons[0].text


def test_sliding_and_bem_stall():
    friction = SimpleNamespace(
        normal_load=np.array([1.0, 2.0]),
        converged=np.array([True, True]),
        sliding_friction=np.array([0.1, np.nan]),
    )
    (reason,) = v.check_sliding(friction)
    assert (reason.code, reason.severity) == ("no_full_sliding", "invalid")
    assert "F_z = 2 N" in reason.text
    bem = SimpleNamespace(
        converged=np.array([[True, False], [True, True]]),
        messages=["load 2: stalled (outlier pixels)"],
        grid_converged=False,
        grid_reason="no decimation converged",
    )
    assert _codes(v.check_bem(bem)) == {("bem_stall", "invalid"), ("bem_grid", "warning")}
    assert v.check_bem(None) == []


def test_surface_warnings_become_reasons():
    reasons = v.check_surface({"warnings": ["89 % of the pixels are missing"]})
    assert _codes(reasons) == {("surface_preparation", "warning")}


def test_verdict_levels_and_exit_status():
    warn = v.Reason("bem_grid", "warning", "w")
    bad = v.Reason("tabor", "invalid", "mu = 2 < 5")
    assert v.Verdict.from_reasons([]).verdict == "valid"
    assert v.Verdict.from_reasons([warn]).verdict == "warnings"
    verdict = v.Verdict.from_reasons([warn, bad])
    assert verdict.verdict == "invalid" and verdict.codes == ["tabor", "bem_grid"]
    assert v.exit_status(True, verdict) == ExitStatus.INVALID_RESULT == 3
    assert v.exit_status(False, verdict) == ExitStatus.NOT_CONVERGED  # 1 takes precedence
    assert v.exit_status(True, v.Verdict.from_reasons([warn])) == ExitStatus.OK
    assert v.mark("4390", verdict) == "invalid: 4390"
    assert v.mark("4390", v.Verdict.from_reasons([warn])) == "4390"


def test_default_small_job_has_a_verdict_in_results_and_report(small_run):
    import h5py

    _, out, result = small_run
    assert result.verdict.verdict in v.VERDICTS
    with h5py.File(out / "results.h5", "r") as f:
        assert "verdict" in f
    report = (out / "report.md").read_text()
    assert report.splitlines()[2].startswith("**Verdict:")
    assert "## Surface" in report


@pytest.mark.slow
def test_x3p_map_with_pdms_material_is_invalid_with_status_3(tmp_path, capsys):
    """x3p-2 (a 83 um x 204 um map with 0.13 x 0.31 um pixels) under the default PDMS-on-glass
    material: the elastic energy to flatten the map is below w (Persson-Tosatti), so the
    interface snaps into near-full contact, the independent-asperity model gives A_r/A_n >> 1
    and no resolution fits the BEM; the job says so (the adhesion regime in place of the
    junction coalescence it causes), marks the numbers and exits 3."""
    from asperity.pipelines.cli import main

    config = tmp_path / "job.toml"
    config.write_text(
        f'[surface]\nfile = "{DATA / "x3p-2.x3p"}"\nmax_stride = 6\ncrop = [0, 96, 0, 96]\n'
        "[loading]\nnormal_loads = [0.2, 0.5]\nsteps = 21\n[bem]\nmax_stride = 2\n"
    )
    status = main(["run", str(config), "--out", str(tmp_path / "out"), "--compute-all"])
    out = capsys.readouterr().out
    assert status == ExitStatus.INVALID_RESULT
    assert out.splitlines()[2] == "VERDICT: INVALID"
    assert "(adhesion_full_contact)" in out and "(area_fraction)" not in out
    report = (tmp_path / "out" / "report.md").read_text()
    assert "**Verdict: INVALID.**" in report and "(`adhesion_full_contact`)" in report
    table = report.split("## Per normal load")[1].split("## Surface")[0]
    lines = [line for line in table.splitlines() if line.startswith("|")]
    header = [h.strip() for h in lines[0].split("|")[1:-1]]
    rows = [[c.strip() for c in line.split("|")[1:-1]] for line in lines if line.startswith("| 0.")]
    # the statistical model's columns are marked; the BEM and Persson columns are references
    # with their own validity and stay plain (units carry SI prefixes: "static F_s (kN)")
    model = ("A_r/A_n model", "static F_s (", "mu_s", "sliding F_x (", "delta_T slide (")
    plain = ("A_r/A_n BEM", "A_r/A_n Persson")
    marked = [i for i, h in enumerate(header) if h.startswith(model)]
    unmarked = [i for i, h in enumerate(header) if h.startswith(plain)]
    assert len(marked) >= 5 and len(unmarked) == 3, header
    assert rows and all(row[i].startswith("invalid:") for row in rows for i in marked)
    assert not any("invalid" in row[i] for row in rows for i in unmarked)
    assert "127.7 nm, 314.6 nm" in report or "0.1277 µm, 0.3146 µm" in report  # dx and dy


def test_bad_input_inside_a_stage_names_its_configuration_keys(small, tmp_path, monkeypatch):
    """A solver argument refused deep in a stage comes back naming the stage and the keys
    that feed it, not only the map-scaled argument."""
    import asperity.pipelines.stages.friction as friction_module
    from asperity.errors import InputError
    from asperity.pipelines.config import ConfigError
    from asperity.pipelines.job import run_job

    def refuse(*args, **kwargs):
        raise InputError("normal_load: expected > 0 N on the map, got -1.2e-06")

    monkeypatch.setattr(friction_module, "friction_prediction", refuse)
    with pytest.raises(ConfigError, match=r"6 friction prediction .*loading.*normal_load"):
        run_job(small(tmp_path), tmp_path / "out")
