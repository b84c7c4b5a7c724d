"""The ``asperity bem`` sub-command, a thin shell over :func:`bem.solve_contact` and
:func:`bem.load_sweep`.

``asperity bem FILE --e-star E (--load F | --mean-pressure P) [--work-of-adhesion W]
[--pixel-size DX] [--detrend none|mean|plane] [--tol T] [--json]``

Several loads (``--load 0.5,1,2``) give a warm-started sweep. ``--json`` prints
``contact_fraction``, ``real_area`` (m^2), ``normal_force`` (N), ``mean_gap`` (m), ``iterations``,
``converged``, ``seconds`` (lists when several loads). Exit status 1 when a solve did not converge
(results still printed).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys

#: Keys of ``asperity bem --json``, in order (a contract with other tools).
JSON_KEYS = (
    "contact_fraction",
    "real_area",
    "normal_force",
    "mean_gap",
    "iterations",
    "converged",
    "seconds",
)


def _positive(name: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{name}: expected a number, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name}: expected a finite value > 0, got {text!r}")
    return value


def _load_list(name: str, text: str) -> list[float]:
    values = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            raise ValueError(f"{name}: empty entry in {text!r} (expected e.g. 0.5,1,2)")
        try:
            value = float(part)
        except ValueError:
            raise ValueError(
                f"{name}: expected numbers separated by commas, got {text!r}"
            ) from None
        if not math.isfinite(value):
            raise ValueError(f"{name}: expected finite numbers, got {text!r}")
        values.append(value)
    return values


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``bem`` sub-command to the asperity parser."""
    p = subparsers.add_parser(
        "bem",
        help="real contact area of a height map pressed on a rigid flat (FFT-BEM)",
        description=(
            "Polonsky-Keer FFT boundary elements (paper Appendix B): an elastic half-space with "
            "the measured surface against a rigid flat, periodic domain, optional Pohrt-Popov "
            "adhesion. SI units: m, Pa, N, J/m^2."
        ),
    )
    p.add_argument("file", metavar="FILE", help="height map (any format topo.read_surface reads)")
    p.add_argument("--e-star", required=True, help="reduced modulus E* = E/(1-nu^2) (Pa)")
    load = p.add_mutually_exclusive_group(required=True)
    load.add_argument("--load", help="total normal force(s) F (N), e.g. 0.5,1,2 for a sweep")
    load.add_argument("--mean-pressure", help="mean pressure(s) F/A (Pa), comma-separated")
    p.add_argument("--work-of-adhesion", default="0", help="w (J/m^2); 0 = no adhesion")
    p.add_argument("--pixel-size", help="pixel size (m) for formats without one (.npy, text)")
    p.add_argument(
        "--detrend",
        choices=("none", "mean", "plane"),
        default="plane",
        help="form removed before the solve (default plane; mean only for periodic maps)",
    )
    p.add_argument("--tol", default="1e-8", help="residual tolerance (see docs/bem.md)")
    p.add_argument("--max-iter", type=int, default=None, help="iteration cap per solve")
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
    p.set_defaults(func=handler)


def handler(args: argparse.Namespace) -> int:
    """Run ``asperity bem``; returns 0, or 1 when a solve did not converge."""
    # OpenMP threads that spin on a shared 2-core machine slow FFTW down badly; must be set
    # before pyFFTW loads libgomp (it is imported lazily by bem.fft_backend).
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    import numpy as np

    from asperity import topo
    from asperity.bem import crop_to_fast_size, load_sweep, solve_contact

    e_star = _positive("--e-star", args.e_star)
    tol = _positive("--tol", args.tol)
    try:
        w = float(args.work_of_adhesion)
    except ValueError:
        raise ValueError(
            f"--work-of-adhesion: expected a number, got {args.work_of_adhesion!r}"
        ) from None
    if not (math.isfinite(w) and w >= 0):
        raise ValueError(f"--work-of-adhesion: expected a finite value >= 0, got {w}")
    pixel_size = _positive("--pixel-size", args.pixel_size) if args.pixel_size is not None else None
    if args.max_iter is not None and args.max_iter < 1:
        raise ValueError(f"--max-iter: expected an integer >= 1, got {args.max_iter}")
    if args.load is not None:
        loads = _load_list("--load", args.load)
        kind = "normal_force"
    else:
        loads = _load_list("--mean-pressure", args.mean_pressure)
        kind = "mean_pressure"
    if w == 0 and any(v <= 0 for v in loads):
        raise ValueError(f"--{kind.replace('_', '-')}: loads must be > 0 without adhesion")

    surface = topo.read_surface(args.file, pixel_size=pixel_size)
    if not isinstance(surface, topo.HeightMap):
        raise ValueError(f"{args.file}: bem needs a 2D height map, the file holds a line profile")
    surface = topo.level(surface, method=args.detrend)
    heights = np.asarray(surface.heights, dtype=np.float64)
    if surface.n_missing:
        raise ValueError(
            f"{args.file}: heights: {surface.n_missing} missing (NaN) pixels; fill or crop them "
            "before a contact solve"
        )
    if args.crop_to_fast_size:
        heights = np.ascontiguousarray(crop_to_fast_size(heights))
    dx, dy = float(surface.dx), float(surface.dy)
    nominal = heights.size * dx * dy
    forces = [v if kind == "normal_force" else v * nominal for v in loads]
    options = dict(
        work_of_adhesion=w, tol=tol, max_iter=args.max_iter, periodic=not args.free_boundary
    )
    if len(forces) == 1:
        results = [solve_contact(heights, dx, dy, e_star, normal_force=forces[0], **options)]
    else:
        results = load_sweep(heights, dx, dy, e_star, forces, **options)

    rows = [r.summary() for r in results]
    if args.json:
        if len(rows) == 1:
            out = {k: rows[0][k] for k in JSON_KEYS}
        else:
            out = {k: [row[k] for row in rows] for k in JSON_KEYS}
        print(json.dumps(out))
    else:
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
    failed = [r for r in results if not r.converged]
    for r in failed:
        print(
            f"asperity bem: solve at F = {r.normal_force:.6g} N did not converge: {r.message}",
            file=sys.stderr,
        )
    return 1 if failed else 0
