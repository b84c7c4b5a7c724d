"""The optional extra ``asperity[formats]``: SurfaceTopography's readers behind asperity's checks.

SurfaceTopography (ContactEngineering, MIT licence) reads some forty instrument formats
(Keyence VK3/VK4/VK6/VK7 and ZON, Bruker Dektak OPDx, Asylum/Oxford IBW, Olympus LEXT/OIR,
JPK, Park TIFF, NT-MDT, Nanosurf NID/EZD, Alicona AL3D, Sensofar PLUX, Digital Surf MNT,
Mitutoyo SurfTest xlsx, Mahr, FRT, NanoFocus, ISO 25178-71 SDF, WSxM, TMD, SPIP BCR, MATLAB,
NetCDF, ...). :func:`read_with_extra` opens a file with it and hands back a
:class:`~asperity.topo.HeightMap` or :class:`~asperity.topo.LineProfile` that passed the
checks every native reader applies (:mod:`asperity.topo.io.limits`): the declared grid
against the memory budget before the data are read, pixel sizes within 1 pm .. 1 m, heights
finite and within 1 m, missing pixels (SurfaceTopography's masked values) as NaN, lengths
converted from the file's unit to metres, and the channel read in the provenance
(``channel``, ``channel_index``, ``channels``). Any failure of SurfaceTopography on the file is
a :class:`~asperity.topo.errors.TopographyFileError` naming the file and the reader.

asperity's own readers keep priority (they are faster, hardened and fuzzed):
:func:`asperity.topo.read_surface` calls this module only for files it does not read itself.
Without the extra, such a file is refused with one line naming it: :data:`INSTALL_HINT`.

Axes: SurfaceTopography's ``heights()[i, j]`` is the point ``(x_i, y_j)``, axis 0 along x,
the convention of :class:`~asperity.topo.HeightMap`; the array is taken as it is.
A line scan SurfaceTopography reads as non-uniform (positions printed rounded) is accepted
when every position lies within a twentieth of a step of a uniform grid (the rule of
asperity's text profiles), and refused otherwise: asperity never interpolates a measurement.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError, UnsupportedContentError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import caller_pixel_size, make_provenance, make_surface
from asperity.topo.io.limits import MAX_FILE_BYTES, check_map_points
from asperity.topo.io.registry import native_formats_text
from asperity.topo.io.text_layouts import profile_step
from asperity.topo.io.units import length_unit_in_metres

#: What a user without the extra is told to run.
INSTALL_HINT = 'pip install "asperity[formats]"'


def extra_available() -> bool:
    """Whether SurfaceTopography (the ``formats`` extra) is installed."""
    return importlib.util.find_spec("SurfaceTopography") is not None


def _open(path: Path):
    """SurfaceTopography's reader of the file, or a typed error naming the file."""
    from SurfaceTopography.IO import open_topography

    try:  # its readers may print while they probe a file: that is not ours to show
        with warnings.catch_warnings(), _silenced():
            warnings.simplefilter("ignore")
            return open_topography(str(path))
    except Exception as exc:  # a third-party reader: any failure is a bad or unknown file
        raise TopographyFileError(
            path,
            "file",
            "matches no supported format: neither asperity's readers nor SurfaceTopography's "
            f"read it (SurfaceTopography: {type(exc).__name__}: {_one_line(exc)})",
        ) from None


@contextlib.contextmanager
def _silenced() -> Iterator[None]:
    """Python-level stdout and stderr discarded inside the block (a third-party reader's
    prints would break the one-line error contract of the command line)."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        yield


def _one_line(error: Exception, limit: int = 200) -> str:
    """A third-party message on one line, shortened."""
    text = " ".join(str(error).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _channel_index(path: Path, reader: Any, channel: str | int | None) -> int:
    """The index of the requested channel (name or index), or the reader's default."""
    names = [info.name for info in reader.channels]
    if channel is None:
        return int(reader.default_channel.index)
    if isinstance(channel, int) or (isinstance(channel, str) and channel.isdigit()):
        index = int(channel)
        if 0 <= index < len(names):
            return index
    elif channel in names:
        return names.index(channel)
    raise TopographyFileError(
        path, "channel", f"{channel!r} does not exist; the file holds {names} (index or name)"
    )


def _metres_per_unit(path: Path, unit: object) -> float:
    if unit is None:
        raise UnsupportedContentError(
            path,
            "unit",
            "is not stated in the file (SurfaceTopography finds none); asperity does not guess "
            "a length unit: convert the file to a two-column x z text file in metres",
        )
    factor = length_unit_in_metres(str(unit))
    if factor is None:
        raise UnsupportedContentError(
            path,
            "unit",
            f"is {unit!r} (SurfaceTopography); expected a length unit (m, mm, µm, nm)",
        )
    return factor


def _caller_sizes(path: Path, info: Any, pixel_size: float | tuple[float, float] | None) -> dict:
    """Physical sizes from a caller's pixel size (m) for a file that carries none."""
    sizes = caller_pixel_size(path, pixel_size)
    if info.physical_sizes is not None:
        if sizes is not None:
            raise InputError(
                f"{path}: pixel_size {pixel_size!r} given, but the file carries its own "
                "calibrated pixel size; leave pixel_size (--pixel-size) out"
            )
        return {}
    if sizes is None:
        raise InputError(
            f"{path}: the file carries no pixel size; give pixel_size= (or --pixel-size DX), "
            "in metres"
        )
    grid = tuple(info.nb_grid_pts)
    return {"physical_sizes": tuple(n * d for n, d in zip(grid, sizes, strict=False)), "unit": "m"}


def read_with_extra(
    path: str | Path,
    *,
    channel: str | int | None = None,
    pixel_size: float | tuple[float, float] | None = None,
) -> HeightMap | LineProfile:
    """Read a file through SurfaceTopography; heights and pixel sizes in m, missing = NaN.

    Parameters
    ----------
    path : str or Path
        The file.
    channel : str or int, optional
        Channel name or index; default: SurfaceTopography's default channel.
    pixel_size : float or (float, float), optional
        Pixel size in m for a file without lateral calibration; refused otherwise.

    Returns
    -------
    HeightMap or LineProfile
        Heights and pixel sizes in m; the provenance names the reader and the channel.

    Raises
    ------
    TopographyFileError
        The extra missing (the message says ``pip install "asperity[formats]"``), a file
        neither asperity nor SurfaceTopography reads, a channel that does not exist, a grid
        over the memory budget, a non-length unit, a non-uniform line scan, pixel sizes or
        heights out of bounds.
    """
    path = Path(path)
    if not extra_available():
        raise UnsupportedContentError(
            path,
            "format",
            f"is not one asperity reads natively ({native_formats_text()}); other instrument "
            f"formats are read through SurfaceTopography: {INSTALL_HINT}",
        )
    if path.stat().st_size > MAX_FILE_BYTES:
        raise TopographyFileError(path, "file", f"is larger than {MAX_FILE_BYTES} bytes")
    reader = _open(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            index = _channel_index(path, reader, channel)
            info = reader.channels[index]
            check_map_points(path, f"channel {info.name!r} grid", *info.nb_grid_pts)
            options = _caller_sizes(path, info, pixel_size)
            topography = reader.topography(channel_index=index, **options)
            heights = np.ma.filled(np.ma.asarray(topography.heights(), dtype=np.float64), np.nan)
    except InputError:
        raise
    except Exception as exc:  # a third-party reader: any failure is a bad file
        raise TopographyFileError(
            path,
            f"channel {channel if channel is not None else 'default'}",
            f"cannot be read by SurfaceTopography's {type(reader).__name__} "
            f"({type(exc).__name__}: {_one_line(exc)})",
        ) from None
    return _surface(path, reader, index, topography, heights)


def _surface(
    path: Path, reader: Any, index: int, topography: Any, heights: np.ndarray
) -> HeightMap | LineProfile:
    """Convert a SurfaceTopography topography to metres and build the checked surface."""
    factor = _metres_per_unit(path, topography.unit)
    if topography.is_uniform:
        grid = heights.shape
        physical = topography.physical_sizes
        sizes = [length * factor / n for length, n in zip(physical, grid, strict=True)]
    else:  # positions printed rounded: uniform within a twentieth of a step, or refused
        sizes = [profile_step(path, np.asarray(topography.positions(), dtype=np.float64) * factor)]
    info = reader.channels[index]
    provenance = make_provenance(
        path,
        f"SurfaceTopography {type(reader).__name__}",
        reader="SurfaceTopography " + _version(),
        channel=info.name,
        channel_index=index,
        channels=[c.name for c in reader.channels],
        units={"all": str(topography.unit)},
    )
    fields = tuple((f"physical_sizes[{i}] / grid points", size) for i, size in enumerate(sizes))
    return make_surface(path, heights * factor, fields, provenance, profile=heights.ndim == 1)


def _version() -> str:
    from importlib.metadata import version

    return version("SurfaceTopography")
