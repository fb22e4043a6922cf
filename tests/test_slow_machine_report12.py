"""A machine that turns slowly: the report's sentences give its speeds to three significant
digits. Dimensional analysis: the compressor rotor with every stiffness divided by 10^6 and
every damping by 10^3 is the same machine on a time scale 1000 times longer, so its peaks and
critical speeds lie at exactly 1/1000 of the original's (5,726 rpm becomes 5.726 rpm, not "6 rpm")."""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.report import collect
from rotordyn_modal.report.collect import ReportInputs

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "compressor_rotor.toml"
SLOWER = 1000.0


def _slow(tmp_path) -> rdm.Model:
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    for material in data["materials"]:
        material["young_modulus"] /= SLOWER ** 2
    for bearing in data["bearings"]:
        for key in ("stiffness", "axial_stiffness"):
            if key in bearing:
                bearing[key] /= SLOWER ** 2
        bearing["damping"] /= SLOWER
    return rdm.Model.from_dict(data, source=str(tmp_path / "slow.toml"))


def _peak_speed(data) -> str:
    criterion = next(c for c in data.criteria if c.name.startswith("API 684 separation margin"))
    return re.search(r"governing peak: \S+ at (\S+) rpm", criterion.why).group(1)


def test_a_slow_machines_governing_peak_keeps_its_digits(tmp_path):
    fast = collect(rdm.load_model(EXAMPLE), ReportInputs("api684", rdm.rpm(9000.0), points=21))
    slow = collect(_slow(tmp_path), ReportInputs("api684", rdm.rpm(9000.0 / SLOWER), points=21))
    original = float(_peak_speed(fast))                      # whole rpm, as always: 5726
    assert original == pytest.approx(5726, abs=1)
    shown = _peak_speed(slow)
    assert float(shown) == pytest.approx(original / SLOWER, abs=0.6e-2)     # 5.73, three digits
    assert len(shown.replace(".", "").lstrip("0")) == 3
    assert math.isclose(float(shown), round(original / SLOWER, 2), abs_tol=1e-12)
