"""The critical speeds' mode numbers (``mode_at_speed``) show their progress where their roots
are solved (issue 27 §1.9: long work shows its progress).

Where the sweep's roots interpolated to a critical speed cannot tell a mode's number, the roots
of the state matrix are solved there: on the 100-rotor gear chain (812 states) about half of its
40,770 crossings, estimated at 2.1 hours of CPU time, which ran after the refinement's bar had
closed with nothing on the terminal. Here every crossing is sent to the solve (the interpolation
made to tell none) and the bars tqdm is asked for are recorded.
"""

from __future__ import annotations

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import mode_numbers
from recorded_bars import RecordedBars


def _none_told(monkeypatch):
    """The interpolation tells no crossing's number: every one is solved."""
    def nothing_known(sweep_speeds, values, speeds, *args, **kwargs):
        count = len(speeds)
        return np.zeros(count, dtype=int), np.zeros(count, dtype=bool)

    monkeypatch.setattr(mode_numbers, "_counted_below", nothing_known)


def test_the_solved_mode_numbers_show_a_bar_over_every_crossing(examples_dir, monkeypatch):
    """With ``progress`` a 'mode numbers' bar counts every crossing solved, up to their number;
    the numbers are the same as without the bar."""
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speeds = rdm.rpm(np.linspace(0.0, 6000.0, 31))
    _none_told(monkeypatch)
    quiet = rdm.campbell(model, speeds).critical.mode_at_speed
    bars = RecordedBars(monkeypatch)
    shown = rdm.campbell(model, speeds, progress=True).critical
    assert len(shown) > 5
    numbers = shown.mode_at_speed
    assert bars.named("mode numbers") == [(len(shown), len(shown))]
    np.testing.assert_array_equal(numbers, quiet)


def test_no_bar_unless_asked(examples_dir, monkeypatch):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    _none_told(monkeypatch)
    bars = RecordedBars(monkeypatch)
    assert len(rdm.campbell(model, rdm.rpm(np.linspace(0.0, 6000.0, 31))).critical.mode_at_speed)
    assert bars.made == []
