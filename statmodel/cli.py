"""Sub-commands of the statmodel package: ``asperity friction`` and ``asperity figures``.

``asperity friction PARAMS.toml [--json] [--out FILE.h5]`` solves the shear curve of the parameter
file (schema in :mod:`statmodel.config`), prints a short summary (or one JSON object with
``--json``) and optionally writes HDF5. Exit status 0, 1 if the solve did not converge (results
still printed/written), 2 for bad input (raised as :class:`asperity.errors.InputError`). A Tabor
parameter below 5 prints ``asperity friction: warning: ...`` on stderr (the run goes on).

``asperity figures --out DIR`` writes the paper's Figs. 1, 2, 4 and 5 as PNG plus their data in
``DIR/statmodel_figures.h5`` (see :mod:`statmodel.figures`).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import warnings
from pathlib import Path

from asperity.errors import ExitStatus
from asperity.statmodel.checks import StatmodelWarning
from asperity.statmodel.config import read_friction_parameters


def run_friction(args: argparse.Namespace) -> int:
    """Handler of ``asperity friction``; returns the exit status."""
    # deferred: numba kernels and h5py, loaded by the command, not by --help
    from asperity.statmodel.results_io import curve_to_json, write_curve_hdf5
    from asperity.statmodel.shear import OUTSIDE_MODEL, shear_curve

    params = read_friction_parameters(args.params)
    # A model outside its validity must say so on stderr whatever the user's warning filters
    # (a StatmodelWarning, TaborWarning included, is printed once as "asperity friction:
    # warning: ..."; others pass through). A curve outside the model (status 3) exits 3.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        curve = shear_curve(
            params.material,
            params.roughness,
            params.nominal_area,
            params.normal_load,
            params.tangential_displacement,
            **params.accuracy,
        )
    seen: set[str] = set()
    for w in caught:
        if issubclass(w.category, StatmodelWarning):  # TaborWarning, area_fraction, ...
            text = str(w.message)
            if text not in seen:
                seen.add(text)
                print(f"asperity friction: warning: {text}", file=sys.stderr)
        else:
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    if args.out is not None:
        attrs = {
            "parameters_file": str(args.params),
            **{f"material.{k}": v for k, v in dataclasses.asdict(params.material).items()},
            **{f"roughness.{k}": v for k, v in dataclasses.asdict(params.roughness).items()},
            "nominal_area_m2": params.nominal_area,
        }
        write_curve_hdf5(curve, args.out, attrs)
    if args.json:
        print(curve_to_json(curve))
    else:
        print(
            f"Tabor parameter          {curve.tabor_parameter:.6g}\n"
            f"preload separation       {curve.separation_preload:.6g} m\n"
            f"real area at preload     {curve.real_area[0]:.6g} m^2\n"
            f"static friction (peak)   {curve.static_friction:.6g} N\n"
            f"sliding friction         {curve.sliding_friction:.6g} N\n"
            f"sliding displacement     {curve.sliding_displacement:.6g} m\n"
            f"steps                    {curve.tangential_displacement.size}\n"
            f"status                   {curve.message}"
        )
    if not curve.converged:
        print(f"asperity friction: {curve.message}", file=sys.stderr)
        return ExitStatus.NOT_CONVERGED
    if curve.status == OUTSIDE_MODEL:
        return ExitStatus.INVALID_RESULT
    return ExitStatus.OK


def run_figures(args: argparse.Namespace) -> int:
    """Handler of ``asperity figures``; returns the exit status."""
    # deferred: numba kernels, h5py and matplotlib, only for the command
    from asperity.statmodel.figures import write_all_figures

    paths = write_all_figures(Path(args.out))
    for p in paths:
        print(p)
    return ExitStatus.OK


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``friction`` and ``figures`` to the asperity parser."""
    p = subparsers.add_parser(
        "friction",
        help="statistical adhesive-friction model: shear curve from a TOML parameter file",
        description="Shear a rough adhesive contact at constant normal load up to full sliding "
        "(Xu et al. 2022, Sections 2-4). SI units. Example: statmodel/examples/fig4.toml.",
    )
    p.add_argument("params", type=Path, help="parameter file (TOML: material/roughness/loading)")
    p.add_argument("--json", action="store_true", help="print the result as one JSON object")
    p.add_argument("--out", type=Path, default=None, help="write the result to this HDF5 file")
    p.set_defaults(func=run_friction)
    f = subparsers.add_parser(
        "figures",
        help="write the paper's Figs. 1, 2, 4, 5 (PNG) and their data (HDF5)",
        description="Draw the paper's Figs. 1 (a single asperity: JKR indentation and "
        "Papangelo-Ciavarella shear), 2 (the stick/slip status map), 4 (a rough-contact shear "
        "curve: F_z, counts, A_r, F_x against delta_T, stick and slip parts) and 5 (shear "
        "curves as w, lambda, tau0 and F_z vary) with the captions' parameters, as PNG in "
        "--out, with every curve's data in DIR/statmodel_figures.h5 (SI units).",
    )
    f.add_argument("--out", type=Path, required=True, help="output directory")
    f.set_defaults(func=run_figures)
