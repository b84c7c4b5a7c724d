"""Rough surface under shear in load control (:func:`asperity.bem.shear.rough.shear_curve`)."""

import numpy as np
import pytest

from asperity.bem import solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.shear.rough import label_junctions, shear_curve

E_STAR, TAU0 = 2.0e6, 0.1e6


def test_junctions_merge_across_the_periodic_boundary():
    m = np.zeros((8, 8), dtype=bool)
    m[0, 3] = m[7, 3] = True  # one cluster cut by the x boundary
    m[4, 0] = m[4, 7] = True  # one cut by the y boundary
    m[3:5, 3:5] = True  # an inner one
    labels, n = label_junctions(m, periodic=True)
    assert n == 3
    assert labels[0, 3] == labels[7, 3] and labels[4, 0] == labels[4, 7]
    assert set(np.unique(labels)) == {0, 1, 2, 3}
    assert label_junctions(m, periodic=False)[1] == 5


def _surface(n=64, seed=2):
    rng = np.random.default_rng(seed)
    q2 = np.add.outer(np.fft.fftfreq(n) ** 2, np.fft.fftfreq(n) ** 2)
    spec = np.fft.fft2(rng.normal(size=(n, n))) / np.maximum(q2, 1.0 / n**2) ** 0.9
    h = np.real(np.fft.ifft2(spec))
    return 1e-6 * h / h.std(), 1e-6


@pytest.fixture(scope="module")
def curve():
    h, dx = _surface()
    force = 0.01 * E_STAR * (64 * dx) ** 2
    d_t = np.linspace(0.05, 1.5, 12) * 1e-6
    return shear_curve(h, dx, dx, E_STAR, force, d_t, shear_strength=TAU0), force


def test_curve_behaviour(curve):
    c, force = curve
    assert c.success
    assert np.all(c.normal_force == pytest.approx(force, rel=1e-6))
    assert np.all(np.diff(c.tangential_force) >= -1e-12 * c.tangential_force.max())
    assert np.all(c.tangential_force <= TAU0 * c.real_area * (1 + 1e-12))
    assert np.allclose(c.stick_area + c.slip_area, c.real_area, rtol=1e-12)
    assert np.all(np.diff(c.stick_area) <= 0)  # monotonic loading: stick zones only shrink
    assert c.junctions[0] > 3 and np.all(c.sliding_junctions <= c.junctions)
    # gross sliding at the end: all elements at tau_0, F_x = tau_0 A_r exactly
    assert c.sliding[-1] and not c.sliding[0]
    assert c.tangential_force[-1] == pytest.approx(TAU0 * c.real_area[-1], rel=1e-12)
    assert np.all(c.sliding == (c.stick_area == 0))
    # the first step is elastic (no slip): a tiny displacement sticks everywhere
    assert c.slip_area[0] < 0.1 * c.real_area[0]


def test_warm_start_pays(curve):
    c, _ = curve
    assert np.median(c.nit[1:]) < c.nit[0]


def test_stop_when_sliding_and_errors():
    h, dx = _surface(32, seed=4)
    force = 0.01 * E_STAR * (32 * dx) ** 2
    c = shear_curve(
        h,
        dx,
        dx,
        E_STAR,
        force,
        np.linspace(0.1, 20, 40) * 1e-6,
        shear_strength=TAU0,
        stop_when_sliding=True,
    )
    assert c.sliding[-1] and not np.any(c.sliding[:-1]) and c.sliding.size < 40
    # a given preload is used as is: the same curve, no normal solve
    pre = solve_contact(h, dx, dx, E_STAR, normal_force=force)
    again = shear_curve(
        h, dx, dx, E_STAR, force, c.tangential_displacement, preload=pre, shear_strength=TAU0
    )
    assert again.normal_seconds == 0.0
    assert np.allclose(again.tangential_force, c.tangential_force, rtol=1e-6)
    with pytest.raises(BemInputError, match="preload"):
        shear_curve(h, dx, dx, E_STAR, 2 * force, [1e-7], preload=pre, shear_strength=TAU0)
    with pytest.raises(BemInputError, match="exactly one"):
        shear_curve(h, dx, dx, E_STAR, force, [1e-7])
    with pytest.raises(BemInputError, match="normal_force"):
        shear_curve(h, dx, dx, E_STAR, -1.0, [1e-7], shear_strength=TAU0)
