"""The HDF5 result store: typed round trip, units and dimensions, checksums, atomic writes."""

from __future__ import annotations

from dataclasses import dataclass

import h5py
import numpy as np
import pytest

import asperity.pipelines.engine.store as store_module
from asperity.fields import array, checksum, field_specs, scalar, text
from asperity.pipelines.engine.store import (
    ResultLayoutError,
    ResultStore,
    StoredStageError,
    read_result,
)


@dataclass
class Toy:
    """A result with every kind of field the store knows."""

    normal_load: np.ndarray = array("N", ("normal_load",), "normal load")
    real_area: np.ndarray = array("m^2", ("normal_load", "step"), "real contact area")
    converged: np.ndarray = array("1", ("normal_load",), "converged")
    effective_resolution: float = scalar("m", "pixel size")
    count: int = scalar("1", "a count")
    flag: bool = scalar("1", "a flag")
    basis: str = text("a word")
    messages: list[str] = text("lines")
    knobs: dict[str, int] = text("settings")
    extra: np.ndarray | None = array("Pa", ("step",), "optional", optional=True)
    note: float | None = scalar("s", "optional number", optional=True)


def toy(n: int = 4) -> Toy:
    return Toy(
        normal_load=np.linspace(0.5, 3.0, n),
        real_area=np.arange(3.0 * n).reshape(n, 3),
        converged=np.arange(n) % 2 == 0,
        effective_resolution=2.6e-4,
        count=7,
        flag=True,
        basis="bem",
        messages=["one", "two\nlines"],
        knobs={"nodes": 8},
    )


def test_round_trip_keeps_values_types_units_and_dims(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k1", seconds=1.5, root_attrs={"asperity_version": "x"})
    back = store.read("stage", Toy)
    original = toy()
    for spec in field_specs(Toy):
        a, b = getattr(original, spec.name), getattr(back, spec.name)
        if spec.kind == "array" and a is not None:
            np.testing.assert_array_equal(a, b)
            assert a.dtype == b.dtype, spec.name
        else:
            assert a == b and type(a) is type(b), spec.name
    assert back.extra is None and back.note is None
    assert store.stored()["stage"].key == "k1" and store.stored()["stage"].seconds == 1.5
    assert store.root_attrs()["asperity_version"] == "x"
    with h5py.File(store.path, "r") as f:
        group = f["stage"]
        assert group["converged"].dtype == bool  # an HDF5 boolean, not int8
        assert group["real_area"].attrs["units"] == "m^2"
        assert "DIMENSION_LABELS" not in group["real_area"].attrs
        assert group["normal_load"].is_scale and group["step"].is_scale  # step: an index
        assert "extra" not in group and "note" not in group.attrs


def test_xarray_opens_a_stage_with_named_dims_units_and_booleans(tmp_path):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k")
    with xr.open_dataset(store.path, group="stage", engine="h5netcdf") as ds:
        assert ds["real_area"].dims == ("normal_load", "step")
        assert ds["real_area"].attrs["units"] == "m^2"
        assert ds["normal_load"].attrs["units"] == "N"
        assert ds["converged"].dtype == bool
        assert ds.attrs["basis"] == "bem"


def test_a_changed_stored_value_fails_its_checksum(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k")
    with h5py.File(store.path, "a") as f:
        f["stage/real_area"][1, 1] = 1e9
    with pytest.raises(StoredStageError, match="checksum"):
        store.read("stage", Toy)


def test_checksum_sees_every_field():
    base = checksum(toy())
    changed = toy()
    changed.knobs = {"nodes": 16}
    assert checksum(changed) != base
    changed = toy()
    changed.real_area = changed.real_area.astype(np.float32)
    assert checksum(changed) != base  # same values, another dtype


def test_a_group_of_another_declaration_is_refused(tmp_path):
    @dataclass
    class Other:
        missing: np.ndarray = array("m", ("missing",))

    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k")
    with h5py.File(store.path, "r") as f, pytest.raises(StoredStageError, match="missing"):
        read_result(f["stage"], Other)


def test_a_field_added_since_reads_back_as_its_declared_default(tmp_path):
    """A file written before a field with a default was added (0.4's shear stage had no
    ``preload``) reads back with that default; a field without one is still refused."""

    @dataclass
    class Grown(Toy):
        preload: str = text("added later", default_factory=lambda: "pohrt-popov")
        stride: int = scalar("1", "added later", default=0)

    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k")
    with h5py.File(store.path, "r") as f:
        back = read_result(f["stage"], Grown)
    assert back.preload == "pohrt-popov" and back.stride == 0
    np.testing.assert_array_equal(back.real_area, toy().real_area)


def test_write_drops_stale_groups_with_the_new_one(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    store.write("a", toy(), key="k")
    store.write("b", toy(2), key="j")
    store.write("a", toy(3), key="k2", drop=["b"], root_attrs={"config_toml": "new"})
    assert set(store.stored()) == {"a"} and store.stored()["a"].key == "k2"
    assert store.read("a", Toy).normal_load.shape == (3,)
    assert store.root_attrs()["config_toml"] == "new"


def test_crash_during_write_keeps_previous_file(tmp_path, monkeypatch):
    store = ResultStore(tmp_path / "results.h5")
    store.write("a", toy(), key="k")
    before = store.path.read_bytes()

    def explode(group, result):
        group.create_dataset("half", data=np.zeros(3))
        raise RuntimeError("power cut")

    monkeypatch.setattr(store_module, "write_result", explode)
    with pytest.raises(RuntimeError, match="power cut"):
        store.write("b", toy(), key="j")
    assert store.path.read_bytes() == before
    assert list(store.stored()) == ["a"]
    assert [p.name for p in tmp_path.iterdir()] == ["results.h5"]  # no temporary left


def test_unreadable_file_is_moved_aside(tmp_path):
    path = tmp_path / "results.h5"
    path.write_bytes(b"not an HDF5 file at all")
    store = ResultStore(path, set_aside=True)  # as `asperity run` opens it
    with pytest.warns(RuntimeWarning, match="unreadable"):
        assert store.stored() == {}
    assert (tmp_path / "results.h5.unreadable").exists()
    store.write("a", toy(), key="k")
    assert list(store.stored()) == ["a"]


def test_inconsistent_result_refused_as_a_defect(tmp_path):
    bad = toy()
    bad.converged = np.zeros(7, dtype=bool)  # 7 entries along normal_load, which has 4
    store = ResultStore(tmp_path / "results.h5")
    with pytest.raises(ResultLayoutError, match="normal_load"):
        store.write("a", bad, key="k")
    assert not store.path.exists()


def test_declarations_are_checked():
    @dataclass
    class NoUnits:
        value: float

    @dataclass
    class Reserved:
        seconds: float = scalar("s")

    with pytest.raises(TypeError, match="units"):
        field_specs(NoUnits)
    with pytest.raises(TypeError, match="reserved"):
        field_specs(Reserved)


def test_a_full_disk_mid_write_keeps_the_previous_file_and_no_temporary(tmp_path, monkeypatch):
    import errno
    import os

    from asperity.pipelines.engine.outdir import OutputWriteError

    store = ResultStore(tmp_path / "results.h5")
    store.write("a", toy(), key="k", root_attrs={"config_toml": "old"})
    before = store.path.read_bytes()
    real_write, calls = os.write, []

    def write_then_full(fd, data):
        calls.append(len(data))
        if len(calls) > 1:  # the first chunk reached the disk, then it was full
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real_write(fd, data)

    monkeypatch.setattr(store_module, "WRITE_CHUNK", 1000)
    monkeypatch.setattr(store_module.os, "write", write_then_full)
    with pytest.raises(OutputWriteError, match="No space left on device") as info:
        store.write("b", toy(50), key="j", root_attrs={"config_toml": "new"})
    monkeypatch.undo()
    assert len(calls) == 2 and info.value.errno == errno.ENOSPC
    assert "unchanged" in str(info.value) and "\n" not in str(info.value)
    assert store.path.read_bytes() == before
    assert store.root_attrs()["config_toml"] == "old" and list(store.stored()) == ["a"]
    assert [p.name for p in tmp_path.iterdir()] == ["results.h5"]


def test_a_flipped_scalar_attribute_fails_its_checksum(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    store.write("stage", toy(), key="k")
    with h5py.File(store.path, "a") as f:
        f["stage"].attrs["effective_resolution"] = 2.7e-4
    with pytest.raises(StoredStageError, match="checksum"):
        store.read("stage", Toy)


def test_a_damaged_compressed_chunk_is_a_stored_stage_error_not_a_crash(tmp_path):
    store = ResultStore(tmp_path / "results.h5")
    big = toy(2000)  # real_area: 6000 values, stored gzip-compressed
    store.write("stage", big, key="k")
    with h5py.File(store.path, "r") as f:
        chunk = f["stage/real_area"].id.get_chunk_info(0)
    data = bytearray(store.path.read_bytes())
    start = chunk.byte_offset + chunk.size // 3
    data[start : start + 64] = bytes(64)  # zeroed bytes inside the deflate stream
    store.path.write_bytes(bytes(data))
    with pytest.raises(StoredStageError, match="cannot be read back"):
        store.read("stage", Toy)
