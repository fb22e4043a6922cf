"""API 617 Level I screening (``level1``): the log decrement against applied cross-coupling of a
rigid rotor against the closed form of its cylindrical whirl, Q0 in closed form, the applied
cross-coupling against the same stiffness given as a bearing, and the anticipated
cross-coupling Qa against a worked example and the standard's US-unit constant."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.level1 import Station, anticipated_cross_coupling, level1
from rotordyn_modal.analysis.modal import modal
from rotordyn_modal.cli import main

MASS, IP, ID, SPAN, K, C = 20.0, 0.1, 0.5, 0.4, 1e6, 200.0     # kg, kg m^2, kg m^2, m, N/m, N s/m


def _rotor(extra=()):
    """A symmetric rigid rotor on two equal isotropic bearings (stiffness K, damping C) at
    +-SPAN, no stator: its cylindrical modes (lowest) decouple from the conical ones."""
    bearings = [dict(name=n, rotor="r", position=[x, 0.0, 0.0], stiffness=K, damping=C)
                for n, x in (("A", SPAN), ("B", -SPAN))]
    return rdm.Model(rotors=[rdm.Rotor("r", MASS, [0.0, 0.0, 0.0], IP, ID, speed_ratio=1.0)],
                     bearings=bearings + list(extra))


def _closed_form_log_dec(q):
    """The cylindrical whirl z = u_a + i u_b (a x b = the spin axis) with Q at the centre of mass:
    the force Q (-u_b, u_a) is i Q z, so m z'' + 2 C z' + 2 K z - i Q z = 0, whose root with
    Im s > 0 whirls forward; log decrement -2 pi Re s / Im s."""
    out = []
    for value in np.atleast_1d(q):
        roots = np.roots([MASS, 2 * C, 2 * K - 1j * value])
        s = roots[roots.imag > 0][0]
        out.append(-2 * np.pi * s.real / s.imag)
    return np.array(out)


@pytest.mark.parametrize("speed_rpm", [3000.0, -3000.0])
def test_log_decrement_against_q_is_the_closed_form(speed_rpm):
    """Every point of the sweep, and Q0 = 2 C sqrt(2K/m) (where s = i w: -m w^2 + 2 K = 0 and
    2 C w = Q), to 1e-9; with the spin reversed the cross-coupling follows it (forward whirl is
    then the other way) and the result is the same."""
    q0 = 2 * C * np.sqrt(2 * K / MASS)
    result = level1(_rotor(), rdm.rpm(speed_rpm), ["r"], qa=q0 / 3)
    np.testing.assert_allclose(result.log_decrements, _closed_form_log_dec(result.cross_coupling), rtol=1e-9,
                               atol=1e-12)
    assert result.q0 == pytest.approx(q0, rel=1e-9)
    assert result.ratio == pytest.approx(3.0, rel=1e-9)
    assert result.log_decrement_at_qa == pytest.approx(_closed_form_log_dec(q0 / 3)[0], rel=1e-9)
    assert result.mode in (1, 2) and result.passes_ratio     # forward and backward cylindrical: one frequency


def test_verdict_follows_both_criteria():
    q0 = 2 * C * np.sqrt(2 * K / MASS)
    delta = _closed_form_log_dec(0.0)[0]                           # 0.226 at Q = 0
    passing = level1(_rotor(), rdm.rpm(3000), ["r"], qa=q0 / 5)
    assert passing.passes_log_decrement and passing.passes_ratio and not passing.level2_required
    assert "Level II not required" in passing.verdict()
    close = level1(_rotor(), rdm.rpm(3000), ["r"], qa=q0 / 1.5)   # Q0/Qa = 1.5 < 2
    assert close.level2_required and not close.passes_ratio and "Level II required" in close.verdict()
    assert delta > 0.1
    odd = level1(_rotor(), rdm.rpm(3000), ["r"], qa=1e4, factor=2.55)   # Qa a point of any sweep
    assert odd.cross_coupling[10] == 1e4 and odd.cross_coupling[-1] == pytest.approx(2.6e4, rel=1e-15)


def test_offset_stations_equal_the_same_stiffness_given_as_a_bearing():
    """Q at two stations off the centre (shares 0.3, 0.7) couples the conical modes: the log
    decrement of the followed mode at 4 Qa equals that of ``modal`` for the model carrying the
    same cross-coupling as two extra bearings of stiffness [[0, q], [-q, 0]] (k_ab = +q in the
    bearings' radial axes a, b = spin axis x a)."""
    qa = 2e4
    stations = [Station("r", 0.25), Station.parse("r@-0.1")]
    result = level1(_rotor(), rdm.rpm(4000), stations, qa=qa, shares=[0.3, 0.7])
    q = 4 * qa
    extra = [dict(name=f"Q{i}", rotor="r", position=[offset, 0.0, 0.0],
                  stiffness=[[0.0, share * q], [-share * q, 0.0]])
             for i, (offset, share) in enumerate(((0.25, 0.3), (-0.1, 0.7)))]
    roots = modal(_rotor(extra), rdm.rpm(4000))
    followed = result.frequencies_hz[40]
    nearest = int(np.argmin(np.abs(roots.frequencies_hz - followed)))
    assert roots.frequencies_hz[nearest] == pytest.approx(followed, rel=1e-9)
    assert roots.log_decrements[nearest] == pytest.approx(result.log_decrements[40], rel=1e-8)
    assert roots.whirl[nearest] == "forward"


def test_anticipated_cross_coupling_reproduces_a_worked_example():
    """ROSS (petrobras/ross, ``Report.stability_level_1``, API 684 SP6.8.5.6) documents two
    compressor impellers of D = 0.35 m, H = 0.08 m, 10 kW each, density ratios 1.11 and 1.14 at
    1000 rpm: Qa = 23022.32142857143 N/m with C = 9.55 (the rounded 60 / 2 pi of q = B C P /
    (D H N) rho_d / rho_s). Here T = P / Omega exactly, so 9.5493 / 9.55 of it."""
    q = anticipated_cross_coupling([10e3, 10e3], rdm.rpm(1000), [0.35, 0.35], [0.08, 0.08], [1.11, 1.14])
    assert q.sum() * 9.55 / (30 / np.pi) == pytest.approx(23022.32142857143, rel=1e-12)


def test_anticipated_cross_coupling_reproduces_ross_tests_compressor_and_turbine():
    """ROSS's own tests of its Level I (petrobras/ross commit 03f22ea9c21445f6ccaea73990d4f517bcacf02c,
    ``ross/tests/test_api_report.py::test_stability_level1``, lines 305-341, removed from ROSS in
    August 2020 with ``ross/api_report.py``): two compressor impellers D = 0.28 / 0.35 m, H = 0.07 m,
    6 / 8 kW, density ratios 1.11 / 1.14 at 1000 rpm give Qa = 20399.969387755104 N/m; the turbine
    rotor of the same file has one stage among its disks (the first: D = 0.28 m, H = 0.07 m, 6 kW,
    B = 1.5, no density ratio): Qa = 4385.204081632653 N/m. ROSS's C = 9.55, here 60 / 2 pi."""
    rounded = 9.55 / (30 / np.pi)
    compressor = anticipated_cross_coupling([6e3, 8e3], rdm.rpm(1000), [0.28, 0.35], [0.07, 0.07], [1.11, 1.14])
    assert compressor.sum() * rounded == pytest.approx(20399.969387755104, rel=1e-12)
    turbine = anticipated_cross_coupling([6e3], rdm.rpm(1000), [0.28], [0.07], machine="turbine")
    assert turbine.sum() * rounded == pytest.approx(4385.204081632653, rel=1e-12)


def test_the_us_constant_63_is_the_same_formula():
    """API's US form q = B 63 HP / (D H N) [klbf/in, HP, in, rpm]: 63 is the torque of 1 hp at
    1 rpm in klbf in (63,025 lbf in); the SI formula gives it to 0.04 %."""
    hp, inch, klbf_per_in = 745.6998715822702, 0.0254, 4448.2216152605 / 0.0254
    q = anticipated_cross_coupling([hp], rdm.rpm(1.0), [inch], [inch], [1.0])[0] / klbf_per_in
    assert q == pytest.approx(3 * 63.0, rel=5e-4)
    assert anticipated_cross_coupling([hp], rdm.rpm(1.0), [inch], [inch], [2.0], machine="turbine")[0] \
        == pytest.approx(q * klbf_per_in / 2, rel=1e-12)            # B = 1.5, no density ratio


def test_the_standards_si_form_in_millimetres_and_kn_per_mm():
    """API 617 (2014) as transcribed in ross-rotordynamics/ross-report ``report/standard_text.py``:
    HP the rated power per impeller in N m/s, C = 9.55, D and H in mm, N in rpm, q_a in kN/mm.
    A 2.5 MW impeller of 0.6 m x 25 mm at 9000 rpm, density ratio 1.3: the standard's number
    in kN/mm is the package's in N/m / 1e6, but for C = 9.55 against 60 / 2 pi (0.0074 %)."""
    power, d_mm, h_mm, n_rpm, ratio = 2.5e6, 600.0, 25.0, 9000.0, 1.3
    standard_kn_per_mm = power * 3 * 9.55 * ratio / (d_mm * h_mm * n_rpm)           # 0.1655 kN/mm
    q = anticipated_cross_coupling([power], rdm.rpm(n_rpm), [d_mm / 1e3], [h_mm / 1e3], [ratio])[0]
    assert q * 9.55 / (30 / np.pi) / 1e6 == pytest.approx(standard_kn_per_mm, rel=1e-12)
    assert q / 1e6 == pytest.approx(standard_kn_per_mm, rel=1e-4)


def test_refusals():
    model = _rotor()
    for kwargs, words in (({"stations": ["nope"], "qa": 1e4}, "no rotor"), ({"stations": ["r"], "qa": 0.0}, "qa"),
                          ({"stations": ["r@x"], "qa": 1e4}, "ROTOR@OFFSET"), ({"stations": [], "qa": 1e4}, "no station")):
        with pytest.raises(rdm.InputError, match=words):
            level1(model, rdm.rpm(3000), **kwargs)
    with pytest.raises(rdm.InputError, match="speed = 0"):
        level1(model, 0.0, ["r"], qa=1e4)
    with pytest.raises(rdm.InputError, match="power"):
        anticipated_cross_coupling([-1.0], 100.0, [0.3], [0.02])


def test_command_line(tmp_path, capsys):
    out, plot = tmp_path / "l1.csv", tmp_path / "l1.png"
    code = main(["level1", "examples/journal_rotor.toml", "--speed", "4000", "--station", "rotor",
                 "--power", "50e3,40e3", "--impeller-diameter", "0.3", "--restriction-height", "0.02",
                 "--density-ratio", "1.2,1.3", "--out", str(out), "--plot", str(plot)])
    assert code == 0 and plot.stat().st_size > 0
    assert out.read_text().splitlines()[0] == "q_n_per_m,q_over_qa,log_decrement,frequency_hz"
    qa = anticipated_cross_coupling([50e3, 40e3], rdm.rpm(4000), [0.3, 0.3], [0.02, 0.02], [1.2, 1.3]).sum()
    assert f"Qa = {qa:.6g} N/m" in capsys.readouterr().err
    assert main(["level1", "examples/journal_rotor.toml", "--speed", "4000", "--station", "rotor"]) == 2
    assert main(["level1", "examples/journal_rotor.toml", "--speed", "4000", "--station", "rotor",
                 "--qa", "1e4", "--power", "1e3"]) == 2


def test_the_followed_mode_is_the_rotors_not_a_casing_mode_on_soft_mounts():
    """With the bearings in a heavy casing on soft mounts the casing's modes (a few Hz) whirl
    too, but barely move the rotor in its bearings: the followed mode is the rotor's cylindrical
    mode, within 1 % of the rotor's on rigid pedestals (its damped frequency), not a mount mode."""
    casing = dict(stator=rdm.Stator(mass=2000.0, inertia=[300.0, 400.0, 400.0]),
                  suspensions=[rdm.Suspension(f"m{i}", [x, y, -0.5], [2e5, 2e5, 4e5])
                               for i, (x, y) in enumerate([(0.6, 0.5), (0.6, -0.5), (-0.6, 0.5), (-0.6, -0.5)])])
    rotor = _rotor()
    model = rdm.Model(rotors=rotor.rotors, bearings=rotor.to_dict()["bearings"], **casing)
    result = level1(model, rdm.rpm(3000), ["r"], qa=1e4)
    wn, zeta = np.sqrt(2 * K / MASS), 2 * C / (2 * np.sqrt(2 * K * MASS))
    assert result.frequencies_hz[0] == pytest.approx(wn * np.sqrt(1 - zeta**2) / (2 * np.pi), rel=1e-2)


def test_a_flexible_rotors_station_equals_the_same_stiffness_given_as_a_bearing_there():
    """A flexible shaft with an impeller disk between damped anisotropic bearings, Q at
    the impeller (its offset from the shaft's computed centre of mass): every point of the sweep's
    followed mode equals ``modal`` of the model carrying that Q as an extra bearing at the
    impeller's axial position (stiffness [[0, q], [-q, 0]] in the bearings' radial axes), by
    frequency and log decrement; a station 0.1 m off the impeller gives another answer (the
    station reaches its own node of the mesh)."""
    steel = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}

    def model(extra=()):
        return rdm.Model.from_dict({
            "spin_axis": [1.0, 0.0, 0.0], "materials": [steel],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                        "shaft": [{"length": 0.8, "outer_diameter": 0.05, "material": "steel", "elements": 8}],
                        "disks": [{"name": "imp", "axial_position": 0.5, "mass": 12.0, "polar_inertia": 0.06,
                                   "diametral_inertia": 0.035}]}],
            "bearings": [{"name": "A", "rotor": "s", "axial_position": 0.05, "stiffness": [2e7, 3e7],
                          "damping": [2e3, 2.5e3]},
                         {"name": "B", "rotor": "s", "axial_position": 0.75, "stiffness": 2.5e7, "damping": 2e3},
                         *extra]})

    base, speed = model(), rdm.rpm(6000)
    centre = base.rotors[0].center_of_mass[0]
    sweep = dict(qa=2e4, factor=4.0, steps_per_qa=2)            # Q = 0, 1e4, ..., 8e4 N/m
    result = level1(base, speed, [Station("s", 0.5 - centre)], **sweep)
    other = level1(base, speed, [Station("s", 0.4 - centre)], **sweep)
    assert abs(other.log_decrements[-1] / result.log_decrements[-1] - 1) > 1e-3
    for i in (0, 4, 8):
        q = result.cross_coupling[i]
        roots = modal(model([{"name": "Q", "rotor": "s", "axial_position": 0.5, "stiffness": [[0.0, q], [-q, 0.0]]}]),
                      speed)
        nearest = int(np.argmin(np.abs(roots.frequencies_hz - result.frequencies_hz[i])))
        assert roots.frequencies_hz[nearest] == pytest.approx(result.frequencies_hz[i], rel=1e-9)
        assert roots.log_decrements[nearest] == pytest.approx(result.log_decrements[i], rel=1e-8)
        assert roots.whirl[nearest] == "forward"
