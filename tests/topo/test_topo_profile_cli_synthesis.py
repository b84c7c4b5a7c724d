"""The profile route of ``asperity stats`` / ``asperity scan`` on the real Dektak file, and
isotropic maps synthesised from a profile's spectrum."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.cli import main
from asperity.topo.cli import STATS_KEYS
from asperity.topo.heightmap import LineProfile
from asperity.topo.nayak import profile_statistics
from asperity.topo.profile_synthesis import (
    isotropic_psd,
    realisation_spread,
    synthesise_from_profile,
)
from asperity.topo.synthetic import self_affine

DEKTAK = Path(__file__).parents[1] / "data" / "dektak-1.csv"


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_stats_of_the_dektak_profile_keeps_the_keys_and_says_it_is_a_profile(capsys):
    status, out, _ = run(capsys, "stats", DEKTAK, "--json")
    record = json.loads(out)
    assert status == 0
    assert list(record)[: len(STATS_KEYS)] == list(STATS_KEYS)
    assert record["ny"] == 1 and record["nx"] == 9600 and record["n_summits"] is None
    assert record["method"] == "nayak-profile"
    assert record["warnings"][0].startswith("statistics from a line profile assume an isotropic")
    for key in ("asperity_density", "summit_radius", "summit_height_rms"):
        assert record[key] > 0
    # the plane removed: a 1.5 mm stylus trace with a 4.8 um tilt, 94 nm of roughness left
    assert record["rms_height"] == pytest.approx(record["summit_height_rms"], rel=0.05)
    assert record["preparation"]["form_rms"] > 10 * record["rms_height"]


def test_scan_of_the_dektak_profile_fits_the_papers_laws(capsys, tmp_path):
    out_file = tmp_path / "scan.h5"
    status, out, _ = run(capsys, "scan", DEKTAK, "--max-stride", 6, "--json", "--out", out_file)
    data = json.loads(out)
    assert status == 0 and data["method"] == "nayak-profile"
    assert data["stride"] == [1, 2, 3, 4, 5, 6] and data["n_fitted"] == 6
    eta = np.array(data["asperity_density"])
    radius = np.array(data["summit_radius"])
    assert np.all(np.diff(eta) < 0) and np.all(np.diff(radius) > 0)  # as in Fig 12a-b
    assert data["density_exponent"] < 0 < data["radius_slope"]
    assert out_file.exists() and out_file.with_suffix(".png").exists()


def test_text_output_and_a_y_crop_on_a_profile(capsys):
    status, out, _ = run(capsys, "stats", DEKTAK, "--crop", "0:4000")
    assert status == 0 and "line profile, Nayak" in out and "isotropic" in out
    status, _, err = run(capsys, "stats", DEKTAK, "--crop", "0:100,0:5")
    assert status == 2 and "no y axis" in err


def isotropic_profile(seed=6):
    surface = self_affine(
        2048,
        1e-6,
        rms_height=1e-6,
        rolloff_wavelength=100e-6,
        hurst=0.8,
        short_cutoff=16e-6,
        seed=seed,
    )
    return LineProfile(np.asarray(surface.heights)[:, 0], surface.dx)


def test_the_2d_spectrum_from_a_profile_holds_its_mean_square_height():
    profile = isotropic_profile()
    q = np.linspace(0, math.pi / profile.dx, 20001)
    c2 = isotropic_psd(profile, q)
    # <z^2> = integral d^2q / (2 pi)^2 C2 = integral q dq / (2 pi) C2
    mean_square = np.trapezoid(q * c2, q) / (2 * math.pi)
    assert mean_square == pytest.approx(np.mean(profile.heights**2), rel=0.1)


def test_maps_synthesised_from_a_profile_have_its_statistics_and_are_seeded():
    profile = isotropic_profile()
    first = synthesise_from_profile(profile, n=1024, seed=1)
    again = synthesise_from_profile(profile, n=1024, seed=1)
    np.testing.assert_array_equal(first.heights, again.heights)
    assert first.periodic and first.dx == profile.dx
    nayak = profile_statistics(profile)
    summits = topo.summit_statistics(first, neighbours=8)
    # measured: eta 2 %, R 0.1 %, sigma_s 7 %, rms 5 % from the profile's own values
    assert summits.asperity_density == pytest.approx(nayak.asperity_density, rel=0.08)
    assert summits.summit_radius == pytest.approx(nayak.summit_radius, rel=0.08)
    assert summits.summit_height_rms == pytest.approx(nayak.summit_height_rms, rel=0.15)
    assert np.std(first.heights) == pytest.approx(np.std(profile.heights), rel=0.12)


def test_realisation_spread_reports_every_seed():
    profile = isotropic_profile()
    spread = realisation_spread(
        profile,
        lambda m: topo.summit_statistics(m, neighbours=8).asperity_density,
        realisations=3,
        seed=10,
        n=256,
    )
    assert spread.seeds == (10, 11, 12) and spread.values.shape == (3,) and spread.n == 256
    assert spread.std > 0 and 0 < spread.relative_spread < 0.5
    with pytest.raises(InputError, match="realisations"):
        realisation_spread(profile, np.std, realisations=0)


def test_a_profile_with_missing_points_has_no_spectrum():
    heights = np.asarray(isotropic_profile().heights).copy()
    heights[5] = np.nan
    with pytest.raises(InputError, match="missing"):
        synthesise_from_profile(LineProfile(heights, 1e-6), n=64)
