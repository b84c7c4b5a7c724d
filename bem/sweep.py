"""Warm-started load sweeps: each solve starts from the previous pressure field."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from bem.polonsky_keer import solve_contact
from bem.result import ContactResult

__all__ = ["load_sweep"]


def load_sweep(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_forces: Sequence[float],
    **options,
) -> list[ContactResult]:
    """Solve at several imposed total forces (N), each warm-started from the previous solution.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights (m), larger = closer to the flat.
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa).
    normal_forces : sequence of float
        Imposed forces F_z (N), solved in the given order (an increasing sequence is the
        natural loading path; with adhesion the order defines the branch).
    **options
        Any keyword of :func:`bem.solve_contact` except the loads (``tol``, ``max_iter``,
        ``work_of_adhesion``, ``periodic``, ``initial`` for the first solve, ...).

    Returns
    -------
    list of ContactResult
        One per force, in the given order.
    """
    for key in ("normal_force", "mean_pressure", "separation"):
        if key in options:
            raise ValueError(f"load_sweep: pass the loads as normal_forces, not {key}=")
    forces = [float(f) for f in normal_forces]
    if not forces:
        raise ValueError("load_sweep: normal_forces is empty")
    previous = options.pop("initial", None)
    results: list[ContactResult] = []
    for f in forces:
        res = solve_contact(heights, dx, dy, e_star, normal_force=f, initial=previous, **options)
        results.append(res)
        previous = res
    return results
