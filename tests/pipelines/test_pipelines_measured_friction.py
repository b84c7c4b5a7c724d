"""Measured friction tests F_x(drive): reading, units, and the checks that refuse mistaken files
(pipelines.measured_friction)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.errors import InputError
from asperity.pipelines.config import ShearCurveFile
from asperity.pipelines.measured_friction import (
    FrictionCurve,
    read_friction_curves,
    read_friction_files,
    write_friction_curves,
)

SAHLI = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)


def _curve(load: float, n: int = 20) -> FrictionCurve:
    """A rising-then-sliding test: 0..1 mm of drive, F_x up to 0.7 F_z, N and m."""
    drive = np.linspace(0.0, 1e-3, n)
    return FrictionCurve(load, drive, 0.7 * load * np.minimum(drive / 5e-4, 1.0))


def _write(path, curves, header=None, scale=(1.0, 1.0)):
    scaled = [
        FrictionCurve(c.normal_load, c.drive_displacement * scale[0], c.tangential_force * scale[1])
        for c in curves
    ]
    write_friction_curves(path, scaled)
    if header is not None:
        lines = path.read_text().splitlines()
        path.write_text("\n".join([header, *lines[1:]]) + "\n")
    return path


def test_long_file_round_trip(tmp_path):
    curves = [_curve(f) for f in SAHLI[:3]]
    read = read_friction_curves(_write(tmp_path / "f.csv", curves))
    assert [c.normal_load for c in read] == list(SAHLI[:3])
    for got, want in zip(read, curves, strict=True):
        np.testing.assert_array_equal(got.drive_displacement, want.drive_displacement)
        np.testing.assert_array_equal(got.tangential_force, want.tangential_force)


def test_units_in_the_header_are_converted(tmp_path):
    curve = _curve(0.56)
    path = _write(
        tmp_path / "mm.csv",
        [curve],
        "normal_load,drive_displacement [mm],tangential_force (mN)",
        scale=(1e3, 1e3),
    )
    (read,) = read_friction_curves(path)
    np.testing.assert_allclose(read.drive_displacement, curve.drive_displacement, rtol=1e-12)
    np.testing.assert_allclose(read.tangential_force, curve.tangential_force, rtol=1e-12)


def test_millinewtons_under_an_si_header_are_refused_with_the_unit(tmp_path):
    path = _write(tmp_path / "mN.csv", [_curve(0.56)], scale=(1.0, 1e3))
    with pytest.raises(InputError, match=r"tangential_force \[mN\]") as info:
        read_friction_curves(path)
    assert str(info.value).startswith(f"{path}: line ")


def test_millimetres_under_an_si_header_are_refused_with_the_unit(tmp_path):
    path = _write(tmp_path / "mm.csv", [_curve(0.56)], scale=(1e3, 1.0))
    with pytest.raises(InputError, match=r"drive_displacement \[mm\]"):
        read_friction_curves(path)


def test_a_drive_moving_back_is_refused_naming_the_line(tmp_path):
    path = _write(tmp_path / "back.csv", [_curve(0.56)])
    lines = path.read_text().splitlines()
    lines[5], lines[6] = lines[6], lines[5]  # two rows out of order: data rows 5 and 6
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="line 7, column 'drive_displacement': the drive moves"):
        read_friction_curves(path)


def test_a_missing_column_is_refused_naming_it(tmp_path):
    path = tmp_path / "nofx.csv"
    path.write_text("normal_load,drive_displacement,force\n0.56,0,0\n0.56,1e-4,0.1\n")
    with pytest.raises(InputError, match="missing column 'tangential_force'"):
        read_friction_curves(path)
    one = tmp_path / "one.csv"
    one.write_text("drive_displacement,tangential_force\n0,0\n1e-4,0.1\n")
    with pytest.raises(InputError, match="missing column 'normal_load'.*friction_curves = "):
        read_friction_curves(one)
    (declared,) = read_friction_curves(one, normal_load=0.56)
    assert declared.normal_load == 0.56


def test_a_load_matching_none_configured_is_refused(tmp_path):
    path = _write(tmp_path / "f.csv", [_curve(0.56), _curve(0.75)])
    with pytest.raises(InputError, match=r"normal_load = 0.75 N matches none of"):
        read_friction_files([ShearCurveFile(path)], SAHLI)
    mn = _write(tmp_path / "mn.csv", [_curve(560.0)])  # loads in mN under an N header
    with pytest.raises(InputError, match=r"'normal_load \[mN\]'"):
        read_friction_files([ShearCurveFile(mn)], SAHLI)


def test_a_declared_load_the_column_contradicts_is_refused(tmp_path):
    path = _write(tmp_path / "f.csv", [_curve(1.06)])
    with pytest.raises(InputError, match="declared at normal_load = 0.56 N"):
        read_friction_curves(path, normal_load=0.56)


def test_job_key_reads_and_the_stiffness_is_bounded(tmp_path):
    from asperity.pipelines.config import ConfigError, config_from_dict

    path = _write(tmp_path / "f.csv", [_curve(0.56)])
    base = {"surface": {"synthetic": {"n": 64}}, "loading": {"normal_loads": [0.56]}}
    config = config_from_dict(
        {
            **base,
            "loading": {"normal_loads": [0.56], "drive_stiffness": 9200.0},
            "measured": {"friction_curves": str(path)},
        },
        base_dir=tmp_path,
    )
    assert config.loading.drive_stiffness == 9200.0
    assert config.measured.friction_curves[0].file == path
    assert config_from_dict(base).loading.drive_stiffness is None  # absent: rigid
    with pytest.raises(ConfigError, match="loading.drive_stiffness"):
        config_from_dict({**base, "loading": {"drive_stiffness": -5.0}})


@settings(max_examples=30, deadline=None)
@given(st.binary(min_size=0, max_size=300))
def test_fuzzed_files_fail_as_input_errors(tmp_path_factory, data):
    """Any bytes: read, or refused as InputError naming the file; never another exception."""
    path = tmp_path_factory.mktemp("fuzz") / "f.csv"
    path.write_bytes(b"normal_load,drive_displacement,tangential_force\n" + data)
    try:
        curves = read_friction_curves(path)
    except InputError as exc:
        assert str(path) in str(exc)
        return
    for curve in curves:
        assert np.all(np.diff(curve.drive_displacement) >= 0)
