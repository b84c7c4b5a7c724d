"""The BEM solver against its floor, and against Tamaas 2.9 (issue 28, section 3).

Two measurements, each code in its own subprocess (so that its set-up and memory are its own),
repeated and alternated (``--repeats``), medians printed: the machine is shared, and only ratios
taken within one run mean anything.

``floor`` (default): the paper-like surface (``asperity.topo.synthetic.paper_like(n)``, 2 um
pixels, E* = 2.133 MPa, 2.08 N scaled with the map's area, tol 1e-6) in a fresh process, as
``asperity bem`` solves it: the cold solve (the process's set-up included: FFT backend choice,
FFTW plans, compiled kernels), then the floor (two bare double-precision real convolutions of
the solver's own operator, median of 5), then the same solve again (warm). Printed: iterations,
FFT transforms per iteration, the float32 share of them, seconds (wall and CPU) and floor
iterations (seconds over the floor, wall over wall and CPU over CPU: CPU seconds hold on a busy
machine, where threads wait for a core). ``--python`` adds interpreters to run the same worker
(e.g. an older asperity on its own ``PYTHONPATH``, ``--pythonpath``): the regression of issue 28
(0.2: 33 floor iterations, 0.3: 69 at 5000^2) shows as a ratio between two rows of one run.
``--options all`` (or a comma-separated subset of ``default``, ``coarse``, ``no-precondition``,
``double``) runs this asperity once per option set instead (issue 36, item 4: each option on
and off); ``chg`` is the number of iterations whose contact-set change recomputed u = K p
(2 transforms more than the search direction's two).

``--tamaas``: the 1024^2 self-affine benchmark surface of ``bem_speed.py`` (H = 0.8, pixel 1,
E* = 1, mean pressure 0.04, tol 1e-8), asperity warm (median of 3 solves after one) against
Tamaas's ``PolonskyKeerRey`` (median of ``--tamaas-repeats`` solves, default 3, a fresh model
each, in its own interpreter, ``--tamaas-python``, default /work/venv-tamaas/bin/python);
printed: seconds (wall and CPU), iterations, contact fractions and the ratios Tamaas /
asperity. On a busy machine the CPU ratio is the one to read: a two-thread transform that
waits for a core shows in wall-clock time only.

Run (the 5000^2 rows need about 2 GiB a process; an older version about 3.5 GiB: use the lock):

    .venv/bin/python benchmarks/bem_floor.py --n 2048 --repeats 2
    .venv/bin/python benchmarks/bem_floor.py --n 1024 --options all
    flock /work/briefs/bigjob.lock .venv/bin/python benchmarks/bem_floor.py --n 5000
    .venv/bin/python benchmarks/bem_floor.py --tamaas --n 1024 --repeats 3
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent

FLOOR_WORKER = r"""
import json, os, resource, sys, time
import numpy as np
w_start, c_start = time.perf_counter(), time.process_time()
from asperity.bem import SolverOptions, solve_contact
from asperity.bem.elastic.operators import influence_operator
h = np.load({surface!r})
n = h.shape[0]
dx, e_star, force = 2e-6, 2.133e6, 2.08 * (n / 5000) ** 2
opts = SolverOptions(tol={tol!r}, coarse_start={coarse!r}, threads={threads!r},
                     precondition={precondition!r}, precision={precision!r})
def solve():
    w, c = time.perf_counter(), time.process_time()
    r = solve_contact(h, dx, dx, e_star, normal_force=force, options=opts)
    return r, time.perf_counter() - w, time.process_time() - c
cold, cold_w, cold_c = solve()
cold_w, cold_c = time.perf_counter() - w_start, time.process_time() - c_start  # imports included
op = influence_operator(h.shape, dx, dx, e_star, "point", True,
                        "auto" if {threads!r} is None else "pyfftw", {threads!r})
x = op.empty(); x[...] = np.random.default_rng(0).standard_normal(h.shape); y = op.empty()
op(x, y)
walls, cpus = [], []
for _ in range(5):
    w, c = time.perf_counter(), time.process_time()
    op(x, y)
    walls.append(time.perf_counter() - w); cpus.append(time.process_time() - c)
floor_w, floor_c = 2 * float(np.median(walls)), 2 * float(np.median(cpus))
del x, y
warm, warm_w, warm_c = solve()
ex = warm.extra
print(json.dumps(dict(nit=warm.nit, cold_nit=cold.nit, threads=op.threads, backend=op.backend,
    floor_w=floor_w, floor_c=floor_c, cold_w=cold_w, cold_c=cold_c, warm_w=warm_w, warm_c=warm_c,
    transforms=ex.get("fft_transforms", 0), f32=ex.get("single_precision_transforms", 0),
    coarse_its=ex.get("coarse_iterations", 0), contact_fraction=warm.contact_fraction,
    coarse_transforms=2 * ex.get("coarse_convolutions", 0),
    set_changes=ex.get("set_change_recomputations", -1), force=warm.normal_force,
    residual=warm.residual, converged=warm.converged,
    peak_gib=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)))
"""

BEM_1024_WORKER = r"""
import json, time
import numpy as np
from asperity.bem import SolverOptions, solve_contact
h = np.load({surface!r})
opts = SolverOptions(tol={tol!r})
solve_contact(h, 1.0, 1.0, 1.0, mean_pressure={p!r}, options=opts)  # warm up
times, cpus = [], []
for _ in range(3):
    t, c = time.perf_counter(), time.process_time()
    r = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure={p!r}, options=opts)
    times.append(time.perf_counter() - t)
    cpus.append(time.process_time() - c)
print(json.dumps(dict(seconds=float(np.median(times)), cpu=float(np.median(cpus)), nit=r.nit,
                      contact_fraction=r.contact_fraction)))
"""

TAMAAS_WORKER = r"""
import json, time
import numpy as np
import tamaas as tm
h = np.load({surface!r})
n = h.shape[0]
times, cpus = [], []
for _ in range({tamaas_repeats!r}):
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [float(n), float(n)], [n, n])
    model.E = 1.0
    model.nu = 0.0
    solver = tm.PolonskyKeerRey(model, h, {tol!r})
    solver.max_iter = 20000
    t, c = time.perf_counter(), time.process_time()
    solver.solve({p!r})
    times.append(time.perf_counter() - t)
    cpus.append(time.process_time() - c)
p = np.array(model.traction).reshape(h.shape)
print(json.dumps(dict(seconds=float(np.median(times)), cpu=float(np.median(cpus)), nit=-1,
                      contact_fraction=float((p > 0).mean()))), flush=True)
"""


def run_worker(python: str, code: str, env_path: str | None, timeout: float) -> dict | None:
    """Run ``code`` in ``python`` (with ``PYTHONPATH=env_path`` when given); its last stdout line
    as JSON, or None (with stderr's tail printed) when it failed."""
    env = dict(os.environ)
    if env_path:
        env["PYTHONPATH"] = env_path
    proc = subprocess.run(
        [python, "-c", code],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
        cwd=tempfile.gettempdir(),  # not the repository: the interpreter's own asperity
    )
    if proc.returncode != 0:
        print(f"# worker {python} failed:\n{proc.stderr[-1500:]}")
        return None
    return json.loads(proc.stdout.strip().splitlines()[-1])


def median_row(rows: list[dict]) -> dict:
    """Per-key median of numeric fields over repeated runs (other fields from the first)."""
    out = dict(rows[0])
    for key, value in rows[0].items():
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = float(np.median([r[key] for r in rows]))
    return out


#: Solver options of ``--options`` (issue 36, item 4: each option on and off).
VARIANTS = {
    "default": dict(coarse=False, precondition=True, precision="auto"),
    "coarse": dict(coarse=True, precondition=True, precision="auto"),
    "no-precondition": dict(coarse=False, precondition=False, precision="auto"),
    "double": dict(coarse=False, precondition=True, precision="double"),
}


def option_variants(args: argparse.Namespace) -> list[str]:
    """The option sets to run: ``--options`` (comma-separated names of :data:`VARIANTS`, or
    "all"), else the default one (with ``--coarse-start`` if given)."""
    if not args.options:
        return ["coarse" if args.coarse_start else "default"]
    names = list(VARIANTS) if args.options == "all" else args.options.split(",")
    unknown = [n for n in names if n not in VARIANTS]
    if unknown:
        raise SystemExit(f"--options: unknown {unknown}; expected names of {list(VARIANTS)}")
    return names


def floor_rows(args: argparse.Namespace) -> list[dict]:
    from asperity.topo.synthetic import paper_like

    tmp = Path(tempfile.mkdtemp(prefix="bem_floor_"))
    surface = tmp / f"paper_like_{args.n}.npy"
    s = paper_like(n=args.n)
    np.save(surface, np.ascontiguousarray(s.heights))
    paths = list(args.pythonpath or []) + [None] * len(args.python)
    codes = [("this", sys.executable, None)] + [
        (f"python{i}", py, paths[i - 1]) for i, py in enumerate(args.python, 1)
    ]
    variants = option_variants(args)
    if len(variants) > 1:
        codes = [(f"this:{v}", sys.executable, None) for v in variants]
    runs: dict[str, list[dict]] = {name: [] for name, _, _ in codes}
    for _ in range(args.repeats):
        for name, py, path in codes:
            variant = name.split(":", 1)[1] if ":" in name else variants[0]
            worker = FLOOR_WORKER.format(
                surface=str(surface), tol=args.tol, threads=args.threads, **VARIANTS[variant]
            )
            got = run_worker(py, worker, path, args.timeout)
            if got is not None:
                runs[name].append(got)
    rows = []
    print(
        f"# paper-like {args.n}^2 at 2 um, 2.08 N scaled, tol {args.tol:g}; "
        f"medians of {args.repeats}; floor = 2 bare float64 convolutions"
    )
    print(
        f"{'code':20s} {'nit':>4s} {'tr/it':>5s} {'f32%':>5s} {'chg':>4s} {'floor s':>8s} "
        f"{'cold s':>7s} {'warm s':>7s} {'cold fl':>7s} {'warm fl':>7s} {'warmCPU fl':>10s} "
        f"{'thr':>3s} {'contact':>10s} {'GiB':>5s}"
    )
    for name, got in runs.items():
        if not got:
            continue
        r = median_row(got)
        r["code"] = name
        rows.append(r)
        print(
            f"{name:20s} {r['nit']:4.0f} {r['transforms'] / max(r['nit'], 1):5.2f} "
            f"{100 * r['f32'] / max(r['transforms'], 1):5.1f} {r.get('set_changes', -1):4.0f} "
            f"{r['floor_w']:8.3f} "
            f"{r['cold_w']:7.1f} {r['warm_w']:7.1f} {r['cold_w'] / r['floor_w']:7.1f} "
            f"{r['warm_w'] / r['floor_w']:7.1f} {r['warm_c'] / r['floor_c']:10.1f} "
            f"{r['threads']:3.0f} {r['contact_fraction']:10.7f} {r['peak_gib']:5.2f}"
        )
    return rows


def tamaas_rows(args: argparse.Namespace) -> list[dict]:
    sys.path.insert(0, str(HERE))
    from bem_surfaces import self_affine_periodic

    tmp = Path(tempfile.mkdtemp(prefix="bem_floor_tamaas_"))
    surface = tmp / f"surface_{args.n}.npy"
    h = self_affine_periodic(args.n, hurst=0.8, short_cutoff_px=8.0, rms_slope=1.0, seed=0)
    np.save(surface, h)
    fmt = dict(surface=str(surface), tol=1e-8, p=0.04, tamaas_repeats=args.tamaas_repeats)
    mine, theirs, ratios = [], [], []
    for _ in range(args.repeats):
        got = run_worker(sys.executable, BEM_1024_WORKER.format(**fmt), None, args.timeout)
        peer = run_worker(args.tamaas_python, TAMAAS_WORKER.format(**fmt), None, args.timeout)
        if not (got and peer):
            continue
        mine.append(got)
        theirs.append(peer)
        ratios.append(peer["seconds"] / got["seconds"])
        print(
            f"# repeat: asperity {got['seconds']:.3f} s ({got['cpu']:.3f} s CPU), Tamaas "
            f"{peer['seconds']:.3f} s ({peer['cpu']:.3f} s CPU), ratio {ratios[-1]:.1f} "
            f"(CPU {peer['cpu'] / got['cpu']:.1f})",
            flush=True,
        )
    if not mine:
        return []
    a, t = median_row(mine), median_row(theirs)
    each = ", ".join(f"{r:.1f}" for r in ratios)
    print(
        f"{args.n}^2 tol 1e-8: asperity {a['seconds']:.3f} s ({a['nit']:.0f} it, contact "
        f"{a['contact_fraction']:.6f}), Tamaas PolonskyKeerRey {t['seconds']:.3f} s (contact "
        f"{t['contact_fraction']:.6f}); ratio of medians {t['seconds'] / a['seconds']:.1f}, "
        f"median of ratios {float(np.median(ratios)):.1f} (each {each}); CPU seconds "
        f"{a['cpu']:.3f} against {t['cpu']:.3f}, ratio {t['cpu'] / a['cpu']:.1f}"
    )
    return [dict(code="asperity", **a), dict(code="tamaas", **t)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=5000, help="grid size (default 5000)")
    parser.add_argument("--tol", type=float, default=1e-6)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--threads", type=int, default=None, help="FFT threads (default auto)")
    parser.add_argument("--coarse-start", action="store_true")
    parser.add_argument(
        "--options",
        default="",
        help=f"option sets to compare, comma-separated, or 'all': {', '.join(VARIANTS)}",
    )
    parser.add_argument("--python", nargs="*", default=[], help="more interpreters to compare")
    parser.add_argument("--pythonpath", nargs="*", default=None, help="PYTHONPATH of each")
    parser.add_argument("--tamaas", action="store_true", help="the Tamaas comparison instead")
    parser.add_argument("--tamaas-python", default="/work/venv-tamaas/bin/python")
    parser.add_argument(
        "--tamaas-repeats", type=int, default=3, help="Tamaas solves per worker (median)"
    )
    parser.add_argument("--timeout", type=float, default=1800.0, help="per worker (s)")
    parser.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    args = parser.parse_args(argv)
    rows = tamaas_rows(args) if args.tamaas else floor_rows(args)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0 if rows else 1


if __name__ == "__main__":
    sys.exit(main())
