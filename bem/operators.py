"""Cached FFT operators of a solve: the influence kernel K and the stiffness preconditioner.

Planning FFTW and building a kernel cost more than a small solve, so operators are kept per
thread (a :class:`~asperity.bem.fft_backend.Convolution` owns work buffers and must never serve
two solves at once).
"""

from __future__ import annotations

import threading
from collections import OrderedDict

import numpy as np

from asperity.bem.fft_backend import Convolution
from asperity.bem.influence import influence_multiplier

__all__ = ["influence_operator", "stiffness_preconditioner"]

# A Convolution owns work buffers (its spectrum and scratch arrays), so it must never be used by
# two solves at once: the cache is per thread. Solves in different threads of one process then
# run concurrently and correctly (each thread plans its own operators; FFTW planning itself is
# serialised inside fft_backend).
_THREAD_STATE = threading.local()
_MAX_OPERATORS = 4


def _operator_cache() -> OrderedDict:
    """This thread's operator cache (least recently used first)."""
    cache = getattr(_THREAD_STATE, "operators", None)
    if cache is None:
        cache = _THREAD_STATE.operators = OrderedDict()
    return cache


def influence_operator(
    shape: tuple[int, int],
    dx: float,
    dy: float,
    e_star: float,
    kernel: str,
    periodic: bool,
    fft_backend: str,
    threads: int | None,
    precision: str = "double",
) -> Convolution:
    """The convolution u = K * p (m from Pa) for heights of ``shape`` with pixel sizes dx, dy
    (m) and modulus E* (Pa): periodic, or zero-padded to the doubled grid; cached per thread.
    ``precision``: "double" or "single" transforms (:class:`Convolution`)."""
    key = (
        shape,
        float(dx),
        float(dy),
        float(e_star),
        kernel,
        bool(periodic),
        fft_backend,
        threads,
        precision,
    )
    cache = _operator_cache()
    op = cache.get(key)
    if op is None:
        mult, grid = influence_multiplier(shape, dx, dy, e_star, kernel=kernel, periodic=periodic)
        op = Convolution(mult, grid, backend=fft_backend, threads=threads, precision=precision)
        cache[key] = op
        while len(cache) > _MAX_OPERATORS:
            cache.popitem(last=False)
    else:
        cache.move_to_end(key)
    return op


def stiffness_preconditioner(op: Convolution, dx: float, dy: float, e_star: float) -> Convolution:
    """The stiffness E* |q| / 2 (Pa/m, the inverse of the point-force kernel) on the FFT grid
    of ``op``, q = 0 set to its smallest non-zero value; same backend, threads and precision
    as ``op``."""
    key = (
        "precondition",
        op.shape,
        float(dx),
        float(dy),
        float(e_star),
        op.backend,
        op.threads,
        op.precision,
    )
    cache = _operator_cache()
    pre = cache.get(key)
    if pre is None:
        gx, gy = op.shape
        qx = 2.0 * np.pi * np.fft.fftfreq(gx, d=dx)
        qy = 2.0 * np.pi * np.fft.rfftfreq(gy, d=dy)
        q = np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
        q[0, 0] = min(2.0 * np.pi / (gx * dx), 2.0 * np.pi / (gy * dy))
        pre = Convolution(
            0.5 * e_star * q,
            op.shape,
            backend=op.backend,
            threads=op.threads,
            precision=op.precision,
        )
        cache[key] = pre
        while len(cache) > 2 * _MAX_OPERATORS:
            cache.popitem(last=False)
    return pre
