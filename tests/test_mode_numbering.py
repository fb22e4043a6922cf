"""One mode numbering (docs/model-file.md, "Mode numbers"): a sweep's line or row names a mode by
its tracked label and by its number in ``modes --speed S`` (``mode_at_speed``); that number is the
mode ``modes`` lists and ``modes --shape`` draws. Round trips through the command line:
stability -> modes at the threshold (the named mode has a zero real part there, the closed form's
frequency, and is the one that is unstable just above), critical-speeds -> modes at each critical
speed (the named mode's frequency is on the excitation order line), campbell -> modes.
"""

from __future__ import annotations

import io
import re

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
from rotordyn_modal.cli import main

LINE = re.compile(r"mode (\d+) loses stability at ([0-9.e+]+) rpm \(([0-9.e+]+) Hz, (\w+) whirl; "
                  r"mode (\d+) of modes --speed ([0-9.e+]+)\)")


def _cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out, err


def _modes_table(model_path, speed_rpm, capsys):
    out, _ = _cli(["modes", model_path, "--speed", speed_rpm, "--out", "-"], capsys)
    return pd.read_csv(io.StringIO(out)).set_index("mode")


# the cross-coupled example's threshold in closed form: tests/test_unstable_example.py
def _cross_coupled_whirl_hz():
    return 8.0e3 / 200.0 / (2 * np.pi)          # |q / c| [rad/s] -> Hz


@pytest.mark.parametrize("example, speeds, tracked_differs", [
    ("unstable_cross_coupled.toml", "0:20000:101", True),
    ("journal_rotor.toml", "500:20000:40", True),
])
def test_the_mode_stability_names_is_the_one_modes_lists_and_draws(examples_dir, capsys, example, speeds,
                                                                     tracked_differs):
    path = examples_dir / example
    _, err = _cli(["stability", path, "--speeds", speeds, "--out", "-"], capsys)
    found = [LINE.search(line) for line in err.splitlines() if " loses stability at " in line]
    assert len(found) == 1 and found[0], err
    tracked, threshold, frequency, whirl, number, again = found[0].groups()
    assert again == threshold                                    # the speed to give modes is the threshold
    table = _modes_table(path, threshold, capsys)
    row = table.loc[int(number)]
    omega = 2 * np.pi * row.frequency_hz
    # the named mode is the one on the boundary: real part zero (to the printed speed's 8 digits)
    assert abs(row.real_part) < 1e-6 * omega
    assert row.frequency_hz == pytest.approx(float(frequency), rel=1e-4) and row.whirl == whirl
    if example.startswith("unstable"):
        assert row.frequency_hz == pytest.approx(_cross_coupled_whirl_hz(), rel=1e-6)
        assert whirl == "backward"
    # ... and the one that is unstable just above: the root nearest its frequency has Re > 0 there
    above = _modes_table(path, f"{float(threshold) * 1.01:.8g}", capsys)
    nearest = (above.frequency_hz - row.frequency_hz).abs().idxmin()
    assert above.loc[nearest].real_part > 0 and (above.real_part > 0).sum() == 1
    # modes --shape N draws that mode (mode_shape_3d is what the command draws)
    model = rdm.load_model(path)
    shape = mode_shape_3d(rdm.modal(model, rdm.rpm(float(threshold))), model, int(number))
    assert shape.frequency_hz == pytest.approx(row.frequency_hz, rel=1e-9)
    # the tracked label alone would name another mode at that speed (the bug this numbering fixes)
    assert (int(tracked) != int(number)) == tracked_differs
    if tracked_differs and int(tracked) in table.index:
        assert abs(table.loc[int(tracked)].real_part) > 1e-3 * omega


def test_the_least_damped_mode_of_a_stable_sweep_is_the_one_modes_lists(examples_dir, capsys):
    """The fan on bearings is stable from 0 to 9000 rpm; the summary names the least damped mode
    and its number in ``modes --speed S``: there that mode has the printed frequency, whirl and log
    decrement, and no mode at S has a smaller log decrement."""
    path = examples_dir / "fan_on_bearings.toml"
    _, err = _cli(["stability", path, "--speeds", "0:9000:19", "--out", "-"], capsys)
    found = re.search(r"stable over the range; least damped: mode \d+ at ([0-9.e+]+) rpm: log decrement ([0-9.e+-]+), "
                      r"([0-9.e+]+) Hz, (\w+) whirl \(mode (\d+) of modes --speed ([0-9.e+]+)\)", err)
    assert found, err
    speed, log_dec, frequency, whirl, number, again = found.groups()
    assert float(again) == float(speed)
    table = _modes_table(path, again, capsys)
    row = table.loc[int(number)]
    assert row.frequency_hz == pytest.approx(float(frequency), rel=1e-4) and row.whirl == whirl
    assert row.log_decrement == pytest.approx(float(log_dec), rel=1e-3)
    assert row.log_decrement == table.log_decrement.min()
    model = rdm.load_model(path)            # modes --shape N draws it
    shape = mode_shape_3d(rdm.modal(model, rdm.rpm(float(again))), model, int(number))
    assert shape.frequency_hz == pytest.approx(row.frequency_hz, rel=1e-9)


def test_the_stability_tables_mode_at_speed_is_the_modes_number(examples_dir, capsys):
    """Every row of the stability CSV: the mode ``modes --speed SPEED`` numbers mode_at_speed has
    the row's frequency and real part."""
    path = examples_dir / "unstable_cross_coupled.toml"
    out, _ = _cli(["stability", path, "--speeds", "0:20000:5", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    assert list(table.columns)[:6] == ["speed_rpm", "value", "mode", "real_part", "damping_ratio", "log_decrement"]
    assert table.columns[-1] == "mode_at_speed"
    checked = 0
    for speed, rows in table.groupby("speed_rpm"):
        modes = _modes_table(path, f"{speed:.10g}", capsys)
        for _, row in rows[rows.mode_at_speed.notna()].iterrows():
            listed = modes.loc[int(row.mode_at_speed)]
            assert listed.frequency_hz == pytest.approx(row.frequency_hz, rel=1e-9)
            assert listed.real_part == pytest.approx(row.real_part, rel=1e-7, abs=1e-9)
            checked += 1
        assert sorted(rows.mode_at_speed.dropna().astype(int)) == list(modes.index)   # each mode once
    assert checked == 5 * 6


@pytest.mark.parametrize("example, speeds, some_differ", [
    ("fan_on_bearings.toml", "0:12000:121", True),
    ("unstable_cross_coupled.toml", "0:20000:101", False),
])
def test_critical_speeds_name_the_mode_modes_lists(examples_dir, capsys, example, speeds, some_differ):
    """At each critical speed, the mode ``modes --speed`` numbers mode_at_speed has its frequency
    on the order line (order x the source rotor's speed ratio x speed) and the row's whirl; on
    the fan, tracked labels and those numbers differ for some rows."""
    path = examples_dir / example
    model = rdm.load_model(path)
    ratios = {rotor.name: abs(rotor.speed_ratio) for rotor in model.rotors}
    out, _ = _cli(["critical-speeds", path, "--speeds", speeds, "--orders", "1,2", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    assert list(table.columns)[:6] == ["source", "order", "mode", "speed_rpm", "frequency_hz", "whirl"]
    assert table.columns[-1] == "mode_at_speed"
    rows = table[table.source.isin(list(ratios))]
    differs = rows["mode"] != rows.mode_at_speed
    assert len(rows) >= 5 and differs.any() == some_differ
    for _, row in rows[differs | (np.arange(len(rows)) % 4 == 0)].iterrows():   # a quarter of the others
        modes = _modes_table(path, f"{row.speed_rpm:.10g}", capsys)
        listed = modes.loc[int(row.mode_at_speed)]
        line = row.order * ratios[row.source] * row.speed_rpm / 60.0
        assert listed.frequency_hz == pytest.approx(line, rel=1e-6)
        assert listed.whirl == row.whirl


def test_campbells_mode_at_speed_is_the_modes_number(examples_dir, capsys):
    path = examples_dir / "fan_on_bearings.toml"
    out, _ = _cli(["campbell", path, "--speeds", "0:9000:4", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    assert table.columns[-1] == "mode_at_speed"
    for speed, rows in table.groupby("speed_rpm"):
        modes = _modes_table(path, f"{speed:.10g}", capsys)
        np.testing.assert_allclose(modes.loc[rows.mode_at_speed.astype(int), "frequency_hz"].to_numpy(),
                                   rows.frequency_hz.to_numpy(), rtol=1e-9)


def test_where_a_root_crosses_the_modes_frequency_inside_the_bracket_the_number_is_solved_for(examples_dir):
    """When the sweep's numbers of a mode at the grid speeds around a crossing differ (another
    root crossed its frequency in between), the number comes from the roots solved at the
    critical speed: that of ``modal`` there. Forced here by swapping two columns of the sweep
    at the grid speed above each crossing."""
    from rotordyn_modal.analysis.mode_numbers import numbers_at_crossings

    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 61)), orders=(1,))
    critical = result.critical
    imag = 2 * np.pi * critical.frequencies_hz
    zeta = critical.damping_ratios
    eigenvalues = -zeta * imag / np.sqrt(1 - zeta**2) + 1j * imag
    for p in range(0, len(critical.speeds), 3):
        sweep = result.eigenvalues.copy()
        k = int(np.searchsorted(result.speeds, critical.speeds[p]))
        column = critical.mode[p] - 1
        other = (column + 1) % sweep.shape[1]
        sweep[k, [column, other]] = sweep[k, [other, column]] + [0.0, 1e3j]   # its number changes at k
        found = numbers_at_crossings(model, result.speeds, sweep, critical.speeds[p:p + 1],
                                     critical.mode[p:p + 1], eigenvalues[p:p + 1])[0]
        modes = rdm.modal(model, critical.speeds[p]).to_dataframe()
        assert modes.frequency_hz[found - 1] == pytest.approx(critical.frequencies_hz[p], rel=1e-6)


def test_where_the_order_changes_between_grid_speeds_the_sweep_tells_the_number_without_solving(examples_dir,
                                                                                                monkeypatch):
    """On a coarse grid of the flexible pump, the motor's 2X critical speed near 10,133 rpm lies
    in a bracket where another root passes the mode's frequency (its number is 9 at 10,000 rpm and
    8 at 11,000 rpm): its number at the critical speed is the one ``modal`` gives there, counted
    from the sweep's roots interpolated to that speed, with no eigen-solution at that speed."""
    from rotordyn_modal.analysis import _eigensolve, mode_numbers

    model = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 13)), orders=(1, 2, 3))
    critical = result.critical
    grid = mode_numbers.numbers_at_speed(result.eigenvalues)
    k = np.searchsorted(result.speeds, critical.speeds) - 1
    column = critical.mode - 1
    changed = np.nonzero(grid[k, column] != grid[k + 1, column])[0]
    assert len(changed) >= 1
    imag = 2 * np.pi * critical.frequencies_hz[changed]
    zeta = critical.damping_ratios[changed]
    eigenvalues = -zeta * imag / np.sqrt(1 - zeta**2) + 1j * imag
    expected = []
    for p, lam in zip(changed, eigenvalues):          # modes --speed S: the listed mode nearest the root
        modes = rdm.modal(model, critical.speeds[p]).to_dataframe()
        listed = 2 * np.pi * modes.frequency_hz.to_numpy()
        expected.append(int(modes["mode"].to_numpy()[np.argmin(np.abs(listed - lam.imag))]))
    monkeypatch.setattr(_eigensolve, "eigenvalues_of", lambda *a, **k: pytest.fail("solved at the critical speed"))
    found = mode_numbers.numbers_at_crossings(model, result.speeds, result.eigenvalues, critical.speeds[changed],
                                              critical.mode[changed], eigenvalues)
    np.testing.assert_array_equal(found, expected)


def test_a_number_equal_at_both_grid_speeds_is_not_trusted_between_them():
    """Mode A stays at 10 rad/s; between the grid speeds 1 and 2 root B rises through it (at
    1.2) and root C falls through it (at 1.8). A is mode 2 at both grid speeds, but at 1.5 both
    others lie above it: there it is mode 1 (the count of roots below, by the straight lines
    the roots follow exactly)."""
    from types import SimpleNamespace

    from rotordyn_modal.analysis.mode_numbers import numbers_at_crossings

    grid = np.arange(4.0)
    a = np.full(4, 10.0)
    b = 10.0 + (grid - 1.2)
    c = 10.0 - (grid - 1.8)
    values = -0.01 + 1j * np.stack([a, b, c], axis=1)
    model = SimpleNamespace(dofs=SimpleNamespace(n=3))     # (no root is solved: the lines tell every side)
    assert list(numbers_at_crossings(model, grid, values, np.array([1.5]), np.ones(1, dtype=int),
                                     np.array([-0.01 + 10j]))) == [1]


@pytest.mark.parametrize("example, speeds", [("journal_rotor.toml", (500.0, 20000.0, 20)),
                                             ("unstable_cross_coupled.toml", (0.0, 20000.0, 101))])
def test_the_stability_figure_names_the_threshold_mode_by_its_number_in_modes_too(examples_dir, example, speeds):
    """The figure's threshold label gives the legend's (tracked) label and the number ``modes
    --speed`` gives the mode there: that of the root on the boundary (zero real part) in
    ``modal`` at the threshold speed."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(examples_dir / example)
    result = rdm.stability(model, rdm.rpm(np.linspace(*speeds)))
    fig = result.plot()
    labels = [t.get_text() for t in fig.axes[0].texts if t.get_gid() == "threshold-label"]
    plt.close(fig)
    assert len(labels) == 1 == len(result.thresholds)
    found = re.search(r"mode (\d+) \(no\. (\d+) there\) becomes unstable", labels[0].replace("\n", " "))
    assert found, labels
    modes = rdm.modal(model, result.thresholds[0]).to_dataframe()
    on_boundary = int(modes["mode"].to_numpy()[np.argmin(np.abs(modes.real_part.to_numpy()))])
    assert int(found.group(2)) == on_boundary != int(found.group(1)) == result.threshold_modes[0]


@pytest.mark.parametrize("example, speeds", [
    ("unstable_cross_coupled.toml", (0.0, 20000.0, 101)),
    ("fan_on_bearings.toml", (0.0, 12000.0, 121)),
])
def test_the_python_critical_speeds_table_gives_mode_at_speed(examples_dir, capsys, example, speeds):
    """``rdm.critical_speeds(...).to_dataframe()`` has the command line's ``mode_at_speed``: each
    row's number is the place (1-based) of the root of ``rdm.modal(model, row's speed)`` with the
    row's frequency (and damping ratio, for ties; found so, independently of the numbering code);
    the CSV's column is the Python one."""
    path = examples_dir / example
    model = rdm.load_model(path)
    table = rdm.critical_speeds(model, rdm.rpm(np.linspace(*speeds)), orders=(1, 2)).to_dataframe()
    assert table.columns[-1] == "mode_at_speed" and len(table) >= 5
    for row in table.itertuples():
        result = rdm.modal(model, rdm.rpm(row.speed_rpm))
        modes = result.oscillatory                                   # modal's modes 1, 2, ... in order
        frequencies, zeta = result.frequencies_hz[modes], result.damping_ratios[modes]
        # a tie in frequency (the isotropic rotor's forward and backward whirl) told by the damping ratio
        place = np.flatnonzero(np.isclose(frequencies, row.frequency_hz, rtol=1e-6, atol=0)
                               & np.isclose(zeta, row.damping_ratio, rtol=1e-6, atol=1e-9))
        assert len(place) == 1 and row.mode_at_speed == place[0] + 1, (row, frequencies, zeta)
    low, high, count = speeds
    out, _ = _cli(["critical-speeds", path, "--speeds", f"{low:g}:{high:g}:{count}", "--orders", "1,2",
                   "--out", "-"], capsys)
    np.testing.assert_array_equal(pd.read_csv(io.StringIO(out))["mode_at_speed"].to_numpy(),
                                  table["mode_at_speed"].to_numpy())


_SYMMETRIC_ROTOR = """\
name = "symmetric rigid rotor on two equal isotropic bearings"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"

[[rotors]]
name = "r"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = {polar}
diametral_inertia = 0.5
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "r"
position = [0.3, 0.0, 0.0]
stiffness = 1.0e6
damping = {damping}

[[bearings]]
name = "B"
rotor = "r"
position = [-0.3, 0.0, 0.0]
stiffness = 1.0e6
damping = {damping}
"""


@pytest.mark.parametrize("polar, damping", [(0.2, 0.0), (0.9, 0.0), (0.2, 300.0)])
def test_a_repeated_roots_two_critical_speeds_name_its_two_modes(tmp_path, capsys, polar, damping):
    """A symmetric rigid rotor (m = 10 kg) on two equal isotropic bearings (k = 1e6 N/m at
    +-0.3 m): its cylindrical whirl is a repeated root at every speed, sqrt(2 k / m) (71.18 Hz,
    4270.58 rpm on the 1X line), one backward and one forward whirl of one frequency. Both cross
    the 1X line at that speed; each row names the mode ``modes --speed`` lists with the row's
    whirl (before: both rows said the backward one's number)."""
    path = tmp_path / "symmetric.toml"
    path.write_text(_SYMMETRIC_ROTOR.format(polar=polar, damping=damping))
    out, _ = _cli(["critical-speeds", path, "--speeds", "-30000:30000:121", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    zeta = 2 * damping / (2 * np.sqrt(2 * 1.0e6 * 10.0))
    cylindrical = np.sqrt(2 * 1.0e6 / 10.0) * np.sqrt(1 - zeta**2) * 30 / np.pi     # [rpm], closed form
    for sign in (1, -1):             # reversed spin: modes lists the forward whirl first there
        pair = table[np.isclose(table.speed_rpm, sign * cylindrical, rtol=1e-6)]
        assert sorted(pair.whirl) == ["backward", "forward"], table
        assert pair.mode_at_speed.nunique() == 2, table
    for row in table.itertuples():
        modes = _modes_table(path, f"{row.speed_rpm:.10g}", capsys)
        listed = modes.loc[int(row.mode_at_speed)]
        assert listed.whirl == row.whirl, (row, modes)
        assert listed.frequency_hz == pytest.approx(abs(row.speed_rpm) / 60.0, rel=1e-6)
    # the same in Python
    model = rdm.load_model(path)
    critical = rdm.critical_speeds(model, rdm.rpm(np.linspace(-30000.0, 30000.0, 121)))
    np.testing.assert_array_equal(critical.mode_at_speed, table.mode_at_speed.to_numpy())


@pytest.mark.parametrize("command", ["campbell", "stability"])
def test_a_repeated_roots_members_in_a_sweep_table_are_the_modes_modes_lists(tmp_path, capsys, command):
    """The symmetric rotor swept from -8000 to 8000 rpm: at 0 rpm its conical whirl is a
    repeated root (sqrt(2 k a^2 / Id) = 95.49 Hz), which the sweep reaches tracked from the
    reversed spin, its forward member first. Each row's mode_at_speed is the mode ``modes
    --speed`` lists with the row's frequency and whirl (before: at 0 rpm the forward member
    said 3, the number of the backward one)."""
    path = tmp_path / "symmetric.toml"
    path.write_text(_SYMMETRIC_ROTOR.format(polar=0.2, damping=0.0))
    out, _ = _cli([command, path, "--speeds", "-8000:8000:5", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    conical = np.sqrt(2 * 1.0e6 * 0.3**2 / 0.5) / (2 * np.pi)                         # [Hz] at rest
    at_rest = table[(table.speed_rpm == 0) & np.isclose(table.frequency_hz, conical, rtol=1e-9)]
    assert sorted(at_rest.whirl) == ["backward", "forward"], table
    for speed, rows in table.groupby("speed_rpm"):
        modes = _modes_table(path, f"{speed:.10g}", capsys)
        for row in rows.itertuples():
            listed = modes.loc[int(row.mode_at_speed)]
            assert listed.whirl == row.whirl and listed.frequency_hz == pytest.approx(row.frequency_hz, rel=1e-9), \
                (speed, row, modes)
    # the labels are modes's numbers at the sweep's speed nearest zero (docs/model-file.md)
    np.testing.assert_array_equal(table[table.speed_rpm == 0]["mode"], table[table.speed_rpm == 0].mode_at_speed)


def test_two_sources_of_one_speed_ratio_name_one_mode_once(tmp_path, capsys):
    """A second rotor turning at the reference's speed (held to the ground, no bearings) is a
    second 1X source: each mode crosses both lines at one speed, and both rows are that one mode
    (the backward and forward cylindrical whirl, a repeated root, still told apart by whirl)."""
    path = tmp_path / "two_sources.toml"
    path.write_text(_SYMMETRIC_ROTOR.format(polar=0.2, damping=0.0)
                    + '\n[[rotors]]\nname = "s"\nmass = 1.0\ncenter_of_mass = [2.0, 0.0, 0.0]\n'
                      'polar_inertia = 0.01\ndiametral_inertia = 0.01\nspeed_ratio = 1.0\n')
    out, _ = _cli(["critical-speeds", path, "--speeds", "0:9000:37", "--out", "-"], capsys)
    table = pd.read_csv(io.StringIO(out))
    assert sorted(set(table.source)) == ["r", "s"] and len(table) == 8, table
    for _, rows in table.groupby("mode"):
        assert rows.mode_at_speed.nunique() == 1 and len(rows) == 2, table
    for row in table.itertuples():
        modes = _modes_table(path, f"{row.speed_rpm:.10g}", capsys)
        listed = modes.loc[int(row.mode_at_speed)]
        assert listed.whirl == row.whirl and listed.frequency_hz == pytest.approx(row.speed_rpm / 60.0, rel=1e-6)
