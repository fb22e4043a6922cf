"""--out of every sub-command: a file ending that is not a format the sub-command writes is refused
before any work (exit 2, one line, nothing written), e.g. ``--out c.png`` (CSV written into a PNG before)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotordyn_modal.cli.main import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
GEAR = str(EXAMPLES / "gear_machine.toml")

COMMANDS = {
    "modes": ["modes", GEAR],
    "static": ["static", GEAR],
    "campbell": ["campbell", GEAR, "--speeds", "0:100:3"],
    "critical-speeds": ["critical-speeds", GEAR, "--speeds", "0:100:3"],
    "stability": ["stability", GEAR, "--speeds", "0:100:3"],
    "ucs-map": ["ucs-map", str(EXAMPLES / "journal_rotor.toml"), "--stiffness", "1e5:1e6:3"],
    "level1": ["level1", str(EXAMPLES / "journal_rotor.toml"), "--speed", "3000", "--station", "rotor", "--qa", "1e4"],
    "simulate": ["simulate", GEAR, "--duration", "0.01"],
    "unbalance": ["unbalance", GEAR, "--speeds", "0:100:3"],
    "frf": ["frf", GEAR, "--freqs", "1:10:3"],
    "fit": ["fit", GEAR, "--measured", GEAR, "--params", "suspensions.mount-FL.stiffness"],
    "study": ["study", GEAR, "--spec", str(EXAMPLES / "mount_tolerance.study.toml")],
    "report": ["report", GEAR, "--standard", "api684", "--mcs", "3000"],
}
ENDINGS = {"fit": ".toml", "study": ".nc", "frf": ".csv or .uff or .unv", "report": ".html or .htm"}


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("name", ["c.png", "c.uff.txt", "c"])
def test_an_out_in_a_format_not_written_is_refused(command, name, tmp_path, capsys):
    target = tmp_path / name
    code = main([*COMMANDS[command], "--out", str(target), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and not target.exists() and len(err.strip().splitlines()) == 1, err
    assert f"{target}" in err and "expected" in err
    if command not in ("study",):
        assert f"expected a file ending in {ENDINGS.get(command, '.csv')}" in err


@pytest.mark.parametrize("name", ["f.CSV", "f.uff", "f.UNV"])
def test_frf_writes_every_ending_it_names(name, tmp_path):
    assert main([*COMMANDS["frf"], "--out", str(tmp_path / name), "--quiet"]) == 0
    assert (tmp_path / name).stat().st_size > 0


def test_unbalance_orbits_table_must_be_csv(tmp_path, capsys):
    target = tmp_path / "o.png"
    code = main([*COMMANDS["unbalance"], "--orbits", str(target), "--quiet"])
    assert code == 2 and not target.exists()
    assert f"--orbits {target}: expected a file ending in .csv" in capsys.readouterr().err
