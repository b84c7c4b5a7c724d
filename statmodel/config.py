"""The ``asperity friction`` parameter file (TOML, SI units): its schema, reading and validation.

Schema (every key required unless marked optional; bounds in brackets, each written once in
:data:`asperity.quantities.QUANTITIES` with its reason)::

    [material]
    E_star = 2.133e6               # Pa, [1e2, 1e13]; also spelled e_star
    work_of_adhesion = 0.040       # J/m^2, [0, 10]
    mode_mixity = 0.2              # lambda, [0, 1]
    shear_strength = 0.13e6        # tau0, Pa, [0, 1e11]
    equilibrium_distance = 0.2e-9  # epsilon, m, [1e-11, 1e-8] (optional, default 0.2e-9)
    [roughness]
    asperity_density = 652.1e6     # eta, 1/m^2, [1e-6, 1e20]
    summit_radius = 0.041e-3       # R, m, [1e-10, 100]
    summit_height_rms = 0.032e-3   # sigma_s, m, [1e-12, 1]
    [loading]
    normal_load = 3.1              # N, [-1e6, 1e6]
    nominal_area = 700e-6          # m^2, (0, 100]
    max_tangential_displacement = 14e-6  # m, (0, 1]
    steps = 281                    # integer in [1, 100000]; delta_T = linspace(0, max, steps)
                                   # (steps = 1: the preload state delta_T = 0 only)
    [accuracy]                     # optional table: knobs of statmodel.options
    nodes = 16                     # [1, 128]
    panels = 4                     # [1, 64]
    cutoff_sigma = 10.0            # [8, 40]
    load_rtol = 1e-12              # [1e-14, 1e-6]
    max_iter = 200                 # [1, 10000]

The ``[material]`` table is the one the job configuration (``asperity run``) reads too
(:func:`material_section`). Every error is one :class:`asperity.schema.ConfigError` line
``file: table.key: expected ..., got ...``.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from asperity.quantities import quantity
from asperity.schema import REQUIRED, Context, Key, Schema, Section, read_toml
from asperity.statmodel.parameters import Material, Roughness

if TYPE_CHECKING:
    from asperity.statmodel.options import QuadratureOptions

#: Default of ``[material] equilibrium_distance``, m.
EQUILIBRIUM_DISTANCE = 0.2e-9


def material_section(defaults: Material | None = None) -> Section:
    """The ``[material]`` table building a :class:`Material` (SI), with its bounds.

    Parameters
    ----------
    defaults : Material, optional
        Values of absent keys; None makes every key but ``equilibrium_distance`` required.
    """

    def default(name: str) -> Any:
        return REQUIRED if defaults is None else getattr(defaults, name)

    return Section(
        "material",
        Material,
        (
            Key(
                "E_star",
                quantity("material.E_star").kind,
                default("e_star"),
                aliases=("e_star",),
                attr="e_star",
            ),
            *(
                Key(name, quantity(f"material.{name}").kind, default(name))
                for name in ("work_of_adhesion", "mode_mixity", "shear_strength")
            ),
            Key(
                "equilibrium_distance",
                quantity("material.equilibrium_distance").kind,
                EQUILIBRIUM_DISTANCE if defaults is None else defaults.equilibrium_distance,
            ),
        ),
        required=defaults is None,
    )


def _keys(table: str, names: tuple[str, ...], default: Any = REQUIRED) -> tuple[Key, ...]:
    """Keys ``names`` of ``table`` bounded by their ``table.name`` quantity."""
    return tuple(Key(name, quantity(f"{table}.{name}").kind, default) for name in names)


ROUGHNESS = Section(
    "roughness",
    Roughness,
    _keys("roughness", ("asperity_density", "summit_radius", "summit_height_rms")),
    required=True,
)


@dataclass(frozen=True)
class FrictionLoading:
    """The ``[loading]`` table of a friction parameter file (SI).

    Attributes
    ----------
    normal_load : float
        Imposed F_z, N.
    nominal_area : float
        A_n, m^2.
    max_tangential_displacement : float
        Last delta_T, m.
    steps : int
        Number of delta_T values, the first at 0.
    """

    normal_load: float
    nominal_area: float
    max_tangential_displacement: float
    steps: int


LOADING = Section(
    "loading",
    FrictionLoading,
    (
        *_keys("loading", ("normal_load", "nominal_area", "max_tangential_displacement")),
        Key("steps", quantity("friction.loading.steps").kind),
    ),
    required=True,
)


def _quadrature_options(**knobs: Any) -> QuadratureOptions:
    # deferred: statmodel.options loads numba kernels; a job's configuration is
    # checked (pipelines.config, `asperity --help` too) before any numerical library loads
    from asperity.statmodel.options import QuadratureOptions  # loads the compiled kernels

    return QuadratureOptions(**{k: v for k, v in knobs.items() if v is not None})


ACCURACY = Section(
    "accuracy",
    _quadrature_options,
    _keys("accuracy", ("nodes", "panels", "cutoff_sigma", "load_rtol", "max_iter"), None),
)

#: The whole friction parameter file.
FRICTION_SCHEMA = Schema((material_section(), ROUGHNESS, LOADING, ACCURACY))


@dataclass(frozen=True)
class FrictionParameters:
    """Validated contents of a friction parameter file (SI units).

    Attributes
    ----------
    material : Material
    roughness : Roughness
    normal_load, nominal_area, max_tangential_displacement : float
        N, m^2, m.
    steps : int
    options : statmodel.QuadratureOptions
        The accuracy knobs (defaults where ``[accuracy]`` does not set them).
    """

    material: Material
    roughness: Roughness
    normal_load: float
    nominal_area: float
    max_tangential_displacement: float
    steps: int
    options: QuadratureOptions

    @property
    def accuracy(self) -> dict[str, Any]:
        """The accuracy knobs as keyword arguments of :func:`statmodel.shear_curve`."""
        return {f.name: getattr(self.options, f.name) for f in fields(self.options)}

    @property
    def tangential_displacement(self) -> Any:
        """delta_T = linspace(0, max_tangential_displacement, steps), m (first entry 0)."""
        import numpy as np

        return np.linspace(0.0, self.max_tangential_displacement, self.steps)


def parse_friction_parameters(data: Any, path: str = "<parameters>") -> FrictionParameters:
    """Validate a parsed TOML document against the schema; see the module docstring.

    Raises
    ------
    ConfigError
        ``path: table.key: expected ..., got ...``.
    """
    # deferred: statmodel.options loads numba kernels (see _quadrature_options)
    from asperity.statmodel.options import check_nominal_area

    values = FRICTION_SCHEMA.read(data, source=path)
    loading: FrictionLoading = values["loading"]
    try:
        check_nominal_area(values["roughness"], loading.nominal_area)
    except ValueError as exc:
        raise Context(path).fail(
            "loading.nominal_area", "an area holding at least one asperity", str(exc)
        ) from None
    return FrictionParameters(
        material=values["material"],
        roughness=values["roughness"],
        normal_load=loading.normal_load,
        nominal_area=loading.nominal_area,
        max_tangential_displacement=loading.max_tangential_displacement,
        steps=loading.steps,
        options=values["accuracy"],
    )


def read_friction_parameters(path: str | Path) -> FrictionParameters:
    """Read and validate a friction parameter TOML file.

    Raises
    ------
    ConfigError
        Missing or unreadable file, invalid TOML, or a key outside the schema.
    """
    return parse_friction_parameters(read_toml(path, "parameter file"), str(path))
