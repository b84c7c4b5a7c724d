"""The sampling half-width of the effective resolution on a densely scanned, jagged misfit.

On a fine scan (the paper's two-step job: 2 um strides near 234 um) the summit statistics are
redrawn from stride to stride, so the misfit m = |mean ln(A_model/A_reference)| is a straight
line in ln resolution through zero plus noise of its own at every sampled resolution. The
refinement's points all lie within one stride of the least sample and hold one draw of that
noise: a parabola through them alone has no positive curvature and the interval opened on both
sides (2..400 um). The fit over every sample within a factor 1.28 of the optimum sees the
noise and closes the interval around the known zero of the line.

The cases: slope 0.8 per unit ln resolution (the two-step job's misfit falls from 0.26 at
162 um to 0 near 235 um), noise 0.05 (its stride-to-stride scatter), zero at 260 um, strides
of 2 um over 150..400 um, six loads.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.statmodel import effective_resolution as optimum
from asperity.statmodel.effective_resolution import locate_least_misfit

TRUTH = 260e-6  # m
SLOPE, NOISE = 0.8, 0.05
STRIDES = 2e-6 * np.arange(75, 201)  # m
SEEDS = range(20)


def _interval(seed: int) -> tuple[np.ndarray, bool, float]:
    """(interval (m), open on a side, half-width in ln resolution) on one noisy misfit."""
    rng = np.random.default_rng(seed)
    drawn: dict[int, float] = {}

    def misfit_at(resolution: float) -> float:
        key = round(resolution * 1e12)  # one draw per resolution, as a map's statistics
        if key not in drawn:
            drawn[key] = abs(SLOPE * math.log(resolution / TRUTH) + NOISE * rng.standard_normal())
        return drawn[key]

    located = locate_least_misfit(STRIDES, [misfit_at(r) for r in STRIDES], 6, misfit_at=misfit_at)
    half_width = optimum.sampling_half_width(located)
    ends, open_finer, open_coarser = optimum.widen_interval(
        located, half_width, (float(STRIDES[0]), float(STRIDES[-1]))
    )
    return ends, open_finer or open_coarser, half_width


def test_window_closes_the_interval_around_the_known_zero():
    """Closed in every case; holds the truth at least as often as a one-sigma interval
    should (14 of 20: 68 %; measured 20 of 20, 40 of 40 on seeds 0-39: the rule is
    conservative, its half-width about twice noise / slope = 0.06); never wider than the
    factor the noise can explain (ln half-width < 0.25)."""
    results = [_interval(seed) for seed in SEEDS]
    assert not any(is_open for _, is_open, _ in results)
    covered = sum(ends[0] <= TRUTH <= ends[1] for ends, _, _ in results)
    assert covered >= 14
    assert max(h for _, _, h in results) < 0.25


def test_the_refinement_bracket_alone_leaves_it_open(monkeypatch):
    """The reason for the window: the ten samples nearest the optimum (the refinement's
    bracket) leave the interval open, or closed and missing the truth (measured: 19 of 20
    cases, 5 of them open; 38 of 40 on seeds 0-39)."""
    monkeypatch.setattr(optimum, "SAMPLING_WINDOW", 0.0)
    results = [_interval(seed) for seed in SEEDS]
    failed = sum(is_open or not ends[0] <= TRUTH <= ends[1] for ends, is_open, _ in results)
    assert failed >= 10
