"""Readers of the real instrument files in tests/data against an independent reader.

The reference values (grid, physical size, rms height, missing pixels) were computed once
with SurfaceTopography 1.27.1 (``read_topography``, heights converted to m, masked pixels
left out of the rms) in a separate venv, and are hard-coded here; SurfaceTopography is not
a dependency. ``benchmarks/topo_readers_crosscheck.py`` re-runs the comparison pixel by
pixel when the peer is installed.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.topo.errors import TopographyFileError

DATA = Path(__file__).resolve().parents[1] / "data"

# file, channel, grid, physical size (m), rms height (m), missing pixels: SurfaceTopography
REFERENCE = [
    ("x3p-2.x3p", None, (650, 650), (8.29767313942749e-05, 0.0002044783737930349),
     7.728033273597876e-08, 0),
    ("sur-3.sur", None, (512, 512), (0.151319552, 0.151319552), 0.0011131994265859693, 233009),
    ("metropro-1.dat", None, (640, 480), (0.0007028812979115173, 0.000527160973433638),
     7.52882220473459e-08, 0),
    ("plu-1.plu", None, (768, 576), (0.0012748800659179687, 0.0009561600494384765),
     2.834390987634884e-06, 0),
    ("opd-1.opd", None, (640, 480), (0.0001259091403335333, 9.443185525014996e-05),
     8.356451162720974e-09, 116),
    ("di-3.di", "Height", (256, 256), (1e-05, 1e-05), 2.640028527620316e-07, 0),
    ("di-3.di", None, (256, 256), (1e-05, 1e-05), 2.264253966845741e-07, 0),
    ("mi-1.mi", None, (256, 256), (2e-05, 2e-05), 3.3215426493512656e-08, 0),
]  # fmt: skip


@pytest.mark.parametrize(("name", "channel", "grid", "size", "rms", "missing"), REFERENCE)
def test_real_file_matches_independent_reader(name, channel, grid, size, rms, missing):
    surface = topo.read_surface(DATA / name, channel=channel)
    assert isinstance(surface, topo.HeightMap)
    assert surface.heights.shape == grid
    assert surface.heights.dtype == np.float64
    np.testing.assert_allclose((surface.lx, surface.ly), size, rtol=1e-6)
    np.testing.assert_allclose(np.nanstd(surface.heights), rms, rtol=1e-6)
    assert surface.n_missing == missing
    assert surface.provenance["file"].endswith(name)
    assert not surface.periodic


def test_x3p_has_non_square_pixels():
    surface = topo.read_surface(DATA / "x3p-2.x3p")
    assert surface.dy / surface.dx == pytest.approx(3.14582113527746e-07 / 1.27656509837346e-07)


def test_sur_reads_units_from_the_step_unit_fields():
    surface = topo.read_surface(DATA / "sur-3.sur")
    # dx is 295546 in 'nm' step units (the axis unit is um): 2.95546e-4 m.
    assert surface.dx == pytest.approx(295546e-9, rel=1e-6)
    assert surface.provenance["units"]["x step"] == "nm"


def test_dektak_csv_is_a_line_profile_refused_by_2d_analyses():
    profile = topo.read_surface(DATA / "dektak-1.csv")
    assert isinstance(profile, topo.LineProfile)
    assert profile.nx == 9600
    assert profile.lx == pytest.approx(0.0014998, rel=1e-3)
    np.testing.assert_allclose(np.std(profile.heights), 4.764232930211045e-06, rtol=1e-6)
    with pytest.raises(ValueError, match="1D line profile"):
        topo.summit_statistics(profile)
    with pytest.raises(ValueError, match="1D line profile"):
        topo.level(profile)


def test_nanoscope_channels_by_name_and_non_height_channel_refused():
    default = topo.read_surface(DATA / "di-3.di")
    assert default.provenance["channel"] == "Height Sensor"
    assert default.provenance["channel_key"] == "ZSensor"
    by_index = topo.read_surface(DATA / "di-3.di", channel=0)
    np.testing.assert_array_equal(default.heights, by_index.heights)
    with pytest.raises(TopographyFileError, match="not a length"):
        topo.read_surface(DATA / "di-3.di", channel="Phase")
    with pytest.raises(ValueError, match="available channels"):
        topo.read_surface(DATA / "di-3.di", channel="nonsense")


def test_picoview_four_channels():
    surface = topo.read_surface(DATA / "mi-1.mi")
    assert surface.provenance["channel"] == "Topography"
    assert surface.provenance["channels"] == ["Topography", "Deflection", "Friction", "Friction"]
    with pytest.raises(TopographyFileError, match="not a length"):
        topo.read_surface(DATA / "mi-1.mi", channel="Deflection")


SAMPLES = [name for name in sorted({row[0] for row in REFERENCE})] + ["dektak-1.csv"]


@pytest.mark.parametrize("name", SAMPLES)
@pytest.mark.parametrize("fraction", [0.5, 0.97])
def test_truncated_copy_is_refused(tmp_path, name, fraction):
    if name == "plu-1.plu" and fraction > 0.95:
        # The last 4 % of this file is a metadata trailer of undocumented size after the
        # RGB image; cut into the RGB image instead.
        fraction = 0.8
    data = (DATA / name).read_bytes()
    truncated = tmp_path / name
    truncated.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(TopographyFileError) as info:
        topo.read_surface(truncated)
    assert name in str(info.value)


@pytest.mark.parametrize(
    ("name", "wrong"),
    [("sur-3.sur", "x3p"), ("x3p-2.x3p", "sur"), ("di-3.di", "opd"), ("metropro-1.dat", "mi")],
)
def test_mislabelled_file_is_refused(tmp_path, name, wrong):
    copy = tmp_path / f"surface.{wrong}"
    shutil.copyfile(DATA / name, copy)
    with pytest.raises(TopographyFileError, match="mislabelled"):
        topo.read_surface(copy)


def test_corrupt_size_field_is_refused(tmp_path):
    data = bytearray((DATA / "metropro-1.dat").read_bytes())
    data[72:76] = (10**8).to_bytes(4, "big")  # cn_n_bytes
    copy = tmp_path / "bad.dat"
    copy.write_bytes(bytes(data))
    with pytest.raises(TopographyFileError, match="cn_n_bytes"):
        topo.read_surface(copy)


def test_unknown_and_empty_files_are_refused(tmp_path):
    empty = tmp_path / "empty.sur"
    empty.write_bytes(b"")
    with pytest.raises(TopographyFileError, match="empty"):
        topo.read_surface(empty)
    junk = tmp_path / "junk.bin"
    junk.write_bytes(bytes(range(256)) * 4)
    # without the formats extra the message names it; with it, neither reader reads the file
    unknown = r"not one asperity reads natively.*asperity\[formats\]|matches no supported format"
    with pytest.raises(TopographyFileError, match=unknown):
        topo.read_surface(junk)
    with pytest.raises(FileNotFoundError):
        topo.read_surface(tmp_path / "missing.x3p")


def test_channel_for_a_single_channel_format_is_refused():
    with pytest.raises(ValueError, match="single channel"):
        topo.read_surface(DATA / "opd-1.opd", channel="Height")
