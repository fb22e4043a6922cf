"""Frequency response functions from excitations to sensors.

The machine's dynamic stiffness at circular frequency ``w`` [rad/s] and
reference speed ``Omega`` [rad/s] is::

    Z(w) = K (1 + i eta) + K_f(w) + i w (C + Omega G) - w^2 M

with ``K (1 + i eta)`` the hysteretic mounts (``loss_factor``) and ``K_f(w)``
the frequency-dependent mounts (Maxwell branches, see
:mod:`rotordyn_modal.elements.mounts`). The receptance from the excitations'
generalized forces ``B_f`` to the sensors' rows ``C_s`` is
``H(w) = C_s Z(w)^-1 B_f``; mobility and accelerance multiply it by ``i w``
and ``(i w)^2``.

Two engines behind :func:`frf`, chosen automatically:

* ``"modal"``: when every mount is viscous (no loss factor, no Maxwell
  branch), one eigen-decomposition ``A = V diag(lam) V^-1`` of the 12-state
  matrix gives ``H(w) = sum_k (C V)_k (V^-1 B)_k / (i w - lam_k)`` for all
  frequencies at once. Used only when ``V`` is well conditioned (LAPACK's 1-norm
  estimate below 1e8).
* ``"direct"``: a batched complex solve of ``Z(w) X = B_f`` at every
  frequency (one LAPACK call over the stack of 6x6 systems).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assembly import constant_matrices, dependent_bearing_matrices, excitation_columns, \
    loss_block, loss_stiffness, sensor_rows, sparse_bearing_matrices, sparse_constant_matrices, sparse_frame_block
from ..errors import InputError
from ..model._table import visible_names
from ..elements.mounts import has_frequency_dependence, maxwell_frame_stiffness, maxwell_stiffness
from .. import _arguments
from . import _batches, _eigensolve

__all__ = ["FRFResult", "frf", "frf_of_checked_model", "dynamic_stiffness", "dof_response", "choose_engine", "QUANTITIES"]

#: quantity -> power of (i w) applied to the receptance
QUANTITIES = {"receptance": 0, "mobility": 1, "accelerance": 2}
_OUTPUT_UNITS = {0: "m", 1: "m/s", 2: "m/s^2"}
#: condition number (1-norm estimate) of the eigenvector matrix above which the modal engine is not trusted
_MAX_CONDITION = 1e8
#: work memory of one part of a batched direct solve (Z, LAPACK's copy): a few parts fit in
#: the cache, and the Python cost of a part stays small beside its LU factorisations [bytes]
_SOLVE_PART_BYTES = 16 * 2**20
#: models of more coordinates (a long flexible rotor: its pencils are banded) take the direct
#: engine with a sparse LU per frequency (SuperLU, O(nnz) memory) instead of the modal
#: superposition (a dense eigen-decomposition of 2n states) and the dense solves (O(n^3) each);
#: their M, C, G, K are assembled sparse (``assembly.sparse_constant_matrices``), never n x n
SPARSE_FRF_DOF = 2500


@dataclass(frozen=True)
class FRFResult:
    """Frequency responses at one speed.

    Attributes
    ----------
    H : ndarray, shape (n_outputs, n_inputs, n_freq), complex
        Indexed by output, input, frequency (as python-control) [output unit / N or N m].
    frequencies_hz : ndarray, shape (n_freq,) [Hz]
    speed : float
        Reference rotor speed [rad/s].
    inputs, outputs : tuple of str
        Names of the excitations and of the outputs (sensors, or force components).
    quantity : str
        'receptance', 'mobility', 'accelerance' or 'force' (transmitted forces).
    engine : str
        'modal' or 'direct'.
    coherence : ndarray, shape like H, or None
        Measured coherence (None for a model).
    resonances_hz : ndarray, shape (P,), or None
        The damped natural frequencies [Hz] within the computed ones that no computed frequency
        resolves (:func:`unresolved_resonances`); None where unknown (the direct engine, measured
        or selected data).
    resonance_H : ndarray, shape (n_outputs, n_inputs, P), complex, or None
        The response at those frequencies.
    cut_hz : ndarray, shape (n_outputs, n_inputs, Q), or None
        Each FRF's maxima between computed frequencies that the line through them cuts
        (:func:`frf_cut_maxima`: the exact response near :attr:`resonances_hz`, the modal
        sum's or, for force FRFs, direct solves; two close modes sharing one peak give one
        maximum, at the peak; modes damped at round-off, of no finite peak, are left out)
        [Hz], NaN after a curve's last; None where not looked for (then :meth:`cut_peaks`
        reads :attr:`resonances_hz`).
    cut_H : ndarray, shape like ``cut_hz``, complex, or None
        The response at those maxima.
    """

    H: np.ndarray
    frequencies_hz: np.ndarray
    speed: float
    inputs: tuple
    outputs: tuple
    quantity: str = "receptance"
    engine: str = "direct"
    coherence: np.ndarray | None = None
    resonances_hz: np.ndarray | None = None
    resonance_H: np.ndarray | None = None
    cut_hz: np.ndarray | None = None
    cut_H: np.ndarray | None = None

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies [rad/s], shape (n_freq,)."""
        return 2 * np.pi * self.frequencies_hz

    def to_control(self):
        """``control.FrequencyResponseData`` with the same data, names and frequencies [rad/s]."""
        import control

        return control.FrequencyResponseData(self.H, self.omega, inputs=list(self.inputs),
                                             outputs=list(self.outputs))

    @classmethod
    def from_control(cls, data, speed: float = 0.0, quantity: str = "receptance") -> "FRFResult":
        """An :class:`FRFResult` from a ``control.FrequencyResponseData``."""
        values = data.frdata if hasattr(data, "frdata") else data.fresp
        H = np.asarray(values).reshape(data.noutputs, data.ninputs, -1)
        return cls(H=H, frequencies_hz=np.asarray(data.omega) / (2 * np.pi), speed=float(speed),
                   inputs=tuple(data.input_labels), outputs=tuple(data.output_labels),
                   quantity=quantity, engine="control")

    def select(self, outputs=None, inputs=None) -> "FRFResult":
        """The FRFs of some outputs and inputs (names), in the order given."""
        o = _positions(self.outputs, outputs, "output")
        i = _positions(self.inputs, inputs, "input")
        coh = None if self.coherence is None else self.coherence[np.ix_(o, i)]
        peaks = None if self.resonance_H is None else self.resonance_H[np.ix_(o, i)]
        cut_hz, cut_H = ((None, None) if self.cut_hz is None
                         else (self.cut_hz[np.ix_(o, i)], self.cut_H[np.ix_(o, i)]))
        return FRFResult(self.H[np.ix_(o, i)], self.frequencies_hz, self.speed,
                         tuple(self.inputs[k] for k in i), tuple(self.outputs[k] for k in o),
                         self.quantity, self.engine, coh, self.resonances_hz, peaks, cut_hz, cut_H)

    def cut_peaks(self, output: str, input: str):
        """The resonances of one FRF that the line drawn through the computed frequencies cuts:
        its maxima of :attr:`cut_hz` where known (the true maxima of ``|H|``), otherwise those
        of :attr:`resonances_hz` where the response is more than sqrt(2) (3 dB) times that at
        both computed frequencies around it (a straight line between them, on any axis whose
        scale is monotonic, lies below the larger of the two).

        Returns
        -------
        frequencies : ndarray, shape (K,) [Hz]; H : ndarray, shape (K,), complex
        """
        if self.cut_hz is not None:
            o, i = self.outputs.index(output), self.inputs.index(input)
            keep = np.isfinite(self.cut_hz[o, i])
            return self.cut_hz[o, i, keep], self.cut_H[o, i, keep]
        if self.resonances_hz is None or not len(self.resonances_hz):
            return np.zeros(0), np.zeros(0, complex)
        o, i = self.outputs.index(output), self.inputs.index(input)
        order = np.argsort(self.frequencies_hz)
        f, h = self.frequencies_hz[order], np.abs(self.H[o, i, order])
        where = np.clip(np.searchsorted(f, self.resonances_hz), 1, len(f) - 1)
        around = np.maximum(h[where - 1], h[where])
        cut = np.abs(self.resonance_H[o, i]) > np.sqrt(2.0) * around
        return self.resonances_hz[cut], self.resonance_H[o, i, cut]

    def to_dataframe(self):
        """Long table ``frequency_hz,output,input,real,imag,magnitude,phase_deg[,coherence]``."""
        import pandas as pd

        n_o, n_i, n_f = self.H.shape
        o, i, f = (a.ravel() for a in np.meshgrid(np.arange(n_o), np.arange(n_i), np.arange(n_f),
                                                  indexing="ij"))
        h = self.H[o, i, f]
        table = pd.DataFrame({
            "frequency_hz": self.frequencies_hz[f],
            "output": np.asarray(self.outputs, dtype=object)[o],
            "input": np.asarray(self.inputs, dtype=object)[i],
            "real": h.real, "imag": h.imag, "magnitude": np.abs(h),
            "phase_deg": np.degrees(np.angle(h)),
        })
        if self.coherence is not None:
            table["coherence"] = self.coherence[o, i, f]
        return table

    def plot(self, measured=None, **kwargs):
        """Bode figure (magnitude and phase); see :func:`rotordyn_modal.plotting.plot_frf`."""
        from ..plotting.frf import plot_frf

        return plot_frf(self, measured=measured, **kwargs)


def _positions(names, wanted, what):
    if wanted is None:
        return list(range(len(names)))
    wanted = [wanted] if isinstance(wanted, str) else list(wanted)
    missing = [w for w in wanted if w not in names]
    if missing:
        raise InputError(f"unknown {what} {', '.join(map(repr, missing))}: expected one of {visible_names(names)}")
    return [list(names).index(w) for w in wanted]


def _names(items, wanted):
    if wanted is None:
        return tuple(item.name for item in items)
    return (wanted,) if isinstance(wanted, str) else tuple(wanted)


def _check_frequencies(freqs_hz) -> np.ndarray:
    return _arguments.frequencies(freqs_hz)


def choose_engine(model) -> str:
    """'modal' when every mount is viscous, else 'direct' (loss factors, Maxwell branches)."""
    if any(s.loss_factor for s in model.suspensions) or has_frequency_dependence(model) \
            or model.dofs.n > SPARSE_FRF_DOF:
        return "direct"
    return "modal"


def dynamic_stiffness(model, speed: float, omega) -> np.ndarray:
    """``Z(w) = K(1 + i eta) + K_f(w) + i w (C + Omega G) - w^2 M`` for many frequencies.

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,)
        Reference rotor speed [rad/s] (one per frequency for unbalance sweeps).
    omega : array_like, shape (n_freq,)
        Circular frequencies [rad/s].

    Returns
    -------
    ndarray, shape (n_freq, n, n), complex [N/m, ...]
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    return _StiffnessTerms(model).at(np.broadcast_to(np.asarray(speed, dtype=float), w.shape), w)


def _broadcast(values, shape):
    """``values`` as floats of ``shape``: the array itself when it has that shape already (no
    ``numpy.broadcast_to``), else a broadcast view."""
    values = np.asarray(values, dtype=float)
    return values if values.shape == shape else np.broadcast_to(values, shape)


class _StiffnessTerms:
    """The parts of ``Z(w)`` that do not depend on frequency, assembled once (``sparse``: as
    ``scipy.sparse`` matrices, for :func:`_sparse_response`; :meth:`at` takes the dense ones)."""

    def __init__(self, model, sparse: bool = False):
        self.model = model
        lossy = any(s.loss_factor for s in model.suspensions)
        if sparse:
            self.matrices = sparse_constant_matrices(model)
            self.loss = sparse_frame_block(model, loss_block(model)) if lossy else 0.0
        else:
            self.matrices = constant_matrices(model)
            # without loss factors a zero: adding it keeps Z's numbers (signed zeros included) as the
            # zero matrix would, without assembling that matrix
            self.loss = loss_stiffness(model) if lossy else 0.0
        self.frequency_dependent = has_frequency_dependence(model)
        self.speed_dependent = model.speed_dependent

    def at(self, speeds, w) -> np.ndarray:
        """``Z`` at frequencies ``w`` (F,) and reference speeds ``speeds`` (F,), shape (F, n, n)."""
        M, C, G, K = self.matrices
        if self.speed_dependent:
            k_b, c_b = dependent_bearing_matrices(self.model, speeds)
            K, C = K + k_b, C + c_b
        speed = speeds[:, None, None]
        w3 = w[:, None, None]
        # built in place, real and imaginary parts apart (the same sums as the formula, without
        # its complex temporaries): re = K - w^2 M, im = eta K + w (C + Omega G)
        Z = np.empty((len(w),) + M.shape, dtype=complex)      # the shape of w3, M, K and C broadcast
        np.multiply(-(w3 ** 2), M, out=Z.real)
        Z.real += K
        np.multiply(speed, G, out=Z.imag)
        Z.imag += C
        Z.imag *= w3
        Z.imag += self.loss
        if self.frequency_dependent:
            Z += maxwell_stiffness(self.model, w)
        return Z


def dof_response(model, speed: float, omega, forces, terms=None) -> np.ndarray:
    """Complex amplitude of ``q`` under harmonic generalized forces (direct solve).

    The systems are built and solved in parts of a few MB (``_SOLVE_PART_BYTES``: bounded
    memory, and each part still in the cache while it is solved); each system is solved on
    its own, so the parts do not change the result. The dense solves run on one BLAS thread
    (:func:`._batches.one_blas_thread`, as every dense eigen-solution): on a machine whose cores
    are shared, OpenBLAS's own threads wait for a core and burn CPU at every speed (measured at
    load 11-15 on 2 cores: 16-48 times one thread's CPU at 246 coordinates, 35 times at 126; no
    difference at 86, where the numbers are bit for bit the same; at 126 and 246 they differ from
    the threaded solve's at round-off, 5e-16 of the largest amplitude).

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,) [rad/s]
    omega : array_like, shape (n_freq,) [rad/s]
    forces : array_like, shape (n_dof, k) or (n_freq, n_dof, k)
        Generalized forces [N, N m].
    terms : _StiffnessTerms, optional
        The model's constant matrices, assembled once by a caller that calls many times
        (:func:`stiffness_terms`; the unbalance peaks' refinement): the same numbers as
        assembling them here.

    Returns
    -------
    ndarray, shape (n_freq, n_dof, k), complex [m, rad]

    Raises
    ------
    ModelError
        A system found singular, of a model whose mass matrix rounding leaves singular (the
        check every analysis makes, made here only when a solve fails: it costs as much as a
        small model's solves).
    InputError
        A system found singular otherwise (an undamped resonance at round-off), naming the first
        such frequency and speed.
    """
    try:
        return _dof_response(model, speed, omega, forces, terms)
    except (np.linalg.LinAlgError, RuntimeError):     # RuntimeError: SuperLU's "exactly singular"
        from ..linear_system import speed_linear_form

        speed_linear_form(model)   # a mass matrix rounding leaves singular: refused, as every analysis does
        raise _singular(model, speed, omega) from None


def _singular(model, speed, omega) -> InputError:
    """The refusal of a dynamic stiffness singular in double precision (a mass matrix the
    analyses take): the first such frequency and speed named, found one system at a time."""
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    speeds = _broadcast(speed, w.shape)
    at = ""
    for s, f in zip(speeds, w):
        try:
            _dof_response(model, s, f, np.zeros((model.dofs.n, 1)))
        except (np.linalg.LinAlgError, RuntimeError):
            at = f" at {f / (2 * np.pi):.6g} Hz, reference speed {s * 30 / np.pi:.6g} rpm"
            break
    if at and f == 0:
        free = _free_motion(model, s)
        if free:
            return InputError(f"{model.source}: the dynamic stiffness K - w^2 M + i w (C + Omega G) is singular in "
                              f"double precision{at}: at 0 Hz it is the stiffness alone, and the model is free to "
                              f"move along {free} (a rigid-body motion that no suspension or bearing holds: 'check' "
                              "counts the directions held); start the frequencies above 0 Hz, or give that motion "
                              "a stiffness")
    return InputError(f"{model.source}: the dynamic stiffness K - w^2 M + i w (C + Omega G) is singular in "
                      f"double precision{at}: an undamped resonance there, or stiffnesses and masses many "
                      "orders of magnitude apart (the model's warnings say where); add damping or move the "
                      "frequencies")


#: the most coordinates whose free motion :func:`_free_motion` names (one dense SVD of the stiffness)
_FREE_MOTION_LARGEST = 2000


def _free_motion(model, speed) -> str:
    """The coordinates a singular stiffness ``K(speed)`` leaves free, as ``'stator.ux'`` or
    ``'stator.ux and stator.ry'``: those of at least half the largest entry of its null vector (the
    right singular vector of its smallest singular value), at most three; ``''`` where the model
    has more than :data:`_FREE_MOTION_LARGEST` coordinates or the SVD fails."""
    names = list(model.dofs.names)
    if len(names) > _FREE_MOTION_LARGEST:
        return ""
    try:
        stiffness = np.asarray(model.matrices(speed)[3], dtype=float)
        null = np.linalg.svd(stiffness)[2][-1]
    except (np.linalg.LinAlgError, ValueError):
        return ""
    size = np.abs(null)
    order = [int(i) for i in np.argsort(-size, kind="stable") if size[i] >= 0.5 * size.max()][:3]
    return " and ".join(names[i] for i in order)


def stiffness_terms(model) -> "_StiffnessTerms":
    """The parts of ``Z(w)`` that do not depend on frequency, as :func:`dof_response` assembles
    them for ``model`` (sparse above ``SPARSE_FRF_DOF`` coordinates): made once by a caller that
    calls :func:`dof_response` many times on one model (its ``terms``)."""
    return _StiffnessTerms(model, sparse=model.dofs.n > SPARSE_FRF_DOF)


def _dof_response(model, speed, omega, forces, terms=None) -> np.ndarray:
    """:func:`dof_response` without the mass matrix's check."""
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    speeds = _broadcast(speed, w.shape)
    n = model.dofs.n
    terms = stiffness_terms(model) if terms is None else terms
    rhs = np.asarray(forces, dtype=complex)
    if rhs.shape != (len(w),) + rhs.shape[-2:]:
        rhs = np.broadcast_to(rhs, (len(w),) + rhs.shape[-2:])
    if n > SPARSE_FRF_DOF:
        return _sparse_response(terms, speeds, w, rhs)
    # per system: Z, LAPACK's copy and the temporaries of its right-hand side
    parts = _batches.chunk_slices(len(w), 48 * n * n, budget=_SOLVE_PART_BYTES)
    with _batches.one_blas_thread(72 * n * n):          # as the dense eigen-solutions
        if len(parts) == 1:
            # the solution made after Z: Z's memory, freed below it, serves the caller's next arrays
            # (as the top of the heap it would be handed back to the system and faulted in again)
            return np.linalg.solve(terms.at(speeds, w), rhs)
        out = np.empty(rhs.shape, dtype=complex)
        for part in parts:
            out[part] = np.linalg.solve(terms.at(speeds[part], w[part]), rhs[part])
        return out


def _sparse_response(terms, speeds, w, rhs) -> np.ndarray:
    """:func:`dof_response` of a large model: ``Z(w_f)`` summed from the sparse constant matrices
    (``terms.matrices``, ``scipy.sparse``; a speed-dependent bearing's block and the Maxwell
    branches' casing block added at their speed and frequency) and solved by a sparse LU each
    (SuperLU), one frequency at a time, every right-hand side of that frequency in one solve:
    memory ``O(nnz)`` per frequency and the response itself (F, n, k), no ``n x n`` array.

    Returns
    -------
    ndarray, shape (n_freq, n_dof, k), complex [m, rad]
    """
    import scipy.sparse
    import scipy.sparse.linalg

    M, C, G, K = terms.matrices
    loss = terms.loss if scipy.sparse.issparse(terms.loss) else None
    out = np.empty(rhs.shape, dtype=complex)
    for f, (speed, omega) in enumerate(zip(speeds, w)):
        stiffness, damping = K, C
        if terms.speed_dependent:
            k_b, c_b = sparse_bearing_matrices(terms.model, speed, dependent_only=True)
            stiffness, damping = K + k_b, C + c_b
        Z = (stiffness - omega ** 2 * M) + 1j * (omega * (damping + speed * G))
        if loss is not None:
            Z = Z + 1j * loss
        if terms.frequency_dependent:
            Z = Z + sparse_frame_block(terms.model, maxwell_frame_stiffness(terms.model, [omega])[0])
        out[f] = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(Z)).solve(np.ascontiguousarray(rhs[f]))
    return out


def frf(model, speed: float, freqs_hz, inputs=None, outputs=None, quantity: str = "receptance",
        engine: str = "auto") -> FRFResult:
    """Frequency responses from excitations to sensors at one speed.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s]; negative reverses every rotor's spin.
    freqs_hz : array_like, shape (n_freq,)
        Frequencies [Hz], >= 0.
    inputs, outputs : str or list of str, optional
        Excitation and sensor names (default: all, in model order).
    quantity : {'receptance', 'mobility', 'accelerance'}
        Displacement [m/N], velocity [m/s/N] or acceleration [m/s^2/N] per force.
    engine : {'auto', 'modal', 'direct'}
        'auto' takes 'modal' for viscous models and 'direct' otherwise; 'modal'
        on a model with loss factors or Maxwell branches is refused. Every engine refuses a
        model whose mass matrix rounding leaves singular (a ``ModelError``, the line of every
        analysis), before any solve: the direct solves of such a model can succeed and give
        numbers of no meaning (a stator of 1e-30 kg under a rotor of 10 kg).

    Returns
    -------
    FRFResult
        ``H`` of shape (n_outputs, n_inputs, n_freq).

    Examples
    --------
    >>> import numpy as np, rotordyn_modal as rdm
    >>> m = rdm.Model(stator=rdm.Stator(mass=2.0, inertia=[1, 1, 1]),
    ...     suspensions=[rdm.Suspension("s", [0, 0, 0], [800.0] * 6)],
    ...     sensors=[rdm.Sensor("z", [0, 0, 0], [0, 0, 1])],
    ...     excitations=[rdm.Excitation("f", [0, 0, 0], [0, 0, 1])])
    >>> res = rdm.frf(m, 0.0, [0.0])
    >>> round(float(res.H[0, 0, 0].real), 12)   # static compliance 1/k
    0.00125
    """
    return _frf(model, speed, freqs_hz, inputs, outputs, quantity, engine)


def frf_of_checked_model(model, speed: float, freqs_hz, inputs=None, outputs=None,
                         quantity: str = "receptance") -> FRFResult:
    """:func:`frf` by the direct engine, without the mass matrix's check, for a caller that made
    it once on a model whose masses its variants keep (``fit``: at each evaluation the check
    would cost as much as a small model's solves). Arguments and result as :func:`frf`'s."""
    return _frf(model, speed, freqs_hz, inputs, outputs, quantity, "direct", mass_checked=True)


def _frf(model, speed, freqs_hz, inputs, outputs, quantity, engine, mass_checked=False) -> FRFResult:
    """:func:`frf`; ``mass_checked``: the caller has refused a singular mass matrix already."""
    if quantity not in QUANTITIES:
        raise InputError(f"quantity {quantity!r}: expected one of {', '.join(QUANTITIES)}")
    if engine not in ("auto", "modal", "direct"):
        raise InputError(f"engine {engine!r}: expected 'auto', 'modal' or 'direct'")
    speed = _arguments.speed(speed)
    f = _check_frequencies(freqs_hz)
    columns = excitation_columns(model, inputs)
    rows = sensor_rows(model, outputs)
    _check_channels(model, rows, columns)
    natural = choose_engine(model)
    if engine == "modal" and natural != "modal":
        raise InputError("engine 'modal' needs a viscous model: this one has loss factors or Maxwell branches")
    used = natural if engine == "auto" else engine
    omega = 2 * np.pi * f
    terms = _modal_terms(model, speed, rows, columns) if used == "modal" else None
    H = None if terms is None else _modal_sum(terms, omega)
    if H is None:
        if not mass_checked:   # the modal engine's state form made the check, if it was tried
            from ..linear_system import speed_linear_form

            speed_linear_form(model)   # a mass matrix rounding leaves singular: refused, as every analysis does
        used = "direct"
        H = np.einsum("sd,fdi->sif", rows, dof_response(model, speed, omega, columns))
    H = H * (1j * omega) ** QUANTITIES[quantity]
    peaks = peak_H = cut_hz = cut_H = None
    if terms is not None:              # the resonances no computed frequency resolves, at their own frequency
        peaks, band = unresolved_resonances(terms[0], f)
        peak_H = _modal_sum(terms, 2 * np.pi * peaks) * (2j * np.pi * peaks) ** QUANTITIES[quantity]
        cut_hz, cut_H = _cut_maxima(terms, f, H, peaks, band, QUANTITIES[quantity])
    return FRFResult(H=H, frequencies_hz=f, speed=float(speed), inputs=_names(model.excitations, inputs),
                     outputs=_names(model.sensors, outputs), quantity=quantity, engine=used,
                     resonances_hz=peaks, resonance_H=peak_H, cut_hz=cut_hz, cut_H=cut_H)


def _cut_maxima(terms, f, H, resonances, band, power):
    """The maxima of each FRF between computed frequencies that its line cuts, by
    :func:`~rotordyn_modal.analysis.unbalance_peaks.cut_maxima` on the exact modal sum, each
    candidate on its own FRF (:func:`_modal_curve`). Roots damped at round-off (less than
    ``unbalance_peaks._LEAST_DAMPING``, no finite peak) are not looked at.

    Parameters
    ----------
    terms : tuple
        :func:`_modal_terms`' result.
    f : ndarray, shape (n_freq,) [Hz]
    H : ndarray, shape (n_outputs, n_inputs, n_freq), complex
        The FRFs at ``f`` (the quantity's factor applied).
    resonances, band : ndarray, shape (P,) [Hz]
        :func:`unresolved_resonances`' damped natural frequencies and half-power bandwidths.
    power : int
        The quantity's power of ``i w`` (0 receptance, 1 mobility, 2 accelerance).

    Returns
    -------
    cut_hz : ndarray, shape (n_outputs, n_inputs, Q) [Hz]; cut_H : same shape, complex
    """
    def curve(s, o, i):
        return _modal_curve(terms, 2 * np.pi * np.asarray(s, dtype=float), o, i) * (2j * np.pi * s) ** power

    return frf_cut_maxima(curve, f, H, resonances, band)


def frf_cut_maxima(curve, f, H, resonances, band):
    """:func:`~rotordyn_modal.analysis.unbalance_peaks.cut_maxima` of FRFs ``H`` (n_outputs,
    n_inputs, n_freq) computed at ``f`` [Hz], near the damped natural frequencies
    ``resonances`` (P,) [Hz] of half-power bandwidths ``band`` (P,) [Hz] (those damped at
    round-off left out), each candidate on its own FRF: ``curve(s, o, i)``, each shape (K,) ->
    (K,), complex, is FRF ``(o[k], i[k])`` at ``s[k]`` [Hz] alone.

    Returns
    -------
    cut_hz : ndarray, shape (n_outputs, n_inputs, Q) [Hz]; cut_H : same shape, complex
        NaN after an FRF's last.
    """
    from .unbalance_peaks import _LEAST_DAMPING, cut_maxima

    resonances, band = np.asarray(resonances, dtype=float), np.asarray(band, dtype=float)
    damped = np.pi * band > _LEAST_DAMPING * np.hypot(np.pi * band, 2 * np.pi * resonances)
    found = [(resonances[damped], band[damped])] * H.shape[1]
    at, value, _ = cut_maxima(curve, f, np.abs(H), found, half_power=False)
    return at, value


def _modal_curve(terms, omega, o, i):
    """The receptance of output ``o[k]`` to input ``i[k]`` at ``omega[k]`` [rad/s] alone, shape
    (K,), complex: :func:`_modal_sum`'s entries, each of its own FRF (``terms``:
    :func:`_modal_terms`)."""
    values, left, right = terms
    omega, o, i = np.asarray(omega, dtype=float), np.asarray(o, dtype=int), np.asarray(i, dtype=int)
    out = np.empty(omega.shape, dtype=complex)
    step = max(1, _CURVE_ENTRIES // max(values.size, 1))          # (step, 2n) at a time: memory bounded
    for start in range(0, omega.size, step):
        part = slice(start, start + step)
        poles = 1.0 / (1j * omega[part, None] - values[None, :])                # (step, 2n)
        out[part] = np.sum(left[o[part]] * right[:, i[part]].T * poles, axis=1)
    return out


#: :func:`_modal_curve` forms at most this many (frequency, root) terms at a time (16 bytes each)
_CURVE_ENTRIES = 1 << 20


def _check_channels(model, rows, columns):
    for table, count in (("sensors", len(rows)), ("excitations", columns.shape[1])):
        if count == 0:
            raise InputError(f"{model.source}: the model has no [[{table}]]: an FRF needs at least one "
                             "sensor and one excitation (see docs/model-file.md)")


def unresolved_resonances(eigenvalues, frequencies_hz) -> tuple[np.ndarray, np.ndarray]:
    """The damped natural frequencies [Hz] of the roots ``eigenvalues`` (all of a state matrix,
    [1/s]) that lie within the computed ``frequencies_hz`` but have no computed frequency within
    a quarter of their half-power bandwidth ``|Re lam| / pi`` [Hz]: there a single mode's
    response falls to about 0.9 of its peak (``1 / sqrt(1 + (2 d / B)^2)`` at a distance ``d``),
    and farther the line drawn between the computed frequencies may cut the resonance's peak.

    Returns
    -------
    resonances : ndarray, shape (P,) [Hz], increasing
    bandwidths : ndarray, shape (P,) [Hz]
        Their half-power bandwidths ``|Re lam| / pi``.
    """
    f = np.sort(np.asarray(frequencies_hz, dtype=float))
    lam = np.asarray(eigenvalues, dtype=complex)
    lam = lam[(lam.imag > 0) & (lam.real < 0)]
    fd, bandwidth = lam.imag / (2 * np.pi), -lam.real / np.pi
    inside = (fd > f[0]) & (fd < f[-1]) if f.size > 1 else np.zeros(fd.shape, bool)
    fd, bandwidth = fd[inside], bandwidth[inside]
    where = np.clip(np.searchsorted(f, fd), 1, max(f.size - 1, 1))
    nearest = np.minimum(np.abs(f[where] - fd), np.abs(fd - f[where - 1])) if f.size > 1 else np.zeros(0)
    keep = 4 * nearest > bandwidth
    order = np.argsort(fd[keep])
    return fd[keep][order], bandwidth[keep][order]


def _modal_sum(terms, omega):
    """The receptance (n_s, n_e, n_f) of modal ``terms`` (:func:`_modal_terms`) at ``omega`` [rad/s]."""
    values, left, right = terms
    poles = 1.0 / (1j * omega[None, :] - values[:, None])   # (2n, n_f)
    return np.einsum("sk,ki,kf->sif", left, right, poles)


def _modal_terms(model, speed, rows, columns):
    """``(eigenvalues, left, right)`` of the modal superposition of the receptance from
    ``columns`` to ``rows``: ``H = sum_k left[:, k] right[k] / (i w - lam_k)``; None when the
    eigenvectors are ill conditioned."""
    import scipy.linalg

    from .._blas import one_blas_thread
    from ..linear_system import speed_linear_form

    form = speed_linear_form(model)
    n = form.n_dof
    matrix = form.at(float(speed))
    # one BLAS thread, as modal's eigen-solution and its CPU estimate (rotordyn_modal/_blas.py):
    # with OpenBLAS's threads, frf on 500 geared rotors (4,012 states) took 118 s of CPU, modes 45 s
    with one_blas_thread(72 * matrix.shape[-1] ** 2):
        values, vectors = _eigensolve.eig(matrix)      # scipy.linalg.eig's, the GIL released (a clock ticks)
        # the LU that solves for V^-1 B also estimates V's condition (LAPACK gecon, 1-norm):
        # O(n^2) where the 2-norm's SVD would cost about half the eigen-decomposition again
        factors = scipy.linalg.lu_factor(vectors, check_finite=False)
    gecon = scipy.linalg.get_lapack_funcs("gecon", (factors[0],))
    rcond, _ = gecon(factors[0], np.linalg.norm(vectors, 1), norm="1")
    if not rcond * _MAX_CONDITION >= 1.0:
        return None
    b = np.zeros((form.n_states, columns.shape[1]))
    b[n:2 * n] = form.mass_inverse @ columns
    left = rows @ vectors[:n]                      # (n_s, 2n)
    right = scipy.linalg.lu_solve(factors, b, check_finite=False)   # V^-1 B, (2n, n_e)
    return values, left, right
