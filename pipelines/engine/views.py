"""What a stage may read: its declared configuration keys, input stages and measurements.

A stage's ``compute`` gets a :class:`~asperity.pipelines.engine.stage.StageContext` whose
``config`` is a :class:`ConfigView`: the job configuration reduced to the keys the stage
declares (a whole section, ``"bem"``, or single keys, ``"material.E_star"``). Reading any other
key raises :class:`UndeclaredReadError`, so a key read but not declared, which would let a
stored result computed with another value be reused, fails at once in every test and run
instead. Declared keys are the documented TOML spellings (``material.E_star``); the view
answers the Python attribute they fill (``config.material.e_star``), as the schema maps them.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from asperity.schema import Section


class UndeclaredReadError(LookupError):
    """A stage read a configuration key, input stage or measurement it does not declare
    (a defect in the stage's declaration, not in the user's input)."""


class DeclaredView:
    """Attribute access to ``value`` limited to ``allowed`` attribute names.

    Parameters
    ----------
    value : object
        The section (a dataclass such as ``BemConfig`` or ``statmodel.Material``).
    allowed : dict
        Attribute name -> the declared key it answers ("material.E_star").
    where : str
        What is read, for the error ("stage 'psd', configuration section 'material'").
    """

    __slots__ = ("_allowed", "_value", "_where")

    def __init__(self, value: Any, allowed: dict[str, str], where: str) -> None:
        object.__setattr__(self, "_value", value)
        object.__setattr__(self, "_allowed", allowed)
        object.__setattr__(self, "_where", where)

    def __getattr__(self, name: str) -> Any:
        if name in self._allowed:
            return getattr(self._value, name)
        raise UndeclaredReadError(
            f"{self._where}: {name!r} is not declared (declared: "
            f"{', '.join(sorted(set(self._allowed.values()))) or 'none'}); add its key to "
            "the stage's config so that a change of it recomputes the stage"
        )

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"{self._where} is read-only")

    def __repr__(self) -> str:
        return f"DeclaredView({self._where}: {sorted(self._allowed)})"


def _section_attributes(section: Section, keys: Iterable[str]) -> dict[str, str]:
    """Attribute name -> declared key, for the declared keys of one section."""
    by_name = {key.name: key.argument for key in section.keys}
    out = {}
    for key in keys:
        name = key.split(".", 1)[1]
        if name not in by_name:
            raise UndeclaredReadError(f"declared key {key!r}: [{section.name}] has no key {name!r}")
        out[by_name[name]] = key
    return out


class ConfigView:
    """The job configuration as one stage sees it: only its declared keys.

    Parameters
    ----------
    config : JobConfig
        The whole validated configuration.
    declared : sequence of str
        Sections ("bem") and keys ("material.E_star") the stage declares.
    stage : str
        The stage's name (for errors).
    sections : sequence of Section
        The job schema's sections (their keys map TOML spellings to attributes).
    """

    def __init__(self, config: Any, declared: Iterable[str], stage: str, sections: Any) -> None:
        self._config = config
        self._stage = stage
        self._declared = tuple(declared)
        self._sections = {s.name: s for s in sections}
        for key in self._declared:
            if key.split(".", 1)[0] not in self._sections:
                raise UndeclaredReadError(f"stage {stage!r} declares {key!r}: no such section")

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        value = getattr(self._config, name)
        if name in self._declared:
            return value  # the whole section is declared
        keys = [k for k in self._declared if k.startswith(name + ".")]
        where = f"stage {self._stage!r}, configuration section [{name}]"
        if not keys:
            raise UndeclaredReadError(
                f"{where}: the stage declares no key of this section (declared: "
                f"{', '.join(self._declared) or 'none'})"
            )
        return DeclaredView(value, _section_attributes(self._sections[name], keys), where)

    @property
    def declared(self) -> tuple[str, ...]:
        """The declared sections and keys."""
        return self._declared
