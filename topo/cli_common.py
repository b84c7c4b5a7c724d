"""What the topo sub-commands share, for maps (:mod:`asperity.topo.cli`) and line profiles
(:mod:`asperity.topo.profile_cli`) alike: the preparation options of the command line, JSON
numbers and the text table of a resolution scan (SI units).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Iterable

import numpy as np

from asperity.errors import InputError


def json_number(value: object) -> object:
    """``value`` as JSON writes it: a Python int, float or bool; a non-finite float as None."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def preparation_options(args: argparse.Namespace):
    """The :class:`~asperity.topo.preparation.PreparationOptions` of the command-line options."""
    # deferred: topo.cleaning and topo.preparation load scipy and numba; `asperity --help` must not
    from asperity.topo.cleaning import CropWindow, OutlierRule
    from asperity.topo.preparation import PreparationOptions

    if args.crop is not None and args.crop_m is not None:
        raise InputError("--crop and --crop-m: give the window once, in pixels or in metres")
    crop = None
    if args.crop is not None:
        crop = CropWindow.parse(args.crop, "px")
    elif args.crop_m is not None:
        crop = CropWindow.parse(args.crop_m, "m")
    order = (
        args.form_order
        if args.form_order is not None
        else PreparationOptions.order_of(args.detrend)
    )
    return PreparationOptions(
        crop=crop,
        missing=args.missing,
        outliers=OutlierRule.parse(args.outliers, args.outlier_action),
        form_order=order,
    )


def print_scan_table(
    scan, count: str = "N", extra: tuple[str, Iterable[object]] | None = None
) -> None:
    """The text table of a resolution scan (SI units) and its fits line.

    ``count`` labels the ``n_summits`` column; ``extra`` is an optional (label, values)
    column printed last (e.g. the bandwidth of a profile scan).
    """
    label, values = extra if extra is not None else ("", [None] * len(scan.stride))
    print(
        f"{'stride':>6s} {'resolution (m)':>15s} {count:>9s} {'eta (1/m^2)':>12s} "
        f"{'R (m)':>11s} {'sigma_s (m)':>12s}" + (f" {label:>9s}" if extra else "")
    )
    for row in zip(
        scan.stride,
        scan.resolution,
        scan.n_summits,
        scan.asperity_density,
        scan.summit_radius,
        scan.summit_height_rms,
        values,
        strict=True,
    ):
        print(
            f"{row[0]:6d} {row[1]:15.4e} {row[2]:9d} {row[3]:12.4e} {row[4]:11.4e} "
            f"{row[5]:12.4e}" + (f" {row[6]:9.3g}" if extra else "")
        )
    print(
        f"R = {scan.radius_slope:.4g} * resolution "
        f"{'-' if scan.radius_intercept < 0 else '+'} {abs(scan.radius_intercept):.4g} m; "
        f"eta = {scan.density_prefactor:.4g} * resolution^{scan.density_exponent:.4g} 1/m^2; "
        f"sigma_s = {scan.height_rms_mean:.4g} m "
        f"(spread {100 * scan.height_rms_relative_spread:.2f} %)"
    )
