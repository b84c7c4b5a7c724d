"""Results of topo, bem and statmodel say themselves when a number means nothing.

Each finding is on the result (codes and sentences) and raised as the package's warning, a
subclass of :class:`asperity.validity.ValidityWarning` with a ``code``.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from asperity import bem, statmodel, topo
from asperity.validity import CODES, ValidityWarning
from tests._helpers import PAPER_MATERIAL

MATERIAL = dataclasses.replace(PAPER_MATERIAL, mode_mixity=0.2)
PATH = np.linspace(0.0, 14e-6, 15)


def test_paper_fig4_curve_is_inside_the_model():
    rough = statmodel.Roughness(652.1e6, 0.041e-3, 0.032e-3)  # the paper's Fig 4
    with warnings.catch_warnings():
        warnings.simplefilter("error", ValidityWarning)
        curve = statmodel.shear_curve(MATERIAL, rough, 700e-6, 3.1, PATH)
    assert curve.success and curve.status == 0 and curve.validity_codes == ()
    assert np.nanmax(curve.real_area) / 700e-6 < 0.1


def test_area_above_nominal_is_status_3_and_warns():
    # x3p-2's stride-4 statistics on the paper's nominal area and load: the model's A_r
    # exceeds A_n twentyfold, which no real contact can do.
    rough = statmodel.Roughness(7.43e10, 5.41e-5, 6.13e-8)
    with pytest.warns(statmodel.StatmodelWarning) as caught:
        curve = statmodel.shear_curve(MATERIAL, rough, 700e-6, 3.1, PATH)
    codes = {w.message.code for w in caught if isinstance(w.message, ValidityWarning)}
    assert "area_fraction" in codes
    assert np.nanmax(curve.real_area) > 700e-6  # the number the finding is about
    assert curve.converged and not curve.success and curve.status == 3
    assert "area_fraction" in curve.validity_codes and "impossible" in curve.message


def test_tabor_warning_carries_its_code():
    with pytest.warns(statmodel.TaborWarning) as caught:
        mu = statmodel.tabor_parameter(1e-6, 0.01, 1e9)
    assert mu < 5
    assert caught[0].message.code == "tabor" and caught[0].message.level == "invalid"
    assert issubclass(statmodel.TaborWarning, statmodel.StatmodelWarning)


def _wavy(n: int = 32, wavelength: float = 32e-6, amplitude: float = 1e-6) -> np.ndarray:
    x = np.arange(n) * (wavelength / n)
    return np.repeat((amplitude * np.cos(2 * math.pi * x / wavelength))[:, None], n, axis=1)


@pytest.mark.parametrize("ratio", [0.3, 2.0])
def test_bem_full_contact_is_said_at_westergaards_pressure(ratio):
    # Westergaard: a wavy surface of amplitude g, wavelength L is in full contact above
    # p* = pi E* g / L (non-adhesive), partial below.
    e_star, g, wavelength = 1e6, 1e-6, 32e-6
    p_full = math.pi * e_star * g / wavelength
    heights = _wavy(amplitude=g, wavelength=wavelength)
    dx = wavelength / heights.shape[0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = bem.solve_contact(heights, dx, dx, e_star, mean_pressure=ratio * p_full)
    full = [w for w in caught if issubclass(w.category, bem.BemWarning)]
    assert res.success
    if ratio > 1:
        assert res.contact_fraction == 1.0
        assert res.extra["validity_codes"] == ["bem_full_contact"]
        assert full and full[0].message.code == "bem_full_contact"
    else:
        assert res.contact_fraction < 0.9
        assert res.extra["validity_codes"] == [] and not full


def test_hurst_exponent_only_inside_zero_one():
    surface = topo.synthetic.self_affine(
        256, 1e-6, rms_height=1e-6, rolloff_wavelength=40e-6, hurst=0.8, seed=3
    )
    psd = topo.radial_psd(surface)
    band = (psd.q > 2 * math.pi / 40e-6 * 1.5) & (psd.q < math.pi / 1e-6 * 0.7)
    slope = np.polyfit(np.log(psd.q[band]), np.log(psd.psd[band]), 1)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", ValidityWarning)
        good = topo.hurst_from_psd_exponent(slope)
    assert good.hurst_exponent == pytest.approx(0.8, abs=0.1) and good.validity_codes == ()
    with pytest.warns(topo.TopoWarning) as caught:
        steep = topo.hurst_from_psd_exponent(-6.7)  # 2.35 "H": a smooth surface
    assert math.isnan(steep.hurst_exponent) and steep.slope_hurst == pytest.approx(2.35)
    assert caught[0].message.code == "hurst_out_of_range" in CODES
