"""TDMS records written by another project (tests/data/tdms, see its README), read through npTDMS."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.errors import InputError
from rotordyn_modal.io.tdms import read_tdms_records

nptdms = pytest.importorskip("nptdms")

DATA = Path(__file__).resolve().parent / "data" / "tdms"
GOOD = DATA / "good_tdms_2.tdms"


def test_group_read_as_nptdms_reads_it_with_a_declared_unit():
    records = read_tdms_records(GOOD, group="acceleration", units={"g": ("acceleration", 9.80665)})
    raw = nptdms.TdmsFile.read(str(GOOD))["acceleration"]
    assert records.channels == tuple(c.name for c in raw.channels())
    assert records.quantities == ("acceleration",) * 8 and records.signals.shape == (1, 8, 15000)
    assert records.sampling_rate_hz == pytest.approx(250.0, rel=1e-12)
    for k, channel in enumerate(raw.channels()):
        np.testing.assert_array_equal(records.signals[0, k], np.asarray(channel[:], dtype=float) * 9.80665)


def test_a_group_in_g_is_read_in_m_per_s2_without_a_declaration():
    """The unit string 'g' is the standard acceleration of gravity, 9.80665 m/s^2."""
    records = read_tdms_records(GOOD, group="acceleration")
    raw = nptdms.TdmsFile.read(str(GOOD))["acceleration"]
    assert records.quantities == ("acceleration",) * 8
    for k, channel in enumerate(raw.channels()):
        np.testing.assert_array_equal(records.signals[0, k], np.asarray(channel[:], dtype=float) * 9.80665)


@pytest.mark.parametrize("kwargs,message", [
    ({"group": "ambient"}, "channel 'temperature air' has unit 'C': expected a unit of force, displacement"),
    ({}, "several groups: give group= one of acceleration, ambient"),
    ({"group": "strain"}, "no group 'strain'"),
    ({"group": "acceleration", "channels": ["x"], "units": {"g": ("acceleration", 9.80665)}}, "has no channel x"),
    ({"group": "ambient", "channels": ["wind speed avg", "pressure"], "units": {"hPa": ("force", 1.0)}},
     "sampling intervals [1.0, 60.0] s and lengths [1, 60]"),
])
def test_misfits_refused(kwargs, message):
    with pytest.raises(InputError) as info:
        read_tdms_records(GOOD, **kwargs)
    assert message in str(info.value)


def test_damaged_file_refused():
    with pytest.raises(InputError, match="faulty_tdms_01.tdms: not a readable TDMS file"):
        read_tdms_records(DATA / "faulty_tdms_01.tdms")


def test_missing_nptdms_named_in_the_message(without_module):
    without_module("nptdms")
    with pytest.raises(InputError, match=r"pip install 'rotordyn_modal\[tdms\]'"):
        read_tdms_records(GOOD)


def test_channels_of_one_interval_but_different_lengths_are_refused(tmp_path):
    """One record needs one length: written here with npTDMS, 100 and 90 samples at 1 ms."""
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    path = tmp_path / "lengths.tdms"
    with TdmsWriter(str(path)) as writer:
        writer.write_segment([GroupObject("g")] + [
            ChannelObject("g", name, np.zeros(count), properties={"unit_string": "m/s^2", "wf_increment": 1e-3})
            for name, count in (("a", 100), ("b", 90))])
    with pytest.raises(InputError, match=r"sampling intervals \[0.001\] s and lengths \[90, 100\]"):
        read_tdms_records(path, group="g")
