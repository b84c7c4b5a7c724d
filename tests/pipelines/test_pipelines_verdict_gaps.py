"""Verdict gaps closed: no finite sliding displacement, a periodic BEM solve across a seam, and
the direction the data point to when the least misfit is at an end of the scan; one wording of
the verdict in the terminal, report.md, report.html and on the figures."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from asperity.bem.reference.grid_refinement import EDGE_MISMATCH_LIMIT, edge_mismatch
from asperity.pipelines.stages import verdict as v


def _friction(displacement, sliding=(0.1, 0.2, 0.3), converged=(True, True, True)):
    return SimpleNamespace(
        normal_load=np.array([1.0, 2.0, 3.0]),
        converged=np.array(converged),
        sliding_friction=np.array(sliding, dtype=float),
        sliding_displacement=np.array(displacement, dtype=float),
    )


def test_nan_sliding_displacement_is_no_full_sliding():
    """plu-1's case: finite sliding friction but a NaN delta_T at 3 of 6 loads; mi-1's: inf."""
    assert v.check_sliding_displacement(_friction([20e-6, 21e-6, 22e-6])) == []
    (reason,) = v.check_sliding_displacement(_friction([20e-6, math.nan, math.inf]))
    assert (reason.code, reason.severity) == ("no_full_sliding", "invalid")
    assert "F_z = 2, 3 N" in reason.text and "2 of 3 loads" in reason.text
    # a curve already reported by check_sliding (unconverged, no sliding friction) is not
    # reported twice
    twice = _friction([math.nan] * 3, sliding=(0.1, math.nan, 0.3), converged=(True, True, False))
    (once,) = v.check_sliding_displacement(twice)
    assert "F_z = 1 N" in once.text
    assert "F_z = 2, 3 N" in v.check_sliding(twice)[0].text


def test_periodic_seam_beyond_the_limit_is_a_warning():
    """x3p-2's 1.50 x the rms height (limit 0.5) under a periodic solve: a warning with its
    number; a free boundary, or a seam within the limit, raises none."""
    bem = SimpleNamespace(boundary="periodic", edge_mismatch=1.50)
    (reason,) = v.check_edge_mismatch(bem)
    assert (reason.code, reason.severity) == ("bem_edge_mismatch", "warning")
    assert "1.50 x the rms height (> 0.5)" in reason.text
    assert v.check_edge_mismatch(SimpleNamespace(boundary="free", edge_mismatch=1.5)) == []
    assert v.check_edge_mismatch(SimpleNamespace(boundary="periodic", edge_mismatch=0.4)) == []
    assert v.check_edge_mismatch(None) == []


def test_edge_mismatch_of_uncorrelated_edges_crosses_the_limit():
    """The stored number the reason reads: about 0 for a periodic map, far beyond the limit
    for a ramp (its seam is a cliff of the full height range)."""
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    periodic = np.sin(x)[:, None] * np.cos(x)[None, :]
    assert edge_mismatch(periodic) < 0.1 < EDGE_MISMATCH_LIMIT
    ramp = np.add.outer(np.arange(64.0), np.zeros(64))
    assert edge_mismatch(ramp) > EDGE_MISMATCH_LIMIT


def test_mean_log_ratio_closed_form():
    model = np.array([[2.0, 2.0], [0.5, 1.0], [np.nan, 0.0]])
    ratio = v.mean_log_ratio(model, np.array([1.0, 1.0]))
    assert ratio[0] == np.log(2.0)
    assert ratio[1] == 0.5 * np.log(0.5)
    assert np.isnan(ratio[2])  # no load where both are positive


def test_edge_direction_between_finer_and_coarser():
    """The default job: least misfit at stride 1, the mean log ratio changes sign between
    strides 1 and 2, so the optimum lies between them, not at a finer resolution."""
    misfit = np.array([0.09, 0.3, 0.6, 0.9])
    assert v.edge_direction(np.array([-0.05, 0.3, 0.6, 0.9]), misfit, 0) == "between"
    assert v.edge_direction(np.array([0.05, 0.3, 0.6, 0.9]), misfit, 0) == "finer"
    rising = np.array([0.9, 0.6, 0.3, 0.1])
    assert v.edge_direction(-rising, rising, 3) == "coarser"
    assert v.edge_direction(np.array([0.9, 0.6, -0.3, 0.1]), rising, 3) == "between"
    assert v.edge_direction(np.array([0.5, -0.1, 0.4, 0.9]), misfit[[1, 0, 2, 3]], 1) == ""


def test_resolution_at_edge_message_follows_the_direction():
    curve = np.array([0.09, 0.3, 0.6])
    (between,) = v.check_resolution(curve, 0, "bem", "between")
    assert between.severity == "warning"
    assert "between strides 1 and 2" in between.text and "finer measurement" not in between.text
    (finer,) = v.check_resolution(curve, 0, "bem", "finer")
    assert "finer measurement may fit better" in finer.text
    (coarser,) = v.check_resolution(curve[::-1], 2, "bem", "coarser")
    assert "max_stride" in coarser.text
    (bad,) = [r for r in v.check_resolution(curve + 0.3, 0, "bem", "between") if "edge" in r.code]
    assert bad.severity == "invalid" and "no resolution of the scan fits" in bad.text


def test_direction_read_from_stored_fields_first():
    """A statistical-model result that stores the direction of its least misfit ("" when it
    lies between strides) is read as such; otherwise the sign of the stored areas decides."""
    stored = SimpleNamespace(resolution_direction="")
    assert v.resolution_direction(stored, None) == "between"
    areas = np.array([[0.9, 1.8], [1.2, 2.4], [2.0, 4.0]])  # ln ratio -0.1, +0.18, +0.69
    res = SimpleNamespace(
        basis="bem",
        real_area=areas,
        nominal_area=1.0,
        misfit=np.abs(np.log(areas / [1.0, 2.0])).mean(axis=1),
        index=0,
        model_real_area_at_measured=None,
    )
    bem = SimpleNamespace(reference_fraction=lambda: np.array([1.0, 2.0]))
    assert v.resolution_direction(res, bem) == "between"
    assert v.resolution_direction(res, None) == ""


def test_one_wording_everywhere():
    bad = v.Verdict.from_reasons([v.Reason("tabor", "invalid", "mu = 2.6 < 5")])
    warn = v.Verdict.from_reasons([v.Reason("bem_grid", "warning", "grid")])
    for verdict, words in ((bad, "INVALID"), (warn, "valid, with warnings")):
        assert v.verdict_wording(verdict) == f"Verdict: {words}"
        assert v.verdict_lines(verdict)[0] == f"VERDICT: {words}"
        assert v.verdict_markdown(verdict)[0].startswith(f"**Verdict: {words}.**")
    assert v.verdict_lines(bad)[1] == "  - INVALID (tabor): mu = 2.6 < 5"
    assert v.verdict_markdown(warn)[2] == "- **warning** (`bem_grid`): grid"
    assert v.verdict_wording(v.Verdict.from_reasons([])) == "Verdict: valid"
