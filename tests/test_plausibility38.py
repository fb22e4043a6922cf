"""The static plausibility lines on journal and table bearings (issue 27 §1.6, issue 29 §1).

* A rotor's sag in its bearings is looked at when some bearing is a journal or a speed table
  (before, one such bearing left the whole machine out): a table at its lowest speed, a pedestal's
  settling on its springs, another rotor's bearings beside journals.
* A journal's given ``load`` is checked against its share of its rotor's weight (the lever rule
  on two bearings, the static solution on more): a load in kN typed as N, or 1000 times too large,
  draws one line.

The expected sags and shares are closed forms: ``W / k`` of springs in parallel, the lever rule,
the two-span continuous beam's reactions 3/16, 10/16, 3/16 of its weight.
"""

from __future__ import annotations

import math
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import ModelWarning
from rotordyn_modal.plausibility import LOAD_FACTOR, SAG_LIMIT, implausible

G = 9.81
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

HEAD = """name = "t"
spin_axis = [1.0, 0.0, 0.0]
gravity = [0.0, 0.0, -9.81]
reference_rotor = "rotor"

[[rotors]]
name = "rotor"
mass = 50.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.5
diametral_inertia = 2.0
"""

JOURNAL = """type = "journal"
diameter = 0.05
length = 0.025
clearance = 5.0e-5
viscosity = 0.02
"""


def _bearing(name, x, body, rotor="rotor", y=0.0):
    return f"""
[[bearings]]
name = "{name}"
rotor = "{rotor}"
position = [{x}, {y}, 0.0]
{body}"""


def _journals(de="", nde="", x_de=0.3, x_nde=-0.3):
    return _bearing("DE", x_de, JOURNAL + de) + _bearing("NDE", x_nde, JOURNAL + nde)


def _lines(tmp_path, text, name="m.toml"):
    """The warning lines of loading ``text`` (every ModelWarning), and the model."""
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = rdm.load_model(path)
    return [str(w.message) for w in caught if issubclass(w.category, ModelWarning)], model


# ------------------------------------------------------------------------------------------
# the sag in the bearings

def test_table_bearings_soft_sag_named(tmp_path):
    """A rotor on two speed tables of 1225 N/m (1225 N/mm meant, typed as N/m): the lever
    rule puts half of 50 kg x 9.81 on each, W / (2 k) = 0.2 m of sag; its mounting mode
    sqrt(2 k / m) / 2 pi = 1.1 Hz is above the mode line's 0.5 Hz, so only the sag tells."""
    k = 1225.0
    table = f"speeds_rpm = [0.0, 3000.0]\nstiffness = [{k}, {k}]\n"
    lines, _ = _lines(tmp_path, HEAD + _bearing("a", 0.3, table) + _bearing("b", -0.3, table))
    expected = 50.0 * G / (2 * k)
    assert expected > SAG_LIMIT and math.sqrt(2 * k / 50.0) / (2 * math.pi) > 0.5
    assert len(lines) == 1, lines
    assert "would sag" in lines[0] and ("[bearings.a]" in lines[0] or "[bearings.b]" in lines[0])
    assert f"{expected:.3g} m" in lines[0]


def test_table_takes_its_lowest_speed(tmp_path):
    """A table soft at its first row only (a table in N/mm is soft at every row; this one stiffens
    with speed): the static sag is the machine's at rest, the first row's."""
    table = "speeds_rpm = [0.0, 3000.0]\nstiffness = [1225.0, 1.0e8]\n"
    lines, _ = _lines(tmp_path, HEAD + _bearing("a", 0.3, table) + _bearing("b", -0.3, table))
    assert len(lines) == 1 and f"{50.0 * G / 2450.0:.3g} m" in lines[0], lines


def test_rotor_on_soft_bearings_beside_a_journal_rotor(tmp_path):
    """A fan on bearings of 490 N/m beside a rotor on journals: 20 kg x 9.81 / 980 = 0.2 m."""
    fan = """
[[rotors]]
name = "fan"
mass = 20.0
center_of_mass = [0.0, 1.0, 0.0]
polar_inertia = 0.2
diametral_inertia = 0.3
speed_ratio = 1.5
"""
    text = HEAD + _journals() + fan + _bearing("fan-a", 0.2, "stiffness = 490.0\n", "fan", 1.0) \
        + _bearing("fan-b", -0.2, "stiffness = 490.0\n", "fan", 1.0)
    lines, _ = _lines(tmp_path, text)
    assert len(lines) == 1, lines
    assert "rotor 'fan' would sag" in lines[0] and f"{20.0 * G / 980.0:.3g} m" in lines[0]


def test_journal_pedestals_soft_sag_named(tmp_path):
    """Journals on pedestals of 5 kg on springs of 1000 N/m (N/mm typed as N/m): each spring
    carries half the rotor and its pedestal, (25 + 5) x 9.81 / 1000 = 0.294 m."""
    pedestal = "pedestal_mass = 5.0\npedestal_stiffness = 1000.0\n"
    lines, _ = _lines(tmp_path, HEAD + _journals(pedestal, pedestal))
    assert len(lines) == 1, lines
    assert "would sag" in lines[0] and "pedestals" in lines[0] and f"{30.0 * G / 1000.0:.3g} m" in lines[0]


def test_journal_pedestals_plausible_quiet(tmp_path):
    """The same pedestals at 1e8 N/m: no line (the films hold the journals within 50 um)."""
    pedestal = "pedestal_mass = 5.0\npedestal_stiffness = 1.0e8\n"
    lines, _ = _lines(tmp_path, HEAD + _journals(pedestal, pedestal))
    assert lines == []


def test_mounts_in_n_per_mm_under_journals_one_line(tmp_path):
    """A casing of 100 kg on four mounts of 30 N/m (3e4 N/mm meant) under a rotor on journals:
    (100 + 50) x 9.81 / (4 x 30) = 12.3 m of sag, named in one line."""
    stator = """
[stator]
mass = 100.0
center_of_mass = [0.0, 0.0, 0.0]
inertia = [5.0, 5.0, 5.0]
"""
    mounts = "".join(f"""
[[suspensions]]
name = "m{i}"
position = [{x}, {y}, -0.3]
stiffness = [30.0, 30.0, 30.0]
""" for i, (x, y) in enumerate([(0.4, 0.3), (0.4, -0.3), (-0.4, 0.3), (-0.4, -0.3)]))
    lines, _ = _lines(tmp_path, HEAD.replace('reference_rotor = "rotor"\n', "") + stator + mounts + _journals())
    assert len(lines) == 1, lines
    assert "the machine would sag" in lines[0] and f"{150.0 * G / 120.0:.3g} m" in lines[0]


# ------------------------------------------------------------------------------------------
# the journal's given load against its weight share

@pytest.mark.parametrize("factor", [1e-3, 1e3])
def test_journal_load_off_its_lever_share(tmp_path, factor):
    """Journals at +0.3 and -0.1 m of the centre of mass: the lever rule gives DE 1/4 and NDE 3/4
    of 490.5 N. DE's load given in kN (x 1e-3) or 1000 times too large: one line naming the file,
    the bearing, the key, the value and the share."""
    share = 50.0 * G * 0.1 / 0.4
    value = share * factor
    lines, _ = _lines(tmp_path, HEAD + _journals(f"load = {value!r}\n", x_nde=-0.1))
    assert len(lines) == 1, lines
    line = lines[0]
    assert line.startswith(f"{tmp_path / 'm.toml'}: [bearings.DE] load = {value:g}:")
    assert f"{share:.4g} N" in line and "lever rule" in line
    assert ("below" in line) == (factor < 1)


def test_journal_loads_right_are_quiet(tmp_path):
    """The lever-rule loads given, and loads within the factor of the share (x 2.5 and / 2.5): no
    line."""
    de, nde = 50.0 * G * 0.1 / 0.4, 50.0 * G * 0.3 / 0.4
    for a, b in [(de, nde), (2.5 * de, nde / 2.5)]:
        lines, _ = _lines(tmp_path, HEAD + _journals(f"load = {a!r}\n", f"load = {b!r}\n", x_nde=-0.1))
        assert lines == []
    assert LOAD_FACTOR == 3.0


def test_journal_load_without_gravity_is_not_compared(tmp_path):
    """Without gravity the given load is the only weight information: taken as it is."""
    text = HEAD.replace("gravity = [0.0, 0.0, -9.81]\n", "") + _journals("load = 0.1\nload_direction = [0, 0, -1]\n",
                                                                         "load = 0.1\nload_direction = [0, 0, -1]\n")
    lines, _ = _lines(tmp_path, text)
    assert not any("load =" in line for line in lines), lines


def test_journal_load_three_journals_static_solution(tmp_path):
    """A rigid rotor on three like journals at -0.3, 0, 0.3 m, its centre of mass in the middle: on
    equal springs each carries a third (beam on springs, closed form). Right loads quiet; the
    middle one in kN named, from the static solution."""
    third = 50.0 * G / 3

    def text(middle):
        return HEAD + _journals(f"load = {third!r}\n", f"load = {third!r}\n") \
            + _bearing("MID", 0.0, JOURNAL + f"load = {middle!r}\n")

    lines, _ = _lines(tmp_path, text(third))
    assert lines == []
    lines, _ = _lines(tmp_path, text(third / 1000))
    assert len(lines) == 1 and "[bearings.MID] load" in lines[0] and "static solution" in lines[0], lines
    assert f"{third:.4g} N" in lines[0]


FLEXIBLE = """name = "beam"
spin_axis = [1.0, 0.0, 0.0]
gravity = [0.0, 0.0, -9.81]

[[materials]]
name = "steel"
density = 7850.0
young_modulus = 2.1e11
poisson_ratio = 0.3

[[rotors]]
name = "shaft"
speed_ratio = 1.0
start = [0.0, 0.0, 0.0]
element_length = 0.1

[[rotors.shaft]]
length = 2.0
outer_diameter = 0.1
material = "steel"
"""


def _flexible_journal(name, at, load):
    return f"""
[[bearings]]
name = "{name}"
rotor = "shaft"
axial_position = {at}
type = "journal"
diameter = 0.1
length = 0.05
clearance = 1.0e-4
viscosity = 0.02
load = {load!r}
"""


def test_flexible_rotor_on_three_journals(tmp_path):
    """A uniform shaft on journals at 0, 1 and 2 m: the two-span continuous beam carries 3/16,
    10/16, 3/16 of its weight (closed form). Those loads given: quiet; the middle one in kN:
    named."""
    weight = 7850.0 * math.pi * 0.05**2 * 2.0 * G
    ends, middle = 3 / 16 * weight, 10 / 16 * weight

    def text(mid):
        return FLEXIBLE + _flexible_journal("A", 0.0, ends) + _flexible_journal("B", 1.0, mid) \
            + _flexible_journal("C", 2.0, ends)

    lines, model = _lines(tmp_path, text(middle))
    assert lines == [], lines
    assert model.dofs.n <= 200
    lines, _ = _lines(tmp_path, text(middle / 1000))
    assert len(lines) == 1 and "[bearings.B] load" in lines[0], lines


def test_geared_rotor_load_not_compared(tmp_path):
    """A rotor in a transmission: its journals carry tooth forces the weight does not tell."""
    pinion = """
[[rotors]]
name = "pinion"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.3]
polar_inertia = 0.05
diametral_inertia = 0.1

[[transmissions]]
type = "gear"
driver = "rotor"
driven = "pinion"
ratio = 2.0
"""
    text = HEAD + _journals("load = 5000.0\n", "load = 5000.0\n") + pinion \
        + _bearing("p-a", 0.2, "stiffness = 1.0e8\n", "pinion").replace("0.0]", "0.3]") \
        + _bearing("p-b", -0.2, "stiffness = 1.0e8\n", "pinion").replace("0.0]", "0.3]")
    lines, _ = _lines(tmp_path, text)
    assert not any("load =" in line for line in lines), lines


def test_implausible_units_us(tmp_path):
    """The share in lbf with units='us'."""
    _, model = _lines(tmp_path, HEAD + _journals("load = 0.1226\n", x_nde=-0.1))
    line = next(line for line in implausible(model, "us") if "load =" in line)
    assert f"{50.0 * G * 0.25 / 4.4482216152605:.4g} lbf" in line


def test_examples_stay_quiet():
    """`check` on every example: nothing on stderr."""
    for path in sorted(EXAMPLES.glob("*.toml")):
        if path.name.endswith(".study.toml"):
            continue
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = rdm.load_model(path)
        assert [str(w.message) for w in caught if issubclass(w.category, ModelWarning)] == [], path.name
        assert implausible(model) == [], path.name


def test_check_cli_one_line(tmp_path):
    """The CLI prints the load line once on stderr, exit 0."""
    path = tmp_path / "m.toml"
    path.write_text(HEAD + _journals("load = 0.1226\n", x_nde=-0.1))
    done = subprocess.run([sys.executable, "-m", "rotordyn_modal", "check", str(path)], capture_output=True,
                          text=True, cwd=Path(__file__).resolve().parent.parent)
    assert done.returncode == 0
    warned = [line for line in done.stderr.splitlines() if "warning" in line]
    assert len(warned) == 1 and "[bearings.DE] load = 0.1226" in warned[0], done.stderr
