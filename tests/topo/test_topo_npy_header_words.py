"""An oversized NPY header is refused in asperity's words (issue 40, item 11): numpy's own
refusal advises ``allow_pickle=True``, i.e. trusting the file, over four lines."""

from __future__ import annotations

import struct

import pytest

from asperity import topo
from asperity.topo.errors import CorruptFileError


def test_an_oversized_npy_header_is_refused_without_numpy_s_advice(tmp_path):
    header = repr({"descr": "<f8", "fortran_order": False, "shape": (4, 4)}) + " " * 20000
    data = b"\x93NUMPY\x02\x00" + struct.pack("<I", len(header) + 1) + header.encode() + b"\n"
    path = tmp_path / "long_header.npy"
    path.write_bytes(data + bytes(128))
    with pytest.raises(CorruptFileError) as info:
        topo.read_surface(path, pixel_size=1e-6)
    message = str(info.value)
    assert "NPY header" in message and "is 2005" in message and "bytes long" in message
    assert "allow_pickle" not in message and "\n" not in message
