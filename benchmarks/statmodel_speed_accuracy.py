"""statmodel: time vs accuracy of the fast shear-curve solver against the converged reference.

Case: the issue's TOML (Fig. 4 parameters, 281 steps of delta_T in [0, 14 um]). The reference is
``statmodel.reference`` (adaptive QUADPACK, epsrel 1e-13, brentq separations). For each setting of
the quadrature / tolerance knobs the script times ``shear_curve`` (median of repeated warm calls,
JIT compiled and cached beforehand) and reports the maximum relative error over all steps of F_x
(steps with delta_T > 0), A_r and F_z against the reference, and F_z against the imposed load.
No peer code implements this model (Tamaas, ContactMechanics, SurfaceTopography and slippy have no
Fuller-Tabor/Papangelo-Ciavarella statistical friction model), so the ratio column compares with
the reference solver run in the same process.

Run (timings on one core, serialised with the other contributors)::

    flock /tmp/asperity-bench.lock taskset -c 0 python benchmarks/statmodel_speed_accuracy.py

Writes ``benchmarks/statmodel_speed_accuracy.png`` (or ``--png PATH``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter  # noqa: E402

from asperity.statmodel import Material, Roughness, shear_curve  # noqa: E402
from asperity.statmodel.reference import ReferenceModel  # noqa: E402

MAT = Material(e_star=2.133e6, work_of_adhesion=0.040, mode_mixity=0.2, shear_strength=0.13e6)
ROUGH = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
AREA, LOAD = 700e-6, 3.1
DTS = np.linspace(0.0, 14e-6, 281)

DEFAULT = {"nodes": 16, "panels": 4, "load_rtol": 1e-12}
SETTINGS = [
    {"nodes": 4, "panels": 1, "load_rtol": 1e-6},
    {"nodes": 6, "panels": 1, "load_rtol": 1e-8},
    {"nodes": 8, "panels": 2, "load_rtol": 1e-9},
    {"nodes": 10, "panels": 2, "load_rtol": 1e-10},
    {"nodes": 12, "panels": 3, "load_rtol": 1e-12},
    {"nodes": 16, "panels": 4, "load_rtol": 1e-12},  # default (QuadratureOptions)
    {"nodes": 24, "panels": 6, "load_rtol": 1e-12},
    {"nodes": 32, "panels": 8, "load_rtol": 1e-13},
]


def timed(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--png", type=Path, default=Path(__file__).with_name("statmodel_speed_accuracy.png")
    )
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()

    shear_curve(MAT, ROUGH, AREA, LOAD, DTS)  # JIT (from the on-disk cache after the first run)
    t0 = time.perf_counter()
    _, states = ReferenceModel(MAT, ROUGH, AREA).shear_states(LOAD, DTS)
    t_ref = time.perf_counter() - t0
    fx_ref = np.array([s.tangential_force for s in states])
    ar_ref = np.array([s.real_area for s in states])
    fz_ref = np.array([s.normal_force for s in states])

    rows = []
    for knobs in SETTINGS:
        c = shear_curve(MAT, ROUGH, AREA, LOAD, DTS, **knobs)
        t = timed(lambda k=knobs: shear_curve(MAT, ROUGH, AREA, LOAD, DTS, **k), args.repeats)
        e_fx = np.max(np.abs(c.tangential_force[1:] / fx_ref[1:] - 1))
        e_ar = np.max(np.abs(c.real_area / ar_ref - 1))
        e_fz = np.max(np.abs(c.normal_force / fz_ref - 1))
        e_load = np.max(np.abs(c.normal_force / LOAD - 1))
        rows.append((knobs, t, max(e_fx, e_ar, e_fz), e_fx, e_ar, e_fz, e_load))

    print(
        f"case: 281 steps, F_z = {LOAD} N, A_n = {AREA} m^2 (issue TOML); "
        f"reference (scipy quad, epsrel 1e-13): {t_ref:.2f} s"
    )
    head = (
        f"{'nodes':>5} {'panels':>6} {'load_rtol':>9} {'time_ms':>8} {'max_rel_err':>11} "
        f"{'err_Fx':>9} {'err_Ar':>9} {'err_Fz':>9} {'Fz-load':>9} {'speedup_vs_ref':>14}"
    )
    print(head)
    for knobs, t, e, e_fx, e_ar, e_fz, e_load in rows:
        print(
            f"{knobs['nodes']:>5} {knobs['panels']:>6} {knobs['load_rtol']:>9.0e} "
            f"{t * 1e3:>8.2f} {e:>11.2e} {e_fx:>9.2e} {e_ar:>9.2e} {e_fz:>9.2e} "
            f"{e_load:>9.2e} {t_ref / t:>14.0f}"
        )

    fig, ax = plt.subplots(figsize=(6, 4.5))
    times = [r[1] * 1e3 for r in rows]
    errs = [max(r[2], 1e-17) for r in rows]
    ax.loglog(times, errs, "o-")
    for (knobs, *_), t, e in zip(rows, times, errs, strict=False):
        ax.annotate(
            f"{knobs['nodes']}x{knobs['panels']}" + (" (default)" if knobs == DEFAULT else ""),
            (t, e),
            fontsize=7,
            textcoords="offset points",
            xytext=(4, -12) if knobs == DEFAULT else (4, 4),
        )
    ax.axhline(1e-6, color="gray", ls="--", lw=0.8, label="accuracy target 1e-6")
    ax.axvline(50, color="gray", ls=":", lw=0.8, label="speed target 50 ms")
    ax.xaxis.set_major_locator(FixedLocator([1, 2, 5, 10, 20, 50]))
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("warm time of the 281-step shear curve (ms, one core)")
    ax.set_ylabel("max relative error vs reference (F_x, A_r, F_z)")
    ax.set_title("statmodel: nodes x panels (Gauss-Legendre)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(args.png, dpi=150)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
