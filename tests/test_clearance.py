"""Close-clearance stations (``[[rotors.clearances]]``) and the API 617 / 684 clearance check.

The check's numbers against an independent solve written here: a rigid, axisymmetric rotor on
two isotropic bearings whirls, under an unbalance that turns with it, in a forward circle; in
the complex coordinates ``z`` (centre of mass, ``y + i z``) and ``psi`` (slope) the synchronous
response solves a 2 x 2 complex system (gyroscopic stiffening ``J_p w^2``), and a point at
``s`` from the centre of mass moves by ``z + s psi`` (virtual work gives a force ``F`` at ``s``
the generalized moment ``s F``). Its pk-pk displacement is ``2 |z + s psi|``; the allowed value
75 % of the diametral clearance, ``0.75 x 2 x radial_clearance``.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import api_unbalance_response
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError

MASS, POLAR, DIAMETRAL = 40.0, 0.8, 2.5
BEARINGS = ((-0.3, 3.0e6, 900.0), (0.5, 5.0e6, 1500.0))      # (offset from the centre [m], k [N/m], c [N s/m])
STATIONS = {"inboard-seal": (-0.1, 10e-6), "overhung-seal": (0.65, 40e-6)}   # offset [m], radial clearance [m]
CENTRE = np.array([1.0, 0.0, 0.2])


def _rigid_data():
    return {"name": "rigid rotor with seals", "spin_axis": [1.0, 0.0, 0.0],
            "rotors": [{"name": "rotor", "mass": MASS, "center_of_mass": CENTRE.tolist(), "polar_inertia": POLAR,
                        "diametral_inertia": DIAMETRAL, "speed_ratio": 1.0,
                        "clearances": [{"name": name, "position": (CENTRE + [s, 0.0, 0.0]).tolist(),
                                        "radial_clearance": c} for name, (s, c) in STATIONS.items()]}],
            "bearings": [{"name": f"b{i}", "rotor": "rotor", "position": (CENTRE + [a, 0.0, 0.0]).tolist(),
                          "stiffness": k, "damping": c, **({"axial_stiffness": 1e7} if i == 0 else {})}
                         for i, (a, k, c) in enumerate(BEARINGS)],
            "sensors": [{"name": "probe", "rotor": "rotor", "measure": "relative",
                         "position": (CENTRE + [0.5, 0.0, 0.0]).tolist(), "direction": [0.0, 1.0, 0.0]}],
            "unbalances": [{"rotor": "rotor", "amount": 1e-4}]}


def _by_hand(w, force, moment):
    """Complex (z, psi) of the synchronous forward whirl at ``w`` [rad/s] (shape (N,))."""
    a, k, c = (np.array(x) for x in zip(*BEARINGS))
    d = k + 1j * w[:, None] * c                               # each bearing's dynamic stiffness
    system = np.empty((len(w), 2, 2), dtype=complex)
    system[:, 0, 0] = d.sum(1) - MASS * w ** 2
    system[:, 0, 1] = system[:, 1, 0] = (d * a).sum(1)
    system[:, 1, 1] = (d * a * a).sum(1) - (DIAMETRAL - POLAR) * w ** 2
    rhs = np.stack([np.broadcast_to(force, w.shape), np.broadcast_to(moment, w.shape)], axis=-1)
    return np.linalg.solve(system, rhs[..., None])[..., 0]


PROBE = 0.5                                                  # the probe's offset from the centre [m]


def _scale(z, psi, checked, mcs_rpm, cap=6.0):
    """API 617 (9th ed. 6.8.2.10, as petrobras/ross PR #1377 implements it): Scc = Avl / Amax, at
    most 6; Avl = 25.4 um sqrt(12000 / N), at most 25.4 um; Amax the probe's largest pk-pk over
    the operating speeds (here 0 to the MCS). A forward circle: the probe reads 2 |z + s psi|."""
    amax = (2 * np.abs(z + PROBE * psi))[checked].max()
    avl = min(25.4e-6, 25.4e-6 * np.sqrt(12000 / mcs_rpm))
    return avl / amax if cap is None else min(avl / amax, cap)


def test_clearance_check_of_a_rigid_rotor_equals_the_hand_solve():
    """API 617 (9th ed. 6.8.2.7, 6.8.2.10, 6.8.2.11 as petrobras/ross PR #1377 implements them):
    the unbalance Ua = 2 Ur, Ur = 6350 W / N g mm; the pk-pk response at each close clearance
    scaled by Scc = Avl / Amax (at most 6) against 75 % of the diametral clearance. The old check
    (Ur, unscaled) fails here."""
    model = rdm.Model.from_dict(_rigid_data(), "seals.toml")
    mcs_rpm = 6000.0
    mcs = mcs_rpm * np.pi / 30
    speeds = np.linspace(0.05, 1.4, 60) * mcs
    check = api_unbalance_response(model, speeds, mcs).clearance_check(model, mcs=mcs)
    table = check.to_dataframe()
    w = speeds
    static = 2 * 6350e-6 * MASS / mcs_rpm                      # API: 2 x 6350 W / N g mm, W the rotor's mass
    couple = 2 * 6350e-6 * (MASS / 2) / mcs_rpm                # at each outermost bearing plane, 180 deg apart
    a1, a2 = BEARINGS[0][0], BEARINGS[1][0]
    solves = {"api-static:rotor": lambda x: _by_hand(x, static * x ** 2, 0.0),
              "api-couple:rotor": lambda x: _by_hand(x, 0.0, couple * x ** 2 * (a1 - a2))}
    cases = {name: solve(w) for name, solve in solves.items()}
    assert check.cases == tuple(cases)
    checked = w <= mcs * (1 + 1e-12)
    for case, (z, psi) in ((name, q.T) for name, q in cases.items()):
        # Amax over the operating speeds, 0 to the MCS: the swept ones and the MCS itself (redteam29r)
        z_mcs, psi_mcs = solves[case](np.array([mcs])).T
        scale = _scale(np.append(z[checked], z_mcs), np.append(psi[checked], psi_mcs), slice(None), mcs_rpm)
        for name, (s, radial) in STATIONS.items():
            pkpk = 2 * np.abs(z + s * psi)
            k = int(np.argmax(np.where(checked, pkpk, -1)))
            # the largest is the hand solve's maximum between the swept speeds around it (issue 29)
            fine = np.linspace(w[max(k - 1, 0)], w[min(k + 1, len(w) - 1)], 20001)
            fine = np.union1d(fine[fine < mcs], [mcs]) if fine[-1] > mcs else fine   # the MCS itself judged too
            zf, psif = solves[case](fine).T
            top = 2 * np.abs(zf + s * psif)
            largest, at = top.max(), fine[np.argmax(top)]
            row = table[(table["clearance"] == name) & (table["case"] == case)].iloc[0]
            assert row["response"] == pytest.approx(largest, rel=1e-8) and largest >= pkpk[k]
            assert row["scale_factor"] == pytest.approx(scale, rel=1e-9)
            assert row["value"] == pytest.approx(scale * largest, rel=1e-8)
            assert row["speed_rpm"] == pytest.approx(at * 30 / np.pi, abs=1e-4 * (fine[-1] - fine[0]) * 30 / np.pi)
            assert row["limit"] == pytest.approx(0.75 * 2 * radial, rel=1e-15)
            assert row["ratio"] == pytest.approx(scale * largest / (1.5 * radial), rel=1e-8)
            assert row["verdict"] == ("pass" if scale * largest <= 1.5 * radial else "fail")
            assert row["amplitude"] == "peak-to-peak"
    # the clearances are chosen so that one station passes and one fails the static case
    static_rows = table[table["case"] == "api-static:rotor"].set_index("clearance")
    assert set(static_rows["verdict"]) == {"pass", "fail"}


def test_scaled_clearance_response_does_not_depend_on_the_unbalance_amount():
    """The analysis is linear: Scc x response is the same for any unbalance while Scc is below
    its cap; with the cap (API 617: 6) a small unbalance's value is 6 x its response. Without a
    probe on the rotor nothing is scaled (said in ``scaling``)."""
    mcs = 6000.0 * np.pi / 30
    speeds = np.linspace(0.05, 1.4, 60) * mcs
    values = []
    for amount in (1e-4, 4e-4):
        data = _rigid_data()
        data["unbalances"][0]["amount"] = amount
        model = rdm.Model.from_dict(data, "seals.toml")
        table = rdm.unbalance_response(model, speeds).clearance_check(model, mcs=mcs, scale_cap=None).to_dataframe()
        values.append(table["value"].to_numpy())
        assert (table["scaling"] == "Avl/Amax").all()
    assert np.allclose(values[0], values[1], rtol=1e-9)
    data = _rigid_data()
    data["unbalances"][0]["amount"] = 1e-9
    model = rdm.Model.from_dict(data, "seals.toml")
    table = rdm.unbalance_response(model, speeds).clearance_check(model, mcs=mcs).to_dataframe()
    assert (table["scale_factor"] == 6.0).all() and (table["scaling"] == "Avl/Amax capped at 6").all()
    assert np.allclose(table["value"], 6.0 * table["response"], rtol=1e-12)
    data["sensors"] = []
    model = rdm.Model.from_dict(data, "seals.toml")
    table = rdm.unbalance_response(model, speeds).clearance_check(model, mcs=mcs).to_dataframe()
    assert (table["scale_factor"] == 1.0).all() and (table["scaling"] == "unscaled: no probe on rotor rotor").all()
    assert np.allclose(table["value"], table["response"], rtol=0)


def test_scale_factor_takes_the_probes_over_the_operating_speeds():
    """Amax is the probes' largest amplitude from the minimum operating speed to the MCS (API 617:
    the operating speeds), not over the run-up through a critical speed below them."""
    model = rdm.Model.from_dict(_rigid_data(), "seals.toml")
    mcs_rpm = 6000.0
    mcs = mcs_rpm * np.pi / 30
    speeds = np.linspace(0.05, 1.4, 60) * mcs
    response = api_unbalance_response(model, speeds, mcs)
    low = 0.8 * mcs
    table = response.clearance_check(model, mcs=mcs, min_operating=low).to_dataframe()
    static = 2 * 6350e-6 * MASS / mcs_rpm
    z, psi = _by_hand(speeds, static * speeds ** 2, 0.0).T
    operating = (speeds >= low) & (speeds <= mcs * (1 + 1e-12))
    row = table[table["case"] == "api-static:rotor"].iloc[0]
    assert row["scale_factor"] == pytest.approx(_scale(z, psi, operating, mcs_rpm), rel=1e-9)
    with pytest.raises(rdm.InputError, match="minimum operating speed"):
        response.clearance_check(model, mcs=mcs, min_operating=1.1 * mcs)
    # no speed of the sweep at exactly the MCS: Amax at the sweep's speed nearest it, said
    row = response.clearance_check(model, mcs=mcs, min_operating=mcs).to_dataframe().iloc[0]
    k = int(np.argmin(np.abs(speeds - mcs)))
    assert not np.isclose(speeds[k], mcs)
    assert row["scale_factor"] == pytest.approx(_scale(z, psi, np.arange(len(speeds)) == k, mcs_rpm), rel=1e-9)
    assert row["scaling"].endswith(f" (Amax at {speeds[k] * 30 / np.pi:.6g} rpm, the sweep's speed nearest "
                                   "the operating speeds)")


def test_trip_speed_widens_the_checked_speeds():
    model = rdm.Model.from_dict(_rigid_data(), "seals.toml")
    mcs = 3000.0 * np.pi / 30
    speeds = np.linspace(0.05, 2.0, 40) * mcs
    response = api_unbalance_response(model, speeds, mcs)
    at_mcs = response.clearance_check(model, mcs=mcs).to_dataframe()
    at_trip = response.clearance_check(model, mcs=mcs, trip_speed=1.9 * mcs).to_dataframe()
    assert (at_mcs["speed_rpm"] <= 3000.0 + 1e-9).all()
    assert (at_trip["value"] >= at_mcs["value"]).all() and (at_trip["speed_rpm"] > 3000.0).any()


@pytest.mark.parametrize("change, key, expected", [
    ({"radial_clearance": 0.0}, "radial_clearance = 0.0", "a finite number > 0"),
    ({"radial_clearance": "0.2 mm"}, "radial_clearance = '0.2 mm'", "a finite number"),
    ({"name": "inboard-seal"}, "name = 'inboard-seal'", "a name unique among the model's [[rotors.clearances]]"),
    ({"position": [1.65, 0.01, 0.2]}, "position = [1.65, 0.01, 0.2]", "a point on the axis of rotor 'rotor'"),
    ({"axial_position": 0.1}, "axial_position = 0.1", "no value: axial_position places a clearance on a flexible"),
    ({"diameter": 0.1}, "diameter = 0.1", "one of the keys name, position, axial_position, radial_clearance"),
])
def test_bad_clearance_refused_by_name(change, key, expected):
    data = _rigid_data()
    data["rotors"][0]["clearances"][1].update(change)
    with pytest.raises(ModelError) as error:
        rdm.Model.from_dict(data, "seals.toml")
    message = str(error.value)
    assert message.startswith("seals.toml: [rotors.rotor.clearances.") and key in message and expected in message


def test_clearance_on_a_flexible_shaft_off_the_shaft_and_on_a_rotor_without_bearings_refused():
    data = rdm.load_model("examples/compressor_rotor.toml").to_dict()
    data["rotors"][0]["clearances"][0]["axial_position"] = 1.5          # the shaft is 1.2 m long
    with pytest.raises(ModelError, match=r"\[rotors.compressor.clearances.eye-seal-1\] axial_position = 1.5: "
                                         r"expected an axial position on the shaft"):
        rdm.Model.from_dict(data, "seals.toml")
    rigid = _rigid_data()
    rigid["bearings"], rigid["sensors"] = [], []
    with pytest.raises(ModelError, match=r"radial_clearance = 1e-05: expected a clearance on a rotor on \[\[bearings\]\]"):
        rdm.Model.from_dict(rigid, "seals.toml")


def test_flexible_station_is_a_node_and_a_dotted_key():
    model = rdm.load_model("examples/compressor_rotor.toml")
    z = model.rotors[0].flexible.mesh.z
    for clearance in model.clearances:
        assert np.min(np.abs(z - clearance.axial_position)) == 0.0
    changed = model.with_values({"rotors.compressor.clearances.balance-piston.radial_clearance": 1e-4})
    assert changed.clearances[-1].radial_clearance == 1e-4


def test_unbalance_prints_the_clearance_check(tmp_path, capsys):
    path = tmp_path / "seals.toml"
    import tomli_w
    path.write_bytes(tomli_w.dumps(_rigid_data()).encode())
    assert main(["unbalance", str(path), "--speeds", "300:8400:29", "--mcs", "6000", "--api-unbalance",
                 "--out", str(tmp_path / "u.csv")]) == 0
    shown = "".join(capsys.readouterr())
    assert "clearance check (API 617/684" in shown and "overhung-seal" in shown and "api-couple:rotor" in shown
    assert main(["--units", "us", "unbalance", str(path), "--speeds", "300:8400:29", "--mcs", "6000",
                 "--api-unbalance", "--out", str(tmp_path / "u2.csv")]) == 0
    assert "mil" in "".join(capsys.readouterr())
    assert main(["unbalance", str(path), "--speeds", "300:8400:29", "--trip-speed", "6300",
                 "--out", str(tmp_path / "u3.csv")]) == 2
    assert main(["unbalance", str(path), "--speeds", "300:8400:29", "--mcs", "6000", "--api-unbalance",
                 "--min-operating-speed", "4800", "--out", str(tmp_path / "u4.csv")]) == 0
    shown = "".join(capsys.readouterr())
    assert "scale_factor" in shown and "Avl/Amax" in shown
    for bad in (["--min-operating-speed", "6500", "--mcs", "6000"], ["--min-operating-speed", "4800"]):
        assert main(["unbalance", str(path), "--speeds", "300:8400:29", *bad,
                     "--out", str(tmp_path / "u5.csv")]) == 2
        error = capsys.readouterr().err
        assert "--min-operating-speed" in error and "expected --mcs too and a speed >= 0 and at most --mcs" in error
        assert not (tmp_path / "u5.csv").exists()


def test_response_is_relative_to_the_moving_casing():
    """A fan on bearings in a housing on rubber mounts: the check at a seal equals twice the
    semi-major axis of the orbit a relative probe pair at the seal sees (the sources' sums), and
    differs from the absolute motion there (the casing moves)."""
    from rotordyn_modal.analysis.orbits import orbit_ellipses
    from rotordyn_modal.analysis.unbalance import unbalance_response

    data = rdm.load_model("examples/fan_on_bearings.toml").to_dict()
    seal = [-0.40, 0.0, 0.30]
    fan = next(r for r in data["rotors"] if r["name"] == "fan")
    fan["clearances"] = [{"name": "impeller-seal", "position": seal, "radial_clearance": 3e-4}]
    data["sensors"] = [{"name": f"{kind}-{axis}", "rotor": "fan", "measure": kind, "position": seal,
                        "direction": direction}
                       for kind in ("relative", "absolute") for axis, direction in (("y", [0, 1, 0]), ("z", [0, 0, 1]))]
    model = rdm.Model.from_dict(data, "fan.toml")
    speeds = np.linspace(100, 4000, 40) * np.pi / 30
    response = unbalance_response(model, speeds)
    check = response.clearance_check(model, mcs=speeds[-1])
    assert len(response.sources) == 2 and check.cases == ("",)
    pairs = dict(zip(response.orbit_pairs, orbit_ellipses(response.orbit_planes, 1.0)[0]))
    relative = 2 * pairs[("relative-y", "relative-z")].sum(axis=0)
    absolute = 2 * pairs[("absolute-y", "absolute-z")].sum(axis=0)
    np.testing.assert_allclose(check.pkpk[0, 0], relative, rtol=1e-10, atol=1e-18)
    assert np.max(np.abs(absolute - relative) / relative) > 0.05
