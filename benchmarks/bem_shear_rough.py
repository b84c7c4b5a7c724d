"""The paper's shear experiment in the BEM: a rough surface under load control with the mixed-mode
edge law (E:failure_locus, chi_T = chi), junctions sliding past their instability with tau_0.

The surface is the default job's recipe, ``asperity.topo.synthetic.paper_like(seed=0)`` on a
10 mm square map at ``--n`` pixels (the default job's BEM uses 1000 px of 10 um), with the
default job's material: E* = 2.133 MPa, w = 0.040 J/m^2, lambda = 0.03, tau_0 = 0.13 MPa,
and the normal force at the job's mean pressure (F_z = 2.08 N on A_n = 700 mm^2). The flat moves
along x in ``--steps`` equal steps up to ``--to`` times the sliding estimate
``3 tau_0 a_max / E*`` (or until every junction slides).

Prints per step delta_T, F_x, A_r, the stick (adhesive) and sliding areas, the junction counts;
then the static peak F_s (largest F_x before gross sliding), the sliding force F_d (last step),
F_s / F_d, the area drop A_r(peak) / A_r(0), and the times.

    python benchmarks/bem_shear_rough.py --n 128
    python benchmarks/bem_shear_rough.py --n 250 --steps 60
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np


def main() -> None:
    from asperity.bem.shear.mixed_mode import MixedModeLaw
    from asperity.bem.shear.rough import label_junctions
    from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
    from asperity.bem.shear.stick_slip import ShearOptions
    from asperity.topo.synthetic import paper_like

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=128, help="pixels per side of the 10 mm map")
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--to", type=float, default=3.0, help="last delta_T over the estimate")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--lam", type=float, default=0.03)
    args = ap.parse_args()

    e_star, w, tau0 = 2.133e6, 0.040, 0.13e6
    size = 10e-3
    dx = size / args.n
    surface = paper_like(n=args.n, pixel_size=dx, seed=0)
    h = np.asarray(surface.heights, dtype=np.float64)
    h = h - h.mean()
    force = 2.08 * size * size / 700e-6
    from asperity.bem import solve_contact

    plain = solve_contact(h, dx, dx, e_star, normal_force=force)
    labels, n = label_junctions(plain.contact_mask)
    a_max = math.sqrt(np.bincount(labels.ravel())[1:].max() * dx * dx / math.pi)
    d_t = np.linspace(0.0, args.to * 3 * tau0 * a_max / e_star, args.steps + 1)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = mixed_mode_shear_curve(
            h,
            dx,
            dx,
            e_star,
            force,
            d_t,
            MixedModeLaw(w, args.lam),
            shear_strength=tau0,
            options=ShearOptions(tol=args.tol),
            stop_when_sliding=True,
        )
    total = time.perf_counter() - t0
    for warning in caught:
        print("warning:", warning.message)
    print(
        f"{args.n}^2 px of {dx * 1e6:.1f} um, F_z = {force:.4g} N, non-adhesive A_r = "
        f"{plain.real_area * 1e6:.4g} mm^2 in {n} junctions; lambda = {args.lam}"
    )
    print(
        f"{'delta_T um':>10} {'F_x N':>10} {'A_r mm2':>9} {'stick':>9} {'slide':>9} "
        f"{'junct':>5} {'sliding':>7} {'nit':>4} {'s':>6}"
    )
    for i in range(c.tangential_displacement.size):
        print(
            f"{c.tangential_displacement[i] * 1e6:10.3f} {c.tangential_force[i]:10.4g} "
            f"{c.real_area[i] * 1e6:9.4g} {c.stick_area[i] * 1e6:9.4g} "
            f"{c.slip_area[i] * 1e6:9.4g} {c.junctions[i]:5d} {c.sliding_junctions[i]:7d} "
            f"{c.nit[i]:4d} {c.seconds[i]:6.2f} {bool(c.converged[i])}"
        )
    before = np.flatnonzero(~c.sliding)
    peak = int(before[np.argmax(c.tangential_force[before])]) if before.size else 0
    f_s, f_d = c.tangential_force[peak], c.tangential_force[-1]
    print(
        f"static peak F_s = {f_s:.4g} N at delta_T = {c.tangential_displacement[peak] * 1e6:.3g} "
        f"um; sliding F_d = {f_d:.4g} N (gross sliding: {bool(c.sliding[-1])}); F_s/F_d = "
        f"{f_s / f_d:.3f}; A_r(peak)/A_r(0) = {c.real_area[peak] / c.real_area[0]:.3f}; "
        f"A_r(end)/A_r(0) = {c.real_area[-1] / c.real_area[0]:.3f}"
    )
    print(
        f"time: preload {c.normal_seconds:.2f} s, curve {total:.2f} s "
        f"({c.tangential_displacement.size} steps), converged {c.success}"
    )


if __name__ == "__main__":
    main()
