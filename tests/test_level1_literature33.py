"""API 617 Level I anticipated cross-coupling Qa: issue 29 §3 asks that Qa reproduce a worked example
from the literature. None could be found (docs/standards.md, "Level I sources, thirteenth search":
what was searched this time, after the twelve searches written there before), so no value here is a
"literature" value. What is checked instead is what a reader can verify without the standard: that
the standard's two printed forms of the formula, as the Level I clause is transcribed in
ross-rotordynamics/ross-report ``report/standard_text.py`` (API 617 8th ed., 2014),

    SI:  q_A = B C P / (D H N_r) (rho_d / rho_s),  C = 9.55,  P in N m/s, D and H in mm, q_A in kN/mm
    US:  q_A = B C P / (D H N_r) (rho_d / rho_s),  C = 63,    P in hp,    D and H in in, q_A in klbf/in

(B = 3 compressors, 1.5 turbines; N_r in rpm), are one formula: both constants are the torque of a
unit power at 1 rpm, 60 / 2 pi in N m per W and 6.6 x 60 / 2 pi = 396 / 2 pi in klbf in per hp
(1 hp = 550 ft lbf/s = 6600 lbf in/s, exactly), rounded; and that the package's q_A, which takes
the torque exactly, equals both exact forms to round-off whatever the units the inputs came in.
Unit definitions: NIST SP 811 appendix B (1 in = 0.0254 m, 1 lbf = 4.4482216152605 N exactly,
1 lbm = 0.45359237 kg)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotordyn_modal.analysis.level1 import anticipated_cross_coupling

INCH = 0.0254                                # m
LBF = 0.45359237 * 9.80665                   # N
HP = 550.0 * 12.0 * INCH * LBF               # W (mechanical horsepower: 550 ft lbf/s)
C_SI = 60.0 / (2.0 * math.pi)                # N m per W at 1 rpm
C_US = 6600.0 / 1000.0 * C_SI                # klbf in per hp at 1 rpm: 6600 lbf in/s per hp

#: stages chosen across the range a compressor or turbine stage has (power W, speed rpm, D m,
#: H m, density ratio); not from a source: any numbers check an identity
STAGES = [(5e3, 1000.0, 0.2, 0.01, 1.05), (2.5e6, 9000.0, 0.6, 0.025, 1.3), (12e6, 3600.0, 1.1, 0.08, 1.9),
          (400e3, 15000.0, 0.35, 0.012, 1.0)]


def test_the_two_constants_are_one_torque_rounded():
    """9.55 is 60 / 2 pi to 3 significant digits and 63 is 396 / 2 pi to 2: the standard's SI and
    US constants are the same torque per power and speed in two unit systems."""
    assert C_SI == pytest.approx(9.549296585513721, rel=1e-15)
    assert HP == pytest.approx(745.6998715822702, rel=1e-15)
    # hp in lbf in/s, and the klbf in of a N m: the ratio of the constants is 6.6, exactly
    assert HP / (LBF * INCH) == pytest.approx(6600.0, rel=1e-14)
    assert C_US == pytest.approx(HP * C_SI / (1000.0 * LBF * INCH), rel=1e-14)
    assert round(C_SI, 2) == 9.55 and round(C_US) == 63
    assert abs(9.55 / C_SI - 1) < 1e-4 and abs(63.0 / C_US - 1) < 5e-4


@pytest.mark.parametrize("machine", ["compressor", "turbine"])
@pytest.mark.parametrize("stage", STAGES)
def test_the_package_equals_the_exact_si_and_us_forms(stage, machine):
    """q_A of the package (SI, torque exact) equals the SI form in mm and kN/mm and the US form in
    hp, in, rpm and klbf/in with the exact constants, to round-off; and the standard's rounded
    constants to their rounding (7.4e-5 and 4.0e-4)."""
    power, rpm, diameter, height, ratio = stage
    b = 3.0 if machine == "compressor" else 1.5
    rho = ratio if machine == "compressor" else 1.0
    q = anticipated_cross_coupling([power], rpm * math.pi / 30, [diameter], [height], [ratio], machine)[0]   # N/m
    si_form = b * C_SI * power / (diameter * 1e3 * height * 1e3 * rpm) * rho                       # kN/mm
    us_form = b * C_US * (power / HP) / (diameter / INCH * height / INCH * rpm) * rho               # klbf/in
    assert q / 1e6 == pytest.approx(si_form, rel=1e-13)                  # 1 kN/mm = 1e6 N/m
    assert q / (1000.0 * LBF / INCH) == pytest.approx(us_form, rel=1e-13)
    rounded_si = b * 9.55 * power / (diameter * 1e3 * height * 1e3 * rpm) * rho
    rounded_us = b * 63.0 * (power / HP) / (diameter / INCH * height / INCH * rpm) * rho
    assert rounded_si / si_form == pytest.approx(9.55 / C_SI, rel=1e-13)
    assert rounded_us / us_form == pytest.approx(63.0 / C_US, rel=1e-13)


def test_inputs_in_us_units_give_the_same_qa_as_in_si():
    """The same machine typed in hp and in (converted by the package's own units module, as
    ``level1 --units us`` converts them) and in W and m gives one Qa, to round-off: a stage sum over
    the four stages above as one compressor at 9000 rpm."""
    from rotordyn_modal.units import from_system

    power = np.array([s[0] for s in STAGES])
    diameter, height, ratio = (np.array([s[k] for s in STAGES]) for k in (2, 3, 4))
    speed = 9000 * math.pi / 30
    si = anticipated_cross_coupling(power, speed, diameter, height, ratio).sum()
    us = anticipated_cross_coupling(from_system(power / HP, "power", "us"), speed,
                                    from_system(diameter / INCH, "length", "us"),
                                    from_system(height / INCH, "length", "us"), ratio).sum()
    assert us == pytest.approx(si, rel=1e-13)
    by_hand = sum(3 * C_US * (p / HP) / (d / INCH * h / INCH * 9000) * r
                  for p, d, h, r in zip(power, diameter, height, ratio))                            # klbf/in
    assert si / (1000.0 * LBF / INCH) == pytest.approx(by_hand, rel=1e-13)
