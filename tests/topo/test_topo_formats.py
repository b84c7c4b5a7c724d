"""Formats without a real sample in tests/data, written here from their documented layouts.

Each test writes a small file with known heights, reads it back with topo.read_surface
and checks heights (m), pixel sizes (m) and missing pixels; then a truncated copy must be
refused with an error naming the file.
"""

from __future__ import annotations

import hashlib
import struct
import zipfile
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity import topo
from asperity.topo.errors import TopographyFileError

RNG = np.random.default_rng(1)
HEIGHTS = RNG.normal(scale=1e-6, size=(7, 5))  # (nx, ny), m


def truncate(path: Path, fraction: float = 0.6) -> Path:
    data = path.read_bytes()
    out = path.with_name("cut_" + path.name)
    out.write_bytes(data[: int(len(data) * fraction)])
    return out


# --- Gwyddion: a minimal serialiser following the documented GWY object format ---------


def gwy_object(name: str, components: list[tuple[str, str, object]]) -> bytes:
    body = b""
    for key, kind, value in components:
        body += key.encode() + b"\0" + kind.encode()
        if kind == "i":
            body += struct.pack("<i", value)
        elif kind == "d":
            body += struct.pack("<d", value)
        elif kind == "s":
            body += value.encode() + b"\0"
        elif kind == "o":
            body += value
        elif kind == "D":
            array = np.asarray(value, dtype="<f8")
            body += struct.pack("<I", array.size) + array.tobytes()
    return name.encode() + b"\0" + struct.pack("<I", len(body)) + body


def gwy_field(heights_xy: np.ndarray, lx: float, ly: float, z_unit: str = "m") -> bytes:
    unit_xy = gwy_object("GwySIUnit", [("unitstr", "s", "m")])
    unit_z = gwy_object("GwySIUnit", [("unitstr", "s", z_unit)])
    nx, ny = heights_xy.shape
    return gwy_object(
        "GwyDataField",
        [("xres", "i", nx), ("yres", "i", ny), ("xreal", "d", lx), ("yreal", "d", ly),
         ("si_unit_xy", "o", unit_xy), ("si_unit_z", "o", unit_z),
         ("data", "D", heights_xy.T.ravel())],
    )  # fmt: skip


def test_gwy_round_trip_and_channels(tmp_path):
    other = np.arange(35.0).reshape(7, 5)
    container = gwy_object(
        "GwyContainer",
        [("/0/data", "o", gwy_field(other, 7e-6, 5e-6, z_unit="V")),
         ("/0/data/title", "s", "Phase"),
         ("/1/data", "o", gwy_field(HEIGHTS, 7e-6, 10e-6)),
         ("/1/data/title", "s", "Topography")],
    )  # fmt: skip
    path = tmp_path / "map.gwy"
    path.write_bytes(b"GWYP" + container)
    surface = topo.read_surface(path)
    assert surface.provenance["channel"] == "Topography"
    np.testing.assert_array_equal(surface.heights, HEIGHTS)
    assert (surface.dx, surface.dy) == pytest.approx((1e-6, 2e-6))
    with pytest.raises(TopographyFileError, match="expected lengths"):
        topo.read_surface(path, channel="Phase")
    with pytest.raises(TopographyFileError, match="cut_map.gwy"):
        topo.read_surface(truncate(path))


# --- Zygo DATX: HDF5 with a MetaData link table -------------------------------------------


def write_datx(path: Path, heights_xy: np.ndarray, pixel: float, no_data: float) -> None:
    links = np.array(
        [(b"Root", b"Measurement", b"{M}"), (b"{M}", b"Surface", b"{S}"),
         (b"{S}", b"Path", b"/Measurement/Surface")],
        dtype=[("Source", "S16"), ("Link", "S16"), ("Destination", "S32")],
    )  # fmt: skip
    converter = np.dtype([("Category", "S16"), ("BaseUnit", "S16"), ("Parameters", "<f8", (4,))])
    with h5py.File(path, "w") as handle:
        handle["MetaData"] = links
        data = heights_xy.T.copy() * 1e6  # stored in um, (ny, nx)
        data[np.isnan(data)] = no_data
        dataset = handle.create_dataset("Measurement/Surface", data=data)
        dataset.attrs["No Data"] = np.array([no_data])
        dataset.attrs["Unit"] = np.array([b"MicroMeters"])
        for axis in ("X", "Y"):
            dataset.attrs[f"{axis} Converter"] = np.array(
                [(b"LateralCat", b"Pixels", [0.0, pixel, 0.0, 0.0])], dtype=converter
            )


def test_datx_round_trip_with_missing_pixels(tmp_path):
    heights = HEIGHTS.copy()
    heights[2, 3] = np.nan
    path = tmp_path / "map.datx"
    write_datx(path, heights, 3e-7, no_data=1.7e308)
    surface = topo.read_surface(path)  # Unit "MicroMeters", as Zygo writes it
    np.testing.assert_allclose(surface.heights, heights, rtol=1e-12)
    assert surface.n_missing == 1
    assert surface.dx == pytest.approx(3e-7)
    with pytest.raises(TopographyFileError, match="cut_map.datx"):
        topo.read_surface(truncate(path))
    with h5py.File(path, "r+") as handle:
        handle["Measurement/Surface"].attrs["Unit"] = np.array([b"Volts"])
    with pytest.raises(TopographyFileError, match="expected a length unit"):
        topo.read_surface(path)


# --- X3P: the amended revision with a valid-points mask, integer data ----------------------


def write_x3p(
    path: Path,
    raw: np.ndarray,
    dtype_code: str,
    valid: np.ndarray | None,
    dx: float,
    dy: float,
    z_increment: float = 1.0,
    declared_nx: int | None = None,
    revision: str = "ISO5436 - 2000",
    inline: bool = False,
) -> None:
    nx, ny = raw.shape
    declared_nx = nx if declared_nx is None else declared_nx
    point_data = raw.T.astype({"I": "<u2", "L": "<u4", "F": "<f4", "D": "<f8"}[dtype_code])
    point_bytes = point_data.tobytes()
    valid_link = ""
    files = {"bindata/data.bin": point_bytes}
    if valid is not None:
        files["bindata/valid.bin"] = np.packbits(valid.T.ravel(), bitorder="little").tobytes()
        valid_link = "<ValidPointsLink>bindata/valid.bin</ValidPointsLink>"
    data = f"""<DataLink><PointDataLink>bindata/data.bin</PointDataLink>
<MD5ChecksumPointData>{hashlib.md5(point_bytes).hexdigest().upper()}</MD5ChecksumPointData>
{valid_link}</DataLink>"""
    if inline:  # XML encoding: one Datum per point, x fastest, empty = invalid
        files = {}
        data = (
            "<DataList>"
            + "".join(
                "<Datum/>" if np.isnan(value) else f"<Datum>{float(value)!r}</Datum>"
                for value in raw.T.ravel()
            )
            + "</DataList>"
        )
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1><Revision>{revision}</Revision><FeatureType>SUR</FeatureType><Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>{dx!r}</Increment></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>{dy!r}</Increment></CY>
<CZ><AxisType>A</AxisType><DataType>{dtype_code}</DataType><Increment>{z_increment!r}</Increment>
<Offset>0.0</Offset></CZ></Axes></Record1>
<Record3><MatrixDimension><SizeX>{declared_nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
{data}</Record3></p:ISO5436_2>"""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("main.xml", xml)
        for name, data in files.items():
            archive.writestr(name, data)


AMENDED = "ISO25178-72:2017/DAM1"  # the Revision text of ISO 25178-72:2017/Amd 1:2020


def test_x3p_amended_revision_with_mask_and_integer_data(tmp_path):
    raw = RNG.integers(0, 60000, size=(7, 5))
    valid = np.ones((7, 5), dtype=bool)
    valid[1, 4] = False
    path = tmp_path / "map.x3p"
    write_x3p(path, raw, "I", valid, 1e-6, 3e-6, z_increment=1e-9, revision=AMENDED)
    surface = topo.read_surface(path)
    assert surface.provenance["revision"] == AMENDED
    expected = raw * 1e-9
    expected[1, 4] = np.nan
    np.testing.assert_allclose(surface.heights, expected)
    assert (surface.dx, surface.dy) == pytest.approx((1e-6, 3e-6))
    with pytest.raises(TopographyFileError, match="cut_map.x3p"):
        topo.read_surface(truncate(path, 0.8))


@pytest.mark.parametrize("revision", ["ISO5436 - 2000", AMENDED])
def test_x3p_inline_xml_point_data(tmp_path, revision):
    heights = HEIGHTS.copy()
    heights[4, 2] = np.nan
    path = tmp_path / "inline.x3p"
    write_x3p(path, heights, "D", None, 2e-6, 3e-6, revision=revision, inline=True)
    surface = topo.read_surface(path)
    np.testing.assert_array_equal(surface.heights, heights)
    assert (surface.dx, surface.dy) == (2e-6, 3e-6) and surface.provenance["revision"] == revision
    short = tmp_path / "short.x3p"
    write_x3p(short, heights[:6], "D", None, 2e-6, 3e-6, declared_nx=7, inline=True)
    with pytest.raises(TopographyFileError, match=r"short\.x3p: Record3/DataList: has 30 Datum"):
        topo.read_surface(short)


def test_x3p_nan_points_and_wrong_size(tmp_path):
    heights = HEIGHTS.copy()
    heights[0, 0] = np.nan
    path = tmp_path / "nan.x3p"
    write_x3p(path, heights, "D", None, 2e-6, 2e-6)
    assert topo.read_surface(path).n_missing == 1
    bad = tmp_path / "bad.x3p"
    write_x3p(bad, heights[:6], "D", None, 2e-6, 2e-6, declared_nx=7)
    with pytest.raises(TopographyFileError, match="expected 280"):
        topo.read_surface(bad)


# --- text, NumPy and the project's HDF5 ----------------------------------------------------


def test_text_matrix_needs_pixel_size_and_refuses_ragged_rows(tmp_path):
    path = tmp_path / "map.txt"
    np.savetxt(path, HEIGHTS)
    with pytest.raises(ValueError, match="pixel_size"):
        topo.read_surface(path)
    surface = topo.read_surface(path, pixel_size=1e-6, unit="m")
    np.testing.assert_allclose(surface.heights, HEIGHTS, rtol=1e-15)
    cut = tmp_path / "cut.txt"
    cut.write_text(path.read_text()[:-30])  # drops the last value and a half
    with pytest.raises(TopographyFileError, match="ragged or truncated"):
        topo.read_surface(cut, pixel_size=1e-6, unit="m")


def test_text_xyz_columns(tmp_path):
    x, y = np.meshgrid(np.arange(7) * 2e-6, np.arange(5) * 3e-6, indexing="ij")
    path = tmp_path / "map.xyz"
    np.savetxt(path, np.column_stack([x.ravel(), y.ravel(), HEIGHTS.ravel()]))
    surface = topo.read_surface(path, unit="m")
    np.testing.assert_allclose(surface.heights, HEIGHTS, rtol=1e-15)
    assert (surface.dx, surface.dy) == pytest.approx((2e-6, 3e-6))


def test_npy_and_npz_never_unpickle(tmp_path):
    path = tmp_path / "map.npy"
    np.save(path, HEIGHTS)
    with pytest.raises(ValueError, match="pixel"):
        topo.read_surface(path)
    surface = topo.read_surface(path, pixel_size=(1e-6, 2e-6))
    np.testing.assert_array_equal(surface.heights, HEIGHTS)
    pickled = tmp_path / "object.npy"
    np.save(pickled, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with pytest.raises(TopographyFileError, match="pickl"):
        topo.read_surface(pickled, pixel_size=1e-6)
    npz = tmp_path / "map.npz"
    np.savez(npz, heights=HEIGHTS, dx=1e-6, dy=2e-6)
    assert topo.read_surface(npz).dy == pytest.approx(2e-6)
    for file in (path, npz):
        with pytest.raises(TopographyFileError, match="cut_map"):
            topo.read_surface(truncate(file), pixel_size=1e-6)


def test_project_hdf5_round_trip(tmp_path):
    heights = HEIGHTS.copy()
    heights[3, 3] = np.nan
    original = topo.HeightMap(heights, 1e-6, 2e-6, periodic=True, provenance={"seed": 3})
    path = topo.write_hdf5(original, tmp_path / "map.h5")
    surface = topo.read_surface(path)
    np.testing.assert_array_equal(surface.heights, heights)
    assert (surface.dx, surface.dy, surface.periodic) == (1e-6, 2e-6, True)
    assert surface.provenance["seed"] == 3
    with pytest.raises(TopographyFileError, match="cut_map.h5"):
        topo.read_surface(truncate(path))


# --- one orientation for every reader --------------------------------------------------
#
# heights[ix, iy]: ix along the scan lines (x), iy from the top line of the image as the
# instrument's software and Gwyddion display it. Fingerprints of asymmetric features read
# by SurfaceTopography 1.27.1 (an independent code) from the same files: the (ix, iy) of
# the highest pixel, and (mean of the top quarter of lines - mean of the bottom quarter) /
# rms and (left quarter - right quarter) / rms; a reader mirrored in y moves the summit to
# (ix, ny - 1 - iy) and changes the sign of the first asymmetry.
ORIENTATION = [
    ("di-3.di", (0, 0), 1.6441, 1.9796),
    ("opd-1.opd", (504, 27), 1.3423, -0.7532),
    ("mi-1.mi", (0, 20), 0.4966, 2.5371),
    ("sur-3.sur", (225, 255), None, 0.1523),  # the top and bottom quarters are missing
    ("x3p-2.x3p", (8, 179), 0.2051, 0.1176),
    ("metropro-1.dat", (565, 405), -0.0812, -2.5619),
    ("plu-1.plu", (767, 574), -0.0484, -2.6005),
]
TEST_DATA = Path(__file__).resolve().parents[1] / "data"


@pytest.mark.parametrize(("name", "summit", "top_minus_bottom", "left_minus_right"), ORIENTATION)
def test_every_reader_has_the_instruments_orientation(
    name, summit, top_minus_bottom, left_minus_right
):
    heights = topo.read_surface(TEST_DATA / name).heights
    nx, ny = heights.shape
    rms = np.nanstd(heights)
    assert np.unravel_index(np.nanargmax(heights), heights.shape) == summit
    if top_minus_bottom is not None:
        top = np.nanmean(heights[:, : ny // 4]) - np.nanmean(heights[:, -(ny // 4) :])
        assert top / rms == pytest.approx(top_minus_bottom, abs=2e-4)
    left = np.nanmean(heights[: nx // 4]) - np.nanmean(heights[-(nx // 4) :])
    assert left / rms == pytest.approx(left_minus_right, abs=2e-4)


def test_stats_json_names_the_channel_read(tmp_path, capsys):
    """Nanoscope: the calibrated Height Sensor (ZSensor) by default, as SurfaceTopography
    reads it (rms 2.264e-7 m over the raw map); the piezo 'Height' channel on request."""
    import json

    from asperity.pipelines.cli import main

    def stats(*args):
        assert main(["stats", *map(str, args), "--json"]) == 0
        return json.loads(capsys.readouterr().out)

    assert stats(TEST_DATA / "di-3.di")["channel"] == "Height Sensor"
    assert stats(TEST_DATA / "di-3.di", "--channel", "Height")["channel"] == "Height"
    assert topo.read_surface(TEST_DATA / "di-3.di").provenance["channel_key"] == "ZSensor"
    assert stats(TEST_DATA / "mi-1.mi")["channel"] == "Topography"
    np.save(tmp_path / "map.npy", HEIGHTS)
    record = stats(tmp_path / "map.npy", "--pixel-size", "1e-6")
    assert record["channel"] == "array" and "rms_height" in record
