"""Typed results: the unit, dimensions and description of each field, declared once.

A result type of any asperity package (``topo.HeightMap``, ``topo.ResolutionScan``,
``statmodel.ShearCurve``, the pipeline's stage results) is a dataclass whose fields say their
SI unit, a description and, for arrays, their named dimensions, as dataclass field metadata.
:mod:`asperity.h5` writes and reads every such dataclass with one generic routine (the job's
``results.h5``, :mod:`asperity.pipelines.engine.store`), :func:`checksum` fingerprints it and
:func:`document_fields` completes its docstring from the same declarations, so a field's
description is written once. Three declarations cover every field:

* :func:`array` (``metadata={"units": "m^2", "dims": ("normal_load",)}``): an HDF5 dataset with
  a ``units`` attribute over named dimensions. A field whose only dimension is its own name is
  a coordinate (a dimension scale); a dimension without a coordinate field gets an index
  coordinate 0..n-1.
* :func:`scalar` (``metadata={"units": "N"}``): a number or boolean, an attribute of the group.
* :func:`text`: a string (stored as is) or a list/dict of plain values (stored as JSON text).

The Python type of a field (its annotation) decides how a stored value is read back: ``float``,
``int``, ``bool``, ``str``, ``numpy.ndarray``, ``X | None`` (optional: ``None`` is not
stored), anything else through JSON. Example::

    @dataclass
    class Scan:
        stride: np.ndarray = array("1", ("stride",), "decimation stride")
        summit_radius: np.ndarray = array("m", ("stride",), "mean summit radius R")
        radius_slope: float = scalar("m/m", "slope of the linear fit of R")
        fit_note: str = text("what the fits are")
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import re
import types
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

#: Group attributes the store writes itself; no result field may use these names.
RESERVED_ATTRIBUTES: frozenset[str] = frozenset(
    {
        "stage_key",
        "key_inputs",
        "checksum",
        "seconds",
        "finished",
        "attribute_units",
        "asperity_version",
    }
)


def array(
    units: str,
    dims: tuple[str, ...],
    long_name: str = "",
    *,
    optional: bool = False,
    init: bool = True,
) -> Any:
    """A stored array field: SI ``units`` ("1" if dimensionless) over named ``dims``.

    ``optional=True`` makes the field default to None (not stored when None); ``init=False``
    marks an array the dataclass derives in ``__post_init__`` (see :func:`scalar`).
    """
    metadata = {"units": units, "dims": tuple(dims), "long_name": long_name}
    if optional:
        return dataclasses.field(default=None, metadata=metadata, init=init)
    return dataclasses.field(metadata=metadata, init=init)


def scalar(
    units: str,
    long_name: str = "",
    *,
    optional: bool = False,
    init: bool = True,
    default: Any = dataclasses.MISSING,
) -> Any:
    """A stored number or boolean (a group attribute) in SI ``units``.

    ``init=False`` marks a value the dataclass derives itself in ``__post_init__`` (stored for
    readers of the file, not passed back to the constructor); ``default`` is its value when not
    given.
    """
    metadata = {"units": units, "long_name": long_name}
    if optional:
        return dataclasses.field(default=None, metadata=metadata, init=init)
    return dataclasses.field(default=default, metadata=metadata, init=init)


def text(
    long_name: str = "",
    *,
    optional: bool = False,
    default_factory: Callable[[], Any] | None = None,
    compare: bool = True,
) -> Any:
    """A stored string, or a list / dict of plain values (kept as JSON text).

    ``optional=True`` makes the field default to None (not stored when None); ``compare=False``
    leaves it out of ``==`` (a provenance record).
    """
    metadata = {"long_name": long_name}
    if optional:
        return dataclasses.field(default=None, metadata=metadata, compare=compare)
    if default_factory is not None:
        return dataclasses.field(
            default_factory=default_factory, metadata=metadata, compare=compare
        )
    return dataclasses.field(metadata=metadata, compare=compare)


@dataclass(frozen=True)
class FieldSpec:
    """How one result field is stored (read from its metadata and annotation).

    Attributes
    ----------
    name : str
        Field, dataset and attribute name.
    kind : str
        "array" (a dataset), "number" (float/int/bool attribute), "string" (str attribute)
        or "json" (JSON text attribute).
    python_type : type
        The annotation without ``| None`` (``float``, ``numpy.ndarray``, ``list``, ...).
    units : str
        SI unit; "" for text.
    dims : tuple of str
        Dimension names of an array.
    long_name : str
        What the value is.
    optional : bool
        None is allowed (and then not stored).
    init : bool
        Passed to the constructor when the result is read back.
    """

    name: str
    kind: str
    python_type: Any
    units: str
    dims: tuple[str, ...]
    long_name: str
    optional: bool
    init: bool

    @property
    def is_coordinate(self) -> bool:
        """An array whose only dimension is its own name (an HDF5 dimension scale)."""
        return self.kind == "array" and self.dims == (self.name,)


def _strip_optional(annotation: Any) -> tuple[Any, bool]:
    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        optional = len(args) < len(typing.get_args(annotation))
        return (args[0] if len(args) == 1 else annotation), optional
    return annotation, False


def _kind(name: str, python_type: Any, metadata: Any) -> str:
    if "dims" in metadata:
        if python_type is not np.ndarray:
            raise TypeError(f"field {name!r}: dims given but the type is {python_type!r}")
        return "array"
    if python_type in (float, int, bool):
        if "units" not in metadata:
            raise TypeError(f"field {name!r}: a number needs its units (asperity.fields.scalar)")
        return "number"
    if python_type is np.ndarray:
        raise TypeError(f"field {name!r}: an array needs units and dims (asperity.fields.array)")
    return "string" if python_type is str else "json"


def field_specs(cls: type) -> tuple[FieldSpec, ...]:
    """The storage description of every field of a result dataclass, in declaration order.

    Computed once per class (cached).

    Raises
    ------
    TypeError
        A field without a storage declaration, a reserved name, or an array of another type
        (a programming error in a result declaration, found at import of the stage).
    """
    return _cached_field_specs(cls)


@functools.cache
def _cached_field_specs(cls: type) -> tuple[FieldSpec, ...]:
    """:func:`field_specs`, cached per class (a plain ``type`` argument, hashable)."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    hints = typing.get_type_hints(cls)
    specs = []
    for f in dataclasses.fields(cls):
        if f.name in RESERVED_ATTRIBUTES:
            raise TypeError(f"{cls.__name__}.{f.name}: the name is reserved by the store")
        python_type, optional = _strip_optional(hints[f.name])
        kind = _kind(f"{cls.__name__}.{f.name}", python_type, f.metadata)
        specs.append(
            FieldSpec(
                name=f.name,
                kind=kind,
                python_type=python_type,
                units=f.metadata.get("units", ""),
                dims=tuple(f.metadata.get("dims", ())),
                long_name=f.metadata.get("long_name", ""),
                optional=optional,
                init=f.init,
            )
        )
    return tuple(specs)


def canonical(spec: FieldSpec, value: Any) -> Any:
    """A field value in the form it is stored and read back (arrays as ndarrays, numbers cast)."""
    if value is None:
        return None
    if spec.kind == "array":
        return np.asarray(value)
    if spec.kind == "number":
        base = typing.get_origin(spec.python_type) or spec.python_type
        return base(value)
    if spec.kind == "string":
        return value.decode() if isinstance(value, bytes) else str(value)
    return json.loads(json.dumps(value))


def checksum(result: Any) -> str:
    """SHA-256 of every stored field of a result (names, dtypes, shapes, bytes, values).

    The same for a result and for what the store reads back of it: the integrity check of a
    stored stage before it is reused.
    """
    digest = hashlib.sha256()
    kind: type = type(result)
    for spec in field_specs(kind):
        value = canonical(spec, getattr(result, spec.name))
        digest.update(spec.name.encode() + b"\0")
        if value is None:
            digest.update(b"none\0")
        elif spec.kind == "array":
            data = np.ascontiguousarray(value)
            digest.update(f"{data.dtype.str}{data.shape}".encode())
            digest.update(data.tobytes())
        else:
            digest.update(json.dumps(value, sort_keys=True).encode())
        digest.update(b"\0")
    return digest.hexdigest()


def _mentioned(name: str, doc: str) -> bool:
    return re.search(rf"(?<![\w.]){re.escape(name)}(?!\w)", doc) is not None


def field_entry(spec: FieldSpec) -> str:
    """One numpy-style attribute entry from a field's declaration (name, unit, dims, text)."""
    if spec.kind == "array":
        kind = f"ndarray over ({', '.join(spec.dims)}), {spec.units}"
    elif spec.kind == "number":
        kind = f"{getattr(spec.python_type, '__name__', spec.python_type)}, {spec.units}"
    else:
        kind = "str" if spec.kind == "string" else "JSON-ready value"
    optional = " or None" if spec.optional else ""
    return f"    {spec.name} : {kind}{optional}\n        {spec.long_name or 'no description'}."


def document_fields(cls: type) -> type:
    """Class decorator: append to the docstring every stored field it does not describe.

    The entries are made from the field declarations (:func:`field_entry`), so a field is
    described once, in its ``long_name``, and still appears in ``help(cls)``. Apply it after
    ``@dataclass``.
    """
    doc = cls.__doc__ or ""
    cls.__written_doc__ = doc  # type: ignore[attr-defined]
    missing = [spec for spec in field_specs(cls) if not _mentioned(spec.name, doc)]
    if missing:
        entries = "\n".join(field_entry(spec) for spec in missing)
        cls.__doc__ = (
            doc.rstrip() + "\n\n    Stored fields (from their declarations)\n"
            "    ---------------------------------------\n" + entries + "\n"
        )
    return cls


def undocumented_fields(cls: type) -> list[str]:
    """Fields of a result dataclass that ``help(cls)`` cannot describe: what a test requires
    to be empty.

    A field is undocumented when its name is missing from the docstring shown, or when it has
    no text anywhere: neither its declaration's ``long_name`` nor an entry in the docstring as
    written (before :func:`document_fields` appended the declarations, which would otherwise
    make every field look described).
    """
    shown = cls.__doc__ or ""
    written = cls.__dict__.get("__written_doc__", shown)
    return [
        spec.name
        for spec in field_specs(cls)
        if not _mentioned(spec.name, shown)
        or not (spec.long_name.strip() or _mentioned(spec.name, written))
    ]


def _copy_declaration(spec: FieldSpec, dim: str | None) -> Any:
    if dim is None and spec.kind == "number":
        return scalar(spec.units, spec.long_name, optional=spec.optional)
    if dim is None:
        return array(spec.units, spec.dims, spec.long_name, optional=spec.optional)
    dims = (dim, *spec.dims) if spec.kind == "array" else (dim,)
    return array(spec.units, dims, spec.long_name)


def _insert_fields(cls: type, added: dict[str, Any], after: str | None) -> type:
    own = dict(cls.__dict__.get("__annotations__", {}))
    items = list(own.items())
    position = 0 if after is None else list(own).index(after) + 1
    annotations = {n: ("float" if _is_scalar(d) else "np.ndarray") for n, d in added.items()}
    cls.__annotations__ = dict(items[:position] + list(annotations.items()) + items[position:])
    for name, declaration in added.items():
        setattr(cls, name, declaration)
    return cls


def _is_scalar(declaration: Any) -> bool:
    return "dims" not in declaration.metadata


def stacked(
    source: type, names: Sequence[str], dim: str | None, *, after: str | None = None
) -> Callable[[type], type]:
    """Class decorator (under ``@dataclass``): the fields ``names`` of ``source``, taken over.

    With ``dim`` None each field is declared as in ``source`` (unit, dims, description); with
    a dimension name each becomes an array field with that leading dimension: an array over
    ``(dim, *its dims)``, a number an array over ``(dim,)``. They are inserted after the field
    ``after`` (first when None), in the order of ``names``. A result that keeps fields of a
    package's result type (the stored resolution scan), or one per ``dim`` entry (the shear
    curve at every normal load), so repeats no unit or description. Numbers are read back as
    float: declare an ``int`` field in the class itself.
    """
    specs = {spec.name: spec for spec in field_specs(source)}

    def decorate(cls: type) -> type:
        added = {name: _copy_declaration(specs[name], dim) for name in names}
        return _insert_fields(cls, added, after)

    return decorate
