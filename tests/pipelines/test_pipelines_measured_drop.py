"""The measured area drop A_r(peak)/A_r(0) comes from a fit of the stick branch with its
uncertainty, not from two single noisy points (issue 37, item 3)."""

from __future__ import annotations

import numpy as np
import pytest

from asperity.pipelines.report.static_peak import stick_branch_drop

FORCE = np.linspace(0.0, 1.0, 40)  # N, the stick branch up to the peak
TRUE_DROP = 0.94  # A_r = A_0 (1 - 0.06 (F_x / F_peak)^2): Sahli et al.'s quadratic decrease


def _noisy(seed: int, noise: float = 0.02) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return 1e-6 * (1 - 0.06 * FORCE**2) * (1 + noise * rng.standard_normal(FORCE.size))


def test_an_exact_quadratic_gives_its_drop_with_no_uncertainty():
    drop, u = stick_branch_drop(FORCE, 1e-6 * (1 - 0.06 * FORCE**2))
    assert drop == pytest.approx(TRUE_DROP, rel=1e-10) and u == pytest.approx(0.0, abs=1e-10)


def test_the_fit_scatters_less_than_the_two_point_ratio_and_covers_at_one_sigma():
    """200 curves at 2 % noise: the two-point ratio spreads over about 0.88 .. 1.03 (the
    issue's 0.89 .. 1.01); the fit's scatter is less than half of it, and its stated one-sigma
    interval covers the true drop in 60-76 % of the curves (68 % expected)."""
    fits = [stick_branch_drop(FORCE, _noisy(seed)) for seed in range(200)]
    drops = np.array([d for d, _ in fits])
    covered = np.mean([abs(d - TRUE_DROP) <= u for d, u in fits])
    two_point = np.array([a[-1] / a[0] for a in (_noisy(seed) for seed in range(200))])
    assert np.std(drops) < 0.5 * np.std(two_point)
    assert 0.60 <= covered <= 0.76
    assert abs(np.mean(drops) - TRUE_DROP) < 3 * np.std(drops) / np.sqrt(drops.size)


def test_too_few_points_give_the_ratio_with_no_uncertainty():
    drop, u = stick_branch_drop(np.array([0.0, 0.5]), np.array([2.0, 1.8]))
    assert drop == pytest.approx(0.9) and np.isnan(u)
    drop, u = stick_branch_drop(np.array([0.0, 0.5]), np.array([0.0, 1.8]))
    assert np.isnan(drop) and np.isnan(u)
