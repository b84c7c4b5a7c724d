"""Periodic sinusoid (Westergaard): full-contact pressure and partial-contact width."""

import numpy as np
import pytest

from asperity.bem import SolverOptions, solve_contact

E, WAVELENGTH, AMPLITUDE = 2.0e9, 1.0e-4, 1.0e-6  # Pa, m, m
P_STAR = np.pi * E * AMPLITUDE / WAVELENGTH  # full-contact mean pressure (Johnson 1985)


def _wavy(nx, ny=8):
    dx = WAVELENGTH / nx
    x = (np.arange(nx) + 0.5) * dx - WAVELENGTH / 2
    h = AMPLITUDE * np.cos(2 * np.pi * x / WAVELENGTH)
    return np.repeat(h[:, None], ny, axis=1), dx, x


@pytest.mark.parametrize("kernel", ["point", "love"])
def test_full_contact_pressure_is_exact(kernel, contact_ok):
    h, dx, x = _wavy(64)
    p_mean = 1.5 * P_STAR
    res = solve_contact(
        h, dx, dx, E, mean_pressure=p_mean, options=SolverOptions(kernel=kernel, tol=1e-12)
    )
    assert res.converged, res.message
    contact_ok(res, h)
    assert res.contact_fraction == 1.0
    expected = p_mean + P_STAR * np.cos(2 * np.pi * x / WAVELENGTH)
    err = np.abs(res.pressure[:, 0] - expected).max() / P_STAR
    if kernel == "point":
        # one Fourier mode: the point-force kernel is exact on the grid
        assert err < 1e-9
    else:
        # the Love patch is stiffer at the pixel scale: within 0.2 % at 64 px per wavelength
        assert err < 2e-3


@pytest.mark.parametrize("ratio", [0.1, 0.3, 0.5, 0.8])
def test_partial_contact_width_and_pressure(ratio, contact_ok):
    """Westergaard: p_mean / p* = sin^2(pi a / l) = s^2 and
    p(x) = 2 p_mean cos(pi x / l) sqrt(s^2 - sin^2(pi x / l)) / s^2."""
    n = 512
    h, dx, x = _wavy(n, ny=4)
    p_mean = ratio * P_STAR
    res = solve_contact(h, dx, dx, E, mean_pressure=p_mean, options=SolverOptions(tol=1e-10))
    assert res.converged, res.message
    contact_ok(res, h, force=p_mean * h.size * dx * dx)
    half_width = WAVELENGTH / np.pi * np.arcsin(np.sqrt(ratio))
    width = res.contact_mask[:, 0].sum() * dx
    assert width == pytest.approx(2 * half_width, abs=2.5 * dx)
    s2 = np.sin(np.pi * half_width / WAVELENGTH) ** 2
    arg = np.clip(s2 - np.sin(np.pi * x / WAVELENGTH) ** 2, 0, None)
    exact = 2 * p_mean * np.cos(np.pi * x / WAVELENGTH) * np.sqrt(arg) / s2
    err = np.sqrt(np.mean((res.pressure[:, 0] - exact) ** 2)) / exact.max()
    assert err < 0.01
