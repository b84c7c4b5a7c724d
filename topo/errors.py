"""Error types raised by the topography readers and analyses.

Every problem with a topography file is a :class:`TopographyFileError` (an
:class:`asperity.errors.InputError`, so the command line exits with status 2), naming the
file, the field, and what was expected and found. The subclasses say what kind of problem
it is, for callers that want to tell them apart:

=========================  ==============================================================
class                      the file ...
=========================  ==============================================================
TruncatedFileError         is shorter than its header declares
CorruptFileError           contradicts itself: checksums, malformed structure, a decoder
                           (deflate, zip, NPY header, HDF5) that fails on its bytes
UnsupportedContentError    uses a feature that is refused: encrypted or unknown zip
                           compression, HDF5 external storage, external links, virtual
                           datasets, unknown filters; an unknown format
OverBudgetError            declares a map larger than the memory budget
PhysicalBoundsError        has a scale factor or pixel size outside the physical bounds
NumberFormatError          holds text that is not a number in the stated format
ChannelNotFoundError       lacks the requested (or the default height) channel
=========================  ==============================================================

The limits themselves are in :mod:`asperity.topo.io.limits`.
"""

from __future__ import annotations

from pathlib import Path

from asperity.errors import InputError
from asperity.validity import ValidityWarning


class TopoWarning(ValidityWarning):
    """A topography result to be read with care; ``code`` names it.

    The codes are those of :data:`asperity.validity.CODES` (``hurst_out_of_range``,
    ``outlier_effect``, ...).
    """


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
    expected, found : object, optional
        The expected and found values, kept as attributes for programs (the message
        already states them).
    """

    def __init__(
        self,
        path: str | Path,
        field: str,
        problem: str,
        *,
        expected: object = None,
        found: object = None,
    ) -> None:
        self.path = str(path)
        self.field = field
        self.problem = problem
        self.expected = expected
        self.found = found
        super().__init__(f"{self.path}: {field}: {problem}")


class TruncatedFileError(TopographyFileError):
    """The file is shorter than its header declares (a cut download, a corrupt size field)."""


class CorruptFileError(TopographyFileError):
    """The file contradicts itself: a failed checksum, malformed structure or encoding."""


class UnsupportedContentError(TopographyFileError):
    """The file uses a refused feature (encryption, external storage or links, a filter)."""


class OverBudgetError(TopographyFileError):
    """The file declares a map larger than the readers' memory budget."""


class PhysicalBoundsError(TopographyFileError):
    """A scale factor or pixel size in the file is outside the documented physical bounds."""


class NumberFormatError(TopographyFileError):
    """Text that is not a number in the stated format (the field names line and column)."""


class ChannelNotFoundError(TopographyFileError):
    """The requested channel, or the default height channel, is not in the file."""


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
    TruncatedFileError
        If ``needed > available`` (a truncated file or a corrupt size field), or
        ``needed < 0`` (a corrupt size field).
    """
    if needed < 0 or needed > available:
        raise TruncatedFileError(
            path,
            field,
            f"declares {needed} bytes but only {available} bytes are in the file "
            "(truncated file or corrupt size field)",
            expected=needed,
            found=available,
        )
