"""``asperity bem --adhesion maugis --adhesion-range H0``: the JSON contract, refusals, warnings."""

import json

import numpy as np
import pytest

from asperity.pipelines.cli import main
from tests._helpers import BEM_JSON_KEYS as KEYS


@pytest.fixture
def npy_surface(tmp_path, rough):
    path = tmp_path / "rough.npy"
    np.save(path, rough(64, seed=1) * 1e-7)  # m, rms slope 0.1 at 1 um pixels
    return path


def _bem(capsys, path, *extra):
    argv = ["bem", str(path), "--e-star", "1e9", "--pixel-size", "1e-6", "--detrend", "mean"]
    status = main([*argv, *extra])
    out, err = capsys.readouterr()
    return status, out, err


def test_maugis_sweep_json_has_todays_keys_and_more_contact(capsys, npy_surface):
    """One entry per load; the finite-range attraction adds contact on loading, where the
    Pohrt-Popov criterion gives the non-adhesive area."""
    loads = ["--mean-pressure", "1e5,2e5", "--work-of-adhesion", "0.05", "--json"]
    status, out, err = _bem(
        capsys, npy_surface, *loads, "--adhesion", "maugis", "--adhesion-range", "2e-7"
    )
    assert status == 0, err
    data = json.loads(out)
    assert list(data) == KEYS
    assert len(data["contact_fraction"]) == 2 and data["branch"] == ["loading", "loading"]
    _, out_pp, _ = _bem(capsys, npy_surface, *loads)
    plain = json.loads(out_pp)
    assert data["contact_fraction"][0] > 1.1 * plain["contact_fraction"][0]
    assert data["contact_fraction"][1] > plain["contact_fraction"][1]
    assert "warning" not in err
    nominal = 64 * 64 * 1e-12
    assert data["normal_force"][1] == pytest.approx(2e5 * nominal, rel=1e-9)


@pytest.mark.parametrize(
    ("extra", "named"),
    [
        (["--adhesion", "maugis"], "--adhesion-range"),
        (["--adhesion-range", "1e-8"], "--adhesion-range"),
        (["--adhesion", "maugis", "--adhesion-range", "-1e-8"], "--adhesion-range"),
    ],
)
def test_bad_maugis_options_exit_2_naming_the_option(capsys, npy_surface, extra, named):
    status, out, err = _bem(
        capsys, npy_surface, "--load", "1e-3", "--work-of-adhesion", "0.05", *extra
    )
    assert status == 2
    assert named in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_unresolved_cohesive_zone_is_said_on_stderr(capsys, npy_surface):
    """A 1 nm range at 1 um pixels on slopes of 0.1: the Dugdale zone is far below an
    element."""
    status, out, err = _bem(
        capsys,
        npy_surface,
        "--mean-pressure",
        "2e5",
        "--work-of-adhesion",
        "0.01",
        "--adhesion",
        "maugis",
        "--adhesion-range",
        "1e-9",
    )
    assert status == 0
    assert "warning" in err and "cohesive zone not resolved" in err
