"""The paper's whole nominal contact in one BEM solve: 35 x 20 mm at 2 um, 175 million elements.

The paper (Xu et al. 2022, Appendix B) solved its BEM on a 10 x 10 mm map, one seventh of the
35 x 20 mm interface, and names that as a likely reason its BEM and experiment differ. This
benchmark solves the whole interface and, on the same surface, its 10 x 10 mm window at the same
load per area, so that the representativeness the paper worried about is measured:

* surface: :func:`asperity.topo.capped_surface.capped_surface` with the paper recipe
  (``--recipe paper``, :data:`asperity.topo.synthetic.PAPER_SURFACE`, the surface of
  :func:`asperity.topo.synthetic.paper_surface`; ``--recipe wavy``: asperity 0.4.1's
  :data:`~asperity.topo.synthetic.PAPER_SURFACE_WAVY`, on which docs/performance.md's
  whole-interface numbers were measured), ``nx x ny`` = 17,500 x 10,000 pixels of
  2 um (35 x 20 mm; axis 0 is the 35 mm side), seed 0, periodic;
* material: E* = 2.133 MPa (the paper's PDMS), w = 0.040 J/m^2;
* load: F_z = 2.08 N (one of the paper's six loads, Sahli et al.) on the whole 700 mm^2, i.e.
  a mean pressure of 2.97 kPa; each window (``window x window`` pixels, 10 x 10 mm, a crop of the
  same heights solved as periodic like the paper's map; ``--windows`` of the six disjoint ones,
  from the corner) carries the same mean pressure (F_z x 100 / 700 = 0.297 N);
* solver: :func:`asperity.bem.solve_contact`, periodic, tol 1e-6, default options (mixed
  precision, preconditioned); non-adhesive, or Maugis-Dugdale on loading with the range
  :func:`asperity.bem.resolving_range` (w, E*, 2 um) = 0.379 um (cohesive zone of 3 pixels on
  the JKR side), the same range on the full map and on the window.

Each case (non-adhesive, Maugis) runs in its own process, one after the other, so that each peak
resident set (``ru_maxrss``, everything the process holds: interpreter, heights, solver) is its
own. Printed and written (``--json``, one line per case): seconds and peak RSS of the surface's
generation, seconds, iterations, status and peak RSS of the full solve, bytes per element, and
the contact fractions A_r/A_n of the full map and of the window with their relative difference.

The full case needs about 10.5 GiB (non-adhesive) and 13 GiB (Maugis) and many minutes on
2 cores: run it under the shared lock, after ``free -g``::

    flock /work/briefs/bigjob.lock .venv/bin/python benchmarks/bem_nominal.py \\
        --json nominal.jsonl

The whole path scaled down (3500 x 2000 pixels of 10 um, the same 35 x 20 mm; all six disjoint
1000 x 1000 windows), 18 min on the shared machine at load 19 (docs/performance.md)::

    .venv/bin/python benchmarks/bem_nominal.py --nx 3500 --ny 2000 --pixel 10e-6 --window 1000 \
        --windows 6
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

E_STAR = 2.133e6  # Pa
WORK_OF_ADHESION = 0.040  # J/m^2
NORMAL_FORCE = 2.08  # N on the whole nominal contact
TOL = 1e-6
GIB = 2**30


def _peak_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _progress(**fields: object) -> None:
    """One JSON line on stderr at the end of each stage: a killed run still leaves its numbers."""
    print(
        json.dumps({"progress": time.strftime("%H:%M:%S"), **fields}), file=sys.stderr, flush=True
    )


def run_case(
    nx: int,
    ny: int,
    pixel: float,
    window: int,
    adhesion: str,
    seed: int,
    force: float,
    windows: int = 1,
    recipe: str = "paper",
) -> dict:
    """Generate the surface, solve it whole, then solve ``windows`` of its disjoint
    ``window``-pixel squares (from the corner, along y first) at the same mean pressure (Pa),
    in this process; returns the measurements (SI units, bytes)."""

    from asperity import bem
    from asperity.topo.capped_surface import capped_surface
    from asperity.topo.synthetic import PAPER_SURFACE, PAPER_SURFACE_WAVY

    x = (np.arange(64) - 32.0) * pixel
    bump = -(x[:, None] ** 2 + x[None, :] ** 2) / 1e-3  # a 0.5 mm sphere: numba compiles here
    bem.solve_contact(bump, pixel, pixel, E_STAR, normal_force=1e-6)
    t0 = time.perf_counter()
    chosen = PAPER_SURFACE_WAVY if recipe == "wavy" else PAPER_SURFACE
    heights = capped_surface(nx, ny, pixel, pixel, chosen, seed)
    gen_seconds = time.perf_counter() - t0
    gen_peak = _peak_bytes()
    _progress(generation_seconds=gen_seconds, generation_peak_bytes=gen_peak)
    area = nx * ny * pixel * pixel
    kw: dict = {}
    h0 = None
    if adhesion == "maugis":
        h0 = bem.resolving_range(WORK_OF_ADHESION, E_STAR, pixel)
        kw = dict(work_of_adhesion=WORK_OF_ADHESION, adhesion="maugis", adhesion_range=h0)
    opts = bem.SolverOptions(tol=TOL)
    t0 = time.perf_counter()
    full = bem.solve_contact(heights, pixel, pixel, E_STAR, normal_force=force, options=opts, **kw)
    full_seconds = time.perf_counter() - t0
    full_peak = _peak_bytes()
    out = {
        "nx": nx,
        "ny": ny,
        "pixel": pixel,
        "seed": seed,
        "recipe": recipe,
        "adhesion": adhesion,
        "adhesion_range": h0,
        "normal_force": force,
        "mean_pressure": force / area,
        "generation_seconds": gen_seconds,
        "generation_peak_bytes": gen_peak,
        "seconds": full_seconds,
        "nit": int(full.nit),
        "status": int(full.status),
        "message": full.message,
        "peak_bytes": full_peak,
        "contact_fraction": float(full.contact_fraction),
        "force_solved": float(full.normal_force),
    }
    _progress(**out)
    del full
    w_force = force * window * window / (nx * ny)
    corners = [
        (i, j) for i in range(0, nx - window + 1, window) for j in range(0, ny - window + 1, window)
    ]
    fractions, seconds, nits = [], [], []
    for i, j in corners[:windows]:
        sub = np.ascontiguousarray(heights[i : i + window, j : j + window])
        t0 = time.perf_counter()
        win = bem.solve_contact(sub, pixel, pixel, E_STAR, normal_force=w_force, options=opts, **kw)
        seconds.append(time.perf_counter() - t0)
        fractions.append(float(win.contact_fraction))
        nits.append(int(win.nit))
        del sub, win
    out.update(
        window=window,
        window_corners=corners[:windows],
        window_seconds=seconds[0],
        window_nit=nits[0],
        window_contact_fraction=fractions[0],
        window_contact_fractions=fractions,
        window_nits=nits,
    )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nx", type=int, default=17500, help="pixels along the 35 mm side")
    ap.add_argument("--ny", type=int, default=10000, help="pixels along the 20 mm side")
    ap.add_argument("--pixel", type=float, default=2e-6, help="pixel size, m")
    ap.add_argument("--window", type=int, default=5000, help="window side, pixels (10 mm)")
    ap.add_argument("--windows", type=int, default=1, help="disjoint windows solved (<= 6)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--recipe", choices=("paper", "wavy"), default="paper",
        help="PAPER_SURFACE (paper) or 0.4.1's PAPER_SURFACE_WAVY (wavy)",
    )  # fmt: skip
    ap.add_argument("--force", type=float, default=NORMAL_FORCE, help="F_z on the map, N")
    ap.add_argument("--adhesion", nargs="+", default=["none", "maugis"])
    ap.add_argument("--case", action="store_true", help="run one case in this process (JSON)")
    ap.add_argument("--json", help="append the rows to this file")
    args = ap.parse_args()
    if args.case:
        out = run_case(
            args.nx,
            args.ny,
            args.pixel,
            args.window,
            args.adhesion[0],
            args.seed,
            args.force,
            args.windows,
            args.recipe,
        )
        print(json.dumps(out))
        return
    size = args.nx * args.ny
    print(
        f"{args.nx} x {args.ny} pixels of {args.pixel * 1e6:g} um ({size / 1e6:.1f} M elements), "
        f"F_z = {args.force:g} N; window {args.window}^2 at the same mean pressure",
        flush=True,
    )
    header = (
        f"{'adhesion':>8} {'gen s':>7} {'gen GiB':>7} {'solve s':>8} {'nit':>4} {'st':>2} "
        f"{'peak GiB':>8} {'B/el':>6} {'A_r/A_n full':>12} {'window':>10} {'diff':>7} "
        f"{'win s':>6} {'win nit':>7}"
    )
    print(header, flush=True)
    for adhesion in args.adhesion:
        cmd = [sys.executable, __file__, "--case", "--adhesion", adhesion]
        for key in ("nx", "ny", "pixel", "window", "windows", "seed", "force", "recipe"):
            cmd += [f"--{key}", str(getattr(args, key))]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            print(f"{adhesion:>8} failed ({proc.returncode}): {proc.stderr[-600:]}", flush=True)
            continue
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        diff = r["contact_fraction"] / r["window_contact_fraction"] - 1
        print(
            f"{adhesion:>8} {r['generation_seconds']:7.1f} "
            f"{r['generation_peak_bytes'] / GIB:7.2f} {r['seconds']:8.1f} {r['nit']:4d} "
            f"{r['status']:2d} {r['peak_bytes'] / GIB:8.2f} {r['peak_bytes'] / size:6.1f} "
            f"{r['contact_fraction']:12.6f} {r['window_contact_fraction']:10.6f} "
            f"{diff:+7.2%} {r['window_seconds']:6.1f} {r['window_nit']:7d}",
            flush=True,
        )
        if len(r["window_contact_fractions"]) > 1:
            f = np.array(r["window_contact_fractions"])
            print(
                f"{'':>8} {len(f)} windows: A_r/A_n {f.min():.6f} .. {f.max():.6f}, mean "
                f"{f.mean():.6f}, sd {f.std(ddof=1):.6f}; whole / mean - 1 = "
                f"{r['contact_fraction'] / f.mean() - 1:+.2%}",
                flush=True,
            )
        if args.json:
            with open(args.json, "a") as fh:
                fh.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
