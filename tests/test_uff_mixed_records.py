"""Time-record files that hold more than time records (issue 27 §4): analysers export their
auto- and cross-spectra, FRFs and coherence beside the time data. The time records are read and
the other dataset 58 sets are skipped with one warning naming their places, function types and
nodes (they used to be skipped without a word); a file without a time record is refused naming
what it holds. The files are written here with pyuff's own writer (as pyuff's PSD sample
``sample_dataset58_psd.uff``: function type 9, abscissa and ordinate data type 0)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import pyuff

from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap
from rotordyn_modal.io.uff import read_uff_time_records

DATA = Path(__file__).resolve().parent / "data" / "uff"
N, DT = 64, 1.0 / 512.0


def _time(node, direction, kind, label, data, func_type=1):
    return pyuff.prepare_58(binary=0, func_type=func_type, rsp_node=node, rsp_dir=direction, ref_node=0, ref_dir=0,
                            ordinate_spec_data_type=kind, ordinate_axis_units_lab=label, orddenom_spec_data_type=0,
                            abscissa_spec_data_type=17, abscissa_axis_units_lab="s", data=np.asarray(data, float),
                            x=np.arange(N) * DT, abscissa_spacing=1, abscissa_inc=DT, abscissa_min=0.0)


def _spectrum(func_type, node, direction, ref_node, ref_dir, data, ordinate=12, denominator=13):
    return pyuff.prepare_58(binary=0, func_type=func_type, rsp_node=node, rsp_dir=direction, ref_node=ref_node,
                            ref_dir=ref_dir, ordinate_spec_data_type=ordinate, orddenom_spec_data_type=denominator,
                            abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz", data=np.asarray(data),
                            x=np.arange(33) * 8.0, abscissa_spacing=1, abscissa_inc=8.0, abscissa_min=0.0)


def _write(path, sets):
    open(path, "w").close()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


@pytest.fixture(scope="module")
def signals():
    return np.random.default_rng(27).normal(size=(2, N))


@pytest.fixture(scope="module")
def analyser_export(tmp_path_factory, signals):
    """A hammer force (node 101 +Z) and an acceleration (node 1 +Z) as time records, datasets 1-2;
    then what the analyser computed from them: two auto-spectra (3, 4), a cross-spectrum (5), the
    FRF (6) and its coherence (7)."""
    rng = np.random.default_rng(1)
    sets = [_time(101, 3, 13, "N", signals[0]), _time(1, 3, 12, "m/s^2", signals[1]),
            _spectrum(2, 101, 3, 101, 3, np.abs(rng.normal(size=33)) + 0j, ordinate=13, denominator=13),
            _spectrum(2, 1, 3, 1, 3, np.abs(rng.normal(size=33)) + 0j, denominator=12),
            _spectrum(3, 1, 3, 101, 3, rng.normal(size=33) + 1j * rng.normal(size=33)),
            _spectrum(4, 1, 3, 101, 3, rng.normal(size=33) + 1j * rng.normal(size=33)),
            _spectrum(6, 1, 3, 101, 3, rng.uniform(size=33), ordinate=0, denominator=0)]
    return _write(tmp_path_factory.mktemp("mixed") / "export.uff", sets)


def test_the_time_records_are_read_and_the_spectra_named_in_one_warning(analyser_export, signals):
    """The two time records are the channels, sample for sample; one warning names the five sets
    skipped by their places in the file, function types and nodes."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        records = read_uff_time_records(analyser_export)
    assert records.channels == ("101:+3", "1:+3") and records.quantities == ("force", "acceleration")
    np.testing.assert_allclose(records.signals[0], signals, rtol=1e-11)     # ASCII: 12 digits
    assert len(caught) == 1, [str(w.message) for w in caught]
    line = str(caught[0].message)
    assert "\n" not in line and str(analyser_export) in line and "read the 2 time records" in line
    assert "skipped 5 dataset 58 sets" in line
    for words in ("function type 2 (auto-spectrum): datasets 3, 4 at 101:+3, 1:+3",
                  "function type 3 (cross-spectrum): dataset 5 at 1:+3 / 101:+3",
                  "function type 4 (FRF): dataset 6 at 1:+3 / 101:+3",
                  "function type 6 (coherence): dataset 7 at 1:+3 / 101:+3"):
        assert words in line, (words, line)


def test_a_mapping_names_the_channels_of_a_mixed_file(analyser_export, signals):
    """The skipped sets' nodes are not looked up in the mapping (the FRF's reference 101 is a
    force node, the auto-spectrum of 1:+3 a response): only the time records are named."""
    mapping = ChannelMap({(1, 3): ("acc-top-z", -1.0)}, {(101, 3): ("hammer-z", 1.0)})
    with pytest.warns(UserWarning, match="skipped 5 dataset 58 sets"):
        records = read_uff_time_records(analyser_export, mapping)
    assert records.channels == ("hammer-z", "acc-top-z")
    np.testing.assert_allclose(records.signals[0, 1], -signals[1], rtol=1e-11)


def test_a_file_of_time_records_alone_reads_without_a_warning(tmp_path, signals):
    path = _write(tmp_path / "time.uff", [_time(101, 3, 13, "N", signals[0]), _time(1, 3, 12, "m/s^2", signals[1])])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        records = read_uff_time_records(path)
    assert records.channels == ("101:+3", "1:+3")


def test_a_general_function_over_time_is_a_time_record(tmp_path, signals):
    """Function type 0 (general or unknown) over an abscissa of data type 17 (time) holds samples
    in time: read as a time record (it was refused as 'no time record')."""
    path = _write(tmp_path / "general.uff", [_time(1, 3, 12, "m/s^2", signals[1], func_type=0)])
    records = read_uff_time_records(path)
    assert records.channels == ("1:+3",) and records.quantities == ("acceleration",)
    np.testing.assert_allclose(records.signals[0, 0], signals[1], rtol=1e-11)
    assert records.sampling_rate_hz == pytest.approx(1.0 / DT, rel=1e-5)


def test_a_file_of_spectra_alone_is_refused_naming_what_it_holds(tmp_path):
    """As pyuff's sample_dataset58_psd.uff: one PSD (function type 9), abscissa data type 0."""
    psd = pyuff.prepare_58(binary=0, func_type=9, rsp_node=0, rsp_dir=0, ref_node=0, ref_dir=0,
                           ordinate_spec_data_type=0, orddenom_spec_data_type=0, abscissa_spec_data_type=0,
                           data=np.linspace(1.0, 2.0, 33), x=np.arange(33) * 8.0, abscissa_spacing=1,
                           abscissa_inc=8.0, abscissa_min=0.0)
    path = _write(tmp_path / "psd.uff", [psd])
    with pytest.raises(InputError) as info:
        read_uff_time_records(path)
    message = str(info.value)
    assert str(path) in message and "no time record (dataset 58, function type 1)" in message
    assert "function type 9 (power spectral density): dataset 1 at 0:+0" in message


def test_a_file_of_no_dataset_58_is_refused_naming_its_datasets():
    path = DATA / "testlab_151_164_18_15_82.uff"
    with pytest.raises(InputError) as info:
        read_uff_time_records(path)
    assert "datasets found: 15 (nodes), 18 (coordinate systems), 82 (trace lines), 151 (header), " \
           "164 (units)" in str(info.value)
