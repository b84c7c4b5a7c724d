"""Plausibility of the predicted friction in the job's verdict, and the optional hardness.

The verdict turns :mod:`asperity.statmodel.plausibility` into reasons: the static to sliding
friction ratio and the junction shear at the peak over tau_0 (warnings above 10, naming tau_0
and lambda), and with ``[material] hardness`` the plasticity index psi = (E*/H) sqrt(sigma_s/R)
(warning > 0.6, invalid > 1) and the mean contact pressure against H (warning > 0.39 H,
invalid > H).
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.errors import ExitStatus, InputError
from asperity.pipelines.config import ConfigError, config_from_dict
from asperity.pipelines.stages.verdict import check_friction_plausibility, check_hardness

DATA = Path(__file__).resolve().parents[1] / "data"
TAU0 = 0.13e6  # Pa, PDMS on glass (the paper's Fig 13)


def _friction(static, sliding, area_at_peak, area_at_rest=None, loads=None):
    """A friction result (N, N, m^2): F_x rises to F_s at step 1 and slides at F_d."""
    static, sliding = np.asarray(static, float), np.asarray(sliding, float)
    peak = np.asarray(area_at_peak, float)
    rest = peak * 1.2 if area_at_rest is None else np.asarray(area_at_rest, float)
    return SimpleNamespace(
        normal_load=np.asarray(loads if loads is not None else np.ones(static.size), float),
        static_friction=static,
        sliding_friction=sliding,
        tangential_force=np.stack([np.zeros_like(static), static, sliding], axis=1),
        real_area=np.stack([rest, peak, 0.8 * peak], axis=1),
        shear_strength=TAU0,
    )


def test_the_papers_own_case_raises_nothing():
    """F_s/F_d ~ 2.6 and a junction shear ~ 2.5 tau_0 (the default job's values)."""
    static = np.array([0.06, 0.2])
    friction = _friction(static, static / 2.6, static / (2.5 * TAU0))
    assert check_friction_plausibility(friction) == []


def test_a_glassy_polymer_with_pdms_tau0_is_flagged_naming_tau0_and_lambda():
    """x3p-2 with E* = 4 GPa: F_s 1.2-1.5 x the load, ~700 x the sliding friction, 78 MPa of
    junction shear against tau_0 = 0.13 MPa."""
    loads = np.array([0.2, 1.75])
    static = 1.3 * loads
    friction = _friction(static, static / 700, static / 78e6, loads=loads)
    reasons = {r.code: r for r in check_friction_plausibility(friction)}
    assert set(reasons) == {
        "static_friction_ratio",
        "junction_shear_at_peak",
        "static_friction_coefficient",  # mu_s = 1.3: a warning without E* to judge the shear
    }
    # past 100, F_s/F_d is invalid (issue 24, section 5); tau_0 alone only warns
    assert reasons["static_friction_ratio"].severity == "invalid"
    assert reasons["junction_shear_at_peak"].severity == "warning"
    for reason in reasons.values():
        assert "material.shear_strength (tau_0)" in reason.text
        assert "material.mode_mixity (lambda)" in reason.text
        assert "Sahli et al." in reason.text  # the experiments the limit is set against
    assert "= 700" in reasons["static_friction_ratio"].text
    assert f"= {78e6 / TAU0:.3g}" in reasons["junction_shear_at_peak"].text


def test_loads_without_full_sliding_leave_the_ratio_to_no_full_sliding():
    static = np.array([0.5, 0.6])
    friction = _friction(static, [math.nan, math.nan], static / (2 * TAU0))
    assert check_friction_plausibility(friction) == []


def test_plasticity_index_and_pressure_against_the_hardness():
    roughness = SimpleNamespace(summit_height_rms=1e-6, summit_radius=1e-4)  # sqrt = 0.1
    friction = _friction([1.0], [0.5], [2e-9], area_at_rest=[1e-8], loads=[1.0])  # 1e8 Pa
    assert check_hardness(None, 4e9, roughness, friction) == []
    assert check_hardness(1e9, 4e9, roughness, friction) == []  # psi 0.4, p = 0.1 H
    plastic, pressure = check_hardness(2e8, 4e9, roughness, friction)  # psi = 2 by hand
    assert (plastic.code, plastic.severity) == ("plastic_asperities", "invalid")
    assert (pressure.code, pressure.severity) == ("contact_pressure_above_yield", "warning")
    assert "psi = (E*/H) sqrt(sigma_s/R) = 2:" in plastic.text and "Greenwood" in plastic.text
    squeezed = _friction([1.0], [0.5], [2e-9], area_at_rest=[2e-9], loads=[1.0])  # 5e8 Pa
    (pressure,) = check_hardness(1e9, 4e9, roughness, squeezed)
    assert (pressure.code, pressure.severity) == ("contact_pressure_above_yield", "warning")
    assert "0.5 H" in pressure.text and "Tabor" in pressure.text


def test_hardness_key_is_optional_bounded_and_named(tmp_path):
    base = {"surface": {"synthetic": {}}}
    assert config_from_dict(base, base_dir=tmp_path).material.hardness is None
    material = config_from_dict({**base, "material": {"hardness": 0.2e9}}, base_dir=tmp_path)
    assert material.material.hardness == 0.2e9
    assert "hardness = 200000000.0" in material.to_toml()
    with pytest.raises(ConfigError, match=r"material\.hardness: expected a number in .* Pa"):
        config_from_dict({**base, "material": {"hardness": -1.0}}, base_dir=tmp_path)


def test_small_job_with_a_soft_hardness_is_invalid(small_run, small, tmp_path):
    """The small job with H = 1 MPa: psi = (2.133 MPa / 1 MPa) sqrt(sigma_s/R) > 1: exit 3
    with ``plastic_asperities``; replacing the small job's finished run, the stored stages
    before the lambda stage are reused."""
    from asperity.pipelines.job import run_job
    from asperity.pipelines.stages.verdict import exit_status

    _, out, _ = small_run
    data = small.data()
    data["material"]["hardness"] = 1e6
    shutil.copy(out / "results.h5", tmp_path / "results.h5")
    with pytest.raises(InputError, match="another job"):  # not unasked
        run_job(config_from_dict(data, base_dir=tmp_path), tmp_path)
    result = run_job(config_from_dict(data, base_dir=tmp_path), tmp_path, replace_run=True)
    codes = dict(zip(result.verdict.codes, result.verdict.severities, strict=True))
    assert codes["plastic_asperities"] == "invalid"
    r = result.statistical_model.roughness
    psi = 2.133e6 / 1e6 * math.sqrt(r.summit_height_rms / r.summit_radius)
    assert f"{psi:.3g}" in " ".join(result.verdict.reasons)
    assert exit_status(True, result.verdict) == ExitStatus.INVALID_RESULT
    assert [s.name for s in result.stages if s.status == "computed"][0] == "mode_mixity"


@pytest.mark.slow
def test_x3p_map_with_a_glassy_polymer_warns_of_its_friction(tmp_path, capsys):
    """x3p-2 with E* = 4 GPa and PDMS's tau_0: static friction hundreds of times the sliding
    friction (invalid past 100) and of tau_0 on the junctions (a warning), naming tau_0 and
    lambda."""
    from asperity.pipelines.cli import main

    config = tmp_path / "job.toml"
    config.write_text(
        f'[surface]\nfile = "{DATA / "x3p-2.x3p"}"\nmax_stride = 6\ncrop = [0, 96, 0, 96]\n'
        "[material]\nE_star = 4e9\n"
        "[loading]\nnormal_loads = [0.2, 0.5, 1.0, 1.75]\nsteps = 41\n[bem]\nmax_stride = 2\n"
    )
    status = main(["run", str(config), "--out", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert status == ExitStatus.INVALID_RESULT
    assert "INVALID (static_friction_ratio): static over sliding friction F_s/F_d = " in out
    assert "warning (junction_shear_at_peak): mean junction shear at the peak F_s/A_r over" in out
    assert out.count("check material.shear_strength (tau_0) and material.mode_mixity") >= 2
