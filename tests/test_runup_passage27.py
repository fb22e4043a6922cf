"""Run-up order tracks at low speed: where the order cannot be told apart from the free
vibration of a mode it passes, the span is marked; elsewhere the track follows the steady
unbalance response (issue 27, section 3).

A ramp through a lightly damped mode faster than about (zeta f)^2 [Hz/s] leaves the mode ringing
at its own frequency, with a size of the order of the peak response; within about a cycle a
window of the order's frequency no window of a few turns tells that ringing from the order.
motor_pump_on_mounts' 300 to 3,000 rpm in 2 s sweeps its 1X through six mount modes (5.5-15.8
Hz, zeta 0.03-0.08) at 22.5 Hz/s, 13 to 930 times (zeta f)^2: main's track there was up to 54
times the steady amplitude and 153 deg off its phase, unmarked.

Truth from outside the tracking: the closed-form steady response of one mode to an unbalance,
and `unbalance_response` (frequency domain) of the simulated machine.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rotordyn_modal as rdm
from rotordyn_modal.analysis.critical_speeds import CriticalSpeeds
from rotordyn_modal.plotting import simulation as figures
from rotordyn_modal.simulation import runup
from rotordyn_modal.simulation.runup import order_track

F_N, ZETA = 6.0, 0.03                  # the mode [Hz] and its damping ratio
F_D = F_N * np.sqrt(1 - ZETA ** 2)


def _swept_mode(duration, f0=2.0, f1=20.0, rate=200.0, rotors=(("r", 1.0, 1.0),), name="one mode"):
    """One mode (unit mass, ``F_N``, ``ZETA``) pushed by the unbalance of each of ``rotors``
    ``(name, speed ratio r, weight w)``, ``w (r Omega)^2 cos(r phi)``, the reference speed ramped
    linearly from ``f0`` to ``f1`` [Hz] over ``duration`` [s] from rest; sampled at ``rate`` [Hz],
    as a run-up record (default: one rotor, ``Omega^2 cos(phi)``)."""
    wn = 2 * np.pi * F_N
    sweep = (f1 - f0) / duration
    ratios = np.array([r for _, r, _ in rotors])

    def angle(t):
        return 2 * np.pi * (f0 * t + 0.5 * sweep * t * t)

    def speed(t):
        return 2 * np.pi * (f0 + sweep * t)

    def rhs(t, y):
        force = sum(w * (r * speed(t)) ** 2 * np.cos(r * angle(t)) for _, r, w in rotors)
        return [y[1], force - 2 * ZETA * wn * y[1] - wn * wn * y[0]]

    t = np.arange(0.0, duration, 1.0 / rate)
    x = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-9, atol=1e-12, method="DOP853").y[0]
    return SimpleNamespace(time=t, rotor_angles=np.outer(angle(t), ratios), speed_ratios=ratios,
                           rotor_names=[n for n, _, _ in rotors], drive_speed=speed(t), sensor=lambda _: x,
                           sensor_names=["s"], model_name=name)


def _steady(speeds):
    """The closed-form steady response ``Omega^2 / (wn^2 - Omega^2 + 2 i zeta wn Omega)``."""
    wn = 2 * np.pi * F_N
    return speeds ** 2 / (wn * wn - speeds ** 2 + 2j * ZETA * wn * speeds)


def _crossing():
    """The mode's one crossing with the rotor's 1X, as a Campbell diagram gives it."""
    one = lambda value: np.array([value])     # noqa: E731
    return CriticalSpeeds(source=one("r"), order=one(1.0), mode=one(1), speeds=one(2 * np.pi * F_N),
                          frequencies_hz=one(F_D), whirl=one("forward"), whirl_ratios=one(1.0),
                          damping_ratios=one(ZETA))


def _marked(record, track, critical):
    """Where the figure marks the track as off the steady response (none on main, which has no marks)."""
    spans = getattr(runup, "unsettled_spans", lambda *args: [])(record, track, critical)
    inside = np.zeros(len(track.speeds), dtype=bool)
    for low, high in spans:
        inside |= (track.speeds >= low) & (track.speeds <= high)
    return inside, spans


@pytest.mark.parametrize("duration", [10.0, 30.0, 90.0])
def test_a_fast_passage_is_marked_and_the_rest_follows_the_steady_response(duration):
    """Sweeps of 1.8, 0.6 and 0.2 Hz/s (56, 19 and 6 times (zeta f)^2) through the mode: every
    unmarked window is within 10 % (complex difference over the steady amplitude) of the
    closed-form steady response, and the mark ends below twice the mode's frequency
    (main: no mark; 1.0, 1.2 and 0.7 times off near the mode)."""
    record = _swept_mode(duration)
    track = order_track(record, "s")
    marked, spans = _marked(record, track, _crossing())
    steady = _steady(track.speeds)
    tracked = track.amplitude * np.exp(1j * np.radians(track.phase_deg))
    error = np.abs(tracked - steady) / np.abs(steady)
    assert np.all(error[~marked] < 0.10), (track.speeds[~marked & (error >= 0.1)] / 2 / np.pi, error[~marked].max())
    above = track.speeds[~marked] / (2 * np.pi)
    assert np.any(above > F_N) and above[above > F_N].min() < 2 * F_N, spans
    assert marked.any() and (track.speeds[marked] / (2 * np.pi)).max() > F_N


def test_a_slow_passage_is_not_marked_and_follows_the_steady_response():
    """Swept at 0.6 (zeta f)^2 from 5 to 7.5 Hz the mode's response follows the steady one
    (within 10 %): nothing is marked near the mode (the start's transient, from rest, is: the
    first windows)."""
    duration = 2.5 / (0.6 * (ZETA * F_N) ** 2)
    record = _swept_mode(duration, f0=5.0, f1=7.5, rate=100.0)
    track = order_track(record, "s")
    marked, spans = _marked(record, track, _crossing())
    assert not marked[track.speeds > 2 * np.pi * 5.5].any(), spans
    steady = _steady(track.speeds)
    tracked = track.amplitude * np.exp(1j * np.radians(track.phase_deg))
    assert np.all(np.abs(tracked - steady)[~marked] / np.abs(steady[~marked]) < 0.10)


def test_the_figure_shades_the_span_and_says_it_in_one_warning(tmp_path):
    """The run-up figure shades the marked span on the amplitude and phase panels, with a legend
    entry, and one warning names the order and the span in rpm."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.patches import Polygon, Rectangle

    record = _swept_mode(10.0)
    record.time, record.drive_speed = np.asarray(record.time), np.asarray(record.drive_speed)
    with warnings.catch_warnings(record=True) as held:
        warnings.simplefilter("always")
        fig = figures.plot_runup(record, "s", critical=_crossing())
    lines = [str(w.message) for w in held if "may differ from the steady response" in str(w.message)]
    assert len(lines) == 1 and "\n" not in lines[0] and "1X r at " in lines[0] and "rpm" in lines[0], lines
    track = order_track(record, "s")
    _, spans = _marked(record, track, _crossing())
    amplitude_ax, phase_ax = fig.axes[1], fig.axes[2]
    for axis in (amplitude_ax, phase_ax):
        shaded = [p for p in axis.patches if isinstance(p, (Polygon, Rectangle))]
        xs = sorted((round(min(p.get_xy()[:, 0]) if isinstance(p, Polygon) else p.get_x(), 3),
                     round(max(p.get_xy()[:, 0]) if isinstance(p, Polygon) else p.get_x() + p.get_width(), 3))
                    for p in shaded)
        assert xs == [(round(low * 30 / np.pi, 3), round(high * 30 / np.pi, 3)) for low, high in spans], xs
    labels = [text.get_text() for text in phase_ax.get_legend().get_texts()]
    assert any("may differ from the steady response" in label for label in labels), labels
    fig.savefig(tmp_path / "runup.png")


@pytest.fixture(scope="module")
def motor_pump_run():
    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "motor_pump_on_mounts.toml")
    run = rdm.simulate(model, 2.0, rdm.rpm(300.0), drive="ramp", final_speed=rdm.rpm(3000.0), initial="equilibrium")
    critical = rdm.campbell(model, np.linspace(rdm.rpm(300.0), rdm.rpm(3000.0), 121)).critical
    return model, run, critical


def test_motor_pump_run_up_is_marked_where_it_is_off_and_follows_the_steady_response_elsewhere(motor_pump_run):
    """`simulate motor_pump_on_mounts --speed 300 --ramp 3000 --duration 2 --initial equilibrium`,
    sensor acc-motor-DE-y: each rotor's unmarked windows are within 10 % and 10 deg of
    `unbalance_response` at the window's mean speed, and they start below 2,100 rpm (main: no
    mark; windows at 580-1,300 rpm up to 54 times the steady amplitude, 153 deg off)."""
    model, run, critical = motor_pump_run
    for source, rotor in enumerate(["motor", "pump"]):
        track = order_track(run, "acc-motor-DE-y", rotor=rotor)
        marked, spans = _marked(run, track, critical)
        steady = rdm.unbalance_response(model, track.speeds)
        o = list(steady.outputs).index("acc-motor-DE-y")
        amplitude, phase = steady.amplitude[o, source], steady.phase_deg[o, source]
        free = ~marked
        assert free.sum() >= 6 and track.speeds[free].min() < rdm.rpm(2100.0), (rotor, spans)
        assert np.all(np.abs(track.amplitude[free] / amplitude[free] - 1) < 0.10), (rotor, track.speeds[free])
        error = (track.phase_deg[free] - phase[free] + 180) % 360 - 180
        assert np.all(np.abs(error) < 10.0), (rotor, error)
