"""Unbalance peaks between swept speeds of a model with hysteretic mounts are marked, and a
model where they are not looked for says so in the figure's legend (issue 27, section 3).

motor_pump_on_mounts with its mounts' viscous damping replaced by a loss factor of 0.15
(``K (1 + 0.15 i)``), ``--speeds 100:6000:60``: the mount modes' peaks are narrower than the
100 rpm step and the line cut them, unmarked (loss factors have no state form, so no damped
critical speed was looked for). Truth from outside: a 0.1 rpm sweep of ``unbalance_response``
(the exact hysteretic response, no marks) and ``amplification_factors`` on it.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import amplification_factors

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
COARSE = np.linspace(100.0, 6000.0, 60)          # rpm
FINE = np.arange(100.0, 1000.05, 0.1)            # rpm


@pytest.fixture(scope="module")
def lossy(tmp_path_factory):
    text = (EXAMPLES / "motor_pump_on_mounts.toml").read_text()
    assert text.count("damping = [50.0, 50.0, 100.0]") == 4
    text = text.replace("damping = [50.0, 50.0, 100.0]", "damping = [0.0, 0.0, 0.0]\nloss_factor = 0.15")
    path = tmp_path_factory.mktemp("lossy") / "lossy.toml"
    path.write_text(text)
    model = rdm.load_model(path)
    assert all(s.loss_factor == 0.15 for s in model.suspensions)
    coarse = rdm.unbalance_response(model, rdm.rpm(COARSE))
    fine = rdm.unbalance_response(model, rdm.rpm(FINE), resonances=False)
    return model, coarse, fine


def test_every_peak_the_line_cuts_is_marked_at_its_true_height(lossy):
    _, coarse, fine = lossy
    count = 0
    for o, output in enumerate(coarse.outputs):
        for j, source in enumerate(coarse.sources):
            at, response, width = coarse.cut_peaks(output, source)
            rpm = at * 30 / np.pi
            for s, a, af in amplification_factors(fine.speeds, fine.amplitude[o, j]):
                speed = s * 30 / np.pi
                k = np.searchsorted(COARSE, speed)
                if not 0 < k < len(COARSE) or a <= np.sqrt(2) * coarse.amplitude[o, j, k - 1:k + 1].max():
                    continue                                        # the line does not cut it
                near = np.abs(rpm - speed) < 0.2
                assert near.sum() == 1, (output, source, speed)
                assert abs(abs(response[near][0]) / a - 1) < 1e-4
                assert abs(abs(at[near][0]) / width[near][0] / af - 1) < 5e-3
                count += 1
            assert len(at) == sum(1 for s, a, _ in amplification_factors(fine.speeds, fine.amplitude[o, j])
                                  if np.any(np.abs(rpm - s * 30 / np.pi) < 0.2))   # no mark at no peak
    assert count >= 3


def test_a_model_whose_roots_are_not_looked_for_says_so(lossy, monkeypatch):
    """Eigen-solutions over the limit (here the limit made tiny): no marks, and the legend of
    each amplitude panel says why."""
    from rotordyn_modal.analysis import unbalance_peaks

    model, _, _ = lossy
    monkeypatch.setattr(unbalance_peaks, "_WORK", 1.0)
    result = rdm.unbalance_response(model, rdm.rpm(COARSE))
    assert result.cut_peak_speeds is None and "not looked for" in result.cut_peak_note
    fig = result.plot()
    try:
        fig.canvas.draw()
        panels = [ax for ax in fig.axes if ax.get_legend() is not None]
        assert panels
        for ax in panels:
            texts = [t.get_text() for t in ax.get_legend().get_texts()]
            assert any("not looked for" in t for t in texts), texts
    finally:
        matplotlib.pyplot.close(fig)


def test_an_frf_of_the_direct_engine_says_its_peaks_are_not_looked_for(lossy):
    """The direct engine (loss factors) solves no roots: its FRF figure marks no cut peak and its
    legend says that none was looked for (a figure of the modal engine has no such entry)."""
    model, _, _ = lossy
    result = rdm.frf(model, rdm.rpm(1500.0), np.linspace(1.0, 300.0, 300), outputs=["acc-pump-z"])
    assert result.engine == "direct" and result.resonances_hz is None
    fig = result.plot()
    try:
        texts = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
        assert any("not looked for" in t for t in texts), texts
    finally:
        matplotlib.pyplot.close(fig)
    viscous = rdm.frf(rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"), rdm.rpm(1500.0),
                      np.linspace(1.0, 300.0, 300), outputs=["acc-pump-z"])
    fig = viscous.plot()
    try:
        texts = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
        assert not any("not looked for" in t for t in texts), texts
    finally:
        matplotlib.pyplot.close(fig)
