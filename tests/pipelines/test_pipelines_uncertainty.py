"""Error bars of the job's predicted numbers: the effective resolution between strides with its
interval, the BEM's discretisation error, the model's predictions +- u, shown everywhere."""

from __future__ import annotations

import dataclasses
import math

import h5py
import numpy as np
import pytest

import asperity
from asperity import topo
from asperity.pipelines.config import load_preset
from asperity.pipelines.measured import NormalAreaCurve
from asperity.pipelines.report import load_table, summary_text
from asperity.pipelines.report.figure_output import read_figure_csv
from asperity.pipelines.report.uncertainty import plus_minus
from asperity.pipelines.stages.friction import friction_prediction
from asperity.pipelines.stages.statistical_model import (
    areas_at_loads,
    normal_contact_material,
    statistical_model_scan,
)
from asperity.pipelines.stages.surface import ScanResult, scan_resolutions
from asperity.statmodel.effective_resolution import roughness_at_resolution
from asperity.statmodel.shear_path import shear_curve_auto

LOADS = np.array([0.56, 1.06, 1.58, 2.08, 2.57, 3.12])


@pytest.fixture(scope="module")
def known_optimum():
    """A 512^2 paper-like map, its scan, and a reference A_r(F_z) made by the model itself at
    the known non-integer resolution 2.5 px (25 um)."""
    surface = topo.synthetic.paper_like(n=512, pixel_size=10e-6, seed=1)
    config = load_preset("default")
    material = normal_contact_material(config.material)
    a_n = config.loading.nominal_area
    scan = ScanResult.from_scan(scan_resolutions(surface, 6))
    truth = 2.5 * surface.dx
    reference = areas_at_loads(material, roughness_at_resolution(surface, truth), a_n, LOADS)[0]
    return surface, scan, material, a_n, truth, reference


def _located(known_optimum, noise):
    surface, scan, material, a_n, _, reference = known_optimum
    measured = NormalAreaCurve(LOADS, reference * noise)
    return statistical_model_scan(scan, material, a_n, LOADS, measured=measured, surface=surface)


@pytest.fixture(scope="module")
def exact(known_optimum):
    """The statistical-model stage against the noise-free reference."""
    return _located(known_optimum, 1.0)


def test_located_interval_covers_a_known_resolution(known_optimum, exact):
    """Noise-free and with 5 % lognormal noise on six loads (four seeds), the one-sigma
    interval holds the resolution the reference was made at (measured: 6 of 6 noisy seeds 0-5,
    7 of 8 for 0-7; a one-sigma interval should hold it in about two thirds)."""
    truth = known_optimum[4]
    low, high = exact.optimum_interval
    assert low <= truth <= high
    assert 20e-6 < exact.optimum_resolution < 30e-6  # between the strides 2 and 3
    assert exact.effective_stride in (2, 3)  # the integer scan is unchanged
    covered = 0
    for seed in range(4):
        noise = np.exp(0.05 * np.random.default_rng(seed).standard_normal(LOADS.size))
        low, high = _located(known_optimum, noise).optimum_interval
        covered += bool(low <= truth <= high)
    assert covered >= 3


def test_profile_interval_alone_is_too_narrow(known_optimum, exact):
    """The reason for the widening: the residuals over loads alone give a zero-width interval
    that misses the known resolution (the misfit between strides is jagged)."""
    truth = known_optimum[4]
    low, high = exact.optimum_profile_interval
    assert not low <= truth <= high
    assert exact.optimum_sampling_half_width > 0.05


def test_predictions_at_the_known_resolution_lie_within_their_error_bars(known_optimum, exact):
    """The model's A_r and static friction at the known resolution lie within value +- u of
    the prediction propagated over the located interval."""
    surface, _, material, a_n, truth, _ = known_optimum
    res = exact
    shear_material = dataclasses.replace(load_preset("default").material)
    loads = LOADS[[0, 3, 5]]
    fr = friction_prediction(
        shear_material, res.roughness, a_n, loads, steps=61,
        roughness_interval=res.roughness_interval,
    )  # fmt: skip
    rough = roughness_at_resolution(surface, truth)
    true_area = areas_at_loads(material, rough, a_n, loads)[0]
    assert np.all(np.abs(true_area - fr.model_real_area) <= fr.model_real_area_uncertainty)
    for i, f in enumerate(loads):
        peak = shear_curve_auto(shear_material, rough, a_n, float(f), steps=61).static_friction
        assert abs(peak - fr.static_friction[i]) <= fr.static_friction_uncertainty[i]


def test_small_job_shows_every_prediction_with_its_error_bar(small_run):
    """Load rows (report.md, terminal) carry ± u for the BEM and model columns; the CSVs of
    the figures showing them carry finite uncertainty columns."""
    _, out, result = small_run
    header, rows = load_table(result)
    names = ("A_r/A_n BEM", "A_r/A_n BEM adh.", "A_r/A_n model", "static F_s (N)")
    names += ("mu_s = F_s/F_z", "sliding F_x (N)", "delta_T slide (\u00b5m)")
    columns = [header.index(name) for name in names]
    for row in rows:
        assert all("±" in row[j] for j in columns), row
    report = (out / "report.md").read_text(encoding="utf-8")
    assert rows[0][4] in report and "±" in summary_text(result)
    friction = read_figure_csv(out / "friction_vs_load.csv")
    assert all(float(r["friction force uncertainty (N)"]) > 0 for r in friction)
    fig12 = read_figure_csv(out / "fig12_resolution.csv")
    bars = [r for r in fig12 if r["panel"] == "d" and r["A_r/A_n uncertainty (1)"]]
    assert {"BEM, non-adhesive", "BEM, adhesive"} <= {r["series"] for r in bars}
    fig13 = read_figure_csv(out / "fig13_area_vs_force.csv")
    assert any(r["tangential load F_x uncertainty (N)"] for r in fig13)
    misfit = read_figure_csv(out / "fig12d_misfit.csv")
    assert any(r["series"] == "located optimum" for r in misfit)


UNCERTAINTY_FIELDS = {
    "bem_reference": ("contact_fraction_uncertainty", "check_extrapolated_fraction"),
    "statistical_model": ("optimum_interval", "interval_summit_radius", "optimum_real_area"),
    "friction": (
        "model_real_area_uncertainty",
        "static_friction_uncertainty",
        "sliding_friction_uncertainty",
        "sliding_displacement_uncertainty",
    ),
}


def test_uncertainties_round_trip_through_open_results(small_run):
    """Every stored uncertainty reopens equal, and its dataset states its unit."""
    _, out, result = small_run
    reopened = asperity.open_results(out)
    with h5py.File(out / "results.h5", "r") as h5:
        for group, names in UNCERTAINTY_FIELDS.items():
            for name in names:
                stored = getattr(getattr(reopened, group), name)
                np.testing.assert_array_equal(stored, getattr(getattr(result, group), name))
                assert h5[group][name].attrs["units"] in ("1", "m", "N", "m^2")
    assert (
        reopened.statistical_model.optimum_resolution == result.statistical_model.optimum_resolution
    )
    assert reopened.friction.uncertainty_message == result.friction.uncertainty_message


def test_bem_adhesion_range_part_adds_in_quadrature(small_run):
    """The hook for the adhesion-range sensitivity: a part given for the adhesive solves adds
    in quadrature to their discretisation part and leaves the non-adhesive ones alone."""
    bem = small_run[2].bem_reference
    part = 0.5 * bem.contact_fraction_adhesive
    with_range = dataclasses.replace(bem, contact_fraction_adhesion_range_uncertainty=part)
    discretisation = bem.contact_fraction_discretisation_uncertainty
    np.testing.assert_allclose(
        with_range.contact_fraction_uncertainty[-1], np.hypot(discretisation[-1], part)
    )
    np.testing.assert_allclose(with_range.contact_fraction_uncertainty[0], discretisation[0])


def test_bem_band_holds_the_extrapolated_band(small_run):
    """The grid used's A_r/A_n +- u holds the Richardson value f_0 +- u_GCI at the check load."""
    bem = small_run[2].bem_reference
    k = int(np.flatnonzero(bem.normal_load == bem.check_load)[0])
    for m, fraction in enumerate((bem.contact_fraction, bem.contact_fraction_adhesive)):
        f0 = bem.check_extrapolated_fraction[m]
        u0 = bem.check_extrapolation_uncertainty[m]
        u = bem.contact_fraction_uncertainty[m, k]
        assert fraction[k] - u <= f0 - u0 + 1e-15 and f0 + u0 <= fraction[k] + u + 1e-15


def test_plus_minus_states_unknown_and_lower_bound_uncertainties():
    assert plus_minus(0.2856, 0.00117) == "0.2856 ± 0.0012"
    assert plus_minus(24.05e-6, 0.14e-6, 1e6) == "24.05 ± 0.14"
    assert plus_minus(1.0, math.nan) == "1 ± ?"
    # u to two significant digits, the value to the same place (report.numbers)
    assert plus_minus(1.0, 0.1, lower_bound=True) == "1.00 ± >0.10"


@pytest.mark.slow
def test_default_job_load_rows_carry_uncertainties(tmp_path):
    """The default job (about a minute): every model and BEM cell of the load table is
    value +- u, and the friction stage uses the located resolution, above 10 um and at most
    20 um (the 20 um stride itself since the located point may not fit worse than a stride)."""
    from asperity.pipelines.job import run_job

    result = run_job(load_preset("default"), tmp_path)
    header, rows = load_table(result)
    assert len(rows) == 6
    with_u = {
        "A_r/A_n BEM",
        "A_r/A_n BEM adh.",
        "A_r/A_n model",
        "static F_s (N)",
        "mu_s = F_s/F_z",
        "sliding F_x (N)",
        "delta_T slide (µm)",
    }
    carried = [i for i, h in enumerate(header) if h in with_u]
    assert len(carried) == len(with_u), header
    for row in rows:
        assert all("±" in row[i] for i in carried), (row, header)
    assert 10e-6 < result.statistical_model.optimum_resolution <= 20e-6
    assert result.statistical_model.optimum_misfit < result.statistical_model.misfit[0]
