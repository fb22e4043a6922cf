"""The run-up figure says and shows the truth (issue 27 §3; issue 28 §3: run-ups through bending
critical speeds with order tracking).

* It draws the steady response the track is compared with: the linear model's unbalance response
  at the track's own speeds (``runup.steady_orders``, computed by the analysis, drawn dashed).
* Its shade says what it means and why: the track may differ from the steady response by more
  than 10 % of its peak, caused by the lag behind the steady response through a mode passed
  between 0.63 and a few ``(zeta f)^2`` (``runup.quasi_static_deviation``), by a fast passage
  (lag and ringing), or by windows that do not settle. Main said "not separable from free
  vibration" throughout, where the track of a slow passage is no free vibration but the lag.

Truth from outside the figure: ``rdm.unbalance_response`` of the model, and the closed-form steady
response of one mode.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.simulation.runup import order_track, unsettled_spans
from test_runup_passage27 import F_N, ZETA, _crossing, _steady, _swept_mode

RPM = 30.0 / np.pi

#: a rigid rotor on two bearings, bearing A on a pedestal (the linear time model, cheap with numpy)
MACHINE = """
name = "rotor on a pedestal"
reference_rotor = "r"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "r"
mass = 10.0
center_of_mass = [0.2, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.2

[[bearings]]
name = "A"
rotor = "r"
position = [0.0, 0.0, 0.0]
stiffness = [1e6, 1.3e6]
damping = 300.0
pedestal_mass = 2.0
pedestal_stiffness = 2e7

[[bearings]]
name = "B"
rotor = "r"
position = [0.4, 0.0, 0.0]
stiffness = [1.2e6, 1.5e6]
damping = 300.0

[[unbalances]]
rotor = "r"
amount = 1e-4
axial_offset = 0.1
phase_deg = 30.0

[[sensors]]
name = "s"
rotor = "r"
position = [0.2, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]
"""


@pytest.fixture(scope="module")
def ramp(tmp_path_factory):
    """The machine run up from 600 to 9,000 rpm in 1 s through its four modes (73-131 Hz)."""
    path = tmp_path_factory.mktemp("runup30") / "pedestal.toml"
    path.write_text(MACHINE, encoding="utf-8")
    model = rdm.load_model(path)
    run = rdm.simulate(model, 1.0, rdm.rpm(600.0), drive="ramp", final_speed=rdm.rpm(9000.0), backend="numpy")
    critical = rdm.campbell(model, np.linspace(rdm.rpm(600.0), rdm.rpm(9000.0), 121)).critical
    return path, model, run, critical


def _steady_line(fig, rotor="r"):
    lines = [line for ax in fig.axes for line in ax.get_lines() if line.get_gid() == f"steady-{rotor}"]
    assert len(lines) == 1, [line.get_label() for ax in fig.axes for line in ax.get_lines()]
    return lines[0]


def test_the_drawn_steady_curve_is_the_unbalance_response_at_the_track_speeds(ramp):
    """The amplitude panel's dashed curve lies at the order track's speeds and equals
    ``|unbalance_response|`` there to 1e-9; where the track is not shaded it is within 10 % of
    that curve's peak (main: no steady curve, ``plot`` takes no ``steady``)."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.simulation.runup import steady_orders

    _, model, run, critical = ramp
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fig = run.plot(sensor="s", critical=critical, steady=steady_orders(model, run, "s"))
    line = _steady_line(fig)
    track = order_track(run, "s")
    truth = rdm.unbalance_response(model, track.speeds, outputs=["s"])
    assert np.allclose(line.get_xdata(), track.speeds * RPM, rtol=1e-12, atol=0)
    assert np.allclose(np.asarray(line.get_ydata()) / 1e6, np.abs(truth.response[0, 0]), rtol=1e-9, atol=0)
    assert "steady" in line.get_label() and line.get_linestyle() == "--"
    shaded = np.zeros(len(track.speeds), dtype=bool)
    for low, high in unsettled_spans(run, track, critical):
        shaded |= (track.speeds >= low) & (track.speeds <= high)
    assert (~shaded).any()
    peak = np.abs(truth.response[0, 0]).max()
    assert np.all(np.abs(track.amplitude - np.abs(truth.response[0, 0]))[~shaded] <= 0.1 * peak)
    plt.close(fig)


def test_simulate_ramp_plot_draws_the_steady_response(ramp, tmp_path, monkeypatch):
    """``simulate MODEL --speed 600 --ramp 9000 --duration 1 --plot``: the figure it saves holds
    the steady curve, equal to ``unbalance_response`` at the track's speeds to 1e-9."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.cli import simulate as command

    path, model, _, _ = ramp
    saved = []
    monkeypatch.setattr(command, "save_figure", lambda fig, args: saved.append(fig))
    code = main(["simulate", str(path), "--speed", "600", "--ramp", "9000", "--duration", "1", "--backend", "numpy",
                 "--plot", str(tmp_path / "runup.png"), "--quiet"])
    assert code == 0 and len(saved) == 1
    line = _steady_line(saved[0])
    speeds = np.asarray(line.get_xdata()) / RPM
    truth = rdm.unbalance_response(model, speeds, outputs=["s"])
    assert np.allclose(np.asarray(line.get_ydata()) / 1e6, np.abs(truth.response[0, 0]), rtol=1e-9, atol=0)


def _shade_text(record, critical):
    """The shade's legend entry and the warning of the run-up figure of ``record``."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.simulation import plot_runup

    record.time, record.drive_speed = np.asarray(record.time), np.asarray(record.drive_speed)
    with warnings.catch_warnings(record=True) as held:
        warnings.simplefilter("always")
        fig = plot_runup(record, "s", critical=critical)
    phase = next(ax for ax in fig.axes if ax.get_title() == "Order-tracked phase")
    labels = [t.get_text().replace("\n", " ") for t in phase.get_legend().get_texts()]
    plt.close(fig)
    notes = [label for label in labels if "steady response" in label]
    warned = [str(w.message) for w in held if "steady response" in str(w.message)]
    assert len(notes) == 1 and len(warned) == 1, (labels, [str(w.message) for w in held])
    return notes[0], warned[0]


def test_a_passage_at_0_8_zeta_f_squared_is_shaded_for_its_lag_as_large_as_stated():
    """One mode (6 Hz, zeta 0.03) swept from 4.5 to 7.5 Hz at 0.8 ``(zeta f)^2``: marked (over
    0.63), and the legend and the warning name the lag, not a fast passage, with the estimate
    13 % of the resonance's steady peak; the track's largest distance from the closed-form steady response
    (complex, over its peak) is that within 3 points (main: 'not separable from free vibration')."""
    sweep = 0.8 * (ZETA * F_N) ** 2
    record = _swept_mode(3.0 / sweep, f0=4.5, f1=7.5, rate=100.0)
    note, warned = _shade_text(record, _crossing())
    for text in (note, warned):
        assert "may differ from the steady response by more than 10% of its peak" in text, text
        assert ("lag through mode 1 (estimate: near it the track is off the steady response by up to 13% of that "
                "resonance's steady peak, amplitude and phase together)") in text, text
        assert "fast passage" not in text and "not separable" not in text, text
    track = order_track(record, "s")
    steady = _steady(track.speeds)
    near = np.abs(track.speeds / (2 * np.pi) - F_N) < 4 * ZETA * F_N
    tracked = track.amplitude * np.exp(1j * np.radians(track.phase_deg))
    distance = np.abs(tracked - steady)[near].max() / np.abs(steady).max()
    stated = float(re.search(r"by up to (\d+)%", note)[1]) / 100
    assert abs(stated - distance) <= 0.03, (stated, distance)


def test_a_fast_passage_is_shaded_for_its_lag_and_ringing():
    """The same mode swept from 2 to 20 Hz in 10 s (56 ``(zeta f)^2``, an estimated lag of 8.8
    times the peak): the shade names a fast passage, lag and ringing."""
    note, warned = _shade_text(_swept_mode(10.0), _crossing())
    for text in (note, warned):
        assert "fast passage of mode 1: lag, ringing" in text and "lag through" not in text, text
