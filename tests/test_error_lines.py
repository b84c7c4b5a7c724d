"""Every error and warning line is bounded and inert (issue 40, item 9).

Whatever a message echoes (a 100,000-character option value, a TOML key holding an escape
sequence, a file name with a newline), the line on stderr is one line of at most 1000
characters, the cut value's full size said, and no control character reaches the terminal.
"""

from __future__ import annotations

import warnings

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.errors import MAX_ERROR_LINE, InputError, bounded_line, cut, error_line, inert
from asperity.pipelines.cli import _report_exception, main, warnings_as_lines


def _controls(text: str) -> list[str]:
    return [c for c in text if (ord(c) < 0x20 and c != "\n") or 0x7F <= ord(c) < 0xA0]


def _one_bounded_line(err: str) -> str:
    assert err.count("\n") == 1 and err.endswith("\n")
    line = err[:-1]
    assert len(line) <= MAX_ERROR_LINE
    assert _controls(line) == []
    return line


def test_a_100000_character_option_value_is_cut_and_its_size_said(capsys):
    assert main(["run", "--preset", "x" * 100_000]) == 2
    line = _one_bounded_line(capsys.readouterr().err)
    assert "--preset" in line and "100002 characters" in line and "choose from" in line


def test_escape_codes_in_an_option_value_are_shown_escaped(capsys):
    assert main(["run", "--preset", "\x1b[2J\x1b[31mred"]) == 2
    line = _one_bounded_line(capsys.readouterr().err)
    assert "[2J" in line and "\x1b" not in line


def test_a_toml_key_holding_an_escape_sequence_reaches_the_terminal_inert(tmp_path, capsys):
    job = tmp_path / "job.toml"
    assert main(["init", str(job)]) == 0
    text = job.read_text().replace("[material]\n", '[material]\n"\\u001b[2J\\u0007" = 1\n', 1)
    job.write_text(text)
    assert main(["run", str(job), "--out", str(tmp_path / "out")]) == 2
    line = _one_bounded_line(capsys.readouterr().err.splitlines(keepends=True)[-1])
    assert "[2J" in line and "\x1b" not in line and "\x07" not in line


def test_bad_input_and_internal_error_lines_are_bounded(capsys):
    huge = "value " + "7," * 50_000 + "\x1b]0;title\x07 end"
    assert _report_exception("bem", InputError(f"--tangential-displacement: {huge}")) == 2
    line = _one_bounded_line(capsys.readouterr().err)
    assert line.startswith("asperity bem: error: --tangential-displacement:")
    assert "characters in all" in line and line.endswith("end")
    assert _report_exception("bem", RuntimeError(huge)) == 70
    line = _one_bounded_line(capsys.readouterr().err)
    assert line.startswith("asperity bem: internal error: RuntimeError:")
    assert line.endswith("for the traceback)")


def test_a_full_disk_reported_by_h5py_is_bad_input_in_one_line(capsys):
    """h5py reports a full disk as a RuntimeError holding the errno (no filename attribute)."""
    full = RuntimeError(
        "Can't synchronously write data (file write failed: filename = 'results.h5', "
        "errno = 28, error message = 'No space left on device')"
    )
    assert _report_exception("run", full) == 2
    line = _one_bounded_line(capsys.readouterr().err)
    assert line.startswith("asperity run: error: ") and "No space left on device" in line


def test_a_warning_line_is_bounded_and_inert(capsys):
    with warnings_as_lines("run"):
        warnings.warn("w" * 5000 + " \x1b[2J file\nname", UserWarning, stacklevel=1)
    line = _one_bounded_line(capsys.readouterr().err)
    assert line.startswith("asperity run: warning: ") and "5000 characters" in line


@settings(max_examples=40)
@given(st.text(max_size=3000), st.integers(100, 2000))
def test_any_text_makes_one_inert_line_within_the_limit(text, limit):
    line = bounded_line(text, limit)
    assert len(line) <= limit and "\n" not in line and _controls(line) == []
    assert len(error_line("asperity x: error: ", text)) <= MAX_ERROR_LINE


@given(st.text(max_size=400))
def test_inert_keeps_printable_text_and_cut_keeps_short_text(text):
    shown = inert(text)
    assert _controls(shown) == [] and "\n" not in shown
    if text.isprintable():
        assert shown == text and cut(text, 400) == text


def test_a_zero_friction_coefficient_is_bad_input_not_a_stalled_solve(capsys):
    from pathlib import Path

    surface = Path(__file__).parent / "data" / "x3p-2.x3p"
    command = ["bem", str(surface), "--e-star", "2e6", "--load", "0.001"]
    shear = ["--tangential-displacement", "1e-6", "--friction-coefficient", "0"]
    assert main([*command, *shear]) == 2  # 0.4.2: solved for minutes, then exit 1
    line = _one_bounded_line(capsys.readouterr().err)
    assert "--friction-coefficient" in line and "stick" in line


def test_an_external_link_is_named_in_english(tmp_path):
    import h5py

    from asperity.h5 import UntrustedContentError, check_self_contained

    path = tmp_path / "linked.h5"
    with h5py.File(path, "w") as f:
        f["elsewhere"] = h5py.ExternalLink("/etc/passwd.h5", "/data")
    with h5py.File(path, "r") as f, pytest.raises(UntrustedContentError) as info:
        check_self_contained(f, path, 10**6)
    assert "is an external link" in str(info.value)


@pytest.mark.slow  # a batch run draws its summary figure: a few seconds
def test_batch_lines_naming_a_hostile_map_are_inert(tmp_path, capsys):
    job = tmp_path / "job.toml"
    assert main(["init", str(job)]) == 0
    bad = tmp_path / "\x1b[2J\x1b[31mmap.npy"
    bad.write_bytes(b"\x93NUMPY not really")
    assert main(["batch", str(job), str(bad), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "[2J" in err and "\x1b" not in err
    assert all(len(line) <= MAX_ERROR_LINE for line in err.splitlines())
