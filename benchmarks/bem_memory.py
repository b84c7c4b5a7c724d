"""Peak resident memory per element of one BEM solve, against the floor and against peers.

Each case runs in a fresh process (``--case``): the surface ``asperity.topo.synthetic.
paper_like(n)`` (2 um pixels), E* = 2.133 MPa, the paper preset's 2.08 N scaled to the map's
area, tol 1e-6, default options; non-adhesive or Maugis-Dugdale (w = 0.040 J/m^2, h_0 =
0.5 um); periodic or free boundary (zero-padded transforms on the doubled grid). Columns:

* ``B/el``: the process's resident peak *during the solve* over the number of height points:
  the kernel's high-water mark (``VmHWM``) is reset (``/proc/self/clear_refs``) after the
  surface is made, so the surface generator's own peak is not counted; everything the process
  holds during the solve is (interpreter, libraries, the input heights);
* ``B/el proc``: the whole process's ``ru_maxrss`` (the surface generation included; the
  measure of the previous rounds' numbers);
* ``B/el solve``: the solve's peak above the resident memory just before it;
* the floor, iterations, seconds, seconds per iteration over two bare real convolutions of
  the solver's own double-precision operator timed in the same process after the solve
  (``s/it/2conv``: catches a speed regression), the contact fraction, mean gap, and a digest
  of the pressure (bit-identity between two versions).

The floor counts the arrays the algorithm cannot do without, in bytes per height point:

* periodic, non-adhesive: heights h, pressure p and gap w (float64, 24 B: the solution and the
  gap must resolve 1e-6 of the rms pressure), the contact set (int8, 1 B), the conjugate
  direction (float32, 4 B) and one real-to-complex transform done in place (float64, 8 B): 37 B;
* Maugis adds the heights lifted by the attraction (float64, 8 B) and the attractive set
  (1 B): 46 B;
* free boundary: the same arrays on the map plus the in-place transform of the doubled grid
  (4 x 8 B) and the influence multiplier of the doubled grid stored as half of its symmetric
  half-spectrum (4 x 2 B): 37 - 8 + 32 + 8 = 69 B (Maugis: 78 B).

Peers (``--peers``), each in its own interpreter on the same heights (saved as .npy), the same
high-water mark: Tamaas 2.9 (``--tamaas-python``; periodic only: ``PolonskyKeerRey`` under a
mean pressure, and its ``MaugisAdhesionFunctional`` under the mean gap of our Maugis solve) and
ContactMechanics (``--cm-python``; ``PeriodicFFTElasticHalfSpace`` and
``FreeFFTElasticHalfSpace`` with ``constrained_conjugate_gradients``, non-adhesive). A peer is
stopped after ``--peer-iterations`` iterations (default 10; every array it holds exists from
the first one): the memory of a solve, not its time.

Run under the lock (a 5000^2 case holds 1-4 GiB)::

    flock /work/briefs/bigjob.lock .venv/bin/python benchmarks/bem_memory.py --n 2000 5000
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import hashlib  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

E_STAR = 2.133e6  # Pa
WORK_OF_ADHESION = 0.040  # J/m^2
ADHESION_RANGE = 0.5e-6  # m
FORCE_10MM = 2.08  # N on the 10 mm x 10 mm map
PIXEL = 2e-6  # m
TOL = 1e-6
TAMAAS_PYTHON = "/work/venv-tamaas/bin/python"
CM_PYTHON = "/work/venv-cm/bin/python"

#: Floor in bytes per height point (see the module docstring).
FLOOR = {
    ("periodic", "none"): 37,
    ("periodic", "maugis"): 46,
    ("free", "none"): 69,
    ("free", "maugis"): 78,
}


def _status_bytes(key: str) -> int:
    """A ``/proc/self/status`` entry in bytes (-1 when absent)."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return -1


def reset_hwm() -> int:
    """Collect garbage, reset this process's resident high-water mark (Linux >= 4.0:
    ``clear_refs`` 5) and return the resident memory now (bytes)."""
    import gc

    gc.collect()
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
    except OSError:
        pass
    return _status_bytes("VmRSS")


def hwm() -> int:
    """The resident high-water mark since the last :func:`reset_hwm` (bytes)."""
    return _status_bytes("VmHWM")


#: The same three functions for the peers' workers.
HWM_CODE = "\n".join(inspect.getsource(f) for f in (_status_bytes, reset_hwm, hwm))

TAMAAS_WORKER = (
    HWM_CODE
    + r"""
import json, sys, time
import numpy as np
import tamaas as tm
heights, dx, e_star, p0, work, rho, mean_gap, tol, iters = sys.argv[1:10]
h = np.load(heights)
n = h.shape[0]
size = n * float(dx)
model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [size, size], [n, n])
model.E, model.nu = float(e_star), 0.0
before = reset_hwm()
t0 = time.perf_counter()
if float(work) > 0:
    surface = np.ascontiguousarray(h - h.max())
    solver = tm.PolonskyKeerRey(model, surface, float(tol), tm.PolonskyKeerRey.gap,
                                tm.PolonskyKeerRey.gap)
    adhesion = tm.MaugisAdhesionFunctional(surface)
    adhesion.setParameters({"rho": float(rho), "surface_energy": float(work)})
    solver.addFunctionalTerm(adhesion)
    solver.max_iter = int(iters)
    solver.solve(float(mean_gap))
else:
    solver = tm.PolonskyKeerRey(model, h, float(tol))
    solver.max_iter = int(iters)
    solver.solve(float(p0))
print(json.dumps({"peak_bytes": hwm(), "rss_before": before,
                  "seconds": time.perf_counter() - t0}))
"""
)

CM_WORKER = (
    HWM_CODE
    + r"""
import json, sys, time
import numpy as np
from ContactMechanics import FreeFFTElasticHalfSpace, PeriodicFFTElasticHalfSpace
from ContactMechanics.Optimization.ConstrainedConjugateGradients import (
    constrained_conjugate_gradients)
from SurfaceTopography import Topography
heights, dx, e_star, p0, periodic, tol, iters = sys.argv[1:8]
periodic = periodic == "periodic"
h = np.load(heights)
n = h.shape[0]
size = (n * float(dx), n * float(dx))
before = reset_hwm()
t0 = time.perf_counter()
half_space = PeriodicFFTElasticHalfSpace if periodic else FreeFFTElasticHalfSpace
substrate = half_space((n, n), float(e_star), physical_sizes=size)
topography = Topography(h, physical_sizes=size, periodic=periodic)
pentol = float(tol) * float(np.sqrt(np.mean((h - h.mean()) ** 2)))
constrained_conjugate_gradients(substrate, topography,
                                external_force=float(p0) * size[0] * size[1],
                                pentol=pentol, maxiter=int(iters))
print(json.dumps({"peak_bytes": hwm(), "rss_before": before,
                  "seconds": time.perf_counter() - t0}))
"""
)


def _peak_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _heights(n: int):
    import numpy as np

    from asperity.topo.synthetic import paper_like

    return np.ascontiguousarray(paper_like(n=n, pixel_size=PIXEL).heights)


def _force(n: int) -> float:
    """The paper preset's 2.08 N on 10 mm x 10 mm, scaled to the map's area (N)."""
    return FORCE_10MM * (n * PIXEL) ** 2 / 1e-4


def run_case(n: int, boundary: str, adhesion: str, precision: str) -> dict:
    """One solve in this process; returns its measurements (bytes, s)."""
    import numpy as np

    from asperity import bem

    heights = _heights(n)
    # the imports and numba's compiled kernels, before the solve
    warm = bem.solve_contact(
        heights[:64, :64], PIXEL, PIXEL, E_STAR, normal_force=1e-4, periodic=boundary == "periodic"
    )
    del warm
    before = reset_hwm()
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
        normal_force=_force(n),
        periodic=boundary == "periodic",
        options=opts,
        **kw,
    )
    seconds = time.perf_counter() - t0
    peak = hwm()
    conv = _bare_convolution_seconds(heights.shape, boundary == "periodic")
    return {
        "n": n,
        "boundary": boundary,
        "adhesion": adhesion,
        "code": "asperity",
        "peak_bytes": peak,
        "process_peak_bytes": _peak_bytes(),
        "rss_before": before,
        "seconds": seconds,
        "nit": int(res.nit),
        "conv_seconds": conv,
        "status": int(res.status),
        "contact_fraction": float(res.contact_fraction),
        "mean_gap": float(res.mean_gap),
        "pressure_sha1": hashlib.sha1(np.ascontiguousarray(res.pressure).tobytes()).hexdigest()[
            :12
        ],
    }


def _bare_convolution_seconds(shape: tuple[int, int], periodic: bool) -> float:
    """Median seconds of one bare real convolution (forward, multiplication, inverse) with the
    solver's own double-precision operator, measured after the solve in the same process."""
    import numpy as np

    from asperity.bem import SolverOptions
    from asperity.bem.elastic.operators import influence_operator

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


def run_peer(args: argparse.Namespace, n: int, boundary: str, adhesion: str, mean_gap: float):
    """One peer case in the peer's own interpreter; None when it does not apply or run."""
    import numpy as np

    peer = args.peer
    if peer == "tamaas" and boundary != "periodic":
        return None  # Tamaas's basic_2d model is periodic
    if peer == "cm" and adhesion != "none":
        return None  # ContactMechanics' constrained CG has no Maugis law
    python = args.tamaas_python if peer == "tamaas" else args.cm_python
    if not Path(python).exists():
        return None
    p0 = _force(n) / (n * PIXEL) ** 2
    with tempfile.TemporaryDirectory() as tmp:
        path = str(Path(tmp) / "h.npy")
        np.save(path, _heights(n))
        if peer == "tamaas":
            work = WORK_OF_ADHESION if adhesion == "maugis" else 0.0
            argv = [path, PIXEL, E_STAR, p0, work, ADHESION_RANGE, mean_gap, TOL]
            code = TAMAAS_WORKER
        else:
            argv = [path, PIXEL, E_STAR, p0, boundary, TOL]
            code = CM_WORKER
        argv = [str(a) for a in argv] + [str(args.peer_iterations)]
        proc = subprocess.run(
            [python, "-c", code, *argv], capture_output=True, text=True, check=False
        )
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        return {"error": (proc.stderr or proc.stdout)[-300:].replace("\n", " ")}
    return json.loads(lines[-1])


def _row(n: int, boundary: str, adhesion: str, r: dict) -> str:
    size = n * n
    if r.get("code") == "asperity":
        ratio = r["seconds"] / max(r["nit"], 1) / (2 * r["conv_seconds"])
        return (
            f"{n:>6} {boundary:>8} {adhesion:>8} {'asperity':>10} {r['peak_bytes'] / 2**30:8.2f} "
            f"{r['peak_bytes'] / size:6.1f} {r['process_peak_bytes'] / size:9.1f} "
            f"{(r['peak_bytes'] - r['rss_before']) / size:10.1f} "
            f"{FLOOR[(boundary, adhesion)]:5d} {r['nit']:4d} {r['seconds']:7.1f} {ratio:10.2f} "
            f"{r['contact_fraction']:9.6f} {r['mean_gap']:.9e} {r['pressure_sha1']:>12}"
        )
    return (
        f"{n:>6} {boundary:>8} {adhesion:>8} {r['code']:>10} {r['peak_bytes'] / 2**30:8.2f} "
        f"{r['peak_bytes'] / size:6.1f} {'':>9} {(r['peak_bytes'] - r['rss_before']) / size:10.1f}"
        f" {FLOOR[(boundary, adhesion)]:5d} (stopped after a few iterations: memory only)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[2000, 5000])
    ap.add_argument("--boundary", nargs="+", default=["periodic", "free"])
    ap.add_argument("--adhesion", nargs="+", default=["none", "maugis"])
    ap.add_argument("--precision", default="auto")
    ap.add_argument("--peers", action="store_true", help="also measure Tamaas, ContactMechanics")
    ap.add_argument("--tamaas-python", default=TAMAAS_PYTHON)
    ap.add_argument("--cm-python", default=CM_PYTHON)
    ap.add_argument("--peer-iterations", type=int, default=10)
    ap.add_argument("--peer", choices=["tamaas", "cm"], help=argparse.SUPPRESS)
    ap.add_argument("--mean-gap", type=float, default=0.0, help=argparse.SUPPRESS)
    ap.add_argument("--case", action="store_true", help="run one case in this process (JSON)")
    ap.add_argument("--json", help="append the rows to this file")
    args = ap.parse_args()
    if args.case:
        if args.peer:
            out = run_peer(args, args.n[0], args.boundary[0], args.adhesion[0], args.mean_gap)
        else:
            out = run_case(args.n[0], args.boundary[0], args.adhesion[0], args.precision)
        print(json.dumps(out))
        return
    header = (
        f"{'n':>6} {'boundary':>8} {'adhesion':>8} {'code':>10} {'peak GiB':>8} {'B/el':>6} "
        f"{'B/el proc':>9} {'B/el solve':>10} {'floor':>5} {'nit':>4} {'s':>7} "
        f"{'s/it/2conv':>10} {'contact':>9} {'mean gap m':>15} {'sha1':>12}"
    )
    print(header, flush=True)
    rows = []
    for n in args.n:
        for boundary in args.boundary:
            for adhesion in args.adhesion:
                base = [sys.executable, __file__, "--case", "--n", str(n), "--boundary", boundary]
                base += ["--adhesion", adhesion]
                proc = subprocess.run(
                    base + ["--precision", args.precision],
                    capture_output=True,
                    text=True,
                    check=False,
                )
                if proc.returncode != 0:
                    print(f"{n:>6} {boundary:>8} {adhesion:>8} failed: {proc.stderr[-400:]}")
                    continue
                r = json.loads(proc.stdout.strip().splitlines()[-1])
                rows.append(r)
                print(_row(n, boundary, adhesion, r), flush=True)
                for peer in ("tamaas", "cm") if args.peers else ():
                    extra = ["--peer", peer, "--mean-gap", repr(r["mean_gap"])]
                    extra += ["--peer-iterations", str(args.peer_iterations)]
                    extra += ["--tamaas-python", args.tamaas_python, "--cm-python", args.cm_python]
                    proc = subprocess.run(base + extra, capture_output=True, text=True, check=False)
                    if proc.returncode != 0:
                        print(
                            f"{n:>6} {boundary:>8} {adhesion:>8} {peer:>10} failed: "
                            f"{proc.stderr[-300:]}"
                        )
                        continue
                    out = json.loads(proc.stdout.strip().splitlines()[-1])
                    if out is None:
                        continue
                    name = "Tamaas 2.9" if peer == "tamaas" else "ContactMe."
                    if "error" in out:
                        print(
                            f"{n:>6} {boundary:>8} {adhesion:>8} {name:>10} error: {out['error']}",
                            flush=True,
                        )
                        continue
                    out.update(code=name, n=n, boundary=boundary, adhesion=adhesion)
                    rows.append(out)
                    print(_row(n, boundary, adhesion, out), flush=True)
    if args.json:
        with open(args.json, "a") as fh:
            for r in rows:
                fh.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
