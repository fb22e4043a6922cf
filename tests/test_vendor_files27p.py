"""Measured files of other tools found in issue 27 §4's third search (files27p; the searches and
every file tried are listed in docs/frf-and-measurement.md, "Files tried"):

* Siemens Simcenter Testlab (Rev work-19A) mode shapes, seen in permas4edu/permas4edu
  ``ema/examples/016/PCB_EMA_6modes_mod.unv``: no licence there, so the file here is written in
  its layout with numbers of our own (151 with a non-ASCII model name, 164 code 9
  ``USER_DEFINED`` in Fortran ``D`` exponents, 2411, 82, 55 complex modes whose ID line 4 states
  ``FREQUENCY ...(Hz), DAMPING ...``). In the real file the six modes' stated frequencies are
  Im(eigenvalue) / 2 pi and their dampings -Re / |eigenvalue| to the printed digits: the
  eigenvalue is in rad/s.
* pyuff's ``data/Sample_UFF58_ascii.uff`` (2016, an acquisition at 65,536 Hz, writer not
  named in the file or its commit): an excerpt of its first 60 samples (MIT, as pyuff).

The truth is the file's own text: what its header lines and ID lines state."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.io.channels import ChannelMap

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "uff"
TESTLAB = DATA / "simcenter_testlab_layout_modes.unv"
SAMPLE = DATA / "pyuff_sample_uff58_excerpt.uff"


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(ROOT / "examples" / "gear_machine.toml")


def test_the_simcenter_testlab_header_and_units():
    info = rdm.read_uff_info(TESTLAB)
    assert info["program"] == "Simcenter Testlab Rev work-19A"
    assert info["model_name"] == "ロータ試験"
    assert info["units"].description == "USER_DEFINED" and info["units"].code == 9
    assert (info["units"].length, info["units"].force, info["units"].temperature) == (1.0, 1.0, 1.0)
    assert info["datasets"] == [151, 164, 2411, 82, 55, 55]


def test_the_simcenter_testlab_modes_are_read_as_their_id_lines_state(model):
    """Frequency = Im(lambda) / 2 pi and damping ratio = -Re(lambda) / |lambda| as ID line 4 states
    them (the eigenvalue of record 8 in rad/s); the Z values of the nodes mapped to the sensors."""
    text = TESTLAB.read_text("utf-8")
    stated = [(float(f), float(z)) for f, z in re.findall(r"FREQUENCY (\S+)\(Hz\), DAMPING (\S+)", text)]
    channels = ChannelMap({(1, 3): ("acc-top-z", 1.0), (3, 3): ("acc-side-y", -1.0)}, {})
    read = rdm.read_uff_modes(TESTLAB, model, channels)
    assert len(stated) == 2 and read.outputs == ("acc-top-z", "acc-side-y")
    np.testing.assert_allclose(read.frequencies_hz, [f for f, _ in stated], rtol=2e-6)
    np.testing.assert_allclose(read.damping_ratios, [z for _, z in stated], atol=1e-6)
    np.testing.assert_allclose(read.poles.imag / (2 * math.pi), [f for f, _ in stated], rtol=2e-6)
    np.testing.assert_array_equal(read.shapes[:, :, 0], [[0.5 + 0.01j, -(1.0 - 0.01j)], [1.0, -(-1.0 + 0.02j)]])


def test_the_sample_time_record_excerpt():
    """60 samples of pressure in Pa at the file's interval 1.52588e-05 s, as written."""
    lines = SAMPLE.read_text("ascii").splitlines()
    written = np.array([float(v) for line in lines[13:23] for v in line.split()])
    read = rdm.read_uff_time_records(SAMPLE)
    assert read.quantities == ("pressure",) and read.signals.shape == (1, 1, 60)
    np.testing.assert_array_equal(read.signals[0, 0], written)
    assert read.sampling_rate_hz == pytest.approx(1 / 1.52588e-05, rel=1e-12)
