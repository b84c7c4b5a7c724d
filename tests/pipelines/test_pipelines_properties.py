"""Property tests: the TOML writer and the HDF5 store give back what they were given."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from asperity.fields import array
from asperity.pipelines.config import dump_toml
from asperity.pipelines.engine.store import ResultStore

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

keys = st.from_regex(r"[a-z][a-z0-9_]{0,8}", fullmatch=True)
scalars = st.one_of(
    st.booleans(),
    st.integers(-(10**12), 10**12),
    st.floats(allow_nan=False, allow_infinity=False),
    st.text(st.characters(blacklist_categories=("Cs",)), max_size=12),
)
values = st.one_of(scalars, st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=4))
tables = st.recursive(
    st.dictionaries(keys, values, max_size=4),
    lambda inner: st.dictionaries(keys, st.one_of(values, inner), max_size=3),
    max_leaves=12,
)


@given(tables)
def test_dump_toml_round_trips(data):
    assert tomllib.loads(dump_toml(data)) == data


@dataclass
class _Values:
    values: np.ndarray = array("Pa", ("d0", "d1", "d2"))


@settings(max_examples=25, deadline=None)
@given(
    hnp.arrays(
        dtype=st.sampled_from([np.float64, np.int64, np.int8, np.bool_]),
        shape=hnp.array_shapes(min_dims=3, max_dims=3, min_side=0, max_side=5),
    )
)
def test_store_round_trips_any_array(array_values):
    with tempfile.TemporaryDirectory() as tmp:
        store = ResultStore(Path(tmp) / "r.h5")
        store.write("stage", _Values(array_values), key="k")
        back = store.read("stage", _Values).values
    np.testing.assert_array_equal(back, array_values)
    assert back.dtype == array_values.dtype
