"""`asperity init` never deletes or mis-writes a job (issue 40, items 1, 2, 8 and 11).

A failed ``--force`` leaves the old job byte for byte; file names and units reach the TOML
escaped, so that the job read back names exactly the file given (or init refuses, exit 2); the
surface is read by the readers the job will use and refused as they refuse it.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity.pipelines.cli import main
from asperity.pipelines.config import load_config

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

DATA = Path(__file__).parents[1] / "data"
OLD_JOB = b"# my own job, edited by hand\n[surface]\nfile = 'x.x3p'\n"


def _keep(tmp_path: Path) -> Path:
    job = tmp_path / "keep.toml"
    job.write_bytes(OLD_JOB)
    return job


def test_failed_force_leaves_the_old_job_byte_identical(tmp_path, capsys):
    job = _keep(tmp_path)
    bogus = tmp_path / 'q".sur'
    bogus.write_bytes(b"not a surface at all")
    assert main(["init", str(job), "--surface", str(bogus), "--force"]) == 2
    assert job.read_bytes() == OLD_JOB
    shutil.copyfile(DATA / "x3p-2.x3p", tmp_path / "map.x3p")
    bad_unit = ["--surface", str(tmp_path / "map.x3p"), "--unit", 'um"\nx = 1', "--force"]
    assert main(["init", str(job), *bad_unit]) == 2
    assert job.read_bytes() == OLD_JOB
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.toml", "map.x3p", 'q".sur']
    capsys.readouterr()


def test_a_quote_in_the_file_name_reads_that_file_not_another(tmp_path):
    shutil.copyfile(DATA / "x3p-2.x3p", tmp_path / 'a.x3p" #.x3p')
    shutil.copyfile(DATA / "x3p-2.x3p", tmp_path / "a.x3p")  # the file 0.4.2's job read
    job = tmp_path / "job.toml"
    assert main(["init", str(job), "--surface", str(tmp_path / 'a.x3p" #.x3p')]) == 0
    assert load_config(job).surface.file.name == 'a.x3p" #.x3p'


def test_a_back_slash_is_part_of_the_name_not_a_folder(tmp_path):
    if os.sep == "\\":  # pragma: no cover - a back-slash is a separator there
        pytest.skip("POSIX file names only")
    shutil.copyfile(DATA / "x3p-2.x3p", tmp_path / "a\\b.x3p")
    job = tmp_path / "job.toml"
    assert main(["init", str(job), "--surface", str(tmp_path / "a\\b.x3p")]) == 0
    assert load_config(job).surface.file == tmp_path / "a\\b.x3p"


#: File name characters: anything a POSIX name may hold but the separator and NUL.
NAME_CHARS = st.characters(blacklist_characters="/\x00", blacklist_categories=("Cs",))


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(stem=st.text(NAME_CHARS, min_size=1, max_size=30))
def test_any_file_name_round_trips_through_the_job(tmp_path, stem):
    folder = tmp_path / str(abs(hash(stem)))
    folder.mkdir(exist_ok=True)
    surface = folder / f"{stem}.x3p"
    try:
        shutil.copyfile(DATA / "x3p-2.x3p", surface)
    except OSError:  # a name this file system refuses (too long, not encodable)
        return
    job = folder / "job.toml"
    job.unlink(missing_ok=True)
    status = main(["init", str(job), "--surface", str(surface)])
    assert status in (0, 2)
    if status == 0:
        assert load_config(job).surface.file.resolve() == surface.resolve()
    else:
        assert not job.exists()


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(unit=st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=12))
def test_any_unit_is_the_job_s_unit_or_refused_and_adds_no_key(tmp_path, unit):
    text = tmp_path / "profile.txt"
    if not text.exists():
        np.savetxt(text, np.column_stack([np.arange(32) * 0.5, np.sin(np.arange(32))]))
    job = tmp_path / "job.toml"
    job.unlink(missing_ok=True)
    status = main(["init", str(job), "--surface", str(text), "--unit", unit])
    assert status in (0, 2)
    if status == 2:
        assert not job.exists()
        return
    data = tomllib.loads(job.read_text(encoding="utf-8"))
    assert data["surface"]["unit"] == unit
    assert load_config(job).surface.unit == unit
    assert sorted(data) == ["bem", "loading", "material", "surface"]


def test_a_file_name_that_is_not_utf8_is_refused(tmp_path, capsys):
    if os.sep == "\\":  # pragma: no cover
        pytest.skip("POSIX byte file names only")
    raw = os.fsencode(tmp_path) + b"/bad\xff.x3p"
    try:
        shutil.copyfile(DATA / "x3p-2.x3p", raw)
    except OSError:  # pragma: no cover - a file system that refuses the byte
        pytest.skip("the file system refuses non-UTF-8 names")
    job = tmp_path / "job.toml"
    assert main(["init", str(job), "--surface", os.fsdecode(raw)]) == 2
    err = capsys.readouterr().err
    assert "UTF-8" in err and not job.exists()
    assert "\udcff" not in err  # shown escaped, never as a raw surrogate


def test_init_refuses_what_the_readers_refuse(tmp_path, capsys):
    huge = tmp_path / "huge.npy"
    with huge.open("wb") as handle:  # a header declaring 30000 x 30000, no data
        np.lib.format.write_array_header_1_0(
            handle, {"descr": "<f8", "fortran_order": False, "shape": (30000, 30000)}
        )
    truncated = tmp_path / "cut.x3p"
    truncated.write_bytes((DATA / "x3p-2.x3p").read_bytes()[:300])
    for surface in (huge, truncated):
        job = tmp_path / "job.toml"
        assert main(["init", str(job), "--surface", str(surface)]) == 2
        err = capsys.readouterr().err
        assert "--surface" in err and surface.name in err and not job.exists()


def test_the_job_name_in_the_comment_cannot_break_the_toml(tmp_path):
    job = tmp_path / "a\nb = 1 #.toml"
    assert main(["init", str(job)]) == 0
    from asperity.pipelines.config import preset_text

    # the tables of the default job, no key added by the name
    assert sorted(tomllib.loads(job.read_text())) == sorted(tomllib.loads(preset_text("default")))


def test_a_300_character_job_name_is_bad_input(tmp_path, capsys):
    assert main(["init", str(tmp_path / ("j" * 300 + ".toml"))]) == 2
    err = capsys.readouterr().err
    assert "at most 255" in err and "internal error" not in err
    name = "k" * 245 + ".toml"  # fits NAME_MAX; its temporary must too
    assert main(["init", str(tmp_path / name)]) == 0
    assert (tmp_path / name).is_file()


def test_surface_that_is_not_a_regular_file_is_named_for_what_it_is(tmp_path, capsys):
    job = str(tmp_path / "job.toml")
    assert main(["init", job, "--surface", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err
    if hasattr(os, "mkfifo"):
        os.mkfifo(tmp_path / "pipe.x3p")
        assert main(["init", job, "--surface", str(tmp_path / "pipe.x3p")]) == 2
        assert "FIFO" in capsys.readouterr().err
    if Path("/dev/zero").exists():
        assert main(["init", job, "--surface", "/dev/zero"]) == 2
        assert "character device" in capsys.readouterr().err
    assert main(["init", job, "--surface", str(tmp_path / "none.x3p")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_force_onto_a_folder_names_the_folder_not_a_temporary(tmp_path, capsys):
    folder = tmp_path / "d.toml"
    folder.mkdir()
    assert main(["init", str(folder), "--force"]) == 2
    err = capsys.readouterr().err
    assert "d.toml: is a directory" in err and ".tmp" not in err
    assert list(folder.iterdir()) == [] and sorted(tmp_path.iterdir()) == [folder]


def test_a_numpy_map_needs_and_takes_its_pixel_size(tmp_path, capsys):
    surface = tmp_path / "map.npy"
    np.save(surface, np.random.default_rng(0).normal(size=(64, 64)) * 1e-6)
    job = tmp_path / "job.toml"
    assert main(["init", str(job), "--surface", str(surface)]) == 2  # the job could not run
    assert "--pixel-size" in capsys.readouterr().err and not job.exists()
    assert main(["init", str(job), "--surface", str(surface), "--pixel-size", "2e-6"]) == 0
    assert load_config(job).surface.pixel_size == 2e-6
