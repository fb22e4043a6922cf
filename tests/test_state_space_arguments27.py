"""``Model.state_space(speed, ...)``, the Python contract's state-space model
(shared spec, python-api.md), refuses what it cannot build in the package's own words.

Before: a speed of NaN or infinity gave a system of NaN matrices without a word, ``None`` or a
list a ``TypeError`` of ``float()``; a model with sensors but no excitation (or ``inputs=[]``)
died inside python-control (``ControlDimension: Incompatible dimensions of D matrix; expected
(1, 0) but found (0, 0)``): python-control has no system of outputs without inputs.
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

BLOCK = """\
name = "block on springs"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"

[stator]
mass = 100.0
inertia = [10.0, 10.0, 10.0]

[[rotors]]
name = "r"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.01
diametral_inertia = 0.01
speed_ratio = 1.0

[[suspensions]]
name = "s"
position = [0.0, 0.0, 0.0]
stiffness = [[1e5, 0, 0, 0, 0, 0], [0, 1e5, 0, 0, 0, 0], [0, 0, 1e5, 0, 0, 0],
             [0, 0, 0, 1e4, 0, 0], [0, 0, 0, 0, 1e4, 0], [0, 0, 0, 0, 0, 1e4]]

[[sensors]]
name = "z"
position = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
"""

HAMMER = """
[[excitations]]
name = "Fz"
position = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
"""


@pytest.fixture
def block(tmp_path):
    path = tmp_path / "block.toml"
    path.write_text(BLOCK + HAMMER)
    return rdm.load_model(path)


@pytest.mark.parametrize("speed, shown", [(np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf"), ("100", "'100'"),
                                          (None, "None"), ([1.0, 2.0], "[1.0, 2.0]"), (True, "True"),
                                          (1e300, "1e+300")])
def test_a_speed_that_is_not_one_finite_number_is_refused_by_name(block, speed, shown):
    with pytest.raises(InputError, match=r"^speed = " + shown.replace("[", r"\[").replace("]", r"\]")
                       .replace("+", r"\+") + ": expected"):
        block.state_space(speed)


def test_a_good_speed_still_gives_the_mass_on_springs(block):
    """The block (101 kg on 1e5 N/m along z): the pole pair of its vertical mode at
    sqrt(k / m), and the static receptance 1 / k from the hammer to the sensor."""
    system = block.state_space(rdm.rpm(1000))
    poles = system.poles()
    assert np.min(np.abs(np.abs(poles) - np.sqrt(1e5 / 101.0))) < 1e-9 * np.sqrt(1e5 / 101.0)
    assert system.dcgain() == pytest.approx(1 / 1e5, rel=1e-9)


def test_sensors_without_an_excitation_are_refused_in_one_line(tmp_path):
    path = tmp_path / "sensor_only.toml"
    path.write_text(BLOCK)
    model = rdm.load_model(path)
    with pytest.raises(InputError, match=r"no input.*\[\[excitations\]\]") as refused:
        model.state_space(0.0)
    assert "\n" not in str(refused.value) and "sensor_only.toml" in str(refused.value)
    with pytest.raises(InputError, match=r"no input"):
        model.state_space(0.0, outputs=["z"])
    assert model.state_space(0.0, outputs=[]).noutputs == 0            # no output: fine (no input either)


def test_inputs_chosen_empty_with_outputs_is_refused(block):
    with pytest.raises(InputError, match=r"inputs = \[\]: .*no input"):
        block.state_space(0.0, inputs=[])
    assert block.state_space(0.0, outputs=[]).ninputs == 1
