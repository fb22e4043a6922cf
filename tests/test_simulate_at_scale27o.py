"""``simulate`` at 2,006 coordinates: a step of milliseconds, so a signal is heeded at once; no private
scipy hook; the natural frequencies from the largest roots (issue 27 §1.4, §1.9).

A signal stops the run at the end of DOP853's step in progress (tests/test_simulate_signals.py).
On 500 geared rotors on bearings one step took 7 to 14 s: each of its 12 evaluations of the
compiled right-hand side took 1.25 s of CPU, all of it the mass matrix's Cholesky solve, which the
frame's coordinates, coming first, filled whole (n^3). The truths here: the readable numpy
right-hand side (``numpy.linalg.solve``), and scipy's dense ``eigvals``.
"""

from __future__ import annotations

import importlib
import time
import tomllib

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.linear_system import speed_linear_form
from rotordyn_modal.simulation._kernels import plain_namespace
from rotordyn_modal.simulation._system import system_arrays
from test_large_machine_cli import chained_gear_toml

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")


def _system(rotors, on_bearings):
    return system_arrays(rdm.Model.from_dict(tomllib.loads(chained_gear_toml(rotors, on_bearings)), "chain.toml"))


def _compiled_and_plain_agree(system, seed, states=3):
    """The compiled right-hand side and the numpy one at random small states, both drives."""
    from rotordyn_modal.simulation._fast import pack

    kn, rng = simulate_module.kernels("numba"), np.random.default_rng(seed)
    for mode in (0, 1):
        extra = (mode, 7.0, 0.0, 1.0)
        for _ in range(states):
            y = rng.normal(size=2 * system.n_dof) * 0.01
            plain = plain_namespace().rhs(0.5, y, *system.kernel_arguments(), *extra)
            np.testing.assert_allclose(kn.rhs_flat(0.5, y, *pack(system, *extra)), plain, rtol=1e-10,
                                       atol=1e-10 * np.abs(plain).max())


def test_one_evaluation_on_500_geared_rotors_takes_milliseconds():
    """main: 1.25 s of CPU an evaluation (measured 4.3 ms now), so a DOP853 step of 15 s."""
    from rotordyn_modal.simulation._fast import pack

    system = _system(500, 500)
    assert system.n_dof == 2007                     # the frame's 6, 4 for each rotor, the drive angle
    kn = simulate_module.kernels("numba")
    arguments = pack(system, 1, 0.0, 0.0, 1.0)
    rest = np.zeros(2 * system.n_dof)
    rest[-1] = 314.0
    kn.rhs_flat(0.0, rest, *arguments)              # compiled (or loaded) first
    best = np.inf
    for _ in range(3):
        start = time.process_time()
        kn.rhs_flat(0.0, rest, *arguments)
        best = min(best, time.process_time() - start)
    assert best < 0.1, f"{best:.3g} s of CPU an evaluation"


@pytest.mark.parametrize("rotors, on_bearings", [(30, 10), (12, 12), (50, 50)],
                         ids=["some on bearings", "all on bearings", "50 on bearings"])
def test_the_reordered_solve_agrees_with_numpy_where_rotors_on_and_off_bearings_mix(rotors, on_bearings):
    """47, 55 and 207 coordinates (the reordered solve from 40), rotors fixed in the casing among the
    first (the numpy right-hand side takes minutes at 2,007 coordinates)."""
    system = _system(rotors, on_bearings)
    assert system.n_dof >= 40
    _compiled_and_plain_agree(system, 11)


def test_the_per_sample_outputs_through_the_reordered_solve_agree_with_numpy():
    system = _system(30, 10)
    states = np.random.default_rng(7).normal(size=(3, 2 * system.n_dof)) * 0.01
    times = np.array([0.1, 0.5, 1.5])
    for mode in (0, 1):
        arguments = system.kernel_arguments() + (mode, 7.0, 0.0, 1.0)
        plain = plain_namespace().sample_outputs(times, states, *arguments)
        compiled = simulate_module.kernels("numba").sample_outputs(times, states, *arguments)
        for a, b in zip(plain, compiled):
            np.testing.assert_allclose(b, a, rtol=1e-10, atol=1e-10 * np.abs(a).max(initial=1.0))


def test_the_step_callback_goes_through_scipys_public_set_solout(monkeypatch):
    """main set scipy's private ``_integrator._solout`` itself, past scipy's own wrapper: a change
    of scipy there would have left the signals unheeded in silence. Through ``set_solout``
    scipy's wrapper (``dop853._solout``) runs at every step, and the run is the same to the bit."""
    from scipy.integrate import _ode

    model = rdm.load_model(simulate_module.__file__.rsplit("rotordyn_modal", 1)[0] + "examples/fan_on_bearings.toml")
    before = rdm.simulate(model, 0.02, 100.0, samples=5, backend="numba")
    wrapper, calls = _ode.dop853._solout, []

    def counted(self, *args):
        calls.append(args[0])
        return wrapper(self, *args)

    monkeypatch.setattr(_ode.dop853, "_solout", counted)
    after = rdm.simulate(model, 0.02, 100.0, samples=5, backend="numba")
    assert len(calls) > 4                            # main: 0 (its own hook, past scipy's wrapper)
    assert np.array_equal(before.states, after.states)


def test_a_noted_signal_stops_dop853_at_the_end_of_its_first_step():
    from scipy.integrate import ode

    solver = ode(lambda t, y: np.array([y[1], -1e4 * y[0]])).set_integrator("dop853", rtol=1e-9, atol=1e-12)
    simulate_module._stop_at_a_step_when(solver, ["a signal"])
    solver.set_initial_value([1.0, 0.0], 0.0)
    solver.integrate(10.0)
    assert solver.get_return_code() == 2 and 0.0 < solver.t < 0.1   # "interrupted by solout"


def test_the_fastest_rate_of_a_large_machine_is_the_dense_one_without_a_dense_solution(monkeypatch):
    """306 coordinates: the largest ``|Im lambda|`` of the dense eigenvalues (main: a dense
    ``eigvals`` of the 612 states; 22 s of CPU at 4,012)."""
    from rotordyn_modal._blas import one_blas_thread

    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(75, 75)), "chain.toml")
    with one_blas_thread(24 * 612**2):
        expected = np.abs(scipy.linalg.eigvals(speed_linear_form(model).at(0.0)).imag).max()
    calls = []
    for name in ("eig", "eigvals"):
        monkeypatch.setattr(scipy.linalg, name, lambda *args, _name=name, **kwargs: calls.append(_name))
        monkeypatch.setattr(np.linalg, name, lambda *args, _name=name, **kwargs: calls.append("numpy " + _name))
    rate = simulate_module._fastest_rate(model, 1.0, None)
    assert calls == []                               # main: ['eigvals']
    assert rate == pytest.approx(expected, rel=1e-12)


def test_where_the_largest_roots_are_real_the_dense_eigenvalues_give_the_fastest_rate():
    """The largest roots cannot bound the imaginary parts of the others when they are all real:
    a matrix of 600 states (the size from which they are sought) whose 500 largest roots are real,
    one pair -1 +- 5i among the rest, its coordinates shuffled."""
    diagonal = np.concatenate([-np.linspace(100.0, 1000.0, 500), -np.linspace(1.0, 2.0, 98)])
    matrix = np.zeros((600, 600))
    matrix[:598, :598] = np.diag(diagonal)
    matrix[598:, 598:] = [[-1.0, 5.0], [-5.0, -1.0]]
    shuffled = np.random.default_rng(2).permutation(600)
    matrix = matrix[np.ix_(shuffled, shuffled)]
    with pytest.raises(simulate_module._NoBound):
        simulate_module._largest_imaginary(matrix)
    assert simulate_module._largest_frequency(matrix) == pytest.approx(5.0, rel=1e-9)


def test_the_natural_frequencies_are_a_phase_of_the_progress(monkeypatch):
    """A clock can tick there (``_progress.phase``); main showed nothing while they were made."""
    from rotordyn_modal import _progress

    shown, original = [], _progress.phase

    def recorded(enabled, description, *args, **kwargs):
        shown.append((enabled, description))
        return original(False, description, *args, **kwargs)

    monkeypatch.setattr(_progress, "phase", recorded)
    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(75, 75)), "chain.toml")
    simulate_module._fastest_rate(model, 1.0, None, progress=True)
    assert shown == [(True, "simulate: the natural frequencies, for the default output times")]


def test_a_signal_noted_between_output_times_whose_handler_returns_leaves_the_run_as_it_was():
    """A handler that returns (a program's own, which only logs) noted before an ``integrate`` call:
    main stopped DOP853 at its start point, which failed the solver for good (code -3, "step size
    too small"), and the run with it."""
    from scipy.integrate import ode

    def oscillator():
        solver = ode(lambda t, y: np.array([y[1], -1e4 * y[0]])).set_integrator("dop853", rtol=1e-9, atol=1e-12)
        caught = []
        simulate_module._stop_at_a_step_when(solver, caught)
        solver.set_initial_value([1.0, 0.0], 0.0)
        return solver, caught

    times = np.linspace(0.0, 0.05, 4)
    solver, caught = oscillator()
    undisturbed = simulate_module._output_times(solver, times, np.array([1.0, 0.0]), None, caught)
    handled = []
    solver, caught = oscillator()
    caught.append((10, None, lambda signum, frame: handled.append(signum)))
    states = simulate_module._output_times(solver, times, np.array([1.0, 0.0]), None, caught)
    assert handled == [10]
    np.testing.assert_allclose(states, undisturbed, rtol=1e-7, atol=1e-9)
    assert np.allclose(states[:, 0], np.cos(100.0 * times), atol=1e-7)
