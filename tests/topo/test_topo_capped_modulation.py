"""The amplitude modulation of ``topo.capped_surface``'s base (``B = A L``, module docstring).

What it is for: at a fixed rms and a fixed spectral knee, spread the coarse summits' heights
and flatten the mean coarse summit (the paper's 260 um statistics with its 600 um roll-off,
Xu et al. 2022, Fig 12 and Section 5). The tests hold it to that, to the rms it promises, and
to the surface being a function of position (the same at any pixel size and block size).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.topo import capped_surface as cs
from asperity.topo import psd, synthetic
from asperity.topo.heightmap import HeightMap

#: The paper recipe's base alone (no caps), unmodulated and modulated.
BARE = dataclasses.replace(synthetic.PAPER_SURFACE, cap_density=0.0, amplitude_modulation=0.0)
MODULATED = dataclasses.replace(BARE, amplitude_modulation=0.6)


def _surface(recipe, n=1000, pixel=10e-6, seed=0) -> HeightMap:
    heights = cs.capped_surface(n, n, pixel, pixel, recipe, seed)
    return HeightMap(heights, pixel, pixel, True, {})


def _coarse_statistics(surface: HeightMap) -> tuple[float, float, float]:
    """eta (1/m^2), R (m), sigma_s (m) averaged over strides 24..28 (240..280 um)."""
    stats = [topo.summit_statistics(surface, stride=k) for k in range(24, 29)]
    return (
        float(np.mean([s.asperity_density for s in stats])),
        float(np.mean([s.summit_radius for s in stats])),
        float(np.mean([s.summit_height_rms for s in stats])),
    )


def test_without_a_modulation_its_parameters_change_nothing():
    off = dataclasses.replace(BARE, modulation_wavelength=1e-3)
    assert np.array_equal(
        cs.capped_surface(60, 50, 20e-6, 20e-6, BARE, 3),
        cs.capped_surface(60, 50, 20e-6, 20e-6, off, 3),
    )
    assert not set(cs.MODULATION_FIELDS) & set(BARE.as_dict())  # hashed as before it existed
    assert set(cs.MODULATION_FIELDS) <= set(MODULATED.as_dict())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_modulation_keeps_the_rms_and_moves_the_knee_by_its_band_at_most(seed):
    """``A L`` has the spectrum of L convolved with A's, whose wavenumbers end at
    ``q_m = 2 pi / modulation_wavelength``: the knee at ``q_r`` can move to ``q_r + q_m`` at
    most (611 um -> 507 um), never to longer wavelengths; one bin (12 %) of the estimator."""
    bare, modulated = _surface(BARE, seed=seed), _surface(MODULATED, seed=seed)
    # <A^2> = 1 on the reference grid; A and L independent: the rms is kept in expectation
    assert np.std(modulated.heights) == pytest.approx(BARE.base_rms, rel=0.08)
    assert np.std(bare.heights) == pytest.approx(BARE.base_rms, rel=0.02)
    knee_bare, knee_modulated = psd.rolloff_wavelength(bare), psd.rolloff_wavelength(modulated)
    assert knee_bare == pytest.approx(BARE.rolloff_wavelength, rel=0.12)
    shifted = 1 / (1 / BARE.rolloff_wavelength + 1 / MODULATED.modulation_wavelength)
    assert shifted / 1.12 <= knee_modulated <= knee_bare * 1.001


def test_the_modulation_spreads_and_flattens_the_coarse_summits_at_a_fixed_rms():
    """The reason it exists: eta at 260 um stays (the summits stay where they are), sigma_s
    grows (heights scaled by a varying A) and the mean radius grows (a mean of 1/kappa, which
    the smooth regions raise); lognormal A with s = 0.6: <1/A> = exp(1.5 s^2) = 1.72."""
    ratios = []
    for seed in (0, 1):
        bare = _coarse_statistics(_surface(BARE, seed=seed))
        modulated = _coarse_statistics(_surface(MODULATED, seed=seed))
        ratios.append(np.array(modulated) / np.array(bare))
    eta, radius, sigma_s = np.mean(ratios, axis=0)
    assert eta == pytest.approx(1.0, abs=0.05)
    assert 1.2 < radius < 2.2
    assert 1.15 < sigma_s < 1.8


def test_the_modulation_is_the_same_surface_at_any_resolving_pixel_size():
    fine = cs.capped_surface(200, 150, 20e-6, 20e-6, MODULATED, 4)
    coarse = cs.capped_surface(100, 75, 40e-6, 40e-6, MODULATED, 4)
    sub = fine[::2, ::2]
    np.testing.assert_allclose(sub - sub.mean(), coarse - coarse.mean(), atol=1e-12)


def test_the_modulation_does_not_depend_on_the_blocks(monkeypatch):
    whole = cs.capped_surface(40, 30, 40e-6, 40e-6, synthetic.PAPER_SURFACE, 6)
    monkeypatch.setattr(cs, "ROWS_PER_BLOCK", 3)
    assert np.array_equal(
        cs.capped_surface(40, 30, 40e-6, 40e-6, synthetic.PAPER_SURFACE, 6), whole
    )


@pytest.mark.parametrize(
    ("field", "value"),
    [("amplitude_modulation", -0.1), ("amplitude_modulation", float("nan")),
     ("modulation_wavelength", 0.0), ("modulation_wavelength", float("inf"))],
)  # fmt: skip
def test_a_bad_modulation_parameter_is_refused_by_name(field, value):
    recipe = dataclasses.replace(MODULATED, **{field: value})
    with pytest.raises(InputError, match=field):
        cs.capped_surface(20, 20, 20e-6, 20e-6, recipe, 0)
