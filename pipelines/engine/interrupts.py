"""Ctrl-C by cooperative cancellation: the handler only sets a flag; safe points raise.

Raising KeyboardInterrupt wherever the main thread happens to be is unsafe in a numerical run:
it can land in a finaliser (where the interpreter prints "Exception ignored" and carries on:
the interrupt is lost) or between calls into compiled, multithreaded solvers (the previous
design re-raised it from a watchdog thread, and the BEM stage then crashed with a segfault in
4 of 25 trials). So while an :class:`InterruptGuard` is active, the first SIGINT only records
the request and sets the solvers' flag (:func:`asperity.bem.cancel.request_cancel`); the run
stops at the next safe point, by :class:`asperity.bem.cancel.Cancelled` (a
KeyboardInterrupt):

* in the BEM solver, before every iteration (:func:`asperity.bem.normal.iteration.iterate`);
* in the stage engine, before each stage and after each write of ``results.h5``
  (:func:`checkpoint`), so every finished stage is stored, then the run ends;
* when the guarded block ends (the request is raised then, at the latest).

Inside :func:`interruptible` (plain Python without a safe point: drawing and writing the
report, whose files are written atomically), the first Ctrl-C raises at once.

A second Ctrl-C before the run has stopped raises KeyboardInterrupt at once, wherever the main
thread is (for a computation with no safe point that the user will not wait for). Once the
run is ending (:meth:`InterruptGuard.acknowledge`), further SIGINTs are ignored, so the lock is
released and the status reported undisturbed. A guard made with ``final=True`` (the
``asperity`` command itself) leaves :func:`exit_interrupted` as the handler when it closes:
every output is written by then, and a Ctrl-C before the command ends its process
(:func:`asperity.pipelines.cli.main` exits at once, skipping the interpreter's teardown, where
CPython restores the default SIGINT action) ends it with status 130, never by SIGINT (-2).
Once a final guard has taken a Ctrl-C, failures of finalisers are dropped
(:func:`drop_unraisable`): an interrupt raised inside a library's ``__init__`` (matplotlib
building its mathtext parser, say) leaves a half-built object whose ``__del__`` fails when the
interrupt's traceback is freed, and CPython would print "Exception ignored ... Traceback" after
the command's last line. The process is ending with 130; that noise is no part of its answer.

Guards nest: an inner guard joins the active one. Off the main thread (a job run by a thread of
``batch``) a guard installs nothing (signals reach the main thread only); the flag is
process-wide, so the solvers of those threads stop too.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType

from asperity.bem.cancel import Cancelled, clear_cancel, request_cancel
from asperity.errors import ExitStatus

__all__ = [
    "InterruptGuard",
    "checkpoint",
    "drop_unraisable",
    "exit_interrupted",
    "interruptible",
]

_active: InterruptGuard | None = None


def checkpoint() -> None:
    """A safe point: raise :class:`~asperity.bem.cancel.Cancelled` if a Ctrl-C was requested
    and the run has not yet stopped for it."""
    if _active is not None:
        _active.checkpoint()


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """A block of plain Python with no safe point, where a Ctrl-C may raise at once (drawing
    and writing the report: every file is written atomically). A request made before the block
    stops the run at its start."""
    guard = _active
    if guard is None:
        yield
        return
    guard.checkpoint()
    guard.immediate = True
    try:
        yield
    finally:
        guard.immediate = False


def drop_unraisable(unraisable: object) -> None:
    """A :data:`sys.unraisablehook` that prints nothing: installed by a final guard once a
    Ctrl-C has come (module docstring), for exceptions in finalisers of objects that the
    interrupt left half-built."""


def exit_interrupted(signum: int = signal.SIGINT, frame: FrameType | None = None) -> None:
    """SIGINT handler of a command that has finished its work: flush, exit 130 at once."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError, AttributeError):  # closed or gone: nothing to flush
            pass
    os._exit(ExitStatus.INTERRUPTED)


class InterruptGuard:
    """SIGINT as a cancellation request while active (a context manager; module docstring).

    Parameters
    ----------
    final : bool
        Leave SIGINT ignored when the guard closes (the process is about to exit), instead of
        restoring the previous handler.

    Attributes
    ----------
    requested : bool
        A SIGINT arrived while the guard was active.
    acknowledged : bool
        The run has stopped for it (it is ending).
    """

    def __init__(self, *, final: bool = False) -> None:
        self.final = final
        self.requested = False
        self.acknowledged = False
        self.immediate = False
        self._previous: Callable[[int, FrameType | None], object] | int | None = None
        self._installed = False
        self._guard: InterruptGuard = self

    def __enter__(self) -> InterruptGuard:
        global _active
        if _active is not None:
            self._guard = _active
            return _active
        if threading.current_thread() is not threading.main_thread():
            return self
        clear_cancel()
        self._previous = signal.signal(signal.SIGINT, self._handle)
        self._installed, _active = True, self
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *details: object) -> None:
        if exc_type is not None:
            self._guard.acknowledge()  # an exception (KeyboardInterrupt or other) ends the run
        if not self._installed:
            return
        pending = self.requested and not self.acknowledged
        self.close()
        if pending:  # no safe point was reached: the run still ends as interrupted
            raise KeyboardInterrupt

    def close(self) -> None:
        """Acknowledge, withdraw the solvers' flag and give SIGINT back (to
        :func:`exit_interrupted` when ``final``); idempotent."""
        global _active
        self.acknowledge()
        if not self._installed:
            return
        signal.signal(signal.SIGINT, exit_interrupted if self.final else self._previous)
        clear_cancel()
        self._installed, _active = False, None

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        """The SIGINT handler: the first one requests (and raises inside
        :func:`interruptible`), a second one raises at once."""
        if self.acknowledged:
            return
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True
        if self.final:  # the process ends with 130: a half-built object's failing __del__
            sys.unraisablehook = drop_unraisable  # prints nothing (module docstring)
        request_cancel()
        if self.immediate:  # inside :func:`interruptible`
            raise Cancelled("interrupted (Ctrl-C)")

    def acknowledge(self) -> None:
        """The run has stopped for the interrupt (or ended otherwise): ignore further ones."""
        self.acknowledged = True

    def checkpoint(self) -> None:
        """Raise :class:`~asperity.bem.cancel.Cancelled` if a Ctrl-C was requested and the run
        has not yet stopped for it."""
        if self.requested and not self.acknowledged:
            raise Cancelled("interrupted (Ctrl-C) at a safe point")
