"""Cross-check every sample instrument file against SurfaceTopography's reader.

Run (SurfaceTopography is a benchmark-only peer, installed in its own venv):

    /tmp/peers-topo/bin/python benchmarks/topo_readers_crosscheck.py [DATA_DIR]

For each file it prints the grid, the physical size (m) and the rms height (m) from
``topo.read_surface`` and from SurfaceTopography, and the largest height difference
after matching orientation (SurfaceTopography flips some formats), relative to the rms.
Without SurfaceTopography the peer columns are left empty.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from asperity import topo  # noqa: E402
from asperity.topo.heightmap import LineProfile  # noqa: E402
from asperity.topo.io.units import length_unit_in_metres  # noqa: E402

try:
    from SurfaceTopography import read_topography
except ImportError:  # the peer is optional
    read_topography = None

FILES = [
    "x3p-2.x3p",
    "sur-3.sur",
    "metropro-1.dat",
    "plu-1.plu",
    "opd-1.opd",
    "di-3.di",
    "mi-1.mi",
    "dektak-1.csv",
]
# Channels that hold the same data in both readers (SurfaceTopography's default for .di is
# the first height channel, 'Height Sensor'; ours is 'Height', so compare that one too).
CHANNELS = {"di-3.di": ["Height", "ZSensor"]}
ST_CHANNEL_INDEX = {("di-3.di", "Height"): 3, ("di-3.di", "ZSensor"): 0}


def peer(path: Path, channel: str | None) -> tuple[np.ndarray, tuple[float, ...]] | None:
    """Heights (m, NaN for masked) and physical sizes (m) from SurfaceTopography."""
    if read_topography is None:
        return None
    kwargs = {}
    if channel is not None:
        kwargs["channel_index"] = ST_CHANNEL_INDEX[(path.name, channel)]
    t = read_topography(str(path), **kwargs)
    factor = length_unit_in_metres(t.unit) or 1.0
    heights = np.ma.filled(np.ma.asarray(t.heights(), dtype=float), np.nan) * factor
    sizes = tuple(np.atleast_1d(t.physical_sizes) * factor)
    return heights, sizes


def best_difference(ours: np.ndarray, theirs: np.ndarray) -> float:
    """Largest |difference| over orientations (identity, flips, transpose), NaN-aware."""
    candidates = [theirs, theirs[::-1]]
    if theirs.ndim == 2:
        candidates += [theirs[:, ::-1], theirs[::-1, ::-1]]
        candidates += [c.T for c in candidates]
    best = np.inf
    for candidate in candidates:
        if candidate.shape != ours.shape:
            continue
        both = ~np.isnan(ours) & ~np.isnan(candidate)
        if both.sum() == 0:
            continue
        a = ours[both] - np.mean(ours[both])
        b = candidate[both] - np.mean(candidate[both])
        best = min(best, float(np.max(np.abs(a - b))))
    return best


def main(data_dir: Path) -> None:
    header = (
        f"{'file':16s} {'channel':9s} {'grid':>11s} {'size x (m)':>11s} {'size y (m)':>11s} "
        f"{'size diff':>9s} {'rms ours (m)':>13s} {'rms peer (m)':>13s} {'rel diff':>9s} "
        f"{'max|dh|/rms':>11s} "
        f"{'t ours (s)':>10s} {'t peer (s)':>10s}"
    )
    print(header)
    print("-" * len(header))
    for name in FILES:
        path = data_dir / name
        for channel in CHANNELS.get(name, [None]):
            start = time.perf_counter()
            surface = topo.read_surface(path, channel=channel)
            t_ours = time.perf_counter() - start
            heights = np.asarray(surface.heights)
            if isinstance(surface, LineProfile):
                sizes = (surface.lx,)
            else:
                sizes = (surface.lx, surface.ly)
            rms_ours = float(np.nanstd(heights))
            start = time.perf_counter()
            other = peer(path, channel)
            t_peer = time.perf_counter() - start
            if other is None:
                rms_peer, rel, diff, t_peer_text = float("nan"), float("nan"), float("nan"), "-"
                size_diff = float("nan")
            else:
                theirs, peer_sizes = other
                size_diff = max(abs(a - b) / b for a, b in zip(sizes, peer_sizes, strict=False))
                both = ~np.isnan(theirs)
                rms_peer = float(np.std(theirs[both]))
                rel = abs(rms_ours - rms_peer) / rms_peer
                diff = best_difference(heights, theirs) / rms_peer
                t_peer_text = f"{t_peer:10.3f}"
            grid = "x".join(str(n) for n in heights.shape)
            size_y = f"{sizes[1]:11.4e}" if len(sizes) > 1 else f"{'-':>11s}"
            print(
                f"{name:16s} {str(channel or '-'):9s} {grid:>11s} {sizes[0]:11.4e} {size_y} "
                f"{size_diff:9.1e} "
                f"{rms_ours:13.6e} {rms_peer:13.6e} {rel:9.1e} {diff:11.1e} "
                f"{t_ours:10.3f} {t_peer_text:>10s}"
            )


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "tests" / "data")
