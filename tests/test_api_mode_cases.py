"""API 684 unbalance "placed to excite the mode of interest" on flexible rotors: the
``api-mode{k}:ROTOR`` cases of :func:`api_unbalance_cases` (docs/standards.md, "Placement").

Truth from outside the code under test: a uniform Euler-Bernoulli shaft pinned at its ends has
its bending modes ``f_n = n^2 (pi / L)^2 sqrt(E I / (rho A)) / (2 pi)`` with shapes
``sin(n pi z / L)``: the first's one antinode at mid-span, the second's two of opposite sign at the
quarter points. The amounts are API 617's ``Ua = 2 x 6350 m / N`` g mm (``m / 2`` for a couple),
worked here from the shaft's mass ``rho A L``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance_checks import api_mode_placements, api_unbalance_cases
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.model_file import load_model

E, RHO, D, L = 2.0e11, 7800.0, 0.05, 1.0           # steel shaft, 1 m long, 50 mm
AREA, INERTIA = np.pi * D ** 2 / 4, np.pi * D ** 4 / 64
MASS = RHO * AREA * L                               # 15.32 kg
F1 = (np.pi / L) ** 2 * np.sqrt(E * INERTIA / (RHO * AREA)) / (2 * np.pi)   # 99.43 Hz
G_MM = 1e-6                                         # kg m per g mm


def _pinned_shaft(bearing_stiffness=1e12, **rotor):
    """The shaft (20 elements of 50 mm, Euler-Bernoulli) on two stiff isotropic bearings at its ends."""
    return rdm.Model.from_dict({
        "name": "pinned shaft", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": RHO, "young_modulus": E, "poisson_ratio": 0.3}],
        "rotors": [{"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": "none",
                    "shaft": [{"length": L, "outer_diameter": D, "material": "steel", "elements": 20}], **rotor}],
        "bearings": [{"name": n, "rotor": "shaft", "axial_position": z, "stiffness": bearing_stiffness}
                     for n, z in (("A", 0.0), ("B", L))]})


def _amount(mass, rpm):
    return 2 * 6350 * mass / rpm * G_MM


def _stations(case):
    """``(axial_position from the start [m], amount, phase)`` of each unbalance of a case's model."""
    rotor = case.rotors[0]
    centre = float(np.asarray(rotor.center_of_mass, float) @ np.asarray(case.spin_axis, float))
    start = float(rotor.flexible.start @ np.asarray(case.spin_axis, float))
    return sorted((round(centre - start + u.axial_offset, 12), u.amount, u.phase_deg) for u in case.unbalances)


def test_first_bending_mode_one_unbalance_at_mid_span():
    """MCS 1.2 x below f1: f1 within reach 1.3, f2 = 4 f1 not: one mode case, the static amount
    at mid-span (0.5 m, a node)."""
    model = _pinned_shaft()
    assert model.rotors[0].mass == pytest.approx(MASS, rel=1e-12)
    rpm = F1 * 60 / 1.2
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no station between nodes, nothing to warn of
        cases = api_unbalance_cases(model, rdm.rpm(rpm))
    assert [name for name, _ in cases] == ["api-static:shaft", "api-couple:shaft", "api-mode1:shaft"]
    (z, amount, phase), = _stations(dict(cases)["api-mode1:shaft"])
    assert z == pytest.approx(0.5, abs=1e-12)
    assert amount == pytest.approx(_amount(MASS, rpm), rel=1e-12)
    assert phase == 0.0
    (mode,) = api_mode_placements(model, rdm.rpm(rpm))
    assert mode.frequency_hz == pytest.approx(F1, rel=5e-3)     # the mesh's rotary inertia: 0.23 % low
    assert mode.energy_share == pytest.approx(1.0, abs=1e-6)
    # the rigid-rotor cases are kept as they were
    (static,) = dict(cases)["api-static:shaft"].unbalances
    assert static.axial_offset == 0.0 and static.amount == pytest.approx(_amount(MASS, rpm), rel=1e-12)


def test_second_bending_mode_a_couple_at_the_quarter_points():
    """With reach 4.5 at MCS = f1 the second mode (4 f1) is in too: the couple amounts (m / 2) at
    0.25 and 0.75 m, 180 deg apart; the backward/forward pairs give one case each."""
    model = _pinned_shaft()
    rpm = F1 * 60
    cases = dict(api_unbalance_cases(model, rdm.rpm(rpm), reach=4.5))
    assert [n for n in cases if n.startswith("api-mode")] == ["api-mode1:shaft", "api-mode2:shaft"]
    first, second = _stations(cases["api-mode1:shaft"]), _stations(cases["api-mode2:shaft"])
    assert [z for z, _, _ in first] == pytest.approx([0.5], abs=1e-12)
    assert [z for z, _, _ in second] == pytest.approx([0.25, 0.75], abs=1e-12)
    assert [a for _, a, _ in second] == pytest.approx([_amount(MASS / 2, rpm)] * 2, rel=1e-12)
    assert [p for _, _, p in second] == [0.0, 180.0]
    modes = api_mode_placements(model, rdm.rpm(rpm), reach=4.5)
    assert [m.frequency_hz for m in modes] == pytest.approx([F1, 4 * F1], rel=1e-2)
    # the deflection lines are the sines (nodes every 50 mm)
    z = modes[0].position
    for n, mode in enumerate(modes, start=1):
        line = np.sin(n * np.pi * z / L)
        line = line * np.sign(mode.deflection @ line)       # the second's two antinodes tie: either sign
        np.testing.assert_allclose(mode.deflection, line, atol=2e-3)


def test_reach_keeps_modes_out():
    """Reach 1.3 at MCS = f1 / 1.4: f1 is above 1.3 x 1X, so no mode case."""
    model = _pinned_shaft()
    cases = api_unbalance_cases(model, rdm.rpm(F1 * 60 / 1.4))
    assert [n for n, _ in cases] == ["api-static:shaft", "api-couple:shaft"]
    assert api_mode_placements(model, rdm.rpm(F1 * 60 / 1.4), reach=1.5)      # and in with a larger reach


def test_overhung_disk_mode_at_the_disk():
    """A shaft on bearings at 0 and 0.6 m with a 30 kg disk overhung at its end (1 m): the first
    mode's largest deflection is at the disk: the static amount there."""
    model = _pinned_shaft(bearing_stiffness=1e9,
                          disks=[{"name": "disk", "axial_position": L, "mass": 30.0, "polar_inertia": 0.3,
                                  "diametral_inertia": 0.15}])
    data = model.to_dict()
    data["bearings"][1]["axial_position"] = 0.6
    model = rdm.Model.from_dict(data)
    mass = MASS + 30.0
    first = api_mode_placements(model, rdm.rpm(3000.0), reach=100.0)[0]
    rpm = first.frequency_hz * 60                                        # 1X at that mode
    cases = dict(api_unbalance_cases(model, rdm.rpm(rpm)))
    (z, amount, phase), = _stations(cases["api-mode1:shaft"])
    assert z == pytest.approx(L, abs=1e-12)
    assert amount == pytest.approx(_amount(mass, rpm), rel=1e-12)
    assert np.argmax(np.abs(first.deflection)) == len(first.deflection) - 1


def test_rigid_rotors_keep_their_cases():
    """Rigid rotors (examples/motor_pump_on_mounts.toml: two, the pump at 1.25 x) get exactly the
    static case at the centre of mass and the couple at the outermost bearing planes, no mode case."""
    model = load_model("examples/motor_pump_on_mounts.toml")
    mcs_rpm = 3000.0
    cases = api_unbalance_cases(model, rdm.rpm(mcs_rpm), reach=100.0)
    expected = []
    for rotor in model.rotors:
        expected += [f"api-static:{rotor.name}", f"api-couple:{rotor.name}"]
    assert [n for n, _ in cases] == expected
    e = np.asarray(model.spin_axis, float)
    for name, case in cases:
        rotor = model.rotor(name.split(":")[1])
        n = abs(rotor.speed_ratio) * mcs_rpm
        if name.startswith("api-static"):
            (u,) = case.unbalances
            assert (u.axial_offset, u.amount) == (0.0, pytest.approx(_amount(rotor.mass, n), rel=1e-12))
        else:
            planes = sorted(float((np.asarray(b.position, float) - rotor.center_of_mass) @ e)
                            for b in model.bearings_of(rotor.name))
            got = sorted((u.axial_offset, u.phase_deg) for u in case.unbalances)
            assert got == [(pytest.approx(planes[0]), 0.0), (pytest.approx(planes[-1]), 180.0)]
            assert [u.amount for u in case.unbalances] == pytest.approx([_amount(rotor.mass / 2, n)] * 2)


def test_reach_refused_when_negative():
    with pytest.raises(InputError, match="reach"):
        api_mode_placements(_pinned_shaft(), rdm.rpm(3000.0), reach=-1.0)


def test_cli_prints_the_mode_case(capsys):
    """``unbalance examples/compressor_rotor.toml --api-unbalance --mcs 9000``: its first bending
    mode (94 Hz; 1X 150 Hz, reach 195 Hz) gets api-mode1:compressor in every table (response,
    peaks, checks, clearance); its conical mode (219 Hz) is beyond reach."""
    code = main(["unbalance", "examples/compressor_rotor.toml", "--speeds", "200:13500:12", "--mcs", "9000",
                 "--api-unbalance"])
    out = capsys.readouterr().out
    assert code == 0
    assert "api-static:compressor" in out and "api-couple:compressor" in out
    assert "api-mode1:compressor" in out and "api-mode2:compressor" not in out
    checks = out[out.index("scale_factor"):]           # the clearance table (its heading on stderr)
    assert "api-mode1:compressor" in checks


@pytest.mark.parametrize("route", ["basis", "sparse"])
def test_a_larger_model_places_as_the_full_solution(monkeypatch, route):
    """Above 400 coordinates the modes come from a basis of the symmetric parts' lowest modes
    (dense, or sparse shift-invert above the sparse size): the same cases as the full state
    solution, frequencies to 1e-4 (the basis: 2e-5 here), on a 120-element shaft with an overhung disk and cross-coupled
    bearings (so that K is not symmetric)."""
    from rotordyn_modal import assembly
    from rotordyn_modal.analysis import unbalance_checks

    def model():
        data = _pinned_shaft(disks=[{"name": "disk", "axial_position": L, "mass": 30.0, "polar_inertia": 0.3,
                                     "diametral_inertia": 0.15}]).to_dict()
        data["rotors"][0]["shaft"][0]["elements"] = 120
        data["bearings"] = [{"name": n, "rotor": "shaft", "axial_position": z,
                             "stiffness": [[1e8, 2e7], [-2e7, 1.5e8]]} for n, z in (("A", 0.0), ("B", 0.6))]
        return rdm.Model.from_dict(data)

    mcs = rdm.rpm(9000.0)
    reduced_model = model()
    assert reduced_model.dofs.n > unbalance_checks._FULL_STATES_DOF
    if route == "sparse":
        monkeypatch.setattr(assembly, "SPARSE_DOF", 100)
        assert assembly.is_large(reduced_model)
    reduced = api_mode_placements(reduced_model, mcs, reach=3.0)
    monkeypatch.setattr(assembly, "SPARSE_DOF", 2500)
    monkeypatch.setattr(unbalance_checks, "_FULL_STATES_DOF", 10 ** 6)
    full = api_mode_placements(model(), mcs, reach=3.0)
    assert len(full) >= 2
    assert [(p.stations, p.phases_deg) for p in reduced] == [(p.stations, p.phases_deg) for p in full]
    assert [p.frequency_hz for p in reduced] == pytest.approx([p.frequency_hz for p in full], rel=1e-4)


def test_report_shows_and_counts_the_mode_case(tmp_path):
    """An API 684 report of the pinned shaft (10 elements, damped 1e8 N/m bearings) at 5400 rpm
    (1X 90 Hz, the first mode at ~97 Hz within 1.3 x): the work estimate counts three cases
    (static, couple, api-mode1), and the page shows api-mode1:shaft with the placement text."""
    from rotordyn_modal.report.collect import _api_cases

    data = _pinned_shaft(bearing_stiffness=1e8).to_dict()
    data["rotors"][0]["shaft"][0]["elements"] = 10
    for bearing in data["bearings"]:
        bearing["damping"] = 2e3
    model = rdm.Model.from_dict(data)
    assert _api_cases(model, rdm.rpm(5400.0)) == 3 == len(api_unbalance_cases(model, rdm.rpm(5400.0)))
    path = tmp_path / "shaft.toml"
    rdm.save_model(model, path)
    out = tmp_path / "r.html"
    assert main(["report", str(path), "--standard", "api684", "--mcs", "5400", "--out", str(out), "--quiet"]) == 0
    page = out.read_text()
    assert "api-mode1:shaft" in page and "api-mode2:shaft" not in page
    assert "api-mode1, api-mode2, ... for each lateral mode up to 1.3 x its 1X frequency" in page



def test_mode_frequencies_are_the_modal_analysis_of_the_undamped_machine():
    """Without damping the modes of interest are rdm.modal's at the MCS (its frequencies to 1e-9):
    an overhung disk (gyroscopic split of the backward and forward pairs) on anisotropic bearings;
    each pair (and each plane) gives one case, the lower frequency's."""
    data = _pinned_shaft(disks=[{"name": "disk", "axial_position": L, "mass": 30.0, "polar_inertia": 0.6,
                                 "diametral_inertia": 0.3}]).to_dict()
    data["bearings"] = [{"name": n, "rotor": "shaft", "axial_position": z, "stiffness": [[2e8, 0.0], [0.0, 1e8]]}
                        for n, z in (("A", 0.0), ("B", 0.6))]
    model = rdm.Model.from_dict(data)
    mcs = rdm.rpm(6000.0)
    placements = api_mode_placements(model, mcs, reach=3.0)
    modal = rdm.modal(model, mcs)
    frequencies = modal.frequencies_hz[modal.oscillatory]
    assert len(placements) >= 2
    for p in placements:
        assert np.min(np.abs(frequencies - p.frequency_hz)) < 1e-9 * p.frequency_hz
    lateral = [f for f in frequencies if f <= 3.0 * 100.0]
    assert len(lateral) > len(placements)            # pairs and planes taken once
