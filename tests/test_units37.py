"""Issue 29, units (note22's spec proposal): every column of every CSV the command line writes either
ends in its unit or is listed in docs/units.md, "Every CSV column without a unit in its name".

The columns are collected by running each sub-command that writes a CSV on examples that between
them have every kind of row (several rotors and a gear mesh, a flexible shaft, bearings with
pedestals and probe pairs), in SI and in US units. The list is read from the page
itself (every name in backquotes in that section), so that the page and the command line cannot
part: a new column without a unit in its name fails here until the page gives its unit."""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd

from quiet_cli import run_quietly
from rotordyn_modal.io import load_model

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

#: the endings of a column that names its unit, SI and US customary (a unit vocabulary of this test's
#: own: rpm, Hz, degrees, radians, seconds, metres, newtons, newton metres, N/m, pascals, percent,
#: joules, rad/s; inches, mils, pounds-force, lbf in, lbf/in, psi, pounds)
UNIT_ENDINGS = ("_rpm", "_hz", "_deg", "_rad", "_s", "_rad_s", "_m", "_N", "_Nm", "_nm", "_n_per_m", "_Pa", "_pct",
                "_J", "_j", "_in", "_mil", "_lbf", "_lbfin", "_lbf_per_in", "_psi", "_lb")

SECTION = "## Every CSV column without a unit in its name"
#: level1's Qa, 1e5 N/m, typed in each system (the same sweep in both: 1e5 lbf/in would sweep 175
#: times further and cost 25 times as much)
QA = {"si": "1e5", "us": "571"}
STUDY = """
seed = 1
samples = 3
design = "latin-hypercube"

[[parameters]]
key = "stator.mass"
apply = "value"
distribution = "uniform"
low = 110.0
high = 130.0

[analyses.critical_speeds]
speeds_rpm = "0:4000:21"
orders = [1]

[analyses.unbalance]
speeds_rpm = "500:4000:8"
forces = "bearings"
"""


def _listed():
    """Every name in backquotes in the page's section, whether it lists a sensor's own column, and
    the section's text."""
    text = (ROOT / "docs" / "units.md").read_text()
    section = text[text.index(SECTION):]
    section = section[:section.index("\n## ", 1)]
    return set(re.findall(r"`([^`]+)`", section)), "each sensor's column (its name)" in section, section


def _commands(tmp_path):
    """(example, argv without --units, {option: file}) of every CSV the command line writes."""
    def ex(name):
        return str(EXAMPLES / f"{name}.toml")

    study = tmp_path / "small.study.toml"
    study.write_text(STUDY)
    for name in ("gear_machine", "flexible_pump_on_mounts", "fan_on_bearings"):
        low = "0"
        model = load_model(ex(name))
        yield name, ["modes", ex(name), "--speed", "3000"], {}
        yield name, ["campbell", ex(name), "--speeds", f"{max(int(low), 100)}:3000:3"], {}
        yield name, ["critical-speeds", ex(name), "--speeds", f"{max(int(low), 100)}:6000:3"], {}
        yield name, ["stability", ex(name), "--speeds", "1000:3000:2"], {}
        yield name, ["stability", ex(name), "--speeds", "1000:3000:2", "--vary", f"rotors.{model.rotors[0].name}.mass",
                     "--scale", "1:2:2"], {}
        if model.excitations:
            yield name, ["frf", ex(name), "--speed", "3000", "--freqs", "10:200:3", "--force-outputs", "all"], {}
        yield name, ["unbalance", ex(name), "--speeds", "1000:5000:3", "--forces", "all", "--mcs", "5000",
                     "--iso-group", "2", "--iso-support", "flexible", "--amplitude", "pk-pk"], \
            {"--checks": "checks.csv", **({"--orbits": "orbits.csv"} if name == "fan_on_bearings" else {})}
        yield name, ["unbalance", ex(name), "--speeds", "1000:5000:3", "--api-unbalance", "--mcs", "5000"], \
            {"--checks": "api_checks.csv"}
        yield name, ["static", ex(name), "--speed", "3000"], {}
        if not model.bearings:                       # ucs-map and level1 need a rotor in bearings
            continue
        yield name, ["ucs-map", ex(name), "--stiffness", "1e5:1e9:2", "--speeds", "1000:5000:3"], {}
        held = {b.rotor for b in model.bearings}
        rotor = next(r.name for r in model.rotors if r.name in held)
        yield name, ["level1", ex(name), "--mcs", "5000", "--station", rotor, "--qa", QA, "--factor", "1",
                     "--forward-mode", "1"], {}
    yield "fan_on_bearings", ["simulate", ex("fan_on_bearings"), "--duration", "0.005", "--speed", "3000",
                              "--samples", "5"], {}
    yield "motor_pump_on_mounts", ["study", ex("motor_pump_on_mounts"), "--spec", str(study), "--workers", "1"], \
        {"--table": "table.csv"}


def _covered(column, listed, sensors_listed, model, keys=(), listed_text=()):
    """Whether ``column`` ends in its unit or the page lists it (a model's names by its patterns)."""
    stem = column.split("[")[0]                        # critical_speed[SOURCE,ORDER,MODE], study's columns
    if stem.endswith(UNIT_ENDINGS) or column in listed or stem in listed:
        return True
    if "[" in column and any(token.split("[")[0] == stem for token in listed):
        return True
    if column in {s.name for s in model.sensors}:
        return sensors_listed
    if column in keys:                                  # a study parameter's column: its key
        return "a parameter's column (its key" in " ".join(listed_text)
    for names, word in (([r.name for r in model.rotors], "ROTOR"), ([b.name for b in model.bearings], "BEARING")):
        for name in names:                             # ROTOR_center_x ..., BEARING_Fx ... _Mz
            if column.startswith(name + "_") and re.sub("[xyz]$", "x", word + column[len(name):]) in listed:
                return True
    return False


def test_every_csv_column_names_its_unit_or_is_listed(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_NUM_THREADS", "1")
    listed, sensors_listed, section = _listed()
    assert "real_part" in listed and "amplitude" in listed
    missing, seen = {}, 0
    for k, (example, argv, extra) in enumerate(_commands(tmp_path)):
        model = load_model(str(EXAMPLES / f"{example}.toml"))
        for units in ("si", "us"):
            folder = tmp_path / f"{k}-{units}"
            folder.mkdir()
            out = ["--out", str(folder / ("results.nc" if argv[0] == "study" else "out.csv"))]
            files = [str(folder / name) for name in extra.values()]
            typed = [QA[units] if a is QA else a for a in argv]
            code, err = run_quietly(["--units", units, *typed, *out, *[a for o, f in zip(extra, files) for a in (o, f)]])
            assert code == 0, (argv, units, err[-400:])
            for path in [p for p in folder.glob("*.csv")]:
                for column in pd.read_csv(path, nrows=0).columns:
                    seen += 1
                    if not _covered(column, listed, sensors_listed, model, ("stator.mass",), (section,)):
                        missing.setdefault(column, f"{argv[0]} {example} --units {units} ({path.name})")
    assert seen > 200
    assert not missing, f"columns without a unit in their name not listed in docs/units.md: {missing}"
