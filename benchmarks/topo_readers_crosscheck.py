"""Cross-check every file of a folder against SurfaceTopography's reader: the table per format.

Run (SurfaceTopography: ``pip install "asperity[formats]"``):

    python benchmarks/topo_readers_crosscheck.py [FOLDER]

FOLDER defaults to tests/data; SurfaceTopography's own example files (its
test/file_format_examples folder) are the broad check. For each file (and, for di-3.di, each
of two channels) it prints a Markdown row: the reader asperity used (native, the ``formats``
extra, or refused with its message), whether SurfaceTopography reads it, the grid of each,
the physical size (m) and its relative difference, the rms height (m) and its relative
difference, the largest height difference after matching orientation relative to the rms,
and the missing pixels of each; then a summary line. SurfaceTopography is called with its
defaults (default channel); lengths are converted to m.
"""

from __future__ import annotations

import sys
import time
import warnings
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
    factor = (length_unit_in_metres(t.unit) or 1.0) if t.unit else 1.0  # no unit: as numbers
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


def _ours(path: Path, channel: str | None) -> tuple[object, str, float]:
    """(surface or error text, reader 'native'/'extra'/'refused', seconds)."""
    start = time.perf_counter()
    try:
        surface = topo.read_surface(path, channel=channel)
    except Exception as exc:  # noqa: BLE001 - the table reports every refusal
        message = " ".join(str(exc).split()).replace(str(path), path.name)
        return f"{type(exc).__name__}: {message}", "refused", time.perf_counter() - start
    fmt = str(surface.provenance.get("format", ""))
    reader = "extra" if fmt.startswith("SurfaceTopography") else "native"
    return surface, reader, time.perf_counter() - start


def _peer_or_error(path: Path, channel: str | None) -> tuple[object, float]:
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = peer(path, channel)
    except Exception as exc:  # noqa: BLE001 - the peer refuses some files
        result = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
    return result, time.perf_counter() - start


def compare(path: Path, channel: str | None) -> dict:
    """One row of the table: asperity against SurfaceTopography on one file (and channel)."""
    surface, reader, t_ours = _ours(path, channel)
    other, t_peer = _peer_or_error(path, channel)
    row = {"file": path.name, "channel": channel or "-", "reader": reader, "t_ours": t_ours}
    row["t_peer"] = t_peer
    if isinstance(surface, str):
        row["note"] = surface[:110]
        row["peer"] = "reads" if isinstance(other, tuple) else "refuses"
        return row
    heights = np.asarray(surface.heights)
    sizes = (surface.lx,) if isinstance(surface, LineProfile) else (surface.lx, surface.ly)
    row |= {"grid": "x".join(str(n) for n in heights.shape), "size": sizes}
    row |= {"missing": int(np.isnan(heights).sum()), "rms": float(np.nanstd(heights))}
    if not isinstance(other, tuple):
        row["peer"], row["note"] = "refuses", (other or "SurfaceTopography absent")[:110]
        return row
    theirs, peer_sizes = other
    row["peer"] = "reads"
    row["peer_grid"] = "x".join(str(n) for n in theirs.shape)
    row["peer_missing"] = int(np.isnan(theirs).sum())
    row["size_diff"] = max(abs(a - b) / b for a, b in zip(sizes, peer_sizes, strict=False))
    rms_peer = float(np.nanstd(theirs))
    row["rms_diff"] = abs(row["rms"] - rms_peer) / rms_peer if rms_peer else float("nan")
    row["max_dh"] = best_difference(heights, theirs) / rms_peer if rms_peer else float("nan")
    return row


def _cell(row: dict, key: str, fmt: str = "{:.1e}") -> str:
    value = row.get(key)
    if value is None:
        return "-"
    return fmt.format(value) if isinstance(value, float) else str(value)


def print_table(rows: list[dict]) -> None:
    """The table per format, as Markdown."""
    print(
        "| file | channel | asperity | peer | grid (asperity / peer) | size (m) | size diff "
        "| rms (m) | rms diff | max abs dh / rms | missing (asperity / peer) | note |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        size = " x ".join(f"{v:.4g}" for v in row.get("size", ())) or "-"
        grid = f"{row.get('grid', '-')} / {row.get('peer_grid', '-')}"
        missing = f"{row.get('missing', '-')} / {row.get('peer_missing', '-')}"
        print(
            f"| {row['file']} | {row['channel']} | {row['reader']} | {row['peer']} | {grid} "
            f"| {size} | {_cell(row, 'size_diff')} | {_cell(row, 'rms', '{:.4e}')} "
            f"| {_cell(row, 'rms_diff')} | {_cell(row, 'max_dh')} | {missing} "
            f"| {row.get('note', '')} |"
        )


def summary(rows: list[dict]) -> str:
    """Counts: read by each side, and agreement where both read (rms within 0.5 %)."""
    both = [r for r in rows if r["reader"] != "refused" and r["peer"] == "reads"]
    agree = [
        r
        for r in both
        if r.get("rms_diff", 1) <= 5e-3
        and r.get("size_diff", 1) <= 5e-3
        and r.get("missing") == r.get("peer_missing")
        and sorted(r["grid"].split("x")) == sorted(r["peer_grid"].split("x"))
    ]
    native = sum(r["reader"] == "native" for r in rows)
    extra = sum(r["reader"] == "extra" for r in rows)
    refused_read = sum(r["reader"] == "refused" and r["peer"] == "reads" for r in rows)
    return (
        f"{len(rows)} rows: asperity reads {native} natively and {extra} through the extra, "
        f"refuses {sum(r['reader'] == 'refused' for r in rows)} ({refused_read} of them read "
        f"by SurfaceTopography); both read {len(both)}, and agree on grid, size, missing "
        f"pixels and rms (0.5 %) on {len(agree)}"
    )


def main(data_dir: Path) -> None:
    """Print the per-format table for every file of ``data_dir`` (the sample files by default)."""
    paths = sorted(
        p
        for p in data_dir.iterdir()
        if p.is_file() and not p.name.startswith(".") and p.suffix.lower() != ".md"
    )
    rows = []
    for path in paths:
        for channel in CHANNELS.get(path.name, [None]):
            rows.append(compare(path, channel))
    print_table(rows)
    print()
    print(summary(rows))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "tests" / "data")
