"""The result of one boundary-element contact solve (scipy.optimize-like status fields)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ContactResult"]


@dataclass(frozen=True, eq=False)
class ContactResult:
    """Solution of the contact problem E:BEM_eq1..E:BEM_eq4 on one height map.

    Attributes
    ----------
    pressure : ndarray (nx, ny)
        Contact pressure p (Pa), compressive positive; tension (p < 0) only with adhesion,
        never below ``-critical_tension`` in a converged result (a result that ends with an
        element below it is reported non-converged, see ``message``).
    gap : ndarray (nx, ny)
        Interfacial gap g = u_z - h + d (m), eq. E:BEM_eq1; ~0 in contact, >= 0 outside.
    contact_mask : ndarray of bool (nx, ny)
        Elements in contact (Omega_c).
    real_area : float
        Real contact area (m^2): number of contact elements times dx*dy.
    contact_fraction : float
        real_area / nominal area (-).
    normal_force : float
        Total normal force F_z = sum p dx dy (N), eq. E:BEM_eq4; negative = adhesive pull.
    mean_pressure : float
        normal_force / nominal area (Pa).
    mean_gap : float
        Mean of the gap over the domain (m).
    separation : float
        The rigid-body distance d of eq. E:BEM_eq1 (m): position of the flat above the height
        datum (for a periodic domain the deformed surface's mean plane is taken as u_z = 0).
    nit : int
        Conjugate-gradient iterations done (``iterations`` is the same number).
    residual_history : ndarray
        ``nit + 1`` values of the convergence residual (dimensionless, see
        :func:`bem.solve_contact`, ``tol``): that of the starting state, then one after each
        iteration; the last equals ``residual``. It decreases overall but not monotonically:
        it jumps up when elements enter or leave the contact set (the conjugacy restarts),
        with adhesion at every Pohrt-Popov delamination step, and the preconditioned
        iteration minimises an energy norm, not this residual. A warm start shows as a small
        first value.
    converged : bool
        True only when the residual fell below ``tol`` with the contact set settled and the
        imposed force reached (``success`` is the same flag); False for an iteration cap, a
        stall, a lost contact or a force that cannot be carried.
    message : str
        Why the iteration stopped: starts with "converged", "iteration cap reached",
        "stalled", "contact lost", "no element in contact" (displacement control beyond the
        highest point: converged, zero force), "imposed force" or "elements in contact below
        -Sigma".
    seconds : float
        Wall-clock time of the solve (s).
    dx, dy : float
        Pixel sizes (m).
    critical_tension : float
        Pohrt-Popov Sigma (Pa, eq:max_sigma); 0 without adhesion.
    residual : float
        The residual of the returned state (``residual_history[-1]``).
    extra : dict
        Diagnostics: ``convolutions`` (FFT convolutions done on this grid), ``fft_seconds``
        (wall time in them, s), ``fft_backend``, ``fft_threads``,
        ``preconditioner_dropped_at`` (iteration where a stalled preconditioned iteration fell
        back to plain Polonsky-Keer, or None), and for a coarse-grid start ``coarse_iterations``,
        ``coarse_convolutions``, ``coarse_seconds``.
    """

    pressure: np.ndarray
    gap: np.ndarray
    contact_mask: np.ndarray
    real_area: float
    contact_fraction: float
    normal_force: float
    mean_pressure: float
    mean_gap: float
    separation: float
    nit: int
    residual_history: np.ndarray
    converged: bool
    message: str
    seconds: float
    dx: float
    dy: float
    critical_tension: float = 0.0
    residual: float = float("nan")
    extra: dict = field(default_factory=dict)

    @property
    def iterations(self) -> int:
        """Number of iterations (same as ``nit``)."""
        return self.nit

    @property
    def success(self) -> bool:
        """Same as ``converged`` (scipy.optimize naming)."""
        return self.converged

    @property
    def nominal_area(self) -> float:
        """Nominal (projected) area of the domain (m^2)."""
        return self.pressure.size * self.dx * self.dy

    def summary(self) -> dict:
        """The scalar results as a JSON-ready dict (SI units), keys as in the CLI's ``--json``."""
        return {
            "contact_fraction": float(self.contact_fraction),
            "real_area": float(self.real_area),
            "normal_force": float(self.normal_force),
            "mean_gap": float(self.mean_gap),
            "iterations": int(self.nit),
            "converged": bool(self.converged),
            "seconds": float(self.seconds),
        }

    def __repr__(self) -> str:
        return (
            f"ContactResult(shape={self.pressure.shape}, "
            f"contact_fraction={self.contact_fraction:.6g}, "
            f"normal_force={self.normal_force:.6g} N, mean_gap={self.mean_gap:.6g} m, "
            f"nit={self.nit}, converged={self.converged}, message={self.message!r})"
        )
