"""Numbers of the balancing and vibration standards, in SI (``docs/standards.md``).

Pure formulas and tables, no model: the ISO 21940-11 permissible residual unbalance of a
balance grade, the API 617 / API 684 residual unbalance and the unbalance of a response
analysis (twice it), the API 617 probe vibration limit and clearance scale factor, the ISO
20816-3 zone boundaries of casing vibration velocity, and the amplitude conventions (0-peak,
peak-to-peak, RMS) of a harmonic.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BALANCE_GRADES", "balance_grade", "permissible_unbalance", "api_unbalance",
           "API_SI_CONSTANT", "API_US_CONSTANT", "API_ANALYSIS_MULTIPLE", "api_analysis_unbalance",
           "API_SCALE_CAP", "api_scale_factor", "api_probe_limit", "ISO_20816_3_ZONES",
           "iso_zone_boundaries", "iso_zones", "AMPLITUDES", "AMPLITUDE_WORDS", "amplitude_factor", "amplitude_label",
           "amplitude_column", "one_convention", "required_separation_margin", "largest_margins_text"]

#: ISO 21940-11 balance quality grades G [mm/s] (G0.4 ... G4000)
BALANCE_GRADES = (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)

#: API 617 / 684 residual unbalance: Ur [g mm] = 6350 W [kg] / N [rpm]
API_SI_CONSTANT = 6350.0
#: the same in US customary units: Ur [oz in] = 4 W [lb] / N [rpm]
API_US_CONSTANT = 4.0
#: API 617 (9th ed. 6.8.2.7, as petrobras/ross implements it): the unbalance of the response
#: analysis is Ua = 2 Ur
API_ANALYSIS_MULTIPLE = 2.0
#: API 617 (9th ed. 6.8.2.10): the largest clearance scale factor Scc = Avl / Amax
API_SCALE_CAP = 6.0

#: ISO 20816-3 zone boundaries A/B, B/C, C/D [mm/s RMS] by (machine group, support class)
ISO_20816_3_ZONES = {
    (1, "rigid"): (2.3, 4.5, 7.1),
    (1, "flexible"): (3.5, 7.1, 11.0),
    (2, "rigid"): (1.4, 2.8, 4.5),
    (2, "flexible"): (2.3, 4.5, 7.1),
}

#: amplitude conventions of a harmonic ``A cos(w t + phi)``: factor on the 0-peak amplitude A,
#: words for labels, suffix for table columns, word written after a unit (``25.4 µm pk-pk``)
AMPLITUDES = {
    "peak": (1.0, "0-peak", "0pk", "0-peak"),
    "pk-pk": (2.0, "peak-to-peak", "pkpk", "pk-pk"),
    "rms": (1.0 / math.sqrt(2.0), "RMS", "rms", "RMS"),
}
#: each convention as written after a unit: ``12.7 µm 0-peak``, ``25.4 µm pk-pk``, ``8.98 µm RMS``
#: (the report's ``--amplitude``)
AMPLITUDE_WORDS = {name: convention[3] for name, convention in AMPLITUDES.items()}


def balance_grade(value) -> float | None:
    """The grade G [mm/s] of ``"G2.5"`` (or ``"g2.5"``, ``"G 2.5"``) or of the number 2.5.

    Returns None when ``value`` names no ISO 21940-11 grade (a caller refuses it by name).

    Examples
    --------
    >>> balance_grade("G6.3"), balance_grade(2.5), balance_grade("G3")
    (6.3, 2.5, None)
    """
    if isinstance(value, str):
        text = value.strip()
        if not text[:1] in ("G", "g"):
            return None
        try:
            value = float(text[1:].strip())
        except ValueError:
            return None
    elif isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        return None
    matches = [g for g in BALANCE_GRADES if math.isclose(float(value), g, rel_tol=1e-9)]
    return matches[0] if matches else None


def permissible_unbalance(grade: float, mass: float, speed: float) -> float:
    """ISO 21940-11 permissible residual unbalance ``U = G m / Omega`` [kg m].

    In the standard's units ``U [g mm] = 1000 G [mm/s] m [kg] / Omega [rad/s]``.

    Parameters
    ----------
    grade : float
        G [mm/s] (2.5 for G2.5).
    mass : float
        [kg] the rotor's (or part's) mass.
    speed : float
        [rad/s] the maximum service speed, > 0.
    """
    return grade * 1e-3 * mass / speed


def api_unbalance(load: float, mcs_rpm: float) -> float:
    """API 617 / API 684 residual unbalance ``Ur = 6350 W / N`` [g mm], returned in [kg m].

    The response analysis uses :func:`api_analysis_unbalance`, ``Ua = 2 Ur``.

    Parameters
    ----------
    load : float
        W [kg]: the journal static load (or the rotor's mass for a mode that moves it whole).
    mcs_rpm : float
        N [rpm]: the rotor's maximum continuous speed, > 0.
    """
    return API_SI_CONSTANT * load / mcs_rpm * 1e-6


def api_analysis_unbalance(load: float, mcs_rpm: float) -> float:
    """API 617 unbalance of the response analysis ``Ua = 2 Ur = 2 x 6350 W / N`` [g mm], in [kg m].

    Parameters
    ----------
    load : float
        W [kg]: the journal static load (or the mass the mode moves).
    mcs_rpm : float
        N [rpm]: the rotor's maximum continuous speed, > 0.
    """
    return API_ANALYSIS_MULTIPLE * api_unbalance(load, mcs_rpm)


def api_scale_factor(limit, largest, cap=API_SCALE_CAP):
    """API 617 clearance scale factor ``Scc = Avl / Amax``, at most ``cap``.

    Parameters
    ----------
    limit : float or ndarray
        Avl [m] pk-pk: the probe vibration limit (:func:`api_probe_limit`).
    largest : float or ndarray
        Amax [m] pk-pk: the largest calculated probe amplitude over the operating speeds, > 0.
    cap : float or None
        The largest factor (API 617: 6); None for none.

    Returns
    -------
    float or ndarray
        The factor that scales the response at the close clearances.
    """
    factor = np.asarray(limit, dtype=float) / np.asarray(largest, dtype=float)
    return factor if cap is None else np.minimum(factor, cap)


def api_probe_limit(mcs_rpm):
    """API 617 vibration limit at the probes, peak-to-peak [m].

    ``A1 = 25.4 um sqrt(12000 / N)``, at most 25.4 um (N [rpm] the maximum continuous speed).
    """
    n = np.asarray(mcs_rpm, dtype=float)
    return 25.4e-6 * np.minimum(1.0, np.sqrt(12000.0 / n))


def iso_zone_boundaries(group: int, support: str) -> tuple[float, float, float]:
    """Boundaries A/B, B/C, C/D [m/s RMS] of ISO 20816-3 for a machine group (1, 2) and a
    support class ('rigid', 'flexible')."""
    from .errors import InputError

    key = (group, support)
    if key not in ISO_20816_3_ZONES:
        raise InputError(f"ISO 20816-3 machine group {group!r}, support {support!r}: expected group 1 or 2 "
                         "and support 'rigid' or 'flexible'")
    return tuple(b * 1e-3 for b in ISO_20816_3_ZONES[key])


def iso_zones(velocity_rms, group: int, support: str) -> np.ndarray:
    """Zone 'A', 'B', 'C' or 'D' of each RMS velocity [m/s]; a value on a boundary is in the
    lower zone (the B/C boundary is "the upper limit of zone B": docs/standards.md)."""
    bounds = np.array(iso_zone_boundaries(group, support))
    index = np.searchsorted(bounds, np.asarray(velocity_rms, dtype=float), side="left")
    return np.array(list("ABCD"), dtype=object)[index]


def _convention(amplitude: str):
    from .errors import InputError

    if amplitude not in AMPLITUDES:
        raise InputError(f"amplitude {amplitude!r}: expected one of {', '.join(AMPLITUDES)}")
    return AMPLITUDES[amplitude]


def amplitude_factor(amplitude: str) -> float:
    """Factor from the 0-peak amplitude of a harmonic to ``amplitude`` ('peak', 'pk-pk', 'rms')."""
    return _convention(amplitude)[0]


def amplitude_label(amplitude: str) -> str:
    """'0-peak', 'peak-to-peak' or 'RMS'."""
    return _convention(amplitude)[1]


def amplitude_column(amplitude: str) -> str:
    """Table column of an amplitude in that convention: ``amplitude_0pk``, ``amplitude_pkpk``,
    ``amplitude_rms``."""
    return "amplitude_" + _convention(amplitude)[2]


def one_convention(table, amplitude: str):
    """A table of 0-peak amplitudes with its amplitudes in ``amplitude`` alone.

    Parameters
    ----------
    table : pandas.DataFrame
        With the 0-peak column ``amplitude`` (and possibly a column of another convention,
        ``amplitude_pkpk`` or ``amplitude_rms``, after it).
    amplitude : {'peak', 'pk-pk', 'rms'}

    Returns
    -------
    pandas.DataFrame
        A copy whose ``amplitude`` column is replaced, in its place, by
        :func:`amplitude_column` (``amplitude_0pk``, ``amplitude_pkpk`` or ``amplitude_rms``:
        the name says the convention) holding ``amplitude`` x :func:`amplitude_factor`; the
        other conventions' columns dropped.
    """
    factor, column = amplitude_factor(amplitude), amplitude_column(amplitude)
    others = [c for c in ("amplitude_0pk", "amplitude_pkpk", "amplitude_rms") if c in table.columns]
    out = table.drop(columns=others)
    position = list(out.columns).index("amplitude")
    values = out["amplitude"].to_numpy(dtype=float) * factor
    out = out.drop(columns=["amplitude"])
    out.insert(position, column, values)
    return out


def required_separation_margin(af: float, position: str = "below") -> float:
    """API 617 / API 684 required separation margin [%] for an amplification factor.

    0 for AF < 2.5 (critically damped); otherwise, for a critical speed below the operating
    range (a percentage of its low end) ``min(16, 17 (1 - 1 / (AF - 1.5)))``, above it (a
    percentage of its high end) ``min(26, 10 + 17 (1 - 1 / (AF - 1.5)))`` (``docs/standards.md``).

    Parameters
    ----------
    af : float
        Amplification factor [-]; NaN gives NaN (not evaluated); ``inf`` the largest any AF
        requires (16 below, 26 above).
    position : {'below', 'above'}
        Where the critical speed lies relative to the operating range.
    """
    if position not in ("below", "above"):
        from .errors import InputError

        raise InputError(f"separation margin position {position!r}: expected 'below' or 'above'")
    if np.isnan(af) or af < 2.5:
        return 0.0 if np.isfinite(af) else np.nan
    margin = 17.0 * (1 - 1 / (af - 1.5))
    return min(16.0, margin) if position == "below" else min(26.0, 10.0 + margin)


def largest_margins_text(where: str = "") -> str:
    """The largest separation margins any AF requires (:func:`required_separation_margin` of an
    infinite AF), as every text says them: ``'16 % below, 26 % above'``; ``where`` follows
    "below" (``' the range'``: ``'16 % below the range, 26 % above'``)."""
    below, above = (required_separation_margin(np.inf, side) for side in ("below", "above"))
    return f"{below:g} % below{where}, {above:g} % above"
