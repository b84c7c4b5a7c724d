"""``undocumented_fields``, the check every result type is held to, can fail both ways: a field
with no text at all, and a field missing from the docstring shown."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from asperity.fields import array, document_fields, scalar, undocumented_fields


@document_fields
@dataclass
class _Described:
    """A result.

    Attributes
    ----------
    depth : float
        Written here, m.
    """

    depth: float = scalar("m", "")
    width: float = scalar("m", "the width, from its declaration")


@document_fields
@dataclass
class _Silent:
    """A result with one field and no text for it anywhere."""

    area: np.ndarray = array("m^2", ("load",), "")


@dataclass
class _NotDecorated:
    """Mentions nothing."""

    force: float = scalar("N", "the force")


def test_a_field_described_in_the_docstring_or_its_declaration_is_documented() -> None:
    assert undocumented_fields(_Described) == []
    assert "the width, from its declaration" in (_Described.__doc__ or "")


def test_a_field_without_any_text_is_undocumented_although_its_name_is_appended() -> None:
    assert "area" in (_Silent.__doc__ or "")  # the decorator appended its entry
    assert undocumented_fields(_Silent) == ["area"]


def test_a_field_missing_from_the_docstring_shown_is_undocumented() -> None:
    assert undocumented_fields(_NotDecorated) == ["force"]
