"""Periodic sinusoid (Westergaard): full-contact pressure and partial-contact width."""

import numpy as np
import pytest

from asperity.bem import SolverOptions, solve_contact
from asperity.bem.normal.validity import BemWarning
from asperity.bem.reference_solutions import (
    westergaard_contact_half_width,
    westergaard_full_contact_pressure,
    westergaard_pressure,
)

E, WAVELENGTH, AMPLITUDE = 2.0e9, 1.0e-4, 1.0e-6  # Pa, m, m
P_STAR = westergaard_full_contact_pressure(AMPLITUDE, WAVELENGTH, E)  # full-contact mean pressure


def _wavy(nx, ny=8):
    dx = WAVELENGTH / nx
    x = (np.arange(nx) + 0.5) * dx - WAVELENGTH / 2
    h = AMPLITUDE * np.cos(2 * np.pi * x / WAVELENGTH)
    return np.repeat(h[:, None], ny, axis=1), dx, x


@pytest.mark.parametrize("kernel", ["point", "love"])
def test_full_contact_pressure_is_exact(kernel, contact_ok):
    h, dx, x = _wavy(64)
    p_mean = 1.5 * P_STAR
    with pytest.warns(BemWarning, match="full contact"):  # above p*: full contact, said
        res = solve_contact(
            h, dx, dx, E, mean_pressure=p_mean, options=SolverOptions(kernel=kernel, tol=1e-12)
        )
    assert res.converged, res.message
    contact_ok(res, h)
    assert res.contact_fraction == 1.0
    expected = westergaard_pressure(x, p_mean, AMPLITUDE, WAVELENGTH, E)
    err = np.abs(res.pressure[:, 0] - expected).max() / P_STAR
    if kernel == "point":
        # one Fourier mode: the point-force kernel is exact on the grid
        assert err < 1e-9
    else:
        # the Love patch is stiffer at the pixel scale: within 0.2 % at 64 px per wavelength
        assert err < 2e-3


@pytest.mark.parametrize("ratio", [0.1, 0.3, 0.5, 0.8])
def test_partial_contact_width_and_pressure(ratio, contact_ok):
    """Westergaard: the contact width 2a and the pressure field of the partial contact."""
    n = 512
    h, dx, x = _wavy(n, ny=4)
    p_mean = ratio * P_STAR
    res = solve_contact(h, dx, dx, E, mean_pressure=p_mean, options=SolverOptions(tol=1e-10))
    assert res.converged, res.message
    contact_ok(res, h, force=p_mean * h.size * dx * dx)
    half_width = westergaard_contact_half_width(p_mean, AMPLITUDE, WAVELENGTH, E)
    width = res.contact_mask[:, 0].sum() * dx
    assert width == pytest.approx(2 * half_width, abs=2.5 * dx)
    exact = westergaard_pressure(x, p_mean, AMPLITUDE, WAVELENGTH, E)
    err = np.sqrt(np.mean((res.pressure[:, 0] - exact) ** 2)) / exact.max()
    assert err < 0.01
