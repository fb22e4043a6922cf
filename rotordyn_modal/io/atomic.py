"""Output files that appear whole or not at all, and never over an input file.

Temporary files are named ``.NAME.rdm-tmp.PID-HOST.XXXXXXXX.SUFFIX`` beside the target
``NAME``: a write that its process cannot finish (``kill -9``, power loss) leaves one
behind, and the next write of ``NAME`` on the same host deletes those of processes that no
longer run (:func:`remove_stale_temporaries`). Outputs written inside
:func:`outputs_together` appear together when it ends, or none of them.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import socket
import stat
import tempfile
import time
from pathlib import Path

from ..errors import InputError, OutputError, OutputWriteError
from .limits import shown_name, unreachable_name

__all__ = ["atomic_write", "check_not_input", "check_writable", "remove_stale_temporaries",
           "outputs_together", "after_commit", "same_file", "real_target"]

#: the part of a temporary file's name that marks it as this package's
_MARK = "rdm-tmp"


def real_target(path) -> Path:
    """The file a write of ``path`` replaces: a symbolic link's target (followed to the end),
    else ``path`` itself. Writing through a link keeps the link, as ``cp`` or an editor does.
    A link to a pipe or a device is ``path`` itself: such a target (``pipe:[...]``) has no name
    to follow, and is written in place through the link."""
    path = Path(path)
    if path.is_symlink() and _is_special(path):
        return path   # a pipe or device behind a link (a shell's >(...) as /dev/fd/63, /dev/stdout): written through it
    return Path(os.path.realpath(path)) if path.is_symlink() else path


def same_file(a, b) -> bool:
    """Whether two paths name one file: the same inode (hard links, symbolic links, other
    spellings), or, when either does not exist yet, the same resolved path."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        pass
    except ValueError:  # a name no file can have (a NUL character): the callers refuse it
        return False
    try:
        return os.path.realpath(a) == os.path.realpath(b)
    except (OSError, ValueError):
        return False


def check_not_input(output, inputs) -> None:
    """Refuse an output path that is one of the input files.

    Parameters
    ----------
    output : path-like
    inputs : iterable of path-like
        None entries are skipped.

    Raises
    ------
    InputError
        ``output`` names an input (through a link, a hard link or another spelling).
    """
    if _is_special(Path(output)):
        return  # a device or FIFO is written in place, never replaced
    for source in inputs:
        if source is not None and same_file(output, source):
            raise InputError(f"{output}: refusing to write over the input file {source}")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: errors of the path itself (exit code 2); any other is the machine's (exit code 1)
_PATH_ERRORS = {errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOENT, errno.ENOTDIR, errno.EISDIR,
                errno.ENAMETOOLONG, errno.ELOOP}


def _cannot(path, error: OSError, batch=None):
    """:class:`OutputError` for a path that cannot be used, :class:`OutputWriteError`
    for a write the machine could not complete (full disk, size limit, I/O error);
    the message ends with what of the outputs of ``batch`` (default: the open one) is in place."""
    reason = error.strerror or str(error) or type(error).__name__
    message = f"cannot write {path}: {reason} ({_what_was_written(batch or _BATCH[0])})"
    if error.errno in _PATH_ERRORS:
        return OutputError(message)
    return OutputWriteError(message, error.errno)


def _open_in_place(path: Path, mode: str, kwargs: dict, shown):
    """``open(path, mode)`` of a device or pipe; a named pipe (FIFO) is opened without waiting
    for a reader, retried for :data:`~rotordyn_modal.io.limits.PIPE_WAIT_S` until a program
    reads it (``>(gzip > c.gz)`` and a reader started before or just after are written; a FIFO
    nothing reads was waited for forever, as ``open`` does)."""
    from .limits import PIPE_WAIT_S

    if not stat.S_ISFIFO(os.stat(path).st_mode):
        return open(path, mode, **kwargs)
    deadline = time.monotonic() + PIPE_WAIT_S
    while True:
        try:
            fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
            break
        except OSError as error:
            if error.errno != errno.ENXIO:
                raise
            if time.monotonic() > deadline:
                raise OutputError(f"cannot write {shown}: a pipe nothing reads from within {PIPE_WAIT_S:g} s "
                                  f"(start the program that reads it first, or give a file; "
                                  f"{_what_was_written(_BATCH[0])})") from None
            time.sleep(0.02)
    os.set_blocking(fd, True)
    return os.fdopen(fd, mode, **kwargs)


def _is_special(path: Path) -> bool:
    """True for an existing target that is not a regular file (a device such as
    ``/dev/null`` or ``/dev/full``, a FIFO): written in place, never renamed over."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return False
    return not stat.S_ISREG(mode) and not stat.S_ISDIR(mode)


def _host() -> str:
    """8 hex digits naming this host (a process id means something on its own host only)."""
    return hashlib.sha1(socket.gethostname().encode(errors="replace")).hexdigest()[:8]


def _temporary_prefix(path: Path) -> str:
    """Name of this process's temporary files beside ``path``: ``.NAME.rdm-tmp.PID-HOST.``
    (NAME shortened by :func:`_temporary_stem` where the whole would be too long a file name)."""
    return f".{_temporary_stem(path)}.{_MARK}.{os.getpid()}-{_host()}."


#: the longest file name (bytes) of the file systems written to (ext4, XFS, btrfs, tmpfs, NTFS)
_NAME_MAX = 255
#: bytes of a temporary's name beside its NAME: dots, the mark, a process id of up to 10 digits,
#: the host's 8 digits, ``mkstemp``'s 8 random letters
_TEMPORARY_EXTRA = len(f"..{_MARK}.-.") + 10 + 8 + 8


def _temporary_stem(path: Path) -> str:
    """The NAME of ``path``'s temporary files: its own name, or where that would make a temporary's
    name longer than a file name may be (an output named with 220 of the 255 bytes allowed was
    refused as "File name too long" although it is a valid name), the name's start and 16 hex
    digits of its hash (``NAME~0123456789abcdef``). The same for every process (its budget takes a
    process id of 10 digits), so that :func:`remove_stale_temporaries` finds another's files."""
    name = path.name
    suffix = max(len(os.fsencode(path.suffix or ".tmp")), len(".probe"))
    budget = _NAME_MAX - _TEMPORARY_EXTRA - suffix
    encoded = os.fsencode(name)
    if len(encoded) <= budget:
        return name
    digest = hashlib.sha1(encoded).hexdigest()[:16]
    return f"{encoded[:max(budget - 17, 0)].decode('utf-8', errors='ignore')}~{digest}"


def check_writable(path) -> None:
    """Refuse, before any work, an output whose folder is missing, is not a folder or
    does not accept a new file (read-only, no permission); also a folder as target.
    A symbolic link is checked at its target (the file a write replaces).

    Parameters
    ----------
    path : path-like

    Raises
    ------
    OutputError
    """
    if not os.fspath(path):     # Path('') is '.': "cannot write : it is a folder"
        raise OutputError("'' (an empty file name): expected the name of the file to write")
    problem = unreachable_name(path)
    if problem and not str(path).endswith((os.sep, "/", "/.")):   # those: "a name ending in '/'" below
        raise OutputError(f"cannot write {shown_name(path)}: its name {problem}")
    shown, path = path, real_target(path)
    if Path(shown).is_symlink():
        try:
            os.path.realpath(shown, strict=True)
        except FileNotFoundError:
            pass                       # a link to a file not there yet: the write creates it
        except OSError as error:       # a loop of links: no target to write (it replaced the link)
            raise _cannot(shown, error) from None
    if path.is_dir():
        raise OutputError(f"cannot write {shown}: it is a folder")
    if str(shown).endswith((os.sep, "/")):   # 'out.csv/' names a folder: Path drops the '/' and wrote a file
        raise OutputError(f"cannot write {shown}: a name ending in '/' is a folder, not a file (give the file's "
                          "name, without the '/')")
    if _is_special(path):
        return
    if not path.parent.exists():
        raise OutputError(f"{shown}: the folder {path.parent} does not exist")
    if not path.parent.is_dir():
        raise OutputError(f"cannot write {shown}: {path.parent} is not a folder")
    _check_not_read_only(shown, path)
    try:
        fd, probe = tempfile.mkstemp(prefix=_temporary_prefix(path), suffix=".probe", dir=path.parent)
    except OSError as error:
        raise _cannot(shown, error) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)


def _check_not_read_only(shown, path: Path) -> None:
    """Refuse an existing file without write permission: the rename of a finished write would
    replace it (a folder that takes new files lets it), where ``>`` or ``cp`` say "Permission
    denied". Read-only is its mode without any write bit (as root, who may write anything, sees
    it too) or one the user may not write (``os.access``)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return                                  # not there yet: the write creates it
    if stat.S_ISREG(mode) and (not mode & 0o222 or not os.access(path, os.W_OK)):
        raise OutputError(f"cannot write {shown}: the file is read-only (no write permission; make it writable "
                          "or remove it to replace it, or give another name)")


def _existing_mode(path: Path, default: int) -> int:
    """The permission bits of the file a write replaces (a private 0600 file stays private), else
    ``default``."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        return default


def remove_stale_temporaries(path) -> list:
    """Delete temporary files that :func:`atomic_write` left beside ``path`` when its
    process was killed (``.NAME.rdm-tmp.PID-HOST.*`` of this host whose process no longer
    runs). Every :func:`atomic_write` calls it for its target.

    Returns
    -------
    list of Path
        The files removed.
    """
    path = real_target(path)
    removed = []
    host = _host()
    try:
        stem = _temporary_stem(path)
        candidates = list(path.parent.glob(f".{_glob_escape(stem)}.{_MARK}.*"))
    except OSError:
        return removed
    for candidate in candidates:
        owner = candidate.name[len(stem) + len(_MARK) + 3:].split(".", 1)[0]
        pid, _, where = owner.partition("-")
        if where == host and pid.isdigit() and int(pid) != os.getpid() and not pid_alive(int(pid)):
            with contextlib.suppress(OSError):
                candidate.unlink()
                removed.append(candidate)
    return removed


def _glob_escape(name: str) -> str:
    import glob

    return glob.escape(name)


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


# ------------------------------------------------------------------ outputs written together
class _Batch:
    """Outputs of one :func:`outputs_together`: temporaries waiting for their rename."""

    def __init__(self, outer):
        self.outer = outer
        self.pending = []      # (temporary, target, name as given)
        self.written = []      # names of outputs already in place (in-place writes, inner batches)
        self.callbacks = []

    def commit(self):
        for i, (temporary, target, shown) in enumerate(self.pending):
            try:
                os.replace(temporary, target)
            except OSError as error:
                self.pending = self.pending[i:]
                self.discard()
                raise _cannot(shown, error, self) from None
            self.written.append(str(shown))
        self.pending = []
        if self.outer is not None:
            self.outer.written.extend(self.written)
        for callback in self.callbacks:
            callback()

    def discard(self):
        for temporary, _, _ in self.pending:
            with contextlib.suppress(OSError):
                os.unlink(temporary)
        self.pending = []


_BATCH: list = [None]


@contextlib.contextmanager
def outputs_together():
    """Every :func:`atomic_write` inside is renamed into place when the block ends, all of
    them, or none when the block raises (a later output that cannot be written, Ctrl-C, a
    signal): a message can then say truthfully that nothing was written. Only a rename
    failing at the end (the folder's permissions changed meanwhile) can leave some
    written, and its message names them. A block inside another commits its own outputs
    when it ends."""
    batch = _Batch(_BATCH[0])
    _BATCH[0] = batch
    try:
        yield batch
    except BaseException:
        batch.discard()
        raise
    finally:
        _BATCH[0] = batch.outer
    batch.commit()


def after_commit(callback) -> None:
    """Call ``callback()`` once the outputs written so far are in place: at the end of the
    open :func:`outputs_together` block (not at all if it fails), or now when none is open."""
    if _BATCH[0] is None:
        callback()
    else:
        _BATCH[0].callbacks.append(callback)


def _what_was_written(batch) -> str:
    """The end of a failed write's message: what of the command's outputs is in place."""
    written = []
    while batch is not None:
        written = batch.written + written
        batch = batch.outer
    if not written:
        return "nothing was written"
    return f"only {', '.join(written)} {'was' if len(written) == 1 else 'were'} written"


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", together: bool = True, tidy: bool = True, **kwargs):
    """Open a temporary file beside ``path``; rename it to ``path`` only on success.

    A target that exists and is not a regular file (a device such as ``/dev/null``,
    a FIFO) is written in place, never replaced; a symbolic link is written through
    (its target is replaced, the link kept). Any failure to write (missing or read-only
    folder, full disk, file size limit) removes the temporary file and raises
    :class:`~rotordyn_modal.errors.OutputError` naming the file and the reason. Inside
    :func:`outputs_together` the rename waits for the end of that block (unless
    ``together`` is False: checkpoints that must be in place at once). ``tidy``: first
    remove the temporaries of ``path`` that killed processes left (a listing of the
    folder; a study's checkpoint, thousands of files cleared as a whole, skips it).

    Yields
    ------
    file object (``mode`` 'w' or 'wb'); with ``mode=None`` the temporary path itself
    (for writers such as ``savefig`` that take a file name).
    """
    shown, path = path, real_target(path)
    if _is_special(path):
        with _in_place(path, mode, kwargs, shown) as target:
            yield target
        if _BATCH[0] is not None:
            _BATCH[0].written.append(str(shown))
        return
    check_writable(shown)
    if tidy:
        remove_stale_temporaries(path)
    try:
        fd, temporary = tempfile.mkstemp(prefix=_temporary_prefix(path), suffix=path.suffix or ".tmp",
                                         dir=path.parent)
    except OSError as error:
        raise _cannot(shown, error) from None
    try:
        if mode is None:
            os.close(fd)
            yield temporary
        else:
            with os.fdopen(fd, mode, **kwargs) as handle:
                yield handle
                handle.flush()
                os.fsync(handle.fileno())  # a full disk may only say so here
        os.chmod(temporary, _existing_mode(path, 0o666 & ~_umask()))  # mkstemp makes 0600: the usual mode, or the replaced file's
        if together and _BATCH[0] is not None:
            _BATCH[0].pending.append((temporary, path, shown))
        else:
            os.replace(temporary, path)
    except BaseException as error:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        if isinstance(error, OSError) and not isinstance(error, OutputWriteError):
            raise _cannot(shown, error) from None
        raise


@contextlib.contextmanager
def _in_place(path: Path, mode, kwargs, shown):
    try:
        if mode is None:
            yield str(path)
        else:
            with _open_in_place(path, mode, kwargs, shown) as handle:
                yield handle
    except OutputWriteError:
        raise
    except OSError as error:
        raise _cannot(shown, error) from None
