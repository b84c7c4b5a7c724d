"""Gwyddion native ``.gwy`` reader (GWY serialised-object format, version ``GWYP``).

Facts (Gwyddion user guide, "GWY file format"): the file is ``GWYP`` followed by one
serialised object. An object is its type name (NUL-terminated), a uint32 byte size, then
components: name (NUL-terminated), a one-character type and the value. Types: ``b`` bool
and ``c`` char (1 byte), ``i`` int32, ``q`` int64, ``d`` float64, ``s`` NUL-terminated
string, ``o`` object; upper-case letters are arrays (uint32 count, then the items).
All numbers are little-endian. The top-level ``GwyContainer`` holds channels as
``/N/data`` (``GwyDataField``: ``xres``, ``yres``, ``xreal``, ``yreal``, ``si_unit_xy``,
``si_unit_z`` (``GwySIUnit`` with ``unitstr``) and ``data``, ``xres*yres`` doubles, row by
row with x fastest) and titles as ``/N/data/title``. Every size and count is checked
against the bytes left in its parent object, objects nest at most :data:`MAX_DEPTH` deep,
and nothing is executed or unpickled.
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import Any, overload

import numpy as np

from asperity.topo.errors import ChannelNotFoundError, CorruptFileError, TopographyFileError
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, make_surface, read_all_bytes
from asperity.topo.io.limits import check_map_points
from asperity.topo.io.units import length_unit_in_metres

MAGIC = b"GWYP"
_SCALAR = {"b": "<?", "c": "<c", "i": "<i", "q": "<q", "d": "<d"}
_ARRAY = {"C": "u1", "I": "<i4", "Q": "<i8", "D": "<f8"}
#: Deepest nesting of objects accepted (Gwyddion writes about 4 levels).
MAX_DEPTH = 32


class _Parser:
    def __init__(self, path: Path, data: bytes) -> None:
        self.path = path
        self.data = data
        self.depth = 0

    def fail(self, field: str, problem: str) -> TopographyFileError:
        return TopographyFileError(self.path, field, problem)

    def string(self, pos: int, end: int, field: str) -> tuple[str, int]:
        stop = self.data.find(b"\x00", pos, end)
        if stop < 0:
            raise self.fail(field, f"string at byte {pos} is not NUL-terminated within its object")
        return self.data[pos:stop].decode("utf-8", "replace"), stop + 1

    def object(self, pos: int, end: int, field: str) -> tuple[dict, int]:
        if self.depth >= MAX_DEPTH:
            raise CorruptFileError(
                self.path, field, f"nests objects more than {MAX_DEPTH} deep; corrupt file"
            )
        self.depth += 1
        try:
            return self._object(pos, end, field)
        finally:
            self.depth -= 1

    def _object(self, pos: int, end: int, field: str) -> tuple[dict, int]:
        name, pos = self.string(pos, end, field)
        if pos + 4 > end:
            raise self.fail(field, f"object {name!r} size field runs past the end of its parent")
        (size,) = struct.unpack_from("<I", self.data, pos)
        pos += 4
        if pos + size > end:
            raise self.fail(
                f"{field} ({name}) size",
                f"declares {size} bytes but only {end - pos} remain (truncated file)",
            )
        stop = pos + size
        components: dict = {"__type__": name}
        while pos < stop:
            key, pos = self.string(pos, stop, f"{name} component name")
            if pos >= stop:
                raise self.fail(f"{name}.{key}", "has no type byte")
            kind = chr(self.data[pos])
            pos += 1
            components[key], pos = self.value(kind, pos, stop, f"{name}.{key}")
        return components, stop

    def value(self, kind: str, pos: int, end: int, field: str) -> tuple[Any, int]:
        if kind in _SCALAR:
            size = struct.calcsize(_SCALAR[kind])
            if pos + size > end:
                raise self.fail(field, "value runs past the end of its object")
            return struct.unpack_from(_SCALAR[kind], self.data, pos)[0], pos + size
        if kind == "s":
            return self.string(pos, end, field)
        if kind == "o":
            return self.object(pos, end, field)
        if kind in _ARRAY or kind in ("S", "O"):
            if pos + 4 > end:
                raise self.fail(field, "array count runs past the end of its object")
            (count,) = struct.unpack_from("<I", self.data, pos)
            pos += 4
            if kind in _ARRAY:
                dtype = np.dtype(_ARRAY[kind])
                nbytes = count * dtype.itemsize
                if pos + nbytes > end:
                    raise self.fail(
                        field, f"array of {count} items needs {nbytes} bytes, {end - pos} remain"
                    )
                return np.frombuffer(self.data, dtype, count, pos), pos + nbytes
            items = []
            for _ in range(count):
                item, pos = (self.string if kind == "S" else self.object)(pos, end, field)
                items.append(item)
            return items, pos
        raise self.fail(field, f"has unknown component type {kind!r}")


def _unit(field: object) -> str:
    unit = field.get("unitstr", "") if isinstance(field, dict) else ""
    return unit if isinstance(unit, str) else ""


@overload
def _component(path: Path, field: dict, key: str, index: int, kind: type[int]) -> int: ...
@overload
def _component(path: Path, field: dict, key: str, index: int, kind: type[float]) -> float: ...
def _component(path: Path, field: dict, key: str, index: int, kind: type) -> float:
    """A scalar component (``xres``, ``xreal`` ...) of a data field, of the right kind."""
    value = field.get(key)
    if isinstance(value, bytes | str | dict | list | np.ndarray) or value is None:
        raise TopographyFileError(
            path, f"/{index}/data {key}", f"is {type(value).__name__}; expected a number"
        )
    number = float(value)
    if kind is int and not (np.isfinite(number) and number == int(number)):
        raise TopographyFileError(
            path, f"/{index}/data {key}", f"is {number!r}; expected a whole number"
        )
    return kind(number)


def _container(path: Path, data: bytes) -> dict:
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:4]!r}; expected b'GWYP'")
    parser = _Parser(path, data)
    container, _ = parser.object(4, len(data), "top-level object")
    if container["__type__"] != "GwyContainer":
        raise TopographyFileError(
            path, "top-level object", f"is {container['__type__']!r}; expected GwyContainer"
        )
    return container


def _fields(container: dict) -> list[tuple[int, str, dict]]:
    fields = []
    for key, value in container.items():
        parts = key.split("/")
        if len(parts) == 3 and parts[0] == "" and parts[1].isdigit() and parts[2] == "data":
            if isinstance(value, dict) and value.get("__type__") == "GwyDataField":
                index = int(parts[1])
                fields.append(
                    (index, str(container.get(f"/{index}/data/title", f"channel {index}")), value)
                )
    return sorted(fields, key=lambda item: item[0])


def read_gwy(path: str | Path, *, channel: str | int | None = None) -> HeightMap:
    """Read one channel of a ``.gwy`` file (default: first channel with a length z unit), in m.

    Parameters
    ----------
    path : str or Path
        The ``.gwy`` file.
    channel : str or int, optional
        Channel title (case-insensitive) or its number N in ``/N/data``.

    Returns
    -------
    HeightMap
        Heights in m, pixel sizes ``xreal/xres``, ``yreal/yres`` in m; provenance lists
        the channels.

    Raises
    ------
    TopographyFileError
        Wrong magic, sizes or counts beyond the bytes present, a data array whose length is
        not ``xres*yres``, non-length units.
    ChannelNotFoundError
        A ``channel`` that is not in the file (the message lists the channels).
    """
    path = Path(path)
    container = _container(path, read_all_bytes(path))
    fields = _fields(container)
    if not fields:
        raise TopographyFileError(path, "/N/data", "no GwyDataField channel in the container")
    titles = [f"{i}: {t}" for i, t, _ in fields]
    index, title, field = _choose_field(path, fields, titles, channel)
    xres, yres, xreal, yreal, values = _field_grid(path, field, index)
    z_unit = _unit(field.get("si_unit_z")) or "m"
    xy_unit = _unit(field.get("si_unit_xy")) or "m"
    z_factor, xy_factor = length_unit_in_metres(z_unit), length_unit_in_metres(xy_unit)
    if z_factor is None or xy_factor is None:
        raise TopographyFileError(
            path, f"/{index}/data units", f"are xy {xy_unit!r}, z {z_unit!r}; expected lengths"
        )
    heights = values.astype(np.float64).reshape(yres, xres).T * z_factor
    provenance = make_provenance(
        path,
        "gwy",
        instrument="Gwyddion",
        channel=title,
        channels=titles,
        units={"lateral": xy_unit, "height": z_unit},
    )
    sizes = (
        (f"/{index}/data xreal / xres", xreal * xy_factor / xres),
        (f"/{index}/data yreal / yres", yreal * xy_factor / yres),
    )
    return make_surface(path, heights, sizes, provenance)


def _choose_field(
    path: Path,
    fields: list[tuple[int, str, dict]],
    titles: list[str],
    channel: str | int | None,
) -> tuple[int, str, dict]:
    """The (N, title, field) named by ``channel``, or the first with a length z unit."""
    if channel is None:
        chosen = next(
            (f for f in fields if length_unit_in_metres(_unit(f[2].get("si_unit_z")) or "m")), None
        )
        if chosen is None:
            raise TopographyFileError(path, "si_unit_z", "no channel has a length unit")
        return chosen
    chosen = next((f for f in fields if str(channel).lower() in (str(f[0]), f[1].lower())), None)
    if chosen is None:
        raise ChannelNotFoundError(path, "channel", f"{channel!r} not found; available: {titles}")
    return chosen


def _field_grid(path: Path, field: dict, index: int) -> tuple[int, int, float, float, np.ndarray]:
    """(xres, yres, xreal, yreal, data) of a data field: sizes > 0, ``xres*yres`` values."""
    xres = _component(path, field, "xres", index, int)
    yres = _component(path, field, "yres", index, int)
    xreal = _component(path, field, "xreal", index, float)
    yreal = _component(path, field, "yreal", index, float)
    values = field.get("data")
    if xres < 1 or yres < 1 or not (xreal > 0 and yreal > 0):
        raise TopographyFileError(path, f"/{index}/data xres/xreal", "must be positive")
    check_map_points(path, f"/{index}/data xres x yres", xres, yres)
    if not isinstance(values, np.ndarray) or values.size != xres * yres:
        raise TopographyFileError(
            path,
            f"/{index}/data data",
            f"has {getattr(values, 'size', 0)} values; expected {xres * yres}",
        )
    return xres, yres, xreal, yreal, values
