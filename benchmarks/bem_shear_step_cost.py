"""Cost of one mixed-mode shear step against a normal solve and the FFT floor (issue 34 part 4).

A step of :func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve` is one
warm-started problem: the active set (detach, attach, junctions to sliding) iterates on the
state of the previous step, and inside it the load-controlled normal solve (a secant on the
separation, each trial a bound-constrained conjugate-gradient solve started from the last
pressure) and the tangential solve (started from the last shear traction) are warm. This prints,
per grid of the default job's surface (``paper_like``, seed 0, 10 mm map, E* = 2.133 MPa,
w = 0.040 J/m^2, lambda = 0.03, tau_0 = 0.13 MPa, 2.08 N on A_n = 700 mm^2 scaled to the map),
started from the Maugis-Dugdale loading branch (h_0 = 12.5 um, the default job's) as the stage
does:

* the convolutions (conjugate-gradient iterations, one FFT convolution each) of one cold
  normal solve at the load (non-adhesive, then the Maugis-Dugdale solve from it);
* per shear step, its convolutions, and that over the cold normal solve's: the normal-solve
  equivalents of a step;
* the seconds per step over the seconds of one bare FFT convolution of the shear solver's
  operator measured in the same run (the floor ratio), and over convolutions x floor (the
  overhead of the pointwise work and the set updates).

    python benchmarks/bem_shear_step_cost.py --n 250 500
    python benchmarks/bem_shear_step_cost.py --n 1000 --steps 41
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

E_STAR, W, LAM, TAU0 = 2.133e6, 0.040, 0.03, 0.13e6
SIZE, A_N, F_Z, H0 = 10e-3, 700e-6, 2.08, 12.5e-6


def _floor_seconds(shape: tuple[int, int], dx: float) -> float:
    """Median seconds of one convolution by the shear solver's normal operator."""
    from asperity.bem.shear.stick_slip import TangentialOperator

    op = TangentialOperator(shape, dx, dx, E_STAR, normal=True)
    x = np.random.default_rng(0).standard_normal(shape)
    op(x)
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        op(x)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _row(n: int, steps: int, end: float) -> dict:
    from asperity.bem import solve_contact
    from asperity.bem.shear.mixed_mode import MixedModeLaw
    from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
    from asperity.bem.shear.stick_slip import ShearOptions
    from asperity.topo.synthetic import paper_like

    dx = SIZE / n
    h = np.asarray(paper_like(n=n, pixel_size=dx, seed=0).heights, dtype=np.float64)
    h = h - h.mean()
    force = F_Z * SIZE * SIZE / A_N
    t0 = time.perf_counter()
    plain = solve_contact(h, dx, dx, E_STAR, normal_force=force)
    md = solve_contact(
        h, dx, dx, E_STAR, normal_force=force, work_of_adhesion=W,
        initial=dataclasses.replace(plain, normal_force=force), adhesion="maugis",
        adhesion_range=H0,
    )  # fmt: skip
    normal_s = time.perf_counter() - t0
    normal_conv = int(plain.extra.get("convolutions", plain.nit)) + int(
        md.extra.get("convolutions", md.nit)
    )
    curve = mixed_mode_shear_curve(
        h, dx, dx, E_STAR, force, np.linspace(0.0, end, steps), MixedModeLaw(W, LAM),
        shear_strength=TAU0, options=ShearOptions(tol=1e-6), stop_when_sliding=True,
        initial=md,
    )  # fmt: skip
    floor = _floor_seconds(h.shape, dx)
    sheared = slice(1, None)  # step 0 is the settle of the preload at delta_T = 0
    conv = curve.convolutions[sheared].astype(float)
    secs = curve.seconds[sheared]
    return {
        "n": n,
        "dx_um": dx * 1e6,
        "steps": int(conv.size),
        "slid": bool(curve.sliding[-1]),
        "normal_conv": normal_conv,
        "normal_s": normal_s,
        "conv_per_step": float(conv.mean()),
        "normal_equivalents": float(conv.mean() / normal_conv),
        "s_per_step": float(secs.mean()),
        "floor_s": floor,
        "floor_ratio": float(secs.mean() / floor),
        "overhead": float(secs.sum() / (conv.sum() * floor)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[250, 500], help="pixels a side")
    ap.add_argument("--steps", type=int, default=31)
    ap.add_argument("--to", type=float, default=60e-6, help="last delta_T, m")
    args = ap.parse_args()
    head = (
        f"{'n':>5} {'dx um':>6} {'steps':>5} {'slid':>4} {'normal conv':>11} {'normal s':>8} "
        f"{'conv/step':>9} {'normal eq/step':>14} {'s/step':>7} {'floor s':>8} "
        f"{'floor ratio':>11} {'overhead':>8}"
    )
    print(head)
    for n in args.n:
        r = _row(n, args.steps, args.to)
        print(
            f"{r['n']:>5} {r['dx_um']:>6.1f} {r['steps']:>5} {str(r['slid']):>4} "
            f"{r['normal_conv']:>11} {r['normal_s']:>8.2f} {r['conv_per_step']:>9.1f} "
            f"{r['normal_equivalents']:>14.2f} {r['s_per_step']:>7.3f} {r['floor_s']:>8.5f} "
            f"{r['floor_ratio']:>11.0f} {r['overhead']:>8.2f}"
        )


if __name__ == "__main__":
    main()
