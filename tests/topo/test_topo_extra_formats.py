"""The ``formats`` extra: SurfaceTopography's readers behind asperity's checks, and the one
line a user without it is told. Files are generated here (none of SurfaceTopography's
example files is committed); tests that need the extra skip when it is absent."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.cli import main
from asperity.topo.errors import TopographyFileError
from asperity.topo.io import surfacetopography

HAS_EXTRA = importlib.util.find_spec("SurfaceTopography") is not None
needs_extra = pytest.mark.skipif(not HAS_EXTRA, reason='needs pip install "asperity[formats]"')


def write_sdf(path, heights, dx=0.5e-6, dy=0.25e-6, zscale=1e-9):
    """An ISO 25178-71 SDF text file (a format asperity does not read natively)."""
    nx, ny = heights.shape
    header = [
        "aISO-1.0",
        "ManufacID = asperity test",
        "CreateDate = 250220261200",
        "ModDate = 250220261200",
        f"NumPoints = {nx}",
        f"NumProfiles = {ny}",
        f"Xscale = {dx:.6E}",
        f"Yscale = {dy:.6E}",
        f"Zscale = {zscale:.6E}",
        "Zresolution = 1.0E-9",
        "Compression = 0",
        "DataType = 7",
        "CheckType = 0",
        "*",
    ]
    rows = [" ".join(f"{v:.6f}" for v in heights[:, j]) for j in range(ny)]
    path.write_text("\n".join([*header, *rows, "*", ""]))
    return path


def test_without_the_extra_a_foreign_format_is_one_line_naming_it(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(surfacetopography, "extra_available", lambda: False)
    path = tmp_path / "scan.vk4"
    path.write_bytes(b"VK4_" + bytes(range(200)))
    with pytest.raises(TopographyFileError, match=r'pip install "asperity\[formats\]"'):
        topo.read_surface(path)
    status = main(["stats", str(path)])
    err = capsys.readouterr().err
    assert status == 2 and 'pip install "asperity[formats]"' in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_native_formats_never_go_to_the_extra(monkeypatch, tmp_path):
    def refuse(*args, **kwargs):
        raise AssertionError("the extra was called for a native format")

    monkeypatch.setattr("asperity.topo.io.read_with_extra", refuse)
    junk = tmp_path / "broken.sur"
    junk.write_bytes(bytes(4096))
    with pytest.raises(TopographyFileError, match="no supported format"):
        topo.read_surface(junk)


@needs_extra
def test_a_foreign_format_is_read_in_metres_with_its_channel(tmp_path):
    heights = np.random.default_rng(4).normal(size=(12, 7))
    surface = topo.read_surface(write_sdf(tmp_path / "map.sdf", heights))
    assert isinstance(surface, topo.HeightMap)
    assert (surface.nx, surface.ny) == (12, 7)
    assert surface.dx == pytest.approx(0.5e-6) and surface.dy == pytest.approx(0.25e-6)
    np.testing.assert_allclose(surface.heights, heights * 1e-9, rtol=1e-5, atol=1e-15)
    provenance = surface.provenance
    assert provenance["format"].startswith("SurfaceTopography")
    assert provenance["channel_index"] == 0 and provenance["channel"] in provenance["channels"]
    with pytest.raises(TopographyFileError, match="channel: 'nope' does not exist"):
        topo.read_surface(tmp_path / "map.sdf", channel="nope")


@needs_extra
def test_the_extra_obeys_asperitys_height_bound(tmp_path):
    heights = np.full((4, 4), 5.0)  # 5 m with Zscale 1: beyond the 1 m bound
    path = write_sdf(tmp_path / "huge.sdf", heights, zscale=1.0)
    with pytest.raises(TopographyFileError, match=r"heights: reach 5 m"):
        topo.read_surface(path)


@needs_extra
def test_a_file_neither_reads_is_a_typed_error_on_one_line(tmp_path):
    path = tmp_path / "notes.xyz1"
    path.write_text("This is not a topography.\nNor is this.\n")
    with pytest.raises(TopographyFileError, match="no supported format") as info:
        topo.read_surface(path)
    assert "\n" not in str(info.value)
