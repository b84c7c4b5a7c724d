"""Readers refuse a header that contradicts the data, and say where nothing can check it."""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest

from asperity import topo
from asperity.topo.errors import CorruptFileError

DATA = Path(__file__).resolve().parents[1] / "data"


def test_an_x3p_profile_feature_type_over_a_grid_is_refused(tmp_path):
    source, path = DATA / "x3p-2.x3p", tmp_path / "lying.x3p"
    with zipfile.ZipFile(source) as old, zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as new:
        for info in old.infolist():
            body = old.read(info)
            if info.filename == "main.xml":
                assert b"<FeatureType>SUR</FeatureType>" in body
                body = body.replace(b"<FeatureType>SUR", b"<FeatureType>PRF")
            new.writestr(info.filename, body)
    surface = topo.read_surface(source)
    nx, ny = surface.heights.shape
    assert ny > 1  # a grid: the PRF label contradicts it
    with pytest.raises(CorruptFileError, match=rf"FeatureType: is 'PRF'.* {nx} x {ny}"):
        topo.read_surface(path)


def test_metropro_says_what_nothing_in_the_file_can_check():
    provenance = topo.read_surface(DATA / "metropro-1.dat").provenance
    unchecked = " ".join(provenance["unchecked"])
    assert "phase_res" in unchecked and "checksum" in unchecked
