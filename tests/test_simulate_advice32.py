"""A sudden load's run refused for its length names the mode that sets it and the option that
leaves that mode out (issue 27: one clear line that says what to change)."""

from pathlib import Path

from rotordyn_modal.cli import main

ROOT = Path(__file__).resolve().parents[1]


def test_a_long_tap_names_the_mode_it_reaches_and_the_option(tmp_path, capsys):
    """flexible_pump_on_mounts tapped at the pump hub for 200 s at rest: the tap reaches a shaft
    mode near 5 kHz, 1e6 periods of it are past the count limit; the run is refused before any work
    and the line says which mode and that --max-frequency leaves it out of the basis."""
    out = tmp_path / "o.csv"
    code = main(["simulate", str(ROOT / "examples" / "flexible_pump_on_mounts.toml"), "--duration", "200",
                 "--excitation", "hub-tap-y", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert not out.exists()
    assert "--max-frequency HZ" in err and "undamped mode" in err and "hub-tap-y" in err
    assert len(err.strip().splitlines()) == 1
