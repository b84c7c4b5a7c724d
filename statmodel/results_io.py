"""Writing friction results: the JSON object of ``asperity friction --json`` and HDF5 files.

Every HDF5 dataset carries a ``units`` attribute (SI, or ``1`` for dimensionless counts).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import h5py

from asperity import h5
from asperity.fields import field_specs
from asperity.statmodel.shear import ShearCurve

#: ShearCurve fields the ``asperity friction`` outputs leave out: the solver's evaluation
#: counts, the displacement at the static peak and the status code (``converged`` and
#: ``message`` are written instead).
NOT_WRITTEN = frozenset({"nit", "static_displacement", "success", "status", "message"})
#: ShearCurve array fields written, and their units (from the ShearCurve declaration).
ARRAY_UNITS: dict[str, str] = {
    s.name: s.units
    for s in field_specs(ShearCurve)
    if s.kind == "array" and s.name not in NOT_WRITTEN
}
#: ShearCurve scalar fields written, and their units (from the ShearCurve declaration).
SCALAR_UNITS: dict[str, str] = {
    s.name: s.units
    for s in field_specs(ShearCurve)
    if s.kind == "number" and s.name not in NOT_WRITTEN
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
    """Create dataset ``name`` in ``group`` with its ``units`` attribute (uncompressed)."""
    h5.write_dataset(group, name, data, units, compression=None)


def write_curve_hdf5(curve: ShearCurve, path: str | Path, attrs: dict | None = None) -> None:
    """Write a ShearCurve to HDF5: one dataset per field, each with a ``units`` attribute."""
    with h5.new_file(path) as fh:  # atomic: a full disk leaves nothing partial
        for name, unit in ARRAY_UNITS.items():
            write_dataset(fh, name, getattr(curve, name), unit)
        for name, unit in SCALAR_UNITS.items():
            write_dataset(fh, name, float(getattr(curve, name)), unit)
        h5.write_attributes(fh, {"converged": bool(curve.converged), "message": curve.message})
        h5.write_attributes(fh, attrs or {})
