"""Measured curves to calibrate against: CSV files in SI units with a header row.

* A_r(F_z) at rest: columns ``normal_load`` (N) and ``real_area`` (m^2).
* A_r(F_x) under shear: columns ``tangential_force`` (N) and ``real_area`` (m^2), one file per
  normal load (the load given in the configuration), or one long file with an extra
  ``normal_load`` (N) column holding several loads.

Extra columns are ignored; comment lines start with ``#``. A file that lacks a column, holds a
non-numeric or non-finite value, or has fewer than two rows is refused with a message naming
the file and the column.
"""

from __future__ import annotations

import csv
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from asperity.errors import InputError


class MeasuredFileError(InputError):
    """A measured CSV file is malformed; the message names the file, row and column."""


@dataclass(frozen=True)
class NormalAreaCurve:
    """Measured real contact area at rest against normal load.

    Attributes
    ----------
    normal_load : ndarray
        F_z, N (sorted ascending).
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: np.ndarray
    real_area: np.ndarray
    source: str = ""


@dataclass(frozen=True)
class ShearAreaCurve:
    """Measured real contact area against tangential force at one normal load.

    Attributes
    ----------
    normal_load : float
        F_z, N.
    tangential_force : ndarray
        F_x, N.
    real_area : ndarray
        A_r, m^2.
    source : str
        File it was read from.
    """

    normal_load: float
    tangential_force: np.ndarray
    real_area: np.ndarray
    source: str = ""


def read_columns(
    path: str | Path, columns: Sequence[str], optional: Iterable[str] = ()
) -> dict[str, np.ndarray]:
    """Read named numeric columns of a CSV file with a header row.

    Parameters
    ----------
    path : path
        The CSV file.
    columns : sequence of str
        Required column names.
    optional : iterable of str
        Columns returned when present.

    Raises
    ------
    MeasuredFileError
        Missing column, non-numeric or non-finite value, fewer than two data rows.
    """
    path = Path(path)
    with open(path, newline="", encoding="utf-8") as handle:
        lines = [line for line in handle if line.strip() and not line.lstrip().startswith("#")]
    reader = csv.reader(lines)
    try:
        header = [name.strip() for name in next(reader)]
    except StopIteration:
        raise MeasuredFileError(
            f"{path}: empty file; expected a header row with {', '.join(columns)}"
        ) from None
    wanted = list(columns) + [c for c in optional if c in header]
    for name in columns:
        if name not in header:
            raise MeasuredFileError(
                f"{path}: missing column {name!r} (header: {', '.join(header)}); "
                f"expected columns {', '.join(columns)} in SI units"
            )
    index = {name: header.index(name) for name in wanted}
    values: dict[str, list[float]] = {name: [] for name in wanted}
    for row_number, row in enumerate(reader, start=2):
        for name, i in index.items():
            try:
                value = float(row[i])
            except (IndexError, ValueError):
                raise MeasuredFileError(
                    f"{path}: row {row_number}, column {name!r}: expected a "
                    f"number, got {row[i] if i < len(row) else 'nothing'!r}"
                ) from None
            if not np.isfinite(value):
                raise MeasuredFileError(f"{path}: row {row_number}, column {name!r}: not finite")
            values[name].append(value)
    arrays = {name: np.asarray(v, dtype=float) for name, v in values.items()}
    if len(arrays[columns[0]]) < 2:
        raise MeasuredFileError(f"{path}: fewer than two data rows")
    return arrays


def read_normal_area(path: str | Path) -> NormalAreaCurve:
    """Read a measured A_r(F_z) CSV (``normal_load`` N, ``real_area`` m^2)."""
    cols = read_columns(path, ("normal_load", "real_area"))
    if np.any(cols["real_area"] < 0):
        raise MeasuredFileError(f"{path}: column 'real_area': negative area (expected m^2 >= 0)")
    order = np.argsort(cols["normal_load"])
    return NormalAreaCurve(cols["normal_load"][order], cols["real_area"][order], str(path))


def read_shear_area(path: str | Path, normal_load: float | None = None) -> list[ShearAreaCurve]:
    """Read measured A_r(F_x) curves from one CSV file.

    Parameters
    ----------
    path : path
        Columns ``tangential_force`` (N), ``real_area`` (m^2) and, for a long file holding
        several loads, ``normal_load`` (N).
    normal_load : float, optional
        The normal load, N, of a one-curve file without a ``normal_load`` column.

    Returns
    -------
    list of ShearAreaCurve
        One per distinct normal load, points sorted by tangential force.
    """
    cols = read_columns(path, ("tangential_force", "real_area"), optional=("normal_load",))
    if np.any(cols["real_area"] < 0):
        raise MeasuredFileError(f"{path}: column 'real_area': negative area (expected m^2 >= 0)")
    if "normal_load" in cols:
        loads = cols["normal_load"]
    elif normal_load is not None:
        loads = np.full(cols["real_area"].shape, float(normal_load))
    else:
        raise MeasuredFileError(
            f"{path}: no 'normal_load' column and no normal_load given in the "
            "configuration (measured.shear_area)"
        )
    curves = []
    for load in np.unique(loads):
        pick = loads == load
        fx, ar = cols["tangential_force"][pick], cols["real_area"][pick]
        order = np.argsort(fx, kind="stable")
        curves.append(ShearAreaCurve(float(load), fx[order], ar[order], str(path)))
    return curves


def write_shear_area(path: str | Path, curves: Sequence[ShearAreaCurve]) -> None:
    """Write curves as one long CSV (``normal_load,tangential_force,real_area``, SI)."""
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(["normal_load", "tangential_force", "real_area"])
        for curve in curves:
            for fx, ar in zip(curve.tangential_force, curve.real_area, strict=True):
                writer.writerow([repr(curve.normal_load), repr(float(fx)), repr(float(ar))])


@dataclass(frozen=True)
class Measurements:
    """The measured curves of a job configuration (``[measured]``), read before any stage.

    Attributes
    ----------
    normal_area : NormalAreaCurve or None
        A_r(F_z) at rest.
    shear_area : list of ShearAreaCurve
        A_r(F_x) curves, one per normal load.
    """

    normal_area: NormalAreaCurve | None = None
    shear_area: list[ShearAreaCurve] = field(default_factory=list)


def read_measurements(config: Any) -> Measurements:
    """Read every measured file of a ``[measured]`` configuration (``MeasuredConfig``)."""
    normal = None if config.normal_area is None else read_normal_area(config.normal_area)
    shear: list[ShearAreaCurve] = []
    for item in config.shear_area:
        shear += read_shear_area(item.file, item.normal_load)
    return Measurements(normal, shear)
