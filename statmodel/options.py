"""Accuracy knobs of the fast statistical model and the assembly of the compiled-kernel inputs.

Knobs (keyword arguments of :func:`statmodel.shear_curve` and friends), each bounded at
construction (:class:`QuadratureOptions`) by its ``accuracy.<knob>`` entry of
:data:`asperity.quantities.QUANTITIES` (the same bound as the ``[accuracy]`` table of a parameter
file); a value outside its range raises :class:`asperity.errors.InputError` with the reason:

``nodes`` (default 16, 1 to 128)
    Gauss-Legendre nodes per panel. 16 already reach 1e-8 relative; more than 128 gain nothing in
    double precision while the cost grows linearly.
``panels`` (default 4, 1 to 64)
    Equal panels per population range: in u = sqrt(k^2 a - c) for the stick (PC) population,
    in the contact radius a for the slip (Hertz) population (see :mod:`statmodel.integrals`).
``cutoff_sigma`` (default 10, 8 to 40)
    Summit heights |z| > cutoff_sigma * sigma_s are ignored (phi(10) ~ 8e-23 relative to phi(0)).
    Below 8 the truncated tail costs more than the model's 1e-6 accuracy (6 sigma_s: 3e-4 on the
    static friction of Fig. 4); beyond 40 the Gaussian underflows (phi(40) ~ 1e-348) and the
    panels only spread over empty heights (1e3 gave a static friction of 2.4e-4 N instead of
    0.82 N).
``load_rtol`` (default 1e-12, 1e-14 to 1e-6)
    The separation is solved until |F_z - F_imposed| <= load_rtol * max(|F_imposed|, |F_pull-off|).
    Looser than 1e-6 the normal load, and with it F_x and A_r, is no longer resolved to the
    model's accuracy (``load_rtol = 1`` accepted the first bracket, 2.9e-14 N of friction); tighter
    than 1e-14 is below the round-off of the load integral.
``max_iter`` (default 200, 1 to 10000)
    Most Brent iterations per separation solve (it needs about 10-40).

With the defaults, F_x, A_r and F_z agree with :mod:`statmodel.reference` to better than 1e-6
relative at every step of the issue's test case (see docs/statmodel.md for the measured table).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from asperity.errors import InputError
from asperity.quantities import quantity
from asperity.statmodel import integrals as _k
from asperity.statmodel.jkr import jkr_jump_in_kernel
from asperity.statmodel.parameters import Material, Roughness, material_tabor_parameter

#: The accuracy knobs, in the order of :class:`QuadratureOptions`; each is bounded by
#: ``accuracy.<knob>`` of :data:`asperity.quantities.QUANTITIES` (shared with ``[accuracy]``).
KNOBS: tuple[str, ...] = ("nodes", "panels", "cutoff_sigma", "load_rtol", "max_iter")

#: knob -> (lowest, highest, why the range): a view of the shared bounds.
KNOB_BOUNDS: dict[str, tuple[float, float, str]] = {
    knob: (
        quantity(f"accuracy.{knob}").low,
        quantity(f"accuracy.{knob}").high,
        quantity(f"accuracy.{knob}").why,
    )
    for knob in KNOBS
}


@dataclass(frozen=True)
class QuadratureOptions:
    """Accuracy knobs of the fast model (see the module docstring)."""

    nodes: int = 16
    panels: int = 4
    cutoff_sigma: float = 10.0
    load_rtol: float = 1e-12
    max_iter: int = 200

    def __post_init__(self) -> None:
        for knob in KNOBS:
            value = quantity(f"accuracy.{knob}").check(getattr(self, knob), knob)
            object.__setattr__(self, knob, value)

    @classmethod
    def from_knobs(cls, **knobs: Any) -> QuadratureOptions:
        """Build from keyword knobs; an unknown knob raises ``InputError`` naming it."""
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(knobs) - names)
        if unknown:
            raise InputError(
                f"unknown accuracy knob(s) {unknown}; expected some of {sorted(names)}"
            )
        return cls(**knobs)


@dataclass(frozen=True)
class ModelSetup:
    """Inputs of the compiled kernels for one (material, roughness, nominal area, options)."""

    prm: np.ndarray
    gl_x: np.ndarray
    gl_w: np.ndarray
    panels: int
    n_asperities: float
    tabor_parameter: float
    jump_in_distance: float
    options: QuadratureOptions
    material: Material
    roughness: Roughness
    nominal_area: float

    def with_preload_separation(self, separation: float) -> np.ndarray:
        """Copy of ``prm`` with the preload separation d_min set (NaN: the preload stage itself)."""
        prm = self.prm.copy()
        prm[_k.P_D_PRELOAD] = separation
        return prm


def check_nominal_area(roughness: Roughness, nominal_area: float) -> float:
    """Validate A_n (m^2): within ``loading.nominal_area`` of :mod:`asperity.quantities` and
    holding at least one asperity (eta A_n >= 1)."""
    area = quantity("loading.nominal_area").check(nominal_area, "nominal_area")
    n = roughness.asperity_density * area
    if n < 1.0:
        raise InputError(
            f"nominal_area = {area:.6g} m^2 holds eta*A_n = {n:.3g} < 1 asperity "
            f"(asperity_density = {roughness.asperity_density:.6g} 1/m^2); "
            "the statistical model needs at least one"
        )
    return area


def setup_model(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    options: QuadratureOptions | None = None,
) -> ModelSetup:
    """Validate the inputs and pack them for the compiled kernels (SI units)."""
    if not isinstance(material, Material):
        raise InputError(f"material: expected a statmodel.Material, got {type(material).__name__}")
    if not isinstance(roughness, Roughness):
        raise InputError(
            f"roughness: expected a statmodel.Roughness, got {type(roughness).__name__}"
        )
    options = options or QuadratureOptions()
    area = check_nominal_area(roughness, nominal_area)
    mu = material_tabor_parameter(material, roughness)
    delta_load = jkr_jump_in_kernel(mu, material.equilibrium_distance)
    prm = np.empty(_k.N_PARAMS)
    prm[_k.P_D_PRELOAD] = np.nan
    prm[_k.P_R] = roughness.summit_radius
    prm[_k.P_E] = material.e_star
    prm[_k.P_W] = material.work_of_adhesion
    prm[_k.P_LAM] = material.mode_mixity
    prm[_k.P_TAU] = material.shear_strength
    prm[_k.P_SIGMA] = roughness.summit_height_rms
    prm[_k.P_DELTA_LOAD] = delta_load
    prm[_k.P_N_ASP] = roughness.asperity_density * area
    prm[_k.P_CUTOFF] = options.cutoff_sigma
    gl_x, gl_w = _k.gauss_legendre(options.nodes)
    return ModelSetup(
        prm=prm,
        gl_x=gl_x,
        gl_w=gl_w,
        panels=int(options.panels),
        n_asperities=float(prm[_k.P_N_ASP]),
        tabor_parameter=mu,
        jump_in_distance=float(delta_load),
        options=options,
        material=material,
        roughness=roughness,
        nominal_area=area,
    )
