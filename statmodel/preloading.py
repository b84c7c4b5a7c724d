"""Pre-loading stage of the rough contact (Section 3.1): Greenwood's improved Fuller-Tabor model.

F_z(d) = eta A_n int_{delta_JKR^loading}^inf P_JKR(delta) phi(d + delta) d delta
         (E:Fy_Greenwood)
A_r(d) = eta A_n int_{delta_JKR^loading}^inf pi a_JKR^2(delta) phi(d + delta)
         d delta (E:Ar_Greenwood)

with Gaussian summit heights phi (standard deviation sigma_s) and Wu's jump-to-contact lower limit
(E:JKR_delta_min_loading): Greenwood's (2017) loading branch. The loading curve F_z(d) tends to 0
at large separations, can dip tensile (its minimum is the loading pull-off force,
:func:`pull_off_force`, the bound an imposed load is checked against) and grows without bound as d
decreases; an imposed load is carried at the separation on the stable branch (dF_z/dd < 0), found
by a bracketed Brent solve. Greenwood's unloading branch after a preload (lower limit
max(d_min - d + delta_JKR^loading, delta_JKR^unloading)) gives :func:`unloading_pull_off_force`.
SI units: m, N, m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from asperity.errors import InputError
from asperity.statmodel import integrals as _k
from asperity.statmodel.jkr import jkr_jump_off_kernel
from asperity.statmodel.options import ModelSetup, QuadratureOptions, setup_model
from asperity.statmodel.parameters import Material, Roughness, finite_number


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
        Loading-branch pull-off force, N (<= 0): the most tensile load the preload stage can
        carry (see :func:`pull_off_force`).
    success : bool
        Whether the separation solve met its tolerance (``converged`` is an alias).
    status : int
        0 converged, 1 the separation solve did not converge within ``max_iter`` (see
        :data:`PRELOAD_STATUS`).
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
    success: bool
    status: int
    message: str
    nit: int

    @property
    def converged(self) -> bool:
        """Alias of ``success`` (the name of asperity 0.1)."""
        return self.success


#: ``PreloadResult.status`` codes and their meaning.
PRELOAD_STATUS: dict[int, str] = {
    0: "converged",
    1: "preload separation solve did not converge",
}


def preload_state(setup: ModelSetup, separation: float) -> np.ndarray:
    """Per-asperity integrals (layout of :mod:`statmodel.integrals`) of the preload at d (m)."""
    out = np.empty(_k.N_RESULTS)
    _k.asperity_integrals(
        float(separation), 0.0, setup.prm, setup.gl_x, setup.gl_w, setup.panels, out
    )
    return out


def _unloading_prm(setup: ModelSetup, preload_separation: float | None) -> np.ndarray:
    """Kernel parameters of the loading branch (None) or the unloading branch after d_min (m)."""
    return (
        setup.prm
        if preload_separation is None
        else setup.with_preload_separation(preload_separation)
    )


def _normal_force(setup: ModelSetup, prm: np.ndarray, separation: float) -> float:
    out = np.empty(_k.N_RESULTS)
    _k.asperity_integrals(float(separation), 0.0, prm, setup.gl_x, setup.gl_w, setup.panels, out)
    return setup.n_asperities * (out[_k.FZ_STICK] + out[_k.FZ_SLIP])


def zero_load_indentation(setup: ModelSetup) -> float:
    """Indentation delta_0 (m) where the JKR load E:JKR_load vanishes, a0^3 = 9 pi w R^2 / (2 E*).

    Asperities with delta > delta_0 push, those below pull: the loading curve can only be tensile
    where part of the contacting population lies below delta_0.
    """
    R, w, E = setup.roughness.summit_radius, setup.material.work_of_adhesion, setup.material.e_star
    a0 = (4.5 * math.pi * w * R * R / E) ** (1.0 / 3.0)
    return a0 * a0 / R - math.sqrt(2.0 * math.pi * w * a0 / E)


def pull_off_point(
    setup: ModelSetup, preload_separation: float | None = None
) -> tuple[float, float]:
    """(F_min, d_at_min): most tensile load (N) of a normal-load branch and where it occurs (m).

    ``preload_separation`` None: the loading branch E:Fy_Greenwood (lower limit
    delta_JKR^loading). A separation d_min (m): Greenwood's unloading branch after a preload to
    d_min (lower limit max(d_min - d + delta_JKR^loading, delta_JKR^unloading), i.e. E:delta_2 at
    delta_T = 0), searched over d >= d_min.

    The search window holds every separation where the asperity integrals are resolved: from
    d = -delta_0 - 6 sigma_s (below it every contact pushes) up to d = -delta_low + (cutoff - m)
    sigma_s, with delta_low the branch's lower limit and m = min(2, cutoff/4) a margin that keeps
    the truncation of the summit heights at cutoff sigma_s below exp(-(cutoff^2 - (cutoff - m)^2)
    / 2) of the integrand. A grid scan (321 points plus 161 around -delta_low) then a bounded
    Brent minimisation (xatol 1e-12 sigma_s) locate the minimum. When the minimum sits at the
    upper end of the window the branch is still compressive where it stops being resolved (rough
    surfaces, e.g. the paper's Fig. 4 where it would lie near d = 67 sigma_s): the pull-off force
    is then zero to the model's resolution and ``(-0.0, d_end)`` is returned.
    """
    sigma = setup.roughness.summit_height_rms
    cutoff = setup.options.cutoff_sigma
    margin = min(2.0, 0.25 * cutoff)
    prm = _unloading_prm(setup, preload_separation)
    delta_load = setup.jump_in_distance
    if preload_separation is None:
        delta_low = delta_load
    else:
        delta_low = min(
            delta_load,
            float(
                jkr_jump_off_kernel(
                    setup.roughness.summit_radius,
                    setup.material.work_of_adhesion,
                    setup.material.e_star,
                )
            ),
        )
    d_hi = -delta_low + (cutoff - margin) * sigma
    d_lo = -zero_load_indentation(setup) - 6.0 * sigma
    if preload_separation is not None:
        d_lo = max(d_lo, preload_separation)
    if not d_hi > d_lo:  # unloading from beyond the window: nothing left in contact
        return -0.0, float(d_lo)
    fine = -delta_low + np.linspace(-8.0, 8.0, 161) * sigma
    grid = np.unique(
        np.concatenate([np.linspace(d_lo, d_hi, 321), fine[(fine > d_lo) & (fine < d_hi)]])
    )
    values = np.array([_normal_force(setup, prm, d) for d in grid])
    i = int(np.argmin(values))
    if i == grid.size - 1 or values[i] >= 0.0:
        return -0.0, float(grid[-1])
    lo = grid[max(i - 1, 0)]
    hi = grid[i + 1]
    res = minimize_scalar(
        lambda d: _normal_force(setup, prm, d),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12 * sigma, "maxiter": 500},
    )
    if res.fun <= values[i]:
        return float(res.fun), float(res.x)
    return float(values[i]), float(grid[i])


def pull_off_force(
    material: Material, roughness: Roughness, nominal_area: float, **accuracy_knobs: float
) -> float:
    """Pull-off force of the loading branch (the preload stage), N (negative or -0.0).

    The minimum over the separation d of the loading curve F_z(d) of E:Fy_Greenwood (Greenwood
    2017's loading branch, lower limit Wu's jump-in distance E:JKR_delta_min_loading): the most
    tensile normal load at which the preload stage of this model has an equilibrium. It is the
    bound ``preload`` and ``shear_curve`` check an imposed load against: a more tensile load has
    no preload separation and raises ``InputError`` naming this force in N.

    It is not the force measured when pulling a pre-pressed contact apart: that one belongs to
    the unloading branch after a preload, depends on the preload and is more tensile (asperities
    hold on down to delta_JKR^unloading); see :func:`unloading_pull_off_force`. For rough surfaces
    (large Fuller-Tabor adhesion parameter, e.g. the paper's Fig. 4) both vanish: the loading
    curve stays compressive wherever the model resolves it and -0.0 is returned (see
    :func:`pull_off_point`).

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2 (must hold eta A_n >= 1 asperity).
    **accuracy_knobs
        See :mod:`statmodel.options`.

    Returns
    -------
    float
        F_pull-off, N (<= 0).
    """
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    return pull_off_point(setup)[0]


def unloading_pull_off_force(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    preload_load: float,
    **accuracy_knobs: float,
) -> float:
    """Pull-off force after a preload, N: the minimum of Greenwood's unloading branch.

    The contact is first loaded to ``preload_load`` (separation d_min on the loading branch,
    E:Fy_Greenwood), then unloaded at delta_T = 0: an asperity touching at the preload stays in
    contact down to delta_JKR^unloading, so the lower limit is max(d_min - d + delta_JKR^loading,
    delta_JKR^unloading) (E:delta_2 at delta_T = 0). The returned force is the most tensile load
    of that branch over d >= d_min (load control), i.e. what a pull-off test after this preload
    measures. It is at most :func:`pull_off_force` (equal or more tensile); in the smooth limit
    sigma_s -> 0 it tends to eta A_n times the JKR load-control pull-off -3/2 pi w R.

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2.
    preload_load : float
        Normal load of the preload, N (not below :func:`pull_off_force`).
    **accuracy_knobs
        See :mod:`statmodel.options`.

    Returns
    -------
    float
        F_pull-off after the preload, N (<= 0; -0.0 when zero to the model's resolution).
    """
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    pull = pull_off_point(setup)
    pre = solve_preload(setup, preload_load, pull)
    if not pre.converged:
        raise InputError(f"preload_load: {pre.message}")
    return pull_off_point(setup, pre.separation)[0]


def solve_preload(
    setup: ModelSetup, normal_load: float, pull_off: tuple[float, float] | None = None
) -> PreloadResult:
    """Preload separation for ``normal_load`` (N) with the kernels of ``setup``.

    ``pull_off`` is :func:`pull_off_point` of the same setup when already known.
    """
    target = finite_number(normal_load, "normal_load", "N", "load")
    f_min, d_min_force = pull_off_point(setup) if pull_off is None else pull_off
    if target < f_min:
        raise InputError(
            f"normal_load = {target:.6g} N is below the pull-off force {f_min:.6g} N of the "
            "loading branch (E:Fy_Greenwood, the most tensile load at which the preload stage "
            "has an equilibrium; see statmodel.pull_off_force)"
        )
    sigma = setup.roughness.summit_height_rms
    ftol = setup.options.load_rtol * max(abs(target), abs(f_min))
    out = np.empty(_k.N_RESULTS)
    work = np.empty(6)
    d, nit, ok = _k.solve_separation(
        d_min_force,
        0.05 * sigma,
        0.0,
        target,
        ftol,
        1e-15 * sigma,
        setup.options.max_iter,
        setup.prm,
        setup.gl_x,
        setup.gl_w,
        setup.panels,
        out,
        work,
    )
    n = setup.n_asperities
    status = 0 if ok else 1
    return PreloadResult(
        separation=float(d),
        normal_force=float(n * (out[_k.FZ_STICK] + out[_k.FZ_SLIP])),
        real_area=float(n * (out[_k.AR_STICK] + out[_k.AR_SLIP])),
        n_contact=float(n * (out[_k.N_STICK] + out[_k.N_SLIP])),
        tabor_parameter=setup.tabor_parameter,
        pull_off_force=f_min,
        success=bool(ok),
        status=status,
        message=PRELOAD_STATUS[status],
        nit=int(nit),
    )


def preload(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    normal_load: float,
    **accuracy_knobs: float,
) -> PreloadResult:
    """Separation, real area and contact count under a purely normal load (E:Fy_Greenwood).

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2 (eta A_n >= 1 required).
    normal_load : float
        Imposed F_z, N (compressive positive); must not be below :func:`pull_off_force` (the
        loading-branch pull-off force; the preload is on the loading branch).
    **accuracy_knobs
        See :mod:`statmodel.options`.

    Returns
    -------
    PreloadResult

    Raises
    ------
    InputError
        Bad inputs, or a normal load below the pull-off force (the message gives it in N).
    """
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    return solve_preload(setup, normal_load)


def real_area_at_loads(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    normal_loads: ArrayLike,
    **accuracy_knobs: float,
) -> np.ndarray:
    """Real contact area A_r (m^2) at delta_T = 0 for each normal load (N), E:Ar_Greenwood."""
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    loads = np.atleast_1d(np.asarray(normal_loads, dtype=float))
    pull = pull_off_point(setup)
    return np.array([solve_preload(setup, f, pull).real_area for f in loads.ravel()]).reshape(
        loads.shape
    )
