"""OpenMP's wait policy, active against passive, on the solves a user runs.

``import asperity`` sets ``OMP_WAIT_POLICY=PASSIVE`` unless the user chose a policy
(:data:`asperity.OMP_WAIT_POLICY`): FFTW (pyFFTW's bundled OpenMP runtime) and numba's parallel
multipliers (numba's OpenMP layer) alternate within every iteration, and with active waiting
the idle pool spins on the cores the other needs. This script measures what that choice is
worth: each case runs in a fresh process per policy (the runtimes read the variable when they
load), alternated ``--repeats`` times; medians printed, with the ratio active / passive and
whether the two policies gave the same answer (iterations and contact fraction).

Cases: ``jkr64`` a free-boundary JKR approach-retract cycle on 64^2 (24 solves, tol 1e-8,
as ``tests/bem/test_bem_omp_wait_policy.py``); ``periodic1024`` the paper-like surface
(``topo.synthetic.paper_like``, 2 um pixels, E* = 2.133 MPa, 2.08 N scaled to the map, tol
1e-6) on 1024^2, periodic, non-adhesive; ``maugis256`` the same surface on 256^2 with
Maugis-Dugdale adhesion (w = 0.05 J/m^2, range 4 pixels).

Run: ``.venv/bin/python benchmarks/omp_wait_policy.py --repeats 3``
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CASES = ("jkr64", "periodic1024", "maugis256")

WORKER = r"""
import json, sys, time
import numpy as np
from asperity import bem
from asperity.topo.synthetic import paper_like

case = sys.argv[1]

def jkr(n):
    dx = 0.2 / n
    x = (np.arange(n) - n / 2 + 0.5) * dx
    h = -(x[:, None] ** 2 + x[None, :] ** 2) / 2.0
    runs = bem.approach_retract(h, dx, dx, 1.0, 1e-4, np.linspace(0.0, -1.5e-3, 8),
                                np.linspace(-1.5e-3, 1.0e-3, 16), periodic=False,
                                options=bem.SolverOptions(tol=1e-8))
    return sum(r.nit for r in runs[0] + runs[1]), runs[0][-1].contact_fraction

def rough(n, **kw):
    surface = paper_like(n=n, pixel_size=2e-6, seed=0)
    load = 2.08 * (n * 2e-6) ** 2 / (10e-3) ** 2
    res = bem.solve_contact(surface.heights, 2e-6, 2e-6, 2.133e6, normal_force=load,
                            options=bem.SolverOptions(tol=1e-6), **kw)
    return res.nit, res.contact_fraction

def run(case):
    if case == "jkr64":
        return jkr(64)
    if case == "periodic1024":
        return rough(1024)
    return rough(256, adhesion="maugis", work_of_adhesion=0.05, adhesion_range=8e-6)

run(case) if case != "periodic1024" else None  # compiled kernels and plans out of the clock
t0, c0 = time.perf_counter(), time.process_time()
nit, fraction = run(case)
print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                  "nit": nit, "fraction": fraction}))
"""


def measure(case: str, policy: str) -> dict:
    """One fresh process with ``OMP_WAIT_POLICY=policy``: seconds, iterations, fraction."""
    env = dict(os.environ, OMP_WAIT_POLICY=policy)
    done = subprocess.run(
        [sys.executable, "-c", WORKER, case], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    args = parser.parse_args()
    print(
        f"{'case':<14}{'active s':>10}{'passive s':>11}{'ratio':>8}"
        f"{'active CPU':>12}{'passive CPU':>13}{'iterations':>12}  same answer"
    )
    for case in args.cases:
        rows: dict[str, list[dict]] = {"ACTIVE": [], "PASSIVE": []}
        for _ in range(args.repeats):
            for policy in rows:
                rows[policy].append(measure(case, policy))
        wall = {p: statistics.median(r["wall"] for r in rows[p]) for p in rows}
        cpu = {p: statistics.median(r["cpu"] for r in rows[p]) for p in rows}
        answers = {(r["nit"], r["fraction"]) for p in rows for r in rows[p]}
        nit = rows["PASSIVE"][0]["nit"]
        print(
            f"{case:<14}{wall['ACTIVE']:>10.2f}{wall['PASSIVE']:>11.2f}"
            f"{wall['ACTIVE'] / wall['PASSIVE']:>7.1f}x{cpu['ACTIVE']:>12.2f}"
            f"{cpu['PASSIVE']:>13.2f}{nit:>12}  {'yes' if len(answers) == 1 else 'NO'}"
        )
    print(f"load average at the end: {os.getloadavg()[0]:.1f} ({os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
