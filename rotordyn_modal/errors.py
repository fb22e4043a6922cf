"""Exception types of the package.

Every error a user can cause by bad input derives from :class:`InputError`; the
command line turns it into one line on stderr and exit code 2.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad input given by the user (model file, option, measured data)."""


class ModelError(InputError):
    """A model description that fails validation.

    The message names the source (file), the table and key, the value found
    and what was expected, e.g.::

        fan.toml: [rotors.fan] mass = -3.0: expected a finite number > 0
    """

    def __init__(self, source: str, where: str, value, expected: str):
        self.source = source
        self.where = where
        self.value = value
        self.expected = expected
        super().__init__(f"{source}: {where} = {_short_repr(value)}: expected {expected}")


def _short_repr(value, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."
