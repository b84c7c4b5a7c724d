"""The periodic non-adhesive BEM on a GPU (CuPy) against the CPU solver, up to the whole interface.

Optional path, run on a machine with an NVIDIA GPU and CuPy (asperity never needs one):
:func:`asperity.bem.normal.array_solver.solve_periodic_array` with ``xp="cupy"`` on the paper-like
surface (``topo.synthetic.PAPER_LIKE`` recipe through :func:`~asperity.topo.synthetic.self_affine`,
2 um pixels), E* = 2.133 MPa, the paper's 3.12 N over its 35 x 20 mm interface as a mean pressure
(4.46 kPa), tol 1e-6. Printed per size: seconds and iterations on the GPU (a first small solve
warms CuPy's FFT plans and kernels), the CPU solver (:func:`asperity.bem.solve_contact`, default
options, all cores; its second solve of the map, warm: the first, also stored, includes the
per-grid FFT set-up) on the same map up to ``--cpu-max`` elements, the contact fractions of both
and the number of elements whose contact state differs, and the GPU's pool memory per element.
``--whole-interface`` adds the paper's 35 x 20 mm interface as ``benchmarks/bem_nominal.py``
solves it on the CPU (``paper_surface`` seed 0 with asperity 0.4.1's recipe
``PAPER_SURFACE_WAVY``, on which docs/performance.md's CPU solve was measured, 17,500 x 10,000
pixels of 2 um, 2.08 N, non-adhesive: the same problem, so the two contact fractions are
comparable) and its 10 x 10 mm
corner window at the same mean pressure.

    python benchmarks/bem_gpu.py --sizes 1024x1024,4096x4096 --whole-interface --json gpu.json
    python benchmarks/bem_gpu.py --xp numpy --sizes 256x256 --cpu-max 70000   # a dry run
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from asperity.bem import SolverOptions, solve_contact
from asperity.bem.normal.array_solver import array_module, solve_periodic_array
from asperity.topo.synthetic import PAPER_LIKE, PAPER_SURFACE_WAVY, paper_surface, self_affine

E_STAR = 2.133e6  # Pa
PIXEL = 2e-6  # m
MEAN_PRESSURE = 3.12 / (35e-3 * 20e-3)  # Pa: the paper's largest load over its interface
TOL = 1e-6
NOMINAL_SHAPE = (17500, 10000)  # pixels: the paper's 35 x 20 mm interface at 2 um
NOMINAL_FORCE = 2.08  # N, as benchmarks/bem_nominal.py


def surface(nx: int, ny: int, seed: int = 0) -> np.ndarray:
    """Paper-like heights (m) on an nx x ny grid of 2 um pixels."""
    return self_affine(
        nx,
        PIXEL,
        rms_height=PAPER_LIKE["rms_height"],
        rolloff_wavelength=PAPER_LIKE["rolloff_wavelength"],
        hurst=PAPER_LIKE["hurst"],
        short_cutoff=PAPER_LIKE["short_cutoff"],
        seed=seed,
        ny=ny,
    ).heights


def gpu_pool_bytes(xp_name: str) -> int:
    """Bytes CuPy's memory pool holds (its high-water mark after a solve); 0 for NumPy."""
    if xp_name != "cupy":
        return 0
    return int(array_module("cupy").get_default_memory_pool().total_bytes())


def free_gpu_pool(xp_name: str) -> None:
    """Release CuPy's pooled blocks, so that the next size's pool figure is its own."""
    if xp_name == "cupy":
        cp = array_module("cupy")
        cp.get_default_memory_pool().free_all_blocks()
        cp.fft.config.get_plan_cache().clear()


def array_solve(h: np.ndarray, force: float, xp_name: str, prefix: str) -> tuple:
    """One solve by the array solver on a freshly emptied GPU pool: the result and its row
    entries ``<prefix>_s``, ``_nit``, ``_converged``, ``_fraction`` and the pool per element."""
    free_gpu_pool(xp_name)
    result = solve_periodic_array(h, PIXEL, PIXEL, E_STAR, force, xp=xp_name, tol=TOL)
    return result, {
        f"{prefix}_s": result.seconds,
        f"{prefix}_nit": result.nit,
        f"{prefix}_converged": result.success,
        f"{prefix}_fraction": result.contact_fraction,
        "pool_B_per_element": gpu_pool_bytes(xp_name) / h.size,
    }


def one_size(nx: int, ny: int, xp_name: str, cpu_max: int) -> dict:
    """The GPU (or array) solve and, up to cpu_max elements, the CPU solve of one map."""
    t0 = time.perf_counter()
    h = surface(nx, ny)
    row: dict = {"nx": nx, "ny": ny, "elements": nx * ny, "surface_s": time.perf_counter() - t0}
    force = MEAN_PRESSURE * nx * ny * PIXEL * PIXEL
    arr, fields = array_solve(h, force, xp_name, "array")
    row |= fields | {"device": arr.extra["device"]}
    if nx * ny <= cpu_max:
        options = SolverOptions(tol=TOL)
        first = solve_contact(h, PIXEL, PIXEL, E_STAR, normal_force=force, options=options)
        cpu = solve_contact(h, PIXEL, PIXEL, E_STAR, normal_force=force, options=options)
        row |= {
            "cpu_first_s": first.seconds,
            "cpu_s": cpu.seconds,
            "cpu_nit": cpu.nit,
            "cpu_fraction": cpu.contact_fraction,
            "differing_elements": int(np.count_nonzero(cpu.contact_mask != arr.contact_mask)),
            "speed_ratio": cpu.seconds / arr.seconds,
        }
    return row


def whole_interface(xp_name: str) -> dict:
    """The paper's whole 35 x 20 mm interface at 2 um as ``benchmarks/bem_nominal.py`` solves it
    on the CPU (``paper_surface`` seed 0, ``PAPER_SURFACE_WAVY``, 17,500 x 10,000, F_z = 2.08 N,
    non-adhesive), and its
    10 x 10 mm corner window (5000 x 5000) at the same mean pressure."""
    t0 = time.perf_counter()
    shape = dict(n=NOMINAL_SHAPE[0], ny=NOMINAL_SHAPE[1], seed=0)
    h = paper_surface(**shape, recipe=PAPER_SURFACE_WAVY).heights
    row: dict = {"surface_s": time.perf_counter() - t0, "elements": h.size}
    full, fields = array_solve(h, NOMINAL_FORCE, xp_name, "full")
    row |= fields
    window = np.ascontiguousarray(h[:5000, :5000])
    force = NOMINAL_FORCE * window.size / h.size
    win = solve_periodic_array(window, PIXEL, PIXEL, E_STAR, force, xp=xp_name, tol=TOL)
    row |= {"window_s": win.seconds, "window_nit": win.nit, "window_fraction": win.contact_fraction}
    row["window_over_full"] = win.contact_fraction / full.contact_fraction - 1
    return row


def print_table(rows: list[dict]) -> None:
    """The table: size, GPU s/nit, CPU s/nit, ratio, fractions, differing elements, memory."""
    print(
        f"{'size':>13} {'elements':>11} {'GPU s':>8} {'nit':>4} {'CPU s':>8} {'nit':>4} "
        f"{'CPU/GPU':>8} {'A_r/A_n GPU':>12} {'CPU':>10} {'differ':>7} {'pool B/el':>9}"
    )
    for r in rows:
        cpu = (
            f"{r['cpu_s']:8.2f} {r['cpu_nit']:4d} {r['speed_ratio']:8.1f}"
            if "cpu_s" in r
            else f"{'-':>8} {'-':>4} {'-':>8}"
        )
        cpu_frac = f"{r['cpu_fraction']:10.6f}" if "cpu_fraction" in r else f"{'-':>10}"
        diff = f"{r['differing_elements']:7d}" if "differing_elements" in r else f"{'-':>7}"
        print(
            f"{r['nx']:>6}x{r['ny']:<6} {r['elements']:11d} {r['array_s']:8.2f} "
            f"{r['array_nit']:4d} {cpu} {r['array_fraction']:12.6f} {cpu_frac} {diff} "
            f"{r['pool_B_per_element']:9.1f}"
        )


def main() -> None:
    """Parse the sizes, warm up, run each size, print the table and write the JSON."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--xp", default="cupy", choices=("cupy", "numpy"))
    parser.add_argument("--sizes", default="1024x1024,4096x4096,10000x10000")
    parser.add_argument("--cpu-max", type=int, default=4096 * 4096, help="elements")
    parser.add_argument("--json", default="", help="write the rows to this file")
    parser.add_argument("--whole-interface", action="store_true", help="also the 175 M case")
    args = parser.parse_args()
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.sizes.split(",")]
    warm = surface(128, 128)  # warm-up: CuPy's kernels and plans, numba's compilation
    solve_periodic_array(warm, PIXEL, PIXEL, E_STAR, 1e-5, xp=args.xp)
    solve_contact(warm, PIXEL, PIXEL, E_STAR, normal_force=1e-5, options=SolverOptions(tol=TOL))
    print(f"array library {args.xp}; CPU threads {os.cpu_count()}; tol {TOL:g}")
    rows = []
    for nx, ny in sizes:
        rows.append(one_size(nx, ny, args.xp, args.cpu_max))
        print(json.dumps(rows[-1]), flush=True)
    print_table(rows)
    if args.whole_interface:
        rows.append(whole_interface(args.xp))
        r = rows[-1]
        print(
            f"whole interface 17500 x 10000 (paper_surface, 2.08 N): {r['full_s']:.2f} s, "
            f"{r['full_nit']} iterations, A_r/A_n {r['full_fraction']:.6f}, "
            f"{r['pool_B_per_element']:.1f} B/element on the GPU; its 10 x 10 mm window "
            f"{r['window_fraction']:.6f} ({r['window_over_full']:+.2%}), {r['window_s']:.2f} s"
        )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
