"""Result tables an engineer can combine (issue 27): the tables of ``modal``, ``campbell``,
``stability`` (one sweep and a map) and the critical speeds keep in ``DataFrame.attrs`` only
numbers, one a column, never an array a row.

pandas compares the attrs of the tables it concatenates (``pd.concat`` of two Campbell tables of
112 and 80 rows raised "operands could not be broadcast together"), deep-copies them on every
operation and keeps them on the rows it selects, sorts or groups, where an array a row no longer
lines up with the rows. Each table is put through those operations here; the round-off the
terminal uses row by row (``round_off_rows()``) is checked against the roots' sizes computed from
the table's own columns.
"""

from __future__ import annotations

import copy
import io
import json
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _load(name):
    return rdm.load_model(EXAMPLES / name)


def _tables(kind):
    """Two tables of one kind from the same machine, of different lengths, and the result of the
    first."""
    fan, cross = _load("fan_on_bearings.toml"), _load("unstable_cross_coupled.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if kind == "campbell":
            a, b = rdm.campbell(fan, np.linspace(0, 300, 5)), rdm.campbell(fan, np.linspace(0, 200, 7))
        elif kind == "critical":
            a = rdm.campbell(fan, np.linspace(0, 300, 5)).critical
            b = rdm.campbell(fan, np.linspace(0, 120, 7)).critical
        elif kind == "stability":
            a, b = rdm.stability(cross, np.linspace(0, 1200, 5)), rdm.stability(cross, np.linspace(0, 800, 7))
        elif kind == "stability map":
            key = "suspensions.bearing-A.damping"
            a = rdm.stability(cross, np.linspace(0, 1200, 5), vary=key, scale=[0.5, 1.0])
            b = rdm.stability(cross, np.linspace(0, 800, 3), vary=key, scale=[1.0, 2.0, 4.0])
        else:
            a, b = rdm.modal(fan, 0.0), rdm.modal(_load("spring_block_rotor.toml"), 150.0)
    return a.to_dataframe(), b.to_dataframe(), a


KINDS = ("campbell", "critical", "stability", "stability map", "modal")


def _numbers_only(table):
    round_off = table.attrs["round_off"]         # empty where no column's is one number (stability)
    for column, value in round_off.items():
        assert column in table.columns, column
        assert isinstance(value, float), (column, type(value))


@pytest.mark.parametrize("kind", KINDS)
def test_tables_of_two_lengths_concatenate(kind):
    a, b, _ = _tables(kind)
    assert len(a) != len(b)
    both = pd.concat([a, b], ignore_index=True)
    assert len(both) == len(a) + len(b)
    pd.testing.assert_frame_equal(both.iloc[len(a):].reset_index(drop=True), b)
    # pandas keeps the attrs the tables share, and drops them where they differ (another speed's
    # eigen-solve round-off on a modal table's real part)
    assert both.attrs == (a.attrs if a.attrs == b.attrs else {})
    if both.attrs:
        _numbers_only(both)


@pytest.mark.parametrize("kind", KINDS)
def test_attrs_deep_copy_and_compare(kind):
    a, _, _ = _tables(kind)
    _numbers_only(a)
    copied = copy.deepcopy(a.attrs)
    assert copied == a.attrs
    again = a.copy(deep=True)
    assert again.attrs == a.attrs
    # a table and a deep copy of it (pandas' own copy of the attrs) concatenate
    assert len(pd.concat([a, again])) == 2 * len(a)


@pytest.mark.parametrize("kind", KINDS)
def test_selected_sorted_and_grouped_rows_keep_a_true_round_off(kind):
    a, _, _ = _tables(kind)
    picked = a[a["mode"] == a["mode"].iloc[-1]]
    ordered = a.sort_values("frequency_hz", ascending=False)
    grouped = a.groupby("mode").agg({"frequency_hz": "max", "damping_ratio": "min"})
    assert len(picked) < len(a) and len(grouped) == a["mode"].nunique()
    for table in (picked, ordered):
        assert table.attrs == a.attrs
        _numbers_only(table)
    # a column's one number holds for whichever rows are left
    assert all(np.ndim(v) == 0 for v in grouped.attrs.get("round_off", {}).values())


@pytest.mark.parametrize("kind", KINDS)
def test_csv_round_trip(kind):
    a, _, _ = _tables(kind)
    text = a.to_csv(index=False, float_format="%.17g")
    back = pd.read_csv(io.StringIO(text))
    assert list(back.columns) == list(a.columns)
    for column in a.columns:
        if a[column].dtype.kind == "f":
            np.testing.assert_array_equal(back[column].to_numpy(dtype=float), a[column].to_numpy(dtype=float))
    # the attrs are plain numbers: written beside the CSV as JSON and given back, they compare
    # with the original table's and the two tables concatenate
    back.attrs = json.loads(json.dumps(a.attrs))
    assert back.attrs == a.attrs
    assert len(pd.concat([a, back])) == 2 * len(a)


def _sizes(table):
    """|lambda| of each row from its own columns: real part and 2 pi times the frequency."""
    return np.hypot(table["real_part"].to_numpy(dtype=float), 2 * np.pi * table["frequency_hz"].to_numpy(dtype=float))


def test_campbell_round_off_rows_line_up_with_the_table():
    """The terminal's round-off row by row: 1e-10 |lambda| on the real part (|lambda| from the
    row's own real part and frequency), 1e-10 on the damping ratio (the table's one number)."""
    fan = _load("fan_on_bearings.toml")
    result = rdm.campbell(fan, np.linspace(0, 300, 5))
    for oscillatory_only in (True, False):
        table = result.to_dataframe(oscillatory_only)
        rows = result.round_off_rows(oscillatory_only)
        assert all(len(v) == len(table) for v in rows.values())
        finite = np.isfinite(table["frequency_hz"].to_numpy(dtype=float))
        np.testing.assert_allclose(rows["real_part"][finite], 1e-10 * _sizes(table)[finite], rtol=1e-12)
        assert np.all(rows["damping_ratio"] == 1e-10)
        assert table.attrs["round_off"]["damping_ratio"] == 1e-10
    # a column is in the attrs where, and only where, its round-off is one number
    for column, values in result.round_off_rows().items():
        constant = bool(np.all(values == values[0]))
        assert (column in result.to_dataframe().attrs["round_off"]) == constant, column


def test_stability_round_off_rows_line_up_with_the_table():
    cross = _load("unstable_cross_coupled.toml")
    result = rdm.stability(cross, np.linspace(0, 1200, 5))
    table, rows = result.to_dataframe(), result.round_off_rows()
    assert all(len(v) == len(table) for v in rows.values())
    # at least 1e-10 |lambda| (the stability verdict's tolerance), the eigen-solve's round-off where larger
    assert np.all(rows["real_part"] >= 1e-10 * _sizes(table) * (1 - 1e-12))
    np.testing.assert_allclose(rows["damping_ratio"], rows["real_part"] / _sizes(table), rtol=1e-9)
    key = "suspensions.bearing-A.damping"
    grid = rdm.stability(cross, np.linspace(0, 1200, 5), vary=key, scale=[0.5, 1.0])
    each = [r.round_off_rows()["real_part"] for r in grid.results]
    np.testing.assert_array_equal(grid.round_off_rows()["real_part"], np.concatenate(each))
    assert len(grid.round_off_rows()["real_part"]) == len(grid.to_dataframe())


# -- issue 29 §6: every CSV column's unit can be told from its name or docs/units.md -----------

DOCS_UNITS = EXAMPLES.parent / "docs" / "units.md"
#: name endings that are units (docs/units.md, "Tables: column names")
UNIT_ENDINGS = ("_rpm", "_hz", "_deg", "_rad", "_s", "_m", "_N", "_Nm", "_Pa", "_n_per_m", "_j", "_nm")


def _documented_columns():
    """The backquoted words of docs/units.md's section on columns without a unit in their name."""
    import re

    text = DOCS_UNITS.read_text()
    start = text.index("## Every CSV column without a unit in its name")
    section = text[start:text.index("\n## ", start + 1)]
    return set(re.findall(r"`([A-Za-z_]+)`", section))


def _run(argv, capsys):
    from rotordyn_modal.cli.main import main

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code = main(argv)
    capsys.readouterr()
    assert code == 0, argv


def test_every_csv_column_names_its_unit_or_docs_units_gives_it(tmp_path, capsys):
    """The CSVs of modes, campbell, critical-speeds, stability (and its map), frf (sensors and
    forces), unbalance (response, checks, orbits), static (a flexible shaft), level1 and ucs-map:
    a column without a unit ending is listed in docs/units.md with its unit, or as having none.
    On the base, real_part (1/s), frf's real/imag/magnitude and unbalance's amplitude were in
    neither."""
    ex = lambda name: str(EXAMPLES / name)                     # noqa: E731
    out = lambda name: str(tmp_path / name)                    # noqa: E731
    runs = [
        ["modes", ex("flexible_pump_on_mounts.toml"), "--speed", "3000", "--out", out("modes.csv")],
        ["campbell", ex("fan_on_bearings.toml"), "--speeds", "0:6000:3", "--out", out("campbell.csv")],
        ["critical-speeds", ex("fan_on_bearings.toml"), "--speeds", "0:6000:7", "--out", out("critical.csv")],
        ["stability", ex("unstable_cross_coupled.toml"), "--speeds", "0:12000:3", "--vary",
         "suspensions.bearing-A.damping", "--scale", "1,2", "--out", out("stability.csv")],
        ["frf", ex("gear_machine.toml"), "--speed", "3000", "--freqs", "1:60:3", "--excitation", "hammer-z",
         "--sensor", "acc-top-z", "--out", out("frf.csv")],
        ["frf", ex("gear_machine.toml"), "--speed", "0", "--freqs", "1:60:3", "--force-outputs", "suspensions",
         "--out", out("frf_forces.csv")],
        ["unbalance", ex("fan_on_bearings.toml"), "--speeds", "100:9000:3", "--mcs", "3000", "--iso-group", "2",
         "--iso-support", "flexible", "--amplitude", "pk-pk", "--forces", "all", "--out", out("unbalance.csv"),
         "--checks", out("checks.csv"), "--orbits", out("orbits.csv")],
        ["static", ex("flexible_pump_on_mounts.toml"), "--out", out("static.csv")],
        ["level1", ex("fan_on_bearings.toml"), "--mcs", "3000", "--station", "fan@-0.1", "--qa", "2e5",
         "--out", out("level1.csv")],
        ["ucs-map", ex("fan_on_bearings.toml"), "--stiffness", "1e5:1e9:3", "--out", out("ucs.csv")],
    ]
    for argv in runs:
        _run([*argv, "--quiet"], capsys)
    documented = _documented_columns()
    missing = {}
    for path in sorted(tmp_path.glob("*.csv")):
        for column in pd.read_csv(path, nrows=0).columns:
            named = column.endswith(UNIT_ENDINGS) or column.startswith(("log_decrement_mode_", "frequency_hz_mode_"))
            if not named and column not in documented:
                missing.setdefault(path.name, []).append(column)
    assert len(list(tmp_path.glob("*.csv"))) == 12
    assert not missing, missing


@pytest.mark.parametrize("command", ["campbell", "stability"])
def test_help_gives_real_parts_unit(command):
    """The spec fixes the name real_part; the --help and docs/units.md give its unit, 1/s."""
    import re
    import subprocess
    import sys

    text = subprocess.run([sys.executable, "-m", "rotordyn_modal", command, "--help"], capture_output=True,
                          text=True, check=True, cwd=EXAMPLES.parent).stdout
    assert re.search(r"real_part is the root's real part in 1/s", " ".join(text.split()))
    assert re.search(r"`real_part` \| 1/s", DOCS_UNITS.read_text())
