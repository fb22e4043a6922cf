"""Issue 29: an undamped resonance's unbalance peak stands at its exact critical speed.

examples/spring_block_rotor.toml has no damping. Its AF table put the unbounded peak at a swept
speed (119.2 rpm at the report's 152 speeds, 100 rpm at 61 speeds), with N1 = N2 that speed and
the swept amplitude, and the report's figure labelled it "AF inf near 119 rpm", while its 1X
critical speeds are 103.85 (backward) and 106.65 rpm (forward). Now the peak stands where the
response is unbounded, the forward 1X critical speed, found exactly; its amplitude is inf.

Truth from outside the code:

- the rigid disk (m, Id, Ip) whose centre of mass is l from a block of springs (radial k, tilt
  kt) whirling in a circle at w = s Omega (s = +1 forward, -1 backward) with complex coordinates
  (translation r, tilt phi): ``[[k - m w^2, -k l], [-k l, k l^2 + kt - Id w^2 + Ip Omega w]]``,
  by hand. The 1X critical speeds are the roots of its determinant in ``u = Omega^2`` (numpy
  roots); the forward one is excited, and the response to an unbalance U at the centre of mass
  is ``r = U Omega^2 a22 / det`` of the forward matrix (w = Omega), which has no pole at the
  backward one (an unbalance of a rotor on isotropic supports excites forward whirl only);
- a damped example's peak: the state-space model of the machine (A, B, C of ``state_space``,
  no unbalance code) driven by the unbalance's rotating force at its stations, solved densely
  at the table's peak speed and beside it.
"""

from __future__ import annotations

import dataclasses
import importlib
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import api_unbalance_response
from rotordyn_modal.cli.main import main

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
collect_module = importlib.import_module("rotordyn_modal.report.collect")
render = importlib.import_module("rotordyn_modal.report.render")
RPM = np.pi / 30

# examples/spring_block_rotor.toml, written out
M, ID, IP, L, K, KT = 5.0, 0.078125, 0.15625, 0.75, 2000.0, 500.0


def _crossings(sense):
    """The 1X critical speeds [rad/s] of whirl ``sense`` (+1 forward, -1 backward), increasing:
    ``(K - M u)(K L^2 + KT + (sense IP - ID) u) - (K L)^2 = 0`` in ``u = Omega^2``."""
    poly = np.polymul([-M, K], [sense * IP - ID, K * L * L + KT])
    poly[-1] -= (K * L) ** 2
    u = np.roots(poly)
    return np.sort(np.sqrt(u[(np.abs(u.imag) == 0) & (u.real > 0)].real))


FORWARD = _crossings(+1)
BACKWARD = _crossings(-1)


def test_the_hand_crossings_are_those_of_the_spring_block():
    """One forward 1X crossing (the disk's polar inertia is twice its diametral one: the conical
    forward mode stiffens faster than the 1X line) and two backward ones, 103.85 and 811.13 rpm."""
    assert len(FORWARD) == 1 and len(BACKWARD) == 2
    np.testing.assert_allclose(FORWARD / RPM, [106.648], atol=5e-4)
    np.testing.assert_allclose(BACKWARD / RPM, [103.851, 811.132], atol=5e-4)


def _spring_block(tmp_path, amount=1e-4):
    """The example with an unbalance ``amount`` [kg m] at the disk's centre of mass."""
    path = tmp_path / "spring_block.toml"
    path.write_text((EXAMPLES / "spring_block_rotor.toml").read_text()
                    + f'\n[[unbalances]]\nrotor = "disk"\namount = {amount!r}\n')
    return rdm.load_model(path)


@pytest.mark.parametrize("points", [61, 152, 400])
def test_the_undamped_peak_stands_at_the_forward_critical_speed(points):
    """Whatever the swept speeds, the API static case's one peak per sensor is at the forward 1X
    critical speed to 1e-9, its amplitude and AF inf, its half-power points at that speed
    (main: 100, 119.2 and 105 rpm, read off the sweep)."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = api_unbalance_response(model, np.linspace(0.0, 3000.0, points) * RPM, 3000.0 * RPM)
    table = result.peaks()
    assert sorted(table["output"]) == ["disk-centre-y", "disk-centre-z"]
    np.testing.assert_allclose(table["speed_rpm"], FORWARD[0] / RPM, rtol=1e-9)
    assert np.all(np.isposinf(table["amplitude"])) and np.all(np.isposinf(table["amplification_factor"]))
    half_power = result.peak_half_power[np.isfinite(result.peak_half_power)]
    np.testing.assert_allclose(half_power, FORWARD[0], rtol=1e-9)


def test_the_backward_crossing_is_not_excited(tmp_path):
    """The response near the backward 1X critical speed (103.85 rpm) is the forward whirl's alone,
    finite: the analysis' amplitude there equals the hand forward model's to 1e-7 (a pole at
    103.85 rpm would make it grow as 1/distance). A sweep that resolves both crossings (0.5 rpm
    steps, 2.8 rpm apart) has one peak per sensor, the forward one's."""
    model = _spring_block(tmp_path)
    u = 1e-4
    near = BACKWARD[0] * (1 + np.array([-1e-3, -1e-6, -1e-9, 1e-9, 1e-6, 1e-3]))
    speeds = np.concatenate([near, FORWARD[0] * np.array([0.5, 0.99, 1.01, 2.0])])
    forward = np.array([[[K - M * s ** 2, -K * L], [-K * L, K * L * L + KT + (IP - ID) * s ** 2]] for s in speeds])
    by_hand = np.abs(np.linalg.solve(forward, np.stack([u * speeds ** 2, 0 * speeds], axis=1)[..., None])[:, 0, 0])
    result = rdm.unbalance_response(model, speeds)
    for name in ("disk-centre-y", "disk-centre-z"):
        np.testing.assert_allclose(result.amplitude[result.outputs.index(name), 0], by_hand, rtol=1e-7)

    table = rdm.unbalance_response(model, np.linspace(0.0, 300.0, 601) * RPM).peaks()
    assert len(table) == 2
    np.testing.assert_allclose(table["speed_rpm"], FORWARD[0] / RPM, rtol=1e-9)
    assert np.all(np.isposinf(table["amplitude"]))


def test_anisotropic_supports_excite_both_crossings_each_at_its_speed(tmp_path):
    """The block's radial stiffness made 2000 N/m along y and 2600 N/m along z: the unbalance
    excites both 1X crossings below 300 rpm (104.72 and 109.62 rpm). Each sensor reports both,
    unbounded, at the crossings of the hand model to 1e-9, also where the sweep (every 5 rpm)
    puts both between two of its speeds (main: one swept peak per sensor, at a swept speed).
    The hand model in (y, z, theta_y, theta_z) at the centre of mass: ``K`` of the springs at l,
    ``M = diag(m, m, Id, Id)``, ``G`` the spin's (``Ip`` between the tilts); at 1X (w = Omega)
    ``det(K - u (M - i G)) = 0``, ``u = Omega^2``, a generalized eigenproblem."""
    import scipy.linalg

    ky, kz = 2000.0, 2600.0
    stiffness = np.array([[ky, 0, 0, -ky * L], [0, kz, kz * L, 0], [0, kz * L, kz * L * L + KT, 0],
                          [-ky * L, 0, 0, ky * L * L + KT]])
    gyroscopic = np.zeros((4, 4))
    gyroscopic[2, 3], gyroscopic[3, 2] = IP, -IP
    u = scipy.linalg.eigvals(stiffness, np.diag([M, M, ID, ID]) - 1j * gyroscopic)
    crossings = np.sort(np.sqrt(u[u.real > 0].real))
    crossings = crossings[crossings < 300.0 * RPM]
    assert len(crossings) == 2

    path = tmp_path / "anisotropic.toml"
    path.write_text((EXAMPLES / "spring_block_rotor.toml").read_text().replace(
        "\nstiffness = 2000.0 ", f"\nstiffness = [{ky}, {kz}] ") + '\n[[unbalances]]\nrotor = "disk"\namount = 1e-4\n')
    model = rdm.load_model(path)
    for points in (61, 601):
        table = rdm.unbalance_response(model, np.linspace(0.0, 300.0, points) * RPM).peaks()
        for name in ("disk-centre-y", "disk-centre-z"):
            mine = table[(table["output"] == name) & np.isposinf(table["amplitude"])]
            np.testing.assert_allclose(mine["speed_rpm"], crossings / RPM, rtol=1e-9)
            assert np.all(np.isposinf(mine["amplification_factor"]))


def test_the_cli_says_the_response_is_unbounded(tmp_path, capsys):
    """``unbalance``'s peaks table prints the critical speed (6 digits) and amplitude inf, and one
    line says what inf means."""
    assert main(["unbalance", str(EXAMPLES / "spring_block_rotor.toml"), "--speeds", "0:3000:61", "--api-unbalance",
                 "--mcs", "1000", "--out", str(tmp_path / "u.csv")]) == 0
    said = capsys.readouterr()
    err = said.out + said.err
    rows = [line.split() for line in err.splitlines() if line.startswith("disk-centre") and "api-static" in line
            and len(line.split()) >= 8]
    peaks = [row for row in rows if row[2] == f"{FORWARD[0] / RPM:.6g}"]
    assert len(peaks) == 2 and all(row[3] == "inf" and row[4] == "inf" for row in peaks), rows
    assert sum(line.startswith("amplitude inf, AF inf: the response is unbounded") for line in err.splitlines()) == 1


def _report(units, path=EXAMPLES / "spring_block_rotor.toml"):
    """``(html, figures)`` of the api684 report of the model file ``path`` (spring_block_rotor's),
    Campbell and unbalance sections."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    inputs = collect_module.ReportInputs("api684", 3000.0 * RPM)
    figures = []
    original = render.figure_png

    def kept(fig, dpi=110):
        figures.append(fig)
        uri = original(fig, dpi)
        FigureCanvasAgg(fig)
        fig.canvas.draw()
        return uri

    sections = ("campbell", "unbalance")
    with pytest.MonkeyPatch.context() as mp:
        mp.setitem(collect_module.STANDARDS, "api684", sections)
        mp.setattr(render, "figure_png", kept)
        data = collect_module.collect(rdm.load_model(path), inputs)
        html = render.render_html(dataclasses.replace(data, sections=sections), units=units)
    return html, figures


@pytest.mark.parametrize("units", ["si", "us"])
def test_the_report_shows_the_critical_speed_and_an_unbounded_response(units):
    """The AF table's rows read the forward critical speed and 'unbounded' (with the note saying
    why and that the backward critical speed has no peak); the figure's label reads 'AF inf at
    107 rpm', its point at that speed (main: 'AF inf near 119 rpm', 119.2 rpm)."""
    html, figures = _report(units)
    speed = f"{FORWARD[0] / RPM:.6g}"
    table = html[html.index('id="margins"'):]
    assert table.count(f">{speed}<") == 2 and table.count("unbounded\u2020") == 2
    assert "excites forward whirl only" in table
    labels = [t for fig in figures for ax in fig.axes for t in ax.texts if t.get_text().startswith("AF inf")]
    assert len(labels) == 1
    assert labels[0].get_text().startswith(f"AF inf at {FORWARD[0] / RPM:.0f} rpm (1X api-static:disk)\n"
                                           "response unbounded")
    assert labels[0].xy[0] == pytest.approx(FORWARD[0] / RPM, rel=1e-12)


def test_an_unbounded_peak_fails_the_probe_limit_and_says_so(tmp_path):
    """The spring block's two sensors made proximity probes (measure = "relative"): the forward
    critical speed (106.648 rpm) lies below the MCS (3000 rpm) and the response there is
    unbounded, so each probe fails the API 617 limit there, its value 'unbounded' (main: twice
    the swept top read at 119.2 rpm)."""
    path = tmp_path / "probes.toml"
    path.write_text((EXAMPLES / "spring_block_rotor.toml").read_text().replace(
        "direction = [0.0, 0.0, 1.0]", 'direction = [0.0, 0.0, 1.0]\nmeasure = "relative"').replace(
        "direction = [0.0, 1.0, 0.0]", 'direction = [0.0, 1.0, 0.0]\nmeasure = "relative"'))
    html, _ = _report("si", path)
    section = html[html.index("<h3>API 617 probe vibration limit</h3>"):]
    section = section[:section.index("<h3", 10)]
    speed = f"{FORWARD[0] / RPM:.6g}"
    assert section.count(f">{speed}<") == 2 and section.count(">unbounded<") == 2 and section.count(">fail<") == 2
    assert "where the response is unbounded (an undamped mode&#x27;s critical speed)" in html


def _state_space_response(path, speed, stations, rotor):
    """The sensors' complex amplitudes (model order) at ``speed`` [rad/s] of the unbalances
    ``stations`` (``[(amount [kg m], axial_position [m], phase [deg])]`` on the flexible ``rotor``
    of the model file ``path``) solved densely on the machine's state-space model: each unbalance
    a force ``U Omega^2`` turning with the rotor about the spin axis (+x here: ``(F_y, F_z) = U
    Omega^2 e^{i phase} (1, -i)``) at its station (two [[excitations]] added to the file)."""
    text = path.read_text()
    names = []
    for k, (_, position, _) in enumerate(stations):
        for axis, direction in (("y", "[0.0, 1.0, 0.0]"), ("z", "[0.0, 0.0, 1.0]")):
            names.append(f"unb35-{k}-{axis}")
            text += (f'\n[[excitations]]\nname = "{names[-1]}"\nrotor = "{rotor}"\naxial_position = {position!r}\n'
                     f"direction = {direction}\n")
    excited = path.with_name("excited.toml")
    excited.write_text(text)
    system = rdm.state_space(rdm.load_model(excited), speed, inputs=names)
    a, b, c = (np.asarray(x) for x in (system.A, system.B, system.C))
    force = np.concatenate([amount * speed ** 2 * np.exp(1j * np.radians(phase)) * np.array([1.0, -1.0j])
                            for amount, _, phase in stations])
    return c @ np.linalg.solve(1j * speed * np.eye(a.shape[0]) - a, b @ force)


#: examples/compressor_rotor.toml's [[unbalances]], written out: (amount, axial_position, phase_deg)
COMPRESSOR_UNBALANCES = [(2.0e-4, 0.30, 0.0), (2.0e-4, 0.84, 180.0)]


def test_a_damped_peak_is_the_maximum_of_an_independent_solve(tmp_path):
    """examples/compressor_rotor.toml (damped): each peak of the AF table is the response of the
    dense state-space solve at the table's speed (to 1e-7), and a maximum of it (the solve 1e-4
    beside it on either side is lower); its AF finite. Nothing of it changed (unb35)."""
    path = tmp_path / "compressor.toml"
    path.write_text((EXAMPLES / "compressor_rotor.toml").read_text())
    model = rdm.load_model(path)
    table = rdm.unbalance_response(model, np.linspace(500.0, 12000.0, 47) * RPM).peaks()
    assert len(table) >= 4 and np.all(np.isfinite(table["amplification_factor"]))
    names = [s.name for s in model.sensors]
    for row in table.itertuples():
        speed = row.speed_rpm * RPM
        at = [np.abs(_state_space_response(path, s, COMPRESSOR_UNBALANCES, "compressor"))[names.index(row.output)]
              for s in (speed * (1 - 1e-4), speed, speed * (1 + 1e-4))]
        assert row.amplitude == pytest.approx(at[1], rel=1e-7)
        assert at[1] > max(at[0], at[2])
