"""Hostile and degenerate inputs: each gets a clear error naming the file/field, never a
traceback, a huge allocation or a silently wrong number (review of issue 4)."""

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
    surface = topo.read_surface(path)  # formerly read as a 19 x 3 height *matrix*
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
        (("stats", tiny, "--pixel-size", "1e-6"), "3 x 3 pixels"),
        (("stats", noisy, "--pixel-size", "1e-6", "--stride", "50"), "3 x 3 pixels"),
        (("scan", noisy, "--pixel-size", "1e-6", "--max-stride", "50"), "max_stride 50"),
        (("stats", noisy, "--pixel-size", "-1e-6"), "--pixel-size: expected finite lengths"),
        (("stats", noisy, "--pixel-size", "0"), "--pixel-size: expected finite lengths"),
        (("stats", noisy, "--pixel-size", "1e-6,2e-6,3e-6"), "expected DX or DX,DY"),
        (("synth", "--out", tmp_path / "s.h5", "--n", 8, "--pixel-size", "-2e-6"), "pixel_size"),
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
