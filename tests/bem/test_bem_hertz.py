"""Hertz sphere on a flat: contact radius, peak pressure and approach vs the closed form."""

import numpy as np
import pytest

from asperity.bem import SolverOptions, solve_contact
from asperity.bem.reference_solutions import (
    hertz_sphere_approach,
    hertz_sphere_contact_radius,
    hertz_sphere_peak_pressure,
    hertz_sphere_pressure,
)

R, E, F = 1.0, 1.0, 1e-4
A_HERTZ = hertz_sphere_contact_radius(F, R, E)
P0_HERTZ = hertz_sphere_peak_pressure(F, R, E)


def _errors(res, dx, n):
    x = (np.arange(n) - n / 2 + 0.5) * dx
    r = np.hypot(x[:, None], x[None, :])
    p_exact = hertz_sphere_pressure(r, F, R, E)
    a_num = np.sqrt(res.real_area / np.pi)
    inside = r < A_HERTZ
    p_rms = np.sqrt(np.mean((res.pressure[inside] - p_exact[inside]) ** 2)) / P0_HERTZ
    return a_num / A_HERTZ - 1, res.pressure.max() / P0_HERTZ - 1, p_rms


def test_hertz_nonperiodic_converges_under_refinement(sphere, contact_ok):
    errs = []
    for n in (32, 64, 128):
        h, dx = sphere(n, 4 * A_HERTZ, R)
        res = solve_contact(
            h, dx, dx, E, normal_force=F, periodic=False, options=SolverOptions(tol=1e-10)
        )
        assert res.converged, res.message
        contact_ok(res, h, force=F)
        errs.append(_errors(res, dx, n))
        # approach: d = -delta for a sphere whose apex is at h = 0
        assert -res.separation == pytest.approx(hertz_sphere_approach(F, R, E), rel=0.02)
    a_err, p0_err, prms = np.array(errs).T
    assert abs(a_err[-1]) < 0.01  # 32 px per contact radius
    assert abs(p0_err[-1]) < 0.002
    # the rms pressure error inside the contact falls under refinement (first order)
    assert prms[1] < 0.75 * prms[0] and prms[2] < 0.75 * prms[1]
    assert prms[-1] < 0.01


@pytest.mark.parametrize("kernel", ["point", "love"])
def test_hertz_periodic_kernels(kernel, sphere, contact_ok):
    """Large periodic box (16 a): both kernels reproduce Hertz; coarse mesh shows their bias."""
    out = {}
    for n in (64, 256):  # 4 and 16 pixels per contact radius
        h, dx = sphere(n, 16 * A_HERTZ, R)
        res = solve_contact(
            h, dx, dx, E, normal_force=F, options=SolverOptions(kernel=kernel, tol=1e-10)
        )
        assert res.converged, res.message
        contact_ok(res, h, force=F)
        out[n] = _errors(res, dx, n)
    assert abs(out[256][1]) < 0.0008  # peak pressure within 0.08 % at 16 px per radius
    assert abs(out[256][0]) < 0.01
    assert abs(out[256][1]) < abs(out[64][1])  # refinement reduces the peak-pressure error


def test_point_kernel_underestimates_peak_more_than_love_on_coarse_mesh(sphere, contact_ok):
    """The stated consequence of the kernel choice (docs/bem.md): at 4 px per contact radius
    the point-force kernel's peak pressure is lower than the Love patch's."""
    h, dx = sphere(64, 16 * A_HERTZ, R)
    p_point = solve_contact(
        h, dx, dx, E, normal_force=F, options=SolverOptions(kernel="point", tol=1e-10)
    )
    p_love = solve_contact(
        h, dx, dx, E, normal_force=F, options=SolverOptions(kernel="love", tol=1e-10)
    )
    contact_ok(p_point, h, force=F)
    contact_ok(p_love, h, force=F)
    np.testing.assert_array_equal(p_point.contact_mask, p_love.contact_mask)
    # measured -1.77 % and -1.43 %
    assert p_point.pressure.max() / P0_HERTZ - 1 == pytest.approx(-0.0177, abs=0.001)
    assert p_point.pressure.max() < p_love.pressure.max()
    assert p_love.pressure.max() / P0_HERTZ - 1 == pytest.approx(-0.0143, abs=0.001)


def test_hertz_displacement_control_matches_load_control(sphere, contact_ok):
    h, dx = sphere(64, 4 * A_HERTZ, R)
    by_load = solve_contact(
        h, dx, dx, E, normal_force=F, periodic=False, options=SolverOptions(tol=1e-10)
    )
    by_disp = solve_contact(
        h,
        dx,
        dx,
        E,
        separation=by_load.separation,
        periodic=False,
        options=SolverOptions(tol=1e-10),
    )
    assert by_load.converged and by_disp.converged
    contact_ok(by_load, h, force=F)
    contact_ok(by_disp, h)
    assert by_disp.normal_force == pytest.approx(F, rel=1e-6)
    np.testing.assert_array_equal(by_disp.contact_mask, by_load.contact_mask)
