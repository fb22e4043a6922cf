"""Output files that appear whole or not at all, and never over an input file."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from ..errors import InputError

__all__ = ["atomic_write", "check_not_input"]


def check_not_input(output, inputs) -> None:
    """Refuse an output path that is one of the input files.

    Parameters
    ----------
    output : path-like
    inputs : iterable of path-like
    """
    out = Path(output)
    for source in inputs:
        if source is None:
            continue
        src = Path(source)
        if out.exists() and src.exists() and os.path.samefile(out, src) or out.resolve() == src.resolve():
            raise InputError(f"{output}: refusing to write over the input file {source}")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", **kwargs):
    """Open a temporary file beside ``path``; rename it to ``path`` only on success.

    Yields
    ------
    file object (``mode`` 'w' or 'wb'); with ``mode=None`` the temporary path itself
    (for writers such as ``savefig`` that take a file name).
    """
    path = Path(path)
    if not path.parent.exists():
        raise InputError(f"{path}: the folder {path.parent} does not exist")
    fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix or ".tmp", dir=path.parent)
    try:
        if mode is None:
            os.close(fd)
            yield temporary
        else:
            with os.fdopen(fd, mode, **kwargs) as handle:
                yield handle
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
