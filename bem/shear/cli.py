"""The shear options of ``asperity bem`` (``--tangential-displacement``): a shear curve in load
control.

``asperity bem FILE --e-star E --load P [--work-of-adhesion W [--mode-mixity LAMBDA]]
(--shear-strength TAU | --friction-coefficient MU) --tangential-displacement D1,D2,... [--json]``

The normal preload at P (N, held during shear), then the flat displaced along x by each
delta_T (m) in order, warm-started:

* with ``--mode-mixity`` (needs ``--work-of-adhesion`` > 0): the paper's mixed-mode edge law
  G_I + lambda G_II = w (E:failure_locus), junctions shrink under shear and one past its
  instability slides with tau_0 (or mu p) on its non-adhesive contact
  (:func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`); the displacements must be
  non-decreasing;
* without it: the preload's contact set is held (Pohrt-Popov preload if w > 0) and each element
  sticks or slips under tau_0 or Coulomb mu p (:func:`asperity.bem.shear.rough.shear_curve`).

``--json`` prints a list, one object per displacement, with the keys of :data:`JSON_KEYS`
(SI units: m, N, m^2). Exit status 0, 1 when a step did not converge (results still printed),
2 for bad input. ``--tol`` applies to the preload and the shear solves, ``--max-iter`` to the
shear solves only (the preload keeps its default cap: a failed preload is reported as an error).
Only the light standard library is imported until the handler runs.
"""

from __future__ import annotations

import argparse
import json

from asperity.errors import InputError
from asperity.quantities import add_bounded_option, quantity

#: Keys of each entry of ``asperity bem --tangential-displacement ... --json`` (add, never
#: rename).
JSON_KEYS = (
    "tangential_displacement",
    "tangential_force",
    "normal_force",
    "real_area",
    "stick_area",
    "slip_area",
    "junctions",
    "sliding_junctions",
    "sliding",
    "converged",
    "iterations",
    "seconds",
)


def _displacements(text: str) -> list[float]:
    """``--tangential-displacement``: comma-separated delta_T (m), each bounded."""
    bound = quantity("loading.tangential_displacement")
    values = []
    for part in text.split(","):
        if not part.strip():
            raise argparse.ArgumentTypeError(f"empty entry in {text!r} (expected e.g. 0,1e-6,2e-6)")
        try:
            values.append(bound.parse(part.strip(), "--tangential-displacement"))
        except InputError as exc:
            raise argparse.ArgumentTypeError(
                str(exc).removeprefix("--tangential-displacement: ")
            ) from None
    return values


def add_shear_options(p: argparse.ArgumentParser) -> None:
    """Add the shear options of ``asperity bem`` to its parser."""
    g = p.add_argument_group("shear (with --tangential-displacement; nu = 1/2)")
    g.add_argument(
        "--tangential-displacement",
        type=_displacements,
        help="delta_T (m) of the flat along x, comma-separated, in loading order: a shear curve "
        "at the single --load, held",
    )
    law = g.add_mutually_exclusive_group()
    add_bounded_option(
        law,
        "--shear-strength",
        "material.shear_strength",
        help="tau_0 (Pa), the paper's sliding law",
    )
    add_bounded_option(
        law,
        "--friction-coefficient",
        "material.friction_coefficient",
        help="Coulomb mu (sliding traction mu p)",
    )
    add_bounded_option(
        g,
        "--mode-mixity",
        "material.mode_mixity",
        help="lambda of the mixed-mode edge law G_I + lambda G_II = w (needs --work-of-adhesion)",
    )


def _bad(message: str) -> Exception:
    from asperity.bem.errors import BemInputError

    return BemInputError(message)


def check_shear_arguments(args: argparse.Namespace) -> None:
    """Refuse shear options without ``--tangential-displacement`` and incomplete shear input."""
    shear_only = {
        "--shear-strength": args.shear_strength,
        "--friction-coefficient": args.friction_coefficient,
        "--mode-mixity": args.mode_mixity,
    }
    if args.tangential_displacement is None:
        given = [k for k, v in shear_only.items() if v is not None]
        if given:
            raise _bad(f"{given[0]}: applies with --tangential-displacement only, got none")
        return
    if args.shear_strength is None and args.friction_coefficient is None:
        raise _bad(
            "--tangential-displacement: needs --shear-strength TAU or --friction-coefficient MU, "
            "got neither"
        )
    if args.load is None or len(args.load) != 1:
        got = "--mean-pressure" if args.load is None else f"{len(args.load)} loads"
        raise _bad(f"--tangential-displacement: needs one --load P (N, held), got {got}")
    if args.adhesion != "pohrt-popov":
        raise _bad(f"--adhesion: a shear curve uses the Pohrt-Popov criterion, got {args.adhesion}")
    if args.mode_mixity is not None:
        if args.work_of_adhesion <= 0:
            raise _bad("--mode-mixity: needs --work-of-adhesion > 0 (J/m^2), got 0")
        values = args.tangential_displacement
        if any(b < a for a, b in zip(values, values[1:], strict=False)):
            raise _bad(
                "--tangential-displacement: with --mode-mixity the values must be non-decreasing "
                f"(the edge law is irreversible), got {','.join(f'{v:g}' for v in values)}"
            )


def run_shear(args: argparse.Namespace, heights, dx: float, dy: float) -> int:
    """The shear curve of the command line on levelled ``heights`` (m); returns the exit status."""
    import sys

    from asperity.bem.options import SolverOptions
    from asperity.bem.shear.mixed_mode import MixedModeLaw
    from asperity.bem.shear.rough import shear_curve
    from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
    from asperity.bem.shear.stick_slip import ShearOptions

    force = args.load[0]
    common = dict(
        shear_strength=args.shear_strength,
        friction_coefficient=args.friction_coefficient,
        periodic=not args.free_boundary,
        normal_options=SolverOptions(tol=args.tol),
        options=ShearOptions(tol=args.tol, max_iter=args.max_iter),
    )
    path = (heights, dx, dy, args.e_star, force, args.tangential_displacement)
    if args.mode_mixity is not None:
        law = MixedModeLaw(args.work_of_adhesion, args.mode_mixity)
        curve = mixed_mode_shear_curve(*path, law, **common)
    else:
        curve = shear_curve(*path, work_of_adhesion=args.work_of_adhesion, **common)
    rows = _json_rows(curve)
    if args.json:
        print(json.dumps(rows))
    else:
        _print_table(args, heights.shape, force, curve.normal_seconds, rows)
    failed = [r for r in rows if not r["converged"]]
    for r in failed:
        print(
            f"asperity bem: shear step at delta_T = {r['tangential_displacement']:.6g} m did not "
            "converge",
            file=sys.stderr,
        )
    return 1 if failed else 0


def _json_rows(curve) -> list[dict]:
    """One JSON-ready row per step of a shear curve (SI: m, N, m^2, s)."""
    return [
        {
            "tangential_displacement": float(curve.tangential_displacement[i]),
            "tangential_force": float(curve.tangential_force[i]),
            "normal_force": float(curve.normal_force[i]),
            "real_area": float(curve.real_area[i]),
            "stick_area": float(curve.stick_area[i]),
            "slip_area": float(curve.slip_area[i]),
            "junctions": int(curve.junctions[i]),
            "sliding_junctions": int(curve.sliding_junctions[i]),
            "sliding": bool(curve.sliding[i]),
            "converged": bool(curve.converged[i]),
            "iterations": int(curve.nit[i]),
            "seconds": float(curve.seconds[i]),
        }
        for i in range(curve.tangential_displacement.size)
    ]


def _print_table(args: argparse.Namespace, shape, force: float, preload_s: float, rows) -> None:
    """The shear curve as a terminal table (SI units), under a line naming the map and law."""
    print(
        f"{args.file}: {shape[0]} x {shape[1]} pixels, F_z = {force:.4g} N, "
        f"E* = {args.e_star:.4g} Pa, w = {args.work_of_adhesion:.4g} J/m^2, preload "
        f"{preload_s:.3f} s"
    )
    print(
        f"{'delta_T (m)':>12} {'F_x (N)':>12} {'A_r (m^2)':>12} {'stick (m^2)':>12} "
        f"{'junctions':>9} {'sliding':>7} {'converged':>9}"
    )
    for r in rows:
        print(
            f"{r['tangential_displacement']:12.5g} {r['tangential_force']:12.5g} "
            f"{r['real_area']:12.5g} {r['stick_area']:12.5g} {r['junctions']:9d} "
            f"{r['sliding']!s:>7} {r['converged']!s:>9}"
        )
