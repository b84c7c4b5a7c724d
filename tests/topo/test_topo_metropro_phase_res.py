"""MetroPro ``phase_res`` against a known answer (issue 40, item 4).

The MetroPro Reference Guide's phase resolutions: code 0 -> R = 4096, 1 -> 32768,
2 -> 131072; height (m) = phase count * S * O * W / R. Copies of tests/data/metropro-1.dat
(header format 1, phase_res 1) with the code rewritten are read, and every height is compared
with the one computed here from the raw big-endian counts and the header's float32 fields.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.topo.errors import TopographyFileError

SOURCE = Path(__file__).parents[1] / "data" / "metropro-1.dat"
RESOLUTION = {0: 4096, 1: 32768, 2: 131072}


def _with_phase_res(tmp_path: Path, code: int) -> Path:
    data = bytearray(SOURCE.read_bytes())
    struct.pack_into(">h", data, 218, code)
    path = tmp_path / f"phase_res_{code}.dat"
    path.write_bytes(bytes(data))
    return path


def _expected_heights(code: int) -> np.ndarray:
    """Heights from first principles: counts * S * O * W / R, invalid counts NaN, (x, y)."""
    data = SOURCE.read_bytes()
    header = struct.unpack_from(">I", data, 6)[0]
    intensity_bytes = struct.unpack_from(">i", data, 60)[0]
    width, height = struct.unpack_from(">HH", data, 68)
    scale, wavelength = struct.unpack_from(">ff", data, 164)
    obliquity = struct.unpack_from(">f", data, 176)[0]
    counts = np.frombuffer(data, ">i4", width * height, header + intensity_bytes)
    step = float(scale) * float(obliquity) * float(wavelength) / RESOLUTION[code]
    heights = np.where(counts >= 2147483640, np.nan, counts * step)
    return heights.reshape(height, width).T


@pytest.mark.parametrize("code", [0, 1, 2])
def test_each_phase_res_code_reads_the_documented_resolution(tmp_path, code):
    surface = topo.read_surface(_with_phase_res(tmp_path, code))
    expected = _expected_heights(code)
    assert surface.heights.shape == expected.shape
    np.testing.assert_array_equal(np.isnan(surface.heights), np.isnan(expected))
    np.testing.assert_allclose(surface.heights, expected, rtol=1e-12, equal_nan=True)
    assert surface.provenance["units"]["phase_resolution"] == RESOLUTION[code]


def test_phase_res_2_is_a_quarter_of_phase_res_1_and_the_code_is_unchecked(tmp_path):
    high = topo.read_surface(_with_phase_res(tmp_path, 1)).heights
    super_ = topo.read_surface(_with_phase_res(tmp_path, 2)).heights
    np.testing.assert_allclose(super_ * 4, high, rtol=1e-12, equal_nan=True)
    unchecked = topo.read_surface(_with_phase_res(tmp_path, 2)).provenance["unchecked"]
    assert any(item.startswith("phase_res: taken as written") for item in unchecked)


@pytest.mark.parametrize("code", [-1, 3, 32767])
def test_an_undocumented_phase_res_is_refused_naming_the_field(tmp_path, code):
    with pytest.raises(TopographyFileError, match=r"phase_res: is -?\d+; expected 0, 1 or 2"):
        topo.read_surface(_with_phase_res(tmp_path, code))
