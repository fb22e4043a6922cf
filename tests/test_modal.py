"""Modal analysis against the independent reference (tests/reference_model.py), closed forms
and invariants.

Tolerances: the reference solves a balanced QZ pencil in different coordinates (model origin)
and agrees with 40-digit mpmath to ~1e-12 relative per eigenvalue; the tests ask 1e-9.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import rotordyn_modal as rdm
from reference_model import ReferenceMachine, random_description, rotated, rotation, translated

RTOL = 1e-9


def load_description(examples_dir, name):
    with open(examples_dir / name, "rb") as handle:
        return tomllib.load(handle)


def matched(reference_values, package_values):
    """Pair two sets of eigenvalues by least total distance; returns (ref_index, pkg_index)."""
    cost = np.abs(reference_values[:, None] - package_values[None, :])
    return linear_sum_assignment(cost)


def compare_with_reference(data, speed):
    """Frequencies, damping ratios, whirl ratios and labels, and point motions vs the reference."""
    ref = ReferenceMachine(data)
    model = rdm.Model.from_dict(data)
    res = rdm.modal(model, speed)
    values, shapes = ref.modes(speed)
    osc = res.oscillatory
    assert osc.sum() == len(values)
    i, j = matched(values, res.eigenvalues[osc])
    lam = res.eigenvalues[osc][j]
    np.testing.assert_allclose(lam, values[i], rtol=RTOL, atol=0)
    freq = values[i].imag / (2 * np.pi)
    zeta = -values[i].real / np.abs(values[i])
    np.testing.assert_allclose(res.frequencies_hz[osc][j], freq, rtol=RTOL)
    np.testing.assert_allclose(res.damping_ratios[osc][j], zeta, rtol=0, atol=RTOL)
    # whirl: the reference's own definition over the particle clouds
    ref_ratio = np.array([ref.whirl_ratio(shapes[k], speed) for k in i])
    np.testing.assert_allclose(res.whirl_ratios[osc][j], ref_ratio, rtol=0, atol=1e-7)
    clear = np.abs(np.abs(ref_ratio) - 1e-3) > 1e-4
    expected = np.where(ref_ratio > 1e-3, "forward", np.where(ref_ratio < -1e-3, "backward", "none"))
    assert list(res.whirl[osc][j][clear]) == list(expected[clear])
    # mode shapes: the motion of stator points, up to a complex factor
    points = [np.array(s["position"], dtype=float) for s in data["suspensions"]]
    for k_ref, k_pkg in zip(i, j):
        a = np.concatenate([ref.point_motion(shapes[k_ref], p) for p in points])
        b = np.concatenate([res.shape_at(p)[osc][k_pkg] for p in points])
        mac = abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)
        assert mac == pytest.approx(1.0, abs=1e-9)
    return res


@pytest.mark.parametrize("speed", [0.0, 150.0, 628.3, 1500.0, -900.0])
def test_gear_machine_matches_independent_reference(examples_dir, speed):
    data = load_description(examples_dir, "gear_machine.toml")
    compare_with_reference(data, speed)


@pytest.mark.parametrize("seed", range(8))
def test_random_machines_match_independent_reference(seed):
    rng = np.random.default_rng(seed)
    data = random_description(rng, n_rotors=int(rng.integers(1, 4)), damping=bool(seed % 3),
                              transmissions=bool(seed % 2), matrix_mount=seed % 4 == 1)
    for speed in rng.uniform(-2500, 2500, 2):
        compare_with_reference(data, float(speed))


def test_gear_machine_variants_with_random_gear(examples_dir):
    rng = np.random.default_rng(42)
    base = load_description(examples_dir, "gear_machine.toml")
    for _ in range(4):
        data = dict(base)
        data["transmissions"] = [dict(base["transmissions"][0], ratio=float(rng.uniform(0.3, 4)),
                                      type=str(rng.choice(["gear", "belt"])))]
        data["rotors"] = [dict(r, center_of_mass=rng.uniform(-0.4, 0.4, 3).tolist()) for r in base["rotors"]]
        compare_with_reference(data, float(rng.uniform(-1500, 1500)))


# ----------------------------------------------------------------------------------------
# Closed forms
# ----------------------------------------------------------------------------------------
MS, JX, JT_S = 60.0, 1.2, 2.0           # stator mass, roll and transverse inertia
MR, JP, JD = 10.0, 0.3, 0.2             # rotor on the spin axis through the centre of mass
K_MOUNT, A_MOUNT, K_ROLL = 1.0e5, 0.3, 2.0e3


def symmetric_machine(with_stator=True, roll=True):
    """Spin axis x through the common centre of mass, two isotropic mounts at x = +-a."""
    stiffness = [K_MOUNT] * 3 + ([K_ROLL, 0.0, 0.0] if roll else [])
    mounts = [rdm.Suspension(f"m{s}", [s * A_MOUNT, 0.0, 0.0], stiffness) for s in (1, -1)]
    stator = rdm.Stator(mass=MS, inertia=[JX, JT_S, JT_S]) if with_stator else None
    rotor = rdm.Rotor("rotor", MR, [0.0, 0.0, 0.0], JP, JD, speed_ratio=1.0)
    return rdm.Model(stator=stator, rotors=[rotor], suspensions=mounts)


def conical(speed, jt, kt):
    s = np.sqrt((speed * JP) ** 2 + 4 * jt * kt)
    return (speed * JP + s) / (2 * jt), (s - speed * JP) / (2 * jt)  # forward, |backward|


@pytest.mark.parametrize("speed", [0.0, 200.0, 1000.0, 5000.0])
def test_symmetric_machine_closed_form(speed):
    model = symmetric_machine()
    res = rdm.modal(model, speed)
    m, jt, kt = MS + MR, JT_S + JD, 2 * K_MOUNT * A_MOUNT**2
    translation = np.sqrt(2 * K_MOUNT / m)
    roll = np.sqrt(2 * K_ROLL / (JX + JP))
    forward, backward = conical(speed, jt, kt)
    expected = np.sort([translation] * 3 + [roll, forward, backward])
    np.testing.assert_allclose(np.sort(res.eigenvalues.imag), expected, rtol=1e-12)
    np.testing.assert_allclose(res.eigenvalues.real, 0.0, atol=1e-12 * expected.max())
    if speed > 0:
        label = dict(zip(res.eigenvalues.imag.round(6), res.whirl))
        fw = res.whirl[np.argmin(np.abs(res.eigenvalues.imag - forward))]
        bw = res.whirl[np.argmin(np.abs(res.eigenvalues.imag - backward))]
        assert (fw, bw) == ("forward", "backward"), label
        ratio_fw = res.whirl_ratios[np.argmin(np.abs(res.eigenvalues.imag - forward))]
        assert ratio_fw == pytest.approx(1.0, abs=1e-9)  # a circular conical orbit
        # roll about the spin axis: a straight-line motion of every particle, no whirl
        # (the axial translation shares its frequency with the lateral pair, so it is not singled out)
        assert res.whirl[np.argmin(np.abs(res.eigenvalues.imag - roll))] == "none"


def test_whirl_labels_at_negative_speed_follow_the_reversed_spin():
    res = rdm.modal(symmetric_machine(), -1000.0)
    forward, backward = conical(1000.0, JT_S + JD, 2 * K_MOUNT * A_MOUNT**2)
    k_fw = np.argmin(np.abs(res.eigenvalues.imag - forward))
    k_bw = np.argmin(np.abs(res.eigenvalues.imag - backward))
    assert res.eigenvalues.imag[k_fw] == pytest.approx(forward, rel=1e-12)
    assert (res.whirl[k_fw], res.whirl[k_bw]) == ("forward", "backward")


def test_rigid_rotor_on_isotropic_springs_no_stator():
    """A rotor alone on two isotropic springs: translations sqrt(2k/m), conical whirl,
    and a zero eigenvalue for the unsupported roll about the spin axis (no crash)."""
    model = symmetric_machine(with_stator=False, roll=False)
    speed = 800.0
    res = rdm.modal(model, speed)
    forward, backward = conical(speed, JD, 2 * K_MOUNT * A_MOUNT**2)
    osc = res.oscillatory
    expected = np.sort([np.sqrt(2 * K_MOUNT / MR)] * 3 + [forward, backward])
    np.testing.assert_allclose(np.sort(res.eigenvalues[osc].imag), expected, rtol=1e-12)
    assert (~osc).sum() == 1
    assert abs(res.eigenvalues[~osc][0]) <= 1e-9 * expected.max()
    assert np.allclose(model.reference_point, 0.0)


def test_unsupported_directions_give_zero_eigenvalues():
    """One mount at the centre of mass with translational stiffness only: three
    rotations are free, so three zero roots (six in the state space), no crash."""
    model = rdm.Model(stator=rdm.Stator(mass=50.0, inertia=[2.0, 3.0, 4.0]),
                      rotors=[rdm.Rotor("r", 5.0, [0.0, 0.0, 0.0], 0.05, 0.04, speed_ratio=1.0)],
                      suspensions=[rdm.Suspension("s", [0.0, 0.0, 0.0], [1e5, 2e5, 3e5])])
    res = rdm.modal(model, 0.0)
    lam = res.eigenvalues
    assert np.all(np.isfinite(lam))
    assert np.sum(np.abs(lam) <= 1e-6) == 3
    np.testing.assert_allclose(np.sort(lam[res.oscillatory].imag),
                               np.sqrt(np.array([1e5, 2e5, 3e5]) / 55.0), rtol=1e-12)
    sys = model.state_space(0.0)
    assert np.sum(np.abs(sys.poles()) <= 1e-6) == 6
    camp = rdm.campbell(model, np.linspace(0, 100, 5))
    assert np.all(np.isfinite(camp.eigenvalues))


def test_zero_speed_degenerate_pairs():
    res = rdm.modal(symmetric_machine(), 0.0)
    tilt = np.sqrt(2 * K_MOUNT * A_MOUNT**2 / (JT_S + JD))
    close = np.abs(res.eigenvalues.imag - tilt) <= 1e-9 * tilt
    assert close.sum() == 2
    # the two shapes of a double root are independent (not the same vector twice)
    shapes = res.shapes[close]
    assert np.linalg.matrix_rank(shapes, tol=1e-6) == 2


def test_counter_rotating_pair_explicit_ratios_is_speed_independent():
    rotors = [rdm.Rotor("a", 8.0, [0.1, 0.05, 0.2], 0.2, 0.15, speed_ratio=1.0),
              rdm.Rotor("b", 6.0, [-0.2, 0.0, -0.1], 0.2, 0.12, speed_ratio=-1.0)]
    data = random_description(np.random.default_rng(3), n_rotors=1)
    model = rdm.Model(stator=rdm.Stator(**data["stator"]), rotors=rotors, reference_rotor="a",
                      suspensions=[rdm.Suspension(**s) for s in data["suspensions"]],
                      spin_axis=data["spin_axis"])
    base = rdm.modal(model, 0.0).eigenvalues
    for speed in (-3000.0, 500.0, 4000.0):
        np.testing.assert_allclose(rdm.modal(model, speed).eigenvalues, base, rtol=0,
                                   atol=1e-12 * np.abs(base).max())


# ----------------------------------------------------------------------------------------
# Invariants
# ----------------------------------------------------------------------------------------
def test_state_space_poles_equal_modal_eigenvalues(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    for speed in (0.0, 700.0, -700.0):
        poles = model.state_space(speed).poles()
        lam = rdm.modal(model, speed).eigenvalues
        both = np.concatenate([lam, lam.conj()])
        i, j = matched(poles, both)
        np.testing.assert_allclose(poles[i], both[j], rtol=1e-10)


@pytest.mark.parametrize("seed", range(3))
def test_origin_shift_and_axes_rotation_leave_results_unchanged(seed):
    rng = np.random.default_rng(100 + seed)
    data = random_description(rng, n_rotors=2)
    speed = float(rng.uniform(-2000, 2000))
    base = rdm.modal(rdm.Model.from_dict(data), speed)
    for variant in (translated(data, rng.uniform(-5, 5, 3)), rotated(data, rotation(rng)),
                    rotated(translated(data, rng.uniform(-1, 1, 3)), rotation(rng))):
        other = rdm.modal(rdm.Model.from_dict(variant), speed)
        np.testing.assert_allclose(other.eigenvalues, base.eigenvalues, rtol=1e-10)
        np.testing.assert_allclose(other.whirl_ratios, base.whirl_ratios, atol=1e-7)
        assert list(other.whirl) == list(base.whirl)


@pytest.mark.parametrize("seed", range(3))
def test_reversed_speed_same_eigenvalues_and_labels_relative_to_spin(seed):
    """With symmetric K and C, Q(lam, -Omega) = Q(lam, Omega)^T: same eigenvalues. Undamped,
    Q(i w) is Hermitian, so the shape at -Omega is conj(phi) at Omega: the orbit about +e
    turns the other way and, judged against the reversed spin, labels are kept."""
    rng = np.random.default_rng(200 + seed)
    data = random_description(rng, n_rotors=2, damping=False)
    model = rdm.Model.from_dict(data)
    ref = ReferenceMachine(data)
    speed = float(rng.uniform(300, 2500))
    plus, minus = rdm.modal(model, speed), rdm.modal(model, -speed)
    np.testing.assert_allclose(minus.eigenvalues, plus.eigenvalues, rtol=1e-10)
    np.testing.assert_allclose(minus.whirl_ratios, plus.whirl_ratios, atol=1e-6)
    assert list(minus.whirl) == list(plus.whirl)
    v_plus, s_plus = ref.modes(speed)
    v_minus, s_minus = ref.modes(-speed)
    about_e_plus = np.array([ref.whirl_ratio(s, +1.0) for s in s_plus])
    about_e_minus = np.array([ref.whirl_ratio(s, +1.0) for s in s_minus])
    np.testing.assert_allclose(about_e_minus, -about_e_plus, atol=1e-6)


def test_reversed_speed_damped_same_eigenvalues(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    for speed in (100.0, 900.0):
        np.testing.assert_allclose(rdm.modal(model, -speed).eigenvalues,
                                   rdm.modal(model, speed).eigenvalues, rtol=1e-10)


def test_undamped_eigenvalues_are_purely_imaginary_at_any_speed():
    rng = np.random.default_rng(7)
    model = rdm.Model.from_dict(random_description(rng, n_rotors=3, damping=False))
    for speed in (-5000.0, 0.0, 1234.5, 20000.0):
        lam = rdm.modal(model, speed).eigenvalues
        assert np.all(np.abs(lam.real) <= 1e-10 * np.abs(lam).max())


def test_mac_helper():
    res = rdm.modal(symmetric_machine(), 500.0)
    m = rdm.mac(res.shapes, res.shapes, mass=rdm.matrices(symmetric_machine()).M)
    np.testing.assert_allclose(np.diag(m), 1.0, atol=1e-12)
    # modes of distinct eigenvalues of an undamped gyroscopic system are not M-orthogonal in
    # general, but the MAC is a squared cosine: within [0, 1]
    assert np.all((m >= -1e-12) & (m <= 1 + 1e-12))


@pytest.mark.parametrize("quantity, power", [("displacement", 0), ("velocity", 1), ("acceleration", 2)])
def test_state_space_response_equals_reference_receptance(examples_dir, quantity, power):
    """H(i w) of model.state_space (named inputs/outputs) against the reference's
    d_s . J(P_s) (K - w^2 M + i w (C + Omega G))^-1 J(P_e)^T d_e, times (i w)^power."""
    from reference_model import _jacobian

    data = load_description(examples_dir, "gear_machine.toml")
    data["excitations"].append({"name": "torque-x", "direction": [1.0, 0.0, 0.0], "kind": "moment"})
    model = rdm.Model.from_dict(data)
    ref = ReferenceMachine(data)
    speed = 420.0
    sys = model.state_space(speed, quantity=quantity)
    assert list(sys.input_labels) == ["hammer-z", "shaker-y", "torque-x"]
    assert list(sys.output_labels) == ["acc-top-z", "acc-side-y"]
    rows = np.array([s["direction"] @ _jacobian(np.array(s["position"])) for s in data["sensors"]])
    columns = []
    for x in data["excitations"]:
        if x.get("kind") == "moment":
            columns.append(np.concatenate([np.zeros(3), x["direction"]]))
        else:
            columns.append(_jacobian(np.array(x["position"])).T @ np.array(x["direction"]))
    columns = np.array(columns).T
    for w in (5.0, 60.0, 400.0):
        dynamic = ref.K - w**2 * ref.M + 1j * w * (ref.C + speed * ref.G)
        expected = (1j * w) ** power * rows @ np.linalg.solve(dynamic, columns)
        np.testing.assert_allclose(sys(1j * w), expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


def test_shapes_are_mass_normalised_with_largest_component_real(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    res = rdm.modal(model, 500.0)
    M = model.matrices().M
    np.testing.assert_allclose(np.einsum("mi,ij,mj->m", res.shapes.conj(), M, res.shapes).real, 1.0, rtol=1e-12)
    biggest = res.shapes[np.arange(6), np.argmax(np.abs(res.shapes), axis=1)]
    np.testing.assert_allclose(biggest.imag, 0.0, atol=1e-14)
    assert np.all(biggest.real > 0)
    point, direction = np.array([0.3, -0.2, 0.4]), np.array([0.0, 3.0, 4.0])
    along = res.shape_at(point, direction)
    moved = res.shapes[:, :3] + np.cross(res.shapes[:, 3:], point - model.reference_point)
    np.testing.assert_allclose(along, moved @ (direction / 5.0), rtol=1e-12, atol=1e-15)


def test_reversed_spin_axis_at_reversed_speed_is_the_same_machine():
    """Spin vector r Omega e is unchanged by (e, Omega) -> (-e, -Omega): same eigenvalues,
    shapes and whirl labels (judged against the same physical spin)."""
    rng = np.random.default_rng(31)
    data = random_description(rng, n_rotors=2)
    flipped = dict(data, spin_axis=(-np.asarray(data["spin_axis"])).tolist())
    speed = 1300.0
    a = rdm.modal(rdm.Model.from_dict(data), speed)
    b = rdm.modal(rdm.Model.from_dict(flipped), -speed)
    np.testing.assert_allclose(b.eigenvalues, a.eigenvalues, rtol=1e-12)
    np.testing.assert_allclose(b.whirl_ratios, a.whirl_ratios, atol=1e-9)
    assert list(b.whirl) == list(a.whirl)


@pytest.mark.parametrize("spin", [1.0, -1.0])
def test_rotor_whirl_is_forward_where_gyroscopic_stiffening_raises_the_frequency(examples_dir, spin):
    """The seed 001 disk on its isotropic bearing: each tilting mode is a circle (its rotor's whirl
    ratio exactly +-1), forward where the frequency rises with the spin and backward where it
    falls (gyroscopic stiffening and softening), the axial mode 'none' and unchanged; reversing
    the spin keeps the labels, which are relative to the spin."""
    model = rdm.load_model(examples_dir / "spring_block_rotor.toml")
    at, faster = rdm.modal(model, spin * rdm.rpm(3000)), rdm.modal(model, spin * rdm.rpm(3300))
    rising = np.sign(np.round(faster.frequencies_hz - at.frequencies_hz, 9))
    assert at.rotor_whirl.shape == (len(at.eigenvalues), 1)
    np.testing.assert_allclose(at.rotor_whirl_ratios[:, 0], rising, atol=1e-12)
    assert at.rotor_whirl[:, 0].tolist() == [{1.0: "forward", -1.0: "backward", 0.0: "none"}[r] for r in rising]
    assert sorted(set(at.rotor_whirl[:, 0])) == ["backward", "forward", "none"]


def test_shape_at_refuses_a_body_that_is_not_a_rotor(examples_dir):
    result = rdm.modal(rdm.load_model(examples_dir / "gear_machine.toml"), 0.0)
    np.testing.assert_array_equal(result.shape_at([0.1, 0.0, 0.0], body="stator"), result.shape_at([0.1, 0.0, 0.0]))
    with pytest.raises(rdm.InputError, match="body 'rotor': expected None .the stator. or one of the rotors motor, fan"):
        result.shape_at([0.0, 0.0, 0.0], body="rotor")
