"""Hostile and degenerate inputs: each gets a clear error naming the file/field, never a
traceback, a huge allocation or a silently wrong number (found by a review of the readers)."""

from __future__ import annotations

import io
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.cli import main
from asperity.topo.errors import TopographyFileError
from asperity.topo.io import limits

DATA = Path(__file__).resolve().parents[1] / "data"


def npy_header(shape: tuple[int, ...], descr: str = "<f8") -> bytes:
    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        buffer, {"descr": descr, "fortran_order": False, "shape": shape}
    )
    return buffer.getvalue()


def run_cli(capsys, *args):
    status = main([str(a) for a in args])
    out = capsys.readouterr()
    return status, out.out, out.err


# --- NumPy files: the header is checked before any allocation ---------------------------


def test_npy_header_claiming_a_huge_array_is_refused_without_allocating(tmp_path):
    path = tmp_path / "huge.npy"
    path.write_bytes(npy_header((100_000, 100_000)) + bytes(800))  # claims 80 GB
    with pytest.raises(TopographyFileError, match=r"huge\.npy: array shape.*only 800 bytes"):
        topo.read_surface(path, pixel_size=1e-6)
    archive = tmp_path / "huge.npz"
    with zipfile.ZipFile(archive, "w") as handle:
        handle.writestr("heights.npy", npy_header((100_000, 100_000)) + bytes(800))
    with pytest.raises(TopographyFileError, match=r"huge\.npz: array 'heights' shape"):
        topo.read_surface(archive, pixel_size=1e-6)


def test_npy_layouts_are_read_exactly(tmp_path):
    values = np.arange(12.0).reshape(3, 4) * 1e-6
    np.save(tmp_path / "f.npy", np.asfortranarray(values))
    np.save(tmp_path / "b.npy", values.astype(">f8"))
    np.savez_compressed(tmp_path / "c.npz", heights=values, dx=2e-6, dy=3e-6)
    for name in ("f.npy", "b.npy"):
        np.testing.assert_array_equal(
            topo.read_surface(tmp_path / name, pixel_size=1e-6).heights, values
        )
    surface = topo.read_surface(tmp_path / "c.npz")
    np.testing.assert_array_equal(surface.heights, values)
    assert (surface.dx, surface.dy) == (2e-6, 3e-6)


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ({"dx": np.array([1e-6, 2e-6])}, "array 'dx': has shape"),
        ({"dx": 0.0}, "array 'dx': is 0.0; expected a finite pixel size > 0 m"),
        ({"dx": 1e-6, "dy": np.nan}, "array 'dy': is nan"),
    ],
)
def test_npz_pixel_size_entries_are_validated(tmp_path, entries, message):
    path = tmp_path / "map.npz"
    np.savez(path, heights=np.zeros((4, 4)), **entries)
    with pytest.raises(TopographyFileError, match=message) as info:
        topo.read_surface(path)
    assert "map.npz" in str(info.value)
    # an explicit pixel size replaces the bad entries
    assert topo.read_surface(path, pixel_size=1e-6).dx == 1e-6


@pytest.mark.parametrize("bad", [-1e-6, 0.0, float("nan"), float("inf"), (1e-6, 0.0), (1, 2, 3)])
def test_invalid_caller_pixel_size_is_refused_naming_the_file(tmp_path, bad):
    path = tmp_path / "map.npy"
    np.save(path, np.zeros((4, 4)))
    with pytest.raises(ValueError, match=r"map\.npy: pixel_size"):
        topo.read_surface(path, pixel_size=bad)


def test_pixel_size_for_a_calibrated_format_is_refused():
    with pytest.raises(ValueError, match="carries its own calibrated pixel size"):
        topo.read_surface(DATA / "x3p-2.x3p", pixel_size=1e-6)
    with pytest.raises(ValueError, match="own lateral positions"):
        topo.read_surface(DATA / "dektak-1.csv", pixel_size=1e-6)


# --- x-y-z text: incomplete, duplicated and non-uniform grids ---------------------------


def xyz_rows(nx=5, ny=4, dx=2e-6, dy=3e-6, seed=0):
    x, y = np.meshgrid(np.arange(nx) * dx, np.arange(ny) * dy, indexing="ij")
    z = np.random.default_rng(seed).normal(size=(nx, ny)) * 1e-6
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()]), z


def test_xyz_with_an_absent_node_is_a_grid_with_a_missing_pixel(tmp_path):
    rows, z = xyz_rows()
    path = tmp_path / "holes.xyz"
    np.savetxt(path, np.delete(rows, 7, axis=0))  # node (1, 3) absent
    surface = topo.read_surface(path, unit="m")  # formerly read as a 19 x 3 height *matrix*
    assert surface.heights.shape == (5, 4) and surface.n_missing == 1
    assert np.isnan(surface.heights[1, 3])
    expected = z.copy()
    expected[1, 3] = np.nan
    np.testing.assert_allclose(surface.heights, expected, rtol=1e-15)
    assert surface.provenance["missing_nodes"] == 1
    with pytest.raises(ValueError, match="own coordinates"):
        topo.read_surface(path, pixel_size=1e-6)


def test_xyz_with_a_duplicated_node_is_refused(tmp_path):
    rows, _ = xyz_rows()
    path = tmp_path / "dup.xyz"
    np.savetxt(path, np.vstack([rows[:-1], rows[0]]))  # last node replaced by a repeat
    with pytest.raises(TopographyFileError, match=r"dup\.xyz: x y columns: give the node"):
        topo.read_surface(path)


def test_xyz_on_a_non_uniform_grid_is_refused(tmp_path):
    rows, _ = xyz_rows()
    rows[rows[:, 0] == 8e-6, 0] = 9e-6  # last x column shifted: steps 2, 2, 2, 3 um
    path = tmp_path / "stretched.xyz"
    np.savetxt(path, rows)
    with pytest.raises(TopographyFileError, match=r"x column: is not a uniform grid"):
        topo.read_surface(path)


# --- degenerate maps: refused by the analysis, not answered with a silent zero ------------


def test_all_nan_two_by_two_and_oversized_stride_are_refused():
    with pytest.raises(ValueError, match="every pixel"):
        topo.summit_statistics(topo.HeightMap(np.full((10, 10), np.nan), 1e-6, 1e-6))
    with pytest.raises(ValueError, match="3 x 3 pixels"):
        topo.summit_statistics(topo.HeightMap(np.eye(2), 1e-6, 1e-6))
    surface = topo.HeightMap(np.random.default_rng(0).normal(size=(30, 30)), 1e-6, 1e-6)
    with pytest.raises(ValueError, match="stride 11 leaves 3 x 3|stride 16 leaves 2 x 2"):
        topo.summit_statistics(surface, stride=16)
    # eta is counted over the sampling area (Appendix A): the whole 3 x 3 map left by stride
    # 10, 30 um x 30 um, though only its 1 interior pixel can host a summit
    stats = topo.summit_statistics(surface, stride=10)
    assert stats.nominal_area == pytest.approx(9e-10) and stats.n_candidates == 1
    assert topo.summit_statistics(surface, stride=10).grid_area == pytest.approx(9e-10)


def test_cli_hostile_inputs_exit_2_with_a_clear_message(capsys, tmp_path):
    empty = tmp_path / "empty.npy"
    empty.write_bytes(b"")
    zeros = tmp_path / "zeros.sur"
    zeros.write_bytes(bytes(4096))
    wrong = tmp_path / "scan.npy"
    shutil.copyfile(DATA / "x3p-2.x3p", wrong)
    nan_map = tmp_path / "nan.npy"
    np.save(nan_map, np.full((8, 8), np.nan))
    tiny = tmp_path / "tiny.txt"
    tiny.write_text("0 1e-6\n2e-6 0\n")
    noisy = tmp_path / "noisy.npy"
    np.save(noisy, np.random.default_rng(1).normal(size=(20, 20)) * 1e-6)
    cases = [
        (("stats", empty), "is empty"),
        (("stats", zeros), "match no supported format"),
        (("stats", wrong), "mislabelled"),
        (("stats", nan_map, "--pixel-size", "1e-6", "--detrend", "none"), "every pixel"),
        (("stats", nan_map, "--pixel-size", "1e-6"), "has 0 valid (non-NaN) pixels"),
        (("stats", tiny, "--pixel-size", "1e-6", "--unit", "m"), "3 x 3 pixels"),
        (("stats", noisy, "--pixel-size", "1e-6", "--stride", "50"), "3 x 3 pixels"),
        (("scan", noisy, "--pixel-size", "1e-6", "--max-stride", "50"), "max_stride 50"),
        (("stats", noisy, "--pixel-size", "-1e-6"), "--pixel-size: expected finite lengths"),
        (("stats", noisy, "--pixel-size", "0"), "--pixel-size: expected finite lengths"),
        (("stats", noisy, "--pixel-size", "1e-6,2e-6,3e-6"), "expected DX or DX,DY"),
        (("synth", "--out", tmp_path / "s.h5", "--n", 8, "--pixel-size", "-2e-6"), "--pixel-size"),
    ]
    for args, message in cases:
        status, out, err = run_cli(capsys, *args)
        assert status == 2, (args, out, err)
        assert message in err, (args, err)
        assert "Traceback" not in err
    status, out, _ = run_cli(capsys, "stats", noisy, "--pixel-size", "1e-6,2e-6", "--json")
    assert status == 0 and '"dy": 2e-06' in out


def test_dektak_profile_with_stretched_lateral_positions_is_refused(tmp_path):
    lines = (DATA / "dektak-1.csv").read_text(encoding="latin-1").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Lateral")) + 1
    n = sum(1 for line in lines[start:] if line.strip())
    # steps of 0.75 dx for the first half, 1.25 dx for the second: every step is within
    # half a step of dx, but the middle samples sit n/8 steps away from a uniform grid
    steps = np.where(np.arange(n) < n // 2, 0.75, 1.25) * 0.15625
    positions = np.concatenate([[0.0], np.cumsum(steps[:-1])])
    for k, x in enumerate(positions):
        lines[start + k] = f"{x:.4f}," + lines[start + k].split(",", 1)[1]
    path = tmp_path / "stretched.csv"
    path.write_text("\n".join(lines), encoding="latin-1")
    with pytest.raises(TopographyFileError, match=r"stretched\.csv: lateral column: is not a"):
        topo.read_surface(path)
    profile = topo.read_surface(DATA / "dektak-1.csv")  # printed to 0.1 um: accepted
    assert profile.dx == pytest.approx(1500e-6 / 9600, rel=1e-6)


@pytest.mark.parametrize(
    ("name", "listed"),
    [
        ("mi-1.mi", "'Topography', 'Deflection', 'Friction', 'Friction'"),
        ("di-3.di", "available channels: 0: "),
    ],
)
def test_unknown_channel_lists_the_channels(name, listed):
    with pytest.raises(ValueError, match="not found") as info:
        topo.read_surface(DATA / name, channel="Curvature")
    assert listed in str(info.value) and name in str(info.value)
    with pytest.raises(ValueError, match="not found"):
        topo.read_surface(DATA / name, channel=17)
    by_index = topo.read_surface(DATA / "mi-1.mi", channel=0)
    assert by_index.provenance["channel"] == "Topography"


def write_project_hdf5(path, **attrs):
    import h5py

    heights = attrs.pop("heights", np.zeros((4, 4)))
    shape = attrs.pop("shape", None)
    with h5py.File(path, "w") as handle:
        if shape is None:
            handle["heights"] = heights
        else:  # declared but never written: HDF5 would hand back fill values
            handle.create_dataset("heights", shape=shape, dtype="f8", chunks=(100, 100))
        values = {"format": "asperity-heightmap", "version": 1, "units": "m", "periodic": False}
        values.update({"dx": 1e-6, "dy": 1e-6}, **attrs)
        for key, value in values.items():
            if value is not None:
                handle.attrs[key] = value


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"dx": None}, r"attribute 'dx': is missing"),
        ({"dy": 0.0}, r"attribute 'dy': is 0.0 m; expected a finite value > 0"),
        ({"heights": np.array([[b"a", b"b"], [b"c", b"d"]])}, r"/heights: has dtype \|S1"),
        ({"shape": (100_000, 100_000)}, r"/heights: has shape \(100000, 100000\)"),
    ],
)
def test_project_hdf5_with_bad_attributes_or_a_hollow_dataset_is_refused(tmp_path, attrs, message):
    path = tmp_path / "bad.h5"
    write_project_hdf5(path, **attrs)
    with pytest.raises(TopographyFileError, match=message) as info:
        topo.read_surface(path)
    assert "bad.h5" in str(info.value)


# --- readers that refuse hostile files ---------------------------------------------------------


def patched(tmp_path: Path, name: str, offset: int, fmt: str, value, suffix: str = "") -> Path:
    """A copy of a sample with one struct field overwritten."""
    import struct

    data = bytearray((DATA / name).read_bytes())
    struct.pack_into(fmt, data, offset, value)
    path = tmp_path / (suffix or name)
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize(
    ("name", "offset", "fmt", "value", "field"),
    [
        ("sur-3.sur", 128, "<f", 0.0, "z spacing"),
        ("sur-3.sur", 128, "<f", -1.0, "invert the surface"),
        ("sur-3.sur", 120, "<f", 1e21, "x spacing: gives a pixel size of"),
        ("sur-3.sur", 120, "<f", 1e-39, "x spacing: gives a pixel size of"),
        ("metropro-1.dat", 164, ">f", 0.0, "intf_scale_factor"),
        ("metropro-1.dat", 184, ">f", 1e21, "lateral_res"),
        ("plu-1.plu", 404, "<f", 1e-39, "micrometers per pixel x"),
    ],
)
def test_zero_negative_or_absurd_scale_factors_are_refused(
    tmp_path, name, offset, fmt, value, field
):
    from asperity.topo.errors import PhysicalBoundsError

    with pytest.raises(PhysicalBoundsError, match=field) as info:
        topo.read_surface(patched(tmp_path, name, offset, fmt, value))
    assert name in str(info.value)


def edited_text(tmp_path: Path, name: str, old: bytes, new: bytes) -> Path:
    data = (DATA / name).read_bytes()
    assert old in data
    path = tmp_path / name
    path.write_bytes(data.replace(old, new, 1))
    return path


def test_nanoscope_and_picoview_zero_height_scales_are_refused(tmp_path):
    from asperity.topo.errors import PhysicalBoundsError

    zero_z = edited_text(
        tmp_path, "di-3.di", b"(0.005035400 V/LSB) 329.9950 V", b"(0.005035400 V/LSB) 0.000000 V"
    )
    with pytest.raises(PhysicalBoundsError, match=r"image 3 '@2:Z scale'.*a zero factor"):
        topo.read_surface(zero_z, channel="Height")
    (tmp_path / "di-3.di").unlink()
    data = (DATA / "mi-1.mi").read_bytes()
    start = data.index(b"bufferRange")
    line_end = data.index(b"\n", start)
    path = tmp_path / "mi-1.mi"
    value = data[start + 14 : line_end].rstrip(b"\r")
    zero = b"0." + b"0" * (len(value) - 2)
    path.write_bytes(data[: start + 14] + zero + data[start + 14 + len(value) :])
    with pytest.raises(PhysicalBoundsError, match="bufferRange"):
        topo.read_surface(path)


def test_nanoscope_data_offset_into_the_header_is_refused(tmp_path):
    from asperity.topo.errors import CorruptFileError

    path = edited_text(tmp_path, "di-3.di", b"\\Data offset: 434176", b"\\Data offset: 004096")
    with pytest.raises(
        CorruptFileError, match=r"image 3 'Data offset': is 4096, inside the header"
    ):
        topo.read_surface(path)


def test_nanoscope_never_falls_back_to_another_channel(tmp_path):
    from asperity.topo.errors import ChannelNotFoundError

    data = (DATA / "di-3.di").read_bytes()
    renamed = data.replace(b'[Height] "Height"', b'[Heighx] "Heighx"', 1)
    renamed = renamed.replace(b'[ZSensor] "Height Sensor"', b'[ZSensox] "Height Sensox"', 1)
    path = tmp_path / "di-3.di"
    path.write_bytes(renamed)
    with pytest.raises(
        ChannelNotFoundError,
        match=r"no channel is named 'Height Sensor' \(ZSensor\) or 'Height'.*3: Heighx",
    ) as info:
        topo.read_surface(path)
    assert "0: Height Sensox [ZSensox]" in str(info.value)
    assert topo.read_surface(path, channel="Heighx").heights.shape == (256, 256)
    # without the sensor channel, the default is the channel named Height
    path.write_bytes(data.replace(b'[ZSensor] "Height Sensor"', b'[ZSensox] "Height Sensox"', 1))
    assert topo.read_surface(path).provenance["channel"] == "Height"
    # a sensor channel whose scale is not a length is refused, not replaced by another one
    path.unlink()
    broken = edited_text(
        tmp_path, "di-3.di", b"@2:Z scale: V [Sens. ZsensSens]", b"@2:Z scale: V [Sens. ZsensSenx]"
    )
    with pytest.raises(TopographyFileError, match="not a length"):
        topo.read_surface(broken)


def test_instrument_invalid_points_are_counted_in_provenance():
    for name, expected in (("sur-3.sur", 233009), ("opd-1.opd", 116), ("plu-1.plu", 0)):
        surface = topo.read_surface(DATA / name)
        assert surface.provenance["missing_pixels"] == expected == surface.n_missing
        assert surface.provenance["invalid_marker"]


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("1,5 2,5\n3,5 4,5\n", r"line 1, column 1: is '1,5' \(a decimal comma"),
        ("1.5;2,5\n3.5;4.5\n", r"line 1, column 5 \(value 2\): is '2,5' \(a decimal comma"),
        ("1e-6 2e-6\n3e-6 1_000\n", r"line 2, column 6 \(value 2\): is '1_000' \(digit sep"),
        ("1e-6 2e-6\n3e-6 inf\n", r"line 2, column 6 \(value 2\): is 'inf'"),
        ("1e-6\t2e-6\n3e-6  0x1p-20\n", r"line 2, column 7 \(value 2\): is '0x1p-20'"),
    ],
)
def test_text_outside_the_stated_number_format_is_refused_with_line_and_column(
    tmp_path, text, where
):
    from asperity.topo.errors import NumberFormatError

    path = tmp_path / "map.txt"
    path.write_text(text)
    with pytest.raises(NumberFormatError, match=where) as info:
        topo.read_surface(path, pixel_size=1e-6)
    assert "map.txt" in str(info.value)


def test_text_separators_and_nan_in_the_stated_format(tmp_path):
    expected = np.array([[1.5e-6, -2e-7], [np.nan, 4e-6]])
    for body in (
        "1.5e-6, -2E-7,\n nan , 4e-6,\n",
        "1.5e-6;-2e-7\nNaN;+4e-6\n",
        "1.5e-6\t-2e-7\nnan 4e-6\n",
    ):
        path = tmp_path / "map.csv"
        path.write_text("# heights in m\n" + body)
        surface = topo.read_surface(path, pixel_size=1e-6, unit="m")
        np.testing.assert_array_equal(surface.heights, expected)
        assert surface.provenance["missing_pixels"] == 1


def zip_with_member(path: Path, flag_bits: int = 0, method: int = zipfile.ZIP_DEFLATED) -> Path:
    buffer = io.BytesIO()
    np.save(buffer, np.zeros((4, 4)))
    with zipfile.ZipFile(path, "w", method) as archive:
        archive.writestr("heights.npy", buffer.getvalue())
    data = bytearray(path.read_bytes())
    for signature, flags_at in ((b"PK\x03\x04", 6), (b"PK\x01\x02", 8)):
        start = data.index(signature)
        data[start + flags_at] |= flag_bits
    path.write_bytes(bytes(data))
    return path


def test_npz_encrypted_unsupported_and_crc_damaged_members_are_refused(tmp_path):
    from asperity.topo.errors import CorruptFileError, UnsupportedContentError

    with pytest.raises(UnsupportedContentError, match="'heights.npy': is encrypted"):
        topo.read_surface(zip_with_member(tmp_path / "enc.npz", flag_bits=1), pixel_size=1e-6)
    with pytest.raises(UnsupportedContentError, match="compression method 12"):
        topo.read_surface(
            zip_with_member(tmp_path / "bz.npz", method=zipfile.ZIP_BZIP2), pixel_size=1e-6
        )
    path = zip_with_member(tmp_path / "crc.npz", method=zipfile.ZIP_STORED)
    data = bytearray(path.read_bytes())
    data[data.index(b"\x93NUMPY") + 200] ^= 0x01  # one data bit; the CRC-32 no longer matches
    path.write_bytes(bytes(data))
    with pytest.raises(CorruptFileError, match="CRC"):
        topo.read_surface(path, pixel_size=1e-6)


def test_damaged_npy_header_is_a_typed_error(tmp_path):
    path = tmp_path / "bad.npy"
    buffer = io.BytesIO()
    np.save(buffer, np.zeros((4, 4)))
    data = buffer.getvalue().replace(b"'shape': (4, 4)", b"'shape': (4, 4 ")
    path.write_bytes(data)
    with pytest.raises(TopographyFileError, match=r"bad\.npy: array NPY header: is unreadable"):
        topo.read_surface(path, pixel_size=1e-6)


def test_x3p_valid_points_mask_larger_than_the_map_is_refused_before_reading(tmp_path):
    from asperity.topo.errors import CorruptFileError

    source = DATA / "x3p-2.x3p"
    path = tmp_path / "mask.x3p"
    with zipfile.ZipFile(source) as old, zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as new:
        for info in old.infolist():
            body = old.read(info)
            if info.filename == "main.xml":
                body = body.replace(
                    b"</DataLink>",
                    b"<ValidPointsLink>bindata/valid.bin</ValidPointsLink></DataLink>",
                )
            new.writestr(info.filename, body)
        new.writestr("bindata/valid.bin", bytes(2**24))  # 16 MiB of zeros, deflates to 16 kB
    with pytest.raises(
        CorruptFileError,
        match=r"valid-points mask bindata/valid.bin: declares 16777216 bytes; expected 52813",
    ):
        topo.read_surface(path)


def test_hdf5_external_storage_links_and_loops_are_refused(tmp_path):
    import h5py

    from asperity.topo.errors import CorruptFileError, UnsupportedContentError

    secret = tmp_path / "secret.bin"
    secret.write_bytes(np.arange(16.0).tobytes())
    external = tmp_path / "external.h5"
    write_project_hdf5(external)
    with h5py.File(external, "r+") as handle:
        del handle["heights"]
        handle.create_dataset(
            "heights", shape=(4, 4), dtype="<f8", external=[(str(secret), 0, 128)]
        )
    with pytest.raises(UnsupportedContentError, match="stores its data in another file"):
        topo.read_surface(external)
    for kind in ("soft-loop", "external-link"):
        path = tmp_path / f"{kind}.h5"
        write_project_hdf5(path)
        with h5py.File(path, "r+") as handle:
            del handle["heights"]
            if kind == "soft-loop":
                handle["heights"] = h5py.SoftLink("/again")
                handle["again"] = h5py.SoftLink("/heights")
            else:
                handle["heights"] = h5py.ExternalLink(str(external), "/heights")
        error = CorruptFileError if kind == "soft-loop" else UnsupportedContentError
        with pytest.raises(error, match="link"):
            topo.read_surface(path)


def test_hdf5_virtual_dataset_is_refused(tmp_path):
    import h5py

    from asperity.topo.errors import UnsupportedContentError

    source = tmp_path / "source.h5"
    write_project_hdf5(source)
    path = tmp_path / "virtual.h5"
    write_project_hdf5(path)
    layout = h5py.VirtualLayout(shape=(4, 4), dtype="f8")
    layout[:] = h5py.VirtualSource(str(source), "heights", shape=(4, 4))
    with h5py.File(path, "r+") as handle:
        del handle["heights"]
        handle.create_virtual_dataset("heights", layout)
    with pytest.raises(UnsupportedContentError, match="virtual dataset"):
        topo.read_surface(path)


@pytest.mark.parametrize(
    ("periodic", "expected"),
    [(True, True), (False, False), (np.int64(1), True), (0, False), ("no", None), (b"yes", None),
     (2, None), (0.5, None)],
)  # fmt: skip
def test_hdf5_periodic_accepts_booleans_and_0_1_only(tmp_path, periodic, expected):
    path = tmp_path / "p.h5"
    write_project_hdf5(path, periodic=periodic)
    if expected is None:
        with pytest.raises(
            TopographyFileError, match="attribute 'periodic': is .*expected a boolean"
        ):
            topo.read_surface(path)
    else:
        assert topo.read_surface(path).periodic is expected


def test_hdf5_non_string_provenance_is_a_typed_error(tmp_path):
    for value in (np.arange(3), 7, "[1, 2]", "{not json"):
        path = tmp_path / "prov.h5"
        write_project_hdf5(path, provenance=value)
        with pytest.raises(TopographyFileError, match="attribute 'provenance'"):
            topo.read_surface(path)
    write_project_hdf5(path, provenance='{"seed": 4}')
    assert topo.read_surface(path).provenance["seed"] == 4


def test_hdf5_pixel_sizes_beyond_the_physical_bounds_are_refused(tmp_path):
    from asperity.topo.errors import PhysicalBoundsError

    for value in (1e21, 1e-39):
        path = tmp_path / "dx.h5"
        write_project_hdf5(path, dx=value)
        with pytest.raises(PhysicalBoundsError, match="attribute 'dx': gives a pixel size"):
            topo.read_surface(path)


def test_directory_is_named_as_a_directory(tmp_path):
    with pytest.raises(TopographyFileError, match="is a directory"):
        topo.read_surface(tmp_path)


# --- special files: a FIFO, a device, a directory or a link to them is named, never read ---


@pytest.fixture
def alarm():
    """Fail (rather than hang) a test whose read blocks for more than 20 s."""
    import signal

    def interrupt(signum, frame):
        raise TimeoutError("a read blocked: a special file was opened")

    previous = signal.signal(signal.SIGALRM, interrupt)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, previous)


def _fifo(tmp_path, name):
    import os

    path = tmp_path / name
    os.mkfifo(path)
    return path


def test_fifo_device_and_links_to_them_are_refused_as_topography_files(tmp_path, alarm):
    fifo = _fifo(tmp_path, "map.npy")
    link = tmp_path / "link.npy"
    link.symlink_to(fifo)
    device_link = tmp_path / "zero.npy"
    device_link.symlink_to("/dev/zero")
    cases = {
        fifo: "is a FIFO",
        link: "is a symlink to a FIFO",
        device_link: "is a symlink to a character device",
        Path("/dev/zero"): "is a character device",
    }
    for path, kind in cases.items():
        with pytest.raises(TopographyFileError, match=f"{kind}.*expected a regular file"):
            topo.read_surface(path, pixel_size=1e-6)
    with pytest.raises(TopographyFileError, match="is a FIFO"):
        topo.read_surface(fifo.rename(fifo.with_suffix(".di")))


def test_special_job_file_surface_file_and_outputs_exit_2_in_one_line(tmp_path, capsys, alarm):
    fifo = _fifo(tmp_path, "job.toml")
    for job, kind in ((fifo, "is a FIFO"), ("/dev/zero", "is a character device")):
        status, out, err = run_cli(capsys, "run", job, "--out", tmp_path / "o")
        assert status == 2 and kind in err and "expected a regular file" in err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    job = tmp_path / "dir.toml"
    job.write_text(f'[surface]\nfile = "{tmp_path}"\n')
    status, _, err = run_cli(capsys, "run", job, "--out", tmp_path / "o")
    assert status == 2 and "surface.file" in err and "is a directory" in err
    link = tmp_path / "map.h5"
    link.symlink_to(_fifo(tmp_path, "pipe"))
    job.write_text('[surface]\nfile = "map.h5"\n')
    status, _, err = run_cli(capsys, "run", job, "--out", tmp_path / "o")
    assert status == 2 and "surface.file" in err and "symlink to a FIFO" in err
    status, _, err = run_cli(capsys, "friction", fifo)
    assert status == 2 and "is a FIFO" in err
    for out_path, kind in ((tmp_path / "pipe", "is a FIFO"), (tmp_path, "is a directory")):
        status, _, err = run_cli(capsys, "synth", "--n", 16, "--out", out_path)
        assert status == 2 and "--out" in err and kind in err
    assert not (tmp_path / "o").exists()


def test_special_measured_csv_is_refused_at_the_open(tmp_path, alarm):
    from asperity.errors import InputError
    from asperity.pipelines.measured import read_normal_area

    fifo = _fifo(tmp_path, "area.csv")
    with pytest.raises(InputError, match="measured file: .*area.csv is a FIFO"):
        read_normal_area(fifo)


# --- size bombs: refused from the declared sizes, before reading, naming the budget -------


def test_gzip_hdf5_map_over_the_pipeline_budget_is_refused_before_reading(tmp_path, monkeypatch):
    """A 16000^2 gzip map storing enough bytes to pass the deflate-ratio check (it would
    inflate to 2 GB of heights and need about 48 GiB in the pipeline) is refused at once."""
    import time

    monkeypatch.setattr(limits, "system_memory_ceilings", dict)  # the configured 16 GiB rules
    monkeypatch.delenv("ASPERITY_MEMORY_BUDGET", raising=False)

    import h5py

    from asperity.topo.errors import OverBudgetError

    path = tmp_path / "bomb.h5"
    with h5py.File(path, "w") as handle:
        data = handle.create_dataset(
            "heights", shape=(16000, 16000), dtype="f8", chunks=(512, 512), compression="gzip"
        )
        data[:512, :512] = np.random.default_rng(0).normal(size=(512, 512)) * 1e-6
        for key, value in {"format": "asperity-heightmap", "version": 1, "units": "m"}.items():
            handle.attrs[key] = value
        handle.attrs.update({"periodic": False, "dx": 1e-6, "dy": 1e-6})
    began = time.perf_counter()
    with pytest.raises(OverBudgetError, match=r"16000 x 16000 = 256000000 points") as info:
        topo.read_surface(path)
    assert time.perf_counter() - began < 1.0
    message = str(info.value)
    assert "memory budget of 16 GiB set by the configured budget" in message
    assert "ASPERITY_MEMORY_BUDGET" in message


def test_npz_bomb_is_refused_from_its_npy_header_before_inflating(tmp_path, monkeypatch):
    import time

    from asperity.topo.errors import OverBudgetError

    path = tmp_path / "bomb.npz"
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        # the header declares 20000^2 float64 (3.2 GB); the member holds 1 MB of zeros
        archive.writestr("heights.npy", npy_header((20000, 20000)) + bytes(2**20))
    began = time.perf_counter()
    with pytest.raises(OverBudgetError, match=r"array 'heights' shape: declare 20000 x 20000"):
        topo.read_surface(path, pixel_size=1e-6)
    assert time.perf_counter() - began < 1.0
    # the knob: a larger budget lets the header through, and the member is then refused
    # for holding less than it declares (on a machine that grants the memory)
    monkeypatch.setattr(limits, "system_memory_ceilings", dict)
    monkeypatch.setenv("ASPERITY_MEMORY_BUDGET", "128GiB")
    with pytest.raises(TopographyFileError, match="array 'heights'") as info:
        topo.read_surface(path, pixel_size=1e-6)
    assert not isinstance(info.value, OverBudgetError)


def test_memory_budget_knob_scales_the_largest_map_and_refuses_nonsense(monkeypatch):
    from asperity.errors import InputError
    from asperity.topo.io import limits

    monkeypatch.setattr(limits, "system_memory_ceilings", dict)  # a machine granting it all
    default = limits.max_map_points()
    assert default == limits.MAX_MAP_POINTS
    # the paper's 5001^2 map fits the default budget; 16000^2 does not
    assert 5001**2 < default < 16000**2
    monkeypatch.setenv("ASPERITY_MEMORY_BUDGET", "64GiB")
    assert limits.max_map_points() > 4 * default
    for text in ("lots", "-1GiB", "1MiB"):
        monkeypatch.setenv("ASPERITY_MEMORY_BUDGET", text)
        with pytest.raises(InputError, match="ASPERITY_MEMORY_BUDGET"):
            limits.max_map_points()
