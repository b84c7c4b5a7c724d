"""The statistical model's pull-off force over a resolution scan, and the check of the loads.

Loads at or below the pull-off force have no equilibrium on the loading branch
(E:Fy_Greenwood); the job refuses them right after the resolution-scan stage, before the BEM,
naming ``loading.normal_loads``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from asperity import statmodel
from asperity.pipelines.config import ConfigError

if TYPE_CHECKING:  # the surface stage imports this module
    from asperity.pipelines.stages.surface import ScanResult


def roughness_from_scan(scan: ScanResult, index: int) -> statmodel.Roughness:
    """The :class:`statmodel.Roughness` (eta 1/m^2, R m, sigma_s m) at one scan entry."""
    return statmodel.Roughness(
        asperity_density=float(scan.asperity_density[index]),
        summit_radius=float(scan.summit_radius[index]),
        summit_height_rms=float(scan.summit_height_rms[index]),
    )


def has_summits(scan: ScanResult, index: int) -> bool:
    """The scan entry has finite, positive eta, R and sigma_s (summits were found)."""
    values = (
        scan.asperity_density[index],
        scan.summit_radius[index],
        scan.summit_height_rms[index],
    )
    return all(np.isfinite(v) and v > 0 for v in values)


def pull_off_forces(
    material: statmodel.Material, scan: ScanResult, nominal_area: float
) -> tuple[np.ndarray, list[str]]:
    """Pull-off force of the statistical model at each scan resolution, N (negative).

    Returns
    -------
    forces : ndarray
        N; NaN where the scan has no summits or the model refuses the roughness there.
    reasons : list of str
        One line per refused resolution, "pull-off at stride S (resolution m): why": the
        model's own message (e.g. fewer than one asperity on A_n), stored with the stage's
        messages and shown in the report.
    """
    out = np.full(len(scan.stride), np.nan)
    reasons = []
    for i in range(len(scan.stride)):
        if not has_summits(scan, i):
            continue
        try:
            out[i] = statmodel.pull_off_force(material, roughness_from_scan(scan, i), nominal_area)
        except ValueError as exc:  # the model refuses this roughness: say so, keep NaN
            reasons.append(
                f"pull-off at stride {int(scan.stride[i])} "
                f"(resolution {float(scan.resolution[i]):.4g} m): {exc}"
            )
    return out, reasons


def check_loads_above_pull_off(
    material: statmodel.Material,
    scan: ScanResult,
    nominal_area: float,
    normal_loads: Sequence[float],
) -> np.ndarray:
    """Raise :class:`ConfigError` naming ``loading.normal_loads`` if a load is not above the
    pull-off force at some resolution (N).

    Returns
    -------
    ndarray
        The pull-off force at each resolution, N.
    """
    pull_off, _ = pull_off_forces(material, scan, nominal_area)  # NaN: no bound there
    worst = np.nanmax(pull_off) if np.isfinite(pull_off).any() else -math.inf
    low = [f for f in normal_loads if f <= worst]
    if low:
        i = int(np.nanargmax(pull_off))
        raise ConfigError(
            f"loading.normal_loads: expected loads above the statistical model's pull-off "
            f"force {worst:.4g} N (at resolution {scan.resolution[i] * 1e6:.4g} um), "
            f"got {low[0]:g} N"
        )
    return pull_off
