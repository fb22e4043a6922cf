"""The damped critical speeds of an unbalance sweep that no swept speed resolves.

A source rotor ``j`` excites at ``f_j(Omega) = |r_j Omega| / 2 pi``; its response peaks near
the speeds where a damped natural frequency ``Im(lam(Omega)) / 2 pi`` equals it. The line
drawn through the swept speeds cuts such a peak where no swept speed lies within a quarter of
its half-power band in speed (there a single mode's response is at least about 0.9 of its
peak). These speeds are found from the state matrix's roots at the swept speeds (the k-th
lowest damped frequency is continuous in speed, so a change of sign of its distance to
``f_j`` between two swept speeds brackets a crossing), each bracket then halved until it is
a small share of the mode's band.

The peaks themselves are the maxima of each curve's exact response near those speeds
(:func:`cut_maxima`): two close modes may share one peak between their damped critical
speeds, which neither speed's response reaches.
"""

from __future__ import annotations

import numpy as np

from ..assembly import is_large
from ..linear_system import speed_linear_form
from ._eigensolve import eigenvalues_of

__all__ = ["crossing_speed", "cut_maxima", "exact_peaks", "not_looked_for", "per_source", "undamped_crossings",
           "unresolved_criticals"]

#: the roots are looked for when the sweep's eigen-solutions cost at most this many
#: ``N n_states^3`` (about a second of one core)
_WORK = 3e9
#: a root damped less than this ratio (an undamped mode at round-off) has no finite peak: not looked for
_LEAST_DAMPING = 1e-8
#: a bracket is halved until its width is below this share of its mode's half-power band
_BRACKET_SHARE = 1.0 / 64
#: at most this many halvings
_HALVINGS = 60


def unresolved_criticals(model, speeds, ratios, roots=None):
    """The damped critical speeds of each source that no swept speed resolves.

    Parameters
    ----------
    model : Model
    speeds : ndarray, shape (N,) [rad/s]
        The sweep's reference rotor speeds, in any order.
    ratios : sequence of float, length n_src
        Each source's speed ratio ``r_j``.
    roots : dict, optional
        Filled with the state matrix's roots found at the sweep's distinct speeds, ``|r_j| -> (x
        (S,) [rad/s], roots (S, 2n) [1/s])``, so that :func:`undamped_crossings` given it solves
        none of them again.

    Returns
    -------
    list of (critical, band) per source, or None
        ``critical`` shape (P_j,) [rad/s], the speeds within the sweep where a damped natural
        frequency equals the source's frequency and no swept speed lies within a quarter of
        ``band``, shape (P_j,) [rad/s]: the mode's half-power band ``|Re lam| / pi`` [Hz]
        over the speed rate of the distance between the two frequencies. None where not
        computed (:func:`not_looked_for`): a large model, or eigen-solutions of the sweep
        costing more than :data:`_WORK`. Hysteretic mounts (loss factors): the roots of
        :class:`_LossyForm`, whose viscous equivalent of the loss stiffness is exact at the
        source's frequency.
    """
    x = np.unique(np.asarray(speeds, dtype=float))
    if x.size < 2 or is_large(model):
        return None
    form = speed_linear_form(model)
    if not_looked_for(model, x, form):
        return None
    lossy = any(s.loss_factor for s in model.suspensions)
    found = {}
    for r in {abs(float(r)) for r in ratios}:                              # once a ratio
        if r == 0 and lossy:
            found[r] = (np.zeros(0), np.zeros(0))
            continue
        each = _LossyForm(form, model, r) if lossy else form
        values = _state_roots(each, x, eigenvalues_of)
        if roots is not None:
            roots[r] = (x, values)
        found[r] = _source_criticals(each, x, _oscillating_roots(each, x, values), r)
    return [found[abs(float(r))] for r in ratios]


def not_looked_for(model, speeds, form=None, n_states=None) -> str:
    """Why the peaks between ``speeds`` (N,) [rad/s] are not looked for (the unbalance figure's
    legend says it), or '' where they are: a large model, or eigen-solutions of the sweep
    costing more than :data:`_WORK` (``form``: the model's state form, if made already;
    ``n_states``: its size, if known)."""
    if is_large(model):
        return f"not looked for in a model of {model.dofs.n} coordinates"
    n_states = (form or speed_linear_form(model)).n_states if n_states is None else n_states
    if np.unique(np.asarray(speeds, dtype=float)).size * float(n_states) ** 3 > _WORK:
        return f"not looked for: {len(np.unique(speeds))} eigen-solutions of {n_states} states"
    return ""


class _LossyForm:
    """The state matrix of a model with hysteretic mounts (``K (1 + i eta)``) for a source of
    speed ratio ``r``: the loss stiffness ``eta K`` taken as the viscous damping
    ``eta K / (r |Omega|)`` it equals at the source's frequency ``r |Omega|``, so that where a
    root's damped frequency equals that frequency (a damped critical speed) the root is the
    hysteretic model's; no root at speed 0 (NaN). ``at(speeds)`` as
    :meth:`~rotordyn_modal.linear_system.SpeedLinearForm.at`."""

    def __init__(self, form, model, ratio):
        from ..assembly import loss_stiffness

        self.form, self.ratio, self.n_states = form, ratio, form.n_states
        self.extra = form.mass_inverse @ loss_stiffness(model)

    def at(self, speeds):
        speeds = np.asarray(speeds, dtype=float)
        out = np.array(self.form.at(speeds), dtype=float)
        n = self.form.n_dof
        with np.errstate(divide="ignore", invalid="ignore"):
            out[..., n:2 * n, n:2 * n] -= self.extra / (self.ratio * np.abs(speeds))[..., None, None]
        out[speeds == 0] = np.nan
        return out


def _state_roots(form, speeds, solve):
    """Every root of the state matrix at each of ``speeds`` (S,) by ``solve`` (a batched
    eigenvalue function), all NaN where the matrix is not finite (:class:`_LossyForm`: at speed
    0): shape (S, 2n), complex [1/s]."""
    matrices = form.at(np.asarray(speeds, dtype=float))
    finite = np.all(np.isfinite(matrices), axis=(1, 2))
    values = np.full(matrices.shape[:2], np.nan + 0j)
    if finite.any():
        values[finite] = solve(matrices[finite] if not finite.all() else matrices)
    return values


def _sign_changes(g, x):
    """``(k, m)``: the steps ``x[k] .. x[k + 1]`` (increasing speeds, shape (S,)) over which column
    ``m`` of ``g`` (S, m), a root's frequency less the source's line (NaN or inf past a speed's
    last root), changes sign, where both speeds have as many roots and lie on one side of 0."""
    count = np.sum(np.isfinite(g), axis=1)
    same = (count[:-1] == count[1:]) & (np.sign(x[:-1]) * np.sign(x[1:]) >= 0)
    return np.nonzero(same[:, None] & np.isfinite(g[:-1]) & (np.sign(g[:-1]) * np.sign(g[1:]) < 0))


def _oscillating_roots(form, speeds, values=None):
    """The roots with ``Im > 0`` and ``-Re > _LEAST_DAMPING |lam|`` of the state matrix at each of
    ``speeds`` (S,), sorted by frequency, NaN after the last (all NaN where the matrix is not
    finite): shape (S, m), complex [1/s]; of ``values`` (S, 2n), every root there, if known."""
    values = _state_roots(form, speeds, eigenvalues_of) if values is None else values
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
    k, m = _sign_changes(g, x)
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


def undamped_crossings(model, ratios, speeds=None, roots=None):
    """Where each source's excitation line meets an undamped root of the state matrix, for
    :func:`exact_peaks`' peaks too narrow for its search (an undamped mode): an
    :class:`_Crossings`, callable as ``crossing(j, start, a, b)`` (the crossing nearest ``start``
    within ``[a, b]``, :func:`crossing_speed`) and with ``every(j)`` (every crossing of an undamped
    root within the sweep ``speeds``). The model's state form is made at the first call (most
    sweeps have no such peak).

    Parameters
    ----------
    model : Model
    ratios : sequence of float, length n_src
        Each source's speed ratio ``r_j``.
    speeds : ndarray, shape (N,) [rad/s], optional
        The sweep (without it, ``every`` finds none).
    roots : dict, optional
        The state matrix's roots at the sweep's distinct speeds where known, filled by
        :func:`unresolved_criticals` (``|r_j| -> (x, roots)``): ``every`` then solves only near
        the crossings it finds.

    Returns
    -------
    _Crossings
    """
    return _Crossings(model, ratios, speeds, roots)


class _Crossings:
    """See :func:`undamped_crossings`."""

    def __init__(self, model, ratios, speeds=None, roots=None):
        self.model, self.ratios, self.speeds = model, ratios, speeds
        self.forms, self.found, self.everywhere = {}, {}, {}
        self.roots = {} if roots is None else roots

    def form(self, r):
        """The state form of a source of speed ratio ``|r|`` (hysteretic mounts: :class:`_LossyForm`)."""
        if r not in self.forms:
            form = speed_linear_form(self.model)
            lossy = r and any(s.loss_factor for s in self.model.suspensions)
            self.forms[r] = _LossyForm(form, self.model, r) if lossy else form
        return self.forms[r]

    def __call__(self, j, start, a, b):
        """``(speed [rad/s], root [1/s])`` of :func:`crossing_speed` nearest ``start`` in ``[a, b]``, or None."""
        r = abs(float(self.ratios[j]))
        for speed, root in self.found.get(r, ()):          # another output's peak of the same crossing
            if a < speed < b and abs(speed - start) < _SAME_MAXIMUM * (b - a):
                return speed, root
        result = crossing_speed(self.form(r), r, start, a, b)
        if result is not None:
            self.found.setdefault(r, []).append(result)
        return result

    def every(self, j):
        """The speeds [rad/s], increasing, where source ``j``'s line meets an undamped root within
        the sweep: between two swept speeds where the distance ``Im lam - |r Omega|`` of the k-th
        lowest undamped frequency changes sign (their count the same), refined by
        :func:`crossing_speed` from the chord's zero; None where not looked for (no sweep, or its
        eigen-solutions cost more than :data:`_WORK`: :func:`not_looked_for`)."""
        r = abs(float(self.ratios[j]))
        if r not in self.everywhere:
            self.everywhere[r] = self._every(r)
        return self.everywhere[r]

    def _every(self, r):
        if self.speeds is None or not r or not_looked_for(self.model, self.speeds):
            return None
        x = np.unique(np.asarray(self.speeds, dtype=float))
        form = self.form(r)
        known = self.roots.get(r)
        values = known[1] if known is not None and np.array_equal(known[0], x) else \
            _state_roots(form, x, np.linalg.eigvals)
        keep = (values.imag > 0) & (np.abs(values.real) <= _LEAST_DAMPING * np.abs(values))
        frequency = np.sort(np.where(keep, values.imag, np.inf), axis=1)       # (S, 2n), inf after the last
        g = frequency - r * np.abs(x)[:, None]
        k, m = _sign_changes(g, x)
        out = []
        for k_, m_ in zip(k, m):
            lo, hi, g_lo, g_hi = x[k_], x[k_ + 1], g[k_, m_], g[k_ + 1, m_]
            start = lo + (hi - lo) * g_lo / (g_lo - g_hi)                        # the chord's zero
            found = crossing_speed(form, r, min(max(start, lo), hi), lo, hi)
            if found is not None and abs(found[1].real) <= _LEAST_DAMPING * abs(found[1]):
                out.append(found[0])
        return np.unique(out)


#: the first half-width of :func:`crossing_speed`'s bracket, as a share of its interval; widened
#: by :data:`_WIDENING` a step until the sign changes
_FIRST_REACH, _WIDENING = 1e-4, 8.0


def crossing_speed(form, ratio, start, a, b):
    """The speed nearest ``start`` within ``[a, b]`` where a root ``lam`` of the state matrix
    equals ``i |ratio Omega|``: the root followed from the one nearest ``i |ratio start|``, its
    ``g(Omega) = Im lam(Omega) - |ratio Omega|`` bracketed around ``start`` (a bracket widened
    from :data:`_FIRST_REACH` of the interval) and solved by Brent's method to round-off. For an
    undamped mode (``lam`` on the imaginary axis) it is the critical speed where ``det(K - w^2 M
    + i w C(Omega)) = 0`` with ``w = ratio Omega``: the unbalance response is unbounded there.

    Parameters
    ----------
    form : SpeedLinearForm or _LossyForm
        ``form.at(speeds)`` the state matrices, shape (S, 2n, 2n).
    ratio : float
        The source's speed ratio ``|r|`` (> 0).
    start, a, b : float
        [rad/s] the first guess and the interval (signed speeds, ``a < start < b``).

    Returns
    -------
    tuple or None
        ``(speed [rad/s], root [1/s])``, the root at that speed; None where ``g`` does not
        change sign within ``[a, b]`` or ``ratio`` is 0.
    """
    from scipy.optimize import brentq

    if not ratio:
        return None

    def root_near(speed, near):
        values = np.linalg.eigvals(form.at(np.array([speed]))[0])
        return values[np.argmin(np.abs(values - near))]

    first = root_near(start, 1j * ratio * abs(start))         # the root followed: nearest this one

    def gap(speed):
        return root_near(speed, first).imag - ratio * abs(speed)

    g_start, reach = gap(start), _FIRST_REACH * (b - a)
    if g_start == 0:
        return float(start), complex(first)
    while True:
        lo, hi = max(start - reach, a), min(start + reach, b)
        g_lo, g_hi = gap(lo), gap(hi)
        if not (np.isfinite(g_lo) and np.isfinite(g_hi)):
            return None
        if g_lo * g_start <= 0 or g_hi * g_start <= 0:
            break
        if lo == a and hi == b:
            return None
        reach *= _WIDENING
    lo, hi = (lo, start) if g_lo * g_start <= 0 else (start, hi)
    speed = brentq(gap, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps)
    return float(speed), complex(root_near(speed, first))


#: each damped critical speed's neighbourhood is sampled at this share of its mode's half-power
#: band in speed (there a single mode's response is at least about 0.9 of its peak) ...
_GRID_STEP = 0.25
#: ... this many bands either side (two close modes' shared peak lies between them)
_GRID_REACH = 2.0
#: the golden-section and bisection searches stop below this share of their first interval
_SEARCH_SHARE = 1e-4
#: ... or after this many steps: an interval a few units in the last place wide (a mode damped
#: at round-off) shrinks no further
_SEARCH_STEPS = 60
#: two maxima of one curve closer than this share of their search intervals are one
_SAME_MAXIMUM = 1e-3
#: the AF table's searches (its peaks and their half-power points) stop below this share of their
#: first interval: the AF whatever the swept speeds, to about 1e-8 (a peak's interval is two swept steps)
_AF_SHARE = 1e-8
#: ... the golden-section search for a swept peak's maximum below this share (the peak's speed to
#: about 1e-7 of itself where its interval is a fifth of it; the AF's level moves by its square)
_AF_PEAK_SHARE = 1e-6
#: the solves of one peak's searches, about (a golden-section step and a bisection step of each
#: side are one call for every peak at once)
_AF_CALLS = 60
#: a peak whose half-power band is narrower than this share of its search interval (two swept
#: steps) is unbounded (an undamped mode; the search ends at round-off of the singularity)
_UNBOUNDED_SHARE = 1e-3


def cut_maxima(curve, speeds, amplitude, found, half_power=True, share=_SEARCH_SHARE):
    """The maxima of each curve's amplitude between swept speeds that the line through the swept
    speeds cuts, with their API 684 half-power width, found on the exact response.

    Around each damped critical speed that no swept speed resolves
    (:func:`unresolved_criticals`) the response is sampled at a quarter of the mode's band,
    two bands either side, within the two swept speeds around it; each interior maximum of
    those samples (a candidate) is refined by a golden-section search on ``|response|`` (two
    close modes sharing one peak give one maximum, at the peak, not one at each damped critical
    speed). A maximum more than sqrt(2) (3 dB) times both swept amplitudes around it is cut;
    its half-power points (``|response| = peak / sqrt(2)``, the nearest either side) are found
    by bisection on the exact response. All candidates step together, one call a step.

    Parameters
    ----------
    curve : callable
        ``curve(s, o, j)``, ``s`` [rad/s] and the integer arrays ``o``, ``j`` each shape (K,)
        -> shape (K,), complex: the response of output ``o[k]`` to source ``j[k]`` at
        ``s[k]`` alone, so that each candidate evaluates its own curve only (the search's cost
        grows as the number of candidates, not as its square).
    speeds : ndarray, shape (N,) [rad/s]
        The swept speeds, any order (repeats allowed).
    amplitude : ndarray, shape (n_out, n_src, N)
        ``|response|`` at ``speeds``.
    found : list of (critical, band) per source
        :func:`unresolved_criticals`' result.
    half_power : bool
        Whether the half-power widths are wanted (False: NaN, and no bisection).
    share : float
        The searches stop below this share of their first interval (the AF table's:
        :data:`_AF_SHARE`).

    Returns
    -------
    at, value, width : ndarray, shape (n_out, n_src, Q)
        Each curve's cut maxima by speed [rad/s], the response there (complex) and the width
        ``N2 - N1`` [rad/s] between the half-power points, NaN after a curve's last.
    """
    x, first = np.unique(np.asarray(speeds, dtype=float), return_index=True)
    swept = np.asarray(amplitude)[:, :, first]                                  # (n_out, n_src, N')
    n_out, n_src = swept.shape[:2]
    samples = _samples(x, found, n_out)
    y = np.abs(curve(samples["s"], samples["o"], samples["j"])) if samples["s"].size else np.zeros(0)
    c = _candidates(samples, y)
    if not c["o"].size:
        return np.full((n_out, n_src, 0), np.nan), np.full((n_out, n_src, 0), np.nan + 0j), \
            np.full((n_out, n_src, 0), np.nan)
    c = _distinct(_refined(curve, c, share))
    o, j, k = c["o"], c["j"], c["k"]
    c = _taken(c, np.abs(c["value"]) > np.sqrt(2.0) * np.maximum(swept[o, j, k], swept[o, j, k + 1]))
    widths = (_half_power_widths(curve, c, samples, y, share) if half_power and c["o"].size
              else np.full(c["o"].size, np.nan))
    return _per_curve(c, widths, n_out, n_src)


def exact_peaks(curve, speeds, amplitude, solve_work: float = 0.0, criticals=None, crossing=None):
    """The AF table's peaks on the exact response: each swept peak of each curve (:func:`spin_curves`', as
    ``unbalance.amplification_factors``') refined to
    the maximum of ``|response|`` between its two swept neighbours (golden-section search), and
    that maximum's half-power points (``|response| = peak / sqrt(2)``, the nearest either side)
    bisected on the exact response between the last swept speed above that level and the first
    below it. The searches run to :data:`_AF_PEAK_SHARE` and :data:`_AF_SHARE` of their interval
    (about 30 steps each, one ``curve`` call a step for every peak at once), so that the amplification
    factor ``|N_c| / (N2 - N1)`` does not depend on the swept speeds (examples/compressor_rotor.toml,
    probe-left-y: 25.9 from the 151 report speeds' interpolated band, 32.4 exact).

    Parameters
    ----------
    curve : callable
        ``curve(s, o, j)`` as :func:`cut_maxima`'s.
    speeds : ndarray, shape (N,) [rad/s]
        The swept speeds, any order (repeats allowed).
    amplitude : ndarray, shape (n_out, n_src, N)
        ``|response|`` at ``speeds``.
    criticals : list of ndarray, optional
        Each source's damped critical speeds within the sweep [rad/s] (:func:`unresolved_criticals`'
        ``critical``): where a peak's band meets one, the response's minimum between them is
        looked for (:func:`_half_power_brackets`).
    solve_work : float
        The work of one solve of ``curve`` at one speed (``n_dof^3``): the peaks are not looked
        for (None) where the search, :data:`_AF_CALLS` solves a peak, would cost more than
        :data:`_WORK` (about a second of one core; the AF table then reads the swept speeds).

    Returns
    -------
    tuple or None
        None where not looked for, else:
    swept, at : ndarray, shape (n_out, n_src, Q) [rad/s]
        Each curve's swept peaks' speeds and the maxima of the exact response found from them,
        NaN after a curve's last.
    value : ndarray, shape (n_out, n_src, Q), complex
        The response at ``at``.
    half_power : ndarray, shape (n_out, n_src, Q, 2) [rad/s]
        The half-power points ``N1, N2`` (signed speeds, in the order of ``|speed|``); NaN on a
        side where the swept amplitude does not fall below the level within the sweep. A peak
        whose band is narrower than :data:`_UNBOUNDED_SHARE` of its search interval (an undamped
        mode: the response is unbounded there; AF above ``500 N_c`` over a swept step) is
        reported where the response is unbounded: at the exact speed where its source's line
        meets the undamped root (``crossing``), its response ``inf``, with ``N1 = N2`` that speed
        (AF infinite) (:func:`_unbounded`).
    crossing : callable, optional
        ``crossing(j, start, a, b)`` of :func:`undamped_crossings`: where source ``j``'s line
        meets a root near ``start`` within ``[a, b]`` [rad/s] (without it, an unbounded peak
        is taken at the search's maximum). With its ``every(j)``, every other crossing of an
        undamped root within the sweep that is a pole of a curve is added, unbounded, whether or
        not a swept peak is near it (:func:`_unbounded_elsewhere`): a damped machine's undamped
        mode whose pole the swept line shows no peak at, or a sweep without swept peaks.
    """
    c, sides = _swept_peaks(np.asarray(speeds, dtype=float), np.asarray(amplitude))
    if c["o"].size * _AF_CALLS * solve_work > _WORK:
        return None
    n_out, n_src = np.shape(amplitude)[:2]
    c, half_power = _bounded_or_not(curve, c, sides, criticals, crossing) if c["o"].size else _no_peaks()
    if hasattr(crossing, "every"):
        c, half_power = _unbounded_elsewhere(curve, c, half_power, crossing, speeds, (n_out, n_src))
    if not c["o"].size:
        empty = np.full((n_out, n_src, 0), np.nan)
        return empty, empty.copy(), empty + 0j, np.full((n_out, n_src, 0, 2), np.nan)
    return _packed(c, half_power, n_out, n_src)


def _bounded_or_not(curve, c, sides, criticals, crossing):
    """The swept peaks ``c`` of :func:`exact_peaks` refined on the exact response, with their
    half-power points (C, 2) [rad/s]; a peak narrower than the search resolves placed where the
    response is unbounded (:func:`_unbounded`)."""
    c = _refined(curve, c, _AF_PEAK_SHARE)
    level = np.abs(c["value"]) / np.sqrt(2.0)
    inside, outside = _half_power_brackets(curve, c, sides, level, criticals)
    known = np.isfinite(outside)
    points = np.full(outside.shape, np.nan)
    if known.any():
        o, j = np.tile(c["o"], 2)[known], np.tile(c["j"], 2)[known]
        points[known] = _level_crossings(curve, o, j, np.tile(level, 2)[known], inside[known], outside[known],
                                         _AF_SHARE)
    n = c["o"].size
    half_power = np.stack([points[:n], points[n:]], axis=1)                 # (C, 2): N1, N2
    narrow = np.abs(half_power[:, 1] - half_power[:, 0]) < _UNBOUNDED_SHARE * c["span"]
    if narrow.any():
        c, half_power = _unbounded(c, half_power, narrow, crossing)
    return c, half_power


def _no_peaks():
    """:func:`_bounded_or_not`'s result for a sweep without swept peaks."""
    c = {name: np.zeros(0, dtype=int) for name in ("o", "j")}
    c.update(swept=np.zeros(0), at=np.zeros(0), value=np.zeros(0, dtype=complex))
    return c, np.zeros((0, 2))


def _unbounded(c, half_power, narrow, crossing=None):
    """The peaks ``c`` (:func:`exact_peaks`', with their ``half_power`` (C, 2) [rad/s]) whose band
    is ``narrow`` (C,) bool (narrower than the search resolves) placed where the response is
    unbounded: the exact speed where the source's excitation line meets an undamped root
    (``crossing(j, start, a, b)`` of :func:`undamped_crossings`, from the search's maximum),
    their response ``inf`` and ``N1 = N2`` that speed (AF infinite). A root found damped
    (``|Re lam| > _LEAST_DAMPING |lam|``) bounds the response: that peak keeps the search's
    maximum and half-power points. Without ``crossing``, or where no root meets the line within
    the peak's interval, the search's maximum is taken for the unbounded speed."""
    at, value, half_power = c["at"].copy(), c["value"].copy(), half_power.copy()
    for m in np.flatnonzero(narrow):
        found = None if crossing is None else crossing(int(c["j"][m]), at[m], c["a"][m], c["b"][m])
        if found is not None and abs(found[1].real) > _LEAST_DAMPING * abs(found[1]):
            continue                                  # a damped root: the response is bounded
        at[m] = at[m] if found is None else found[0]
        value[m], half_power[m] = complex(np.inf, 0.0), at[m]
    return dict(c, at=at, value=value), half_power


#: a crossing of an undamped root excites a curve (a pole of its response) where the response at
#: :data:`_POLE_NEAR` of the speed from it is more than :data:`_POLE_GROWTH` times the response at
#: :data:`_POLE_FAR`, on both sides (a pole: about their ratio, 1000; a smooth curve: about 1)
_POLE_NEAR, _POLE_FAR, _POLE_GROWTH = 1e-9, 1e-6, 30.0


def _unbounded_elsewhere(curve, c, half_power, crossing, speeds, shape):
    """The peaks ``c`` with their ``half_power`` (C, 2) of :func:`_bounded_or_not` (any, none) and
    every other pole of each curve within the sweep: each
    crossing of an undamped root with its source's line (``crossing.every(j)``) that excites the
    curve (:data:`_POLE_GROWTH`) and has no unbounded peak of it yet is added, unbounded (its
    response ``inf``, ``N1 = N2`` its speed, its swept speed the nearest), so that two poles
    between two swept speeds, which the swept line shows as one peak, are both reported (a rotor
    on anisotropic supports: its forward and backward 1X crossings 5 rpm apart, swept every 5 rpm).
    ``shape``: ``(n_out, n_src)``. The peaks come each curve's by direction of spin and speed."""
    x = np.unique(np.asarray(speeds, dtype=float))
    added = {name: [] for name in ("o", "j", "swept", "at")}
    for j in range(shape[1]):
        every = crossing.every(j)
        if every is None or not len(every):
            continue
        o, at = np.repeat(np.arange(shape[0]), len(every)), np.tile(every, shape[0])
        for m in np.flatnonzero(_excited(curve, o, np.full(o.size, j), at)):
            mine = (c["o"] == o[m]) & (c["j"] == j) & np.isinf(c["value"])
            if np.any(np.abs(c["at"][mine] - at[m]) <= 1e-9 * abs(at[m])):
                continue                                   # placed already from its swept peak
            for name, item in zip(added, (o[m], j, x[np.argmin(np.abs(x - at[m]))], at[m])):
                added[name].append(item)
    if not added["o"]:
        return c, half_power
    joined = {name: np.concatenate([c[name], np.array(added[name], dtype=c[name].dtype)]) for name in added}
    joined["value"] = np.concatenate([c["value"], np.full(len(added["o"]), complex(np.inf, 0.0))])
    half_power = np.concatenate([half_power, np.repeat(np.array(added["at"])[:, None], 2, axis=1)])
    order = np.lexsort((np.abs(joined["at"]), joined["at"] >= 0, joined["j"], joined["o"]))
    return {name: value[order] for name, value in joined.items()}, half_power[order]


def _excited(curve, o, j, at):
    """Whether each crossing ``at`` (K,) [rad/s] is a pole of curve ``(o, j)`` (K,):
    :data:`_POLE_GROWTH` on both sides."""
    growth = []
    for side in (-1.0, 1.0):
        near = np.abs(curve(at * (1 + side * _POLE_NEAR), o, j))
        far = np.abs(curve(at * (1 + side * _POLE_FAR), o, j))
        with np.errstate(divide="ignore", invalid="ignore"):
            growth.append(near / far)
    return np.minimum(*growth) > _POLE_GROWTH


def _swept_peaks(speeds, amplitude):
    """The swept peaks of each curve of ``amplitude`` (n_out, n_src, N) over ``speeds`` (N,)
    [rad/s] (:func:`spin_curves`'): a dict of arrays ``o``, ``j``, ``side``, ``swept`` (the peak's
    signed speed) and ``a < b`` (its swept neighbours, the search interval), and ``sides``:
    ``[(sign, x (N',) increasing |speed|, y (n_out, n_src, N'))]``."""
    sides, c = [], {name: [] for name in ("o", "j", "side", "swept", "a", "b")}
    for sign, _, x, y, peaks in spin_curves(speeds, amplitude):
        sides.append((sign, x, y))
        for (o, j), k in peaks:
            ends = sorted((sign * x[k - 1], sign * x[k + 1]))
            for name, item in zip(c, (o, j, len(sides) - 1, sign * x[k], *ends)):
                c[name].append(item)
    return {name: np.array(items, dtype=int if name in ("o", "j", "side") else float)
            for name, items in c.items()}, sides


def spin_curves(speeds, amplitude):
    """The swept peaks of each curve, the one search of them (:func:`exact_peaks`',
    :func:`.unbalance.amplification_factors`'): each direction of spin a curve of its own over
    ``|speed|``, its peaks ``scipy``'s ``find_peaks``.

    Parameters
    ----------
    speeds : ndarray, shape (N,) [rad/s]
        Any order, repeats allowed (each distinct speed of a side counted once, its first).
    amplitude : ndarray, shape (..., N)

    Returns
    -------
    list of (sign, index, x, y, peaks), the negative speeds' first
        ``index`` (N',): the side's speeds in ``speeds`` by increasing ``x`` (N',) ``= |speed|``
        (``speeds[index] = sign * x``); ``y = amplitude[..., index]``; ``peaks``: ``[(curve,
        k)]``, each curve's (its index over the leading axes) peaks by ``k``, their index into ``x``.
    """
    from scipy.signal import find_peaks

    out = []
    for sign, side in ((-1.0, np.flatnonzero(speeds < 0)), (1.0, np.flatnonzero(speeds >= 0))):
        x, first = np.unique(np.abs(speeds[side]), return_index=True)
        y = amplitude[..., side[first]]
        peaks = [(curve, k) for curve in np.ndindex(*y.shape[:-1]) for k in find_peaks(y[curve])[0]]
        out.append((sign, side[first], x, y, peaks))
    return out


def _half_power_brackets(curve, c, sides, level, criticals=None):
    """Each peak's brackets of its half-power points: ``inside`` (at or above ``level``) and
    ``outside`` (below it), each shape (2C,) [rad/s], first the lower side's then the upper's,
    NaN where the amplitude does not fall below ``level`` on that side within the sweep.

    Walking out from the peak over the swept speeds: the first one below ``level`` and the one
    (or the peak) before it. But the response may dip below ``level`` between swept speeds and
    rise again, towards a neighbouring peak (another of the curve's peaks, or a damped critical
    speed of ``criticals``, a list per source of speeds [rad/s], that the swept speeds may not
    resolve): between the peak and each such speed nearer than that swept speed its minimum is
    searched (:func:`_gap_minima`), and the nearest below ``level`` gives the bracket, so that
    the crossing is the nearest whatever the swept speeds (examples/fan_on_bearings.toml, 3891
    rpm beside a peak of AF 101 at 3949 rpm: AF 27.1 at 51 report points, 35.7 at 401, without it)."""
    n = c["o"].size
    inside, outside = np.full(2 * n, np.nan), np.full(2 * n, np.nan)
    gaps = []                                     # (slot, start, end) [|rad/s|], each side's nearest first
    for m in range(n):
        sign, x, y = sides[c["side"][m]]
        u, yy = abs(c["at"][m]), y[c["o"][m], c["j"][m]]
        marks = _marks(c, m, criticals)
        for slot, step in ((m, -1), (n + m, 1)):
            below = np.flatnonzero(((x < u) if step < 0 else (x > u)) & (yy < level[m]))
            limit = x[0] if step < 0 else x[-1]
            if below.size:
                k = below[-1] if step < 0 else below[0]
                limit = x[k]
                inside[slot], outside[slot] = sign * (min(x[k + 1], u) if step < 0 else max(x[k - 1], u)), sign * x[k]
            t = np.sort(marks[(step * (marks - u) > 1e-9 * u) & (step * (limit - marks) > 0)])[::step]
            gaps += [(slot, a, b) for a, b in zip(np.r_[u, t[:-1]], t)]
    return _gap_minima(curve, c, sides, level, gaps, inside, outside)


def _marks(c, m, criticals):
    """The speeds [|rad/s|] of peak ``m``'s neighbours: the other peaks of its curve (its
    direction of spin) and its source's damped critical speeds (``criticals``) of that direction."""
    same = (c["o"] == c["o"][m]) & (c["j"] == c["j"][m]) & (c["side"] == c["side"][m])
    marks = [np.abs(c["at"][same])]
    if criticals is not None and len(criticals[c["j"][m]]):
        speeds = np.asarray(criticals[c["j"][m]], dtype=float)
        marks.append(np.abs(speeds[np.sign(speeds) * np.sign(c["swept"][m]) >= 0]))
    return np.concatenate(marks)


def _gap_minima(curve, c, sides, level, gaps, inside, outside):
    """``inside``, ``outside`` (2C,) of :func:`_half_power_brackets` with, on each side, the nearest
    of its ``gaps`` (``(slot, start, end)`` [|rad/s|]) where the response's minimum (golden-section
    search of ``1 / |response|``) is below ``level``: its start inside, that minimum outside."""
    if not gaps:
        return inside, outside
    n = c["o"].size
    slot = np.array([g[0] for g in gaps])
    m = slot % n
    sign = np.array([sides[c["side"][k]][0] for k in m])
    ends = np.sort(sign[:, None] * np.array([[g[1], g[2]] for g in gaps]), axis=1)
    found = _refined(lambda s, o, j: 1.0 / np.maximum(np.abs(curve(s, o, j)), 1e-300),
                     {"o": c["o"][m], "j": c["j"][m], "a": ends[:, 0], "b": ends[:, 1]}, _AF_PEAK_SHARE)
    deep = 1.0 / np.abs(found["value"]) < level[m]
    for k in np.flatnonzero(deep)[::-1]:                     # a side's nearest gap last: it stays
        inside[slot[k]], outside[slot[k]] = sign[k] * gaps[k][1], found["at"][k]
    return inside, outside


def _packed(c, half_power, n_out, n_src):
    """``swept, at, value, half_power`` of :func:`exact_peaks` (each curve's in candidate order,
    NaN padded) from its peaks ``c`` and their ``half_power`` (C, 2)."""
    o, j = c["o"], c["j"]
    rank = np.zeros(o.size, dtype=int)
    seen: dict = {}
    for m in range(o.size):
        rank[m] = seen.get((o[m], j[m]), 0)
        seen[(o[m], j[m])] = rank[m] + 1
    q = int(rank.max()) + 1
    swept, at = np.full((n_out, n_src, q), np.nan), np.full((n_out, n_src, q), np.nan)
    value, points = np.full((n_out, n_src, q), np.nan + 0j), np.full((n_out, n_src, q, 2), np.nan)
    swept[o, j, rank], at[o, j, rank], value[o, j, rank] = c["swept"], c["at"], c["value"]
    points[o, j, rank] = half_power
    return swept, at, value, points


def per_source(solve):
    """A ``curve(s, o, j)`` of :func:`cut_maxima` from ``solve(at, j)``: the response (n_out, K')
    of every output to source (or input) ``j`` alone at the distinct speeds (or frequencies)
    ``at`` (K',), increasing; each source solved once at each of its distinct speeds, the
    entries scattered back to the candidates.

    Parameters
    ----------
    solve : callable
        ``solve(at, j)``, ``at`` ndarray (K',) and ``j`` int -> ndarray, shape (n_out, K'), complex.

    Returns
    -------
    callable
        ``curve(s, o, j)``, each shape (K,) -> shape (K,), complex.
    """
    def curve(s, o, j):
        s, o, j = np.asarray(s, dtype=float), np.asarray(o, dtype=int), np.asarray(j, dtype=int)
        out = np.empty(s.shape, dtype=complex)
        for each in np.unique(j):
            mine = np.flatnonzero(j == each)
            at, where = np.unique(s[mine], return_inverse=True)                 # each speed once
            out[mine] = solve(at, int(each))[o[mine], where.ravel()]
        return out

    return curve


def refined_maxima(curve, speeds, pkpk, top=None):
    """The maxima of each curve between the swept speeds near its swept local maxima, and at the
    top of the checked speeds: the largest the exact response reaches there, which the swept
    speeds miss (examples/compressor_rotor.toml at 151 speeds: 9 % low).

    Each interior local maximum of the swept ``pkpk`` is refined between its two neighbours by
    the AF table's golden-section search (:func:`_refined`), and where the sweep
    runs past ``top`` without it, the curve is also read at ``top`` itself (the response may still
    be rising there). The clearance check and the probe limits
    (:func:`.unbalance_checks.unbalance_checks`) both read these.

    Parameters
    ----------
    curve : callable
        ``curve(s, o, j)``, each shape (K,) -> shape (K,), complex: half the peak-to-peak amplitude
        (the 0-peak) of curve ``o`` of case ``j`` at the speeds ``s`` [rad/s]
        (:func:`per_source`).
    speeds : ndarray, shape (N,) [rad/s]
        The swept speeds.
    pkpk : ndarray, shape (n_curves, n_cases, N) [m]
        The peak-to-peak amplitude at them.
    top : float, optional
        [rad/s] the top of the checked speeds.

    Returns
    -------
    at, value : ndarray, shape (n_curves, n_cases, Q)
        The speeds [rad/s] and the peak-to-peak amplitude there [m], NaN after a curve's last.
    """
    peaks = [_swept_maxima(curve, speeds, pkpk, _refined)]
    speed = np.abs(speeds)
    if top is not None and speed.min() < top < speed.max() and not np.any(speed == top):
        o, j = (index.ravel() for index in np.indices(pkpk.shape[:2]))
        at = np.full(o.size, top * np.sign(speeds[np.argmax(speed)]))
        peaks.append((at.reshape(pkpk.shape[:2] + (1,)), 2.0 * np.abs(curve(at, o, j)).reshape(pkpk.shape[:2] + (1,))))
    return np.concatenate([p[0] for p in peaks], axis=2), np.concatenate([p[1] for p in peaks], axis=2)


def _swept_maxima(curve, speeds, pkpk, refined):
    """Each curve's interior local maxima of the swept ``pkpk`` (n_stations, n_cases, N) [m],
    refined by ``refined`` (:func:`_refined`) between the swept speeds either
    side: (speeds [rad/s], pkpk [m]), each shape (n_stations, n_cases, Q), NaN padded."""
    x, first = np.unique(np.asarray(speeds, dtype=float), return_index=True)
    y = pkpk[:, :, first]
    n_st, n_cases = y.shape[:2]
    top = np.zeros(y.shape, dtype=bool)
    top[:, :, 1:-1] = (y[:, :, 1:-1] > y[:, :, :-2]) & (y[:, :, 1:-1] >= y[:, :, 2:])
    o, j, k = np.nonzero(top)
    if not o.size:
        return np.full((n_st, n_cases, 0), np.nan), np.full((n_st, n_cases, 0), np.nan)
    c = refined(curve, {"o": o, "j": j, "a": x[k - 1], "b": x[k + 1]})
    width = int(top.sum(axis=2).max())
    at, value = np.full((n_st, n_cases, width), np.nan), np.full((n_st, n_cases, width), np.nan)
    slot = top.cumsum(axis=2)[o, j, k] - 1
    at[o, j, slot], value[o, j, slot] = c["at"], 2.0 * np.abs(c["value"])
    return at, value


def _samples(x, found, n_out):
    """The speeds sampled around the damped critical speeds, as rows laid end to end: one row a
    source ``j``, swept interval ``[x_k, x_k+1]`` holding damped critical speeds of it, and output
    (segments in order, outputs within a segment). A row's speeds are sorted: both ends of the
    interval, and :data:`_GRID_STEP` bands apart within :data:`_GRID_REACH` bands of each.

    Returns
    -------
    dict
        ``s`` (L,) [rad/s], ``o``, ``j`` (L,) each sample's curve, ``row`` (L,) its row;
        ``start`` (R + 1,) each row's first sample; ``k`` (R,) each row's swept interval.
    """
    offsets = np.arange(-_GRID_REACH, _GRID_REACH + _GRID_STEP / 2, _GRID_STEP)
    points, sources, brackets = [], [], []
    for j, (critical, band) in enumerate(found):
        if not len(critical):
            continue
        k = np.clip(np.searchsorted(x, critical) - 1, 0, len(x) - 2)
        for bracket in np.unique(k):
            lo, hi = x[bracket], x[bracket + 1]
            grid = (critical[k == bracket, None] + band[k == bracket, None] * offsets).ravel()
            points.append(np.unique(np.concatenate([[lo, hi], grid[(grid > lo) & (grid < hi)]])))
            sources.append(j)
            brackets.append(int(bracket))
    segment = np.repeat(np.arange(len(points)), n_out)                             # (R,)
    output = np.tile(np.arange(n_out), len(points))
    lengths = np.array([len(points[g]) for g in segment], dtype=int)
    row = np.repeat(np.arange(segment.size), lengths)
    s = np.concatenate([points[g] for g in segment]) if segment.size else np.zeros(0)
    return {"s": s, "o": output[row], "j": np.asarray(sources, dtype=int)[segment][row] if row.size else row,
            "row": row, "start": np.concatenate([[0], np.cumsum(lengths)]),
            "k": np.asarray(brackets, dtype=int)[segment] if segment.size else segment}


def _candidates(samples, y):
    """Each interior maximum of each row's samples ``y`` (L,) (:func:`_samples`), in row order:
    a dict of arrays ``o``, ``j``, ``k`` (its curve and swept interval), ``row``, and ``a``, ``b``
    its neighbours' speeds (the search interval)."""
    s, row = samples["s"], samples["row"]
    inner = np.zeros(s.size, dtype=bool)
    if s.size > 2:
        same = (row[1:-1] == row[:-2]) & (row[1:-1] == row[2:])
        inner[1:-1] = same & (y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])
    i = np.flatnonzero(inner)
    return {"o": samples["o"][i], "j": samples["j"][i], "k": samples["k"][row[i]], "row": row[i],
            "a": s[i - 1], "b": s[i + 1]}


def _taken(c, keep):
    """The candidates ``c`` (a dict of arrays of one length) where ``keep`` (an index or mask)."""
    return {key: value[keep] for key, value in c.items()}


def _refined(curve, c, share=_SEARCH_SHARE):
    """The candidates ``c`` (:func:`_candidates`) with ``at``, the maximum of ``|response|`` in
    each interval ``[a, b]`` by golden-section search (all at once, one ``curve`` call a step,
    each candidate on its own curve; until ``share`` of ``b - a``), ``value``, the response there,
    and ``span``, ``b - a``."""
    o, j = c["o"], c["j"]
    a, b = c["a"].astype(float), c["b"].astype(float)
    first = b - a
    ratio = (np.sqrt(5.0) - 1) / 2
    c_, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = np.abs(curve(c_, o, j)), np.abs(curve(d, o, j))
    for _ in range(_SEARCH_STEPS):
        if not np.any(b - a > share * first):
            break
        left = fc > fd                                  # the maximum lies in [a, d]
        b, a = np.where(left, d, b), np.where(left, a, c_)
        c_, d, fc, fd = (np.where(left, b - ratio * (b - a), d), np.where(left, c_, a + ratio * (b - a)),
                         np.where(left, np.nan, fd), np.where(left, fc, np.nan))
        new = np.where(left, c_, d)
        f_new = np.abs(curve(new, o, j))
        fc, fd = np.where(left, f_new, fc), np.where(left, fd, f_new)
    at = 0.5 * (a + b)
    return dict(c, at=at, value=np.asarray(curve(at, o, j), dtype=complex), span=first)


def _distinct(c):
    """The candidates ``c`` of :func:`_refined`, one of those of a curve that converged to the
    same speed (within :data:`_SAME_MAXIMUM` of their search intervals): the highest."""
    kept: dict = {}
    chosen = []
    for n in np.argsort(-np.abs(c["value"]), kind="stable"):
        others = kept.setdefault((int(c["o"][n]), int(c["j"][n])), [])
        if not any(abs(c["at"][m] - c["at"][n]) < _SAME_MAXIMUM * min(c["span"][m], c["span"][n])
                   for m in others):
            others.append(n)
            chosen.append(n)
    return _taken(c, np.array(chosen, dtype=int))


def _half_power_widths(curve, c, samples, y, share=_SEARCH_SHARE):
    """Each candidate's ``N2 - N1`` [rad/s] (shape (C,)): its nearest speeds either side where
    ``|response| = |value| / sqrt(2)``, bisected (all at once, until ``share`` of the first
    bracket) between its row's sample nearest to it below that level and the next one towards it."""
    level = np.abs(c["value"]) / np.sqrt(2.0)
    lo, hi = [], []                                     # each side's bracket: (outside, inside)
    for r, at, h in zip(c["row"], c["at"], level):
        points = samples["s"][samples["start"][r]:samples["start"][r + 1]]
        below_level = y[samples["start"][r]:samples["start"][r + 1]] < h
        below = np.flatnonzero((points < at) & below_level)[-1]
        lo.append((points[below], min(points[below + 1], at)))
        above = np.flatnonzero((points > at) & below_level)[0]
        hi.append((points[above], max(points[above - 1], at)))
    outside = np.array([s for s, _ in lo] + [s for s, _ in hi])
    inside = np.array([s for _, s in lo] + [s for _, s in hi])
    crossing = _level_crossings(curve, np.tile(c["o"], 2), np.tile(c["j"], 2), np.tile(level, 2), inside,
                                outside, share)
    n = len(level)
    return crossing[n:] - crossing[:n]


def _level_crossings(curve, o, j, level, inside, outside, share=_SEARCH_SHARE):
    """Where ``|curve(s, o, j)|`` falls to ``level`` (each shape (K,)) between ``inside`` (at or
    above it) and ``outside`` (below it) [rad/s], by bisection (all at once, one ``curve`` call a
    step) until ``share`` of the first bracket: shape (K,) [rad/s]."""
    first = np.abs(inside - outside)
    for _ in range(_SEARCH_STEPS):
        if not np.any(np.abs(inside - outside) > share * first):
            break
        mid = 0.5 * (inside + outside)
        over = np.abs(curve(mid, o, j)) >= level
        inside, outside = np.where(over, mid, inside), np.where(over, outside, mid)
    return 0.5 * (inside + outside)


def _per_curve(c, widths, n_out, n_src):
    """``at``, ``value``, ``width`` of :func:`cut_maxima` (n_out, n_src, Q) from the cut maxima
    ``c`` and their ``widths``: each curve's by speed, NaN after its last."""
    o, j = c["o"].astype(int), c["j"].astype(int)
    order = np.lexsort((c["at"], j, o)) if o.size else np.zeros(0, dtype=int)
    o, j = o[order], j[order]
    curve_id = o * n_src + j
    starts = np.flatnonzero(np.r_[True, curve_id[1:] != curve_id[:-1]]) if o.size else np.zeros(0, dtype=int)
    rank = np.arange(o.size) - np.repeat(starts, np.diff(np.r_[starts, o.size]))
    q = int(rank.max()) + 1 if o.size else 0
    at, width = np.full((n_out, n_src, q), np.nan), np.full((n_out, n_src, q), np.nan)
    value = np.full((n_out, n_src, q), np.nan + 0j)
    at[o, j, rank], value[o, j, rank], width[o, j, rank] = c["at"][order], c["value"][order], widths[order]
    return at, value, width
