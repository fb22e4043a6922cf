"""A critical speed's last bits do not depend on which other crossings share its batch (issue 28
§4, determ28's item 5). The refinement multiplied ``M phi, (C + Omega G) phi, K phi`` of every
crossing of a batch by one matrix product (a model above 48 coordinates), whose bits depend on
the batch's size; with ``_batches.CHUNK_BYTES`` of one byte (each crossing refined alone) the
critical speeds of flexible_pump_on_mounts and of a 100-coordinate shaft came out other in their
last bits (a study's chunk size did the same). Truth from outside: the same refinement with each
crossing alone, which no batch can touch.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches

from shaft_models import fan_shaft

RPM = np.pi / 30


def _critical(model, speeds, keywords):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = rdm.campbell(model, speeds, orders=(1, 2), **keywords).critical
    return [np.asarray(getattr(table, name)) for name in ("order", "mode", "speeds", "frequencies_hz",
                                                          "whirl_ratios", "damping_ratios")]


@pytest.mark.parametrize("case", ["pump modes", "shaft all"])
def test_each_crossing_alone_gives_the_batchs_bits(case, monkeypatch):
    if case == "pump modes":
        model, speeds, keywords = (rdm.load_model("examples/flexible_pump_on_mounts.toml"),
                                   np.linspace(0, 6000, 31) * RPM, {"modes": 8})
    else:
        model, speeds, keywords = fan_shaft(100), np.linspace(0, 1500, 16), {}
    batched = _critical(model, speeds, keywords)
    assert len(batched[2]) >= 4                       # crossings enough to share a batch
    monkeypatch.setattr(_batches, "CHUNK_BYTES", 1)
    alone = _critical(model, speeds, keywords)
    for a, b in zip(batched, alone):
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), (a, b)
