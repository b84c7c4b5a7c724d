"""The line-profile route of ``asperity stats`` and ``asperity scan`` (Nayak's theory).

``asperity stats PROFILE --json`` prints the keys of :data:`asperity.topo.cli.STATS_KEYS`
(``ny`` = 1; ``dy``, ``n_summits``, ``nominal_area`` and ``grid_area`` are null: a profile
has no y pixel size and no counted areal summits) and adds ``method`` ("nayak-profile"),
``n_peaks``, ``bandwidth``, the moments ``m0`` (m^2), ``m2`` (1), ``m4`` (1/m^2), ``status``,
``message``, ``warnings`` (the isotropy assumption first) and ``preparation``. Every value in
SI units.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from asperity.errors import ExitStatus
from asperity.topo.cli_common import json_number, preparation_options, print_scan_table
from asperity.topo.heightmap import LineProfile
from asperity.topo.nayak import profile_statistics


def _prepared(args: argparse.Namespace, profile: LineProfile, what: str):
    # deferred: profile_preparation loads scipy and numba (cleaning); `asperity --help` must not
    from asperity.topo.profile_preparation import prepare_profile

    options = argparse.Namespace(**vars(args))
    for name in ("crop", "crop_m"):  # a profile's window may be X0:X1 alone
        text = getattr(options, name)
        if text is not None and "," not in text:
            setattr(options, name, f"{text},:")
    prepared, record = prepare_profile(profile, preparation_options(options))
    if args.json:
        for warning in record["warnings"]:
            print(f"asperity {what}: warning: {warning}", file=sys.stderr)
    return prepared, record


def profile_record(profile: LineProfile, *, stride: int = 1) -> dict:
    """The ``asperity stats`` record of a levelled profile (keys in the module docstring)."""
    stats = profile_statistics(profile, stride=stride)
    heights = profile.heights[::stride]
    moments = stats.moments
    record = {
        "nx": int(heights.size),
        "ny": 1,
        "dx": moments.spacing,
        "dy": None,
        "rms_height": _profile_rms(heights),
        "n_missing": int(np.count_nonzero(np.isnan(heights))),
        "n_summits": None,
        "asperity_density": stats.asperity_density,
        "summit_radius": stats.summit_radius,
        "summit_height_rms": stats.summit_height_rms,
        "nominal_area": None,
        "grid_area": None,
        "method": stats.method,
        "n_peaks": stats.n_peaks,
        "bandwidth": stats.bandwidth,
        "m0": moments.m0,
        "m2": moments.m2,
        "m4": moments.m4,
        "status": stats.status,
        "message": stats.message,
        "warnings": list(stats.warnings),
    }
    return {key: json_number(value) for key, value in record.items()}


def _profile_rms(heights: np.ndarray) -> float:
    """``sqrt(<h^2>)`` over the valid points (m), about zero (the levelled datum)."""
    valid = np.asarray(heights)[~np.isnan(heights)]
    return float(np.sqrt(np.mean(valid * valid)))


def _print_record(args: argparse.Namespace, record: dict) -> None:
    units = {"dx": "m", "rms_height": "m", "asperity_density": "1/m^2", "summit_radius": "m"}
    units |= {"summit_height_rms": "m"}
    print(f"{args.file}: line profile, Nayak's theory (stride {args.stride})")
    for key in ("nx", "n_missing", "n_peaks", "bandwidth", *units):
        value = record[key]
        text = "nan" if value is None else (f"{value:.6g}" if isinstance(value, float) else value)
        print(f"  {key:18s} {text} {units.get(key, '')}".rstrip())
    _print_preparation(record["preparation"], record["warnings"])


def _print_preparation(preparation: dict, warnings: list[str]) -> None:
    print("  profile preparation:")
    print(f"    crop               {preparation['crop'] or 'none'} (points start, stop)")
    print(
        f"    levelling          {preparation['levelling']} (form rms "
        f"{preparation['form_rms']:.4g} m)"
    )
    print(
        f"    missing points     {preparation['n_missing']}, policy "
        f"{preparation['missing_policy']}, {preparation['n_filled']} filled"
    )
    print(f"    outliers           {preparation['n_outliers']} ({preparation['outlier_rule']})")
    for warning in (*preparation["warnings"], *warnings):
        print(f"  WARNING: {warning}")


def profile_stats(args: argparse.Namespace, profile: LineProfile) -> int:
    """``asperity stats`` of a line profile; exit 0, or 1 when R and sigma_s are undefined."""
    prepared, preparation = _prepared(args, profile, "stats")
    record = profile_record(prepared, stride=args.stride)
    record["channel"] = prepared.provenance.get("channel")
    record["preparation"] = preparation
    if args.json:
        print(json.dumps(record, allow_nan=False))
        if record["status"] >= 2:  # the status 1 says why on stderr too, not only in the JSON
            print(f"asperity stats: {args.file}: {record['message']}", file=sys.stderr)
    else:
        _print_record(args, record)
    return ExitStatus.OK if record["status"] < 2 else ExitStatus.NOT_CONVERGED


def profile_scan(args: argparse.Namespace, profile: LineProfile) -> int:
    """``asperity scan`` of a line profile (Nayak's statistics against the sampling interval)."""
    # deferred: numba kernels, scipy and h5py, loaded by the command, not by --help
    from asperity.topo.profile_scan import profile_resolution_scan
    from asperity.topo.scan import plot_resolution_scan, write_scan_hdf5

    prepared, preparation = _prepared(args, profile, "scan")
    scan = profile_resolution_scan(prepared, args.max_stride)
    figure = args.figure
    if args.out:
        source = {"file": str(args.file), "method": scan.method, "preparation": preparation}
        write_scan_hdf5(scan, args.out, source=source)
        figure = figure or str(Path(args.out).with_suffix(".png"))
    if figure:
        figure = plot_resolution_scan(scan, figure, title=f"{args.file} (line profile, Nayak)")
    data = {
        key: (json_number(v) if not isinstance(v, list) else [json_number(x) for x in v])
        for key, v in scan.as_dict().items()
    }
    if args.json:
        print(json.dumps(data | {"preparation": preparation}, allow_nan=False))
    else:
        print_scan_table(scan, "peaks", ("alpha", scan.bandwidth))
        _print_preparation(preparation, list(scan.warnings))
        for target in (args.out, figure):
            if target:
                print(f"wrote {target}")
    return ExitStatus.OK
