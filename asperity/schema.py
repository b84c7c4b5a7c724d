"""One schema mechanism for every TOML file asperity reads (job and friction parameter files).

A file is a :class:`Schema` of :class:`Section` tables; a section is a list of :class:`Key`
entries, each with a value :class:`Kind` that converts and bounds it, and a ``build`` callable
that makes the library's own dataclass from the converted values (``statmodel.Material``,
``pipelines.config.LoadingConfig``, ...). Every error is one :class:`ConfigError` line::

    job.toml: material.E_star: expected a number in [100, 1e+13] Pa (from the softest gels
    (~1 kPa) to diamond (~1.2e12 Pa)), got -2133000.0

A key may have other accepted spellings (``aliases``: ``e_star`` beside ``E_star``); giving two
spellings of one key is refused. The bounds of physical quantities come from
:mod:`asperity.quantities` (one entry per quantity, shared with the dataclasses and the
command-line options). Bounds carry their reason, so a value that would exhaust
memory or make a solver meaningless is refused before any work. Pure Python: validating a file
loads no numerical library.

Example::

    SECTION = Section("loading", LoadingConfig, (
        Key("nominal_area", Real("m^2", 0, 100, open_low=True, why="...")),
        Key("steps", Integer(3, 100_000, why="..."), default=201),
    ))
    SCHEMA = Schema((SECTION, ...))
    values = SCHEMA.read(tomllib.loads(text), source="job.toml", base_dir=".")
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from asperity.errors import InputError
from asperity.files import MAX_CONFIG_BYTES, describe_kind, read_bytes_bounded

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

#: Marks a key without a default (it must be given).
REQUIRED: Any = object()


class ConfigError(InputError):
    """A configuration value is wrong; the message names the file and the key."""


_UNSET: Any = object()


class Invalid(Exception):
    """Raised by a :class:`Kind`: what was expected; the section adds the key and the value.

    ``key_suffix`` names a part of the value (``"[2].file"``) and ``value`` that part's value
    when the error is about a part.
    """

    def __init__(self, expected: str, key_suffix: str = "", value: Any = _UNSET):
        super().__init__(expected)
        self.expected = expected
        self.key_suffix = key_suffix
        self.value = value


#: Longest piece of user input quoted in an error line, characters.
MAX_QUOTED = 200
#: Deepest nesting of tables and arrays accepted in a TOML file (a job file nests 3 levels).
MAX_TOML_DEPTH = 32


def clip(text: str, limit: int = MAX_QUOTED) -> str:
    """``text`` cut to ``limit`` characters with an ellipsis, for quoting input in an error line.

    A 10 MB unknown key or value must not make a 20 MB line on stderr: every error line
    quotes at most about ``limit`` characters of what it was given (its first and last
    halves) and says how long it was.
    """
    text = str(text)
    if len(text) <= limit:
        return text
    half = max(limit // 2 - 1, 1)
    return f"{text[:half]}...{text[-half:]} ({len(text)} characters)"


def quoted(value: Any) -> str:
    """``repr(value)``, clipped (:func:`clip`); a structure too deep to print is said so."""
    try:
        return clip(repr(value))
    except RecursionError:
        return f"a {type(value).__name__} nested too deeply to print"


def nesting_depth(data: Any) -> int:
    """How deeply tables (mappings) and arrays (lists) nest in ``data`` (a scalar: 0)."""
    deepest, stack = 0, [(data, 0)]
    while stack:
        value, depth = stack.pop()
        if isinstance(value, Mapping):
            stack += [(v, depth + 1) for v in value.values()]
        elif isinstance(value, list):
            stack += [(v, depth + 1) for v in value]
        else:
            deepest = max(deepest, depth)
    return deepest


@dataclass(frozen=True)
class Context:
    """Where values come from: the file name for messages, the directory for relative files."""

    source: str = "<dict>"
    base_dir: Path = Path(".")

    def fail(self, key: str, expected: str, value: Any) -> ConfigError:
        """The one error format: ``source: section.key: expected ..., got ...``."""
        return ConfigError(f"{self.source}: {clip(key)}: expected {expected}, got {quoted(value)}")


class Kind(ABC):
    """How one value is converted and bounded; subclasses implement :meth:`convert`."""

    @abstractmethod
    def convert(self, value: Any, context: Context) -> Any:
        """The checked value; raise :class:`Invalid` with what was expected."""

    def plain(self, value: Any) -> Any:
        """The value as TOML data (None: omitted)."""
        return value

    def document(self, value: Any) -> Any:
        """The value as hashable plain data (files by path and SHA-256)."""
        return self.plain(value)


def _file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(1 << 20):
            digest.update(block)
    return digest.hexdigest()


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def interval_text(low: float, high: float, open_low: bool = False, open_high: bool = False) -> str:
    """``[low, high]`` with parentheses at the open ends (numbers as ``%g``)."""
    return f"{'(' if open_low else '['}{low:g}, {high:g}{')' if open_high else ']'}"


@dataclass(frozen=True)
class Real(Kind):
    """A finite number in [low, high] (ends open when asked), SI ``unit``, ``why`` the bounds."""

    unit: str
    low: float
    high: float
    open_low: bool = False
    open_high: bool = False
    why: str = ""
    tiny: float = 0.0

    def expected(self) -> str:
        """What a valid value is, in words."""
        unit = f" {self.unit}" if self.unit else ""
        why = f" ({self.why})" if self.why else ""
        interval = interval_text(self.low, self.high, self.open_low, self.open_high)
        return f"a number in {interval}{unit}{tiny_text(self.tiny)}{why}"

    def convert(self, value: Any, context: Context) -> float:
        if not _is_number(value) or not math.isfinite(value):
            raise Invalid(self.expected())
        low_ok = value > self.low if self.open_low else value >= self.low
        high_ok = value < self.high if self.open_high else value <= self.high
        if not (low_ok and high_ok) or 0 < abs(value) < self.tiny:
            raise Invalid(self.expected())
        return float(value)


def tiny_text(tiny: float) -> str:
    """``", 0 or of magnitude >= TINY"`` for a bound with a floor on nonzero magnitudes (a
    value that would underflow the computation), else ``""``."""
    return f", 0 or of magnitude >= {tiny:g}" if tiny else ""


@dataclass(frozen=True)
class Integer(Kind):
    """An integer in [low, high]; ``why`` the bounds (e.g. the memory a count implies)."""

    low: int
    high: int
    why: str = ""

    def expected(self) -> str:
        """What a valid value is, in words."""
        why = f" ({self.why})" if self.why else ""
        return f"an integer in [{self.low}, {self.high}]{why}"

    def convert(self, value: Any, context: Context) -> int:
        if (
            isinstance(value, bool)
            or not isinstance(value, int)
            or not (self.low <= value <= self.high)
        ):
            raise Invalid(self.expected())
        return int(value)


@dataclass(frozen=True)
class Flag(Kind):
    """true or false."""

    def convert(self, value: Any, context: Context) -> bool:
        if not isinstance(value, bool):
            raise Invalid("true or false")
        return value


@dataclass(frozen=True)
class Choice(Kind):
    """One of a few strings."""

    options: tuple[str, ...]

    def convert(self, value: Any, context: Context) -> str:
        if value not in self.options:
            raise Invalid("one of " + ", ".join(repr(o) for o in self.options))
        return value


@dataclass(frozen=True)
class Text(Kind):
    """A non-empty string (a channel name)."""

    def convert(self, value: Any, context: Context) -> str:
        if not isinstance(value, str) or not value:
            raise Invalid("a non-empty string")
        return value


@dataclass(frozen=True)
class ExistingFile(Kind):
    """A file name, relative to the configuration's directory, that exists."""

    def convert(self, value: Any, context: Context) -> Path:
        if not isinstance(value, str) or not value:
            raise Invalid("a file name")
        try:
            path = Path(value).expanduser()
        except RuntimeError:  # "~name" of no known user: the name as written, as a shell does
            path = Path(value)
        if not path.is_absolute():
            path = context.base_dir / path
        if (kind := describe_kind(path)) not in (None, "a regular file"):
            raise Invalid(f"a regular file ({path} is {kind})")
        if not path.is_file():
            raise Invalid(f"an existing file (file not found: {path})")
        return path

    def plain(self, value: Any) -> Any:
        return None if value is None else str(value)

    def document(self, value: Any) -> Any:
        return None if value is None else {"path": str(value), "sha256": _file_sha256(value)}


@dataclass(frozen=True)
class OrAuto(Kind):
    """``"auto"`` (read as None) or a value of ``kind``."""

    kind: Kind

    def convert(self, value: Any, context: Context) -> Any:
        if value == "auto":
            return None
        try:
            return self.kind.convert(value, context)
        except Invalid as exc:
            raise Invalid(f'"auto" or {exc.expected}') from None

    def plain(self, value: Any) -> Any:
        return "auto" if value is None else self.kind.plain(value)

    def document(self, value: Any) -> Any:
        return "auto" if value is None else self.kind.document(value)


@dataclass(frozen=True)
class ListOf(Kind):
    """A list of ``min_len``..``max_len`` values of ``kind`` (``why`` the length limit)."""

    kind: Kind
    min_len: int = 1
    max_len: int = 1000
    why: str = ""

    def convert(self, value: Any, context: Context) -> tuple:
        why = f" ({self.why})" if self.why else ""
        if not isinstance(value, list) or not self.min_len <= len(value) <= self.max_len:
            raise Invalid(f"a list of {self.min_len} to {self.max_len} values{why}")
        out = []
        for i, item in enumerate(value):
            try:
                out.append(self.kind.convert(item, context))
            except Invalid as exc:
                got = item if exc.value is _UNSET else exc.value
                raise Invalid(exc.expected, f"[{i}]{exc.key_suffix}", got) from None
        return tuple(out)

    def plain(self, value: Any) -> Any:
        return [self.kind.plain(v) for v in value]

    def document(self, value: Any) -> Any:
        return [self.kind.document(v) for v in value]


@dataclass(frozen=True)
class Key:
    """One key of a section.

    Attributes
    ----------
    name : str
        The documented TOML spelling.
    kind : Kind
        Conversion and bounds.
    default : Any
        Used when the key is absent (:data:`REQUIRED`: it must be given).
    aliases : tuple of str
        Other accepted spellings.
    attr : str or None
        Argument of the section's ``build`` (default: ``name``).
    """

    name: str
    kind: Kind
    default: Any = REQUIRED
    aliases: tuple[str, ...] = ()
    attr: str | None = None

    @property
    def argument(self) -> str:
        """The ``build`` argument this key fills."""
        return self.attr or self.name


@dataclass(frozen=True)
class Section(Kind):
    """A TOML table: its keys, the dataclass they build, and checks across keys.

    Also a :class:`Kind`, for tables inside tables (``[surface.synthetic]``).

    Attributes
    ----------
    name : str
        Table name (dotted for nested tables).
    build : callable
        Makes the value from the keys' converted values (by ``Key.argument``).
    keys : tuple of Key
    required : bool
        The table must be present.
    check : callable or None
        ``check(values) -> None`` on the converted values; raises :class:`Invalid` with the
        key suffix (relative to the section) of the offending key.
    """

    name: str
    build: Callable[..., Any]
    keys: tuple[Key, ...]
    required: bool = False
    check: Callable[[dict[str, Any]], None] | None = None

    def spelling(self, data: Mapping[str, Any], key: Key, context: Context) -> str | None:
        """The spelling of ``key`` used in ``data`` (None when absent; two are refused)."""
        given = [n for n in (key.name, *key.aliases) if n in data]
        if len(given) > 1:
            raise context.fail(
                f"{self.name}.{key.name}", "one spelling of the key", {n: data[n] for n in given}
            )
        return given[0] if given else None

    def values(self, data: Any, context: Context) -> dict[str, Any]:
        """The converted values of the table, by ``build`` argument."""
        if not isinstance(data, Mapping):
            raise context.fail(self.name, "a table", data)
        known = {n for k in self.keys for n in (k.name, *k.aliases)}
        unknown = sorted(set(data) - known)
        if unknown:
            names = ", ".join(k.name for k in self.keys)
            raise context.fail(f"{self.name}.{unknown[0]}", f"one of the keys {names}", unknown[0])
        out = {}
        for key in self.keys:
            spelling = self.spelling(data, key, context)
            where = f"{self.name}.{spelling or key.name}"
            if spelling is None:
                if key.default is REQUIRED:
                    raise context.fail(where, "a value (the key is required)", None)
                out[key.argument] = key.default
                continue
            try:
                out[key.argument] = key.kind.convert(data[spelling], context)
            except Invalid as exc:
                got = data[spelling] if exc.value is _UNSET else exc.value
                raise context.fail(where + exc.key_suffix, exc.expected, got) from None
        if self.check is not None:
            try:
                self.check(out)
            except Invalid as exc:
                got = data.get(exc.key_suffix) if exc.value is _UNSET else exc.value
                raise context.fail(f"{self.name}.{exc.key_suffix}", exc.expected, got) from None
        return out

    def convert(self, value: Any, context: Context) -> Any:
        try:
            return self.build(**self.values(value, context))
        except ConfigError:
            raise
        except ValueError as exc:  # the dataclass's own check, after ours
            raise context.fail(self.name, "values the model accepts", str(exc)) from None

    def plain(self, value: Any) -> dict[str, Any] | None:
        """The built value as TOML data, documented spellings, defaults filled in."""
        if value is None:
            return None
        out = {}
        for key in self.keys:
            item = key.kind.plain(getattr(value, key.argument))
            if item is not None:
                out[key.name] = item
        return out

    def document(self, value: Any) -> dict[str, Any] | None:
        """Like :meth:`plain`, with every key (None included) and files by SHA-256."""
        if value is None:
            return None
        return {k.name: k.kind.document(getattr(value, k.argument)) for k in self.keys}


@dataclass(frozen=True)
class Schema:
    """A whole file: its sections (tables), by name."""

    sections: tuple[Section, ...]

    def read(
        self, data: Any, *, source: str = "<dict>", base_dir: str | Path = "."
    ) -> dict[str, Any]:
        """Validate parsed TOML data; returns each section's built value by section name.

        Raises
        ------
        ConfigError
            ``source: section.key: expected ..., got ...``.
        """
        context = Context(source, Path(base_dir))
        if not isinstance(data, Mapping):
            raise context.fail("the file", "a TOML document with tables", data)
        names = [s.name for s in self.sections]
        unknown = sorted(set(data) - set(names))
        if unknown:
            raise context.fail(unknown[0], "one of the tables " + ", ".join(names), unknown[0])
        out = {}
        for section in self.sections:
            if section.name not in data and section.required:
                raise context.fail(section.name, "a table (it is required)", None)
            out[section.name] = section.convert(data.get(section.name, {}), context)
        return out

    def plain(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Built sections back to TOML data (documented spellings)."""
        return {s.name: s.plain(values[s.name]) for s in self.sections}

    def document(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Built sections as hashable plain data (:meth:`Section.document`)."""
        return {s.name: s.document(values[s.name]) for s in self.sections}


def read_toml(path: str | Path, what: str) -> dict[str, Any]:
    """The parsed TOML document of the file ``path`` (``what`` it is, for the messages).

    Raises
    ------
    ConfigError
        ``path: <what> file not found``, ``path: cannot read the <what>: <reason>`` or
        ``path: not valid TOML: <where and why>``.
    """
    path = Path(path)
    try:
        text = read_bytes_bounded(path, f"{what} file", MAX_CONFIG_BYTES).decode("utf-8")
    except FileNotFoundError:
        raise ConfigError(
            f"{path}: cannot read the {what}: No such file or directory ({what} file not found)"
        ) from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or exc
        raise ConfigError(f"{path}: cannot read the {what}: {reason}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {clip(str(exc))}") from None
    except RecursionError:  # tomllib recurses once per level of nesting
        data = None
    if data is None or nesting_depth(data) > MAX_TOML_DEPTH:
        raise ConfigError(
            f"{path}: not a {what}: tables or arrays nested more than {MAX_TOML_DEPTH} levels deep"
        )
    return data


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):  # a JSON string is a TOML basic string, once DEL is escaped
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        items = (f"{k} = {_toml_value(v)}" for k, v in value.items() if v is not None)
        return "{" + ", ".join(items) + "}"
    raise TypeError(f"cannot write {value!r} as TOML")


def dump_toml(data: Mapping[str, Any], prefix: str = "") -> str:
    """Write nested plain data (tables, lists, str, numbers, bool; None omitted) as TOML."""
    lines: list[str] = []
    tables: list[tuple[str, Mapping[str, Any]]] = []
    for key, value in data.items():
        if value is None:
            continue
        if isinstance(value, Mapping):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {_toml_value(value)}")
    text = "\n".join(lines) + ("\n" if lines else "")
    for key, table in tables:
        name = f"{prefix}{key}"
        text += f"\n[{name}]\n" + dump_toml(table, prefix=name + ".")
    return text
