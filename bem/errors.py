"""The validation error of the bem package."""

from __future__ import annotations

from asperity.errors import InputError

__all__ = ["BemInputError"]


class BemInputError(InputError):
    """A bem argument or option out of its domain (a ValueError through
    :class:`asperity.errors.InputError`): the message names the argument, what was expected
    and what was found."""
