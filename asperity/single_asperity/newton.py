"""One safeguarded Newton iteration for the convex, decreasing-onto-the-root solves of the model.

Every root the single-asperity laws need (the JKR radius of E:JKR_indent, the Papangelo-Ciavarella
radius of E:PC_indent, the fold radius of E:Instable_boundary and of E:PC_a_min_1, and their
dimensionless forms of the status map) is the largest root of a function f that is convex to the
right of it. Newton's method started at a point x0 with f(x0) >= 0 then decreases monotonically
onto the root, and the iteration is safeguarded in three ways:

* the iterates are clamped at ``lower`` (the fold, where the stable branch ends), so a point on
  the fold is returned exactly instead of overshooting into the unstable branch;
* the iteration stops as soon as f(x) <= 0 (the root is crossed, within round-off) or the step
  is below ``STEP_RTOL`` (4e-16) of x, i.e. within two ulps;
* it stops after ``MAX_ITERATIONS`` (200) steps, or at once when an iterate is NaN, and says so
  in its status.

:func:`newton_solver` builds the compiled solver of one residual: ``residual(x, params)`` is a
numba ``@njit`` function returning ``(f(x), f'(x))`` and ``params`` a tuple of floats. The
solver is itself ``@njit`` and is called from compiled kernels (it is not disk-cached itself:
the cached kernels that call it hold its machine code, so a changed residual is recompiled with
its caller). Units are the caller's (m for radii).
"""

from __future__ import annotations

from collections.abc import Callable

from numba import njit

__all__ = [
    "CONVERGED",
    "MAX_ITERATIONS",
    "MAX_ITERATIONS_REACHED",
    "MESSAGES",
    "NOT_A_NUMBER",
    "STEP_RTOL",
    "newton_solver",
]

#: Iteration cap of every solve (quadratic convergence needs fewer than 10 from the start points).
MAX_ITERATIONS = 200
#: Relative step below which the iterate is final (two ulps of x).
STEP_RTOL = 4.0e-16

#: Status codes of :func:`newton_solver`'s solvers (as scipy.optimize's ``status``).
CONVERGED = 0
MAX_ITERATIONS_REACHED = 1
NOT_A_NUMBER = 2

#: Status code -> message.
MESSAGES = {
    CONVERGED: "converged: the root is crossed or the last step is below 4e-16 of x",
    MAX_ITERATIONS_REACHED: f"not converged in {MAX_ITERATIONS} Newton iterations",
    NOT_A_NUMBER: "an iterate is NaN (the residual or its derivative is not finite)",
}


def newton_solver(residual: Callable) -> Callable:
    """The compiled safeguarded Newton solver of ``residual`` (module docstring).

    Parameters
    ----------
    residual : numba dispatcher
        ``residual(x, params) -> (f, fprime)``, an ``@njit`` function; f must be convex and
        decreasing onto its largest root from the start point.

    Returns
    -------
    callable
        ``solve(x0, lower, params) -> (x, status, nit)``, an ``@njit`` function: ``x0`` the
        start point (f(x0) >= 0), ``lower`` the clamp (``-inf``: none), ``x`` the root (or the
        last iterate), ``status`` one of :data:`CONVERGED`, :data:`MAX_ITERATIONS_REACHED`,
        :data:`NOT_A_NUMBER`, ``nit`` the Newton steps taken.
    """

    @njit
    def solve(x0: float, lower: float, params: tuple) -> tuple[float, int, int]:
        x = x0
        for nit in range(MAX_ITERATIONS):
            f, fprime = residual(x, params)
            if f <= 0.0:
                return x, CONVERGED, nit
            x_new = x - f / fprime
            if x_new < lower:
                x_new = lower
            if x - x_new <= STEP_RTOL * x:
                return x_new, CONVERGED, nit + 1
            if x_new != x_new:
                return x_new, NOT_A_NUMBER, nit + 1
            x = x_new
        return x, MAX_ITERATIONS_REACHED, MAX_ITERATIONS

    return solve
