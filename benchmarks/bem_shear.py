"""Speed of the shear BEM: a 100-step shear curve against one normal solve of the same grid,
its accuracy against a tight-tolerance reference, and the comparison with Tamaas 2.9's
``PolonskyKeerTan``.

**The curve.** The surface is the default job's: ``asperity.topo.synthetic.paper_like(n,
pixel_size=10 mm / n, seed=0)`` (10 mm square, periodic; the job's BEM grid is n = 1000),
E* = 2.133 MPa, tau_0 = 0.13 MPa, the normal force at the job's mean pressure F_z / A_n
(2.08 N on 700 mm^2), non-adhesive preload (nu = 1/2: the tangential steps do not change it).
``--steps`` equal increments up to ``--to-sliding`` times ``delta_slide = 3 tau_0 a_max / E*``
(a_max: radius of a disc of the largest junction's area), each warm-started
(:func:`asperity.bem.shear.rough.shear_curve`).

Solvers compared (rows of the table):

``legacy``   asperity 0.4.0's curve: :func:`asperity.bem.shear.stick_slip.solve_tangential` per
step (FFT
             convolutions of the whole grid, MPRGP without preconditioner), warm-started by the
             same linear extrapolation;
``fft``      the contact-set loop with FFT products, no preconditioner;
``fft+pc``   the same, preconditioned by junction (:class:`JunctionPreconditioner`);
``dense``    products by the dense matrix on the contact set (:class:`ContactMatrix`), no
             preconditioner;
``dense+pc`` both (the default).

Columns: the normal solve's time (tol 1e-6, the job's; cold-started in a process that already
solved once, so that compiling and FFT planning are not counted, the fastest of three; every
curve shares it as its preload), the curve's time and their ratio (the issue's target: within
10x), the same ratio in CPU time (steadier on a loaded machine), MPRGP iterations
and operator products per step, and the accuracy: the largest difference along the curve from
the reference curve (``dense+pc`` at ``--reference-tol``) of F_x, over tau_0 A_r, and of the
stick area, over A_r. The last lines compare 0.4.0's solver with the new one, both at the
reference tolerance. The chart (``--png``) is CPU time against F_x error, one line per solver
through its tolerances.

**Tamaas** (``--tamaas-n``, 0: skipped; skipped with a note when ``--tamaas-python`` is absent).
Both codes solve the same problem on the same periodic grid: the rough surface above (at
``--tamaas-n`` pixels, the same 10 mm map), nu = 1/2, Coulomb friction with mu =
``--mu``, the mean pressure held, one loading step from the unloaded, slip-free state (no
history): stick elements move with the flat, slip elements carry ``|q| = mu p`` along the slip.
asperity solves the normal problem, then the tangential one
(:func:`asperity.bem.shear.stick_slip.solve_tangential`, tol 1e-9); Tamaas's
``PolonskyKeerTan.solve`` (model
``surface_2d``, E = 3/4 E*, nu = 1/2, both problems together under the Coulomb cone) is given
the mean tractions ``(0.4 mu F_z / A, 0, F_z / A)``. Tamaas's mean tractions are
the loads it reached; asperity is solved at those (the normal solve at its F_z, delta_T by
bisection to its F_x). Printed: contact and slip areas of both, the rms difference of the
tractions over the rms traction, and both times. Tamaas runs in its own interpreter, in a
subprocess, with one OpenMP thread.

Why ``--tamaas-load-factor`` 10 (the mean pressure ten times the job's, contact about 10 % of
the map) and a 64^2 grid: at the job's pressure (contact about 1 %), ``PolonskyKeerTan`` meets
its tolerance with its mean pressure far from the one asked (measured: 1.7 times at 128^2, tol
1e-6; 1.3 times at 64^2, tol 1e-9, even with mu = 0, where Tamaas's own ``PolonskyKeerRey``
holds it to 1e-16): its normal part has not converged there. At ten times the pressure it holds
both mean tractions to 1e-14 at tol 1e-8, in about 20000 iterations (40 s at 64^2 on the
shared machine), which bounds the grid.

Run (serialise timings on the shared machine):

    flock /tmp/asperity-bench.lock python benchmarks/bem_shear.py --n 500
    python benchmarks/bem_shear.py --n 1000 --solvers fft+pc dense+pc --tamaas-n 0
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

E_STAR, TAU0, F_Z, A_N = 2.133e6, 0.13e6, 2.08, 700e-6
SIZE = 10e-3
TAMAAS_PYTHON = "/work/venv-tamaas/bin/python"
SOLVERS = ("legacy", "fft", "fft+pc", "dense", "dense+pc")

#: Run by Tamaas's interpreter: argv = heights.npy, pixel (m), E* (Pa), mu, mean tractions
#: t_x, t_z (Pa), tol, max_iter, output .npy; prints seconds and the final error as JSON.
TAMAAS_SCRIPT = """
import json, sys, time
import numpy as np
import tamaas as tm
heights_file, dx, e_star, mu, tx, tz, tol, max_iter, out = sys.argv[1:10]
h = np.load(heights_file)
n = h.shape[0]
size = n * float(dx)
model = tm.ModelFactory.createModel(tm.model_type.surface_2d, [size, size], [n, n])
model.E, model.nu = 0.75 * float(e_star), 0.5
solver = tm.PolonskyKeerTan(model, np.ascontiguousarray(h - h.max()), float(tol), float(mu))
solver.max_iter = int(max_iter)
t0 = time.perf_counter()
error = solver.solve([float(tx), 0.0, float(tz)])
seconds = time.perf_counter() - t0
np.save(out, np.array(model.traction))
print(json.dumps({"seconds": seconds, "error": float(error)}))
"""


def surface(n: int) -> tuple[np.ndarray, float, float]:
    """Heights (m, zero mean), pixel (m) and F_z (N) of the default job's map at n pixels."""
    from asperity.topo.synthetic import paper_like

    pixel = SIZE / n
    h = np.array(paper_like(n=n, pixel_size=pixel, seed=0).heights, dtype=np.float64)
    return h - h.mean(), pixel, F_Z * SIZE * SIZE / A_N


def legacy_curve(h, pixel, pre, d_t, tol: float):
    """asperity 0.4.0's curve: solve_tangential per step, warm-started by linear extrapolation
    of the tractions (the loop of 0.4.0's rough_shear.shear_curve). Returns (F_x, stick area,
    iterations, products, seconds)."""
    from asperity.bem.shear.stick_slip import (
        ShearOptions,
        TangentialOperator,
        solve_tangential,
        traction_bound,
    )

    t0 = time.perf_counter()
    contact = pre.contact_mask
    bound = traction_bound(contact, shear_strength=TAU0)
    op = TangentialOperator(h.shape, pixel, pixel, E_STAR)
    opts = ShearOptions(tol=tol)
    prev = older = None
    force, stick, nit, conv = [], [], 0, 0
    for value in d_t:
        guess = None
        if prev is not None and older is not None:
            span = prev.tangential_displacement - older.tangential_displacement
            rate = (value - prev.tangential_displacement) / span
            guess = prev.traction + rate * (prev.traction - older.traction)
        elif prev is not None:
            guess = prev.traction
        step = solve_tangential(
            contact,
            bound,
            pixel,
            pixel,
            E_STAR,
            float(value),
            slip=None if prev is None else prev.slip,
            initial=guess,
            options=opts,
            operator=op,
        )
        force.append(step.tangential_force)
        stick.append(step.stick_area)
        nit += step.nit
        conv += step.convolutions
        older, prev = prev, step
    return np.array(force), np.array(stick), nit, conv, time.perf_counter() - t0


def new_curve(h, pixel, force, pre, d_t, tol: float, solver: str):
    """shear_curve with the solver's options. Returns as :func:`legacy_curve`."""
    from asperity.bem.shear.rough import shear_curve
    from asperity.bem.shear.stick_slip import ShearOptions

    dense = solver.startswith("dense")
    opts = ShearOptions(
        tol=tol,
        dense_limit_bytes=ShearOptions().dense_limit_bytes if dense else 0,
        precondition=solver.endswith("+pc"),
    )
    t0 = time.perf_counter()
    c = shear_curve(
        h, pixel, pixel, E_STAR, force, d_t, shear_strength=TAU0, preload=pre, options=opts
    )
    seconds = time.perf_counter() - t0
    if not c.success:
        print(f"  ({solver}, tol {tol:g}: {int((~c.converged).sum())} steps not converged)")
    return c.tangential_force, c.stick_area, int(c.nit.sum()), int(c.convolutions.sum()), seconds


def run_curve(solver, h, pixel, force, pre, d_t, tol):
    if solver == "legacy":
        return legacy_curve(h, pixel, pre, d_t, tol)
    return new_curve(h, pixel, force, pre, d_t, tol, solver)


def speed(args) -> None:
    from asperity.bem import SolverOptions, solve_contact
    from asperity.bem.shear.rough import label_junctions

    h, pixel, force = surface(args.n)
    nopts = SolverOptions(tol=1e-6)
    # the first solve compiles the kernels and plans the FFTs; the second, cold-started in the
    # warm process, is the reference time
    solve_contact(h, pixel, pixel, E_STAR, normal_force=force, options=nopts)
    normal_seconds = normal_cpu = math.inf
    for _ in range(3):  # the fastest of three: the machine is shared
        t0, c0 = time.perf_counter(), time.process_time()
        pre = solve_contact(h, pixel, pixel, E_STAR, normal_force=force, options=nopts)
        normal_seconds = min(normal_seconds, time.perf_counter() - t0)
        normal_cpu = min(normal_cpu, time.process_time() - c0)
    labels, n_j = label_junctions(pre.contact_mask)
    sizes = np.bincount(labels.ravel())[1:]
    a_max = math.sqrt(sizes.max() * pixel * pixel / math.pi)
    d_t = np.linspace(0, 1, args.steps + 1)[1:] * args.to_sliding * 3 * TAU0 * a_max / E_STAR
    print(
        f"grid {args.n}^2 ({pixel * 1e6:.1f} um), {int(pre.contact_mask.sum())} contact elements "
        f"(A_r/A_n {pre.contact_fraction:.5f}) in {n_j} junctions (largest {sizes.max()}), "
        f"delta_T up to {d_t[-1] * 1e6:.2f} um in {args.steps} steps; normal solve "
        f"{normal_seconds:.2f} s wall, {normal_cpu:.2f} s CPU ({pre.nit} iterations)",
        flush=True,
    )
    # compile the numba kernels on a small case before anything is timed
    new_curve(h, pixel, force, pre, d_t[:2], 1e-4, "dense+pc")
    ref_f, ref_s, _, _, ref_t = run_curve("dense+pc", h, pixel, force, pre, d_t, args.reference_tol)
    scale_f, area = TAU0 * pre.real_area, pre.real_area
    print(
        f"reference: dense+pc at tol {args.reference_tol:g}, {ref_t:.2f} s; peak F_x "
        f"{ref_f.max():.5g} N = {ref_f.max() / scale_f:.4f} tau_0 A_r"
    )
    head = (
        f"{'size':>5} {'steps':>5} {'solver':>9} {'tol':>6} {'curve s':>8} {'/normal':>7} "
        f"{'CPU /normal':>11} "
        f"{'it/step':>7} {'prod/step':>9} {'max dF_x/(tau0 A_r)':>19} {'max dA_stick/A_r':>16}"
    )
    print(head)
    points: dict[str, list[tuple[float, float, float]]] = {}
    for solver in args.solvers:
        for tol in args.tols:
            if solver == "legacy" and args.n > args.legacy_max_n:
                continue
            c0 = time.process_time()
            f, s, nit, conv, seconds = run_curve(solver, h, pixel, force, pre, d_t, tol)
            cpu = time.process_time() - c0
            err_f = float(np.max(np.abs(f - ref_f))) / scale_f
            err_s = float(np.max(np.abs(s - ref_s))) / area
            points.setdefault(solver, []).append((cpu, max(err_f, 1e-16), tol))
            print(
                f"{args.n:>5} {args.steps:>5} {solver:>9} {tol:>6.0e} {seconds:>8.2f} "
                f"{seconds / normal_seconds:>7.2f} {cpu / normal_cpu:>11.2f} "
                f"{nit / args.steps:>7.2f} "
                f"{conv / args.steps:>9.2f} {err_f:>19.2e} {err_s:>16.2e}",
                flush=True,
            )
    if "legacy" in args.solvers and args.n <= args.legacy_max_n:
        f, s, *_ = run_curve("legacy", h, pixel, force, pre, d_t, args.reference_tol)
        print(
            f"0.4.0's solver against the new one, both at tol {args.reference_tol:g}: max |dF_x| "
            f"{np.max(np.abs(f - ref_f)) / scale_f:.2e} tau_0 A_r, max |d stick area| "
            f"{np.max(np.abs(s - ref_s)) / area:.2e} A_r (A_r is the preload's, held)"
        )
    if args.png:
        chart(points, args, normal_cpu)


def chart(points, args, normal_cpu: float) -> None:
    """Time (CPU: steadier than wall time on a shared machine) against the F_x error."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for solver, pts in points.items():
        t, e, tols = zip(*pts, strict=True)
        ax.loglog(t, e, "o-", label=solver)
        for ti, ei, tol in zip(t, e, tols, strict=True):
            ax.annotate(
                f"{tol:.0e}", (ti, ei), fontsize=7, xytext=(3, 3), textcoords="offset points"
            )
    ax.axvline(10 * normal_cpu, color="k", ls="--", lw=0.8)
    ax.text(10 * normal_cpu, ax.get_ylim()[1], " 10 normal solves", va="top", fontsize=8)
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(f"CPU time of the {args.steps}-step curve (s)")
    ax.set_ylabel("max |F_x - F_x,ref| / (tau_0 A_r)")
    ax.set_title(f"shear curve, default job's surface at {args.n}^2 (labels: tol)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.png, dpi=150)
    print(f"chart: {args.png}")


def tamaas(args) -> None:
    """The Tamaas comparison (module docstring)."""
    from asperity.bem import SolverOptions, solve_contact
    from asperity.bem.shear.stick_slip import ShearOptions, solve_tangential, traction_bound

    if not Path(args.tamaas_python).exists():
        print(f"Tamaas comparison skipped: {args.tamaas_python} not found")
        return
    n = args.tamaas_n
    h, pixel, force = surface(n)
    a = SIZE * SIZE
    el = pixel * pixel
    with tempfile.TemporaryDirectory() as tmp:
        hf, out = Path(tmp) / "h.npy", Path(tmp) / "t.npy"
        np.save(hf, h)
        f_asked = args.tamaas_load_factor * force
        asked = (0.4 * args.mu * f_asked / a, f_asked / a)
        argv = [hf, pixel, E_STAR, args.mu, *asked, args.tamaas_tol, 20000, out]
        env = {**os.environ, "OMP_NUM_THREADS": "1"}
        try:
            proc = subprocess.run(
                [args.tamaas_python, "-c", TAMAAS_SCRIPT, *map(str, argv)],
                capture_output=True,
                text=True,
                env=env,
                timeout=args.tamaas_timeout,
            )
        except subprocess.TimeoutExpired:
            print(f"Tamaas comparison: no answer within {args.tamaas_timeout} s")
            return
        if proc.returncode != 0:
            print("Tamaas comparison failed:", proc.stderr.strip().splitlines()[-1:])
            return
        info = json.loads(proc.stdout.strip().splitlines()[-1])
        traction = np.load(out)
    p_t, q_t = traction[..., 2], traction[..., 0]
    f_z, f_x = float(p_t.sum() * el), float(q_t.sum() * el)
    # asperity at the loads Tamaas reached: the normal solve at its F_z, then delta_T by
    # bisection until F_x is Tamaas's (F_x grows with delta_T), each a step from rest
    t0 = time.perf_counter()
    pre = solve_contact(h, pixel, pixel, E_STAR, normal_force=f_z, options=SolverOptions(tol=1e-9))
    contact = pre.contact_mask
    bound = traction_bound(contact, pressure=pre.pressure, friction_coefficient=args.mu)
    opts = ShearOptions(tol=1e-9)

    def at(d: float):
        return solve_tangential(contact, bound, pixel, pixel, E_STAR, d, options=opts)

    lo, hi = 0.0, 1e-6
    while at(hi).tangential_force < f_x:
        lo, hi = hi, 2.0 * hi
    solves = 0
    while hi - lo > 1e-12 * hi and solves < 60:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if at(mid).tangential_force < f_x else (lo, mid)
        solves += 1
    ours = at(0.5 * (lo + hi))
    ours_seconds = time.perf_counter() - t0
    c_t = p_t > 0
    # Tamaas's slip elements: the tangential traction on the cone (relative 1e-4)
    slip_t = c_t & (np.hypot(q_t, traction[..., 1]) >= (1 - 1e-4) * args.mu * p_t)
    slip_o = contact & ~ours.stick
    on = contact | c_t
    dq = math.sqrt(float(np.mean((q_t - ours.traction)[on] ** 2)))
    dp = math.sqrt(float(np.mean((p_t - pre.pressure)[on] ** 2)))
    dq_max = float(np.abs(q_t - ours.traction).max()) / (args.mu * float(pre.pressure.max()))
    print(
        f"Tamaas 2.9 PolonskyKeerTan vs asperity, {n}^2 periodic ({pixel * 1e6:.1f} um), "
        f"nu = 1/2, Coulomb mu = {args.mu}, one loading step from rest"
    )
    print(
        f"  loads          asked of Tamaas: F_z {asked[1] * a:.4g} N, F_x {asked[0] * a:.4g} N; "
        f"reached (its mean tractions): F_z {f_z:.4g} N, F_x {f_x:.4g} N "
        f"({f_x / (args.mu * f_z):.3f} mu F_z); asperity solved at those"
    )
    print(
        f"  contact area   asperity {contact.sum() * el * 1e6:.4f} mm^2, Tamaas "
        f"{c_t.sum() * el * 1e6:.4f} mm^2 ({int(contact.sum())} / {int(c_t.sum())} elements, "
        f"{int((contact ^ c_t).sum())} differ)"
    )
    print(
        f"  slip area      asperity {slip_o.sum() * el * 1e6:.4f} mm^2, Tamaas "
        f"{slip_t.sum() * el * 1e6:.4f} mm^2 ({int(slip_o.sum())} / {int(slip_t.sum())} "
        f"elements, {int((slip_o ^ slip_t).sum())} differ)"
    )
    print(
        f"  tractions      on the union of the contacts: rms(q_T - q_A) / rms(q_A) = "
        f"{dq / math.sqrt(float(np.mean(ours.traction[on] ** 2))):.2e}, rms(p_T - p_A) / "
        f"rms(p_A) = {dp / math.sqrt(float(np.mean(pre.pressure[on] ** 2))):.2e}; max |q_T - q_A|"
        f" / (mu max p_A) = {dq_max:.1e}"
    )
    print(
        f"  time           Tamaas {info['seconds']:.2f} s (its error {info['error']:.1e}); "
        f"asperity {ours_seconds:.2f} s for the normal solve and {solves + 2} tangential solves "
        f"of the bisection, {ours.seconds:.3f} s for the last one (tol 1e-9); "
        f"ratio Tamaas / asperity's solve {info['seconds'] / ours.seconds:.0f}"
    )


def _tight():
    from asperity.bem.shear.stick_slip import ShearOptions

    return ShearOptions(tol=1e-8)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="pixels per side (10 mm map); 0: none")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--tols", type=float, nargs="+", default=[1e-4, 1e-6, 1e-8])
    ap.add_argument("--solvers", nargs="+", choices=SOLVERS, default=list(SOLVERS))
    ap.add_argument("--reference-tol", type=float, default=1e-10)
    ap.add_argument("--to-sliding", type=float, default=1.5)
    ap.add_argument(
        "--legacy-max-n", type=int, default=500, help="larger grids skip 0.4.0's solver (slow)"
    )
    ap.add_argument("--png", default="", help="chart of time against accuracy")
    ap.add_argument("--tamaas-n", type=int, default=64, help="0: no Tamaas comparison")
    ap.add_argument("--mu", type=float, default=0.5)
    ap.add_argument(
        "--tamaas-load-factor",
        type=float,
        default=10.0,
        help="F_z of the comparison over the job's (module docstring: why not 1)",
    )
    ap.add_argument("--tamaas-tol", type=float, default=1e-8)
    ap.add_argument("--tamaas-python", default=TAMAAS_PYTHON)
    ap.add_argument("--tamaas-timeout", type=float, default=170.0)
    args = ap.parse_args()
    if args.n:
        speed(args)
    if args.tamaas_n:
        tamaas(args)


if __name__ == "__main__":
    main()
