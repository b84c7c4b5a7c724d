"""The result of one boundary-element contact solve (scipy.optimize-like status fields).

Status codes (``ContactResult.status``, :class:`SolverStatus`), the same for every bem result:

====  ================  ======================================================================
code  name              meaning
====  ================  ======================================================================
0     CONVERGED         residual below ``tol`` with the contact set settled and the imposed
                        load carried (also: displacement control with the flat beyond the
                        highest point, an exact no-contact state)
1     ITERATION_CAP     ``max_iter`` iterations done, residual still above ``tol``
2     STALLED           no progress: the residual did not decrease by 0.1 % in
                        ``stall_window`` iterations, or the search direction vanished; the
                        message names the likely cause it detects (outlier pixels, near-full
                        contact, a tolerance below the attainable precision)
3     CONTACT_LOST      every element left the contact set (an adhesive load beyond pull-off)
4     LOAD_NOT_CARRIED  the iteration ended but the contact cannot carry the imposed load
                        (force not reached, or elements in contact below -Sigma): a tensile
                        load needs a start on the unloading branch (``initial=``)
====  ================  ======================================================================

``success`` (and its alias ``converged``) is ``status == 0``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np

__all__ = ["BRANCHES", "ContactResult", "SolverStatus"]


class SolverStatus(IntEnum):
    """Outcome of a solve (see the module docstring for the meaning of each code)."""

    CONVERGED = 0
    ITERATION_CAP = 1
    STALLED = 2
    CONTACT_LOST = 3
    LOAD_NOT_CARRIED = 4


#: Values of ``ContactResult.branch``: which solution of the (history-dependent) adhesive
#: problem a result is. "unique": no adhesion, the solution does not depend on the path;
#: "loading": reached by increasing the load (or the approach) from first contact;
#: "unloading": reached by decreasing it from a loaded state; "from initial": continued from
#: a caller's pressure field whose history the solver does not know.
BRANCHES = ("unique", "loading", "unloading", "from initial")


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
    status : int
        Outcome code (:class:`SolverStatus`): 0 converged, 1 iteration cap, 2 stalled,
        3 contact lost, 4 load not carried. ``success`` and ``converged`` are ``status == 0``.
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
        ``coarse_convolutions``, ``coarse_seconds``; for a stall ``stall_causes`` (the
        causes named in the message); for an adhesive solve on the loading branch
        ``loading_iterations``, ``loading_convolutions`` and ``loading_message`` of the
        non-adhesive solve it starts from (not counted in ``nit``).
    branch : str
        Which solution this is (one of :data:`BRANCHES`): "unique" without adhesion,
        "loading", "unloading" or "from initial" with adhesion.
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
    status: int
    message: str
    seconds: float
    dx: float
    dy: float
    critical_tension: float = 0.0
    residual: float = float("nan")
    extra: dict = field(default_factory=dict)
    branch: str = "unique"

    @property
    def iterations(self) -> int:
        """Number of iterations (same as ``nit``)."""
        return self.nit

    @property
    def success(self) -> bool:
        """The solve converged: ``status == 0`` (scipy.optimize naming)."""
        return self.status == SolverStatus.CONVERGED

    @property
    def converged(self) -> bool:
        """Same as ``success``."""
        return self.success

    @property
    def nominal_area(self) -> float:
        """Nominal (projected) area of the domain (m^2)."""
        return self.pressure.size * self.dx * self.dy

    def summary(self) -> dict:
        """The scalar results as a JSON-ready dict (SI units), keys as in the CLI's ``--json``."""
        return {
            "contact_fraction": float(self.contact_fraction),
            "real_area": float(self.real_area),
            "normal_force": float(self.normal_force) + 0.0,  # + 0.0: never "-0"
            "mean_gap": float(self.mean_gap) + 0.0,
            "iterations": int(self.nit),
            "converged": bool(self.converged),
            "seconds": float(self.seconds),
            "status": int(self.status),
            "branch": self.branch,
        }

    def __repr__(self) -> str:
        return (
            f"ContactResult(shape={self.pressure.shape}, "
            f"contact_fraction={self.contact_fraction:.6g}, "
            f"normal_force={self.normal_force:.6g} N, mean_gap={self.mean_gap:.6g} m, "
            f"nit={self.nit}, status={self.status}, branch={self.branch!r}, "
            f"message={self.message!r})"
        )
