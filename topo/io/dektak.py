"""Dektak-style stylus profilometer CSV (header blocks, then ``Scan Data``) -> LineProfile.

Facts (from the sample files): a ``Scan Parameters`` block with ``Length,<value> <unit>`` and
``Resolution,<value> <unit>/sample``, an ``Analytical Results`` block, then ``Scan Data``
followed by a column header such as ``Lateral um,Raw Micrometer,`` and one
``lateral,height,,`` line per sample. The lateral positions must be uniform (each within
half a step of ``x0 + i dx``, since they are printed rounded); the last position must reach
the declared ``Length`` (so a truncated file is refused). Numbers are in the text readers'
one format (``.`` decimal point; an empty height field is a missing point).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import LineProfile
from asperity.topo.io._common import (
    NUMBER,
    make_provenance,
    make_surface,
    parse_number,
    read_all_bytes,
)
from asperity.topo.io.limits import check_map_points
from asperity.topo.io.units import length_unit_in_metres

_COLUMN_UNITS = {"micrometer": "um", "nanometer": "nm", "millimeter": "mm", "angstrom": "A"}


def looks_like_dektak(head: bytes) -> bool:
    """Whether the first kilobytes of a text file look like a Dektak CSV export.

    Parameters
    ----------
    head : bytes
        The first bytes of the file.

    Returns
    -------
    bool
        True if they hold a ``Scan Data`` block (or ``Scan Parameters`` and ``Lateral``).
    """
    return b"Scan Data" in head or (b"Scan Parameters" in head and b"Lateral" in head)


def _column_unit(path: Path, label: str, field: str) -> float:
    words = label.replace("(", " ").replace(")", " ").split()
    for word in reversed(words):
        factor = length_unit_in_metres(_COLUMN_UNITS.get(word.lower(), word))
        if factor is not None:
            return factor
    raise TopographyFileError(path, field, f"is {label!r}; expected a length unit such as 'um'")


_DATA_LINE = re.compile(rf"[ \t]*({NUMBER.pattern})[ \t]*,[ \t]*({NUMBER.pattern})?[ \t]*(?:,.*)?")


def _data_columns(path: Path, lines: list[str], first: int) -> tuple[np.ndarray, np.ndarray]:
    """Lateral positions and heights (NaN where empty) of the data lines from ``first``."""
    lateral, heights = [], []
    for number, line in enumerate(lines[first:], start=first + 1):
        match = _DATA_LINE.fullmatch(line)
        if match is None:
            if not line.strip():
                continue
            parts = line.split(",")
            if len(parts) < 2:
                raise TopographyFileError(
                    path, f"data line {number}", f"is {line[:60]!r}; expected 'lateral,height'"
                )
            parse_number(path, f"data line {number}, lateral", parts[0])
            parse_number(path, f"data line {number}, height", parts[1])
            raise TopographyFileError(path, f"data line {number}", f"is {line[:60]!r}")
        lateral.append(match.group(1))
        heights.append(match.group(2) or "nan")
    check_map_points(path, "Scan Data", len(lateral))
    return np.array(lateral, dtype=np.float64), np.array(heights, dtype=np.float64)


def read_dektak(path: str | Path) -> LineProfile:
    """Read a Dektak CSV line scan; heights and sampling distance in m.

    Parameters
    ----------
    path : str or Path
        The CSV file (units from its column headers, e.g. ``Lateral um``).

    Returns
    -------
    LineProfile
        Heights in m (empty height fields are NaN), ``dx`` in m (least-squares step).

    Raises
    ------
    TopographyFileError
        No ``Scan Data`` block, malformed or ragged data lines, non-uniform lateral
        positions, or fewer samples than the declared scan ``Length``.
    """
    path = Path(path)
    text = read_all_bytes(path).decode("latin-1")
    lines = text.splitlines()
    try:
        start = next(i for i, line in enumerate(lines) if line.strip().startswith("Scan Data"))
    except StopIteration:
        raise TopographyFileError(path, "Scan Data", "block not found; not a Dektak CSV") from None
    declared_length = _declared_length(path, lines[:start])
    header_line, columns = _column_header(path, lines, start)
    lateral_factor = _column_unit(path, columns[0], "lateral column header")
    height_factor = _column_unit(path, columns[1], "height column header")
    lateral, heights = _data_columns(path, lines, header_line + 1)
    x = lateral * lateral_factor
    z = heights * height_factor
    dx = _uniform_step(path, x)
    if declared_length is not None and x[-1] - x[0] < declared_length - 2.5 * dx:
        raise TopographyFileError(
            path,
            "Length",
            f"declares {declared_length:.6g} m but the data stop at {x[-1] - x[0]:.6g} m "
            "(truncated file)",
        )
    provenance = make_provenance(
        path,
        "dektak-csv",
        instrument="stylus profilometer (Dektak CSV)",
        channel=columns[1].strip(),
        units={"lateral": columns[0].strip(), "height": columns[1].strip()},
    )
    return make_surface(path, z, (("lateral column step", dx),), provenance, profile=True)


def _declared_length(path: Path, header_lines: list[str]) -> float | None:
    """The scan ``Length,<value> <unit>`` of the header in m (the last one), or None."""
    declared_length = None
    for line in header_lines:
        parts = line.split(",")
        if parts[0].strip() == "Length" and len(parts) > 1:
            value = parts[1].split()
            factor = length_unit_in_metres(value[1]) if len(value) > 1 else None
            if factor is not None:
                declared_length = parse_number(path, "Length", value[0]) * factor
    return declared_length


def _column_header(path: Path, lines: list[str], start: int) -> tuple[int, list[str]]:
    """(line index, labels) of the column header: the first non-blank line after ``Scan Data``."""
    header_line = next((i for i in range(start + 1, len(lines)) if lines[i].strip()), None)
    if header_line is None:
        raise TopographyFileError(path, "Scan Data", "has no column header and no data lines")
    columns = lines[header_line].split(",")
    if len(columns) < 2:
        raise TopographyFileError(
            path, "column header", f"is {lines[header_line]!r}; expected 'lateral,height' labels"
        )
    return header_line, columns


def _uniform_step(path: Path, x: np.ndarray) -> float:
    """The sampling distance (m) of lateral positions ``x`` (m) that lie on a uniform grid.

    The positions are printed rounded (e.g. to 0.1 um for 0.156 um steps): dx and x0 are the
    least-squares line through them, and every sample must lie within half a step of that
    uniform grid, with increasing positions; at least 2 samples, all within 1 km.
    """
    if x.size < 2:
        raise TopographyFileError(path, "Scan Data", f"has {x.size} samples; expected at least 2")
    if not np.all(np.abs(x) < 1e3):
        raise TopographyFileError(
            path, "lateral column", "holds positions beyond 1 km; expected positions in m"
        )
    index = np.arange(x.size)
    dx, x0 = np.polyfit(index, x, 1)
    offset = np.abs(x - (x0 + dx * index))
    if dx <= 0 or np.any(np.diff(x) <= 0) or offset.max() > 0.51 * dx:
        worst = int(np.argmax(offset))
        raise TopographyFileError(
            path,
            "lateral column",
            f"is not a uniform, increasing grid: sample {worst + 1} is at {x[worst]:.6g} m, "
            f"{offset[worst] / abs(dx):.2f} steps from the best uniform grid (step "
            f"{dx:.6g} m); expected every sample within half a step of it",
        )
    return dx
