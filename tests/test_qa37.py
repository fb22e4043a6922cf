"""Issue 29 (note22's leftover): the AF table lists every undamped critical speed a curve has in the
sweep, also where no swept peak is narrow.

An undamped mode's unbalance response is unbounded at the speed where the source's 1X line meets
its root. Before, the AF table looked for such crossings only once a swept peak was too narrow for
its search (some unbounded peak found): a damped model with one undamped mode whose pole has a small
residue (the swept line shows no peak there) listed only its damped peak, and a sweep without any
swept peak listed nothing, while the response is unbounded inside the sweep.

The machine (written here): a rigid rotor (m = 10 kg, Id = 0.3, Ip = 0.1 kg m^2) on two bearings of
k = 1e5 N/m at +-a = +-0.1 m from its centre of mass, a damper of c = 300 N s/m at the centre of mass
(no stiffness), an unbalance U = 1e-4 kg m at e = 1e-5 m from the centre of mass, probes at the
+a bearing. Translation and tilt are uncoupled (symmetric bearings); the damper damps the
translation only: the conical modes are undamped. Truth from outside the code, by hand, whirl at
w = Omega (forward; an unbalance on isotropic supports excites forward whirl only), complex
coordinates ``p = y + i z`` (centre) and ``psi = theta_z - i theta_y`` (tilt), so that the point at
``x = a`` moves ``p + a psi`` and the unbalance's moment drives ``psi`` with ``e`` times its force:

    p   = U Omega^2 / (2 k - m Omega^2 + i c Omega)
    psi = U e Omega^2 / (2 k a^2 - (Id - Ip) Omega^2)

The forward conical 1X critical speed is ``Omega_c = sqrt(2 k a^2 / (Id - Ip)) = 100 rad/s``
(954.93 rpm), undamped: the response is unbounded there. The backward one,
``sqrt(2 k a^2 / (Id + Ip)) = 70.71 rad/s``, is not excited. The cylindrical mode (1366 rpm) is
damped (AF 4.5).
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import api_unbalance_response

RPM = np.pi / 30
M, ID, IP, A, K, C, U, E = 10.0, 0.3, 0.1, 0.1, 1e5, 300.0, 1e-4, 1e-5
FORWARD_CONICAL = np.sqrt(2 * K * A * A / (ID - IP))         # 100 rad/s
BACKWARD_CONICAL = np.sqrt(2 * K * A * A / (ID + IP))        # 70.71 rad/s

MODEL = f"""
name = "rigid rotor, a damper at its centre of mass: its conical modes undamped"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = {M}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = {IP}
diametral_inertia = {ID}
speed_ratio = 1.0

[[bearings]]
name = "DE"
rotor = "rotor"
position = [{A}, 0.0, 0.0]
stiffness = {K}

[[bearings]]
name = "NDE"
rotor = "rotor"
position = [{-A}, 0.0, 0.0]
stiffness = {K}

[[bearings]]
name = "damper"
rotor = "rotor"
position = [0.0, 0.0, 0.0]
stiffness = 0.0
damping = {C}

[[unbalances]]
rotor = "rotor"
amount = {U}
axial_offset = {E}

[[sensors]]
name = "DE-y"
rotor = "rotor"
position = [{A}, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]

[[sensors]]
name = "DE-z"
rotor = "rotor"
position = [{A}, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
"""


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = tmp_path_factory.mktemp("qa37") / "conical_undamped.toml"
    path.write_text(MODEL)
    return rdm.load_model(path)


def _by_hand(speeds):
    """|p + a psi| at ``speeds`` [rad/s]: the probes' 0-peak amplitude [m]."""
    s = np.asarray(speeds, dtype=float)
    p = U * s ** 2 / (2 * K - M * s ** 2 + 1j * C * s)
    psi = U * E * s ** 2 / (2 * K * A * A - (ID - IP) * s ** 2)
    return np.abs(p + A * psi)


def test_the_analysis_is_the_hand_model(model):
    """The response at speeds around both conical crossings and the cylindrical mode equals the hand
    model's to 1e-7: a pole at the forward conical crossing (the amplitude grows as 1/distance),
    none at the backward one."""
    near = np.array([-1e-3, -1e-6, 1e-6, 1e-3])
    speeds = np.concatenate([FORWARD_CONICAL * (1 + near), BACKWARD_CONICAL * (1 + near), [50.0, 143.0, 300.0]])
    result = rdm.unbalance_response(model, speeds, resonances=False)
    for name in ("DE-y", "DE-z"):
        np.testing.assert_allclose(result.amplitude[result.outputs.index(name), 0], _by_hand(speeds), rtol=1e-7)
    assert _by_hand(FORWARD_CONICAL * (1 + 1e-9)) > 300 * _by_hand(FORWARD_CONICAL * (1 + 1e-6))


@pytest.mark.parametrize("points", [41, 81, 401])
def test_the_undamped_crossing_is_listed_beside_the_damped_peak(model, points):
    """Over 0-4000 rpm the swept line shows one peak per probe, the damped cylindrical mode's: the AF
    table also lists the forward conical critical speed (to 1e-9), its amplitude and AF inf, and
    not the backward one (base: the cylindrical peak alone, at every sweep)."""
    table = rdm.unbalance_response(model, np.linspace(0.0, 4000.0, points) * RPM).peaks()
    for name in ("DE-y", "DE-z"):
        mine = table[table["output"] == name]
        unbounded = mine[np.isposinf(mine["amplitude"])]
        assert len(unbounded) == 1, mine
        assert unbounded["speed_rpm"].iloc[0] == pytest.approx(FORWARD_CONICAL / RPM, rel=1e-9)
        assert np.isposinf(unbounded["amplification_factor"].iloc[0])
        damped = mine[np.isfinite(mine["amplitude"])]
        assert len(damped) == 1
        assert not np.any(np.abs(mine["speed_rpm"] - BACKWARD_CONICAL / RPM) < 1.0)


def test_a_sweep_without_swept_peaks_lists_the_undamped_crossing(model):
    """Over 0-1200 rpm the swept amplitude only rises (towards the cylindrical mode at 1366 rpm): no
    swept peak. The response is unbounded at 954.93 rpm all the same, and the table says so
    (base: an empty table)."""
    speeds = np.linspace(0.0, 1200.0, 25) * RPM
    result = rdm.unbalance_response(model, speeds)
    assert np.all(np.diff(result.amplitude, axis=-1) > 0)
    table = result.peaks()
    assert sorted(table["output"]) == ["DE-y", "DE-z"]
    np.testing.assert_allclose(table["speed_rpm"], FORWARD_CONICAL / RPM, rtol=1e-9)
    assert np.all(np.isposinf(table["amplitude"])) and np.all(np.isposinf(table["amplification_factor"]))


def test_the_api_unbalance_cases_list_it_too(model):
    """``--api-unbalance``: the static case (at the centre of mass) excites the translation only;
    the couple case excites the tilt and lists the forward conical crossing (it did before too,
    from its narrow swept peak). Every unbounded row of the table stands at that speed."""
    result = api_unbalance_response(model, np.linspace(0.0, 4000.0, 81) * RPM, 3000.0 * RPM)
    table = result.peaks()
    unbounded = table[np.isposinf(table["amplitude"])]
    assert len(unbounded) >= 2
    np.testing.assert_allclose(unbounded["speed_rpm"], FORWARD_CONICAL / RPM, rtol=1e-9)
