"""The verdict where the numbers say so (issue 24, section 5): friction past stated thresholds
is invalid, and the adhesive BEM column is marked where its range decides it.

x3p-2 with a glassy polymer (E* = 3.5 GPa) and PDMS's tau_0 (0.13 MPa) ended exit 0 with F_s/F_d
~700, mu_s 2.1-2.2 and a mean junction shear of 70 MPa. The thresholds and their reasons are the
one table ``statmodel.plausibility.THRESHOLDS``; here they are held to the physics they state and
to the real job's numbers (the slow test runs the job itself).
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from asperity.errors import ExitStatus
from asperity.pipelines.config import preset_text
from asperity.pipelines.report.verdict_marks import RANGE_DECIDED_MARK, mark_adhesive_bem
from asperity.pipelines.stages.verdict import (
    RANGE_DECIDED_REASON,
    Verdict,
    check_bem_adhesive_range,
    check_friction_plausibility,
)
from asperity.statmodel import plausibility
from asperity.statmodel.regimes import full_contact_check

DATA = Path(__file__).resolve().parents[1] / "data"
TAU0 = 0.13e6  # Pa, PDMS on glass (the paper's Fig 13)
GLASSY = 3.5e9  # Pa, E* of the hard glassy polymer of x3p_hard
PDMS = 2.133e6  # Pa, E* of the paper's PDMS

# x3p_hard as run on 2026-11-27 (tests/data/x3p-2.x3p, the default job with E* = 3.5 GPa):
# per load, F_z, F_s, F_d (N) and A_r at the static peak (m^2).
HARD_LOADS = np.array([0.56, 1.06, 1.58, 2.08, 2.57, 3.12])
HARD_STATIC = np.array([1.2587, 2.3134, 3.3829, 4.3934, 5.3709, 6.4560])
HARD_SLIDING = np.array([0.0017957, 0.0033460, 0.0049363, 0.0064510, 0.0079249, 0.0095691])
HARD_AREA_AT_PEAK = np.array([1.7999e-8, 3.3326e-8, 4.8787e-8, 6.3427e-8, 7.7615e-8, 9.3971e-8])


def _friction(loads, static, sliding, area_at_peak, shear_strength=TAU0):
    """A friction result: F_x rises to F_s at step 1 (A_r there = area_at_peak) and slides."""
    static, sliding = np.asarray(static, float), np.asarray(sliding, float)
    peak = np.asarray(area_at_peak, float)
    return SimpleNamespace(
        normal_load=np.asarray(loads, float),
        static_friction=static,
        sliding_friction=sliding,
        tangential_force=np.stack([np.zeros_like(static), static, sliding], axis=1),
        real_area=np.stack([1.2 * peak, peak, 0.8 * peak], axis=1),
        shear_strength=shear_strength,
    )


def test_the_table_holds_every_threshold_with_its_reason():
    table = plausibility.THRESHOLDS
    assert set(table) == {
        "plastic_asperities",
        "contact_pressure_above_yield",
        "static_friction_ratio",
        "junction_shear_at_peak",
        "junction_shear_yield",
        "static_friction_coefficient",
    }
    for code, row in table.items():
        assert row.code == code and row.warning <= row.invalid and len(row.reason) > 40
    # the module's constants are the table's
    assert plausibility.FRICTION_RATIO_LIMIT == table["static_friction_ratio"].warning == 10
    assert plausibility.FRICTION_RATIO_INVALID == table["static_friction_ratio"].invalid == 100


def test_glassy_shear_yield_from_the_modulus_agrees_with_the_one_from_the_hardness():
    """Two independent routes to PMMA's shear yield: 0.03 E*/sqrt 3 from its modulus (E = 3.0
    GPa, nu = 0.35: E* = 3.42 GPa) and H / (2.8 sqrt 3) from its Vickers hardness (~0.2-0.25
    GPa); both must lie near its measured shear yield stress, ~50-60 MPa (Ward and Sweeney)."""
    e_star = 3.0e9 / (1 - 0.35**2)
    from_modulus = plausibility.shear_limit(e_star)
    assert from_modulus.kind == "glassy"
    assert from_modulus.stress == pytest.approx(0.03 * e_star / math.sqrt(3), rel=1e-12)
    for hardness in (0.20e9, 0.25e9):
        from_hardness = plausibility.shear_limit(e_star, hardness)
        assert from_hardness.kind == "hardness"
        assert 0.6 < from_hardness.stress / from_modulus.stress < 1.2
    assert 40e6 < from_modulus.stress < 70e6


def test_a_rubber_is_limited_at_a_shear_strain_of_one():
    """Incompressible (nu = 1/2): E = 3 G and E* = E / (1 - 1/4), so G = E*/4."""
    limit = plausibility.shear_limit(PDMS)
    assert limit.kind == "rubbery"
    e = PDMS * (1 - 0.25)
    assert limit.stress == pytest.approx(e / 3, rel=1e-12)
    # the rubber is only graded at its limit: no warning below it
    below = plausibility.junction_yield_check([0.99 * limit.stress], [1.0], PDMS)
    above = plausibility.junction_yield_check([1.01 * limit.stress], [1.0], PDMS)
    assert (below.level, above.level) == ("ok", "invalid")


def test_the_default_job_stays_valid():
    """The default job (PDMS, report of the baseline): F_s/F_d 2.5, junction shear 2.5 tau_0
    = 0.61 G, mu_s at most 0.52: no friction reason at all."""
    loads = np.array([0.56, 3.12])
    static = np.array([0.2893, 1.437])
    sliding = np.array([0.1169, 0.6032])
    friction = _friction(loads, static, sliding, static / (2.51 * TAU0))
    assert check_friction_plausibility(friction, PDMS) == []
    yielded = plausibility.junction_yield_check(static, static / (2.51 * TAU0), PDMS)
    assert yielded.value == pytest.approx(2.51 * TAU0 / (PDMS / 4), rel=1e-12)


def test_x3p_hard_is_invalid_with_the_new_codes():
    friction = _friction(HARD_LOADS, HARD_STATIC, HARD_SLIDING, HARD_AREA_AT_PEAK)
    reasons = {r.code: r for r in check_friction_plausibility(friction, GLASSY)}
    assert reasons["static_friction_ratio"].severity == "invalid"  # ~700 > 100
    assert reasons["junction_shear_yield"].severity == "invalid"  # 70 MPa > 60.6 MPa
    assert reasons["static_friction_coefficient"].severity == "invalid"  # 2.25 > 1, past yield
    assert reasons["junction_shear_at_peak"].severity == "warning"  # ~540 tau_0
    assert Verdict.from_reasons(list(reasons.values())).invalid
    assert "6.06e+07 Pa" in reasons["junction_shear_yield"].text
    assert "invalid above 100" in reasons["static_friction_ratio"].text


def test_mu_above_one_is_invalid_only_past_the_shear_limit():
    """An adhesive soft contact may exceed mu_s = 1 (a warning); with the junctions past the
    solid's shear limit the same mu_s is invalid."""
    loads, static = [0.1], [0.3]  # mu_s = 3
    soft = _friction(loads, static, [0.15], [0.3 / (0.5 * PDMS / 4)])  # half the rubber limit
    codes = {r.code: r.severity for r in check_friction_plausibility(soft, PDMS)}
    assert codes == {"static_friction_coefficient": "warning"}  # 2 tau_0, 0.5 G: plausible
    sheared = _friction(loads, static, [0.15], [0.3 / (2 * PDMS / 4)])  # twice the limit
    codes = {r.code: r.severity for r in check_friction_plausibility(sheared, PDMS)}
    assert codes["static_friction_coefficient"] == "invalid"
    assert codes["junction_shear_yield"] == "invalid"


@pytest.mark.parametrize(("ratio", "level"), [(9.0, "ok"), (50.0, "warning"), (150.0, "invalid")])
def test_static_to_sliding_ratio_levels(ratio, level):
    check = plausibility.static_to_sliding_check([1.0], [1.0 / ratio])
    assert check.level == level and check.value == pytest.approx(ratio)


def _bem(adhesive, adhesion="maugis"):
    return SimpleNamespace(
        adhesion=adhesion,
        contact_fraction_adhesive=np.asarray(adhesive, float),
        adhesion_range=9.7e-5,
        range_sensitivity=np.array([0.2, 0.135, 0.05]),
    )


def _regime(ratio):
    check = full_contact_check(ratio * 0.04, 0.04)
    return SimpleNamespace(full_contact=check, energy_ratio=check.value)


def test_adhesive_bem_in_full_contact_is_marked_range_decided():
    """plu-1: the regime says full contact, the adhesive BEM gives 0.135 with h_0 = 97 um."""
    (reason,) = check_bem_adhesive_range(_bem([0.12, 0.135]), _regime(0.05), None, "bem")
    assert reason.code == RANGE_DECIDED_REASON and reason.severity == "invalid"
    assert "9.7e-05 m" in reason.text and '"auto"' in reason.text
    assert "0.2, 0.135, 0.05" in reason.text
    (measured,) = check_bem_adhesive_range(_bem([0.12]), _regime(0.05), 1e-9, "measured")
    assert measured.severity == "warning" and "[bem] adhesion_range" in measured.text


def test_adhesive_bem_reaching_full_contact_is_marked_without_the_regime():
    (reason,) = check_bem_adhesive_range(_bem([0.97, 1.0]), _regime(50.0), None, "bem")
    assert "reaches 1" in reason.text


@pytest.mark.parametrize(
    ("bem", "regime"),
    [
        (_bem([0.004, 0.0075]), _regime(369.0)),  # the default job: partial contact
        (_bem([1.0], adhesion="pohrt-popov"), _regime(0.05)),  # no adhesion on loading
        (None, _regime(0.05)),  # no BEM
        (_bem([0.5]), None),  # no adhesion (w = 0)
    ],
)
def test_adhesive_bem_left_unmarked_where_the_roughness_decides(bem, regime):
    assert check_bem_adhesive_range(bem, regime, None, "bem") == []


def test_the_mark_is_on_the_adhesive_cells_only_with_the_reason():
    marked = Verdict("invalid", ["range"], [RANGE_DECIDED_REASON], ["invalid"], None, None, None)
    plain = Verdict("warnings", ["grid"], ["bem_grid"], ["warning"], None, None, None)
    assert mark_adhesive_bem("0.64 +- 0.2", marked) == f"{RANGE_DECIDED_MARK}: 0.64 +- 0.2"
    assert mark_adhesive_bem("-", marked) == "-"
    assert mark_adhesive_bem("0.64 +- 0.2", plain) == "0.64 +- 0.2"
    assert mark_adhesive_bem("0.64", None) == "0.64"


def _x3p_hard_job(tmp_path: Path) -> Path:
    """The user's job: the default preset on x3p-2 with E* = 3.5 GPa."""
    text = preset_text("default")
    start = text.index("[surface.synthetic]")
    text = text[:start] + text[text.index("[material]") :]
    text = text.replace("[surface]\n", f'[surface]\nfile = "{DATA / "x3p-2.x3p"}"\n', 1)
    text = text.replace("E_star = 2.133e6", "E_star = 3.5e9", 1)
    path = tmp_path / "x3p_hard.toml"
    path.write_text(text)
    return path


@pytest.mark.slow
def test_x3p_hard_exits_3_with_the_new_reason_codes(tmp_path, capsys):
    """The whole job (about 60-75 s on a quiet 2-core machine, BEM included)."""
    import h5py

    from asperity.pipelines.cli import main

    out = tmp_path / "out"
    status = main(["run", str(_x3p_hard_job(tmp_path)), "--out", str(out)])
    captured = capsys.readouterr()
    assert status == ExitStatus.INVALID_RESULT
    assert "INVALID (static_friction_ratio)" in captured.out
    assert "(junction_shear_yield)" in captured.out
    assert "(static_friction_coefficient)" in captured.out
    assert "before 3 BEM reference: adhesion regime judged from the map" in captured.err
    report = (out / "report.md").read_text()
    assert "`static_friction_ratio`" in report and "`junction_shear_yield`" in report
    with h5py.File(out / "results.h5", "r") as f:
        codes = str(f["verdict"].attrs["codes"])
        assert "static_friction_ratio" in codes and "junction_shear_yield" in codes
        assert "preview_adhesion_regime" in f.attrs
