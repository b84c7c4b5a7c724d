"""The paper's BEM at the paper's resolution: one cold 5000^2 solve and six-load sweeps.

Surface: ``asperity.topo.synthetic.paper_like(n)`` (2 um pixels, 10 mm at n = 5000, the
paper's 5001^2 map cropped to a fast FFT size), E* = 2.133 MPa, w = 0.040 J/m^2 (the paper
preset), tol 1e-6, loads in N on the 10 mm map (1e-4 m^2): the paper preset's six
(0.56 .. 3.12 N), the cold solve at 2.08 N (a few per cent contact); a smaller ``--n`` scales
the loads with its area (same mean pressures).

Printed, all in one process and one run (ratios only within it):

* the FFT floor: one bare real convolution (forward transform, multiplication, inverse) of the
  solver's own operator, double and single precision, median of 5 calls, with its planning
  time (FFTW wisdom reused from ``~/.cache/asperity`` when present);
* the cold non-adhesive solve: seconds, iterations, convolutions (single / double), seconds per
  convolution against the floor, seconds per iteration against two double convolutions;
* the six-load non-adhesive sweep (``load_sweep``, warm-started) against six times the cold
  solve, and the adhesive sweep on the loading branch given it (``non_adhesive=``) against it
  (``--adhesive-alone``: also the adhesive sweep that solves its loading branch itself);
* the peak resident memory (ru_maxrss) after each stage.

Run it alone, under the lock (a 5000^2 run takes minutes and ~3 GiB):

    flock /tmp/asperity-bench.lock .venv/bin/python benchmarks/bem_paper_scale.py
    .venv/bin/python benchmarks/bem_paper_scale.py --n 1024 --precision double
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

E_STAR = 2.133e6  # Pa (paper preset)
WORK_OF_ADHESION = 0.040  # J/m^2 (paper preset)
LOADS = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)  # N, the paper preset's six
COLD_LOAD = 2.08  # N


def peak_gib() -> float:
    """Peak resident memory of this process so far (GiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def fft_floor(shape, dx, backend, threads, precision) -> dict:
    """Planning time and median seconds of one bare convolution with the solver's operator."""
    from asperity.bem.elastic.operators import influence_operator

    t0 = time.perf_counter()
    op = influence_operator(shape, dx, dx, E_STAR, "point", True, backend, threads, precision)
    planning = time.perf_counter() - t0
    x = op._aligned(op.dtype)  # the transform's own precision: no cast, the bare floor
    x[...] = np.random.default_rng(0).standard_normal(shape)
    y = op._aligned(op.dtype)
    op(x, y)
    times = []
    for _ in range(5):
        t1 = time.perf_counter()
        op(x, y)
        times.append(time.perf_counter() - t1)
    return {"planning_s": planning, "conv_s": float(np.median(times)), "backend": op.backend}


def solve_row(name: str, results: list, seconds: float, floor: dict) -> dict:
    """One table row from the results of a solve or a sweep."""

    def total(key: str) -> float:
        # the solve, its loading-branch part and a non-adhesive start solved by the sweep
        return sum(
            r.extra.get(key, 0)
            + r.extra.get(f"loading_{key}", 0)
            + r.extra.get("loading_start", {}).get(key, 0)
            for r in results
        )

    nit = sum(r.nit + r.extra.get("loading_start", {}).get("nit", 0) for r in results)
    # convolutions as FFT pairs: a forward transform whose product was not needed counts half
    conv = total("fft_transforms") / 2
    single = total("single_precision_transforms") / 2
    fft_s = total("fft_seconds")
    nit_all = nit + sum(r.extra.get("loading_iterations", 0) for r in results)
    # the floor of the convolutions this run did: single ones at the single floor
    floor_s = single * floor["single"]["conv_s"] + (conv - single) * floor["double"]["conv_s"]
    return {
        "case": name,
        "seconds": seconds,
        "iterations": nit_all,
        "convolutions": conv,
        "single": single,
        "fft_seconds": fft_s,
        "floor_seconds": floor_s,
        "over_floor": seconds / floor_s if floor_s else float("nan"),
        "per_it_over_2double": seconds / max(nit_all, 1) / (2 * floor["double"]["conv_s"]),
        "contact": [round(r.contact_fraction, 6) for r in results],
        "converged": all(r.converged for r in results),
        "peak_gib": peak_gib(),
    }


def sweep_rows(h, dx, loads, opts, floor, adhesive_alone: bool) -> list[dict]:
    """The six-load sweeps: non-adhesive, adhesive given it (``non_adhesive=``: the loading
    branch is the non-adhesive solution, only the adhesive checks remain) and, optionally, the
    adhesive sweep solving its loading branch itself."""
    from asperity.bem import load_sweep

    rows = []
    t0 = time.perf_counter()
    plain = load_sweep(h, dx, dx, E_STAR, loads, **opts)
    rows.append(solve_row("sweep, non-adhesive", plain, time.perf_counter() - t0, floor))
    print(f"# non-adhesive sweep iterations per load: {[r.nit for r in plain]}")
    t0 = time.perf_counter()
    reused = load_sweep(
        h, dx, dx, E_STAR, loads, work_of_adhesion=WORK_OF_ADHESION, non_adhesive=plain, **opts
    )
    rows.append(solve_row("sweep, adhesive from it", reused, time.perf_counter() - t0, floor))
    if adhesive_alone:
        t0 = time.perf_counter()
        alone = load_sweep(h, dx, dx, E_STAR, loads, work_of_adhesion=WORK_OF_ADHESION, **opts)
        rows.append(solve_row("sweep, adhesive alone", alone, time.perf_counter() - t0, floor))
    return rows


def print_rows(rows: list[dict]) -> None:
    head = (
        f"{'case':<26} {'seconds':>8} {'iters':>6} {'convs':>6} {'single':>6} {'fft s':>7} "
        f"{'floor s':>8} {'/floor':>7} {'t_it/2conv64':>12} {'peak GiB':>8}  contact"
    )
    print(head)
    for r in rows:
        contact = ", ".join(f"{c:.4f}" for c in r["contact"])
        print(
            f"{r['case']:<26} {r['seconds']:>8.1f} {r['iterations']:>6} {r['convolutions']:>6.1f} "
            f"{r['single']:>6.1f} {r['fft_seconds']:>7.1f} {r['floor_seconds']:>8.1f} "
            f"{r['over_floor']:>7.2f} {r['per_it_over_2double']:>12.2f} {r['peak_gib']:>8.2f}  "
            f"{contact}{'' if r['converged'] else '  NOT CONVERGED'}"
        )
    sys.stdout.flush()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=5000, help="pixels per side (2 um each)")
    parser.add_argument("--tol", type=float, default=1e-6)
    parser.add_argument("--precision", default="auto", choices=("auto", "mixed", "double"))
    parser.add_argument("--backend", default="pyfftw", choices=("auto", "pyfftw", "scipy"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--no-sweeps", action="store_true", help="the cold solve only")
    parser.add_argument(
        "--adhesive-alone",
        action="store_true",
        help="also the adhesive sweep that solves its loading branch itself",
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    args = parser.parse_args(argv)

    from asperity.bem import SolverOptions, solve_contact
    from asperity.topo.synthetic import paper_like

    print(
        f"# bem paper scale, {time.strftime('%Y-%m-%d %H:%M:%S')}, load average "
        f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; n = {args.n}, tol {args.tol:g}, "
        f"precision {args.precision}, {args.backend} x{args.threads} threads"
    )
    surface = paper_like(n=args.n)
    h = np.ascontiguousarray(surface.heights)
    dx = surface.dx
    area = h.size * dx * dx
    scale = area / 1e-4  # the loads are given for the 10 mm map
    loads = [f * scale for f in LOADS]
    floor = {p: fft_floor(h.shape, dx, args.backend, args.threads, p) for p in ("double", "single")}
    for p, f in floor.items():
        print(
            f"# FFT floor ({p}): one bare convolution {f['conv_s']:.3f} s ({f['backend']}), "
            f"planning {f['planning_s']:.1f} s; two per iteration: {2 * f['conv_s']:.3f} s"
        )
    options = SolverOptions(
        tol=args.tol, fft_backend=args.backend, threads=args.threads, precision=args.precision
    )
    opts = {"options": options}
    t0 = time.perf_counter()
    cold = solve_contact(h, dx, dx, E_STAR, normal_force=COLD_LOAD * scale, **opts)
    rows = [solve_row(f"cold {COLD_LOAD} N", [cold], time.perf_counter() - t0, floor)]
    print(
        f"# cold solve: {cold.message}; single-precision phase ended at iteration "
        f"{cold.extra.get('precision_switched_at')}; nominal area {area:.3g} m^2; residuals "
        + " ".join(f"{x:.1e}" for x in cold.residual_history)
    )
    print_rows(rows)
    if not args.no_sweeps:
        rows += sweep_rows(h, dx, loads, opts, floor, args.adhesive_alone)
        print_rows(rows)
        plain, reused = rows[1], rows[2]
        print(
            f"# non-adhesive sweep / six cold solves (6 x the cold {COLD_LOAD} N solve): "
            f"{plain['seconds'] / (6 * rows[0]['seconds']):.2f} in seconds, "
            f"{plain['iterations'] / (6 * rows[0]['iterations']):.2f} in iterations; "
            f"adhesive sweep from it / non-adhesive sweep: "
            f"{reused['seconds'] / plain['seconds']:.2f} in seconds, "
            f"{reused['convolutions'] / plain['convolutions']:.2f} in convolutions"
        )
        if args.adhesive_alone:
            alone = rows[3]
            print(
                f"# adhesive sweep alone / non-adhesive sweep: "
                f"{alone['seconds'] / plain['seconds']:.2f} in seconds, "
                f"{alone['convolutions'] / plain['convolutions']:.2f} in convolutions"
            )
    if args.json:
        args.json.write_text(json.dumps({"floor": floor, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
