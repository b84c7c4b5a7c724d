"""topo.capped_surface generates by blocks of rows: the same heights whatever the block, and the
base equal to scipy's two-dimensional inverse transform (an independent implementation)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.fft

from asperity.errors import InputError
from asperity.topo import capped_surface as cs
from asperity.topo.synthetic import PAPER_SURFACE, paper_surface


@pytest.mark.parametrize(("nx", "ny"), [(97, 64), (64, 97), (130, 131)])
def test_the_base_is_irfft2_of_the_half_spectrum_bit_for_bit(monkeypatch, nx, ny):
    monkeypatch.setattr(cs, "ROWS_PER_BLOCK", 7)  # many blocks and a short last one
    rng = np.random.default_rng(3)
    m_x, m_y = 20, 25
    coef = rng.standard_normal((2 * m_x + 1, m_y + 1)) + 1j * rng.standard_normal(
        (2 * m_x + 1, m_y + 1)
    )
    coef[:m_x, 0] = np.conj(coef[:m_x:-1, 0])
    spectrum = np.zeros((nx, ny // 2 + 1), dtype=np.complex128)
    spectrum[np.arange(-m_x, m_x + 1) % nx, : m_y + 1] = coef
    expected = scipy.fft.irfft2(spectrum, s=(nx, ny)) * (nx * ny)
    assert np.array_equal(cs._sample_base(coef, m_x, m_y, nx, ny), expected)


def test_the_caps_do_not_depend_on_the_blocks(monkeypatch):
    """40 um pixels on a 1.2 x 1.0 mm domain: the 50 um caps span blocks of 3 rows and wrap
    around the periodic edges."""
    whole = cs.capped_surface(30, 25, 40e-6, 40e-6, PAPER_SURFACE, 5)
    for rows, caps in ((1, 1000), (3, 77), (29, 1)):
        monkeypatch.setattr(cs, "ROWS_PER_BLOCK", rows)
        monkeypatch.setattr(cs, "CAPS_PER_BLOCK", caps)  # the base read at the caps by blocks
        assert np.array_equal(cs.capped_surface(30, 25, 40e-6, 40e-6, PAPER_SURFACE, 5), whole)
    assert np.ptp(whole) > 0


def test_the_side_limit_is_the_whole_interface():
    with pytest.raises(InputError, match=r"paper_surface: n: expected at most 17500 pixels"):
        paper_surface(n=17501, ny=10, pixel_size=2e-6)
