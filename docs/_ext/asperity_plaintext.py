"""Let docstrings keep their plain-text maths when Sphinx reads them as reStructuredText.

asperity's docstrings are written to be read in a terminal (``help()``) as much as in HTML, so
they write an absolute value as ``|F_x|`` and a product as ``p *= alpha``. In reST a ``|...|``
pair is a substitution reference and a lone ``*`` opens emphasis: both make the page wrong
(an "undefined substitution" error box, or a warning that fails the ``-W`` build). This
extension escapes, in every docstring autodoc reads, outside inline literals, roles and
tables:

* every ``|`` (asperity's docstrings define no substitutions);
* every ``*`` that does not open or close a well-formed ``*emphasis*`` or ``**strong**`` on
  its line (``*args``, ``*.toml``, ``p *= alpha``);
* an inline literal ending in a space (the comment marker "# " in double back-quotes), which
  reST cannot end: it is shown with quotes, ``'# '``.

Intentional markup (``*valid*``, ``**invalid**``, ````literals````, ``:func:`...```) is kept.
"""

from __future__ import annotations

import re
from typing import Any

#: Inline literals and interpreted text (roles), left untouched.
_PROTECTED = re.compile(r"``.+?``|:[\w:.-]+:`[^`]*`|`[^`]+`_{0,2}")
#: Well-formed emphasis or strong emphasis: opening star(s) before a non-space, closing after.
_EMPHASIS = re.compile(r"(?<![\w*\\])(\*\*?)(?=\S)(?!\*)(.+?)(?<=\S)(?<!\\)\1(?![\w*])")
#: An inline literal whose text ends in a space (``# ``): invalid reST, shown quoted instead.
_TRAILING_SPACE_LITERAL = re.compile(r"``(\S[^`]*?\s+)``")
#: A table row or border, or a line block: their bars and stars are markup.
_TABLE_LINE = re.compile(r"^\s*(\+[-=+]+\+\s*$|\|.*\|\s*$|\|\s)")
#: A bullet-list item's star (kept as the list marker).
_BULLET = re.compile(r"^\s*\* ")


def _escape_plain(text: str) -> str:
    """Escape ``|`` and unpaired ``*`` in a run of text free of literals and roles."""
    parts = []
    last = 0
    for match in _EMPHASIS.finditer(text):
        parts.append(_escape_stars(text[last : match.start()]))
        parts.append(match.group(0).replace("|", r"\|"))
        last = match.end()
    parts.append(_escape_stars(text[last:]))
    return "".join(parts)


def _escape_stars(text: str) -> str:
    return text.replace("|", r"\|").replace("*", r"\*")


def escape_line(line: str) -> str:
    """One docstring line with its plain-text ``|`` and unpaired ``*`` escaped."""
    line = _TRAILING_SPACE_LITERAL.sub(r"``'\1'``", line)
    if _TABLE_LINE.match(line) or ("|" not in line and "*" not in line):
        return line
    bullet = _BULLET.match(line)
    out = [bullet.group(0)] if bullet else []
    last = bullet.end() if bullet else 0
    for match in _PROTECTED.finditer(line, last):
        out.append(_escape_plain(line[last : match.start()]))
        out.append(match.group(0))
        last = match.end()
    out.append(_escape_plain(line[last:]))
    return "".join(out)


def _in_literal_block(lines: list[str]) -> list[bool]:
    """True for the lines of ``::`` literal blocks and doctest blocks (kept verbatim)."""
    flags = []
    block_indent: int | None = None
    opener = False
    for line in lines:
        indent = len(line) - len(line.lstrip())
        stripped = line.strip()
        if block_indent is not None and stripped and indent <= block_indent:
            block_indent = None
        if opener and stripped:
            block_indent, opener = indent - 1, False
        literal = block_indent is not None or stripped.startswith(">>>")
        flags.append(literal)
        if not literal and stripped.endswith("::"):
            opener, block_indent = True, None
    return flags


def escape_docstring(app: Any, what: str, name: str, obj: Any, options: Any, lines: list) -> None:
    """``autodoc-process-docstring`` handler: escape plain-text ``|`` and ``*`` in place."""
    literal = _in_literal_block(lines)
    lines[:] = [
        line if keep else escape_line(line) for line, keep in zip(lines, literal, strict=True)
    ]


def setup(app: Any) -> dict[str, Any]:
    """Register the handler after numpydoc's (priority 600 > 500): it sees numpydoc's reST."""
    app.connect("autodoc-process-docstring", escape_docstring, priority=600)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
