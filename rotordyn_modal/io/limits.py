"""Size limits of the files read whole, checked before a byte is parsed.

A model or study file is a short text (the 200-rotor machine of the tests is 49 kB); a
file of many megabytes is a mistake (a wrong path, a data file given as a model) whose
parsing would take the memory of the machine. Measured-data files read whole (UFF,
CSV, TDMS) are allowed much more. Each limit can be raised by an environment variable
(a number of megabytes), as ``docs/model-file.md`` says.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import math
import os
import select
import stat
import warnings
from pathlib import Path

from .._limits import environment_number
from ..errors import InputError

__all__ = ["MODEL_FILE_MB", "MEASURED_FILE_MB", "PIPE_WAIT_S", "check_size", "limit_bytes", "read_limited",
           "input_path", "refuse_beyond_memory", "refuse_unsized", "refuse_compressed", "unreadable", "is_fifo", "pipe_copied", "reads_pipes",
           "named_as", "unreachable_name", "shown_name"]

#: default limit of model and study files [MB]; environment: ROTORDYN_MODAL_MAX_MODEL_MB
MODEL_FILE_MB = 10
#: default limit of measured-data files read whole [MB]; environment: ROTORDYN_MODAL_MAX_MEASURED_MB
MEASURED_FILE_MB = 512
#: how long a named pipe (FIFO) given as an input is waited for, until a program writes to it [s]
PIPE_WAIT_S = 5.0

_LIMITS = {"model": ("ROTORDYN_MODAL_MAX_MODEL_MB", MODEL_FILE_MB),
           "measured": ("ROTORDYN_MODAL_MAX_MEASURED_MB", MEASURED_FILE_MB)}


def input_path(path, what: str) -> Path:
    """``path`` as a :class:`~pathlib.Path` when it is a file's name (``str`` or path-like), else
    :class:`InputError` naming ``what`` (``None``, a number, bytes or a dict raised ``TypeError``
    in ``open``; ``''`` read the current folder, said to be a folder named '.'). A name that can
    lead to no file (:func:`unreachable_name`: too long, or a file's name followed by '/', which
    ``Path`` dropped, so that ``m.toml/`` read ``m.toml``) is refused naming it."""
    if isinstance(path, (str, os.PathLike)) and not isinstance(path, bytes):
        text = os.fspath(path)
        if isinstance(text, str) and text.strip():
            problem = unreachable_name(text)
            if problem:
                raise InputError(f"{shown_name(text)}: the {what}'s name {problem}")
            return Path(text)
    raise InputError(f"{what} = {path!r}: expected the name of a file (a str or path-like, not empty)")


#: names longer than this are shown by their start and end in messages [characters]
_SHOWN_NAME = 80


def shown_name(text) -> str:
    """``text`` (a file's name) for a message: whole up to 80 characters, else its first 40 and
    last 20 characters around '...' with its length (a 300-character name filled the line)."""
    text = os.fspath(text)
    if len(text) <= _SHOWN_NAME:
        return text
    return f"{text[:40]}...{text[-20:]} ({len(text)} characters)"


def unreachable_name(text) -> str | None:
    """Why the name ``text`` can lead to no file (the end of a message: "name ..."), or None.

    * too long for the file system (``ENAMETOOLONG``: one file or folder name over 255 bytes, a
      path over 4096), which ``pathlib`` raised as an ``OSError`` (exit 1);
    * a file followed by '/' or '/.' (``ENOTDIR``), which names a folder: ``Path`` drops the '/',
      so the file itself was read; or a path through a file as if it were a folder.

    Any other state (missing, a loop of links, no permission) is the reader's or writer's to say.
    """
    text = os.fspath(text)
    try:
        os.stat(text)
    except OSError as error:
        if error.errno == errno.ENAMETOOLONG:
            longest = max((len(os.fsencode(part)) for part in text.split(os.sep)), default=0)
            return (f"is too long for the file system: {len(os.fsencode(text))} bytes, its longest file or folder "
                    f"name {longest} bytes (at most 255 bytes a name and 4096 a path): give a shorter name")
        if error.errno == errno.ENOTDIR:
            if Path(text).is_file():    # 'm.toml/', 'm.toml/.': Path drops the ending
                return (f"ends in '/', which names a folder, but {shown_name(Path(text))} is a file: give the "
                        "file's name without the '/'")
            file = next((p for p in Path(text).parents if p.is_file()), None)
            if file is not None:
                return f"leads through {shown_name(file)}, a file, not a folder"
    except ValueError:          # a NUL character: the callers refuse it
        return None
    return None


def limit_bytes(kind: str) -> tuple[int, str]:
    """The limit of a kind of file ('model': model and study files; 'measured') [bytes],
    and the environment variable that sets it."""
    variable, default = _LIMITS[kind]
    megabytes = environment_number(variable, "a number of megabytes > 0 (not inf)", lambda v: 0 < v < math.inf,
                                   float(default))
    return int(megabytes * 2**20), variable


def check_size(path, kind: str, what: str) -> None:
    """Refuse a file larger than its kind's limit, before reading it.

    Parameters
    ----------
    path : path-like
    kind : {'model', 'measured'}
    what : str
        Named in the message ('model file', 'study file', 'measured-data file').

    Raises
    ------
    InputError
        With the file, its size, the limit and how to raise it. A missing or
        unreadable file passes (the reader reports it).
    """
    try:
        size = Path(path).stat().st_size
    except OSError:
        return
    limit, variable = limit_bytes(kind)
    if size > limit:
        raise InputError(f"{path}: a {what} of {size / 2**20:.1f} MB is larger than the limit of "
                         f"{limit / 2**20:g} MB and is not read (set {variable} to a number of MB to allow it)")


def refuse_beyond_memory(path, needed: float, described: str, advice: str) -> None:
    """Refuse, before it is read, a measured-data file whose reading needs about ``needed`` bytes
    where they do not fit (:func:`.._limits.memory_problem`): ``path: reading this measured-data
    file (DESCRIBED) needs about ...: ADVICE``."""
    from .._limits import memory_problem

    problem = memory_problem(needed, f"reading this measured-data file ({described})", advice)
    if problem:
        raise InputError(f"{path}: {problem}")


def refuse_unsized(path, what: str) -> None:
    """Refuse a pipe or a device (``/dev/zero``, a FIFO) given to a reader that reads to the end
    (pyuff, npTDMS): it never ends, or blocks until a program writes to it.

    Parameters
    ----------
    path : path-like
    what : str
        The file expected, with its article ('a Universal File', 'a TDMS file').

    Raises
    ------
    InputError
        ``path`` exists and is neither a regular file nor a folder. A missing file or a folder
        passes (the reader reports it).
    """
    if os.path.exists(path) and not os.path.isdir(path) and not os.path.isfile(path):
        raise InputError(f"{path}: expected {what}, not a pipe or device (its size is not known before reading)")


#: first bytes of a compressed file or an archive: (bytes, what it is, what opens it)
_COMPRESSED = ((b"\x1f\x8b", "a gzip-compressed file", "gunzip it first"),
               (b"\xfd7zXZ\x00", "an xz-compressed file", "unxz it first"),
               (b"\x28\xb5\x2f\xfd", "a zstd-compressed file", "unzstd it first"),
               (b"PK\x03\x04", "a zip archive (a spreadsheet's .xlsx is one)", "unzip it, or export the sheet as CSV"))


def refuse_compressed(head: bytes, path, what: str) -> None:
    """Refuse a compressed file or an archive by its first bytes (``head``: 8 are enough), e.g.
    ``m.csv.gz`` or a gzip file named ``m.csv``: its bytes were read as text and refused in words
    about the text (a control character, a byte that is no UTF-8, no dataset), or taken for a
    bzip2 file's ``BZh1``... header.

    Parameters
    ----------
    head : bytes
    path : path-like
        Named in the message.
    what : str
        The file expected ('model file', 'stator outline', 'Universal File').

    Raises
    ------
    InputError
    """
    for magic, kind, remedy in _COMPRESSED + _BZIP2:
        if head.startswith(magic):
            raise InputError(f"{path}: {kind}: expected the {what} itself, uncompressed ({remedy})")


#: bzip2's 'BZh' and a block size '1'..'9', then the block's 0x314159265359 (text rarely begins so)
_BZIP2 = tuple((b"BZh" + str(k).encode() + b"\x31\x41\x59\x26\x53\x59", "a bzip2-compressed file",
                "bunzip2 it first") for k in range(1, 10))


def unreadable(path, what: str, error: OSError) -> InputError:
    """The one line of a file that ``open`` refused: missing, a folder, no permission to read it.

    Parameters
    ----------
    path : path-like
    what : str
        The file expected, as in "cannot read the stator outline".
    error : OSError

    Returns
    -------
    InputError
        ``PATH: cannot read the WHAT (no such file)``, ``(a folder, not a file)``, ``(no
        permission to read it)``, else the system's words (``strerror``).
    """
    if isinstance(error, FileNotFoundError):
        said = "no such file"
    elif isinstance(error, IsADirectoryError):
        said = "a folder, not a file"
    elif isinstance(error, PermissionError):
        said = "no permission to read it"
    else:
        said = error.strerror or " ".join(str(error).split())
    return InputError(f"{path}: cannot read the {what} ({said})")


def read_limited(path, kind: str, what: str) -> bytes:
    """The bytes of a file read whole, never more than its kind's limit: also a pipe or a
    device (``/dev/stdin``, a FIFO, ``/dev/zero``), whose size no ``stat`` tells.

    Parameters
    ----------
    path : path-like
    kind : {'model', 'measured'}
    what : str
        Named in the message.

    Raises
    ------
    InputError
        The file is larger than the limit (a regular file before a byte is read).
        A pipe that nothing writes to within :data:`PIPE_WAIT_S` (opening it would wait forever).
        A compressed file (:func:`refuse_compressed`).
    OSError
        As ``open`` raises it (missing file, folder, permission): the caller names it.
    """
    check_size(path, kind, what)
    limit, variable = limit_bytes(kind)
    with _open_input(path, what) as handle:
        data = _read_at_most(handle, limit + 1)
    if len(data) > limit:
        raise InputError(f"{path}: a {what} of more than the limit of {limit / 2**20:g} MB is not read "
                         f"(set {variable} to a number of MB to allow it)")
    refuse_compressed(data[:16], path, what)
    return data


def is_fifo(path) -> bool:
    """True for a named pipe (``<(cat m.uff)``'s /dev/fd/63, ``/dev/stdin`` of a pipe, a FIFO);
    False for anything else, and for a path that cannot be looked at (missing, unreadable: its
    reader says why).

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    bool
    """
    try:
        return stat.S_ISFIFO(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def _open_input(path, what: str):
    """``open(path, 'rb')``; a named pipe (FIFO) is opened without waiting for a writer, then
    waited for :data:`PIPE_WAIT_S` until a program writes to it or closes it (``<(cat m.toml)``
    and a writer started before or just after are read whole; a FIFO nothing writes to was
    waited for forever, as ``open`` does)."""
    if not is_fifo(path):
        return open(path, "rb")
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    try:
        poller = select.poll()
        poller.register(fd, select.POLLIN | select.POLLHUP)
        if not poller.poll(PIPE_WAIT_S * 1000.0):
            raise InputError(f"{path}: a pipe nothing writes to: no byte of the {what} came within {PIPE_WAIT_S:g} s "
                             "(start the program that writes into it first, or give a file)")
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


#: bytes of one read of a pipe or device, whose size ``stat`` does not tell
_BLOCK = 2**20


def _read_at_most(handle, count: int) -> bytes:
    """Up to ``count`` bytes of an open binary file: first as many as its size and one more (all
    of a regular file, in one buffer of its size), then blocks of :data:`_BLOCK` (a pipe, a
    device, a file that grew). One read of ``count`` would allocate ``count`` bytes at once,
    which fails for a large limit (``ROTORDYN_MODAL_MAX_MODEL_MB=1e6``) whatever the file."""
    size = os.fstat(handle.fileno()).st_size
    parts = [handle.read(min(count, size + 1))]
    count -= len(parts[0])
    while count > 0 and parts[-1]:
        parts.append(handle.read(min(count, _BLOCK)))
        count -= len(parts[-1])
    parts = [part for part in parts if part]
    return parts[0] if len(parts) == 1 else b"".join(parts)


@contextlib.contextmanager
def pipe_copied(path, ending, kind: str = "measured", what: str = "measured-data file", name: str = "pipe"):
    """A pipe (``<(cat m.uff)``, ``/dev/stdin`` of a pipe, a FIFO a program writes to) read once,
    up to its kind's limit (:func:`read_limited`), into a regular file in a temporary folder of its
    own, removed with the copy at the end: the readers of UFF and TDMS read a file by its name,
    and seek. The one copy of a pipe shared by every reader (:func:`reads_pipes`,
    :func:`rotordyn_modal.io.measured.piped_copy`, the command line's ``-``).

    Parameters
    ----------
    path : path-like
        A named pipe (:func:`is_fifo`), or any file :func:`read_limited` reads.
    ending : str or callable
        The copy's ending (``'.uff'``), or a function of the first 512 bytes that gives it.
    kind : {'model', 'measured'}
        Whose size limit applies.
    what : str
        Named in the messages (the limit, a pipe nothing writes to).
    name : str
        The copy's name before its ending.

    Yields
    ------
    Path
        The copy.

    Raises
    ------
    InputError
        The pipe holds more than the limit, nothing writes to it, or it is compressed.
    """
    import tempfile

    with tempfile.TemporaryDirectory(prefix="rotordyn-modal-pipe-") as folder:
        data = read_limited(path, kind, what)
        copy = Path(folder) / (name + (ending(data[:512]) if callable(ending) else ending))
        copy.write_bytes(data)
        yield copy


@contextlib.contextmanager
def named_as(copy, path):
    """Inside it, an :class:`InputError` or a warning that names the file ``copy`` names ``path``
    instead (the pipe a user typed, not its temporary copy)."""
    copy, path = str(copy), str(path)
    held = []
    try:
        with warnings.catch_warnings(record=True) as held:
            warnings.simplefilter("always")
            try:
                yield
            except InputError as error:
                if copy in str(error):
                    error.args = (str(error).replace(copy, path),)
                raise
    finally:
        for record in held:   # said again, as the caller's filters take them
            warnings.warn_explicit(str(record.message).replace(copy, path), record.category, record.filename,
                                   record.lineno)


def reads_pipes(ending: str, what: str):
    """Decorator of a reader whose first argument names a file it opens by name and seeks in
    (pyuff, npTDMS): a named pipe given to it is read whole first (:func:`pipe_copied`, the
    measured-data limit), the reader reads the copy, and its messages name the pipe.

    Parameters
    ----------
    ending : str
        The format's ending (``'.uff'``, ``'.tdms'``), given to the copy.
    what : str
        The file expected, named if the pipe cannot be read ('Universal File').
    """
    def decorate(reader):
        @functools.wraps(reader)
        def read(path, *args, **kwargs):
            if not is_fifo(path):
                return reader(path, *args, **kwargs)
            with pipe_copied(path, ending, what=what) as copy, named_as(copy, path):
                return reader(copy, *args, **kwargs)
        return read
    return decorate
