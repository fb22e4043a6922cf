"""API 617 Level I's sweep is refused, before its arrays are made, where they cannot fit.

The sweep holds every value of Q's state matrix and shapes at once. 500 geared rotors (4,012
states, about 150 values of Q) took 21.9 GB and were killed by the system after 102 s, with
nothing on the screen. The memory counted on is set here by ``ROTORDYN_MODAL_MEMORY_GB``.
"""

from __future__ import annotations

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError


def _rotor_on_bearings():
    return rdm.Model(rotors=[rdm.Rotor("r", 20.0, [0.0, 0.0, 0.0], 0.1, 0.5, speed_ratio=1.0)],
                     bearings=[dict(name=n, rotor="r", position=[x, 0.0, 0.0], stiffness=1e6, damping=200.0)
                               for n, x in (("A", 0.4), ("B", -0.4))])


def test_a_sweep_that_cannot_fit_is_refused_with_its_size(monkeypatch):
    """With 1 kB to count on, the sweep (at least 101 values of Q of the states' squared size) is
    refused by name, with its estimate and the memory available."""
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1e-6")
    with pytest.raises(InputError, match=r"an API 617 Level I sweep of \d+ coordinates at \d+ values of Q needs "
                                         r"about [0-9.]+ GiB of memory, 0\.0+ GiB is available"):
        rdm.level1(_rotor_on_bearings(), rdm.rpm(3000), ["r"], qa=2.0e6)


def test_the_command_refuses_it_in_one_line_exit_2(monkeypatch, tmp_path, capsys):
    """``level1`` on the command line: exit 2 and one line naming the model file."""
    path = tmp_path / "rotor.toml"
    path.write_text('spin_axis = [1.0, 0.0, 0.0]\nreference_rotor = "r"\n[stator]\nmass = 10.0\n'
                    'center_of_mass = [0.0, 0.0, 0.0]\ninertia = [1.0, 1.0, 1.0]\n[[rotors]]\nname = "r"\nmass = 20.0\n'
                    'center_of_mass = [0.0, 0.0, 0.0]\npolar_inertia = 0.1\ndiametral_inertia = 0.5\nspeed_ratio = 1.0\n'
                    + "".join(f'[[bearings]]\nname = "{n}"\nrotor = "r"\nposition = [{x}, 0.0, 0.0]\n'
                              'stiffness = 1.0e6\ndamping = 200.0\n' for n, x in (("A", 0.4), ("B", -0.4))))
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1e-6")
    assert main(["level1", str(path), "--mcs", "3000", "--station", "r", "--qa", "2e6"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0] and "Level I sweep" in err[0], err


def test_a_sweep_that_fits_runs(monkeypatch):
    """The same sweep with 1 GB to count on runs as before."""
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1")
    result = rdm.level1(_rotor_on_bearings(), rdm.rpm(3000), ["r"], qa=2.0e6)
    assert result.swept
