"""The damped critical speeds of an unbalance sweep that no swept speed resolves.

A source rotor ``j`` excites at ``f_j(Omega) = |r_j Omega| / 2 pi``; its response peaks near
the speeds where a damped natural frequency ``Im(lam(Omega)) / 2 pi`` equals it. The line
drawn through the swept speeds cuts such a peak where no swept speed lies within a quarter of
its half-power band in speed (there a single mode's response is at least about 0.9 of its
peak). These speeds are found from the state matrix's roots at the swept speeds (the k-th
lowest damped frequency is continuous in speed, so a change of sign of its distance to
``f_j`` between two swept speeds brackets a crossing), each bracket then halved until it is
a small share of the mode's band.
"""

from __future__ import annotations

import numpy as np

from ..assembly import is_large
from ..linear_system import speed_linear_form
from ._eigensolve import eigenvalues_of

__all__ = ["unresolved_criticals"]

#: the roots are looked for when the sweep's eigen-solutions cost at most this many
#: ``N n_states^3`` (about a second of one core)
_WORK = 3e9
#: a root damped less than this ratio (an undamped mode at round-off) has no finite peak: not looked for
_LEAST_DAMPING = 1e-8
#: a bracket is halved until its width is below this share of its mode's half-power band
_BRACKET_SHARE = 1.0 / 64
#: at most this many halvings
_HALVINGS = 60


def unresolved_criticals(model, speeds, ratios):
    """The damped critical speeds of each source that no swept speed resolves.

    Parameters
    ----------
    model : Model
    speeds : ndarray, shape (N,) [rad/s]
        The sweep's reference rotor speeds, in any order.
    ratios : sequence of float, length n_src
        Each source's speed ratio ``r_j``.

    Returns
    -------
    list of (critical, band) per source, or None
        ``critical`` shape (P_j,) [rad/s], the speeds within the sweep where a damped natural
        frequency equals the source's frequency and no swept speed lies within a quarter of
        ``band``, shape (P_j,) [rad/s]: the mode's half-power band ``|Re lam| / pi`` [Hz]
        over the speed rate of the distance between the two frequencies. None where not
        computed: loss factors (no state form of their damping), a large model, or
        eigen-solutions of the sweep costing more than :data:`_WORK`.
    """
    x = np.unique(np.asarray(speeds, dtype=float))
    if x.size < 2 or any(s.loss_factor for s in model.suspensions) or is_large(model):
        return None
    form = speed_linear_form(model)
    if x.size * float(form.n_states) ** 3 > _WORK:
        return None
    roots = _oscillating_roots(form, x)
    found = {r: _source_criticals(form, x, roots, r) for r in {abs(float(r)) for r in ratios}}   # once a ratio
    return [found[abs(float(r))] for r in ratios]


def _oscillating_roots(form, speeds):
    """The roots with ``Im > 0`` and ``-Re > _LEAST_DAMPING |lam|`` of the state matrix at each of
    ``speeds`` (S,), sorted by frequency, NaN after the last: shape (S, m), complex [1/s]."""
    values = eigenvalues_of(form.at(np.asarray(speeds, dtype=float)))
    keep = (values.imag > 0) & (values.real < -_LEAST_DAMPING * np.abs(values))
    key = np.where(keep, values.imag, np.inf)
    order = np.argsort(key, axis=1)
    values = np.take_along_axis(np.where(keep, values, np.nan + 0j), order, axis=1)
    width = int(keep.sum(axis=1).max(initial=0))
    return values[:, :width]


def _source_criticals(form, x, roots, ratio):
    """``(critical, band)`` of one source of speed ratio ``ratio`` (> 0): see
    :func:`unresolved_criticals`; ``x`` (S,) increasing, ``roots`` (S, m) of
    :func:`_oscillating_roots`."""
    if ratio == 0 or not roots.shape[1]:
        return np.zeros(0), np.zeros(0)
    g = roots.imag / (2 * np.pi) - ratio * np.abs(x)[:, None] / (2 * np.pi)      # (S, m) [Hz]
    count = np.sum(np.isfinite(g), axis=1)
    same = (count[:-1] == count[1:]) & (np.sign(x[:-1]) * np.sign(x[1:]) >= 0)
    k, m = np.nonzero(same[:, None] & (np.sign(g[:-1]) * np.sign(g[1:]) < 0))
    if not k.size:
        return np.zeros(0), np.zeros(0)
    lo, hi, g_lo = x[k].copy(), x[k + 1].copy(), g[k, m].copy()
    slope = np.abs(g[k + 1, m] - g[k, m]) / (x[k + 1] - x[k])                  # [Hz s/rad]
    bandwidth = -roots[k, m].real / np.pi                                      # [Hz]
    for _ in range(_HALVINGS):
        band = bandwidth / slope
        open_ = (hi - lo) > _BRACKET_SHARE * band
        if not open_.any():
            break
        mid = 0.5 * (lo + hi)
        at = _oscillating_roots(form, mid[open_])
        if not at.shape[1]:                  # no oscillating root there: the brackets stay as they are
            break
        rows = np.flatnonzero(open_)
        column = np.minimum(m[open_], at.shape[1] - 1)
        root = at[np.arange(rows.size), column]
        g_mid = root.imag / (2 * np.pi) - ratio * np.abs(mid[open_]) / (2 * np.pi)
        known = np.isfinite(g_mid)
        bandwidth[rows[known]] = -root[known].real / np.pi
        left = known & (np.sign(g_mid) == np.sign(g_lo[open_]))
        lo[rows[left]], g_lo[rows[left]] = mid[open_][left], g_mid[left]
        hi[rows[known & ~left]] = mid[open_][known & ~left]
        if not known.all():
            break
    critical, band = 0.5 * (lo + hi), bandwidth / slope
    nearest = np.min(np.abs(x[None, :] - critical[:, None]), axis=1)
    unresolved = 4 * nearest > band
    order = np.argsort(critical[unresolved])
    return critical[unresolved][order], band[unresolved][order]
