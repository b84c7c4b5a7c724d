"""Plain-text height data: a matrix of heights, ``x y z`` columns on a regular grid, an
``x z`` line profile, or a Gwyddion text export (the last two in
:mod:`asperity.topo.io.text_layouts`).

Units are never guessed: a Gwyddion export states its own; any other layout carries no unit,
so the caller states it (``unit="um"``: heights and x, y columns in that length unit; the
command line's ``--unit``, the job's ``[surface] unit``), or the file is refused with an error
naming it and saying how to state the unit. Lines starting with ``#`` or ``%`` are comments.
A line of words before the first number (a header asperity does not know) is refused as an
unsupported format, not as a badly written number.

The one number format (stated, never guessed): ``[+-]digits[.digits][(e|E)[+-]digits]``
with ``.`` as the decimal point, or ``nan`` (a missing pixel). Decimal commas, digit
separators (``1_000``, ``1,000``), ``inf`` and hexadecimal are refused with an error naming
the file, line and column. Separators: the first data line fixes one for the whole file:
``;`` if it holds one, else ``,`` if it holds one, else blanks (spaces or tabs); blanks
around ``,``/``;`` and one trailing separator per line are allowed. So ``1,5;2,5`` and
``1,5 2,5`` (decimal commas) are refused, never read as four numbers.

* Gwyddion text export (``# Width:``, ``# Height:``, ``# Value units:`` comment lines): the
  pixel sizes are Width / columns and Height / rows; the file rows run along x, so the map
  is the transposed matrix (axis 0 = x).
* ``x z`` profile: two columns, at least 8 rows, x strictly increasing and uniform.
* Matrix: read as written, ``heights[i, j]`` is row ``i``, column ``j`` of the file, so the
  row index is axis 0 (x). The pixel size must come from the caller (``pixel_size``).
* ``x y z`` columns (three columns whose first two repeat like grid coordinates): the grid
  is rebuilt from the distinct x and y values, whose steps must be uniform (within 1e-4 of
  the step: a non-uniform grid is refused, never interpolated); ``dx``, ``dy`` are those
  steps. A node may appear at most once; nodes absent from the file (instruments often
  skip invalid points) become missing pixels (NaN), counted in ``provenance["missing_nodes"]``.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import CorruptFileError, TopographyFileError, UnsupportedContentError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import (
    NAN_WORDS,
    NUMBER,
    caller_pixel_size,
    make_provenance,
    make_surface,
    parse_number,
    read_all_bytes,
)
from asperity.topo.io.limits import check_map_points
from asperity.topo.io.text_layouts import (
    MIN_PROFILE_POINTS,
    comment_header,
    gwyddion_grid,
    is_gwyddion_header,
    is_xz_profile,
    profile_step,
)
from asperity.topo.io.units import length_unit_in_metres

#: Largest relative deviation of an x or y step from the mean step of an x-y-z grid.
_STEP_TOLERANCE = 1e-4


_VALUE = f"(?:{NUMBER.pattern}|[+-]?(?:nan|NaN|NAN))"
_LINE_PATTERNS = {
    None: re.compile(rf"{_VALUE}(?:[ \t]+{_VALUE})*"),
    ",": re.compile(rf"{_VALUE}(?:[ \t]*,[ \t]*{_VALUE})*(?:[ \t]*,)?"),
    ";": re.compile(rf"{_VALUE}(?:[ \t]*;[ \t]*{_VALUE})*(?:[ \t]*;)?"),
}


#: A first data line that starts with neither a digit, a sign nor a point: a header.
_HEADER_WORDS = re.compile(r"[^0-9+\-.]")
_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?")


def _separator(line: str) -> str | None:
    """The separator the first data line announces: ';', ',' or None (blanks)."""
    if ";" in line:
        return ";"
    if "," in line:
        return ","
    return None


def _fields(line: str, separator: str | None) -> list[str]:
    if separator is None:
        return line.split()
    fields = [field.strip() for field in line.split(separator)]
    return fields[:-1] if len(fields) > 1 and fields[-1] == "" else fields


def _refuse_line(path: Path, number: int, line: str, separator: str | None) -> None:
    """Name the first value of a refused line that is not a number (line and column)."""
    if separator == ",":  # blank-separated decimal commas, e.g. '1,5 2,5'
        for token in line.split():
            if _DECIMAL_COMMA.fullmatch(token):
                where = f"line {number}, column {line.find(token) + 1}"
                parse_number(path, where, token)
    cursor = 0
    for index, field in enumerate(_fields(line, separator), start=1):
        column = line.find(field, cursor) + 1 if field else cursor + 1
        cursor = max(column, cursor)
        where = f"line {number}, column {column} (value {index})"
        if field == "":
            raise CorruptFileError(
                path, where, f"is empty; expected a number (separator {separator!r}; nan = missing)"
            )
        parse_number(path, where, field, allow_nan=True)
    raise CorruptFileError(path, f"line {number}", f"is {line[:60]!r}; expected numbers only")


def _decoded(path: Path) -> str:
    """The file's text: UTF-8 where it decodes as such (Gwyddion writes 'µm' so), else latin-1."""
    raw = read_all_bytes(path)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _refuse_header(path: Path, number: int, line: str) -> None:
    """A line of words before the first number: a header asperity does not know."""
    raise UnsupportedContentError(
        path,
        f"line {number}",
        f"is {line[:60]!r}, a header asperity does not read: unsupported format (text files "
        "are read as a height matrix, x y z columns, an x z profile or a Gwyddion text "
        "export, with '#' comment lines; SurfaceTopography reads more text layouts: "
        '"asperity[formats]", then asperity.topo.io.surfacetopography.read_with_extra)',
    )


def _rows(path: Path) -> tuple[list[np.ndarray], list[str]]:
    """The numeric lines of the file (float64 arrays) and the comment lines before them."""
    rows: list[np.ndarray] = []
    comments: list[str] = []
    separator: str | None = None
    values = 0
    for number, line in enumerate(_decoded(path).splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped[0] in "#%":
            if not rows and stripped:
                comments.append(stripped)
            continue
        if not rows:
            if _HEADER_WORDS.match(stripped) and stripped.split()[0] not in NAN_WORDS:
                _refuse_header(path, number, stripped)
            separator = _separator(stripped)
        if not _LINE_PATTERNS[separator].fullmatch(stripped):
            _refuse_line(path, number, stripped, separator)
        fields = _fields(stripped, separator)
        row = np.array([float("nan") if field in NAN_WORDS else float(field) for field in fields])
        values += row.size
        check_map_points(path, f"data up to line {number}", values)
        rows.append(row)
    if not rows:
        raise TopographyFileError(path, "data", "no numeric lines found")
    return rows, comments


def _pixel_sizes(
    path: Path, pixel_size: float | tuple[float, float] | None, shape: tuple[int, ...]
) -> tuple[float, float]:
    sizes = caller_pixel_size(path, pixel_size)
    if sizes is None:
        two_columns = (
            f" (two columns are read as an x z profile only from {MIN_PROFILE_POINTS} rows on, "
            "with x strictly increasing)"
            if shape[1] == 2
            else ""
        )
        raise InputError(
            f"{path}: a plain height matrix ({shape[0]} x {shape[1]} values, no '# Width:' / "
            "'# Height:' header) carries no pixel size; give pixel_size= (or --pixel-size DX "
            f"on the command line), in metres{two_columns}"
        )
    return sizes


def _looks_like_xyz(rows: list[np.ndarray]) -> bool:
    """Three columns whose first two repeat like grid coordinates (not a 3-column matrix)."""
    if len(rows) < 4 or any(len(row) != 3 for row in rows):
        return False
    array = np.vstack(rows)
    n_x, n_y = np.unique(array[:, 0]).size, np.unique(array[:, 1]).size
    return 1 < n_x < len(rows) and 1 < n_y < len(rows) and n_x * n_y <= 2 * len(rows)


def _grid_step(path: Path, values: np.ndarray, name: str) -> float:
    """The uniform step (m) of the sorted distinct coordinates ``values``, or refuse."""
    steps = np.diff(values)
    step = float(steps.mean())
    if np.ptp(steps) > _STEP_TOLERANCE * step:
        worst = int(np.argmax(np.abs(steps - step)))
        raise TopographyFileError(
            path,
            f"{name} column",
            f"is not a uniform grid: steps range from {steps.min():.6g} to {steps.max():.6g} "
            f"(e.g. {values[worst]:.6g} -> {values[worst + 1]:.6g}); expected one constant "
            f"step (within {_STEP_TOLERANCE:g} of it); resample the data onto a regular grid",
        )
    return step


def _metres_per_unit(path: Path, unit: str | None, layout: str) -> float:
    """Metres per the stated ``unit``; a refusal naming the file when none is stated."""
    if unit is None:
        raise TopographyFileError(
            path,
            "unit",
            f"is not stated ({layout}): a text file carries no length unit, and asperity "
            "never guesses one "
            "(metres or micrometres differ by 1e6); state it: read_surface(path, unit='um'), "
            '--unit um on the command line, or unit = "um" under [surface] in the job file',
        )
    factor = length_unit_in_metres(str(unit))
    if factor is None:
        raise InputError(f"{path}: unit: expected a length unit (m, mm, um, nm, ...), got {unit!r}")
    return factor


def _read_xyz(path: Path, rows: list[np.ndarray], unit: str | None) -> HeightMap:
    array = np.vstack(rows)
    if np.isnan(array[:, :2]).any():
        line = int(np.flatnonzero(np.isnan(array[:, :2]).any(axis=1))[0]) + 1
        raise TopographyFileError(
            path, "x y columns", f"data row {line} has a nan coordinate; expected x and y in m"
        )
    xs, ix = np.unique(array[:, 0], return_inverse=True)
    ys, iy = np.unique(array[:, 1], return_inverse=True)
    dx = _grid_step(path, xs, "x")
    dy = _grid_step(path, ys, "y")
    node = ix * ys.size + iy
    counts = np.bincount(node, minlength=xs.size * ys.size)
    if counts.max() > 1:
        first = int(np.flatnonzero(counts > 1)[0])
        raise TopographyFileError(
            path,
            "x y columns",
            f"give the node ({xs[first // ys.size]:.6g}, {ys[first % ys.size]:.6g}) "
            f"{counts[first]} times; expected every grid node at most once "
            "(if this is a 3-column height matrix, save it as .npy instead)",
        )
    factor = _metres_per_unit(path, unit, "x y z columns")  # after the layout's own checks
    dx, dy = dx * factor, dy * factor
    heights = np.full((xs.size, ys.size), np.nan)
    heights[ix, iy] = array[:, 2] * factor
    missing = int(xs.size * ys.size - len(rows))
    provenance = make_provenance(
        path,
        "xyz-text",
        channel="z",
        units={"all": f"{unit} (stated)"},
        missing_nodes=missing or None,
    )
    return make_surface(path, heights, (("x column step", dx), ("y column step", dy)), provenance)


def _refuse_pixel_size(path: Path, pixel_size: object, layout: str) -> None:
    if pixel_size is not None:
        raise InputError(
            f"{path}: pixel_size {pixel_size!r} given, but {layout} carry their own "
            "coordinates (lateral calibration); leave pixel_size (--pixel-size) out"
        )


def _read_xz_profile(path: Path, rows: list[np.ndarray], unit: str | None) -> LineProfile:
    """Two columns ``x z`` (in ``unit``) with uniform, increasing x -> LineProfile (m)."""
    array = np.vstack(rows)
    if np.isnan(array[:, 0]).any():
        line = int(np.flatnonzero(np.isnan(array[:, 0]))[0]) + 1
        raise TopographyFileError(
            path, "x column", f"data row {line} has a nan position; expected x in m"
        )
    dx = profile_step(path, array[:, 0])
    factor = _metres_per_unit(path, unit, "x z profile columns")  # after the layout's checks
    array, dx = array * factor, dx * factor
    provenance = make_provenance(
        path, "xz-profile-text", channel="z", units={"all": f"{unit} (stated)"}
    )
    return make_surface(path, array[:, 1], (("x column step", dx),), provenance, profile=True)


def _read_gwyddion(path: Path, rows: list[np.ndarray], header: dict) -> HeightMap | LineProfile:
    """A Gwyddion text export: the matrix (file rows along x) with Width/Height/units."""
    matrix = _matrix(path, rows)
    heights, dx, dy, units = gwyddion_grid(path, header, matrix)
    provenance = make_provenance(
        path, "gwyddion-text", channel=header.get("channel", "heights"), units=units
    )
    sizes = (("# Width / columns", dx), ("# Height / rows", dy))
    profile = min(heights.shape) == 1
    return make_surface(path, heights, sizes, provenance, profile=profile)


def _matrix(path: Path, rows: list[np.ndarray]) -> np.ndarray:
    """The rows as one matrix, or refuse ragged rows naming the first one."""
    lengths = [len(row) for row in rows]
    if len(set(lengths)) != 1:
        bad = next(i for i, n in enumerate(lengths) if n != lengths[0])
        raise TopographyFileError(
            path,
            f"data row {bad + 1}",
            f"has {lengths[bad]} values; expected {lengths[0]} like the first row "
            "(ragged or truncated matrix)",
        )
    return np.vstack(rows)


def read_text(
    path: str | Path,
    *,
    pixel_size: float | tuple[float, float] | None = None,
    unit: str | None = None,
) -> HeightMap | LineProfile:
    """Read a text height matrix, ``x y z`` columns, an ``x z`` profile or a Gwyddion export.

    Layouts (values in ``unit``, converted to m; the rules in this module's docstring and in
    :mod:`asperity.topo.io.text_layouts`):

    * a Gwyddion text export (``# Width:``/``# Height:`` header): a map whose pixel sizes
      come from the header, file rows along x;
    * ``x y z`` columns of a regular grid: a map;
    * two columns, at least 8 rows, the first strictly increasing: an ``x z`` profile
      (uniform positions required);
    * any other matrix: ``heights[i, j]`` = row i, column j (needs ``pixel_size``); a single
      row or column is a :class:`LineProfile`.

    Parameters
    ----------
    path : str or Path
        The text file.
    pixel_size : float or (float, float), optional
        ``dx`` or ``(dx, dy)`` in m for a plain matrix; refused for the layouts that carry
        their own calibration.
    unit : str, optional
        The length unit of the file's numbers (heights and x, y columns): "m", "mm", "um",
        "nm", ... Required for every layout but a Gwyddion export (which states its own, and
        refuses a second statement).

    Returns
    -------
    HeightMap or LineProfile

    Raises
    ------
    TopographyFileError
        Text not in the stated number format (:class:`NumberFormatError`, naming line and
        column), a header asperity does not know (:class:`UnsupportedContentError`,
        "unsupported format"), ragged rows (e.g. a truncated file), a non-uniform x-y grid
        or profile, a node given twice; no ``unit`` stated for a layout without one.
    InputError
        A matrix without ``pixel_size``, an invalid ``pixel_size``, or ``pixel_size``
        given for a layout with its own calibration.
    """
    path = Path(path)
    rows, comments = _rows(path)
    header = comment_header(comments)
    if is_gwyddion_header(header):
        _refuse_pixel_size(path, pixel_size, "the Gwyddion header lines (# Width, # Height)")
        if unit is not None:
            raise InputError(
                f"{path}: unit {unit!r} given, but a Gwyddion text export states its own "
                "units in its header; leave unit (--unit) out"
            )
        return _read_gwyddion(path, rows, header)
    if _looks_like_xyz(rows):
        _refuse_pixel_size(path, pixel_size, "x y z columns (the pixel sizes are their steps)")
        return _read_xyz(path, rows, unit)
    if is_xz_profile(rows):
        _refuse_pixel_size(path, pixel_size, "the x positions of an x z profile")
        return _read_xz_profile(path, rows, unit)
    if path.suffix.lower() == ".xyz":
        raise TopographyFileError(
            path,
            "columns",
            f"hold {len(rows)} rows of {len(rows[0])} values; a .xyz file must hold x y z "
            "columns of a regular grid (at least 2 x 2 nodes)",
        )
    heights = _matrix(path, rows)
    dx, dy = _pixel_sizes(path, pixel_size, heights.shape)
    heights = heights * _metres_per_unit(path, unit, "a plain height matrix")
    provenance = make_provenance(
        path, "matrix-text", channel="heights", units={"z": f"{unit} (stated)", "xy": "m"}
    )
    profile = heights.shape[1] == 1 or heights.shape[0] == 1
    sizes = (("pixel_size dx", dx), ("pixel_size dy", dy))
    return make_surface(path, heights, sizes, provenance, profile=profile)
