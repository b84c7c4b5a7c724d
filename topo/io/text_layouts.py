"""Layouts of plain-text topography beyond a bare matrix: the Gwyddion text export and the
two-column ``x z`` line profile (the universal stylus export).

* Gwyddion text export (``File > Save as > ASCII data matrix`` with the header option): comment
  lines ``# Channel: NAME``, ``# Width: 12.34 µm``, ``# Height: 5678.9 nm`` and
  ``# Value units: m`` (German: ``Kanal``, ``Breite``, ``Höhe``) before a height matrix whose
  file rows run along x: row ``r`` of the file is the line ``y = r dy``, column ``c`` the point
  ``x = c dx``. So ``heights[i, j] = matrix[j, i]`` (axis 0 is x, as in every HeightMap),
  ``dx = Width / columns``, ``dy = Height / rows``, heights times the value unit in m.
* ``x z`` profile: two columns, at least :data:`MIN_PROFILE_POINTS` rows, the first one
  strictly increasing: positions and heights, both in m. The positions must be uniform
  (each within :data:`POSITION_TOLERANCE` of a step from the least-squares uniform grid):
  asperity reads uniformly sampled profiles only and never interpolates.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.topo.errors import TopographyFileError, UnsupportedContentError
from asperity.topo.io._common import NUMBER, parse_number
from asperity.topo.io.units import length_unit_in_metres

#: Fewest rows of two columns read as an ``x z`` profile (fewer: a two-column matrix).
MIN_PROFILE_POINTS = 8
#: Largest distance of a profile position from the uniform grid, in steps.
POSITION_TOLERANCE = 0.05

#: Gwyddion header keys (English and German) and the field each one gives.
_GWYDDION_KEYS = {
    "channel": "channel",
    "kanal": "channel",
    "width": "width",
    "breite": "width",
    "height": "height",
    "höhe": "height",
    "value units": "value_units",
    "werteinheiten": "value_units",
}
_HEADER_LINE = re.compile(r"[#%]\s*([^:=]+?)\s*[:=]\s*(.*?)\s*")


def comment_header(comments: list[str]) -> dict[str, str]:
    """The Gwyddion header fields found in the comment lines before the data.

    Parameters
    ----------
    comments : list of str
        The comment lines (starting with ``#`` or ``%``), stripped.

    Returns
    -------
    dict
        ``{"channel", "width", "height", "value_units"}`` as written (those present), each
        ``(value, line)``-free text; unknown keys are ignored (plain comments).
    """
    header: dict[str, str] = {}
    for line in comments:
        match = _HEADER_LINE.fullmatch(line)
        if match is None:
            continue
        key = _GWYDDION_KEYS.get(match.group(1).strip().lower())
        if key is not None and key not in header:
            header[key] = match.group(2)
    return header


def is_gwyddion_header(header: dict[str, str]) -> bool:
    """Whether the comment header is a Gwyddion text export's (it gives Width or Height)."""
    return "width" in header or "height" in header


def _length(path: Path, field: str, text: str) -> float:
    """A header length such as ``12.34 µm`` in m."""
    match = re.fullmatch(rf"({NUMBER.pattern})\s*(\S*)", text.strip())
    if match is None:
        raise TopographyFileError(
            path, field, f"is {text[:40]!r}; expected a length such as '12.34 µm'"
        )
    factor = length_unit_in_metres(match.group(2) or "m")
    if factor is None:
        raise TopographyFileError(
            path, field, f"has the unit {match.group(2)!r}; expected a length unit (m, µm, nm)"
        )
    return parse_number(path, field, match.group(1)) * factor


def gwyddion_grid(
    path: Path, header: dict[str, str], matrix: np.ndarray
) -> tuple[np.ndarray, float, float, dict]:
    """Heights (m, axis 0 = x), dx, dy (m) and units of a Gwyddion text export's matrix.

    Parameters
    ----------
    path : Path
        The file (for messages).
    header : dict
        From :func:`comment_header`.
    matrix : ndarray, shape (rows, columns)
        The numbers as written (file rows along x).

    Returns
    -------
    heights, dx, dy, units

    Raises
    ------
    TopographyFileError
        ``Width`` or ``Height`` missing or not a length; a value unit that is not a length.
    """
    for key, label in (("width", "# Width"), ("height", "# Height")):
        if key not in header:
            raise TopographyFileError(
                path, label, "is missing; a Gwyddion text export gives both Width and Height"
            )
    width = _length(path, "# Width", header["width"])
    height = _length(path, "# Height", header["height"])
    unit = header.get("value_units", "m").strip() or "m"
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise UnsupportedContentError(
            path,
            "# Value units",
            f"is {unit!r}; expected a length unit (a height channel), not another quantity",
        )
    rows, columns = matrix.shape
    units = {"lateral": f"{header['width']} / {header['height']}", "height": unit}
    return matrix.T * factor, width / columns, height / rows, units


def is_xz_profile(rows: list[np.ndarray]) -> bool:
    """Two columns, at least :data:`MIN_PROFILE_POINTS` rows, the first strictly increasing."""
    if len(rows) < MIN_PROFILE_POINTS or any(len(row) != 2 for row in rows):
        return False
    positions = np.array([row[0] for row in rows])
    return bool(np.all(np.diff(positions) > 0))


def profile_step(path: Path, positions: np.ndarray) -> float:
    """The uniform step (m) of increasing profile ``positions`` (m), or refuse them.

    The step and origin are the least-squares line through the positions (they are often
    printed rounded); every position must lie within :data:`POSITION_TOLERANCE` steps of it.
    """
    index = np.arange(positions.size)
    step, origin = np.polyfit(index, positions, 1)
    offset = np.abs(positions - (origin + step * index))
    worst = int(np.argmax(offset))
    if offset[worst] > POSITION_TOLERANCE * step:
        raise UnsupportedContentError(
            path,
            "x column",
            f"is not uniformly sampled: point {worst + 1} is at {positions[worst]:.6g}, "
            f"{offset[worst] / step:.2f} steps from the best uniform grid (step {step:.6g} m); "
            f"expected every position within {POSITION_TOLERANCE:g} of a step of it "
            "(asperity reads uniformly sampled profiles; resample a non-uniform one first)",
        )
    return float(step)
