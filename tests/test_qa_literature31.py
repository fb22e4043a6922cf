"""API 617 Level I anticipated cross-coupling Qa: what the twelfth search for a worked example from
the literature found (issue 29; docs/standards.md, "Level I sources, twelfth search").

No worked example from the literature (a stage's inputs printed with its Qa) could be reached, so
none is reproduced here. The one new set of published Qa values found is in the tests of
ross-rotordynamics/ross-report, a report generator of the ROSS project (not literature, and not
independent of ROSS): ``report/tests/test_analysis.py::test_stability_level1`` (commit b64db70)
asserts Qa = 2113.54853260414442, 669.69218396836 and 895.3125000000002 for three machines. Its
``report/analysis.py`` (``Report._stability_level_1``, 2021) converts the rated power to **hp**
but keeps the SI constant ``C = 9.55`` with D and H in m and the speed in rpm, and applies the
result as a stiffness in N/m. These tests pin both statements made in the docs: fed the hp number
as if it were watts, the package's formula gives ross-report's printed values (after the rounded
C = 9.55 for the exact 60 / 2 pi); fed the power in watts, it gives 745.7 times more, which the
clause's own US form (C = 63, hp, in, rpm, klbf/in) confirms independently.
"""

import math

import pytest

from rotordyn_modal.analysis.level1 import anticipated_cross_coupling

INCH, LBF = 0.0254, 4.4482216152605           # m, N (NIST SP 811)
HP = 550.0 * 12.0 * INCH * LBF                 # W: 550 ft lbf/s
ROUNDED_C = 9.55 / (60.0 / (2.0 * math.pi))    # the standard's C over the package's exact torque factor
D, H = [0.35, 0.35], [0.08, 0.08]              # m, ross-report's fixtures
RATIOS = [1.11, 1.14]

# ross-report's fixtures: rated power (config "power_unit": "hp"), speed, machine type, and the
# Qa its test asserts; report1 is single overhung: ross-report counts its one disk (stage 0) only
CASES = {
    "report0 compressor, 800 rad/s": ([6000, 8000], 800.0, D, H, RATIOS, "compressor", 2113.54853260414442),
    "report1 turbine, one stage, 800 rad/s": ([10000], 800.0, D[:1], H[:1], 1.0, "turbine", 669.69218396836),
    "report2 axial flow, 8000 rpm": ([6000, 8000], 8000 * 2 * math.pi / 60, D, H, 1.0, "turbine", 895.3125000000002),
}


@pytest.mark.parametrize("case", list(CASES))
def test_ross_report_values_are_the_si_formula_fed_horsepower(case):
    """The package's q_A with the hp number in place of watts, times 9.55 / (60 / 2 pi), is the value
    ross-report prints, to its printed digits; with the power in watts it is HP (745.7) times more."""
    power_hp, speed, diameter, height, ratio, machine, printed = CASES[case]
    as_if_watts = anticipated_cross_coupling(power_hp, speed, diameter, height, ratio, machine).sum()
    assert as_if_watts * ROUNDED_C == pytest.approx(printed, rel=1e-12)
    in_watts = anticipated_cross_coupling([p * HP for p in power_hp], speed, diameter, height, ratio, machine).sum()
    assert in_watts * ROUNDED_C / printed == pytest.approx(HP, rel=1e-12)


def test_the_unit_consistent_qa_of_ross_reports_compressor_from_the_us_form():
    """report0's compressor by the clause's US form, worked here: 3 x 63 x (6000 x 1.11 + 8000 x 1.14)
    / (13.78 in x 3.150 in x 7639.4 rpm) = 9.00 klbf/in = 1.58e6 N/m, not ross-report's 2113.5."""
    d_in, h_in, rpm = 0.35 / INCH, 0.08 / INCH, 800.0 * 60 / (2 * math.pi)
    us_form = 3 * 63 * (6000 * 1.11 + 8000 * 1.14) / (d_in * h_in * rpm)      # klbf/in
    assert us_form == pytest.approx(8.995, abs=5e-4)
    q = anticipated_cross_coupling([6000 * HP, 8000 * HP], 800.0, D, H, RATIOS).sum()     # N/m
    assert q / (1000 * LBF / INCH) == pytest.approx(us_form, rel=5e-4)    # C = 63 is 63.025 rounded
    assert q / 2113.54853260414442 == pytest.approx(HP, rel=1e-4)          # C = 9.55 is 9.5493 rounded
