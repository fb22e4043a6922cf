"""The analyses' Python entry points refuse bad numeric arguments before any work, with an
InputError that names the argument, shows the value and says what was expected (issue 27
§1.10): no silent NaN results, no string read as a number, no numpy error without a name."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError


@pytest.fixture(scope="module")
def model(request):
    from pathlib import Path

    return rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml")


SPEEDS = [0.0, 50.0, 100.0]
FREQS = [1.0, 2.0]

# (call, argument name, what the message must say)
_CASES = {
    "modal: a string speed": (lambda m: rdm.modal(m, "3000"), "speed = '3000'", "one finite number"),
    "modal: NaN": (lambda m: rdm.modal(m, math.nan), "speed = nan", "one finite number"),
    "modal: inf": (lambda m: rdm.modal(m, math.inf), "speed = inf", "one finite number"),
    "modal: an array": (lambda m: rdm.modal(m, [1.0, 2.0]), "speed = [1.0, 2.0]", "shape (2,)"),
    "modal: a boolean": (lambda m: rdm.modal(m, True), "speed = True", "one finite number"),
    "frf: NaN speed": (lambda m: rdm.frf(m, math.nan, FREQS), "speed = nan", "one finite number"),
    "frf: 2-D frequencies": (lambda m: rdm.frf(m, 0.0, [[1.0, 2.0], [3.0, 4.0]]), "freqs_hz = [[1.0, 2.0], [3.0, 4.0]]",
                             "got shape (2, 2)"),
    "frf: no frequencies": (lambda m: rdm.frf(m, 0.0, []), "freqs_hz = []", "non-empty"),
    "frf: inf frequency": (lambda m: rdm.frf(m, 0.0, [1.0, math.inf]), "freqs_hz = [1.0, inf]", "element 1 is inf"),
    "frf: negative frequency": (lambda m: rdm.frf(m, 0.0, [1.0, -2.0]), "freqs_hz = [1.0, -2.0]",
                                "element 1 is -2.0"),
    "frf: string frequencies": (lambda m: rdm.frf(m, 0.0, ["1", "2"]), "freqs_hz = ['1', '2']", "finite numbers"),
    "force_frf: string speed": (lambda m: rdm.force_frf(m, "fast", FREQS), "speed = 'fast'", "one finite number"),
    "force_frf: NaN frequency": (lambda m: rdm.force_frf(m, 0.0, [math.nan]), "freqs_hz = [nan]", "element 0 is nan"),
    "critical_speeds: NaN": (lambda m: rdm.critical_speeds(m, [0.0, math.nan, 3.0]), "speeds = [0.0, nan, 3.0]",
                             "element 1 is nan"),
    "critical_speeds: decreasing": (lambda m: rdm.critical_speeds(m, [0.0, 3.0, 1.0]), "speeds = [0.0, 3.0, 1.0]",
                                    "strictly increasing"),
    "critical_speeds: 2-D": (lambda m: rdm.critical_speeds(m, np.zeros((2, 2))), "speeds = [[0.0, 0.0], [0.0, 0.0]]", "shape (2, 2)"),
    "critical_speeds: string": (lambda m: rdm.critical_speeds(m, "0:100:3"), "speeds = '0:100:3'", "finite numbers"),
    "critical_speeds: negative order": (lambda m: rdm.critical_speeds(m, SPEEDS, orders=(1, -2)), "orders = (1, -2)",
                                        "numbers > 0"),
    "critical_speeds: NaN order": (lambda m: rdm.critical_speeds(m, SPEEDS, orders=[math.nan]), "orders = [nan]",
                                   "finite numbers"),
    "critical_speeds: string orders": (lambda m: rdm.critical_speeds(m, SPEEDS, orders="1,2"), "orders = '1,2'",
                                       "finite numbers"),
    "campbell: empty": (lambda m: rdm.campbell(m, []), "speeds = []", "non-empty"),
    "stability: inf": (lambda m: rdm.stability(m, [0.0, math.inf]), "speeds = [0.0, inf]", "element 1 is inf"),
    "unbalance_response: NaN": (lambda m: rdm.unbalance_response(m, [0.0, math.nan]), "speeds = [0.0, nan]",
                                "element 1 is nan"),
    "unbalance_response: empty": (lambda m: rdm.unbalance_response(m, []), "speeds = []", "non-empty"),
    "unbalance_response: booleans": (lambda m: rdm.unbalance_response(m, [True, False]), "speeds = [True, False]",
                                     "finite numbers"),
    "unbalance_response: 2-D": (lambda m: rdm.unbalance_response(m, [[1.0], [2.0]]), "speeds = [[1.0], [2.0]]",
                                "shape (2, 1)"),
}


@pytest.mark.parametrize("case", list(_CASES))
def test_a_bad_argument_is_refused_by_name(model, case):
    call, named, expected = _CASES[case]
    with pytest.raises(InputError) as info:
        call(model)
    message = str(info.value)
    assert named in message and expected in message and "\n" not in message


def test_good_arguments_keep_working(model):
    """Integers, numpy scalars and tuples are numbers; a scalar speed sweep is one speed."""
    assert rdm.modal(model, np.float64(10.0)).speed == rdm.modal(model, 10).speed == 10.0
    assert rdm.unbalance_response(model, 100.0).speeds.shape == (1,)
    assert rdm.frf(model, 0, (1, 2)).frequencies_hz.tolist() == [1.0, 2.0]
    assert len(rdm.campbell(model, SPEEDS, orders=()).critical.to_dataframe()) == 0


def test_frequencies_keep_their_documented_message(model):
    with pytest.raises(InputError, match=re.escape("frequencies: expected a 1-D array of finite values >= 0 Hz")):
        rdm.frf(model, 0.0, [1.0, -2.0])


@pytest.fixture(scope="module")
def flexible():
    from pathlib import Path

    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "flexible_pump_on_mounts.toml")
    return model, rdm.modal(model, 100.0)


# the drawing entry points (redteam44): a count of 10**7 points per element asked for the machine's
# whole memory (the process was killed), -3 and 2.5 failed inside numpy, a NaN mode in int(), and a
# NaN scale drew a shape of NaN motions without a word
_DRAWING_CASES = {
    "shaft_lines: too many points per element": (lambda m, r: rdm.shaft_lines(r, m, 1, points_per_element=5000),
                                                 "points_per_element = 5000", "a whole number from 0 to 1000"),
    "shaft_lines: negative points": (lambda m, r: rdm.shaft_lines(r, m, 1, points_per_element=-3),
                                     "points_per_element = -3", "a whole number"),
    "shaft_lines: fractional points": (lambda m, r: rdm.shaft_lines(r, m, 1, points_per_element=2.5),
                                       "points_per_element = 2.5", "a whole number"),
    "shaft_lines: NaN mode": (lambda m, r: rdm.shaft_lines(r, m, math.nan), "mode nan", "a mode number from 1"),
    "mode_shape_3d: NaN scale": (lambda m, r: rdm.mode_shape_3d(r, m, 1, scale=math.nan), "scale = nan",
                                 "one finite number"),
    "mode_shape_3d: inf scale": (lambda m, r: rdm.mode_shape_3d(r, m, 1, scale=math.inf), "scale = inf",
                                 "one finite number"),
}


@pytest.mark.parametrize("case", list(_DRAWING_CASES))
def test_a_bad_drawing_argument_is_refused_by_name(flexible, case):
    call, named, expected = _DRAWING_CASES[case]
    with pytest.raises(InputError) as info:
        call(*flexible)
    message = str(info.value)
    assert named in message and expected in message and "\n" not in message


def test_drawing_arguments_that_are_whole_numbers_keep_working(flexible):
    """0 points per element draws the nodes only: each element's left node and the shaft's end;
    a whole float or a numpy integer is a mode number."""
    model, result = flexible
    nodes = len(model.rotors[1].flexible.node_positions)
    line = next(line for line in rdm.shaft_lines(result, model, 1, points_per_element=0).lines if line.flexible)
    assert len(line.position) == nodes
    assert rdm.shaft_lines(result, model, np.int64(2)).mode == rdm.shaft_lines(result, model, 2.0).mode == 2
    assert rdm.mode_shape_3d(result, model, 1, scale=0.1).scale == 0.1
