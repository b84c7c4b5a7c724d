"""The calibration against the BEM is like for like: the model under the BEM's own law chooses
the effective resolution, one effective resolution (and one set of statistics) everywhere, the
BEM reference's band reaches the interval, and a measured point is never beaten by the
reported one."""

from __future__ import annotations

import math
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

from asperity import statmodel, topo
from asperity.pipelines.config import load_preset
from asperity.pipelines.report import key_numbers, load_table
from asperity.pipelines.report.figures import draw_resolution, nyquist_marks
from asperity.pipelines.stages.statistical_model import (
    GREENWOOD_WILLIAMSON,
    MAUGIS_DUGDALE,
    bem_law_areas_at_loads,
    bem_law_of,
    normal_contact_material,
    statistical_model_scan,
)
from asperity.pipelines.stages.surface import ScanResult, scan_resolutions
from asperity.statmodel.effective_resolution import locate_least_misfit, roughness_at_resolution
from asperity.statmodel.maugis_rough import asperity_law_regime

LOADS = np.array([0.56, 1.06, 1.58, 2.08, 2.57, 3.12])
#: The default job's BEM (baseline report): non-adhesive and Maugis-Dugdale A_r/A_n, h_0 12.5 um.
BEM_PLAIN = np.array([0.001329, 0.00254, 0.003754, 0.004919, 0.00613, 0.007451])
BEM_MD = np.array([0.001351, 0.002591, 0.003818, 0.004992, 0.006236, 0.007567])
H0 = 12.5e-6


def _material():
    return normal_contact_material(load_preset("default").material)


def _fake_bem(fraction, plain=None, *, adhesion="maugis", h0=H0, relative=None):
    """A stand-in for the BEM stage's result: the fields the statistical-model stage reads."""
    fraction = np.asarray(fraction, dtype=float)
    plain = fraction if plain is None else np.asarray(plain, dtype=float)
    u = None if relative is None else np.asarray(relative) * fraction
    return SimpleNamespace(
        adhesion=adhesion,
        adhesion_range=h0 if adhesion == "maugis" else None,
        contact_fraction=plain,
        contact_fraction_adhesive=fraction,
        reference_fraction=lambda: fraction,
        reference_fraction_uncertainty=lambda: u,
    )


def test_bem_law_rules():
    """Maugis-Dugdale BEM -> MD model at its h_0; Pohrt-Popov, no adhesive solves or w = 0 ->
    Greenwood-Williamson."""
    assert bem_law_of(_fake_bem(BEM_MD), 0.04) == (MAUGIS_DUGDALE, H0)
    assert bem_law_of(_fake_bem(BEM_MD, adhesion="pohrt-popov"), 0.04) == (
        GREENWOOD_WILLIAMSON,
        None,
    )
    assert bem_law_of(_fake_bem(BEM_MD), 0.0)[0] == GREENWOOD_WILLIAMSON
    no_adhesive = _fake_bem(BEM_MD)
    no_adhesive.contact_fraction_adhesive = None
    assert bem_law_of(no_adhesive, 0.04)[0] == GREENWOOD_WILLIAMSON
    assert bem_law_of(None, 0.04)[0] == GREENWOOD_WILLIAMSON


@pytest.mark.parametrize(
    "rough",
    [
        statmodel.Roughness(67.87e6, 0.05584e-3, 0.04872e-3),  # baseline's located 15.01 um
        statmodel.Roughness(49.03e6, 0.06663e-3, 0.04851e-3),  # the 20 um stride
    ],
)
def test_default_job_gain_bar(rough):
    """The issue's bar on the default job's statistics: the model's adhesive gain over GW under
    the BEM's law (MD at h_0 = 12.5 um) is within a factor 2 of the BEM's at every load, while
    the JKR model's is over 5 times larger."""
    material = _material()
    a_n = load_preset("default").loading.nominal_area
    md, message = bem_law_areas_at_loads(material, rough, a_n, LOADS, H0)
    gw = bem_law_areas_at_loads(material, rough, a_n, LOADS, None)[0]
    jkr = statmodel.real_area_at_loads(material, rough, a_n, LOADS)
    assert message == "" and np.all(np.isfinite(md))
    gain, bem_gain = md / gw - 1, BEM_MD / BEM_PLAIN - 1
    assert np.all(gain > bem_gain / 2) and np.all(gain < 2 * bem_gain)
    assert np.all(jkr / gw - 1 > 5 * gain)


@pytest.fixture(scope="module")
def small_map():
    """A 256^2 paper-like map (10 um pixels), its scan to stride 5, the default material."""
    surface = topo.synthetic.paper_like(n=256, pixel_size=10e-6, seed=2)
    scan = ScanResult.from_scan(scan_resolutions(surface, 5))
    return surface, scan, _material(), load_preset("default").loading.nominal_area


def _reference(small_map, resolution, h0=None):
    surface, _, material, a_n = small_map
    rough = roughness_at_resolution(surface, resolution)
    return bem_law_areas_at_loads(material, rough, a_n, LOADS, h0)[0] / a_n


def _stage(small_map, bem):
    surface, scan, material, a_n = small_map
    return statistical_model_scan(scan, material, a_n, LOADS, bem=bem, surface=surface)


def test_pohrt_popov_pairs_with_gw_and_one_resolution_everywhere(small_map):
    """A Pohrt-Popov BEM made by GW at 25 um: GW chooses (its areas are the law's), the located
    resolution's interval holds 25 um, and every field of the effective resolution is that
    one: its statistics are the map's there, the Tabor parameter is at its R."""
    surface, scan, material, _ = small_map
    reference = _reference(small_map, 25e-6)
    res = _stage(small_map, _fake_bem(reference, adhesion="pohrt-popov"))
    assert res.bem_law == GREENWOOD_WILLIAMSON and res.bem_law_adhesion_range is None
    np.testing.assert_array_equal(res.real_area_bem_law, res.real_area_non_adhesive)
    low, high = res.optimum_interval
    assert low <= 25e-6 <= high
    assert res.effective_resolution == res.optimum_resolution
    assert res.effective_resolution != res.resolution[res.effective_index]
    at = roughness_at_resolution(surface, res.effective_resolution)
    assert res.roughness == at
    assert res.summit_radius == res.optimum_summit_radius == at.summit_radius
    mu = statmodel.tabor_parameter(
        at.summit_radius, material.work_of_adhesion, material.e_star, 0.2e-9, warn=False
    )
    assert res.tabor_parameter == pytest.approx(mu, rel=1e-12)
    assert res.maugis_parameter is None  # no Maugis-Dugdale law to state


def test_reference_band_reaches_the_interval(small_map):
    """The same reference scaled by 0.91 and 1.18 moves the optimum finer and coarser; with a
    relative band u = 0.18 the interval holds both and the misfit's own interval, and the
    optima it stores against (1 -/+ u) are those of the scaled references."""
    reference = _reference(small_map, 25e-6)

    def located(scale, relative=None):
        bem = _fake_bem(reference * scale, adhesion="pohrt-popov", relative=relative)
        return _stage(small_map, bem)

    plain, low, high = located(1.0), located(0.91), located(1.18)
    assert plain.optimum_reference_shift is None
    assert low.effective_resolution < plain.effective_resolution < high.effective_resolution
    banded = located(1.0, np.full(LOADS.size, 0.18))
    lo, hi = banded.optimum_interval
    assert lo <= low.effective_resolution and high.effective_resolution <= hi
    assert lo <= plain.optimum_interval[0] and plain.optimum_interval[1] <= hi
    np.testing.assert_allclose(banded.optimum_misfit_interval, plain.optimum_interval)
    shifted = located(1.0 - 0.18), located(1.18)
    for stored, own in zip(banded.optimum_reference_shift, shifted, strict=True):
        # placed on the resolutions already sampled (no refinement inside the scan): equal to a
        # full relocation within the misfit's scatter between strides (measured 0 and 9 %)
        assert abs(math.log(stored / own.effective_resolution)) < 0.15
    np.testing.assert_allclose(banded.reference_relative_uncertainty, 0.18)
    assert "(1 - u)" in banded.optimum_message


@pytest.mark.slow
def test_maugis_bem_pairs_with_the_maugis_model(small_map):
    """A Maugis-Dugdale BEM made by the MD model at 25 um (h_0 = 12.5 um): the MD model
    chooses and its interval holds 25 um; the JKR model would not fit it as well; the BEM's
    Maugis parameter and statement are those at the effective R."""
    surface, _, material, a_n = small_map
    reference = _reference(small_map, 25e-6, H0)
    plain = _reference(small_map, 25e-6)
    res = _stage(small_map, _fake_bem(reference, plain))
    assert res.bem_law == MAUGIS_DUGDALE and res.bem_law_adhesion_range == H0
    low, high = res.optimum_interval
    assert low <= 25e-6 <= high
    assert res.real_area_bem_law.shape == res.real_area.shape
    gain = res.effective_real_area_bem_law / res.effective_real_area_non_adhesive - 1
    assert np.all((gain > 0) & (gain < 0.05))
    regime = asperity_law_regime(
        res.summit_radius, material.e_star, material.work_of_adhesion, H0, 0.2e-9
    )
    assert res.maugis_parameter == pytest.approx(regime.maugis_parameter)
    assert res.adhesion_statement == regime.statement
    jkr_misfit = np.sqrt(np.mean(np.log(res.optimum_real_area / a_n / reference) ** 2))
    assert jkr_misfit > 2 * res.optimum_misfit


def test_a_measured_point_beats_a_worse_vertex():
    """The parabola's vertex fits worse than the best resolution sampled: the sampled one is
    reported, and the message says why."""
    strides = np.array([10e-6, 20e-6, 30e-6, 40e-6])
    misfit = np.array([0.3, 0.1, 0.12, 0.4])
    fine = np.exp(np.linspace(np.log(10e-6), np.log(30e-6), 10)[1:-1])
    sampled = np.concatenate([strides, fine])

    def misfit_at(resolution):
        if np.isclose(resolution, sampled, rtol=1e-9).any():
            return 0.1 + 2.0 * (math.log(resolution / 21e-6)) ** 2  # smooth at the samples
        return 0.2  # the vertex: worse than measured

    located = locate_least_misfit(strides, misfit, 6, misfit_at=misfit_at)
    best = float(np.min(located.sampled_misfit))
    assert located.misfit == pytest.approx(best)
    assert np.isclose(located.resolution, located.sampled_resolution, rtol=1e-12).any()
    assert located.kept_sample and "reported instead" in located.message


def test_one_effective_resolution_everywhere(small_run):
    """The job: the result's effective resolution is the located one, in the API, in
    results.h5, in Fig 12a-c, the PSD's Nyquist line, the verdict's regime Tabor and the
    report; the stride stays as ``effective_stride``."""
    _, out, result = small_run
    res = result.statistical_model
    assert res.effective_resolution == res.optimum_resolution
    assert res.summit_radius == res.optimum_summit_radius
    with h5py.File(out / "results.h5", "r") as f:
        attrs = f["statistical_model"].attrs
        assert attrs["effective_resolution"] == res.effective_resolution
        assert attrs["summit_radius"] == res.summit_radius
        assert attrs["effective_stride"] == res.effective_stride
        assert f["statistical_model/real_area_bem_law"].attrs["units"] == "m^2"
    assert result.psd.effective_resolution == res.effective_resolution
    marks = nyquist_marks(result)
    assert any(np.isclose(q, math.pi / res.effective_resolution) for q in marks.values())
    assert result.verdict.regime_tabor_parameter == pytest.approx(res.tabor_parameter)
    fig, _ = draw_resolution(result)
    for ax in fig.axes[:3]:
        (line,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("effective")]
        assert line.get_xdata()[0] == pytest.approx(res.effective_resolution * 1e6)
    rows = dict(key_numbers(result))
    assert rows["effective resolution"].startswith(f"{res.effective_resolution * 1e6:.4g} \u00b5m")
    assert f"{res.tabor_parameter:.4g}" in rows["Tabor parameter mu"]
    header, _ = load_table(result)
    assert any(h.startswith("A_r/A_n model MD") for h in header)


def test_configured_lambda_is_said_assumed_with_a_decade(small_run):
    """Without measured shear curves lambda is assumed: the report says so and shows the static
    friction at lambda / sqrt(10) and x sqrt(10) (larger lambda, less friction)."""
    _, _, result = small_run
    fr = result.friction
    assert fr.mode_mixity_assumed
    np.testing.assert_allclose(
        fr.mode_mixity_decade, fr.mode_mixity * np.array([10**-0.5, 10**0.5])
    )
    low, high = fr.static_friction_mode_mixity_decade
    assert np.all(low > fr.static_friction) and np.all(fr.static_friction > high)
    rows = dict(key_numbers(result))
    assert "assumed" in rows["mode mixity lambda (configured)"]
    assert "lambda assumed" in fr.uncertainty_message
    header, _ = load_table(result)
    assert any("lambda assumed" in h for h in header)


def test_a_stride_up_to_round_off_is_the_stride(small_map):
    """exp(log(20 um)) is the stride 2, not a resampling 1e-16 off it: the statistics are the
    scan's own (a kept stride reports the stride's statistics)."""
    surface, scan, _, _ = small_map
    index = int(np.flatnonzero(np.asarray(scan.stride) == 2)[0])
    near = math.exp(math.log(float(scan.resolution[index])))
    assert near != float(scan.resolution[index])  # round-off, as in the location
    rough = roughness_at_resolution(surface, near)
    assert rough.summit_radius == pytest.approx(float(scan.summit_radius[index]), rel=1e-12)
    assert rough.asperity_density == pytest.approx(float(scan.asperity_density[index]), rel=1e-12)
