"""``critical-speeds`` builds its model's linear form once (issue 27 §1.9, issue 29 §7).

Its sweep built the state form, and the mode numbers of its table (``mode_at_speed``) built it
again where the sweep's roots could not tell a crossing's number. Inside
``linear_system.kept_form`` both take one form, and no result keeps it: the form is let go at
the block's end while the result lives. Builds are counted by a spy on the form's constructor.
"""

from __future__ import annotations

import gc
import sys
import weakref
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
import rotordyn_modal.linear_system as linear_system
from rotordyn_modal.analysis.campbell import campbell
from rotordyn_modal.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

#: a 6-rotor gear chain's sweep at 5 speeds leaves some crossings' numbers to a solve
SPEEDS_RPM = (100.0, 3000.0, 5)


@pytest.fixture
def chain(tmp_path):
    path = tmp_path / "chain6.toml"
    path.write_text(chained_gear_toml(6, 6))
    return path


@pytest.fixture
def built(monkeypatch):
    """Weak references to every linear form built while the test runs."""
    forms = []
    real = linear_system.SpeedLinearForm.__init__

    def counted(self, *args, **kwargs):
        real(self, *args, **kwargs)
        forms.append(weakref.ref(self))

    monkeypatch.setattr(linear_system.SpeedLinearForm, "__init__", counted)
    return forms


def test_critical_speeds_command_builds_the_linear_form_once(chain, built, tmp_path):
    start, stop, count = SPEEDS_RPM
    out = tmp_path / "critical.csv"
    code = main(["critical-speeds", str(chain), "--speeds", f"{start:g}:{stop:g}:{count}", "--speed-unit", "rpm",
                 "--out", str(out), "--quiet"])
    assert code == 0
    rows = out.read_text().splitlines()
    assert len(rows) > 1 and rows[0].endswith("mode_at_speed")
    assert len(built) == 1, f"{len(built)} linear forms built for one critical-speeds run"


def test_kept_form_serves_the_sweep_and_the_mode_numbers_and_is_let_go(chain, built):
    model = rdm.load_model(chain)
    speeds = rdm.rpm(np.linspace(*SPEEDS_RPM))
    free = campbell(model, speeds).critical
    alone = np.array(free.mode_at_speed)
    assert len(built) == 2                  # without a block: the sweep's form, the numbers' own
    del built[:]
    with linear_system.kept_form(model):
        result = campbell(model, speeds)
        numbers = np.array(result.critical.mode_at_speed)
    assert len(built) == 1
    np.testing.assert_array_equal(numbers, alone)           # the same numbers from the one form
    gc.collect()
    assert built[0]() is None, "the result keeps the linear form alive"
    assert len(result.critical) == len(free)
    # outside the block a form is built for each call again, a different one each time
    first, second = linear_system.speed_linear_form(model), linear_system.speed_linear_form(model)
    assert first is not second


def test_kept_form_is_the_very_models_only(chain):
    model, other = rdm.load_model(chain), rdm.load_model(chain)
    with linear_system.kept_form(model):
        one = linear_system.speed_linear_form(model)
        assert linear_system.speed_linear_form(model) is one
        assert linear_system.speed_linear_form(other) is not one      # an equal model: its own form
        with linear_system.kept_form(model):                          # nested: the outer block's form
            assert linear_system.speed_linear_form(model) is one
        assert linear_system.speed_linear_form(model) is one
    assert linear_system.speed_linear_form(model) is not one
