"""Speed of the shear BEM: a 100-step shear curve against one normal solve of the same grid.

The surface is the default job's: ``asperity.topo.synthetic.paper_like(n=1000, pixel_size=10e-6,
seed=0)`` (10 mm square, periodic), E* = 2.133 MPa, tau_0 = 0.13 MPa, the normal force at the
job's mean pressure F_z / A_n (F_z = 2.08 N, A_n = 700 mm^2) on the map, non-adhesive preload
(nu = 1/2: the tangential steps do not change it). The curve has ``--steps`` equal increments
up to ``--to-sliding`` times the estimate ``delta_slide = 3 tau_0 a_max / E*`` (a_max: radius of
the largest junction), warm-started.

Per tolerance the table gives: the normal solve's time (tol 1e-6, the job's; a cold-started
solve in a process that already solved once, so that compiling and FFT planning are not counted;
shared by every curve as the preload), the curve's total time, their ratio
(the issue's target: within 10x), iterations and FFT convolutions per step, the time per
convolution inside the steps against a bare convolution of the same operator (``t_conv/floor``:
1 means the vector work around the FFTs is free), and the accuracy: the largest F_x difference
along the curve from a reference curve at ``--reference-tol``, over tau_0 A_r.

Run (serialise timings on the shared machine):

    flock /tmp/asperity-bench.lock python benchmarks/bem_shear.py
    python benchmarks/bem_shear.py --n 250 --tols 1e-4 1e-6 1e-8
    python benchmarks/bem_shear.py --n 1000 --tols 1e-6 --reference-tol 0   # timings only
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def main() -> None:
    from asperity.bem import SolverOptions
    from asperity.bem.rough_shear import label_junctions, shear_curve
    from asperity.bem.shear import ShearOptions, TangentialOperator
    from asperity.topo.synthetic import paper_like

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="pixels per side (10 mm map)")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--tols", type=float, nargs="+", default=[1e-6])
    ap.add_argument(
        "--reference-tol", type=float, default=1e-9, help="0: no reference (timings only)"
    )
    ap.add_argument("--to-sliding", type=float, default=1.5)
    ap.add_argument("--threads", type=int, default=None)
    args = ap.parse_args()

    e_star, tau0, f_z, a_n = 2.133e6, 0.13e6, 2.08, 700e-6
    pixel = 10e-3 / args.n
    hm = paper_like(n=args.n, pixel_size=pixel, seed=0)
    h = np.asarray(hm.heights, dtype=np.float64)
    h = h - h.mean()
    side = args.n * pixel
    force = f_z * side * side / a_n
    nopts = SolverOptions(tol=1e-6, threads=args.threads)

    # the displacement range from the preload's largest junction
    from asperity.bem import solve_contact

    # a first solve loads the compiled kernels and plans the FFTs; the second, cold-started in
    # the warm process, is the reference time
    solve_contact(h, pixel, pixel, e_star, normal_force=force, options=nopts)
    t0 = time.perf_counter()
    pre = solve_contact(h, pixel, pixel, e_star, normal_force=force, options=nopts)
    normal_seconds = time.perf_counter() - t0
    labels, n_j = label_junctions(pre.contact_mask)
    a_max = math.sqrt(np.bincount(labels.ravel())[1:].max() * pixel * pixel / math.pi)
    d_slide = 3 * tau0 * a_max / e_star
    d_t = np.linspace(0, 1, args.steps + 1)[1:] * args.to_sliding * d_slide
    print(
        f"grid {args.n}^2 ({pixel * 1e6:.1f} um), A_r/A_n {pre.contact_fraction:.5f}, "
        f"{n_j} junctions, a_max {a_max * 1e6:.1f} um, delta_T up to {d_t[-1] * 1e6:.2f} um; "
        f"normal solve {normal_seconds:.2f} s ({pre.nit} iterations)",
        flush=True,
    )

    op = TangentialOperator(h.shape, pixel, pixel, e_star, threads=args.threads)
    x = np.random.default_rng(0).normal(size=h.shape)
    op(x)
    t0 = time.perf_counter()
    reps = 10
    for _ in range(reps):
        op(x)
    floor = (time.perf_counter() - t0) / reps

    def run(tol: float):
        return shear_curve(
            h,
            pixel,
            pixel,
            e_star,
            force,
            d_t,
            shear_strength=tau0,
            normal_options=SolverOptions(tol=tol if tol >= 1e-8 else 1e-8, threads=args.threads),
            options=ShearOptions(tol=tol, threads=args.threads),
        )

    ref = run(args.reference_tol) if args.reference_tol > 0 else None
    scale = tau0 * pre.real_area
    if ref is not None:
        sliding_at = np.flatnonzero(ref.sliding)
        print(
            f"reference (tol {args.reference_tol:g}): peak F_x {ref.tangential_force.max():.4g} N"
            f" = {ref.tangential_force.max() / scale:.4f} tau_0 A_r; gross sliding from step "
            f"{sliding_at[0] + 1 if sliding_at.size else 'none'}"
        )
    head = (
        f"{'tol':>8} {'normal s':>9} {'curve s':>8} {'ratio':>6} {'it/step':>8} "
        f"{'conv/step':>9} {'t_conv/floor':>12} {'max dF_x/(tau0 A_r)':>20}"
    )
    print(head)
    for tol in args.tols:
        c = run(tol)
        total = float(c.seconds.sum())
        per_conv = total / max(int(c.convolutions.sum()), 1)
        if ref is None:
            err = math.nan
        else:
            err = float(np.max(np.abs(c.tangential_force - ref.tangential_force))) / scale
        print(
            f"{tol:>8.0e} {normal_seconds:>9.2f} {total:>8.2f} {total / normal_seconds:>6.2f} "
            f"{c.nit.mean():>8.1f} {c.convolutions.mean():>9.1f} {per_conv / floor:>12.2f} "
            f"{err:>20.2e}"
        )
        slid = np.flatnonzero(c.sliding)
        print(
            f"         peak F_x {c.tangential_force.max() / scale:.4f} tau_0 A_r, stick area at "
            f"half range {c.stick_area[len(d_t) // 2] / c.real_area[0]:.3f} A_r, gross sliding "
            f"from step {slid[0] + 1 if slid.size else 'none'}, junctions {c.junctions[0]}"
        )


if __name__ == "__main__":
    main()
