"""Form removal by least squares over the valid (non-NaN) pixels.

Methods: ``"none"`` (unchanged), ``"mean"`` (subtract the mean height), ``"plane"``
(subtract the least-squares plane ``a + b x + c y``), ``"quadratic"`` (second-order form,
``a + b x + c y + d x^2 + e x y + f y^2``) or an integer polynomial order n (0..8: every term
``x^p y^q`` with ``p + q <= n``; 0, 1 and 2 are ``mean``, ``plane`` and ``quadratic``). The fit
is over valid pixels only (:mod:`asperity.topo.form`: Legendre basis on coordinates scaled to
[-1, 1], normal equations from one compiled pass, no design matrix).
"""

from __future__ import annotations

import numpy as np

from asperity.errors import InputError
from asperity.topo.form import (
    MAX_ORDER,
    check_order,
    fit_polynomial,
    legendre_to_monomial,
    subtract_polynomial,
)
from asperity.topo.heightmap import HeightMap, require_height_map

METHODS = ("none", "mean", "plane", "quadratic")
#: Polynomial order of each named method.
METHOD_ORDER = {"mean": 0, "plane": 1, "quadratic": 2}
#: Name of each low polynomial order (used in records and messages).
ORDER_NAME = {0: "mean", 1: "plane", 2: "quadratic"}


def method_order(method: str | int) -> int | None:
    """Polynomial order of a levelling ``method`` (None for ``"none"``).

    Parameters
    ----------
    method : str or int
        ``"none"``, ``"mean"``, ``"plane"``, ``"quadratic"`` or an order 0..8.

    Returns
    -------
    int or None
        0, 1, 2, ... or None (no levelling).

    Raises
    ------
    InputError
        Anything else (the message lists what is accepted).
    """
    if isinstance(method, str):
        if method == "none":
            return None
        if method in METHOD_ORDER:
            return METHOD_ORDER[method]
        raise InputError(
            f"levelling method {method!r}: expected one of {METHODS} or a polynomial order "
            f"0..{MAX_ORDER}"
        )
    return check_order(method)


def order_name(order: int | None) -> str:
    """``"none"``, ``"mean"``, ``"plane"``, ``"quadratic"`` or ``"polynomial order n"``."""
    if order is None:
        return "none"
    return ORDER_NAME.get(order, f"polynomial order {order}")


def fit_form(surface: HeightMap, method: str = "plane") -> np.ndarray:
    """Least-squares coefficients of the form ``method`` over the valid pixels.

    Parameters
    ----------
    surface : HeightMap
        Heights in m (NaN pixels ignored).
    method : {"mean", "plane", "quadratic"}
        The form: 1, 3 or 6 terms of the basis below.

    Returns
    -------
    ndarray
        Coefficients in m of the basis ``1, u, v, u^2, u v, v^2`` (first 1, 3 or 6), with
        ``u = 2 i/(nx-1) - 1`` and ``v = 2 j/(ny-1) - 1`` (pixel indices scaled to [-1, 1]).
    """
    if method not in METHOD_ORDER:
        raise InputError(f"levelling method {method!r}: expected one of {METHODS[1:]}")
    surface = require_height_map(surface, "level")
    n_terms = {0: 1, 1: 3, 2: 6}[METHOD_ORDER[method]]
    form = fit_polynomial(surface.heights, METHOD_ORDER[method])
    if form.n_valid < n_terms:
        source = surface.provenance.get("file", "the map")
        raise InputError(
            f"level({method!r}): {source} has {form.n_valid} valid (non-NaN) pixels; the fit "
            f"needs at least {n_terms}"
        )
    return legendre_to_monomial(form.coefficients)


def level(surface: HeightMap, method: str | int = "plane") -> HeightMap:
    """Remove the mean, the best plane, the best quadratic or a polynomial form (heights in m).

    Parameters
    ----------
    surface : HeightMap
        Heights in m; NaN pixels are ignored by the fit and stay NaN.
    method : {"none", "mean", "plane", "quadratic"} or int
        The form removed (least squares over the valid pixels); an int is a polynomial
        order 0..8.

    Returns
    -------
    HeightMap
        Same grid and provenance (with ``levelling`` recorded); ``"none"`` returns the input.

    Notes
    -----
    A periodic map has no tilt or form to remove (a plane is not periodic): for
    ``periodic=True`` maps every order >= 1 subtracts the mean only, so the map stays
    periodic; the provenance records ``"mean (periodic map)"``.
    """
    order = method_order(method)
    surface = require_height_map(surface, "level")
    if order is None:
        return surface
    applied = order_name(order)
    if surface.periodic and order > 0:
        order, applied = 0, "mean (periodic map)"
    n_valid = surface.nx * surface.ny - surface.n_missing
    n_terms = (order + 1) * (order + 2) // 2
    if n_valid < n_terms:
        source = surface.provenance.get("file", "the map")
        raise InputError(
            f"level({method!r}): {source} has {n_valid} valid (non-NaN) pixels; the fit "
            f"needs at least {n_terms}"
        )
    removal = subtract_polynomial(surface.heights, order)
    provenance = dict(surface.provenance)
    provenance["levelling"] = applied
    return surface.with_heights(removal.heights, provenance=provenance)
