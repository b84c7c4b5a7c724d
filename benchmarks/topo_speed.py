"""Speed, memory and peer comparison of topo's statistics on the paper's map size.

Run under the shared lock (peers in their own venv; without them the peer rows are
skipped):

    flock /tmp/asperity-bench.lock /tmp/peers-topo/bin/python benchmarks/topo_speed.py [N]

On an N x N (default 5001 x 5001) ``paper_like`` map it prints one table: the operation,
the map size, wall time (best of a few runs, after a warm-up that compiles the numba
kernels), peak traced memory as a multiple of the map (numpy allocations, tracemalloc),
an accuracy column and, where a peer does the same job, the peer's time and the ratio
peer time / our time.

Peers: SurfaceTopography (rms curvature and PSD of the same map) and slippy 0.5.2
(``find_summits(four_nearest=True)``: interior points strictly higher than their four
neighbours, the same rule as ours on a non-periodic map, so the counts must agree
exactly; ``get_summit_curvatures`` returns the mean curvature ``-(z_xx + z_yy)/2`` of
each summit, compared with ours computed the same way; the paper's R is
``<(1/|z_xx| + 1/|z_yy|)/2>``, which by the AM-HM inequality is >= ``<1/kappa>``).
"""

from __future__ import annotations

import sys
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from asperity import topo  # noqa: E402
from asperity.topo.summits import summit_mask  # noqa: E402

try:
    from SurfaceTopography import Topography
except ImportError:
    Topography = None
try:
    from slippy.surface.roughness_funcs import find_summits, get_summit_curvatures
except ImportError:
    find_summits = get_summit_curvatures = None


def timed(function: Callable[[], object], repeat: int = 3) -> tuple[float, object]:
    """Best wall time of ``repeat`` calls and the last result."""
    best, result = float("inf"), None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def peak_memory(function: Callable[[], object]) -> float:
    """Peak traced (numpy) allocation in bytes during one call."""
    tracemalloc.start()
    tracemalloc.reset_peak()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return float(peak)


def row(name, size, seconds, memory, accuracy, peer_seconds=None):
    ratio = f"{peer_seconds / seconds:8.1f}" if peer_seconds else f"{'-':>8s}"
    peer = f"{peer_seconds:10.3f}" if peer_seconds else f"{'-':>10s}"
    mem = f"{memory:8.2f}" if memory is not None else f"{'-':>8s}"
    print(f"{name:38s} {size:>11s} {seconds:9.3f} {mem} {accuracy:>34s} {peer} {ratio}")


def harmonic_fill_row(n: int = 1000, fraction: float = 0.03) -> None:
    """Harmonic fill of a rough 1000 x 1000 map with 3 % of its pixels (in blobs) missing,
    plus the error on a plane with the same holes (exact up to rounding)."""
    rng = np.random.default_rng(0)
    rough = np.array(topo.synthetic.paper_like(n=n, pixel_size=2e-6, seed=1).heights)
    holes = np.zeros((n, n), dtype=bool)
    while holes.mean() < fraction:
        i, j = rng.integers(0, n - 6, size=2)
        holes[i : i + 6, j : j + 6] = True
    x = np.arange(n)[:, None] * 2e-6
    plane = 1e-5 + 0.01 * x - 0.02 * x.T
    filled_plane = topo.harmonic_fill(np.where(holes, np.nan, plane), 2e-6, 2e-6)
    error = float(np.abs(filled_plane - plane).max() / np.abs(plane).max())
    seconds, _ = timed(lambda: topo.harmonic_fill(np.where(holes, np.nan, rough), 2e-6, 2e-6))
    row(
        f"harmonic_fill, {100 * fraction:.0f} % missing",
        f"{n}x{n}",
        seconds,
        None,
        f"plane error {error:.1e}",
    )


def main(n: int) -> None:
    start = time.perf_counter()
    surface = topo.synthetic.paper_like(n=n, pixel_size=2e-6, seed=0)
    generation = time.perf_counter() - start
    open_map = topo.HeightMap(surface.heights, surface.dx, surface.dy, periodic=False)
    nbytes = surface.heights.nbytes
    size = f"{n}x{n}"
    print(f"paper_like map {size}, {nbytes / 2**20:.0f} MiB, generated in {generation:.2f} s")
    print(
        f"{'operation':38s} {'size':>11s} {'time (s)':>9s} {'mem/map':>8s} {'accuracy':>34s} "
        f"{'peer (s)':>10s} {'peer/us':>8s}"
    )
    print("-" * 125)
    topo.summit_statistics(open_map)  # compile / load the cached kernels
    topo.level(
        topo.synthetic.paper_like(n=64, pixel_size=50e-6).with_heights(
            np.zeros((64, 64)), periodic=False
        ),
        "plane",
    )
    topo.resolution_scan(topo.synthetic.paper_like(n=64, pixel_size=50e-6), 3)

    seconds, stats = timed(lambda: topo.summit_statistics(surface))
    memory = peak_memory(lambda: topo.summit_statistics(surface)) / nbytes
    row(
        "summit_statistics (periodic, stride 1)",
        size,
        seconds,
        memory,
        f"N={stats.n_summits} R={stats.summit_radius:.3e} m",
    )

    seconds, stats = timed(lambda: topo.summit_statistics(open_map))
    memory = peak_memory(lambda: topo.summit_statistics(open_map)) / nbytes
    peer_seconds = None
    accuracy = f"N={stats.n_summits}"
    if find_summits is not None:
        peer_seconds, peer_mask = timed(
            lambda: find_summits(np.array(open_map.heights), four_nearest=True), repeat=1
        )
        ours = summit_mask(open_map)
        same = bool(np.array_equal(ours, peer_mask))
        accuracy = f"N={stats.n_summits} slippy {int(peer_mask.sum())} same={same}"
    row("summit_statistics (open edges)", size, seconds, memory, accuracy, peer_seconds)

    seconds, levelled = timed(lambda: topo.level(open_map, "plane"))
    memory = peak_memory(lambda: topo.level(open_map, "plane")) / nbytes
    row("level plane (new map)", size, seconds, memory, "")

    def full_stats():
        return topo.summit_statistics(topo.level(open_map, "plane"))

    seconds, _ = timed(full_stats)
    row("stats: level plane + summits", size, seconds, peak_memory(full_stats) / nbytes, "")

    seconds, prepared = timed(lambda: topo.prepare_surface(open_map), repeat=2)
    memory = peak_memory(lambda: topo.prepare_surface(open_map)) / nbytes
    outliers = f"{prepared.record.n_outliers} outliers, {len(prepared.record.warnings)} warnings"
    row("prepare_surface (defaults)", size, seconds, memory, outliers)
    harmonic_fill_row()

    max_stride = min(130, n // 3)
    seconds, scan = timed(lambda: topo.resolution_scan(surface, max_stride), repeat=2)
    memory = peak_memory(lambda: topo.resolution_scan(surface, max_stride)) / nbytes
    row(
        f"resolution_scan strides 1..{max_stride}",
        size,
        seconds,
        memory,
        f"eta exponent {scan.density_exponent:.3f}",
    )

    if get_summit_curvatures is not None:
        h = np.asarray(open_map.heights)
        dx = open_map.dx

        def our_curvatures():
            i, j = np.nonzero(summit_mask(open_map))
            zxx = (h[i + 1, j] - 2 * h[i, j] + h[i - 1, j]) / dx**2
            zyy = (h[i, j + 1] - 2 * h[i, j] + h[i, j - 1]) / dx**2
            return zxx, zyy

        seconds, (zxx, zyy) = timed(our_curvatures)
        ours = -0.5 * (zxx + zyy)
        mask = summit_mask(open_map)
        peer_seconds, curvatures = timed(
            lambda: get_summit_curvatures(np.array(h), summits=mask, grid_spacing=dx), repeat=1
        )
        curvatures = np.asarray(curvatures)
        error = float(np.max(np.abs(curvatures - ours) / np.abs(ours)))
        radius_paper = float(np.mean(0.5 * (1 / np.abs(zxx) + 1 / np.abs(zyy))))
        row(
            "summit mean curvatures (slippy's rule)",
            size,
            seconds,
            None,
            f"max rel diff {error:.1e}",
            peer_seconds,
        )
        print(
            f"    R (paper) = {radius_paper:.4e} m >= <1/kappa> = {np.mean(1 / curvatures):.4e} m"
            " (slippy's mean curvature converted to a radius)"
        )

    seconds, ours_curvature = timed(lambda: topo.rms_curvature(open_map))
    memory = peak_memory(lambda: topo.rms_curvature(open_map)) / nbytes
    peer_seconds, accuracy = None, f"{ours_curvature:.5e} 1/m"
    if Topography is not None:
        t = Topography(np.array(open_map.heights), (open_map.lx, open_map.ly), periodic=False)
        peer_seconds, peer_curvature = timed(t.rms_curvature_from_area, repeat=1)
        accuracy = f"rel diff to SurfaceTopography {abs(ours_curvature / peer_curvature - 1):.1e}"
    row("rms_curvature", size, seconds, memory, accuracy, peer_seconds)

    seconds, radial = timed(lambda: topo.radial_psd(surface), repeat=1)
    memory = peak_memory(lambda: topo.radial_psd(surface)) / nbytes
    parseval = float(
        np.sum(topo.psd.psd_2d(surface)[2]) / surface.nominal_area / np.var(surface.heights)
    )
    peer_seconds = None
    if Topography is not None:
        t = Topography(np.array(surface.heights), (surface.lx, surface.ly), periodic=True)
        peer_seconds, _ = timed(t.power_spectrum_from_area, repeat=1)
    row("radial_psd", size, seconds, memory, f"Parseval sum/var = {parseval:.12f}", peer_seconds)
    print(
        f"roll-off estimate {topo.rolloff_wavelength(surface) * 1e6:.0f} um (generated with 600 um)"
    )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5001)
