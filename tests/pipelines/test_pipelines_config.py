"""Configuration: presets, one error format naming the key, bounds, spellings, paths."""

from __future__ import annotations

from pathlib import Path

import pytest

from asperity.pipelines.config import (
    ConfigError,
    config_from_dict,
    load_config,
    load_preset,
    preset_text,
)
from tests._helpers import python_stdout

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]


def test_default_preset_is_shipped_once():
    """The documented default lives in the package (it ships in the wheel), not twice."""
    assert not (ROOT / "data" / "default.toml").exists()
    assert "[surface.synthetic]" in preset_text("default")


def test_presets_load_with_paper_parameters():
    default, paper = load_preset("default"), load_preset("paper")
    for cfg in (default, paper):
        assert cfg.material.e_star == pytest.approx(2.133e6)
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
    ("edit", "key", "expected"),
    [
        (lambda d: d["material"].update(E_star=-1.0), "material.E_star", "a number in [100, "),
        (lambda d: d["material"].update(E_star=1e308), "material.E_star", "diamond"),
        (lambda d: d["material"].update(youngs_modulus=1.0), "material.youngs_modulus", "one of"),
        (lambda d: d["material"].update(mode_mixity=1.5), "material.mode_mixity", "[0, 1]"),
        (
            lambda d: d["material"].update(work_of_adhesion="a lot"),
            "material.work_of_adhesion",
            "a number",
        ),
        (lambda d: d["loading"].update(normal_loads=[]), "loading.normal_loads", "a list of 1"),
        (lambda d: d["loading"].update(normal_loads=[1.0, "x"]), "loading.normal_loads[1]", "N"),
        (lambda d: d["loading"].update(steps=1), "loading.steps", "an integer in [3, 100000]"),
        (lambda d: d["loading"].update(steps=10**9), "loading.steps", "1.4 GB"),
        (lambda d: d["loading"].update(steps=1e9), "loading.steps", "an integer"),
        (
            lambda d: d["loading"].update(max_tangential_displacement=-1e-6),
            "loading.max_tangential_displacement",
            '"auto" or a number',
        ),
        (lambda d: d["bem"].update(tol=0.0), "bem.tol", "double precision"),
        (lambda d: d["bem"].update(tol=1e300), "bem.tol", "wrong by more than a per cent"),
        (lambda d: d["bem"].update(enabled="no"), "bem.enabled", "true or false"),
        (lambda d: d["statmodel"].update(area_tolerance=1.0), "statmodel.area_tolerance", "0.5"),
        (lambda d: d["surface"].update(detrend="cubic"), "surface.detrend", "'plane'"),
        (lambda d: d["surface"]["synthetic"].update(n=30000), "surface.synthetic.n", "8 n^2"),
        (
            lambda d: d["surface"]["synthetic"].update(recipe="moon"),
            "surface.synthetic.recipe",
            "one of",
        ),
        (lambda d: d["surface"].update(file="no/such/map.x3p"), "surface.file", "file not found"),
        (
            lambda d: d["fit"].update(mode_mixity_bounds=[0.5, 0.1]),
            "fit.mode_mixity_bounds",
            "low < high",
        ),
        (lambda d: d["run"].update(workers=0), "run.workers", "an integer in [1, 256]"),
        (lambda d: d.update(extra={"a": 1}), "extra", "one of the tables"),
        (
            lambda d: d.update(measured={"normal_area": "missing.csv"}),
            "measured.normal_area",
            "file not found",
        ),
        (
            lambda d: d.update(measured={"shear_area": [{"normal_load": 1.0, "file": "x.csv"}]}),
            "measured.shear_area[0].file",
            "file not found",
        ),
    ],
)
def test_bad_values_fail_in_one_format_naming_the_key(edit, key, expected, tmp_path):
    """``file: section.key: expected ..., got ...`` for every kind of mistake."""
    data = _base()
    edit(data)
    with pytest.raises(ConfigError) as info:
        config_from_dict(data, source="job.toml", base_dir=tmp_path)
    message = str(info.value)
    assert message.startswith(f"job.toml: {key}: expected "), message
    assert expected in message and ", got " in message
    assert "\n" not in message


def test_both_spellings_of_the_modulus_are_accepted_once(tmp_path):
    data = _base()
    del data["material"]["E_star"]
    data["material"]["e_star"] = 3e6
    assert config_from_dict(data, base_dir=tmp_path).material.e_star == 3e6
    data["material"]["E_star"] = 3e6
    with pytest.raises(ConfigError, match=r"material\.E_star: expected one spelling"):
        config_from_dict(data, base_dir=tmp_path)


def test_the_job_and_the_friction_file_share_the_material_table():
    """Both files build a statmodel.Material through the same section, with the same errors."""
    from asperity.statmodel import Material
    from asperity.statmodel.config import parse_friction_parameters

    cfg = load_preset("default")
    assert isinstance(cfg.material, Material)
    friction = {
        "material": {"e_star": -1.0},
        "roughness": {},
        "loading": {},
    }
    job = {**_base(), "material": {"e_star": -1.0}}
    messages = []
    for parse in (
        lambda: parse_friction_parameters(friction, "f.toml"),
        lambda: config_from_dict(job, source="f.toml"),
    ):
        with pytest.raises(ConfigError) as info:
            parse()
        messages.append(str(info.value))
    assert messages[0] == messages[1]
    assert messages[0].startswith("f.toml: material.e_star: expected a number in [100, 1e+13] Pa")


def test_bem_disabled_needs_a_measured_normal_area(tmp_path):
    data = _base()
    data["bem"]["enabled"] = False
    with pytest.raises(ConfigError, match=r"bem\.enabled: expected true unless measured"):
        config_from_dict(data, source="job.toml", base_dir=tmp_path)
    (tmp_path / "area.csv").write_text("normal_load,real_area\n1,1e-6\n2,2e-6\n")
    data["measured"] = {"normal_area": "area.csv"}
    assert not config_from_dict(data, base_dir=tmp_path).bem.enabled


def test_missing_surface_file_named_with_path(tmp_path):
    data = _base()
    del data["surface"]["synthetic"]
    data["surface"]["file"] = "map.x3p"
    with pytest.raises(ConfigError, match=r"surface\.file: expected an existing file .*map\.x3p"):
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
    with pytest.raises(ConfigError, match="--preset: expected one of"):
        load_preset("huge")


def test_validation_imports_no_numerical_library():
    """Validation is pure Python: a bad config fails before numpy/h5py/solvers load."""
    code = (
        "import sys; from asperity.pipelines.config import load_preset; load_preset('default'); "
        "print(sorted(m for m in ('numpy', 'h5py', 'scipy', 'numba', 'asperity.bem', "
        "'asperity.topo', 'asperity.statmodel.shear') if m in sys.modules))"
    )
    assert python_stdout(code) == "[]"


def test_cli_bad_config_exits_2_naming_the_key(tmp_path, capsys):
    from asperity.pipelines.cli import main

    bad = tmp_path / "job.toml"
    bad.write_text(preset_text("default").replace("E_star = 2.133e6", "E_star = -2.133e6"))
    assert main(["run", str(bad), "--out", str(tmp_path / "out")]) == 2
    assert "material.E_star: expected" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
