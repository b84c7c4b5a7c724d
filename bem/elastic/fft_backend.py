"""Real-to-complex 2D FFT convolution with a fixed real Fourier multiplier.

Two backends:

* ``"pyfftw"``: FFTW through pyFFTW, threaded, planned once per (shape, threads, precision) with
  ``FFTW_MEASURE`` and the wisdom cached on disk under ``~/.cache/asperity`` (or
  ``$XDG_CACHE_HOME/asperity``; override with ``$ASPERITY_CACHE_DIR``), so that a second process
  does not re-plan (:mod:`asperity.bem.elastic.fftw_wisdom`: a file planned while other
  processes held the cores is set aside on a quiet machine and re-planned). Grids above
  2048^2 whose sizes are not products of 2, 3, 5 and 7 are planned with ``FFTW_ESTIMATE``
  (measuring 5001^2 = 3 x 1667 takes minutes); smooth sizes are always measured: at 5000^2 a
  measured plan convolves in 0.73 s against 1.02 s estimated (2 threads, busy machine), for
  15 s of planning once per machine (the wisdom file).
* ``"scipy"``: ``scipy.fft.rfft2``/``irfft2`` with ``workers`` threads, always available.

``precision="single"`` transforms in float32 (complex64 spectra): the input (float64) is cast
into a float32 buffer and the result cast back, so callers keep float64 arrays. Measured at
5000^2 (pyFFTW, measured plans, 2 threads): 0.47 s per convolution against 0.73 s in double.
The relative error of a single-precision convolution is ~1e-7 of the largest value: the
solver uses it only while its residual is far above that (:mod:`asperity.bem.normal.iteration`).

``"auto"`` times pyfftw (requested threads and one thread) and scipy (below 2048^2 points: above,
scipy's per-call spectrum and output arrays cost 16 B a point) on the grid once per process
and shape and keeps the fastest: pyfftw when installed and measured faster.

Pitfall handled here: the pyFFTW wheel threads through OpenMP, so ``OMP_NUM_THREADS=1`` silently
turns ``threads=2`` into one thread; :func:`default_threads` and :class:`Convolution` warn about it.

Awkward sizes (e.g. 5001 = 3 x 1667) transform more slowly than nearby smooth sizes;
:func:`fast_size` gives the largest size <= n whose prime factors are 2, 3, 5 and 7 and
:func:`crop_to_fast_size` crops a height map to it with a warning stating what was cut.
"""

from __future__ import annotations

import math
import os
import threading
import time
import warnings
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange
from numba.extending import overload

from asperity.bem.elastic import fftw_wisdom
from asperity.bem.elastic.fftw_wisdom import cache_dir
from asperity.bem.errors import BemInputError

__all__ = [
    "Convolution",
    "NumbaThreads",
    "RadialMultiplier",
    "available_backends",
    "cache_dir",
    "crop_to_fast_size",
    "default_threads",
    "fast_size",
    "new_workspace",
]

_LOCK = threading.Lock()
_MEASURE_LIMIT = 2048 * 2048  # non-smooth grids larger than this are planned with FFTW_ESTIMATE
_PLANNING_TIMELIMIT = 300.0  # s: FFTW keeps the best plan found so far beyond it
PRECISIONS = {"double": (np.float64, np.complex128), "single": (np.float32, np.complex64)}
_AUTO_CHOICE: dict[tuple, tuple[str, int]] = {}
_PYFFTW_ONLY = 2048 * 2048  # grid points from which "auto" does not consider scipy
_ALIGN = 64  # bytes: the alignment of workspace views (>= any SIMD alignment FFTW asks)


def _planning_effort(shape: tuple[int, int]) -> str:
    """FFTW_MEASURE (it times candidate algorithms by running them) unless the grid is above
    2048^2 with a size that is not a product of 2, 3, 5 and 7, where measuring takes minutes
    (5001^2: prime factor 1667): FFTW_ESTIMATE there."""
    smooth = all(_is_smooth(int(n)) for n in shape)
    return "FFTW_MEASURE" if smooth or shape[0] * shape[1] <= _MEASURE_LIMIT else "FFTW_ESTIMATE"


def _timed(conv: Convolution, x: np.ndarray, out: np.ndarray) -> float:
    t0 = time.perf_counter()
    conv(x, out)
    return time.perf_counter() - t0


class RadialMultiplier(NamedTuple):
    """A Fourier multiplier that depends on |q| alone, evaluated where it is used instead of
    stored (a stored half-spectrum costs 4 B per grid point in double precision).

    ``m(q) = coef / |q|`` (``power = -1``; zero at q = 0: the periodic point-force compliance
    2 / (E* |q|), m/Pa) or ``coef |q|`` (``power = 1``; |q| = ``q00`` at q = 0: the stiffness
    E* |q| / 2, Pa/m), with |q| = sqrt(qx2[i] + qy2[j]) on the half-spectrum grid.
    """

    qx2: np.ndarray  # (nx,) qx^2 (rad^2/m^2), in numpy's FFT order
    qy2: np.ndarray  # (ny // 2 + 1,) qy^2 (rad^2/m^2)
    coef: float
    power: int
    q00: float = 0.0

    def materialise(self) -> np.ndarray:
        """The multiplier as a float64 half-spectrum array (for checks and small grids)."""
        out = np.empty((self.qx2.size, self.qy2.size))
        _radial_fill(out, self.qx2, self.qy2, self.coef, self.power, self.q00, 1.0)
        return out


@njit(inline="always")
def _radial_value(qx2, qy2, i, j, coef, power, q00, nn):  # pragma: no cover - compiled
    q = math.sqrt(qx2[i] + qy2[j])
    if i == 0 and j == 0 and q00 > 0.0:
        q = q00
    if power < 0:
        m = coef / q if q > 0.0 else 0.0
    else:
        m = coef * q
    return m / nn


@njit(cache=True, fastmath=False)
def _radial_fill(out, qx2, qy2, coef, power, q00, nn):  # pragma: no cover - compiled
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = _radial_value(qx2, qy2, i, j, coef, power, q00, nn)


def _in_precision_of(spec, v):
    """``v`` (a multiplier value, float64) in the real type of ``spec``'s elements: rounded to
    float32 for a complex64 spectrum (as a stored float32 multiplier would hold it), unchanged
    for a complex128 one. Compiled code uses the overload below (chosen by ``spec``'s type)."""
    return spec.real.dtype.type(v)


@overload(_in_precision_of)
def _in_precision_of_compiled(spec, v):  # pragma: no cover - compiled
    if spec.dtype == numba.types.complex64:
        return lambda spec, v: np.float32(v)
    return lambda spec, v: v


# How _multiply_spectrum reads its multiplier M[i, j]: a stored half-spectrum table[i, j], or
# the rows 0 .. nx // 2 of one even in qx, table[min(i, nx - i), j] (a radial multiplier has a
# kernel of its own, _multiply_radial_rows).
_STORED, _EVEN = 0, 1


@njit(cache=True, fastmath=False, parallel=True)
def _multiply_spectrum(spec, ny, energy, kind, table):  # pragma: no cover - compiled
    """spec *= M in place (M read as ``kind`` says, in the precision of ``spec``); returns the
    Parseval sum over the full spectrum of M |spec|^2 when ``energy`` (the columns 0 and, for
    an even ``ny``, ny // 2 once, the others twice), else 0. Rows run in parallel (numba
    threads); the energy is summed per row, then over the rows in order, so it does not depend
    on the number of threads, nor on how M is held."""
    nx, nyh = spec.shape
    last = nyh - 1 if ny % 2 == 0 else -1
    rows = np.zeros(nx)
    for i in prange(nx):
        k = np.int64(i)
        if kind == _EVEN and k > nx // 2:
            k = nx - k
        e0 = 0.0
        e1 = 0.0
        for j in range(nyh):
            m = _in_precision_of(spec, table[k, j])
            z = spec[i, j]
            if energy:
                a = m * (z.real * z.real + z.imag * z.imag)
                if j == 0 or j == last:
                    e0 += a
                else:
                    e1 += a
            spec[i, j] = z * m
        rows[i] = e0 + 2.0 * e1
    total = 0.0
    for i in range(nx):
        total += rows[i]
    return total


@njit(cache=True, fastmath=False, parallel=True, error_model="numpy")
def _multiply_radial_rows(spec, ny, energy, qx2, qy2, coef, power, q00, nn):  # pragma: no cover
    """:func:`_multiply_spectrum` for a radial multiplier, with the same bits, in three passes
    a row: the row's multiplier (``_radial_value``'s operations in its order, branch-free so
    that the compiler vectorises the square root and the divisions; the q = 0 element is
    patched after), the energy sum (the same sequence of additions), then the product.
    Measured at 5000^2 (complex64, 2 threads): 8.0 ms against 24.1 ms for the one-pass form."""
    nx, nyh = spec.shape
    last = nyh - 1 if ny % 2 == 0 else -1
    stop = last if last > 0 else nyh
    rows = np.zeros(nx)
    for i in prange(nx):
        m = np.empty(nyh, dtype=spec.real.dtype)  # rounded as _in_precision_of rounds
        qi = qx2[i]
        if power < 0:
            for j in range(nyh):
                m[j] = (coef / math.sqrt(qi + qy2[j])) / nn
        else:
            for j in range(nyh):
                m[j] = (coef * math.sqrt(qi + qy2[j])) / nn
        if i == 0:
            m[0] = _radial_value(qx2, qy2, 0, 0, coef, power, q00, nn)
        if energy:
            z = spec[i, 0]
            e0 = m[0] * (z.real * z.real + z.imag * z.imag) + 0.0
            e1 = 0.0
            for j in range(1, stop):
                z = spec[i, j]
                e1 += m[j] * (z.real * z.real + z.imag * z.imag)
            if last > 0:
                z = spec[i, last]
                e0 += m[last] * (z.real * z.real + z.imag * z.imag)
            rows[i] = e0 + 2.0 * e1
        for j in range(nyh):
            spec[i, j] = spec[i, j] * m[j]
    total = 0.0
    for i in range(nx):
        total += rows[i]
    return total


def _multiply_stored(spec: np.ndarray, mult: np.ndarray, ny: int) -> float:
    """``spec *= mult`` in place (a stored half-spectrum multiplier, its values already divided
    by the number of grid points: m/Pa or Pa/m); returns the energy sum(x * y) of the
    convolution (J, for x in Pa and y in m on a unit pixel), as :func:`_multiply_spectrum`."""
    return _multiply_spectrum(spec, ny, True, _STORED, mult)


def _multiply_radial(
    spec: np.ndarray, rm: RadialMultiplier, nn: float, ny: int, energy: bool
) -> float:
    """``spec *= m(|q|) / nn`` in place for the radial multiplier ``rm`` (``nn`` the number of
    grid points); returns the energy when ``energy``, else 0 (:func:`_multiply_radial_rows`)."""
    return _multiply_radial_rows(
        spec, ny, energy, rm.qx2, rm.qy2, float(rm.coef), int(rm.power), float(rm.q00), nn
    )


def _multiply_even(spec: np.ndarray, half: np.ndarray, ny: int, energy: bool) -> float:
    """``spec *= M`` in place for a multiplier even in qx stored as its rows 0 .. nx // 2
    (``half``, float64, already divided by the number of grid points); returns the energy
    when ``energy``, else 0 (:func:`_multiply_spectrum`)."""
    e = _multiply_spectrum(spec, ny, energy, _EVEN, half)
    return e if energy else 0.0


@njit(cache=True, fastmath=False, parallel=True)
def _cast_rows(dst, src):  # pragma: no cover - compiled
    """dst[...] = src for two 2D arrays of one shape (float64 <-> float32), rows in parallel:
    the precision casts of a single-precision convolution (a serial numpy cast of a 5000^2
    grid costs a tenth of the transform it feeds)."""
    for i in prange(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


class _NumbaThreads:
    """Run numba's parallel kernels on at most ``n`` threads inside the block (numba's thread
    mask is per calling thread; the previous count is restored on exit)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.previous = 0

    def __enter__(self) -> None:
        self.previous = numba.get_num_threads()
        want = max(1, min(self.n, self.previous))
        if want != self.previous:
            numba.set_num_threads(want)

    def __exit__(self, *exc: object) -> None:
        if numba.get_num_threads() != self.previous:
            numba.set_num_threads(self.previous)


#: Public name of the thread-mask context (the solver's pointwise kernels run inside it).
NumbaThreads = _NumbaThreads


def _cast_into(dst: np.ndarray, src: np.ndarray, threads: int) -> None:
    """``dst[...] = src`` (a precision cast between real grids), on ``threads`` numba threads
    for C-contiguous 2D arrays of one shape, by numpy otherwise."""
    if (
        dst.ndim == 2
        and dst.shape == src.shape
        and dst.flags.c_contiguous
        and src.flags.c_contiguous
        and dst.dtype in (np.float32, np.float64)
        and src.dtype in (np.float32, np.float64)
    ):
        with _NumbaThreads(threads):
            _cast_rows(dst, src)
    else:
        np.copyto(dst, src, casting="same_kind")


def workspace_bytes(shape: tuple[int, int]) -> int:
    """Bytes of the transform workspace of a real grid ``shape``: a complex128 half-spectrum,
    which in single precision holds the complex64 half-spectrum and a float32 real grid."""
    nx, ny = int(shape[0]), int(shape[1])
    return max(16 * nx * (ny // 2 + 1), _single_offset(shape) + 4 * nx * ny) + _ALIGN


def _single_offset(shape: tuple[int, int]) -> int:
    nx, ny = int(shape[0]), int(shape[1])
    return -(-8 * nx * (ny // 2 + 1) // _ALIGN) * _ALIGN


def new_workspace(shape: tuple[int, int]) -> np.ndarray:
    """A transform workspace for the real grid ``shape`` (uint8, 64-byte aligned) that the
    :class:`Convolution` objects of one grid share (``workspace=``): one half-spectrum for all
    of them, double and single precision, the influence kernel and the preconditioner. They
    must then not interleave: a forward transform's pending product lives in it until its
    inverse (every caller in :mod:`asperity.bem` completes one convolution before the next)."""
    raw = np.empty(workspace_bytes(shape) + _ALIGN, dtype=np.uint8)
    start = (-raw.ctypes.data) % _ALIGN
    return raw[start : start + workspace_bytes(shape)]


def default_threads() -> int:
    """Number of CPU cores this process may use (``os.sched_getaffinity`` when available)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def available_backends() -> list[str]:
    """The FFT backends importable here, fastest-first by expectation."""
    names = []
    try:
        import pyfftw  # noqa: F401

        names.append("pyfftw")
    except ImportError:
        pass
    names.append("scipy")
    return names


def _is_smooth(n: int, primes: tuple[int, ...] = (2, 3, 5, 7)) -> bool:
    for p in primes:
        while n % p == 0 and n > 1:
            n //= p
    return n == 1


def fast_size(n: int) -> int:
    """Largest size ``m <= n`` whose prime factors are all in {2, 3, 5, 7} (fast FFTs).

    Parameters
    ----------
    n : int
        A grid size (pixels), >= 1.
    """
    if n < 1:
        raise BemInputError(f"fast_size: expected a size >= 1, got {n}")
    m = n
    while not _is_smooth(m):
        m -= 1
    return m


def crop_to_fast_size(heights: np.ndarray, *, warn: bool = True) -> np.ndarray:
    """Crop a 2D height map (m) to fast FFT sizes along both axes, keeping the leading corner.

    The trailing rows/columns are cut; a ``UserWarning`` states how many along each axis. Note
    that a periodic map cropped this way is no longer exactly periodic at the cut.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights (m); axis 0 is x.
    warn : bool
        Emit the warning describing the cut (default True).

    Returns
    -------
    ndarray
        A view ``heights[:mx, :my]`` with ``mx = fast_size(nx)``, ``my = fast_size(ny)``.
    """
    heights = np.asarray(heights)
    if heights.ndim != 2:
        raise BemInputError(
            f"crop_to_fast_size: expected a 2D height map, got shape {heights.shape}"
        )
    nx, ny = heights.shape
    mx, my = fast_size(nx), fast_size(ny)
    if warn and (mx, my) != (nx, ny):
        warnings.warn(
            f"cropped the height map from {nx} x {ny} to {mx} x {my} pixels for a fast FFT: "
            f"removed the last {nx - mx} row(s) along x (axis 0) and the last {ny - my} "
            f"column(s) along y (axis 1)",
            UserWarning,
            stacklevel=2,
        )
    return heights[:mx, :my]


def _check_omp(threads: int) -> None:
    omp = os.environ.get("OMP_NUM_THREADS")
    if omp is None or threads <= 1:
        return
    try:
        import pyfftw.pyfftw as _pp

        kind = getattr(_pp, "_threading_type", None)
    except ImportError:  # pragma: no cover
        return
    try:
        omp_n = int(omp.split(",")[0])
    except ValueError:
        return
    if kind == "OMP" and omp_n < threads:
        warnings.warn(
            f"pyFFTW threads through OpenMP here and OMP_NUM_THREADS={omp} caps FFTW at "
            f"{omp_n} thread(s) although threads={threads} was requested; unset it or raise it",
            RuntimeWarning,
            stacklevel=3,
        )


def _checked_multiplier(
    multiplier: np.ndarray | RadialMultiplier,
    spectral_shape: tuple[int, int],
    shape: tuple[int, int],
) -> np.ndarray | RadialMultiplier:
    """The multiplier of a :class:`Convolution` of the grid ``shape`` (an array as float64),
    a BemInputError when it does not cover the half-spectrum ``spectral_shape``."""
    if isinstance(multiplier, RadialMultiplier):
        found = (multiplier.qx2.size, multiplier.qy2.size)
    else:
        multiplier = np.asarray(multiplier, dtype=np.float64)
        found = multiplier.shape
    if found != spectral_shape:
        raise BemInputError(
            f"Convolution: multiplier shape {found} does not match the half "
            f"spectrum {spectral_shape} of the grid {shape}"
        )
    return multiplier


def _check_workspace(workspace: np.ndarray | None, shape: tuple[int, int]) -> None:
    """A BemInputError unless ``workspace`` is None or a uint8 array of
    :func:`workspace_bytes` (shape) bytes at least."""
    if workspace is not None and (
        workspace.dtype != np.uint8 or workspace.size < workspace_bytes(shape)
    ):
        raise BemInputError(
            f"Convolution: workspace must be a uint8 array of at least "
            f"{workspace_bytes(shape)} bytes (new_workspace), got {workspace.dtype} "
            f"of {workspace.size}"
        )


def _check_backend(backend: str) -> None:
    """A BemInputError for an unknown backend, or pyFFTW asked for and not installed."""
    if backend not in ("auto", "pyfftw", "scipy"):
        raise BemInputError(f"fft_backend: expected 'auto', 'pyfftw' or 'scipy', got {backend!r}")
    if backend == "pyfftw" and "pyfftw" not in available_backends():
        raise BemInputError("fft_backend='pyfftw' requested but pyFFTW is not installed")


class Convolution:
    """Periodic convolution ``out = irfft2(multiplier * rfft2(x))`` on a fixed real grid shape.

    Parameters
    ----------
    multiplier : ndarray, shape (nx, ny // 2 + 1), real
        The Fourier multiplier in the DFT sense (for an influence kernel: compliance in m/Pa,
        such that ``u = irfft2(multiplier * rfft2(p))``).
    shape : tuple of int
        The real grid shape ``(nx, ny)``.
    backend : {"auto", "pyfftw", "scipy"}
        FFT backend (see the module docstring).
    threads : int, optional
        Threads for the transforms; default: all cores available to this process.

    Notes
    -----
    For speed, pass input arrays obtained from :meth:`empty` (aligned, C-contiguous): the
    pyfftw backend then transforms them in place of its own buffers without copying.
    """

    def __init__(
        self,
        multiplier: np.ndarray | RadialMultiplier,
        shape: tuple[int, int],
        *,
        backend: str = "auto",
        threads: int | None = None,
        precision: str = "double",
        workspace: np.ndarray | None = None,
    ) -> None:
        nx, ny = (int(shape[0]), int(shape[1]))
        self.shape = (nx, ny)
        self.spectral_shape = (nx, ny // 2 + 1)
        if precision not in PRECISIONS:
            raise BemInputError(
                f"Convolution: precision must be 'double' or 'single', got {precision!r}"
            )
        self.precision = precision
        self.dtype, self.cdtype = PRECISIONS[precision]
        multiplier = _checked_multiplier(multiplier, self.spectral_shape, self.shape)
        _check_workspace(workspace, self.shape)
        self.threads = int(threads) if threads else default_threads()
        _check_backend(backend)
        self._fwd = None
        self.calls = 0  # convolutions started (a machine-independent cost measure)
        self.transforms = 0  # FFTs done, forward and inverse (2 per full convolution)
        self._pending: np.ndarray | None = None  # the product of the last forward transform
        self.seconds = 0.0  # wall time spent in them (s)
        self._workspace = workspace
        if backend == "auto":
            backend = self._choose_backend(multiplier, threads_given=bool(threads))
        self.backend = backend
        # fold the 1/N normalisation of the unnormalised inverse transform into the multiplier
        # (a radial one divides by N where it is evaluated)
        if isinstance(multiplier, RadialMultiplier):
            self._radial: RadialMultiplier | None = multiplier
            self._mult = None
        else:
            self._radial = None
            self._mult = np.ascontiguousarray(multiplier / (nx * ny), dtype=self.dtype)
        if backend == "pyfftw":
            self._setup_pyfftw()
        else:  # release plans made while measuring
            self._fwd = self._inv = None

    def _workspace_views(self) -> tuple[np.ndarray, np.ndarray | None]:
        """The half-spectrum (this precision) in the workspace and, in single precision, the
        float32 real scratch grid after it (None in double precision)."""
        ws = self._workspace
        nspec = self.spectral_shape[0] * self.spectral_shape[1]
        csize = np.dtype(self.cdtype).itemsize
        spec = ws[: nspec * csize].view(self.cdtype).reshape(self.spectral_shape)
        if self.precision == "double":
            return spec, None
        off = _single_offset(self.shape)
        n = self.shape[0] * self.shape[1]
        return spec, ws[off : off + 4 * n].view(np.float32).reshape(self.shape)

    # -- backend selection -------------------------------------------------------------
    def _choose_backend(
        self, multiplier: np.ndarray | RadialMultiplier, threads_given: bool
    ) -> str:
        """Time the candidate (backend, threads) pairs on this grid and keep the fastest.

        Candidates: pyfftw with the requested threads, pyfftw with one thread (OpenMP threads
        that wait on a busy core make 2 threads slower than 1 on a shared 2-core machine) unless
        ``threads`` was given explicitly, and scipy with the requested workers (below 2048^2
        points). The choice is made once per grid shape for both precisions and remembered
        for this process (it depends on the machine's current load, so it is not
        written to disk; the FFTW plans are, as wisdom).
        """
        # one timing per grid and process, whatever the precision (the double and single
        # precision operators of a mixed solve were timed apart: with three candidates, a
        # warm-up and two timed convolutions each, about 18 convolutions of 0.4-0.7 s at
        # 5000^2 in every fresh process; now 2 candidates x 2 convolutions there)
        key = (self.shape, self.threads, threads_given)
        with _LOCK:
            known = _AUTO_CHOICE.get(key)
        if known is not None:
            self.threads = known[1]
            return known[0]
        candidates = [("scipy", self.threads)]
        if "pyfftw" in available_backends() and self.shape[0] * self.shape[1] >= _PYFFTW_ONLY:
            # scipy allocates a spectrum and an output grid at every call (16 B a point above
            # the shared workspace at the solver's peak): large grids keep to pyfftw
            candidates = []
        if "pyfftw" in available_backends():
            candidates.insert(0, ("pyfftw", self.threads))
            if self.threads > 1 and not threads_given:
                candidates.insert(1, ("pyfftw", 1))
        # timed with this operator's own multiplier and workspace: the candidates add two
        # real grids (input and output) to the memory, nothing else
        rng = np.random.default_rng(0)
        reps = 5 if self.shape[0] * self.shape[1] <= 2048 * 2048 else 1
        timings = []
        for name, nthreads in candidates:
            conv = Convolution(
                multiplier,
                self.shape,
                backend=name,
                threads=nthreads,
                precision=self.precision,
                workspace=self._workspace,
            )
            buf = conv.empty()
            rng.standard_normal(out=buf)
            out = conv.empty()
            conv(buf, out)  # warm up
            # the median, not the minimum: threads that wait on a busy core show up as a
            # spread of slow calls, not in the best one
            elapsed = float(np.median([_timed(conv, buf, out) for _ in range(reps)]))
            # prefer fewer threads unless more are clearly (15 %) faster
            timings.append((elapsed * (1.0 if nthreads == 1 else 1.15), name, nthreads))
            del conv, buf, out
        _, name, nthreads = min(timings)
        with _LOCK:
            _AUTO_CHOICE[key] = (name, nthreads)
        self.threads = nthreads
        return name

    def _setup_pyfftw(self) -> None:
        if getattr(self, "_fwd", None) is not None:
            return
        import pyfftw

        _check_omp(self.threads)
        with _LOCK, fftw_wisdom.planning():
            self._scratch = None
            if self._workspace is not None:
                self._spec, self._scratch = self._workspace_views()
            else:
                self._spec = pyfftw.empty_aligned(self.spectral_shape, dtype=self.cdtype)
            # the planning arrays are released at the first transform (update_arrays)
            real_in = pyfftw.empty_aligned(self.shape, dtype=self.dtype)
            real_out = (
                self._scratch
                if self._scratch is not None
                else pyfftw.empty_aligned(self.shape, dtype=self.dtype)
            )
            effort = _planning_effort(self.shape)
            self._fwd = pyfftw.FFTW(
                real_in,
                self._spec,
                axes=(0, 1),
                direction="FFTW_FORWARD",
                flags=(effort,),
                threads=self.threads,
                planning_timelimit=_PLANNING_TIMELIMIT,
            )
            self._inv = pyfftw.FFTW(
                self._spec,
                real_out,
                axes=(0, 1),
                direction="FFTW_BACKWARD",
                flags=(effort, "FFTW_DESTROY_INPUT"),
                threads=self.threads,
                planning_timelimit=_PLANNING_TIMELIMIT,
            )
            if self._workspace is not None:
                # release the planning arrays now rather than at the first transform (a plan
                # made late in a solve would otherwise hold two grids more at its peak): the
                # plans point at a real grid viewed in the workspace until their first use,
                # which always passes its own arrays (update_arrays)
                parked = self._parked_real()
                self._fwd.update_arrays(parked, self._spec)
                self._inv.update_arrays(self._spec, parked)
            del real_in, real_out
        self._align = pyfftw.simd_alignment

    def _park(self, plan) -> None:
        """Point ``plan`` back at the workspace after a transform, so that it does not keep the
        caller's array alive (a cached operator would otherwise hold the last solve's
        direction and work arrays until the next one)."""
        if self._workspace is None:
            return
        if plan is self._fwd:
            plan.update_arrays(self._parked_real(), self._spec)
        else:
            plan.update_arrays(self._spec, self._parked_real())

    def _parked_real(self) -> np.ndarray:
        """A real grid of this precision viewed in the workspace (it fits: the workspace holds
        a complex128 half-spectrum), never transformed: see :meth:`_setup_pyfftw`."""
        n = self.shape[0] * self.shape[1] * np.dtype(self.dtype).itemsize
        return self._workspace[:n].view(self.dtype).reshape(self.shape)

    # -- public --------------------------------------------------------------------------
    def empty(self) -> np.ndarray:
        """A new uninitialised float64 array of the grid shape, aligned for the backend."""
        return self._aligned(np.float64)

    def _aligned(self, dtype: type) -> np.ndarray:
        if self.backend == "pyfftw":
            import pyfftw

            return pyfftw.empty_aligned(self.shape, dtype=dtype)
        return np.empty(self.shape, dtype=dtype)

    def zeros(self) -> np.ndarray:
        """Like :meth:`empty`, filled with zeros."""
        a = self.empty()
        a[...] = 0.0
        return a

    def diagonal(self) -> float:
        """The real-space kernel at zero offset, ``irfft2(multiplier)[0, 0]`` (for an
        influence kernel: the deflection of a pixel under its own unit pressure, m/Pa)."""
        if self._radial is not None:
            n = self.shape[0] * self.shape[1]
            mult = (self._radial.materialise() / n).astype(self.dtype)
        else:
            mult = self._mult  # already divided by the number of grid points
        ny = self.shape[1]
        total = 2.0 * float(mult.sum()) - float(mult[:, 0].sum())
        if ny % 2 == 0:
            total -= float(mult[:, -1].sum())
        return total

    def direct_input(self) -> np.ndarray | None:
        """The single-precision real grid this operator's pyFFTW plans read and write as it is
        (its own aligned scratch), or None (double precision or scipy: the caller's float64
        arrays are transformed without a cast anyway).

        A kernel that writes its output here (or reads the inverse transform's output from
        here) saves the float64 <-> float32 cast pass of every single-precision transform:
        the same bits (the kernel rounds to float32 where the cast did; float32 to float64 is
        exact), 12 B a point less memory traffic."""
        if self.backend != "pyfftw" or self.precision == "double":
            return None
        if self._scratch is None:
            self._scratch = self._aligned(self.dtype)
        return self._scratch

    def _usable(self, a: np.ndarray) -> bool:
        return (
            a.dtype == self.dtype
            and a.shape == self.shape
            and a.flags.c_contiguous
            and a.ctypes.data % self._align == 0
        )

    def __call__(self, x: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Return ``irfft2(multiplier * rfft2(x))`` (written into ``out`` when given)."""
        if out is None:
            out = self.empty()
        self._forward(x, False)
        self.inverse(out)
        return out

    def with_energy(self, x: np.ndarray, out: np.ndarray) -> float:
        """Write ``y = irfft2(multiplier * rfft2(x))`` into ``out`` and return ``sum(x * y)``.

        The sum is evaluated in Fourier space (Parseval) during the multiplication, so it costs
        no extra pass over the real arrays.
        """
        e = self._forward(x, True)
        self.inverse(out)
        return e

    def forward_with_energy(self, x: np.ndarray) -> float:
        """The first half of :meth:`with_energy`: transform ``x``, multiply, return
        ``sum(x * y)``; the product stays here until :meth:`inverse` (or the next forward
        transform, which discards it: a caller that finds it does not need ``y`` saves the
        inverse transform)."""
        return self._forward(x, True)

    def inverse(self, out: np.ndarray) -> np.ndarray:
        """Write the inverse transform of the pending product (from the last forward
        transform) into ``out`` (float64 or this operator's dtype)."""
        if self._pending is None:
            raise RuntimeError("Convolution.inverse: no forward transform pending")
        t0 = time.perf_counter()
        spec, self._pending = self._pending, None
        if self.backend == "pyfftw":
            target = out
            if not self._usable(out):
                if self._scratch is None:
                    self._scratch = self._aligned(self.dtype)
                target = self._scratch
            self._inv.update_arrays(spec, target)
            self._inv.execute()
            self._park(self._inv)
            if target is not out:
                _cast_into(out, target, self.threads)
        else:
            import scipy.fft

            # norm="forward": the inverse is unnormalised, the 1/N sits in the multiplier
            out[...] = scipy.fft.irfft2(spec, s=self.shape, norm="forward", workers=self.threads)
        self.transforms += 1
        self.seconds += time.perf_counter() - t0
        return out

    def _forward(self, x: np.ndarray, energy: bool) -> float:
        """Forward transform of ``x`` times the multiplier, kept as the pending product;
        returns the energy sum(x * y) when ``energy`` (else 0)."""
        t0 = time.perf_counter()
        if self.backend == "pyfftw":
            if not self._usable(x):
                if self._scratch is None:
                    self._scratch = self._aligned(self.dtype)
                _cast_into(self._scratch, x, self.threads)
                x = self._scratch
            self._fwd.update_arrays(x, self._spec)
            self._fwd.execute()
            self._park(self._fwd)
            spec = self._spec
        else:
            import scipy.fft

            spec = scipy.fft.rfft2(np.asarray(x, dtype=self.dtype), workers=self.threads)
        e = 0.0
        if self._radial is not None:
            nn = float(self.shape[0] * self.shape[1])
            with _NumbaThreads(self.threads):
                e = _multiply_radial(spec, self._radial, nn, self.shape[1], energy)
        elif energy:
            with _NumbaThreads(self.threads):
                e = _multiply_stored(spec, self._mult, self.shape[1])
        else:
            np.multiply(spec, self._mult, out=spec)
        self._pending = spec
        self.calls += 1
        self.transforms += 1
        self.seconds += time.perf_counter() - t0
        return e
