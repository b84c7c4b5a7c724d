"""Input checks and the set-up of one contact problem (eqs. E:BEM_eq1..E:BEM_eq4).

:func:`set_up_problem` turns the arguments of :func:`asperity.bem.solve_contact` into a
:class:`ContactProblem`: validated heights (m) on the FFT grid, the imposed load (force in N,
or separation in m), the Pohrt-Popov critical tension (Pa, eq:max_sigma) and the influence
operator. Every refusal is a :class:`~asperity.bem.errors.BemInputError` naming the argument.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from asperity.bem.elastic.fft_backend import Convolution
from asperity.bem.elastic.operators import PaddedConvolution, influence_operator
from asperity.bem.elastic.pohrt_popov import critical_tension
from asperity.bem.errors import BemInputError
from asperity.bem.options import SolverOptions
from asperity.quantities import quantity

__all__ = ["ContactProblem", "set_up_problem"]


@dataclass(frozen=True, eq=False)
class ContactProblem:
    """One validated contact problem.

    Attributes
    ----------
    heights : ndarray (nx, ny)
        The surface heights h (m) as given.
    grid_heights : ndarray
        The heights (m) as the iteration reads them: ``heights``, C-contiguous. The solver's
        arrays have the map's shape with either boundary (a finite specimen is padded only
        inside the transforms, :class:`~asperity.bem.elastic.operators.PaddedConvolution`).
    dx, dy, e_star : float
        Pixel sizes (m) and reduced modulus (Pa).
    periodic : bool
        Periodic domain or finite specimen.
    load_control : bool
        Imposed force (True) or imposed separation (False).
    force : float
        Imposed total force F_z (N); NaN under displacement control.
    separation : float
        Imposed rigid-body distance d (m); NaN under load control.
    work_of_adhesion, critical_tension : float
        w (J/m^2) and the Pohrt-Popov Sigma (Pa); both 0 without adhesion.
    op : Convolution or PaddedConvolution
        u = K * p (m from Pa) on the map.
    """

    heights: np.ndarray
    grid_heights: np.ndarray
    dx: float
    dy: float
    e_star: float
    periodic: bool
    load_control: bool
    force: float
    separation: float
    work_of_adhesion: float
    critical_tension: float
    op: Convolution | PaddedConvolution

    @property
    def adhesive(self) -> bool:
        """Pohrt-Popov adhesion active (w > 0)."""
        return self.work_of_adhesion > 0

    @property
    def pixel_area(self) -> float:
        """dx dy (m^2)."""
        return self.dx * self.dy

    @property
    def nominal_area(self) -> float:
        """Projected area of the map (m^2)."""
        return self.heights.size * self.pixel_area

    @property
    def stiffness(self) -> float:
        """E*/sqrt(dx dy) (Pa/m): the stiffness of a pixel-sized wavelength."""
        return self.e_star / math.sqrt(self.pixel_area)

    @functools.cached_property
    def height_scale(self) -> float:
        """max |h| (m): sets the round-off floor of the gaps (computed once: the iteration
        asks for it every step)."""
        return float(max(self.heights.max(), -self.heights.min()))

    @property
    def target_pressure_sum(self) -> float:
        """sum p (Pa) that carries the imposed force: F / (dx dy)."""
        return self.force / self.pixel_area


def real_scalar(name: str, val: Any) -> float:
    """``val`` as a float, or a BemInputError naming the argument (bools, strings, arrays with
    more than one element and complex numbers are refused)."""
    if isinstance(val, (bool, np.bool_, str, bytes)) or np.ndim(val) != 0 or np.iscomplexobj(val):
        raise BemInputError(f"solve_contact: {name} must be a real number, got {val!r}")
    try:
        return float(val)
    except (TypeError, ValueError):
        raise BemInputError(f"solve_contact: {name} must be a real number, got {val!r}") from None


def checked_heights(heights: Any) -> np.ndarray:
    """Heights (m) as a real 2D float64 array of at least 2 x 2 finite values."""
    if np.iscomplexobj(heights):
        raise BemInputError("solve_contact: heights must be real (m), got a complex array")
    try:
        h = np.asarray(heights, dtype=np.float64)
    except (TypeError, ValueError):
        raise BemInputError("solve_contact: heights must be a 2D array of numbers (m)") from None
    if h.ndim != 2:
        raise BemInputError(f"solve_contact: heights must be a 2D array (m), got shape {h.shape}")
    if h.shape[0] < 2 or h.shape[1] < 2:
        raise BemInputError(f"solve_contact: heights must be at least 2 x 2 pixels, got {h.shape}")
    n_bad = int(np.count_nonzero(~np.isfinite(h)))
    if n_bad:
        raise BemInputError(
            f"solve_contact: heights contain {n_bad} missing/non-finite values (NaN or inf); "
            "fill or crop them before a contact solve"
        )
    return h


def _bounded(key: str, name: str, val: object) -> float:
    """``val`` checked against the quantity ``solve_contact.<key>`` (message names ``name``)."""
    return quantity(f"solve_contact.{key}").check(val, f"solve_contact: {name}", BemInputError)


def _the_load(loads: Mapping[str, object]) -> tuple[str, float]:
    given = [k for k, v in loads.items() if v is not None]
    if len(given) != 1:
        raise BemInputError(
            "solve_contact: give exactly one of normal_force (N), mean_pressure (Pa) or "
            f"separation (m); got {given or 'none'}"
        )
    value = real_scalar(given[0], loads[given[0]])
    if not math.isfinite(value):
        raise BemInputError(f"solve_contact: {given[0]} must be finite, got {value}")
    return given[0], value


def _checked_force(force: float, adhesive: bool) -> float:
    if not math.isfinite(force):
        raise BemInputError(f"solve_contact: the imposed load must be finite, got {force}")
    if not adhesive and force <= 0:
        raise BemInputError(
            f"solve_contact: without adhesion the imposed force must be > 0 (N), got {force}: "
            "a rigid flat cannot pull on a non-adhesive surface"
        )
    return force


def _checked_separation(separation: float, h: np.ndarray, periodic: bool) -> float:
    if periodic and separation <= float(h.mean()):
        # periodic kernels have K(q = 0) = 0: the mean deflection is zero, so the mean gap
        # is d - mean(h) whatever the pressure; d <= mean(h) has no finite solution
        raise BemInputError(
            f"solve_contact: separation {separation:.6g} m must exceed the mean height "
            f"{float(h.mean()):.6g} m on a periodic domain (the mean deflection is zero: "
            "the flat cannot be pushed below the mean plane; d -> mean(h) is full contact "
            "at infinite force)"
        )
    return separation


def set_up_problem(
    heights: object,
    dx: object,
    dy: object,
    e_star: object,
    loads: Mapping[str, object],
    work_of_adhesion: object,
    periodic: object,
    options: SolverOptions,
    in_place: bool = False,
) -> ContactProblem:
    """Validate the arguments of :func:`asperity.bem.solve_contact` and build the problem.

    ``loads`` maps ``normal_force`` (N), ``mean_pressure`` (Pa) and ``separation`` (m) to their
    values, exactly one not None. ``in_place``: transform in place in the workspace also on a
    periodic grid (a finite specimen always does), so that the iteration stores its direction
    and work arrays in float32 (:func:`~asperity.bem.normal.iteration.new_state`): 8 B per point
    less, for the Maugis iteration's inner solves.
    """
    h = checked_heights(heights)
    dx_, dy_ = _bounded("dx", "dx", dx), _bounded("dx", "dy", dy)
    e_ = _bounded("e_star", "e_star", e_star)
    name, value = _the_load(loads)
    w = _bounded("work_of_adhesion", "work_of_adhesion", work_of_adhesion)
    if not isinstance(periodic, (bool, np.bool_)):
        raise BemInputError(f"solve_contact: periodic must be True or False, got {periodic!r}")
    force, separation = math.nan, math.nan
    if name == "separation":
        separation = _checked_separation(value, h, bool(periodic))
    else:
        nominal = h.size * dx_ * dy_
        force = _checked_force(value if name == "normal_force" else value * nominal, w > 0)
    op = influence_operator(
        h.shape,
        dx_,
        dy_,
        e_,
        options.kernel,
        bool(periodic),
        options.fft_backend,
        options.threads,
        in_place=in_place,
    )
    return ContactProblem(
        heights=h,
        grid_heights=np.ascontiguousarray(h),
        dx=dx_,
        dy=dy_,
        e_star=e_,
        periodic=bool(periodic),
        load_control=name != "separation",
        force=force,
        separation=separation,
        work_of_adhesion=w,
        critical_tension=critical_tension(w, e_, dx_, dy_) if w > 0 else 0.0,
        op=op,
    )
