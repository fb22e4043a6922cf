"""Measured mode shapes (UFF dataset 55) read, and paired with the model's modes by MAC.

Truth from outside the reader: files written by pyuff's own dataset 55 writer from known
shapes and eigenvalues (E13.5: 6 digits), hand-written files in the layouts of ARTeMIS Modal and
of permas4edu's EMA (seen in permas4edu/permas4edu ema/examples/007/EstimatedModesRFPZ.uff and
ema/examples/019/Rotor_2_BandsFit.uff; no licence found there, so the files here are written by
hand with numbers of our own), and the model's eigen-solution."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import mac
from rotordyn_modal.assembly import sensor_rows
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "uff"
#: stator accelerometers added to gear_machine: position [m], axis (1 X, 2 Y, 3 Z)
EXTRA = [((0.5, 0.3, 0.5), 1), ((-0.5, -0.3, 0.5), 2), ((0.5, -0.3, -0.2), 3), ((-0.5, 0.3, 0.0), 1),
         ((0.2, 0.3, 0.5), 3), ((-0.3, -0.3, -0.2), 2), ((0.0, 0.0, 0.5), 2), ((0.4, 0.1, -0.2), 1)]


@pytest.fixture(scope="module")
def model():
    data = rdm.load_model(ROOT / "examples" / "gear_machine.toml").to_dict()
    for k, (position, axis) in enumerate(EXTRA):
        data["sensors"].append({"name": f"s{k}", "position": list(position),
                                "direction": [float(axis == a) for a in (1, 2, 3)]})
    return rdm.Model.from_dict(data)


@pytest.fixture(scope="module")
def model_modes(model):
    """The model's oscillating modes at rest: eigenvalues and shapes at the sensors (the default
    mapping: sensor k at node k along its axis)."""
    res = rdm.modal(model, 0.0)
    osc = np.flatnonzero(res.oscillatory)
    at = res.shapes[osc] @ sensor_rows(model, [s.name for s in model.sensors]).T
    return res.eigenvalues[osc], at


def _axis(sensor):
    return int(np.argmax(np.abs(sensor.direction)))


def _write_complex_modes(model, eigenvalues, shapes, path):
    """Dataset 55, analysis type 3, 3 complex values a node, by pyuff's writer."""
    uff = pyuff.UFF(str(path))
    for n, (lam, shape) in enumerate(zip(eigenvalues, shapes), start=1):
        r = np.zeros((3, len(model.sensors)), complex)
        for k, sensor in enumerate(model.sensors):
            r[_axis(sensor), k] = shape[k]
        uff.write_sets(pyuff.prepare_55(model_type=1, id1="NONE", id2="NONE", id3="NONE", id4="NONE", id5="NONE",
                                        analysis_type=3, data_ch=2, spec_data_type=8, data_type=5,
                                        n_data_per_node=3, r1=r[0], r2=r[1], r3=r[2],
                                        node_nums=list(range(1, len(model.sensors) + 1)), load_case=1, mode_n=n,
                                        eig=complex(lam), modal_a=0j, modal_b=0j), "add")


def test_complex_modes_written_by_pyuff_read_back_and_pair_with_mac_1(model, model_modes, tmp_path):
    eigenvalues, shapes = model_modes
    path = tmp_path / "modes.uff"
    _write_complex_modes(model, eigenvalues, shapes, path)
    read = rdm.read_uff_modes(path, model)
    assert read.outputs == tuple(s.name for s in model.sensors)
    np.testing.assert_allclose(read.poles, eigenvalues, rtol=1e-5)
    np.testing.assert_allclose(read.frequencies_hz, eigenvalues.imag / (2 * np.pi), rtol=1e-5)
    np.testing.assert_allclose(read.damping_ratios, -eigenvalues.real / np.abs(eigenvalues), rtol=1e-4)
    scale = np.abs(shapes).max(axis=1, keepdims=True)
    assert np.all(np.abs(read.shapes[:, :, 0] - shapes) <= 1e-5 * scale)
    assert np.allclose(np.diag(mac(shapes, shapes)), 1.0, atol=1e-12)         # the model's own shapes
    table = rdm.correlate_modes(model, read)
    assert list(table["model_mode"]) == list(table["measured_mode"]) == list(range(1, len(eigenvalues) + 1))
    assert (table["mac"] > 1 - 1e-8).all()
    assert (table["difference_pct"].abs() < 1e-3).all()


def test_normal_modes_of_six_values_a_node_with_a_mapping(model, tmp_path):
    """Analysis type 2 (real normal modes, data characteristic 3): frequency and viscous damping
    ratio from record 8; a sensor mapped to direction -2 reads minus the Y value."""
    rng = np.random.default_rng(7)
    nodes = [11, 12, 13]
    values = rng.normal(size=(2, 6, len(nodes)))
    path = tmp_path / "normal.uff"
    uff = pyuff.UFF(str(path))
    for n, (f, zeta) in enumerate([(12.5, 0.02), (31.25, 0.0125)], start=1):
        r = values[n - 1]
        uff.write_sets(pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=3, spec_data_type=12, data_type=2,
                                        n_data_per_node=6, r1=r[0], r2=r[1], r3=r[2], r4=r[3], r5=r[4], r6=r[5],
                                        node_nums=nodes, load_case=1, mode_n=n, modal_m=0.0, freq=f,
                                        modal_damp_vis=zeta, modal_damp_his=0.0), "add")
    channels = ChannelMap({(11, 3): ("acc-top-z", 1.0), (12, -2): ("acc-side-y", 1.0), (13, 1): ("s0", -1.0)}, {})
    read = rdm.read_uff_modes(path, model, channels)
    np.testing.assert_array_equal(read.frequencies_hz, [12.5, 31.25])
    np.testing.assert_array_equal(read.damping_ratios, [0.02, 0.0125])
    assert read.outputs == ("acc-top-z", "acc-side-y", "s0")
    expected = np.stack([values[:, 2, 0], -values[:, 1, 1], -values[:, 0, 2]], axis=1)
    np.testing.assert_allclose(read.shapes[:, :, 0].real, expected, rtol=1e-5, atol=0)


def _header(analysis=2, character=2, specific=8, data_type=2, per_node=3, ints=(2, 4, 1, 1)):
    return ["    -1", "    55", "NONE", "NONE", "NONE", "NONE", "NONE",
            "".join(f"{v:10d}" for v in (1, analysis, character, specific, data_type, per_node)),
            "".join(f"{v:10d}" for v in ints)]


def _e(*values):
    return "".join(f"{v:13.5E}" for v in values)


def test_a_record_8_over_two_lines_is_read_by_its_count(model, tmp_path):
    """Record 7 says 8 reals (6E13.5: two lines); pyuff reads record 8 as one line and the
    second line as the first node."""
    lines = _header(ints=(2, 8, 1, 1)) + [_e(20.0, 1.0, 0.03, 0.0, 0.0, 0.0), _e(0.0, 0.0),
                                          f"{1:10d}", _e(0.0, 0.0, 2.0), f"{2:10d}", _e(0.0, -1.0, 0.0), "    -1"]
    path = tmp_path / "two.uff"
    path.write_text("\n".join(lines) + "\n")
    read = rdm.read_uff_modes(path, model)
    assert read.frequencies_hz[0] == 20.0 and read.damping_ratios[0] == 0.03
    np.testing.assert_array_equal(read.shapes[0, :, 0], [2.0, -1.0])       # acc-top-z (node 1 Z), acc-side-y (2 Y)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            nodes = list(pyuff.UFF(str(path)).read_sets(0)["node_nums"])
        except Exception:       # pyuff's reader raises: it cannot read it either
            nodes = None
    assert nodes != [1, 2]      # pyuff misreads it (or raises): the record 8 count is this reader's own


def test_the_artemis_layout(model):
    """Complex eigenvalues in rad/s as ID line 3 states them: f = |lambda| / 2 pi and z in %;
    the package's frequency is the damped one, f sqrt(1 - z^2)."""
    path = DATA / "artemis_layout_modes.uff"
    stated = [(float(f), float(z) / 100) for f, z in re.findall(r"f=(\S+)Hz; z=(\S+)%", path.read_text("utf-8"))]
    channels = ChannelMap({(1, 1): ("s0", 1.0), (2, 1): ("s3", 1.0), (3, 1): ("s7", 1.0), (3, 2): ("s1", 1.0),
                           (9, 1): ("acc-top-z", 1.0)}, {})
    read = rdm.read_uff_modes(path, model, channels)
    assert len(stated) == 2 and read.outputs == ("s0", "s3", "s7", "s1")       # node 9 is in no set
    np.testing.assert_allclose(read.damping_ratios, [z for _, z in stated], rtol=2e-5)
    np.testing.assert_allclose(read.frequencies_hz, [f * np.sqrt(1 - z * z) for f, z in stated], rtol=2e-5)
    np.testing.assert_array_equal(read.shapes[0, :, 0], [0, -1.2e-7 + 3.1e-6j, 5.5e-7 - 2.5e-6j, 1e-8 + 2e-8j])


def test_the_permas4edu_layout_of_four_reals_is_refused(model):
    with pytest.raises(InputError, match=r"permas4edu_layout_modes_4_reals.uff: dataset 55 from line 2: record 7 "
                                         r"gives 2 integer and 4 real values where analysis type 3 \(complex "
                                         r"eigenvalue first order\) has 2 and 6"):
        rdm.read_uff_modes(DATA / "permas4edu_layout_modes_4_reals.uff", model)


REFUSED = {
    "frequency response data": (_header(analysis=5, ints=(2, 1, 1, 1)) + [_e(10.0)], r"analysis type 5 \(frequency "
                                                                                      r"response\) is not a mode"),
    "scalar data": (_header(character=1, per_node=1) + [_e(10.0, 0, 0.01, 0)], r"data characteristic 1 with 1 "),
    "a stress": (_header(specific=2) + [_e(10.0, 0, 0.01, 0)], r"specific data type 2 is not a motion"),
    "a node twice": (_header() + [_e(10.0, 0, 0.01, 0), f"{1:10d}", _e(1, 2, 3), f"{1:10d}", _e(1, 2, 3)],
                     r"line 13: node 1 is given twice"),
    "values short of record 6": (_header() + [_e(10.0, 0, 0.01, 0), f"{1:10d}", _e(1, 2)],
                                 r"from line 2 ends before its record 10 \(the values of node 1\)"),
    "values short of record 6, a node after": (_header() + [_e(10.0, 0, 0.01, 0), f"{1:10d}", _e(1, 2), f"{2:10d}",
                                                             _e(1, 2, 3)],
                                                r"line 14: record 9 \(node label\): expected whole numbers"),
    "a frequency of 0": (_header() + [_e(0.0, 0, 0.01, 0), f"{1:10d}", _e(1, 2, 3)], r"frequency 0 Hz"),
}


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_what_cannot_be_understood_is_refused_in_one_line(model, tmp_path, case):
    lines, message = REFUSED[case]
    path = tmp_path / "bad.uff"
    path.write_text("\n".join(lines + ["    -1"]) + "\n")
    with pytest.raises(InputError, match=message) as error:
        rdm.read_uff_modes(path, model)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


def test_a_file_without_dataset_55_is_refused(model):
    with pytest.raises(InputError, match=r"no dataset 55 or 2414 mode shapes \(data at nodes\) in the file; datasets "
                                         r"found: 58 \(function data\) \(FRFs and time records: frf --measured"):
        rdm.read_uff_modes(DATA / "ufffiles_frf_filled_excerpt.unv", model)


def test_modes_measured_on_the_command_line(model, model_modes, tmp_path, capsys):
    """``modes MODEL --measured FILE.uff --mapping FILE.csv --out T.csv``: the pairs by MAC."""
    eigenvalues, shapes = model_modes
    modes_file = tmp_path / "modes.uff"
    _write_complex_modes(model, eigenvalues, shapes, modes_file)
    model_file = tmp_path / "machine.toml"
    rdm.save_model(model, model_file)
    mapping = tmp_path / "nodes.csv"
    mapping.write_text("name,node,direction\n" + "".join(f"{s.name},{k + 1},{_axis(s) + 1}\n"
                                                         for k, s in enumerate(model.sensors)))
    out = tmp_path / "pairs.csv"
    assert main(["modes", str(model_file), "--measured", str(modes_file), "--mapping", str(mapping),
                 "--out", str(out)]) == 0
    table = pd.read_csv(out)
    assert list(table.columns) == ["measured_mode", "measured_hz", "measured_damping", "model_mode", "model_hz",
                                   "model_damping", "difference_pct", "mac"]
    assert list(table["model_mode"]) == list(range(1, len(eigenvalues) + 1)) and (table["mac"] > 1 - 1e-8).all()
    assert f"{len(eigenvalues)} modes (dataset 55) at {len(model.sensors)} sensors" in capsys.readouterr().err
    assert main(["modes", str(model_file), "--mapping", str(mapping)]) == 2
    assert "--mapping" in capsys.readouterr().err
    one = tmp_path / "one.csv"
    one.write_text("name,node,direction\nacc-top-z,1,3\n")
    assert main(["modes", str(model_file), "--measured", str(modes_file), "--mapping", str(one)]) == 2
    assert "a MAC needs two or more" in capsys.readouterr().err


def test_the_dataset_55_of_ufffiles_jl(model):
    """UFFFiles.jl's dataset151_164_58_55.unv (MIT, tests/data/uff/README.md): one complex mode of 7
    nodes, eigenvalue -0.90604 + 25.080i rad/s (E12.4 in 13 columns), modal A and B not zero; the
    sensors at nodes 1 (+Z), 2 (+Y), 3 (+X), ..., 7 (+Z) by the default mapping. The 164 of the file
    (inch) scales every value alike: no factor is applied to the shapes."""
    read = rdm.read_uff_modes(DATA / "ufffiles_units_inch_pound.unv", model)
    assert read.outputs == ("acc-top-z", "acc-side-y", "s0", "s1", "s2", "s3", "s4")    # nodes 1 to 7
    assert read.poles[0] == complex(-9.0604e-01, 2.5080e01)
    assert read.frequencies_hz[0] == pytest.approx(25.080 / (2 * np.pi), rel=1e-15)
    assert read.damping_ratios[0] == pytest.approx(0.90604 / np.hypot(0.90604, 25.080), rel=1e-15)
    np.testing.assert_array_equal(read.shapes[0, :, 0], [1.3622e-07 + 1.8514e-07j, -1.0507e-08 - 1.2645e-05j,
                                                         7.6630e-07 + 2.6104e-06j, -4.6781e-08 - 1.2152e-05j,
                                                         6.3576e-08 - 1.1018e-07j, 8.1909e-07 + 3.2610e-06j,
                                                         5.2119e-07 + 6.6091e-07j])


def test_the_artemis_suite_layout(model, tmp_path):
    """HEAD acoustics ArtemiS SUITE 17.5's export (layout seen in permas4edu
    ema/examples/015/mode_shapes.uff): header lines padded to 80 columns, 7-digit node labels,
    ID line 5 'Frequency [Hz]: f  Attenuation [%]: z' with f = |lambda| / 2 pi; read with a
    mapping table as the command line takes it, a sensor mounted along -Z."""
    path = DATA / "artemis_suite_layout_modes.uff"
    text = path.read_text("utf-8")
    stated = [(float(f), float(z) / 100) for f, z in re.findall(r"Frequency \[Hz\]: (\S+)\s+Attenuation \[%\]: (\S+)",
                                                                 text)]
    mapping = tmp_path / "nodes.csv"
    mapping.write_text("name,node,direction\ns0,3000105,1\ns1,3000153,-3\ns2,3000201,2\n")
    read = rdm.read_uff_modes(path, model, mapping)
    assert len(stated) == 2 and read.outputs == ("s0", "s1", "s2")
    np.testing.assert_allclose(read.damping_ratios, [z for _, z in stated], rtol=5e-4)     # 4 decimals stated
    np.testing.assert_allclose(read.frequencies_hz, [f * np.sqrt(1 - z * z) for f, z in stated], rtol=1e-7)
    # s0: node 3000105's X; s1: minus node 3000153's Z; s2: node 3000201's Y (complex pairs 1, 3, 2)
    np.testing.assert_array_equal(read.shapes[:, :, 0], [[0.5 + 0.01j, -0.1 + 0.02j, -0.4 + 0.02j],
                                                         [-0.1 + 0.002j, -0.25 - 0.01j, 0.05]])


def test_a_measured_mode_the_sensors_do_not_see_is_paired_by_frequency(model):
    """Mode 2 of the ARTeMIS-layout file is zero at nodes 3 (Y) and 4: its MAC is 0/0, reported
    nan with a warning (scipy's assignment refused the nan before)."""
    channels = ChannelMap({(3, 2): ("s1", 1.0), (4, 1): ("s0", 1.0)}, {})
    read = rdm.read_uff_modes(DATA / "artemis_layout_modes.uff", model, channels)
    with pytest.warns(UserWarning, match=r"measured mode 2 is zero at every sensor \(s1, s0\): paired by frequency"):
        table = rdm.correlate_modes(model, read)
    assert list(table["measured_mode"]) == [1, 2]
    assert np.isfinite(table["mac"][0]) and np.isnan(table["mac"][1])


def test_pyuffs_record10_file_with_touching_fields(model):
    """pyuff's 'uff55 sample_test record10.uff' (MIT, tests/data/uff/README.md): an OMA export
    whose E13.6 fields touch (``4.111111E+03-3.111111E+03``) and whose ID line 5 is I-DEAS Test's
    4I10; values from its text."""
    channels = ChannelMap({(111111, 2): ("acc-top-z", 1.0), (60101, -3): ("acc-side-y", 1.0)}, {})
    read = rdm.read_uff_modes(DATA / "pyuff_uff55_record10.uff", model, channels)
    assert read.poles[0] == complex(-1.111111e-01, 4.111111e01)
    assert read.frequencies_hz[0] == pytest.approx(4.111111e01 / (2 * np.pi), rel=1e-15)
    np.testing.assert_array_equal(read.shapes[0, :, 0], [1.111111e-01 + 9.111111e-02j, 4.111111e-02 + 1.111111e-02j])


def test_mode_shapes_given_as_frfs_say_where_they_are_read(model):
    with pytest.raises(InputError, match=r"no dataset 58/58b \(FRF\) in the file; datasets found: 55 \(data at "
                                         r"nodes\) \(mode shapes: modes --measured, rdm.read_uff_modes\)"):
        rdm.read_measured(DATA / "artemis_layout_modes.uff", model)


def test_a_sensor_mapped_to_direction_0_reads_no_component(model):
    """Direction 0 (a channel without direction, which FRF files use) names no value of a node:
    the sensor is not measured (index -1 would have read its last value, RZ or Z)."""
    channels = ChannelMap({(1, 0): ("acc-top-z", 1.0), (2, 1): ("s0", 1.0), (3, 1): ("s1", 1.0)}, {})
    read = rdm.read_uff_modes(DATA / "artemis_layout_modes.uff", model, channels)
    assert read.outputs == ("s0", "s1")
