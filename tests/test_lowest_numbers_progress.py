"""``critical-speeds --lowest N`` shows a bar while the mode numbers' lowest roots are solved.

After its crossings bar, the lowest route worked out each critical speed's ``mode_at_speed`` by
shift-invert Arnoldi at every critical speed (``mode_numbers._numbers_among_lowest``) without a
bar: 177 s of silence at 200 geared rotors, 38 s at 80 (issue 27 §1.9, clock27o's report). Each
of those per-speed solves must now run under an open bar that counts it, and the numbers must be
those of the same sweep without any bar.
"""

from __future__ import annotations

import contextlib
import io

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal import _progress
from rotordyn_modal.analysis import _arnoldi
from rotordyn_modal.analysis.campbell import campbell
from test_large_machine_cli import chained_gear_toml

#: 26 geared rotors on bearings: 110 coordinates (at least ``_arnoldi.MIN_DOF``), crowded enough
#: for the Arnoldi route; 3 speeds to 100 rpm keep it to a few seconds
_ROTORS, _TOP_RPM, _MODES = 26, 100.0, 6


def _sweep(tmp_path, progress):
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(_ROTORS, _ROTORS))
    model = rdm.load_model(path)
    assert model.dofs.n >= _arnoldi.MIN_DOF
    return campbell(model, np.linspace(0.0, _TOP_RPM, 3) * np.pi / 30, progress=progress, modes=_MODES)


def test_every_lowest_roots_solve_for_the_mode_numbers_runs_under_a_bar_that_counts_it(tmp_path, monkeypatch):
    bars, solves = [], []
    real_bar, real_solve = _progress.tqdm, _arnoldi._counted_roots

    def bar(*args, **kwargs):
        made = real_bar(*args, **kwargs)
        bars.append(made)
        return made

    def solve(parts, p, want):
        solves.append([b for b in bars if not b.disable])       # the bars open during this speed's solve
        return real_solve(parts, p, want)

    monkeypatch.setattr(_progress, "tqdm", bar)
    monkeypatch.setattr(_arnoldi, "_counted_roots", solve)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        result = _sweep(tmp_path, progress=True)
        bars.clear()
        solves.clear()
        shown = result.critical.mode_at_speed                   # the numbers' work, after the sweep's bars
    assert solves, "the mode numbers solved no lowest roots: the case does not reach the route"
    assert all(open_bars for open_bars in solves), \
        f"{sum(not b for b in solves)} of {len(solves)} lowest-roots solves of the mode numbers ran with no bar open"
    counted = {id(b): b for open_bars in solves for b in open_bars}
    assert sum(b.n for b in counted.values()) == len(solves) and all(b.total == b.n for b in counted.values())

    monkeypatch.setattr(_progress, "tqdm", real_bar)
    monkeypatch.setattr(_arnoldi, "_counted_roots", real_solve)
    quiet = _sweep(tmp_path, progress=False).critical.mode_at_speed
    np.testing.assert_array_equal(shown, quiet)                 # the bar changes no number
    assert (shown > 0).any()
