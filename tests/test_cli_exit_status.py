"""Every exit status of the ``asperity`` command means one thing (asperity.errors.ExitStatus).

In-process: ``main([...])`` returns the status; handlers are replaced with monkeypatch where a
fault has to be injected (``asperity figures``'s handler stands in for any command).
"""

from __future__ import annotations

import builtins
import errno
import io
import os
import re
import shutil
import signal
import subprocess
import warnings
from collections.abc import Iterator
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity.errors import ExitStatus, InputError, exit_status_epilog, exit_status_table
from asperity.pipelines.cli import main
from asperity.statmodel import TaborWarning
from tests._helpers import adhesive_in_tension_toml

DATA = Path(__file__).resolve().parent / "data"
FRICTION_EXAMPLE = Path(__file__).resolve().parents[1] / "statmodel" / "examples" / "fig4.toml"


def run(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def replace_handler(monkeypatch: pytest.MonkeyPatch, handler) -> None:  # noqa: ANN001
    """Make ``asperity figures`` run ``handler(args)`` instead of drawing the figures."""
    monkeypatch.setattr("asperity.statmodel.cli.run_figures", handler)


def test_codes_are_the_documented_ones():
    codes = {s.name: int(s) for s in ExitStatus}
    assert codes == {
        "OK": 0,
        "NOT_CONVERGED": 1,
        "BAD_INPUT": 2,
        "INVALID_RESULT": 3,
        "INTERNAL_ERROR": 70,
        "INTERRUPTED": 130,
    }


# --------------------------------------------------------------------------- 0 and 1


def test_success_is_0(capsys, tmp_path):
    status, out, err = run(
        capsys, "synth", "--n", 32, "--pixel-size", 1e-5, "--out", tmp_path / "s.npy"
    )
    assert status == ExitStatus.OK and isinstance(status, ExitStatus)
    assert "wrote" in out and err == ""


ADHESIVE_IN_TENSION = adhesive_in_tension_toml(11)


def test_a_solve_that_fails_is_1_with_its_results(capsys, tmp_path):
    """A smooth adhesive contact held in tension: shear peels the junctions until the tensile
    load can no longer be carried, the solve stops (a physical end, not bad input)."""
    params = tmp_path / "tension.toml"
    params.write_text(ADHESIVE_IN_TENSION)
    status, out, err = run(capsys, "friction", params, "--json")
    assert status == ExitStatus.NOT_CONVERGED
    assert '"converged": false' in out
    assert "cannot be carried" in err and "error" not in err


# ------------------------------------------------------------------------------ 2


def test_usage_errors_are_2_in_one_line_without_the_usage_block(capsys):
    for argv in (["stats"], ["stats", "x.npy", "--neighbours", "5"], ["no-such-command"]):
        assert main(argv) == ExitStatus.BAD_INPUT
        err = capsys.readouterr().err
        assert len(err.splitlines()) == 1 and "usage:" not in err
        assert err.startswith("asperity") and ": error: " in err


def _bump_map(tmp_path: Path) -> Path:
    """A 16 x 16 paraboloid bump (heights in m), as .npy (no pixel size stored)."""
    x = np.linspace(-1.0, 1.0, 16)
    path = tmp_path / "bump.npy"
    np.save(path, -1e-6 * (x[:, None] ** 2 + x[None, :] ** 2))
    return path


BUMP = ["bem", "{map}", "--pixel-size", "1e-5"]


@pytest.mark.parametrize(
    "argv, line",
    [
        # each of these used to run: exit 1 with a residual of 7e278, a NaN force, 1.6e294 N
        (
            [*BUMP, "--e-star", "1e300", "--load", "1"],
            "asperity bem: error: --e-star: expected a number in [100, 1e+13] Pa (",
        ),
        ([*BUMP, "--e-star", "1e6", "--load", "1e300"], "--load: expected a number in [-1e+06,"),
        (
            [*BUMP, "--e-star", "1e6", "--mean-pressure", "1e300"],
            "--mean-pressure: expected a number in [-1e+11, 1e+11] Pa",
        ),
        ([*BUMP, "--e-star", "1e6", "--load", "1e5"], "--load: 100000 N on the map's"),
        # a pull from a cold start has nothing to pull on: bad input, not "not converged"
        (
            [*BUMP, "--e-star", "1e6", "--load", "-1e-3", "--work-of-adhesion", "0.05"],
            "--load: the first load must be >= 0",
        ),
        ([*BUMP, "--e-star", "1e6", "--load", "1", "--tol", "1"], "--tol: expected a number in"),
        (["synth", "--out", "{tmp}/s.npy", "--pixel-size", "1e300"], "--pixel-size: expected"),
        (["synth", "--out", "{tmp}/s.npy", "--rms-height", "1e300"], "--rms-height: expected"),
        (["synth", "--out", "{tmp}/s.npy", "--seed", "-1"], "--seed: expected an integer in [0,"),
        (["stats", "{map}", "--pixel-size", "1e-5", "--outliers", "mad:"], "--outliers: mad:''"),
        (["stats", "{map}", "--pixel-size", "1e300"], "--pixel-size: expected a number in"),
        (["batch", "job.toml", "m.npy", "--workers", "1000000000"], "--workers: expected an"),
        (["run", "--workers", "0"], "--workers: expected an integer in [1, 256]"),
        (["report", "{tmp}", "--dpi", "1"], "--dpi: expected an integer in [30, 2400]"),
    ],
)
def test_options_share_the_jobs_bounds_exit_2_in_one_line(capsys, tmp_path, argv, line):
    argv = [
        a.replace("{map}", str(_bump_map(tmp_path))).replace("{tmp}", str(tmp_path)) for a in argv
    ]
    status = main(argv)  # refused by argparse (the option) or the handler (the value's use)
    err = capsys.readouterr().err
    assert status == ExitStatus.BAD_INPUT, err
    assert len(err.splitlines()) == 1 and "usage:" not in err and "Traceback" not in err
    assert err.startswith(f"asperity {argv[0]}: error: ") and line in err, err
    assert not (tmp_path / "s.npy").exists()


def test_an_option_and_the_job_key_give_the_same_bound(capsys, tmp_path):
    from asperity.pipelines.config import config_from_dict
    from asperity.schema import ConfigError

    assert main(["synth", "--out", str(tmp_path / "s.npy"), "--pixel-size", "1"]) == 2
    option = capsys.readouterr().err.split("--pixel-size: ", 1)[1].rsplit(", got", 1)[0]
    with pytest.raises(ConfigError) as info:
        config_from_dict({"surface": {"synthetic": {"pixel_size": 1.0}}}, source="job.toml")
    key = str(info.value).split("surface.synthetic.pixel_size: ", 1)[1].rsplit(", got", 1)[0]
    assert option == key


def test_scan_figure_into_a_folder_writes_inside_it_and_says_where(capsys, tmp_path):
    folder = tmp_path / "figures"
    folder.mkdir()
    status = main(
        ["scan", str(_bump_map(tmp_path)), "--pixel-size", "1e-5", "--max-stride", "2"]
        + ["--figure", str(folder)]
    )
    out = capsys.readouterr().out
    assert status == ExitStatus.OK
    assert (folder / "resolution_scan.png").is_file()
    assert f"wrote {folder / 'resolution_scan.png'}" in out
    assert not (tmp_path / "figures.png").exists()


def test_no_command_is_2(capsys):
    assert main([]) == ExitStatus.BAD_INPUT
    assert "COMMAND" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, named",
    [
        (["stats", "{tmp}/missing.x3p"], "{tmp}/missing.x3p"),
        (
            ["friction", "{tmp}/missing.toml"],
            "missing.toml: cannot read the parameter file: No such file or directory",
        ),
        (["friction", "{tmp}"], "{tmp}"),  # a directory where a file was expected
        (["figures", "--out", "{tmp}/a_file.txt"], "a_file.txt"),  # a file where a folder was
        (["scan", str(DATA / "dektak-1.csv"), "--max-stride", "5000"], "--max-stride"),
        (["stats", "{tmp}/m.npy", "--pixel-size", "-1e-6"], "--pixel-size"),  # InputError (CLI)
        (["stats", "{tmp}/m.npy"], "--pixel-size"),  # a file without a pixel size
        (["synth", "--n", "32", "--pixel-size", "1e-5", "--out", "{tmp}/s.png"], "--out"),
    ],
)
def test_bad_input_is_2_with_one_line_naming_it(capsys, tmp_path, argv, named):
    np.save(tmp_path / "m.npy", np.zeros((8, 8)))
    (tmp_path / "a_file.txt").write_text("not a folder")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    status, _, err = run(capsys, *argv)
    assert status == ExitStatus.BAD_INPUT
    assert err.startswith(f"asperity {argv[0]}: error: ")
    assert named.replace("{tmp}", str(tmp_path)) in err
    assert len(err.splitlines()) == 1 and "Traceback" not in err


def test_bad_parameter_value_is_2(capsys, tmp_path):
    params = tmp_path / "p.toml"
    params.write_text(
        FRICTION_EXAMPLE.read_text().replace("mode_mixity = 0.2", "mode_mixity = 1.2")
    )
    status, _, err = run(capsys, "friction", params)
    assert status == ExitStatus.BAD_INPUT
    assert err.startswith("asperity friction: error: ") and "mode_mixity" in err


def test_library_validation_errors_are_input_errors():
    """Bad arguments to library functions raise InputError (still a ValueError)."""
    from asperity import statmodel, topo

    with pytest.raises(InputError, match="mode_mixity"):
        statmodel.Material(2e6, 0.04, 1.5, 1e5)
    with pytest.raises(InputError, match="pixel size"):
        topo.HeightMap(np.zeros((4, 4)), 0.0, 1e-6)
    with pytest.raises(InputError, match="stride"):
        topo.decimate(topo.HeightMap(np.zeros((4, 4)), 1e-6, 1e-6), 0)
    with pytest.raises(ValueError, match="max_stride"):
        topo.resolution_scan(topo.HeightMap(np.zeros((9, 9)), 1e-6, 1e-6), 5)


# ----------------------------------------------------------------------------- 70


@pytest.mark.parametrize(
    "fault",
    [
        ZeroDivisionError("division by zero"),
        ValueError("a bare ValueError is a bug"),
        OSError(5, "I/O"),
    ],
)
def test_an_internal_bug_is_70_never_2(capsys, monkeypatch, fault):
    def broken(args):  # noqa: ANN001, ARG001
        raise fault

    replace_handler(monkeypatch, broken)
    monkeypatch.delenv("ASPERITY_DEBUG", raising=False)
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.INTERNAL_ERROR
    assert err == (
        f"asperity figures: internal error: {type(fault).__name__}: {fault} "
        "(please report this; run with ASPERITY_DEBUG=1 for the traceback)\n"
    )


def test_asperity_debug_adds_the_traceback(capsys, monkeypatch):
    def broken(args):  # noqa: ANN001, ARG001
        return 1 / 0

    replace_handler(monkeypatch, broken)
    monkeypatch.setenv("ASPERITY_DEBUG", "1")
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.INTERNAL_ERROR
    assert err.startswith("Traceback (most recent call last):")
    assert "in broken" in err and "return 1 / 0" in err
    assert err.splitlines()[-1].startswith("asperity figures: internal error: ZeroDivisionError")
    monkeypatch.setenv("ASPERITY_DEBUG", "0")
    assert run(capsys, "figures", "--out", "anywhere")[2].startswith("asperity figures:")


def test_an_undocumented_status_from_a_handler_is_70(capsys, monkeypatch):
    replace_handler(monkeypatch, lambda args: 5)
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.INTERNAL_ERROR and "5 is not a valid ExitStatus" in err


# ---------------------------------------------------------------------------- 130


def test_ctrl_c_is_130(capsys, monkeypatch):
    def interrupted(args):  # noqa: ANN001, ARG001
        raise KeyboardInterrupt

    replace_handler(monkeypatch, interrupted)
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.INTERRUPTED
    assert err.startswith("asperity figures: interrupted")


# ------------------------------------------------------------------------- warnings


def test_warnings_are_one_clean_line_each(capsys, monkeypatch):
    """TaborWarning, numpy's RuntimeWarnings and others: one line per distinct message,
    ``asperity CMD: warning: ...``, never Python's ``file:line: Category: message`` form."""

    def noisy(args):  # noqa: ANN001, ARG001
        for _ in range(3):
            warnings.warn(
                "Tabor parameter mu = 2.6 < 5: outside the model's\n  validity",
                TaborWarning,
                stacklevel=1,
            )
            with np.errstate(divide="warn"):
                np.log(np.zeros(2))
        warnings.warn("something else", UserWarning, stacklevel=1)
        return ExitStatus.OK

    replace_handler(monkeypatch, noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.OK
    assert err.splitlines() == [
        "asperity figures: warning: Tabor parameter mu = 2.6 < 5: outside the model's validity",
        "asperity figures: warning: RuntimeWarning: divide by zero encountered in log",
        "asperity figures: warning: something else",
    ]


def test_warning_filters_still_apply_and_are_restored(capsys, monkeypatch):
    def noisy(args):  # noqa: ANN001, ARG001
        warnings.warn("silenced by the user", RuntimeWarning, stacklevel=1)

    replace_handler(monkeypatch, noisy)
    before = warnings.showwarning
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.OK and err == ""
    assert warnings.showwarning is before


# ------------------------------------------------ 2: the user's disk (read-only, full)


class _FillingFile:
    """A file that takes ``room[0]`` more bytes, then fails as a full disk does (ENOSPC),
    after writing what fitted (a half-written file is what the failure leaves)."""

    def __init__(self, handle, room: list[int]):  # noqa: ANN001 (a file object)
        self._handle, self._room = handle, room

    def write(self, data):  # noqa: ANN001, ANN201
        if len(data) > self._room[0]:
            self._handle.write(data[: self._room[0]])
            self._room[0] = 0
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        self._room[0] -= len(data)
        return self._handle.write(data)

    def fileno(self) -> int:  # writers must go through write() (PIL would use the fd)
        raise io.UnsupportedOperation("fileno")

    def __getattr__(self, name: str):  # noqa: ANN204
        return getattr(self._handle, name)

    def __enter__(self):  # noqa: ANN204
        return self

    def __exit__(self, *exc: object) -> None:
        self._handle.close()


def fill_disk_after(monkeypatch: pytest.MonkeyPatch, folder: Path, n_bytes: int) -> None:
    """Every file opened for writing in ``folder`` shares ``n_bytes`` of free space."""
    real_open, room = builtins.open, [n_bytes]

    def open_on_a_small_disk(file, mode="r", *args, **kwargs):  # noqa: ANN001, ANN202
        handle = real_open(file, mode, *args, **kwargs)
        if isinstance(file, str | os.PathLike) and Path(file).parent == folder and "w" in mode:
            return _FillingFile(handle, room)
        return handle

    monkeypatch.setattr(builtins, "open", open_on_a_small_disk)


@pytest.fixture(scope="module")
def small_map(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("map") / "map.h5"
    assert main(["synth", "--n", "64", "--seed", "3", "--out", str(path)]) == 0
    return path


def _tmpfs(folder: Path, options: str) -> bool:
    """Mount a tmpfs on ``folder`` (root only); False where that is not possible."""
    if os.geteuid() != 0 or shutil.which("mount") is None:
        return False
    folder.mkdir(parents=True, exist_ok=True)
    command = ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)]
    done = subprocess.run(command, check=False, capture_output=True)
    return done.returncode == 0


@pytest.fixture
def read_only_folder(tmp_path) -> Iterator[Path]:
    """A folder no file can be written in: a read-only tmpfs as root, else mode 0o500."""
    folder = tmp_path / "ro"
    if _tmpfs(folder, "ro,size=64k"):
        yield folder
        subprocess.run(["umount", str(folder)], check=False)
        return
    if os.geteuid() == 0:
        pytest.skip("root writes into read-only folders and cannot mount one here")
    folder.mkdir()
    folder.chmod(0o500)
    yield folder
    folder.chmod(0o700)


@pytest.fixture
def tiny_disk(tmp_path) -> Iterator[Path]:
    """A real 20 kB file system (root only: a tmpfs), full after a few kB of output."""
    folder = tmp_path / "tiny"
    if not _tmpfs(folder, "size=20k"):
        pytest.skip("needs root and tmpfs to make a real full disk (the patched disk tests run)")
    yield folder
    subprocess.run(["umount", str(folder)], check=False)


def _one_error_line(err: str, *words: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    assert all(word in lines[0] for word in words), lines[0]
    return lines[0]


WRITERS = {
    "scan --out": ("scan", "{map}", "--max-stride", "4", "--out", "{folder}/scan.h5"),
    "synth --out .npy": ("synth", "--n", "64", "--out", "{folder}/a.npy"),
    "synth --out .npz": ("synth", "--n", "64", "--out", "{folder}/a.npz"),
    "synth --out .h5": ("synth", "--n", "64", "--out", "{folder}/a.h5"),
}


def _argv(name: str, small_map: Path, folder: Path) -> list[str]:
    return [a.format(map=small_map, folder=folder) for a in WRITERS[name]]


@pytest.mark.parametrize("name", list(WRITERS))
def test_a_read_only_folder_is_2_in_one_line_and_nothing_written(
    capsys, small_map, read_only_folder, name
):
    status, _, err = run(capsys, *_argv(name, small_map, read_only_folder))
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, str(read_only_folder), "while writing")
    assert list(read_only_folder.iterdir()) == []


@pytest.mark.parametrize("n_bytes", [0, 3000])
@pytest.mark.parametrize("name", list(WRITERS))
def test_a_full_disk_is_2_in_one_line_and_leaves_no_partial_file(
    capsys, monkeypatch, small_map, tmp_path, name, n_bytes
):
    folder = tmp_path / "disk"
    folder.mkdir()
    fill_disk_after(monkeypatch, folder, n_bytes)
    status, _, err = run(capsys, *_argv(name, small_map, folder))
    monkeypatch.undo()
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "No space left on device while writing")
    left = sorted(p.name for p in folder.iterdir())
    # nothing, or (scan) the complete scan file written before its figure filled the disk
    assert left in ([], ["scan.h5"]), left
    for name_left in left:
        with h5py.File(folder / name_left, "r") as handle:
            assert handle["stride"][:].tolist() == [1, 2, 3, 4]


@pytest.mark.parametrize("name", list(WRITERS))
def test_a_real_full_disk_leaves_no_zero_byte_or_partial_file(capsys, tiny_disk, small_map, name):
    (tiny_disk / "filler").write_bytes(b"\0" * 12_000)  # about 8 kB left
    status, _, err = run(capsys, *_argv(name, small_map, tiny_disk))
    assert status == ExitStatus.BAD_INPUT, err
    _one_error_line(err, "No space left on device")
    left = sorted(p.name for p in tiny_disk.iterdir() if p.name != "filler")
    assert left in ([], ["scan.h5"]), left


def test_dev_full_as_the_scan_output_is_2(capsys, small_map):
    status, _, err = run(capsys, "scan", small_map, "--max-stride", "4", "--out", "/dev/full")
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "/dev/full", "character device")


def test_run_out_empty_is_refused_before_anything_is_written(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, _, err = run(capsys, "run", "--out", "")
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "--out", "empty")
    assert list(tmp_path.iterdir()) == []


def test_batch_out_read_only_is_2_before_any_map_runs(
    capsys, small_map, read_only_folder, tmp_path
):
    job = tmp_path / "job.toml"
    job.write_text(f'[surface]\nfile = "{small_map}"\n')
    status, _, err = run(capsys, "batch", job, small_map, "--out", read_only_folder / "batch")
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "--out", f"cannot write in {read_only_folder} (")
    status, _, err = run(capsys, "batch", job, small_map, "--out", "")
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "--out", "empty")


def test_a_storage_error_escaping_a_command_is_2_not_70(capsys, monkeypatch):
    def read_only(args):  # noqa: ANN001, ARG001
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), "/mnt/ro/out")

    replace_handler(monkeypatch, read_only)
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.BAD_INPUT
    _one_error_line(err, "/mnt/ro/out", "Read-only file system")


# ----------------------------------------------------- 130: an interrupt is never lost


def test_a_ctrl_c_turned_into_another_error_by_a_library_is_still_130(capsys, monkeypatch):
    def interrupted_then_relabelled(args):  # noqa: ANN001, ARG001
        try:
            signal.raise_signal(signal.SIGINT)
        except KeyboardInterrupt:
            raise RuntimeError("a library's cleanup failed") from None

    replace_handler(monkeypatch, interrupted_then_relabelled)
    status, _, err = run(capsys, "figures", "--out", "anywhere")
    assert status == ExitStatus.INTERRUPTED
    _one_error_line(err, "interrupted")


ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("document", ["README.md", "docs/DEVELOPING.md"])
def test_the_exit_status_tables_are_generated_from_exit_status(document: str) -> None:
    """README's and docs/DEVELOPING.md's tables are the text ExitStatus writes, and the
    ``--help`` epilog is built from its labels: one source for every status's meaning."""
    text = (ROOT / document).read_text(encoding="utf-8")
    block = re.search(
        r"<!-- exit statuses: asperity.errors -->\n(.*?)\n<!-- end exit statuses -->", text, re.S
    )
    assert block, f"{document} lost its generated exit-status table"
    assert block.group(1) == exit_status_table(), (
        "regenerate the table: python -c 'from asperity.errors import exit_status_table; "
        "print(exit_status_table())'"
    )


def test_every_status_has_a_meaning_and_the_help_lists_every_status(capsys) -> None:
    with pytest.raises(SystemExit):
        main(["--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert exit_status_epilog() in help_text
    for status in ExitStatus:
        assert status.label and status.meaning
        assert f"{status.value} {status.label}" in help_text
    assert [int(s) for s in ExitStatus] == [0, 1, 2, 3, 70, 130]
