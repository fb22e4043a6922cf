"""Correlation measures against their definitions, measured modes, and the experimental transformation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rotordyn_modal as rdm
from rotordyn_modal.analysis.correlation import correlate, csac, csf, fit_measured_modes, frac
from rotordyn_modal.analysis.experimental import shift_motion, stator_motion, transformation_matrix
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.errors import InputError

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


@settings(max_examples=25, deadline=None)
@given(scale=st.floats(0.1, 10.0), angle=st.floats(-3.0, 3.0))
def test_scale_and_phase(scale, angle):
    """A measured set c H of the model H: FRAC = CSAC = 1, CSF = 2|c| / (1 + |c|^2)."""
    rng = np.random.default_rng(1)
    H = rng.normal(size=(4, 50)) + 1j * rng.normal(size=(4, 50))
    c = scale * np.exp(1j * angle)
    np.testing.assert_allclose(frac(H, c * H), 1.0, rtol=1e-12)
    np.testing.assert_allclose(csac(H, c * H), 1.0, rtol=1e-12)
    np.testing.assert_allclose(csf(H, c * H), 2 * scale / (1 + scale ** 2), rtol=1e-12)


def test_orthogonal_frfs_give_zero():
    H = np.array([[1.0, 1.0j, -1.0, -1.0j]])
    assert frac(H, H.conj())[0] == pytest.approx(0.0, abs=1e-15)


def test_single_oscillator_modes_recovered():
    """One mode, exactly: receptance of m, c, k; the pole is -zeta wn + i wn sqrt(1 - zeta^2)."""
    m, k, zeta = 2.0, 8.0e4, 0.03
    wn = np.sqrt(k / m)
    f = np.linspace(10, 50, 801)
    w = 2 * np.pi * f
    H = (1 / (k - m * w ** 2 + 2j * zeta * wn * m * w))[None, None]
    modes = fit_measured_modes(FRFResult(H=H, frequencies_hz=f, speed=0.0, inputs=("f",), outputs=("z",)))
    assert len(modes.poles) == 1
    # one pole with a constant residual over +-8 % of the peak: the conjugate pole's tail is the error
    assert modes.frequencies_hz[0] == pytest.approx(wn * np.sqrt(1 - zeta ** 2) / (2 * np.pi), rel=1e-3)
    assert modes.damping_ratios[0] == pytest.approx(zeta, rel=3e-2)


def test_model_against_itself():
    model = rdm.load_model(EXAMPLE)
    measured = rdm.frf(model, rdm.rpm(3000), np.linspace(1, 40, 800))
    result = correlate(model, measured)
    np.testing.assert_allclose(result.frac, 1.0, rtol=1e-12)
    np.testing.assert_allclose(result.csac, 1.0, rtol=1e-10)
    assert np.all(result.modes.mac > 0.95)
    assert np.all(np.abs(result.modes.difference_pct) < 1.0)
    assert list(result.to_dataframe().columns) == ["output", "input", "frac"]
    ax = result.plot().axes[0]
    csac, csf = ax.get_lines()[:2]
    np.testing.assert_array_equal(csac.get_xdata(), result.frequencies_hz)
    np.testing.assert_array_equal(csac.get_ydata(), result.csac)
    np.testing.assert_array_equal(csf.get_ydata(), result.csf)
    legend = [text.get_text() for text in ax.get_legend().get_texts()]
    assert legend[:2] == ["CSAC (shape)", "CSF (shape and amplitude)"]
    assert legend[2:] == [f"FRAC {o} / {i}: {v:.3f}" for (o, i), v in zip(result.pairs, result.frac)]
    assert ax.get_title() == "Model versus measurement at 3000 rpm"


def test_correlation_needs_the_measured_lines():
    from rotordyn_modal.analysis.correlation import _pairs

    model = rdm.load_model(EXAMPLE)
    a = rdm.frf(model, 0.0, np.linspace(1, 40, 10))
    b = rdm.frf(model, 0.0, np.linspace(1, 41, 10))
    with pytest.raises(InputError, match="computed on the measured frequency lines"):
        _pairs(a, b)


def _channels_model(points_dirs):
    data = rdm.load_model(EXAMPLE).to_dict()
    data["sensors"] = [{"name": f"c{k}", "position": p, "direction": d} for k, (p, d) in enumerate(points_dirs)]
    return rdm.Model.from_dict(data)


CHANNELS = [(p, d) for p in ([0.5, 0.3, 0.2], [-0.5, 0.3, 0.2], [0.0, -0.3, -0.2])
            for d in ([1, 0, 0], [0, 1, 0], [0, 0, 1])]     # three triaxial accelerometers


def test_rigid_motion_recovered_from_channels():
    """Readings made from a known motion (u + theta x r at each channel) give it back."""
    model = _channels_model(CHANNELS)
    rng = np.random.default_rng(3)
    q = rng.normal(size=(6, 40))
    S = model.reference_point
    readings = np.array([[np.dot(d, q[:3, t] + np.cross(q[3:, t], np.subtract(p, S))) for t in range(40)]
                         for p, d in CHANNELS])
    result = stator_motion(model, readings)
    np.testing.assert_allclose(result.q, q, atol=1e-12)
    np.testing.assert_allclose(result.residual, 0, atol=1e-12)
    assert result.condition < 1e3
    # expressed at another point: u_P = u + theta x (P - S)
    P = np.array([1.0, 2.0, 3.0])
    at_p = stator_motion(model, readings, point=P)
    np.testing.assert_allclose(at_p.q[:3], q[:3] + np.cross(q[3:].T, P - S).T, atol=1e-12)
    # the rigid-body motion moved between points by shift_motion follows the same kinematics
    np.testing.assert_allclose(shift_motion(result.q, S, P), at_p.q, atol=1e-12)
    # the condition reported is the transformation matrix's (largest / smallest singular value)
    T = transformation_matrix(*zip(*CHANNELS), S)
    assert result.condition == pytest.approx(np.linalg.cond(T), rel=1e-12)
    table = result.to_dataframe()
    assert list(table.columns) == ["u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z"]
    np.testing.assert_allclose(table.to_numpy().T, q, atol=1e-12)
    # the figure: translations on top, rotations below, each against the abscissa given
    times = np.arange(40) * 0.01
    top, bottom = result.plot(times).axes
    for axes, rows, names in ((top, q[:3], ("u_x", "u_y", "u_z")), (bottom, q[3:], ("θ_x", "θ_y", "θ_z"))):
        assert [line.get_label() for line in axes.get_lines()] == list(names)
        for line, row in zip(axes.get_lines(), rows):
            np.testing.assert_array_equal(line.get_xdata(), times)
            np.testing.assert_allclose(line.get_ydata(), row, atol=1e-12)


def test_too_few_and_degenerate_channels_refused():
    model = _channels_model(CHANNELS[:5])
    with pytest.raises(InputError, match="5 channel\\(s\\) .* cannot determine the stator's six rigid-body motions"):
        stator_motion(model, np.zeros((5, 3)))
    parallel = [([x, 0.1 * x, 0.0], [1, 0, 0]) for x in range(6)]   # rows [1, 0, 0, 0, 0, -y]: rank 2
    model = _channels_model(parallel)
    with pytest.raises(InputError, match="do not determine all six rigid-body motions \\(rank 2 of 6\\)"):
        stator_motion(model, np.zeros((6, 3)))
    with pytest.raises(InputError, match="readings: 2 rows for 6 sensors"):
        stator_motion(model, np.zeros((2, 3)))


def test_transformation_matrix_rows_are_shift_matrix_projections():
    S = np.array([0.1, -0.2, 0.3])
    T = transformation_matrix([[1.0, 2.0, 3.0]], [[0.0, 0.0, 2.0]], S)
    B = rdm.shift_matrix(S, [1.0, 2.0, 3.0])          # q_P = B_SP^T q_S
    np.testing.assert_allclose(T[0], B[:, 2])


def test_modes_are_paired_as_their_full_shapes_pair_them_even_where_two_sensors_cannot_tell():
    """Measured: the gear machine with one mount 5 % stiffer. With its two sensors, the MAC of
    unrelated modes reaches that of the right ones (1 - MAC alone pairs them wrongly), so the
    pairing weighs the frequency too; it must pair each measured mode with the model mode
    whose shape over all coordinates (unseen by the sensors) is its own: MAC above 0.99 there,
    below 0.6 for every other pair."""
    from rotordyn_modal.analysis.modal import mac

    model = rdm.load_model(EXAMPLE)
    speed = rdm.rpm(3000)
    stiffer = model.scaled({"suspensions.mount-FL.stiffness": 1.05})
    full = mac(*(m.shapes[m.oscillatory] for m in (rdm.modal(stiffer, speed), rdm.modal(model, speed))))
    truth = full.argmax(axis=1)
    assert (np.sort(full, axis=1)[:, -1] > 0.99).all() and (np.sort(full, axis=1)[:, -2] < 0.6).all()
    pairs = correlate(model, rdm.frf(stiffer, speed, np.linspace(1, 40, 800))).modes
    assert (pairs.model_mode.to_numpy() - 1).tolist() == truth[pairs.measured_mode.to_numpy() - 1].tolist()
