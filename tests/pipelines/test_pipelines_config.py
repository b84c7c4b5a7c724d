"""Configuration: presets, validation errors naming the key, resolution of paths."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from asperity.pipelines.config import (
    ConfigError,
    config_from_dict,
    load_config,
    load_preset,
    preset_text,
)

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]


def test_default_preset_shipped_twice_identical():
    """data/default.toml (the documented default) is byte-identical to the package data."""
    assert (ROOT / "data" / "default.toml").read_text("utf-8") == preset_text("default")


def test_presets_load_with_paper_parameters():
    default, paper = load_preset("default"), load_preset("paper")
    for cfg in (default, paper):
        assert cfg.material.E_star == pytest.approx(2.133e6)
        assert cfg.material.work_of_adhesion == pytest.approx(0.040)
        assert cfg.material.shear_strength == pytest.approx(0.13e6)
        assert cfg.loading.nominal_area == pytest.approx(700e-6)
        assert len(cfg.loading.normal_loads) == 6
    assert paper.surface.synthetic.n == 5001
    assert paper.surface.synthetic.pixel_size == pytest.approx(2e-6)
    # both map 10 mm squares, like the measured map of Appendix A
    for cfg in (default, paper):
        s = cfg.surface.synthetic
        assert s.n * s.pixel_size == pytest.approx(10e-3, rel=1e-3)


def test_resolved_config_round_trips_through_toml():
    cfg = load_preset("default")
    again = config_from_dict(tomllib.loads(cfg.to_toml()), source=cfg.source)
    assert again == cfg


def _base() -> dict:
    return tomllib.loads(preset_text("default"))


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["material"].update(E_star=-1.0), "material.E_star"),
        (lambda d: d["material"].update(youngs_modulus=1.0), "material.youngs_modulus"),
        (lambda d: d["material"].update(mode_mixity=1.5), "material.mode_mixity"),
        (lambda d: d["material"].update(work_of_adhesion="a lot"), "material.work_of_adhesion"),
        (lambda d: d["loading"].update(normal_loads=[]), "loading.normal_loads"),
        (lambda d: d["loading"].update(steps=1), "loading.steps"),
        (
            lambda d: d["loading"].update(max_tangential_displacement=-1e-6),
            "loading.max_tangential_displacement",
        ),
        (lambda d: d["bem"].update(tol=0.0), "bem.tol"),
        (lambda d: d["surface"].update(detrend="cubic"), "surface.detrend"),
        (lambda d: d["surface"]["synthetic"].update(recipe="moon"), "surface.synthetic.recipe"),
        (lambda d: d["surface"].update(file="no/such/map.x3p"), "surface"),
        (lambda d: d["fit"].update(mode_mixity_bounds=[0.5, 0.1]), "fit.mode_mixity_bounds"),
        (lambda d: d["run"].update(workers=0), "run.workers"),
        (lambda d: d.update(extra={"a": 1}), "extra"),
        (lambda d: d.update(measured={"normal_area": "missing.csv"}), "measured.normal_area"),
    ],
)
def test_bad_values_fail_naming_the_key(edit, key, tmp_path):
    data = _base()
    edit(data)
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        config_from_dict(data, source="job.toml", base_dir=tmp_path)


def test_missing_surface_file_named_with_path(tmp_path):
    data = _base()
    del data["surface"]["synthetic"]
    data["surface"]["file"] = "map.x3p"
    with pytest.raises(ConfigError, match=r"surface\.file: file not found: .*map\.x3p"):
        config_from_dict(data, source="job.toml", base_dir=tmp_path)


def test_relative_files_resolve_against_config_dir(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "area.csv").write_text("normal_load,real_area\n1,1e-6\n2,2e-6\n")
    (tmp_path / "sub" / "shear.csv").write_text("tangential_force,real_area\n0,1e-6\n1,0.9e-6\n")
    text = preset_text("default") + (
        '\n[measured]\nnormal_area = "area.csv"\n'
        'shear_area = [{normal_load = 1.0, file = "shear.csv"}]\n'
    )
    path = tmp_path / "sub" / "job.toml"
    path.write_text(text)
    cfg = load_config(path)
    assert cfg.measured.normal_area == tmp_path / "sub" / "area.csv"
    assert cfg.measured.shear_area[0].normal_load == 1.0
    assert cfg.measured.shear_area[0].file == tmp_path / "sub" / "shear.csv"


def test_invalid_toml_and_missing_config(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[material\nE_star = 1")
    with pytest.raises(ConfigError, match="bad.toml: not valid TOML"):
        load_config(bad)
    with pytest.raises(ConfigError, match="configuration file not found"):
        load_config(tmp_path / "nope.toml")
    with pytest.raises(ConfigError, match="unknown preset"):
        load_preset("huge")


def test_validation_imports_no_numerical_library():
    """Validation is pure Python: a bad config fails before numpy/h5py/solvers load."""
    code = (
        "import sys; from pipelines.config import load_preset; load_preset('default'); "
        "print(sorted(m for m in ('numpy', 'h5py', 'scipy', 'numba', 'bem', 'statmodel', "
        "'topo') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_cli_bad_config_exits_2_naming_the_key(tmp_path):
    bad = tmp_path / "job.toml"
    bad.write_text(preset_text("default").replace("E_star = 2.133e6", "E_star = -2.133e6"))
    out = subprocess.run(
        [sys.executable, "-m", "asperity", "run", str(bad), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2
    assert "material.E_star" in out.stderr
    assert not (tmp_path / "out").exists()
