"""API 617 Level I anticipated cross-coupling Qa against examples worked by hand from the clause's
text (docs/level1_and_ucs.md, "Hand examples"): no published worked example with its inputs was
found, so these are computed here with the standard's constants (B_c = 3, B_t = 1.5, C = 9.55 in
N m/s, mm, rpm, kN/mm; C = 63 in hp, in, rpm, klbf/in), numbers chosen so that the arithmetic is
exact, and the package's Qa (exact torque, 60 / 2 pi) must print the same to the digits printed."""

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.level1 import anticipated_cross_coupling
from rotordyn_modal.cli import main

INCH, LBF = 0.0254, 4.4482216152605           # m, N (NIST SP 811)
HP = 550.0 * 12.0 * INCH * LBF                 # W: 550 ft lbf/s


def _digits(value, printed: str) -> bool:
    """``value`` rounded to the significant digits of ``printed`` equals it."""
    significant = len(printed.replace(".", "").lstrip("0"))
    return f"{value:.{significant}g}" == f"{float(printed):.{significant}g}"


def test_si_compressor_in_the_millimetre_form():
    """2,000,000 N m/s, density ratio 1.4, Dc 500 mm, Hc 20 mm, 6000 rpm:
    2e6 x 3 x 9.55 x 1.4 / (500 x 20 x 6000) = 1.337 kN/mm exactly."""
    assert 2e6 * 3 * 9.55 * 1.4 / (500 * 20 * 6000) == pytest.approx(1.337, rel=1e-15)
    q = anticipated_cross_coupling([2e6], rdm.rpm(6000), [0.5], [0.02], [1.4]).sum()
    assert _digits(q / 1e6, "1.337")                                  # N/m -> kN/mm


def test_us_turbine_stage_without_the_density_ratio():
    """5000 hp, Dt 40 in, Ht 3 in, 3600 rpm: 5000 x 1.5 x 63 / (40 x 3 x 3600) = 1.09375 klbf/in,
    printed 1.09; a density ratio given is not used for turbines."""
    assert 5000 * 1.5 * 63 / (40 * 3 * 3600) == 1.09375
    q = anticipated_cross_coupling([5000 * HP], rdm.rpm(3600), [40 * INCH], [3 * INCH], [1.7], machine="turbine")
    assert _digits(q.sum() / (1000 * LBF / INCH), "1.09")


def test_us_compressor_through_the_command_line(capsys):
    """1000 hp, density ratio 2, Dc 15 in, Hc 0.5 in, 10,000 rpm: 1000 x 3 x 63 x 2 / (15 x 0.5 x
    10,000) = 5.04 klbf/in exactly; `level1 --units us` reads hp and in and prints Qa in lbf/in."""
    assert 1000 * 3 * 63 * 2 / (15 * 0.5 * 10000) == 5.04
    code = main(["level1", "examples/journal_rotor.toml", "--mcs", "4000", "--station", "rotor", "--units", "us",
                 "--rated-power", "1000", "--impeller-diameter", "15", "--restriction-height", "0.5",
                 "--density-ratio", "2", "--operating-speed", "10000"])
    assert code == 0
    line = next(x for x in capsys.readouterr().err.splitlines() if x.startswith("Qa = "))
    value, unit = line.split()[2:4]
    assert unit == "lbf/in"
    assert _digits(float(value) / 1000, "5.04")
