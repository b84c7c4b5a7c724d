"""Warm-started load sweeps vs independent cold solves.

One periodic self-affine surface (H = 0.8, wavelengths down to 8 px, rms slope 1, E* = 1,
pixel 1), 10 loads from a mean pressure of 0.02 (about 4 % contact) in geometric steps of
2.5 % and 20 %, tol 1e-8. Three ways to run the same loads:

* cold: independent ``solve_contact`` calls (no ``initial``);
* previous: each solve started from the previous solution (``initial=previous``; what
  ``load_sweep`` did before the secant start);
* sweep: ``bem.load_sweep`` (secant prediction from the two previous solutions).

Prints, per grid and step: total iterations and seconds of each, the ratio sweep / cold, and
the largest differences from the cold solves in contact elements and in pressure (relative to
the peak pressure). Run: ``flock /tmp/asperity-bench.lock python benchmarks/bem_sweep.py [N ...]``
(default 256 512).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bem_surfaces import self_affine_periodic  # noqa: E402

from asperity.bem import SolverOptions, load_sweep, solve_contact  # noqa: E402

TOL = 1e-8
N_LOADS = 10
MEAN_PRESSURE = 0.02


def _previous_only(h, forces):
    results = []
    for f in forces:
        start = results[-1] if results else None
        results.append(
            solve_contact(
                h, 1.0, 1.0, 1.0, normal_force=f, initial=start, options=SolverOptions(tol=TOL)
            )
        )
    return results


def _cold(h, forces):
    return [
        solve_contact(h, 1.0, 1.0, 1.0, normal_force=f, options=SolverOptions(tol=TOL))
        for f in forces
    ]


def _sweep(h, forces):
    return load_sweep(h, 1.0, 1.0, 1.0, forces, options=SolverOptions(tol=TOL))


def _timed(fn, *args):
    t0 = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - t0


def main(sizes: list[int]) -> None:
    print(
        f"{'N':>5} {'step':>5} {'contact %':>11} | {'cold it':>7} {'s':>6} | "
        f"{'prev it':>7} {'s':>6} | {'sweep it':>8} {'s':>6} | {'it ratio':>8} {'s ratio':>7} | "
        f"{'d elems':>7} {'max dp/pmax':>11}"
    )
    for n in sizes:
        h = self_affine_periodic(n, seed=1)
        f0 = MEAN_PRESSURE * n * n
        solve_contact(
            h, 1.0, 1.0, 1.0, normal_force=f0, options=SolverOptions(tol=TOL)
        )  # compile, plan the FFTs
        for step in (0.025, 0.2):
            forces = [f0 * (1 + step) ** k for k in range(N_LOADS)]
            cold, t_cold = _timed(_cold, h, forces)
            prev, t_prev = _timed(_previous_only, h, forces)
            sweep, t_sweep = _timed(_sweep, h, forces)
            assert all(r.converged for r in cold + prev + sweep)
            it_cold = sum(r.nit for r in cold)
            it_prev = sum(r.nit for r in prev)
            it_sweep = sum(r.nit for r in sweep)
            d_elems = max(
                int(np.count_nonzero(a.contact_mask != b.contact_mask))
                for a, b in zip(cold, sweep, strict=True)
            )
            dp = max(
                float(np.abs(a.pressure - b.pressure).max() / a.pressure.max())
                for a, b in zip(cold, sweep, strict=True)
            )
            frac = f"{100 * cold[0].contact_fraction:.1f}-{100 * cold[-1].contact_fraction:.1f}"
            print(
                f"{n:>5} {100 * step:>4.1f}% {frac:>11} | {it_cold:>7} {t_cold:>6.2f} | "
                f"{it_prev:>7} {t_prev:>6.2f} | {it_sweep:>8} {t_sweep:>6.2f} | "
                f"{it_sweep / it_cold:>8.2f} {t_sweep / t_cold:>7.2f} | {d_elems:>7} {dp:>11.2g}"
            )


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [256, 512])
