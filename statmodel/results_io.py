"""Writing friction results: the JSON object of ``asperity friction --json`` and HDF5 files.

Every HDF5 dataset carries a ``units`` attribute (SI, or ``1`` for dimensionless counts).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import h5py
import numpy as np

from asperity.statmodel.shear import ShearCurve

#: ShearCurve array fields and their units.
ARRAY_UNITS = {
    "tangential_displacement": "m",
    "tangential_force": "N",
    "normal_force": "N",
    "real_area": "m^2",
    "n_contact": "1",
    "n_stick": "1",
    "n_slip": "1",
    "separation": "m",
    "tangential_force_stick": "N",
    "tangential_force_slip": "N",
    "normal_force_stick": "N",
    "normal_force_slip": "N",
    "real_area_stick": "m^2",
    "real_area_slip": "m^2",
    "delta_1": "m",
    "delta_2": "m",
}
#: ShearCurve scalar fields and their units.
SCALAR_UNITS = {
    "tabor_parameter": "1",
    "separation_preload": "m",
    "static_friction": "N",
    "sliding_friction": "N",
    "sliding_separation": "m",
    "sliding_displacement": "m",
    "normal_load": "N",
    "pull_off_force": "N",
}


def _json_number(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def curve_to_dict(curve: ShearCurve) -> dict:
    """JSON-ready dict: arrays as lists, non-finite numbers as None (null), plus ``units``."""
    out: dict = {}
    for name in ARRAY_UNITS:
        out[name] = [_json_number(v) for v in getattr(curve, name)]
    for name in SCALAR_UNITS:
        out[name] = _json_number(getattr(curve, name))
    out["converged"] = bool(curve.converged)
    out["message"] = curve.message
    out["units"] = {**ARRAY_UNITS, **SCALAR_UNITS}
    return out


def curve_to_json(curve: ShearCurve) -> str:
    """One JSON object (see :func:`curve_to_dict`)."""
    return json.dumps(curve_to_dict(curve), allow_nan=False)


def write_dataset(group: h5py.Group, name: str, data, units: str) -> None:
    """Create dataset ``name`` in ``group`` with its ``units`` attribute."""
    ds = group.create_dataset(name, data=np.asarray(data))
    ds.attrs["units"] = units


def write_curve_hdf5(curve: ShearCurve, path: str | Path, attrs: dict | None = None) -> None:
    """Write a ShearCurve to HDF5: one dataset per field, each with a ``units`` attribute."""
    with h5py.File(path, "w") as fh:
        for name, unit in ARRAY_UNITS.items():
            write_dataset(fh, name, getattr(curve, name), unit)
        for name, unit in SCALAR_UNITS.items():
            write_dataset(fh, name, float(getattr(curve, name)), unit)
        fh.attrs["converged"] = bool(curve.converged)
        fh.attrs["message"] = curve.message
        for key, value in (attrs or {}).items():
            fh.attrs[key] = value
