"""Accuracy knobs of the fast statistical model and the assembly of the compiled-kernel inputs.

Knobs (keyword arguments of :func:`statmodel.shear_curve` and friends):

``nodes`` (default 16)
    Gauss-Legendre nodes per panel.
``panels`` (default 4)
    Equal panels per population range: in u = sqrt(k^2 a - c) for the stick (PC) population,
    in the contact radius a for the slip (Hertz) population (see :mod:`statmodel.integrals`).
``cutoff_sigma`` (default 10)
    Summit heights |z| > cutoff_sigma * sigma_s are ignored (phi(10) ~ 8e-23 relative to phi(0)).
``load_rtol`` (default 1e-12)
    The separation is solved until |F_z - F_imposed| <= load_rtol * max(|F_imposed|, |F_pull-off|).
``max_iter`` (default 200)
    Most Brent iterations per separation solve.

With the defaults, F_x, A_r and F_z agree with :mod:`statmodel.reference` to better than 1e-6
relative at every step of the issue's test case (see docs/statmodel.md for the measured table).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from asperity.errors import InputError
from asperity.statmodel import integrals as _k
from asperity.statmodel.jkr import jkr_jump_in_kernel
from asperity.statmodel.parameters import Material, Roughness, material_tabor_parameter


@dataclass(frozen=True)
class QuadratureOptions:
    """Accuracy knobs of the fast model (see the module docstring)."""

    nodes: int = 16
    panels: int = 4
    cutoff_sigma: float = 10.0
    load_rtol: float = 1e-12
    max_iter: int = 200

    def __post_init__(self) -> None:
        if int(self.nodes) != self.nodes or self.nodes < 1:
            raise InputError(f"nodes: expected a positive integer, got {self.nodes!r}")
        if int(self.panels) != self.panels or self.panels < 1:
            raise InputError(f"panels: expected a positive integer, got {self.panels!r}")
        if not (math.isfinite(self.cutoff_sigma) and self.cutoff_sigma > 0):
            raise InputError(f"cutoff_sigma: expected a positive number, got {self.cutoff_sigma!r}")
        if not (math.isfinite(self.load_rtol) and self.load_rtol > 0):
            raise InputError(f"load_rtol: expected a positive number, got {self.load_rtol!r}")
        if int(self.max_iter) != self.max_iter or self.max_iter < 1:
            raise InputError(f"max_iter: expected a positive integer, got {self.max_iter!r}")

    @classmethod
    def from_knobs(cls, **knobs: float) -> QuadratureOptions:
        """Build from keyword knobs; an unknown knob raises ``ValueError`` naming it."""
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
    """Validate A_n (m^2): finite, positive and holding at least one asperity (eta A_n >= 1)."""
    try:
        area = float(nominal_area)
    except (TypeError, ValueError):
        raise InputError(f"nominal_area: expected a number in m^2, got {nominal_area!r}") from None
    if not (math.isfinite(area) and area > 0.0):
        raise InputError(f"nominal_area: expected a positive area in m^2, got {nominal_area!r}")
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
