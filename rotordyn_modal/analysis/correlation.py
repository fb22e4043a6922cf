"""Model versus measurement: FRAC, CSAC, CSF, and a MAC-paired natural-frequency table.

For model FRFs ``H_a`` and measured ``H_m`` on the same frequency lines:

* FRAC of one FRF (over frequency):
  ``|sum H_m^* H_a|^2 / (sum |H_m|^2 sum |H_a|^2)`` in [0, 1].
* CSAC at one frequency (over the vector of every output/input pair):
  ``|H_m^H H_a|^2 / ((H_m^H H_m)(H_a^H H_a))``: shape agreement, blind to scale.
* CSF at one frequency: ``2 |H_m^H H_a| / (H_m^H H_m + H_a^H H_a)``: also sensitive to amplitude.

Measured modes come from :func:`~rotordyn_modal.analysis.identification.identify_modes`
(LSCF + LSFD through ``sdypy-ema`` when the ``ema`` extra is installed, else single-pole fits);
their modal constants at the sensors (one input) are the measured mode shapes; the model's
shapes at the sensors are paired to them one to one by MAC and relative frequency distance
(see :func:`pair_modes`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .identification import MeasuredModes, fit_measured_modes, identify_modes

__all__ = ["Correlation", "correlate", "frac", "csac", "csf", "fit_measured_modes", "MeasuredModes",
           "pair_modes", "correlate_modes", "check_mode_sensors"]


def _pairs(model_frf, measured):
    """Model and measured H on the measured pairs, (n_pairs, n_freq), after checking they match."""
    if not np.allclose(model_frf.frequencies_hz, measured.frequencies_hz, rtol=1e-9, atol=1e-9):
        raise InputError("correlation: the model FRFs must be computed on the measured frequency lines")
    model_part = model_frf.select(measured.outputs, measured.inputs)
    a = model_part.H.reshape(-1, model_part.H.shape[-1])
    m = measured.H.reshape(-1, measured.H.shape[-1])
    keep = np.all(np.isfinite(m), axis=1)
    return a[keep], m[keep]


def frac(model_H, measured_H) -> np.ndarray:
    """FRAC of each FRF: arrays (..., n_freq) -> (...)."""
    cross = np.abs(np.sum(measured_H.conj() * model_H, axis=-1)) ** 2
    return cross / (np.sum(np.abs(measured_H) ** 2, axis=-1) * np.sum(np.abs(model_H) ** 2, axis=-1))


def csac(model_H, measured_H) -> np.ndarray:
    """CSAC at each frequency: arrays (n_pairs, n_freq) -> (n_freq,)."""
    return frac(model_H.T, measured_H.T)


def csf(model_H, measured_H) -> np.ndarray:
    """CSF at each frequency: arrays (n_pairs, n_freq) -> (n_freq,)."""
    cross = np.abs(np.sum(measured_H.conj() * model_H, axis=0))
    return 2 * cross / (np.sum(np.abs(measured_H) ** 2, axis=0) + np.sum(np.abs(model_H) ** 2, axis=0))


def pair_modes(model_modes, measured_modes, sensor_rows, excitation_index=None):
    """Pair measured and model modes one to one, by MAC at the sensors and by frequency.

    With few sensors MAC alone cannot tell modes apart (two channels give MAC near 1 for
    unrelated modes), so the assignment minimises ``sum (1 - MAC) + |f_model - f_meas| / f_meas``
    (``scipy.optimize.linear_sum_assignment``); the table reports the MAC of each pair.

    Parameters
    ----------
    model_modes : ModalResult
    measured_modes : MeasuredModes
    sensor_rows : ndarray, shape (n_outputs, n_dof)
        Rows of the measured outputs (``assembly.sensor_rows``).
    excitation_index : int, optional
        Input whose modal constants give the measured shapes (default: for each mode the input
        with the largest constants, the one that excites it best).

    Returns
    -------
    pandas.DataFrame
        ``measured_mode, measured_hz, measured_damping, model_mode, model_hz, model_damping,
        difference_pct, mac``.
    """
    import pandas as pd

    from .modal import mac

    osc = np.nonzero(model_modes.oscillatory)[0]
    model_shapes = model_modes.shapes[osc] @ sensor_rows.T            # (n_model, n_outputs)
    shapes = measured_modes.shapes                                     # (n_meas, n_outputs, n_inputs)
    columns = np.argmax(np.linalg.norm(shapes, axis=1), axis=1) if excitation_index is None \
        else np.full(len(shapes), excitation_index)
    measured_shapes = shapes[np.arange(len(shapes)), :, columns]      # (n_meas, n_outputs)
    rows = []
    if len(measured_shapes) and len(osc):
        from scipy.optimize import linear_sum_assignment

        with np.errstate(invalid="ignore"):
            macs = mac(measured_shapes, model_shapes)    # nan for a shape zero at every sensor (0/0)
        f_meas = measured_modes.frequencies_hz[:, None]
        distance = np.abs(model_modes.frequencies_hz[osc][None, :] - f_meas) / f_meas
        # a shape the sensors do not see agrees with none: paired by frequency, its MAC reported nan
        pairs = dict(zip(*linear_sum_assignment((1 - np.nan_to_num(macs, nan=0.0)) + distance)))
        for i, row in enumerate(macs):
            if i not in pairs:
                continue
            j = int(pairs[i])
            f_model = model_modes.frequencies_hz[osc[j]]
            rows.append({"measured_mode": i + 1, "measured_hz": measured_modes.frequencies_hz[i],
                         "measured_damping": measured_modes.damping_ratios[i], "model_mode": j + 1,
                         "model_hz": f_model, "model_damping": model_modes.damping_ratios[osc[j]],
                         "difference_pct": 100 * (f_model - measured_modes.frequencies_hz[i])
                         / measured_modes.frequencies_hz[i], "mac": row[j]})
    return pd.DataFrame(rows, columns=["measured_mode", "measured_hz", "measured_damping", "model_mode",
                                       "model_hz", "model_damping", "difference_pct", "mac"])


@dataclass(frozen=True)
class Correlation:
    """Agreement of model and measured FRFs at one speed.

    Attributes
    ----------
    speed : float [rad/s]
    frequencies_hz : ndarray, shape (n_freq,)
    pairs : tuple of (output, input)
    frac : ndarray, shape (n_pairs,)
    csac, csf : ndarray, shape (n_freq,)
    mode_pairs : dict[str, ndarray]
        Columns of the MAC-paired natural-frequency table (see :func:`pair_modes`);
        :attr:`modes` gives it as a DataFrame.
    identification : str
        How the measured modes were identified: 'lscf' or 'single-pole'.
    measured_modes : MeasuredModes or None
        The identified modes (with the stabilization chart of an LSCF identification).
    """

    speed: float
    frequencies_hz: np.ndarray
    pairs: tuple
    frac: np.ndarray
    csac: np.ndarray
    csf: np.ndarray
    mode_pairs: dict
    identification: str = "single-pole"
    measured_modes: MeasuredModes | None = None

    @property
    def modes(self):
        """The natural-frequency table: ``measured_mode, measured_hz, measured_damping,
        model_mode, model_hz, model_damping, difference_pct, mac`` (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame(self.mode_pairs)

    def to_dataframe(self):
        """FRAC per FRF: ``output,input,frac``."""
        import pandas as pd

        return pd.DataFrame({"output": [p[0] for p in self.pairs], "input": [p[1] for p in self.pairs],
                             "frac": self.frac})

    def plot(self):
        """CSAC and CSF against frequency; see :func:`rotordyn_modal.plotting.correlation.plot_correlation`."""
        from ..plotting.correlation import plot_correlation

        return plot_correlation(self)


def correlate(model, measured, identification: str = "auto") -> Correlation:
    """Correlate the model with one measured FRF set (its speed, quantity and frequency lines).

    Parameters
    ----------
    model : Model
    measured : FRFResult
        Measured FRFs named after the model's sensors and excitations.
    identification : {'auto', 'lscf', 'single-pole'} or MeasuredModes
        How the measured modes of the natural-frequency table are found (see
        :func:`~rotordyn_modal.analysis.identification.identify_modes`), or modes already identified.

    Returns
    -------
    Correlation
    """
    from ..assembly import sensor_rows
    from .frf import frf
    from .modal import modal

    model_frf = frf(model, measured.speed, measured.frequencies_hz, inputs=list(measured.inputs),
                    outputs=list(measured.outputs), quantity=measured.quantity)
    a, m = _pairs(model_frf, measured)
    pairs = tuple((o, i) for o in measured.outputs for i in measured.inputs
                  if np.all(np.isfinite(measured.H[measured.outputs.index(o), measured.inputs.index(i)])))
    identified = identification if isinstance(identification, MeasuredModes) \
        else identify_modes(measured, method=identification)
    modes = pair_modes(modal(model, measured.speed), identified, sensor_rows(model, list(measured.outputs)))
    return Correlation(speed=measured.speed, frequencies_hz=measured.frequencies_hz, pairs=pairs,
                       frac=frac(a, m), csac=csac(a, m), csf=csf(a, m),
                       mode_pairs={k: modes[k].to_numpy() for k in modes.columns},
                       identification=identified.method, measured_modes=identified)


def correlate_modes(model, measured, speed: float = 0.0, model_modes=None):
    """Measured mode shapes (e.g. a Universal File's dataset 55, as modal analysis programs
    export them: ``rdm.read_uff_modes``) against the model's modes at ``speed``, at the sensors:
    the MAC-paired natural-frequency table of :func:`pair_modes`.

    Parameters
    ----------
    model : Model
    measured : MeasuredModes
        Modes with their shapes at the sensors, e.g. of a Universal File's dataset 55
        (:func:`~rotordyn_modal.io.uff_modes.read_uff_modes`).
    speed : float [rad/s]
        Reference rotor speed of the model's modes (default 0: the machine at rest, as in a
        hammer test).
    model_modes : ModalResult, optional
        The model's modes at ``speed`` when already computed (default: computed here).

    Returns
    -------
    pandas.DataFrame
        ``measured_mode, measured_hz, measured_damping, model_mode, model_hz, model_damping,
        difference_pct, mac`` (``model_mode`` is the 'mode' column of ``modes``; the MAC over the
        sensors the file has, ``measured.outputs``).

    Raises
    ------
    InputError
        Fewer than two sensors in the file (one sensor's MAC is 1 for any pair of modes).
    """
    from ..assembly import sensor_rows
    from .modal import modal

    check_mode_sensors(measured)
    unseen = np.flatnonzero(~np.any(measured.shapes != 0, axis=(1, 2)))
    if unseen.size:
        import warnings

        warnings.warn(f"measured mode{'s' if unseen.size > 1 else ''} {', '.join(str(i + 1) for i in unseen)} "
                      f"{'are' if unseen.size > 1 else 'is'} zero at every sensor ({', '.join(measured.outputs)}): "
                      "paired by frequency only, MAC nan", stacklevel=2)
    model_modes = modal(model, speed) if model_modes is None else model_modes
    return pair_modes(model_modes, measured, sensor_rows(model, list(measured.outputs)), excitation_index=0)


def check_mode_sensors(measured):
    """``measured`` (MeasuredModes) when its shapes are at two sensors or more, else InputError:
    one sensor's MAC is 1 for any pair of modes."""
    if len(measured.outputs) < 2:
        raise InputError(f"measured mode shapes at {len(measured.outputs)} sensor ({', '.join(measured.outputs)}): a "
                         "MAC needs two or more (one sensor's MAC is 1 for any pair of modes)")
    return measured
