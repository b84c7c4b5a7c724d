"""Ctrl-C that is never lost: a SIGINT ends the run with KeyboardInterrupt, whatever it hits.

Python raises KeyboardInterrupt wherever the main thread happens to be when SIGINT arrives. When
that is a ``__del__`` method or a weakref callback (a ``WeakValueDictionary`` of numba or h5py
dropping an entry during garbage collection), the interpreter cannot propagate it: it prints
"Exception ignored in: ... KeyboardInterrupt" and carries on, and the job ran to its end with
exit status 0. A library's ``except BaseException`` or ``finally`` can swallow it the same way.

Design (:class:`InterruptGuard`): while a guard is active, SIGINT runs its handler, which
records the request and raises KeyboardInterrupt at once (an interrupt is as prompt as before).
Until the request has been seen, i.e. until a KeyboardInterrupt leaves the guarded block or
the code that catches it calls :meth:`InterruptGuard.acknowledge`, the request is raised again:

* by a watchdog thread, every :data:`RETRY_SECONDS`, through :func:`_thread.interrupt_main`
  (the same handler, so a re-raise swallowed in another finaliser is raised once more);
* at each safe point, :func:`checkpoint`: after every write of ``results.h5`` (the finished
  stages are kept, then the run ends; ``pipelines.job.InterruptibleRunner``);
* when the guarded block ends normally (the request is raised then, at the latest).

A KeyboardInterrupt that a finaliser could not raise is not printed as "Exception ignored in"
with its traceback (the guard's :func:`sys.unraisablehook` drops those: the request is raised
again); every other unraisable exception still goes to the previous hook.

Once acknowledged, further SIGINTs are ignored while the run ends (finished stages are kept,
the lock is released). :meth:`InterruptGuard.close` ends a guard whose exit a late re-raise cut
short, and :func:`forget_escaped_interrupts` keeps ``python -m asperity``'s status 130 (CPython
would otherwise end the process by SIGINT after a Ctrl-C seen inside a library's ``exec``).

Guards nest: an inner guard joins the active one. Off the main thread
(a job run by a thread of ``batch``) a guard does nothing: signals reach the main thread only.
"""

from __future__ import annotations

import _thread
import signal
import sys
import threading
from collections.abc import Callable
from types import FrameType

__all__ = [
    "RETRY_SECONDS",
    "InterruptGuard",
    "active_guard",
    "checkpoint",
    "forget_escaped_interrupts",
]

#: Seconds between re-raises of an interrupt that was not seen (swallowed in a finaliser).
RETRY_SECONDS = 0.5

_active: InterruptGuard | None = None


def active_guard() -> InterruptGuard | None:
    """The guard installed in this process, or None."""
    return _active


def checkpoint() -> None:
    """A safe point: raise KeyboardInterrupt if a Ctrl-C was requested and not yet seen."""
    if _active is not None:
        _active.checkpoint()


def forget_escaped_interrupts() -> None:
    """Clear CPython's record of a KeyboardInterrupt that escaped an ``exec`` of source text.

    CPython notes, process-wide, any KeyboardInterrupt that leaves code run from a source string
    (``exec`` of a string: dataclass and namedtuple creation during a lazy import, numba's
    generated wrappers), even when the caller catches it later. Under ``python -m`` the note
    outlives ``sys.exit``: the process then kills itself with SIGINT after finalising, and its
    parent sees -2 in place of the status the run chose (130, 0, ...). Running an empty source
    string resets the note. ``python -m asperity`` calls this just before it exits; the
    ``asperity`` script does not need it (a script's ``sys.exit`` ends the process at once).
    """
    exec("", {})  # noqa: S102 (an empty, constant source: the reset itself)


class InterruptGuard:
    """SIGINT handling that cannot lose an interrupt (a context manager; module docstring).

    Attributes
    ----------
    requested : bool
        A SIGINT arrived while the guard was active.
    acknowledged : bool
        The resulting KeyboardInterrupt was seen by the run (it is ending).
    """

    def __init__(self) -> None:
        self.requested = False
        self.acknowledged = False
        self._previous: Callable[[int, FrameType | None], object] | int | None = None
        self._previous_hook: Callable[[sys.UnraisableHookArgs], object] = sys.unraisablehook
        self._installed = False
        self._lock = threading.RLock()  # re-entered when a SIGINT interrupts the handler
        self._guard: InterruptGuard = self
        self._stopped = threading.Event()
        self._watchdog: threading.Thread | None = None

    def __enter__(self) -> InterruptGuard:
        global _active
        if _active is not None:
            self._guard = _active
            return _active
        if threading.current_thread() is not threading.main_thread():
            return self
        self._previous = signal.signal(signal.SIGINT, self._handle)
        self._previous_hook, sys.unraisablehook = sys.unraisablehook, self._unraisable
        self._installed = True
        _active = self
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *details: object) -> None:
        if exc_type is not None:
            self._guard.acknowledge()  # an exception (KeyboardInterrupt or other) ends the run
        if not self._installed:
            return
        pending = self.requested and not self.acknowledged
        self.close()
        if pending:  # every raise was swallowed: the run must still end as interrupted
            raise KeyboardInterrupt

    def close(self) -> None:
        """Acknowledge, stop the watchdog and give SIGINT back; idempotent.

        A re-raise that lands while the guard is being closed (the watchdog fired just before
        the acknowledgement) is absorbed and the closing done again, so no KeyboardInterrupt
        is left pending once the run has reported itself interrupted. Callers that catch the
        KeyboardInterrupt call this first (a re-raise can cut ``__exit__`` short).
        """
        while True:
            try:
                self.acknowledge()
                self._uninstall()
                return
            except KeyboardInterrupt:
                continue

    def _uninstall(self) -> None:
        """Join the watchdog, then restore the previous SIGINT handler and unraisable hook."""
        global _active
        if not self._installed:
            return
        if self._watchdog is not None:
            self._watchdog.join()
        signal.signal(signal.SIGINT, self._previous)  # runs a pending re-raise first (a no-op)
        sys.unraisablehook = self._previous_hook
        self._installed, _active = False, None

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        """The SIGINT handler: record, and raise unless the run is already ending."""
        self.requested = True
        if self.acknowledged:
            return
        self._start_watchdog()
        raise KeyboardInterrupt

    def _unraisable(self, unraisable: sys.UnraisableHookArgs) -> None:
        """Drop a KeyboardInterrupt a finaliser swallowed (raised again); pass the rest on."""
        if isinstance(unraisable.exc_value, KeyboardInterrupt) and self.requested:
            return
        self._previous_hook(unraisable)

    def _start_watchdog(self) -> None:
        with self._lock:
            if self._watchdog is None:
                self._watchdog = threading.Thread(
                    target=self._raise_until_seen, name="asperity-interrupt", daemon=True
                )
                self._watchdog.start()

    def _raise_until_seen(self) -> None:
        while not self._stopped.wait(RETRY_SECONDS):
            with self._lock:
                if self.acknowledged:
                    return
                _thread.interrupt_main(signal.SIGINT)

    def acknowledge(self) -> None:
        """The KeyboardInterrupt was seen: stop raising it again (the run is ending)."""
        self.acknowledged = True
        with self._lock:
            self.acknowledged = True
            self._stopped.set()

    def checkpoint(self) -> None:
        """Raise KeyboardInterrupt if a Ctrl-C was requested and not yet seen."""
        if self.requested and not self.acknowledged:
            raise KeyboardInterrupt
