"""Pre-loading stage of the rough contact (Section 3.1): Greenwood's improved Fuller-Tabor model.

F_z(d) = eta A_n int_{delta_JKR^loading}^inf P_JKR(delta) phi(d + delta) d delta
         (E:Fy_Greenwood)
A_r(d) = eta A_n int_{delta_JKR^loading}^inf pi a_JKR^2(delta) phi(d + delta)
         d delta (E:Ar_Greenwood)

with Gaussian summit heights phi (standard deviation sigma_s) and Wu's jump-to-contact lower limit
(E:JKR_delta_min_loading). The loading curve F_z(d) is tensile at large separations, reaches its
minimum (the pull-off force under load control, :func:`pull_off_force`) and then grows without
bound as d decreases; an imposed load is carried at the separation on the stable branch
(dF_z/dd < 0), found by a bracketed Brent solve. SI units: m, N, m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from statmodel import integrals as _k
from statmodel.options import ModelSetup, QuadratureOptions, setup_model
from statmodel.parameters import Material, Roughness


@dataclass(frozen=True)
class PreloadResult:
    """State at the end of the pre-loading stage (delta_T = 0).

    Attributes
    ----------
    separation : float
        d_min, separation between the flat and the mean summit height, m.
    normal_force : float
        F_z carried at that separation, N (the imposed load to ``load_rtol``).
    real_area : float
        A_r, m^2.
    n_contact : float
        Expected number of asperities in contact, eta A_n int_{delta_load}^inf phi(d + delta).
    tabor_parameter : float
        mu (dimensionless).
    pull_off_force : float
        Most tensile load the preload branch can carry, N (negative).
    converged : bool
        Whether the separation solve met its tolerance.
    message : str
        Solver message.
    nit : int
        Normal-load evaluations used.
    """

    separation: float
    normal_force: float
    real_area: float
    n_contact: float
    tabor_parameter: float
    pull_off_force: float
    converged: bool
    message: str
    nit: int


def preload_state(setup: ModelSetup, separation: float) -> np.ndarray:
    """Per-asperity integrals (layout of :mod:`statmodel.integrals`) of the preload at d (m)."""
    out = np.empty(_k.N_RESULTS)
    _k.asperity_integrals(float(separation), 0.0, setup.prm, setup.gl_x, setup.gl_w,
                          setup.panels, out)
    return out


def preload_normal_force(setup: ModelSetup, separation: float) -> float:
    """F_z(d) of E:Fy_Greenwood at separation d (m), N."""
    out = preload_state(setup, separation)
    return setup.n_asperities * (out[_k.FZ_STICK] + out[_k.FZ_SLIP])


def pull_off_point(setup: ModelSetup) -> tuple[float, float]:
    """(F_min, d_at_min): minimum of the preload curve F_z(d) (N) and where it occurs (m).

    A grid scan over d in [-6, cutoff] sigma_s locates the minimum, then a bounded Brent
    minimisation refines it (xatol = 1e-12 sigma_s).
    """
    sigma = setup.roughness.summit_height_rms
    grid = np.linspace(-6.0, setup.options.cutoff_sigma, 321) * sigma
    values = np.array([preload_normal_force(setup, d) for d in grid])
    i = int(np.argmin(values))
    lo = grid[max(i - 1, 0)]
    hi = grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(
        lambda d: preload_normal_force(setup, d),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12 * sigma, "maxiter": 500},
    )
    if res.fun <= values[i]:
        return float(res.fun), float(res.x)
    return float(values[i]), float(grid[i])


def pull_off_force(material: Material, roughness: Roughness, nominal_area: float,
                   **accuracy_knobs: float) -> float:
    """Pull-off force of the rough contact under load control, N (negative).

    The minimum over the separation of the preload curve F_z(d) (E:Fy_Greenwood): the most tensile
    normal load at which the pre-loaded contact is stable; a smaller (more tensile) imposed load
    separates the surfaces.

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2 (must hold eta A_n >= 1 asperity).
    **accuracy_knobs
        See :mod:`statmodel.options`.
    """
    setup = setup_model(material, roughness, nominal_area,
                        QuadratureOptions.from_knobs(**accuracy_knobs))
    return pull_off_point(setup)[0]


def solve_preload(setup: ModelSetup, normal_load: float,
                  pull_off: tuple[float, float] | None = None) -> PreloadResult:
    """Preload separation for ``normal_load`` (N) with the kernels of ``setup``.

    ``pull_off`` is :func:`pull_off_point` of the same setup when already known.
    """
    try:
        target = float(normal_load)
    except (TypeError, ValueError):
        raise ValueError(f"normal_load: expected a number in N, got {normal_load!r}") from None
    if not math.isfinite(target):
        raise ValueError(f"normal_load: expected a finite load in N, got {normal_load!r}")
    f_min, d_min_force = pull_off_point(setup) if pull_off is None else pull_off
    if target < f_min:
        raise ValueError(
            f"normal_load = {target:.6g} N is below the pull-off force {f_min:.6g} N of this "
            "contact (the most tensile load the pre-loaded interface can carry)"
        )
    sigma = setup.roughness.summit_height_rms
    ftol = setup.options.load_rtol * max(abs(target), abs(f_min))
    out = np.empty(_k.N_RESULTS)
    work = np.empty(6)
    d, nit, ok = _k.solve_separation(
        d_min_force, 0.05 * sigma, 0.0, target, ftol, 1e-15 * sigma, setup.options.max_iter,
        setup.prm, setup.gl_x, setup.gl_w, setup.panels, out, work,
    )
    n = setup.n_asperities
    message = "converged" if ok else "preload separation solve did not converge"
    return PreloadResult(
        separation=float(d),
        normal_force=float(n * (out[_k.FZ_STICK] + out[_k.FZ_SLIP])),
        real_area=float(n * (out[_k.AR_STICK] + out[_k.AR_SLIP])),
        n_contact=float(n * (out[_k.N_STICK] + out[_k.N_SLIP])),
        tabor_parameter=setup.tabor_parameter,
        pull_off_force=f_min,
        converged=bool(ok),
        message=message,
        nit=int(nit),
    )


def preload(material: Material, roughness: Roughness, nominal_area: float, normal_load: float,
            **accuracy_knobs: float) -> PreloadResult:
    """Separation, real area and contact count under a purely normal load (E:Fy_Greenwood).

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2 (eta A_n >= 1 required).
    normal_load : float
        Imposed F_z, N (compressive positive); must not be below :func:`pull_off_force`.
    **accuracy_knobs
        See :mod:`statmodel.options`.

    Returns
    -------
    PreloadResult

    Raises
    ------
    ValueError
        Bad inputs, or a normal load below the pull-off force (the message gives it in N).
    """
    setup = setup_model(material, roughness, nominal_area,
                        QuadratureOptions.from_knobs(**accuracy_knobs))
    return solve_preload(setup, normal_load)


def real_area_at_loads(material: Material, roughness: Roughness, nominal_area: float,
                       normal_loads: ArrayLike, **accuracy_knobs: float) -> np.ndarray:
    """Real contact area A_r (m^2) at delta_T = 0 for each normal load (N), E:Ar_Greenwood."""
    setup = setup_model(material, roughness, nominal_area,
                        QuadratureOptions.from_knobs(**accuracy_knobs))
    loads = np.atleast_1d(np.asarray(normal_loads, dtype=float))
    pull = pull_off_point(setup)
    return np.array([solve_preload(setup, f, pull).real_area for f in loads.ravel()]).reshape(
        loads.shape
    )
