"""The one registry of asperity's native readers: each format's name, extensions, magic test,
reader and arguments, in the order the magic tests are tried.

Everything per-format that :func:`asperity.topo.io.read_surface` needs derives from
:data:`READERS`: :func:`detect_format` (the magic tests, in order), :data:`FORMATS_BY_EXTENSION`
(the extensions), the dispatch to a reader with the arguments it takes (``channel=``,
``pixel_size=``), and the list of formats in every message that names them
(:func:`native_formats_text`). Adding a reader is adding one :class:`ReaderEntry`.
"""

from __future__ import annotations

import struct
import tokenize
import zipfile
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import h5py
import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import CorruptFileError, UnsupportedContentError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io.datx import is_datx, read_datx
from asperity.topo.io.dektak import looks_like_dektak, read_dektak
from asperity.topo.io.gwy import read_gwy
from asperity.topo.io.hdf5 import H5PY_ERRORS, is_project_hdf5, read_project_hdf5
from asperity.topo.io.metropro import MAGICS as _METROPRO_MAGICS
from asperity.topo.io.metropro import read_metropro
from asperity.topo.io.nanoscope import read_nanoscope
from asperity.topo.io.numpy_files import read_numpy
from asperity.topo.io.opd import read_opd
from asperity.topo.io.picoview import read_picoview
from asperity.topo.io.plu import read_plu
from asperity.topo.io.sur import read_sur
from asperity.topo.io.text import read_text
from asperity.topo.io.x3p import read_x3p

__all__ = [
    "DECODER_FAILURES",
    "FORMATS_BY_EXTENSION",
    "FORMATS_BY_NAME",
    "READERS",
    "Probe",
    "ReaderEntry",
    "detect_format",
    "native_formats_text",
    "reader_for",
]

#: Bytes of a file's head the magic tests see.
HEAD_BYTES = 4096

#: Exceptions of the decoders run on a file's bytes: a bad file, not a defect of asperity.
DECODER_FAILURES = (
    zlib.error,
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    struct.error,
    UnicodeDecodeError,
    tokenize.TokenError,
    EOFError,
    OverflowError,
    ZeroDivisionError,
    RecursionError,
    OSError,
    np.linalg.LinAlgError,
)

_ZIP_MAGIC = b"PK\x03\x04"


class Probe:
    """What the magic tests look at: a file's first :data:`HEAD_BYTES` bytes and, for a zip
    archive, its member names (listed once, on first use).

    Parameters
    ----------
    path : Path
        The file.
    head : bytes
        Its first bytes.
    """

    def __init__(self, path: Path, head: bytes) -> None:
        self.path = path
        self.head = head

    @cached_property
    def zip_names(self) -> tuple[str, ...] | None:
        """The member names of a zip archive; None if the file is not one that opens."""
        if not self.head.startswith(_ZIP_MAGIC):
            return None
        try:
            with zipfile.ZipFile(self.path) as archive:
                return tuple(archive.namelist())
        except (*DECODER_FAILURES, ValueError, NotImplementedError):
            return None


@dataclass(frozen=True)
class ReaderEntry:
    """One native format.

    Attributes
    ----------
    name : str
        The format's name, as :func:`detect_format` returns it.
    extensions : tuple of str
        Lower-case extensions (with the dot) that announce this format.
    sniff : callable or None
        ``sniff(probe) -> bool``: whether the file's content is this format (magic bytes).
        None for a format without magic, which goes by extension and is validated field by
        field by its reader.
    read : callable
        ``read(path, **options) -> HeightMap | LineProfile``, heights and pixel sizes in m.
    also_under : tuple of str
        Extensions that announce another format but may hold this one too (a text table
        named ``.dat``, the MetroPro extension): not mislabelled.
    channels : bool
        Whether the format holds several channels (the reader takes ``channel=``).
    calibrated : bool
        Whether the file carries its own pixel size (in m); if not, the reader takes
        ``pixel_size=`` (m).
    """

    name: str
    extensions: tuple[str, ...]
    sniff: Callable[[Probe], bool] | None
    read: Callable[..., HeightMap | LineProfile]
    also_under: tuple[str, ...] = ()
    channels: bool = False
    calibrated: bool = True

    def options(
        self, channel: str | int | None, pixel_size: float | tuple[float, float] | None
    ) -> dict[str, object]:
        """The keyword arguments of :attr:`read` for this format."""
        options: dict[str, object] = {}
        if self.channels:
            options["channel"] = channel
        if not self.calibrated:
            options["pixel_size"] = pixel_size
        return options


def _looks_like_text(head: bytes) -> bool:
    if b"\x00" in head:
        return False
    try:
        head.decode("utf-8")
    except UnicodeDecodeError:
        try:
            head.decode("latin-1")
        except UnicodeDecodeError:
            return False
    return True


def _magic(*prefixes: bytes) -> Callable[[Probe], bool]:
    """A magic test: the file starts with one of ``prefixes``."""
    return lambda probe: probe.head.startswith(prefixes)


def _is_x3p(probe: Probe) -> bool:
    return probe.zip_names is not None and "main.xml" in probe.zip_names


def _is_npz(probe: Probe) -> bool:
    names = probe.zip_names
    return names is not None and len(names) > 0 and all(name.endswith(".npy") for name in names)


def _is_text(probe: Probe) -> bool:
    # A zip archive that no reader claims (or that does not open) is "zip", never text.
    return (
        bool(probe.head) and not probe.head.startswith(_ZIP_MAGIC) and _looks_like_text(probe.head)
    )


def _read_hdf5(path: Path) -> HeightMap:
    """An HDF5 file: an asperity height map (``.h5``) or a Zygo DATX file."""
    try:
        handle = h5py.File(path, "r")
    except H5PY_ERRORS as exc:
        raise CorruptFileError(
            path, "HDF5 container", f"cannot be opened ({exc}); truncated?"
        ) from None
    with handle:
        if is_project_hdf5(handle):
            return read_project_hdf5(path, handle)
        if is_datx(handle):
            return read_datx(path, handle)
    raise UnsupportedContentError(
        path, "HDF5 layout", "is neither an asperity height map nor a Zygo DATX file"
    )


def read_text_table(
    path: Path,
    *,
    pixel_size: float | tuple[float, float] | None = None,
    unit: str | None = None,
) -> HeightMap | LineProfile:
    """A text file: a Dektak CSV profile (own lateral positions) or a matrix / x y z table.

    Parameters
    ----------
    path : Path
        The file.
    pixel_size : float or (float, float), optional
        Pixel size in m of a matrix; refused for a Dektak CSV profile.
    unit : str, optional
        The length unit of a matrix / x y z / x z table (:func:`asperity.topo.io.text.
        read_text` refuses such a table without it); refused for a Dektak CSV profile,
        whose header states its units.

    Returns
    -------
    HeightMap or LineProfile
        Heights and pixel sizes in m.
    """
    with open(path, "rb") as handle:
        head = handle.read(8192)
    if looks_like_dektak(head):
        if pixel_size is not None:
            raise InputError(
                f"{path}: pixel_size {pixel_size!r} given, but a Dektak CSV file carries its "
                "own lateral positions; leave pixel_size (--pixel-size) out"
            )
        if unit is not None:
            raise InputError(
                f"{path}: unit {unit!r} given, but a Dektak CSV file states its own units; "
                "leave unit (--unit) out"
            )
        return read_dektak(path)
    return read_text(path, pixel_size=pixel_size, unit=unit)


#: The native formats, in the order their magic tests are tried: the first that claims the
#: file names its format. The order matters only where a test is loose:
#:
#: - the fixed magic numbers first (Digital Surf, MetroPro, HDF5, Gwyddion, Nanoscope,
#:   PicoView, NPY, Wyko OPD): each is a prefix no other format starts with;
#: - then the zip archives: X3P (has ``main.xml``) before NPZ (only ``.npy`` members); an
#:   archive neither claims is ``"zip"`` (see :func:`detect_format`);
#: - text last: it claims any head without NUL bytes that decodes, so every binary magic
#:   must have been tried before it;
#: - Sensofar ``.plu`` has no magic (``sniff`` None): it goes by extension only.
READERS: tuple[ReaderEntry, ...] = (
    ReaderEntry("sur", (".sur",), _magic(b"DIGITAL SURF"), read_sur),
    ReaderEntry("metropro", (".dat",), _magic(*_METROPRO_MAGICS), read_metropro),
    ReaderEntry("hdf5", (".h5", ".hdf5", ".datx"), _magic(b"\x89HDF\r\n\x1a\n"), _read_hdf5),
    ReaderEntry("gwy", (".gwy",), _magic(b"GWYP"), read_gwy, channels=True),
    ReaderEntry(
        "nanoscope", (".di", ".spm"), _magic(b"\\*File list"), read_nanoscope, channels=True
    ),
    ReaderEntry("picoview", (".mi",), _magic(b"fileType"), read_picoview, channels=True),
    ReaderEntry("npy", (".npy",), _magic(b"\x93NUMPY"), read_numpy, calibrated=False),
    ReaderEntry("opd", (".opd",), _magic(b"\x01\x00Directory"), read_opd),
    ReaderEntry("x3p", (".x3p",), _is_x3p, read_x3p),
    ReaderEntry("npz", (".npz",), _is_npz, read_numpy, calibrated=False),
    ReaderEntry(
        "text",
        (".csv", ".txt", ".asc", ".xyz"),
        _is_text,
        read_text_table,
        also_under=(".dat",),
        calibrated=False,
    ),
    ReaderEntry("plu", (".plu", ".apx"), None, read_plu),
)

#: File extensions and the format each one announces (from :data:`READERS`).
FORMATS_BY_EXTENSION: dict[str, str] = {
    extension: entry.name for entry in READERS for extension in entry.extensions
}

#: The registry by format name.
FORMATS_BY_NAME: dict[str, ReaderEntry] = {entry.name: entry for entry in READERS}


def reader_for(name: str) -> ReaderEntry:
    """The registry entry of the format ``name`` (as :func:`detect_format` returns it).

    Raises
    ------
    KeyError
        If ``name`` is not a native format.
    """
    return FORMATS_BY_NAME[name]


def native_formats_text() -> str:
    """The native formats by extension, for messages: ``"sur, dat, h5/hdf5/datx, ..."``."""
    return ", ".join("/".join(ext.lstrip(".") for ext in entry.extensions) for entry in READERS)


def detect_format(path: str | Path) -> str | None:
    """The format named by the first bytes of a file (magic numbers).

    The magic tests of :data:`READERS` are tried in its order; the first that claims the file
    names it.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    str or None
        The ``name`` of a :data:`READERS` entry with a magic test (``"sur"``, ``"metropro"``,
        ``"hdf5"``, ``"gwy"``, ``"nanoscope"``, ``"picoview"``, ``"npy"``, ``"opd"``,
        ``"x3p"``, ``"npz"``, ``"text"``), ``"zip"`` (another archive), or None if unknown.
    """
    path = Path(path)
    with open(path, "rb") as handle:
        probe = Probe(path, handle.read(HEAD_BYTES))
    for entry in READERS:
        if entry.sniff is not None and entry.sniff(probe):
            return entry.name
    if probe.head.startswith(_ZIP_MAGIC):
        return "zip"
    return None
