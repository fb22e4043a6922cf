"""``stability`` checks its sweep's memory before the work, as ``campbell --no-critical`` does
(issue 27 §1.9): 500 geared rotors (2,006 coordinates) at 11 speeds under ``ulimit -v`` 2.4 GiB
solved for 2 minutes and died in ``MemoryError`` (exit 1), where campbell refused the same sweep
in 3 s ("needs about 2.7 GiB of memory, 2.0 GiB is available")."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotordyn_modal.analysis import campbell as campbell_module
from rotordyn_modal.analysis.campbell import memory_estimate
from rotordyn_modal.cli import main

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "fan_on_bearings.toml"
GIB = 2.0 ** 30


@pytest.mark.parametrize("extra", [[], ["--vary", "suspensions.mount-FL.damping", "--scale", "0.5:2:3"]])
def test_a_sweep_that_cannot_fit_is_refused_before_the_work_with_the_estimate(capsys, monkeypatch, no_solutions,
                                                                               extra):
    # the fan's sweep is small: the check's floor and the memory at hand scaled down with it
    monkeypatch.setattr(campbell_module, "_CHECKED_BYTES", 0)
    needed = memory_estimate(16, 32, 31, 1, False)                     # 16 coordinates, 32 states
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", repr(needed / GIB / 2))
    code = main(["stability", str(EXAMPLE), "--speeds", "0:9000:31", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert f"{EXAMPLE}: a stability sweep of 16 coordinates at 31 speeds needs about" in err[0]
    assert "ROTORDYN_MODAL_MEMORY_GB" in err[0] and "--lowest N" in err[0]


def test_a_sweep_that_fits_runs(capsys, monkeypatch):
    monkeypatch.setattr(campbell_module, "_CHECKED_BYTES", 0)
    needed = memory_estimate(16, 32, 31, 1, False)
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", repr(needed / GIB * 2))
    assert main(["stability", str(EXAMPLE), "--speeds", "0:9000:31", "--out", "-"]) == 0
