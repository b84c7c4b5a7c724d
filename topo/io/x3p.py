"""ISO 25178-72 / ISO 5436-2 X3P reader (zip archive: ``main.xml`` + binary point data).

Both revisions are read: ISO 25178-72:2017 (``Revision`` ``ISO5436 - 2000``) and its
amendment Amd 1:2020 (``ISO25178-72:2017/DAM1``); the point data may be a binary member
(``DataLink``, with the optional ``ValidPointsLink`` bit mask) or inline XML
(``DataList`` of ``Datum`` elements, an empty one being an invalid point). Lateral axes must be
incremental (``AxisType`` ``I``); x and y increments may differ (non-square pixels).
Invalid points are NaN (float data) or flagged in the valid-points mask (1 bit per point,
least significant bit first); both become NaN. Point data is stored x fastest, so the raw
buffer is ``(ny, nx)`` in C order and is transposed to the project's ``(nx, ny)``.

Checks before anything is decompressed or allocated: ``SizeX*SizeY`` within the memory
budget; every member stored or deflated (encrypted members and other methods refused), its
declared size exactly what ``main.xml`` implies (the valid-points mask: ``ceil(n/8)`` bytes,
up to 64 KiB of padding), and no more than deflate's ratio; CRC-32 of every member and the
MD5 of the point data checked. ``CX``/``CY`` increments are pixel sizes of 1 pm .. 1 m; the
``CZ`` increment of integer data a height step of 1e-24 .. 1 m.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ElementTree
import zipfile
from pathlib import Path
from typing import overload

import numpy as np

from asperity.topo.errors import CorruptFileError, TopographyFileError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import (
    make_provenance,
    make_surface,
    open_zip,
    parse_number,
    read_zip_member,
    zip_member_info,
)
from asperity.topo.io.limits import MAX_MAP_BYTES, check_height_step, check_map_points

_DTYPES: dict[str, np.dtype] = {
    "I": np.dtype("<u2"),
    "L": np.dtype("<u4"),
    "F": np.dtype("<f4"),
    "D": np.dtype("<f8"),
}
#: Padding accepted after the valid-points bits, bytes.
_MASK_SLACK = 65536


def _strip_namespaces(root: ElementTree.Element) -> None:
    for element in root.iter():
        if isinstance(element.tag, str) and "}" in element.tag:
            element.tag = element.tag.split("}", 1)[1]


def _text(path: Path, parent: ElementTree.Element | None, tag: str, where: str) -> str:
    node = None if parent is None else parent.find(tag)
    if node is None or node.text is None or not node.text.strip():
        raise TopographyFileError(path, f"main.xml {where}/{tag}", "is missing; expected a value")
    return node.text.strip()


@overload
def _number(
    path: Path, parent: ElementTree.Element, tag: str, where: str, kind: type[int]
) -> int: ...
@overload
def _number(
    path: Path, parent: ElementTree.Element, tag: str, where: str, kind: type[float]
) -> float: ...
def _number(path: Path, parent: ElementTree.Element, tag: str, where: str, kind: type) -> float:
    text = _text(path, parent, tag, where)
    if kind is int:
        if not text.lstrip("+-").isdigit() or not text.isascii():
            raise TopographyFileError(
                path, f"main.xml {where}/{tag}", f"is {text!r}; expected an integer"
            )
        return int(text)
    return parse_number(path, f"main.xml {where}/{tag}", text)


def _optional_number(path: Path, parent: ElementTree.Element, tag: str, default: float) -> float:
    text = parent.findtext(tag)
    if text is None or not text.strip():
        return default
    return parse_number(path, f"main.xml Axes/CZ/{tag}", text)


def _data_list_values(path: Path, data_list: ElementTree.Element, count: int) -> np.ndarray:
    """Heights stored in the XML itself (``Record3/DataList/Datum``), x fastest.

    With incremental x and y axes every ``Datum`` holds the z value alone (a
    ``x;y;z`` triple is also accepted: its last field is z); an empty ``Datum`` is an
    invalid point (NaN).
    """
    datums = data_list.findall("Datum")
    if len(datums) != count:
        raise TopographyFileError(
            path,
            "Record3/DataList",
            f"has {len(datums)} Datum elements; expected SizeX*SizeY = {count}",
        )
    values = np.full(count, np.nan)
    for index, datum in enumerate(datums):
        text = (datum.text or "").strip()
        if not text:
            continue
        values[index] = parse_number(
            path, f"Record3/DataList/Datum {index}", text.split(";")[-1], allow_nan=True
        )
    return values


def read_x3p(path: str | Path) -> HeightMap | LineProfile:
    """Read an X3P file; heights and pixel sizes in m, invalid points NaN.

    Parameters
    ----------
    path : str or Path
        The ``.x3p`` file.

    Returns
    -------
    HeightMap or LineProfile
        A profile (``SizeY == 1``, feature type ``PRF``) is returned as a LineProfile.

    Raises
    ------
    TopographyFileError
        Not a zip archive, missing ``main.xml`` records, a point-data member whose size
        does not match ``SizeX*SizeY*SizeZ`` times the item size, a failed MD5 or CRC, a
        ``PRF`` (profile) feature type over a grid of more than one row.
    """
    path = Path(path)
    with open_zip(path, "X3P") as archive:
        root = _main_xml(path, archive)
        record1, record3, revision, feature = _records(path, root)
        spacing, data_type, z_increment, z_offset = _axes(path, record1)
        nx, ny = _matrix_size(path, record3)
        if feature == "PRF" and ny != 1:  # which of the two lies cannot be told: refuse
            raise CorruptFileError(
                path,
                "Record1/FeatureType",
                f"is 'PRF' (a line profile) but Record3/MatrixDimension is {nx} x {ny}; a "
                "profile has SizeY = 1",
            )
        values = _point_values(path, archive, record3, nx * ny, data_type)
        if data_type in "IL":
            values = values * z_increment + z_offset
        link = record3.find("DataLink")
        valid_member = link.findtext("ValidPointsLink") if link is not None else None
        if valid_member and valid_member.strip():
            values[~_valid_points(path, archive, valid_member.strip(), nx * ny)] = np.nan
        heights = values.reshape(ny, nx).T
        instrument = _instrument(root)
    provenance = make_provenance(
        path,
        "x3p",
        revision=revision,
        instrument=instrument,
        channel="CZ",
        units={"lateral": "m", "height": "m", "data_type": data_type},
        invalid_marker="valid-points mask, NaN or empty Datum",
    )
    if feature == "PRF" or ny == 1:
        return make_surface(
            path, heights[:, 0], (("Axes/CX/Increment", spacing["CX"]),), provenance, profile=True
        )
    sizes = (("Axes/CX/Increment", spacing["CX"]), ("Axes/CY/Increment", spacing["CY"]))
    return make_surface(path, heights, sizes, provenance)


def _records(
    path: Path, root: ElementTree.Element
) -> tuple[ElementTree.Element, ElementTree.Element, str, str]:
    """(Record1, Record3, revision, feature type 'SUR' or 'PRF') of ``main.xml``."""
    record1, record3 = root.find("Record1"), root.find("Record3")
    if record1 is None or record3 is None:
        raise TopographyFileError(path, "main.xml", "lacks Record1 or Record3")
    revision = _text(path, record1, "Revision", "Record1")
    feature = _text(path, record1, "FeatureType", "Record1")
    if feature not in ("SUR", "PRF"):
        raise TopographyFileError(
            path, "Record1/FeatureType", f"is {feature!r}; expected 'SUR' or 'PRF'"
        )
    return record1, record3, revision, feature


def _matrix_size(path: Path, record3: ElementTree.Element) -> tuple[int, int]:
    """(SizeX, SizeY) of ``Record3/MatrixDimension``, within the map budget; SizeZ must be 1."""
    dims = record3.find("MatrixDimension")
    if dims is None:
        raise TopographyFileError(path, "Record3/MatrixDimension", "is missing")
    nx = _number(path, dims, "SizeX", "MatrixDimension", int)
    ny = _number(path, dims, "SizeY", "MatrixDimension", int)
    nz = _number(path, dims, "SizeZ", "MatrixDimension", int)
    if nx < 1 or ny < 1 or nz != 1:
        raise TopographyFileError(
            path,
            "Record3/MatrixDimension",
            f"is {nx} x {ny} x {nz}; expected SizeX, SizeY >= 1 and SizeZ == 1",
        )
    check_map_points(path, "Record3/MatrixDimension SizeX x SizeY", nx, ny)
    return nx, ny


def _point_values(
    path: Path, archive: zipfile.ZipFile, record3: ElementTree.Element, count: int, data_type: str
) -> np.ndarray:
    """The ``count`` raw values: from the inline ``DataList`` or the binary member it links."""
    link = record3.find("DataLink")
    data_list = record3.find("DataList")
    if link is None and data_list is not None:
        return _data_list_values(path, data_list, count)
    return _point_data(path, archive, link, count, data_type)


def _main_xml(path: Path, archive: zipfile.ZipFile) -> ElementTree.Element:
    """Parse ``main.xml`` (namespaces stripped) after checking its member header."""
    info = zip_member_info(path, archive, "main.xml", "main.xml")
    xml_bytes = read_zip_member(path, archive, info, MAX_MAP_BYTES)
    try:
        root = ElementTree.fromstring(xml_bytes)
    except (ElementTree.ParseError, ValueError, RecursionError) as exc:
        raise CorruptFileError(path, "main.xml", f"is not well-formed XML ({exc})") from None
    _strip_namespaces(root)
    return root


def _axes(path: Path, record1: ElementTree.Element) -> tuple[dict, str, float, float]:
    """Lateral increments (m), z data type, z increment (m per count) and offset (m)."""
    axes = record1.find("Axes")
    spacing = {}
    for name in ("CX", "CY"):
        axis = None if axes is None else axes.find(name)
        if axis is None:
            raise TopographyFileError(path, f"Record1/Axes/{name}", "is missing")
        axis_type = _text(path, axis, "AxisType", f"Axes/{name}")
        if axis_type != "I":
            raise TopographyFileError(
                path,
                f"Axes/{name}/AxisType",
                f"is {axis_type!r}; only incremental axes ('I') are supported",
            )
        spacing[name] = _number(path, axis, "Increment", f"Axes/{name}", float)
    cz = None if axes is None else axes.find("CZ")
    if cz is None:
        raise TopographyFileError(path, "Record1/Axes/CZ", "is missing")
    data_type = _text(path, cz, "DataType", "Axes/CZ")
    if data_type not in _DTYPES:
        raise TopographyFileError(
            path, "Axes/CZ/DataType", f"is {data_type!r}; expected one of I, L, F, D"
        )
    z_increment = _optional_number(path, cz, "Increment", 1.0)
    z_offset = _optional_number(path, cz, "Offset", 0.0)
    if data_type in "IL":
        check_height_step(path, "Axes/CZ/Increment", z_increment)
    return spacing, data_type, z_increment, z_offset


def _point_data(
    path: Path, archive: zipfile.ZipFile, link: ElementTree.Element | None, count: int, kind: str
) -> np.ndarray:
    """The binary point data (float64, x fastest), size and MD5 checked."""
    member = _text(path, link, "PointDataLink", "Record3/DataLink")
    dtype = _DTYPES[kind]
    expected = count * dtype.itemsize
    info = zip_member_info(path, archive, member, "Record3/DataLink/PointDataLink")
    if info.file_size != expected:
        raise TopographyFileError(
            path,
            f"point data {member}",
            f"has {info.file_size} bytes; expected {expected} ({count} points of type {kind})",
        )
    raw = read_zip_member(path, archive, info, expected)
    md5 = link.findtext("MD5ChecksumPointData") if link is not None else None
    if md5 and hashlib.md5(raw).hexdigest().lower() != md5.strip().lower():
        raise CorruptFileError(
            path, "Record3/DataLink/MD5ChecksumPointData", "does not match the point data"
        )
    return np.frombuffer(raw, dtype=dtype).astype(np.float64)


def _valid_points(path: Path, archive: zipfile.ZipFile, member: str, count: int) -> np.ndarray:
    """The valid-points bit mask (1 bit per point, least significant first) as booleans."""
    field = f"valid-points mask {member}"
    info = zip_member_info(path, archive, member, "Record3/DataLink/ValidPointsLink")
    needed = (count + 7) // 8
    if not needed <= info.file_size <= needed + _MASK_SLACK:
        raise CorruptFileError(
            path,
            field,
            f"declares {info.file_size} bytes; expected {needed} (one bit per point)",
            expected=needed,
            found=info.file_size,
        )
    bits = read_zip_member(path, archive, info, needed + _MASK_SLACK)
    mask = np.frombuffer(bits, np.uint8, count=needed)
    return np.unpackbits(mask, bitorder="little")[:count].astype(bool)


def _instrument(root: ElementTree.Element) -> str | None:
    record2 = root.find("Record2")
    instrument = None if record2 is None else record2.find("Instrument")
    if instrument is None:
        return None
    parts = [instrument.findtext(tag) or "" for tag in ("Manufacturer", "Model", "Version")]
    return " ".join(part for part in parts if part) or None
