"""Inputs of issues 27-29's families that the earlier red teams had not tried (redteam11).

* A disk given by its mass (no ``width``: a point on the axis) inside another disk's width is
  an overlap of two disks, refused as two overlapping widths are (issue 28, "overlapping disks").
* The report's checks run "from 0 to the MCS" and its margins from the operating range, but its
  sweep (``points`` from 2 % to 150 % of the MCS) held neither the MCS nor the range's ends:
  with the default 151 points at an MCS of 3000 rpm the probe-limit check stopped at 2990.4 rpm,
  below the MCS, and judged a response smaller than the one at the MCS (issue 29).
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
SHAFT = {
    "spin_axis": [1.0, 0.0, 0.0],
    "materials": [STEEL],
    "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}],
                "disks": [{"name": "hub", "axial_position": 0.5, "outer_diameter": 0.3, "width": 0.1,
                           "material": "steel"}]}],
    "bearings": [{"name": n, "rotor": "r", "axial_position": z, "stiffness": 1e7} for n, z in (("a", 0.0), ("b", 1.0))],
}


def _with_point_disk(z):
    data = copy.deepcopy(SHAFT)
    data["rotors"][0]["disks"].append({"name": "balance-ring", "axial_position": z, "mass": 2.0,
                                       "polar_inertia": 0.01, "diametral_inertia": 0.006})
    return data


@pytest.mark.parametrize("z", [0.52, 0.46, 0.5495])
def test_a_disk_without_width_inside_another_disks_width_is_refused(z):
    """The hub spans 0.45 to 0.55 m: a point disk anywhere inside it is a second disk in the
    same material; the line names the disk, its key and value, and the hub's width."""
    with pytest.raises(InputError) as caught:
        rdm.Model.from_dict(_with_point_disk(z))
    line = str(caught.value)
    assert "[rotors.r.disks.balance-ring] axial_position" in line and "overlap disk 'hub'" in line, line
    assert "width 0.1 m" in line and "0.05 m apart" in line, line


@pytest.mark.parametrize("z", [0.55, 0.7, 0.2])
def test_a_disk_without_width_beside_another_disks_width_is_read(z):
    """At the hub's face (0.55 m) or clear of it, the point disk is a disk of its own: the rotor's
    mass is the shaft's, the hub's (a solid ring) and the point disk's, added by hand."""
    model = rdm.Model.from_dict(_with_point_disk(z))
    shaft = 7810.0 * np.pi / 4 * 0.05 ** 2 * 1.0
    hub = 7810.0 * np.pi / 4 * 0.3 ** 2 * 0.1
    assert model.rotors[0].mass == pytest.approx(shaft + hub + 2.0, rel=1e-12)


def test_two_disks_without_width_close_together_stay_allowed():
    """Two disks given by mass alone have no width to overlap: 1 cm apart is legal."""
    data = copy.deepcopy(SHAFT)
    data["rotors"][0]["disks"] = [{"name": n, "axial_position": z, "mass": 2.0, "polar_inertia": 0.01,
                                   "diametral_inertia": 0.006} for n, z in (("a", 0.50), ("b", 0.51))]
    assert len(rdm.Model.from_dict(data).rotors[0].disks) == 2


# -- the report's sweep holds the MCS and the operating range ---------------------------------------
def _probed_rotor():
    """A rigid rotor of 50 kg on two bearings of 1e7 N/m, four probes: its first critical speed
    (about 6000 rpm) lies far above an MCS of 3000 rpm, so its response rises all the way to the
    MCS and the largest one "from 0 to the MCS" is the one at the MCS."""
    probes = [{"name": f"p{n}{c}", "rotor": "r", "measure": "relative", "position": [x, 0.0, 0.0], "direction": v}
              for n, x in (("a", -0.3), ("b", 0.3)) for c, v in (("y", [0.0, 1.0, 0.0]), ("z", [0.0, 0.0, 1.0]))]
    return rdm.Model.from_dict({
        "spin_axis": [1.0, 0.0, 0.0],
        "rotors": [{"name": "r", "mass": 50.0, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                    "diametral_inertia": 1.0}],
        "bearings": [{"name": n, "rotor": "r", "position": [x, 0.0, 0.0], "stiffness": 1e7, "damping": 500.0}
                     for n, x in (("a", -0.3), ("b", 0.3))],
        "sensors": probes})


def test_the_report_sweep_holds_the_mcs_and_the_operating_range_ends():
    from rotordyn_modal.report.collect import ReportInputs

    rpm = np.pi / 30
    inputs = ReportInputs("api684", 3000 * rpm, operating=(2000 * rpm, 2900 * rpm))
    speeds = inputs.speeds
    for speed in (3000 * rpm, 2000 * rpm, 2900 * rpm):
        assert np.any(speeds == speed), speed / rpm
    assert np.all(np.diff(speeds) > 0)
    assert speeds[0] == pytest.approx(0.02 * 3000 * rpm) and speeds[-1] == pytest.approx(1.5 * 3000 * rpm)
    assert len(speeds) == 151 + 3


def test_the_report_judges_the_probes_at_the_mcs():
    """The governing probe amplitude is the response at the MCS itself, computed alone."""
    from rotordyn_modal.analysis.unbalance import api_unbalance_response
    from rotordyn_modal.report.collect import ReportInputs, collect

    model, mcs = _probed_rotor(), 3000 * np.pi / 30
    data = collect(model, ReportInputs("api684", mcs, points=151, stiffness=np.geomspace(1e6, 1e8, 3)))
    checks = data.results["checks"].to_dataframe()
    checks = checks[checks["check"] == "API 617 probe limit"]
    assert checks["speed_rpm"].max() == pytest.approx(3000.0, rel=1e-12)
    alone = api_unbalance_response(model, [mcs], mcs).to_dataframe()
    assert checks["value"].max() == pytest.approx(2 * alone["amplitude"].max(), rel=1e-9)
    criterion = next(c for c in data.criteria if c.name == "API 617 probe vibration limit")
    assert "at 3000 rpm" in criterion.why, criterion.why


# -- the UCS map over many decades ------------------------------------------------------------------
def _undamped_compressor(examples_dir):
    """examples/compressor_rotor.toml without its bearings' damping (the map is undamped, and so
    are then the critical speeds it must equal)."""
    import tomllib

    data = tomllib.loads((examples_dir / "compressor_rotor.toml").read_text())
    for bearing in data["bearings"]:
        bearing.pop("damping", None)
    return rdm.Model.from_dict(data)


def test_a_ucs_map_from_1e_3_n_per_m_keeps_every_mode_at_the_bearings_own_stiffness(examples_dir):
    """The map's value at one stiffness cannot depend on the other stiffness values swept. Its
    free motions were found on the first (softest) one: on 1e-3 N/m bearings the rotor's rigid
    motions are free to round-off beside its shaft, and were dropped at every stiffness, so at
    the bearings' own 5e7 N/m the map gave 30647 and 54044 rpm (the third and fourth modes) as
    the two lowest forward critical speeds. They must equal critical-speeds' forward 1X crossings
    of the model (5721 and 14391 rpm) to 1e-9, and the map of that stiffness alone."""
    from rotordyn_modal.analysis.ucs_map import ucs_map

    model = _undamped_compressor(examples_dir)
    wide = ucs_map(model, np.geomspace(1e-3, 1e16, 20), modes=4)
    at = ucs_map(model, np.array([1e-3, 5e7, 1e16]), modes=4).speeds[1]
    alone = ucs_map(model, np.array([5e7]), modes=4).speeds[0]
    np.testing.assert_allclose(at, alone, rtol=1e-12)
    critical = rdm.critical_speeds(model, np.linspace(0.0, 16000.0, 33) * np.pi / 30, orders=(1,)).to_dataframe()
    forward = np.sort(critical.loc[critical["whirl"] == "forward", "speed_rpm"].to_numpy())
    np.testing.assert_allclose(at[:2] * 30 / np.pi, forward[:2], rtol=1e-9)
    # the whole wide sweep holds the rigid-body modes, which rise as sqrt(k) on soft bearings
    # (1 to 100 N/m: at 1e-3 N/m their 1e-13 share of the stiffness costs them digits)
    soft = wide.speeds[3:6, 0]
    np.testing.assert_allclose(soft[1:] / soft[:-1], np.sqrt(10.0), rtol=1e-5)
    assert np.all(np.isfinite(wide.speeds[:, 0])) and wide.speeds[0, 0] * 30 / np.pi < 0.1


# -- one vocabulary: a second figure is --plot-WHAT everywhere ---------------------------------------
def _subcommands():
    from rotordyn_modal.cli.main import build_parser

    return build_parser()._subparsers._group_actions[0].choices


def test_every_figure_option_is_spelled_plot_what():
    """``modes --plot-shaft``, ``study --plot-map``/``--plot-histogram``/``--plot-sensitivity``
    beside ``unbalance --orbit-plot`` and ``level1 --csr-plot``: one concept, two word orders.
    Every figure option --help shows is ``--plot`` or ``--plot-WHAT``."""
    import argparse

    for command, sub in _subcommands().items():
        for action in sub._actions:
            if action.help is argparse.SUPPRESS:
                continue
            for option in action.option_strings:
                if "plot" in option:
                    assert option == "--plot" or option.startswith("--plot-"), (command, option)


@pytest.mark.parametrize("command, shown, old", [("unbalance", "--plot-orbits", "--orbit-plot"),
                                                 ("level1", "--plot-csr", "--csr-plot")])
def test_the_earlier_figure_spelling_still_works_hidden(command, shown, old):
    import argparse

    sub = _subcommands()[command]
    new, hidden = sub._option_string_actions[shown], sub._option_string_actions[old]
    assert new.help is not argparse.SUPPRESS and hidden.help is argparse.SUPPRESS
    assert (hidden.dest, hidden.metavar) == (new.dest, new.metavar)
    assert old not in sub.format_help()


def test_a_file_refusal_names_the_figure_option_as_typed(tmp_path, examples_dir, capsys):
    from rotordyn_modal.cli.main import main

    base = ["unbalance", str(examples_dir / "compressor_rotor.toml"), "--speeds", "500:1000:3", "--quiet"]
    for spelling in ("--orbit-plot", "--plot-orbits"):
        assert main(base + [spelling, str(tmp_path / "p.png"), "--plot", str(tmp_path / "p.png")]) == 2
        err = capsys.readouterr().err
        assert f"{spelling} and --plot name the same file" in err and err.count("\n") == 1, err
    assert not (tmp_path / "p.png").exists()


# -- a circular orbit has no major axis ------------------------------------------------------------
def test_a_circular_orbit_has_inclination_zero_not_noise(examples_dir):
    """compressor_rotor: an axisymmetric rotor on isotropic bearings, so each probe pair's
    unbalance orbit is a forward circle (forward part m e w^2 / ..., backward part exactly 0 but
    computed as round-off). The inclination of the major axis of a circle was the phase of that
    round-off: 0.0156 deg at the left pair, 180 deg at the right. It is 0; an ellipse keeps its
    angle (fan_on_bearings' anisotropic bearings, checked against the definition by hand)."""
    from rotordyn_modal.analysis.orbits import orbit_ellipses

    model = rdm.load_model(examples_dir / "compressor_rotor.toml")
    orbits = rdm.unbalance_response(model, np.array([10.0, 20.0, 3000.0]) * np.pi / 30).orbits()
    assert len(orbits) and np.allclose(orbits["minor"], orbits["major"], rtol=1e-9)
    assert (orbits["inclination_deg"] == 0.0).all(), orbits["inclination_deg"].tolist()
    assert (orbits["precession"] == "forward").all()
    # an ellipse: x = cos(wt), y = 0.5 sin(wt + 30 deg) has its major axis where |x + i y| is largest
    t = np.linspace(0.0, 2 * np.pi, 200001)
    plane = np.array([1.0, 0.5 * np.exp(1j * np.radians(-60.0))])     # y = 0.5 cos(wt - 60 deg)
    x, y = np.real(plane[0] * np.exp(1j * t)), np.real(plane[1] * np.exp(1j * t))
    far = np.argmax(x * x + y * y)
    angle = np.degrees(np.arctan2(y[far], x[far])) % 180.0
    major, minor, inclination, _ = orbit_ellipses(plane, 1.0)
    assert inclination == pytest.approx(angle, abs=1e-3)
    assert major == pytest.approx(np.hypot(x[far], y[far]), rel=1e-9)
