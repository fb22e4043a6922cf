"""Units of UFF 58 sets: unit labels (g, mm/s, lbf, ...) and dataset 164 factors convert to SI; what
cannot be understood is refused. Files are written here with pyuff (records as other tools write
them); the factors are the definitions (g = 9.80665 m/s^2, lbf = 0.45359237 kg x g, inch = 25.4 mm)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap
from rotordyn_modal.io.measured import read_measured
from rotordyn_modal.io.uff import read_uff_time_records
from rotordyn_modal.io.unit_labels import parse_unit

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
G, LBF, INCH = 9.80665, 0.45359237 * 9.80665, 0.0254
FREQS = np.linspace(1.0, 40.0, 40)
DATA = np.sin(np.arange(64) * 0.3) + 0.1


def _write(path, sets):
    open(path, "w").close()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _time_set(kind, label, node=1, direction=3, abscissa_label="s", **extra):
    return pyuff.prepare_58(binary=0, func_type=1, rsp_node=node, rsp_dir=direction, ref_node=0, ref_dir=0,
                            ordinate_spec_data_type=kind, ordinate_axis_units_lab=label, orddenom_spec_data_type=0,
                            abscissa_spec_data_type=17, abscissa_axis_units_lab=abscissa_label, data=DATA,
                            x=np.arange(64) / 512.0, abscissa_spacing=1, abscissa_inc=1 / 512.0, abscissa_min=0.0,
                            **extra)


def _units(length, force):
    return pyuff.prepare_164(units_code=9, units_description="USER_DEFINED", temp_mode=2, length=length,
                             force=force, temp=1.0, temp_offset=273.15)


@pytest.mark.parametrize("kind,label,quantity,factor", [
    (12, "g", "acceleration", G), (12, "G", "acceleration", G), (12, "m/s2", "acceleration", 1.0),
    (12, "mm/s^2", "acceleration", 1e-3), (1, "m/s²", "acceleration", 1.0), (0, "g", "acceleration", G),
    (11, "mm/s", "velocity", 1e-3), (11, "in/s", "velocity", INCH), (8, "um", "displacement", 1e-6),
    (8, "µm", "displacement", 1e-6), (8, "mil", "displacement", 1e-3 * INCH), (13, "lbf", "force", LBF),
    (13, "kN", "force", 1e3), (9, "N", "force", 1.0), (15, "kPa", "pressure", 1e3), (1, "bar", "pressure", 1e5),
])
def test_time_records_are_converted_with_their_unit_label(tmp_path, kind, label, quantity, factor):
    path = _write(tmp_path / "t.uff", [_time_set(kind, label)])
    records = read_uff_time_records(path)
    assert records.quantities == (quantity,)
    np.testing.assert_allclose(records.signals[0, 0], DATA * factor, rtol=1e-11)   # ASCII: 12+ digits


def test_the_time_abscissa_label_gives_the_sampling_rate(tmp_path):
    path = _write(tmp_path / "t.uff", [_time_set(12, "g", abscissa_label="ms")])
    assert read_uff_time_records(path).sampling_rate_hz == pytest.approx(512_000.0, rel=1e-5)


@pytest.mark.parametrize("length,force,kind,factor", [
    (1000.0, 1.0, 12, 1e-3),       # mm/s^2
    (1000.0, 1.0, 8, 1e-3),        # mm
    (1000.0, 1.0, 13, 1.0),        # a force does not scale with length
    (1.0, 1000.0, 13, 1e-3),       # mN
    (1000.0, 1000.0, 15, 1e3),     # mN/mm^2 (F L^-2): 1e-3 N / 1e-6 m^2 = 1000 Pa
])
def test_unlabelled_time_records_take_the_dataset_164_factors(tmp_path, length, force, kind, factor):
    """SI value = file value / (length factor^a x force factor^b), with a, b of dataset 58 Addendum A
    for the record's data type (acceleration L, force F, pressure F L^-2)."""
    path = _write(tmp_path / "t.uff", [_units(length, force), _time_set(kind, "NONE")])
    np.testing.assert_allclose(read_uff_time_records(path).signals[0, 0], DATA * factor, rtol=1e-11)


def test_rotations_take_the_rotational_exponents_of_dataset_164(tmp_path):
    """About an axis (direction 5) an angular acceleration [rad/s^2] does not scale with the length
    unit (Addendum A: exponent 0) while a moment (type 13) scales with length x force."""
    path = _write(tmp_path / "t.uff", [_units(1000.0, 1000.0), _time_set(12, "NONE", direction=5),
                                       _time_set(13, "NONE", node=2, direction=5)])
    records = read_uff_time_records(path)
    np.testing.assert_allclose(records.signals[0], [DATA, DATA * 1e-6], rtol=1e-11)


def _frf_set(h, top_kind=12, top="NONE", bottom_kind=13, bottom="NONE"):
    return pyuff.prepare_58(binary=1, func_type=4, rsp_node=1, rsp_dir=3, ref_node=101, ref_dir=3,
                            ordinate_spec_data_type=top_kind, ordinate_axis_units_lab=top,
                            orddenom_spec_data_type=bottom_kind, orddenom_axis_units_lab=bottom,
                            abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz", data=h, x=FREQS,
                            z_axis_value=0.0)


@pytest.fixture
def model():
    return rdm.load_model(EXAMPLE)


def _h(model):
    return rdm.frf(model, 0.0, FREQS, "hammer-z", "acc-top-z", "accelerance").H[0, 0]


@pytest.mark.parametrize("units,labels,quantity,factor", [
    (None, dict(top="g", bottom="lbf"), "accelerance", G / LBF),
    (None, dict(top="mm/s", top_kind=11, bottom="N"), "mobility", 1e-3),
    (None, dict(top="(1/N)*(m/s²)", top_kind=1, bottom_kind=0), "accelerance", 1.0),
    (None, dict(top="g/N", top_kind=0, bottom_kind=0), "accelerance", G),
    (None, dict(top="m/s^2/N"), "accelerance", 1.0),                               # over type 13, no label
    (None, dict(top="g/lbf", bottom="lbf"), "accelerance", G / LBF),               # the force said twice
    (None, dict(top="um", top_kind=1), "receptance", 1e-6),                       # over the force of type 13
    ((1000.0, 1.0), dict(), "accelerance", 1e-3),                                  # (mm/s^2)/N
    ((1.0, 1000.0), dict(), "accelerance", 1e3),                                   # (m/s^2)/mN
    ((1.0, 1000.0), dict(bottom_kind=0), "accelerance", 1e3),                      # untyped denominator: mN
    ((1000.0, 1.0), dict(top="mm/s^2", bottom="N"), "accelerance", 1e-3),          # labels agreeing with 164
])
def test_frfs_are_converted_with_labels_or_dataset_164(tmp_path, model, units, labels, quantity, factor):
    h = _h(model)
    sets = ([_units(*units)] if units else []) + [_frf_set(h, **labels)]
    path = _write(tmp_path / "frf.uff", sets)
    mapping = ChannelMap({(1, 3): ("acc-top-z", 1.0)}, {(101, 3): ("hammer-z", 1.0)})
    res, = read_measured(path, model, mapping)
    assert res.quantity == quantity
    np.testing.assert_allclose(res.H[0, 0], h * factor, rtol=1e-14)


@pytest.mark.parametrize("kind,label,message", [
    (12, "V", "ordinate unit 'V' is not understood: expected units such as m, mm"),
    (12, "mV/g", "ordinate unit 'mV/g' is not understood"),
    (12, "N", "ordinate data type 12 (acceleration) but unit 'N' is a force: the file contradicts itself"),
    (1, "NONE", "ordinate data type 1 (general) with unit 'NONE': cannot tell what was measured"),
    (1, "g^2/Hz", "ordinate data type 1 (general) with unit 'g^2/Hz': cannot tell what was measured"),
    (2, "Pa", "ordinate data type 2 (stress): expected 8 (displacement)"),
])
def test_time_records_that_cannot_be_understood_are_refused(tmp_path, kind, label, message):
    path = _write(tmp_path / "t.uff", [_time_set(kind, label)])
    with pytest.raises(InputError) as info:
        read_uff_time_records(path)
    assert str(info.value).startswith(f"{path}: time record 1:3: ") and message in str(info.value)


def test_a_time_record_label_contradicting_dataset_164_is_refused(tmp_path):
    path = _write(tmp_path / "t.uff", [_units(1000.0, 1.0), _time_set(12, "g")])
    with pytest.raises(InputError, match="ordinate unit 'g' \\(factor 9.80665 to SI\\) contradicts the dataset 164"):
        read_uff_time_records(path)


def test_a_force_and_a_response_at_one_node_and_direction_are_two_channels(tmp_path):
    """A driving point: the hammer and the accelerometer both at node 1 +Z, three hits."""
    sets = [_time_set(kind, label) for _ in range(3) for kind, label in ((13, "N"), (12, "g"))]
    path = _write(tmp_path / "t.uff", sets)
    records = read_uff_time_records(path)
    assert records.channels == ("1:+3", "1:+3#2") and records.signals.shape == (3, 2, 64)
    mapping = ChannelMap({(1, 3): ("acc-top-z", 1.0)}, {(1, 3): ("hammer-z", 1.0)})
    records = read_uff_time_records(path, mapping)
    assert records.channels == ("hammer-z", "acc-top-z") and records.quantities == ("force", "acceleration")
    np.testing.assert_allclose(records.signals[:, 1], np.tile(DATA * G, (3, 1)), rtol=1e-11)


@pytest.mark.parametrize("label,factor,dimension", [
    ("m/s/s", 1.0, (1, 0, -2)), ("m/s**2", 1.0, (1, 0, -2)), ("m s^-2", 1.0, (1, 0, -2)),
    ("(m/s^2)/N", 1.0, (0, -1, 0)), ("g/lbf", G / LBF, (0, -1, 0)), ("in/s", INCH, (1, 0, -1)),
    ("psi", LBF / INCH ** 2, (-1, 1, -2)), ("Hz", 1.0, (0, 0, -1)),
])
def test_unit_expressions(label, factor, dimension):
    parsed = parse_unit(label)
    assert parsed[1] == dimension and parsed[0] == pytest.approx(factor, rel=1e-15)
    for bad in ("(m/s", "m/", "V", "m/s-2", "", "m^5", "mm^400/mm^400", "(" * 5000 + "m" + ")" * 5000):
        assert parse_unit(bad) is None


def test_channels_told_apart_by_their_entity_names_only(tmp_path):
    """A recorder that numbers no nodes (node 0, direction 0) but names its channels: four sets, one
    record of four channels (not four records of one), the later ones named 0:+0#2.. with a warning;
    the same names twice (two hits) are two records."""
    sets = [_time_set(12, "g", node=0, direction=0, rsp_ent_name=f"Ch{k}") for k in range(1, 5)]
    path = _write(tmp_path / "t.uff", sets)
    with pytest.warns(UserWarning, match=r"node 0 direction \+0 is given by the time records 1 \('Ch1', 'NONE'\)"):
        records = read_uff_time_records(path)
    assert records.channels == ("0:+0", "0:+0#2", "0:+0#3", "0:+0#4") and records.signals.shape == (1, 4, 64)
    hits = _write(tmp_path / "hits.uff", [_time_set(12, "g", rsp_ent_name="acc") for _ in range(2)])
    assert read_uff_time_records(hits).signals.shape == (2, 1, 64)
