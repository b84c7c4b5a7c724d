"""OpenMP's wait policy: FFTW's and numba's thread pools must not spin on each other's cores.

One solve alternates FFTW transforms (pyFFTW's bundled OpenMP runtime) with numba's parallel
multipliers (numba's OpenMP layer): two runtimes, two pools. With OpenMP's default (active)
wait policy the idle pool spins on the cores the other needs and every hand-off waits for a
scheduler slice; ``import asperity`` therefore makes the policy passive unless the user chose
one (:data:`asperity.OMP_WAIT_POLICY`). Measured on a 2-core machine under load, a 64^2
free-boundary JKR cycle (48 solves, 540 iterations): 37 s active, 0.3-0.6 s passive
(``benchmarks/omp_wait_policy.py``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np

from asperity.bem import SolverOptions, approach_retract

R, E, W = 1.0, 1.0, 1.0e-4  # m, Pa, J/m^2 (a JKR sphere: contact radius ~ 0.04 m at zero load)


def _policy_seen_by_a_fresh_process(preset: str | None) -> str:
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if preset is not None:
        env["OMP_WAIT_POLICY"] = preset
    code = "import os, asperity.bem; print(os.environ['OMP_WAIT_POLICY'])"
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_importing_asperity_makes_threads_passive_unless_the_user_chose():
    assert _policy_seen_by_a_fresh_process(None) == "PASSIVE"
    assert _policy_seen_by_a_fresh_process("ACTIVE") == "ACTIVE"


def _jkr_cycle(n: int) -> tuple[float, int]:
    """Seconds and iterations of a free-boundary JKR approach-retract cycle on n x n."""
    box = 0.2
    dx = box / n
    x = (np.arange(n) - n / 2 + 0.5) * dx
    heights = -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * R)
    d_in = np.linspace(0.0, -1.5e-3, 8)
    d_out = np.linspace(-1.5e-3, 1.0e-3, 16)
    t0 = time.perf_counter()
    loading, unloading = approach_retract(
        heights, dx, dx, E, W, d_in, d_out, periodic=False, options=SolverOptions(tol=1e-8)
    )
    seconds = time.perf_counter() - t0
    assert all(r.converged for r in loading + unloading)
    return seconds, sum(r.nit for r in loading + unloading)


def test_a_small_adhesive_solve_costs_well_under_a_millisecond_per_iteration_step():
    """Each iteration at 64^2 (a 128^2 padded transform pair and a few multipliers) costs
    0.7 ms with passive threads and 95 ms when the pools spin on each other (2-core machine,
    load 4): the guard sits at 5 ms, 7x above the first."""
    _jkr_cycle(16)  # compiled kernels and FFT plans out of the measurement
    seconds, iterations = _jkr_cycle(64)
    assert iterations > 50
    assert seconds / iterations < 5e-3, f"{seconds:.2f} s for {iterations} iterations"
