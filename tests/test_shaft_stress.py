"""Stresses along flexible shafts (``static``): the bending stress, the torsional shear stress of
a transmitted torque and their von Mises combination against closed forms of beams written out
here (a simply supported uniform tube under its own weight, an overhung shaft with a tip disk,
a belt-driven shaft carrying a torque), the verdict against the material's ``allowable_stress``
or ``--allowable-stress``, in SI and US customary units, on the command line and in the report.

The closed forms: ``sigma = M c / I`` with ``c = D / 2`` and ``I = pi (D^4 - d^4) / 64``;
``tau = T c / J`` with ``J = 2 I``; von Mises ``sqrt(sigma^2 + 3 tau^2)``. The moments are the
beams' own (statics of the free bodies, not the code's moment arrays): a simply supported
span under its weight ``w L^2 / 8`` at mid-span, an overhang of length ``b`` with its weight and
a tip load ``P`` ``P b + w b^2 / 2`` over its support, a pulley's pull ``F`` on an overhang
``a`` ``F a`` over the bearing. Tolerances: see tests/test_static_shafts.py (cubic elements are
exact at the nodes; round-off of the stiff bearings ~1e-10)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from test_static_shafts import E, NU, RHO, TIGHT, _at, _belt_data, _section

G = 9.81
PSI = 4.4482216152605 / 0.0254 ** 2          # Pa per psi (lbf / in^2)
LBF_IN = 4.4482216152605 * 0.0254            # N m per lbf in


def _data(length, supports, disks=(), d=0.05, inner=0.0, allowable=None, n=8):
    """A uniform steel tube of ``length`` along x on stiff bearings at ``supports``, under
    gravity along -z, with disks ``(z, mass)``; its material's ``allowable_stress`` [Pa]."""
    material = {"name": "steel", "density": RHO, "young_modulus": E, "poisson_ratio": NU}
    if allowable is not None:
        material["allowable_stress"] = allowable
    return {
        "spin_axis": [1.0, 0.0, 0.0], "gravity": [0.0, 0.0, -G], "materials": [material],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "shear": "none",
                    "element_length": length / n,
                    "shaft": [{"length": length, "outer_diameter": d, "inner_diameter": inner, "material": "steel"}],
                    "disks": [{"name": f"d{i}", "axial_position": z, "mass": m, "polar_inertia": 1e-3,
                               "diametral_inertia": 1e-3} for i, (z, m) in enumerate(disks)]}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "stiffness": 1e12}
                     for i, z in enumerate(supports)],
    }


def _write(tmp_path, data, name="shaft.toml"):
    """``data`` as a model file (TOML written by hand: tables of numbers and strings)."""
    import tomli_w

    path = tmp_path / name
    path.write_bytes(tomli_w.dumps(data).encode())
    return path


# -- closed forms ------------------------------------------------------------------------------------
@pytest.mark.parametrize("allowable, verdict", [(None, "not evaluated"), (50e6, "pass"), (1e6, "fail")])
def test_simply_supported_tube_under_its_weight(allowable, verdict):
    """M_max = w L^2 / 8 at mid-span, sigma = M_max (D/2) / I, no torque: von Mises = sigma; the
    verdict against the material's allowable_stress (5.28 MPa here)."""
    length, d, inner = 2.0, 0.05, 0.02
    shaft = rdm.static(rdm.Model.from_dict(_data(length, (0.0, length), d=d, inner=inner,
                                                 allowable=allowable))).shafts["s"]
    _, second, w = _section(d, inner)
    sigma = w * length ** 2 / 8 * (d / 2) / second
    check = shaft.stress_check()
    assert check.von_mises == pytest.approx(sigma, rel=TIGHT)
    assert check.position == pytest.approx(length / 2, abs=1e-12) and check.label == "n4"
    assert check.torque == 0.0 and check.shear == 0.0
    assert check.verdict == verdict
    if allowable is not None:
        assert check.allowable == allowable and check.utilization == pytest.approx(sigma / allowable, rel=TIGHT)
    else:
        assert np.isnan(check.allowable) and np.isnan(check.utilization)
    np.testing.assert_allclose(shaft.von_mises, shaft.stress, rtol=1e-15)      # bending alone


def test_overhung_shaft_with_a_tip_disk():
    """Supports at 0 and a, an overhang b to a tip disk P: over the second support the moment is
    P b + w b^2 / 2 (the free body of the overhang), the largest of the shaft; the von Mises
    stress there is M (D/2) / I."""
    a, b, mass, d = 0.6, 0.4, 5.0, 0.04
    shaft = rdm.static(rdm.Model.from_dict(_data(a + b, (0.0, a), disks=((a + b, mass),), d=d, n=10))).shafts["s"]
    _, second, w = _section(d)
    moment = mass * G * b + w * b ** 2 / 2
    check = shaft.stress_check()
    assert check.von_mises == pytest.approx(moment * (d / 2) / second, rel=TIGHT)
    assert check.position == pytest.approx(a, abs=1e-12)
    assert shaft.von_mises[_at(shaft, a + b)] == pytest.approx(0.0, abs=1e-9 * check.von_mises)   # free end


def test_a_transmitted_torque_adds_its_shear_stress():
    """A belt (pretension 400 N, pulley radius 0.1 m) passing 50 N m to a 50 mm shaft (bearings
    at 0.1 and 0.7 m, pulley at 0.9 m, its centre of mass, where its coupling takes the torque,
    at 0.55 m: the node at 0.5 m): the shaft carries T = 50 N m between the coupling and the
    pulley, none elsewhere; tau = 16 T / (pi D^3); over the outer bearing M = 800 N x 0.2 m and
    von Mises sqrt(sigma^2 + 3 tau^2), the shaft's largest."""
    data = _belt_data([0.9, 0.0, 0.0])
    data["transmissions"][0]["driver_radius"] = 0.1
    data["materials"][0]["allowable_stress"] = 20e6
    torque, d = 50.0, 0.05
    shaft = rdm.static(rdm.Model.from_dict(data), speed=100.0, torques=torque).shafts["s"]
    carrying = (shaft.z > 0.5 + 1e-9) | ((shaft.z == 0.5) & (shaft.side == "right"))
    carrying &= (shaft.z < 0.9 - 1e-9) | ((shaft.z == 0.9) & (shaft.side == "left"))
    np.testing.assert_allclose(np.abs(shaft.torque), np.where(carrying, torque, 0.0), rtol=1e-12, atol=1e-12)
    tau = 16 * torque / (np.pi * d ** 3)
    np.testing.assert_allclose(shaft.shear_stress, np.where(carrying, tau, 0.0), rtol=1e-12, atol=1e-6)
    second = np.pi * d ** 4 / 64
    sigma = 800.0 * 0.2 * (d / 2) / second
    check = shaft.stress_check()
    assert (check.label, check.position) == ("n7", pytest.approx(0.7, abs=1e-12))      # both sides alike
    assert check.von_mises == pytest.approx(np.sqrt(sigma ** 2 + 3 * tau ** 2), rel=TIGHT)
    assert check.verdict == "pass" and check.utilization == pytest.approx(check.von_mises / 20e6, rel=1e-12)
    override = rdm.static(rdm.Model.from_dict(data), speed=100.0, torques=torque, allowable_stress=10e6)
    assert override.stress_checks()[0].verdict == "fail"         # 13.6 MPa > 10 MPa


def test_coupling_position_is_where_the_torque_leaves_the_shaft():
    """With coupling_position = 0.05 m (the drive end) the same 50 N m runs from there to the
    pulley at 0.9 m: |T| = 50 N m on every station between, 0 outside; the coupling is a
    station of the mesh; the loads table shows it there; a position off the shaft, or one on a
    rigid rotor, is refused by name."""
    data = _belt_data([0.9, 0.0, 0.0])
    data["transmissions"][0]["driver_radius"] = 0.1
    data["rotors"][0]["coupling_position"] = 0.05
    result = rdm.static(rdm.Model.from_dict(data), speed=100.0, torques=50.0)
    shaft = result.shafts["s"]
    carrying = ((shaft.z > 0.05 + 1e-9) | ((shaft.z == 0.05) & (shaft.side == "right"))) & \
        ((shaft.z < 0.9 - 1e-9) | ((shaft.z == 0.9) & (shaft.side == "left")))
    assert 0.05 in shaft.z
    np.testing.assert_allclose(np.abs(shaft.torque), np.where(carrying, 50.0, 0.0), rtol=1e-12, atol=1e-12)
    (coupling,) = [x for x in result.loads if x.kind == "coupling" and x.body == "s"]
    np.testing.assert_allclose(coupling.point, [0.05, 0.0, 0.0], atol=1e-15)
    data["rotors"][0]["coupling_position"] = 1.5
    with pytest.raises(rdm.ModelError, match=r"rotors.s\] coupling_position = 1.5: expected an axial position"):
        rdm.Model.from_dict(data)
    rigid = _belt_data()
    rigid["rotors"][1]["coupling_position"] = 0.1
    with pytest.raises(rdm.ModelError, match=r"rotors.motor\] coupling_position = 0.1: expected no value"):
        rdm.Model.from_dict(rigid)


def test_allowable_stress_is_refused_by_name():
    data = _data(1.0, (0.0, 1.0), allowable=-5.0)
    with pytest.raises(rdm.InputError, match=r"materials.steel\] allowable_stress = -5"):
        rdm.Model.from_dict(data)
    with pytest.raises(rdm.InputError, match="allowable_stress = 0"):
        rdm.static(rdm.Model.from_dict(_data(1.0, (0.0, 1.0))), allowable_stress=0.0)


# -- command line, SI and US units -------------------------------------------------------------------
@pytest.mark.parametrize("units, option, to_si", [("si", "5e5", 1.0), ("us", "72.5", PSI)])
def test_static_command_gives_the_verdict_in_either_unit_system(units, option, to_si, tmp_path, capsys):
    """The simply supported tube's 5.28 MPa (766 psi) against --allowable-stress 0.5 MPa
    (72.5 psi): fail, in the summary and the CSV, the stress columns in Pa or psi."""
    length, d, inner = 2.0, 0.05, 0.02
    path = _write(tmp_path, _data(length, (0.0, length), d=d, inner=inner))
    out = tmp_path / "static.csv"
    assert main(["static", str(path), "--allowable-stress", option, "--units", units, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    _, second, w = _section(d, inner)
    sigma = w * length ** 2 / 8 * (d / 2) / second
    unit = "MPa" if units == "si" else "psi"
    shown = sigma / 1e6 if units == "si" else sigma / PSI
    assert f"von Mises stress {shown:.4g} {unit}" in printed and ": fail (utilization" in printed
    table = pd.read_csv(out)
    rows = table[table["table"] == "shaft"]
    suffix = "Pa" if units == "si" else "psi"
    np.testing.assert_allclose(rows[f"allowable_{suffix}"] * to_si, float(option) * to_si, rtol=1e-12)
    assert rows[f"von_mises_{suffix}"].max() * to_si == pytest.approx(sigma, rel=1e-9)
    assert rows["utilization"].max() == pytest.approx(sigma / (float(option) * to_si), rel=1e-9)
    assert f"T_{'Nm' if units == 'si' else 'lbfin'}" in rows.columns


def test_bad_allowable_stress_option_exits_2(tmp_path, capsys):
    path = _write(tmp_path, _data(1.0, (0.0, 1.0)))
    assert main(["static", str(path), "--allowable-stress", "-3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--allowable-stress -3" in err[0]


# -- report ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("allowable, verdict", [(None, "not evaluated"), (10e6, "pass"), (5e6, "fail")])
def test_report_criterion_says_the_value_limit_and_verdict(allowable, verdict):
    """The report's static step adds one criterion per flexible shaft: its largest von Mises
    stress and where, the allowable stress and the verdict; the US page shows psi."""
    from rotordyn_modal.report import ReportInputs
    import importlib

    collect_module = importlib.import_module("rotordyn_modal.report.collect")

    length, d, inner = 2.0, 0.05, 0.02
    model = rdm.Model.from_dict(_data(length, (0.0, length), d=d, inner=inner, allowable=allowable))
    data = collect_module.ReportData(ReportInputs(standard="api684", mcs=300.0), model, {}, ("static",))
    collect_module._static(data)
    (criterion,) = data.criteria
    _, second, w = _section(d, inner)
    sigma = w * length ** 2 / 8 * (d / 2) / second
    assert criterion.verdict == verdict and criterion.section == "static"
    assert criterion.value == f"{sigma / 1e6:.3g} MPa at n4"
    us = criterion.in_system("us")
    assert us.value == f"{sigma / PSI:.3g} psi at n4" and us.verdict == verdict
    if allowable is not None:
        assert criterion.limit == f"<= {allowable / 1e6:.3g} MPa (allowable_stress)"
        assert us.limit == f"<= {allowable / PSI:.3g} psi (allowable_stress)"
