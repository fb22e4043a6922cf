"""The text of a file's bytes, for every reader of text files (model, study and ROSS files in
TOML; CSV tables: measured FRFs, mapping tables, outlines): a byte-order mark says UTF-8,
UTF-16 or UTF-32; UTF-16 without one (what some Windows programs and test-rig exports write) is
told by its NUL bytes at every other position; else UTF-8, else the reader's fallback
(Latin-1 for a spreadsheet's 8-bit export, none for TOML).
"""

from __future__ import annotations

import os

__all__ = ["decode_text", "marked_encoding", "utf16_without_mark", "UTF16_WITHOUT_MARK", "shown_text"]

#: byte-order marks and the codec that reads the text after them (UTF-32's before UTF-16's:
#: UTF-32 LE's mark begins with UTF-16 LE's)
_MARKS = ((b"\xef\xbb\xbf", "utf-8-sig"), (b"\xff\xfe\x00\x00", "utf-32"), (b"\x00\x00\xfe\xff", "utf-32"),
          (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"))
#: bytes looked at to tell UTF-16 without a mark (the first 256 characters)
_HEAD = 512
#: what a message says of such a file
UTF16_WITHOUT_MARK = "it looks like UTF-16 text without a byte-order mark (a NUL byte at every other position)"


def utf16_without_mark(data: bytes) -> str | None:
    """``'utf-16-le'`` or ``'utf-16-be'`` when the first bytes are UTF-16 text of mostly
    Latin-1 characters written without a byte-order mark, else None.

    UTF-8 text holds no NUL byte; UTF-16 text of characters below U+0100 has one at every
    other position: the high byte of each 2-byte unit (the second of the pair in little-endian
    order, the first in big-endian). Told from the first :data:`_HEAD` bytes: at least half of
    the units' high bytes are NUL and at most a quarter of their low bytes (a character such as
    U+4E00 or U+0100 has a NUL low byte).

    Parameters
    ----------
    data : bytes
        The file's bytes (without a byte-order mark).

    Returns
    -------
    str or None
    """
    head = data[:min(len(data), _HEAD) // 2 * 2]
    units = len(head) // 2
    if units == 0 or b"\0" not in head:
        return None
    for encoding, high, low in (("utf-16-le", head[1::2], head[0::2]), ("utf-16-be", head[0::2], head[1::2])):
        if 2 * high.count(0) >= units and 4 * low.count(0) <= units:
            return encoding
    return None


def marked_encoding(data: bytes) -> str | None:
    """The codec a byte-order mark at the start of ``data`` names ('utf-8-sig', 'utf-32',
    'utf-16'; each reads the text after the mark), or None."""
    return next((encoding for mark, encoding in _MARKS if data.startswith(mark)), None)


def decode_text(data: bytes, fallback: str | None = "latin-1") -> str:
    """The text of a file's bytes.

    Parameters
    ----------
    data : bytes
        The whole file.
    fallback : str or None
        The codec of bytes that are no UTF-8 ('latin-1': every byte is a character), or None to
        raise.

    Returns
    -------
    str
        Without the byte-order mark.

    Raises
    ------
    UnicodeDecodeError
        The bytes look like UTF-16 without a mark (:func:`utf16_without_mark`) but are no valid
        UTF-16 (an odd count of bytes, a lone surrogate): its ``encoding`` is the UTF-16 codec
        tried and its ``reason`` says :data:`UTF16_WITHOUT_MARK`. Or, without ``fallback``, the
        bytes are no UTF-8.
    """
    if encoding := marked_encoding(data):
        try:
            return data.decode(encoding)
        except UnicodeDecodeError:
            pass        # no text of that encoding after all: as if unmarked
    guessed = utf16_without_mark(data)
    if guessed:
        try:
            return data.decode(guessed)
        except UnicodeDecodeError as problem:
            raise UnicodeDecodeError(guessed, data, problem.start, problem.end,
                                     f"{UTF16_WITHOUT_MARK}, but is no valid UTF-16 ({problem.reason})") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        if fallback is None:
            raise
        return data.decode(fallback)


def shown_text(text) -> str:
    """``text`` (a file name, a command line) as every UTF-8 writer takes it: bytes of a file name
    that are no UTF-8 (Python holds them as lone surrogates, ``'g\\udcffear.toml'``, which a UTF-8
    file, an HTML page or a netCDF attribute refuses) shown as ``\\xNN`` (``'g\\xffear.toml'``);
    any other text unchanged.

    Parameters
    ----------
    text : str, bytes or path-like

    Returns
    -------
    str
    """
    text = os.fspath(text)
    if isinstance(text, bytes):
        return text.decode("utf-8", "backslashreplace")
    try:
        return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:          # a surrogate no file name's byte gives: escaped as itself
        return text.encode("utf-8", "backslashreplace").decode("utf-8")
