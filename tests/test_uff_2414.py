"""Mode shapes as UFF dataset 2414 (analysis data at nodes, as FE programs write results) read by
``rdm.read_uff_modes`` / ``modes --measured``; what a 2414 set cannot mean refused in one line.

Truth from outside the reader: files written by pyuff's own 2414 writer from known numbers and
from the model's eigenvalues and shapes, and two excerpts of real files of pyuff's test data
(PERMAS normal modes, NX complex-stored normal modes; tests/data/uff/README.md), whose values
pyuff itself reads."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import pyuff
from test_uff_mode_shapes import _axis, model, model_modes  # noqa: F401  (fixtures)

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "uff"


def _set_2414(label, analysis, data_type, per_node, nodes, values, record10=(), record12=(), record13=(),
              result=8, location=1, character=None):
    """One dataset 2414 for pyuff's writer (its general layout: records 10 to 13 by field, each
    node's values on one line)."""
    dataset = pyuff.prepare_2414(analysis_dataset_label=label, analysis_dataset_name=f"set {label}",
                                 dataset_location=location, id1="NONE", id2="NONE", id3="NONE", id4="NONE",
                                 id5="NONE", model_type=1, analysis_type=analysis,
                                 data_characteristic={3: 2, 6: 3}.get(per_node, 1) if character is None else character,
                                 result_type=result, data_type=data_type,
                                 number_of_data_values_for_the_data_component=per_node,
                                 node_nums=np.asarray(nodes, int))
    dataset.update({f"record10_field{k + 1}": v for k, v in enumerate(record10)})
    dataset.update({f"record12_field{k + 1}": float(v) for k, v in enumerate(record12)})
    dataset.update({f"record13_field{k + 1}": float(v) for k, v in enumerate(record13)})
    dataset["data_at_node"] = [np.asarray(v, float) for v in values]
    return dataset


def _write(path, sets):
    uff = pyuff.UFF(str(path))
    for dataset in sets:
        uff.write_sets(dataset, "add")
    return path


def _normal_modes(nodes, values, modes):
    """Normal modes (analysis type 2): record 10 field 6 the mode number, record 12 fields 2, 4, 5
    the frequency [Hz], modal mass and viscous damping ratio."""
    return [_set_2414(n, 2, 2, values.shape[2], nodes, values[n - 1], record10=(0, 0, 1, 0, 0, n),
                      record12=(0.0, f, 0.0, 1.0, zeta, 0.0)) for n, (f, zeta) in enumerate(modes, start=1)]


def test_normal_modes_written_by_pyuff_read_back(model, tmp_path):
    """Three real modes of 3 values a node at nodes 11, 12, 13, frequencies and damping ratios of
    6 digits (pyuff writes %.5e): read back exactly; a sensor mapped to -2 reads minus Y."""
    rng = np.random.default_rng(3)
    values = np.round(rng.normal(size=(3, 3, 3)), 5)        # mode, node, component (6 digits)
    modes = [(47.25, 0.0125), (12.5, 0.02), (130.0, 0.0)]
    path = _write(tmp_path / "normal.uff", _normal_modes([11, 12, 13], values, modes))
    channels = ChannelMap({(11, 3): ("acc-top-z", 1.0), (12, -2): ("acc-side-y", 1.0), (13, 1): ("s0", -1.0)}, {})
    read = rdm.read_uff_modes(path, model, channels)
    assert read.method == "uff-2414" and read.outputs == ("acc-top-z", "acc-side-y", "s0")
    np.testing.assert_array_equal(read.frequencies_hz, [12.5, 47.25, 130.0])        # sorted by frequency
    np.testing.assert_array_equal(read.damping_ratios, [0.02, 0.0125, 0.0])
    order = [1, 0, 2]
    expected = np.stack([values[order, 0, 2], -values[order, 1, 1], -values[order, 2, 0]], axis=1)
    np.testing.assert_allclose(read.shapes[:, :, 0].real, expected, rtol=1e-12, atol=0)
    assert not read.shapes.imag.any()


def test_complex_modes_written_by_pyuff_pair_with_the_model_by_mac_1(model, model_modes, tmp_path, capsys):
    """The model's own eigenvalues and shapes at its 10 sensors as 2414 complex eigenvalue sets
    (analysis type 3, data type 5; the eigenvalue in record 13 fields 1 and 2, rad/s): read back to
    pyuff's 6 digits, paired one to one with MAC 1; the same on the command line."""
    eigenvalues, shapes = model_modes
    nodes = np.arange(1, len(model.sensors) + 1)
    sets = []
    for n, (lam, shape) in enumerate(zip(eigenvalues, shapes), start=1):
        values = np.zeros((len(nodes), 6))
        for k, sensor in enumerate(model.sensors):
            values[k, 2 * _axis(sensor):2 * _axis(sensor) + 2] = shape[k].real, shape[k].imag
        sets.append(_set_2414(n, 3, 5, 3, nodes, values, record10=(0, 0, 1, 0, 0, n),
                              record13=(lam.real, lam.imag, 0.0, 0.0, 0.0, 0.0)))
    path = _write(tmp_path / "complex.uff", sets)
    read = rdm.read_uff_modes(path, model)
    assert read.outputs == tuple(s.name for s in model.sensors)
    np.testing.assert_allclose(read.poles, eigenvalues, rtol=1e-5)
    np.testing.assert_allclose(read.frequencies_hz, eigenvalues.imag / (2 * np.pi), rtol=1e-5)
    scale = np.abs(shapes).max(axis=1, keepdims=True)
    assert np.all(np.abs(read.shapes[:, :, 0] - shapes) <= 1e-5 * scale)
    table = rdm.correlate_modes(model, read)
    assert list(table["model_mode"]) == list(table["measured_mode"]) == list(range(1, len(eigenvalues) + 1))
    assert (table["mac"] > 1 - 1e-8).all()
    model_file = tmp_path / "machine.toml"
    rdm.save_model(model, model_file)
    assert main(["modes", str(model_file), "--measured", str(path), "--out", str(tmp_path / "pairs.csv")]) == 0
    assert f"{len(eigenvalues)} modes (dataset 2414) at {len(model.sensors)} sensors" in capsys.readouterr().err


def _pyuff_sets(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [s for s in pyuff.UFF(str(path)).read_sets() if s["type"] == 2414]


def test_permas_normal_modes_read_as_pyuff_reads_them(model):
    """PERMAS 18's 2414 normal modes (excerpt of pyuff's '2411 and 2414.uff': 10 modes, nodes 1 to
    7, 6 real values a node): frequencies from record 12 field 2 and values as pyuff reads them;
    sensors at node 1 +Z, node 2 -X, node 3 RY."""
    path = DATA / "permas_2414_modes_excerpt.uff"
    channels = ChannelMap({(1, 3): ("acc-top-z", 1.0), (2, -1): ("acc-side-y", 1.0), (3, 5): ("s0", 1.0)}, {})
    read = rdm.read_uff_modes(path, model, channels)
    sets = _pyuff_sets(path)
    assert len(sets) == 10 and read.method == "uff-2414"
    np.testing.assert_array_equal(read.frequencies_hz, [s["record12_field2"] for s in sets])
    assert read.frequencies_hz[0] == 0.956363 and read.frequencies_hz[-1] == 25.7643   # the file's text
    assert np.all(read.damping_ratios == 0.0)
    expected = [[s["data_at_node"][0][2], -s["data_at_node"][1][0], s["data_at_node"][2][4]] for s in sets]
    np.testing.assert_array_equal(read.shapes[:, :, 0], expected)


def test_nx_modes_stored_complex_read_as_pyuff_reads_them(model):
    """NX Advanced Simulation's 2414 normal modes stored as complex single precision (data type 5,
    3 values a node: X re, X im, Y re, ...; excerpt of pyuff's 'NX simulation output.uff', 6 modes,
    7 nodes): node 3992's Y and node 9581's X as pyuff reads them, real and imaginary parts."""
    path = DATA / "nx_2414_complex_modes_excerpt.uff"
    channels = ChannelMap({(3992, 2): ("acc-top-z", 1.0), (9581, 1): ("acc-side-y", 1.0)}, {})
    read = rdm.read_uff_modes(path, model, channels)
    sets = _pyuff_sets(path)
    np.testing.assert_array_equal(read.frequencies_hz, [s["record12_field2"] for s in sets])
    assert read.frequencies_hz[0] == 23383.2
    expected = [[complex(*s["data_at_node"][0][2:4]), complex(*s["data_at_node"][1][0:2])] for s in sets]
    np.testing.assert_array_equal(read.shapes[:, :, 0], expected)


def _frequency_response(path):
    """A 2414 frequency response set (analysis type 5) as pyuff's own writer lays it out (its
    docstring's example): one frequency's complex displacements at three nodes."""
    dataset = pyuff.prepare_2414(
        analysis_dataset_label=1, analysis_dataset_name="Solid displacement at 1.00000e+02 Hz", dataset_location=1,
        id1="FEMTown to UNV output driver", id2="Analysis", id3="Solid displacement at 1.00000e+02 Hz",
        id4="LoadCase 1", id5="none", model_type=0, analysis_type=5, data_characteristic=2, result_type=8,
        data_type=5, number_of_data_values_for_the_data_component=3, design_set_id=1, iteration_number=0,
        solution_set_id=1, boundary_condition=0, load_set=1, mode_number=0, time_step_number=0, frequency_number=0,
        creation_option=1, number_retained=1, time=0.0, frequency=100.0, eigenvalue=100.0, modal_mass=0.0,
        viscous_damping=0.0, hysteretic_damping=0.0, real_part_eigenvalue=0.0, imaginary_part_eigenvalue=0.0,
        real_part_of_modal_A_or_modal_mass=0.0, imaginary_part_of_modal_A_or_modal_mass=0.0,
        real_part_of_modal_B_or_modal_mass=0.0, imaginary_part_of_modal_B_or_modal_mass=0.0,
        node_nums=np.array([1, 2, 3]), x=np.array([2.8e-09 + 1.7e-09j, 3.1e-09 + 1.2e-09j, 3.3e-09 + 6.1e-10j]),
        y=np.array([-7.1e-10 + 6.5e-10j, -5.0e-10 + 8.1e-10j, -2.5e-10 + 9.1e-10j]),
        z=np.array([4.3e-10 + 2.5e-10j, 4.7e-10 + 1.7e-10j, 4.9e-10 + 8.7e-11j]))
    return _write(path, [dataset])


def test_a_frequency_response_2414_is_no_frf_and_no_mode(model, tmp_path, capsys):
    """One frequency's response at nodes to a load case whose force the file does not give: as
    modes and as FRFs it is refused in one line naming it (exit 2 on the command line)."""
    path = _frequency_response(tmp_path / "response.uff")
    with pytest.raises(InputError, match=r"no dataset 55 or 2414 mode shapes \(data at nodes\) in the file; its "
                                         r"dataset 2414 holds no mode shape at nodes: 1 set of analysis type 5 "
                                         r"\(frequency response\) displacement, data at nodes"):
        rdm.read_uff_modes(path, model)
    with pytest.raises(InputError, match=r"no dataset 58/58b \(FRF\) in the file; .*2414 \(analysis results\): "
                                         r"dataset 2414: 1 set of analysis type 5 \(frequency response\) "
                                         r"displacement, data at nodes; a frequency response set is one frequency's "
                                         r"response at the nodes to a load case whose force the file does not give: "
                                         r"no FRF \(export FRFs as dataset 58\)"):
        rdm.read_measured(path, model)
    model_file = tmp_path / "machine.toml"
    rdm.save_model(model, model_file)
    assert main(["frf", str(model_file), "--measured", str(path), "--freqs", "1:100:10"]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1 and "load case whose force the file does not give" in err[0]


def test_a_file_of_2414_modes_given_as_frfs_says_where_they_are_read(model):
    with pytest.raises(InputError, match=r"2414 \(analysis results\): 10 dataset 2414 mode shapes \(read by modes "
                                         r"--measured, rdm.read_uff_modes\)"):
        rdm.read_measured(DATA / "permas_2414_modes_excerpt.uff", model)


def test_a_static_temperature_2414_is_no_mode(model):
    """VKI's heat_engine_housing.uff: a static temperature at nodes (model type 2, scalar)."""
    with pytest.raises(InputError, match=r"its dataset 2414 holds no mode shape at nodes: 1 set of analysis type 1 "
                                         r"\(static\) temperature, data at nodes; datasets found: 151"):
        rdm.read_uff_modes(DATA / "heat_engine_housing.uff", model)


def test_an_element_result_of_ufffiles_jl_is_no_mode(model):
    """UFFFiles.jl's dataset2414_elt.unv (MIT, tests/data/uff/README.md): a thickness on 20
    elements (location 2, result type 94, an unknown scalar), refused as modes and as FRFs naming it."""
    path = DATA / "ufffiles_2414_elements.unv"
    named = r"1 set of analysis type 1 \(static\) unknown scalar, data on elements"
    with pytest.raises(InputError, match=r"its dataset 2414 holds no mode shape at nodes: " + named):
        rdm.read_uff_modes(path, model)
    with pytest.raises(InputError, match=r"no dataset 58/58b \(FRF\) in the file; .*: dataset 2414: " + named + "$"):
        rdm.read_measured(path, model)


def test_other_2414_results_beside_modes_are_passed_over_with_one_warning(model, tmp_path):
    """An FE export of modes and, per mode, element strain energies: the modes read, the others
    named in one warning."""
    values = np.ones((1, 2, 3))
    sets = _normal_modes([1, 2], values, [(10.0, 0.01)])
    sets += [_set_2414(2, 2, 2, 1, [1, 2], [[0.5], [0.25]], result=7, location=2, character=1)]
    sets[-1]["element_nums"] = np.array([1, 2])
    sets[-1]["data_at_element"] = sets[-1].pop("data_at_node")
    path = _write(tmp_path / "mixed.uff", sets)
    with pytest.warns(UserWarning, match=r"read the 1 dataset 2414 mode shapes and passed over 1 other dataset 2414 "
                                         r"sets: 1 set of analysis type 2 \(normal mode\) strain energy, data on "
                                         r"elements"):
        read = rdm.read_uff_modes(path, model)
    np.testing.assert_array_equal(read.frequencies_hz, [10.0])


def test_rigid_body_modes_of_an_fe_model_are_passed_over(model, tmp_path):
    """A free-free FE model's rigid-body modes (0 Hz, or round-off below) say no oscillation: passed
    over beside the elastic modes, named in the refusal of a file of none but them; a data
    characteristic 0 with an unknown 3-value vector (result type 95) is read as the shape."""
    values = np.arange(1.0, 13.0).reshape(2, 2, 3)
    sets = _normal_modes([1, 2], values, [(0.0, 0.0), (-1.5e-4, 0.0)])
    alone = _write(tmp_path / "rigid.uff", sets)
    with pytest.raises(InputError, match=r"2414 holds no mode shape at nodes: 1 set of analysis type 2 \(normal mode\) "
                                         r"of frequency 0 Hz \(a rigid-body mode\); 1 set of analysis type 2 "
                                         r"\(normal mode\) of frequency -0.00015 Hz \(a rigid-body mode\)"):
        rdm.read_uff_modes(alone, model)
    elastic = _set_2414(3, 2, 2, 3, [1, 2], [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], record10=(0, 0, 1, 0, 0, 3),
                        record12=(0.0, 250.0, 0.0, 1.0, 0.0, 0.0), result=95, character=0)
    path = _write(tmp_path / "free.uff", sets + [elastic])
    with pytest.warns(UserWarning, match=r"passed over 2 other dataset 2414 sets: 1 set of analysis type 2 \(normal "
                                         r"mode\) of frequency 0 Hz \(a rigid-body mode\)"):
        read = rdm.read_uff_modes(path, model)
    np.testing.assert_array_equal(read.frequencies_hz, [250.0])
    np.testing.assert_array_equal(read.shapes[0, :, 0], [3.0, 5.0])     # node 1 Z, node 2 Y (default mapping)


def test_modes_as_both_55_and_2414_are_refused(model, tmp_path):
    path = tmp_path / "both.uff"
    path.write_bytes((DATA / "pyuff_uff55_record10.uff").read_bytes()
                     + (DATA / "permas_2414_modes_excerpt.uff").read_bytes())
    with pytest.raises(InputError, match=r"mode shapes as dataset 55 \(1 sets\) and as dataset 2414 \(10 sets\): "
                                         r"whether they are the same modes cannot be told"):
        rdm.read_uff_modes(path, model)


BAD = {
    "NVALDC against the data characteristic": (dict(per_node=4, character=2),
                                               r"record 9: data characteristic 2 with NVALDC 4: expected 2"),
    "integer data": (dict(data_type=1), r"record 9: data type 1: expected 2 or 4 \(real\), 5 or 6 \(complex\)"),
    "a node twice": (dict(nodes=[1, 1]), r"node 1 is given twice in one mode"),
    "values short": (dict(values=[[1.0, 2.0, 3.0], [1.0, 2.0]]), r"record 15 \(the values of node 2\)"),
    "a complex eigenvalue that is real": (dict(analysis=3, record13=(-5.0, 0.0)),
                                          r"dataset 2414 from line 2: record 13: eigenvalue -5 \+ 0i is real"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_2414_mode_that_cannot_be_understood_is_refused_in_one_line(model, tmp_path, case):
    changes, message = BAD[case]
    fields = dict(label=1, analysis=2, data_type=2, per_node=3, nodes=[1, 2], values=[[1.0, 2.0, 3.0]] * 2,
                  record10=(0, 0, 1, 0, 0, 1), record12=(0.0, 10.0, 0.0, 1.0, 0.01, 0.0))
    fields.update(changes)
    path = _write(tmp_path / "bad.uff", [_set_2414(**fields)])
    with pytest.raises(InputError, match=message) as error:
        rdm.read_uff_modes(path, model)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


def test_dataset_55_modes_beside_other_2414_results_are_counted_as_read(model, tmp_path):
    """A file of one dataset 55 mode (pyuff's record-10 example) and one 2414 strain energy on
    elements: the warning counts the dataset 55 mode read, not 0 dataset 2414 ones."""
    energy = _set_2414(2, 2, 2, 1, [1, 2], [[0.5], [0.25]], result=7, location=2, character=1)
    energy["element_nums"] = np.array([1, 2])
    energy["data_at_element"] = energy.pop("data_at_node")
    path = tmp_path / "mixed55.uff"
    path.write_bytes((DATA / "pyuff_uff55_record10.uff").read_bytes()
                     + _write(tmp_path / "energy.uff", [energy]).read_bytes())
    with pytest.warns(UserWarning, match=r"read the 1 dataset 55 mode shapes and passed over 1 other dataset 2414 "
                                         r"sets: 1 set of analysis type 2 \(normal mode\) strain energy"):
        read = rdm.read_uff_modes(path, model, ChannelMap({(60101, 1): ("s0", 1.0)}, {}))
    assert read.method == "uff-55" and len(read.frequencies_hz) == 1


def test_a_2414_hysteretic_damping_warning_names_record_12(model, tmp_path):
    """A 2414 normal mode of hysteretic damping only (record 12 field 6): the warning names record
    12, where the ratio is, not dataset 55's record 8."""
    mode = _set_2414(1, 2, 2, 3, [1, 2], [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], record10=(0, 0, 1, 0, 0, 1),
                     record12=(0.0, 40.0, 0.0, 1.0, 0.0, 0.03))
    path = _write(tmp_path / "hysteretic.uff", [mode])
    with pytest.warns(UserWarning, match=r"record 12 gives a hysteretic damping ratio \(0.03\)") as caught:
        read = rdm.read_uff_modes(path, model)
    assert not any("record 8" in str(w.message) for w in caught)
    assert np.isnan(read.damping_ratios[0])
