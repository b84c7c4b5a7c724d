"""The memory budget is the smallest of the configured one and the system's ceilings (issue 40,
item 3): a map that fits 16 GiB but not a 6 GiB address-space limit is refused at once, naming
the limit, instead of computing for minutes and failing with a MemoryError."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

from asperity.topo.errors import OverBudgetError
from asperity.topo.io import limits

GIB = 1024**3


def _chunked_map(path, n: int) -> None:
    """An asperity-heightmap HDF5 file declaring n x n heights, one chunk of them stored."""
    with h5py.File(path, "w") as handle:
        data = handle.create_dataset(
            "heights", shape=(n, n), dtype="f8", chunks=(512, 512), compression="gzip"
        )
        data[:512, :512] = np.random.default_rng(0).normal(size=(512, 512)) * 1e-6
        handle.attrs.update(
            {"format": "asperity-heightmap", "version": 1, "units": "m", "periodic": False}
        )
        handle.attrs.update({"dx": 1e-6, "dy": 1e-6})


def _limit_address_space() -> None:  # pragma: no cover - runs in the child
    import resource

    _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (6 * GIB, hard))


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS as Linux enforces it")
def test_a_map_inside_16_gib_is_refused_at_once_under_a_6_gib_ulimit(tmp_path):
    path = tmp_path / "big.h5"
    _chunked_map(path, 11000)  # 121 M points: 14.9 GiB for the pipeline, under 16 GiB
    env = {k: v for k, v in os.environ.items() if k != limits.MEMORY_BUDGET_ENV}
    began = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "asperity", "stats", str(path)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**env, "OPENBLAS_NUM_THREADS": "1"},
        preexec_fn=_limit_address_space,
    )
    assert done.returncode == 2, done.stderr
    assert time.perf_counter() - began < 30
    assert "memory budget of 6 GiB set by the process limit RLIMIT_AS" in done.stderr
    assert "11000 x 11000" in done.stderr and len(done.stderr.splitlines()) == 1


def test_the_smallest_ceiling_refuses_and_is_named(monkeypatch):
    monkeypatch.delenv(limits.MEMORY_BUDGET_ENV, raising=False)
    monkeypatch.setattr(limits, "system_memory_ceilings", dict)
    assert limits.check_map_points("map.h5", "shape", 11000, 11000) == 121_000_000
    cgroup = "the control group's memory limit (/sys/fs/cgroup/job/memory.max)"
    ceilings = {cgroup: 4 * GIB, "the memory available now (MemAvailable)": 9 * GIB}
    monkeypatch.setattr(limits, "system_memory_ceilings", lambda: dict(ceilings))
    assert limits.memory_budget() == (4 * GIB, cgroup)
    with pytest.raises(OverBudgetError) as info:
        limits.check_map_points("map.h5", "shape", 11000, 11000)
    message = str(info.value)
    assert "budget of 4 GiB set by the control group's memory limit" in message
    assert "does not lift" in message
    monkeypatch.setenv(limits.MEMORY_BUDGET_ENV, "2GiB")  # the configured one, when smaller
    assert limits.memory_budget() == (
        2 * GIB,
        f"the configured budget ({limits.MEMORY_BUDGET_ENV})",
    )


def test_cgroup_v2_limit_is_the_smallest_up_the_tree(tmp_path):
    proc = tmp_path / "cgroup"
    proc.write_text("0::/batch/job42\n")
    root = tmp_path / "fs"
    (root / "batch" / "job42").mkdir(parents=True)
    (root / "batch" / "job42" / "memory.max").write_text("max\n")
    (root / "batch" / "memory.max").write_text(f"{6 * GIB}\n")
    (root / "memory.max").write_text(f"{64 * GIB}\n")
    found = limits._cgroup_limits(proc, root)
    assert list(found.values()) == [6 * GIB]
    assert str(root / "batch" / "memory.max") in next(iter(found))


def test_cgroup_v1_limit_and_no_limit(tmp_path):
    proc = tmp_path / "cgroup"
    proc.write_text("5:cpu:/\n4:memory:/slurm/uid_1/job_7\n")
    group = tmp_path / "fs" / "memory" / "slurm" / "uid_1" / "job_7"
    group.mkdir(parents=True)
    (group / "memory.limit_in_bytes").write_text(f"{3 * GIB}\n")
    (tmp_path / "fs" / "memory" / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    assert list(limits._cgroup_limits(proc, tmp_path / "fs").values()) == [3 * GIB]
    (group / "memory.limit_in_bytes").write_text("9223372036854771712\n")  # v1's "no limit"
    assert limits._cgroup_limits(proc, tmp_path / "fs") == {}


def test_available_memory_counts_this_process(tmp_path):
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:  24683664 kB\nMemAvailable:    1048576 kB\n")
    assert limits._meminfo_bytes(meminfo, "MemAvailable") == GIB
    assert limits._meminfo_bytes(meminfo, "SwapFree") is None
