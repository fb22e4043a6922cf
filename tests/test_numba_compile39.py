"""numba's first compilation of the simulation kernels, shorter (issue 27 §3): each compiled
function numba builds is optimised and translated to machine code again inside every compiled
caller, so ``rhs`` is compiled once, inlined in ``rhs_flat`` (called from Python through it), and
the functions only compiled code calls get no wrappers for calls from Python. The numbers stay
the plain (numpy) kernels' to round-off."""

from __future__ import annotations

import importlib
import importlib.util
import textwrap
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.simulation import _kernels
from rotordyn_modal.simulation._system import system_arrays

numba = pytest.importorskip("numba")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

#: a caller and a helper only compiled code calls
KERNELS = textwrap.dedent('''
    import numpy as np


    def outer(x):
        return inner(x) + 2.0 * x[0]


    def inner(x):
        total = 0.0
        for value in x:
            total += np.cos(value)
        return total
''')


def _module(folder: Path):
    path = folder / "kernels39.py"
    path.write_text(KERNELS)
    spec = importlib.util.spec_from_file_location("kernels39", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_function_only_compiled_code_calls_has_no_python_wrapper_and_gives_the_plain_number(tmp_path,
                                                                                               monkeypatch):
    from rotordyn_modal.simulation._jit import compile_together

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    kernels = _module(tmp_path)
    namespace = compile_together([kernels.outer, kernels.inner], {"np": np}, kernels.__name__, internal=("inner",))
    x = np.linspace(0.1, 2.0, 9)
    expected = float(np.sum(np.cos(x)) + 2.0 * x[0])          # numpy directly, not the kernel
    assert namespace["outer"](x) == pytest.approx(expected, rel=1e-14)
    assert namespace["inner"].targetoptions["no_cpython_wrapper"] is True
    assert "no_cpython_wrapper" not in namespace["outer"].targetoptions or \
        namespace["outer"].targetoptions["no_cpython_wrapper"] is False


@pytest.mark.parametrize("example", ["counter_rotating", "fan_on_bearings"])
def test_the_compiled_rhs_called_from_python_is_rhs_flats_and_the_plain_one_to_round_off(example):
    """``kn.rhs`` (the static equilibrium's and the linearisation's) goes through ``rhs_flat``: numba
    compiles the right-hand side once. Checked against the readable numpy kernel at random states,
    both drives."""
    simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")
    kn = simulate_module.kernels("numba")
    assert not hasattr(kn.rhs, "signatures")                 # a Python function, not a numba dispatcher
    system = system_arrays(rdm.load_model(EXAMPLES / f"{example}.toml"))
    plain = _kernels.plain_namespace()
    rng = np.random.default_rng(39)
    for extra in ((_kernels.FREE, 0.0, 0.0, 0.0), (_kernels.PRESCRIBED, 7.0, 0.0, 1.0)):
        for _ in range(3):
            y = rng.normal(size=2 * system.n_dof) * 0.01
            y[-1] = 100.0
            expected = plain.rhs(0.5, y, *system.kernel_arguments(), *extra)
            np.testing.assert_allclose(kn.rhs(0.5, y, *system.kernel_arguments(), *extra), expected, rtol=1e-10,
                                       atol=1e-10 * np.abs(expected).max())
