"""Sweeps in worker processes and on dask.distributed, with thread caps per worker."""

from __future__ import annotations

import math
import os

import pytest

from asperity.errors import InputError
from asperity.pipelines.engine.parallel import (
    SerialExecutor,
    make_executor,
    run_map,
    worker_thread_settings,
)


def _worker_report(x: float) -> tuple[float, int, dict]:
    """Runs in the worker: a result, the worker's pid, its thread caps."""
    import numba  # imported after the initializer set the caps

    settings = worker_thread_settings()
    settings["numba_threads"] = numba.get_num_threads()
    return math.sqrt(x), os.getpid(), settings


def test_serial_executor_is_plain_calls():
    with make_executor(1) as ex:
        assert isinstance(ex, SerialExecutor)
        out = run_map(_worker_report, [(4.0,), (9.0,)], ex)
    assert [o[0] for o in out] == [2.0, 3.0]
    assert {o[1] for o in out} == {os.getpid()}
    with pytest.raises(InputError, match="workers"):
        make_executor(0)


@pytest.mark.slow
def test_process_workers_cap_threads():
    with make_executor(2, threads_per_worker=1) as ex:
        out = run_map(_worker_report, [(float(i),) for i in range(6)], ex)
    assert [o[0] for o in out] == [math.sqrt(i) for i in range(6)]  # order kept
    assert os.getpid() not in {o[1] for o in out}
    for _, _, settings in out:
        assert settings["OMP_NUM_THREADS"] == "1"
        assert settings["OPENBLAS_NUM_THREADS"] == "1"
        assert settings["NUMBA_NUM_THREADS"] == "1"
        assert settings["numba_threads"] == 1


@pytest.mark.slow
def test_dask_local_cluster_runs_the_same_map():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        with make_executor(scheduler=cluster.scheduler_address) as ex:
            out = run_map(_worker_report, [(float(i),) for i in range(4)], ex)
    assert [o[0] for o in out] == [math.sqrt(i) for i in range(4)]
    assert os.getpid() not in {o[1] for o in out}
    for _, _, settings in out:
        assert settings["OMP_NUM_THREADS"] == "1"


def _bem_on(executor):
    import numpy as np

    from asperity import topo
    from asperity.pipelines.config import BemConfig
    from asperity.pipelines.stages.bem import bem_reference

    surface = topo.synthetic.paper_like(n=64, pixel_size=50e-6, seed=3)
    ref = bem_reference(
        surface,
        2.133e6,
        0.04,
        [0.5, 1.0, 1.5, 2.0, 3.0],
        40e-6,
        BemConfig(max_stride=2),
        executor=executor,
    )
    return np.concatenate([ref.contact_fraction, ref.contact_fraction_adhesive]), ref


@pytest.mark.slow
def test_bem_load_chains_on_two_workers_equal_the_serial_run():
    import numpy as np

    serial, ref = _bem_on(None)
    with make_executor(2, threads_per_worker=1) as ex:
        parallel, ref2 = _bem_on(ex)
    np.testing.assert_array_equal(parallel, serial)
    np.testing.assert_array_equal(ref2.iterations, ref.iterations)
    assert ref2.branch == ref.branch


@pytest.mark.slow
def test_bem_load_chains_on_dask_equal_the_serial_run():
    import numpy as np

    distributed = pytest.importorskip("distributed")
    serial, _ = _bem_on(None)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        with make_executor(scheduler=cluster.scheduler_address) as ex:
            parallel, _ = _bem_on(ex)  # the map is scattered to the workers once
    np.testing.assert_array_equal(parallel, serial)
