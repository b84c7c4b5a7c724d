"""The like-for-like calibration (Maugis-Dugdale BEM against the adhesive statistical model,
Greenwood-Williamson against the non-adhesive BEM), the [bem] adhesion keys, and the verdict
that names the adhesion regime (Persson-Tosatti) on real PDMS maps."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.config import BemConfig, ConfigError, config_from_dict
from asperity.pipelines.report import load_table
from asperity.pipelines.stages.bem import bem_reference
from asperity.pipelines.stages.surface import LevelledSurface, prepare
from asperity.pipelines.stages.verdict import (
    Reason,
    adhesion_regime_of,
    check_adhesion_regime,
    in_place_of_coalescence,
)

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

DATA = Path(__file__).resolve().parents[1] / "data"
PDMS = SimpleNamespace(e_star=2.133e6, work_of_adhesion=0.040, equilibrium_distance=0.2e-9)


def test_default_job_solves_both_pairs_and_adhesion_adds_area(small_run):
    """The Maugis BEM attracts outside the contact, so at the same load it has more contact than
    the non-adhesive BEM; JKR asperities likewise carry more area than Greenwood-Williamson's
    Hertzian ones at every resolution and load."""
    _, _, result = small_run
    bem, res = result.bem_reference, result.statistical_model
    assert bem.adhesion == "maugis" and bem.adhesion_range > 0
    assert np.all(bem.contact_fraction_adhesive >= bem.contact_fraction)
    assert bem.contact_fraction_adhesive.sum() > bem.contact_fraction.sum()
    both = np.isfinite(res.real_area) & np.isfinite(res.real_area_non_adhesive)
    assert both.any()
    assert np.all(res.real_area[both] > res.real_area_non_adhesive[both])
    assert res.effective_resolution_non_adhesive in res.resolution
    header, rows = load_table(result)
    assert any(h.startswith("A_r/A_n model w=0") for h in header)
    assert len(rows[0]) == len(header)


def test_range_rule_and_its_sensitivity_are_stated(small_run):
    """The range's cohesive zone spans 3 elements (or the rule says it was not reached), and
    the range part of the uncertainty is half the spread of the three areas it stores."""
    _, _, result = small_run
    bem = result.bem_reference
    assert ("reached" in bem.range_rule) and "3 elements" in bem.range_rule
    if "NOT reached" not in bem.range_rule:
        assert bem.range_zone_elements >= 3.0
    a = bem.range_sensitivity
    assert a.shape == (3,) and np.all(a > 0)
    assert bem.area_range_uncertainty == pytest.approx(0.5 * (a.max() - a.min()))


def test_pohrt_popov_loading_branch_carries_no_adhesion_and_says_so():
    surface = topo.synthetic.paper_like(n=64, pixel_size=40e-6, seed=3)
    settings = BemConfig(adhesion="pohrt-popov")
    ref = bem_reference(surface, 2.133e6, 0.04, [1.0, 3.0], 700e-6, settings)
    np.testing.assert_array_equal(ref.contact_fraction_adhesive, ref.contact_fraction)
    assert ref.adhesion == "pohrt-popov" and ref.adhesion_range is None
    assert any("carries no adhesion" in w for w in ref.warnings)


def _bem_data(**bem) -> dict:
    from asperity.pipelines.config import preset_text

    data = tomllib.loads(preset_text("default"))
    data["bem"].update(bem)
    return data


def test_adhesion_keys_round_trip(tmp_path):
    cfg = config_from_dict(
        _bem_data(adhesion="pohrt-popov", adhesion_range=2e-6), base_dir=tmp_path
    )
    assert cfg.bem.adhesion == "pohrt-popov" and cfg.bem.adhesion_range == pytest.approx(2e-6)
    again = config_from_dict(tomllib.loads(cfg.to_toml()), source=cfg.source, base_dir=tmp_path)
    assert again == cfg
    auto = config_from_dict(_bem_data(adhesion_range="auto"), base_dir=tmp_path)
    assert auto.bem.adhesion == "maugis" and auto.bem.adhesion_range is None


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        ({"adhesion": "jkr"}, "bem.adhesion"),
        ({"adhesion_range": -1e-6}, "bem.adhesion_range"),
        ({"adhesion_range": 1.0}, "bem.adhesion_range"),
    ],
)
def test_bad_adhesion_keys_are_refused_by_name(tmp_path, edit, key):
    with pytest.raises(ConfigError, match=rf"{key}: expected"):
        config_from_dict(_bem_data(**edit), base_dir=tmp_path)


def _crop(name: str, crop: list[int]) -> LevelledSurface:
    cfg = config_from_dict({"surface": {"file": str(DATA / name), "crop": crop}})
    return LevelledSurface.from_prepared(prepare(cfg.surface))


@pytest.mark.parametrize(
    ("name", "crop"), [("x3p-2.x3p", [0, 128, 0, 128]), ("di-3.di", [0, 128, 0, 128])]
)
def test_pdms_maps_are_adhesion_full_contact(name, crop):
    """With PDMS (E* 2.1 MPa, w 40 mJ/m^2) flattening these maps costs a few per cent of w:
    full contact is expected, and the reason replaces junction coalescence."""
    regime = adhesion_regime_of(_crop(name, crop), PDMS, summit_radius=1e-6)
    assert regime.energy_ratio < 1
    reasons = check_adhesion_regime(regime)
    assert [r.code for r in reasons] == ["adhesion_full_contact"]
    assert "Tabor parameter" in reasons[0].text and "S_PR" in reasons[0].text
    coalescence = Reason("area_fraction", "invalid", "junctions merge")
    merged = in_place_of_coalescence([coalescence], reasons)
    assert [r.code for r in merged] == ["adhesion_full_contact"]


def test_glassy_polymer_on_x3p2_stays_partial_contact():
    """E* ~ 4 GPa (E = 3.5 GPa): the energy ratio is ~ 2000 times PDMS's, above 1."""
    glassy = SimpleNamespace(**{**vars(PDMS), "e_star": 4e9})
    regime = adhesion_regime_of(_crop("x3p-2.x3p", [0, 128, 0, 128]), glassy, 1e-6)
    assert regime.energy_ratio > 1
    assert check_adhesion_regime(regime) == []


def test_maugis_solves_are_all_counted(monkeypatch):
    """Every bem.solve_contact call of the stage is in ``solves``: the check and sweeps, the
    range search beyond its first solve and the two sensitivity solves (h_0 / 2, 2 h_0)."""
    from asperity.bem.reference import load_sweeps

    calls = []
    real = load_sweeps.solve_contact

    def counting(*args, **kwargs):
        calls.append(kwargs.get("adhesion_range"))
        return real(*args, **kwargs)

    monkeypatch.setattr(load_sweeps, "solve_contact", counting)
    surface = topo.synthetic.paper_like(n=64, pixel_size=40e-6, seed=3)
    ref = bem_reference(surface, 2.133e6, 0.04, [1.0, 3.0], 700e-6, BemConfig(max_stride=2))
    assert ref.solves == len(calls)
    h0 = ref.adhesion_range
    assert calls.count(0.5 * h0) == 1 and calls.count(2.0 * h0) == 1
