"""`asperity init` writes a starter job that loads as written, on a file or the synthetic map."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

from asperity.pipelines.cli import main
from asperity.pipelines.config import load_config, load_preset

DATA = Path(__file__).parents[1] / "data"


def test_init_on_a_measured_map_loads_with_that_file(tmp_path, capsys):
    shutil.copyfile(DATA / "x3p-2.x3p", tmp_path / "map.x3p")
    job = tmp_path / "job.toml"
    assert main(["init", str(job), "--surface", str(tmp_path / "map.x3p")]) == 0
    config = load_config(job)
    assert Path(config.surface.file).resolve() == (tmp_path / "map.x3p").resolve()
    assert config.surface.synthetic is None  # nothing to delete before `file` works
    assert 'file = "map.x3p"' in job.read_text()
    assert main(["init", str(job)]) == 2  # never overwritten
    assert "exists" in capsys.readouterr().err


def test_init_without_surface_is_the_default_synthetic_map(tmp_path):
    job = tmp_path / "job.toml"
    assert main(["init", str(job)]) == 0
    config, default = load_config(job), load_preset("default")
    assert config.surface.synthetic == default.surface.synthetic
    assert config.material == default.material
    # the whole job is the one `asperity run` runs without a file: its six loads, its keys
    assert config.loading == default.loading and len(config.loading.normal_loads) == 6
    assert config.key_document() == default.key_document()


def test_init_on_text_needs_the_unit(tmp_path, capsys):
    text = tmp_path / "profile.txt"
    np.savetxt(text, np.column_stack([np.arange(32) * 0.5, np.sin(np.arange(32))]))
    assert main(["init", str(tmp_path / "a.toml"), "--surface", str(text)]) == 2
    assert "--unit" in capsys.readouterr().err and not (tmp_path / "a.toml").exists()
    assert main(["init", str(tmp_path / "a.toml"), "--surface", str(text), "--unit", "um"]) == 0
    assert load_config(tmp_path / "a.toml").surface.unit == "um"
