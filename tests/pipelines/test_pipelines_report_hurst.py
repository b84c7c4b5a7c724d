"""The report calls the PSD slope a Hurst exponent only where it is one, 0 < H < 1."""

from __future__ import annotations

import pytest

from asperity.pipelines.report.text import hurst_text


@pytest.mark.parametrize("slope_hurst", [0.3, 0.8, 0.99])
def test_a_self_affine_slope_is_printed_as_its_hurst_exponent(slope_hurst):
    assert hurst_text(slope_hurst) == f"{slope_hurst:.3g}"


@pytest.mark.parametrize("slope_hurst", [1.35, 2.02, -0.2])
def test_a_slope_outside_zero_one_is_no_hurst_exponent(slope_hurst):
    text = hurst_text(slope_hurst)
    assert text.startswith("none: ")
    assert f"{slope_hurst:.3g}" in text
    assert "not a Hurst exponent" in text
