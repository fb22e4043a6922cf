"""``simulate`` on a large machine within the CPU limit: no eigenvector solve for the CPU check (issue 27 §1.9).

The CPU check counts the integrator's fewest steps from the fastest mode the impulse excites
(``_fewest_steps``: the state matrix's eigenvectors, and a solve for the impulse's share of each).
On 500 geared rotors (2,006 coordinates) that and the natural frequencies took about 245 s of
silence before the run. On a large machine an upper bound comes first (ARPACK's largest
``|lambda|`` of the same matrix, 0.3 s there): a check the bound passes, the exact count passes
too. The same machine scaled down: 75 rotors chained by gears (306 coordinates), a hammer on
the casing. The truth: the largest ``|lambda|`` of scipy's dense ``eigvals`` of the state matrix.
"""

from __future__ import annotations

import importlib
import tomllib
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve
from rotordyn_modal.linear_system import speed_linear_form
from rotordyn_modal.simulation._system import system_arrays
from test_large_machine_cli import chained_gear_toml

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")

ROTORS = 75                 # 306 coordinates
SPEED = 100.0               # rad/s of the first rotor
EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "motor_pump_on_mounts.toml"
HAMMER = '\n[[excitations]]\nname = "hammer-z"\nposition = [0.0, 0.3, 0.5]\ndirection = [0.0, 0.0, 1.0]\n'


@pytest.fixture(scope="module")
def model():
    built = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(ROTORS, ROTORS) + HAMMER), source="chain.toml")
    assert built.dofs.n == 306
    return built


def _record(monkeypatch, name, calls=None):
    """``scipy.linalg.<name>``'s calls, recorded in ``calls`` (a new list by default), which is returned.
    ``eig``: also ``_eigensolve.eig``'s, the dense eigen-solution that calls LAPACK itself."""
    calls = [] if calls is None else calls
    for module in (scipy.linalg, _eigensolve) if name == "eig" else (scipy.linalg,):
        original = getattr(module, name)

        def recorded(*args, _original=original, **kwargs):
            calls.append(name)
            return _original(*args, **kwargs)

        monkeypatch.setattr(module, name, recorded)
    return calls


def test_a_large_machine_within_the_limit_with_its_output_times_given_runs_without_a_dense_eigen_solution(
        model, monkeypatch):
    calls = []
    for name in ("eig", "eigvals"):
        calls = _record(monkeypatch, name, calls)
    result = rdm.simulate(model, 1e-3, speed=SPEED, samples=3, impulse="hammer-z", impulse_size=0.01)
    assert calls == []   # main: ['eigvals', 'eig'] (the natural frequencies; the impulse's fastest excited mode)
    assert len(result.time) == 3 and np.isfinite(result.states).all()


@pytest.fixture(scope="module")
def small():
    """The motor and pump on mounts (34 states): the bound and its check need no large machine."""
    return rdm.load_model(EXAMPLE)


@pytest.mark.parametrize("impulse", ["hammer-z", "hub-tap-y"])
def test_the_bound_is_the_largest_root_of_the_dense_solution_raised_by_at_most_the_margin(small, impulse):
    duration = 0.05
    largest = np.abs(scipy.linalg.eigvals(speed_linear_form(small).at(SPEED))).max()
    exact = duration * largest / (2 * 6.77)                 # DOP853's reach, twice (simulate._STEP_REACH)
    bound = simulate_module._most_steps(small, SPEED, duration, impulse)
    assert exact <= bound <= 1.06 * exact
    assert simulate_module._most_steps(small, SPEED, duration, None) == 0.0


@pytest.mark.parametrize("final", [None, 300.0])
def test_the_rate_bound_is_above_the_fastest_rate_by_at_most_the_margin(small, final):
    exact = simulate_module._fastest_rate(small, SPEED, final)
    bound = simulate_module._most_rate(small, SPEED, final)
    largest = np.abs(scipy.linalg.eigvals(speed_linear_form(small).at(0.0))).max()
    assert exact <= bound <= 1.06 * max(largest, SPEED * max(small.speed_ratios.values()), abs(final or 0))


def _checked(small, monkeypatch, bound):
    """The check before compiling, with ``_most_steps`` giving ``bound``: the steps checked with."""
    monkeypatch.setattr(simulate_module, "_most_steps", lambda *args: bound)
    duration, samples = 1e-3, 3
    steps = simulate_module._Bounded(lambda: simulate_module._fewest_steps(small, SPEED, duration, "hammer-z"),
                                     simulate_module._most_steps(small, SPEED, duration, "hammer-z"))
    kn, system = simulate_module.kernels("auto"), system_arrays(small)
    simulate_module._checked_with(lambda: simulate_module._check_cpu_time(
        kn, system, (0, 0.0, 0.0, duration), duration, 1e4, samples, steps.value), steps)
    return steps


def test_a_bound_refused_is_checked_again_with_the_exact_count(small, monkeypatch):
    """A bound far too high (as for a fastest mode the impulse does not excite) refuses; the exact
    count then passes. A bound that passes is kept: no eigenvector solve."""
    calls = _record(monkeypatch, "eig")
    steps = _checked(small, monkeypatch, 1e12)
    assert steps.exact and calls == ["eig"]
    assert steps.value == simulate_module._fewest_steps(small, SPEED, 1e-3, "hammer-z") < 1e6
    calls.clear()
    steps = _checked(small, monkeypatch, 1.0)
    assert not steps.exact and steps.value == 1.0 and calls == []


def test_an_exact_count_over_the_limit_is_refused_with_its_own_line(small, monkeypatch):
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-9")
    with pytest.raises(rdm.InputError, match="this simulation would take at least") as refused:
        _checked(small, monkeypatch, 1e12)
    assert "1e+12" not in str(refused.value)
