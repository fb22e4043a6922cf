"""A sweep's mass-weighted unit shapes, computed a part at a time where they are read.

Mode tracking (:mod:`.tracking`) and the critical speeds' refinement (:mod:`.critical_speeds`)
compare shapes by the mass-weighted MAC: they read the weighted shapes of neighbouring speeds,
of each mode's last sure speed, and of the crossings' brackets, never of every root at every
speed at once. :class:`WeightedRows` is read like the array ``Stack.weighted`` would return for
the whole sweep (a second copy of every shape: 77 MB for the lowest 12 of 400 coordinates at
1,001 speeds), but computes only the parts read, in the parts ``Stack.weighted`` cuts
(:meth:`~._stack.Stack.weighted_parts`), so each row has the bits it has in the whole array.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from .._blas import BLAS_THREADED_BYTES, one_blas_thread

__all__ = ["WeightedRows"]

#: computed parts kept for the next reads (tracking reads the speeds in turn; a look back to a
#: mode's last sure speed in the part before computes that part again)
_KEPT_PARTS = 1


class WeightedRows:
    """The mass-weighted unit shapes of a sweep's shapes, read as an array, computed by part.

    Parameters
    ----------
    stack : Stack
    shapes : ndarray, shape (V, N, c, n), complex
        Unit shapes of ``V`` variants at ``N`` speeds.
    columns : ndarray of int, shape (V, N, c), optional
        Where the shapes are a reordering (or a choice of columns) of the shapes the parts were
        cut on (:meth:`reordered`): each column's column there. Default: those shapes.
    width : int, optional
        The columns of the shapes the parts were cut on (default ``c``).
    one_thread : bool
        Compute the parts with one BLAS thread (as the caller would have computed the whole:
        the same bits whatever BLAS's threads would split).

    Attributes
    ----------
    shape : tuple
        ``shapes.shape``: (V, N, c, n).
    """

    def __init__(self, stack, shapes, columns=None, width=None, one_thread=False, _parts=None, _kept=None):
        variants, count, c, n = shapes.shape
        self.stack, self.shapes, self.shape, self.one_thread = stack, shapes, shapes.shape, one_thread
        self._columns, self._width = columns, c if width is None else width
        if _parts is None:
            rows = np.repeat(np.arange(variants), count)
            _parts = stack.weighted_parts((variants * count, self._width, n), rows)
        self._parts = _parts
        self._starts = np.array([part.start for _, part in _parts], dtype=int)
        self._kept = OrderedDict() if _kept is None else _kept

    def reordered(self, order, shapes):
        """The weighted shapes of ``shapes`` (V, N, c', n): the shapes reordered in place,
        ``shapes[v, k, j]`` the former ``[v, k, order[v, k, j]]`` (``order`` (V, N, c'))."""
        columns = order if self._columns is None else np.take_along_axis(self._columns, order, axis=2)
        return WeightedRows(self.stack, shapes, columns, self._width, self.one_thread, self._parts, self._kept)

    def variant(self, v: int) -> "_Variant":
        """The rows of variant ``v`` read as the array ``self[v]`` (N, c, n), computed by part."""
        return _Variant(self, v)

    def __getitem__(self, key) -> np.ndarray:
        """``array[key]`` of the whole array (V, N, c, n) for ``key`` of up to three indices
        (integers, slices, integer arrays) over its first three axes."""
        key = key if isinstance(key, tuple) else (key,)
        if len(key) > 3:
            raise IndexError("WeightedRows: index the variants, speeds and columns only")
        variants, count, c, n = self.shape
        axes = [np.broadcast_to(np.arange(size).reshape([-1 if a == i else 1 for a in range(3)]),
                                (variants, count, c))[key]
                for i, size in enumerate((variants, count, c))]
        v, k, j = (np.asarray(a).ravel() for a in axes)
        return self._rows(v, k, j).reshape(np.shape(axes[0]) + (n,))

    def _rows(self, v, k, j) -> np.ndarray:
        """The weighted shapes (P, n) at variants ``v``, speeds ``k``, columns ``j`` (P,)."""
        if self._columns is not None:
            j = self._columns[v, k, j]
        flat = (v * self.shape[1] + k) * self._width + j       # rows of the shapes the parts were cut on
        part = np.searchsorted(self._starts, flat, side="right") - 1
        out = np.empty((len(flat), self.shape[-1]), dtype=complex)
        for p in np.unique(part):
            mine = part == p
            out[mine] = self._part(int(p))[flat[mine] - self._starts[p]]
        return out

    def _part(self, p: int) -> np.ndarray:
        """Part ``p`` of :meth:`~._stack.Stack.weighted_parts`, computed as ``Stack.weighted``
        computes it in the whole (its rows alone, of the same shape: one product), kept."""
        if p in self._kept:
            self._kept.move_to_end(p)
            return self._kept[p]
        variant, rows = self._parts[p]
        while len(self._kept) >= _KEPT_PARTS:           # before the next is computed: one at a time
            self._kept.popitem(last=False)
        block = self._source(rows.start, rows.stop)
        width, n = self._width, self.shape[-1]
        whole = rows.start % width == 0 and rows.stop % width == 0
        block = block.reshape(-1, width, n) if whole else block[None]
        with one_blas_thread(BLAS_THREADED_BYTES if self.one_thread else 0):
            weighted = self.stack.weighted(block, np.full(len(block), variant)).reshape(-1, n)
        self._kept[p] = weighted
        return weighted

    def _source(self, start: int, stop: int) -> np.ndarray:
        """The rows ``start:stop`` (R, n) of the shapes the parts were cut on, from the shapes as
        they are now; zero where a column was left out (a row's product does not depend on the
        others' values)."""
        variants, count, c, n = self.shape
        if self._columns is None and self.shapes.flags.c_contiguous:        # the rows themselves: a view
            return self.shapes.reshape(-1, n)[start:stop]
        width = self._width
        first, last = start // width, -(-stop // width)                 # the speeds (of every variant) touched
        speeds = np.arange(first, last)
        v, k = speeds // count, speeds % count
        where = np.full((len(speeds), width), -1, dtype=int)            # each column's place now
        if self._columns is None:
            where[:, :c] = np.arange(c)
        else:
            where[np.arange(len(speeds))[:, None], self._columns[v, k]] = np.arange(c)
        where = where.ravel()[start - first * width:stop - first * width]
        row = (np.arange(start, stop) // width) - first
        there = where >= 0
        if there.all():
            return self.shapes[v[row], k[row], where]
        block = np.zeros((stop - start, n), dtype=complex)
        block[there] = self.shapes[v[row[there]], k[row[there]], where[there]]
        return block


class _Variant:
    """One variant's rows of a :class:`WeightedRows`, read as the array ``rows[v]`` (N, c, n)."""

    def __init__(self, rows: WeightedRows, v: int):
        self.rows, self.v = rows, v
        self.shape = rows.shape[1:]

    def __getitem__(self, key) -> np.ndarray:
        key = key if isinstance(key, tuple) else (key,)
        return self.rows[(self.v,) + key]
