"""A rotor that does not turn (speed ratio 0, no transmission): its unbalance gives no force and
no response at any speed (red team 12). The unbalance figure draws no curve of it (and no
meaningless flat phase line), names it in the legend, and leaks no numpy warning ("All-NaN slice
encountered" on stderr, from the magnitude axis' range)."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "motor_pump_on_mounts.toml"


def _still_pump() -> dict:
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data.pop("transmissions")
    next(r for r in data["rotors"] if r["name"] == "pump")["speed_ratio"] = 0.0
    return data


def test_a_still_rotors_unbalance_draws_no_curve_and_no_numpy_warning():
    import matplotlib.pyplot as plt

    model = rdm.Model.from_dict(_still_pump(), source=str(EXAMPLE))
    result = rdm.unbalance_response(model, np.linspace(rdm.rpm(100.0), rdm.rpm(3000.0), 30))
    pump = result.sources.index("pump")
    assert not np.any(result.amplitude[:, pump] > 0)          # the physics: no force, no response
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fig = result.plot(peaks=result.peaks())
    fig.canvas.draw()
    labels = [line.get_label() for ax in fig.axes for line in ax.get_lines()]
    assert not any(label.endswith("1X pump") for label in labels)
    assert any(label.endswith("1X motor") for label in labels)
    flat = [line for ax in fig.axes for line in ax.get_lines() if len(line.get_ydata()) > 1
            and np.nanmin(line.get_ydata()) == np.nanmax(line.get_ydata()) == 0.0]
    assert not flat                                             # no phase line at 0 deg of no response
    legends = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert any("1X pump: zero at every speed (pump does not turn)" in t for t in legends)
    plt.close(fig)


def test_the_command_line_prints_no_raw_numpy_warning(tmp_path, capsys):
    import tomli_w

    model = tmp_path / "mp.toml"
    model.write_bytes(tomli_w.dumps(_still_pump()).encode())
    assert main(["unbalance", str(model), "--speeds", "100:3000:30", "--plot", str(tmp_path / "u.png")]) == 0
    err = capsys.readouterr().err
    assert not [line for line in err.splitlines() if "warning" in line.lower()], err
    assert (tmp_path / "u.png").stat().st_size > 0
