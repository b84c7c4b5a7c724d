"""The ``asperity init`` sub-command: write a commented starter job file.

``asperity init job.toml --surface map.x3p`` writes a job that runs as it is
(``asperity run job.toml``) on that measured map or line profile, with every key a newcomer
changes first commented in place: the material, the loads, the preparation, the BEM's adhesion
law and the measured curves to calibrate against. Without ``--surface`` the job names the
paper-like synthetic surface, so that it also runs as written; replacing its one ``recipe`` line
by ``file = "..."`` is the only change needed to use a measured map. The text is checked with
the job's own schema (:func:`asperity.pipelines.config.load_config`) before it is written, and
an existing file is never overwritten (``--force`` does).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from asperity.atomic import write_text_atomic
from asperity.errors import ExitStatus, InputError

#: File name endings of plain-text height files, which state no length unit.
TEXT_SUFFIXES = (".txt", ".asc", ".xyz", ".csv")

_HEAD = """\
# asperity job file, written by `asperity init`. Run it with:
#     asperity run {name} --out asperity-out
# SI units throughout (m, Pa, N, J/m^2, m^2). Every key and its bounds: docs/pipelines.md.

[surface]
"""

_SYNTHETIC = """\
# The paper-like synthetic surface (10 mm square). For your measurement, replace the
# [surface.synthetic] table below by one line: file = "your-map.x3p"
detrend = "plane"          # form removed: none | mean | plane | quadratic
max_stride = 26            # resolution scan over strides 1..26 of the map's pixel

[surface.synthetic]
recipe = "paper_like"
n = 1000                   # pixels per side
pixel_size = 10e-6         # m
seed = 0
"""

_FILE = """\
file = "{file}"{unit_line}
# channel = "Height"       # a multi-channel file's channel (default: the height channel)
detrend = "plane"          # form removed: none | mean | plane | quadratic
max_stride = 20            # resolution scan over strides 1..20 of the map's pixel
missing = "interpolate"    # missing pixels: refuse | fill-lowest | interpolate
outliers = "mad"           # outlier rule on the levelled heights: mad | percentile | none
# crop = [0, 512, 0, 512]  # pixel window kept (x0, x1, y0, y1)
"""

_REST = """
[material]
E_star = 2.133e6             # Pa, reduced modulus E* = E / (1 - nu^2)
work_of_adhesion = 0.040     # J/m^2
mode_mixity = 0.03           # lambda (fitted when measured shear curves are given)
shear_strength = 0.13e6      # tau0, Pa
equilibrium_distance = 0.2e-9  # epsilon, m
# hardness = 1e9             # Pa: turns on the plasticity checks

[loading]
nominal_area = {nominal_area}      # m^2, the apparent contact area A_n
normal_loads = [0.56, 1.06, 2.08]   # N
max_tangential_displacement = "auto"   # m, or "auto": until full sliding
steps = 201

[bem]
adhesive = true            # also the adhesive solves (loading branch)
adhesion = "maugis"        # maugis (adhesive on loading) | pohrt-popov (the paper's Appendix B)
adhesion_range = "auto"    # m, or "auto": the shortest range the grid resolves
# boundary = "free"        # periodic (default) | free: a map whose edges do not meet
# enabled = false          # no BEM: calibrate against [measured] normal_area instead

# [measured]               # your measurements, CSV with a header row (units in the header)
# normal_area = "area_vs_load.csv"    # columns normal_load [N], real_area [mm^2]
# shear_area = [{{normal_load = 1.06, file = "area_vs_shear.csv"}}]   # tangential_force, real_area
"""


def starter_job(name: str, surface: str | None, unit: str | None = None) -> str:
    """The text of a starter job file named ``name``.

    Parameters
    ----------
    name : str
        The file name, quoted in the file's run line.
    surface : str or None
        The measured map or line profile (a path as the job will read it); None: the
        paper-like synthetic surface.
    unit : str or None
        The length unit of a plain-text ``surface`` (written as ``unit = "..."``); a
        placeholder line asks for it when the file is text and no unit is given.
    """
    text = _HEAD.format(name=name)
    if surface is None:
        text += _SYNTHETIC
    else:
        unit_line = ""
        if unit is not None:
            unit_line = f'\nunit = "{unit}"               # length unit of the text file'
        elif surface.lower().endswith(TEXT_SUFFIXES):
            unit_line = (
                '\n# unit = "um"             # a text matrix or x y z / x z columns: '
                "state their length unit (m, mm, um, nm)"
            )
        text += _FILE.format(file=surface.replace("\\", "/"), unit_line=unit_line)
    return text + _REST.format(nominal_area="700e-6")


def _states_no_unit(path: Path) -> bool:
    """Whether ``path`` reads as plain text that needs a stated unit (not a Dektak CSV or a
    Gwyddion export, which state theirs)."""
    from asperity.errors import InputError as Refused
    from asperity.topo import read_surface  # deferred: topo.io loads h5py

    try:
        read_surface(path)
    except Refused as exc:
        return "unit: is not stated" in str(exc)
    return False


def run_init(args: argparse.Namespace) -> int:
    """Write the starter job; refuse an existing file unless ``--force``."""
    from asperity.pipelines.config import load_config  # deferred: loads the schema

    target = Path(args.job)
    if target.exists() and not args.force:
        raise InputError(f"{target}: exists; choose another name or give --force to overwrite")
    surface = None
    if args.surface is not None:
        path = Path(args.surface)
        if not path.is_file():
            raise InputError(f"--surface: {path}: no such file")
        surface = os.path.relpath(path.resolve(), target.resolve().parent)
        if surface.startswith(".."):  # outside the job's folder: the absolute path is clearer
            surface = str(path.resolve())
        if args.unit is None and _states_no_unit(path):
            raise InputError(
                f"--surface: {path} is plain text, which states no length unit; give --unit "
                "(m, mm, um, nm)"
            )
    text = starter_job(target.name, surface, args.unit)
    write_text_atomic(target, text)
    try:
        load_config(target)  # the starter must load as written
    except InputError:
        target.unlink()
        raise
    print(f"wrote {target}: edit the material and loads, then `asperity run {target}`")
    return int(ExitStatus.OK)


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``init`` sub-command."""
    parser = subparsers.add_parser(
        "init",
        help="write a commented starter job file (job.toml) to edit and run",
        description="Write a commented starter job file that `asperity run` runs as written: "
        "on --surface FILE (a measured map or line profile) or, without it, on the paper-like "
        "synthetic surface. SI units throughout.",
    )
    parser.add_argument("job", metavar="JOB.toml", help="the file to write (refused if it exists)")
    parser.add_argument(
        "--surface", metavar="FILE", help="your measured map or line profile (any format read)"
    )
    parser.add_argument(
        "--unit", help="length unit of a plain-text --surface (m, mm, um, nm): text states none"
    )
    parser.add_argument("--force", action="store_true", help="overwrite an existing JOB.toml")
    parser.set_defaults(func=run_init)
