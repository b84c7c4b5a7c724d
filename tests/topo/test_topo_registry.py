"""The reader registry: one entry per format, the detection precedence it states, the format
lists of the messages drawn from it."""

from __future__ import annotations

import numpy as np
import pytest

from asperity.topo.errors import TopographyFileError
from asperity.topo.io import FORMATS_BY_EXTENSION, READERS, detect_format, read_surface


def test_every_extension_announces_one_format_and_every_name_is_unique():
    extensions = [ext for entry in READERS for ext in entry.extensions]
    assert len(extensions) == len(set(extensions)) == len(FORMATS_BY_EXTENSION)
    assert all(ext == ext.lower() and ext.startswith(".") for ext in extensions)
    assert len({entry.name for entry in READERS}) == len(READERS)


@pytest.mark.parametrize(
    ("head", "expected"),
    [
        (b"", None),  # empty: nothing claims it
        (b"PK\x03\x04 not an archive", "zip"),  # a zip magic is never text
        (b"\x89HDF\r\n\x1a\n" + b"\x00" * 8, "hdf5"),
        (b"\x93NUMPY\x01\x00", "npy"),
        (b"1 2 3\n4 5 6\n", "text"),
        (b"\x00\x01\x02\x03", None),  # binary without a magic
    ],
)
def test_detection_precedence(tmp_path, head, expected):
    path = tmp_path / "probe.bin"
    path.write_bytes(head)
    assert detect_format(path) == expected


def test_unknown_content_message_lists_every_native_extension(tmp_path):
    path = tmp_path / "noise.sur"
    path.write_bytes(np.arange(64, dtype=np.uint8).tobytes())
    with pytest.raises(TopographyFileError, match="no supported format") as info:
        read_surface(path)
    for extension in FORMATS_BY_EXTENSION:
        assert extension.lstrip(".") in str(info.value)
