"""File names that are no UTF-8 (a byte such as 0xff in a Latin-1 name copied from an old
system): Python holds such a name as text with a lone surrogate (``'g\\udcffear.toml'``), which
an HTML page, a netCDF attribute or a TOML file written in UTF-8 refuses. Every command that
writes a file name into a file (the report's model file and command line, a study's
``model_source``, an imported ROSS rotor's name) writes it with the byte shown as ``\\xff``,
and the command ends as it does for any other name."""

from __future__ import annotations

import os
import sys
from pathlib import Path


from rotordyn_modal.cli.main import main
from rotordyn_modal.io.text import shown_text

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
ROSS = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"

#: a file name byte that no UTF-8 text has
NAME = os.fsdecode(b"g\xffear")


def _copy(source: Path, target: Path) -> Path:
    target.write_bytes(source.read_bytes())
    return target


def test_shown_text_shows_the_byte_and_leaves_other_text():
    """The definition: the name's bytes, each byte that is no UTF-8 as ``\\xNN``."""
    assert shown_text(NAME + ".toml") == "g\\xffear.toml"
    assert shown_text(b"g\xffear.toml") == "g\\xffear.toml"
    assert shown_text(Path("caf\u00e9 \u00fc.toml")) == "caf\u00e9 \u00fc.toml"
    assert shown_text("a\ud800b") == "a\\ud800b"       # a surrogate no file name gives
    shown_text(NAME).encode("utf-8")                      # and what comes out is UTF-8


def test_report_of_a_model_whose_name_is_no_utf8(tmp_path, monkeypatch):
    model = _copy(EXAMPLES / "motor_fan_minimal.toml", tmp_path / (NAME + ".toml"))
    out = tmp_path / (NAME + ".html")
    argv = ["report", str(model), "--standard", "iso", "--mcs", "3000", "--points", "11", "--out", str(out),
            "--quiet"]
    monkeypatch.setattr(sys, "argv", ["rotordyn-modal", *argv])      # the command line the report quotes
    assert main(argv) == 0
    html = out.read_text(encoding="utf-8")
    assert "g\\xffear.toml" in html                   # the model file's name
    assert "g\\xffear.html" in html                   # and the command line


def test_study_of_a_model_whose_name_is_no_utf8(tmp_path):
    import xarray as xr

    model = _copy(EXAMPLES / "gear_machine.toml", tmp_path / (NAME + ".toml"))
    spec = tmp_path / (NAME + ".study.toml")
    spec.write_text('samples = 2\nseed = 1\n[[parameters]]\nkey = "suspensions.mount-FL.stiffness"\n'
                    'apply = "scale"\ndistribution = "uniform"\nlow = 0.9\nhigh = 1.1\n'
                    '[analyses.campbell]\nspeeds_rpm = "0:3000:3"\n', encoding="utf-8")
    out = tmp_path / "s.nc"
    assert main(["study", str(model), "--spec", str(spec), "--out", str(out), "--quiet"]) == 0
    with xr.open_dataset(out) as data:
        assert data.attrs["model_source"] == str(tmp_path / "g\\xffear.toml")
        assert data.attrs["study_source"] == str(tmp_path / "g\\xffear.study.toml")


def test_import_ross_of_a_file_whose_name_is_no_utf8(tmp_path):
    import tomllib

    source = _copy(ROSS, tmp_path / (NAME + ".toml"))
    out = tmp_path / "model.toml"
    assert main(["import-ross", str(source), "--out", str(out), "--quiet"]) == 0
    written = tomllib.loads(out.read_text(encoding="utf-8"))
    assert written["rotors"][0]["name"] == "g\\xffear"
    assert "file g\\xffear.toml" in written["name"]
    assert main(["check", str(out), "--quiet"]) == 0
