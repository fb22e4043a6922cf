"""Universal Files written by other tools (tests/data/uff, see its README): read to the values
pyuff reads; nodes placed through their coordinate systems and units; misfits refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap
from rotordyn_modal.io.measured import read_measured
from rotordyn_modal.io.uff import (place_channels, read_uff_info, read_uff_nodes, read_uff_time_records,
                                   write_uff58)

DATA = Path(__file__).resolve().parent / "data" / "uff"
EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
TESTLAB = DATA / "testlab_151_164_18_15_82.uff"
HOUSING = DATA / "heat_engine_housing.uff"


def _pyuff_sets(path, kind):
    uff = pyuff.UFF(str(path))
    types = list(uff.get_set_types())
    return [uff.read_sets(k) for k, t in enumerate(types) if t == kind]


def test_header_and_units():
    info = read_uff_info(TESTLAB)
    assert info["program"] == "LMS Test.Lab Rev project-15A" and info["model_name"] == "AME_Test"
    assert info["units"].is_si and info["datasets"] == [151, 164, 18, 15, 82, 82, 82]
    housing = read_uff_info(HOUSING)["units"]
    assert (housing.length, housing.force) == (1000.0, 1000.0) and not housing.is_si


def test_testlab_nodes_and_their_displacement_systems():
    nodes = read_uff_nodes(TESTLAB)
    raw, = _pyuff_sets(TESTLAB, 15)
    np.testing.assert_array_equal(nodes.numbers, np.asarray(raw["node_nums"]).astype(int))
    # defined in the global system (def_cs 0) and SI: the coordinates are pyuff's
    np.testing.assert_array_equal(nodes.coordinates, np.column_stack([raw["x"], raw["y"], raw["z"]]))
    systems, = _pyuff_sets(TESTLAB, 18)
    for k, number in enumerate(nodes.numbers):
        axes = nodes.axes[k]
        np.testing.assert_allclose(axes @ axes.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
        cs = list(np.asarray(systems["cs_num"]).astype(int)).index(int(raw["disp_cs"][k]))
        origin = systems["ref_o"][cs]
        x_dir = systems["x_point"][cs] - origin
        np.testing.assert_allclose(nodes.direction(number, 1), x_dir / np.linalg.norm(x_dir), atol=1e-12)
        # the system's x-z point lies in its x-z plane, on the +z side
        in_xz = systems["xz_point"][cs] - origin
        assert abs(np.dot(in_xz, axes[1])) < 1e-12 and np.dot(in_xz, axes[2]) > 0
    # node 1's system turns x to -X: its +Z points down
    np.testing.assert_allclose(nodes.direction(1, 3), [0.0, 0.0, -1.0], atol=1e-7)


def test_millimetre_nodes_are_converted_to_metres():
    nodes = read_uff_nodes(HOUSING)
    raw, = _pyuff_sets(HOUSING, 2411)
    np.testing.assert_allclose(nodes.coordinates, np.column_stack([raw["x"], raw["y"], raw["z"]]) / 1000.0,
                               rtol=1e-15)
    assert list(nodes.to_dataframe().columns) == ["node", "x", "y", "z"]


def test_nodes_place_the_sensors():
    model = rdm.load_model(EXAMPLE)
    nodes = read_uff_nodes(TESTLAB)
    mapping = ChannelMap({(7, 3): ("acc-top-z", 1.0), (12, 1): ("acc-side-y", -1.0)},
                         {(20, 2): ("hammer-z", 1.0)})
    placed = place_channels(model, nodes, mapping)
    top, side = placed.sensors
    np.testing.assert_allclose(top.position, nodes.position(7))
    np.testing.assert_allclose(top.direction, nodes.direction(7, 3), atol=1e-12)
    np.testing.assert_allclose(side.direction, -nodes.direction(12, 1), atol=1e-12)
    np.testing.assert_allclose(placed.excitations[0].position, nodes.position(20))
    np.testing.assert_allclose(placed.excitations[1].position, model.excitations[1].position)
    with pytest.raises(InputError, match="node 99 is not in the file's node table"):
        nodes.position(99)


def test_time_record_from_catman_reads_as_pyuff_does():
    path = DATA / "time-history-not-all-columns-filled.uff"
    records = read_uff_time_records(path)
    raw, = _pyuff_sets(path, 58)
    assert records.channels == ("0:+0",) and records.quantities == ("acceleration",)
    assert records.sampling_rate_hz == pytest.approx(1 / raw["abscissa_inc"], rel=1e-12)
    np.testing.assert_array_equal(records.signals[0, 0], raw["data"])


@pytest.mark.parametrize("name,reader,message", [
    ("non_ascii_header.uff", "time", "no time record (dataset 58, function type 1) in the file; "
                                     "dataset 58 function types found: [4]"),
    ("testlab_151_164_18_15_82.uff", "frf", "no dataset 58/58b (FRF) in the file; datasets found: 15 (nodes), 18 (coordinate systems), "
     "82 (trace lines), 151 (header), 164 (units)"),
    ("time-history-not-all-columns-filled.uff", "nodes", "no node coordinates (dataset 15 or 2411) in the file; "
                                                         "datasets found: 58 (function data)"),
])
def test_files_that_do_not_fit_are_refused(name, reader, message):
    model = rdm.load_model(EXAMPLE)
    read = {"time": read_uff_time_records, "nodes": read_uff_nodes,
            "frf": lambda p: read_measured(p, model)}[reader]
    with pytest.raises(InputError) as info:
        read(DATA / name)
    assert name in str(info.value) and message in str(info.value)


def _write(path, sets):
    open(path, "w").close()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")


def test_frfs_whose_unit_labels_contradict_dataset_164_are_refused(tmp_path):
    """Labels m/s^2 and N (factors 1) in a file whose 164 says mm and mN (m/s^2 would be 1/1000):
    which one holds cannot be told."""
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, 0.0, np.linspace(1, 40, 40), quantity="accelerance")
    path = tmp_path / "mm.uff"
    write_uff58([res], path, rdm.io.measured.default_mapping(model))
    sets = pyuff.UFF(str(path)).read_sets()
    _write(path, [pyuff.prepare_164(units_code=5, units_description="mm (milli-newton)", temp_mode=2,
                                    length=1000.0, force=1000.0, temp=1.0, temp_offset=273.15)] + sets)
    with pytest.raises(InputError, match="ordinate unit 'm/s\\^2' \\(factor 1 to SI\\) contradicts the dataset 164 "
                                         "units 'mm \\(milli-newton\\)'.*cannot tell which is right"):
        read_measured(path, model)


def test_accelerations_in_g_are_converted_with_standard_gravity():
    """pyuff's binary8byte.uff: a 5 Hz sine in g (ordinate type 12, label 'g'), in m/s^2 x 9.80665."""
    path = DATA / "binary8byte.uff"
    records = read_uff_time_records(path)
    raw, = _pyuff_sets(path, 58)
    assert raw["ordinate_axis_units_lab"] == "g" and records.quantities == ("acceleration",)
    np.testing.assert_array_equal(records.signals[0, 0], raw["data"] * 9.80665)
    assert records.sampling_rate_hz == pytest.approx(1 / raw["abscissa_inc"], rel=1e-12)


def test_the_real_frf_file_is_read_by_its_unit_label(tmp_path):
    """pyuff's non_ascii_header.uff: an H1 of ordinate type 1 (general), unit '(1/N)*(m/s²)' written in
    Latin-1 (pyuff decodes the ² as U+FFFD), node and direction 0: an accelerance in SI units, read
    through a mapping of node 0 direction 0 (response and reference alike), also by `frf --measured`."""
    from rotordyn_modal.cli.main import main

    path = DATA / "non_ascii_header.uff"
    raw, = _pyuff_sets(path, 58)
    assert raw["ordinate_spec_data_type"] == 1 and raw["ordinate_axis_units_lab"] == "(1/N)*(m/s\ufffd)"
    table = tmp_path / "map.csv"
    table.write_text("name,node,direction\nacc-top-z,0,0\nhammer-z,0,0\n")
    model = rdm.load_model(EXAMPLE)
    res, = read_measured(path, model, table)
    assert res.quantity == "accelerance" and res.outputs == ("acc-top-z",) and res.inputs == ("hammer-z",)
    np.testing.assert_array_equal(res.H[0, 0], raw["data"])
    np.testing.assert_array_equal(res.frequencies_hz, raw["x"])
    code = main(["frf", str(EXAMPLE), "--speed", "0", "--freqs", "0.2:1:5", "--measured", str(path), "--mapping",
                 str(table), "--quantity", "accelerance", "--input", "hammer-z", "--output", "acc-top-z",
                 "--quiet", "--out", str(tmp_path / "frf.csv")])
    assert code == 0 and (tmp_path / "frf.csv").exists()


def test_a_channel_repeated_in_a_four_channel_recording():
    """An excerpt of pyuff's MPSTD file: four accelerations Dof1..Dof4, the fourth labelled node 1 +Z
    like the first. Read as one record of four channels (the repeat named 1:+3#2, with a warning);
    with a mapping the repeat cannot be named: refused."""
    path = DATA / "mps_4_channels_excerpt.uff"
    raw = _pyuff_sets(path, 58)
    assert [(s["rsp_node"], s["rsp_dir"]) for s in raw] == [(1, 3), (2, 3), (3, 3), (1, 3)]
    with pytest.warns(UserWarning, match=r"node 1 direction \+3 is given by the time records 1 \('1\+Z', 'MPS set1 "
                                         r"Dof1'\) and 4 \('1\+Z', 'MPS set1 Dof4'\) of one recording of 4 channels"):
        records = read_uff_time_records(path)
    assert records.channels == ("1:+3", "2:+3", "3:+3", "1:+3#2") and records.signals.shape == (1, 4, 64)
    np.testing.assert_array_equal(records.signals[0], np.stack([s["data"] for s in raw]))
    assert records.sampling_rate_hz == pytest.approx(3200.0, rel=1e-12)
    mapping = ChannelMap({(1, 3): ("acc-top-z", 1.0), (2, 3): ("acc-side-y", 1.0)}, {})
    with pytest.raises(InputError, match="the mapping cannot tell which is its channel"):
        read_uff_time_records(path, mapping)


@pytest.mark.parametrize("code", [15, 21])
def test_pressure_records_are_read_in_pascal(tmp_path, code):
    """pyuff's dataset_milestone_in_header.uff: a microphone, data type 15 (pressure) in Pa; the same
    file as data type 21 (sound pressure, as pyuff's Sample_UFF58 files)."""
    path = tmp_path / "mic.uff"
    text = (DATA / "dataset_milestone_in_header.uff").read_text()
    record_9 = "    0    0    0 Sound Pressure"
    path.write_text(text.replace(f"        15{record_9}", f"        {code}{record_9}"))
    raw, = _pyuff_sets(DATA / "dataset_milestone_in_header.uff", 58)
    records = read_uff_time_records(path)
    assert records.quantities == ("pressure",) and records.channels == ("1:+1",)
    np.testing.assert_array_equal(records.signals[0, 0], raw["data"])
    figure = records.plot()
    assert [ax.get_ylabel() for ax in figure.axes] == ["pressure [Pa]"]


def test_hits_of_a_mapped_hammer_test(tmp_path):
    """Three hits, each a force and two accelerations (repeated channels are successive records)."""
    rng = np.random.default_rng(0)
    data = rng.normal(size=(3, 3, 64))
    channels = [(101, 3, 13, "N"), (1, 3, 12, "m/s^2"), (2, 2, 12, "m/s^2")]
    sets = [pyuff.prepare_58(binary=0, func_type=1, rsp_node=node, rsp_dir=code, ref_node=0, ref_dir=0,
                             ordinate_spec_data_type=kind, ordinate_axis_units_lab=label, orddenom_spec_data_type=0,
                             abscissa_spec_data_type=17, data=data[h, c], x=np.arange(64) / 512.0,
                             abscissa_spacing=1, abscissa_inc=1 / 512.0, abscissa_min=0.0)
            for h in range(3) for c, (node, code, kind, label) in enumerate(channels)]
    _write(tmp_path / "hits.uff", sets)
    mapping = ChannelMap({(1, 3): ("acc-top-z", 1.0), (2, 2): ("acc-side-y", -1.0)}, {(101, 3): ("hammer-z", 1.0)})
    records = read_uff_time_records(tmp_path / "hits.uff", mapping, speed=rdm.rpm(1200))
    assert records.channels == ("hammer-z", "acc-top-z", "acc-side-y")
    assert records.quantities == ("force", "acceleration", "acceleration")
    # the ASCII header holds the increment to 6 digits (E13.5)
    assert records.sampling_rate_hz == pytest.approx(512.0, rel=1e-5) and records.speed == pytest.approx(rdm.rpm(1200))
    expected = data * np.array([1.0, 1.0, -1.0])[None, :, None]
    np.testing.assert_allclose(records.signals, expected, rtol=1e-10)     # ASCII: 12+ digits
    with pytest.raises(InputError, match="force node 101 direction 3 is not in the mapping table"):
        read_uff_time_records(tmp_path / "hits.uff", ChannelMap(mapping.outputs, {}))


def test_nodes_defined_in_local_and_nested_coordinate_systems(tmp_path):
    """Dataset 18 defines a system by its origin, a point on its +x axis and a point in its x-z
    plane (+z side), all in its parent system. System 2 sits at (1, 2, 3) m, turned so that its
    x, y, z are the global y, z, x; system 3 is defined inside system 2, 0.5 m along its x and
    turned 90 degrees about its z. A node's global position is the origin plus its local
    coordinates along the system's axes, worked out here by hand."""
    sets = [pyuff.prepare_18(cs_num=[2, 3], cs_type=[0, 0], ref_cs_num=[0, 2], color=[1, 1], method=[1, 1],
                             cs_name=["turned", "nested"],
                             ref_o=[[1.0, 2.0, 3.0], [0.5, 0.0, 0.0]],
                             x_point=[[1.0, 3.0, 3.0], [0.5, 1.0, 0.0]],            # +x: global +Y; nested: local +y
                             xz_point=[[2.0, 2.0, 3.0], [0.5, 0.0, 1.0]]),           # +z: global +X; nested: local +z
            pyuff.prepare_15(node_nums=[1, 2, 3], def_cs=[0, 2, 3], disp_cs=[0, 2, 3], color=[1, 1, 1],
                             x=[0.1, 0.1, 0.1], y=[0.2, 0.2, 0.2], z=[0.3, 0.3, 0.3])]
    _write(tmp_path / "systems.uff", sets)
    nodes = read_uff_nodes(tmp_path / "systems.uff")
    turned = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])        # rows: its x, y, z in global
    # nested: x along system 2's y (global Z), y along system 2's -x (global -Y), z along system 2's z (global X)
    nested = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])
    origin3 = np.array([1.0, 2.0, 3.0]) + 0.5 * turned[0]
    local = np.array([0.1, 0.2, 0.3])
    expected = [local, np.array([1.0, 2.0, 3.0]) + local @ turned, origin3 + local @ nested]
    np.testing.assert_allclose(nodes.coordinates, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nodes.axes[1], turned, atol=1e-12)
    np.testing.assert_allclose(nodes.axes[2], nested, atol=1e-12)


def test_a_file_pyuff_prints_while_reading_is_read_without_a_word(capsys):
    """pyuff's groups_test.uff: pyuff prints every dataset 2467 (groups) to standard output as it
    reads; the terminal must show only what rotordyn_modal says."""
    path = DATA / "groups_test.uff"
    nodes = read_uff_nodes(path)
    raw, = _pyuff_sets(path, 2411)
    capsys.readouterr()
    np.testing.assert_array_equal(nodes.numbers, np.asarray(raw["node_nums"]).astype(int))
    assert read_uff_info(path)["datasets"] == [164, 2420, 2411, 2412, 2467]
    with pytest.raises(InputError, match="no time record"):
        read_uff_time_records(path)
    assert capsys.readouterr().out == ""
