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
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:12]!r}; expected {MAGIC!r}")
    check_size(path, "header", HEADER_SIZE, len(data))
    fields = _HEADER.unpack_from(data, 0)
    (
        _magic, _fmt, n_objects, _version, _type, obj_name, instrument, _mat, _acq, _range,
        special_points, _absolute, _r1, _r2, bits, zmin, zmax, nx, ny, n_points,
        step_x, step_y, step_z, _name_x, _name_y, name_z, unit_dx, unit_dy, unit_dz,
        unit_x, unit_y, unit_z, _ratio_x, _ratio_y, _ratio_z,
    ) = fields  # fmt: skip
    comment_size, private_size = struct.unpack_from("<HH", data, 334)
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
    dtype = np.dtype("<i2") if bits == 16 else np.dtype("<i4")
    start = HEADER_SIZE + comment_size + private_size
    check_size(
        path, "point data (header point count)", start + n_points * dtype.itemsize, len(data)
    )
    dx = step_x * _unit(path, "x step unit", unit_dx)
    dy = step_y * _unit(path, "y step unit", unit_dy)
    dz = check_height_step(path, "z spacing", step_z * _unit(path, "z step unit", unit_dz))
    raw = np.frombuffer(data, dtype=dtype, count=n_points, offset=start)
    heights = raw.astype(np.float64) * dz
    if special_points:
        heights[(raw < zmin) | (raw > zmax)] = np.nan
    heights = heights.reshape(ny, nx).T
    provenance = make_provenance(
        path,
        "sur",
        instrument=decode_text(instrument),
        object_name=decode_text(obj_name),
        channel=decode_text(name_z),
        n_objects=int(n_objects),
        invalid_marker="raw value outside [zmin, zmax]" if special_points else None,
        units={
            "x step": decode_text(unit_dx),
            "y step": decode_text(unit_dy),
            "z step": decode_text(unit_dz),
            "x": decode_text(unit_x),
            "y": decode_text(unit_y),
            "z": decode_text(unit_z),
        },
    )
    sizes = (("x spacing", dx), ("y spacing", dy))
    return make_surface(path, heights, sizes[: 1 if ny == 1 else 2], provenance, profile=ny == 1)
