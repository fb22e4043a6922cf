"""What ``stability`` reports: thresholds only where the real part's sign change is beyond
round-off (never a crash on round-off), every interval of instability (an island of stability
included) against a closed form, and, stable throughout, the least damped mode.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import rotordyn_modal as rdm
from journal_reference import lund_threshold
from rotordyn_modal.cli import main

G = 9.81


def _cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------------------- round-off
def _rotor_in_journals(mass, **geometry):
    return rdm.Model.from_dict({
        "spin_axis": [1.0, 0.0, 0.0], "gravity": [0.0, 0.0, -G],
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.01 * mass,
                    "diametral_inertia": 0.04 * mass, "speed_ratio": 1.0}],
        "bearings": [{"name": n, "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal", **geometry}
                     for n, s in (("A", 0.3), ("B", -0.3))]})


@pytest.mark.parametrize("viscosity", [20.0, 1000.0])
def test_thick_oil_threshold_equals_lunds_though_the_real_parts_are_tiny_beside_the_film_roots(viscosity):
    """A viscous film makes roots of -1e8 1/s beside the whirl mode's real parts of 1e-3 1/s: a
    real part is not round-off because it is small beside the largest root (that hid the sign
    change at 1000 Pa s), and the sign change is refined between speeds where it is beyond
    round-off (the grid's values near zero gave 0.46 % at 20 Pa s). Lund's analysis
    (tests/journal_reference.py) is independent of the package."""
    geometry = {"diameter": 0.05, "length": 0.025, "clearance": 5e-5, "viscosity": viscosity}
    expected, _ = lund_threshold(25.0, **geometry, gravity=G)
    result = rdm.stability(_rotor_in_journals(50.0, **geometry), np.linspace(0.3, 2.0, 35) * expected)
    assert result.threshold_speed == pytest.approx(expected, rel=1e-6)


def test_a_sign_change_within_round_off_is_no_threshold_and_no_crash(examples_dir, tmp_path, capsys):
    """viscosity = 1e9 Pa s: the whirl roots' real parts (below 1e-5 1/s) are far below the
    round-off of a state matrix of norm 1e16 (about 0.1 1/s): their signs are noise, once
    ending in scipy's "f(a) and f(b) must have different signs". Exit 0, no threshold, the roots
    in the table as they are, a line saying why."""
    text = (examples_dir / "journal_rotor.toml").read_text()
    path = tmp_path / "thick.toml"
    path.write_text(re.sub(r"(?m)^viscosity = 0\.02", "viscosity = 1e9", text))
    assert path.read_text().count("viscosity = 1e9") == 2
    code, out, err = _cli(["stability", path, "--speeds", "500:20000:40", "--out", tmp_path / "s.csv"], capsys)
    assert code == 0, err
    assert "failed" not in err and "Traceback" not in err and "stability at" not in err
    assert "zero to round-off" in err
    assert (tmp_path / "s.csv").exists()
    result = rdm.stability(rdm.load_model(path), rdm.rpm(np.linspace(500, 20000, 40)))
    assert len(result.thresholds) == 0
    assert np.all(np.abs(result.real_parts[np.abs(result.eigenvalues) < 1e6]) <= result.roundoff[:, None].max())


# ------------------------------------------------------------------------------- island
K, C, M, JP, JD, A = 1.0e6, 100.0, 20.0, 0.3, 0.5, 0.3
TABLE_RPM = [0.0, 2000.0, 4000.0, 6000.0, 8000.0]
TABLE_Q = [0.0, 4.0e4, 2.0e4, 4.5e4, 4.5e4]


def _island_rotor(mass=M):
    """A rigid rotor on two like bearings at +-A, each [[K, q], [-q, K]] with damping C, q over
    speed from a table (linear between its points). Its bounce z = u_y + i u_z obeys
    m z'' + 2 C z' + 2 (K - i q) z = 0: on the boundary (lam = i w) w = q / C and m w^2 = 2 K, so
    it is unstable where q > q* = C sqrt(2 K / m). q rises above q*, falls below and rises again:
    unstable, stable, unstable. The tilt (J_d, J_p) needs q > C sqrt(2 A^2 K / J_d) = 6e4 > max q."""
    bearings = [{"name": name, "rotor": "r", "position": [s, 0.0, 0.0], "speeds_rpm": TABLE_RPM,
                 "stiffness": [[[K, q], [-q, K]] for q in TABLE_Q], "damping": [C] * len(TABLE_RPM)}
                for name, s in (("A", A), ("B", -A))]
    return {"spin_axis": [1.0, 0.0, 0.0], "bearings": bearings,
            "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0],
                        "polar_inertia": JP, "diametral_inertia": JD, "speed_ratio": 1.0}]}


def _crossings_rpm(mass):
    """Where q(speed) = q* on each segment of the table [rpm], with the direction of the change."""
    limit = C * np.sqrt(2 * K / mass)
    found = []
    for (s0, s1), (q0, q1) in zip(zip(TABLE_RPM, TABLE_RPM[1:]), zip(TABLE_Q, TABLE_Q[1:])):
        if (q0 - limit) * (q1 - limit) < 0:
            found.append((s0 + (limit - q0) / (q1 - q0) * (s1 - s0), q1 > q0))
    return found


def _intervals_rpm(mass):
    crossings, intervals = _crossings_rpm(mass), []
    for speed, onset in crossings:
        if onset:
            intervals.append([speed, np.nan])
        else:
            intervals[-1][1] = speed
    return intervals


def test_every_interval_of_instability_equals_the_closed_form():
    assert [onset for _, onset in _crossings_rpm(M)] == [True, False, True]      # an island
    model = rdm.Model.from_dict(_island_rotor())
    result = rdm.stability(model, rdm.rpm(np.linspace(0.0, 8000.0, 81)))
    expected = _intervals_rpm(M)
    found = rdm.to_rpm(np.array(result.unstable_intervals, dtype=float))
    np.testing.assert_allclose(found, expected, rtol=1e-9)
    assert result.threshold_onsets.tolist() == [True, False, True]


def _least_damped_log_dec(mass, speeds_rpm):
    """Smallest log decrement over the speeds of the bounce and tilt roots (quadratics in lam)."""
    smallest = np.inf
    for speed in speeds_rpm:
        q = np.interp(speed, TABLE_RPM, TABLE_Q)
        omega = speed * np.pi / 30
        roots = np.concatenate([np.roots([mass, 2 * C, 2 * (K - 1j * q)]),
                                np.roots([JD, 2 * A * A * C - 1j * omega * JP, 2 * A * A * (K - 1j * q)])])
        smallest = min(smallest, np.min(-2 * np.pi * roots.real / np.abs(roots.imag)))
    return smallest


def test_the_map_summary_lists_every_interval_per_value_and_names_the_least_damped_mode(tmp_path, capsys):
    """``--vary rotors.r.mass --scale``: per factor, each interval (onset, and where it exists
    the speed where stability returns) as the closed form puts it; the factor that is stable
    throughout names the least damped mode with the closed form's log decrement, and its number
    in ``modes --speed`` there is that mode."""
    path = tmp_path / "island.toml"
    rdm.save_model(rdm.Model.from_dict(_island_rotor()), path)
    factors = [0.3, 0.5, 1.0, 2.0]
    code, out, err = _cli(["stability", path, "--speeds", "0:8000:81", "--vary", "rotors.r.mass",
                           "--scale", ",".join(map(str, factors)), "--out", tmp_path / "map.csv"], capsys)
    assert code == 0, err
    lines = [line for line in err.splitlines() if line.startswith("rotors.r.mass x ")]
    assert len(lines) == len(factors)
    for line, factor in zip(lines, factors):
        assert line.startswith(f"rotors.r.mass x {factor:g}: ")
        expected = _intervals_rpm(M * factor)
        if not expected:
            continue
        found = re.findall(r"from ([0-9.e+]+) rpm(?: to ([0-9.e+]+) rpm)?", line)
        assert len(found) == len(expected), line
        for (start, stop), (x0, x1) in zip(found, expected):
            assert float(start) == pytest.approx(x0, rel=1e-5)
            assert (stop == "") == np.isnan(x1) and (stop == "" or float(stop) == pytest.approx(x1, rel=1e-5))
    assert len(_intervals_rpm(M * 2.0)) == 2 and lines[2].count(" rpm to ") == 1      # islands shown
    stable = lines[0]
    match = re.search(r"stable over the range; least damped: mode (\d+) at ([0-9.e+]+) rpm: log decrement "
                      r"([0-9.e+-]+), ([0-9.e+]+) Hz, (\w+) whirl \(mode (\d+) of modes --speed ([0-9.e+]+)\)", stable)
    assert match, stable
    _, speed, log_dec, frequency, _, number, again = match.groups()
    assert float(log_dec) == pytest.approx(_least_damped_log_dec(M * 0.3, np.linspace(0, 8000, 81)), rel=1e-3)
    light = tmp_path / "light.toml"
    rdm.save_model(rdm.Model.from_dict(_island_rotor(M * 0.3)), light)
    code, out, err = _cli(["modes", light, "--speed", again, "--out", "-"], capsys)
    assert code == 0, err
    row = [line.split(",") for line in out.splitlines()[1:]][int(number) - 1]
    assert float(row[1]) == pytest.approx(float(frequency), rel=1e-4)      # frequency_hz
    assert float(row[3]) == pytest.approx(float(log_dec), rel=1e-3)        # log_decrement


def test_the_single_sweep_prints_each_threshold_and_the_intervals(tmp_path, capsys):
    path = tmp_path / "island.toml"
    rdm.save_model(rdm.Model.from_dict(_island_rotor()), path)
    code, out, err = _cli(["stability", path, "--speeds", "0:8000:81", "--out", tmp_path / "s.csv"], capsys)
    assert code == 0, err
    changes = re.findall(r"mode \d+ (loses|regains) stability at ([0-9.e+]+) rpm", err)
    expected = _crossings_rpm(M)
    assert [kind == "loses" for kind, _ in changes] == [onset for _, onset in expected]
    for (_, speed), (x, _) in zip(changes, expected):
        assert float(speed) == pytest.approx(x, rel=1e-7)
    (x0, x1), (x2, _) = _intervals_rpm(M)
    assert f"unstable from {x0:.6g} rpm to {x1:.6g} rpm and from {x2:.6g} rpm" in err


def test_an_undamped_machine_is_marginal_and_its_least_damped_mode_has_log_decrement_zero(tmp_path, capsys):
    """Undamped and conservative (a gyroscopic rotor on symmetric springs): every real part is 0
    (Re lam = 0 exactly; computed ones are round-off of either sign). Marginal at every speed,
    never a threshold, and the least damped mode's log decrement is 0, not a round-off negative
    that reads as unstable."""
    data = _island_rotor()
    for bearing in data["bearings"]:
        bearing.update(stiffness=[[K, 0.0], [0.0, K]], damping=0.0)
        del bearing["speeds_rpm"]
    path = tmp_path / "undamped.toml"
    rdm.save_model(rdm.Model.from_dict(data), path)
    code, out, err = _cli(["stability", path, "--speeds", "0:8000:17", "--out", tmp_path / "s.csv"], capsys)
    assert code == 0, err
    assert "stability at" not in err
    assert "stable or marginal over the range: at 17 of 17 speeds" in err
    assert "log decrement 0 (zero to round-off)" in err


def test_the_map_figure_marks_every_onset_and_every_return_to_stability():
    """The island rotor over its mass: each factor's onsets (filled) and returns to stability
    (open) are drawn where the closed form puts them, not only the lowest onset."""
    import matplotlib

    matplotlib.use("Agg")
    from rotordyn_modal.plotting.stability import plot_stability_map

    factors = np.array([0.5, 1.0, 2.0])
    result = rdm.stability_map(rdm.Model.from_dict(_island_rotor()), rdm.rpm(np.linspace(0.0, 8000.0, 81)),
                               "rotors.r.mass", scale=factors)
    fig = plot_stability_map(result)
    drawn = {gid: line for line in fig.axes[0].lines if (gid := line.get_gid()) and gid.startswith("threshold")}
    for onset in (True, False):
        expected = sorted((x, factor) for factor in factors for x, o in _crossings_rpm(M * factor) if o == onset)
        line = drawn[f"threshold-{onset}"]
        found = sorted(zip(line.get_xdata(), line.get_ydata()))
        assert len(found) == len(expected) and len(expected) > 0
        np.testing.assert_allclose(found, expected, rtol=1e-6)
