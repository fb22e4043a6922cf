"""Command line: frf, unbalance, fit (exit codes, CSV columns, refusals), as a new user tries them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.cli import main
from rotordyn_modal.io.measured import default_mapping
from rotordyn_modal.io.uff import write_uff58

EXAMPLE = str(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml")


def test_frf_csv_matches_the_api(tmp_path):
    out = tmp_path / "frf.csv"
    code = main(["frf", EXAMPLE, "--speed", "-3000", "--freqs", "1:40:40", "--input", "hammer-z",
                 "--output", "acc-top-z,acc-side-y", "--quantity", "mobility", "--out", str(out), "--quiet"])
    assert code == 0
    table = pd.read_csv(out)
    assert list(table.columns)[:7] == ["frequency_hz", "output", "input", "real", "imag", "magnitude", "phase_deg"]
    H = rdm.frf(rdm.load_model(EXAMPLE), rdm.rpm(-3000), np.linspace(1, 40, 40), "hammer-z", None, "mobility").H
    got = table[table.output == "acc-side-y"]
    np.testing.assert_allclose(got.real + 1j * got.imag, H[1, 0], rtol=1e-9)


def test_frf_forces_and_plot(tmp_path):
    out, plot = tmp_path / "f.csv", tmp_path / "f.png"
    assert main(["frf", EXAMPLE, "--freqs", "0:40:5", "--forces", "suspensions", "--out", str(out),
                 "--plot", str(plot), "--quiet"]) == 0
    assert plot.stat().st_size > 0
    assert "mount-FL:Fz" in set(pd.read_csv(out).output)


def _measured(tmp_path, quantity="receptance"):
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, rdm.rpm(3000), np.linspace(2, 40, 120), quantity=quantity)
    path = tmp_path / "measured.uff"
    write_uff58([FRFResult(**{**res.__dict__, "coherence": np.full(res.H.shape, 0.99)})], path,
                default_mapping(model))
    return path


def test_frf_over_measured(tmp_path):
    meas = _measured(tmp_path)
    assert main(["frf", EXAMPLE, "--speed", "3000", "--freqs", "2:40:200", "--measured", str(meas),
                 "--plot", str(tmp_path / "o.png"), "--quiet"]) == 0


@pytest.mark.parametrize("extra,message", [
    (["--speed", "1000"], "no data at 1000 rpm; the file has 3000 rpm"),
    (["--speed", "3000", "--quantity", "accelerance"], "the file holds receptance"),
])
def test_frf_measured_mismatch_exit_2(tmp_path, capsys, extra, message):
    meas = _measured(tmp_path)
    code = main(["frf", EXAMPLE, "--freqs", "2:40:20", "--measured", str(meas), "--quiet", *extra])
    assert code == 2
    assert message in capsys.readouterr().err


def test_frf_broken_measured_file_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.uff"
    bad.write_text("    -1\n    58\nnot a dataset\n")
    assert main(["frf", EXAMPLE, "--freqs", "2:40:20", "--measured", str(bad), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "bad.uff" in err and "Traceback" not in err


@pytest.mark.parametrize("args,message", [
    (["--freqs", "1:2"], "--freqs '1:2': expected START:STOP:N"),
    (["--freqs", "1:40:5", "--output", "nope"], "unknown sensor 'nope'"),
])
def test_frf_bad_options_exit_2(capsys, args, message):
    assert main(["frf", EXAMPLE, *args, "--quiet"]) == 2
    assert message in capsys.readouterr().err


def test_unbalance_csv(tmp_path):
    out = tmp_path / "u.csv"
    assert main(["unbalance", EXAMPLE, "--speeds", "0:6000:61", "--output", "acc-top-z", "--out", str(out),
                 "--plot", str(tmp_path / "u.png"), "--operating-speed", "3000", "--quiet"]) == 0
    table = pd.read_csv(out)
    assert list(table.columns)[:6] == ["speed_rpm", "output", "source", "frequency_hz", "amplitude", "phase_deg"]
    fan = table[(table.output == "acc-top-z") & (table.source == "fan")]
    # the CSV holds 10 significant digits
    np.testing.assert_allclose(fan.frequency_hz, 0.4 * np.linspace(0, 6000, 61) / 60, rtol=1e-9)


FANS = str(Path(__file__).resolve().parent.parent / "examples" / "fan_on_bearings.toml")
_COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def _unbalance_table(tmp_path, model, *options):
    out = tmp_path / "u.csv"
    assert main(["unbalance", model, "--speeds", "0:6000:7", "--out", str(out), "--quiet", *options]) == 0
    return pd.read_csv(out)


def test_unbalance_named_output_gives_that_output_only(tmp_path):
    table = _unbalance_table(tmp_path, EXAMPLE, "--output", "acc-top-z")
    assert set(table.output) == {"acc-top-z"}


def test_unbalance_without_output_gives_every_sensor_and_no_force(tmp_path):
    sensors = {s.name for s in rdm.load_model(EXAMPLE).sensors}
    assert set(_unbalance_table(tmp_path, EXAMPLE).output) == sensors


@pytest.mark.parametrize("model,forces,items", [
    (EXAMPLE, "suspensions", ["mount-FL", "mount-FR", "mount-RL", "mount-RR"]),
    (EXAMPLE, "bearings", ["motor", "fan"]),            # no [[bearings]]: the rigidly attached rotors
    (EXAMPLE, "rotors", ["motor", "fan"]),
    (FANS, "bearings", ["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"]),
    (FANS, "all", ["mount-FL", "mount-FR", "mount-RL", "mount-RR", "motor-DE", "motor-NDE", "fan-DE",
                   "fan-NDE", "motor", "fan"]),
])
def test_unbalance_forces_are_added_on_request(tmp_path, model, forces, items):
    sensor = rdm.load_model(model).sensors[0].name
    table = _unbalance_table(tmp_path, model, "--output", sensor, "--forces", forces)
    expected = [sensor] + [f"{item}:{c}" for item in items for c in _COMPONENTS]
    assert list(dict.fromkeys(table.output)) == expected


def test_unbalance_rotor_force_is_the_sum_of_its_bearings(tmp_path):
    """A rotor on bearings passes to the stator what its bearings carry: the forces (not the
    moments, which depend on the point) of 'rotors' equal the sum over its [[bearings]]."""
    table = _unbalance_table(tmp_path, FANS, "--output", "acc-fan-z", "--forces", "all")
    value = table.amplitude * np.exp(1j * np.radians(table.phase_deg))
    for rotor in ("motor", "fan"):
        for c in ("Fx", "Fy", "Fz"):
            total = value[table.output == f"{rotor}:{c}"].to_numpy()
            parts = sum(value[table.output == f"{rotor}-{end}:{c}"].to_numpy() for end in ("DE", "NDE"))
            np.testing.assert_allclose(parts, total, rtol=0, atol=1e-8 * np.abs(total).max())


def test_fit_writes_the_model_and_never_over_the_input(tmp_path, capsys):
    true = rdm.load_model(EXAMPLE)
    start = true.scaled({"suspensions.mount-FL.stiffness": 1.5})
    start_path = tmp_path / "start.toml"
    rdm.save_model(start, start_path)
    meas = _measured(tmp_path)
    out = tmp_path / "fitted.toml"
    assert main(["fit", str(start_path), "--measured", str(meas), "--params", "suspensions.mount-FL.stiffness",
                 "--out", str(out), "--plot", str(tmp_path / "fit.png")]) == 0
    assert (tmp_path / "fit.png").stat().st_size > 0
    fitted = rdm.load_model(out)
    np.testing.assert_allclose(fitted.get("suspensions.mount-FL.stiffness"),
                               true.get("suspensions.mount-FL.stiffness"), rtol=1e-6)
    assert "std_relative" in capsys.readouterr().out
    before = start_path.read_text()
    assert main(["fit", str(start_path), "--measured", str(meas), "--params", "gain", "--out", str(start_path),
                 "--quiet"]) == 2
    assert start_path.read_text() == before
    assert "refusing to write over the input file" in capsys.readouterr().err


def test_fit_that_cannot_converge_says_why(tmp_path, capsys):
    data = rdm.load_model(EXAMPLE).to_dict()
    data["suspensions"].append({"name": "feeler", "position": [0.0, 0.0, 0.0], "stiffness": [1e-6] * 3})
    start = tmp_path / "start.toml"
    rdm.save_model(rdm.Model.from_dict(data), start)
    out = tmp_path / "fitted.toml"
    code = main(["fit", str(start), "--measured", str(_measured(tmp_path)), "--params",
                 "suspensions.feeler.stiffness", "--out", str(out), "--quiet", "--starts", "1"])
    assert code == 1
    assert "not converged: the measured FRFs do not determine the parameters" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("args,message", [
    (["--params", "suspensions.nope.stiffness"], "nope"),
    (["--params", "gain", "--freq-band", "40:2"], "--freq-band 40:2: expected LO:HI"),
    (["--params", "gain", "--bound-factor", "0.5"], "--bound-factor 0.5: expected a number > 1"),
])
def test_fit_bad_options_exit_2(tmp_path, capsys, args, message):
    code = main(["fit", EXAMPLE, "--measured", str(_measured(tmp_path)), "--out", str(tmp_path / "f.toml"),
                 "--quiet", *args])
    assert code == 2
    assert message in capsys.readouterr().err


def test_frf_measured_missing_channel_exit_2(tmp_path, capsys):
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, 0.0, np.linspace(2, 40, 50), outputs=["acc-top-z"])
    path = tmp_path / "one.uff"
    write_uff58([res], path, default_mapping(model))
    code = main(["frf", EXAMPLE, "--freqs", "2:40:20", "--measured", str(path), "--sensor", "acc-side-y",
                 "--quiet"])
    assert code == 2
    assert "no channel acc-side-y (--sensor) in the file at this speed; it has acc-top-z" in capsys.readouterr().err


def test_frf_out_uff_reads_back(tmp_path):
    out = tmp_path / "model.uff"
    assert main(["frf", EXAMPLE, "--speed", "1500", "--freqs", "1:40:30", "--quantity", "accelerance",
                 "--out", str(out), "--quiet"]) == 0
    back, = rdm.read_measured(out, rdm.load_model(EXAMPLE))
    H = rdm.frf(rdm.load_model(EXAMPLE), rdm.rpm(1500), np.linspace(1, 40, 30), quantity="accelerance").H
    np.testing.assert_allclose(back.H, H, rtol=1e-10)
    assert back.speed == pytest.approx(rdm.rpm(1500))


def test_fit_band_without_measured_lines_names_the_file_and_its_lines(tmp_path, capsys):
    meas = _measured(tmp_path)
    out = tmp_path / "fitted.toml"
    code = main(["fit", str(EXAMPLE), "--measured", str(meas), "--params", "suspensions.mount-FL.stiffness",
                 "--freq-band", "5000:6000", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists() and err.count("\n") == 0
    assert f"{meas}: --freq-band 5000:6000" in err
    assert "measured frequency lines" in err and " Hz)" in err


def test_unbalance_orbits_written_and_drawn_as_the_python_result_gives_them(tmp_path, capsys):
    """--orbits writes every probe pair's orbit (the table of ``result.orbits()``, 10 digits),
    --orbit-plot draws them, and the largest orbit of each pair and source is reported; a
    model whose outputs hold no probe pair is refused."""
    orbits, figure = tmp_path / "o.csv", tmp_path / "o.png"
    argv = ["unbalance", FANS, "--speeds", "0:6000:13", "--output", "probe-DE-x,probe-DE-y",
            "--out", str(tmp_path / "u.csv"), "--orbits", str(orbits), "--orbit-plot", str(figure)]
    assert main(argv) == 0
    captured = capsys.readouterr()
    err, printed = captured.err, captured.out + captured.err
    model = rdm.load_model(FANS)
    expected = rdm.unbalance_response(model, rdm.rpm(np.linspace(0, 6000, 13)),
                                      outputs=["probe-DE-x", "probe-DE-y"]).orbits()
    table = pd.read_csv(orbits)
    assert list(table.columns) == list(expected.columns) and len(table) == len(expected)
    for column in ("speed_rpm", "frequency_hz", "major", "minor", "precession_ratio"):
        np.testing.assert_allclose(table[column], expected[column], rtol=1e-9, atol=1e-300)
    assert table.pair.tolist() == expected.pair.tolist() and table.precession.tolist() == expected.precession.tolist()
    assert figure.read_bytes()[:4] == b"\x89PNG"
    assert "largest orbit of each probe pair (major, minor: semi-axes, 0-peak):" in err
    largest = expected.loc[expected.groupby(["pair", "source"])["major"].idxmax()]
    for major in largest.major:
        assert f"{major:.6g}" in printed
    assert main(["unbalance", FANS, "--speeds", "0:6000:13", "--output", "acc-fan-z",
                 "--orbits", str(tmp_path / "none.csv"), "--quiet"]) == 2
    assert "--orbits/--plot-orbits need a probe pair among the outputs" in capsys.readouterr().err
    assert not (tmp_path / "none.csv").exists()


@pytest.mark.parametrize("options, message", [
    (["--orbit-plot", "{tmp}/o.txt"], "--orbit-plot {tmp}/o.txt: expected a file ending in .png, .svg or .pdf"),
    (["--plot", "{tmp}/u.png", "--orbit-plot", "{tmp}/u.png"],
     "--orbit-plot and --plot name the same file {tmp}/u.png: give two different files"),
    (["--out", "{tmp}/u.csv", "--orbits", "{tmp}/./u.csv"],
     "--orbits and --out name the same file {tmp}/./u.csv: give two different files"),
    (["--orbits", "{tmp}/no-folder/o.csv"], "--orbits {tmp}/no-folder/o.csv: the folder {tmp}/no-folder does not exist"),
    (["--orbits", FANS], "refusing to write over the input file"),
])
def test_unbalance_extra_outputs_are_refused_before_any_work(tmp_path, capsys, options, message):
    before = sorted(tmp_path.iterdir())
    argv = ["unbalance", FANS, "--speeds", "0:6000:13", "--output", "probe-DE-x,probe-DE-y", "--quiet",
            *[o.format(tmp=tmp_path) for o in options]]
    assert main(argv) == 2
    assert message.format(tmp=tmp_path) in capsys.readouterr().err
    assert sorted(tmp_path.iterdir()) == before
