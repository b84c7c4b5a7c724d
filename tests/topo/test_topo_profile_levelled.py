"""The Python API gives a line profile's statistics as `asperity stats` does, or refuses."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.cli import main

DEKTAK = Path(__file__).parents[1] / "data" / "dektak-1.csv"


def test_unlevelled_profile_is_refused_and_prepared_one_matches_the_cli(capsys):
    raw = topo.read_surface(DEKTAK)
    with pytest.raises(InputError, match="not levelled.*prepare_profile"):
        topo.profile_statistics(raw)
    prepared, _ = topo.prepare_profile(raw, topo.PreparationOptions())
    api = topo.profile_statistics(prepared)
    assert main(["stats", str(DEKTAK), "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert api.summit_height_rms == pytest.approx(cli["summit_height_rms"], rel=1e-12)
    assert api.summit_radius == pytest.approx(cli["summit_radius"], rel=1e-12)


def test_a_levelled_profile_is_taken_as_it_is():
    # a random profile about zero: no trend to remove, the statistics are read directly
    rng = np.random.default_rng(2)
    heights = np.convolve(rng.normal(size=4096), np.ones(8) / 8, mode="same") * 1e-7
    profile = topo.LineProfile(heights, 1e-6)
    stats = topo.profile_statistics(profile)
    assert stats.moments.m0 == pytest.approx(np.var(heights), rel=0.05)
