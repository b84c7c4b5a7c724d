"""Statistical model: preload, shear at constant load, fixed grip, derived friction values."""

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
    StatmodelWarning,
    TaborWarning,
    preload,
    pull_off_force,
    real_area_at_loads,
    shear_curve,
    shear_curve_fixed_separation,
    tabor_parameter,
)
from asperity.statmodel.reference import ReferenceModel
from tests._helpers import FIG4_AREA, FIG4_LOAD, FIG4_MATERIAL, FIG4_ROUGHNESS

# Fig. 4 case (the TOML)
MAT, ROUGH, AREA, LOAD = FIG4_MATERIAL, FIG4_ROUGHNESS, FIG4_AREA, FIG4_LOAD
DTS = np.linspace(0.0, 14e-6, 281)


@pytest.fixture(scope="module")
def curve():
    return shear_curve(MAT, ROUGH, AREA, LOAD, DTS)


@pytest.fixture(scope="module")
def reference_path():
    idx = np.array([0, 20, 60, 90, 100, 110, 130, 160, 200, 280])
    d_pre, states = ReferenceModel(MAT, ROUGH, AREA).shear_states(LOAD, DTS[idx])
    return idx, d_pre, states


def test_preload_carries_the_load_and_matches_reference():
    pre = preload(MAT, ROUGH, AREA, LOAD)
    assert pre.converged
    assert pre.normal_force == pytest.approx(LOAD, rel=1e-11)
    ref = ReferenceModel(MAT, ROUGH, AREA)
    d_ref = ref.preload_separation(LOAD)
    assert pre.separation == pytest.approx(d_ref, rel=1e-12)
    st = ref.state(d_ref, 0.0, None)
    assert pre.real_area == pytest.approx(st.real_area, rel=1e-10)
    assert pre.n_contact == pytest.approx(st.n_contact, rel=1e-12)
    assert pre.tabor_parameter == pytest.approx(1217, rel=1e-3)


def test_real_area_at_loads_is_greenwood_williamson_without_adhesion_and_more_with_it():
    loads = np.array([0.5, 1.0, 3.1, 8.0])
    hertz = Material(MAT.e_star, 0.0, MAT.mode_mixity, MAT.shear_strength)
    areas_gw = real_area_at_loads(hertz, ROUGH, AREA, loads)
    for load, area in zip(loads, areas_gw, strict=True):
        assert area == pytest.approx(
            _greenwood_williamson_sliding_state(ROUGH, MAT.e_star, load)[1], rel=1e-9
        )
    # adhesion pulls more of the surface into contact at the same load, all the more so at low
    # load (Fig. 4 surface: +17 % at 0.5 N, +14 % at 8 N)
    gain = real_area_at_loads(MAT, ROUGH, AREA, loads) / areas_gw
    assert np.all(gain > 1.05) and np.all(np.diff(gain) < 0)


def test_continuity_between_preload_and_shear(curve):
    pre = preload(MAT, ROUGH, AREA, LOAD)
    assert curve.tangential_displacement[0] == 0.0
    assert curve.separation[0] == pre.separation
    assert curve.real_area[0] == pytest.approx(pre.real_area, rel=1e-15)
    assert curve.normal_force[0] == pytest.approx(pre.normal_force, rel=1e-15)
    assert curve.n_contact[0] == pytest.approx(pre.n_contact, rel=1e-15)
    assert curve.tangential_force[0] == 0.0
    assert curve.n_slip[0] == 0.0 and curve.real_area_slip[0] == 0.0
    # first shear steps stay close to the preload state (no jump)
    assert abs(curve.real_area[1] / pre.real_area - 1) < 1e-4
    assert abs(curve.separation[1] - pre.separation) < 1e-6 * ROUGH.summit_height_rms


def test_load_conservation_at_every_step(curve):
    assert curve.converged, curve.message
    np.testing.assert_allclose(curve.normal_force, LOAD, rtol=1e-9)
    # both populations really share the load when sliding
    mid = 110
    assert curve.normal_force_stick[mid] > 0.1 * LOAD and curve.normal_force_slip[mid] > 0.1 * LOAD
    # separation increases while junctions slip away (paper, Section 3.2)
    assert curve.separation[100] > curve.separation[0]


def test_against_the_converged_reference(curve, reference_path):
    idx, d_pre, states = reference_path
    assert curve.separation_preload == pytest.approx(d_pre, rel=1e-12)
    for i, s in zip(idx, states, strict=False):
        assert curve.normal_force[i] == pytest.approx(s.normal_force, rel=1e-9)
        assert curve.real_area[i] == pytest.approx(s.real_area, rel=1e-6)
        assert curve.real_area_stick[i] == pytest.approx(s.real_area_stick, rel=1e-6, abs=1e-20)
        assert curve.n_stick[i] == pytest.approx(s.n_stick, rel=1e-6, abs=1e-9)
        if i:
            assert curve.tangential_force[i] == pytest.approx(s.tangential_force, rel=1e-6)
            assert curve.tangential_force_slip[i] == pytest.approx(
                s.tangential_force_slip, rel=1e-6, abs=1e-15
            )


def test_convergence_under_refinement(reference_path):
    idx, _, states = reference_path
    ref_fx = np.array([s.tangential_force for s in states])[1:]
    errors = []
    for nodes, panels in [(4, 1), (6, 2), (8, 2), (12, 3)]:
        c = shear_curve(MAT, ROUGH, AREA, LOAD, DTS, nodes=nodes, panels=panels)
        errors.append(np.max(np.abs(c.tangential_force[idx][1:] / ref_fx - 1)))
    assert all(e2 < e1 for e1, e2 in zip(errors, errors[1:], strict=False)), errors
    assert errors[0] > 1e-4 and errors[-1] < 1e-8


def test_sliding_friction_is_the_hertz_only_closed_form(curve):
    # the all-sliding limit: F_x at large delta_T -> tau0 * A_GW(d_s)
    assert curve.n_stick[-1] < 1e-30
    assert curve.tangential_force[-1] == pytest.approx(curve.sliding_friction, rel=1e-9)
    # all junctions slide: Greenwood-Williamson with Hertz asperities, written out independently
    d_s, area_s = _greenwood_williamson_sliding_state(ROUGH, MAT.e_star, LOAD)
    assert curve.sliding_separation == pytest.approx(d_s, rel=1e-9)
    assert curve.sliding_friction == pytest.approx(MAT.shear_strength * area_s, rel=1e-9)
    assert curve.separation[-1] == pytest.approx(curve.sliding_separation, rel=1e-9)
    # static friction peak above the sliding friction (Fig. 4d)
    assert curve.static_friction > 1.1 * curve.sliding_friction
    # real area shrinks under shear (Fig. 4c)
    assert curve.real_area[-1] < 0.9 * curve.real_area[0]


def _greenwood_williamson_sliding_state(roughness, e_star, load):
    """(separation m, real area m^2) of Hertz asperities carrying ``load`` N (GW 1966).

    Load by adaptive quadrature of the Hertz law over the Gaussian heights, separation by Brent,
    area from the Gaussian partial moment N pi R sigma (pdf(h) - h Q(h)).
    """
    r, s = roughness.summit_radius, roughness.summit_height_rms
    n = roughness.asperity_density * AREA

    def gw_load(d):
        def integrand(z):
            hertz = 4 / 3 * e_star * math.sqrt(r) * (z - d) ** 1.5
            return hertz * math.exp(-0.5 * (z / s) ** 2)

        value = quad(integrand, d, d + 14 * s, epsabs=0, epsrel=1e-13, limit=200)[0]
        return n * value / (math.sqrt(2 * math.pi) * s)

    d = brentq(lambda x: gw_load(x) - load, -5 * s, 5 * s, xtol=1e-16 * s, rtol=1e-15)
    h = d / s
    pdf = math.exp(-0.5 * h * h) / math.sqrt(2 * math.pi)
    return d, n * math.pi * r * s * (pdf - h * 0.5 * math.erfc(h / math.sqrt(2)))


@pytest.mark.parametrize("grip", ["load", "fixed"])
def test_static_friction_is_the_continuous_peak(grip):
    # The static friction is the peak of the continuous F_x(delta_T), not of the grid: a 17-step
    # curve (grid maximum 1.2 % low) must give the peak of a 1600x finer grid to 1e-6, with the
    # displacement at the peak. The fine grid's maximum is a lower bound within h^2 F'' of it.
    if grip == "load":
        run = lambda dts: shear_curve(MAT, ROUGH, AREA, LOAD, dts)  # noqa: E731
    else:
        d_min = preload(MAT, ROUGH, AREA, LOAD).separation
        run = lambda dts: shear_curve_fixed_separation(MAT, ROUGH, AREA, d_min, dts)  # noqa: E731
    coarse = run(np.linspace(0.0, 14e-6, 17))
    fine = run(np.linspace(0.0, 14e-6, 28001))
    fine_grid_peak = np.max(fine.tangential_force)
    assert np.max(coarse.tangential_force) < (1 - 5e-3) * coarse.static_friction
    assert coarse.static_friction == pytest.approx(fine.static_friction, rel=1e-6)
    assert fine_grid_peak <= fine.static_friction * (1 + 1e-12)
    assert fine_grid_peak == pytest.approx(fine.static_friction, rel=1e-6)
    i = int(np.argmax(fine.tangential_force))
    h = fine.tangential_displacement[1]
    assert abs(coarse.static_displacement - fine.tangential_displacement[i]) <= h
    assert coarse.static_displacement == pytest.approx(fine.static_displacement, rel=1e-5)


def test_static_friction_agrees_with_the_reference_at_the_peak(curve):
    # the refined peak is a state of the model itself: the independent adaptive-quadrature
    # reference gives the same F_x there, and less on either side of it
    dt = curve.static_displacement
    ref = ReferenceModel(MAT, ROUGH, AREA)
    _, states = ref.shear_states(LOAD, np.array([0.0, 0.99 * dt, dt, 1.01 * dt]))
    fx = [s.tangential_force for s in states[1:]]
    assert fx[1] == pytest.approx(curve.static_friction, rel=1e-6)
    assert fx[0] < fx[1] and fx[2] < fx[1]


@pytest.mark.parametrize(
    "changes, load",
    [
        ({"work_of_adhesion": 0.015}, 3.1),
        ({"work_of_adhesion": 0.060, "mode_mixity": 0.05}, 0.5),
        ({"mode_mixity": 0.9, "shear_strength": 0.5e6}, 10.0),
    ],
)
def test_static_friction_peak_across_the_fig5_range(changes, load):
    # smooth maxima, kinks where junctions start to slide, or a monotonic rise to the sliding
    # friction: the coarse refined peak is the fine grid's maximum to 1e-6, never below it
    mat = Material(**{**MAT.__dict__, **changes})
    coarse = shear_curve(mat, ROUGH, AREA, load, np.linspace(0.0, 20e-6, 21))
    fine = shear_curve(mat, ROUGH, AREA, load, np.linspace(0.0, 20e-6, 20001))
    fine_grid_peak = np.max(fine.tangential_force)
    assert fine_grid_peak <= coarse.static_friction * (1 + 1e-9)
    assert coarse.static_friction == pytest.approx(fine_grid_peak, rel=1e-6)


def test_sliding_displacement_is_where_one_asperity_still_sticks(curve):
    s = curve.sliding_displacement
    assert 0.0 < s < DTS[-1]
    c = shear_curve(MAT, ROUGH, AREA, LOAD, np.array([0.0, 0.5 * s, s]))
    assert c.n_stick[-1] == pytest.approx(1.0, rel=1e-6)


def test_pure_jkr_coupling_never_slides():
    mat = Material(2.133e6, 0.040, 0.0, 0.13e6)
    c = shear_curve(mat, ROUGH, AREA, LOAD, DTS[::20])
    assert c.converged
    assert np.all(c.n_slip == 0.0)
    assert math.isinf(c.sliding_displacement)
    # lambda = 0: the normal problem is unaffected by shear (separation constant)
    np.testing.assert_allclose(c.separation, c.separation[0], rtol=1e-12)
    np.testing.assert_allclose(c.real_area, c.real_area[0], rtol=1e-12)


def test_hertz_limit_without_adhesion_slides_at_once():
    mat = Material(2.133e6, 0.0, 0.2, 0.13e6)
    c = shear_curve(mat, ROUGH, AREA, LOAD, np.array([0.0, 1e-9, 1e-6]))
    assert c.converged
    assert c.n_stick[1] == 0.0 and c.n_stick[2] == 0.0
    np.testing.assert_allclose(c.tangential_force[1:], c.sliding_friction, rtol=1e-9)
    np.testing.assert_allclose(c.real_area[1:], c.real_area[0], rtol=1e-9)


def test_fixed_grip_shear_at_the_preload_separation():
    pre = preload(MAT, ROUGH, AREA, LOAD)
    c = shear_curve_fixed_separation(MAT, ROUGH, AREA, pre.separation, DTS)
    assert c.normal_force[0] == pytest.approx(LOAD, rel=1e-11)
    assert c.real_area[0] == pytest.approx(pre.real_area, rel=1e-14)
    # in fixed grip the normal load changes under shear (coupling through lambda)
    assert abs(c.normal_force[100] / LOAD - 1) > 1e-3
    assert c.tangential_force[-1] == pytest.approx(c.sliding_friction, rel=1e-9)


def test_errors_name_the_problem():
    with pytest.raises(InputError, match="pull-off force"):
        preload(MAT, ROUGH, AREA, -1e-3)
    with pytest.raises(InputError, match="nominal_area.*< 1 asperity"):
        shear_curve(MAT, ROUGH, 1e-10, LOAD, DTS)
    with pytest.raises(InputError, match="Material.e_star"):
        Material(-1.0, 0.04, 0.2, 1e5)
    with pytest.raises(InputError, match="Material.mode_mixity"):
        Material(1e6, 0.04, 1.5, 1e5)
    with pytest.raises(InputError, match="Roughness.summit_radius"):
        Roughness(1e6, float("nan"), 1e-5)
    with pytest.raises(InputError, match="tangential_displacement"):
        shear_curve(MAT, ROUGH, AREA, LOAD, [0.0, 2e-6, 1e-6])
    with pytest.raises(InputError, match="unknown accuracy knob"):
        shear_curve(MAT, ROUGH, AREA, LOAD, DTS, node=3)


def test_pull_off_force_is_the_minimum_of_the_preload_curve():
    # a smooth, strongly adhesive surface where adhesion matters: sigma_s comparable to the
    # jump-off distance
    rough = Roughness(asperity_density=1e9, summit_radius=1e-4, summit_height_rms=3e-8)
    mat = Material(1e6, 0.05, 0.2, 1e5)
    f_po = pull_off_force(mat, rough, 1e-4)
    assert f_po < 0
    # the load just above it is carried, just below it is refused with the force named
    pre = preload(mat, rough, 1e-4, 0.999 * f_po)
    assert pre.converged and pre.normal_force == pytest.approx(0.999 * f_po, rel=1e-9)
    with pytest.raises(InputError, match=f"{f_po:.6g} N"):
        preload(mat, rough, 1e-4, 1.001 * f_po)


def test_tabor_warning_below_five():
    with pytest.warns(TaborWarning):
        tabor_parameter(1e-9, 0.01, 1e11, 0.2e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tabor_parameter(1e-9, 0.0, 1e11, 0.2e-9)  # no adhesion: Hertz, no warning


@pytest.mark.parametrize(
    "changes, load",
    [
        ({"work_of_adhesion": 0.015}, 3.1),
        ({"work_of_adhesion": 0.060, "mode_mixity": 0.05}, 0.5),
        ({"mode_mixity": 0.9, "shear_strength": 0.5e6}, 10.0),
        ({"mode_mixity": 1.0}, 1.0),
    ],
)
def test_default_accuracy_across_the_fig5_parameter_range(changes, load):
    base = {
        "e_star": 2.133e6,
        "work_of_adhesion": 0.040,
        "mode_mixity": 0.2,
        "shear_strength": 0.13e6,
    }
    mat = Material(**{**base, **changes})
    dts = np.linspace(0.0, 20e-6, 9)
    c = shear_curve(mat, ROUGH, AREA, load, dts)
    assert c.converged
    _, states = ReferenceModel(mat, ROUGH, AREA).shear_states(load, dts)
    for i, s in enumerate(states):
        assert c.normal_force[i] == pytest.approx(load, rel=1e-9)
        assert c.real_area[i] == pytest.approx(s.real_area, rel=1e-6)
        if i:
            assert c.tangential_force[i] == pytest.approx(s.tangential_force, rel=1e-6)


@pytest.mark.parametrize("seed", range(8))
def test_default_accuracy_on_random_parameters(seed):
    rng = np.random.default_rng(seed)
    mat = Material(
        10 ** rng.uniform(5.5, 7),
        10 ** rng.uniform(-2.5, -0.7),
        rng.uniform(0, 1),
        10 ** rng.uniform(4.5, 6.5),
    )
    rough = Roughness(
        10 ** rng.uniform(6, 9), 10 ** rng.uniform(-5.5, -3), 10 ** rng.uniform(-6.5, -4.5)
    )
    with warnings.catch_warnings():
        # random parameters: some are outside the model (mu < 5, A_r/A_n > 0.1); the accuracy
        # against the reference is the subject here, and holds there too
        warnings.simplefilter("ignore", StatmodelWarning)
        probe = shear_curve(mat, rough, 1e-4, 1.0, [0.0, 1e-9])
        end = 1.5 * probe.sliding_displacement
        dts = np.linspace(0.0, end if np.isfinite(end) else 1e-5, 7)
        c = shear_curve(mat, rough, 1e-4, 1.0, dts)
        _, states = ReferenceModel(mat, rough, 1e-4).shear_states(1.0, dts)
    assert c.converged
    for i, s in enumerate(states):
        assert c.normal_force[i] == pytest.approx(1.0, rel=1e-9)
        assert c.real_area[i] == pytest.approx(s.real_area, rel=1e-6)
        if i:
            assert c.tangential_force[i] == pytest.approx(s.tangential_force, rel=1e-6)
