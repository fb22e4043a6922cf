"""A sixth round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families5.py``): flexible rotors at scales decades apart (a shaft on soft bearings
in a casing on mounts), every file-valued option given a file it cannot use, and measured files
as other tools write them (a Universal File with a byte-order mark, a CSV of a header alone).
Each case through the command line in this process (exit 2 with one line naming the option or
file) or through the reader the command line calls."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import read_measured
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"
MAPPING = "name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,101,3\nshaker-y,102,2\n"


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """The gear machine's FRFs at 600 rpm, 2 to 40 Hz in 5 lines, as ``frf --out`` writes them
    in CSV and in UFF 58 (read only: each test writes its own files)."""
    folder = tmp_path_factory.mktemp("measured")
    for name in ("g.csv", "g.uff"):
        assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--out", str(folder / name),
                     "--quiet"]) == 0
    return folder


# ----------------------------------------------------------------------- file-valued options
@pytest.mark.parametrize("argv", [
    ["frf", GEAR, "--speed", "600", "--freqs", "2:40:5", "--measured", "{csv}", "--mapping", "{tmp}/missing.csv"],
    ["frf", GEAR, "--speed", "600", "--freqs", "2:40:5", "--mapping", "{tmp}/map.csv", "--out", "{tmp}/f.csv"],
    ["fit", GEAR, "--measured", "{csv}", "--mapping", "{tmp}/missing.csv", "--params",
     "suspensions.mount-FL.damping", "--out", "{tmp}/fit.toml"],
], ids=["frf-csv-missing-table", "frf-no-uff", "fit-csv-missing-table"])
def test_a_mapping_beside_no_universal_file_is_refused(tmp_path, capsys, measured, argv):
    """A mapping table places a Universal File's channels: beside a CSV (read or written) it was
    passed over without a word, even a table that does not exist (exit 0, a fitted model
    written)."""
    (tmp_path / "map.csv").write_text(MAPPING)
    argv = [str(a).replace("{csv}", str(measured / "g.csv")).replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv + ["--quiet"]) == 2
    _one_line_error(capsys, "--mapping", "Universal File")
    assert not any(p.suffix in (".toml", ".csv") and p.name != "map.csv" for p in tmp_path.iterdir())


def test_a_mapping_beside_a_universal_file_written_is_used(tmp_path, measured):
    """The table still places the channels of a UFF written beside a CSV read."""
    (tmp_path / "map.csv").write_text(MAPPING.replace("acc-top-z,1,3", "acc-top-z,7,3"))
    out = tmp_path / "f.uff"
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--measured", str(measured / "g.csv"),
                 "--mapping", str(tmp_path / "map.csv"), "--out", str(out), "--quiet"]) == 0
    assert " acc-top-z          7   3" in out.read_text()     # record 6: entity name (10A1), node (I10), direction


def test_the_reader_refuses_a_missing_mapping_beside_a_csv(tmp_path, measured):
    model = rdm.load_model(GEAR)
    with pytest.raises(InputError, match="missing.csv"):
        read_measured(measured / "g.csv", model, tmp_path / "missing.csv")


# ----------------------------------------------------------------------- other tools' files
def test_a_universal_file_with_a_byte_order_mark_reads_as_without(tmp_path, measured):
    """Windows tools write a UTF-8 byte-order mark before the first ``    -1``: the file was
    refused as 'incomplete ... not closed by a -1 line (from line 77)'."""
    model = rdm.load_model(GEAR)
    path = tmp_path / "bom.uff"
    path.write_bytes(b"\xef\xbb\xbf" + (measured / "g.uff").read_bytes())
    plain, marked = read_measured(measured / "g.uff", model)[0], read_measured(path, model)[0]
    assert marked.outputs == plain.outputs and marked.inputs == plain.inputs
    np.testing.assert_array_equal(marked.frequencies_hz, plain.frequencies_hz)
    np.testing.assert_array_equal(marked.H, plain.H)


def test_a_measured_csv_of_a_header_alone_is_refused_as_such(tmp_path, capsys, measured):
    """It was refused as "quantity column holds []", a column no line filled."""
    path = tmp_path / "header.csv"
    path.write_text((measured / "g.csv").read_text().splitlines()[0] + "\n")
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--measured", str(path), "--quiet"]) == 2
    _one_line_error(capsys, str(path), "no data line")


# ----------------------------------------------------------------------- scales decades apart
def _shaft_in_casing(bearing_stiffness: float) -> dict:
    """A uniform steel shaft (1 m, 50 mm, Euler-Bernoulli) on a bearing at each end in a 50 kg
    casing on four mounts of 1e5 N/m each way, under gravity."""
    return {
        "spin_axis": [1.0, 0.0, 0.0], "gravity": [0.0, 0.0, -9.81],
        "stator": {"mass": 50.0, "center_of_mass": [0.0, 0.0, 0.0], "inertia": [2.0, 3.0, 3.0]},
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "shaft", "start": [-0.5, 0.0, 0.0], "shear": "none",
                    "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel", "elements": 10}]}],
        "bearings": [{"name": n, "rotor": "shaft", "axial_position": z, "stiffness": bearing_stiffness}
                     for n, z in (("a", 0.0), ("b", 1.0))],
        "suspensions": [{"name": f"m{i}", "position": [x, y, 0.0], "stiffness": [1e5, 1e5, 1e5]}
                        for i, (x, y) in enumerate(((0.4, 0.3), (0.4, -0.3), (-0.4, 0.3), (-0.4, -0.3)))]}


@pytest.mark.parametrize("bearing_stiffness", [100.0, 10.0])
def test_a_stiff_shaft_on_soft_bearings_in_a_casing_stands_under_gravity(bearing_stiffness):
    """Bearings of 100 N/m under a shaft whose elements are 1e9 N/m stiff: the static stiffness's
    smallest scaled singular values are 3e-13 of its largest, which a fixed 1e-12 cut-off took for
    free motions ('no suspension or bearing holds ...: the machine would not stand still'); they
    hold 3 more digits than round-off. The sag is the closed form: the casing ``(M + m) g / 4 k_m``,
    the shaft's ends ``w L / 2 k`` below it, its middle ``5 w L^4 / 384 E I`` further (exact at
    the nodes of cubic elements)."""
    model = rdm.Model.from_dict(_shaft_in_casing(bearing_stiffness))
    q = rdm.static(model).coordinates
    names = list(model.dofs.names)
    area, second = math.pi * 0.05**2 / 4, math.pi * 0.05**4 / 64
    w = 7800.0 * area * 9.81                            # [N/m] the shaft's weight per length
    ends = -w / (2 * bearing_stiffness)
    assert q[names.index("stator.uz")] == pytest.approx(-(50.0 + 7800.0 * area) * 9.81 / 4e5, rel=1e-12)
    assert q[names.index("shaft.n0.uz")] == pytest.approx(ends, rel=1e-5)
    assert q[names.index("shaft.n5.uz")] == pytest.approx(ends - 5 * w / (384 * 2e11 * second), rel=1e-5)


OVERDAMPED = """spin_axis = [1.0, 0.0, 0.0]
[[rotors]]
name = "r"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.5
speed_ratio = 1.0
[[bearings]]
name = "a"
rotor = "r"
position = [-0.2, 0.0, 0.0]
stiffness = 1.0e3
damping = 1.0e3
[[bearings]]
name = "b"
rotor = "r"
position = [0.2, 0.0, 0.0]
stiffness = 1.0e3
damping = 1.0e3
"""


def test_level1_of_a_root_that_does_not_oscillate_at_zero_names_no_mode(tmp_path, capsys):
    """A rotor of 10 kg on bearings of 2 x 1e3 N/m and 2 x 1e3 N s/m (damping ratio 7): at Q = 0
    its cylindrical roots are real, and ``level1`` printed 'mode 0 (0 Hz at Q = 0) followed', a
    mode no table has (and counted the modes before a root that is none as its number). The
    cross-coupling makes ``m r'' + c r' + k r - i Q r = 0`` whirl; it loses stability where
    ``k = m w^2`` and ``Q = c w``: ``Q0 = c sqrt(k / m)``."""
    path = tmp_path / "overdamped.toml"
    path.write_text(OVERDAMPED)
    result = rdm.level1(rdm.load_model(path), rdm.rpm(3000.0), ["r"], 1e4, factor=3, steps_per_qa=4)
    assert result.q0 == pytest.approx(2e3 * math.sqrt(2e3 / 10.0), rel=1e-9)
    assert result.mode == 0 and result.frequencies_hz[0] == 0.0
    assert main(["level1", str(path), "--speed", "3000", "--station", "r", "--qa", "1e4", "--factor", "3"]) == 0
    err = capsys.readouterr().err
    assert "a root that does not oscillate at Q = 0 followed" in err and "mode 0" not in err, err


def test_a_soft_axial_bearing_beside_stiff_radial_ones_holds_the_rotor(tmp_path):
    """A rigid rotor (10 kg, diametral inertia 0.5) on two radial bearings of 1e8 N/m 0.4 m apart,
    one of them also axial with 1e-6 N/m: refused as 'nothing holds its translation along the y
    axis', which 2e8 N/m hold. The bearings' stiffness was scaled ``K_ij / (s_i s_j)``, a unit
    diagonal's inverse, so the stiffest motion read as the free one. Its roots are the closed
    forms ``sqrt(k / m)``: axial ``sqrt(1e-6 / 10)``, lateral ``sqrt(2e8 / 10)``, tilt
    ``sqrt(1e8 * 2 * 0.2^2 / 0.5)`` [rad/s]; an axial force F moves it ``F / k_axial``."""
    path = tmp_path / "axial.toml"
    path.write_text(OVERDAMPED.replace("stiffness = 1.0e3", "stiffness = 1.0e8").replace("damping = 1.0e3", "")
                    + "axial_stiffness = 1.0e-6\n")
    model = rdm.load_model(path)
    roots = np.sort(rdm.modal(model, 0.0).eigenvalues.imag)
    expected = np.sqrt([1e-6 / 10, 1e8 * 2 * 0.04 / 0.5, 1e8 * 2 * 0.04 / 0.5, 2e8 / 10, 2e8 / 10])
    np.testing.assert_allclose(roots, expected, rtol=1e-9)
    q = rdm.static(model, forces=[("r", [0.0, 0.0, 0.0], [1e-3, 0.0, 0.0])]).coordinates
    assert q[list(model.dofs.names).index("r.ux")] == pytest.approx(1e-3 / 1e-6, rel=1e-9)


# ----------------------------------------------------------------------- flexible rotors' keys
COMPRESSOR = ROOT / "examples" / "compressor_rotor.toml"


@pytest.mark.parametrize("old, new, words", [
    ("poisson_ratio = 0.3", "shear_modulus = 1.0e30",
     ["[materials.steel] shear_modulus = 1e+30", "above -1"]),
    ("outer_diameter = 0.11\nmaterial", "outer_diameter = 0.11\ninner_diameter = 0.10999999999999989\nmaterial",
     ["[rotors.compressor.shaft.1] inner_diameter = 0.10999999999999989", "at least 1e-06 m below"]),
], ids=["shear-modulus-rounding-nu-to-minus-one", "wall-of-round-off"])
def test_a_material_or_bore_of_no_shaft_is_refused_by_its_key(tmp_path, capsys, old, new, words):
    """``shear_modulus = 1e30`` beside E = 2.11e11: Poisson's ratio ``E / 2G - 1`` rounds to -1, the
    shear coefficient to 0, and every analysis ended in ZeroDivisionError (exit 1). A bore of the
    outer diameter less round-off (a wall of 5e-17 m) was refused as '[stator], [[rotors]] mass and
    inertia = <mass matrix>', naming neither the key nor the rotor."""
    text = COMPRESSOR.read_text()
    assert old in text
    path = tmp_path / "m.toml"
    path.write_text(text.replace(old, new, 1))
    assert main(["modes", str(path), "--speed", "3000", "--quiet"]) == 2
    _one_line_error(capsys, str(path), *words)


def test_check_counts_a_slender_shafts_bending_as_held(tmp_path, capsys):
    """The compressor with a 1 mm shaft 20 m long at its end (10 elements): ``check`` noted
    'restrain 87 of 93 directions (the others give zero eigenvalues)' from the rank of K
    unscaled (its overhang's elements 1 N/m beside the compressor's 1e9). The overhang's bending
    is held: every eigenvalue of the undamped machine at rest, ``K phi = w^2 M phi`` (scipy), is
    positive, the lowest at 0.011 rad/s."""
    import scipy.linalg

    text = COMPRESSOR.read_text().replace("[[rotors.disks]]", "[[rotors.shaft]]\nlength = 20.0\n"
                                          "outer_diameter = 1.0e-3\nmaterial = \"steel\"\nelements = 10\n\n"
                                          "[[rotors.disks]]", 1)
    path = tmp_path / "slender.toml"
    path.write_text(text)
    model = rdm.load_model(path)
    M, _, _, K = model.matrices()
    squares = scipy.linalg.eigh(0.5 * (K + K.T), M, eigvals_only=True)
    assert len(squares) == 93 and squares.min() > 0 and math.sqrt(squares.min()) == pytest.approx(0.0114, rel=0.02)
    assert main(["check", str(path)]) == 0
    assert "note:" not in capsys.readouterr().out


def test_a_pedestal_of_no_mass_is_refused_pointing_at_the_mass(tmp_path, capsys):
    """``pedestal_mass = 1e-30`` under the pump's inboard bearing: refused as the bearing's 1e8 N/m
    being far too stiff ('at most about 9e-13 N/m'), the mass it acts on not mentioned."""
    text = (ROOT / "examples" / "flexible_pump_on_mounts.toml").read_text()
    old = 'name = "pump-IB"                  # inboard, next to the impeller\n'
    assert old in text
    path = tmp_path / "pedestal.toml"
    path.write_text(text.replace(old, old + "pedestal_mass = 1.0e-30\npedestal_stiffness = 1.0e7\n"))
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "[bearings.pump-IB]", "a mass or inertia where it acts far too small")


def test_an_unbalance_offset_off_the_shaft_is_refused_in_its_own_terms(tmp_path, capsys):
    """``axial_offset = 0.65`` on the compressor (centre of mass 0.583 m from the start of its
    1.2 m shaft) lands at 1.233 m: refused as 'expected an axial position on the shaft, from 0 to
    its length 1.2 m (measured from the rotor's start)', which 0.65 is. The range of an offset
    runs from minus the centre's distance to the shaft's length less it."""
    text = COMPRESSOR.read_text()
    old = "amount = 2.0e-4\naxial_position = 0.30\n"
    assert old in text
    path = tmp_path / "offset.toml"
    path.write_text(text.replace(old, "amount = 2.0e-4\naxial_offset = 0.65\n", 1))
    centre = rdm.load_model(COMPRESSOR).rotor("compressor").center_of_mass[0]
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "[unbalances[0]] axial_offset = 0.65", f"from {-centre:.6g} to {1.2 - centre:.6g} m",
                    "centre of mass")


def test_a_stiff_axial_bearing_beside_soft_radial_ones_is_named_by_its_key(tmp_path, capsys):
    """The compressor's bearings made 1e-10 N/m radially, the thrust bearing kept at 2e8 N/m:
    refused first as 'nothing holds its translation along the x axis' (the axis 2e8 N/m hold),
    then, by the stiffness spread, as 'stiffness = '2e+08'', a value the file gives as
    axial_stiffness."""
    text = COMPRESSOR.read_text().replace("stiffness = 5.0e7", "stiffness = 1.0e-10")
    path = tmp_path / "soft.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "[bearings.right] axial_stiffness = '2e+08'", "stiffness spread")


# ----------------------------------------------------------------------- a long modes solve
COMPRESSOR = ROOT / "examples" / "compressor_rotor.toml"


def test_a_long_modes_solve_is_announced_with_its_estimate_before_it_starts(capsys, monkeypatch):
    """``modes`` on a 513-node shaft (4,114 states) ran over 10 minutes without a word: LAPACK's
    one call shows no progress, so the estimate is said on stderr before it starts. The solve runs
    with one BLAS thread, as the estimate times it (tests/test_cost_estimate.py): a limit below
    the estimate is refused."""
    from rotordyn_modal.analysis import _work
    from rotordyn_modal.cli import modes

    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1e-4)           # 106 states: timed at that size
    monkeypatch.setattr(modes, "_NOTICE_SECONDS", 1e-9)
    n_states = 2 * rdm.load_model(COMPRESSOR).dofs.n
    assert main(["modes", str(COMPRESSOR), "--speed", "3000", "--out", "-"]) == 0
    err = capsys.readouterr().err
    assert f"one eigen-solution of {n_states:,} states" in err and "--lowest N" in err, err
    monkeypatch.setenv(_work.ENVIRONMENT, str(0.5 * 1e-4 / 60))            # below the estimate
    assert main(["modes", str(COMPRESSOR), "--speed", "3000"]) == 2
    _one_line_error(capsys, "more than the limit", "--allow-long", str(COMPRESSOR))


def test_level1_figure_and_report_name_a_root_that_does_not_oscillate_and_bold_one_curve(tmp_path):
    """The figure's legend and the report's Level I section printed 'mode 0' for the overdamped
    root of ``test_level1_of_a_root_that_does_not_oscillate_at_zero_names_no_mode``, and chose the
    bold (judged) curve by ``mode``: two followed roots of mode 0 were both drawn bold. The
    judged root is the one of the result's forward rank, whatever its mode number."""
    from dataclasses import replace
    from types import SimpleNamespace

    import matplotlib

    matplotlib.use("Agg")
    from rotordyn_modal.report.render import _level1

    path = tmp_path / "overdamped.toml"
    path.write_text(OVERDAMPED)
    one = rdm.level1(rdm.load_model(path), rdm.rpm(3000.0), ["r"], 1e4, factor=3, steps_per_qa=4)
    assert one.mode == 0
    other = replace(one, forward_mode=2, log_decrements=one.log_decrements + 0.5, swept=())
    result = replace(one, swept=(replace(one, swept=()), other))
    figure = result.plot()
    lines = [line for line in figure.axes[0].get_lines() if "forward" in str(line.get_label())]
    assert len(lines) == 2
    assert [line.get_linewidth() > 1.5 for line in lines] == [True, False]   # forward 1 judged, alone bold
    assert not any("mode 0" in str(line.get_label()) for line in lines)
    html = _level1(SimpleNamespace(results={"level1": result}), "si")
    assert "mode 0" not in html and "does not oscillate at Q = 0" in html
    table = html.split("Forward modes swept")[1]
    assert len(re.findall(r"log decrement at Qa(?! \[)", table)) == 1, table   # one row governs it


def test_a_cross_spectrum_of_a_pair_without_its_frf_is_refused_by_name(tmp_path, capsys, measured):
    """A dataset 58 of function type 3 (a cross-spectrum) in place of a pair's FRF was skipped
    without a word and the pair read as NaN: refused in one line naming the dataset."""
    import pyuff

    sets = pyuff.UFF(str(measured / "g.uff")).read_sets()
    sets = [sets] if isinstance(sets, dict) else list(sets)
    frfs = [k for k, s in enumerate(sets) if s["type"] == 58 and s["func_type"] == 4]
    sets[frfs[1]]["func_type"] = 3
    path = tmp_path / "spectrum.uff"
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    (tmp_path / "spectrum.csv").write_text(MAPPING)
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--measured", str(path),
                 "--mapping", str(tmp_path / "spectrum.csv"), "--out", str(tmp_path / "f.csv")]) == 2
    _one_line_error(capsys, str(path), f"dataset {frfs[1] + 1} (", "function type 3 (cross-spectrum) is not an FRF")


def test_a_shafts_bending_puts_no_stiffness_on_its_rigid_axial_coordinate():
    """The axial coordinate moves every node of the shaft alike: a rigid translation of the free
    shaft strains no element, so its row and column of the shafts' stiffness are zero in exact
    arithmetic (round-off had left ~4e-6 N/m, above an axial_stiffness of 1e-6 N/m); the rest is
    the sum of the elements' (not touched)."""
    from rotordyn_modal.assembly import shaft_stiffness, sparse_constant_matrices

    model = rdm.load_model(ROOT / "examples" / "compressor_rotor.toml")
    axial = model.dofs.names.index("compressor.ux")
    K = shaft_stiffness(model)
    assert np.all(K[axial] == 0.0) and np.all(K[:, axial] == 0.0)
    assert np.abs(K).max() > 1e9                                          # the bending is there
    assert model.matrices(0.0).K[axial, axial] == 2.0e8                  # the thrust bearing's alone
    assert sparse_constant_matrices(model)[3].toarray()[axial, axial] == 2.0e8
