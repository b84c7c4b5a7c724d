"""The measured curves the calibration reads, as plain SI data (N, m, m^2).

A tribologist's measurements at rest and under shear (paper Section 5, Figs 6 and 13): the real
contact area against the normal load, A_r(F_z); against the tangential force at one normal
load, A_r(F_x); and a friction test, F_x against the drive's displacement. The readers, with
their checks, are :mod:`asperity.pipelines.measured` and
:mod:`asperity.pipelines.measured_friction`; the fits of lambda that use these curves are
:mod:`asperity.statmodel.lambda_fit` and :mod:`asperity.statmodel.lambda_fit_friction`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the job-file validation imports this module: no numpy at run time
    import numpy as np

__all__ = ["FIT_SOURCES", "FrictionCurve", "NormalAreaCurve", "ShearAreaCurve"]

#: What lambda may be fitted to: the A_r(F_x) curves ("area"), the friction tests F_x(drive)
#: ("friction"), or both ("joint"; :mod:`asperity.statmodel.lambda_fit_friction`).
FIT_SOURCES: tuple[str, ...] = ("area", "friction", "joint")


@dataclass(frozen=True)
class NormalAreaCurve:
    """Measured real contact area at rest against normal load.

    Attributes
    ----------
    normal_load : ndarray
        F_z, N (sorted ascending).
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: np.ndarray
    real_area: np.ndarray
    source: str = ""


@dataclass(frozen=True)
class ShearAreaCurve:
    """Measured real contact area against tangential force at one normal load.

    Attributes
    ----------
    normal_load : float
        F_z, N.
    tangential_force : ndarray
        F_x, N, in acquisition (file) order.
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: float
    tangential_force: np.ndarray
    real_area: np.ndarray
    source: str = ""


@dataclass(frozen=True)
class FrictionCurve:
    """A measured friction test at one normal load (SI units).

    Attributes
    ----------
    normal_load : float
        F_z, N.
    drive_displacement : ndarray
        The drive's displacement, m, non-decreasing, in acquisition (file) order.
    tangential_force : ndarray
        F_x, N.
    source : str
        File it was read from.
    """

    normal_load: float
    drive_displacement: np.ndarray
    tangential_force: np.ndarray
    source: str = ""

    @property
    def drive_from_start(self) -> np.ndarray:
        """The drive measured from the curve's first point, m."""
        return self.drive_displacement - self.drive_displacement[0]
