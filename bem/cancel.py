"""Cooperative cancellation of the solver loops: one flag, checked once per iteration.

A Ctrl-C must stop a long solve without raising an exception into the middle of compiled or
multithreaded code (FFTW plans, numba kernels). So the program that owns the signal (the
``asperity`` command, :mod:`asperity.pipelines.engine.interrupts`) only calls
:func:`request_cancel` from its SIGINT handler, and the loops call :func:`check_cancelled` at
points where stopping is safe: :func:`asperity.bem.normal.iteration.iterate` once per iteration (a
few milliseconds apart), the stage engine between stages. :func:`check_cancelled` then
raises :class:`Cancelled`, a :class:`KeyboardInterrupt`, so every caller handles it as it
handles Ctrl-C.

This flag is the module's only state, and it is process-wide on purpose: a signal handler has
no other way to reach a loop running in the main thread or in a thread of ``batch``. Nothing
in the library sets it by itself; a library user who never calls :func:`request_cancel` never
sees :class:`Cancelled`.
"""

from __future__ import annotations

import threading

__all__ = ["Cancelled", "cancel_requested", "check_cancelled", "clear_cancel", "request_cancel"]

_requested = threading.Event()


class Cancelled(KeyboardInterrupt):
    """Raised at a safe point after :func:`request_cancel` (a Ctrl-C)."""


def request_cancel() -> None:
    """Ask every solver loop of this process to stop at its next safe point."""
    _requested.set()


def clear_cancel() -> None:
    """Withdraw the request (the program that asked has ended its run)."""
    _requested.clear()


def cancel_requested() -> bool:
    """Whether a cancellation was requested and not cleared."""
    return _requested.is_set()


def check_cancelled() -> None:
    """A safe point: raise :class:`Cancelled` if a cancellation was requested.

    Raises
    ------
    Cancelled
        :func:`request_cancel` was called since the last :func:`clear_cancel`.
    """
    if _requested.is_set():
        raise Cancelled("cancelled at a safe point (Ctrl-C)")
