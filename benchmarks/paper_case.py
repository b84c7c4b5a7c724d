"""The paper case (``asperity run --preset paper``): the stage table and the FFT floor.

Run under the shared lock, in the background for the full case (many minutes, a few GiB)::

    flock /tmp/asperity-bench.lock python benchmarks/paper_case.py [--n 2000] [--workers 2]

``--n N`` solves the paper preset on an N x N map at the same 2 um pixel (a 2N um square of the
same synthetic surface; the full case is N = 5001). Prints one row per stage: wall seconds, the
peak resident memory of the process tree (this process and its workers, sampled every 0.1 s;
a stage's window runs from the end of the previous stage, so it includes the previous stage's
HDF5 write), and for the BEM its solves, iterations and FFT convolutions (grid check included).
Then the FFT floor of the BEM grid, timed in the same run: two bare real convolutions
(rfft2, multiply, irfft2; pyFFTW with FFTW_MEASURE when installed, else scipy.fft; all cores),
i.e. the cost of one two-convolution iteration, and the BEM stage's convolutions times the
cost of one bare convolution. Writes ``paper_case.png`` (time per stage; for N = 5001 beside
the asperity 0.1 measurement, before the solver levers) into ``--out``.

Then the paper's Fig 12d at 2 um (:func:`fig12d_rows`): per load, the BEM's A_r/A_n
(non-adhesive, and Maugis-Dugdale at its range h_0) beside the statistical model at the map's
2 um summit statistics (JKR, the job's model; GW; Maugis-Dugdale at the BEM's h_0, the like-for-like
partner) and at the paper's 2 um statistics (Appendix A: eta 652.1 mm^-2, R 0.041 mm, sigma_s
0.032 mm), and the reproduction of the paper's measured curve (the model at its 260 um
statistics, benchmarks/paper_reproduction_data.py). ``--from RESULTS.h5`` prints only that
table from a finished ``--preset paper`` job (seconds, no lock). ``--fine`` sets ``[bem] coarsen =
false`` (every sweep, the Maugis ones included, at 2 um instead of the coarsest grid within the
area tolerance); ``--job-dir DIR`` runs the job in DIR and keeps it (results.h5, report, figures)
instead of a temporary folder.
"""

from __future__ import annotations

import argparse
import os
import re
import tempfile
import threading
import time
from pathlib import Path

# As `asperity run` does: OpenMP threads must not spin on a shared 2-core machine.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import numpy as np  # noqa: E402
import psutil  # noqa: E402

from asperity.pipelines.config import config_from_dict, preset_text  # noqa: E402
from asperity.pipelines.job import run_job  # noqa: E402

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

#: asperity 0.1 on the full case, before the solver levers: 461 s, BEM 438 s at stride 4 (8 um).
BEFORE = {"total": 461.0, "bem_reference": 438.0}

#: One bare 5000^2 pyFFTW real convolution on the quiet machine of that measurement, s.
QUIET_CONVOLUTION = 0.46


class MemorySampler:
    """Resident memory (bytes) of this process and its children, sampled in a thread."""

    def __init__(self, interval: float = 0.1):
        self.samples: list[tuple[float, int]] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(interval,), daemon=True)

    def _run(self, interval: float) -> None:
        me = psutil.Process()
        while not self._stop.is_set():
            total = 0
            for p in [me, *me.children(recursive=True)]:
                try:
                    total += p.memory_info().rss
                except psutil.Error:
                    pass
            self.samples.append((time.perf_counter(), total))
            time.sleep(interval)

    def __enter__(self) -> MemorySampler:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()

    def peak(self, start: float, end: float) -> float:
        """Peak resident bytes in [start, end] (NaN when no sample fell inside)."""
        inside = [rss for t, rss in self.samples if start <= t <= end]
        return float(max(inside)) if inside else float("nan")


def paper_config(n: int, workers: int, coarsen: bool = True):
    """The paper preset on an n x n map at its 2 um pixel (``coarsen``: its ``[bem] coarsen``;
    False sweeps every load at 2 um)."""
    data = tomllib.loads(preset_text("paper"))
    data["surface"]["synthetic"]["n"] = n
    data["surface"]["max_stride"] = min(data["surface"]["max_stride"], max(n // 40, 2))
    data["run"]["workers"] = workers
    data["bem"]["coarsen"] = coarsen
    return config_from_dict(data, source=f"paper preset, n = {n}")


def convolution_seconds(shape: tuple[int, int], repeats: int = 3) -> tuple[float, str]:
    """Best time (s) of one bare real convolution on ``shape`` and the library used."""
    rng = np.random.default_rng(0)
    x = rng.random(shape)
    kernel = rng.random((shape[0], shape[1] // 2 + 1))
    threads = os.cpu_count() or 1
    try:
        import pyfftw

        a = pyfftw.empty_aligned(shape, dtype="float64")
        forward = pyfftw.builders.rfft2(a, threads=threads, planner_effort="FFTW_MEASURE")
        backward = pyfftw.builders.irfft2(
            forward.output_array, s=shape, threads=threads, planner_effort="FFTW_MEASURE"
        )

        def convolve() -> None:
            a[...] = x
            spectrum = forward()
            spectrum *= kernel
            backward(spectrum)

        name = f"pyFFTW (FFTW_MEASURE, {threads} threads)"
    except ImportError:
        import scipy.fft

        def convolve() -> None:
            scipy.fft.irfft2(scipy.fft.rfft2(x, workers=threads) * kernel, s=shape, workers=threads)

        name = f"scipy.fft ({threads} workers)"
    convolve()
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        convolve()
        best = min(best, time.perf_counter() - t)
    return float(best), name


#: The last line a stage logs: its time, or that it was disabled or taken from the store
#: (previews and notes log lines of their own before it).
STAGE_END = re.compile(r": (\d+\.\d\d s|disabled|stored, skipped)$")


def stage_table(result, marks: list[float], start: float, memory: MemorySampler) -> list[list]:
    """Rows: stage, seconds, peak GiB, solves, iterations, convolutions."""
    rows, t0 = [], start
    for run, t1 in zip(result.stages, marks, strict=True):
        row = [run.name, run.seconds, memory.peak(t0, t1) / 2**30, "-", "-", "-"]
        if run.name == "bem_reference" and result.bem_reference is not None:
            b = result.bem_reference
            row[3:] = [b.solves, b.total_iterations, b.total_convolutions]
        rows.append(row)
        t0 = t1
    return rows


def bem_rows(bem) -> list[str]:
    """The BEM stage's own breakdown: grid check per stride, then the sweeps."""
    lines = []
    for i, s in enumerate(bem.check_stride):
        lines.append(
            f"  check stride {int(s):>2}: {bem.check_seconds[i].sum():8.1f} s, iterations "
            f"{bem.check_iterations[i].tolist()}, convolutions {bem.check_convolutions[i].tolist()}"
            f", A_r/A_n {np.round(bem.check_contact_fraction[i], 6).tolist()}"
        )
    for m, name in enumerate(("non-adhesive", "adhesive")[: bem.iterations.shape[0]]):
        lines.append(
            f"  {name:>12} per load: s {np.round(bem.solve_seconds[m], 1).tolist()}, iterations "
            f"{bem.iterations[m].tolist()}, convolutions {bem.convolutions[m].tolist()}"
        )
    return lines


def plot(rows: list[list], n: int, convolution: float, path: Path) -> None:
    """Bar chart of seconds per stage; for the full case beside the asperity 0.1 measurement
    and scaled to its quiet machine (times ``QUIET_CONVOLUTION / convolution``, the ratio of
    the bare convolution there and in this run)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 4.5))
    ax = fig.subplots()
    names = [r[0] for r in rows] + ["total"]
    after = [r[1] for r in rows] + [sum(r[1] for r in rows)]
    x = np.arange(len(names))
    if n == 5001:
        before = [BEFORE.get(name, np.nan) for name in names]
        scale = QUIET_CONVOLUTION / convolution
        ax.bar(x - 0.27, before, 0.27, label="asperity 0.1, quiet machine (BEM at 8 um)")
        speed = f"{1 / scale:.2f}x the quiet machine's FFT time"
        ax.bar(x, after, 0.27, label=f"now, this run (BEM at 2 um; {speed})")
        ax.bar(x + 0.27, np.multiply(after, scale), 0.27, label="now, scaled to the quiet FFT")
    else:
        ax.bar(x, after, 0.6, label=f"now, {n} x {n} px at 2 um")
    ax.set_xticks(x, names, rotation=30, ha="right")
    ax.set_ylabel("wall time (s)")
    ax.set_title(f"asperity run --preset paper, {n} x {n} px")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


#: The paper's summit statistics at 2 um (Appendix A, Fig 4 caption), SI.
PAPER_2UM = (652.1e6, 0.041e-3, 0.032e-3)


def fig12d_rows(results: Path) -> list[str]:
    """Fig 12d at 2 um from a finished paper job's results.h5: BEM vs model vs reproduction."""
    import sys

    import h5py

    from asperity import statmodel
    from asperity.statmodel.maugis_rough import maugis_rough_contact

    sys.path.insert(0, str(Path(__file__).parent))
    from paper_reproduction_data import NORMAL_LOADS, normal_area_curve

    with h5py.File(results, "r") as f:
        bem, scan, sm = f["bem_reference"], f["resolution_scan"], f["statistical_model"]
        loads = sm["normal_load"][:]
        a_n = float(sm.attrs["nominal_area"])
        bem_dry = bem["contact_fraction"][:]
        bem_md = bem["contact_fraction_adhesive"][:] if "contact_fraction_adhesive" in bem else None
        h0 = float(bem.attrs.get("adhesion_range", float("nan")))
        stride = int(bem.attrs["stride"])
        pixel = float(scan["resolution"][0])
        rough = statmodel.Roughness(
            float(scan["asperity_density"][0]),
            float(scan["summit_radius"][0]),
            float(scan["summit_height_rms"][0]),
        )
        material = statmodel.Material(
            2.133e6, 0.040, 0.03, 0.13e6, 0.2e-9
        )  # the preset's (normal contact reads E*, w, epsilon)
    paper = statmodel.Roughness(*PAPER_2UM)
    jkr = np.asarray(statmodel.real_area_at_loads(material, rough, a_n, loads)) / a_n
    jkr_paper = np.asarray(statmodel.real_area_at_loads(material, paper, a_n, loads)) / a_n
    gw = maugis_rough_contact(rough, material.e_star, 0.0, 1e-9, a_n, loads).real_area / a_n
    md = (
        maugis_rough_contact(
            rough, material.e_star, material.work_of_adhesion, h0, a_n, loads
        ).real_area
        / a_n
        if np.isfinite(h0)
        else np.full(loads.shape, np.nan)
    )
    reproduction = dict(zip(NORMAL_LOADS, normal_area_curve() / 700e-6, strict=True))
    lines = [
        f"Fig 12d at 2 um: BEM on the {pixel * stride * 1e6:.0f} um grid (stride {stride}), "
        f"Maugis range h_0 = {h0 * 1e9:.0f} nm; model at the map's 2 um statistics eta = "
        f"{rough.asperity_density * 1e-6:.1f} mm^-2, R = {rough.summit_radius * 1e3:.4f} mm, "
        f"sigma_s = {rough.summit_height_rms * 1e3:.4f} mm; A_r/A_n (%)",
        f"{'F_z (N)':>8} {'BEM dry':>8} {'BEM MD':>8} {'GW 2um':>8} {'MD 2um':>8} {'JKR 2um':>8}"
        f" {'JKR paper 2um':>14} {'reproduction':>13}",
    ]
    for i, load in enumerate(loads):
        md_bem = bem_md[i] if bem_md is not None else float("nan")
        rep = reproduction.get(round(float(load), 2), float("nan"))
        lines.append(
            f"{load:8.2f} {100 * bem_dry[i]:8.3f} {100 * md_bem:8.3f} {100 * gw[i]:8.3f} "
            f"{100 * md[i]:8.3f} {100 * jkr[i]:8.3f} {100 * jkr_paper[i]:14.3f} {100 * rep:13.3f}"
        )
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=5001, help="pixels per side (5001: the paper)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--from", dest="results", type=Path, default=None, metavar="RESULTS.h5")
    parser.add_argument(
        "--fine", action="store_true", help="[bem] coarsen = false: every sweep at 2 um"
    )
    parser.add_argument(
        "--job-dir",
        type=Path,
        default=None,
        help="run the job here and keep it (default: a temporary folder)",
    )
    args = parser.parse_args()
    if args.results is not None:
        print("\n".join(fig12d_rows(args.results)))
        return
    config = paper_config(args.n, args.workers, coarsen=not args.fine)
    marks: list[float] = []

    def mark_stage_ends(line: str) -> None:  # the stages' last lines; not previews or notes
        if STAGE_END.search(line):
            marks.append(time.perf_counter())

    with tempfile.TemporaryDirectory() as tmp, MemorySampler() as memory:
        job_dir = args.job_dir or Path(tmp)
        start = time.perf_counter()
        result = run_job(config, job_dir, force=True, log=mark_stage_ends)
        fig12d = fig12d_rows(Path(job_dir) / "results.h5")
        print("\n".join(fig12d), flush=True)
    rows = stage_table(result, marks, start, memory)
    bem = result.bem_reference
    print(
        f"paper case, {args.n} x {args.n} px at 2 um, workers {args.workers}, "
        f"BEM grid {bem.contact_mask.shape}, boundary {bem.boundary}"
    )
    print(
        f"{'stage':<18} {'seconds':>9} {'peak GiB':>9} {'solves':>7} {'iterations':>11} "
        f"{'convolutions':>13}"
    )
    for r in rows:
        print(f"{r[0]:<18} {r[1]:9.1f} {r[2]:9.2f} {r[3]!s:>7} {r[4]!s:>11} {r[5]!s:>13}")
    print(
        f"{'total (job)':<18} {result.total_seconds:9.1f} "
        f"{memory.peak(start, marks[-1]) / 2**30:9.2f}"
    )
    print("\n".join(bem_rows(result.bem_reference)))
    print(f"  grid: {result.bem_reference.grid_reason}")
    conv, lib = convolution_seconds(bem.contact_mask.shape)
    bem_seconds = next(r[1] for r in rows if r[0] == "bem_reference")
    floor = conv * bem.total_convolutions
    print(
        f"FFT floor on {bem.contact_mask.shape}, {lib}: one bare real convolution "
        f"{conv:.3f} s, two (one iteration) {2 * conv:.3f} s; BEM stage {bem_seconds:.1f} s for "
        f"{bem.total_convolutions} convolutions = {bem_seconds / floor:.2f} x the floor "
        f"({floor:.1f} s)"
    )
    args.out.mkdir(parents=True, exist_ok=True)
    plot(rows, args.n, conv, args.out / "paper_case.png")
    print(f"figure: {args.out / 'paper_case.png'}")


if __name__ == "__main__":
    main()
