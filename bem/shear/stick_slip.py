"""Stick and slip under a tangential displacement of the rigid flat, for a given contact set.

The flat is displaced by delta_T (m) along x. On the contact set Omega_c (from a normal solve)
an element either sticks, moving with the flat, ``u_x = delta_T - s`` with s its slip
accumulated in earlier steps, or slips with a bounded traction ``|q| = q_max`` (Pa): Coulomb
``q_max = mu p`` or the paper's constant shear strength ``q_max = tau_0`` (E:Hertz_theory), slip
increment in the direction of q. nu = 1/2, so the tangential problem does not change the
normal one (:mod:`asperity.bem.elastic.tangential_influence`); loading is along x only (q_y = 0).

One quasi-static step is the convex box-constrained quadratic program (Kalker's incremental
principle)

    minimise 1/2 q.K q - q.(delta_T - s_prev)  over  -q_max <= q <= q_max on Omega_c, q = 0 off,

with K the Cerruti compliance: its gradient ``g = u_x - delta_T + s_prev`` is minus the slip
increment, so the optimality conditions are exactly stick (g = 0 where |q| < q_max) and slip in
the direction of the traction (g <= 0 where q = q_max, g >= 0 where q = -q_max). The history
enters through s only: for monotonic loading a single step from s = 0 gives the same state as
many (Cattaneo-Mindlin, :mod:`asperity.bem.reference_solutions`).

Solver: constrained conjugate gradients in the style of Polonsky & Keer, for two-sided bounds:
Dostal's MPRGP (modified proportioning with reduced gradient projections; Dostal & Schoeberl
2005, Comput. Optim. Appl. 30:23). Conjugate-gradient steps on the free set (|q| < q_max) while
they stay feasible; a step that would cross a bound is cut there and followed by a projected
gradient step of length 1/||K|| (the expansion, which binds elements); elements at a bound whose
gradient points inward are released by a proportioning step when that gradient outweighs the
free one. Each step costs one FFT convolution (two for an expansion). :func:`solve_tangential`
is not preconditioned; the shear curve of a rough surface
(:func:`asperity.bem.shear.rough.shear_curve`), which keeps one contact set for many steps, works
on that set only, with the operator as a dense matrix there (:class:`ContactMatrix`) and the
conjugate-gradient steps preconditioned by junction (:class:`JunctionPreconditioner`).

Convergence residual (the ``tol`` knob), as the normal solver's: the rms of the projected
gradient (m: stick violation on free elements, wrong-signed slip on bound ones) times the pixel
stiffness E*/sqrt(dx dy), over the rms traction on Omega_c: a relative rms traction error.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from asperity.bem.elastic.fft_backend import Convolution, default_threads
from asperity.bem.elastic.influence import influence_multiplier
from asperity.bem.elastic.tangential_influence import check_poisson, tangential_multiplier
from asperity.bem.errors import BemInputError

__all__ = [
    "BoxCGResult",
    "ContactMatrix",
    "JunctionPreconditioner",
    "ShearOptions",
    "TangentialOperator",
    "TangentialResult",
    "box_conjugate_gradients",
    "kernel_block",
    "solve_tangential",
    "traction_bound",
]


@dataclass(frozen=True)
class ShearOptions:
    """How the shear solvers iterate.

    Attributes
    ----------
    tol : float
        Convergence threshold on the relative rms traction residual (module docstring), in
        [1e-14, 1e-2].
    max_iter : int or None
        Iteration cap per linear solve (>= 1); None: ``max(1000, 4 max(nx, ny))``.
    fft_backend : {"auto", "pyfftw", "scipy"}
        FFT backend of :class:`asperity.bem.elastic.fft_backend.Convolution`.
    threads : int or None
        FFT threads; None: one thread on FFT grids below 512^2 points (measured on 200^2 with
        pyFFTW on a busy 2-core machine: 0.4 ms per convolution on one thread against 59 ms on
        two, OpenMP threads waiting on each other), all available cores above.
    dense_limit_bytes : int
        Solvers that keep one contact set for many solves
        (:func:`asperity.bem.shear.rough.shear_curve`) apply the operator as a dense matrix on
        that set (:class:`ContactMatrix`,
        ``8 n_c^2`` bytes) when it fits in this many bytes, and by FFT convolutions of the whole
        grid otherwise; 0: always FFT. Default 256 MiB: up to 5792 elements (the default
        job's 1000^2 map has 4918 at 2.08 N, 7451 at 3.12 N).
    precondition : bool
        Those solvers precondition the conjugate-gradient steps by junction
        (:class:`JunctionPreconditioner`); False: plain MPRGP.
    preload_load_factor : float
        > 1: the mixed-mode curve's preload
        (:func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`) loads to this
        multiple of F_z, then unloads to F_z (Pohrt-Popov); doubled while its rim holds too much
        of the unloaded contact.
    collapse_fraction : float
        In (0, 1): a junction whose area falls below this fraction of its area at the step's
        start has passed its instability (E:max_disp_PC).
    slide_margin : int
        >= 0: elements added round a sliding junction's footprint.
    load_tolerance : float
        In (0, 0.1]: relative error allowed on F_z in load control (at least 10 ``tol`` is
        used: the load cannot be closer than the conjugate-gradient solves).
    max_active_set : int
        >= 1: cap on the active-set iterations of one step.
    max_step_halvings : int
        In [0, 8]: a step of the mixed-mode curve that fails (its active set does not settle, a
        linear solve stalls, the load is not reached) is undone and retried as 2, 4, ...
        sub-steps of delta_T, at most ``2**max_step_halvings``; 0: no retry.
    rebond_slides : bool
        Under shear, a junction of the mixed-mode curve that an element it detached in the
        step penetrates again has passed its fold (the cascade overshot to the Hertz contact)
        and slides (issue 34; :mod:`asperity.bem.shear.mixed_mode`); False: such elements bond
        again where they stand (0.4.2).
    """

    tol: float = 1e-8
    max_iter: int | None = None
    fft_backend: str = "auto"
    threads: int | None = None
    dense_limit_bytes: int = 256 * 2**20
    precondition: bool = True
    preload_load_factor: float = 4.0
    collapse_fraction: float = 0.5
    slide_margin: int = 2
    load_tolerance: float = 1e-8
    max_active_set: int = 500
    max_step_halvings: int = 3
    rebond_slides: bool = True

    def __post_init__(self) -> None:
        self._check_curve_knobs()
        if not (
            isinstance(self.dense_limit_bytes, (int, np.integer)) and self.dense_limit_bytes >= 0
        ):
            raise BemInputError(
                "ShearOptions: dense_limit_bytes must be an integer >= 0 (bytes), got "
                f"{self.dense_limit_bytes!r}"
            )
        if not isinstance(self.precondition, (bool, np.bool_)):
            raise BemInputError(
                f"ShearOptions: precondition must be True or False, got {self.precondition!r}"
            )
        if not (isinstance(self.tol, (int, float)) and 1e-14 <= self.tol <= 1e-2):
            raise BemInputError(f"ShearOptions: tol must be in [1e-14, 1e-2], got {self.tol!r}")
        if self.max_iter is not None and not (
            isinstance(self.max_iter, (int, np.integer)) and 1 <= self.max_iter <= 10**6
        ):
            raise BemInputError(
                f"ShearOptions: max_iter must be an integer in [1, 10^6] or None, "
                f"got {self.max_iter!r}"
            )
        if self.fft_backend not in ("auto", "pyfftw", "scipy"):
            raise BemInputError(
                "ShearOptions: fft_backend must be 'auto', 'pyfftw' or 'scipy', "
                f"got {self.fft_backend!r}"
            )

    def _check_curve_knobs(self) -> None:
        """The knobs of the mixed-mode curve: a BemInputError naming the one out of range."""
        factor = self.preload_load_factor
        if not (isinstance(factor, (int, float)) and math.isfinite(factor) and factor > 1):
            raise BemInputError(f"preload_load_factor: expected a number > 1, got {factor!r}")
        frac = self.collapse_fraction
        if not (isinstance(frac, (int, float)) and 0.0 < frac < 1.0):
            raise BemInputError(f"collapse_fraction: expected in (0, 1), got {frac!r}")
        for name, low, high in (
            ("slide_margin", 0, 10**6),
            ("max_active_set", 1, 10**6),
            ("max_step_halvings", 0, 8),
        ):
            val = getattr(self, name)
            if not (
                isinstance(val, (int, np.integer))
                and not isinstance(val, bool)
                and low <= val <= high
            ):
                raise BemInputError(f"{name}: expected an integer in [{low}, {high}], got {val!r}")
        if not isinstance(self.rebond_slides, (bool, np.bool_)):
            raise BemInputError(
                f"rebond_slides: expected True or False, got {self.rebond_slides!r}"
            )
        tol = self.load_tolerance
        if not (isinstance(tol, (int, float)) and 0.0 < tol <= 0.1):
            raise BemInputError(f"load_tolerance: expected a number in (0, 0.1], got {tol!r}")

    def max_iterations(self, shape: tuple[int, int]) -> int:
        """The iteration cap for a grid of ``shape``."""
        return self.max_iter if self.max_iter is not None else max(1000, 4 * max(shape))


class TangentialOperator:
    """u_x = K q on a height-map grid (free or periodic), with its FFT plan kept for reuse.

    Parameters
    ----------
    shape : (int, int)
        Grid shape (pixels).
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa), nu = 1/2.
    periodic : bool
        Periodic domain, or a free one (zero-padded doubled grid).
    fft_backend, threads
        As :class:`asperity.bem.elastic.fft_backend.Convolution`; threads None: as
        :class:`ShearOptions`.
    normal : bool
        Build the normal (Boussinesq) operator u_z = K p instead, from
        :func:`asperity.bem.elastic.influence.influence_multiplier` (point kernel when periodic,
        Love's patch when free): the same machinery serves both problems of the mixed-mode solver.
    """

    def __init__(
        self,
        shape: tuple[int, int],
        dx: float,
        dy: float,
        e_star: float,
        *,
        periodic: bool = True,
        fft_backend: str = "auto",
        threads: int | None = None,
        normal: bool = False,
    ) -> None:
        self.shape = (int(shape[0]), int(shape[1]))
        if normal:
            mult, grid = influence_multiplier(self.shape, dx, dy, e_star, periodic=periodic)
        else:
            mult, grid = tangential_multiplier(self.shape, dx, dy, e_star, periodic=periodic)
        self.periodic = periodic
        self.normal = normal
        self.grid = grid
        self.norm = float(np.max(np.abs(mult)))  # ||K||_2 of the circulant operator (m/Pa)
        if threads is None:
            threads = 1 if grid[0] * grid[1] < 512 * 512 else default_threads()
        self.conv = Convolution(mult, grid, backend=fft_backend, threads=threads)
        self._buf = self.conv.zeros()
        self._out = self.conv.zeros()
        self._kernel: np.ndarray | None = None
        self.calls = 0

    def kernel(self) -> np.ndarray:
        """The real-space kernel (m/Pa) on the height-map grid: the response to a unit traction
        (1 Pa) on element (0, 0), i.e. the displacement at offsets ``(i, j)`` pixels (modulo the
        grid when periodic; for a free grid the offsets ``(-i, j)``, ``(i, -j)`` have the same
        value: both kernels of this module are even in x and in y). One convolution, kept."""
        if self._kernel is None:
            impulse = np.zeros(self.shape)
            impulse[0, 0] = 1.0
            self._kernel = self(impulse)
        return self._kernel

    def __call__(self, q: np.ndarray) -> np.ndarray:
        """Displacement (m) of the tractions ``q`` (Pa) on the height-map grid (a new array)."""
        self.calls += 1
        if self.periodic:
            self._buf[...] = q
        else:
            nx, ny = self.shape
            self._buf[:nx, :ny] = q
        self.conv(self._buf, self._out)
        return self._out[: self.shape[0], : self.shape[1]].copy()


@njit(cache=True, fastmath=False)
def _matvec(matrix, v, out):  # pragma: no cover - compiled
    """``out = matrix @ v`` on one thread (four partial sums per row).

    BLAS would use every core: on a shared machine its threads wait on each other (a 1313^2
    product measured 2.2 ms on one thread against 29 ms on two, load 12 on 2 cores), as the FFT
    threads do (:class:`ShearOptions`)."""
    n, k = matrix.shape
    k4 = k - k % 4
    for i in range(n):
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        a3 = 0.0
        for j in range(0, k4, 4):
            a0 += matrix[i, j] * v[j]
            a1 += matrix[i, j + 1] * v[j + 1]
            a2 += matrix[i, j + 2] * v[j + 2]
            a3 += matrix[i, j + 3] * v[j + 3]
        for j in range(k4, k):
            a0 += matrix[i, j] * v[j]
        out[i] = (a0 + a1) + (a2 + a3)
    return out


@njit(cache=True, fastmath=False)
def _matvec_rows(matrix, rows, v, out):  # pragma: no cover - compiled
    """``out += matrix @ v`` for a symmetric ``matrix`` and ``v`` zero off ``rows``: the sum of
    ``v[r] matrix[r, :]`` (contiguous rows), ``len(rows) n`` operations."""
    n = matrix.shape[1]
    for r in rows:
        s = v[r]
        for k in range(n):
            out[k] += s * matrix[r, k]
    return out


@njit(cache=True, fastmath=False)
def _fill_matrix(kernel, ix, iy, periodic, out):  # pragma: no cover - compiled
    """``out[a, b] = kernel[offset(ix[a] - ix[b]), offset(iy[a] - iy[b])]`` (as
    :func:`kernel_block` for the same elements on both sides)."""
    nx, ny = kernel.shape
    n = ix.size
    for a in range(n):
        for b in range(n):
            di = ix[a] - ix[b]
            dj = iy[a] - iy[b]
            if di < 0:
                di = di + nx if periodic else -di
            if dj < 0:
                dj = dj + ny if periodic else -dj
            out[a, b] = kernel[di, dj]
    return out


@njit(cache=True, fastmath=False)
def _cholesky(a):  # pragma: no cover - compiled
    """Lower Cholesky factor L of the symmetric positive definite ``a`` (a new array; rows of L
    read contiguously), and 0, or the failing column + 1 when ``a`` is not positive definite.

    One thread, as :func:`_matvec` (LAPACK's threads wait on each other on a shared machine:
    a 250^2 factorisation and solve measured 64 ms under load 20)."""
    n = a.shape[0]
    low = np.zeros((n, n))
    for j in range(n):
        s = a[j, j]
        for k in range(j):
            s -= low[j, k] * low[j, k]
        if not s > 0.0:
            return low, j + 1
        d = np.sqrt(s)
        low[j, j] = d
        for i in range(j + 1, n):
            t = a[i, j]
            for k in range(j):
                t -= low[i, k] * low[j, k]
            low[i, j] = t / d
    return low, 0


@njit(cache=True, fastmath=False)
def _cholesky_solve(low, b):  # pragma: no cover - compiled
    """``z`` with ``L L^T z = b`` for the factor of :func:`_cholesky` (rows read contiguously)."""
    n = b.size
    y = b.copy()
    for i in range(n):
        t = y[i]
        for k in range(i):
            t -= low[i, k] * y[k]
        y[i] = t / low[i, i]
    for i in range(n - 1, -1, -1):
        y[i] /= low[i, i]
        zi = y[i]
        for k in range(i):
            y[k] -= zi * low[i, k]
    return y


def kernel_block(
    kernel: np.ndarray,
    ix_a: np.ndarray,
    iy_a: np.ndarray,
    ix_b: np.ndarray,
    iy_b: np.ndarray,
    *,
    periodic: bool,
) -> np.ndarray:
    """Entries ``K[a, b]`` (m/Pa) between elements at pixels ``(ix_a, iy_a)`` and
    ``(ix_b, iy_b)`` from a real-space kernel of :meth:`TangentialOperator.kernel` (offsets taken
    modulo the grid when periodic, by absolute value when free)."""
    di = ix_a[:, None] - ix_b[None, :]
    dj = iy_a[:, None] - iy_b[None, :]
    if periodic:
        di %= kernel.shape[0]
        dj %= kernel.shape[1]
    else:
        np.abs(di, out=di)
        np.abs(dj, out=dj)
    return kernel[di, dj]


class JunctionPreconditioner:
    """Block-Jacobi preconditioner of the tangential operator on the free set, one block per
    junction (connected contact cluster).

    On a rough surface the junctions are far apart compared with their size, so the operator
    restricted to the contact set is nearly block-diagonal by junction, and its condition number
    (which grows with the junction's size in elements, as that of the discretised 1/r kernel)
    is in the blocks. ``M^-1 phi`` solves, for each junction J, ``K[F_J, F_J] z_J = phi_J`` on
    its free (sticking) elements F_J by a Cholesky factorisation (reused while F_J shrinks a
    little: ``refactor_fraction``); single
    free elements and junctions above ``max_block`` free elements take the diagonal
    ``z = phi / K_00`` instead. Symmetric positive definite for a fixed free set, as
    :func:`_mprgp` needs.

    Parameters
    ----------
    kernel : ndarray
        Real-space kernel (m/Pa), :meth:`TangentialOperator.kernel`.
    index : ndarray of int
        Flat indices (C order, on the grid of ``shape``) of the contact elements: the entries of
        the gathered vectors.
    labels : ndarray of int
        The junction of each contact element (same length as ``index``).
    shape : (int, int)
        The height-map grid.
    periodic : bool
        As the operator.
    max_block : int
        Largest block factorised (its cost grows as the cube).
    refactor_fraction : float
        A junction's factor is kept while its free set F is a subset of the set F' it was
        computed on (``M^-1`` on F is then the restriction of ``K[F', F']^-1``, still symmetric
        positive definite) and has lost at most this fraction of F'; 0: refactor on every
        change. Under increasing shear the stick zones shrink, so factors are reused.
    """

    def __init__(
        self,
        kernel: np.ndarray,
        index: np.ndarray,
        labels: np.ndarray,
        shape: tuple[int, int],
        *,
        periodic: bool,
        max_block: int = 1500,
        refactor_fraction: float = 0.25,
    ) -> None:
        if not 0.0 <= refactor_fraction < 1.0:
            raise BemInputError(
                f"refactor_fraction: expected a number in [0, 1), got {refactor_fraction!r}"
            )
        self.refactor_fraction = float(refactor_fraction)
        ix, iy = np.divmod(np.asarray(index), shape[1])
        self.diagonal = float(kernel[0, 0])
        order = np.argsort(labels, kind="stable")
        _, starts = np.unique(labels[order], return_index=True)
        groups = np.split(order, starts[1:])
        self.groups = [grp for grp in groups if 1 < grp.size]
        self._order = np.concatenate(self.groups) if self.groups else np.zeros(0, dtype=int)
        self._starts = np.cumsum([0] + [g.size for g in self.groups[:-1]]).astype(np.intp)
        self.blocks = [
            kernel_block(kernel, ix[g], iy[g], ix[g], iy[g], periodic=periodic)
            if g.size <= max_block
            else None
            for g in self.groups
        ]
        self._factors: dict[int, tuple[bytes, object]] = {}
        self.factorisations = 0

    def __call__(self, phi: np.ndarray, free: np.ndarray) -> np.ndarray:
        """``M^-1 phi`` (Pa) for the free gradient ``phi`` (m, zero off ``free``)."""
        z = phi / self.diagonal
        # free elements per junction in one pass; junctions with fewer than two are diagonal
        if not self.groups:
            return z
        counts = np.add.reduceat(free[self._order].astype(np.intp), self._starts)
        for j in np.flatnonzero(counts >= 2):
            members, block = self.groups[j], self.blocks[j]
            if block is None:
                continue
            f = free[members]
            n_f = int(counts[j])
            cached = self._factors.get(j)
            if (
                cached is None
                or n_f < (1.0 - self.refactor_fraction) * cached[2]
                or bool(np.any(f & ~cached[0]))
            ):
                factor, info = _cholesky(np.ascontiguousarray(block[np.ix_(f, f)]))
                if info != 0:
                    raise BemInputError(
                        f"JunctionPreconditioner: the block of junction {j} is not positive "
                        f"definite (Cholesky fails at its free element {info - 1})"
                    )
                cached = (f, factor, n_f)
                self._factors[j] = cached
                self.factorisations += 1
            # the factor of a superset F' of the free set: phi is 0 on F' \ F, and the
            # restriction of K[F', F']^-1 to F is symmetric positive definite
            sol = _cholesky_solve(cached[1], np.ascontiguousarray(phi[members[cached[0]]]))
            z[members[f]] = sol[f[cached[0]]]
        return z


class ContactMatrix:
    """An operator of this module restricted to a fixed set of elements, as a dense matrix.

    On a rough surface the contact set is a small part of the grid (0.5 % of the default job's
    map), so ``K`` restricted to it, ``n_c x n_c`` entries, is cheaper to apply than an FFT
    convolution of the whole grid whenever ``n_c^2`` is below a few times ``nx ny log(nx ny)``
    (``benchmarks/bem_shear.py`` measures both). The entries are the operator's own real-space
    kernel, taken from its response to one unit impulse (one convolution), so both
    representations give the same products up to rounding (``tests/bem/test_bem_shear_speed.py``).
    Both kernels of this module (Boussinesq's and Cerruti's u_x from q_x) are even in x and in y,
    which gives the negative offsets of a free (non-periodic) grid.

    Parameters
    ----------
    operator : TangentialOperator
        The operator (tangential or normal, periodic or free) on the height-map grid.
    mask : ndarray of bool, shape ``operator.shape``
        The elements kept; vectors are their entries in C order (``np.flatnonzero(mask)``).

    Attributes
    ----------
    matrix : ndarray, shape (n_c, n_c)
        K (m/Pa) between the kept elements.
    size : int
        n_c.
    norm : float
        An upper bound of the largest eigenvalue (m/Pa): the full operator's.
    calls : int
        Products computed.
    """

    def __init__(self, operator: TangentialOperator, mask: np.ndarray) -> None:
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != operator.shape:
            raise BemInputError(
                f"mask: expected shape {operator.shape} (the operator's grid), got {mask.shape}"
            )
        kernel = operator.kernel()
        idx = np.flatnonzero(mask)
        ix, iy = np.divmod(idx, operator.shape[1])
        n_c = idx.size
        self.matrix = _fill_matrix(kernel, ix, iy, bool(operator.periodic), np.empty((n_c, n_c)))
        self.size = n_c
        self.norm = operator.norm
        self.calls = 0

    @staticmethod
    def nbytes(count: int) -> int:
        """Bytes of the matrix for ``count`` elements (float64)."""
        return 8 * int(count) * int(count)

    def __call__(self, v: np.ndarray) -> np.ndarray:
        """``K v`` (m) for tractions ``v`` (Pa) on the kept elements."""
        self.calls += 1
        v = np.ascontiguousarray(v, dtype=np.float64)
        rows = np.flatnonzero(v)
        if 10 * rows.size < 9 * self.size:
            # a vector on few elements (a stick zone, the elements a step changed): only
            # their rows, read contiguously (the matrix is symmetric)
            return _matvec_rows(self.matrix, rows, v, np.zeros(self.size))
        return _matvec(self.matrix, v, np.empty(self.size))


@dataclass
class BoxCGResult:
    """Outcome of :func:`box_conjugate_gradients` (scipy-like)."""

    x: np.ndarray
    gradient: np.ndarray
    success: bool
    status: int
    message: str
    nit: int
    residual: float
    convolutions: int


def box_conjugate_gradients(
    apply: Callable[[np.ndarray], np.ndarray],
    rhs: np.ndarray,
    mask: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    x0: np.ndarray,
    *,
    norm: float,
    scale: float,
    tol: float,
    max_iter: int,
    restricted: Callable[[np.ndarray], np.ndarray] | None = None,
) -> BoxCGResult:
    """Minimise ``1/2 x.A x - x.rhs`` over ``lower <= x <= upper`` on ``mask`` (x = 0 off it).

    MPRGP (module docstring); plain conjugate gradients when every bound is infinite.
    ``A v = mask * apply(mask * v)`` must be symmetric positive definite on the mask; ``norm``
    bounds its largest eigenvalue; ``scale`` converts the projected gradient to the residual's
    units (``residual = rms(g_P) * scale / rms(x)``, 0 when g_P = 0). The iteration works on the
    masked entries only (gathered vectors).

    Parameters
    ----------
    restricted : callable, optional
        ``A`` acting directly on the gathered vectors (the masked entries in C order), e.g. a
        :class:`ContactMatrix` built for this ``mask``; then ``apply`` is not called.

    Returns
    -------
    BoxCGResult
        ``x`` and ``gradient`` (A x - rhs on the mask, 0 off it) as full arrays; status 0:
        converged (residual <= tol); 1: iteration cap; 2: non-finite values or non-positive
        curvature. ``convolutions`` counts the operator applications.
    """
    shape = mask.shape
    idx = np.flatnonzero(mask)
    lo = np.asarray(lower, dtype=np.float64).ravel()[idx]
    hi = np.asarray(upper, dtype=np.float64).ravel()[idx]
    b = np.asarray(rhs, dtype=np.float64).ravel()[idx]
    x = np.clip(np.asarray(x0, dtype=np.float64).ravel()[idx], lo, hi)
    calls = 0
    if restricted is not None:
        if getattr(restricted, "size", idx.size) != idx.size:
            raise BemInputError(
                f"restricted: built for {restricted.size} elements, the mask has {idx.size}"
            )

        def a_of(v: np.ndarray) -> np.ndarray:
            nonlocal calls
            calls += 1
            return restricted(v)

    else:
        full = np.zeros(shape)
        flat = full.reshape(-1)

        def a_of(v: np.ndarray) -> np.ndarray:
            nonlocal calls
            calls += 1
            flat[idx] = v
            return np.asarray(apply(full)).reshape(-1)[idx]

    x, g, status, message, nit, res = _mprgp(
        a_of, b, lo, hi, x, norm=norm, scale=scale, tol=tol, max_iter=max_iter
    )
    xf = np.zeros(shape)
    xf.reshape(-1)[idx] = x
    gf = np.zeros(shape)
    gf.reshape(-1)[idx] = g
    return BoxCGResult(xf, gf, status == 0, status, message, nit, res, calls)


_NOT_POSITIVE = "non-positive curvature (operator not positive definite)"

#: ``(x, g, status, message, nit, residual)`` of :func:`_mprgp`.
_Outcome = tuple[np.ndarray, np.ndarray, int, str, int, float]


@dataclass(frozen=True)
class _BoxProblem:
    """The box-constrained quadratic program of :func:`_mprgp` on gathered vectors:
    minimise ``1/2 x.A x - x.b`` over ``lo <= x <= hi`` (x tractions in Pa, ``A x`` and ``b``
    displacements in m; Kalker's incremental principle, module docstring).

    Attributes
    ----------
    a_of : callable
        ``v -> A v`` (Pa -> m), symmetric positive definite.
    b : ndarray
        Right-hand side (m).
    lo, hi : ndarray
        Bounds (Pa), ``-q_max`` and ``q_max`` (tau_0 of E:Hertz_theory, or mu p); infinite where
        unbounded.
    alpha_bar : float
        Expansion step length 1/||A|| (Pa/m).
    scale : float
        Pixel stiffness E*/sqrt(dx dy) (Pa/m) of the residual.
    precondition : callable or None
        ``(phi, free) -> M^-1 phi`` on the free set (:class:`JunctionPreconditioner`).
    sparse_updates : bool
        Update the gradient after an expansion by the product of the change of x.
    """

    a_of: Callable[[np.ndarray], np.ndarray]
    b: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    alpha_bar: float
    scale: float
    precondition: Callable[[np.ndarray, np.ndarray], np.ndarray] | None
    sparse_updates: bool

    def residual(self, x: np.ndarray, gp2: float) -> float:
        """The relative rms traction residual (module docstring) of tractions ``x`` (Pa) whose
        projected gradient has squared norm ``gp2`` (m^2); 0 when it is 0, inf when x = 0."""
        if gp2 == 0.0:
            return 0.0
        n_m = max(x.size, 1)
        xr = math.sqrt(float(x @ x) / n_m)
        return math.sqrt(gp2 / n_m) * self.scale / xr if xr > 0 else math.inf

    def parts(self, x: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The gradient ``g`` (m) at ``x`` split: the free gradient phi (on |x| inside the bounds:
        stick violation), the chopped gradient beta (on elements at a bound whose gradient points
        inward: wrong-signed slip), and the free set (bool)."""
        at_lo = x <= self.lo
        at_hi = (x >= self.hi) & ~at_lo
        free = ~at_lo & ~at_hi
        phi = np.where(free, g, 0.0)
        beta = np.where(at_lo, np.minimum(g, 0.0), 0.0) + np.where(at_hi, np.maximum(g, 0.0), 0.0)
        return phi, beta, free

    def max_step(self, x: np.ndarray, p: np.ndarray) -> float:
        """The largest feasible step length (Pa/m) along ``-p`` from ``x``: where the first
        element reaches its bound (inf if none does)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            down = np.where(p > 0, (x - self.lo) / p, np.inf)
            up = np.where(p < 0, (x - self.hi) / p, np.inf)
        return float(min(down.min(), up.min()))

    def direction(self, phi: np.ndarray, free: np.ndarray) -> np.ndarray:
        """A new search direction from the free gradient: phi, or ``M^-1 phi`` (preconditioned)."""
        return phi.copy() if self.precondition is None else self.precondition(phi, free)


@dataclass
class _Iterate:
    """The state of one MPRGP iteration: tractions x (Pa), gradient g = A x - b (m), its free
    and chopped parts phi, beta (m) and the free set, search direction p, iterations done and
    the residual of x."""

    x: np.ndarray
    g: np.ndarray
    phi: np.ndarray = field(init=False)
    beta: np.ndarray = field(init=False)
    free: np.ndarray = field(init=False)
    p: np.ndarray = field(init=False)
    nit: int = 0
    res: float = 0.0


def _restart(qp: _BoxProblem, it: _Iterate) -> None:
    """Split the gradient at the current x and restart the search direction from it."""
    it.phi, it.beta, it.free = qp.parts(it.x, it.g)
    it.p = qp.direction(it.phi, it.free)


def _projected_residual(qp: _BoxProblem, it: _Iterate) -> float:
    """The residual of the projected gradient phi + beta (stopping test's measure)."""
    return qp.residual(it.x, float(it.phi @ it.phi + it.beta @ it.beta))


def _stopping_test(res: float, nit: int, tol: float, max_iter: int) -> tuple[int, str] | None:
    """``(status, message)`` as scipy.optimize when the iteration ends (2: a non-finite
    residual, 0: ``res <= tol``, 1: ``nit >= max_iter``), None to go on."""
    if not math.isfinite(res) and res != math.inf:
        return 2, "non-finite values in the iteration"
    if res <= tol:
        return 0, "converged"
    if nit >= max_iter:
        return 1, "iteration limit reached"
    return None


def _proportional(qp: _BoxProblem, it: _Iterate) -> bool:
    """Dostal's proportioning test: ``beta.beta <= phi_red.phi``, with phi_red the free gradient
    reduced to the steps of length ``alpha_bar`` that stay feasible. True: the iterate is
    proportional (work on the free set); False: release elements by a proportioning step."""
    x, phi = it.x, it.phi
    with np.errstate(divide="ignore", invalid="ignore"):
        phi_red = np.where(
            phi > 0,
            np.minimum((x - qp.lo) / qp.alpha_bar, phi),
            np.where(phi < 0, np.maximum((x - qp.hi) / qp.alpha_bar, phi), 0.0),
        )
    return float(it.beta @ it.beta) <= float(phi_red @ phi)


def _free_set_step(qp: _BoxProblem, it: _Iterate) -> bool:
    """A conjugate-gradient step on the free set; when it would cross a bound, the step cut at
    the bound and an expansion (:func:`_expansion_step`). False: non-positive curvature."""
    ap = qp.a_of(it.p)
    pap = float(it.p @ ap)
    if not pap > 0.0:
        return False
    a_cg = float(it.g @ it.p) / pap
    a_f = qp.max_step(it.x, it.p)
    if a_cg <= a_f:
        _conjugate_gradient_step(qp, it, a_cg, ap, pap)
    else:
        _expansion_step(qp, it, a_cg, a_f, ap)
    return True


def _conjugate_gradient_step(
    qp: _BoxProblem, it: _Iterate, a_cg: float, ap: np.ndarray, pap: float
) -> None:
    """The feasible conjugate-gradient step of length ``a_cg`` along ``-p`` (``ap = A p``,
    ``pap = p.A p``), then the next direction, A-conjugate to p on the free set."""
    it.x -= a_cg * it.p
    it.g -= a_cg * ap
    it.phi, it.beta, it.free = qp.parts(it.x, it.g)
    z = it.phi if qp.precondition is None else qp.precondition(it.phi, it.free)
    gamma = float(z @ ap) / pap
    it.p = z - gamma * it.p
    it.p[~it.free] = 0.0


def _expansion_step(qp: _BoxProblem, it: _Iterate, a_cg: float, a_f: float, ap: np.ndarray) -> None:
    """The conjugate-gradient step cut at the first bound (``a_f``), then either the projection
    of the whole step (preconditioned only, :func:`_projected_cg_step`) or the projected
    gradient step of length ``alpha_bar`` (:func:`_projected_gradient_step`); both bind
    elements. The search direction restarts."""
    x_cg = it.x - a_cg * it.p if qp.precondition is not None else None
    before = (it.x.copy(), it.g.copy()) if x_cg is not None and qp.sparse_updates else None
    it.x -= a_f * it.p
    it.g -= a_f * ap
    projected = None if x_cg is None else _projected_cg_step(qp, it, x_cg, before)
    it.x, it.g = projected if projected is not None else _projected_gradient_step(qp, it)
    _restart(qp, it)


def _projected_cg_step(
    qp: _BoxProblem,
    it: _Iterate,
    x_cg: np.ndarray,
    before: tuple[np.ndarray, np.ndarray] | None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """The projection onto the box of the whole conjugate-gradient step ``x_cg`` (Pa): it binds
    at once every element the step pushes out. Its ``(x, g)`` when its energy
    ``1/2 x.(g - b)`` is at most the cut step's (``it``), else None. ``before``: ``(x, g)``
    before the cut step, for the sparse gradient update."""
    x_try = np.clip(x_cg, qp.lo, qp.hi)
    if before is not None:
        g_try = before[1] + qp.a_of(x_try - before[0])
    else:
        g_try = qp.a_of(x_try) - qp.b
    if float(x_try @ (g_try - qp.b)) <= float(it.x @ (it.g - qp.b)):
        return x_try, g_try
    return None


def _projected_gradient_step(qp: _BoxProblem, it: _Iterate) -> tuple[np.ndarray, np.ndarray]:
    """The expansion proper: the projection onto the box of the gradient step of length
    ``alpha_bar`` along the free gradient; its ``(x, g)``."""
    phi, _, _ = qp.parts(it.x, it.g)
    x = np.clip(it.x - qp.alpha_bar * phi, qp.lo, qp.hi)
    g = it.g + qp.a_of(x - it.x) if qp.sparse_updates else qp.a_of(x) - qp.b
    return x, g


def _proportioning_step(qp: _BoxProblem, it: _Iterate) -> bool:
    """Release elements at a bound whose gradient points inward: a minimising step along the
    chopped gradient beta, cut at the box; the search direction restarts. False: non-positive
    curvature."""
    d = it.beta
    ad = qp.a_of(d)
    dad = float(d @ ad)
    if not dad > 0.0:
        return False
    a = min(float(it.g @ d) / dad, qp.max_step(it.x, d))
    it.x = np.clip(it.x - a * d, qp.lo, qp.hi)
    it.g -= a * ad
    _restart(qp, it)
    return True


def _unbounded_cg(
    qp: _BoxProblem, x: np.ndarray, g: np.ndarray, tol: float, max_iter: int
) -> _Outcome:
    """Plain conjugate gradients, for a box with every bound infinite (full stick)."""
    p = g.copy()
    gg = float(g @ g)
    res = qp.residual(x, gg)
    nit = 0
    while (stop := _stopping_test(res, nit, tol, max_iter)) is None:
        nit += 1
        ap = qp.a_of(p)
        pap = float(p @ ap)
        if not pap > 0.0:
            return x, g, 2, _NOT_POSITIVE, nit, res
        a = gg / pap
        x -= a * p
        g -= a * ap
        gg_new = float(g @ g)
        p *= gg_new / gg
        p += g
        gg = gg_new
        res = qp.residual(x, gg)
    return x, g, *stop, nit, res


def _mprgp(
    a_of: Callable[[np.ndarray], np.ndarray],
    b: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    x: np.ndarray,
    *,
    norm: float,
    scale: float,
    tol: float,
    max_iter: int,
    precondition: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
    g0: np.ndarray | None = None,
    sparse_updates: bool = False,
) -> _Outcome:
    """The MPRGP iteration on gathered vectors (``x`` feasible, modified in place or replaced).

    Each iteration is the proportioning test (:func:`_proportional`), then a step on the free
    set (:func:`_free_set_step`: conjugate gradients, or the expansion when a bound is crossed)
    or a proportioning step (:func:`_proportioning_step`), then the stopping test
    (:func:`_stopping_test`) on the projected gradient's residual.

    Parameters
    ----------
    a_of : callable
        ``v -> A v``: tractions (Pa) to displacements (m), symmetric positive definite.
    b : ndarray
        Right-hand side (m): ``delta_T - s_prev`` for the tangential step.
    lo, hi : ndarray
        Bounds (Pa), ``-q_max`` and ``q_max``; all infinite: plain conjugate gradients.
    x : ndarray
        A feasible start (Pa).
    norm : float
        An upper bound of the largest eigenvalue of A (m/Pa).
    scale : float
        Pixel stiffness E*/sqrt(dx dy) (Pa/m) of the residual (module docstring).
    tol : float
        Residual to reach.
    max_iter : int
        Iteration cap.
    precondition : callable, optional
        ``precondition(phi, free)``: an approximation of ``A_FF^-1 phi`` on the free set
        (zero elsewhere), symmetric positive definite for a fixed free set. It is used in the
        conjugate-gradient steps (preconditioning in face, as in Dostal's Optimal Quadratic
        Programming Algorithms, Springer 2009); the proportioning test, the proportioning step
        and the stopping test keep the plain gradient. With it, a step cut by a bound first
        tries the projection onto the box of the whole conjugate-gradient step (it binds at once
        every element that step pushes out, where the cut step binds one): kept when its energy
        ``1/2 x.(g - b)`` is at most the cut step's, else the usual expansion follows, so the
        energy still decreases at every iteration.
    g0 : ndarray, optional
        The gradient ``A x - b`` (m) at the start, when the caller has it (saves a product).
    sparse_updates : bool
        After an expansion the gradient is updated by the product of the change of x (non-zero
        on the free set only) instead of recomputed from x, so that every product acts on a
        vector supported on the free set or on the elements released (cheap for
        :class:`ContactMatrix`; rounding accumulates as in the conjugate-gradient updates).

    Returns
    -------
    tuple
        ``(x, g, status, message, nit, residual)``: status 0 converged, 1 iteration cap,
        2 non-finite values or non-positive curvature.
    """
    alpha_bar = 1.0 / norm
    if x.size == 0:
        return x, np.zeros(0), 0, "converged", 0, 0.0
    qp = _BoxProblem(a_of, b, lo, hi, alpha_bar, scale, precondition, sparse_updates)
    g = a_of(x) - b if g0 is None else g0
    if np.all(np.isinf(lo)) and np.all(np.isinf(hi)):
        return _unbounded_cg(qp, x, g, tol, max_iter)
    it = _Iterate(x, g)
    _restart(qp, it)
    it.res = _projected_residual(qp, it)
    while (stop := _stopping_test(it.res, it.nit, tol, max_iter)) is None:
        it.nit += 1
        moved = _free_set_step(qp, it) if _proportional(qp, it) else _proportioning_step(qp, it)
        if not moved:
            return it.x, it.g, 2, _NOT_POSITIVE, it.nit, it.res
        it.res = _projected_residual(qp, it)
    return it.x, it.g, *stop, it.nit, it.res


def traction_bound(
    contact: np.ndarray,
    *,
    pressure: np.ndarray | None = None,
    friction_coefficient: float | None = None,
    shear_strength: float | None = None,
) -> np.ndarray:
    """The slip threshold q_max (Pa) per element: Coulomb ``mu max(p, 0)`` or constant ``tau_0``.

    Exactly one of ``friction_coefficient`` (with ``pressure``, Pa) or ``shear_strength`` (Pa).
    Zero off the contact set.
    """
    if (friction_coefficient is None) == (shear_strength is None):
        raise BemInputError(
            "traction_bound: give exactly one of friction_coefficient (Coulomb) or "
            f"shear_strength (tau_0), got {friction_coefficient!r} and {shear_strength!r}"
        )
    if friction_coefficient is not None:
        if not (math.isfinite(friction_coefficient) and friction_coefficient >= 0):
            raise BemInputError(
                f"friction_coefficient: expected a finite number >= 0, got {friction_coefficient}"
            )
        if pressure is None:
            raise BemInputError("traction_bound: Coulomb friction needs the pressure (Pa)")
        return np.where(contact, friction_coefficient * np.maximum(pressure, 0.0), 0.0)
    if not (math.isfinite(shear_strength) and shear_strength >= 0):
        raise BemInputError(
            f"shear_strength: expected a finite number >= 0 (Pa), got {shear_strength}"
        )
    return np.where(contact, float(shear_strength), 0.0)


@dataclass
class TangentialResult:
    """One tangential step (SI units).

    Attributes
    ----------
    traction : ndarray
        q_x (Pa) on each element; 0 off the contact set.
    displacement : ndarray
        u_x (m) on the contact set (NaN off it: not computed, it costs a convolution).
    slip : ndarray
        Accumulated slip s = delta_T - u_x (m) for slipping elements, the previous value for
        sticking and non-contact ones: the ``slip`` argument of the next step.
    contact, stick : ndarray of bool
        The contact set and its sticking elements (|q| < q_max).
    tangential_displacement : float
        delta_T (m).
    tangential_force : float
        F_x = sum q dx dy (N).
    stick_area, slip_area : float
        Areas (m^2) of the sticking and slipping elements.
    success, status, message, nit, residual
        As scipy.optimize (status 0 converged, 1 iteration cap, 2 numerical failure);
        ``residual`` as the module docstring.
    convolutions : int
        FFT convolutions used.
    seconds : float
        Wall time (s).
    """

    traction: np.ndarray
    displacement: np.ndarray
    slip: np.ndarray
    contact: np.ndarray
    stick: np.ndarray
    tangential_displacement: float
    tangential_force: float
    stick_area: float
    slip_area: float
    success: bool
    status: int
    message: str
    nit: int
    residual: float
    convolutions: int
    seconds: float


def solve_tangential(
    contact: np.ndarray,
    bound: np.ndarray | None,
    dx: float,
    dy: float,
    e_star: float,
    tangential_displacement: float,
    *,
    slip: np.ndarray | None = None,
    initial: np.ndarray | TangentialResult | None = None,
    periodic: bool = True,
    poisson_ratio: float = 0.5,
    options: ShearOptions | None = None,
    operator: TangentialOperator | None = None,
) -> TangentialResult:
    """Stick/slip tractions for the flat displaced by ``tangential_displacement`` along x.

    Parameters
    ----------
    contact : ndarray of bool, shape (nx, ny)
        The contact set Omega_c (e.g. ``ContactResult.contact`` of a normal solve).
    bound : ndarray or None
        Slip threshold q_max >= 0 (Pa) per element (:func:`traction_bound`); None: full stick
        (no slip anywhere).
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa).
    tangential_displacement : float
        delta_T (m), the flat's displacement along x from the unloaded reference.
    slip : ndarray, optional
        Slip accumulated before this step (m), the previous result's ``slip``; default zero.
    initial : ndarray or TangentialResult, optional
        Warm start: tractions (Pa) of a previous step.
    periodic : bool
        Periodic domain (default) or a free one.
    poisson_ratio : float
        Must be 0.5 (:func:`asperity.bem.elastic.tangential_influence.check_poisson`).
    options : ShearOptions, optional
        Tolerance, iteration cap, FFT backend.
    operator : TangentialOperator, optional
        A prepared operator for this grid (saves the FFT planning across steps).

    Returns
    -------
    TangentialResult
    """
    t0 = time.perf_counter()
    check_poisson(poisson_ratio)
    opts = options if options is not None else ShearOptions()
    contact = _checked_contact(contact, periodic)
    if not math.isfinite(tangential_displacement):
        raise BemInputError(
            f"tangential_displacement: expected a finite number (m), got {tangential_displacement}"
        )
    q_max, s_prev, x0 = _checked_state(contact, bound, slip, initial)
    op = _tangential_operator(operator, contact.shape, dx, dy, e_star, periodic, opts)
    rhs = tangential_displacement - s_prev
    cg = box_conjugate_gradients(
        op,
        rhs,
        contact,
        -q_max,
        q_max,
        x0,
        norm=op.norm,
        scale=e_star / math.sqrt(dx * dy),
        tol=opts.tol,
        max_iter=opts.max_iterations(contact.shape),
    )
    return _tangential_result(cg, contact, q_max, rhs, s_prev, tangential_displacement, dx * dy, t0)


def _checked_contact(contact: np.ndarray, periodic: bool) -> np.ndarray:
    """The contact set as a 2D bool array; a BemInputError for another rank, or a periodic
    cell in full contact (singular: the q = 0 mode is the reference)."""
    contact = np.asarray(contact, dtype=bool)
    if contact.ndim != 2:
        raise BemInputError(f"contact: expected a 2D boolean array, got shape {contact.shape}")
    if periodic and contact.all():
        raise BemInputError(
            "contact: covers the whole periodic cell; the periodic tangential operator has no "
            "stiffness for a uniform traction (its q = 0 mode is the reference), so the problem "
            "is singular: use a free domain or a partial contact"
        )
    return contact


def _checked_state(
    contact: np.ndarray,
    bound: np.ndarray | None,
    slip: np.ndarray | None,
    initial: np.ndarray | TangentialResult | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The slip threshold q_max (Pa; inf: full stick), the slip before the step (m) and the
    start tractions (Pa) on the contact's grid; a BemInputError naming a misfit one."""
    shape = contact.shape
    if bound is None:
        q_max = np.full(shape, np.inf)
    else:
        q_max = np.asarray(bound, dtype=np.float64)
        if q_max.shape != shape or not np.all(q_max[contact] >= 0) or np.isnan(q_max).any():
            raise BemInputError(
                f"bound: expected q_max >= 0 (Pa) of shape {shape}, got shape {q_max.shape} "
                "with negative or NaN entries"
            )
    s_prev = np.zeros(shape) if slip is None else np.asarray(slip, dtype=np.float64)
    if s_prev.shape != shape:
        raise BemInputError(f"slip: expected shape {shape}, got {s_prev.shape}")
    if isinstance(initial, TangentialResult):
        initial = initial.traction
    x0 = np.zeros(shape) if initial is None else np.asarray(initial, dtype=np.float64)
    if x0.shape != shape:
        raise BemInputError(f"initial: expected shape {shape}, got {x0.shape}")
    return q_max, s_prev, x0


def _tangential_operator(
    operator: TangentialOperator | None,
    shape: tuple[int, int],
    dx: float,
    dy: float,
    e_star: float,
    periodic: bool,
    opts: ShearOptions,
) -> TangentialOperator:
    """``operator`` when it fits the problem (grid, boundary, tangential), a new one when
    None (pixel sizes m, E* Pa); a BemInputError for a misfit one."""
    if operator is None:
        return TangentialOperator(
            shape,
            dx,
            dy,
            e_star,
            periodic=periodic,
            fft_backend=opts.fft_backend,
            threads=opts.threads,
        )
    if operator.shape != shape or operator.periodic != periodic or operator.normal:
        raise BemInputError(
            f"operator: built for shape {operator.shape}, periodic={operator.periodic}, "
            f"normal={operator.normal}; the problem needs {shape}, periodic={periodic}, "
            "tangential"
        )
    return operator


def _tangential_result(
    cg: BoxCGResult,
    contact: np.ndarray,
    q_max: np.ndarray,
    rhs: np.ndarray,
    s_prev: np.ndarray,
    tangential_displacement: float,
    area: float,
    t0: float,
) -> TangentialResult:
    """The step's :class:`TangentialResult` from the box-constrained solve ``cg``: stick where
    |q| < q_max, the slip updated elsewhere on the contact, forces and areas over the element
    ``area`` (m^2), the time since ``t0`` (s, perf_counter)."""
    q = cg.x
    # u_x on the contact set from the final gradient g = u_x - (delta_T - s_prev): no extra
    # convolution; off the contact set it is not needed (NaN)
    u = np.where(contact, cg.gradient + rhs, np.nan)
    stick = contact & (np.abs(q) < q_max)
    new_slip = np.where(contact & ~stick, tangential_displacement - u, s_prev)
    return TangentialResult(
        traction=q,
        displacement=u,
        slip=new_slip,
        contact=contact,
        stick=stick,
        tangential_displacement=float(tangential_displacement),
        tangential_force=float(q.sum() * area),
        stick_area=float(stick.sum() * area),
        slip_area=float((contact & ~stick).sum() * area),
        success=cg.success,
        status=cg.status,
        message=cg.message,
        nit=cg.nit,
        residual=cg.residual,
        convolutions=cg.convolutions,
        seconds=time.perf_counter() - t0,
    )
