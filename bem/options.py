"""The tuning options of :func:`asperity.bem.solve_contact`, one validated frozen dataclass.

Every knob is bounded by its ``bem.<knob>`` entry of :data:`asperity.quantities.QUANTITIES`
(the same bound as the job's ``[bem]`` table and the ``asperity bem`` options), with the reason in
the message: a tolerance outside [1e-14, 1e-2] either cannot be reached in double precision or
accepts pressures wrong by more than a per cent as "converged"; iteration counts are positive
and capped at 10^6.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from asperity.bem.errors import BemInputError
from asperity.quantities import quantity

__all__ = ["SolverOptions", "resolve_options"]

#: Bounds of ``tol`` (see :class:`SolverOptions`).
TOL_RANGE = (quantity("bem.tol").low, quantity("bem.tol").high)
#: Upper bound of ``max_iter``, ``stall_window`` and ``refresh``.
MAX_COUNT = int(quantity("bem.max_iter").high)
#: Upper bound of ``threads``.
MAX_THREADS = int(quantity("bem.threads").high)
#: The bounded numeric knobs; None is allowed for the optional ones.
_NUMBERS = ("tol", "max_iter", "stall_window", "refresh", "threads")
_OPTIONAL = ("max_iter", "threads")
KERNELS = ("point", "love")
FFT_BACKENDS = ("auto", "pyfftw", "scipy")
PRECISIONS = ("auto", "mixed", "double")
#: ``precision="auto"`` is mixed from this many grid points on (below, a transform is cheap
#: next to the vector work and the casts, and the single-precision phase saves nothing).
MIXED_MIN_POINTS = 512 * 512


@dataclass(frozen=True)
class SolverOptions:
    """How :func:`~asperity.bem.solve_contact` iterates (not what it solves).

    Attributes
    ----------
    tol : float
        Convergence threshold on the residual, an estimate of the relative rms pressure error:
        the rms violation of g = 0 in contact and g >= 0 outside (m) times the pixel stiffness
        E*/sqrt(dx dy) (Pa/m), over the rms pressure (Pa). Within [1e-14, 1e-2]: below 1e-14
        the residual is under the round-off of the gaps (2.2e-16 x the height range) on any
        map; above 1e-2 a "converged" pressure may be wrong by more than a per cent.
    max_iter : int or None
        Iteration cap, in [1, 10^6]; None: ``max(1000, 2 max(nx, ny))``.
    precondition : bool
        Precondition the conjugate gradients with the half-space stiffness E*|q|/2 applied to
        the contact-set residual (Vollebregt 2014): one more convolution per iteration, 4x
        fewer iterations on the 1024^2 benchmark surface (280 -> 69 iterations).
    stall_window : int
        A stall is declared when the residual has not decreased by 0.1 % in this many
        iterations, in [1, 10^6].
    refresh : int
        Recompute u = K * p from scratch at least every this many iterations, in [1, 10^6].
    kernel : {"point", "love"}
        Periodic influence kernel (:mod:`asperity.bem.elastic.influence`).
    fft_backend : {"auto", "pyfftw", "scipy"}
        FFT backend (:mod:`asperity.bem.elastic.fft_backend`).
    threads : int or None
        FFT threads, in [1, 1024]; None: all available cores.
    coarse_start : bool
        Start a cold load-controlled periodic non-adhesive solve from the solution on a grid
        coarsened 2x (recursively down to 64 px, each level solved to 1e-2). Off by default:
        on the paper-like surface the fine grid then needs fewer iterations (2048^2: 22 vs 31,
        5000^2: 30 vs 41) but the coarse levels cost about what they save (FFT work within
        +-5 %); formerly, with coarse levels solved to 1e-6, it was slower.
    precision : {"auto", "mixed", "double"}
        FFT precision. "mixed": single-precision transforms while the residual is far above
        ``tol`` and above the single-precision floor, then double precision from an exactly
        recomputed gap to the end (the result meets ``tol`` in double precision like an
        all-double solve); "double": double throughout; "auto" (default): mixed from 512^2
        grid points on.
    """

    tol: float = 1e-8
    max_iter: int | None = None
    precondition: bool = True
    stall_window: int = 200
    refresh: int = 50
    kernel: str = "point"
    fft_backend: str = "auto"
    threads: int | None = None
    coarse_start: bool = False
    precision: str = "auto"

    def __post_init__(self) -> None:
        for name in _NUMBERS:
            value = getattr(self, name)
            if value is None and name in _OPTIONAL:
                continue
            bound = quantity(f"bem.{name}")
            checked = bound.check(value, f"solve_contact: {name}", BemInputError)
            object.__setattr__(self, name, checked)
        for name in ("precondition", "coarse_start"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise BemInputError(
                    f"solve_contact: {name} must be True or False, got {getattr(self, name)!r}"
                )
        _check_choice("kernel", self.kernel, KERNELS)
        _check_choice("fft_backend", self.fft_backend, FFT_BACKENDS)
        _check_choice("precision", self.precision, PRECISIONS)

    def max_iterations(self, shape: tuple[int, int]) -> int:
        """The iteration cap for heights of ``shape``: ``max_iter`` or the size default."""
        return self.max_iter if self.max_iter is not None else max(1000, 2 * max(shape))

    def mixed_precision(self, shape: tuple[int, int]) -> bool:
        """Whether a solve on an FFT grid of ``shape`` starts with single-precision transforms."""
        if self.precision == "auto":
            return shape[0] * shape[1] >= MIXED_MIN_POINTS
        return self.precision == "mixed"


def _check_choice(name: str, value: object, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise BemInputError(
            f"solve_contact: {name} must be one of {', '.join(map(repr, choices))}, got {value!r}"
        )


def resolve_options(options: SolverOptions | None, **keywords: Any) -> SolverOptions:
    """The options of one solve: ``options`` (default :class:`SolverOptions`) with every
    keyword that is not None replacing its field (validated again)."""
    if options is not None and not isinstance(options, SolverOptions):
        raise BemInputError(
            f"solve_contact: options must be a SolverOptions, got {type(options).__name__}"
        )
    given = {k: v for k, v in keywords.items() if v is not None}
    base = options if options is not None else SolverOptions()
    return dataclasses.replace(base, **given) if given else base
