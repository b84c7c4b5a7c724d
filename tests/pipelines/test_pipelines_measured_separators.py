"""Measured files separated by tabs, semicolons, commas or whitespace are read alike; a file
that still lacks a column is refused naming the separator found (issue 37, item 4)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.pipelines.measured import MeasuredFileError, read_normal_area, read_shear_area

ROWS = [(0.0, 2.0), (0.1, 1.9), (0.2, 1.7)]


def _write(tmp_path, header: list[str], sep: str, rows=ROWS) -> object:
    path = tmp_path / "curve.txt"
    lines = [sep.join(header)] + [sep.join(f"{v:g}" for v in row) for row in rows]
    path.write_text("# exported\n" + "\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("sep", ["\t", ";", ",", " ", "   ", " \t "])
def test_every_separator_gives_the_same_curve(tmp_path, sep):
    path = _write(tmp_path, ["tangential_force [mN]", "real_area [mm^2]"], sep)
    (curve,) = read_shear_area(path, normal_load=1.0)
    np.testing.assert_allclose(curve.tangential_force, [0.0, 1e-4, 2e-4])  # mN -> N
    np.testing.assert_allclose(curve.real_area, [2e-6, 1.9e-6, 1.7e-6])  # mm^2 -> m^2


def test_a_tab_separated_long_file_with_a_load_column(tmp_path):
    path = tmp_path / "long.tsv"
    path.write_text(
        "normal_load\ttangential_force\treal_area\n1\t0\t3e-6\n1\t0.1\t2.9e-6\n"
        "2\t0\t5e-6\n2\t0.2\t4.6e-6\n"
    )
    curves = read_shear_area(path)
    assert [c.normal_load for c in curves] == [1.0, 2.0]
    np.testing.assert_allclose(curves[1].real_area, [5e-6, 4.6e-6])


@pytest.mark.parametrize(("sep", "name"), [("\t", "tab"), (";", "semicolon"), (" ", "whitespace")])
def test_a_missing_column_names_the_separator_found(tmp_path, sep, name):
    path = _write(tmp_path, ["force", "area"], sep)
    with pytest.raises(MeasuredFileError, match=rf"separated by {name}: 'force', 'area'"):
        read_shear_area(path, normal_load=1.0)


def test_a_tab_file_with_commas_as_decimal_marks_is_refused_naming_the_cell(tmp_path):
    path = tmp_path / "area.tsv"
    path.write_text("normal_load\treal_area\n1,5\t2e-6\n2,5\t3e-6\n")
    with pytest.raises(MeasuredFileError, match=r"line 2, column 'normal_load'.*'1,5'"):
        read_normal_area(path)


@settings(max_examples=40, deadline=None)
@given(
    sep=st.sampled_from(["\t", ";", ",", " "]),
    values=st.lists(st.tuples(st.floats(0.1, 10.0), st.floats(1e-7, 1e-5)), min_size=2, max_size=8),
)
def test_any_separator_round_trips_the_values(tmp_path_factory, sep, values):
    path = _write(tmp_path_factory.mktemp("sep"), ["normal_load", "real_area"], sep, values)
    curve = read_normal_area(path)
    expected = sorted((float(f"{a:g}"), float(f"{b:g}")) for a, b in values)
    np.testing.assert_allclose(curve.normal_load, [a for a, _ in expected])
