"""The ``asperity init`` sub-command: write a commented starter job file.

``asperity init job.toml --surface map.x3p`` writes a job that runs as it is
(``asperity run job.toml``) on that measured map or line profile, with every key a newcomer
changes first commented in place: the material, the loads, the preparation, the BEM's adhesion
law and the measured curves to calibrate against. Without ``--surface`` the job names the
paper-like synthetic surface, so that it also runs as written; replacing its one ``recipe`` line
by ``file = "..."`` is the only change needed to use a measured map. The text is checked with
the job's own schema (:func:`asperity.pipelines.config.load_config`) before it is written, and
an existing file is never overwritten (``--force`` does), and then only by a job that loads.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shlex
from pathlib import Path

from asperity.atomic import atomic_output, sync_directory, write_error
from asperity.errors import ExitStatus, InputError, cut, inert
from asperity.files import describe_kind
from asperity.pipelines.config import preset_text
from asperity.quantities import quantity

#: File name endings of plain-text height files, which state no length unit.
TEXT_SUFFIXES = (".txt", ".asc", ".xyz", ".csv")

_HEAD = """\
# asperity job file, written by `asperity init`. Run it with:
#     asperity run {name} --out asperity-out
# SI units throughout (m, Pa, N, J/m^2, m^2). Every key and its bounds: docs/pipelines.md.

"""

#: Above the default job's text in a job written without ``--surface``.
_DEFAULT_NOTE = """\
# This is the embedded default job (what `asperity run` runs without a file): the paper-like
# synthetic surface. For your measurement, replace the [surface.synthetic] table below by one
# line in [surface]: file = "your-map.x3p" (`asperity init JOB.toml --surface MAP` does that).

"""

_FILE = """\
file = {file}{unit_line}
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
normal_loads = [0.56, 1.06, 1.58, 2.08, 2.57, 3.12]   # N, the six loads of Sahli et al.
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


def toml_string(text: str, option: str) -> str:
    """``text`` as a TOML basic string (``"..."``), escaped per the TOML 1.0 specification.

    The quotation mark and the back-slash are escaped, and so is every control character
    (U+0000..U+001F, U+007F): a file name or unit can then hold any character without ending
    the string, starting a comment or adding a key.

    Parameters
    ----------
    text : str
        The value (a file name, a unit).
    option : str
        The option it came from, for the message.

    Raises
    ------
    InputError
        ``text`` holds undecodable bytes (a file name that is not UTF-8): a TOML file, which
        is UTF-8, cannot name it.
    """
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise InputError(
            f"--{option}: {cut(text)} is not valid UTF-8 (a file name with undecodable bytes); "
            "a TOML job file cannot name it: rename the file"
        ) from None
    out = []
    for char in text:
        if char in ('"', "\\"):
            out.append("\\" + char)
        elif ord(char) < 0x20 or ord(char) == 0x7F:
            out.append(_TOML_SHORT.get(char, f"\\u{ord(char):04X}"))
        else:
            out.append(char)
    return '"' + "".join(out) + '"'


#: TOML's short escapes of control characters.
_TOML_SHORT = {"\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def starter_job(
    name: str, surface: str | None, unit: str | None = None, pixel_size: float | None = None
) -> str:
    """The text of a starter job file named ``name``.

    Parameters
    ----------
    name : str
        The file name, quoted in the file's run line (in a comment: its control characters
        are shown escaped).
    surface : str or None
        The measured map or line profile (a path as the job will read it); None: the
        paper-like synthetic surface.
    unit : str or None
        The length unit of a plain-text ``surface`` (written as ``unit = "..."``); a
        placeholder line asks for it when the file is text and no unit is given.
    pixel_size : float or None
        The pixel size of a ``surface`` that carries none (a NumPy array, a text matrix), m
        (written as ``pixel_size = ...``).

    Raises
    ------
    InputError
        ``surface`` or ``unit`` cannot be written in TOML (:func:`toml_string`).
    """
    text = _HEAD.format(name=inert(shlex.quote(name)))
    if surface is None:
        return text + _DEFAULT_NOTE + preset_text("default")
    unit_line = ""
    if unit is not None:
        unit_line = f"\nunit = {toml_string(unit, 'unit')}   # length unit of the text file"
    elif surface.lower().endswith(TEXT_SUFFIXES):
        unit_line = (
            '\n# unit = "um"             # a text matrix or x y z / x z columns: '
            "state their length unit (m, mm, um, nm)"
        )
    if pixel_size is not None:
        unit_line += f"\npixel_size = {float(pixel_size)!r}   # m, the map's pixel"
    text += "[surface]\n" + _FILE.format(file=toml_string(surface, "surface"), unit_line=unit_line)
    return text + _REST.format(nominal_area="700e-6")


def _surface_refusal(path: Path, unit: str | None, pixel_size: float | None) -> InputError | None:
    """What the readers say of ``path`` read as the job will read it (None: it reads).

    A plain-text file without ``--unit`` is refused asking for it; any other refusal of the
    readers is passed on, naming ``--surface``.
    """
    from asperity.topo import read_surface  # deferred: topo.io loads h5py

    try:
        read_surface(path, unit=unit, pixel_size=pixel_size)
    except InputError as exc:
        if unit is None and "unit: is not stated" in str(exc):
            return InputError(
                f"--surface: {cut(path)} is plain text, which states no length unit; give "
                "--unit (m, mm, um, nm)"
            )
        return InputError(f"--surface: {exc}")
    return None


def _surface_in_job(path: Path, target: Path) -> str:
    """How the job names ``path``: relative to the job's folder, or absolute when outside it.

    The name is refused when it is not a regular file (a folder, a FIFO, a device), and made
    absolute where the job's reader would expand a leading ``~``.
    """
    kind = describe_kind(path)
    if kind is None:
        raise InputError(f"--surface: {cut(path)}: no such file")
    if kind != "a regular file":
        raise InputError(f"--surface: {cut(path)}: is {cut(kind)}; expected a regular file")
    surface = os.path.relpath(path.resolve(), target.resolve().parent)
    if surface.startswith(".."):  # outside the job's folder: the absolute path is clearer
        surface = str(path.resolve())
    if os.sep != "/":  # Windows: the job writes forward slashes
        surface = surface.replace(os.sep, "/")
    if surface.startswith("~"):  # the job would read it as a home folder: say it in full
        surface = str(path.resolve())
    return surface


def _check_target(target: Path, force: bool) -> None:
    """Refuse a job file name that exists (unless ``force``), is a folder, or is too long."""
    if len(os.fsencode(target.name)) > _MAX_NAME_BYTES:
        raise InputError(
            f"{cut(target)}: the file name is {len(os.fsencode(target.name))} bytes long; "
            f"expected at most {_MAX_NAME_BYTES} (the file system's limit)"
        )
    kind = describe_kind(target)
    if kind not in (None, "a regular file"):
        raise InputError(f"{cut(target)}: is {cut(kind)}; expected a job file name (JOB.toml)")
    if kind is not None and not force:
        raise InputError(f"{cut(target)}: exists; choose another name or give --force to overwrite")


#: Longest file name most file systems accept, bytes (NAME_MAX).
_MAX_NAME_BYTES = 255


def _write_validated(target: Path, text: str) -> None:
    """Write ``text`` to ``target`` through a temporary file in its folder that replaces
    ``target`` only once it loads as a job; on any failure ``target`` is as it was."""
    from asperity.pipelines.config import load_config  # deferred: loads the schema

    folder = target.parent
    tmp = folder / f".asperity-init.{os.getpid()}.toml.tmp"
    try:
        with atomic_output(tmp) as part:
            part.write_text(text, encoding="utf-8")
        try:  # the starter must load as written, from the job's own folder
            load_config(tmp)
        except InputError as exc:
            raise InputError(str(exc).replace(str(tmp), str(target))) from None
        os.replace(tmp, target)
        sync_directory(folder)
    except OSError as exc:
        error = write_error(target, exc, _kept(target))
        if error is None:
            raise
        raise error from exc
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()


def _kept(target: Path) -> str:
    return f"{target} is unchanged" if target.exists() else "nothing was written"


def run_init(args: argparse.Namespace) -> int:
    """Write the starter job; refuse an existing file unless ``--force``.

    The surface is read as the job will read it and refused as the readers refuse it; the
    text is written to a temporary file, loaded and validated, and only then renamed over
    ``JOB.toml``: a refusal leaves an existing job byte for byte as it was.
    """
    target = Path(args.job)
    _check_target(target, args.force)
    surface = None
    if args.surface is not None:
        path = Path(args.surface)
        surface = _surface_in_job(path, target)
        refusal = _surface_refusal(path, args.unit, args.pixel_size)
        if refusal is not None:
            raise refusal
    elif args.unit is not None or args.pixel_size is not None:
        raise InputError("--unit, --pixel-size: given without --surface; they describe its file")
    text = starter_job(target.name, surface, args.unit, args.pixel_size)
    _write_validated(target, text)
    print(
        f"wrote {inert(target)}: edit the material and loads, then `asperity run {inert(target)}`"
    )
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
    parser.add_argument(
        "--pixel-size",
        type=quantity("surface.pixel_size").option("--pixel-size"),
        default=None,
        metavar="DX",
        help="pixel size (m) of a --surface that carries none (.npy, .npz, a text matrix)",
    )
    parser.add_argument("--force", action="store_true", help="overwrite an existing JOB.toml")
    parser.set_defaults(func=run_init)
