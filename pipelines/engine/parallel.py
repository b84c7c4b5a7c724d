"""Where the sweeps run: in this process, in worker processes, or on a dask.distributed cluster.

Every stage maps a picklable top-level function over independent items (loads, resolutions,
BEM branches) through an :class:`Executor`-like object; this module makes one.

* ``workers == 1``: :class:`SerialExecutor`, plain calls in this process.
* ``workers > 1``: a :class:`WorkerPool` (a :class:`concurrent.futures.ProcessPoolExecutor`)
  with the ``spawn`` start method. Its workers end with this process, even when it is killed
  (:func:`start_worker`), and with the pool when its ``with`` block ends by an exception. Its
  initializer sets ``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``,
  ``MKL_NUM_THREADS``, ``NUMBA_NUM_THREADS`` (and pyFFTW's OpenMP threads through
  ``OMP_NUM_THREADS``) to ``threads_per_worker`` before numpy, numba or the FFT libraries are
  imported in the worker, so N workers do not start N x cores threads and fight for the cores.
* ``scheduler`` given: a dask.distributed :class:`Client` connected to that address (the
  optional ``dask`` extra); its ``get_executor()`` offers the same ``submit``/``map`` interface,
  and the same thread caps are applied on each worker with ``client.run``.

This module imports only the standard library at the top, so that the worker initializer runs
before any numerical library is loaded.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING, ParamSpec, TypeAlias, TypeVar

from asperity.errors import InputError

if TYPE_CHECKING:  # optional: the dask extra
    import distributed

P = ParamSpec("P")
T = TypeVar("T")
#: Where the sweeps run: a dask.distributed scheduler address, a client, or None (this machine).
Scheduler: TypeAlias = "str | distributed.Client | None"

#: Environment variables that cap the threads of the numerical libraries.
THREAD_ENV_VARS: tuple[str, ...] = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "NUMBA_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMEXPR_NUM_THREADS",
)


#: Set by :func:`cap_threads`: the FFT threads a BEM solve in this worker may use.
WORKER_THREADS_VAR = "ASPERITY_WORKER_THREADS"


def cap_threads(threads: int) -> dict[str, str]:
    """Cap the numerical libraries of this process at ``threads`` threads.

    Sets the environment variables (effective for libraries imported afterwards). When numba
    is already imported (a spawned worker re-imports the parent's main module first), its
    configuration is reloaded if its thread pool has not started yet, and its active thread
    count is lowered; once numba's pool runs, ``NUMBA_NUM_THREADS`` is left at the pool's size
    (numba refuses to compile after it changes).

    Returns
    -------
    dict
        The variables set.
    """
    import sys

    threads = max(int(threads), 1)
    values = {name: str(threads) for name in THREAD_ENV_VARS}
    values[WORKER_THREADS_VAR] = str(threads)
    numba = sys.modules.get("numba")
    launched = False
    if numba is not None:
        try:
            from numba.np.ufunc import parallel as numba_parallel

            launched = bool(numba_parallel._is_initialized)
        except (ImportError, AttributeError):
            launched = True
    if launched:
        values.pop("NUMBA_NUM_THREADS")
    os.environ.update(values)
    if numba is not None:
        if not launched:
            numba.config.reload_config()
        try:
            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        except (ValueError, AttributeError):
            pass
    return values


def worker_threads() -> int | None:
    """The per-worker thread cap set by :func:`cap_threads`, or None outside a capped worker."""
    value = os.environ.get(WORKER_THREADS_VAR)
    return int(value) if value else None


def worker_thread_settings() -> dict[str, str | None]:
    """The thread-cap environment of the calling process (used by tests and the report)."""
    return {name: os.environ.get(name) for name in THREAD_ENV_VARS}


class SerialExecutor(concurrent.futures.Executor):
    """An executor that runs each call immediately in this process."""

    def submit(
        self, fn: Callable[P, T], /, *args: P.args, **kwargs: P.kwargs
    ) -> concurrent.futures.Future[T]:
        future: concurrent.futures.Future[T] = concurrent.futures.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # delivered through the future, like a pool would
            future.set_exception(exc)
        return future

    def map(
        self,
        fn: Callable[..., T],
        *iterables: Iterable,
        timeout: float | None = None,
        chunksize: int = 1,
    ) -> Iterator[T]:
        return map(fn, *iterables)


class DaskExecutor(concurrent.futures.Executor):
    """The executor of a dask.distributed client, owning the client (closed on shutdown)."""

    def __init__(self, client: distributed.Client):
        self.client = client
        self._executor = client.get_executor()

    def submit(
        self, fn: Callable[P, T], /, *args: P.args, **kwargs: P.kwargs
    ) -> concurrent.futures.Future[T]:
        return self._executor.submit(fn, *args, **kwargs)

    def map(
        self,
        fn: Callable[..., T],
        *iterables: Iterable,
        timeout: float | None = None,
        chunksize: int = 1,
    ) -> Iterator[T]:
        return self._executor.map(fn, *iterables, timeout=timeout)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._executor.shutdown(wait=wait)
        self.client.close()


def make_executor(
    workers: int = 1, *, scheduler: Scheduler = None, threads_per_worker: int = 1
) -> concurrent.futures.Executor:
    """An executor for the sweeps.

    Parameters
    ----------
    workers : int
        Worker processes on this machine (1: run in this process). Ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        Address of a dask.distributed scheduler (``tcp://host:8786``) or a client object.
    threads_per_worker : int
        Threads each worker's FFT / numba / BLAS may use.

    Returns
    -------
    concurrent.futures.Executor
        Use as a context manager (``with make_executor(2) as ex: ex.map(...)``).
    """
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError as exc:  # pragma: no cover - depends on the installed extras
            raise InputError(
                "--scheduler: expected dask.distributed to be installed, got an ImportError "
                "(pip install 'asperity[dask]')"
            ) from exc
        client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
        # Workers in other processes get the caps; in-process workers (a LocalCluster with
        # processes=False) share this process, whose settings are left alone.
        pids = client.run(os.getpid)
        remote = [address for address, pid in pids.items() if pid != os.getpid()]
        if remote:
            client.run(cap_threads, threads_per_worker, workers=remote)
        if isinstance(scheduler, Client):  # caller owns the client: do not close it
            return _BorrowedDaskExecutor(client)
        return DaskExecutor(client)
    if workers < 1:
        raise InputError(f"workers: expected an integer >= 1, got {workers}")
    if workers == 1:
        return SerialExecutor()
    return WorkerPool(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=start_worker,
        initargs=(threads_per_worker, os.getpid()),
    )


#: Linux ``prctl`` option: the signal a process gets when its parent ends.
_PR_SET_PDEATHSIG = 1
#: Seconds between checks of the parent where ``prctl`` is not available.
PARENT_POLL_SECONDS = 0.5


def start_worker(threads: int, parent_pid: int) -> None:
    """Initializer of a worker process: thread caps, and an end that follows the parent's.

    On Linux the kernel sends the worker SIGKILL when its parent ends (``PR_SET_PDEATHSIG``,
    also after ``kill -9`` of the parent); elsewhere a daemon thread checks every
    :data:`PARENT_POLL_SECONDS` whether the parent still runs. A worker whose parent ended
    before this ran exits at once. (Linux counts the *thread* that started the worker as its
    parent: the pool's workers are started by the thread that submits to it, which must outlive
    the pool, as the job's main thread does.)
    """
    cap_threads(threads)
    if not _exit_with_parent_linux():
        threading.Thread(target=_watch_parent, args=(parent_pid,), daemon=True).start()
    if os.getppid() != parent_pid:  # the parent ended before the watch was set up
        os._exit(1)


def _exit_with_parent_linux() -> bool:
    """Ask Linux to SIGKILL this process when its parent ends; False where unavailable."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes
    import signal

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent_pid: int) -> None:
    while os.getppid() == parent_pid:
        time.sleep(PARENT_POLL_SECONDS)
    os._exit(1)


class WorkerPool(concurrent.futures.ProcessPoolExecutor):
    """A process pool whose workers end with it.

    Leaving its ``with`` block by an exception (Ctrl-C, a failed stage) cancels the queued
    calls and terminates the workers at once, instead of waiting for the running calls; the
    workers also end when this process is killed (:func:`start_worker`).
    """

    def __exit__(self, exc_type, exc, tb) -> bool | None:  # noqa: ANN001
        if exc_type is None:
            return super().__exit__(exc_type, exc, tb)
        self.terminate_workers()
        return False

    def terminate_workers(self) -> None:
        """Cancel what is queued, SIGTERM every worker, and reap them."""
        processes = list((getattr(self, "_processes", None) or {}).values())
        self.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            if process.is_alive():
                process.terminate()
        for process in processes:
            process.join(timeout=5)


class _BorrowedDaskExecutor(DaskExecutor):
    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._executor.shutdown(wait=wait)


def share(executor: concurrent.futures.Executor | None, value: T) -> T | distributed.Future:
    """``value`` as an argument that reaches each worker once.

    On dask.distributed it is scattered to every worker (``broadcast=True``) and the returned
    future, passed as an argument, resolves to the worker's copy, however many calls use it.
    Elsewhere ``value`` itself (a process pool pickles it with each call: the stages send one
    call per worker, e.g. one BEM load chain each).
    """
    if isinstance(executor, DaskExecutor):
        return executor.client.scatter([value], broadcast=True)[0]
    return value


def run_map(
    fn: Callable[..., T],
    jobs: list[tuple],
    executor: concurrent.futures.Executor | None = None,
    *,
    desc: str = "",
    progress: bool = False,
) -> list[T]:
    """``[fn(*job) for job in jobs]``, through ``executor`` when given, with a progress bar.

    Parameters
    ----------
    fn : callable
        Picklable top-level function (it may run in another process).
    jobs : list of tuple
        Positional arguments of each call.
    executor : Executor, optional
        Runs the calls (in order of submission; results are returned in the order of ``jobs``).
    desc : str
        Label of the tqdm bar.
    progress : bool
        Show a tqdm bar (on stderr).
    """
    from tqdm import tqdm

    iterator: Iterator[T]
    if executor is None or isinstance(executor, SerialExecutor):
        iterator = (fn(*job) for job in jobs)
    else:
        iterator = executor.map(fn, *zip(*jobs, strict=True)) if jobs else iter(())
    bar = tqdm(iterator, total=len(jobs), desc=desc, disable=not progress, leave=False, unit="run")
    return list(bar)
