"""The rough Maugis-Dugdale model's fast separation solve (statmodel.maugis_rough with
statmodel.maugis_march): the batched law against the one-separation quadrature, the turning
points of the force against the law itself, the skipping march against the full march and
against a direct solve written here (one separation at a time, every march step), and the
march's bracket against a brute-force march on random piecewise-linear residuals."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from asperity.statmodel import Roughness
from asperity.statmodel import maugis_rough as mr
from asperity.statmodel.integrals import gauss_legendre
from asperity.statmodel.maugis_march import first_crossing, monotone_runs
from asperity.statmodel.maugis_rough import MaugisAsperity, maugis_rough_contact

E_STAR, WORK, AREA = 2.133e6, 0.040, 700e-6  # PDMS (pipelines/presets/default.toml)
#: plu-1.plu's finest stride (eta 1/m^2, R m, sigma_s m; default preparation) and the range
#: the BEM's rule starts from at its 1.66 um pixel (bem.resolving_range): lambda = 1.7.
PLU1 = Roughness(27037150901.697315, 4.192972590425341e-4, 1.7854443151623673e-08)
PLU1_H0 = 3.448294185634421e-07
#: A surface on which the march crosses a zone of turning points (DMT side, lambda = 0.058):
#: d0 lies where the window of first contact is, the load is reached below it.
ZONE = Roughness(2.7e9, 4.2e-4, 1e-7)
ZONE_H0 = 1e-5
GL = gauss_legendre(16)


def jkr_range(radius: float) -> float:
    """h_0 (m) giving lambda = 3 at the summit radius (the folding Maugis curve)."""
    return WORK / (1.5 * (math.pi * WORK * (4 * E_STAR / 3) ** 2 / radius) ** (1 / 3))


LAWS = [
    pytest.param(5.584e-5, 12.5e-6, id="DMT side, default job"),
    pytest.param(5.584e-5, 2e-6, id="transition"),
    pytest.param(5.584e-5, jkr_range(5.584e-5), id="JKR side, lambda 3"),
    pytest.param(PLU1.summit_radius, PLU1_H0, id="plu-1 stride 1"),
]


@pytest.mark.parametrize(("radius", "h0"), LAWS)
def test_batched_integrals_equal_the_one_separation_form(radius, h0):
    asp = MaugisAsperity(radius, E_STAR, WORK, h0)
    sigma = 0.3 * asp.approach_scale
    d = np.linspace(-3.0 * asp.approach_scale, 10.0 * sigma + h0, 41)
    fz, ar = asp.gaussian_integrals_many(d, sigma, 10.0, GL, 16)
    ref = np.array([asp.gaussian_integrals(x, sigma, 10.0, GL, 16) for x in d])
    assert np.any(ref[:, 0] < 0) and np.any(ref[:, 0] > 0)  # attraction and compression
    assert np.max(np.abs(fz - ref[:, 0])) <= 1e-12 * np.max(np.abs(ref[:, 0]))
    on = ref[:, 1] > 0
    assert np.all(ar[~on] == 0.0)
    assert np.max(np.abs(ar[on] / ref[on, 1] - 1.0)) <= 1e-12


@pytest.mark.parametrize(("radius", "h0"), LAWS)
def test_force_is_monotone_between_its_turning_points(radius, h0):
    asp = MaugisAsperity(radius, E_STAR, WORK, h0)
    turning = asp.force_turning_points()
    assert turning[0][0] == pytest.approx(-h0, rel=1e-12)  # the edge of the range
    edges = [-1.5 * h0] + [x for t in turning for x in t] + [5.0 * asp.approach_scale]
    for lo, hi in zip(edges[0::2], edges[1::2], strict=True):
        if hi - lo > 1e-12 * asp.approach_scale:
            delta = np.linspace(lo, hi, 2003)[1:-1]
            steps = np.diff(asp.loading_state(delta)[0])
            assert np.all(steps >= 0) or np.all(steps <= 0), (lo, hi)


def test_the_dmt_side_minimum_of_the_force_is_a_turning_point():
    """On the DMT side the force is most tensile just inside contact: an extremum that is not
    a join, bracketed by the turning points; the force falls before it and rises after."""
    asp = MaugisAsperity(5.584e-5, E_STAR, WORK, 12.5e-6)
    joins = {p.delta_start * asp.approach_scale for p in asp.pieces}
    inner = [t for t in asp.force_turning_points() if t[1] > t[0]]
    assert len(inner) == 1 and inner[0][0] not in joins
    lo, hi = inner[0]
    width = hi - lo
    f = asp.loading_state(np.array([lo - 50 * width, lo, hi, hi + 50 * width]))[0]
    assert f[1] < f[0] and f[2] < f[3]


@pytest.mark.parametrize(("rough", "h0"), [(PLU1, PLU1_H0), (ZONE, ZONE_H0), (PLU1, 30 * PLU1_H0)])
def test_force_is_monotone_on_the_monotone_separations(rough, h0):
    law = mr._gaussian_law(rough, E_STAR, WORK, h0, AREA, {})
    finite = [(lo, hi) for lo, hi in law.monotone_separations() if math.isfinite(lo + hi)]
    spans = [(lo, hi) for lo, hi in law.monotone_separations()]
    lowest = spans[0][1]
    finite.append((lowest - 40.0 * rough.summit_height_rms, lowest))  # the open run below
    for lo, hi in finite:
        d = np.linspace(lo, hi, 201)
        steps = np.diff(law.forces(d))
        assert np.all(steps >= -1e-12 * np.max(np.abs(steps))) or np.all(
            steps <= 1e-12 * np.max(np.abs(steps))
        )


def _full_march(monkeypatch) -> None:
    """Every march point evaluated: no interval of d declared monotone."""
    monkeypatch.setattr(mr._Law, "monotone_separations", lambda self: [])


@pytest.mark.parametrize(("rough", "h0"), [(PLU1, PLU1_H0), (ZONE, ZONE_H0)])
def test_skipping_march_equals_the_full_march(rough, h0, monkeypatch):
    loads = [0.56, 3.12]
    fast = maugis_rough_contact(rough, E_STAR, WORK, h0, AREA, loads)
    _full_march(monkeypatch)
    full = maugis_rough_contact(rough, E_STAR, WORK, h0, AREA, loads)
    assert np.all(fast.success) and np.all(full.success)
    # both roots to Brent's xtol of 1e-15 m in d; F_z is the net of compressive and adhesive
    # forces up to 1e5 times larger on a sticky map, so it is held to the load instead
    for name in ("separation", "real_area", "n_contact", "n_attracted"):
        np.testing.assert_allclose(getattr(fast, name), getattr(full, name), rtol=1e-9)
    np.testing.assert_allclose(fast.normal_force, loads, rtol=1e-6)
    assert np.all(fast.nit < full.nit)


def test_a_sticky_map_costs_a_few_evaluations_per_load():
    """plu-1's finest stride with PDMS: the full march took about 2900 steps per load."""
    res = maugis_rough_contact(PLU1, E_STAR, WORK, PLU1_H0, AREA, [0.56, 1.58, 3.12])
    assert np.all(res.success)
    assert np.all(res.real_area > AREA)  # the model's areas beyond A_n: full contact
    assert np.all(res.nit <= 40)


def direct_solve(rough: Roughness, h0: float, load: float) -> tuple[float, float, float]:
    """(d m, F_z N, A_r m^2) by the one-separation quadrature, every march step evaluated:
    from the Hertz separation at the load, down by 0.02 sigma_s until F_z reaches it."""
    asp = MaugisAsperity(rough.summit_radius, E_STAR, WORK, h0)
    sigma, n = rough.summit_height_rms, rough.asperity_density * AREA

    def fa(d: float) -> tuple[float, float]:
        f, a = asp.gaussian_integrals(d, sigma, 10.0, GL, 16)
        return n * f, n * a

    def hertz(d: float) -> float:
        return n * mr._hertz_integrals(asp.radius, E_STAR, d, sigma, 10.0, GL, 16)[0] - load

    d0 = brentq(hertz, -1010 * sigma, 10 * sigma + h0, xtol=1e-15)
    upper = d0
    while fa(upper - 0.02 * sigma)[0] < load:
        upper -= 0.02 * sigma
    d = brentq(lambda x: fa(x)[0] - load, upper - 0.02 * sigma, upper, xtol=1e-15, rtol=1e-15)
    return (d, *fa(d))


def test_agrees_with_the_direct_solve():
    """Through a zone of turning points: d, F_z and A_r within 1e-10 of the direct solve."""
    res = maugis_rough_contact(ZONE, E_STAR, WORK, ZONE_H0, AREA, [0.56])
    d, fz, ar = direct_solve(ZONE, ZONE_H0, 0.56)
    assert res.separation[0] == pytest.approx(d, rel=1e-10)
    assert res.normal_force[0] == pytest.approx(fz, rel=1e-10)
    assert res.real_area[0] == pytest.approx(ar, rel=1e-10)


DATA = Path(__file__).resolve().parents[1] / "data"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["plu-1.plu", "opd-1.opd"])
def test_measured_maps_agree_with_the_direct_solve(name):
    """The stage's call on the real maps' finest stride (default preparation, PDMS, the BEM
    rule's starting range): d and A_r within 1e-9 of the direct solve, F_z within 1e-6 of
    the load (each root to Brent's 1e-15 m in d; F_z is the net of forces up to 1e5 times
    larger)."""
    from asperity import topo
    from asperity.bem import resolving_range

    raw = topo.read_surface(DATA / name)
    surface = topo.prepare_surface(raw, topo.PreparationOptions(missing="interpolate")).surface
    scan = topo.resolution_scan(surface, 1)
    rough = Roughness(
        float(scan.asperity_density[0]),
        float(scan.summit_radius[0]),
        float(scan.summit_height_rms[0]),
    )
    h0 = resolving_range(WORK, E_STAR, min(surface.dx, surface.dy))
    res = maugis_rough_contact(rough, E_STAR, WORK, h0, AREA, [1.58])
    d, fz, ar = direct_solve(rough, h0, 1.58)
    assert res.separation[0] == pytest.approx(d, rel=1e-9)
    assert res.real_area[0] == pytest.approx(ar, rel=1e-9)
    assert res.normal_force[0] == pytest.approx(1.58, rel=1e-6) == fz


# --- the march on its own: random piecewise-linear residuals ---------------------------------


def _piecewise(knots_d: np.ndarray, knots_f: np.ndarray):
    order = np.argsort(knots_d)
    xs, ys = knots_d[order], knots_f[order]
    return lambda d: np.interp(np.asarray(d, dtype=float), xs, ys)


@settings(max_examples=60, deadline=None)
@given(
    values=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=12),
    shift=st.floats(0.0, 0.999),
)
def test_march_brackets_the_root_the_full_march_finds(values, shift):
    knots = np.arange(len(values), dtype=float) * -1.0 - shift  # 0 - shift downwards
    residual = _piecewise(knots, np.array(values))
    # linear between knots: monotone on each interval of knots, shrunk by a margin
    monotone = [(knots[k + 1] + 0.01, knots[k] - 0.01) for k in range(len(values) - 1)]
    d_low = float(knots[-1])
    full = first_crossing(residual, 0.0, 0.005, d_low)
    fast = first_crossing(residual, 0.0, 0.005, d_low, monotone)
    assert fast.reached == full.reached
    assert fast.evaluations <= full.evaluations
    if full.reached:
        assert fast.lower <= full.lower <= full.upper <= fast.upper
        if fast.lower < fast.upper:
            assert residual(fast.lower) >= 0 > residual(fast.upper)


def test_march_at_a_start_that_already_carries_the_load():
    found = first_crossing(lambda d: np.ones_like(d), 0.5, 0.1, -1.0)
    assert (found.lower, found.upper, found.reached) == (0.5, 0.5, True)


def test_march_that_never_reaches_the_load_says_so():
    found = first_crossing(lambda d: -np.ones_like(d), 0.0, 0.1, -1.0, [(-0.75, -0.25)])
    assert not found.reached and math.isnan(found.upper)
    assert found.evaluations < 12  # the interior of the monotone run skipped


def test_monotone_runs_keep_both_ends_of_each_run():
    d = -0.1 * np.arange(11)  # 0 .. -1
    keep = monotone_runs(d, [(-0.85, -0.15)])  # holds d_2 .. d_8
    assert keep.tolist() == [0, 1, 2, 8, 9, 10]
