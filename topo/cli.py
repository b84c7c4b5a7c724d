"""Sub-commands of the topo package: ``stats``, ``scan`` and ``synth``.

A thin shell over :func:`topo.read_surface`, :func:`topo.level`,
:func:`topo.summit_statistics`, :func:`topo.resolution_scan` and
:func:`topo.synthetic.paper_like`; every value printed is in SI units (m, m^2, 1/m^2).
"""

from __future__ import annotations

import argparse
import json
import math
import re
from pathlib import Path

import numpy as np

from asperity.errors import ExitStatus, InputError
from asperity.topo.heightmap import HeightMap, require_height_map

#: Keys of ``asperity stats --json``, in order (a contract with other tools).
STATS_KEYS = (
    "nx",
    "ny",
    "dx",
    "dy",
    "rms_height",
    "n_missing",
    "n_summits",
    "asperity_density",
    "summit_radius",
    "summit_height_rms",
)


def _json_number(value: object) -> object:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def _pixel_size(text: str | None) -> float | tuple[float, float] | None:
    """``--pixel-size DX`` or ``DX,DY`` (m) as a float or a pair; refuse anything else."""
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) > 2:
        raise InputError(f"--pixel-size: expected DX or DX,DY in metres, got {text!r}")
    values = []
    for part in parts:
        try:
            value = float(part)
        except ValueError:
            raise InputError(
                f"--pixel-size: expected DX or DX,DY in metres, got {text!r}"
            ) from None
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"--pixel-size: expected finite lengths > 0 m, got {text!r}")
        values.append(value)
    return values[0] if len(values) == 1 else (values[0], values[1])


def _load_levelled(args: argparse.Namespace, what: str) -> HeightMap:
    from asperity.topo.io import read_surface
    from asperity.topo.levelling import level

    surface = read_surface(args.file, channel=args.channel, pixel_size=_pixel_size(args.pixel_size))
    surface = require_height_map(surface, f"asperity {what}")
    return level(surface, args.detrend)


def surface_stats(surface: HeightMap, *, stride: int = 1, neighbours: int = 4) -> dict:
    """The ``asperity stats`` record of an (already levelled) map, SI units.

    Parameters
    ----------
    surface : HeightMap
        The levelled map (heights in m).
    stride : int
        Decimation before the analysis (the paper's resampling).
    neighbours : {4, 8}
        Summit rule (4: Appendix A).

    Returns
    -------
    dict
        The keys of :data:`STATS_KEYS`: ``nx``, ``ny``, ``dx``, ``dy`` (m, ``nx``/``dx``
        along the first array axis), ``rms_height`` (m, ``sqrt(<h^2>)`` of the levelled
        heights: about the mean plane after ``plane``/``mean``), ``n_missing``,
        ``n_summits``, ``asperity_density`` (1/m^2), ``summit_radius`` (m),
        ``summit_height_rms`` (m), all of the analysed grid ``decimate(surface, stride)``;
        NaN becomes None (JSON null).
    """
    from asperity.topo.psd import rms_height
    from asperity.topo.resampling import decimate
    from asperity.topo.summits import summit_statistics

    stats = summit_statistics(surface, stride=stride, neighbours=neighbours)
    grid = decimate(surface, stride)
    record = {
        "nx": grid.nx,
        "ny": grid.ny,
        "dx": stats.dx,
        "dy": stats.dy,
        "rms_height": rms_height(grid, about_mean=False),
        "n_missing": grid.n_missing,
        "n_summits": stats.n_summits,
        "asperity_density": stats.asperity_density,
        "summit_radius": stats.summit_radius,
        "summit_height_rms": stats.summit_height_rms,
    }
    return {key: _json_number(record[key]) for key in STATS_KEYS}


_UNITS = {
    "dx": "m",
    "dy": "m",
    "rms_height": "m",
    "asperity_density": "1/m^2",
    "summit_radius": "m",
    "summit_height_rms": "m",
}


def _stats(args: argparse.Namespace) -> int:
    surface = _load_levelled(args, "stats")
    record = surface_stats(surface, stride=args.stride, neighbours=args.neighbours)
    if args.json:
        print(json.dumps(record, allow_nan=False))
    else:
        print(
            f"{args.file} (detrend {args.detrend}, stride {args.stride}, "
            f"{args.neighbours} neighbours)"
        )
        for key in STATS_KEYS:
            value = record[key]
            text = (
                "nan"
                if value is None
                else (f"{value:.6g}" if isinstance(value, float) else str(value))
            )
            print(f"  {key:18s} {text} {_UNITS.get(key, '')}".rstrip())
    return ExitStatus.OK


def _scan(args: argparse.Namespace) -> int:
    from asperity.topo.scan import plot_resolution_scan, resolution_scan, write_scan_hdf5

    surface = _load_levelled(args, "scan")
    scan = resolution_scan(surface, args.max_stride, neighbours=args.neighbours)
    figure = args.figure
    if args.out:
        write_scan_hdf5(scan, args.out, source={"file": str(args.file), "detrend": args.detrend})
        if figure is None:
            figure = str(Path(args.out).with_suffix(".png"))
    if figure:
        plot_resolution_scan(scan, figure, title=str(args.file))
    if args.json:
        data = {
            key: (_json_number(v) if not isinstance(v, list) else [_json_number(x) for x in v])
            for key, v in scan.as_dict().items()
        }
        print(json.dumps(data, allow_nan=False))
    else:
        print(
            f"{'stride':>6s} {'resolution (m)':>15s} {'N':>9s} {'eta (1/m^2)':>12s} "
            f"{'R (m)':>11s} {'sigma_s (m)':>12s}"
        )
        for row in zip(
            scan.stride,
            scan.resolution,
            scan.n_summits,
            scan.asperity_density,
            scan.summit_radius,
            scan.summit_height_rms,
            strict=True,
        ):
            print(
                f"{row[0]:6d} {row[1]:15.4e} {row[2]:9d} {row[3]:12.4e} {row[4]:11.4e} "
                f"{row[5]:12.4e}"
            )
        print(
            f"R = {scan.radius_slope:.4g} * resolution + {scan.radius_intercept:.4g} m; "
            f"eta = {scan.density_prefactor:.4g} * resolution^{scan.density_exponent:.4g} 1/m^2; "
            f"sigma_s = {scan.height_rms_mean:.4g} m "
            f"(spread {100 * scan.height_rms_relative_spread:.2f} %)"
        )
        for target in (args.out, figure):
            if target:
                print(f"wrote {target}")
    return ExitStatus.OK


def _synth(args: argparse.Namespace) -> int:
    from asperity.topo.io import write_hdf5
    from asperity.topo.synthetic import paper_like

    out = Path(args.out)
    if out.suffix.lower() not in (".h5", ".hdf5", ".npy", ".npz"):
        raise InputError(f"--out {out}: expected a .h5 (project HDF5), .npy or .npz file name")
    recipe = {
        "hurst": args.hurst,
        "rms_height": args.rms_height,
        "rolloff_wavelength": args.rolloff,
        "short_cutoff": args.short_cutoff,
    }
    recipe = {key: value for key, value in recipe.items() if value is not None}
    if recipe.get("short_cutoff") == 0:
        recipe["short_cutoff"] = None
    surface = paper_like(n=args.n, pixel_size=args.pixel_size, seed=args.seed, **recipe)
    if out.suffix.lower() in (".h5", ".hdf5"):
        write_hdf5(surface, out)
    elif out.suffix.lower() == ".npz":
        np.savez(out, heights=surface.heights, dx=surface.dx, dy=surface.dy)
    else:
        np.save(out, np.asarray(surface.heights), allow_pickle=False)
    print(
        f"wrote {out}: {surface.nx} x {surface.ny} pixels of {surface.dx:g} m, "
        f"rms height {surface.provenance['rms_height']:g} m, periodic"
        + (
            f" (read it back with --pixel-size {surface.dx:g})"
            if out.suffix.lower() == ".npy"
            else ""
        )
    )
    return ExitStatus.OK


def _add_input_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file", help="height map: x3p, sur, dat, datx, plu, opd, di, mi, gwy, txt, npy, npz, h5"
    )
    parser.add_argument(
        "--detrend",
        choices=("none", "mean", "plane"),
        default="plane",
        help="form removed before the analysis (default: plane)",
    )
    parser.add_argument(
        "--pixel-size",
        dest="pixel_size",
        metavar="DX",
        default=None,
        help="pixel size in m (DX, or DX,DY), for files that carry none (npy, npz, text)",
    )
    parser.add_argument(
        "--channel",
        default=None,
        help="channel of a multi-channel file (name or index; default: height)",
    )
    parser.add_argument(
        "--neighbours",
        type=int,
        choices=(4, 8),
        default=4,
        help="summit rule: higher than 4 (paper) or 8 neighbours",
    )


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}")
    return value


def _accept_negative_numbers(parser: argparse.ArgumentParser) -> None:
    """Let ``--pixel-size -1e-6`` reach our validation instead of argparse's "expected one
    argument": argparse only takes ``-1`` or ``-0.5`` as numbers, not ``-1e-6``."""
    parser._negative_number_matcher = re.compile(  # noqa: SLF001 (no public hook)
        r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.IGNORECASE
    )


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``stats``, ``scan`` and ``synth`` to the asperity parser."""
    stats = subparsers.add_parser(
        "stats",
        help="asperity statistics of a height map (eta, R, sigma_s; Appendix A)",
        description="Summit statistics of a height map (paper, Appendix A), SI units.",
    )
    _add_input_options(stats)
    stats.add_argument(
        "--stride",
        type=_positive_int,
        default=1,
        help="keep one point in K along x and y first (default 1)",
    )
    stats.add_argument("--json", action="store_true", help="print one JSON object")
    _accept_negative_numbers(stats)
    stats.set_defaults(func=_stats)

    scan = subparsers.add_parser(
        "scan",
        help="statistics against resolution, strides 1..K (Fig 12a-c)",
        description="Resolution scan with the paper's fits (R linear, eta power law).",
    )
    _add_input_options(scan)
    scan.add_argument(
        "--max-stride",
        dest="max_stride",
        type=_positive_int,
        required=True,
        help="largest stride K",
    )
    scan.add_argument(
        "--out",
        default=None,
        help="write the scan to this HDF5 file (and the figure beside it as .png)",
    )
    scan.add_argument("--figure", default=None, help="write the figure (PNG, 150 dpi) here")
    scan.add_argument("--json", action="store_true", help="print the scan as one JSON object")
    _accept_negative_numbers(scan)
    scan.set_defaults(func=_scan)

    synth = subparsers.add_parser(
        "synth",
        help="write a seeded synthetic (paper-like) self-affine surface",
        description="Periodic self-affine surface; defaults are the paper-like preset.",
    )
    synth.add_argument("--out", required=True, help="output .h5 (project HDF5), .npy or .npz")
    synth.add_argument("--n", type=_positive_int, default=5000, help="pixels per side (5000)")
    synth.add_argument(
        "--pixel-size", dest="pixel_size", type=float, default=2e-6, help="pixel size in m (2e-6)"
    )
    synth.add_argument("--seed", type=int, default=0, help="random seed (0)")
    # defaults None: topo.synthetic.PAPER_LIKE (not imported here, to keep --help fast)
    synth.add_argument(
        "--hurst", type=float, default=None, help="spectral (Hurst) exponent H (paper-like: 1.36)"
    )
    synth.add_argument(
        "--rms-height", dest="rms_height", type=float, default=None, help="rms height in m (50e-6)"
    )
    synth.add_argument(
        "--rolloff", type=float, default=None, help="roll-off wavelength in m (600e-6)"
    )
    synth.add_argument(
        "--short-cutoff",
        dest="short_cutoff",
        type=float,
        default=None,
        help="shortest wavelength in m (4e-6; 0 for none)",
    )
    _accept_negative_numbers(synth)
    synth.set_defaults(func=_synth)
