"""Progress bars (``tqdm.auto``) that show on every terminal, whatever size it reports.

tqdm sizes its bar from the terminal of its stream, taking one column and one row off what the
terminal reports. A pseudo-terminal that reports no size at all (0 x 0: ``script`` run without a
terminal, a container's ``-t`` before its size is set, some CI runners) then gives a width of -1,
which cuts the bar's last character off, and a height of -1, which hides the bar altogether: a
study or a sweep of an hour ran without any sign of progress (tqdm 4.70). A terminal of two rows
showed ``... (more hidden) ...`` in place of the bar. :func:`tqdm` gives such terminals tqdm's own
defaults for an unknown size instead: the counts and rates without the meter (``ncols=0``: nothing
to overflow a width that is not known) and 20 rows; terminals of a known size, files, pipes and
notebooks are left to tqdm.
"""

from __future__ import annotations

import os
import sys

__all__ = ["tqdm", "terminal_defaults"]

#: rows tqdm assumes where the terminal's height is not known
_UNKNOWN_ROWS = 20


def terminal_defaults(stream=None) -> dict:
    """The ``ncols`` and ``nrows`` a tqdm bar on ``stream`` (default ``sys.stderr``) needs where
    the terminal reports a size of 0 (or a height that leaves the bar no row); empty where tqdm's
    own reading serves (a sized terminal, or no terminal at all)."""
    stream = sys.stderr if stream is None else stream
    try:
        if not stream.isatty():
            return {}
        columns, rows = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):
        return {}
    sizes = {}
    if columns <= 1:                      # tqdm would draw within columns - 1 <= 0
        sizes["ncols"] = 0
    if rows <= 2:                         # tqdm hides bar 0 from rows - 1 <= 1 on
        sizes["nrows"] = _UNKNOWN_ROWS if rows <= 0 else 2
    if sizes:                             # tqdm reads the other from the terminal only if both are unset
        sizes.setdefault("ncols", columns - 1)
        sizes.setdefault("nrows", rows - 1)
    return sizes


def tqdm(*args, **kwargs):
    """A ``tqdm.auto.tqdm`` bar with the same arguments, sized for terminals that report no size
    (:func:`terminal_defaults`, for the bar's ``file``, default ``sys.stderr``)."""
    from tqdm.auto import tqdm as bar

    for key, value in terminal_defaults(kwargs.get("file")).items():
        kwargs.setdefault(key, value)
    return bar(*args, **kwargs)
