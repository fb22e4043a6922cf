"""Roots that are not modes (docs/model-file.md): real relaxation roots of rubber mounts, rigid-body
zeros and almost critically damped pairs have no whirl, are not listed or drawn as modes, and are
numbered after the modes, so that mode labels mean the same thing in every output."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import OVERDAMPED_LIMIT
from rotordyn_modal.cli import main


def _csv(argv, capsys):
    assert main([str(a) for a in argv]) == 0
    return pd.read_csv(io.StringIO(capsys.readouterr().out))


def test_relaxation_roots_have_no_whirl_in_the_stability_table(examples_dir, capsys):
    table = _csv(["stability", examples_dir / "rubber_mounts.toml", "--speeds", "0:3000:2", "--out", "-"], capsys)
    relaxation = table[table["frequency_hz"] == 0]
    assert len(relaxation) == 48
    assert set(relaxation["whirl"]) == {"none"}


def test_campbell_numbers_the_modes_as_modes_does(examples_dir, capsys):
    model = examples_dir / "rubber_mounts.toml"
    campbell = _csv(["campbell", model, "--speeds", "0:3000:31", "--out", "-"], capsys)
    modes = _csv(["modes", model, "--speed", "0", "--out", "-"], capsys)
    at_zero = campbell[campbell["speed_rpm"] == 0].sort_values("mode")
    assert list(at_zero["mode"]) == [1, 2, 3, 4, 5, 6] == list(modes["mode"])
    np.testing.assert_allclose(at_zero["frequency_hz"], modes["frequency_hz"], rtol=1e-12)


def test_a_free_direction_is_numbered_after_the_modes(examples_dir):
    """The spring-block rotor (no stator) rolls freely about its axis: a zero root."""
    model = rdm.load_model(examples_dir / "spring_block_rotor_suspension.toml")
    result = rdm.campbell(model, np.linspace(0, 50, 11))
    assert np.all(result.oscillatory[:, :5]) and not np.any(result.oscillatory[:, 5:])


def test_an_almost_critically_damped_pair_is_not_a_mode(examples_dir, capsys):
    """Two relaxation roots of the rubber mounts merge near 9,200 rpm into a complex pair with
    damping ratio 1 - 1e-12: real physics, but no vibration an engineer can see."""
    path = examples_dir / "rubber_mounts.toml"
    model = rdm.load_model(path)
    at = rdm.modal(model, rdm.rpm(9200))
    pair = (at.eigenvalues.imag > 0) & (at.damping_ratios > OVERDAMPED_LIMIT)
    assert pair.sum() == 1                                   # the pair exists ...
    assert not at.oscillatory[pair].any() and at.whirl[pair][0] == "none"
    # no whirl for any root that is not a mode, of the machine or of any of its rotors
    assert np.all(at.whirl_ratios[~at.oscillatory] == 0) and np.all(at.rotor_whirl_ratios[~at.oscillatory] == 0)
    assert (~at.oscillatory).sum() > 1 and at.rotor_whirl_ratios.shape == (len(at.eigenvalues), len(model.rotors))
    assert len(at.to_dataframe()) == 6                       # ... and is not listed as a mode
    modes = _csv(["modes", path, "--speed", "9200", "--out", "-"], capsys)
    assert len(modes) == 6
    sweep = rdm.campbell(model, rdm.rpm(np.linspace(9000, 9400, 41)), orders=(1, 2))
    assert sweep.to_dataframe()["damping_ratio"].max() < OVERDAMPED_LIMIT
    assert np.all(sweep.critical.damping_ratios < OVERDAMPED_LIMIT)
    assert not np.any(sweep.oscillatory & (sweep.damping_ratios > OVERDAMPED_LIMIT))
