"""The ``asperity friction`` parameter file (TOML, SI units): reading and validation.

Schema (every key required unless marked optional)::

    [material]
    E_star = 2.133e6               # Pa, > 0
    work_of_adhesion = 0.040       # J/m^2, >= 0
    mode_mixity = 0.2              # lambda, in [0, 1]
    shear_strength = 0.13e6        # tau0, Pa, >= 0
    equilibrium_distance = 0.2e-9  # epsilon, m, > 0 (optional, default 0.2e-9)
    [roughness]
    asperity_density = 652.1e6     # eta, 1/m^2, > 0
    summit_radius = 0.041e-3       # R, m, > 0
    summit_height_rms = 0.032e-3   # sigma_s, m, > 0
    [loading]
    normal_load = 3.1              # N
    nominal_area = 700e-6          # m^2, > 0
    max_tangential_displacement = 14e-6  # m, > 0
    steps = 281                    # integer >= 1; delta_T = linspace(0, max, steps)
                                   # (steps = 1: the preload state delta_T = 0 only)
    [accuracy]                     # optional table: knobs of statmodel.options
    nodes = 16
    panels = 4
    cutoff_sigma = 10.0
    load_rtol = 1e-12

Unknown tables or keys, missing keys, non-numbers and out-of-range values raise ``ValueError``
naming the file, the table, the key and what was expected.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from asperity.errors import InputError
from asperity.statmodel.options import QuadratureOptions, check_nominal_area
from asperity.statmodel.parameters import Material, Roughness

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

# key -> (attribute name, unit, check, required)
_MATERIAL = {
    "E_star": ("e_star", "Pa", "positive", True),
    "work_of_adhesion": ("work_of_adhesion", "J/m^2", "non-negative", True),
    "mode_mixity": ("mode_mixity", "dimensionless", "unit-interval", True),
    "shear_strength": ("shear_strength", "Pa", "non-negative", True),
    "equilibrium_distance": ("equilibrium_distance", "m", "positive", False),
}
_ROUGHNESS = {
    "asperity_density": ("asperity_density", "1/m^2", "positive", True),
    "summit_radius": ("summit_radius", "m", "positive", True),
    "summit_height_rms": ("summit_height_rms", "m", "positive", True),
}
_LOADING = {
    "normal_load": ("normal_load", "N", "finite", True),
    "nominal_area": ("nominal_area", "m^2", "positive", True),
    "max_tangential_displacement": ("max_tangential_displacement", "m", "positive", True),
    "steps": ("steps", "count", "steps", True),
}
_ACCURACY = {
    "nodes": ("nodes", "count", "count", False),
    "panels": ("panels", "count", "count", False),
    "cutoff_sigma": ("cutoff_sigma", "sigma_s", "positive", False),
    "load_rtol": ("load_rtol", "relative", "positive", False),
}
_TABLES = {
    "material": _MATERIAL,
    "roughness": _ROUGHNESS,
    "loading": _LOADING,
    "accuracy": _ACCURACY,
}
_REQUIRED_TABLES = ("material", "roughness", "loading")


@dataclass(frozen=True)
class FrictionParameters:
    """Validated contents of a friction parameter file (SI units)."""

    material: Material
    roughness: Roughness
    normal_load: float
    nominal_area: float
    max_tangential_displacement: float
    steps: int
    accuracy: dict

    @property
    def tangential_displacement(self) -> np.ndarray:
        """delta_T = linspace(0, max_tangential_displacement, steps), m (first entry 0)."""
        return np.linspace(0.0, self.max_tangential_displacement, self.steps)


def _value(path: str, table: str, key: str, raw: Any, unit: str, check: str) -> float | int:
    where = f"{path}: [{table}] {key}"
    if isinstance(raw, bool) or not isinstance(raw, (int, float)):
        raise InputError(f"{where}: expected a number ({unit}), got {raw!r}")
    value = float(raw)
    if not math.isfinite(value):
        raise InputError(f"{where}: expected a finite number ({unit}), got {raw!r}")
    if check == "positive" and not value > 0:
        raise InputError(f"{where}: expected a positive value ({unit}), got {raw!r}")
    if check == "non-negative" and not value >= 0:
        raise InputError(f"{where}: expected a value >= 0 ({unit}), got {raw!r}")
    if check == "unit-interval" and not 0 <= value <= 1:
        raise InputError(f"{where}: expected a value in [0, 1], got {raw!r}")
    if check in ("steps", "count"):
        least = 1
        if not isinstance(raw, int) or raw < least:
            raise InputError(f"{where}: expected an integer >= {least}, got {raw!r}")
        return int(raw)
    return value


def parse_friction_parameters(data: dict, path: str = "<parameters>") -> FrictionParameters:
    """Validate a parsed TOML document (dict) against the schema; see the module docstring."""
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a TOML document with tables")
    unknown = sorted(set(data) - set(_TABLES))
    if unknown:
        raise InputError(
            f"{path}: unknown table or key {unknown[0]!r}; expected tables {sorted(_TABLES)}"
        )
    values: dict[str, dict[str, float | int]] = {}
    for table, schema in _TABLES.items():
        section = data.get(table)
        if section is None:
            if table in _REQUIRED_TABLES:
                raise InputError(f"{path}: missing table [{table}]")
            section = {}
        if not isinstance(section, dict):
            raise InputError(f"{path}: {table!r} must be a table [{table}]")
        extra = sorted(set(section) - set(schema))
        if extra:
            raise InputError(
                f"{path}: [{table}] unknown key {extra[0]!r}; expected keys {sorted(schema)}"
            )
        values[table] = {}
        for key, (attr, unit, check, required) in schema.items():
            if key not in section:
                if required:
                    raise InputError(f"{path}: [{table}] missing key {key!r} ({unit})")
                continue
            values[table][attr] = _value(path, table, key, section[key], unit, check)
    try:
        material = Material(**values["material"])
        roughness = Roughness(**values["roughness"])
        accuracy = dict(values["accuracy"])
        QuadratureOptions.from_knobs(**accuracy)
    except ValueError as exc:
        raise InputError(f"{path}: {exc}") from None
    load = values["loading"]
    try:
        check_nominal_area(roughness, load["nominal_area"])
    except ValueError as exc:
        raise InputError(f"{path}: [loading] {exc}") from None
    return FrictionParameters(
        material=material,
        roughness=roughness,
        normal_load=float(load["normal_load"]),
        nominal_area=float(load["nominal_area"]),
        max_tangential_displacement=float(load["max_tangential_displacement"]),
        steps=int(load["steps"]),
        accuracy=accuracy,
    )


def read_friction_parameters(path: str | Path) -> FrictionParameters:
    """Read and validate a friction parameter TOML file (raises ``ValueError`` / ``OSError``)."""
    path = Path(path)
    with path.open("rb") as fh:
        try:
            data = tomllib.load(fh)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{path}: not valid TOML: {exc}") from None
    return parse_friction_parameters(data, str(path))
