"""Inputs, files and options a user tries that the earlier reproductions did not: files the
package itself wrote read back, measured lines of no physical meaning, ROSS rotors that are no
model, study paths and ranges, files that are pipes. Each case through the command line in
this process (``rotordyn_modal.cli.main``): the right answer, or exit 2 with one line naming
the file or option and nothing written."""

from __future__ import annotations

import os
import threading
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tomli_w

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.io.measured import read_measured

ROOT = Path(__file__).resolve().parent.parent
GEAR = str(ROOT / "examples" / "gear_machine.toml")
ROSS = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"
#: one US customary unit of each FRF over a force, in SI: in/lbf, in/s/lbf, g/lbf
_INCH, _LBF, _G = 0.0254, 0.45359237 * 9.80665, 9.80665


def _one_line_error(capsys, *words):
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    return err


# ----------------------------------------------------------------------- FRF CSV read back
@pytest.mark.parametrize("quantity, si_per_us", [("receptance", _INCH / _LBF), ("mobility", _INCH / _LBF),
                                                 ("accelerance", _G / _LBF)],
                         ids=["receptance", "mobility", "accelerance"])
def test_an_frf_csv_written_in_us_units_reads_back_as_the_si_frf(tmp_path, quantity, si_per_us):
    """``--units us frf --out f.csv`` then ``--measured f.csv``: the same FRF in SI, of its own
    speed and quantity (the CSV had neither, and its unit column was ignored: read as SI
    receptance at 0 rpm)."""
    out = tmp_path / "us.csv"
    assert main(["--units", "us", "frf", GEAR, "--speed", "3000", "--freqs", "2:40:5", "--quantity", quantity,
                 "--out", str(out), "--quiet"]) == 0
    us = pd.read_csv(out)
    model = rdm.load_model(GEAR)
    exact = rdm.frf(model, rdm.rpm(3000), np.linspace(2, 40, 5), quantity=quantity)
    row = us.iloc[0]   # the file's number is the SI value over the unit's size in SI
    assert row.real + 1j * row.imag == pytest.approx(exact.H[0, 0, 0] / si_per_us, rel=1e-9)
    [back] = read_measured(out, model)
    assert back.quantity == quantity and back.speed == pytest.approx(rdm.rpm(3000), rel=1e-12)
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-9)


def test_an_si_unit_column_is_converted_and_an_unknown_one_refused(tmp_path, capsys):
    out = tmp_path / "si.csv"
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--out", str(out), "--quiet"]) == 0
    table = pd.read_csv(out).drop(columns=["quantity"])
    table["unit"] = "mm/N"   # the same numbers said to be in mm/N are 1000 times smaller in m/N
    table.to_csv(tmp_path / "mm.csv", index=False)
    model = rdm.load_model(GEAR)
    [si], [mm] = read_measured(out, model), read_measured(tmp_path / "mm.csv", model)
    np.testing.assert_allclose(mm.H, si.H * 1e-3, rtol=1e-15)
    table["unit"] = "V/N"
    table.to_csv(tmp_path / "volts.csv", index=False)
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--measured", str(tmp_path / "volts.csv"),
                 "--plot", str(tmp_path / "v.png"), "--quiet"]) == 2
    _one_line_error(capsys, "volts.csv", "unit", "'V/N'")
    assert not (tmp_path / "v.png").exists()


@pytest.mark.parametrize("change, words", [
    ({"frequency_hz": -1.0}, ["-1 Hz", "frequencies >= 0"]),
    ({"coherence": 2.0}, ["coherence of 2", "from 0 to 1"]),
    ({"real": 1e308, "imag": 1e308}, ["magnitude", "at most 1e+30"]),
], ids=["negative-frequency", "coherence-above-1", "overflowing-value"])
def test_measured_lines_of_no_physical_meaning_are_refused(tmp_path, capsys, change, words):
    """Each was accepted (drawn, fitted) or ended in an OverflowError (exit 1)."""
    out = tmp_path / "m.csv"
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--out", str(out), "--quiet"]) == 0
    table = pd.read_csv(out)
    table["coherence"] = 1.0
    for column, value in change.items():
        table.loc[table.index[:1], column] = value
    table.to_csv(out, index=False)
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--measured", str(out), "--plot", str(tmp_path / "p.png"),
                 "--quiet"]) == 2
    _one_line_error(capsys, "m.csv", *words)
    assert not (tmp_path / "p.png").exists()


def test_a_mapping_names_a_driving_point_once_for_both_roles(tmp_path):
    """A sensor and an excitation of one name (a driving point named once): a mapping row of
    that name maps both (it mapped the sensor only, and the excitation could never be read)."""
    text = Path(GEAR).read_text().replace('name = "hammer-z"', 'name = "acc-top-z"')
    model_file = tmp_path / "same.toml"
    model_file.write_text(text)
    uff = tmp_path / "m.uff"
    assert main(["frf", str(model_file), "--freqs", "2:40:5", "--out", str(uff), "--quiet"]) == 0
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nacc-top-z,101,3\nshaker-y,102,2\n")
    model = rdm.load_model(model_file)
    [back] = read_measured(uff, model, mapping)
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 5))
    assert back.inputs == exact.inputs and back.outputs == exact.outputs
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-9)


def test_a_mapping_node_beyond_the_uff_field_is_refused(tmp_path, capsys):
    """It reached pyuff's writer: TypeError, exit 1."""
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,1e30,3\nshaker-y,102,2\n")
    out = tmp_path / "o.uff"
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--mapping", str(mapping), "--out", str(out), "--quiet"]) == 2
    _one_line_error(capsys, "map.csv", "line 4", "node")
    assert not out.exists()


# ----------------------------------------------------------------------- ROSS rotors
@pytest.mark.parametrize("element, key, value, words", [
    ("ShaftElement_Shaft Element 0", "L", -0.25, ["shaft.0] length", "-0.25"]),
    ("DiskElement_Disk 0", "m", 0.0, ["Disk 0] mass"]),
    ("BearingElement_Bearing 0", "cxx", -1.0, ["Bearing 0] damping"]),
], ids=["negative-length", "massless-disk", "negative-damping"])
def test_a_ross_rotor_that_is_no_model_is_refused_and_nothing_written(tmp_path, capsys, element, key, value,
                                                                      words):
    """``import-ross`` wrote these (exit 0) as model files that ``check`` then refused."""
    data = tomllib.loads(ROSS.read_text())
    data[element][key] = value
    bad = tmp_path / "bad.toml"
    bad.write_bytes(tomli_w.dumps(data).encode())
    out = tmp_path / "model.toml"
    assert main(["import-ross", str(bad), "--out", str(out)]) == 2
    _one_line_error(capsys, "bad.toml", *words)
    assert not out.exists()


# ----------------------------------------------------------------------- studies
_STUDY = ('samples = 2\n[[parameters]]\nkey = "suspensions.mount-FL.stiffness"\napply = "scale"\n'
          'distribution = "uniform"\nlow = 0.9\nhigh = 1.1\n[analyses.campbell]\nspeeds_rpm = "{speeds}"\n')


@pytest.mark.parametrize("speeds, extra, words", [
    ("0:3000:3", ["--table", "{tmp}/t.png"], ["--table", ".csv"]),
    ("0:3000:1", [], ["speeds_rpm", "N >= 2"]),
    ("0:3000:3", ["--dangling"], ["symbolic link", "does not exist"]),
], ids=["table-not-csv", "one-point-range", "dangling-checkpoint-link"])
def test_study_paths_and_ranges_refused_before_the_work(tmp_path, capsys, speeds, extra, words):
    """A CSV written into ``t.png``; ``0:3000:1`` computed at 0 rpm only; a checkpoint folder
    that is a dangling link ended in FileExistsError (exit 1)."""
    spec = tmp_path / "s.toml"
    spec.write_text(_STUDY.format(speeds=speeds))
    out = tmp_path / "r.nc"
    if extra == ["--dangling"]:
        os.symlink(tmp_path / "nowhere", tmp_path / "r.nc.partial")
        extra = []
    extra = [e.format(tmp=tmp_path) for e in extra]
    assert main(["study", GEAR, "--spec", str(spec), "--out", str(out), "--quiet", *extra]) == 2
    _one_line_error(capsys, *words)
    assert not out.exists() and not (tmp_path / "t.png").exists()


# ----------------------------------------------------------------------- pipes
def test_a_model_through_a_pipe_is_read_up_to_the_limit(tmp_path, capsys, monkeypatch):
    """A pipe has no size to check before reading (``/dev/zero`` took every byte of memory):
    a model file through a pipe is read, one longer than the limit refused."""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", "0.01")   # 10,485 bytes
    model = Path(GEAR).read_text()

    def run(text):
        fifo = tmp_path / f"pipe{len(text)}.toml"
        os.mkfifo(fifo)

        def write():
            try:
                with open(fifo, "w") as handle:
                    handle.write(text)
            except BrokenPipeError:   # the reader stopped at the limit
                pass

        writer = threading.Thread(target=write)
        writer.start()
        try:
            return main(["check", str(fifo)])
        finally:
            writer.join(timeout=10)

    assert len(model) < 10_000 and run(model) == 0
    capsys.readouterr()
    assert run(model + "#" * 20_000 + "\n") == 2
    _one_line_error(capsys, "pipe", "limit")


def test_every_output_folder_is_checked_before_the_work_by_its_option(tmp_path, capsys):
    """``level1 --csr-plot missing/x.png`` was refused only by the final write, without the option's name."""
    journal = str(ROOT / "examples" / "journal_rotor.toml")
    out = tmp_path / "missing" / "csr.png"
    assert main(["level1", journal, "--speed", "4000", "--station", "rotor", "--qa", "2e5", "--gas-density", "10",
                 "--quiet", "--csr-plot", str(out)]) == 2
    _one_line_error(capsys, "--csr-plot", "does not exist")
    assert not out.parent.exists()


@pytest.mark.parametrize("kind, old, new, suggestion", [
    ("model", "\nstiffness = ", "\nstifness = ", "'stiffness'"),
    ("study", 'speeds_rpm = "0:3000:3"', 'speed_rpm = "0:3000:3"', "'speeds_rpm'"),
    ("study", "samples = 2", "sample = 2", "'samples'"),
], ids=["model-key", "analysis-key", "study-key"])
def test_a_typed_key_is_refused_with_the_key_it_is_probably_a_typo_of(tmp_path, capsys, kind, old, new, suggestion):
    model_file, spec = tmp_path / "m.toml", tmp_path / "s.toml"
    model_text, study_text = Path(GEAR).read_text(), _STUDY.format(speeds="0:3000:3")
    model_file.write_text(model_text.replace(old, new, 1) if kind == "model" else model_text)
    spec.write_text(study_text.replace(old, new, 1) if kind == "study" else study_text)
    assert main(["study", str(model_file), "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]) == 2
    _one_line_error(capsys, new.strip().split()[0], f"did you mean {suggestion}?")


@pytest.mark.parametrize("old, new, where", [
    ("[stator]\nmass = 150.0", "[stator]\nmass = 1" + "0" * 400, "stator.mass"),
    ("spin_axis = [1.0,", "spin_axis = [1" + "0" * 400 + ",", "spin_axis[0]"),
], ids=["scalar", "in-an-array"])
def test_an_integer_beyond_every_float_is_refused_by_its_key(tmp_path, capsys, old, new, where):
    """TOML integers have no limit: one of 401 digits ended in OverflowError (exit 1)."""
    text = Path(GEAR).read_text()
    assert old in text
    model_file = tmp_path / "m.toml"
    model_file.write_text(text.replace(old, new, 1))
    assert main(["check", str(model_file)]) == 2
    _one_line_error(capsys, "m.toml", where, "401 digits", "at most 1e+30")


@pytest.mark.parametrize("command", ["campbell", "critical-speeds"])
def test_lowest_modes_beyond_the_models_roots_are_every_root(tmp_path, command):
    """``--lowest 1000`` of a machine of 6 roots ended in ValueError (exit 1); a number of 17
    digits asked numpy for 711 PiB. The 1000 lowest of 6 roots are the 6: the table without
    --lowest."""
    args = [command, GEAR, "--speeds", "0:3000:4", "--quiet", "--out"]
    assert main([*args, str(tmp_path / "all.csv")]) == 0
    for count in ("1000", "9" * 17):
        assert main([*args, str(tmp_path / "low.csv"), "--lowest", count]) == 0
        pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "low.csv"), pd.read_csv(tmp_path / "all.csv"))


def test_a_bore_tapering_to_zero_at_a_sections_end_is_a_valid_shaft(tmp_path):
    """ROSS's compressor rotor with one layer's bore tapering to 0: the element's end, found by
    summing the lengths, lay past the section by round-off, and the bore there came out as
    -7.5e-17 m (ValueError, exit 1 from `check` and `import-ross`)."""
    from rotordyn_modal.io.ross_file import read_ross_rotor

    description = read_ross_rotor(ROOT / "tests" / "data" / "ross" / "compressor_example.toml")
    layer = description["rotors"][0]["shaft"][9]["layers"][0]   # a parallel element of ROSS's
    assert layer["inner_diameter"] == 0.085
    layer["inner_diameter"] = [0.085, 0.0]
    rdm.Model.from_dict(description)   # refused, or a ValueError, if a bore came out below 0
