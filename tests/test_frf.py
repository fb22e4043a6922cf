"""FRFs against closed forms, python-control, an independent solve, reciprocity and spin reversal."""

from __future__ import annotations

import warnings
from pathlib import Path

import control
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rotordyn_modal as rdm
from reference_bearings import random_bearing_description, with_mount_channels
from rotordyn_modal.analysis.forces import force_frf
from rotordyn_modal.analysis.frf import dof_response, dynamic_stiffness, frf
from rotordyn_modal.errors import InputError

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


def _block(k=8.0e4, c=40.0, eta=0.0, maxwell=None):
    """A 2 kg block on one isotropic mount at its centre of mass: six uncoupled oscillators."""
    extra = {} if maxwell is None else {"maxwell_stiffness": [[maxwell[0]] * 6], "maxwell_time": [maxwell[1]]}
    return rdm.Model.from_dict({
        "stator": {"mass": 2.0, "inertia": [0.1, 0.1, 0.1]},
        "suspensions": [{"name": "s", "position": [0, 0, 0], "stiffness": [k] * 6,
                         "damping": [c] * 6, "loss_factor": eta, **extra}],
        "sensors": [{"name": "z", "position": [0, 0, 0], "direction": [0, 0, 1]}],
        "excitations": [{"name": "f", "position": [0, 0, 0], "direction": [0, 0, 1]}],
    })


def _colocated(loss_factor=0.0):
    """The gear machine with sensors placed where (and along what) the excitations act."""
    data = rdm.load_model(EXAMPLE).to_dict()
    data["sensors"] = [{"name": f"at-{x['name']}", "position": x["position"], "direction": x["direction"]}
                       for x in data["excitations"]]
    for s in data["suspensions"]:
        s["loss_factor"] = loss_factor
    return rdm.Model.from_dict(data)


FREQS = np.linspace(0.0, 60.0, 241)


@pytest.mark.parametrize("engine", ["modal", "direct"])
def test_single_oscillator_closed_form(engine):
    w = 2 * np.pi * FREQS
    expected = 1 / (8.0e4 - 2.0 * w ** 2 + 1j * w * 40.0)
    res = frf(_block(), 0.0, FREQS, engine=engine)
    np.testing.assert_allclose(res.H[0, 0], expected, rtol=1e-10)
    assert res.engine == engine
    acc = frf(_block(), 0.0, FREQS, quantity="accelerance", engine=engine)
    np.testing.assert_allclose(acc.H[0, 0], -w ** 2 * expected, rtol=1e-10, atol=1e-14)


def test_loss_factor_closed_form_uses_direct_engine():
    w = 2 * np.pi * FREQS
    res = frf(_block(c=0.0, eta=0.08), 0.0, FREQS)
    assert res.engine == "direct"
    np.testing.assert_allclose(res.H[0, 0], 1 / (8.0e4 * (1 + 0.08j) - 2.0 * w ** 2), rtol=1e-12)


def test_maxwell_branch_closed_form():
    w = 2 * np.pi * FREQS
    res = frf(_block(c=0.0, maxwell=(3.0e4, 0.004)), 0.0, FREQS)
    branch = 3.0e4 * 1j * w * 0.004 / (1 + 1j * w * 0.004)
    np.testing.assert_allclose(res.H[0, 0], 1 / (8.0e4 + branch - 2.0 * w ** 2), rtol=1e-12)
    assert res.engine == "direct"


@pytest.mark.parametrize("quantity,ss_quantity", [("receptance", "displacement"), ("mobility", "velocity"),
                                                  ("accelerance", "acceleration")])
@pytest.mark.parametrize("speed_rpm", [0.0, 3000.0, -4500.0])
def test_agrees_with_python_control_state_space(quantity, ss_quantity, speed_rpm):
    model = rdm.load_model(EXAMPLE)
    speed = rdm.rpm(speed_rpm)
    res = frf(model, speed, FREQS, quantity=quantity)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        reference = control.frequency_response(model.state_space(speed, ss_quantity), 2 * np.pi * FREQS)
        H = np.asarray(reference.frdata if hasattr(reference, "frdata") else reference.fresp)
    # relative to each FRF's peak; one FRF is zero by symmetry at zero speed, so against the largest
    peak = np.abs(H).max(axis=-1, keepdims=True)
    scale = np.where(peak > 1e-6 * peak.max(), peak, peak.max())
    assert (np.abs(res.H - H) / scale).max() < 1e-9


def test_direct_engine_equals_independent_loop_solve_with_loss_factor():
    """One np.linalg.solve per frequency from M, C, G, K and (1 + i eta) K written out here."""
    model = _colocated(loss_factor=0.05)
    speed = rdm.rpm(2000)
    M, C, G, K = model.matrices()
    loss = sum(0.05 * (rdm.shift_matrix(model.reference_point, s.position) @ s.stiffness_matrix
                       @ rdm.shift_matrix(model.reference_point, s.position).T) for s in model.suspensions)
    rows = np.array([np.concatenate([s.direction, np.cross(s.position - model.reference_point, s.direction)])
                     for s in model.sensors])
    cols = rows.T  # sensors are colocated with the excitations
    res = frf(model, speed, FREQS)
    for k, f in enumerate(FREQS):
        w = 2 * np.pi * f
        Z = K + 1j * loss + 1j * w * (C + speed * G) - w ** 2 * M
        np.testing.assert_allclose(res.H[:, :, k], rows @ np.linalg.solve(Z, cols), rtol=1e-10)


def test_direct_solve_in_parts_gives_the_solve_of_all_at_once(monkeypatch):
    """The harmonic systems are solved in parts of bounded memory (a part of 2 frequencies here):
    each system on its own, so the parts change no bit of the response."""
    from rotordyn_modal.analysis import frf as frf_module

    model = _colocated(loss_factor=0.05)
    forces = np.eye(model.dofs.n)[:, :3]
    whole = dof_response(model, rdm.rpm(2000), 2 * np.pi * FREQS, forces)
    n = model.dofs.n
    monkeypatch.setattr(frf_module, "_SOLVE_PART_BYTES", 2 * 48 * n * n)
    assert len(frf_module._batches.chunk_slices(len(FREQS), 48 * n * n, budget=2 * 48 * n * n)) > 1
    np.testing.assert_array_equal(dof_response(model, rdm.rpm(2000), 2 * np.pi * FREQS, forces), whole)


@pytest.mark.parametrize("eta", [0.0, 0.05])
def test_reciprocal_at_zero_speed(eta):
    H = frf(_colocated(eta), 0.0, FREQS).H
    np.testing.assert_allclose(H, np.swapaxes(H, 0, 1), rtol=1e-10, atol=1e-16)
    assert np.abs(H[0, 1] - H[1, 0]).max() < 1e-10 * np.abs(H[0, 1]).max()


@settings(max_examples=15, deadline=None)
@given(speed=st.floats(min_value=10.0, max_value=2000.0), eta=st.sampled_from([0.0, 0.03]))
def test_spin_reversal_transposes(speed, eta):
    model = _colocated(eta)
    forward, backward = frf(model, speed, FREQS).H, frf(model, -speed, FREQS).H
    np.testing.assert_allclose(forward, np.swapaxes(backward, 0, 1), rtol=1e-9, atol=1e-16)
    # and spin really matters here (the test is not vacuous)
    assert np.abs(forward[0, 1] - forward[1, 0]).max() > 1e-6 * np.abs(forward[0, 1]).max()


def _bearing_machine(seed, rotors, symmetric):
    """A random machine on bearings (:func:`reference_bearings.random_bearing_description`) with
    three sensors colocated with three excitations at mount positions, along x, y, z; with
    ``symmetric``, its bearing coefficients made symmetric (K, C symmetric: reciprocity holds at
    zero speed)."""
    data = with_mount_channels(random_bearing_description(np.random.default_rng(seed), n_rotors=rotors, stator=True))
    for bearing in data["bearings"] if symmetric else ():
        for key in ("stiffness", "damping"):
            if key in bearing:
                k = np.asarray(bearing[key])
                bearing[key] = (0.5 * (k + k.T) + (np.abs(k).max() * np.eye(2) if key == "stiffness" else 0)).tolist()
    return rdm.Model.from_dict(data)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rotors=st.integers(1, 3),
       speed=st.one_of(st.just(0.0), st.floats(min_value=10.0, max_value=2000.0)))
def test_spin_reversal_transposes_on_random_machines_on_bearings(seed, rotors, speed):
    """``H(Omega) = H(-Omega)^T`` (reciprocity at zero speed) for random machines on symmetric
    bearings, colocated: the gyroscopic matrix is the only non-symmetric part of the system."""
    model = _bearing_machine(seed, rotors, symmetric=True)
    freqs = np.linspace(0.5, 300.0, 120)
    forward, backward = frf(model, speed, freqs).H, frf(model, -speed, freqs).H
    assert np.abs(forward - np.swapaxes(backward, 0, 1)).max() <= 1e-9 * np.abs(forward).max()


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rotors=st.integers(1, 3), speed=st.floats(min_value=-2000.0, max_value=2000.0))
def test_modal_engine_equals_the_direct_solve_on_random_machines_on_bearings(seed, rotors, speed):
    """The modal sum (one eigendecomposition) against the dynamic stiffness solved at every
    frequency, for random machines on cross-coupled, non-symmetric bearings (160 cases
    explored: within 2.3e-13 of max|H|)."""
    model = _bearing_machine(seed, rotors, symmetric=False)
    freqs = np.linspace(0.5, 300.0, 120)
    modal = frf(model, speed, freqs, engine="modal").H
    direct = frf(model, speed, freqs, engine="direct").H
    assert np.abs(modal - direct).max() <= 1e-9 * np.abs(direct).max()


@pytest.mark.parametrize("rpm", [1500.0, -4000.0])
def test_modal_engine_equals_the_direct_solve_on_speed_dependent_journal_bearings(examples_dir, rpm):
    """The journal rotor's film stiffness and damping depend on speed: both engines take them
    at the rotor's own speed (the state matrix there, the dynamic stiffness there)."""
    model = rdm.load_model(examples_dir / "journal_rotor.toml")
    freqs = np.linspace(1.0, 400.0, 200)
    modal = frf(model, rdm.rpm(rpm), freqs, engine="modal").H
    direct = frf(model, rdm.rpm(rpm), freqs, engine="direct").H
    assert np.abs(modal - direct).max() <= 1e-9 * np.abs(direct).max()


def test_state_space_picks_inputs_and_outputs_by_name_in_the_order_given():
    """``model.state_space(..., inputs, outputs)`` is the full system's columns and rows picked
    by name, in the order asked (not the model's)."""
    model = rdm.load_model(EXAMPLE)
    full = model.state_space(rdm.rpm(1200), "velocity")
    part = model.state_space(rdm.rpm(1200), "velocity", inputs=["shaker-y", "hammer-z"], outputs="acc-side-y")
    assert part.input_labels == ["shaker-y", "hammer-z"] and part.output_labels == ["acc-side-y"]
    columns = [full.input_labels.index(name) for name in ("shaker-y", "hammer-z")]
    row = full.output_labels.index("acc-side-y")
    np.testing.assert_array_equal(part.A, full.A)
    np.testing.assert_array_equal(part.B, full.B[:, columns])
    np.testing.assert_array_equal(part.C, full.C[[row]])
    np.testing.assert_array_equal(part.D, full.D[[row]][:, columns])
    with pytest.raises(InputError, match="unknown sensor 'acc-nope'"):
        model.state_space(0.0, outputs=["acc-nope"])


def test_to_control_round_trip():
    res = frf(rdm.load_model(EXAMPLE), 100.0, FREQS[1:])
    data = res.to_control()
    assert isinstance(data, control.FrequencyResponseData)
    np.testing.assert_allclose(data.omega, 2 * np.pi * FREQS[1:])
    back = type(res).from_control(data)
    np.testing.assert_array_equal(back.H, res.H)
    assert back.outputs == res.outputs and back.inputs == res.inputs


def test_dataframe_columns_and_rows():
    res = frf(rdm.load_model(EXAMPLE), 0.0, FREQS, inputs="hammer-z")
    table = res.to_dataframe()
    assert list(table.columns)[:7] == ["frequency_hz", "output", "input", "real", "imag", "magnitude", "phase_deg"]
    assert len(table) == 2 * 1 * len(FREQS)
    row = table[(table.output == "acc-side-y")].iloc[7]
    assert row.real == res.H[1, 0, 7].real and row.frequency_hz == FREQS[7]


def test_ground_forces_at_zero_frequency_balance_the_input():
    """Statically the suspensions pass the whole applied force (and its moment) to the ground."""
    model = rdm.load_model(EXAMPLE)
    res = force_frf(model, 0.0, [0.0])
    total = np.zeros((6, 2), dtype=complex)
    for k, s in enumerate(model.suspensions):
        total += rdm.shift_matrix([0, 0, 0], s.position) @ res.H[6 * k:6 * k + 6, :, 0]
    for i, x in enumerate(model.excitations):
        applied = np.concatenate([x.direction, np.cross(x.position, x.direction)])
        np.testing.assert_allclose(total[:, i], applied, atol=1e-12)


def test_stator_equilibrium_with_bearing_and_suspension_forces():
    """Seed eq. (70): M_S q'' = -sum B_SP T_susp + sum B_SR T_B + B_f f, at speed, with loss factor."""
    model = _colocated(loss_factor=0.04)
    speed, freqs = rdm.rpm(3000), np.array([3.0, 11.0, 27.0])
    S = model.reference_point
    susp = force_frf(model, speed, freqs).H
    bear = force_frf(model, speed, freqs, where="bearings").H
    q = dof_response(model, speed, 2 * np.pi * freqs,
                     rdm.assembly.excitation_columns(model))
    st_ = model.stator
    mass = rdm.assembly.rigid_mass_matrix(st_.mass, st_.inertia, st_.center_of_mass, S)
    for k, f in enumerate(freqs):
        w = 2 * np.pi * f
        lhs = -w ** 2 * mass @ q[k]
        rhs = rdm.assembly.excitation_columns(model).astype(complex)
        for i, s in enumerate(model.suspensions):
            rhs -= rdm.shift_matrix(S, s.position) @ susp[6 * i:6 * i + 6, :, k]
        for j, r in enumerate(model.rotors):
            rhs += rdm.shift_matrix(S, r.center_of_mass) @ bear[6 * j:6 * j + 6, :, k]
        np.testing.assert_allclose(lhs, rhs, rtol=1e-9, atol=1e-9 * np.abs(rhs).max())


def test_dynamic_stiffness_shape():
    Z = dynamic_stiffness(rdm.load_model(EXAMPLE), 10.0, FREQS)
    assert Z.shape == (len(FREQS), 6, 6) and Z.dtype == complex


@pytest.mark.parametrize("kwargs,message", [
    ({"quantity": "stiffness"}, "quantity 'stiffness': expected one of receptance, mobility, accelerance"),
    ({"engine": "fast"}, "engine 'fast': expected 'auto', 'modal' or 'direct'"),
    ({"outputs": ["nope"]}, "unknown sensor 'nope': the model's sensors are acc-top-z, acc-side-y"),
    ({"inputs": "nope"}, "unknown excitation 'nope': the model's excitations are hammer-z, shaker-y"),
    ({"freqs_hz": [1.0, -2.0]}, "frequencies: expected a 1-D array of finite values >= 0 Hz"),
])
def test_errors(kwargs, message):
    args = {"freqs_hz": FREQS, **kwargs}
    with pytest.raises(InputError) as info:
        frf(rdm.load_model(EXAMPLE), 0.0, **args)
    assert message in str(info.value)


def test_modal_engine_refused_for_hysteretic_model():
    with pytest.raises(InputError, match="engine 'modal' needs a viscous model"):
        frf(_block(eta=0.1), 0.0, FREQS, engine="modal")


def test_force_frf_refuses_unknown_place():
    with pytest.raises(InputError, match="where 'shafts': expected 'suspensions', 'bearings', 'rotors' or 'all'"):
        force_frf(_block(), 0.0, FREQS, where="shafts")


@pytest.mark.parametrize("bad,message", [
    ({"maxwell_stiffness": [[1e4] * 3]}, "maxwell_time = '<missing>'"),
    ({"maxwell_stiffness": [[1e4] * 3], "maxwell_time": [0.1, 0.2]}, "one per branch"),
    ({"maxwell_stiffness": [[1e4] * 3], "maxwell_time": [-0.1]}, "maxwell_time[0] = -0.1: expected a finite relaxation time > 0"),
    ({"maxwell_stiffness": [[1e4] * 4], "maxwell_time": [0.1]}, "maxwell_stiffness[0]"),
])
def test_maxwell_keys_are_validated(bad, message):
    data = _block().to_dict()
    data["suspensions"][0].update(bad)
    with pytest.raises(rdm.ModelError) as info:
        rdm.Model.from_dict(data, "m.toml")
    assert message in str(info.value)


def _maxwell_machine():
    data = rdm.load_model(EXAMPLE).to_dict()
    data["suspensions"][0].update(maxwell_stiffness=[[6e4, 4.5e4, 1.2e5], [3e4, 2e4, 6e4, 10, 10, 10]],
                                  maxwell_time=[0.02, 0.002])
    data["suspensions"][2].update(maxwell_stiffness=[[6e4, 4.5e4, 1.2e5]], maxwell_time=[0.01])
    return rdm.Model.from_dict(data)


@pytest.mark.parametrize("quantity,ss_quantity", [("receptance", "displacement"), ("accelerance", "acceleration")])
def test_maxwell_branches_are_states_of_the_state_space(quantity, ss_quantity):
    model = _maxwell_machine()
    system = model.state_space(rdm.rpm(3000), ss_quantity)
    assert system.nstates == 12 + 6 * 3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        reference = control.frequency_response(system, 2 * np.pi * FREQS)
    H = np.asarray(reference.frdata if hasattr(reference, "frdata") else reference.fresp)
    res = frf(model, rdm.rpm(3000), FREQS, quantity=quantity)
    assert res.engine == "direct"
    assert np.abs(res.H - H).max() < 1e-10 * np.abs(H).max()


def test_models_without_branches_keep_twelve_states():
    assert rdm.load_model(EXAMPLE).state_space(100.0).nstates == 12


def test_model_without_sensors_is_refused():
    data = _block().to_dict()
    data["sensors"] = []
    model = rdm.Model.from_dict(data, "bare.toml")
    with pytest.raises(InputError, match="bare.toml: the model has no \\[\\[sensors\\]\\]: an FRF needs"):
        frf(model, 0.0, FREQS)
    data["excitations"] = []
    with pytest.raises(InputError, match="the model has no \\[\\[excitations\\]\\]: a force FRF needs one"):
        force_frf(rdm.Model.from_dict(data, "bare.toml"), 0.0, FREQS)


def _same_angles(drawn, degrees) -> bool:
    """Whether the finite points of ``drawn`` [deg] are ``degrees`` one by one, each give or
    take whole turns."""
    drawn = np.asarray(drawn, float)
    drawn = drawn[np.isfinite(drawn)]
    turns = (drawn - degrees) / 360.0 if drawn.shape == np.shape(degrees) else np.nan
    return bool(np.all(np.abs(turns - np.round(turns)) < 1e-12))


def test_bode_figures_draw_each_pair_by_name_in_degrees():
    """Model lines and measured dots of each output/input pair (matched by name, the
    measurement's channels listed in another order and 10 % larger), magnitude |H| and phase
    in degrees; the overlay of several speeds likewise."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.frf import FRFResult
    from rotordyn_modal.plotting.frf import plot_frf, plot_overlay

    model = rdm.load_model(EXAMPLE)
    res = frf(model, 100.0, FREQS[1:])
    H = 1.1 * res.H[::-1, ::-1] * np.exp(0.3j)
    measured = FRFResult(**{**res.__dict__, "H": H, "outputs": res.outputs[::-1], "inputs": res.inputs[::-1]})
    pairs = [(o, i) for o in res.outputs for i in res.inputs]
    for fig in (plot_frf(res, measured), plot_overlay([res], [measured])):
        mag, phase = fig.axes[:2]
        # phases in degrees, the same angle (whole turns apart: dots lie beside their line, a line
        # breaks where it wraps, test_figure_audit7); magnitudes exactly
        for axis, value, same in ((mag, np.abs, np.array_equal),
                                  (phase, lambda h: np.degrees(np.angle(h)), _same_angles)):
            drawn = [(line.get_marker(), line.get_color(), np.asarray(line.get_ydata()))
                     for line in axis.get_lines() if len(line.get_xdata())]
            for o, i in pairs:
                h = res.H[res.outputs.index(o), res.inputs.index(i)]
                hm = H[measured.outputs.index(o), measured.inputs.index(i)]
                at, = [k for k, (marker, c, y) in enumerate(drawn) if marker != "." and same(y, value(h))]
                # the pair's measurement: the dots drawn just before its model line, in its colour
                marker, c, y = drawn[at - 1]
                assert marker == "." and c == drawn[at][1] and same(y, value(hm)), (o, i)
        plt.close(fig)


def test_fit_overlay_tells_every_curve_apart():
    """The fit's overlay (`fit --plot`) of 4 FRFs at two speeds: one magnitude and phase panel per
    speed, named by it; within a panel each FRF has a style (colour, line style) of its own, named
    in the legend, and its measured dots in its colour. The old overlay drew every FRF of a speed
    in that speed's colour on one panel: 8 lines in 2 colours, which curve was which FRF could not
    be read, and the 2400 rpm lines covered the 0 rpm ones."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.frf import FRFResult
    from rotordyn_modal.plotting.frf import plot_overlay

    model = rdm.load_model(EXAMPLE)
    speeds = (0.0, rdm.rpm(2400))
    models = [frf(model, s, FREQS[1:], quantity="accelerance") for s in speeds]
    measured = [FRFResult(**{**m.__dict__, "H": 1.1 * m.H}) for m in models]
    pairs = [(o, i) for o in models[0].outputs for i in models[0].inputs]
    assert len(pairs) == 4
    fig = plot_overlay(models, measured)
    magnitudes = [ax for ax in fig.axes if ax.get_yscale() == "log"]
    assert len(magnitudes) == len(speeds)
    for ax, speed, m in zip(magnitudes, speeds, models):
        assert f"{speed * 30 / np.pi:.0f} rpm" in ax.get_title()
        lines = [line for line in ax.get_lines() if line.get_marker() in ("None", "", None) and len(line.get_xdata())]
        dots = [line for line in ax.get_lines() if line.get_marker() == "."]
        assert len(lines) == len(dots) == len(pairs)
        styles = [(matplotlib.colors.to_hex(line.get_color()), line.get_linestyle()) for line in lines]
        assert len(set(styles)) == len(pairs), styles
        for o, i in pairs:
            h = np.abs(m.H[m.outputs.index(o), m.inputs.index(i)])
            line, = [line for line in lines if np.array_equal(line.get_ydata(), h)]
            assert line.get_label().startswith(f"{o} / {i}")     # '(round-off ...)' where zero by symmetry
            dot, = [d for d in dots if np.allclose(d.get_ydata(), 1.1 * h)]
            assert dot.get_color() == line.get_color()
        assert [t.get_text() for t in ax.get_legend().get_texts()] == [line.get_label() for line in lines]
    plt.close(fig)


def test_frf_over_three_decades_shows_the_mount_modes_apart():
    """motor_pump_on_mounts from 1 to 1,500 Hz: mount modes at 5-16 Hz, bearing modes at
    530-1,180 Hz. On a linear frequency axis the six mount modes' peaks stood within 1 % of the
    axis' width (a few pixels); the axis is logarithmic when the frequencies span more than 30
    times (as the Campbell diagram's), so the lowest and the highest mount mode (the modal
    analysis' frequencies) stand at least a tenth of the width apart. A band of one decade
    (2-40 Hz) stays linear."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLE.parent / "motor_pump_on_mounts.toml")
    speed = rdm.rpm(3000)
    modes = rdm.modal(model, speed).frequencies_hz
    mounts = modes[modes < 50]
    assert len(mounts) == 6 and modes.max() > 1000
    fig = rdm.frf(model, speed, np.linspace(1.0, 1500.0, 100)).plot()
    fig.canvas.draw()
    mag = fig.axes[0]
    assert mag.get_xscale() == "log"
    left, right = (mag.transData.transform((f, 1.0))[0] for f in (mounts.min(), mounts.max()))
    assert right - left >= 0.1 * mag.get_window_extent().width
    plt.close(fig)
    narrow = rdm.frf(model, speed, np.linspace(2.0, 40.0, 20)).plot()
    assert narrow.axes[0].get_xscale() == "linear"
    plt.close(narrow)
