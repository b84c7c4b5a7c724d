"""Speed and accuracy of bem.solve_contact against Tamaas and ContactMechanics.

One periodic self-affine surface per size (H = 0.8, wavelengths from the box down to 8 px, rms
slope 1, pixel 1, E* = 1), mean pressure 0.04 (about 8 % contact), every code at tolerance 1e-8.
Accuracy is measured against a tight bem reference (tol 1e-12) on the same surface: the contact
fraction difference and the relative L2 pressure difference. Each code runs in a fresh
subprocess, so that the peak resident memory (ru_maxrss) is its own.

Peers are optional: they are looked for in the interpreter given by ``--peer-python`` (default
``/tmp/peers-bem/bin/python``, a venv made with ``python -m venv --system-site-packages`` and
``pip install tamaas ContactMechanics``); a missing peer leaves its column empty.

Run (the machine is shared: serialise timings with the lock):

    flock /tmp/asperity-bench.lock python benchmarks/bem_speed.py --sizes 512 1024
    flock /tmp/asperity-bench.lock python benchmarks/bem_speed.py --sizes 5001 --no-peers
    python benchmarks/bem_speed.py --hertz-plot benchmarks/bem_time_vs_accuracy.png --sizes

Prints one table row per (size, code): N, iterations, seconds (wall and CPU), peak memory,
contact fraction, errors vs the reference, ratio of the peer's time to bem's, and for bem the
time per iteration over the time of two FFT convolutions (``t_it/2conv``) and the solve time over
the time spent in its convolutions, timed inside the solve (``t/t_fft``: 1 would mean the vector
work is free).

Issue-10 columns, for the two bem rows ``bem`` (``precision="auto"``: float32 transforms, then
float64, from 512^2 on) and ``bem f64`` (float64 throughout): ``conv/it`` = FFTs per iteration / 2
(3 was the former loop: preconditioner, K t and u = K p after a contact-set change; the inverse
of K t is now skipped when u = K p is recomputed), ``f32 %`` the share of the FFTs done in
float32, ``2conv64 s`` the FFT floor measured in the same worker (two bare float64 convolutions
of the solver's operator, its own backend and threads), and ``t_it/2conv`` the time per
iteration over it. ``--paper`` adds the paper-scale row: ``asperity.topo.synthetic.paper_like``
at 5000^2 (2 um), E* = 2.133 MPa, 2.08 N, tol 1e-6, both bem rows (minutes and ~3 GiB each).
"""

from __future__ import annotations

import os

# pin BLAS before numpy loads (an unpinned OpenBLAS made 2-thread runs slower here); OpenMP
# threads of pyFFTW must not spin on a shared machine. OMP_NUM_THREADS is left alone: the
# pyFFTW wheel threads through OpenMP and OMP_NUM_THREADS=1 would silently serialise FFTW.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import json  # noqa: E402
import re  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MEAN_PRESSURE = 0.04
TOL = 1e-8

# ------------------------------------------------------------------------------------------
# workers (each runs in its own subprocess and prints one JSON line)
# ------------------------------------------------------------------------------------------

BEM_WORKER = r"""
import json, os, resource, sys, time
sys.path.insert(0, {root!r})
import numpy as np
from asperity.bem import SolverOptions, solve_contact
from asperity.bem.elastic.operators import influence_operator as _operator
h = np.load({surface!r})
n = h.shape[0]
dx, e_star = {dx!r}, {e_star!r}
t0 = time.perf_counter()
op = _operator(h.shape, dx, dx, e_star, "point", True, "auto", None)
setup = time.perf_counter() - t0
x = op.empty(); x[...] = h; y = op.empty()
conv = []
for _ in range(5):
    t1 = time.perf_counter(); op(x, y); conv.append(time.perf_counter() - t1)
c0 = time.process_time()
res = solve_contact(h, dx, dx, e_star, mean_pressure={p},
                    options=SolverOptions(tol={tol}, max_iter=20000, coarse_start={coarse},
                                          precision={precision!r}))
cpu = time.process_time() - c0
if {save!r}:
    np.save({save!r}, res.pressure)
    np.save({save!r}.replace(".npy", "_history.npy"), res.residual_history)
print(json.dumps(dict(nit=res.nit, seconds=res.seconds, setup=setup, conv=float(np.median(conv)),
    cpu=cpu, convolutions=res.extra["convolutions"], fft_seconds=res.extra["fft_seconds"],
    transforms=res.extra["fft_transforms"], f32=res.extra["single_precision_transforms"],
    dropped=res.extra["preconditioner_dropped_at"],
    backend=op.backend, threads=op.threads, converged=res.converged, message=res.message,
    contact_fraction=res.contact_fraction,
    peak_mib=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)))
"""

TAMAAS_WORKER = r"""
import json, resource, time
import numpy as np
import tamaas as tm
h = np.load({surface!r})
n = h.shape[0]
model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [float(n), float(n)], [n, n])
model.E = 1.0
model.nu = 0.0
solver = tm.PolonskyKeerRey(model, h, {tol})
solver.max_iter = 20000
t0 = time.perf_counter()
c0 = time.process_time()
solver.solve({p})
seconds = time.perf_counter() - t0
cpu = time.process_time() - c0
p = np.array(model.traction).reshape(h.shape)
np.save({save!r}, p)
print(json.dumps(dict(nit=-1, seconds=seconds, cpu=cpu, contact_fraction=float((p > 0).mean()),
    peak_mib=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)), flush=True)
"""

CM_WORKER = r"""
import json, resource, sys, time
import numpy as np
from ContactMechanics import PeriodicFFTElasticHalfSpace
from ContactMechanics.Optimization.ConstrainedConjugateGradients import (
    constrained_conjugate_gradients)
from SurfaceTopography import Topography
h = np.load({surface!r})
n = h.shape[0]
substrate = PeriodicFFTElasticHalfSpace((n, n), 1.0, physical_sizes=(float(n), float(n)))
topography = Topography(h, physical_sizes=(float(n), float(n)), periodic=True)
pentol = {tol} * float(np.sqrt(np.mean((h - h.mean()) ** 2)))
t0 = time.perf_counter()
c0 = time.process_time()
res = constrained_conjugate_gradients(substrate, topography, external_force={p} * n * n,
                                      pentol=pentol, maxiter=20000)
seconds = time.perf_counter() - t0
cpu = time.process_time() - c0
forces = np.asarray(res.jac).reshape(h.shape)
np.save({save!r}, forces)
print(json.dumps(dict(nit=int(res.nit), seconds=seconds, cpu=cpu,
    contact_fraction=float((forces > 0).mean()), converged=bool(res.success),
    peak_mib=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)))
"""


def _run_worker(python: str, code: str, timeout: float) -> dict | None:
    try:
        proc = subprocess.run(
            [python, "-c", code], capture_output=True, text=True, timeout=timeout, check=False
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        print(f"  worker failed: {exc}", file=sys.stderr)
        return None
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr or proc.stdout)[-800:]
        print(f"  worker failed (rc {proc.returncode}): {tail}", file=sys.stderr)
        return None
    out = json.loads(lines[-1])
    if out.get("nit") == -1:
        # Tamaas logs "iteration cost error" rows from C++ on stdout: the last one counts
        iters = re.findall(r"^\s*(\d+)\s+\S+\s+\S+\s*$", proc.stdout + proc.stderr, re.M)
        out["nit"] = int(iters[-1]) if iters else -1
    return out


def _peer_available(python: str, module: str) -> bool:
    if not Path(python).exists():
        return False
    proc = subprocess.run([python, "-c", f"import {module}"], capture_output=True, check=False)
    return proc.returncode == 0


def _errors(pressure: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    d_cf = abs(float((pressure > 0).mean()) - float((reference > 0).mean()))
    rel = float(np.linalg.norm(pressure - reference) / np.linalg.norm(reference))
    return d_cf, rel


def _bem_rows(surface, dx, e_star, p, tol, save_stem, reference, timeout, coarse, n) -> list:
    """The two bem rows (precision auto and float64) for one surface, with the issue-10
    columns and the errors against ``reference`` (a pressure array or None)."""
    rows = []
    for code, precision in (("bem", "auto"), ("bem f64", "double")):
        save = f"{save_stem}_{precision}.npy"
        got = _run_worker(
            sys.executable,
            BEM_WORKER.format(
                root=str(ROOT),
                surface=str(surface),
                dx=dx,
                e_star=e_star,
                p=p,
                tol=tol,
                save=save,
                coarse=repr(coarse),
                precision=precision,
            ),
            timeout,
        )
        if got is None:
            continue
        got.update(code=code, n=n)
        if reference is not None:
            got["d_cf"], got["p_err"] = _errors(np.load(save), reference)
        nit = max(got["nit"], 1)
        got["per_iter_over_2conv"] = got["seconds"] / nit / (2 * got["conv"])
        got["over_fft"] = got["seconds"] / got["fft_seconds"]
        got["conv_per_it"] = got["transforms"] / 2 / nit
        got["f32_share"] = got["f32"] / max(got["transforms"], 1)
        rows.append(got)
    return rows


def run_sizes(
    sizes, peer_python, with_peers, timeout, coarse, with_reference=True, crop_fast=False
) -> list[dict]:
    sys.path.insert(0, str(HERE))
    from bem_surfaces import self_affine_periodic

    peers = _peers(peer_python, with_peers)
    rows = []
    tmp = Path(tempfile.mkdtemp(prefix="bem_speed_"))
    for n in sizes:
        h = self_affine_periodic(n, hurst=0.8, short_cutoff_px=8.0, rms_slope=1.0, seed=0)
        if crop_fast:
            from asperity.bem import crop_to_fast_size

            h = np.ascontiguousarray(crop_to_fast_size(h))  # warns what was cut
            print(f"# N={n}: cropped to {h.shape[0]} x {h.shape[1]} (fast FFT size)")
        surface = tmp / f"surface_{n}.npy"
        np.save(surface, h)
        ref_path = tmp / f"ref_{n}.npy"
        ref = None
        if with_reference:
            ref = _run_worker(
                sys.executable,
                BEM_WORKER.format(
                    root=str(ROOT),
                    surface=str(surface),
                    dx=1.0,
                    e_star=1.0,
                    p=MEAN_PRESSURE,
                    tol=1e-12,
                    save=str(ref_path),
                    coarse=repr(coarse),
                    precision="double",
                ),
                timeout,
            )
        reference = np.load(ref_path) if ref else None
        mine = _bem_rows(
            surface,
            1.0,
            1.0,
            MEAN_PRESSURE,
            TOL,
            str(tmp / f"bem_{n}"),
            reference,
            timeout,
            coarse,
            n,
        )
        if not mine:
            continue
        rows.extend(mine)
        for name, worker in peers.items():
            out = tmp / f"{name}_{n}.npy"
            got = _run_worker(
                peer_python,
                worker.format(surface=str(surface), p=MEAN_PRESSURE, tol=TOL, save=str(out)),
                timeout,
            )
            if got is None:
                continue
            got.update(code=name, n=n, ratio=got["seconds"] / mine[0]["seconds"])
            if reference is not None:
                # ContactMechanics returns pixel forces = pressure x pixel area (1)
                got["d_cf"], got["p_err"] = _errors(np.load(out), reference)
            rows.append(got)
        _print_rows([r for r in rows if r["n"] == n])
    return rows


def _peers(peer_python: str, with_peers: bool) -> dict:
    peers = {}
    if with_peers:
        for name, module, worker in (
            ("tamaas", "tamaas", TAMAAS_WORKER),
            ("ContactMechanics", "ContactMechanics", CM_WORKER),
        ):
            if _peer_available(peer_python, module):
                peers[name] = worker
            else:
                print(f"# peer {name}: not importable from {peer_python}; column skipped")
    return peers


def run_paper_scale(timeout: float) -> list[dict]:
    """The 5000^2 row: the paper-like surface at 2.08 N, tol 1e-6, both bem rows."""
    from asperity.topo.synthetic import paper_like

    surface = paper_like(n=5000)
    tmp = Path(tempfile.mkdtemp(prefix="bem_speed_paper_"))
    path = tmp / "paper_like_5000.npy"
    np.save(path, np.ascontiguousarray(surface.heights))
    area = surface.heights.size * surface.dx * surface.dy
    rows = _bem_rows(
        path,
        surface.dx,
        2.133e6,
        2.08 / area,
        1e-6,
        str(tmp / "bem"),
        None,
        timeout,
        False,
        5000,
    )
    _print_rows(rows)
    return rows


def _print_rows(rows: list[dict]) -> None:
    print(
        f"{'N':>6} {'code':>17} {'iters':>6} {'seconds':>9} {'cpu s':>8} {'peak MiB':>9} "
        f"{'contact':>9} "
        f"{'|dcf| vs ref':>12} {'p err':>9} {'peer/bem':>9} {'conv/it':>7} {'f32 %':>6} "
        f"{'2conv64 s':>9} {'t_it/2conv':>10} {'t/t_fft':>8}"
    )
    nan = float("nan")
    for r in rows:
        print(
            f"{r['n']:>6} {r['code']:>17} {r['nit']:>6} {r['seconds']:>9.2f} "
            f"{r.get('cpu', nan):>8.2f} {r['peak_mib']:>9.0f} "
            f"{r['contact_fraction']:>9.5f} "
            f"{r.get('d_cf', nan):>12.2e} {r.get('p_err', nan):>9.1e} "
            f"{r.get('ratio', nan):>9.2f} {r.get('conv_per_it', nan):>7.2f} "
            f"{100 * r.get('f32_share', nan):>6.0f} {2 * r.get('conv', nan):>9.3f} "
            f"{r.get('per_iter_over_2conv', nan):>10.2f} "
            f"{r.get('over_fft', nan):>8.2f}"
        )
    for r in rows:
        if r["code"].startswith("bem"):
            print(
                f"# {r['code']} N={r['n']}: backend {r['backend']} x{r['threads']} threads, one "
                f"float64 FFT convolution {r['conv'] * 1e3:.2f} ms (median of 5), "
                f"{r['transforms']} FFTs ({r['f32']} float32), setup {r['setup']:.2f} s, "
                f"{r['message']}"
            )
    sys.stdout.flush()


def hertz_accuracy_plot(path: Path) -> None:
    """Time vs Hertz error: tolerance sweep at fixed mesh and mesh refinement at fixed tol."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from asperity.bem import SolverOptions, solve_contact
    from asperity.bem.reference_solutions import (
        hertz_sphere_contact_radius,
        hertz_sphere_peak_pressure,
        hertz_sphere_pressure,
    )

    R, E, F = 1.0, 1.0, 1e-4
    a = hertz_sphere_contact_radius(F, R, E)
    p0 = hertz_sphere_peak_pressure(F, R, E)

    def case(n, tol):
        box = 4 * a
        dx = box / n
        x = (np.arange(n) - n / 2 + 0.5) * dx
        r = np.hypot(x[:, None], x[None, :])
        h = -(r**2) / (2 * R)
        solve_contact(
            h, dx, dx, E, normal_force=F, periodic=False, options=SolverOptions(tol=tol, max_iter=1)
        )
        t0 = time.perf_counter()
        res = solve_contact(
            h, dx, dx, E, normal_force=F, periodic=False, options=SolverOptions(tol=tol)
        )
        sec = time.perf_counter() - t0
        exact = hertz_sphere_pressure(r, F, R, E)
        inside = r < a
        err = np.sqrt(np.mean((res.pressure[inside] - exact[inside]) ** 2)) / p0
        return sec, err, res.nit

    rows_tol = [(tol, *case(128, tol)) for tol in (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10)]
    rows_n = [(n, *case(n, 1e-10)) for n in (16, 32, 64, 128, 256, 512)]
    print("# Hertz (non-periodic, Love kernel): rms pressure error inside the contact / p0")
    print(f"{'tol':>8} {'N':>5} {'seconds':>9} {'error':>9} {'iters':>6}")
    for tol, sec, err, nit in rows_tol:
        print(f"{tol:>8.0e} {128:>5} {sec:>9.4f} {err:>9.2e} {nit:>6}")
    for n, sec, err, nit in rows_n:
        print(f"{1e-10:>8.0e} {n:>5} {sec:>9.4f} {err:>9.2e} {nit:>6}")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog(
        [r[1] for r in rows_tol],
        [r[2] for r in rows_tol],
        "o-",
        label="tolerance 1e-2 .. 1e-10 (N = 128)",
    )
    ax.loglog(
        [r[1] for r in rows_n], [r[2] for r in rows_n], "s-", label="grid N = 16 .. 512 (tol 1e-10)"
    )
    for n, sec, err, _ in rows_n:
        ax.annotate(str(n), (sec, err), textcoords="offset points", xytext=(4, 4), fontsize=7)
    ax.set_xlabel("solve time (s)")
    ax.set_ylabel("rms pressure error in contact / $p_0$ (Hertz)")
    ax.set_title("bem: time vs accuracy (Hertz sphere, 4a box)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"# wrote {path}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[512, 1024])
    parser.add_argument("--peer-python", default="/tmp/peers-bem/bin/python")
    parser.add_argument("--no-peers", action="store_true")
    parser.add_argument("--coarse-start", action="store_true", help="bem coarse-grid start")
    parser.add_argument("--no-reference", action="store_true", help="skip the tol 1e-12 solve")
    parser.add_argument(
        "--crop-fast",
        action="store_true",
        help="crop each surface to a fast FFT size (5001 -> 5000)",
    )
    parser.add_argument("--timeout", type=float, default=1800.0, help="per worker (s)")
    parser.add_argument("--hertz-plot", type=Path, default=None, help="write the PNG here")
    parser.add_argument(
        "--paper", action="store_true", help="add the 5000^2 paper-like row (minutes, ~3 GiB)"
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    args = parser.parse_args(argv)
    print(
        f"# bem speed benchmark, {time.strftime('%Y-%m-%d %H:%M:%S')}, load average "
        f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"
    )
    rows = []
    if args.sizes:
        rows = run_sizes(
            args.sizes,
            args.peer_python,
            not args.no_peers,
            args.timeout,
            args.coarse_start,
            not args.no_reference,
            args.crop_fast,
        )
    if args.paper:
        rows += run_paper_scale(args.timeout)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    if args.hertz_plot:
        hertz_accuracy_plot(args.hertz_plot)
    return 0


if __name__ == "__main__":
    sys.exit(main())
