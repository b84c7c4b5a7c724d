"""The fold of Papangelo-Ciavarella's sphere in fixed grip, converged (issue 34 part 3).

xi = 100, indentation 3 R / xi^2, lambda = 0.2, tau_0 = 1e-3 E* (dimensionless: R = E* = 1,
w = 1e-6); the free grid spans 2.25 JKR radii. For each mesh (elements per JKR radius) it prints
the last delta_T / delta_T^max with a stick state (E:max_disp_PC), the first without, the
largest |T / T_PC - 1| up to 0.9 delta_T^max (E:PC_T), the preload's errors (E:JKR_indent,
E:JKR_load) and the wall time. Path: 0.1 to 0.9 by 0.1, then 0.92 by 0.01.

    python benchmarks/bem_shear_fold.py --n-per 24 48 64 --to 1.03
"""

import argparse
import math
import time

import numpy as np


def fold_row(n_per: int, end: float, lam: float) -> dict:
    """One mesh: the sweep and its comparison with the closed forms (SI units, scaled)."""
    from asperity.bem.reference_solutions import pc_sphere
    from asperity.bem.shear.mixed_mode import MixedModeLaw, tangential_sweep
    from asperity.bem.shear.stick_slip import ShearOptions
    from asperity.statmodel.jkr import jkr_contact_radius, jkr_normal_load

    r, e_star, w = 1.0, 1.0, 1e-6
    delta = 3.0 * r / 100**2
    a_jkr = float(jkr_contact_radius(delta, r, w, e_star))
    dx = a_jkr / n_per
    n = int(2.25 * n_per) + 2
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    d_max = pc_sphere(delta, 0.0, r, w, e_star, lam).max_tangential_displacement
    path = np.r_[np.arange(0.1, 0.91, 0.1), np.arange(0.92, end + 1e-9, 0.01)]
    t0 = time.perf_counter()
    sweep = tangential_sweep(
        -(xx**2 + yy**2) / (2 * r),
        dx,
        dx,
        e_star,
        -delta,
        path * d_max,
        MixedModeLaw(w, lam),
        preload_separation=-((1.1 * a_jkr) ** 2) / r,
        shear_strength=1e-3 * e_star,
        options=ShearOptions(tol=1e-6),
    )
    seconds = time.perf_counter() - t0
    errors = [
        s.tangential_force
        / pc_sphere(delta, s.tangential_displacement, r, w, e_star, lam).tangential_force
        - 1.0
        for f, s in zip(path, sweep.states, strict=False)
        if f <= 0.905
    ]
    jump = sweep.jump_index
    return {
        "n_per": n_per,
        "grid": n,
        "last_stick": float(path[jump - 1]) if jump else math.nan,
        "lost": float(path[jump]) if jump is not None else math.nan,
        "t_error": float(np.max(np.abs(errors))),
        "preload_a": sweep.preload.contact_radius / a_jkr - 1.0,
        "preload_p": sweep.preload.normal_force / float(jkr_normal_load(delta, r, w, e_star)) - 1,
        "seconds": seconds,
        "converged": sweep.success,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-per", type=int, nargs="+", default=[24, 48])
    ap.add_argument("--to", type=float, default=1.03, help="last delta_T / delta_T^max")
    ap.add_argument("--lam", type=float, default=0.2)
    args = ap.parse_args()
    print("el/radius grid  last-stick  lost  max|T err|<=0.9  preload a  preload P  seconds")
    for n_per in args.n_per:
        r = fold_row(n_per, args.to, args.lam)
        print(
            f"{r['n_per']:9d} {r['grid']:4d}  {r['last_stick']:10.2f} {r['lost']:5.2f}"
            f"  {r['t_error']:15.2%}  {r['preload_a']:+9.2%}  {r['preload_p']:+9.2%}"
            f"  {r['seconds']:7.1f}{'' if r['converged'] else '  (a solve did not converge)'}",
            flush=True,
        )


if __name__ == "__main__":
    main()
