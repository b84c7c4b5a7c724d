"""A verdict known early is given early (issue 37, item 1): in the full-contact regime the job
skips the BEM and the model stages, writes the verdict with the full-contact limit, and exits 3;
``run.compute_all`` computes everything anyway."""

from __future__ import annotations

import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity.errors import ExitStatus
from asperity.pipelines.config import config_from_dict
from asperity.pipelines.job import run_job
from asperity.pipelines.report import write_report
from asperity.pipelines.stages.early_verdict import (
    CONTRADICTED_FRACTION,
    SKIPPED_WHEN_KNOWN,
    full_contact_limit,
    full_contact_test,
    known_invalid,
)
from asperity.pipelines.stages.verdict import exit_status

DATA = Path(__file__).resolve().parents[1] / "data"
PDMS = {"E_star": 2.133e6, "work_of_adhesion": 0.040}  # the paper's PDMS on glass
GLASSY = {"E_star": 4e9, "work_of_adhesion": 0.040}  # a glassy polymer
TAU0 = 0.13e6  # Pa, the default material.shear_strength
A_N = 700e-6  # m^2, the default loading.nominal_area


def _config(tmp_path, name="plu-1.plu", crop=(0, 64, 0, 64), material=PDMS, **extra):
    data = {
        "surface": {
            "file": str(DATA / name),
            "max_stride": 4,
            **({"crop": list(crop)} if crop else {}),
        },
        "material": dict(material),
        "loading": {"normal_loads": [0.5, 2.0], "steps": 21},
        "bem": {"max_stride": 2},
        **extra,
    }
    return config_from_dict(data, base_dir=tmp_path)


def test_the_full_contact_limit_is_a_closed_interface():
    area, sliding = full_contact_limit(A_N, TAU0)
    assert area == A_N and sliding == pytest.approx(91.0)  # tau_0 A_n = 0.13 MPa x 700 mm^2


def test_the_limit_is_tested_against_the_measured_fraction():
    sentence, found = full_contact_test(np.array([0.02, 0.04]))
    ((code, severity, text),) = found
    assert "contradicts" in sentence and code == "full_contact_contradicted"
    assert severity == "warning" and "E*" in text
    sentence, found = full_contact_test(np.array([0.3, CONTRADICTED_FRACTION + 0.3]))
    assert "consistent" in sentence and not found
    sentence, found = full_contact_test(np.array([]))
    assert "no measured" in sentence and not found


def test_only_invalid_preview_reasons_stop_the_job():
    assert known_invalid({"codes": ["a", "b"], "severities": ["warning", "invalid"]}) == ["b"]
    assert known_invalid({"codes": [], "severities": []}) == []
    assert known_invalid(None) == []


def test_pdms_on_a_measured_map_stops_before_the_bem(tmp_path):
    """plu-1 (a 64 x 64 px crop) with PDMS: full contact; nothing after the scan is computed,
    the verdict states the limit, the report marks every cell as that limit, exit 3."""
    out = tmp_path / "out"
    log: list[str] = []
    result = run_job(_config(tmp_path), out, log=log.append)
    verdict = result.verdict
    assert verdict.invalid and verdict.codes[0] == "adhesion_full_contact"
    assert exit_status(result.converged, verdict) == ExitStatus.INVALID_RESULT
    status = {run.name: run.status for run in result.stages}
    assert status["surface"] == status["resolution_scan"] == status["verdict"] == "computed"
    for name in ("bem_reference", "statistical_model", "mode_mixity", "friction", "psd"):
        assert status[name] == "skipped" and getattr(result, name) is None
    assert status["realisations"] == status["bem_shear"] == "disabled"  # off anyway
    assert any("3 BEM reference: skipped" in line for line in log)
    assert verdict.full_contact_real_area == pytest.approx(A_N)
    assert verdict.full_contact_sliding_friction == pytest.approx(TAU0 * A_N)
    np.testing.assert_allclose(verdict.full_contact_normal_load, [0.5, 2.0])
    with h5py.File(out / "results.h5", "r") as f:
        assert set(f) == {"surface", "resolution_scan", "verdict"}
    report = write_report(result, out).read_text()
    assert "## Full-contact limit" in report and "not the asperity model's" in report
    table = report.split("## Per normal load")[1].split("## Full-contact limit")[0]
    rows = [line.split("|")[2:-1] for line in table.splitlines() if line.startswith("| 0.5")]
    assert rows and all(cell.strip().startswith("full-contact limit:") for cell in rows[0])
    assert (out / "surface.png").exists() and not (out / "fig12_resolution.png").exists()
    assert "Full-contact limit" in (out / "report.html").read_text()


def test_a_rerun_reuses_the_early_stages_and_the_cli_redraws_with_status_3(tmp_path, capsys):
    from asperity.pipelines.cli import main

    config = tmp_path / "job.toml"
    config.write_text(
        f'[surface]\nfile = "{DATA / "opd-1.opd"}"\nmax_stride = 4\ncrop = [0, 48, 0, 48]\n'
        "[loading]\nnormal_loads = [0.5, 2.0]\nsteps = 21\n"
    )  # the default material is PDMS
    out = tmp_path / "out"
    assert main(["run", str(config), "--out", str(out)]) == ExitStatus.INVALID_RESULT
    text = capsys.readouterr().out
    assert "(adhesion_full_contact)" in text and "Full-contact limit" in text
    assert "full-contact limit: 1" in text
    assert main(["report", str(out)]) == ExitStatus.INVALID_RESULT


def test_skipped_stages_are_those_that_cannot_change_the_verdict():
    from asperity.pipelines.stages import STAGE_NAMES

    assert set(SKIPPED_WHEN_KNOWN) == set(STAGE_NAMES) - {"surface", "resolution_scan", "verdict"}


@pytest.mark.slow
def test_compute_all_runs_every_stage_and_keeps_the_reason(tmp_path, capsys):
    """--compute-all on the same crop: the model stages run, the verdict is still invalid for
    the same reason and carries no full-contact limit (it is the full verdict)."""
    from asperity.pipelines.cli import main

    config = tmp_path / "job.toml"
    config.write_text(
        f'[surface]\nfile = "{DATA / "plu-1.plu"}"\nmax_stride = 4\ncrop = [0, 48, 0, 48]\n'
        "[loading]\nnormal_loads = [0.5, 2.0]\nsteps = 21\n[bem]\nmax_stride = 2\n"
    )
    out = tmp_path / "out"
    status = main(["run", str(config), "--out", str(out), "--compute-all"])
    assert status in (ExitStatus.INVALID_RESULT, ExitStatus.NOT_CONVERGED)
    with h5py.File(out / "results.h5", "r") as f:
        assert {"statistical_model", "friction", "verdict"} <= set(f)
        assert "full_contact_real_area" not in f["verdict"].attrs
    assert "(adhesion_full_contact)" in capsys.readouterr().out


@pytest.mark.slow
@pytest.mark.parametrize("name", ["plu-1.plu", "opd-1.opd"])
def test_whole_measured_maps_with_pdms_end_in_seconds_with_status_3(tmp_path, capsys, name):
    """The whole plu-1 (768 x 576 px) and opd-1 maps with PDMS and the default loads: exit 3,
    adhesion_full_contact, within 120 s of CPU (0.4.2: 1643 s and 990 s)."""
    from asperity.pipelines.cli import main

    config = tmp_path / "job.toml"
    config.write_text(
        f'[surface]\nfile = "{DATA / name}"\n[material]\nE_star = 2.133e6\n'
        "work_of_adhesion = 0.040\n"
    )
    cpu = time.process_time()
    status = main(["run", str(config), "--out", str(tmp_path / "out")])
    cpu = time.process_time() - cpu
    assert status == ExitStatus.INVALID_RESULT
    assert "INVALID (adhesion_full_contact)" in capsys.readouterr().out
    assert cpu < 120.0


@pytest.mark.slow
def test_a_glassy_polymer_on_the_same_map_is_not_stopped(tmp_path):
    """E* = 4 GPa on an x3p-2 crop (U_el/(A0 w) ~ 77 on the whole map): partial contact, no
    early stop, every stage runs. (On plu-1 even E* = 4 GPa stays below 1: 5.2e-4 x 1875.)"""
    config = _config(tmp_path, name="x3p-2.x3p", crop=(0, 64, 0, 64), material=GLASSY)
    result = run_job(config, tmp_path / "out")
    assert result.statistical_model is not None and result.friction is not None
    assert "adhesion_full_contact" not in result.verdict.codes
    assert result.verdict.full_contact_real_area is None


def test_the_measured_fractions_are_the_rest_points_of_every_curve():
    from types import SimpleNamespace

    from asperity.pipelines.stages.early_verdict import measured_fractions

    measured = SimpleNamespace(
        normal_area=SimpleNamespace(real_area=np.array([7e-6, 14e-6])),
        shear_area=[
            SimpleNamespace(
                tangential_force=np.array([0.3, 0.0, 0.1]), real_area=np.array([1, 21, 3]) * 1e-6
            )
        ],
    )
    np.testing.assert_allclose(measured_fractions(measured, A_N), [0.01, 0.02, 0.03])
    assert measured_fractions(SimpleNamespace(normal_area=None, shear_area=[]), A_N).size == 0


def test_without_the_bem_the_regime_still_stops_the_job_and_the_measurement_tests_it(tmp_path):
    """[bem] enabled = false with a measured A_r(F_z) of 1-2 % of A_n: the regime is judged
    before the statistical model, the job stops there, and the measurement contradicts the
    full-contact limit (warning full_contact_contradicted)."""
    measured = tmp_path / "area.csv"
    measured.write_text("normal_load,real_area\n0.5,7e-6\n2.0,14e-6\n")  # 1 % and 2 % of A_n
    extra = {"bem": {"enabled": False}, "measured": {"normal_area": str(measured)}}
    result = run_job(_config(tmp_path, crop=(0, 64, 0, 64), **extra), tmp_path / "out")
    status = {run.name: run.status for run in result.stages}
    assert status["bem_reference"] == "disabled" and status["statistical_model"] == "skipped"
    verdict = result.verdict
    assert verdict.codes[0] == "adhesion_full_contact"
    assert "full_contact_contradicted" in verdict.codes
    assert "reaches only 0.02" in verdict.full_contact_test
    assert verdict.stages_skipped[0] == "statistical_model"  # the BEM was off, not skipped
