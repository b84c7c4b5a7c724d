"""Peak resident memory per element of one BEM solve, against the floor of the algorithm.

Each case runs in a fresh process (``--case``), so that its peak resident set (``ru_maxrss``)
is its own: the surface ``asperity.topo.synthetic.paper_like(n)`` (2 um pixels), E* = 2.133 MPa,
the paper preset's 2.08 N scaled to the map's area, tol 1e-6, default options; non-adhesive or
Maugis-Dugdale (w = 0.040 J/m^2, h_0 = 0.5 um); periodic or free boundary (zero-padded
transforms on the doubled grid). Printed per case: peak RSS over the number of height points
(B/element, everything the process holds, the interpreter and the input heights included), the
same above the interpreter's own peak before the solve, the floor, iterations, seconds,
seconds per iteration over two bare real convolutions of the solver's own double-precision
operator timed in the same process after the solve (``s/it/2conv``: the row that catches a
speed regression such as issue 28's 2.4 against 1.0), the contact fraction, and a digest of the
pressure (bit-identity between two versions).

The floor counts the arrays the algorithm cannot do without, in bytes per height point:

* periodic, non-adhesive: heights h, pressure p and gap w (float64, 24 B: the solution and the
  gap must resolve 1e-6 of the rms pressure), the contact set (int8, 1 B), the conjugate
  direction (float32, 4 B) and one real-to-complex transform done in place (float64, 8 B): 37 B;
* Maugis adds the heights lifted by the attraction (float64, 8 B) and the attractive set
  (1 B): 46 B;
* free boundary: the same arrays on the map plus the in-place transform of the doubled grid
  (4 x 8 B) and the influence multiplier of the doubled grid stored as half of its symmetric
  half-spectrum (4 x 2 B): 37 - 8 + 32 + 8 = 69 B (Maugis: 78 B).

Run under the lock (a 5000^2 case holds 1-4 GiB)::

    flock /work/briefs/bigjob.lock .venv/bin/python benchmarks/bem_memory.py --n 2000 5000
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import hashlib  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

E_STAR = 2.133e6  # Pa
WORK_OF_ADHESION = 0.040  # J/m^2
ADHESION_RANGE = 0.5e-6  # m
FORCE_10MM = 2.08  # N on the 10 mm x 10 mm map
PIXEL = 2e-6  # m
TOL = 1e-6

#: Floor in bytes per height point (see the module docstring).
FLOOR = {
    ("periodic", "none"): 37,
    ("periodic", "maugis"): 46,
    ("free", "none"): 69,
    ("free", "maugis"): 78,
}


def _peak_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def run_case(n: int, boundary: str, adhesion: str, precision: str) -> dict:
    """One solve in this process; returns its measurements (peak RSS in bytes)."""
    import numpy as np

    from asperity import bem
    from asperity.topo.synthetic import paper_like

    heights = np.ascontiguousarray(paper_like(n=n, pixel_size=PIXEL).heights)
    # the imports, numba's compiled kernels and the heights, before the solve
    warm = bem.solve_contact(
        heights[:64, :64], PIXEL, PIXEL, E_STAR, normal_force=1e-4, periodic=boundary == "periodic"
    )
    del warm
    before = _peak_bytes()
    force = FORCE_10MM * (n * PIXEL) ** 2 / 1e-4
    kw = {}
    if adhesion == "maugis":
        kw = dict(
            work_of_adhesion=WORK_OF_ADHESION, adhesion="maugis", adhesion_range=ADHESION_RANGE
        )
    opts = bem.SolverOptions(tol=TOL, precision=precision)
    t0 = time.perf_counter()
    res = bem.solve_contact(
        heights,
        PIXEL,
        PIXEL,
        E_STAR,
        normal_force=force,
        periodic=boundary == "periodic",
        options=opts,
        **kw,
    )
    seconds = time.perf_counter() - t0
    peak = _peak_bytes()
    conv = _bare_convolution_seconds(heights.shape, boundary == "periodic")
    return {
        "n": n,
        "boundary": boundary,
        "adhesion": adhesion,
        "peak_bytes": peak,
        "before_bytes": before,
        "seconds": seconds,
        "nit": int(res.nit),
        "conv_seconds": conv,
        "status": int(res.status),
        "contact_fraction": float(res.contact_fraction),
        "pressure_sha1": hashlib.sha1(np.ascontiguousarray(res.pressure).tobytes()).hexdigest()[
            :12
        ],
    }


def _bare_convolution_seconds(shape: tuple[int, int], periodic: bool) -> float:
    """Median seconds of one bare real convolution (forward, multiplication, inverse) with the
    solver's own double-precision operator, measured after the solve in the same process."""
    import numpy as np

    from asperity.bem import SolverOptions
    from asperity.bem.operators import influence_operator

    o = SolverOptions()
    op = influence_operator(shape, PIXEL, PIXEL, E_STAR, o.kernel, periodic, o.fft_backend, None)
    x = op.zeros()
    out = op.empty()
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        op(x, out)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[2000, 5000])
    ap.add_argument("--boundary", nargs="+", default=["periodic", "free"])
    ap.add_argument("--adhesion", nargs="+", default=["none", "maugis"])
    ap.add_argument("--precision", default="auto")
    ap.add_argument("--case", action="store_true", help="run one case in this process (JSON)")
    ap.add_argument("--json", help="append the rows to this file")
    args = ap.parse_args()
    if args.case:
        out = run_case(args.n[0], args.boundary[0], args.adhesion[0], args.precision)
        print(json.dumps(out))
        return
    header = (
        f"{'n':>6} {'boundary':>8} {'adhesion':>8} {'peak GiB':>8} {'B/el':>6} "
        f"{'B/el solve':>10} {'floor':>5} {'nit':>4} {'s':>7} {'s/it/2conv':>10} {'contact':>9} "
        f"{'sha1':>12}"
    )
    print(header)
    rows = []
    for n in args.n:
        for boundary in args.boundary:
            for adhesion in args.adhesion:
                cmd = [sys.executable, __file__, "--case", "--n", str(n), "--boundary", boundary]
                cmd += ["--adhesion", adhesion, "--precision", args.precision]
                proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
                if proc.returncode != 0:
                    print(f"{n:>6} {boundary:>8} {adhesion:>8} failed: {proc.stderr[-400:]}")
                    continue
                r = json.loads(proc.stdout.strip().splitlines()[-1])
                size = n * n
                rows.append(r)
                print(
                    f"{n:>6} {boundary:>8} {adhesion:>8} {r['peak_bytes'] / 2**30:8.2f} "
                    f"{r['peak_bytes'] / size:6.1f} "
                    f"{(r['peak_bytes'] - r['before_bytes']) / size:10.1f} "
                    f"{FLOOR[(boundary, adhesion)]:5d} {r['nit']:4d} {r['seconds']:7.1f} "
                    f"{r['seconds'] / max(r['nit'], 1) / (2 * r['conv_seconds']):10.2f} "
                    f"{r['contact_fraction']:9.6f} {r['pressure_sha1']:>12}",
                    flush=True,
                )
    if args.json:
        with open(args.json, "a") as fh:
            for r in rows:
                fh.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
