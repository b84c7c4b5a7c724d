"""Cached FFT operators of a solve: the influence kernel K and the stiffness preconditioner.

Planning FFTW and building a kernel cost more than a small solve, so operators are kept per
thread (a :class:`~asperity.bem.elastic.fft_backend.Convolution` owns work buffers and must never
serve two solves at once).

Memory: the operators of one grid (the influence kernel and the preconditioner, double and
single precision) share one transform workspace, a complex128 half-spectrum (8 B per grid
point; :func:`~asperity.bem.elastic.fft_backend.new_workspace`), and the multipliers that depend
on ``|q|`` alone (the periodic point-force kernel 2 / (E* |q|) and the stiffness E* |q| / 2)
are evaluated where they are applied from two 1D arrays instead of being stored (4 B per grid point
each in
double precision, 2 B in single). Measured at 5000^2: before, the four operators held 24 B per
point of spectra, 12 B of multipliers and 8 B of single-precision scratch.

A finite specimen (``periodic=False``) is convolved on the zero-padded doubled grid (Hockney's
method) by a :class:`PaddedConvolution`: its input and output arrays have the map's own shape,
only the transform is done on the doubled grid, in place in the shared workspace (one
complex128 half-spectrum of the doubled grid, 32 B per map point, holds the padded real grid
and its spectrum in turn). The solver's arrays then live on the map (before: every array on the
doubled grid, 4x its size, and a padded real scratch grid beside the spectrum; measured at
2000^2: 321 B per map point before).
"""

from __future__ import annotations

import threading
import time
import weakref
from collections import OrderedDict
from typing import NamedTuple

import numpy as np
from numba import njit

from asperity.bem.elastic import fft_backend as fb
from asperity.bem.elastic import fftw_wisdom
from asperity.bem.elastic.fft_backend import Convolution, RadialMultiplier, new_workspace
from asperity.bem.elastic.influence import (
    influence_multiplier,
    padded_love_coefficients,
    wavevectors_squared,
)
from asperity.bem.errors import BemInputError

__all__ = [
    "EvenMultiplier",
    "PaddedConvolution",
    "influence_operator",
    "stiffness_preconditioner",
]

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


@njit(cache=True, fastmath=False)
def _lay_in(real, x):  # pragma: no cover - compiled
    """real[:nx, :ny] = x (cast to real's dtype), zero elsewhere: no temporary (numpy's
    assignment may copy the source first when it cannot rule out an overlap)."""
    nx, ny = x.shape
    gx, gy = real.shape
    for i in range(nx):
        for j in range(ny):
            real[i, j] = x[i, j]
        for j in range(ny, gy):
            real[i, j] = 0.0
    for i in range(nx, gx):
        for j in range(gy):
            real[i, j] = 0.0


@njit(cache=True, fastmath=False)
def _take_out(out, real):  # pragma: no cover - compiled
    """out = real[:nx, :ny] (cast to out's dtype), no temporary."""
    nx, ny = out.shape
    for i in range(nx):
        for j in range(ny):
            out[i, j] = real[i, j]


@njit(inline="always")
def _expand(head, real, gx, gy, nx, ny, pitch):  # pragma: no cover - compiled
    """The map (nx, ny) stored flat at the head of the workspace moved into its padded real
    grid (rows of ``pitch`` values, gx rows), zero elsewhere on the (gx, gy) grid. In place:
    the last element first, so that no value is overwritten before it is read (the padded
    position of every element lies at or after its flat one, in bytes as well)."""
    for i in range(gx - 1, nx - 1, -1):
        base = i * pitch
        for j in range(gy):
            real[base + j] = 0.0
    for i in range(nx - 1, -1, -1):
        base = i * pitch
        for j in range(gy - 1, ny - 1, -1):
            real[base + j] = 0.0
        src = i * ny
        for j in range(ny - 1, -1, -1):
            real[base + j] = head[src + j]


@njit(inline="always")
def _compact(real, head, nx, ny, pitch):  # pragma: no cover - compiled
    """The map's block of the padded real grid moved to the head of the workspace as flat
    float32 values, in place: the first element first (the reverse of :func:`_expand`)."""
    for i in range(nx):
        base = i * pitch
        dst = i * ny
        for j in range(ny):
            head[dst + j] = real[base + j]


# the float32 head and the real grid are viewed inside the kernels, from the one workspace
# argument: the compiler then knows they may overlap
@njit(cache=True, fastmath=False)
def _expand_double(ws, gx, gy, nx, ny):  # pragma: no cover - compiled
    pitch = 2 * (gy // 2 + 1)
    head = ws[: 4 * nx * ny].view(np.float32)
    _expand(head, ws[: 8 * gx * pitch].view(np.float64), gx, gy, nx, ny, pitch)


@njit(cache=True, fastmath=False)
def _expand_single(ws, gx, gy, nx, ny):  # pragma: no cover - compiled
    pitch = 2 * (gy // 2 + 1)
    head = ws[: 4 * nx * ny].view(np.float32)
    _expand(head, ws[: 4 * gx * pitch].view(np.float32), gx, gy, nx, ny, pitch)


@njit(cache=True, fastmath=False)
def _compact_double(ws, gx, gy, nx, ny):  # pragma: no cover - compiled
    pitch = 2 * (gy // 2 + 1)
    head = ws[: 4 * nx * ny].view(np.float32)
    _compact(ws[: 8 * gx * pitch].view(np.float64), head, nx, ny, pitch)


@njit(cache=True, fastmath=False)
def _compact_single(ws, gx, gy, nx, ny):  # pragma: no cover - compiled
    pitch = 2 * (gy // 2 + 1)
    head = ws[: 4 * nx * ny].view(np.float32)
    _compact(ws[: 4 * gx * pitch].view(np.float32), head, nx, ny, pitch)


class EvenMultiplier(NamedTuple):
    """A Fourier multiplier of an FFT grid (gx, gy) that is even in qx, M[gx - i, j] = M[i, j]
    (the transform of a kernel even in x, e.g. Love's patch), stored as its rows 0 .. gx // 2
    only (float64, already divided by gx * gy): half the rows of the half-spectrum. Operators
    of both precisions read the same array (single precision rounds each value to float32
    where it is applied, as a stored float32 copy would hold it)."""

    half: np.ndarray  # (gx // 2 + 1, gy // 2 + 1), m/Pa (or Pa/m) over gx * gy


def _checked_backend(
    shape: tuple[int, int], grid: tuple[int, int], backend: str, precision: str, workspace
) -> str:
    """The backend a :class:`PaddedConvolution` of ``shape`` on the FFT ``grid`` uses ("auto"
    resolved); a BemInputError for a grid that does not hold the map, an unknown precision or
    backend, a missing pyFFTW or a workspace short of :func:`fb.workspace_bytes` (grid)."""
    if grid[0] < shape[0] or grid[1] < shape[1]:
        raise BemInputError(f"PaddedConvolution: the FFT grid {grid} must hold the map {shape}")
    if precision not in fb.PRECISIONS:
        raise BemInputError(
            f"PaddedConvolution: precision must be 'double' or 'single', got {precision!r}"
        )
    if backend not in ("auto", "pyfftw", "scipy"):
        raise BemInputError(f"fft_backend: expected 'auto', 'pyfftw' or 'scipy', got {backend!r}")
    if backend == "auto":
        backend = "pyfftw" if "pyfftw" in fb.available_backends() else "scipy"
    if backend == "pyfftw" and "pyfftw" not in fb.available_backends():
        raise BemInputError("fft_backend='pyfftw' requested but pyFFTW is not installed")
    if workspace.dtype != np.uint8 or workspace.size < fb.workspace_bytes(grid):
        raise BemInputError(
            f"PaddedConvolution: workspace must be a uint8 array of at least "
            f"{fb.workspace_bytes(grid)} bytes, got {workspace.dtype} of "
            f"{workspace.size}"
        )
    return backend


def _multiplier_shape(multiplier, spectral_shape: tuple[int, int]) -> tuple[int, ...]:
    """The half-spectrum shape a multiplier stands for (an even one's half rows counted as
    the full gx; a callable's kernel is made on the grid, so it fits)."""
    gx = spectral_shape[0]
    if isinstance(multiplier, RadialMultiplier):
        return (multiplier.qx2.size, multiplier.qy2.size)
    if isinstance(multiplier, EvenMultiplier):
        rows, cols = multiplier.half.shape
        return (gx if rows == gx // 2 + 1 else rows, cols)
    if callable(multiplier):
        return spectral_shape
    return np.shape(multiplier)


class PaddedConvolution:
    """Convolution ``out = K * x`` of arrays of the map's shape on a larger FFT grid, in place.

    The input (the map's shape, ``shape``) is laid into the real view of the workspace, zero
    elsewhere on the FFT grid ``grid`` (for a finite specimen: the doubled grid, Hockney's
    method), transformed real-to-complex in place, multiplied, transformed back in place, and
    the map's block is copied out: no array of the FFT grid's size exists besides the
    workspace. The interface is :class:`~asperity.bem.elastic.fft_backend.Convolution`'s (``shape``
    is the map's, ``grid`` the transform's).

    Parameters
    ----------
    multiplier : ndarray (gx, gy // 2 + 1), RadialMultiplier, EvenMultiplier or callable
        The Fourier multiplier of the FFT grid in the DFT sense (compliance m/Pa, or stiffness
        Pa/m); an array is divided by gx * gy unless ``normalised``. A callable ``fill(real)``
        writes a real-space kernel (m/Pa) even in x and y on the FFT grid into ``real``: it is
        transformed in place in the workspace and the real part kept as an
        :class:`EvenMultiplier` (rows i and gx - i averaged: equal but for the transform's
        round-off), 2 B per grid point in float64 for both precisions (before: 4 B for the
        double operator and 2 B for the single one).
    shape : (int, int)
        The map's shape (nx, ny) (pixels).
    grid : (int, int)
        The FFT grid (gx, gy), at least ``shape`` along each axis.
    backend : {"auto", "pyfftw", "scipy"}
        "auto" takes pyFFTW when installed (in-place plans), else scipy (which allocates a
        padded grid and its spectrum at each call).
    threads : int or None
        FFT threads; None: all available cores.
    precision : {"double", "single"}
        Transforms in float64 or float32 (inputs and outputs stay float64).
    workspace : ndarray
        A uint8 workspace of :func:`~asperity.bem.elastic.fft_backend.workspace_bytes` (grid) bytes,
        shared by the operators of the grid (used one convolution at a time).
    normalised : bool
        The multiplier array is already divided by gx * gy.
    """

    def __init__(
        self,
        multiplier: np.ndarray | RadialMultiplier,
        shape: tuple[int, int],
        grid: tuple[int, int],
        *,
        backend: str,
        threads: int | None,
        precision: str,
        workspace: np.ndarray,
        normalised: bool = False,
    ) -> None:
        self.shape = (int(shape[0]), int(shape[1]))
        self.grid = (int(grid[0]), int(grid[1]))
        self.backend = _checked_backend(self.shape, self.grid, backend, precision, workspace)
        self.precision = precision
        self.dtype, self.cdtype = fb.PRECISIONS[precision]
        self.threads = int(threads) if threads else fb.default_threads()
        gx, gy = self.grid
        self.spectral_shape = (gx, gy // 2 + 1)
        found = _multiplier_shape(multiplier, self.spectral_shape)
        if found != self.spectral_shape:
            raise BemInputError(
                f"PaddedConvolution: multiplier shape {found} does not match the half "
                f"spectrum {self.spectral_shape} of the grid {self.grid}"
            )
        self._hold_workspace(workspace)
        self._pending: np.ndarray | None = None
        self.calls = 0  # convolutions started
        self.transforms = 0  # FFTs done, forward and inverse
        self.seconds = 0.0  # wall time spent in them (s)
        self._fwd = self._inv = None
        if self.backend == "pyfftw":
            self._plan()
        self._set_multiplier(multiplier, normalised)

    def _hold_workspace(self, workspace: np.ndarray) -> None:
        """The spectrum and the padded real grid as views of ``workspace`` (uint8)."""
        gx, gy = self.grid
        nbytes = self.spectral_shape[0] * self.spectral_shape[1] * np.dtype(self.cdtype).itemsize
        # held as given: the views below keep only the buffer alive (numpy collapses a view's
        # base to the owner), so without this reference the per-thread pool forgets the
        # workspace and every operator of the grid made a workspace of its own (measured at
        # 2000^2, free boundary: 4 doubled-grid workspaces, 32 B per map point each)
        self._workspace = workspace
        self._spec = workspace[:nbytes].view(self.cdtype).reshape(self.spectral_shape)
        padded = workspace[:nbytes].view(self.dtype).reshape(gx, 2 * self.spectral_shape[1])
        self._real = padded[:, :gy]

    def _set_multiplier(self, multiplier, normalised: bool) -> None:
        """Keep the multiplier as applied: radial (evaluated where used), even (its half rows;
        a callable's kernel transformed here), or a stored array divided by gx * gy unless
        ``normalised``, in the operator's precision."""
        self._radial: RadialMultiplier | None = None
        self._mult: np.ndarray | None = None
        self._even: EvenMultiplier | None = None
        if isinstance(multiplier, RadialMultiplier):
            self._radial = multiplier
        elif isinstance(multiplier, EvenMultiplier):
            self._even = multiplier
        elif callable(multiplier):
            self._even = self._transformed_kernel(multiplier)
        else:
            mult = np.asarray(multiplier, dtype=np.float64)
            if not normalised:
                mult = mult / (self.grid[0] * self.grid[1])
            self._mult = np.ascontiguousarray(mult, dtype=self.dtype)

    def _transformed_kernel(self, fill) -> EvenMultiplier:
        """The multiplier of a real-space kernel that ``fill(real)`` writes on the FFT grid:
        the real part of its transform (the kernel is even), divided by gx * gy, transformed
        in place in the workspace; rows 0 .. gx // 2 kept, row i the mean of rows i and
        gx - i (they differ by the transform's round-off only, ~1e-15 of the largest value)."""
        fill(self._real)
        if self._fwd is not None:
            self._fwd.execute()
            spec = self._spec
        else:
            import scipy.fft

            spec = scipy.fft.rfft2(self._real, workers=self.threads)
        gx = self.grid[0]
        re = spec.real
        half = np.empty((gx // 2 + 1, self.spectral_shape[1]))
        k = (gx + 1) // 2  # rows 1 .. k - 1 have a mirror row gx - i of their own
        half[0] = re[0]
        if k > 1:
            np.add(re[1:k], re[gx - 1 : gx - k : -1], out=half[1:k])
            np.multiply(half[1:k], 0.5, out=half[1:k])
        if gx % 2 == 0:
            half[gx // 2] = re[gx // 2]
        np.divide(half, float(gx * self.grid[1]), out=half)
        return EvenMultiplier(half)

    def _plan(self) -> None:
        """In-place FFTW plans on the workspace (measured plans overwrite it: made here,
        before any caller's data lives there); the wisdom is
        :mod:`asperity.bem.elastic.fft_backend`'s."""
        import pyfftw

        fb._check_omp(self.threads)
        with fb._LOCK, fftw_wisdom.planning():
            effort = fb._planning_effort(self.grid)
            kw = dict(axes=(0, 1), threads=self.threads, planning_timelimit=fb._PLANNING_TIMELIMIT)
            self._fwd = pyfftw.FFTW(
                self._real, self._spec, direction="FFTW_FORWARD", flags=(effort,), **kw
            )
            self._inv = pyfftw.FFTW(
                self._spec,
                self._real,
                direction="FFTW_BACKWARD",
                flags=(effort, "FFTW_DESTROY_INPUT"),
                **kw,
            )

    def empty(self) -> np.ndarray:
        """A new uninitialised float64 array of the map's shape."""
        return np.empty(self.shape)

    def work_array(self) -> np.ndarray:
        """A float32 array of the map's shape viewed at the head of the shared workspace: an
        input or output of every operator of this grid that costs no memory of its own.

        Given as the input, it is moved into the padded grid in place; given as the output,
        the result is moved (rounded to float32) to it in place. Its values live only
        between transforms: the next transform of any operator of the grid overwrites them
        (the iteration's work array r = K t, or s -> z of the preconditioner, is consumed
        before the next transform; :func:`~asperity.bem.normal.iteration.new_state`)."""
        n = self.shape[0] * self.shape[1]
        return self._workspace[: 4 * n].view(np.float32).reshape(self.shape)

    def direct_input(self) -> None:
        """None: a padded operator moves its input into the doubled grid itself (the work
        array is already the head of its workspace, :meth:`work_array`); the interface of
        :meth:`~asperity.bem.elastic.fft_backend.Convolution.direct_input`."""
        return None

    def _is_head(self, a: np.ndarray) -> bool:
        """Whether ``a`` is :meth:`work_array` (of any operator sharing this workspace)."""
        return (
            a.dtype == np.float32
            and a.shape == self.shape
            and a.ctypes.data == self._workspace.ctypes.data
            and a.flags.c_contiguous
        )

    def zeros(self) -> np.ndarray:
        """A new float64 array of the map's shape filled with zeros."""
        return np.zeros(self.shape)

    def __call__(self, x: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Return ``K * x`` on the map (written into ``out`` when given; it may be ``x``)."""
        if out is None:
            out = self.empty()
        self._forward(x, False)
        return self.inverse(out)

    def with_energy(self, x: np.ndarray, out: np.ndarray) -> float:
        """Write ``y = K * x`` into ``out`` and return ``sum(x * y)`` (Parseval, in Fourier
        space: x is zero in the padding, so the sum is the map's)."""
        e = self._forward(x, True)
        self.inverse(out)
        return e

    def forward_with_energy(self, x: np.ndarray) -> float:
        """Transform ``x``, multiply and return ``sum(x * y)``; the product waits in the
        workspace for :meth:`inverse` (the next forward transform discards it)."""
        return self._forward(x, True)

    def inverse(self, out: np.ndarray) -> np.ndarray:
        """Write the map's block of the inverse transform of the pending product into
        ``out``."""
        if self._pending is None:
            raise RuntimeError("PaddedConvolution.inverse: no forward transform pending")
        t0 = time.perf_counter()
        spec, self._pending = self._pending, None
        nx, ny = self.shape
        if self._inv is not None:
            self._inv.execute()
            if self._is_head(out):
                compact = _compact_double if self.precision == "double" else _compact_single
                compact(self._workspace, self.grid[0], self.grid[1], nx, ny)
            else:
                _take_out(out, self._real)
        else:
            import scipy.fft

            full = scipy.fft.irfft2(spec, s=self.grid, norm="forward", workers=self.threads)
            out[...] = full[:nx, :ny]
        self.transforms += 1
        self.seconds += time.perf_counter() - t0
        return out

    def _forward(self, x: np.ndarray, energy: bool) -> float:
        """Lay ``x`` into the padded grid, transform, multiply (the product is kept pending);
        returns sum(x * y) when ``energy`` (else 0)."""
        t0 = time.perf_counter()
        nx, ny = self.shape
        if np.shape(x) != self.shape:
            raise BemInputError(
                f"PaddedConvolution: input shape {np.shape(x)} does not match the map {self.shape}"
            )
        if self._fwd is not None:
            if self._is_head(x):
                expand = _expand_double if self.precision == "double" else _expand_single
                expand(self._workspace, self.grid[0], self.grid[1], nx, ny)
            else:
                _lay_in(self._real, x)
            self._fwd.execute()
            spec = self._spec
        else:
            import scipy.fft

            padded = np.zeros(self.grid, dtype=self.dtype)
            padded[:nx, :ny] = x
            spec = scipy.fft.rfft2(padded, workers=self.threads)
            del padded
        e = 0.0
        gy = self.grid[1]
        if self._radial is not None:
            nn = float(self.grid[0] * self.grid[1])
            e = fb._multiply_radial(spec, self._radial, nn, gy, energy)
        elif self._even is not None:
            e = fb._multiply_even(spec, self._even.half, gy, energy)
        elif energy:
            e = fb._multiply_stored(spec, self._mult, gy)
        else:
            # the real and imaginary parts apart: same values as spec * mult, without the
            # ufunc's casting buffer (64 KiB)
            np.multiply(spec.real, self._mult, out=spec.real)
            np.multiply(spec.imag, self._mult, out=spec.imag)
        self._pending = spec
        self.calls += 1
        self.transforms += 1
        self.seconds += time.perf_counter() - t0
        return e


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
    in_place: bool = False,
) -> Convolution | PaddedConvolution:
    """The convolution u = K * p (m from Pa) for heights of ``shape`` with pixel sizes dx, dy
    (m) and modulus E* (Pa): periodic, or zero-padded to the doubled grid; cached per thread.
    ``precision``: "double" or "single" transforms (:class:`Convolution`). A finite specimen
    always gets a :class:`PaddedConvolution`; a periodic grid gets one when ``in_place`` (it
    then takes inputs and outputs of any float dtype, e.g. float32 direction and work arrays,
    without a scratch grid, at the cost of a copy in and out of the workspace)."""
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
        bool(in_place) or not periodic,
    )
    cache = _operator_cache()
    op = cache.get(key)
    if op is None:
        if not periodic:
            op = _padded_influence_operator(key)
        elif in_place:
            qx2, qy2 = wavevectors_squared(shape[0], shape[1], dx, dy)
            if kernel == "point":
                mult = RadialMultiplier(qx2, qy2, 2.0 / e_star, -1)
            else:
                mult, _ = influence_multiplier(shape, dx, dy, e_star, kernel=kernel)
            kw = dict(backend=fft_backend, threads=threads, precision=precision)
            op = PaddedConvolution(mult, shape, shape, workspace=_workspace(tuple(shape)), **kw)
        else:
            if kernel == "point":
                # 2 / (E* |q|), zero at q = 0 (influence.point_force_multiplier), not stored
                qx2, qy2 = wavevectors_squared(shape[0], shape[1], dx, dy)
                mult = RadialMultiplier(qx2, qy2, 2.0 / e_star, -1)
            else:
                mult, _ = influence_multiplier(shape, dx, dy, e_star, kernel=kernel)
            op = Convolution(
                mult,
                tuple(shape),
                backend=fft_backend,
                threads=threads,
                precision=precision,
                workspace=_workspace(tuple(shape)),
            )
        cache[key] = op
        while len(cache) > _MAX_OPERATORS:
            cache.popitem(last=False)
    else:
        cache.move_to_end(key)
    return op


def _padded_influence_operator(key: tuple) -> PaddedConvolution:
    """The finite-specimen operator of :func:`influence_operator`'s ``key``: Love's patch on the
    doubled grid (:func:`~asperity.bem.elastic.influence.padded_love_multiplier`). The
    single-precision
    operator reads the double one's multiplier (an :class:`EvenMultiplier`, 8 B per map point
    stored once for both, made by one doubled-grid transform in the workspace)."""
    shape, dx, dy, e_star, kernel, _, fft_backend, threads, precision, _ = key
    grid = (2 * shape[0], 2 * shape[1])
    if precision == "single":
        double = influence_operator(
            shape, dx, dy, e_star, kernel, False, fft_backend, threads, "double", True
        )
        mult, normalised = double._even, True
    else:
        # the real-space kernel written into the transform's own buffer and transformed
        # there: no array of the doubled grid besides the workspace
        def mult(real: np.ndarray) -> None:
            padded_love_coefficients(real, shape[0], shape[1], dx, dy, e_star)

        normalised = False
    return PaddedConvolution(
        mult,
        shape,
        grid,
        backend=fft_backend,
        threads=threads,
        precision=precision,
        workspace=_workspace(grid),
        normalised=normalised,
    )


def stiffness_preconditioner(op: Convolution, dx: float, dy: float, e_star: float) -> Convolution:
    """The stiffness E* |q| / 2 (Pa/m, the inverse of the point-force kernel) on the FFT grid
    of ``op``, q = 0 set to its smallest non-zero value; same backend, threads and precision
    as ``op``."""
    key = (
        "precondition",
        type(op).__name__,
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
        grid = op.grid if isinstance(op, PaddedConvolution) else op.shape
        gx, gy = grid
        qx2, qy2 = wavevectors_squared(gx, gy, dx, dy)
        q00 = min(2.0 * np.pi / (gx * dx), 2.0 * np.pi / (gy * dy))
        stiffness = RadialMultiplier(qx2, qy2, 0.5 * e_star, 1, q00)
        kw = dict(backend=op.backend, threads=op.threads, precision=op.precision)
        if isinstance(op, PaddedConvolution):
            pre = PaddedConvolution(stiffness, op.shape, grid, workspace=_workspace(grid), **kw)
        else:
            pre = Convolution(stiffness, grid, workspace=_workspace(grid), **kw)
        cache[key] = pre
        while len(cache) > 2 * _MAX_OPERATORS:
            cache.popitem(last=False)
    return pre
