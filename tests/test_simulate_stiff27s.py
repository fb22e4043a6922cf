"""The stiff casing hit by its hammer (issue 27 §1.3): ``simulate`` with the compiled kernel runs
it to the end, as the numpy backend does, instead of a ZeroDivisionError (API) or DOP853's
"the problem became stiff" (command line, exit 1).

The machine (``tests/degenerate_models.py``): a 100 kg casing of inertia [10, 10, 1.1e-11] kg m^2
about a 10 kg rotor on bearings of 1e6 N/m, under gravity, no damping. The casing's 1.1e-11 kg m^2
against the bearings' 8e4 N m/rad about z is a 13.7 MHz mode, which holds DOP853's steps at the
edge of their stability region. Two causes, both in the compiled path only:

* Each output time restarts Hairer's DOP853 with its own first-step guess; on this machine the
  first trial step after 50 us reached a stage state 1e9 rad away, where the mass matrix is not
  positive definite in double precision: the Cholesky pivot was 0 (ZeroDivisionError; a negative
  one gave NaN, which DOP853 rejects and retries). Now every pivot that is not > 0 gives NaN.
* Hairer's stiffness test stopped the run with code -4 after 32 us; ``solve_ivp``'s DOP853 (the
  numpy backend) has none and ran the same command to the end. Now it is switched off.

Truth from outside the code: the conservation of energy (no damping; the drive holds a speed the
motion hardly loads: the numpy backend keeps it to 2.7e-12), and the motion in the x-z plane, which
the casing's inertia about z hardly enters (the same run with 1 kg m^2 there).
"""

from __future__ import annotations

import re
import tomllib

import numpy as np
import pytest

import rotordyn_modal as rdm
from degenerate_models import variant
from rotordyn_modal.cli import main

pytest.importorskip("numba")

SPEED = 100.0                   # rad/s
DURATION = 1e-4                 # s: 1,370 periods of the 13.7 MHz mode


def _text(about_z="1.1e-11"):
    return variant(stator_mass="100.0", rotor_mass="10.0", stator_inertia=f"[10.0, 10.0, {about_z}]")


def _run(inertia, size):
    model = rdm.Model.from_dict(tomllib.loads(_text(inertia)), source="stiff.toml")
    with rdm.long_work_allowed():
        result = rdm.simulate(model, DURATION, speed=SPEED, impulse="hammer", impulse_size=size, samples=3,
                              backend="numba")
    return model, result


def test_the_api_runs_the_hammered_stiff_casing_to_its_end():
    """Impulse 1e-3 N s along -z: ZeroDivisionError in ``_fast._solve_spd`` on main. The hammer
    pitches the casing about y and drops the machine; the 1.1e-11 kg m^2 about z hardly takes part:
    the casing's and the rotor's motions in x-z agree with those of a casing of 1 kg m^2 about z,
    and the energy is kept."""
    model, stiff = _run("1.1e-11", 1e-3)
    _, plain = _run("1.0", 1e-3)
    assert np.isfinite(stiff.states).all()
    energy = stiff.kinetic_energy + stiff.elastic_energy + stiff.gravity_energy
    assert abs(energy[-1] / energy[0] - 1) < 1e-9
    for name in ("stator.uz", "stator.ry", "r.uz", "r.ry"):
        j = model.dofs.names.index(name)
        assert stiff.states[-1, j] == pytest.approx(plain.states[-1, j], rel=1e-6), name


def test_the_command_line_runs_it_to_its_end(tmp_path, capsys):
    """The default impulse of 1 N s: exit 1, 'integration failed ... the problem became stiff' on
    main; now exit 0, the output written, the energy kept (the numpy backend prints 2.68e-12)."""
    path, out = tmp_path / "stiff.toml", tmp_path / "s.csv"
    path.write_text(_text(), encoding="utf-8")
    # 955 rpm: at 100 rad/s exactly main's stiffness test happened to let this run through
    code = main(["simulate", str(path), "--speed", "955", "--duration", repr(DURATION),
                 "--excitation", "hammer", "--samples", "3", "--backend", "numba", "--allow-long",
                 "--out", str(out)])
    printed = capsys.readouterr()
    assert code == 0, printed.err
    assert out.exists()
    change = float(re.search(r"relative change of total energy ([0-9.e+-]+)", printed.out + printed.err)[1])
    assert abs(change) < 1e-9
