"""The HDF5 result store: round trip, units and dimension scales, atomic writes."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import asperity.pipelines.store as store_module
from asperity.pipelines.store import ResultStore, StageRecord, Variable


def _record(n: int = 4) -> StageRecord:
    return StageRecord(
        coords={
            "normal_load": Variable(np.linspace(0.5, 3.0, n), "N", ("normal_load",)),
            "step": Variable(np.arange(3), "1", ("step",)),
        },
        variables={
            "real_area": Variable(
                np.arange(3.0 * n).reshape(n, 3),
                "m^2",
                ("normal_load", "step"),
                "real contact area",
            ),
            "converged": Variable(np.ones(n, dtype=bool), "1", ("normal_load",)),
        },
        attrs={"effective_resolution": 2.6e-4, "basis": "bem", "nothing": None, "flag": True},
    )


def test_round_trip_with_units_and_dimensions(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", _record(), key="k1", seconds=1.5, root_attrs={"asperity_version": "x"})
    back = store.read_stage("stage")
    np.testing.assert_array_equal(back.variables["real_area"].data, np.arange(12.0).reshape(4, 3))
    assert back.variables["real_area"].dims == ("normal_load", "step")
    assert back.variables["real_area"].units == "m^2"
    assert back.variables["converged"].data.dtype == np.int8
    assert back.attrs["basis"] == "bem" and back.attrs["nothing"] == "none"
    assert back.attrs["seconds"] == 1.5 and back.attrs["stage_key"] == "k1"
    assert store.root_attrs()["asperity_version"] == "x"
    with h5py.File(store.path, "r") as f:
        ds = f["stage/real_area"]
        assert [dim.label or h5py.h5ds.get_scale_name(dim[0].id).decode() for dim in ds.dims] == [
            "normal_load",
            "step",
        ]
        assert f["stage/normal_load"].is_scale
        assert f["stage/normal_load"].attrs["units"] == "N"


def test_keys_decide_what_is_stored(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    assert store.stage_key("a") is None and not store.has_stage("a", "k")
    store.write("a", _record(), key="k")
    store.write("b", _record(2), key="j")
    assert store.has_stage("a", "k") and not store.has_stage("a", "other")
    assert set(store.stages()) == {"a", "b"}
    store.write("a", _record(3), key="k2")  # replaced, b kept
    assert store.stage_key("a") == "k2" and store.has_stage("b", "j")
    assert store.read_stage("a").coords["normal_load"].data.shape == (3,)


def test_crash_during_write_keeps_previous_file(tmp_path, monkeypatch):
    store = ResultStore(tmp_path / "results.h5")
    store.write("a", _record(), key="k")
    before = store.path.read_bytes()

    def explode(group, record):
        group.create_dataset("half", data=np.zeros(3))
        raise RuntimeError("power cut")

    monkeypatch.setattr(store_module, "write_record", explode)
    with pytest.raises(RuntimeError, match="power cut"):
        store.write("b", _record(), key="j")
    assert store.path.read_bytes() == before
    assert store.stages() == ["a"]
    assert [p.name for p in tmp_path.iterdir()] == ["results.h5"]  # no temporary left


def test_unreadable_file_is_moved_aside(tmp_path):
    path = tmp_path / "results.h5"
    path.write_bytes(b"not an HDF5 file at all")
    store = ResultStore(path)
    with pytest.warns(RuntimeWarning, match="unreadable"):
        assert store.stages() == []
    assert (tmp_path / "results.h5.unreadable").exists()
    store.write("a", _record(), key="k")
    assert store.stages() == ["a"]


def test_inconsistent_record_refused(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    bad = _record()
    bad.variables["oops"] = Variable(np.zeros(7), "m", ("normal_load",))
    with pytest.raises(ValueError, match="oops"):
        store.write("a", bad, key="k")
    assert not store.path.exists()


def test_xarray_opens_a_stage_group(tmp_path):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", _record(), key="k")
    with xr.open_dataset(store.path, group="stage", engine="h5netcdf") as ds:
        assert ds["real_area"].dims == ("normal_load", "step")
        assert ds["real_area"].attrs["units"] == "m^2"
        assert ds["normal_load"].attrs["units"] == "N"
