"""Measured A_r(F_x) curves checked against the configuration before any stage runs.

The mistaken-data cases found with generated "measured" curves of known lambda: loads in mN
under an ``N`` header, curves at loads 4-11 % from the configured ones, a file declared at
one load holding six, negative loads, a long file without its ``normal_load`` column. Each
ends with exit 2 and one line that quotes the user's own values, and results.h5 is never
created (the job stops before its first stage).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from asperity.errors import ExitStatus, InputError
from asperity.pipelines.config import ConfigError, config_from_dict, dump_toml
from asperity.pipelines.measured import (
    LOAD_MATCH,
    ShearAreaCurve,
    check_curve_loads,
    read_shear_area,
    write_shear_area,
)

#: The six loads of Sahli et al. (the default job), N.
SAHLI = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)


def _curves(loads, scale=1.0):
    """One short A_r(F_x) curve per load (N, N, m^2), the load stored times ``scale``."""
    fx = np.array([0.0, 0.1, 0.2, 0.3])
    return [ShearAreaCurve(f * scale, fx * f, 1e-6 * f * (1 - fx)) for f in loads]


def _long_file(path, loads, scale=1.0, header=None):
    write_shear_area(path, _curves(loads, scale))
    if header is not None:
        lines = path.read_text().splitlines()
        path.write_text("\n".join([header, *lines[1:]]) + "\n")
    return path


def test_loads_in_mn_under_an_n_header_are_refused_with_the_unit_named(tmp_path):
    path = _long_file(tmp_path / "mN.csv", SAHLI, scale=1000.0)
    (first, *_) = read_shear_area(path)
    with pytest.raises(InputError) as info:
        check_curve_loads([first], SAHLI)
    message = str(info.value)
    assert message.startswith(f"{path}: a curve at normal_load = 560 N")
    assert "0.56, 1.06, 1.58, 2.08, 2.57, 3.12 N" in message  # the user's configured values
    assert "nearest 3.12 N, a factor 179 away" in message and "'normal_load [mN]'" in message
    # said in the header, the same numbers are the configured loads
    fixed = _long_file(
        tmp_path / "mN2.csv", SAHLI, 1000.0, "normal_load [mN],tangential_force,real_area"
    )
    check_curve_loads(read_shear_area(fixed), SAHLI)


@pytest.mark.parametrize("offset", [1.04, 0.93, 1.11])
def test_curves_at_loads_4_to_11_percent_off_are_refused(tmp_path, offset):
    """The model would be evaluated at the curve's own load, but the report compares the
    prediction with it at a configured load: a curve at no configured load is refused."""
    path = _long_file(tmp_path / "off.csv", SAHLI, scale=offset)
    with pytest.raises(InputError, match=r"matches none of loading\.normal_loads") as info:
        check_curve_loads(read_shear_area(path), SAHLI)
    assert f"{0.56 * offset:.6g} N" in str(info.value)
    assert "add its load to loading.normal_loads" in str(info.value)


def test_loads_within_the_match_are_accepted(tmp_path):
    within = 1 + 0.5 * LOAD_MATCH
    path = _long_file(tmp_path / "near.csv", SAHLI, scale=within)
    check_curve_loads(read_shear_area(path), SAHLI)


def test_a_declared_load_that_the_file_contradicts_names_both(tmp_path):
    path = _long_file(tmp_path / "six.csv", SAHLI)
    with pytest.raises(InputError) as info:
        read_shear_area(path, normal_load=2.08)
    message = str(info.value)
    assert "declared at normal_load = 2.08 N in measured.shear_area" in message
    assert "holds 6 loads (0.56, 1.06, 1.58, 2.08, 2.57, 3.12 N)" in message
    assert "line 2: 0.56 N" in message


def test_a_declared_load_that_the_file_repeats_is_one_curve(tmp_path):
    path = _long_file(tmp_path / "one.csv", [2.08])
    (curve,) = read_shear_area(path, normal_load=2.08 * (1 + 0.5 * LOAD_MATCH))
    assert curve.normal_load == pytest.approx(2.08 * (1 + 0.5 * LOAD_MATCH))
    assert curve.real_area.size == 4


def test_negative_loads_refused_at_validation_quoting_the_users_value(tmp_path):
    data = {"surface": {"synthetic": {}}, "loading": {"normal_loads": [1.0, -0.5]}}
    with pytest.raises(ConfigError) as info:
        config_from_dict(data, source="job.toml", base_dir=tmp_path)
    message = str(info.value)
    assert message.startswith("job.toml: loading.normal_loads: expected loads > 0 N")
    assert message.endswith("got -0.5")
    # without the BEM the statistical model alone may go below zero, down to its pull-off
    normal = tmp_path / "area.csv"
    normal.write_text("normal_load,real_area\n0.5,1e-6\n1.0,2e-6\n")
    data["bem"] = {"enabled": False}
    data["measured"] = {"normal_area": str(normal)}
    assert config_from_dict(data, base_dir=tmp_path).loading.normal_loads == (1.0, -0.5)


def _job(tmp_path, small, measured, **loading):
    data = small.data(**loading)
    data["measured"] = {"shear_area": measured}
    path = tmp_path / "job.toml"
    path.write_text(dump_toml(data))
    return path


@pytest.mark.parametrize(
    ("case", "expected"),
    [
        ("mN", r"a curve at normal_load = 1000 N matches none of loading.normal_loads"),
        ("off", r"a curve at normal_load = 1.04 N matches none"),
        ("declared", r"declared at normal_load = 2 N in measured.shear_area, but its "),
        ("no_column", r"missing column 'normal_load' .*expected columns normal_load, "),
        ("negative", r"loading.normal_loads: expected loads > 0 N .*got -0.5"),
    ],
)
def test_each_mistaken_case_exits_2_before_any_stage(tmp_path, small, capsys, case, expected):
    """The job's own command: exit 2, one line, and no results.h5 written."""
    from asperity.pipelines.cli import main

    loads = (1.0, 2.0, 3.0)
    long_file = _long_file(tmp_path / "long.csv", loads)
    measured, loading = {
        "mN": (str(_long_file(tmp_path / "mN.csv", loads, 1000.0)), {}),
        "off": (str(_long_file(tmp_path / "off.csv", loads, 1.04)), {}),
        "declared": ([{"normal_load": 2.0, "file": str(long_file)}], {}),
        "no_column": (str(tmp_path / "bare.csv"), {}),
        "negative": (str(long_file), {"normal_loads": [-0.5, 1.0, 2.0, 3.0]}),
    }[case]
    (tmp_path / "bare.csv").write_text("tangential_force,real_area\n0,1e-6\n0.1,0.9e-6\n")
    config = _job(tmp_path, small, measured, **loading)
    out = tmp_path / "out"
    status = main(["run", str(config), "--out", str(out)])
    err = capsys.readouterr().err
    assert status == ExitStatus.BAD_INPUT
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert re.search(expected, err), err
    assert not (out / "results.h5").exists()
