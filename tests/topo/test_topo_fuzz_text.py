"""Hypothesis fuzzing of the text reader: any text ends in a typed error or a valid map, and
numbers written in the stated format are read back exactly whatever the separator."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity import topo
from asperity.topo.errors import TopographyFileError
from asperity.topo.io.limits import MAX_ABS_HEIGHT_M

ALPHABET = "0123456789.,;-+eE_ \t\nnaif#x"
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))


@SETTINGS
@given(text=st.text(alphabet=ALPHABET, max_size=200), suffix=st.sampled_from([".txt", ".xyz"]))
def test_any_text_is_a_typed_error_or_a_valid_map(tmp_path_factory, text, suffix):
    path = tmp_path_factory.mktemp("text") / f"fuzz{suffix}"
    path.write_text(text)
    try:
        surface = topo.read_surface(path, pixel_size=1e-6 if suffix == ".txt" else None, unit="m")
    except TopographyFileError as exc:
        assert str(path) in str(exc)
        return
    heights = np.asarray(surface.heights)
    assert not np.isinf(heights).any()
    assert np.nanmax(np.abs(heights), initial=0.0) <= MAX_ABS_HEIGHT_M
    assert 0 < surface.dx < np.inf


finite = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False, allow_subnormal=False)


@SETTINGS
@given(
    values=st.lists(st.lists(finite, min_size=2, max_size=2), min_size=2, max_size=5),
    separator=st.sampled_from([" ", "\t", ",", ", ", ";", " ; "]),
    trailing=st.booleans(),
)
def test_stated_format_is_read_exactly(tmp_path_factory, values, separator, trailing):
    end = separator.strip() if trailing and separator.strip() else ""
    text = "\n".join(separator.join(repr(v) for v in row) + end for row in values)
    path = tmp_path_factory.mktemp("text") / "exact.txt"
    path.write_text("# m\n" + text + "\n")
    surface = topo.read_surface(path, pixel_size=1e-6, unit="m")
    np.testing.assert_array_equal(surface.heights, np.array(values))
