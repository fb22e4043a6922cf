"""``simulate`` refuses, before the work, a duration it cannot integrate, and names the cause of
any remaining integrator failure (issue 27 §1; redteam30's reproductions).

Truth from outside the code: the float resolution of the end time (``np.spacing``, the machine
epsilon) against the model's periods from a plain eigen-solution of its (K, M) (scipy), and DOP853's
own abort rule (a step below 10 x 2.3e-16 x t, Hairer's UROUND), not a value the code prints.
On main: ``simulate examples/compressor_rotor.toml --duration 1e9`` failed after the work with
exit 1, "failed: RuntimeError: integration failed at t = 4.55e+08 s (DOP853 code -3)";
``examples/journal_rotor.toml --duration 1e9`` named eccentricity 0.0000 (t = 0, its last output
time) beside "ran into its bearing wall".
"""

from __future__ import annotations

import re

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError

EPS = np.finfo(float).eps


def _error_lines(capsys):
    err = capsys.readouterr().err
    return [line for line in err.splitlines() if line.startswith("rotordyn-modal simulate: ")]


def test_compressor_duration_beyond_float_resolution_is_refused_with_the_largest(capsys):
    """--duration 1e9: exit 2 before any work, one line naming the option, its value and the
    largest duration; that duration's end-time resolution is well below the fastest period of
    the linear model's basis, bounded from the model's own eigen-solution."""
    assert main(["simulate", "examples/compressor_rotor.toml", "--duration", "1e9", "--quiet"]) == 2
    lines = _error_lines(capsys)
    assert len(lines) == 1 and "RuntimeError" not in lines[0], lines
    assert "--duration 1e9" in lines[0] and "--allow-long does not lift" in lines[0], lines
    largest = float(re.search(r"expected at most ([0-9.e+]+) s", lines[0])[1])
    model = rdm.load_model("examples/compressor_rotor.toml")
    from rotordyn_modal.assembly import constant_matrices
    m = constant_matrices(model)
    values = scipy.linalg.eigh(0.5 * (m.K + m.K.T), 0.5 * (m.M + m.M.T), eigvals_only=True)
    fastest_full = np.sqrt(values.max())        # no basis motion is faster (Rayleigh-Ritz)
    sixth = np.sqrt(np.sort(np.abs(values))[5])  # the basis holds at least the 6 lowest modes
    # the end time's resolution is at most 1e-6 of the basis' fastest period, which lies between these
    assert np.spacing(largest) <= largest * EPS <= 1e-6 * 2 * np.pi / sixth
    assert largest * EPS >= 0.5e-6 * 2 * np.pi / fastest_full
    # and 1e9 s: DOP853's smallest step there (10 x 2.3e-16 x t) is above 1e-4 of the fastest period
    assert 10 * 2.3e-16 * 1e9 > 1e-4 * 2 * np.pi / sixth


def test_rigid_duration_beyond_float_resolution_is_refused_before_compiling(capsys, monkeypatch):
    """The nonlinear model: the same refusal, before any compilation or eigen-solution of its
    steps (it comes before the CPU estimate: no CPU time makes the steps representable), naming the
    largest duration below the one asked. The count limit of periods, which comes first, lifted.
    (With --allow-long main would integrate 1e13 s for ever, so the test does not pass it.)"""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_POINTS", "1e18")
    assert main(["simulate", "examples/spring_block_rotor.toml", "--speed", "50", "--speed-unit", "rad/s",
                 "--duration", "1e13", "--quiet"]) == 2
    lines = _error_lines(capsys)
    assert len(lines) == 1 and "--duration 1e13" in lines[0], lines
    largest = float(re.search(r"expected at most ([0-9.e+]+) s", lines[0])[1])
    period = float(re.search(r"Hz, ([0-9.e+-]+) s\)", lines[0])[1])
    assert largest < 1e13 and largest * EPS <= 1e-6 * period * (1 + 1e-3)


def test_the_stated_largest_duration_passes_and_a_little_more_does_not():
    """The largest duration the line names passes the check it comes from (rounded down)."""
    from rotordyn_modal.simulation._system import check_resolution

    rate = 8494.45832956
    try:
        check_resolution(1e9, rate)
    except InputError as error:
        largest = float(re.search(r"expected at most ([0-9.e+]+) s", str(error))[1])
    check_resolution(largest, rate)
    try:
        check_resolution(largest * 1.01, rate)
        raise AssertionError("1 % above the stated largest duration passed")
    except InputError:
        pass


def test_journal_message_names_where_it_stopped():
    """At speed 0 the short-bearing film has no wedge: the journals sink. With a duration of 1e9 s
    the first output interval is 5e8 s, so the last output time is t = 0 (eccentricity 0); the line
    must also give the eccentricity where the integrator stopped, well off centre."""
    model = rdm.load_model("examples/journal_rotor.toml")
    try:
        rdm.simulate(model, 1e9, 0.0, samples=3)
        raise AssertionError("the run at speed 0 went through")
    except InputError as error:
        text = str(error)
    assert "\n" not in text and "RuntimeError" not in text
    where = re.search(r"where it stopped \(t = ([0-9.e+-]+) s\): \[bearings.DE\] ([0-9.]+)", text)
    assert where, text
    assert float(where[1]) < 10 and float(where[2]) > 0.5, text


def test_a_linear_model_that_blows_up_fails_in_one_line_naming_the_cause(monkeypatch):
    """Where the state the integrator returns is no longer finite, the linear time model's failure
    is one line (an InputError, the command line's exit 2) naming the time and the cause; on main a
    RuntimeError 'integration failed at t = ... (DOP853 code 1)' that the command line printed as
    'failed: RuntimeError'. The blow-up is forced on the pedestal-free compressor (numpy path)."""
    from rotordyn_modal.simulation import _system

    real = _system.integrate_to

    def blown(solver, t, stiffness_test=False):
        return real(solver, t, stiffness_test) * np.nan

    monkeypatch.setattr(_system, "integrate_to", blown)
    model = rdm.load_model("examples/compressor_rotor.toml")
    try:
        rdm.simulate(model, 0.01, 300.0, samples=3, backend="numpy")
        raise AssertionError("a non-finite state went through")
    except InputError as error:
        text = str(error)
    assert "\n" not in text and text.startswith("examples/compressor_rotor.toml: the integration stopped at t = ")
    assert "infinite or NaN" in text, text
