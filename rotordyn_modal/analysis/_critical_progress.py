"""The progress bar of the critical speeds' refinement (:mod:`.critical_speeds`): one bar over the
sweep's crossings, which the brackets swept again and the refinement's parts advance by their
share (a context variable, so that a study's threads each see their own).
"""

from __future__ import annotations

import contextlib
import contextvars

class _Progress:
    """A progress bar over the sweep's crossings (a ``tqdm`` bar); the work of a part (a bracket
    swept again) advances it by that part's share, scaled to the units of its own crossings."""

    def __init__(self, bar):
        self.bar, self.scale, self.done, self.shown = bar, 1.0, 0.0, 0

    def advance(self, count):
        self.done += count * self.scale
        shown = min(int(self.done + 1e-6), self.bar.total)
        if shown > self.shown:
            self.bar.update(shown - self.shown)
            self.shown = shown


_PROGRESS = contextvars.ContextVar("rotordyn_modal_critical_progress", default=None)


@contextlib.contextmanager
def _progress_bar(enabled, total):
    """While refining ``total`` crossings: a bar (``tqdm.auto``) when ``enabled``."""
    if not enabled:
        yield
        return
    from .._progress import tqdm

    with tqdm(total=total, desc="critical speeds", unit="crossing", leave=False) as bar:
        token = _PROGRESS.set(_Progress(bar))
        try:
            yield
        finally:
            _PROGRESS.reset(token)


def _progress_advance(count):
    """``count`` crossings (of the current part's units) done."""
    progress = _PROGRESS.get()
    if progress is not None:
        progress.advance(count)


@contextlib.contextmanager
def _progress_share(weight):
    """A part of the work worth ``weight`` of the current units (0: work already counted, such as
    a jump's bracket swept again); :func:`_progress_units` sets how many units of its own it
    has. On leaving, the bar stands exactly ``weight`` further."""
    progress = _PROGRESS.get()
    if progress is None:
        yield
        return
    outer, goal = progress.scale, progress.done + weight * progress.scale
    progress.scale = 0.0 if weight == 0 else outer * weight
    try:
        yield
    finally:
        progress.scale = outer
        progress.advance((goal - progress.done) / outer if outer else 0.0)


def _progress_units(count):
    """The current part (:func:`_progress_share`) has ``count`` crossings of its own."""
    progress = _PROGRESS.get()
    if progress is not None and count:
        progress.scale /= count
