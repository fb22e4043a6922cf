"""numba's first compilation of the simulation kernels, one compiled root (issue 27 §3, session 40).

numba builds every compiled function again into the machine code of each compiled caller above
it. ``rhs_flat`` (the right-hand side) and ``sample_outputs`` (each output time's energies, drive
torque, angular velocity and bearing forces) were two roots, each holding ``assemble_into`` and the
solve. ``rhs_flat`` now makes both (a count of output times in its integer arguments), and the
compiled namespace's ``sample_outputs`` packs its arguments and calls it. The numbers stay the
readable numpy kernels' to round-off.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.simulation import _fast
from rotordyn_modal.simulation._kernels import plain_namespace
from rotordyn_modal.simulation._system import system_arrays

numba = pytest.importorskip("numba")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _states(system, count, seed):
    """``count`` random states (count, 2 n) near rest, the reference rotor spinning, and their times."""
    rng = np.random.default_rng(seed)
    states = rng.normal(size=(count, 2 * system.n_dof)) * 0.05
    states[:, -1] = 300.0
    return np.linspace(0.1, 1.5, count), states


@pytest.mark.parametrize("example", ["counter_rotating", "fan_on_bearings", "journal_rotor"])
def test_the_compiled_outputs_are_made_by_rhs_flat_and_agree_with_numpy(example):
    """One compiled root: ``kn.sample_outputs`` is not a numba function of its own but goes through
    ``rhs_flat`` (one signature for the right-hand side and the outputs), and gives the readable
    numpy kernels' outputs, free and driven (a ramp from 0.2 s to 1 s)."""
    from rotordyn_modal.simulation.simulate import kernels

    kn = kernels("numba")
    assert not hasattr(kn.sample_outputs, "signatures")      # a Python function, not a dispatcher
    system = system_arrays(rdm.load_model(EXAMPLES / f"{example}.toml"))
    times, states = _states(system, 5, 11)
    for mode in (0, 1):
        arguments = system.kernel_arguments() + (mode, 7.0, 0.2, 1.0)
        plain = plain_namespace().sample_outputs(times, states, *arguments)
        compiled = kn.sample_outputs(times, states, *arguments)
        assert [np.shape(a) for a in compiled] == [np.shape(a) for a in plain]
        for a, b in zip(plain, compiled):
            np.testing.assert_allclose(b, a, rtol=1e-10, atol=1e-10 * np.abs(a).max(initial=1.0))
        y = states[2]
        np.testing.assert_allclose(kn.rhs(0.5, y, *arguments), plain_namespace().rhs(0.5, y, *arguments),
                                   rtol=1e-10, atol=1e-10)
    assert len(kn.rhs_flat.signatures) == 1


def test_each_output_time_is_its_own():
    """The outputs of several states in one call are those of each state alone, to the bit (the
    loop keeps nothing from one output time to the next): the plain Python path of ``rhs_flat``."""
    system = system_arrays(rdm.load_model(EXAMPLES / "fan_on_bearings.toml"))
    times, states = _states(system, 4, 3)
    arguments = system.kernel_arguments() + (1, 7.0, 0.2, 1.0)
    together = _fast.sample_outputs(times, states, *arguments)
    for s in range(len(times)):
        alone = _fast.sample_outputs(times[s:s + 1], states[s:s + 1], *arguments)
        for a, b in zip(together, alone):
            assert np.array_equal(a[s], b[0])
