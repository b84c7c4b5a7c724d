"""The ``asperity friction`` parameter file (TOML, SI units): its schema, reading and validation.

Schema (every key required unless marked optional; bounds in brackets)::

    [material]
    E_star = 2.133e6               # Pa, (0, 1e13]; also spelled e_star
    work_of_adhesion = 0.040       # J/m^2, [0, 10]
    mode_mixity = 0.2              # lambda, [0, 1]
    shear_strength = 0.13e6        # tau0, Pa, [0, 1e11]
    equilibrium_distance = 0.2e-9  # epsilon, m, [1e-11, 1e-8] (optional, default 0.2e-9)
    [roughness]
    asperity_density = 652.1e6     # eta, 1/m^2, (0, 1e20]
    summit_radius = 0.041e-3       # R, m, [1e-10, 10]
    summit_height_rms = 0.032e-3   # sigma_s, m, [1e-12, 1]
    [loading]
    normal_load = 3.1              # N, [-1e6, 1e6]
    nominal_area = 700e-6          # m^2, (0, 100]
    max_tangential_displacement = 14e-6  # m, (0, 1]
    steps = 281                    # integer in [1, 100000]; delta_T = linspace(0, max, steps)
                                   # (steps = 1: the preload state delta_T = 0 only)
    [accuracy]                     # optional table: knobs of statmodel.options
    nodes = 16                     # [1, 64]
    panels = 4                     # [1, 64]
    cutoff_sigma = 10.0            # [3, 40]
    load_rtol = 1e-12              # [1e-15, 1e-3]

The ``[material]`` table is the one the job configuration (``asperity run``) reads too
(:func:`material_section`). Every error is one :class:`asperity.schema.ConfigError` line
``file: table.key: expected ..., got ...``.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from asperity.files import MAX_CONFIG_BYTES, read_bytes_bounded
from asperity.schema import (
    REQUIRED,
    ConfigError,
    Context,
    Integer,
    Key,
    Real,
    Schema,
    Section,
)
from asperity.statmodel.parameters import Material, Roughness

if TYPE_CHECKING:
    from asperity.statmodel.options import QuadratureOptions

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

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
                Real("Pa", 0, 1e13, open_low=True, why="no solid is stiffer than diamond"),
                default("e_star"),
                aliases=("e_star",),
                attr="e_star",
            ),
            Key(
                "work_of_adhesion",
                Real("J/m^2", 0, 10, why="twice the surface energy of the strongest solids"),
                default("work_of_adhesion"),
            ),
            Key(
                "mode_mixity",
                Real("", 0, 1, why="lambda: 0 pure JKR, 1 Savkoor-Briggs (E:failure_locus)"),
                default("mode_mixity"),
            ),
            Key(
                "shear_strength",
                Real("Pa", 0, 1e11, why="the theoretical shear strength of solids, ~G/10"),
                default("shear_strength"),
            ),
            Key(
                "equilibrium_distance",
                Real("m", 1e-11, 1e-8, why="an interatomic distance"),
                EQUILIBRIUM_DISTANCE if defaults is None else defaults.equilibrium_distance,
            ),
        ),
        required=defaults is None,
    )


ROUGHNESS = Section(
    "roughness",
    Roughness,
    (
        Key(
            "asperity_density",
            Real("1/m^2", 0, 1e20, open_low=True, why="at most one summit per 0.1 nm square"),
        ),
        Key("summit_radius", Real("m", 1e-10, 10, why="from an atom to a 10 m sphere")),
        Key("summit_height_rms", Real("m", 1e-12, 1, why="from a picometre to a metre")),
    ),
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
        Key("normal_load", Real("N", -1e6, 1e6, why="a laboratory or machine contact")),
        Key("nominal_area", Real("m^2", 0, 100, open_low=True, why="up to 10 m x 10 m")),
        Key(
            "max_tangential_displacement",
            Real("m", 0, 1, open_low=True, why="a shear path up to 1 m"),
        ),
        Key(
            "steps",
            Integer(1, 100_000, why="one separation solve and 17 stored values per step"),
        ),
    ),
    required=True,
)


def _quadrature_options(**knobs: Any) -> QuadratureOptions:
    from asperity.statmodel.options import QuadratureOptions  # loads the compiled kernels

    return QuadratureOptions(**{k: v for k, v in knobs.items() if v is not None})


ACCURACY = Section(
    "accuracy",
    _quadrature_options,
    (
        Key("nodes", Integer(1, 64, why="Gauss-Legendre nodes per panel"), None),
        Key("panels", Integer(1, 64, why="panels per population range"), None),
        Key(
            "cutoff_sigma",
            Real(
                "",
                3,
                40,
                why="summits beyond cutoff_sigma * sigma_s are ignored: below 3 a visible "
                "share is dropped, beyond 40 the Gaussian weight underflows",
            ),
            None,
        ),
        Key(
            "load_rtol",
            Real(
                "",
                1e-15,
                1e-3,
                why="relative load error of each separation solve: double precision to 0.1 %",
            ),
            None,
        ),
    ),
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
    path = Path(path)
    try:
        text = read_bytes_bounded(path, "parameter file", MAX_CONFIG_BYTES).decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(
            f"{path}: cannot read the parameter file: {getattr(exc, 'strerror', None) or exc}"
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    return parse_friction_parameters(data, str(path))
