"""The error types and exit statuses shared by every asperity package and command.

Exit statuses of every ``asperity`` command, one meaning each: :class:`ExitStatus`, whose
members carry their ``label`` and ``meaning``. It is the one source of the table:
:func:`exit_status_table` writes the Markdown of README.md and docs/DEVELOPING.md (a test holds
them to it) and ``asperity --help`` builds its epilog from the labels.
"""

from __future__ import annotations

from enum import IntEnum


class ExitStatus(IntEnum):
    """Process exit statuses of the ``asperity`` commands, one meaning each.

    Each member is its integer code and carries ``label`` (a few words, for ``--help``) and
    ``meaning`` (the sentence of the documentation tables). Status 1 takes precedence over 3.
    """

    label: str
    meaning: str

    def __new__(cls, code: int, label: str, meaning: str) -> ExitStatus:
        member = int.__new__(cls, code)
        member._value_ = code
        member.label = label
        member.meaning = meaning
        return member

    @classmethod
    def from_code(cls, code: int) -> ExitStatus:
        """The status whose number is ``code`` (``ExitStatus(code)``, which a type checker
        reads as a call of ``__new__``).

        Raises
        ------
        ValueError
            ``code`` is not one of the documented statuses.
        """
        for status in cls:
            if status.value == code:
                return status
        raise ValueError(f"{code!r} is not a valid {cls.__name__}")

    OK = (
        0,
        "ok",
        "success: every number shown is one the report stands behind (warnings, if any, are "
        "listed)",
    )
    NOT_CONVERGED = (
        1,
        "not converged",
        "a solver did not converge: everything is still written and the report says which "
        "solve failed",
    )
    BAD_INPUT = (
        2,
        "bad input",
        "bad input: a file, a configuration key, an option or a value (one line names it, what "
        "was expected and what was found); also an output folder or file in use by another "
        "run, not writable, or on a full disk, or a folder holding a finished run of a "
        "different job (`run --force` or `--replace` replaces it) (every command; nothing "
        "partial is left)",
    )
    INVALID_RESULT = (
        3,
        "outside the model's validity",
        "computed, but outside the model's validity: the verdict says why; the numbers are "
        "written, marked invalid",
    )
    INTERNAL_ERROR = (
        70,
        "internal error",
        "an internal error of asperity, not of the input (one line; `ASPERITY_DEBUG=1` shows "
        "the traceback): please report it",
    )
    INTERRUPTED = (
        130,
        "interrupted",
        "interrupted (Ctrl-C), always, even when the interrupt lands inside a library "
        "callback; stages already stored are kept",
    )


def exit_status_table() -> str:
    """The exit statuses as a Markdown table (status, name, meaning), from :class:`ExitStatus`.

    The generated text of README.md's and docs/DEVELOPING.md's tables.
    """
    rows = ["| status | name | meaning |", "|---|---|---|"]
    rows += [f"| {s.value} | `{s.name}` | {s.meaning} |" for s in ExitStatus]
    return "\n".join(rows)


def exit_status_epilog() -> str:
    """One line for ``--help``: ``Exit status: 0 ok, 1 not converged, ...``."""
    return "Exit status: " + ", ".join(f"{s.value} {s.label}" for s in ExitStatus) + "."


class InputError(ValueError):
    """Bad input named by the user: a file, a configuration key, an option or an argument.

    Every validation error of the library derives from this class, so that the command line
    reports it as bad input (exit status 2) and anything else as an internal error (70).
    The message names the file, key or argument, what was expected and what was found.
    """


#: Longest error or warning line a command prints, characters (its whole message).
MAX_ERROR_LINE = 1000
#: Longest piece of a value echoed in a message, characters (the rest is cut, its size said).
MAX_ECHOED = 200
#: Longest unbroken word of an error line, characters (a long path fits; a 100,000-character
#: option value is cut to its ends, its size said).
MAX_ECHOED_WORD = 300

#: Short escapes for the control characters that have one.
_SHORT_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t", "\b": "\\b", "\f": "\\f", "\x1b": "\\e"}


def _escaped(char: str) -> str:
    """One character as it is shown in a message: itself, or an inert escape."""
    code = ord(char)
    if char in _SHORT_ESCAPES:
        return _SHORT_ESCAPES[char]
    if code < 0x20 or 0x7F <= code < 0xA0:  # C0, DEL and C1 controls (ESC, CSI, ...)
        return f"\\x{code:02x}"
    if 0xD800 <= code < 0xE000:  # a lone surrogate: an undecodable byte of a file name
        return f"\\u{code:04x}"
    if code in (0x2028, 0x2029, 0x200E, 0x200F) or 0x202A <= code <= 0x202E:
        return f"\\u{code:04x}"  # line separators and bidirectional overrides
    return char


def inert(text: object) -> str:
    """``text`` with every control character shown as an escape (``\\e``, ``\\n``, ``\\x9b``).

    What a message echoes (a file name, a TOML key, an option's value) cannot then move the
    cursor, clear or recolour the terminal, or start a line of its own: ESC, CSI and every
    other C0/C1 control, DEL, lone surrogates (undecodable bytes of a file name), the Unicode
    line separators and bidirectional overrides are written as backslash escapes.
    """
    text = str(text)
    if text.isprintable():
        return text
    return "".join(_escaped(char) for char in text)


def cut(text: object, limit: int = MAX_ECHOED) -> str:
    """``text`` cut to about ``limit`` characters (its first and last parts, and how long it
    was), its control characters escaped (:func:`inert`): an echoed value in a message."""
    text = inert(text)
    if len(text) <= limit:
        return text
    half = max((limit - 40) // 2, 1)
    return f"{text[:half]}...{text[-half:]} (cut: {len(text)} characters in all)"


def bounded_line(text: object, limit: int = MAX_ERROR_LINE) -> str:
    """One message line: runs of white space made one space, controls escaped, every word
    (an echoed value) cut to :data:`MAX_ECHOED_WORD` characters and the whole to ``limit``
    (each cut says the full length).

    The one place every error and warning line of the ``asperity`` command passes through
    (:mod:`asperity.pipelines.cli`, the option parser), so that no message, whatever it
    echoes, is longer than :data:`MAX_ERROR_LINE` characters or drives the terminal.
    """
    words = [cut(word, MAX_ECHOED_WORD) for word in str(text).split()]
    return cut(" ".join(words), limit)


def error_line(prefix: str, message: object, suffix: str = "") -> str:
    """``prefix + message + suffix`` as one bounded, inert line of at most
    :data:`MAX_ERROR_LINE` characters (:func:`bounded_line` cuts the message)."""
    room = max(MAX_ERROR_LINE - len(prefix) - len(suffix), 80)
    return f"{prefix}{bounded_line(message, room)}{suffix}"
