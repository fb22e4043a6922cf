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


class ModelWarning(UserWarning):
    """A model that is legal but probably not what was meant (a mount stiffness that would let
    the machine sag metres under its weight, a journal bearing longer than short-bearing theory
    is made for). The command line prints it as one line on stderr and goes on."""


class OutputError(InputError):
    """An output path that cannot be used: its folder is missing or read-only, a folder
    is in the way, another study is writing it. Like bad input (the remedy is another
    path), the command line reports it on one line with exit code 2."""


class OutputWriteError(OSError):
    """Writing an output failed for a reason of the machine, not of the path: the disk
    is full, a quota or file-size limit is reached, an I/O error. Nothing is left behind
    (no partial or temporary file); the command line reports it on one line with exit
    code 1.

    Parameters
    ----------
    message : str
        Names the file and the reason.
    code : int, optional
        The ``errno`` of the failure.
    """

    def __init__(self, message: str, code: int | None = None):
        super().__init__(code, message)

    def __str__(self) -> str:
        return str(self.strerror)


def _short_repr(value, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."
