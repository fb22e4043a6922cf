"""TDMS files of other tools beyond sdypy_io_tdms's (tests/data/tdms/README.md): an NI InsightCM
condition-monitoring export and an NI DAQmx raw recording, from the nitdms project."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.errors import InputError
from rotordyn_modal.io.tdms import read_tdms_records

nptdms = pytest.importorskip("nptdms")

DATA = Path(__file__).resolve().parent / "data" / "tdms"
PUMP = DATA / "insightcm_cooling_tower_pump_excerpt.tdms"
DAQMX = DATA / "nitdms_daqmx_linear_voltage.tdms"


def test_the_waveform_group_of_an_insightcm_export_is_read_without_naming_it():
    """InsightCM writes a group 'Waveform' (a tri-axial accelerometer in g, 5 kHz) beside a group
    'Static' of one temperature (no samples): the waveforms are the record; the other group is
    named in a warning. Values in g times 9.80665."""
    with pytest.warns(UserWarning, match="read group 'Waveform', the only one holding waveforms; skipped the groups "
                                         "of fewer than 2 samples a channel: 'Static' \\(channel 'MIT': 0 samples\\)"):
        records = read_tdms_records(PUMP)
    raw = nptdms.TdmsFile.read(str(PUMP))["Waveform"]
    assert records.channels == ("MIH", "MIA", "MIV") and records.quantities == ("acceleration",) * 3
    assert records.signals.shape == (1, 3, 256)
    assert records.sampling_rate_hz == pytest.approx(5000.0, rel=1e-12)
    for k, name in enumerate(records.channels):
        np.testing.assert_array_equal(records.signals[0, k], np.asarray(raw[name][:], dtype=float) * 9.80665)
    same = read_tdms_records(PUMP, group="Waveform")      # named, no warning needed
    np.testing.assert_array_equal(same.signals, records.signals)


def test_the_static_group_alone_is_refused_by_its_unit():
    with pytest.raises(InputError, match="channel 'MIT' has unit 'F'"):
        read_tdms_records(PUMP, group="Static")


def test_a_daqmx_recording_in_volts_is_read_scaled_once_declared():
    """DAQmx stores raw counts with a linear scale (slope and intercept in the channel's
    properties) and the unit 'Volts': volts say no quantity, so refused until declared; declared,
    the scaled values are those nitdms's own tests give (-0.000409137, -0.000727973, -9.0301e-5 V)
    times the declared factor."""
    with pytest.raises(InputError, match="has unit 'Volts'.*declare it"):
        read_tdms_records(DAQMX)
    records = read_tdms_records(DAQMX, units={"Volts": ("acceleration", 98.0665)})
    np.testing.assert_allclose(records.signals[0, 0, :3], np.array([-0.000409137, -0.000727973, -9.0301e-5]) * 98.0665,
                               rtol=1e-6)
    assert records.sampling_rate_hz == pytest.approx(1000.0, rel=1e-12) and records.signals.shape == (1, 1, 10)
