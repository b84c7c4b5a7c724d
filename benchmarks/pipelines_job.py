"""Benchmark of the main job (``asperity run``): wall time per stage against map size and workers.

Run under the shared lock so timings do not collide::

    flock /tmp/asperity-bench.lock python benchmarks/pipelines_job.py [--quick]

Prints one row per (map size, workers): pixels per side, pixel size, the time of each stage,
the total, the BEM adhesive A_r/A_n at the median load (how the answer moves with the grid:
the accuracy column) and the speed-up against one worker at the same size (the "peer" of a
pipeline is its own serial run; no other code runs this job). The last row is the default job
through the command line in a fresh process (imports, JIT cache loading and figures included),
the number CI sees.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# As `asperity run` does: OpenMP threads must not spin on a shared 2-core machine (set before
# the FFT library loads the OpenMP runtime).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

from asperity.pipelines.config import config_from_dict, preset_text  # noqa: E402
from asperity.pipelines.job import STAGE_NAMES as STAGES  # noqa: E402
from asperity.pipelines.job import run_job  # noqa: E402
from asperity.pipelines.report import write_report  # noqa: E402

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

MAP_SIZE = 10e-3  # m, the paper's map
COARSEST = 260e-6  # m, the paper's effective resolution: the scan goes up to it


def config_for(n: int):
    data = tomllib.loads(preset_text("default"))
    pixel = MAP_SIZE / n
    data["surface"]["synthetic"].update(n=n, pixel_size=pixel)
    data["surface"]["max_stride"] = max(2, round(COARSEST / pixel))
    return config_from_dict(data, source=f"benchmark n={n}")


def time_job(n: int, workers: int) -> dict:
    cfg = config_for(n)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        result = run_job(cfg, tmp, force=True, workers=workers)
        t_job = time.perf_counter() - t0
        t0 = time.perf_counter()
        write_report(result, tmp)
        t_report = time.perf_counter() - t0
    median = len(result.bem_reference.normal_load) // 2
    return {
        "n": n,
        "pixel": cfg.surface.synthetic.pixel_size,
        "workers": workers,
        "stages": {s.name: s.seconds for s in result.stages},
        "job": t_job,
        "report": t_report,
        "fraction": float(result.bem_reference.reference_fraction()[median]),
        "stride": result.bem_reference.stride,
        "converged": result.converged,
    }


def time_cli() -> float:
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "asperity", "run", "--out", str(Path(tmp) / "o")],
            check=True,
            capture_output=True,
        )
        return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small maps only")
    args = parser.parse_args()
    sizes = (250, 500) if args.quick else (250, 500, 1000)
    time_job(128, 1)  # warm the JIT caches so the first row is not a compile time
    rows = []
    for n in sizes:
        for workers in (1, 2):
            rows.append(time_job(n, workers))
    short = {
        "surface": "read",
        "resolution_scan": "scan",
        "bem_reference": "BEM",
        "statistical_model": "model",
        "mode_mixity": "lambda",
        "friction": "friction",
    }
    header = (
        ["n", "pixel_um", "workers"]
        + [f"{short[s]}_s" for s in STAGES]
        + ["job_s", "report_s", "speedup", "bem_stride", "Ar/An_bem_adh", "ok"]
    )
    print(" ".join(f"{h:>13}" for h in header))
    serial = {}
    for r in rows:
        if r["workers"] == 1:
            serial[r["n"]] = r["job"]
        cells = [r["n"], f"{r['pixel'] * 1e6:.3g}", r["workers"]]
        cells += [f"{r['stages'][s]:.2f}" for s in STAGES]
        cells += [
            f"{r['job']:.2f}",
            f"{r['report']:.2f}",
            f"{serial[r['n']] / r['job']:.2f}",
            r["stride"],
            f"{r['fraction']:.4g}",
            r["converged"],
        ]
        print(" ".join(f"{c!s:>13}" for c in cells))
    finest = rows[-1]["fraction"]
    print(
        "\nBEM A_r/A_n at the median load relative to the finest map: "
        + ", ".join(f"n={r['n']}: {r['fraction'] / finest:.3f}" for r in rows[::2])
    )
    if not args.quick:
        print(
            f"\nasperity run (default preset, fresh process, figures included): {time_cli():.1f} s"
        )


if __name__ == "__main__":
    main()
