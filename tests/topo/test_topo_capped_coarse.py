"""The coarse cap level of topo.capped_surface: off by default, a function of position, every
coarse summit a cap apex of the caps' sphere radius, and a spectrum that rolls off at the
scale of its cells."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.topo import capped_surface as cs
from asperity.topo import psd, synthetic

#: Only the coarse level (a base of 1 nm, no small caps): caps of sphere radius 1 mm whose
#: apices (300 +- 30 um above the floor) bury one another, so no floor shows.
COARSE_ONLY = dataclasses.replace(
    synthetic.PAPER_SURFACE,
    base_rms=1e-9,
    waviness_rms=0.0,
    cap_density=0.0,
    coarse_cap_density=20e6,
    coarse_sphere_radius=1e-3,
    coarse_height_mean=300e-6,
    coarse_height_sd=30e-6,
)


def test_without_a_coarse_level_its_parameters_change_nothing():
    """Off (density 0) the coarse parameters are neither drawn from the generator nor recorded:
    a recipe without the level is the surface, the provenance and the hash it was before."""
    other = dataclasses.replace(
        synthetic.PAPER_SURFACE,
        coarse_sphere_radius=3e-3,
        coarse_height_mean=1e-4,
        coarse_height_sd=1e-5,
    )
    a = cs.capped_surface(60, 50, 20e-6, 20e-6, synthetic.PAPER_SURFACE, 2)
    b = cs.capped_surface(60, 50, 20e-6, 20e-6, other, 2)
    assert np.array_equal(a, b)
    assert not set(cs.COARSE_FIELDS) & set(synthetic.PAPER_SURFACE.as_dict())
    on = dataclasses.replace(synthetic.PAPER_SURFACE, coarse_cap_density=2e6)
    assert set(cs.COARSE_FIELDS) <= set(on.as_dict())
    assert cs.CappedSurfaceRecipe(**on.as_dict()) == on
    c = cs.capped_surface(60, 50, 20e-6, 20e-6, on, 2)
    assert np.ptp(c - a) > 10e-6  # the level is there when on


def test_the_coarse_level_is_the_same_surface_at_any_resolving_pixel_size():
    # 2.4 mm square at 8 um and at 16 um: the coarse map is the fine one decimated by 2
    recipe = dataclasses.replace(
        synthetic.PAPER_SURFACE,
        waviness_rms=0.0,
        coarse_cap_density=2e6,
        coarse_height_sd=50e-6,
    )
    fine = synthetic.paper_surface(n=300, pixel_size=8e-6, seed=3, recipe=recipe)
    coarse = synthetic.paper_surface(n=150, pixel_size=16e-6, seed=3, recipe=recipe)
    sub = fine.heights[::2, ::2]
    np.testing.assert_allclose(sub - sub.mean(), coarse.heights - coarse.heights.mean(), atol=1e-12)
    assert coarse.provenance["recipe"]["coarse_cap_density"] == 2e6


def test_the_coarse_level_does_not_depend_on_the_blocks(monkeypatch):
    whole = cs.capped_surface(40, 30, 40e-6, 40e-6, COARSE_ONLY, 5)
    monkeypatch.setattr(cs, "ROWS_PER_BLOCK", 3)  # caps of ~0.8 mm span many blocks, wrap
    assert np.array_equal(cs.capped_surface(40, 30, 40e-6, 40e-6, COARSE_ONLY, 5), whole)


def test_every_coarse_summit_is_a_cap_apex_of_the_sphere_radius():
    """At strides well inside a cell (10..50 um for cells ~400 um wide) the finite-difference
    radius of a sphere of radius rho at its apex is rho (1 + O(s^2 / rho^2)); a summit on a
    crease or on the floor would give another radius."""
    surface = synthetic.paper_surface(n=400, pixel_size=10e-6, seed=3, recipe=COARSE_ONLY)
    for stride in (1, 2, 5):
        stats = topo.summit_statistics(surface, stride=stride)
        assert stats.n_summits > 50
        assert stats.summit_radius == pytest.approx(1e-3, rel=0.01)


def test_the_coarse_level_rolls_off_at_its_cells():
    """Spectrum of the coarse level alone: flat above the roll-off, which sits at the cells'
    scale (between one and three mean distances between summits), and it moves with the
    cells: four times the apex spread makes cells twice as wide (sqrt(2 rho sd))."""
    narrow = synthetic.paper_surface(n=500, pixel_size=10e-6, seed=1, recipe=COARSE_ONLY)
    spacing = 1 / math.sqrt(topo.summit_statistics(narrow, stride=2).asperity_density)
    knee = psd.rolloff_wavelength(narrow)
    assert spacing < knee < 3 * spacing
    wide_recipe = dataclasses.replace(
        COARSE_ONLY, coarse_height_sd=120e-6, coarse_height_mean=600e-6
    )
    wide = synthetic.paper_surface(n=500, pixel_size=10e-6, seed=1, recipe=wide_recipe)
    wide_spacing = 1 / math.sqrt(topo.summit_statistics(wide, stride=2).asperity_density)
    assert 1.5 < wide_spacing / spacing < 2.7
    assert 1.3 < psd.rolloff_wavelength(wide) / knee < 3.0


def test_bad_coarse_parameters_are_refused_by_name():
    for key, value in (
        ("coarse_cap_density", -1.0),
        ("coarse_sphere_radius", 0.0),
        ("coarse_height_mean", math.nan),
        ("coarse_height_sd", -1e-6),
    ):
        bad = dataclasses.replace(COARSE_ONLY, **{key: value})
        with pytest.raises(InputError, match=key):
            cs.capped_surface(20, 20, 40e-6, 40e-6, bad, 0)
