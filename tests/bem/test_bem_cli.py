"""The ``asperity bem`` command: JSON contract, sweeps, exit statuses."""

import json

import numpy as np
import pytest

from asperity.bem import SolverOptions
from asperity.pipelines.cli import main
from tests._helpers import BEM_JSON_KEYS as KEYS


@pytest.fixture
def npy_surface(tmp_path, rough):
    path = tmp_path / "rough.npy"
    np.save(path, rough(64, seed=1) * 1e-6)  # m, rms slope 1 at 1 um pixels
    return path


def _run(capsys, argv):
    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def _bem(path, *args: str) -> list[str]:
    """The ``asperity bem`` argv on ``path`` with E* = 1 GPa and 1 um pixels, then ``args``."""
    return ["bem", str(path), "--e-star", "1e9", "--pixel-size", "1e-6", *args]


def test_single_load_json(capsys, npy_surface):
    status, out, _ = _run(
        capsys,
        _bem(str(npy_surface), "--mean-pressure", "4e7", "--detrend", "mean", "--json"),
    )
    assert status == 0
    data = json.loads(out)
    assert list(data) == KEYS
    assert data["converged"] is True
    nominal = 64 * 64 * 1e-12
    assert data["normal_force"] == pytest.approx(4e7 * nominal, rel=1e-9)
    assert data["real_area"] == pytest.approx(data["contact_fraction"] * nominal)
    assert 0 < data["contact_fraction"] < 0.3
    assert data["mean_gap"] > 0 and data["iterations"] > 0


def test_sweep_json_lists_and_matches_api(capsys, npy_surface, contact_ok):
    from asperity.bem import solve_contact

    status, out, _ = _run(
        capsys,
        _bem(
            str(npy_surface),
            "--load",
            "0.1,0.15,0.2",
            "--detrend",
            "none",
            "--tol",
            "1e-10",
            "--json",
        ),
    )
    assert status == 0
    data = json.loads(out)
    assert all(isinstance(data[k], list) and len(data[k]) == 3 for k in KEYS)
    assert data["normal_force"] == pytest.approx([0.1, 0.15, 0.2], rel=1e-9)
    assert data["contact_fraction"] == sorted(data["contact_fraction"])
    h = np.load(npy_surface)
    direct = solve_contact(
        h, 1e-6, 1e-6, 1000000000.0, normal_force=0.15, options=SolverOptions(tol=1e-10)
    )
    assert direct.converged, direct.message
    contact_ok(direct, h, force=0.15)
    assert data["contact_fraction"][1] == pytest.approx(direct.contact_fraction, abs=2 / h.size)


def test_non_convergence_exits_1(capsys, npy_surface):
    status, out, err = _run(
        capsys,
        _bem(str(npy_surface), "--load", "0.1", "--max-iter", "2", "--json"),
    )
    assert status == 1
    assert json.loads(out)["converged"] is False
    assert "did not converge" in err and "iteration cap" in err


def test_table_output_and_adhesion(capsys, npy_surface):
    status, out, _ = _run(
        capsys,
        _bem(str(npy_surface), "--load", "0.1", "--work-of-adhesion", "0.05"),
    )
    assert status == 0
    assert "contact_fraction" in out and "w = 0.05 J/m^2" in out


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--load", "1", "--e-star", "0"], "--e-star"),
        (["--load", "1,x", "--e-star", "1e9"], "--load"),
        (["--load", "-1", "--e-star", "1e9"], "> 0 without adhesion"),
        (["--load", "1", "--e-star", "1e9", "--tol", "-1"], "--tol"),
        (["--load", "1", "--e-star", "1e9", "--tol", "1e300"], "--tol"),
        (["--load", "1", "--e-star", "1e9", "--tol", "1e-20"], "precision"),
        (["--load", "1", "--e-star", "1e9", "--max-iter", "0"], "--max-iter"),
        (["--mean-pressure", "-1e6", "--e-star", "1e9"], "> 0 without adhesion"),
    ],
)
def test_bad_input_exits_2(capsys, npy_surface, extra, message):
    status, _, err = _run(capsys, ["bem", str(npy_surface), "--pixel-size", "1e-6", *extra])
    assert status == 2
    assert message in err


def test_missing_file_exits_2(capsys, tmp_path):
    status, _, err = _run(
        capsys,
        _bem(str(tmp_path / "none.npy"), "--load", "1"),
    )
    assert status == 2 and "none.npy" in err


def test_nan_pixels_are_refused(capsys, tmp_path):
    h = np.zeros((16, 16))
    h[3, 3] = np.nan
    path = tmp_path / "holes.npy"
    np.save(path, h)
    status, _, err = _run(
        capsys,
        _bem(str(path), "--load", "1", "--detrend", "none"),
    )
    assert status == 2 and "holes.npy" in err and "missing" in err


def test_negative_mean_pressure_from_a_cold_start_is_bad_input(capsys, npy_surface):
    """ "-1e6" is parsed as a number; with adhesion a pull from scratch has no loaded contact to
    pull on: exit 2 in one line saying what to do (a sweep from a compressive load)."""
    argv = ["bem", str(npy_surface), "--pixel-size", "1e-6", "--e-star", "1e9", "--json"]
    argv += ["--mean-pressure", "-1e6", "--work-of-adhesion", "0.05"]
    status, out, err = _run(capsys, argv)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1
    assert "--mean-pressure: the first load must be >= 0" in err and "e.g. 1e-3,-1e+06" in err


def test_zero_adhesive_load_prints_no_negative_zero(capsys, npy_surface):
    argv = ["bem", str(npy_surface), "--pixel-size", "1e-6", "--e-star", "1e9"]
    status, out, _ = _run(capsys, [*argv, "--load", "0", "--work-of-adhesion", "0.05"])
    assert status == 0
    assert "-0 " not in out and "-0\n" not in out
