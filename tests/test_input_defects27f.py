"""Small input defects (input27f): each case failed on main before its fix.

1. ``ucs-map --operating-range`` outside a chosen bearing's speed table is refused, as
   ``report`` refuses it (one check, ``elements.bearings.table_left``).
2. ``check``'s frequencies 'at rest ... on its bearings' name the speed of a table's first row.
3. An unbalance whose eccentricity no rotor can have is refused when the model is read.
4. ``simulate`` estimates its CPU time before the integration and refuses it over the limit.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import rotordyn_modal as rdm
from degenerate_models import ROTOR_ON_BEARINGS, variant
from rotordyn_modal.errors import InputError

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

TABLE_MODEL = """name = "table rotor"
[[rotors]]
name = "r"
mass = 20.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.1
diametral_inertia = 1.0
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "r"
position = [0.3, 0.0, 0.0]
speeds_rpm = [{first}, 3000.0, 5000.0]
stiffness = [1e6, 2e6, 3e6]
damping = [100.0, 100.0, 100.0]

[[bearings]]
name = "B"
rotor = "r"
position = [-0.3, 0.0, 0.0]
stiffness = 2e6
"""


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "rotordyn_modal", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def _table_model(tmp_path, first=1000.0):
    path = tmp_path / "table.toml"
    path.write_text(TABLE_MODEL.format(first=first), encoding="utf-8")
    return path


@pytest.mark.parametrize("band", ["6000:8000", "500:3000", "0:3000"])
def test_ucs_map_operating_range_outside_a_speed_table_is_refused(tmp_path, band):
    """The table holds 1000 .. 5000 rpm: a band above or below it drew the band where the
    bearing's curve has no point, without a word (exit 0)."""
    path = _table_model(tmp_path)
    done = _cli("ucs-map", path, "--stiffness", "1e5:1e8:4", "--operating-range", band, "--out", tmp_path / "u.csv")
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and f"--operating-range {band}" in lines[0] and "[bearings.A]" in lines[0]
    assert "1000 .. 5000 rpm" in lines[0]
    assert not (tmp_path / "u.csv").exists()


def test_ucs_map_operating_range_inside_the_table_runs(tmp_path):
    path = _table_model(tmp_path)
    done = _cli("ucs-map", path, "--stiffness", "1e5:1e8:4", "--operating-range", "1000:5000", "--out",
                tmp_path / "u.csv")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "u.csv").is_file()


def test_ucs_map_api_operating_range_outside_a_speed_table_is_refused(tmp_path):
    model = rdm.load_model(_table_model(tmp_path))
    with pytest.raises(InputError, match=r"^operating = .*\[bearings\.A\] speeds_rpm 1000 \.\. 5000 rpm"):
        rdm.ucs_map(model, [1e6, 1e7], operating=(rdm.rpm(6000), rdm.rpm(8000)))
    result = rdm.ucs_map(model, [1e6, 1e7], operating=(rdm.rpm(1000), rdm.rpm(5000)))
    assert np.isfinite(result.speeds[:, 0]).all()


FLEXIBLE_MODEL = """name = "flexible shaft on a table"
spin_axis = [1.0, 0.0, 0.0]

[[materials]]
name = "steel"
density = 7810.0
young_modulus = 2.11e11
poisson_ratio = 0.3

[[rotors]]
name = "r"
start = [0.0, 0.0, 0.0]

[[rotors.shaft]]
length = 1.0
outer_diameter = 0.05
material = "steel"

[[bearings]]
name = "A"
rotor = "r"
axial_position = 0.05
{bearing_a}

[[bearings]]
name = "B"
rotor = "r"
axial_position = 0.95
stiffness = 2e6
"""


def _rest_line(tmp_path, name, bearing_a):
    path = tmp_path / f"{name}.toml"
    path.write_text(FLEXIBLE_MODEL.format(bearing_a=bearing_a), encoding="utf-8")
    done = _cli("check", path)
    assert done.returncode == 0, done.stderr
    return next(line for line in done.stdout.splitlines() if "at rest:" in line)


@pytest.mark.parametrize("first", [1000.0, 0.0])
def test_check_names_the_table_row_it_takes_for_the_bearings_at_rest(tmp_path, first):
    """2. A table starting at 1000 rpm: 'at rest ... on its bearings' used its first row (the
    stiffness of 1000 rpm) without saying so. The line now names that row's speed; the
    frequencies are those of the same shaft on a constant bearing of that row's stiffness (an
    independent build), and a table starting at 0 rpm says nothing more."""
    table = _rest_line(tmp_path, "table", f"axial_stiffness = [1e8, 1e8, 1e8]\nspeeds_rpm = [{first}, 3000.0, 6000.0]\n"
                                          "stiffness = [2e6, 4e7, 8e7]")
    constant = _rest_line(tmp_path, "constant", "axial_stiffness = 1e8\nstiffness = 2e6")
    named = "[bearings.A] at its table's first row, 1000 rpm"
    if first:
        assert f"(stator held; {named})" in table
        assert table.replace(f"; {named}", "") == constant
    else:
        assert table == constant and "first row" not in table


def _rigid_rotor(mass, polar, unbalance):
    """``ROTOR_ON_BEARINGS`` of ``mass`` [kg] and polar and diametral inertia ``polar`` [kg m^2],
    with an unbalance given by the lines ``unbalance``."""
    rotor = (ROTOR_ON_BEARINGS.replace("mass = 1e30", f"mass = {mass}")
             .replace("polar_inertia = 0.05", f"polar_inertia = {polar}")
             .replace("diametral_inertia = 0.05", f"diametral_inertia = {polar}"))
    return rotor + f'[[unbalances]]\nrotor = "r"\n{unbalance}\n'


def test_simulate_refuses_an_unbalance_of_absurd_eccentricity_in_one_line(tmp_path):
    """3. 1e-4 kg m on a rotor of 1e-30 kg (eccentricity 1e26 m): ``simulate`` failed at t = 0
    with 'step size too small', exit 1. Now the model is refused, naming the unbalance."""
    path = tmp_path / "light.toml"
    path.write_text(variant(stator_mass="100.0", stator_inertia="[10.0, 10.0, 10.0]", rotor_mass="1e-30",
                            bearing="4e-13"), encoding="utf-8")
    done = _cli("simulate", path, "--speed", "1000", "--duration", "0.001", "--out", tmp_path / "s.csv")
    assert done.returncode == 2, done.stderr
    line = done.stderr.strip().splitlines()[-1]
    assert "error: " in line and "[unbalances[0]] amount = 0.0001" in line and "1e+26 m" in line
    assert "Traceback" not in done.stderr and not (tmp_path / "s.csv").exists()


@pytest.mark.parametrize("mass, polar, unbalance, refused", [
    (10.0, 0.05, "amount = 10.0", False),          # e = 1 m: the floor, kept
    (10.0, 0.05, "amount = 10.01", True),          # e = 1.001 m > max(1 m, sqrt(0.005) m)
    (10.0, 90.0, "amount = 29.9", False),          # radius of gyration 3 m: e = 2.99 m kept
    (10.0, 90.0, "amount = 30.1", True),
    (10.0, 0.05, 'grade = "G4000"\nservice_speed_rpm = 1.0', True),   # G / Omega = 38 m
    (10.0, 0.05, 'grade = "G4000"\nservice_speed_rpm = 100.0', False),  # 0.38 m (a slow diesel crank)
], ids=["floor", "above-floor", "gyration", "above-gyration", "grade-refused", "grade-kept"])
def test_the_eccentricity_bound_is_the_larger_of_one_metre_and_the_radius_of_gyration(
        tmp_path, mass, polar, unbalance, refused):
    """e = amount / m <= sqrt(Jp / m) for any mass of the rotor at any radius (Cauchy-Schwarz);
    1 m at least. A graded unbalance is named by its grade."""
    path = tmp_path / "rotor.toml"
    path.write_text(_rigid_rotor(mass, polar, unbalance), encoding="utf-8")
    if not refused:
        assert rdm.load_model(path).unbalances[0].amount > 0
        return
    key = "grade" if "grade" in unbalance else "amount"
    with pytest.raises(InputError, match=rf"\[unbalances\[0\]\] {key} = .*eccentricity"):
        rdm.load_model(path)


def _stiff_casing(tmp_path):
    """A casing of inertia [10, 10, 1.1e-11] kg m^2 about a 10 kg rotor: loadable, with a 13.7 MHz
    mode about z that the explicit integrator must follow (about 25 s of CPU per simulated ms)."""
    path = tmp_path / "stiff.toml"
    path.write_text(variant(stator_mass="100.0", rotor_mass="10.0", stator_inertia="[10.0, 10.0, 1.1e-11]"),
                    encoding="utf-8")
    return path


def test_simulate_refuses_a_run_over_the_cpu_limit_before_the_work(tmp_path, monkeypatch):
    """4. 0.01 s of that casing took minutes without a word (the 1e6-periods limit passes it).
    Now the estimate (2,000,001 output times x 14 evaluations x at least the ~0.1 us of a Python
    call) exceeds a limit of 0.6 s: one line naming --duration, the estimate and --allow-long, at
    once, no output, and nothing compiled first: in a fresh checkout (an empty numba cache, as CI
    has) the kernel's ~20 s compilation and its notice line come only after this check."""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "0.01")
    cache = tmp_path / "numba-cache"
    out = tmp_path / "s.csv"
    done = subprocess.run([sys.executable, "-m", "rotordyn_modal", "simulate", str(_stiff_casing(tmp_path)),
                           "--speed", "100", "--duration", "0.01", "--out", str(out)],
                          capture_output=True, text=True, timeout=60, env=dict(os.environ, NUMBA_CACHE_DIR=str(cache)))
    assert done.returncode == 2, done.stderr
    # the casing's own conditioning warning (a spread of masses: docs/theory.md section 8) is not
    # part of the refusal
    lines = [line for line in done.stderr.strip().splitlines() if "times the scale of what it holds" not in line]
    assert len(lines) == 1 and lines[0].startswith("rotordyn-modal simulate: error: --duration 0.01: "), lines
    assert "more than the limit of 0.6 s" in lines[0] and "--allow-long" in lines[0] and "1.37e+05 periods" in lines[0] and "2,000,001 output times" in lines[0]
    assert not out.exists()
    assert not list(cache.rglob("*.nbc")), "the kernel was compiled before the refusal"


def test_the_cpu_estimate_of_simulate_errs_low_and_allow_long_runs_it(tmp_path, monkeypatch):
    """The same casing for 0.02 ms (5,463 output times, 20 a period of its 13.7 MHz mode) under a
    limit of 60 us: refused by the API with the estimate; inside ``long_work_allowed`` it runs,
    and its CPU time is at least the estimate (a low bound, so that nothing the limit lets
    through is refused)."""
    import re
    import time

    model = rdm.load_model(_stiff_casing(tmp_path))
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-6")
    with pytest.raises(InputError, match=r"^duration = 2e-05 s: this simulation would take at least") as refused:
        rdm.simulate(model, 2e-5, speed=100.0)
    estimate = float(re.search(r"at least ([0-9.e+-]+) s of CPU", str(refused.value))[1])
    assert "5,463 output times" in str(refused.value)   # int(20 x 273.15 + 1)
    start = time.process_time()
    with rdm.long_work_allowed():
        result = rdm.simulate(model, 2e-5, speed=100.0)
    assert np.isfinite(result.states).all()
    assert time.process_time() - start >= estimate
