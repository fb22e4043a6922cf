"""An eighth round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families7.py``): lists with an empty item (``--orders 1,,2``), numbers written with
Python's digit separators (``5_0``, which ``int`` and ``float`` read as 50), the maximum
continuous speed that ``level1`` and ``report`` check the same way, and the implausible-value
warnings (their hint, and what a study says of them). Each case through the command line in
this process; every refusal comes before the work, so the file costs seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotordyn_modal.cli import main
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
FAN = str(ROOT / "examples" / "fan_on_bearings.toml")
MINIMAL = str(ROOT / "examples" / "motor_fan_minimal.toml")
_STAGE = ["--rated-power", "5e5", "--impeller-diameter", "0.3", "--restriction-height", "0.02"]


# ----------------------------------------------------------------------- empty list items
@pytest.mark.parametrize("argv, option, value", [
    (["campbell", MINIMAL, "--speeds", "0:100:2", "--orders", "1,,2"], "--orders", "1,,2"),
    (["critical-speeds", MINIMAL, "--speeds", "0:100:2", "--orders", "1,2,"], "--orders", "1,2,"),
    (["frf", FAN, "--speed", "1000", "--freqs", "1:2:2", "--sensor", "probe-DE-x,,acc-fan-z"],
     "--sensor", "probe-DE-x,,acc-fan-z"),
    (["level1", FAN, "--mcs", "3000", "--station", "fan", "--rated-power", "5e5,,5e5", "--impeller-diameter",
      "0.3", "--restriction-height", "0.02", "--quiet"], "--rated-power", "5e5,,5e5"),
], ids=["orders", "orders-trailing", "sensor", "rated-power"])
def test_an_empty_list_item_is_refused_not_dropped(capsys, argv, option, value):
    """``--orders 1,,2`` ran orders 1 and 2 and ``--sensor a,,b`` sensors a and b: an item left
    out by mistake (a number or a name deleted) went unsaid."""
    assert main(argv) == 2
    _one_line_error(capsys, option, value, "an empty item between commas")


# ----------------------------------------------------------------------- digit separators
@pytest.mark.parametrize("argv, option, value", [
    (["campbell", MINIMAL, "--speeds", "0:100:5_0"], "--speeds", "5_0"),
    (["campbell", MINIMAL, "--speeds", "0:100:2", "--lowest", "1_0"], "--lowest", "1_0"),
    (["stability", MINIMAL, "--speeds", "0:100:2", "--lowest", "0_1"], "--lowest", "0_1"),
    (["modes", MINIMAL, "--speed", "1_000"], "--speed", "1_000"),
    (["campbell", MINIMAL, "--speeds", "0:1_00:2"], "--speeds", "1_00"),
    (["campbell", MINIMAL, "--speeds", "0:100:2", "--orders", "1,1_0"], "--orders", "1_0"),
    (["campbell", MINIMAL, "--speeds", "0:100:2", "--freq-range", "0:1_0"], "--freq-range", "1_0"),
    (["ucs-map", FAN, "--stiffness", "1e6:1e8:3", "--lowest", "2_0"], "--lowest", "2_0"),
    (["report", FAN, "--standard", "iso", "--mcs", "3000", "--iso-group", "2", "--iso-support", "rigid",
      "--points", "1_51", "--out", "r.html"], "--points", "1_51"),
], ids=["range-count", "lowest", "lowest-stability", "speed", "range-end", "list", "band", "ucs-lowest",
        "points"])
def test_a_number_with_digit_separators_is_refused(tmp_path, monkeypatch, capsys, argv, option, value):
    """Python's ``int('5_0')`` is 50 and ``float('1_0')`` 10.0: ``--speeds 0:3000:5_0`` ran 50
    speeds, a typo (a shifted key) read as a number nobody typed."""
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    _one_line_error(capsys, option, value)
    assert not (tmp_path / "r.html").exists()


def test_a_range_count_with_digit_separators_says_what_a_count_is(capsys):
    assert main(["campbell", MINIMAL, "--speeds", "0:3000:5_0"]) == 2
    _one_line_error(capsys, "--speeds '0:3000:5_0'", "whole number", "like 50")


@pytest.mark.parametrize("option", ["--workers", "--chunk-size"])
def test_a_study_count_with_digit_separators_is_refused(tmp_path, capsys, option):
    study = str(ROOT / "examples" / "mount_tolerance.study.toml")
    with pytest.raises(SystemExit) as exit_:
        main(["study", study, "--out", str(tmp_path / "r.nc"), option, "2_0"])
    assert exit_.value.code == 2
    _one_line_error(capsys, option, "2_0")
    assert not (tmp_path / "r.nc").exists()


@pytest.mark.parametrize("argv, option, value", [
    (["modes", MINIMAL, "--speed", "0", "--shape", "1_0", "--plot", "x.png"], "--shape", "1_0"),
    (["modes", MINIMAL, "--speed", "0", "--animate", "1", "--frames", "3_6", "--plot", "x.gif"], "--frames", "3_6"),
    (["unbalance", MINIMAL, "--speeds", "0:100:2", "--iso-group", "0_1"], "--iso-group", "0_1"),
    (["simulate", MINIMAL, "--speed", "100", "--duration", "0.1", "--samples", "1_0", "--out", "x.csv"],
     "--samples", "1_0"),
], ids=["shape", "frames", "iso-group", "samples"])
def test_a_counted_option_with_digit_separators_is_refused(tmp_path, monkeypatch, capsys, argv, option, value):
    """The options argparse read with ``int`` (``--shape 1_0`` drew mode 10, ``--iso-group 0_1``
    was group 1) read whole numbers as typed."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    _one_line_error(capsys, option, value, "whole number")
    assert not list(tmp_path.iterdir())


# ----------------------------------------------------------------------- --mcs of level1 and report
@pytest.mark.parametrize("command", ["level1", "report"])
@pytest.mark.parametrize("mcs", ["1e-300", "0"])
def test_level1_and_report_refuse_a_vanishing_mcs_alike(tmp_path, monkeypatch, capsys, command, mcs):
    """``level1 --mcs 1e-300`` ran (Qa from the API's power / speed, every speed of the sweep 0 to
    round-off) where ``report`` refused it: the two now share one check and one message."""
    monkeypatch.chdir(tmp_path)
    extra = ["--standard", "api617", "--out", "r.html"] if command == "report" else ["--quiet"]
    argv = [command, FAN, "--mcs", mcs, "--station", "fan", "--qa", "2e5", *extra]
    assert main(argv) == 2
    _one_line_error(capsys, f"--mcs {mcs}", "expected a maximum continuous speed", "1e-30 rad/s")


# ----------------------------------------------------------------------- the hint of a sag or a low mount mode
def _in_grams(gravity: bool) -> str:
    """``motor_fan_minimal.toml`` with every mass typed in g where kg is meant (1000 times too
    heavy), under gravity or not."""
    text = Path(MINIMAL).read_text()
    for old, new in (("mass = 120.0", "mass = 120000.0"), ("mass = 18.0", "mass = 18000.0"),
                     ("mass = 6.0", "mass = 6000.0")):
        assert old in text
        text = text.replace(old, new, 1)
    if gravity:
        text = text.replace('reference_rotor = "motor"', 'reference_rotor = "motor"\ngravity = [0.0, 0.0, -9.81]', 1)
    return text


@pytest.mark.parametrize("gravity, words", [
    (True, ["would sag"]),          # 144 t on 4 x 3e5 N/m: m g / k = 1.18 m
    (False, ["lowest mode on its suspensions"]),
], ids=["sag", "low-mode"])
def test_a_mass_in_grams_is_named_beside_a_stiffness_in_n_per_mm(tmp_path, capsys, gravity, words):
    """Masses 1000 times too large sag the machine 1000 times too far and lower its mount modes
    sqrt(1000) times, as stiffnesses 1000 times too small do: the hint named the stiffness only
    (a 5000 "kg" disk meant in g was told to look at its mounts)."""
    assert 144000 * 9.81 / (4 * 3.0e5) > 1.0
    path = tmp_path / "grams.toml"
    path.write_text(_in_grams(gravity))
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    [line] = [line for line in err.splitlines() if words[0] in line]
    assert "a stiffness in N/mm given as N/m" in line and "a mass in g given as kg" in line, line


# ----------------------------------------------------------------------- a study's implausible variants
_SKID_MASSES = [120.0, 120000.0, 150.0, 60000.0, 100.0]     # kg; 120000 and 60000: g typed as kg


def _mass_study(tmp_path) -> Path:
    spec = tmp_path / "skid.study.toml"
    spec.write_text('[[parameters]]\nname = "skid mass"\nkeys = ["stator.mass"]\n'
                    f"values = {_SKID_MASSES}\n\n[analyses.modes]\nspeed_rpm = 0.0\n")
    return spec


def _check_warns(tmp_path, capsys, mass: float) -> bool:
    """Whether ``check`` warns of the model with the skid's mass ``mass``: the oracle the study's
    count must agree with, variant by variant."""
    path = tmp_path / f"skid-{mass:g}.toml"
    path.write_text(Path(MINIMAL).read_text().replace("mass = 120.0", f"mass = {mass!r}", 1))
    capsys.readouterr()
    assert main(["check", str(path)]) == 0
    return "warning:" in capsys.readouterr().err


def test_a_study_says_how_many_variants_are_implausible(tmp_path, capsys):
    """A study ran every variant without the warnings ``check`` gives of its model (a 35 µm pump
    shaft ran with '0 failed'): now one line at the end counts them and quotes the first."""
    warned = [i for i, mass in enumerate(_SKID_MASSES) if _check_warns(tmp_path, capsys, mass)]
    assert warned == [1, 3]          # the two skids of 60 t and 120 t only
    out = tmp_path / "skid.nc"
    assert main(["study", MINIMAL, "--spec", str(_mass_study(tmp_path)), "--out", str(out)]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "variants" in line and "warning" in line]
    assert len(lines) == 1, lines
    assert f"{len(warned)} of {len(_SKID_MASSES)} variants" in lines[0] and f"variant {warned[0]}:" in lines[0]
    assert "lowest mode on its suspensions" in lines[0], lines[0]


def test_a_study_without_implausible_variants_says_nothing_of_them(tmp_path):
    import warnings

    import rotordyn_modal as rdm
    from rotordyn_modal.study import ImplausibleVariants, parse_study

    model = rdm.load_model(MINIMAL)
    spec = parse_study({"parameters": [{"name": "m", "keys": ["stator.mass"], "values": [100.0, 150.0]}],
                        "analyses": {"modes": {"speed_rpm": 0.0}}}, model=model)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleVariants)
        result = rdm.study(model, spec)
    assert result.n_variants == 2 and not int(result.failed.sum())


@pytest.mark.parametrize("where, grid", [("campbell", "0:3000:5_0"), ("campbell", "0:3_000:50"), ("values", "1:2:1_0")])
def test_a_study_files_range_with_digit_separators_is_refused(where, grid):
    """``speeds_rpm = "0:3000:5_0"`` in a study file ran 50 speeds, as ``--speeds`` did."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import StudyError, parse_study

    model = rdm.load_model(MINIMAL)
    spec = {"parameters": [{"name": "m", "keys": ["stator.mass"], "values": [100.0, 150.0]}],
            "analyses": {"campbell": {"speeds_rpm": "0:100:3"}}}
    if where == "campbell":
        spec["analyses"]["campbell"]["speeds_rpm"] = grid
    else:
        spec["parameters"][0]["scale"] = grid
        del spec["parameters"][0]["values"]
    with pytest.raises(StudyError, match="START:STOP:N") as error:
        parse_study(spec, model=model)
    assert grid in str(error.value) and len(str(error.value).splitlines()) == 1


@pytest.mark.parametrize("argv, option, value", [
    (["modes", MINIMAL, "--speed", "\uff15\uff10\uff10"], "--speed", "\uff15\uff10\uff10"),           # full-width 500
    (["campbell", MINIMAL, "--speeds", "0:\u0661\u0660\u0660:2"], "--speeds", "\u0661\u0660\u0660"),  # Arabic-Indic 100
    (["campbell", MINIMAL, "--speeds", "0:100:2", "--freq-range", "0:\uff11\uff10"], "--freq-range", "\uff11\uff10"),
], ids=["speed-fullwidth", "range-arabic-indic", "band-fullwidth"])
def test_a_number_in_another_scripts_digits_is_refused(tmp_path, monkeypatch, capsys, argv, option, value):
    """Python's ``float('５００')`` is 500.0: a number pasted from a document set in another script
    was read as digits nobody typed on the command line; refused as no number, like ``1_0``."""
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    _one_line_error(capsys, option)
