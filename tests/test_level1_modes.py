"""``level1`` judges the least stable of the rotor's first forward modes, not the first by
frequency alone: checked through the Python API and the command line against the rigid rotor
written out by hand in tests/rigid_two_forward.py (its first forward mode passes both criteria,
the machine fails both). ``--forward-mode N`` still follows one mode.

Fast: one rigid rotor of 4 degrees of freedom."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

from rigid_two_forward import MCS, QA, least_log_decrement, roots, threshold, write_model


@pytest.fixture(scope="module")
def path(tmp_path_factory):
    return write_model(tmp_path_factory.mktemp("level1_modes"))


def _hand_log_decrements(q):
    lam = roots(q)
    lam = lam[lam.imag > 0]
    return -2 * np.pi * lam.real / lam.imag


def test_python_api_judges_the_least_stable_forward_mode(path):
    model = rdm.load_model(path)
    result = rdm.level1(model, MCS, ["rotor"], QA)
    assert result.log_decrement_at_qa == pytest.approx(least_log_decrement(QA), rel=1e-8)
    assert result.q0 == pytest.approx(threshold(), rel=1e-8)
    assert not result.passes_log_decrement and not result.passes_ratio and result.level2_required
    # every swept mode is one of the machine's, the first by frequency among them
    assert len(result.swept) >= 2 and [r.forward_mode for r in result.swept] == list(range(1, len(result.swept) + 1))
    hand = _hand_log_decrements(QA)
    for run in result.swept:
        assert np.min(np.abs(hand - run.log_decrement_at_qa)) < 1e-8 * abs(run.log_decrement_at_qa)
    assert result.governs_q0 is not None and result.governs_q0.q0 == result.q0
    # --forward-mode 1: the first forward mode alone, which the cross-coupling at the centre
    # barely reaches: it passes (what level1 judged the machine by before)
    first = rdm.level1(model, MCS, ["rotor"], QA, forward_mode=1)
    assert first.forward_mode == 1 and len(first.swept) == 1 and first.mode == result.swept[0].mode
    assert first.log_decrement_at_qa > 0.1 and not np.isfinite(first.q0) and not first.level2_required


def test_command_line_judges_the_least_stable_forward_mode(path, tmp_path, capsys):
    out = tmp_path / "l1.csv"
    assert main(["level1", str(path), "--speed", str(MCS * 30 / np.pi), "--station", "rotor", "--qa", str(QA),
                 "--out", str(out)]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert f"log dec at Qa = {least_log_decrement(QA):.3g} (< 0.1)" in err
    assert f"Q0/Qa = {threshold() / QA:.3g} (< 2)" in err and "Level II required" in err
    assert "forward mode 1:" in err and "forward mode 2:" in err and "governs" in err
    table = pd.read_csv(out)
    at_qa = table.iloc[int(np.argmin(np.abs(table["q_over_qa"] - 1.0)))]
    assert at_qa["log_decrement"] == pytest.approx(least_log_decrement(QA), rel=1e-8)
    per_mode = [c for c in table.columns if c.startswith("log_decrement_mode_")]
    assert len(per_mode) >= 2 and min(at_qa[per_mode]) == at_qa["log_decrement"]
    # one mode asked for: that mode alone, the columns as before
    assert main(["level1", str(path), "--speed", str(MCS * 30 / np.pi), "--station", "rotor", "--qa", str(QA),
                 "--forward-mode", "1", "--out", str(out)]) == 0
    assert "Level II not required" in capsys.readouterr().err
    assert out.read_text().splitlines()[0] == "q_n_per_m,q_over_qa,log_decrement,frequency_hz"


def test_figure_draws_every_swept_mode(path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = rdm.level1(rdm.load_model(path), MCS, ["rotor"], QA)
    fig = result.plot()
    labels = [line.get_label() for line in fig.axes[0].get_lines() if "(forward " in line.get_label()]
    assert len(labels) == len(result.swept)
    assert sum("governs log dec at Qa" in label for label in labels) == 1
    assert any(f"mode {result.mode} (forward" in label and "governs log dec at Qa" in label for label in labels)
    plt.close(fig)


def test_help_documents_the_sweep_and_forward_mode(capsys):
    with pytest.raises(SystemExit):
        main(["level1", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "first three forward modes" in text and "the least stable is judged" in text
    assert "--forward-mode N follows the N-th forward mode alone" in text
