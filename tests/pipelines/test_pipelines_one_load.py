"""A job with one normal load: the effective resolution's interval cannot be sized (its misfit
has no scatter over loads), so the predictions are written "± ?" and the verdict says so.
Before 0.4.1 the friction stage stopped on a NaN asperity density (exit 2)."""

from __future__ import annotations

import numpy as np

from asperity.pipelines.job import run_job


def test_one_load_runs_and_the_verdict_names_the_unknown_uncertainty(small, tmp_path):
    result = run_job(small(tmp_path, normal_loads=[2.0]), tmp_path)
    ends = result.statistical_model.roughness_interval
    assert ends is not None and all(end is None for end in ends)
    friction = result.friction
    assert np.isfinite(friction.static_friction).all()
    assert np.isnan(friction.static_friction_uncertainty).all()
    verdict = result.verdict
    codes = dict(zip(verdict.codes, verdict.severities, strict=True))
    assert codes.get("prediction_uncertainty_unknown") == "warning"
