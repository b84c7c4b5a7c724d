"""ISO 25178-72 / ISO 5436-2 X3P reader (zip archive: ``main.xml`` + binary point data).

Both revisions are read: ISO 25178-72:2017 (``Revision`` ``ISO5436 - 2000``) and its
amendment Amd 1:2020 (``ISO25178-72:2017/DAM1``); the point data may be a binary member
(``DataLink``, with the optional ``ValidPointsLink`` bit mask) or inline XML
(``DataList`` of ``Datum`` elements, an empty one being an invalid point). Lateral axes must be
incremental (``AxisType`` ``I``); x and y increments may differ (non-square pixels).
Invalid points are NaN (float data) or flagged in the valid-points mask (1 bit per point,
least significant bit first); both become NaN. Point data is stored x fastest, so the raw
buffer is ``(ny, nx)`` in C order and is transposed to the project's ``(nx, ny)``.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ElementTree
import zipfile
from pathlib import Path

import numpy as np

from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import make_provenance

_DTYPES = {"I": np.dtype("<u2"), "L": np.dtype("<u4"), "F": np.dtype("<f4"), "D": np.dtype("<f8")}


def _strip_namespaces(root: ElementTree.Element) -> None:
    for element in root.iter():
        if isinstance(element.tag, str) and "}" in element.tag:
            element.tag = element.tag.split("}", 1)[1]


def _text(path: Path, parent: ElementTree.Element | None, tag: str, where: str) -> str:
    node = None if parent is None else parent.find(tag)
    if node is None or node.text is None or not node.text.strip():
        raise TopographyFileError(path, f"main.xml {where}/{tag}", "is missing; expected a value")
    return node.text.strip()


def _number(path: Path, parent: ElementTree.Element, tag: str, where: str, kind: type) -> float:
    text = _text(path, parent, tag, where)
    try:
        return kind(text)
    except ValueError:
        raise TopographyFileError(
            path, f"main.xml {where}/{tag}", f"is {text!r}; expected a {kind.__name__}"
        ) from None


def _check_compression(path: Path, info: zipfile.ZipInfo) -> None:
    """Refuse a member whose declared size no deflate stream could give (about 1032:1 max)."""
    if (
        info.compress_type != zipfile.ZIP_STORED
        and info.file_size > 1100 * info.compress_size + 4096
    ):
        raise TopographyFileError(
            path,
            f"zip member {info.filename}",
            f"claims {info.file_size} bytes from {info.compress_size} compressed bytes; "
            "corrupt archive",
        )


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
        try:
            values[index] = float(text.split(";")[-1])
        except ValueError:
            raise TopographyFileError(
                path, f"Record3/DataList/Datum {index}", f"is {text[:40]!r}; expected a number"
            ) from None
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
        does not match ``SizeX*SizeY*SizeZ`` times the item size, a failed MD5 or CRC.
    """
    path = Path(path)
    try:
        archive = zipfile.ZipFile(path)
    except zipfile.BadZipFile as exc:
        raise TopographyFileError(
            path, "zip container", f"is not a readable ZIP archive ({exc}); truncated or not X3P"
        ) from None
    with archive:
        try:
            _check_compression(path, archive.getinfo("main.xml"))
            xml_bytes = archive.read("main.xml")
        except KeyError:
            raise TopographyFileError(path, "main.xml", "is missing from the archive") from None
        except (zipfile.BadZipFile, OSError, EOFError) as exc:
            raise TopographyFileError(path, "main.xml", f"cannot be extracted ({exc})") from None
        try:
            root = ElementTree.fromstring(xml_bytes)
        except ElementTree.ParseError as exc:
            raise TopographyFileError(path, "main.xml", f"is not well-formed XML ({exc})") from None
        _strip_namespaces(root)
        record1, record3 = root.find("Record1"), root.find("Record3")
        if record1 is None or record3 is None:
            raise TopographyFileError(path, "main.xml", "lacks Record1 or Record3")
        revision = _text(path, record1, "Revision", "Record1")
        feature = _text(path, record1, "FeatureType", "Record1")
        if feature not in ("SUR", "PRF"):
            raise TopographyFileError(
                path, "Record1/FeatureType", f"is {feature!r}; expected 'SUR' or 'PRF'"
            )
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
        dtype = _DTYPES[data_type]
        z_increment = float(cz.findtext("Increment") or 1.0)
        z_offset = float(cz.findtext("Offset") or 0.0)

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
        link = record3.find("DataLink")
        data_list = record3.find("DataList")
        if link is None and data_list is not None:
            values = _data_list_values(path, data_list, nx * ny)
        else:
            member = _text(path, link, "PointDataLink", "Record3/DataLink")
            expected = nx * ny * dtype.itemsize
            try:
                info = archive.getinfo(member)
            except KeyError:
                raise TopographyFileError(
                    path, "Record3/DataLink/PointDataLink", f"names {member!r}, not in the archive"
                ) from None
            _check_compression(path, info)
            if info.file_size != expected:
                raise TopographyFileError(
                    path,
                    f"point data {member}",
                    f"has {info.file_size} bytes; expected {expected} "
                    f"({nx} x {ny} points of type {data_type})",
                )
            try:
                raw = archive.read(member)
            except (zipfile.BadZipFile, OSError, EOFError) as exc:
                raise TopographyFileError(
                    path, f"point data {member}", f"is corrupt ({exc})"
                ) from None
            md5 = link.findtext("MD5ChecksumPointData") if link is not None else None
            if md5 and hashlib.md5(raw).hexdigest().lower() != md5.strip().lower():
                raise TopographyFileError(
                    path, "Record3/DataLink/MD5ChecksumPointData", "does not match the point data"
                )
            values = np.frombuffer(raw, dtype=dtype).astype(np.float64)
        if data_type in "IL":
            values = values * z_increment + z_offset
        valid_member = link.findtext("ValidPointsLink") if link is not None else None
        if valid_member:
            try:
                bits = archive.read(valid_member.strip())
            except (KeyError, zipfile.BadZipFile, OSError, EOFError) as exc:
                raise TopographyFileError(
                    path, "Record3/DataLink/ValidPointsLink", f"cannot be read ({exc})"
                ) from None
            if len(bits) * 8 < nx * ny:
                raise TopographyFileError(
                    path,
                    f"valid-points mask {valid_member}",
                    f"has {len(bits)} bytes; expected at least {(nx * ny + 7) // 8}",
                )
            valid = np.unpackbits(np.frombuffer(bits, np.uint8), bitorder="little")[: nx * ny]
            values[valid == 0] = np.nan
        heights = values.reshape(ny, nx).T
        record2 = root.find("Record2")
        instrument = None
        if record2 is not None and record2.find("Instrument") is not None:
            parts = [
                record2.find("Instrument").findtext(tag) or ""
                for tag in ("Manufacturer", "Model", "Version")
            ]
            instrument = " ".join(part for part in parts if part)
    provenance = make_provenance(
        path,
        "x3p",
        revision=revision,
        instrument=instrument,
        channel="CZ",
        units={"lateral": "m", "height": "m", "data_type": data_type},
    )
    if feature == "PRF" or ny == 1:
        return LineProfile(heights[:, 0], spacing["CX"], provenance)
    return HeightMap(heights, spacing["CX"], spacing["CY"], False, provenance)
