"""A machine that turns slowly: the figures give its speeds to three significant digits, as the
report's sentences do (``report.collect._rpm``). Dimensional analysis: the compressor rotor with
every stiffness divided by 10^6 and every damping by 10^3 is the same machine on a time scale
1000 times longer (as tests/test_slow_machine_report12.py builds it), so its unbalance peak lies
at exactly 1/1000 of the original's speed: 5,726 rpm becomes 5.73 rpm, not "6 rpm"."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.units import rpm_text

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "compressor_rotor.toml"
SLOWER = 1000.0


def _model(slower=1.0) -> rdm.Model:
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    for material in data["materials"]:
        material["young_modulus"] /= slower ** 2
    for bearing in data["bearings"]:
        for key in ("stiffness", "axial_stiffness"):
            if key in bearing:
                bearing[key] /= slower ** 2
        bearing["damping"] /= slower
    return rdm.Model.from_dict(data, source=str(EXAMPLE))


def _peak_marks(slower):
    """The speeds [rpm] written in the unbalance figure's peak marks ("AF 15.4 at 5.73 rpm")."""
    import matplotlib.pyplot as plt

    model = _model(slower)
    result = rdm.unbalance_response(model, np.linspace(rdm.rpm(1000.0), rdm.rpm(9000.0), 81) / slower)
    fig = result.plot(peaks=result.peaks(operating_speed=rdm.rpm(9000.0) / slower))
    fig.canvas.draw()
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    plt.close(fig)
    return [m.group(1) for t in texts for m in [re.search(r"AF [\d.]+ at (\S+) rpm", t)] if m]


def test_a_slow_machines_peak_marks_keep_their_digits():
    fast, slow = _peak_marks(1.0), _peak_marks(SLOWER)
    assert fast and len(slow) == len(fast)
    for original, shown in zip(fast, slow):
        assert float(original) >= 1000 and "." not in original            # whole rpm, as always
        assert float(shown) == pytest.approx(float(original) / SLOWER, abs=0.6e-2)
        assert len(shown.replace(".", "").lstrip("0")) == 3                # 5.73: three digits, not "6"


@pytest.mark.parametrize("speed, text", [(5726.0, "5726"), (99.5, "100"), (99.4, "99.4"), (5.726, "5.73"),
                                         (5.75, "5.75"), (0.05726, "0.0573"), (0.0, "0"), (-5.726, "-5.73"),
                                         (150.4, "150")])
def test_rpm_text_keeps_three_digits_below_100_rpm(speed, text):
    assert rpm_text(speed) == text


def test_rpm_text_is_the_reports_rule():
    """The report's sentences and the figures write speeds by one function."""
    import importlib

    assert importlib.import_module("rotordyn_modal.report.collect").rpm_text is rpm_text
