"""The paper presets' stand-in (topo.synthetic.paper_spectrum): Gaussian, from the stated spectrum.

The paper states its map's spectrum only as an rms (about 51 um), a roll-off (about 600 um)
and a power law beyond it (Section 5). The stand-in is a random-phase Gaussian surface with that
spectrum; what it is checked for is being Gaussian and carrying the stated rms and roll-off, and
the slope bound of a plateau: ``h'_rms >= q_r h_rms / sqrt(2)``, not the paper's summit table
(which no such surface follows: docs/paper.md).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.stats

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.config import load_preset
from asperity.topo import psd, synthetic


def _skew_kurtosis(surface: topo.HeightMap) -> tuple[float, float]:
    h = np.asarray(surface.heights).ravel()
    return float(scipy.stats.skew(h)), float(scipy.stats.kurtosis(h))


@pytest.mark.parametrize("preset", ["paper", "paper-two-step"])
def test_paper_presets_use_the_gaussian_stand_in(preset):
    recipe = load_preset(preset).surface.synthetic
    assert recipe.recipe == "paper_spectrum"
    assert (recipe.n, recipe.pixel_size) == (5001, 2e-6)  # the paper's map (Appendix A)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_stand_in_heights_are_gaussian(seed):
    """The 10 mm domain at 10 um (1001^2): about 200 plateau modes carry the heights."""
    surface = synthetic.paper_spectrum(n=1001, pixel_size=10e-6, seed=seed)
    skew, kurtosis = _skew_kurtosis(surface)
    assert abs(skew) <= 0.15
    assert abs(kurtosis) <= 0.5
    assert float(np.std(surface.heights)) == pytest.approx(51e-6, rel=1e-9)
    # the capped recipe, for contrast, is heavy-tailed (its excess kurtosis is about +4)
    assert surface.provenance["generator"] == "asperity.topo.synthetic.paper_spectrum"


def test_stand_in_rolls_off_near_600_um():
    surface = synthetic.paper_spectrum(n=1001, pixel_size=10e-6, seed=1)
    # one log-spaced bin of the estimator either side (538, 605, 690 um are neighbours)
    assert psd.rolloff_wavelength(surface) == pytest.approx(600e-6, rel=0.2)


def test_a_plateau_alone_sets_the_slope_bound():
    """A spectrum flat below q_r and cut at q_r: h'^2 = int q^3 C / int q C = q_r^2 / 2 of
    h^2 (isotropic, continuous limit), so h' = q_r h / sqrt(2); a power law beyond q_r only
    adds slope. With the paper's 51 um and 600 um the bound is 0.378."""
    h_rms, rolloff = 51e-6, 600e-6
    bound = (2 * math.pi / rolloff) * h_rms / math.sqrt(2)
    assert bound == pytest.approx(0.378, abs=5e-4)
    plateau = synthetic.self_affine(
        1001, 10e-6, rms_height=h_rms, rolloff_wavelength=rolloff, short_cutoff=rolloff, seed=3
    )
    assert psd.rms_slope(plateau) == pytest.approx(bound, rel=0.05)
    stand_in = synthetic.paper_spectrum(n=1001, pixel_size=10e-6, seed=3)
    assert psd.rms_slope(stand_in) > 2 * bound


def test_stand_in_refuses_a_bad_pixel_size():
    with pytest.raises(InputError, match="pixel_size"):
        synthetic.paper_spectrum(n=100, pixel_size=float("nan"))


def test_capped_recipe_keeps_its_clear_name():
    assert synthetic.PAPER_CAPPED_SURFACE is synthetic.PAPER_SURFACE
    a = synthetic.paper_capped_surface(n=60, pixel_size=10e-6, seed=2)
    b = synthetic.paper_surface(n=60, pixel_size=10e-6, seed=2)
    assert np.array_equal(a.heights, b.heights)


@pytest.mark.slow
def test_preset_stand_in_is_gaussian_on_the_full_map():
    """The presets' own map (5001^2 at 2 um, their seed): 3 s to make."""
    recipe = load_preset("paper").surface.synthetic
    surface = synthetic.paper_spectrum(n=recipe.n, pixel_size=recipe.pixel_size, seed=recipe.seed)
    skew, kurtosis = _skew_kurtosis(surface)
    assert abs(skew) <= 0.15
    assert abs(kurtosis) <= 0.5
