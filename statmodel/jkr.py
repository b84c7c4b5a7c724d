"""JKR theory of a single spherical asperity on a rigid flat (paper, Section 2.1).

The closed forms (E:JKR_indent, E:JKR_load, the jump-off distance E:JKR_delta_min_unloading, the
pull-off forces) are :mod:`asperity.single_asperity.jkr`'s, the ground both :mod:`asperity.bem`
and :mod:`asperity.statmodel` stand on; re-exported here under the statistical model's name. Wu's
jump-to-contact distance (E:JKR_delta_min_loading), a fit in Tabor's parameter with the range
the model assumes (:data:`asperity.statmodel.parameters.TABOR_JKR_LIMIT`), is the model's and is
defined here. SI units: m, Pa, J/m^2, N.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike

from asperity.single_asperity import jkr as _closed_forms
from asperity.single_asperity.jkr import *  # noqa: F403
from asperity.statmodel.parameters import TABOR_JKR_LIMIT, TaborWarning

__all__ = [*_closed_forms.__all__, "jkr_jump_in_distance", "jkr_jump_in_kernel"]


@njit(cache=True)
def jkr_jump_in_kernel(tabor: float, equilibrium_distance: float) -> float:
    """Wu's jump-to-contact indentation (m), E:JKR_delta_min_loading; 0 when mu = 0.

    NaN for a NaN or negative Tabor parameter or a non-positive equilibrium distance.
    """
    if not (tabor >= 0.0 and equilibrium_distance > 0.0):
        return math.nan
    if tabor == 0.0:
        return 0.0
    return -2.641 * tabor ** (3.0 / 7.0) * math.exp(-0.5 / math.sqrt(tabor)) * equilibrium_distance


@vectorize(["float64(float64, float64)"], cache=True)
def _jkr_jump_in_ufunc(tabor, equilibrium_distance):
    return jkr_jump_in_kernel(tabor, equilibrium_distance)


def jkr_jump_in_distance(tabor: ArrayLike, equilibrium_distance: ArrayLike) -> np.ndarray | float:
    """Jump-to-contact indentation delta_JKR^loading (m, <= 0), Wu's fit E:JKR_delta_min_loading.

    delta = -2.641 mu^(3/7) exp(-1 / (2 sqrt(mu))) epsilon, with mu Tabor's parameter and epsilon
    the equilibrium distance (m). Returns 0 for mu = 0 (no adhesion: Fuller-Tabor/Hertz limit) and
    NaN for a NaN or negative mu or a non-positive epsilon. Warns (:class:`TaborWarning`) where
    0 < mu < 5: the fit is used outside the JKR range the paper assumes (there it can even fall
    below the jump-off distance, which happens for mu < ~1).

    Parameters
    ----------
    tabor : float or array
        Tabor's parameter mu (dimensionless).
    equilibrium_distance : float or array
        epsilon, m.

    Returns
    -------
    float or ndarray
        delta_JKR^loading, m (broadcast shape).
    """
    mu = np.asarray(tabor, dtype=float)
    if np.any((mu > 0.0) & (mu < TABOR_JKR_LIMIT)):
        warnings.warn(
            f"Tabor parameter mu = {float(np.min(mu[mu > 0.0])):.3g} < {TABOR_JKR_LIMIT:g}: Wu's "
            "jump-in fit (E:JKR_delta_min_loading) is used outside the JKR range",
            TaborWarning,
            stacklevel=2,
        )
    return _jkr_jump_in_ufunc(mu, equilibrium_distance)
