"""statmodel.maugis_rough: time and agreement of the current implementation against a reference.

The reference is ``statmodel/maugis_rough.py`` as it stood at a git revision (default 971fad9,
the 80-step bisection inverse), loaded from ``git show`` into its own module, so both run in the
same process on the same inputs. Cases: the default job's statistical-model calls (six loads at
three effective resolutions, h_0 = 12.5 um, lambda ~ 0.02), the transition and JKR side
(h_0 = 2 um and the lambda = 3 range), ``maugis_rough_state`` on a separation grid,
``maugis_discrete_contact`` over 200 evenly spaced summit heights (loads / 20) and
``MaugisAsperity.loading_state``.

For each case: calls, CPU seconds (process time, best of ``--repeat`` runs: the machine is
shared, and the code is single-threaded) for the reference and the current
code, the speed-up and the largest relative difference over every returned array (separation,
F_z, A_r, n_contact, n_attracted; F and a for the single asperity). SI units throughout.

Run::

    .venv/bin/python benchmarks/statmodel_maugis_speed.py [--rev 971fad9] [--repeat 3]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from asperity.statmodel import Roughness
from asperity.statmodel import maugis_rough as current

ROOT = Path(__file__).resolve().parents[1]
E_STAR, WORK, AREA, H0 = 2.133e6, 0.040, 700e-6, 1.251138753667512e-05
LOADS = np.array([0.56, 1.06, 1.58, 2.08, 2.57, 3.12])
#: (eta 1/m^2, R m, sigma_s m) of three of the default job's effective resolutions.
STATS = [
    (99.98e6, 4.4384313576647234e-05, 4.902268055282954e-05),
    (48.97e6, 6.67533329939382e-05, 4.856959098136071e-05),
    (30537726.94132692, 9.097200120848467e-05, 4.76883013164824e-05),
]


def reference_module(rev: str):
    """statmodel/maugis_rough.py at git revision ``rev`` as a module of its own."""
    source = subprocess.run(
        ["git", "show", f"{rev}:statmodel/maugis_rough.py"],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    spec = importlib.util.spec_from_loader("_maugis_rough_reference", loader=None)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    exec(compile(source, f"{rev}:statmodel/maugis_rough.py", "exec"), module.__dict__)
    return module


def jkr_range(radius: float) -> float:
    """h_0 (m) giving lambda = 3 at the summit radius (the folding Maugis curve)."""
    return WORK / (1.5 * (math.pi * WORK * (4 * E_STAR / 3) ** 2 / radius) ** (1 / 3))


def cases(mod):
    """name -> (calls, callable returning a list of arrays) for module ``mod``."""
    rough = [Roughness(*s) for s in STATS]
    r0 = rough[0]
    heights = np.linspace(-2.0, 2.0, 200) * r0.summit_height_rms
    seps = np.linspace(-1.0, 3.0, 21) * r0.summit_height_rms

    def contact(h0, rs):
        def run():
            out = []
            for r in rs:
                res = mod.maugis_rough_contact(r, E_STAR, WORK, h0, AREA, LOADS)
                out += [res.separation, res.normal_force, res.real_area, res.n_contact]
                out += [res.n_attracted]
            return out

        return len(rs), run

    def state():
        return list(mod.maugis_rough_state(r0, E_STAR, WORK, H0, AREA, seps))

    def discrete():
        loads = LOADS / 20.0
        res = mod.maugis_discrete_contact(heights, r0.summit_radius, E_STAR, WORK, H0, loads)
        return [res.separation, res.normal_force, res.real_area, res.n_contact, res.n_attracted]

    def single():
        asp = mod.MaugisAsperity(r0.summit_radius, E_STAR, WORK, H0)
        delta = np.linspace(-1.2, 40.0, 5000) * H0
        return list(asp.loading_state(delta))

    return {
        "default job (3 resolutions x 6 loads)": contact(H0, rough),
        "transition h0 = 2 um": contact(2e-6, rough[:1]),
        "JKR side lambda = 3": contact(jkr_range(r0.summit_radius), rough[:1]),
        "rough_state, 21 separations": (1, state),
        "discrete, 200 summits x 6 loads": (1, discrete),
        "loading_state, 5000 approaches": (1, single),
    }


def best_time(fn, repeat: int):
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def max_rel_diff(new: list, old: list) -> float:
    worst = 0.0
    for a, b in zip(new, old, strict=True):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        scale = np.maximum(np.abs(b), 1e-300)
        both = np.isfinite(a) & np.isfinite(b)
        if not np.array_equal(np.isfinite(a), np.isfinite(b)):
            return math.inf
        if np.any(both):
            worst = max(worst, float(np.max(np.abs(a[both] - b[both]) / scale[both])))
    return worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rev", default="971fad9", help="git revision of the reference")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per case (best kept)")
    args = parser.parse_args()
    ref = cases(reference_module(args.rev))
    new = cases(current)
    print(f"reference: statmodel/maugis_rough.py at {args.rev}; CPU s, best of {args.repeat}")
    head = (
        f"{'case':38s} {'calls':>5s} {'ref s':>8s} {'new s':>8s} {'speed-up':>8s} "
        + "max rel".rjust(9)
    )
    print(head)
    print("-" * len(head))
    total_ref = total_new = 0.0
    for name, (calls, run_new) in new.items():
        t_ref, out_ref = best_time(ref[name][1], args.repeat)
        t_new, out_new = best_time(run_new, args.repeat)
        total_ref, total_new = total_ref + t_ref, total_new + t_new
        diff = max_rel_diff(out_new, out_ref)
        print(f"{name:38s} {calls:5d} {t_ref:8.3f} {t_new:8.3f} {t_ref / t_new:8.1f} {diff:9.1e}")
    print(f"{'all':38s} {'':5s} {total_ref:8.3f} {total_new:8.3f} {total_ref / total_new:8.1f}")


if __name__ == "__main__":
    main()
