"""The static checks at any size (issue 27 §6): a rotor's sag in its bearings is now looked at
in models of more than 200 coordinates too, the static solution being an LU where the
stiffness is regular (an SVD of 2,006 coordinates had cost seconds on every load).

Before: over 200 coordinates (``SAG_CHECK_DOF``) the sag of a rotor in its bearings was not
looked at, so bearings typed in N/mm as N/m in a 60-rotor gear chain (246 coordinates) passed
without a word."""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.linear_system import static_solution

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

G = 9.81


def _chain(soft_rotor: int, stiffness: float):
    """The 60-rotor gear chain on mounts, every rotor on two bearings, under gravity, the bearings
    of rotor ``soft_rotor`` of ``stiffness`` [N/m]."""
    data = tomllib.loads(chained_gear_toml(60, 60))
    data["gravity"] = [0.0, 0.0, -G]
    name = f"r{soft_rotor:03d}"
    for bearing in data["bearings"]:
        if bearing["rotor"] == name:
            bearing["stiffness"] = stiffness
    rotor = next(r for r in data["rotors"] if r["name"] == name)
    return data, rotor


def test_a_rotor_on_bearings_typed_in_n_per_mm_sags_in_a_machine_of_246_coordinates():
    """Rotor r030 (3 kg) centred between its two bearings of 20 N/m (2e4 N/m typed in N/mm):
    it sinks m g / (2 k) = 0.736 m in them, whatever the stator does on its mounts."""
    from rotordyn_modal.plausibility import implausible

    data, rotor = _chain(30, 20.0)
    model = rdm.Model.from_dict(data, source="chain.toml")
    lines = implausible(model)
    assert model.dofs.n > 200
    expected = rotor["mass"] * G / (2 * 20.0)
    sag = [line for line in lines if "rotor 'r030' would sag" in line]
    assert sag, lines
    assert f"sag {expected:.3g} m at [bearings.b030" in sag[0]


def test_the_same_chain_on_its_own_bearings_says_nothing_of_sag():
    data, _ = _chain(30, 2.3e6)
    from rotordyn_modal.plausibility import implausible

    model = rdm.Model.from_dict(data, source="chain.toml")
    assert not [line for line in implausible(model) if "sag" in line]


@pytest.mark.parametrize("seed", range(8))
def test_a_regular_stiffness_of_mixed_units_is_solved_to_round_off(seed):
    """Random regular stiffnesses (not symmetric: cross-coupling) ``D C D``, a well-conditioned
    core ``C`` with rows and columns scaled over 12 decades by ``D`` (N/m beside N m/rad, long
    arms): the solution equals ``numpy.linalg.solve`` of the core's system to round-off, in the
    core's norm (``|D (x - x_exact)| / |D x_exact|``). The SVD route of the base reached 2.4e-7
    here over 200 such seeds (its equilibration by row and column norms is not the core's), the
    LU 6e-14."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 80))
    core = rng.standard_normal((n, n)) + n * np.eye(n)
    scale = 10.0 ** rng.uniform(-6, 6, n)
    stiffness = scale[:, None] * core * scale[None, :]
    load = rng.standard_normal(n) * scale
    x = static_solution(stiffness, load)
    exact = np.linalg.solve(core, load / scale) / scale
    assert np.linalg.norm(scale * (x - exact)) <= 1e-12 * np.linalg.norm(scale * exact)


def test_a_free_direction_keeps_the_least_norm_solution():
    """Two springs in series with a free rigid motion (a stiffness of rank 1 on two coordinates):
    a load across them moves them apart by F/k, split equally (the least-norm solution), and a
    load on the free motion is refused (None)."""
    k, force = 5e4, 3.0
    stiffness = k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    x = static_solution(stiffness, np.array([force, -force]))
    assert np.allclose(x, [force / (2 * k), -force / (2 * k)], rtol=1e-12, atol=0.0)
    assert static_solution(stiffness, np.array([force, force])) is None
