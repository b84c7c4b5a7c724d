"""statmodel.maugis_rough: time and agreement of the current implementation against a reference.

The reference is ``statmodel/maugis_rough.py`` as it stood at a git revision (default 1467064,
the last one before the batched, skipping separation solve: every separation solved on its own
and every march step of 0.02 sigma_s evaluated, the direct solve), loaded from ``git show`` into
its own module, so both run in the same process on the same inputs.

1. Per stride on the sticky measured maps (``--maps``, default plu-1.plu and opd-1.opd from
   tests/data; default preparation, resolution scan to stride 26, PDMS: E* = 2.133 MPa,
   w = 0.040 J/m^2, A_n = 700 mm^2, the six loads of Sahli et al., h_0 = the BEM rule's start
   ``bem.resolving_range(w, E*, pixel)`` times ``--h0-factor``): the stage's call under the
   BEM's law (``bem_law_areas_at_loads`` of pipelines/stages/statistical_model.py, which calls
   ``maugis_rough_contact``), CPU seconds before (the reference, on ``--before-strides`` only:
   it takes 3-30 s a stride) and after, the JKR model's call (``areas_at_loads``) beside it, and
   the largest relative difference from the reference of A_r, F_z and d over the loads.
2. ``--cases``: the earlier cases (the default job's statistical-model calls at three effective
   resolutions, h_0 = 12.5 um, lambda ~ 0.02; the transition and JKR side; ``maugis_rough_state``
   on a separation grid; ``maugis_discrete_contact`` over 200 summits; ``loading_state``).

CPU seconds are process time, best of ``--repeat`` runs (the machine is shared, the code is
single-threaded). SI units throughout.

Run::

    .venv/bin/python benchmarks/statmodel_maugis_speed.py [--rev 1467064] [--repeat 3]
        [--maps plu-1.plu,opd-1.opd] [--before-strides 1,4,11] [--h0-factor 1] [--cases]
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

from asperity import topo
from asperity.bem import resolving_range
from asperity.pipelines.stages import statistical_model as stage
from asperity.pipelines.stages import surface as surface_stage
from asperity.statmodel import Material, Roughness
from asperity.statmodel import maugis_rough as current

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
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


def scan_statistics(name: str) -> tuple[list[tuple[int, Roughness]], float]:
    """[(stride, Roughness)] of the map's resolution scan (strides 1..26, the job's default
    preparation) and its pixel size (m)."""
    raw = topo.read_surface(DATA / name)
    surface = topo.prepare_surface(raw, topo.PreparationOptions(missing="interpolate")).surface
    scan = surface_stage.scan_resolutions(surface, 26)
    rows = []
    for i, stride in enumerate(scan.stride):
        values = (scan.asperity_density[i], scan.summit_radius[i], scan.summit_height_rms[i])
        if all(np.isfinite(v) and v > 0 for v in values):
            rows.append((int(stride), Roughness(*(float(v) for v in values))))
    return rows, min(surface.dx, surface.dy)


def rel(new: np.ndarray, old: np.ndarray) -> float:
    """Largest |new / old - 1| (inf where only one is finite)."""
    return max_rel_diff([new], [old])


def stride_table(name: str, ref, args) -> tuple[float, float, float]:
    """Print the per-stride rows of one map; returns the totals (after, JKR, before) in s."""
    rows, pixel = scan_statistics(name)
    h0 = args.h0_factor * resolving_range(WORK, E_STAR, pixel)
    material = Material(E_STAR, WORK, 0.03, 0.13e6)
    before_at = {int(s) for s in args.before_strides.split(",") if s}
    print(f"\n{name}: h_0 = {h0:.4g} m ({args.h0_factor:g} x the rule's start at {pixel:.3g} m)")
    head = (
        f"{'stride':>6s} {'lambda':>7s} {'before s':>9s} {'after s':>8s} {'JKR s':>7s} "
        f"{'speed-up':>8s} {'rel A_r':>8s} {'rel d':>8s} {'F_z res':>17s} {'evals':>11s}"
    )
    print(head)
    print("-" * len(head))
    total = [0.0, 0.0, 0.0]
    for stride, rough in rows:
        t_new, (area, message) = best_time(
            lambda r=rough: stage.bem_law_areas_at_loads(material, r, AREA, LOADS, h0),
            args.repeat,
        )
        t_jkr, _ = best_time(
            lambda r=rough: stage.areas_at_loads(material, r, AREA, LOADS), args.repeat
        )
        new = current.maugis_rough_contact(rough, E_STAR, WORK, h0, AREA, LOADS)
        total[0], total[1] = total[0] + t_new, total[1] + t_jkr
        residual = f"{rel(new.normal_force, LOADS):7.1e}"
        cells = ["-"] * 4 + [residual]
        evals = f"{int(np.mean(new.nit))}"
        if stride in before_at:
            t_old, old = best_time(
                lambda r=rough: ref.maugis_rough_contact(r, E_STAR, WORK, h0, AREA, LOADS), 1
            )
            total[2] += t_old
            cells = [
                f"{t_old:9.2f}",
                f"{t_old / t_new:8.0f}",
                f"{rel(new.real_area, old.real_area):8.1e}",
                f"{rel(new.separation, old.separation):8.1e}",
                f"{rel(old.normal_force, LOADS):7.1e} -> {residual}",
            ]
            evals = f"{int(np.mean(old.nit))}->{evals}"
        print(
            f"{stride:6d} {new.maugis_parameter:7.3g} {cells[0]:>9s} {t_new:8.3f} {t_jkr:7.3f} "
            f"{cells[1]:>8s} {cells[2]:>8s} {cells[3]:>8s} {cells[4]:>17s} {evals:>11s}"
            + (f"  ({message})" if message else "")
        )
    print(
        f"{'all':>6s} {'':7s} {total[2]:9.2f} {total[0]:8.3f} {total[1]:7.3f}"
        f"   (before: on strides {sorted(before_at)} only)"
    )
    return tuple(total)


def case_table(args) -> None:
    """The earlier cases, reference against current."""
    ref = cases(reference_module(args.rev))
    new = cases(current)
    print(
        f"\ncases: reference statmodel/maugis_rough.py at {args.rev}; CPU s, best of {args.repeat}"
    )
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rev", default="1467064", help="git revision of the reference")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per case (best kept)")
    parser.add_argument("--maps", default="plu-1.plu,opd-1.opd", help="files in tests/data")
    parser.add_argument(
        "--before-strides", default="1,4,11", help="strides the reference is timed on"
    )
    parser.add_argument("--h0-factor", type=float, default=1.0, help="h_0 / the rule's start")
    parser.add_argument("--cases", action="store_true", help="also the earlier cases")
    args = parser.parse_args()
    ref = reference_module(args.rev)
    print(
        f"before: statmodel/maugis_rough.py at {args.rev}; after: this tree; CPU s per stride "
        f"(best of {args.repeat}; before: 1 run); rel: max |after / before - 1| over the loads; "
        "F_z res: max |F_z / F - 1| at the solved separation, before -> after (F_z is the net "
        "of compressive and adhesive forces far larger than F, so Brent's 1e-15 m in d leaves "
        "up to 1e-7 of F); evals: force evaluations per load"
    )
    for name in [m for m in args.maps.split(",") if m]:
        stride_table(name, ref, args)
    if args.cases:
        case_table(args)


if __name__ == "__main__":
    main()
