"""Digital Surf ``.sur`` reader (MountainsMap / SurfStand binary surface files).

Layout (little-endian, 512-byte header per object; facts from the public format notes):
magic ``DIGITAL SURF`` (bytes 0-11), object count (14), non-measured-points flag (86),
bits per point, 16 or 32 (98), ``zmin``/``zmax`` (100/104), points per line / lines /
total points (108/112/116), x, y, z spacings as float32 (120/124/128), then nine 16-byte
unit strings: axis names, *step units* (the units of the spacings) and axis units, and
three unit ratios; comment and private zone sizes at 334/336. The data (int16/int32,
x fastest) starts ``512 + comment + private`` bytes into the file.

Units: each spacing is converted with its own step unit (``delta_x_unit`` for ``dx``,
``delta_data_unit`` for the z step), so files whose axes use different units are right.
Missing pixels: when the non-measured flag is set, a raw value outside the declared
``[zmin, zmax]`` range (MountainsMap writes ``zmin - 2``) marks a non-measured point; they
become NaN, counted in ``provenance["missing_pixels"]``.

Bounds: the x and y steps must give pixel sizes of 1 pm .. 1 m; the z step must be > 0
(a zero step would flatten the map; the format defines no inverted axis, so a negative step
is refused rather than silently inverting the surface).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from asperity.topo.errors import TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import decode_text, make_provenance, make_surface, read_all_bytes
from asperity.topo.io.limits import check_height_step, check_map_points
from asperity.topo.io.units import length_unit_in_metres

MAGIC = b"DIGITAL SURF"
_HEADER = struct.Struct("<12sHHHH30s30sHHHHHIIHiiiiIfff16s16s16s16s16s16s16s16s16sfff")
HEADER_SIZE = 512
#: Names of the fields of :data:`_HEADER`, in order.
_FIELDS = (
    "magic", "format", "n_objects", "version", "type", "obj_name", "instrument", "material",
    "acquisition", "range", "special_points", "absolute", "reserved_1", "reserved_2", "bits",
    "zmin", "zmax", "nx", "ny", "n_points", "step_x", "step_y", "step_z", "name_x", "name_y",
    "name_z", "unit_dx", "unit_dy", "unit_dz", "unit_x", "unit_y", "unit_z", "ratio_x",
    "ratio_y", "ratio_z",
)  # fmt: skip


def _unit(path: Path, field: str, raw: bytes) -> float:
    unit = decode_text(raw)
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise TopographyFileError(
            path, field, f"is {unit!r}; expected a length unit (m, mm, um, nm)"
        )
    return factor


def read_sur(path: str | Path) -> HeightMap | LineProfile:
    """Read the first object of a Digital Surf ``.sur`` file (heights, pixel sizes in m).

    Parameters
    ----------
    path : str or Path
        The .sur file.

    Returns
    -------
    HeightMap or LineProfile
        Heights in m (NaN = non-measured point), pixel sizes in m,
        provenance (instrument, units seen).

    Raises
    ------
    TopographyFileError
        Wrong magic, unsupported bits per point, a point count that is not
        ``points per line * lines``, a non-length unit, or a file too short for its data.
    """
    path = Path(path)
    data = read_all_bytes(path)
    header = _read_header(path, data)
    nx, ny, n_points = header["nx"], header["ny"], header["n_points"]
    dtype = _point_type(path, header)
    start = HEADER_SIZE + header["comment_size"] + header["private_size"]
    check_size(
        path, "point data (header point count)", start + n_points * dtype.itemsize, len(data)
    )
    dx = header["step_x"] * _unit(path, "x step unit", header["unit_dx"])
    dy = header["step_y"] * _unit(path, "y step unit", header["unit_dy"])
    dz = check_height_step(
        path, "z spacing", header["step_z"] * _unit(path, "z step unit", header["unit_dz"])
    )
    raw = np.frombuffer(data, dtype=dtype, count=n_points, offset=start)
    heights = raw.astype(np.float64) * dz
    if header["special_points"]:
        heights[(raw < header["zmin"]) | (raw > header["zmax"])] = np.nan
    heights = heights.reshape(ny, nx).T
    sizes = (("x spacing", dx), ("y spacing", dy))
    return make_surface(
        path, heights, sizes[: 1 if ny == 1 else 2], _provenance(path, header), profile=ny == 1
    )


def _read_header(path: Path, data: bytes) -> dict:
    """The header fields by name (see :data:`_FIELDS`) and the comment/private zone sizes."""
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:12]!r}; expected {MAGIC!r}")
    check_size(path, "header", HEADER_SIZE, len(data))
    header = dict(zip(_FIELDS, _HEADER.unpack_from(data, 0), strict=True))
    header["comment_size"], header["private_size"] = struct.unpack_from("<HH", data, 334)
    return header


def _point_type(path: Path, header: dict) -> np.dtype:
    """The point dtype (int16 or int32), the grid and point count checked."""
    bits, nx, ny, n_points = header["bits"], header["nx"], header["ny"], header["n_points"]
    if bits not in (16, 32):
        raise TopographyFileError(path, "bits per point", f"is {bits}; expected 16 or 32")
    if nx < 1 or ny < 1:
        raise TopographyFileError(
            path, "points per line / lines", f"are {nx} x {ny}; expected >= 1"
        )
    if n_points != nx * ny:
        raise TopographyFileError(
            path, "total points", f"is {n_points}; expected points per line * lines = {nx * ny}"
        )
    check_map_points(path, "points per line / lines", nx, ny)
    return np.dtype("<i2") if bits == 16 else np.dtype("<i4")


def _provenance(path: Path, header: dict) -> dict:
    """Provenance: instrument, object and channel names, the units as written."""
    return make_provenance(
        path,
        "sur",
        instrument=decode_text(header["instrument"]),
        object_name=decode_text(header["obj_name"]),
        channel=decode_text(header["name_z"]),
        n_objects=int(header["n_objects"]),
        invalid_marker="raw value outside [zmin, zmax]" if header["special_points"] else None,
        units={
            "x step": decode_text(header["unit_dx"]),
            "y step": decode_text(header["unit_dy"]),
            "z step": decode_text(header["unit_dz"]),
            "x": decode_text(header["unit_x"]),
            "y": decode_text(header["unit_y"]),
            "z": decode_text(header["unit_z"]),
        },
    )
