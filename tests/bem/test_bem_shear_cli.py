"""``asperity bem ... --tangential-displacement``: the shear curve's JSON contract, its agreement
with the Python function, the held load, and the exit statuses (0, 1, 2)."""

import json

import numpy as np
import pytest

from asperity.bem.shear.cli import JSON_KEYS
from asperity.bem.shear.mixed_mode import MixedModeLaw
from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
from asperity.pipelines.cli import main

CONTRACT = (
    "tangential_displacement",
    "tangential_force",
    "normal_force",
    "real_area",
    "stick_area",
    "sliding",
    "converged",
)


@pytest.fixture
def caps(tmp_path):
    """Four separate paraboloid caps (R = 40 um) on a 48 x 48 map of 1 um pixels (m)."""
    x = (np.arange(24) - 11.5) * 1e-6
    xx, yy = np.meshgrid(x, x, indexing="ij")
    cap = -(xx**2 + yy**2) / (2 * 40e-6)
    h = np.tile(cap, (2, 2))
    path = tmp_path / "caps.npy"
    np.save(path, h)
    return path, h


def _run(capsys, argv):
    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


BASE = ["--e-star", "1e6", "--pixel-size", "1e-6", "--detrend", "none"]


def test_mixed_mode_json_contract(capsys, caps):
    """One entry per displacement with the contract's keys; the load is held; the real area
    drops under shear and the caps end in gross sliding at tau_0 times their Hertz area."""
    path, h = caps
    d_t = [0.0, 4e-7, 3.2e-6]
    argv = ["bem", str(path), *BASE, "--load", "4e-6", "--work-of-adhesion", "0.002"]
    argv += ["--mode-mixity", "0.2", "--shear-strength", "2e4", "--json"]
    argv += ["--tangential-displacement", ",".join(f"{v:g}" for v in d_t)]
    status, out, _ = _run(capsys, argv)
    assert status == 0
    rows = json.loads(out)
    assert len(rows) == len(d_t)
    assert all(list(r) == list(JSON_KEYS) for r in rows)
    assert set(CONTRACT) <= set(JSON_KEYS)
    assert [r["tangential_displacement"] for r in rows] == pytest.approx(d_t)
    assert all(r["normal_force"] == pytest.approx(4e-6, rel=1e-6) for r in rows)
    assert rows[0]["tangential_force"] == 0 and rows[0]["junctions"] == 4
    assert not rows[0]["sliding"] and rows[-1]["sliding"]
    assert rows[-1]["real_area"] < 0.8 * rows[0]["real_area"]
    # gross sliding: tau_0 on the Hertz contact of each cap at F_z / 4
    a_h = (3 * 1e-6 * 40e-6 / (4 * 1e6)) ** (1 / 3)
    assert rows[-1]["tangential_force"] == pytest.approx(2e4 * 4 * np.pi * a_h**2, rel=0.1)
    # the same as the Python function behind it
    curve = mixed_mode_shear_curve(
        h, 1e-6, 1e-6, 1e6, 4e-6, d_t, MixedModeLaw(0.002, 0.2), shear_strength=2e4
    )
    assert [r["tangential_force"] for r in rows] == pytest.approx(curve.tangential_force)
    assert [r["real_area"] for r in rows] == pytest.approx(curve.real_area)


def test_coulomb_held_contact_table(capsys, caps):
    """Without --mode-mixity the preload's contact is held: A_r constant, F_x bounded by mu F_z
    and reaching it in gross sliding."""
    path, _ = caps
    argv = ["bem", str(path), *BASE, "--load", "4e-6", "--friction-coefficient", "0.5"]
    status, out, _ = _run(capsys, [*argv, "--tangential-displacement", "0,1e-7,1e-5", "--json"])
    assert status == 0
    rows = json.loads(out)
    assert rows[0]["real_area"] == rows[2]["real_area"] > 0
    assert rows[1]["tangential_force"] < 0.5 * 4e-6
    assert rows[2]["sliding"] and rows[2]["tangential_force"] == pytest.approx(2e-6, rel=1e-6)
    status, out, _ = _run(capsys, [*argv, "--tangential-displacement", "0,1e-7"])
    assert status == 0 and "delta_T (m)" in out and "F_z = 4e-06 N" in out


def test_non_convergence_exits_1(capsys, caps):
    path, _ = caps
    argv = ["bem", str(path), *BASE, "--load", "4e-6", "--shear-strength", "2e4"]
    status, out, err = _run(
        capsys, [*argv, "--tangential-displacement", "1e-7", "--max-iter", "1", "--json"]
    )
    assert status == 1
    assert json.loads(out)[0]["converged"] is False
    assert "did not converge" in err


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--load", "1e-6", "--tangential-displacement", "1e-7"], "--shear-strength TAU"),
        (["--load", "1e-6", "--shear-strength", "1e4"], "--tangential-displacement only"),
        (
            ["--load", "1e-6,2e-6", "--shear-strength", "1e4", "--tangential-displacement", "0"],
            "one --load",
        ),
        (
            ["--load", "1e-6", "--shear-strength", "1e4", "--mode-mixity", "0.2"]
            + ["--tangential-displacement", "0"],
            "--work-of-adhesion > 0",
        ),
        (
            ["--load", "1e-6", "--shear-strength", "1e4", "--mode-mixity", "0.2"]
            + ["--work-of-adhesion", "0.01", "--tangential-displacement", "2e-7,1e-7"],
            "non-decreasing",
        ),
        (["--load", "1e-6", "--shear-strength", "-1", "--tangential-displacement", "0"], "shear"),
        (["--load", "1e-6", "--mode-mixity", "2", "--tangential-displacement", "0"], "mixity"),
        (
            ["--load", "1e-6", "--friction-coefficient", "1", "--tangential-displacement", "x"],
            "--tangential-displacement",
        ),
        (
            ["--load", "1e-6", "--friction-coefficient", "1", "--shear-strength", "1"]
            + ["--tangential-displacement", "0"],
            "not allowed with",
        ),
    ],
)
def test_bad_input_exits_2(capsys, caps, extra, message):
    path, _ = caps
    status, out, err = _run(
        capsys, ["bem", str(path), "--e-star", "1e6", "--pixel-size", "1e-6", *extra]
    )
    assert status == 2 and out == ""
    assert message in err and len(err.strip().splitlines()) == 1


def test_real_file_bad_input_exits_2(capsys):
    status, _, err = _run(
        capsys,
        ["bem", "tests/data/di-3.di", "--e-star", "1e6", "--load", "5e-8", "--mode-mixity", "0.2"]
        + ["--shear-strength", "1e5", "--tangential-displacement", "0,1e-8"],
    )
    assert status == 2 and "--work-of-adhesion > 0" in err


@pytest.mark.slow
def test_real_file_mixed_mode(capsys):
    """A measured map (di-3.di, 256 x 256, 39 nm pixels): the load held, the junctions shrinking
    and ending in gross sliding at tau_0 times the (Hertz-like) sliding area, exit 0 (9 s)."""
    status, out, _ = _run(
        capsys,
        ["bem", "tests/data/di-3.di", "--e-star", "1e8", "--load", "5e-6", "--json"]
        + ["--work-of-adhesion", "1e-3", "--mode-mixity", "0.2", "--shear-strength", "1e6"]
        + ["--tangential-displacement", "0,4e-9,1.6e-8,6.4e-8", "--tol", "1e-6"],
    )
    assert status == 0
    rows = json.loads(out)
    assert len(rows) == 4 and all(r["converged"] for r in rows)
    assert all(r["normal_force"] == pytest.approx(5e-6, rel=1e-5) for r in rows)
    assert not rows[0]["sliding"] and rows[-1]["sliding"]
    assert rows[-1]["real_area"] < rows[0]["real_area"]
    assert rows[-1]["tangential_force"] == pytest.approx(1e6 * rows[-1]["real_area"], rel=1e-9)
    assert rows[1]["tangential_force"] > rows[-1]["tangential_force"]  # a static peak
