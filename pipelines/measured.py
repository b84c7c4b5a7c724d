"""Measured curves to calibrate against: CSV files with a header row (SI, or units stated).

* A_r(F_z) at rest: columns ``normal_load`` (N) and ``real_area`` (m^2).
* A_r(F_x) under shear: columns ``tangential_force`` (N) and ``real_area`` (m^2), one file per
  normal load (the load given in the configuration), or one long file with an extra
  ``normal_load`` (N) column holding several loads. A ``normal_load`` column in a file whose
  load is declared must hold that load, and every curve's load must be one of the configured
  ``loading.normal_loads`` (within :data:`LOAD_MATCH`): the contradiction is refused, naming
  both, before any stage runs.

A header cell may state its unit, ``real_area [mm^2]`` or ``tangential_force (mN)``; values
are converted to SI (:data:`UNIT_FACTORS`). Tabs, semicolons, commas or whitespace separate
the columns (the header row's most frequent of the first three, else whitespace); a message
about a missing column names the separator found. Extra
columns are ignored; comment lines start with ``#``. A file that lacks a column, holds a
non-numeric or non-finite value, a negative area or an area above A_n, or has fewer than two
rows is refused with a message naming the file, the file's own line number and the column.
"""

from __future__ import annotations

import csv
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.files import require_regular_file
from asperity.pipelines.config import MeasuredConfig


class MeasuredFileError(InputError):
    """A measured CSV file is malformed; the message names the file, row and column."""


@dataclass(frozen=True)
class NormalAreaCurve:
    """Measured real contact area at rest against normal load.

    Attributes
    ----------
    normal_load : ndarray
        F_z, N (sorted ascending).
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: np.ndarray
    real_area: np.ndarray
    source: str = ""


@dataclass(frozen=True)
class ShearAreaCurve:
    """Measured real contact area against tangential force at one normal load.

    Attributes
    ----------
    normal_load : float
        F_z, N.
    tangential_force : ndarray
        F_x, N, in acquisition (file) order.
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: float
    tangential_force: np.ndarray
    real_area: np.ndarray
    source: str = ""


#: Units accepted in a column header (``name [unit]`` or ``name (unit)``), as SI factors.
UNIT_FACTORS: dict[str, dict[str, float]] = {
    "area": {
        "m^2": 1.0,
        "cm^2": 1e-4,
        "mm^2": 1e-6,
        "um^2": 1e-12,
        "nm^2": 1e-18,
    },
    "force": {"N": 1.0, "kN": 1e3, "mN": 1e-3, "uN": 1e-6, "nN": 1e-9},
}
#: What each known column measures.
COLUMN_QUANTITY: dict[str, str] = {
    "real_area": "area",
    "normal_load": "force",
    "tangential_force": "force",
}
_HEADER = re.compile(r"^\s*([^\[\(]*?)\s*(?:[\[\(]\s*([^\]\)]*?)\s*[\]\)])?\s*$")


def _normal_unit(unit: str) -> str:
    """``µm²`` -> ``um^2``: one spelling per unit."""
    return (
        unit.replace("\u00b5", "u")
        .replace("\u03bc", "u")
        .replace("\u00b2", "^2")
        .replace("**", "^")
    )


def parse_header_cell(path: Path, cell: str) -> tuple[str, float]:
    """Column name and SI factor of a header cell (``real_area [mm^2]`` -> real_area, 1e-6).

    A known column without a unit is taken as SI; an unknown unit of a known column is refused.
    """
    match = _HEADER.match(cell)
    name, unit = (match.group(1), match.group(2)) if match else (cell.strip(), None)
    quantity = COLUMN_QUANTITY.get(name)
    if not unit or quantity is None:
        return name, 1.0
    factors = UNIT_FACTORS[quantity]
    factor = factors.get(_normal_unit(unit))
    if factor is None:
        raise MeasuredFileError(
            f"{path}: line 1, column {name!r}: unit {unit!r} not understood; expected one of "
            f"{', '.join(factors)}"
        )
    return name, factor


def _data_lines(path: Path) -> list[tuple[int, str]]:
    """(line number in the file, text) of every line that is not blank or a ``#`` comment."""
    require_regular_file(path, "measured file")
    with open(path, newline="", encoding="utf-8") as handle:
        return [
            (number, line)
            for number, line in enumerate(handle, start=1)
            if line.strip() and not line.lstrip().startswith("#")
        ]


#: The separators a measured file may use, by the name its messages give them.
SEPARATOR_NAMES: dict[str, str] = {"\t": "tab", ";": "semicolon", ",": "comma", " ": "whitespace"}
#: A whitespace-separated header cell that is only a unit (``[mm^2]``, ``(mN)``).
_UNIT_CELL = re.compile(r"^[\[\(][^\]\)]*[\]\)]$")


def _delimiter(header_line: str) -> str:
    """The separator of a file, found from its header row: the most frequent of tab,
    semicolon and comma (ties in that order), else whitespace (``" "``: runs of blanks)."""
    counts = {sep: header_line.count(sep) for sep in ("\t", ";", ",")}
    best = max(counts, key=lambda sep: counts[sep])  # first of the ties: tab, ;, ,
    return best if counts[best] else " "


def _whitespace_cells(text: str, header: bool) -> list[str]:
    """Cells of a whitespace-separated line; in the header a unit standing alone after its
    column (``real_area [mm^2]``) joins that column's cell."""
    cells: list[str] = []
    for token in text.split():
        if header and cells and _UNIT_CELL.match(token):
            cells[-1] = f"{cells[-1]} {token}"
        else:
            cells.append(token)
    return cells


def _split_rows(lines: list[tuple[int, str]], delimiter: str) -> list[list[str]]:
    """The cells of every line (header first), split at ``delimiter`` (:func:`_delimiter`)."""
    texts = [text for _, text in lines]
    if delimiter != " ":
        return [[cell.strip() for cell in row] for row in csv.reader(texts, delimiter=delimiter)]
    return [_whitespace_cells(text, header=i == 0) for i, text in enumerate(texts)]


def _cell_value(path: Path, number: int, name: str, row: list[str], i: int) -> float:
    try:
        value = float(row[i])
    except (IndexError, ValueError):
        found = row[i] if i < len(row) else "nothing"
        raise MeasuredFileError(
            f"{path}: line {number}, column {name!r}: expected a number, got {found!r}"
        ) from None
    if not np.isfinite(value):
        raise MeasuredFileError(f"{path}: line {number}, column {name!r}: not finite")
    return value


def read_columns(
    path: str | Path, columns: Sequence[str], optional: Iterable[str] = (), hint: str = ""
) -> dict[str, np.ndarray]:
    """Read named numeric columns of a CSV file with a header row, converted to SI.

    Parameters
    ----------
    path : path
        The CSV file: separated by tabs, semicolons, commas or whitespace (found from the
        header row, :func:`_delimiter`, and named in the messages); a header cell may carry a unit,
        ``real_area [mm^2]`` or ``tangential_force (mN)`` (:data:`UNIT_FACTORS`); without
        one the column is in SI (m^2, N).
    columns : sequence of str
        Required column names.
    optional : iterable of str
        Columns returned when present.
    hint : str
        Appended to the message of a missing column (another way to give it).

    Returns
    -------
    dict
        Column name -> values in SI units; ``"_line"`` -> each row's line number in the file.

    Raises
    ------
    MeasuredFileError
        Missing column, unknown unit, non-numeric or non-finite value (naming the file's own
        line number and the column), fewer than two data rows.
    """
    path = Path(path)
    lines = _data_lines(path)
    if not lines:
        raise MeasuredFileError(
            f"{path}: empty file; expected a header row with {', '.join(columns)}"
        )
    delimiter = _delimiter(lines[0][1])
    rows = _split_rows(lines, delimiter)
    cells = [parse_header_cell(path, cell) for cell in rows[0]]
    header = [name for name, _ in cells]
    for name in columns:
        if name not in header:
            raise MeasuredFileError(
                f"{path}: missing column {name!r} (header cells, separated by "
                f"{SEPARATOR_NAMES[delimiter]}: {', '.join(map(repr, header))}); expected "
                f"columns {', '.join(columns)} (SI, or with a unit: 'real_area [mm^2]')" + hint
            )
    wanted = list(columns) + [c for c in optional if c in header and c not in columns]
    index = {name: header.index(name) for name in wanted}
    values: dict[str, list[float]] = {name: [] for name in wanted}
    for (number, _), row in zip(lines[1:], rows[1:], strict=True):
        for name, i in index.items():
            values[name].append(_cell_value(path, number, name, row, i) * cells[i][1])
    arrays = {name: np.asarray(v, dtype=float) for name, v in values.items()}
    if len(arrays[columns[0]]) < 2:
        raise MeasuredFileError(f"{path}: fewer than two data rows")
    arrays["_line"] = np.array([number for number, _ in lines[1:]], dtype=int)
    return arrays


def check_areas(path: str | Path, cols: dict[str, np.ndarray], nominal_area: float | None) -> None:
    """Refuse a negative A_r, or A_r > A_n (m^2), naming the file's line and the column.

    An A_r above A_n is physically impossible; it is what areas in mm^2 under an SI header
    look like (``real_area`` means m^2: write ``real_area [mm^2]``).
    """
    area, lines = cols["real_area"], cols["_line"]
    negative = np.flatnonzero(area < 0)
    if negative.size:
        i = int(negative[0])
        raise MeasuredFileError(
            f"{path}: line {lines[i]}, column 'real_area': negative area {area[i]:.6g} "
            "(expected m^2 >= 0)"
        )
    if nominal_area is None:
        return
    above = np.flatnonzero(area > nominal_area)
    if above.size:
        i = int(above[0])
        raise MeasuredFileError(
            f"{path}: line {lines[i]}, column 'real_area': A_r = {area[i]:.6g} m^2 exceeds "
            f"the nominal area A_n = {nominal_area:.6g} m^2 (loading.nominal_area), which is "
            "impossible; if the file holds mm^2 or um^2, say so in the header "
            "('real_area [mm^2]')"
        )


def read_normal_area(path: str | Path, nominal_area: float | None = None) -> NormalAreaCurve:
    """Read a measured A_r(F_z) CSV (``normal_load`` N, ``real_area`` m^2, or with units).

    ``nominal_area`` (m^2), when given, refuses any A_r above it (:func:`check_areas`).
    """
    cols = read_columns(path, ("normal_load", "real_area"))
    check_areas(path, cols, nominal_area)
    order = np.argsort(cols["normal_load"])
    return NormalAreaCurve(cols["normal_load"][order], cols["real_area"][order], str(path))


#: Relative difference within which two normal loads are the same load: a measured curve's
#: load and a configured one, or a file's ``normal_load`` column and the load declared for it.
#: Laboratory load cells hold a set load to about 1 %; a larger difference is another load.
LOAD_MATCH = 0.02

#: Force units whose factor a wrongly labelled load column is off by (for the hint).
_LOAD_UNIT_HINTS = {1e-3: "mN", 1e-6: "uN", 1e3: "kN"}

_LONG_FILE_HINT = (
    '; or declare the file\'s one load: shear_area = [{normal_load = N, file = "curve.csv"}]'
)


def _same_load(a: np.ndarray | float, b: float) -> np.ndarray | bool:
    """Loads (N) within :data:`LOAD_MATCH` of ``b`` (relative to the larger magnitude)."""
    a = np.asarray(a, dtype=float)
    return np.abs(a - b) <= LOAD_MATCH * np.maximum(np.abs(a), abs(b))


def _declared_load(path: Path, cols: dict[str, np.ndarray], declared: float) -> np.ndarray:
    """The loads of a file declared at ``declared`` N; a contradicting column is refused."""
    if "normal_load" not in cols:
        return np.full(cols["real_area"].shape, float(declared))
    column = cols["normal_load"]
    wrong = np.flatnonzero(~_same_load(column, declared))
    if wrong.size:
        i = int(wrong[0])
        distinct = np.unique(column)
        held = (
            f"{distinct.size} loads ({', '.join(f'{v:.4g}' for v in distinct[:8])} N)"
            if distinct.size > 1
            else f"{distinct[0]:.6g} N"
        )
        raise MeasuredFileError(
            f"{path}: declared at normal_load = {declared:g} N in measured.shear_area, but its "
            f"'normal_load' column holds {held} (line {cols['_line'][i]}: {column[i]:.6g} N, "
            f"more than {100 * LOAD_MATCH:g} % from the declaration): give the file without "
            "a declaration (a long file, one curve per load of its column), or correct one of "
            "the two"
        )
    return np.full(column.shape, float(declared))


def read_shear_area(
    path: str | Path, normal_load: float | None = None, nominal_area: float | None = None
) -> list[ShearAreaCurve]:
    """Read measured A_r(F_x) curves from one CSV file.

    Parameters
    ----------
    path : path
        Columns ``tangential_force`` (N), ``real_area`` (m^2) and, for a long file holding
        several loads, ``normal_load`` (N).
    normal_load : float, optional
        The normal load, N, of a one-curve file. Without it the file must have a
        ``normal_load`` column; with it, a ``normal_load`` column (when present) must hold
        that load (within :data:`LOAD_MATCH`), else the contradiction is refused.
    nominal_area : float, optional
        A_n, m^2: any A_r above it is refused (:func:`check_areas`).

    Returns
    -------
    list of ShearAreaCurve
        One per distinct normal load, points in the file's order (the acquisition order:
        the fit finds the first static peak of F_x in it, before the stick-slip tail).

    Raises
    ------
    MeasuredFileError
        A malformed file (:func:`read_columns`), impossible areas, or a declared load that
        the file's ``normal_load`` column contradicts (naming both).
    """
    path = Path(path)
    if normal_load is None:
        cols = read_columns(
            path, ("normal_load", "tangential_force", "real_area"), hint=_LONG_FILE_HINT
        )
        loads = cols["normal_load"]
    else:
        cols = read_columns(path, ("tangential_force", "real_area"), optional=("normal_load",))
        loads = _declared_load(path, cols, normal_load)
    check_areas(path, cols, nominal_area)
    curves = []
    for load in np.unique(loads):
        pick = loads == load
        fx, ar = cols["tangential_force"][pick], cols["real_area"][pick]
        check_friction_magnitude(path, load, fx, cols["_line"][pick])
        curves.append(ShearAreaCurve(float(load), fx, ar, str(path)))
    return curves


#: Largest |F_x| / F_z a measured shear curve may show: adhesive elastomer contacts reach
#: friction coefficients of a few to some tens at light loads; a hundred or more is what a
#: tangential force in mN (or uN) under an SI header (``tangential_force`` means N) looks like.
MAX_FRICTION_COEFFICIENT = 100.0


def check_friction_magnitude(
    path: str | Path, normal_load: float, tangential_force: np.ndarray, lines: np.ndarray
) -> None:
    """Refuse a curve whose |F_x| / F_z exceeds :data:`MAX_FRICTION_COEFFICIENT`.

    The magnitude check of the ``tangential_force`` column, as the configured loads check
    the ``normal_load`` one: the message names the file's line and, when a force unit would
    bring the ratio into the plausible range, that unit (``tangential_force [mN]``). Curves
    at F_z <= 0 N (adhesive contacts under tension) are not checked: any ratio is possible.
    """
    if not normal_load > 0 or tangential_force.size == 0:
        return
    ratio = np.abs(tangential_force) / normal_load
    worst = int(np.argmax(ratio))
    if ratio[worst] <= MAX_FRICTION_COEFFICIENT:
        return
    hint = next(
        (
            f"; if the column holds {unit}, say so in the header ('tangential_force [{unit}]'): "
            f"|F_x|/F_z would be {ratio[worst] * factor:.3g}"
            for factor, unit in ((1e-3, "mN"), (1e-6, "uN"))
            if ratio[worst] * factor <= MAX_FRICTION_COEFFICIENT
        ),
        "",
    )
    raise MeasuredFileError(
        f"{path}: line {lines[worst]}, column 'tangential_force': F_x = "
        f"{tangential_force[worst]:.6g} N at F_z = {normal_load:.6g} N is |F_x|/F_z = "
        f"{ratio[worst]:.3g} > {MAX_FRICTION_COEFFICIENT:g}, beyond any measured friction "
        "coefficient ('tangential_force' means N)" + hint
    )


def _unit_hint(load: float, configured: np.ndarray) -> str:
    """A hint when ``load`` (N) is a unit factor (1e-3, 1e3, ...) from a configured load."""
    for factor, unit in _LOAD_UNIT_HINTS.items():
        if np.any(_same_load(configured, load * factor)):
            return (
                f"; {load:.6g} {unit} would be a configured load: if the column holds {unit}, "
                f"say so in its header ('normal_load [{unit}]')"
            )
    return ""


def _distance_text(load: float, nearest: float) -> str:
    """How far a load is from the nearest configured one (N): a percentage or a factor."""
    if nearest != 0 and load / nearest > 0 and max(load / nearest, nearest / load) >= 2:
        return f"a factor {max(load / nearest, nearest / load):.3g} away"
    return f"{abs(load - nearest) / max(abs(nearest), abs(load)):.1%} away"


def check_curve_loads(curves: Sequence[ShearAreaCurve], normal_loads: Sequence[float]) -> None:
    """Refuse a measured A_r(F_x) curve whose load is none of the configured loads (N).

    The lambda fit evaluates the model at each curve's own load, and the report compares the
    prediction with the measurement at the configured loads; a curve at a load that is not
    configured (beyond :data:`LOAD_MATCH`) is most often a mistake (loads in mN under an
    ``N`` header, the loads of another experiment), so it is refused before any stage runs,
    quoting the file's value and the configured ones.

    Raises
    ------
    MeasuredFileError
        Naming the file, the curve's load and the configured loads.
    """
    configured = np.asarray(normal_loads, dtype=float)
    if not configured.size:
        return
    for curve in curves:
        load = curve.normal_load
        if np.any(_same_load(configured, load)):
            continue
        nearest = float(configured[np.argmin(np.abs(configured - load))])
        listed = ", ".join(f"{f:g}" for f in configured)
        raise MeasuredFileError(
            f"{curve.source}: a curve at normal_load = {load:.6g} N matches none of "
            f"loading.normal_loads ({listed} N; nearest {nearest:g} N, "
            f"{_distance_text(load, nearest)}, more than {100 * LOAD_MATCH:g} %): "
            "add its load to loading.normal_loads, or correct the file"
            + _unit_hint(load, configured)
        )


def write_shear_area(path: str | Path, curves: Sequence[ShearAreaCurve]) -> None:
    """Write curves as one long CSV (``normal_load,tangential_force,real_area``, SI)."""
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(["normal_load", "tangential_force", "real_area"])
        for curve in curves:
            for fx, ar in zip(curve.tangential_force, curve.real_area, strict=True):
                writer.writerow([repr(curve.normal_load), repr(float(fx)), repr(float(ar))])


@dataclass(frozen=True)
class Measurements:
    """The measured curves of a job configuration (``[measured]``), read before any stage.

    Attributes
    ----------
    normal_area : NormalAreaCurve or None
        A_r(F_z) at rest.
    shear_area : list of ShearAreaCurve
        A_r(F_x) curves, one per normal load.
    """

    normal_area: NormalAreaCurve | None = None
    shear_area: list[ShearAreaCurve] = field(default_factory=list)


def read_measurements(
    config: MeasuredConfig,
    nominal_area: float | None = None,
    normal_loads: Sequence[float] | None = None,
) -> Measurements:
    """Read every measured file of a ``[measured]`` configuration (``MeasuredConfig``).

    ``nominal_area`` (m^2, ``loading.nominal_area``) refuses any measured A_r above it;
    ``normal_loads`` (N, ``loading.normal_loads``) refuses an A_r(F_x) curve at a load that
    is none of them (:func:`check_curve_loads`). Both checks run before any stage.
    """
    normal = (
        None if config.normal_area is None else read_normal_area(config.normal_area, nominal_area)
    )
    shear: list[ShearAreaCurve] = []
    for item in config.shear_area:
        shear += read_shear_area(item.file, item.normal_load, nominal_area)
    if normal_loads is not None:
        check_curve_loads(shear, normal_loads)
    return Measurements(normal, shear)
