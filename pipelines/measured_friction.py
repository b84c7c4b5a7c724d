"""Measured friction tests: F_x against the drive's displacement, CSV files with a header row.

Columns ``drive_displacement`` (m: the drive, the motor, not the interface; the loading system's
spring is in between, ``loading.drive_stiffness``), ``tangential_force`` (N) and, for a long
file holding several loads, ``normal_load`` (N). One file per normal load (the load declared in
the configuration, ``friction_curves = [{normal_load = 0.56, file = "f056.csv"}]``), or one long
file (``friction_curves = "friction.csv"``), as the A_r(F_x) curves of
:mod:`asperity.pipelines.measured`, whose reading, units and checks this module reuses:

* a header cell may state its unit: ``drive_displacement [mm]``, ``tangential_force (mN)``
  (:data:`asperity.pipelines.measured.UNIT_FACTORS`); without one the column is SI;
* a missing column, a non-numeric or non-finite value, fewer than two rows: refused naming the
  file, its line and the column (:func:`asperity.pipelines.measured.read_columns`);
* |F_x| / F_z above 100, what mN under an SI header looks like: refused with the unit that
  would fit (:func:`asperity.pipelines.measured.check_friction_magnitude`);
* a curve at a load matching none of ``loading.normal_loads``: refused before any stage
  (:func:`asperity.pipelines.measured.check_curve_loads`);
* a drive that moves backwards within a curve (a friction test drives one way): refused naming
  the line; a drive range above :data:`MAX_DRIVE_RANGE` (mm under an SI header): refused with
  the unit that would fit.

The drive's origin is the file's first row of each curve: :attr:`FrictionCurve.drive_from_start`
is the drive measured from there. Start each curve where the loading system begins to carry the
force (any slack of the wire taken up), so that it compares with the model's drive, which starts
at F_x = 0 (docs/job.md, "Measured friction curves").
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path
from typing import cast

import numpy as np

from asperity.pipelines.config import ShearCurveFile
from asperity.pipelines.measured import (
    LOAD_MATCH,
    MeasuredFileError,
    ShearAreaCurve,
    _same_load,
    check_curve_loads,
    check_friction_magnitude,
    read_columns,
)
from asperity.statmodel.measured_curves import FrictionCurve

#: Largest drive range (m) of one measured curve: friction tests drive millimetres to a few
#: centimetres; 0.1 m and more is what a drive in mm (or um) under an SI header looks like.
MAX_DRIVE_RANGE = 0.1

_COLUMNS = ("drive_displacement", "tangential_force")
_LONG_FILE_HINT = (
    '; or declare the file\'s one load: friction_curves = [{normal_load = N, file = "f.csv"}]'
)


def _declared_loads(path: Path, cols: dict[str, np.ndarray], declared: float) -> np.ndarray:
    """Every row's load (N) of a file declared at ``declared`` N; a ``normal_load`` column
    that contradicts it (beyond :data:`LOAD_MATCH`) is refused, naming both."""
    loads = np.full(cols["tangential_force"].shape, float(declared))
    if "normal_load" not in cols:
        return loads
    wrong = np.flatnonzero(~_same_load(cols["normal_load"], declared))
    if wrong.size:
        i = int(wrong[0])
        raise MeasuredFileError(
            f"{path}: declared at normal_load = {declared:g} N in measured.friction_curves, but "
            f"its 'normal_load' column holds {cols['normal_load'][i]:.6g} N at line "
            f"{cols['_line'][i]} (more than {100 * LOAD_MATCH:g} % from it): correct one of "
            "the two, or give the file without a declaration (a long file)"
        )
    return loads


def check_drive(path: str | Path, drive: np.ndarray, lines: np.ndarray, load: float) -> None:
    """Refuse a drive that moves backwards, or spans more than :data:`MAX_DRIVE_RANGE` (m).

    A friction test drives one way: a decreasing drive is another test appended, a reversed
    unloading, or rows out of order; the message names the file's line. A range of 0.1 m or
    more is what mm or um under an SI header (``drive_displacement`` means m) look like.
    """
    back = np.flatnonzero(np.diff(drive) < 0.0)
    if back.size:
        i = int(back[0]) + 1
        raise MeasuredFileError(
            f"{path}: line {lines[i]}, column 'drive_displacement': the drive moves back from "
            f"{drive[i - 1]:.6g} m to {drive[i]:.6g} m in the curve at normal_load = "
            f"{load:.6g} N; expected a non-decreasing drive (one forward test per load, rows in "
            "acquisition order)"
        )
    span = float(drive[-1] - drive[0])
    if span >= MAX_DRIVE_RANGE:
        hint = next(
            (
                f"; if the column holds {unit}, say so in the header "
                f"('drive_displacement [{unit}]'): the range would be {span * f:.3g} m"
                for f, unit in ((1e-3, "mm"), (1e-6, "um"))
                if span * f < MAX_DRIVE_RANGE
            ),
            "",
        )
        raise MeasuredFileError(
            f"{path}: line {lines[-1]}, column 'drive_displacement': the drive spans "
            f"{span:.6g} m at normal_load = {load:.6g} N, at least {MAX_DRIVE_RANGE:g} m, "
            "beyond a friction test ('drive_displacement' means m)" + hint
        )


def read_friction_curves(path: str | Path, normal_load: float | None = None) -> list[FrictionCurve]:
    """Read measured friction tests F_x(drive) from one CSV file.

    Parameters
    ----------
    path : path
        Columns ``drive_displacement`` (m), ``tangential_force`` (N) and, for a long file,
        ``normal_load`` (N); units in the header allowed (``drive_displacement [mm]``).
    normal_load : float, optional
        The normal load, N, of a one-curve file; a ``normal_load`` column, when present, must
        hold it (within :data:`asperity.pipelines.measured.LOAD_MATCH`).

    Returns
    -------
    list of FrictionCurve
        One per distinct normal load, in file order.

    Raises
    ------
    MeasuredFileError
        A malformed file, a contradicted declared load, an implausible F_x / F_z, a drive
        moving backwards or spanning an implausible range; the message names file and line.
    """
    path = Path(path)
    if normal_load is None:
        cols = read_columns(path, ("normal_load", *_COLUMNS), hint=_LONG_FILE_HINT)
        loads = cols["normal_load"]
    else:
        cols = read_columns(path, _COLUMNS, optional=("normal_load",))
        loads = _declared_loads(path, cols, normal_load)
    curves = []
    for load in np.unique(loads):
        pick = loads == load
        drive, fx, lines = (
            cols["drive_displacement"][pick],
            cols["tangential_force"][pick],
            cols["_line"][pick],
        )
        if drive.size < 2:
            raise MeasuredFileError(
                f"{path}: one row at normal_load = {load:.6g} N (line {lines[0]}); expected a "
                "curve of at least two rows per load"
            )
        check_friction_magnitude(path, float(load), fx, lines)
        check_drive(path, drive, lines, float(load))
        curves.append(FrictionCurve(float(load), drive, fx, str(path)))
    return curves


def read_friction_files(
    files: Sequence[ShearCurveFile], normal_loads: Sequence[float] | None = None
) -> list[FrictionCurve]:
    """Every curve of ``measured.friction_curves`` (files with their declared loads, N).

    ``normal_loads`` (N, ``loading.normal_loads``) refuses a curve at a load matching none of
    them (:func:`asperity.pipelines.measured.check_curve_loads`), before any stage runs.
    """
    curves: list[FrictionCurve] = []
    for item in files:
        curves += read_friction_curves(item.file, item.normal_load)
    if normal_loads is not None:  # check_curve_loads reads a curve's normal_load and source only
        check_curve_loads(cast("list[ShearAreaCurve]", curves), normal_loads)
    return curves


def write_friction_curves(path: str | Path, curves: Sequence[FrictionCurve]) -> None:
    """Write curves as one long CSV (``normal_load,drive_displacement,tangential_force``, SI)."""
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(["normal_load", "drive_displacement", "tangential_force"])
        for curve in curves:
            for drive, fx in zip(curve.drive_displacement, curve.tangential_force, strict=True):
                writer.writerow([repr(curve.normal_load), repr(float(drive)), repr(float(fx))])
