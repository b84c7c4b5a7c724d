"""The ``asperity bem`` sub-command, a thin shell over :func:`bem.solve_contact` and
:func:`bem.load_sweep`.

``asperity bem FILE --e-star E (--load F | --mean-pressure P) [--work-of-adhesion W
[--adhesion maugis --adhesion-range H0]] [--pixel-size DX] [--unit U]
[--detrend none|mean|plane|quadratic | --form-order N] [--tol T] [--json]``

Several loads (``--load 0.5,1,2``) give a warm-started sweep. ``--json`` prints
``contact_fraction``, ``real_area`` (m^2), ``normal_force`` (N), ``mean_gap`` (m), ``iterations``,
``converged``, ``seconds``, ``status``, ``branch`` (lists when several loads). Exit status 1 when a
solve did not converge (results still printed), 2 for bad input. Negative loads (``--load -1e-3``,
a pull) are parsed as numbers; they need adhesion and a loaded state to pull on (a sweep such as
``--load 1e-3,-1e-4``).
"""

from __future__ import annotations

import argparse
import json
import re
import sys

from asperity.errors import InputError
from asperity.quantities import add_bounded_option, quantity

#: Keys of ``asperity bem --json``, in order (a contract with other tools: add, never rename).
JSON_KEYS = (
    "contact_fraction",
    "real_area",
    "normal_force",
    "mean_gap",
    "iterations",
    "converged",
    "seconds",
    "status",
    "branch",
)

# argparse takes "-1e6" for an option unless told that negative numbers (with exponents)
# are values: this sub-command has no option that looks like a number
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def _bad(message: str) -> Exception:
    from asperity.bem.errors import BemInputError

    return BemInputError(message)


def _load_list(key: str, option: str):
    """An argparse ``type=``: comma-separated loads of ``option``, each bounded by ``key``."""
    bound = quantity(key)

    def parse(text: str) -> list[float]:
        values = []
        for part in text.split(","):
            if not part.strip():
                raise argparse.ArgumentTypeError(f"empty entry in {text!r} (expected e.g. 0.5,1,2)")
            try:
                values.append(bound.parse(part.strip(), option))
            except InputError as exc:
                raise argparse.ArgumentTypeError(str(exc).removeprefix(f"{option}: ")) from None
        return values

    return parse


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``bem`` sub-command to the asperity parser."""
    p = subparsers.add_parser(
        "bem",
        help="real contact area of a height map pressed on a rigid flat (FFT-BEM)",
        description=(
            "Polonsky-Keer FFT boundary elements (paper Appendix B): an elastic half-space with "
            "the measured surface against a rigid flat, periodic domain, optional adhesion. "
            "Adhesion defaults to Pohrt-Popov (the paper's Appendix B, no adhesion on loading), "
            "while `asperity run` defaults to Maugis-Dugdale ([bem] adhesion): give --adhesion "
            "maugis --adhesion-range H0 to compare with a job. SI units: m, Pa, N, J/m^2."
        ),
    )
    p._negative_number_matcher = _NEGATIVE_NUMBER
    p.add_argument("file", metavar="FILE", help="height map (any format topo.read_surface reads)")
    add_bounded_option(
        p,
        "--e-star",
        "material.E_star",
        required=True,
        help="reduced modulus E* = E/(1-nu^2) (Pa)",
    )
    load = p.add_mutually_exclusive_group(required=True)
    load.add_argument(
        "--load",
        type=_load_list("loading.normal_load", "--load"),
        help="total normal force(s) F (N), e.g. 0.5,1,2 for a sweep",
    )
    load.add_argument(
        "--mean-pressure",
        type=_load_list("loading.mean_pressure", "--mean-pressure"),
        help="mean pressure(s) F/A (Pa), comma-separated",
    )
    add_bounded_option(
        p,
        "--work-of-adhesion",
        "material.work_of_adhesion",
        default="0",
        help="w (J/m^2); 0 = no adhesion",
    )
    p.add_argument(
        "--adhesion",
        choices=("pohrt-popov", "maugis"),
        default="pohrt-popov",
        help=(
            "how w acts: pohrt-popov (default, the paper's Appendix B) or maugis "
            "(Maugis-Dugdale: tension w/H0 wherever the gap is below --adhesion-range)"
        ),
    )
    add_bounded_option(
        p,
        "--adhesion-range",
        "bem.adhesion_range",
        help="Maugis-Dugdale range H0 (m), with --adhesion maugis",
    )
    add_bounded_option(
        p,
        "--pixel-size",
        "surface.pixel_size",
        help="pixel size (m) for formats without one (.npy, text)",
    )
    p.add_argument("--unit", help="length unit of a plain-text file (m, mm, um, nm): required")
    form = p.add_mutually_exclusive_group()
    form.add_argument(
        "--detrend",
        choices=("none", "mean", "plane", "quadratic"),
        default="plane",
        help="form removed before the solve (default plane; mean only for periodic maps)",
    )
    form.add_argument(
        "--form-order", type=int, choices=range(9), metavar="N", help="polynomial form 0..8"
    )
    add_bounded_option(
        p,
        "--tol",
        "bem.tol",
        default="1e-8",
        help="residual tolerance in [1e-14, 1e-2]",
    )
    add_bounded_option(
        p,
        "--max-iter",
        "bem.max_iter",
        default=None,
        help="iteration cap per solve",
    )
    p.add_argument(
        "--free-boundary",
        action="store_true",
        help="finite specimen (zero-padded, non-periodic) instead of the periodic domain",
    )
    p.add_argument(
        "--crop-to-fast-size",
        action="store_true",
        help="crop the map to FFT-friendly sizes (warns what was cut)",
    )
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    _add_shear_options(p)
    p.set_defaults(func=handler)


def _add_shear_options(p: argparse.ArgumentParser) -> None:
    """The shear curve's options (:mod:`asperity.bem.shear.cli`)."""
    from asperity.bem.shear.cli import add_shear_options

    add_shear_options(p)


def _solver_options(args: argparse.Namespace):
    """The SolverOptions of the command line (each option bounded by argparse already)."""
    from asperity.bem.options import SolverOptions

    return SolverOptions(tol=args.tol, max_iter=args.max_iter)


def _adhesion_law(args: argparse.Namespace) -> dict:
    """The ``adhesion`` and ``adhesion_range`` keywords of the command line (none for the
    default Pohrt-Popov criterion)."""
    if args.adhesion != "maugis":
        if args.adhesion_range is not None:
            raise _bad(
                f"--adhesion-range: applies to --adhesion maugis only, got {args.adhesion_range:g} "
                f"with --adhesion {args.adhesion}"
            )
        return {}
    if args.adhesion_range is None:
        raise _bad("--adhesion maugis: needs --adhesion-range H0 (m), got none")
    return {
        "adhesion": "maugis",
        "adhesion_range": args.adhesion_range,
    }


def _loads(args: argparse.Namespace, adhesive: bool) -> tuple[str, list[float]]:
    """Which load is imposed and its values; a pull needs adhesion and a loaded start."""
    kind = "normal_force" if args.load is not None else "mean_pressure"
    values = args.load if args.load is not None else args.mean_pressure
    option = "--load" if kind == "normal_force" else "--mean-pressure"
    if not adhesive and any(v <= 0 for v in values):
        raise _bad(
            f"{option}: loads must be > 0 without adhesion (a rigid flat "
            f"cannot pull on a non-adhesive surface), got {min(values):g}"
        )
    if values[0] < 0:
        raise _bad(
            f"{option}: the first load must be >= 0 (a pull needs a loaded adhesive contact to "
            f"pull on: sweep from a compressive load, e.g. 1e-3,{values[0]:g}), got {values[0]:g}"
        )
    return kind, values


def _check_mean_pressure(option: str, forces: list[float], nominal: float) -> None:
    """Refuse a force whose mean pressure on the map is beyond the bound of any contact."""
    bound = quantity("loading.mean_pressure")
    for force in forces:
        try:
            bound.check(float(f"{force / nominal:.6g}"), "mean pressure")
        except InputError as exc:
            raise _bad(
                f"{option}: {force:g} N on the map's {nominal:.4g} m^2 gives a {exc}"
            ) from None


def _read_heights(args: argparse.Namespace):
    """Heights (m) and pixel sizes (m) of the file, levelled (and cropped if asked)."""
    import numpy as np

    from asperity import topo
    from asperity.bem import crop_to_fast_size

    surface = topo.read_surface(args.file, pixel_size=args.pixel_size, unit=args.unit)
    if not isinstance(surface, topo.HeightMap):
        raise _bad(f"{args.file}: bem needs a 2D height map, the file holds a line profile")
    form = args.detrend if args.form_order is None else args.form_order
    surface = topo.level(surface, method=form)
    heights = np.asarray(surface.heights, dtype=np.float64)
    if surface.n_missing:
        raise _bad(
            f"{args.file}: heights: {surface.n_missing} missing (NaN) pixels; fill or crop them "
            "before a contact solve"
        )
    if args.crop_to_fast_size:
        heights = np.ascontiguousarray(crop_to_fast_size(heights))
    return heights, float(surface.dx), float(surface.dy)


def _print_table(args, heights, dx, dy, e_star, w, rows) -> None:
    print(
        f"{args.file}: {heights.shape[0]} x {heights.shape[1]} pixels, dx = {dx:.4g} m, "
        f"dy = {dy:.4g} m, E* = {e_star:.4g} Pa, w = {w:.4g} J/m^2"
    )
    print(
        f"{'normal_force (N)':>18} {'contact_fraction':>17} {'real_area (m^2)':>16} "
        f"{'mean_gap (m)':>13} {'iterations':>10} {'converged':>9} {'seconds':>8}"
    )
    for row in rows:
        print(
            f"{row['normal_force']:18.6g} {row['contact_fraction']:17.6g} "
            f"{row['real_area']:16.6g} {row['mean_gap']:13.6g} {row['iterations']:10d} "
            f"{row['converged']!s:>9} {row['seconds']:8.3f}"
        )


def handler(args: argparse.Namespace) -> int:
    """Run ``asperity bem``; returns 0, or 1 when a solve did not converge."""
    from asperity.bem import load_sweep, solve_contact
    from asperity.bem.shear.cli import check_shear_arguments, run_shear

    check_shear_arguments(args)
    e_star = args.e_star
    options = _solver_options(args)
    w = args.work_of_adhesion
    kind, loads = _loads(args, w > 0)
    heights, dx, dy = _read_heights(args)
    nominal = heights.size * dx * dy
    forces = [v if kind == "normal_force" else v * nominal for v in loads]
    if kind == "normal_force":
        _check_mean_pressure("--load", forces, nominal)
    if args.tangential_displacement is not None:
        return run_shear(args, heights, dx, dy)
    common = dict(work_of_adhesion=w, options=options, periodic=not args.free_boundary)
    common.update(_adhesion_law(args))
    if len(forces) == 1:
        results = [solve_contact(heights, dx, dy, e_star, normal_force=forces[0], **common)]
    else:
        results = load_sweep(heights, dx, dy, e_star, forces, **common)
    rows = [r.summary() for r in results]
    if args.json:
        pick = (lambda k: rows[0][k]) if len(rows) == 1 else (lambda k: [r[k] for r in rows])
        print(json.dumps({k: pick(k) for k in JSON_KEYS}))
    else:
        _print_table(args, heights, dx, dy, e_star, w, rows)
    for r in results:
        for warning in r.extra.get("warnings", []):
            print(
                f"asperity bem: warning at F = {r.normal_force + 0.0:.6g} N: {warning}",
                file=sys.stderr,
            )
    failed = [r for r in results if not r.converged]
    for r in failed:
        print(
            f"asperity bem: solve at F = {r.normal_force + 0.0:.6g} N did not converge "
            f"(status {r.status}): {r.message}",
            file=sys.stderr,
        )
    return 1 if failed else 0
