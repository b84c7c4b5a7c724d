"""Show the stored fields that :func:`asperity.fields.document_fields` appends to a docstring.

Result dataclasses get their undescribed fields appended to the docstring under the heading
"Stored fields (from their declarations)", so that ``help()`` lists them. numpydoc knows no
such section and drops it with a warning, so the HTML page would lack those fields. Before
numpydoc reads the docstring, this handler moves the entries into the class's "Attributes"
section (creating it where there is none).
"""

from __future__ import annotations

import re
from typing import Any

HEADING = "Stored fields (from their declarations)"
_UNDERLINE = re.compile(r"^\s*-{3,}\s*$")


def _section_starts(lines: list[str]) -> list[int]:
    """Indices of numpydoc section headings (a line underlined by dashes)."""
    return [
        i
        for i in range(len(lines) - 1)
        if lines[i].strip() and _UNDERLINE.match(lines[i + 1]) and not _UNDERLINE.match(lines[i])
    ]


def merge_stored_fields(lines: list[str]) -> list[str]:
    """``lines`` with the stored-fields block moved to the end of the Attributes section."""
    starts = _section_starts(lines)
    block = [i for i in starts if lines[i].strip() == HEADING]
    if not block:
        return lines
    begin = block[0]
    end = next((i for i in starts if i > begin), len(lines))
    entries = [line for line in lines[begin + 2 : end] if line.strip()]
    rest = lines[:begin] + lines[end:]
    attributes = [i for i in _section_starts(rest) if rest[i].strip() == "Attributes"]
    if not attributes:
        return [*rest, "", "Attributes", "----------", *entries, ""]
    after = next((i for i in _section_starts(rest) if i > attributes[0]), len(rest))
    while after > attributes[0] + 2 and not rest[after - 1].strip():
        after -= 1
    return [*rest[:after], *entries, *rest[after:]]


def move_stored_fields(app: Any, what: str, name: str, obj: Any, options: Any, lines: list) -> None:
    """``autodoc-process-docstring`` handler, run before numpydoc's (priority 400 < 500)."""
    if what == "class":
        lines[:] = merge_stored_fields(lines)


def setup(app: Any) -> dict[str, Any]:
    """Register the handler."""
    app.connect("autodoc-process-docstring", move_stored_fields, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
