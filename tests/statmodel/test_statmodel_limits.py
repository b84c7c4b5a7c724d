"""Statistical model: pull-off on loading/unloading, the Greenwood-Williamson limit, edge inputs."""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from asperity.errors import InputError
from asperity.statmodel import (
    Material,
    Roughness,
    TaborWarning,
    jkr_jump_in_distance,
    jkr_normal_load,
    preload,
    pull_off_force,
    shear_curve,
    shear_curve_fixed_separation,
    tabor_parameter,
    unloading_pull_off_force,
)
from asperity.statmodel.checks import StatmodelWarning
from tests._helpers import FIG4_AREA, FIG4_LOAD, FIG4_MATERIAL, FIG4_ROUGHNESS

MAT, ROUGH, AREA, LOAD = FIG4_MATERIAL, FIG4_ROUGHNESS, FIG4_AREA, FIG4_LOAD

# a smooth, strongly adhesive surface (sigma_s comparable to the JKR length scales)
SMOOTH_MAT = Material(1e6, 0.05, 0.2, 1e5)
SMOOTH_R, SMOOTH_ETA, SMOOTH_AREA = 1e-4, 1e9, 1e-4
N_SMOOTH = SMOOTH_ETA * SMOOTH_AREA


def smooth(sigma):
    return Roughness(SMOOTH_ETA, SMOOTH_R, sigma)


def test_pull_off_in_the_smooth_limit_loading_and_unloading():
    # sigma_s -> 0: all asperities alike. Loading (jump-in at delta_JKR^loading, where P_JKR is
    # most tensile on that branch): N P_JKR(delta_load), first order in sigma_s. Unloading after
    # a preload: each asperity passes the JKR load-control pull-off -3/2 pi w R before it jumps
    # off at delta_JKR^unloading, so the contact pulls off at N (-3/2 pi w R), second order.
    w = SMOOTH_MAT.work_of_adhesion
    mu = tabor_parameter(SMOOTH_R, w, SMOOTH_MAT.e_star)
    f_load = N_SMOOTH * jkr_normal_load(
        jkr_jump_in_distance(mu, 0.2e-9), SMOOTH_R, w, SMOOTH_MAT.e_star
    )
    f_unload = N_SMOOTH * (-1.5 * math.pi * w * SMOOTH_R)
    err_load, err_unload = [], []
    for sigma in (1e-9, 1e-10):
        err_load.append(abs(pull_off_force(SMOOTH_MAT, smooth(sigma), SMOOTH_AREA) / f_load - 1))
        f = unloading_pull_off_force(SMOOTH_MAT, smooth(sigma), SMOOTH_AREA, 1.0)
        err_unload.append(abs(f / f_unload - 1))
    assert err_load[1] < 3e-4 and err_load[1] < 0.2 * err_load[0]
    assert err_unload[1] < 1e-7 and err_unload[1] < 0.05 * err_unload[0]


def test_pull_off_does_not_depend_on_the_height_cutoff():
    rough = smooth(3e-8)
    forces = [
        pull_off_force(SMOOTH_MAT, rough, SMOOTH_AREA, cutoff_sigma=c) for c in (8.0, 10.0, 12.0)
    ]
    assert forces[0] < 0.0
    np.testing.assert_allclose(forces, forces[0], rtol=1e-10)
    # the unloading pull-off after a preload is more tensile than the loading one
    assert unloading_pull_off_force(SMOOTH_MAT, rough, SMOOTH_AREA, 1.0) < forces[0]


def test_rough_paper_case_pull_off_is_zero_and_tension_is_refused_naming_it():
    # Fig. 4 surface: the loading curve stays compressive wherever it is resolved (its true
    # minimum would sit near d = 67 sigma_s, ~exp(-2000) N): the pull-off force is zero, whatever
    # the cut-off (it used to be the -2e-24 N of the truncated integrand at the cut-off).
    for c in (8.0, 10.0, 12.0):
        assert pull_off_force(MAT, ROUGH, AREA, cutoff_sigma=c) == 0.0
    assert unloading_pull_off_force(MAT, ROUGH, AREA, LOAD) == 0.0
    with pytest.raises(
        InputError, match=r"normal_load = -1e-06 N is below the pull-off force -?0 N"
    ):
        preload(MAT, ROUGH, AREA, -1e-6)
    assert preload(MAT, ROUGH, AREA, 0.0).converged


def test_tensile_load_error_names_the_force_in_newton():
    rough = smooth(3e-8)
    f_po = pull_off_force(SMOOTH_MAT, rough, SMOOTH_AREA)
    with pytest.raises(InputError, match=rf"below the pull-off force {f_po:.6g} N of the loading"):
        shear_curve(SMOOTH_MAT, rough, SMOOTH_AREA, 1.01 * f_po, [0.0, 1e-6])


def _gw(roughness, e_star, d):
    """Greenwood-Williamson Hertz integrals (load N, area m^2) at separation d, by quad."""
    r, s = roughness.summit_radius, roughness.summit_height_rms
    n = roughness.asperity_density * AREA

    def phi(z):
        return math.exp(-0.5 * (z / s) ** 2) / (math.sqrt(2 * math.pi) * s)

    load = quad(
        lambda z: 4 / 3 * e_star * math.sqrt(r) * (z - d) ** 1.5 * phi(z),
        d,
        d + 14 * s,
        epsabs=0,
        epsrel=1e-12,
        limit=200,
    )[0]
    area = quad(
        lambda z: math.pi * r * (z - d) * phi(z), d, d + 14 * s, epsabs=0, epsrel=1e-12, limit=200
    )[0]
    return n * load, n * area


def test_without_adhesion_the_model_is_greenwood_williamson():
    mat = Material(2.133e6, 0.0, 0.2, 0.13e6)
    pre = preload(mat, ROUGH, AREA, LOAD)
    load, area = _gw(ROUGH, mat.e_star, pre.separation)
    assert load == pytest.approx(LOAD, rel=1e-9)
    assert pre.real_area == pytest.approx(area, rel=1e-9)
    assert pre.n_contact == pytest.approx(
        ROUGH.asperity_density * AREA * 0.5 * math.erfc(pre.separation / (math.sqrt(2) * 32e-6)),
        rel=1e-12,
    )
    assert pull_off_force(mat, ROUGH, AREA) == 0.0


def _gw_separation(roughness, e_star, load):
    """Separation (m) at which Hertz asperities carry ``load`` N (quadrature + Brent)."""
    s = roughness.summit_height_rms
    return brentq(lambda d: _gw(roughness, e_star, d)[0] - load, -5 * s, 5 * s, xtol=1e-16 * s)


def test_w_to_zero_converges_to_the_closed_form_greenwood_williamson():
    # Weak adhesion: the preload tends to Greenwood-Williamson with Hertz asperities (the
    # non-adhesive limit of E:Fy_Greenwood / E:Ar_Greenwood), computed here independently by
    # quadrature of the Hertz laws over the Gaussian summit heights, not by the model at w = 0.
    d_gw = _gw_separation(ROUGH, 2.133e6, LOAD)
    area_gw = _gw(ROUGH, 2.133e6, d_gw)[1]
    area_errors, separation_errors = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TaborWarning)  # mu < 5 here: outside JKR, warned
        for w in (1e-3, 1e-5, 1e-7):
            pre = preload(Material(2.133e6, w, 0.2, 0.13e6), ROUGH, AREA, LOAD)
            area_errors.append(abs(pre.real_area / area_gw - 1))
            separation_errors.append(abs(pre.separation - d_gw) / ROUGH.summit_height_rms)
    # At fixed indentation the JKR contact radius is a_Hertz (1 + O(sqrt(w))): 100x less w, the
    # area 10x closer to GW. In the load the two sqrt(w) terms of E:JKR_load cancel to first
    # order (4E*/(3R) d(a^3) = sqrt(8 pi E* a^3 w)), so it and the separation converge as O(w).
    for e1, e2 in zip(area_errors, area_errors[1:], strict=False):
        assert 8.0 < e1 / e2 < 12.0
    for e1, e2 in zip(separation_errors, separation_errors[1:], strict=False):
        assert 80.0 < e1 / e2 < 120.0
    assert area_errors[2] < 3e-4 and separation_errors[2] < 1e-6


def test_weak_adhesion_warns_on_every_entry_point():
    mat = Material(2.133e6, 1e-7, 0.2, 0.13e6)
    for call in (
        lambda: preload(mat, ROUGH, AREA, LOAD),
        lambda: pull_off_force(mat, ROUGH, AREA),
        lambda: shear_curve(mat, ROUGH, AREA, LOAD, [0.0]),
        lambda: shear_curve_fixed_separation(mat, ROUGH, AREA, 0.0, [0.0]),
    ):
        with warnings.catch_warnings():
            # the shear curves of this weak adhesion also exceed A_n (area_fraction): not the
            # subject here, the Tabor warning of every entry point is
            warnings.filterwarnings("ignore", "the model's A_r/A_n", StatmodelWarning)
            with pytest.warns(TaborWarning, match="Tabor parameter"):
                call()


@pytest.mark.parametrize(
    "changes, load",
    [
        ({}, LOAD),
        ({"mode_mixity": 1.0}, 0.5),
        ({"work_of_adhesion": 0.06, "mode_mixity": 0.05}, 10.0),
    ],
)
def test_separation_never_decreases_under_shear(changes, load):
    # Section 3.2: shear unloads every junction (P_PC grows with delta_T, a sliding junction
    # carries the Hertz load >= P_PC, a lost tensile junction relieves the rest), so d(delta_T)
    # rises from d_min; E:delta_2 assumes d >= d_min throughout.
    mat = Material(**{**MAT.__dict__, **changes})
    c = shear_curve(mat, ROUGH, AREA, load, np.linspace(0.0, 25e-6, 126))
    assert c.converged
    assert c.separation[0] == c.separation_preload
    assert np.all(np.diff(c.separation) >= 0.0)
    assert c.separation[-1] > c.separation[0] + 1e-3 * ROUGH.summit_height_rms


def test_single_step_histories():
    only_preload = shear_curve(MAT, ROUGH, AREA, LOAD, [0.0])
    pre = preload(MAT, ROUGH, AREA, LOAD)
    assert only_preload.converged
    assert only_preload.tangential_force.shape == (1,)
    assert only_preload.tangential_force[0] == 0.0
    assert only_preload.real_area[0] == pytest.approx(pre.real_area, rel=1e-15)
    # the state at delta_T depends on the preload and delta_T only: one step straight there
    dt = 6e-6
    one = shear_curve(MAT, ROUGH, AREA, LOAD, np.array([dt]))
    path = shear_curve(MAT, ROUGH, AREA, LOAD, np.linspace(0.0, dt, 7))
    for name in ("tangential_force", "real_area", "n_stick", "separation"):
        assert getattr(one, name)[0] == pytest.approx(getattr(path, name)[-1], rel=1e-9), name


def test_very_large_tangential_displacement_is_full_sliding():
    c = shear_curve(MAT, ROUGH, AREA, LOAD, [0.0, 1e-3, 1.0, 1e6])
    assert c.converged
    np.testing.assert_array_equal(c.n_stick[1:], 0.0)
    np.testing.assert_allclose(c.tangential_force[1:], c.sliding_friction, rtol=1e-9)
    np.testing.assert_allclose(c.normal_force, LOAD, rtol=1e-9)


@pytest.mark.parametrize(
    "history, match",
    [
        ([0.0, math.nan], "finite values >= 0"),
        ([0.0, math.inf], "finite values >= 0"),
        ([-1e-6, 0.0], "finite values >= 0"),
        ([0.0, 2e-6, 1e-6], "non-decreasing"),
        ([], "non-empty 1D"),
        ([[0.0, 1e-6]], "non-empty 1D"),
    ],
)
def test_bad_displacement_histories_are_refused(history, match):
    with pytest.raises(InputError, match=match):
        shear_curve(MAT, ROUGH, AREA, LOAD, history)


def test_nan_scalar_inputs_are_refused_by_name():
    with pytest.raises(InputError, match="normal_load"):
        shear_curve(MAT, ROUGH, AREA, math.nan, [0.0])
    with pytest.raises(InputError, match="nominal_area"):
        preload(MAT, ROUGH, math.nan, LOAD)
    with pytest.raises(InputError, match="separation"):
        shear_curve_fixed_separation(MAT, ROUGH, AREA, math.nan, [0.0])
    with pytest.raises(InputError, match="Material.work_of_adhesion"):
        Material(2.133e6, math.nan, 0.2, 0.13e6)
    with pytest.raises(InputError, match="nominal_area = 1e-09 m.2 holds eta.A_n = 0.652 < 1"):
        preload(MAT, ROUGH, 1e-9, LOAD)


def test_smooth_limit_sliding_friction_is_the_single_hertz_contact():
    # sigma_s -> 0: every asperity has the same indentation; once all slide, each carries the
    # Hertz load F/N at delta = (3 F / (4 N E* sqrt(R)))^(2/3) and the friction is
    # tau0 N pi R delta (E:Hertz_theory). The closed-form GW load used to overflow (NaN) here.
    rough = smooth(1e-10)
    with pytest.warns(StatmodelWarning, match="A_r/A_n"):  # this limit is beyond A_n: said
        c = shear_curve(SMOOTH_MAT, rough, SMOOTH_AREA, 1.0, np.linspace(0.0, 50e-6, 11))
    assert c.converged and c.status == 3
    delta = (3 * 1.0 / (4 * N_SMOOTH * SMOOTH_MAT.e_star * math.sqrt(SMOOTH_R))) ** (2 / 3)
    # height spread: E[(Z - h)^(3/2)] = |h|^(3/2) (1 + 3/(8 h^2) + ...) -> d = -delta (1 - s^2/4)
    # with s = sigma_s / delta (here 1.2e-4: a 4e-9 correction)
    d_s = -delta * (1 - 0.25 * (1e-10 / delta) ** 2)
    expected = SMOOTH_MAT.shear_strength * N_SMOOTH * math.pi * SMOOTH_R * (-d_s)
    assert c.sliding_friction == pytest.approx(expected, rel=1e-11)
    assert c.tangential_force[-1] == pytest.approx(expected, rel=1e-10)
    assert c.sliding_separation == pytest.approx(d_s, rel=1e-11)


def test_composite_limits_are_the_printed_delta_2_and_delta_1():
    from asperity.statmodel import pc_min_indentation

    c = shear_curve(MAT, ROUGH, AREA, LOAD, np.linspace(0.0, 14e-6, 29))
    mu = tabor_parameter(ROUGH.summit_radius, MAT.work_of_adhesion, MAT.e_star)
    d_load = jkr_jump_in_distance(mu, MAT.equilibrium_distance)
    d_pc = pc_min_indentation(
        c.tangential_displacement,
        ROUGH.summit_radius,
        MAT.work_of_adhesion,
        MAT.e_star,
        MAT.mode_mixity,
    )
    delta_2 = np.maximum(c.separation_preload - c.separation + d_load, d_pc)  # E:delta_2
    np.testing.assert_allclose(c.delta_2, delta_2, rtol=1e-12)
    np.testing.assert_array_equal(c.delta_1, np.minimum(0.0, c.delta_2))  # E:delta_1
    # both branches of the max are active along the path: history first, then the PC fold
    assert c.delta_2[0] == pytest.approx(d_load, rel=1e-14)
    assert c.delta_2[-1] == pytest.approx(d_pc[-1], rel=1e-14) and d_pc[-1] > 0
    # the counts are the Gaussian probabilities of the populations
    n = ROUGH.asperity_density * AREA
    z2 = (c.separation + c.delta_2) / (math.sqrt(2) * ROUGH.summit_height_rms)
    np.testing.assert_allclose(
        c.n_stick, n * 0.5 * np.array([math.erfc(z) for z in z2]), rtol=1e-12, atol=1e-300
    )
