"""Output files that appear whole or not at all, and never over an input file."""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from pathlib import Path

from ..errors import InputError, OutputError, OutputWriteError

__all__ = ["atomic_write", "check_not_input", "check_writable", "remove_stale_temporaries"]


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


#: errors of the path itself (exit code 2); any other is the machine's (exit code 1)
_PATH_ERRORS = {errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOENT, errno.ENOTDIR, errno.EISDIR,
                errno.ENAMETOOLONG, errno.ELOOP}


def _cannot(path, error: OSError):
    """:class:`OutputError` for a path that cannot be used, :class:`OutputWriteError`
    for a write the machine could not complete (full disk, size limit, I/O error)."""
    reason = error.strerror or str(error) or type(error).__name__
    message = f"cannot write {path}: {reason} (nothing was written)"
    if error.errno in _PATH_ERRORS:
        return OutputError(message)
    return OutputWriteError(message, error.errno)


def _is_special(path: Path) -> bool:
    """True for an existing target that is not a regular file (a device such as
    ``/dev/null`` or ``/dev/full``, a FIFO): written in place, never renamed over."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not stat.S_ISREG(mode) and not stat.S_ISDIR(mode)


def _temporary_prefix(path: Path) -> str:
    """Name of this process's temporary files beside ``path``: ``.NAME.PID.``."""
    return f".{path.name}.{os.getpid()}."


def check_writable(path) -> None:
    """Refuse, before any work, an output whose folder is missing, is not a folder or
    does not accept a new file (read-only, no permission); also a folder as target.

    Parameters
    ----------
    path : path-like

    Raises
    ------
    OutputError
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"cannot write {path}: it is a folder")
    if _is_special(path):
        return
    if not path.parent.exists():
        raise OutputError(f"{path}: the folder {path.parent} does not exist")
    if not path.parent.is_dir():
        raise OutputError(f"cannot write {path}: {path.parent} is not a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=_temporary_prefix(path), suffix=".probe", dir=path.parent)
    except OSError as error:
        raise _cannot(path, error) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)


def remove_stale_temporaries(path) -> list:
    """Delete temporary files that :func:`atomic_write` left beside ``path`` when its
    process was killed (``.NAME.PID.*`` of a process that no longer runs).

    Call it only while no other process of this host may be writing ``path``
    (the study command does, under its lock).

    Returns
    -------
    list of Path
        The files removed.
    """
    path = Path(path)
    removed = []
    for candidate in path.parent.glob(f".{path.name}.*"):
        pid = candidate.name[len(path.name) + 2:].split(".", 1)[0]
        if pid.isdigit() and int(pid) != os.getpid() and not pid_alive(int(pid)):
            with contextlib.suppress(OSError):
                candidate.unlink()
                removed.append(candidate)
    return removed


def pid_alive(pid: int) -> bool:
    """Whether a process with this id runs on this host."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", **kwargs):
    """Open a temporary file beside ``path``; rename it to ``path`` only on success.

    A target that exists and is not a regular file (a device such as ``/dev/null``,
    a FIFO) is written in place, never replaced. Any failure to write (missing or
    read-only folder, full disk, file size limit) removes the temporary file and
    raises :class:`~rotordyn_modal.errors.OutputError` naming the file and the reason.

    Yields
    ------
    file object (``mode`` 'w' or 'wb'); with ``mode=None`` the temporary path itself
    (for writers such as ``savefig`` that take a file name).
    """
    path = Path(path)
    if _is_special(path):
        with _in_place(path, mode, kwargs) as target:
            yield target
        return
    check_writable(path)
    try:
        fd, temporary = tempfile.mkstemp(prefix=_temporary_prefix(path), suffix=path.suffix or ".tmp",
                                         dir=path.parent)
    except OSError as error:
        raise _cannot(path, error) from None
    try:
        if mode is None:
            os.close(fd)
            yield temporary
        else:
            with os.fdopen(fd, mode, **kwargs) as handle:
                yield handle
                handle.flush()
                os.fsync(handle.fileno())  # a full disk may only say so here
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
        os.replace(temporary, path)
    except BaseException as error:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        if isinstance(error, OSError) and not isinstance(error, OutputWriteError):
            raise _cannot(path, error) from None
        raise


@contextlib.contextmanager
def _in_place(path: Path, mode, kwargs):
    try:
        if mode is None:
            yield str(path)
        else:
            with open(path, mode, **kwargs) as handle:
                yield handle
    except OutputWriteError:
        raise
    except OSError as error:
        raise _cannot(path, error) from None
