"""Measured CSV curves: per-load and long files, errors naming file and column."""

from __future__ import annotations

import numpy as np
import pytest

from asperity.errors import InputError
from asperity.pipelines.measured import (
    ShearAreaCurve,
    read_normal_area,
    read_shear_area,
    write_shear_area,
)


def test_normal_area_sorted_by_load(tmp_path):
    path = tmp_path / "area.csv"
    path.write_text("# Sahli-like\nnormal_load,real_area,comment\n2.0,3e-6,x\n1.0,2e-6,y\n")
    curve = read_normal_area(path)
    np.testing.assert_array_equal(curve.normal_load, [1.0, 2.0])
    np.testing.assert_array_equal(curve.real_area, [2e-6, 3e-6])


def test_long_file_round_trip(tmp_path):
    curves = [
        ShearAreaCurve(1.0, np.array([0.0, 0.1, 0.2]), np.array([3e-6, 2.9e-6, 2.7e-6])),
        ShearAreaCurve(2.0, np.array([0.0, 0.3]), np.array([5e-6, 4.5e-6])),
    ]
    path = tmp_path / "long.csv"
    write_shear_area(path, curves)
    back = read_shear_area(path)
    assert [c.normal_load for c in back] == [1.0, 2.0]
    for a, b in zip(curves, back, strict=True):
        np.testing.assert_array_equal(a.tangential_force, b.tangential_force)
        np.testing.assert_array_equal(a.real_area, b.real_area)


def test_one_curve_file_takes_load_from_config(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("tangential_force,real_area\n0.2,1e-6\n0.0,2e-6\n")
    (curve,) = read_shear_area(path, normal_load=1.5)
    assert curve.normal_load == 1.5
    np.testing.assert_array_equal(curve.tangential_force, [0.2, 0.0])  # file order kept
    # without a declared load the file must hold its loads, and the message lists them
    with pytest.raises(
        InputError,
        match=r"missing column 'normal_load' .*expected columns normal_load, tangential_force, "
        r"real_area .*or declare the file's one load",
    ):
        read_shear_area(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("tangential_force,area\n0,1\n1,2\n", "missing column 'real_area'"),
        ("tangential_force,real_area\n0,abc\n1,2\n", "line 2, column 'real_area'"),
        ("tangential_force,real_area\n0,nan\n1,2\n", "not finite"),
        ("tangential_force,real_area\n0,1\n", "fewer than two"),
        ("", "empty file"),
        ("tangential_force,real_area\n0,-1\n1,2\n", "negative area"),
    ],
)
def test_bad_files_named(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as info:
        read_shear_area(path, normal_load=1.0)
    assert "bad.csv" in str(info.value)


@pytest.mark.parametrize(
    ("header", "force_factor", "area_factor"),
    [
        ("tangential_force,real_area", 1.0, 1.0),
        ("tangential_force (mN),real_area [mm^2]", 1e-3, 1e-6),
        ("tangential_force [uN],real_area (um^2)", 1e-6, 1e-12),
        ("tangential_force (\u00b5N),real_area [\u00b5m\u00b2]", 1e-6, 1e-12),
        ("tangential_force [kN],real_area [cm^2]", 1e3, 1e-4),
    ],
)
def test_unit_headers_converted_to_si(tmp_path, header, force_factor, area_factor):
    path = tmp_path / "units.csv"
    for sep in (",", ";"):
        path.write_text(f"{header.replace(',', sep)}\n0{sep}3\n2{sep}1.5\n", encoding="utf-8")
        # a load at which 2 of the header's force unit is a plausible friction force
        (curve,) = read_shear_area(path, normal_load=max(1.0, 10 * force_factor))
        np.testing.assert_allclose(curve.tangential_force, [0.0, 2 * force_factor])
        np.testing.assert_allclose(curve.real_area, [3 * area_factor, 1.5 * area_factor])


def test_unknown_unit_and_impossible_areas_name_line_and_column(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("tangential_force (lbf),real_area\n0,1e-6\n1,1e-6\n")
    with pytest.raises(InputError, match=r"c\.csv: line 1, column 'tangential_force': unit"):
        read_shear_area(path, normal_load=1.0)
    # comments and blank lines count: the message gives the file's own line number
    path.write_text("# rig 2\n\ntangential_force,real_area\n0,1e-6\n# pause\n1,-2e-6\n")
    with pytest.raises(InputError, match=r"line 6, column 'real_area': negative area"):
        read_shear_area(path, normal_load=1.0)
    path.write_text("normal_load;real_area\n1;1e-4\n2;9e-4\n")
    with pytest.raises(InputError, match=r"line 3, column 'real_area': A_r = 0.0009 m\^2 exceeds"):
        read_normal_area(path, nominal_area=700e-6)
    assert read_normal_area(path).real_area[1] == 9e-4  # without A_n nothing to compare
