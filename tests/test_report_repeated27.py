"""The report's mode-shape table names each mode's 1X critical speed. A symmetric rigid rotor
(m = 10 kg) on two equal bearings of 1e6 N/m radially, one with 2e6 N/m axially, has at
sqrt(2e6 / 10) rad/s (71.18 Hz, 4270.58 rpm on the 1X line) a root of three members: its
backward and forward cylindrical whirl and its axial mode. Each of modes 1, 2 and 3 at the MCS
is one of them, with its own critical speed. Before, all three crossings were given the number
of the first, so the backward mode 1 read "1X critical speed 4271 rpm (the critical-speed
table's mode 3)", the table's forward whirl, and modes 2 and 3 their frequency only."""

from __future__ import annotations

import html
import re

from rotordyn_modal.cli import main

MODEL = """\
name = "symmetric rigid rotor, a triple root"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"

[[rotors]]
name = "r"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.2
diametral_inertia = 0.5
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "r"
position = [0.3, 0.0, 0.0]
stiffness = 1.0e6
axial_stiffness = 2.0e6

[[bearings]]
name = "B"
rotor = "r"
position = [-0.3, 0.0, 0.0]
stiffness = 1.0e6

[[unbalances]]
rotor = "r"
amount = 1.0e-3

[[sensors]]
name = "ry"
rotor = "r"
position = [0.0, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]
"""


def test_each_member_of_a_repeated_root_has_its_own_critical_speed_in_the_report(tmp_path, capsys):
    model = tmp_path / "triple.toml"
    model.write_text(MODEL)
    out = tmp_path / "r.html"
    code = main(["report", str(model), "--standard", "api684", "--mcs", "5000", "--points", "41", "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    text = re.sub(r"<[^>]+>", " ", re.sub(r"<style.*?</style>", "", out.read_text(), flags=re.S))
    text = re.sub(r"\s+", " ", html.unescape(text))
    table = text[text.index("shown because"):text.index("Figure: each coordinate")]
    for number, whirl in ((1, "backward whirl"), (2, "no whirl"), (3, "forward whirl")):
        assert f" {number} 71.176 {whirl} 0 0 1X critical speed 4271 rpm in the window" in table, table
    assert "critical-speed table's mode" not in table, table
