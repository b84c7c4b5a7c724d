"""Error types raised by the topography readers and analyses."""

from __future__ import annotations

from pathlib import Path

from asperity.errors import InputError


class TopographyFileError(InputError):
    """A topography file is truncated, corrupt, mislabelled or unsupported.

    The message always names the file, the offending field and what was expected, so that
    the command line can print it as is.

    Parameters
    ----------
    path : str or Path
        The file that could not be read.
    field : str
        The header field, block or section that is wrong (e.g. ``"Samps/line"``).
    problem : str
        What was found, and what was expected instead.
    """

    def __init__(self, path: str | Path, field: str, problem: str) -> None:
        self.path = str(path)
        self.field = field
        self.problem = problem
        super().__init__(f"{self.path}: {field}: {problem}")


def check_size(path: str | Path, field: str, needed: int, available: int) -> None:
    """Refuse a block of ``needed`` bytes when only ``available`` bytes are in the file.

    Parameters
    ----------
    path : str or Path
        File being read (for the message).
    field : str
        The size field or block that declares ``needed``.
    needed, available : int
        Bytes the header promises and bytes actually present.

    Raises
    ------
    TopographyFileError
        If ``needed > available`` (a truncated file or a corrupt size field).
    """
    if needed < 0 or needed > available:
        raise TopographyFileError(
            path,
            field,
            f"declares {needed} bytes but only {available} bytes are in the file "
            "(truncated file or corrupt size field)",
        )
