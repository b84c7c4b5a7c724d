"""Cached FFT operators of a solve: the influence kernel K and the stiffness preconditioner.

Planning FFTW and building a kernel cost more than a small solve, so operators are kept per
thread (a :class:`~asperity.bem.fft_backend.Convolution` owns work buffers and must never serve
two solves at once).

Memory: the operators of one grid (the influence kernel and the preconditioner, double and
single precision) share one transform workspace, a complex128 half-spectrum (8 B per grid
point; :func:`~asperity.bem.fft_backend.new_workspace`), and the multipliers that depend on |q|
alone (the periodic point-force kernel 2 / (E* |q|) and the stiffness E* |q| / 2) are evaluated
where they are applied from two 1D arrays instead of being stored (4 B per grid point each in
double precision, 2 B in single). Measured at 5000^2: before, the four operators held 24 B per
point of spectra, 12 B of multipliers and 8 B of single-precision scratch.
"""

from __future__ import annotations

import threading
import weakref
from collections import OrderedDict

import numpy as np

from asperity.bem.fft_backend import Convolution, RadialMultiplier, new_workspace
from asperity.bem.influence import influence_multiplier, wavevectors_squared

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


def _workspace(shape: tuple[int, int]) -> np.ndarray:
    """This thread's transform workspace for the FFT grid ``shape``: shared by the operators of
    that grid while any of them is alive (they are used one convolution at a time)."""
    pool = getattr(_THREAD_STATE, "workspaces", None)
    if pool is None:
        pool = _THREAD_STATE.workspaces = weakref.WeakValueDictionary()
    ws = pool.get(tuple(shape))
    if ws is None:
        ws = new_workspace(shape)
        pool[tuple(shape)] = ws
    return ws


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
        if periodic and kernel == "point":
            # 2 / (E* |q|), zero at q = 0 (influence.point_force_multiplier), not stored
            qx2, qy2 = wavevectors_squared(shape[0], shape[1], dx, dy)
            mult, grid = RadialMultiplier(qx2, qy2, 2.0 / e_star, -1), tuple(shape)
        else:
            mult, grid = influence_multiplier(
                shape, dx, dy, e_star, kernel=kernel, periodic=periodic
            )
        op = Convolution(
            mult,
            grid,
            backend=fft_backend,
            threads=threads,
            precision=precision,
            workspace=_workspace(grid),
        )
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
        qx2, qy2 = wavevectors_squared(gx, gy, dx, dy)
        q00 = min(2.0 * np.pi / (gx * dx), 2.0 * np.pi / (gy * dy))
        pre = Convolution(
            RadialMultiplier(qx2, qy2, 0.5 * e_star, 1, q00),
            op.shape,
            backend=op.backend,
            threads=op.threads,
            precision=op.precision,
            workspace=_workspace(op.shape),
        )
        cache[key] = pre
        while len(cache) > 2 * _MAX_OPERATORS:
            cache.popitem(last=False)
    return pre
