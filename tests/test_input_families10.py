"""Hidden-check families of issue 27 tried anew (scales across decades, roots of very different
sizes): each test here failed on the main of 2026-11-29 before its fix.

Truth from outside the code: a machine without damping and with a symmetric stiffness is
conservative, so every root is on the imaginary axis (no damping ratio can be anything but 0);
a short solid shaft is, in its conical modes, the rigid rotor of the same mass properties, whose
orbits are circles (whirl ratio +-1).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main

_MATERIAL = """
[[materials]]
name = "steel"
density = 7800.0
young_modulus = 2.0e11
poisson_ratio = 0.3
"""


def _shaft_model(path, sections, bearings, stiffness, element_length=None):
    """A flexible rotor of ``sections`` (length, diameter) on two isotropic bearings of
    ``stiffness`` N/m at ``bearings`` (axial positions), no damping anywhere; written to ``path``."""
    text = 'name = "shaft"\n' + _MATERIAL + '\n[[rotors]]\nname = "s"\nspeed_ratio = 1.0\nstart = [0.0, 0.0, 0.0]\nshear = "none"\n'
    if element_length:
        text += f"element_length = {element_length!r}\n"
    for length, diameter in sections:
        text += f'\n[[rotors.shaft]]\nlength = {length!r}\nouter_diameter = {diameter!r}\nmaterial = "steel"\n'
    for i, at in enumerate(bearings):
        text += f'\n[[bearings]]\nname = "b{i}"\nrotor = "s"\naxial_position = {at!r}\nstiffness = {stiffness!r}\n'
    path.write_text(text, encoding="utf-8")
    return path


def _terminal_table(text):
    """The modes table printed on the terminal, as strings by column."""
    lines = [line.split() for line in text.splitlines() if line.strip()]
    header = lines[0]
    rows = [line for line in lines[1:] if len(line) == len(header) and line[0].isdigit()]
    return pd.DataFrame(rows, columns=header)


def test_modes_of_an_undamped_machine_print_no_damping(tmp_path, capsys):
    """A 10 m shaft meshed around a 1 mm section, on 1e3 N/m bearings, no damping: the eigen-solve's
    real parts (1e-6 .. 1e-5 1/s, above its round-off estimate: the roots are ill-conditioned) printed
    as damping ratios of +-4e-7 and log decrements of -2.6e-6 on main, which read as unstable."""
    model = _shaft_model(tmp_path / "shaft.toml", [(5.0, 0.05), (0.001, 0.05), (4.999, 0.05)], [1.0, 9.0],
                         1e3, element_length=1.0)
    assert main(["modes", str(model), "--speed", "3000"]) == 0
    table = _terminal_table(capsys.readouterr().out)
    assert len(table) >= 6
    for column in ("damping_ratio", "log_decrement", "real_part"):
        assert (table[column].astype(float) == 0.0).all(), (column, table[column].tolist())


def _conical_roots(mass_moment_polar, mass_moment_diametral, tilt_stiffness, speed):
    """The rigid rotor's conical whirl frequencies [rad/s] (backward, forward) on isotropic
    bearings: ``J_d w^2 -+ J_p Omega w - k_t = 0``."""
    b = mass_moment_polar * speed / (2.0 * mass_moment_diametral)
    root = math.sqrt(b * b + tilt_stiffness / mass_moment_diametral)
    return root - b, root + b


def test_a_short_solid_shafts_conical_modes_whirl_as_the_rigid_rotors(tmp_path):
    """A solid shaft 2 mm long and 50 mm across (a disk) on 1e7 N/m bearings at its ends: its conical
    modes are the rigid disk's, circular orbits backward and forward. On main the consistent mass's
    node inertias (diametral below half the polar) made the whirl form N negative: ratio 0, 'none'."""
    import rotordyn_modal as rdm

    diameter, length, k = 0.05, 0.002, 1e7
    path = _shaft_model(tmp_path / "disk.toml", [(length / 2, diameter), (length / 2, diameter)], [0.0, length], k)
    speed = 3000 * math.pi / 30
    result = rdm.modal(rdm.load_model(path), speed)
    mass = 7800.0 * math.pi * diameter ** 2 / 4 * length
    polar = mass * diameter ** 2 / 8
    diametral = mass * (3 * (diameter / 2) ** 2 + length ** 2) / 12
    backward, forward = _conical_roots(polar, diametral, 2 * k * (length / 2) ** 2, speed)
    for expected, label, sign in ((backward, "backward", -1.0), (forward, "forward", 1.0)):
        i = int(np.argmin(np.abs(result.frequencies_hz - expected / (2 * math.pi))))
        assert result.frequencies_hz[i] == pytest.approx(expected / (2 * math.pi), rel=0.01)
        assert result.whirl[i] == label
        assert result.whirl_ratios[i] == pytest.approx(sign, abs=1e-3)


def test_the_whirl_forms_of_a_flexible_rotor_count_no_negative_motion():
    """The mean square motion normal to the spin axis (the whirl form N) and the whole motion are
    sums of squares: positive semidefinite, for the compressor's 0.1 m elements of a 0.1-0.2 m
    shaft too (on main: N had an eigenvalue of -1.2e-4 beside 30)."""
    from pathlib import Path

    import rotordyn_modal as rdm
    from rotordyn_modal.analysis._whirl import whirl_forms

    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "compressor_rotor.toml")
    forms = whirl_forms(model)
    for form in (forms.N, forms.total):
        values = np.linalg.eigvalsh(0.5 * (form + form.T))
        assert values.min() >= -1e-12 * values.max()


_EXAMPLES = __import__("pathlib").Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("old, new, table", [
    ('name = "motor-DE"', 'name = "fan"', "[bearings.fan]"),             # a bearing called as a rotor
    ('name = "motor-DE"', 'name = "mount-FL"', "[bearings.mount-FL]"),   # ... as a suspension
    ('name = "mount-RR"', 'name = "motor"', "[suspensions.motor]"),      # a suspension called as a rotor
    ('name = "acc-fan-z"', 'name = "mount-FL:Fz"', "[sensors.mount-FL:Fz]"),   # a sensor as a force row
], ids=["bearing-rotor", "bearing-suspension", "suspension-rotor", "sensor-force-row"])
def test_two_items_whose_force_rows_would_share_a_name_are_refused(tmp_path, capsys, old, new, table):
    """``frf``/``unbalance --forces all`` name force rows NAME:Fx ... NAME:Mz by suspension, bearing
    and rotor, in the sensors' output column. On main a bearing called as its rotor gave two
    different series both ``fan:Fx`` (exit 0); now the model is refused naming the table."""
    text = (_EXAMPLES / "fan_on_bearings.toml").read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / "m.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    out = tmp_path / "f.csv"
    code = main(["frf", str(path), "--freqs", "1:50:3", "--excitation", "hammer-z", "--forces", "all", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    if code == 0:      # what main did: the rows of two items under one name
        rows = pd.read_csv(out)
        assert not rows.groupby(["output", "frequency_hz"]).size().gt(1).any(), "two force series share a name"
    assert code == 2 and len(err) == 1 and table in err[0] and "name" in err[0], err
    assert not out.exists()


@pytest.mark.parametrize("length", [200, 250])
def test_an_output_whose_name_is_near_the_longest_allowed_is_written(tmp_path, capsys, length):
    """A file name of 200-250 bytes is valid (the limit is 255), but the temporary written beside it
    and renamed into place (``.NAME.rdm-tmp.PID-HOST.XXXXXXXX.csv``) was 40 bytes longer: on main
    ``modes --out`` refused such a name as "File name too long" after the work."""
    model = _EXAMPLES / "gear_machine.toml"
    out = tmp_path / ("m" * (length - len(".csv")) + ".csv")
    assert main(["modes", str(model), "--speed", "100", "--out", str(out)]) == 0, capsys.readouterr().err
    rows = pd.read_csv(out)
    assert list(rows["mode"]) == list(range(1, len(rows) + 1)) and len(rows) == 6
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]      # no temporary left


def test_a_long_named_outputs_temporary_left_by_a_killed_run_is_removed(tmp_path):
    """The next write of the same long name finds the temporary a killed process left (its name
    shortened the same way in every process) and removes it."""
    from rotordyn_modal.io import atomic

    out = tmp_path / ("n" * 246 + ".csv")
    dead = 2 ** 22 + 12345              # above Linux's largest process id: never alive
    left = tmp_path / f".{atomic._temporary_stem(out)}.{atomic._MARK}.{dead}-{atomic._host()}.abcdefgh.csv"
    left.write_text("partial")
    assert len(left.name.encode()) <= 255
    with atomic.atomic_write(out) as handle:
        handle.write("whole\n")
    assert out.read_text() == "whole\n" and not left.exists()


def _python(code, timeout=60):
    """Run ``code`` in a fresh interpreter with this checkout first on the path; (exit code, output).
    A reader that hangs fails the test by its timeout instead of hanging the suite."""
    import os
    import subprocess
    import sys

    root = str(_EXAMPLES.parent)
    env = {**os.environ, "PYTHONPATH": root + os.pathsep + os.environ.get("PYTHONPATH", "")}
    try:
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                              env=env, cwd=root)
    except subprocess.TimeoutExpired:
        return None, "timed out"
    return done.returncode, done.stdout + done.stderr


@pytest.mark.parametrize("reader", ["read_uff_info", "read_uff_nodes", "read_uff_time_records", "read_tdms_records"])
@pytest.mark.parametrize("device", ["/dev/zero", "fifo"])
def test_the_apis_measured_file_readers_refuse_a_device_or_pipe_at_once(tmp_path, reader, device):
    """On main ``rdm.read_uff_info('/dev/zero')`` (and the UFF node and time-record readers) read
    for ever, and ``read_tdms_records`` of a named pipe no program writes to waited for ever; the
    command line refuses these (``read_measured``), the API now does too, with the CLI's words. A
    FIFO is read as the command line reads it (files27p): one that nothing writes to is refused
    after the wait for a writer (``io.limits.PIPE_WAIT_S``, shortened here)."""
    import os

    path = device
    if device == "fifo":
        path = str(tmp_path / ("record.tdms" if "tdms" in reader else "record.uff"))
        os.mkfifo(path)
    code = (f"import rotordyn_modal as rdm\nimport rotordyn_modal.io.limits as limits\nlimits.PIPE_WAIT_S = 0.2\n"
            f"try:\n    rdm.{reader}({path!r})\nexcept rdm.InputError as e:\n    print('REFUSED', e)\n")
    status, output = _python(code)
    if device == "fifo":
        assert status == 0 and output.startswith(f"REFUSED {path}: a pipe nothing writes to: no byte of the "), output
        return
    assert status == 0 and output.startswith(f"REFUSED {path}: expected a "), output
    assert "not a pipe or device" in output


def test_an_empty_tdms_file_says_it_has_no_group(tmp_path):
    """On main: "several groups: give group= one of none" for a file of no group at all."""
    import rotordyn_modal as rdm

    path = tmp_path / "empty.tdms"
    path.write_bytes(b"")
    with pytest.raises(rdm.InputError) as refused:
        rdm.read_tdms_records(path)
    assert "no group of channels in the file" in str(refused.value) and "several" not in str(refused.value)


def _frf_csv_and_uff(tmp_path):
    """A measured FRF of the gear machine written by ``frf --out`` as CSV and as UFF."""
    model = str(_EXAMPLES / "gear_machine.toml")
    for ending in ("csv", "uff"):
        assert main(["frf", model, "--freqs", "1:50:20", "--sensor", "acc-top-z", "--excitation", "hammer-z",
                     "--out", str(tmp_path / f"m.{ending}"), "--quiet"]) == 0
    return model


@pytest.mark.parametrize("name", ["frf.csv", "frf.txt"])
def test_a_universal_file_with_a_table_ending_is_read_as_the_universal_file_it_is(tmp_path, name):
    """On main: "found -1" (a Universal File read as CSV). A UFF export saved as .csv or .txt is
    recognised by its content (its first lines: ``-1`` and a dataset number) and gives the FRFs
    of the same file named .uff."""
    model = rdm.load_model(_frf_csv_and_uff(tmp_path))
    (tmp_path / name).write_bytes((tmp_path / "m.uff").read_bytes())
    renamed, = rdm.read_measured(tmp_path / name, model)
    original, = rdm.read_measured(tmp_path / "m.uff", model)
    assert np.array_equal(renamed.frequencies_hz, original.frequencies_hz) and np.array_equal(renamed.H, original.H)


@pytest.mark.parametrize("source, name, words", [
    ("tdms", "rec.csv", "a TDMS file (it begins with 'TDSm')"),      # a TDMS recording given as FRFs
    ("tdms", "rec.uff", "a TDMS file (it begins with 'TDSm')"),
], ids=["tdms-as-csv", "tdms-as-uff"])
def test_a_measured_file_of_another_format_with_the_wrong_ending_is_named_as_what_it_is(
        tmp_path, capsys, source, name, words):
    """On main: "found -1" (a Universal File read as CSV), "cannot read as CSV (Error tokenizing data.
    C error: ...)" and "no dataset 58/58b (FRF) in the file; datasets found: none" (TDMS): the format
    the file is in was never said."""
    model = _frf_csv_and_uff(tmp_path)
    capsys.readouterr()
    data = (_EXAMPLES.parent / "tests" / "data" / "tdms" / "good_tdms_2.tdms").read_bytes() if source == "tdms" \
        else (tmp_path / source).read_bytes()
    (tmp_path / name).write_bytes(data)
    code = main(["frf", model, "--freqs", "1:50:20", "--sensor", "acc-top-z", "--excitation", "hammer-z",
                 "--measured", str(tmp_path / name)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and name in err[0] and words in err[0], err


def test_the_apis_writers_refuse_an_empty_name_and_a_missing_mapping_in_their_words(tmp_path):
    """On main ``rdm.save_model(model, '')`` said "cannot write : it is a folder" (``Path('')`` is the
    current folder) and ``rdm.write_uff58(results, path, None)`` failed with AttributeError
    "'NoneType' object has no attribute 'oblique'"; nothing is written either way."""
    import rotordyn_modal as rdm

    model = rdm.load_model(_EXAMPLES / "gear_machine.toml")
    for write in (lambda: rdm.save_model(model, ""), lambda: rdm.write_measured_csv([], "")):
        with pytest.raises(rdm.InputError, match="an empty file name"):
            write()
    result = rdm.frf(model, 0.0, np.linspace(1.0, 50.0, 5))
    out = tmp_path / "f.uff"
    with pytest.raises(rdm.InputError, match="mapping = None: expected a ChannelMap"):
        rdm.write_uff58([result], out, None)
    assert not out.exists()
