"""Sub-commands of the topo package: ``stats``, ``scan`` and ``synth``.

A thin shell over :func:`topo.read_surface`, :func:`topo.level`,
:func:`topo.summit_statistics`, :func:`topo.resolution_scan` and
:func:`topo.synthetic.paper_like`; every value printed is in SI units (m, m^2, 1/m^2).
"""

from __future__ import annotations

import argparse
import functools
import io
import json
import math
import re
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from asperity.atomic import write_bytes_atomic
from asperity.errors import ExitStatus, InputError
from asperity.files import require_output_path
from asperity.length_units import UNIT_HELP
from asperity.quantities import add_bounded_option, quantity
from asperity.topo.cli_common import json_number, preparation_options, print_scan_table
from asperity.topo.heightmap import HeightMap, LineProfile, require_height_map
from asperity.topo.profile_cli import profile_scan, profile_stats

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
        values.append(quantity("surface.pixel_size").check(value, "--pixel-size"))
    return values[0] if len(values) == 1 else (values[0], values[1])


def _read(args: argparse.Namespace):
    """The file as a HeightMap or a LineProfile."""
    # deferred: topo.io loads h5py; `asperity --help` must not
    from asperity.topo.io import read_surface

    return read_surface(
        args.file,
        channel=args.channel,
        pixel_size=_pixel_size(args.pixel_size),
        unit=getattr(args, "unit", None),
    )


def _load_prepared(args: argparse.Namespace, what: str, surface=None):
    """Read the file and prepare it as the options say; warnings go to stderr."""
    # deferred: topo.preparation loads scipy and numba; `asperity --help` must not
    from asperity.topo.preparation import prepare_surface

    options = preparation_options(args)
    surface = require_height_map(surface or _read(args), f"asperity {what}")
    prepared = prepare_surface(surface, options)
    if args.json:  # the text output shows them in its surface block
        for warning in prepared.record.warnings:
            print(f"asperity {what}: warning: {warning}", file=sys.stderr)
    return prepared


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
        along the first array axis), ``rms_height`` (m, ``sqrt(<h^2>)`` of the valid levelled
        heights: about the mean plane after ``plane``/``mean``), ``n_missing`` (pixels still
        missing after the preparation), ``n_summits``, ``asperity_density`` (1/m^2),
        ``summit_radius`` (m), ``summit_height_rms`` (m); then ``nominal_area`` (m^2, the
        valid area over which the summits are counted: eta = n_summits / nominal_area) and
        ``grid_area`` (m^2, the whole analysed grid, holes included); all of the analysed
        grid ``decimate(surface, stride)``;
        NaN becomes None (JSON null).
    """
    # deferred: numba kernels and scipy, loaded by the command, not by --help
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
    record["nominal_area"] = stats.nominal_area
    record["grid_area"] = stats.grid_area
    return {key: json_number(value) for key, value in record.items()}


_UNITS = {
    "nominal_area": "m^2",
    "dx": "m",
    "dy": "m",
    "rms_height": "m",
    "asperity_density": "1/m^2",
    "summit_radius": "m",
    "summit_height_rms": "m",
}


def _print_preparation(record: dict) -> None:
    """The "Surface" block of the text output (the preparation record)."""
    crop = record["crop"]
    print("  surface preparation:")
    print(f"    crop               {'none' if crop is None else crop} (pixels i0, i1, j0, j1)")
    print(f"    pixels             dx = {record['dx']:.6g} m, dy = {record['dy']:.6g} m")
    print(
        f"    levelling          {record['levelling']} (form rms {record['form_rms']:.4g} m, "
        f"form/roughness {record['form_to_roughness']:.3g})"
    )
    masked = record["n_outliers"] if record["outlier_action"] == "mask" else 0
    print(
        f"    missing pixels     {record['n_missing']} measured "
        f"({100 * record['missing_fraction']:.3g} %) + {masked} masked outliers; policy "
        f"{record['missing_policy']}: {record['n_filled']} filled, "
        f"{record['n_missing_left']} left (n_missing above)"
    )
    ratio = record.get("outlier_rms_ratio")
    effect = "" if ratio is None else f", rms height x{ratio:.3g}"
    print(
        f"    outliers           {record['n_outliers']} "
        f"({100 * record['outlier_fraction']:.3g} %) "
        f"{'masked' if record['outlier_action'] == 'mask' else 'clipped'}, rule "
        f"{record['outlier_rule']}{effect}"
    )
    for warning in record["warnings"]:
        print(f"  WARNING: {warning}")


def _naming_the_file(handler: Callable[[argparse.Namespace], int]):
    """``handler`` whose bad-input errors name FILE when their message does not (an empty
    heights dataset, a profile with a single value): ``FILE: message``."""

    @functools.wraps(handler)
    def run(args: argparse.Namespace) -> int:
        try:
            return handler(args)
        except InputError as exc:
            text = str(exc)
            if str(args.file) in text or text.startswith("-"):  # named, or about an option
                raise
            raise InputError(f"{args.file}: {text}") from exc

    return run


@_naming_the_file
def _stats(args: argparse.Namespace) -> int:
    surface = _read(args)
    if isinstance(surface, LineProfile):  # Nayak's theory: asperity.topo.profile_cli
        return profile_stats(args, surface)
    prepared = _load_prepared(args, "stats", surface)
    record = surface_stats(prepared.surface, stride=args.stride, neighbours=args.neighbours)
    record["channel"] = prepared.surface.provenance.get("channel")
    record["preparation"] = prepared.record.as_dict()
    if args.json:
        print(json.dumps(record, allow_nan=False))
    else:
        print(
            f"{args.file} (channel {record['channel']}, detrend {prepared.record.levelling}, "
            f"stride {args.stride}, {args.neighbours} neighbours)"
        )
        for key in (*STATS_KEYS, "nominal_area"):
            value = record[key]
            text = (
                "nan"
                if value is None
                else (f"{value:.6g}" if isinstance(value, float) else str(value))
            )
            print(f"  {key:18s} {text} {_UNITS.get(key, '')}".rstrip())
        _print_preparation(record["preparation"])
    return ExitStatus.OK


@_naming_the_file
def _scan(args: argparse.Namespace) -> int:
    # deferred: numba kernels, scipy and h5py, loaded by the command, not by --help
    from asperity.topo.scan import plot_resolution_scan, resolution_scan, write_scan_hdf5

    if args.out is not None:
        require_output_path(args.out, "--out")
    surface = _read(args)
    if isinstance(surface, LineProfile):  # Nayak's theory: asperity.topo.profile_cli
        return profile_scan(args, surface)
    prepared = _load_prepared(args, "scan", surface)
    preparation = prepared.record.as_dict()
    scan = resolution_scan(prepared.surface, args.max_stride, neighbours=args.neighbours)
    figure = args.figure
    if args.out:
        source = {"file": str(args.file), "detrend": preparation["levelling"]}
        write_scan_hdf5(scan, args.out, source=source | {"preparation": preparation})
        if figure is None:
            figure = str(Path(args.out).with_suffix(".png"))
    if figure:
        try:
            figure = plot_resolution_scan(scan, figure, title=str(args.file))
        except OSError:  # a full disk: the pair is written whole or not at all
            if args.out:
                Path(args.out).unlink(missing_ok=True)
            raise
    if args.json:
        data = {
            key: (json_number(v) if not isinstance(v, list) else [json_number(x) for x in v])
            for key, v in scan.as_dict().items()
        }
        data["preparation"] = preparation
        print(json.dumps(data, allow_nan=False))
    else:
        print_scan_table(scan)
        _print_preparation(preparation)
        for target in (args.out, figure):
            if target:
                print(f"wrote {target}")
    return ExitStatus.OK


def _synth(args: argparse.Namespace) -> int:
    # deferred: h5py and scipy, loaded by the command, not by --help
    from asperity.topo.io import write_hdf5
    from asperity.topo.synthetic import check_map_size, paper_like

    check_map_size(args.n, args.n, "--n")  # at once, with the memory it would take
    quantity("surface.synthetic.n").check(args.n, "--n")  # the job's bound (n >= 8)

    out = require_output_path(args.out, "--out")
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
    else:
        _write_numpy(surface, out)
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


def _write_numpy(surface, out: Path) -> None:  # noqa: ANN001 (a HeightMap)
    """``synth --out`` as .npz (heights, dx, dy in m) or .npy (heights in m), atomically: a
    full disk leaves the previous file or none, never a 0-byte or truncated one. The bytes are
    built in memory first: numpy's direct file write reports a full disk without its errno."""
    image = io.BytesIO()
    if out.suffix.lower() == ".npz":
        np.savez(image, heights=surface.heights, dx=surface.dx, dy=surface.dy)
    else:
        np.save(image, np.asarray(surface.heights), allow_pickle=False)
    write_bytes_atomic(out, image.getbuffer())


def _add_input_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file",
        help="height map or line profile: x3p, sur, dat, datx, plu, opd, di/spm, mi, gwy, "
        "csv (Dektak profile), txt/asc/xyz (text: needs --unit), npy, npz, h5",
    )
    form = parser.add_mutually_exclusive_group()
    form.add_argument(
        "--detrend",
        choices=("none", "mean", "plane", "quadratic"),
        default="plane",
        help="form removed before the analysis (default: plane)",
    )
    add_bounded_option(
        form,
        "--form-order",
        "surface.form_order",
        dest="form_order",
        default=None,
        metavar="N",
        help="remove the least-squares polynomial of order N (0 mean, 1 plane, 2 quadratic, "
        "... 8) instead of --detrend",
    )
    parser.add_argument(
        "--crop",
        default=None,
        metavar="X0:X1,Y0:Y1",
        help="keep pixels X0 <= i < X1 (axis 0) and Y0 <= j < Y1 (axis 1); an empty bound is "
        "the edge, e.g. 100:,:400",
    )
    parser.add_argument(
        "--crop-m",
        dest="crop_m",
        default=None,
        metavar="X0:X1,Y0:Y1",
        help="the same window in metres from the first pixel, e.g. 0:2e-4,1e-4:3e-4",
    )
    parser.add_argument(
        "--missing",
        choices=("keep", "refuse", "fill-lowest", "interpolate"),
        default="keep",
        help="missing pixels: keep them as holes (statistics over the valid area; default), "
        "refuse the map, fill them with the lowest height, or interpolate (harmonic fill)",
    )
    parser.add_argument(
        "--outliers",
        default="mad:10",
        type=_outlier_rule,
        metavar="RULE",
        help="outlier rule on the levelled heights: mad:K (beyond K x 1.4826 MAD of the "
        "median; default mad:10), percentile:P (below P or above 100-P percent), or none",
    )
    parser.add_argument(
        "--outlier-action",
        dest="outlier_action",
        choices=("mask", "clip"),
        default="mask",
        help="outliers become missing pixels, treated by --missing (mask; default), or are "
        "clipped to the rule's bounds",
    )
    parser.add_argument(
        "--pixel-size",
        dest="pixel_size",
        metavar="DX",
        default=None,
        help="pixel size in m (DX, or DX,DY), for files that carry none (npy, npz, text)",
    )
    parser.add_argument(
        "--unit",
        default=None,
        metavar="UNIT",
        help="length unit of a plain-text file's numbers, as in a job's [surface] unit: "
        f"{UNIT_HELP}; long names in any case, plural too. Text states none, and asperity "
        "never guesses it (required for text matrices and x y z / x z columns)",
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


def _short_cutoff(text: str) -> float:
    """``--short-cutoff``: 0 (none) or a wavelength within the shared bound."""
    try:
        if float(text) == 0:
            return 0.0
    except ValueError:
        pass
    return quantity("surface.synthetic.wavelength").option("--short-cutoff")(text)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}")
    return value


#: Figure formats ``scan --figure`` writes (the suffix picks the format).
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def _figure_path(text: str) -> Path | str:
    """``--figure``: a .png/.svg/.pdf file, a name without suffix (.png added), a folder
    (``resolution_scan.png`` inside it); the path returned is the file written. An empty name
    is refused (it would write nothing and say nothing)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(
            f"expected a file name ending in {', '.join(FIGURE_SUFFIXES)} or a folder, got an "
            "empty name"
        )
    path = Path(text)
    if path.is_dir():
        return path / "resolution_scan.png"
    if not path.suffix:
        return path.with_suffix(".png")
    if path.suffix.lower() not in FIGURE_SUFFIXES:
        raise argparse.ArgumentTypeError(
            f"expected a file name ending in {', '.join(FIGURE_SUFFIXES)} or a folder, got {text!r}"
        )
    return path


def _outlier_rule(text: str) -> str:
    """``--outliers``: none, mad, mad:K or percentile:P with K and P given and bounded."""
    method, colon, parameter = text.partition(":")
    if not colon or method not in ("mad", "percentile"):
        return text  # "none", "mad" or a wrong method: OutlierRule.parse names the mistake
    bound = quantity("surface.outlier_threshold")
    try:
        value = bound.parse(parameter, "--outliers")
    except InputError as exc:
        raise argparse.ArgumentTypeError(
            f"{method}:{parameter!r}: " + str(exc).removeprefix("--outliers: ")
        ) from None
    if method == "percentile" and not value < 50:
        raise argparse.ArgumentTypeError(f"expected a percentile P < 50, got {text!r}")
    return text


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
    add_bounded_option(
        scan,
        "--max-stride",
        "surface.max_stride",
        dest="max_stride",
        required=True,
        help="largest stride K",
    )
    scan.add_argument(
        "--out",
        default=None,
        help="write the scan to this HDF5 file (and the figure beside it as .png)",
    )
    scan.add_argument(
        "--figure",
        default=None,
        type=_figure_path,
        help="write the figure (PNG, 150 dpi) to this file, or into this folder "
        "(resolution_scan.png)",
    )
    scan.add_argument("--json", action="store_true", help="print the scan as one JSON object")
    _accept_negative_numbers(scan)
    scan.set_defaults(func=_scan)

    synth = subparsers.add_parser(
        "synth",
        help="write a seeded synthetic (paper-like) rough surface",
        description="Periodic random-phase surface, PSD flat below the roll-off and C ~ "
        "q^-2(1+H) above it (self-affine for H <= 1); defaults are the paper-like recipe "
        "(H = 1.36: smooth at small scales, not self-affine).",
    )
    synth.add_argument("--out", required=True, help="output .h5 (project HDF5), .npy or .npz")
    synth.add_argument(
        "--n", type=_positive_int, default=5000, help="pixels per side (5000; at most 10001)"
    )
    add_bounded_option(
        synth,
        "--pixel-size",
        "surface.pixel_size",
        dest="pixel_size",
        default=2e-6,
        help="pixel size in m (2e-6)",
    )
    add_bounded_option(synth, "--seed", "surface.synthetic.seed", default=0, help="random seed (0)")
    # defaults None: topo.synthetic.PAPER_LIKE (not imported here, to keep --help fast)
    add_bounded_option(
        synth,
        "--hurst",
        "surface.synthetic.hurst",
        default=None,
        help="spectral exponent H of C ~ q^-2(1+H), 0 < H <= 2: a Hurst exponent only for "
        "H <= 1 (self-affine); above 1 the surface is smooth at small scales (paper-like: 1.36)",
    )
    add_bounded_option(
        synth,
        "--rms-height",
        "surface.synthetic.rms_height",
        dest="rms_height",
        default=None,
        help="rms height in m (50e-6)",
    )
    add_bounded_option(
        synth,
        "--rolloff",
        "surface.synthetic.wavelength",
        default=None,
        help="roll-off wavelength in m (600e-6)",
    )
    synth.add_argument(
        "--short-cutoff",
        dest="short_cutoff",
        type=_short_cutoff,
        default=None,
        help="shortest wavelength in m (4e-6; 0 for none)",
    )
    _accept_negative_numbers(synth)
    synth.set_defaults(func=_synth)
