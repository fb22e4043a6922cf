"""Mode tracking: a mode keeps its label through crossings, veering and Omega = 0.

The machine of `crossing_machine` has exact closed forms for every branch: spin axis x
through the common centre of mass, two mounts at x = +-a ([kx, k, k] plus a roll spring)
and one more at the centre of mass acting along y only. Translations x, y, z and roll are
flat lines at distinct frequencies; the conical modes are
w(Omega) = (Omega Jp +- sqrt((Omega Jp)^2 + 4 Jt kt)) / (2 Jt), which cross all of them.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.analysis.tracking import track_modes
from rotordyn_modal.linear_system import state_matrices
from reference_model import random_description

MS, JX, JT_S = 60.0, 1.2, 0.6
MR, JP, JD = 10.0, 0.3, 0.2
KX, K, KY_EXTRA, A, K_ROLL = 3.0e5, 1.0e5, 1.5e5, 0.3, 1.5e3


def crossing_machine():
    mounts = [rdm.Suspension(f"m{s}", [s * A, 0.0, 0.0], [KX, K, K, K_ROLL, 0.0, 0.0]) for s in (1, -1)]
    mounts.append(rdm.Suspension("y-only", [0.0, 0.0, 0.0], [0.0, KY_EXTRA, 0.0]))
    return rdm.Model(stator=rdm.Stator(mass=MS, inertia=[JX, JT_S, JT_S]),
                     rotors=[rdm.Rotor("rotor", MR, [0.0, 0.0, 0.0], JP, JD, speed_ratio=1.0)],
                     suspensions=mounts)


def branches(speeds):
    """Closed-form frequency [rad/s] of every branch over speed, shape (N, 6)."""
    m, jt, kt = MS + MR, JT_S + JD, 2 * K * A**2
    s = np.sqrt((speeds * JP) ** 2 + 4 * jt * kt)
    flat = np.ones_like(speeds)
    return np.column_stack([
        np.sqrt(2 * KX / m) * flat, np.sqrt((2 * K + KY_EXTRA) / m) * flat, np.sqrt(2 * K / m) * flat,
        np.sqrt(2 * K_ROLL / (JX + JP)) * flat,
        (speeds * JP + s) / (2 * jt),      # the conical mode whose orbit turns about +e
        (s - speeds * JP) / (2 * jt),      # the one turning about -e
    ])


def assign_columns(result, expected):
    """For each tracked mode, the closed-form branch nearest to it over the whole sweep (a
    mode that jumped between branches then fits none of them and the comparison fails)."""
    w = result.eigenvalues.imag
    return [int(np.argmin(np.abs(expected - w[:, [m]]).sum(axis=0))) for m in range(w.shape[1])]


def test_every_tracked_mode_follows_one_closed_form_branch_through_all_crossings():
    speeds = np.linspace(-3000.0, 3000.0, 301)
    expected = branches(speeds)
    # the sweep does cross: the conical branches pass through every flat line
    assert expected[:, 4].min() < expected[:, :4].min() and expected[:, 4].max() > expected[:, :4].max()
    result = rdm.campbell(crossing_machine(), speeds)
    columns = assign_columns(result, expected)
    assert sorted(columns) == list(range(6))
    for mode, branch in enumerate(columns):
        np.testing.assert_allclose(result.eigenvalues[:, mode].imag, expected[:, branch], rtol=1e-10,
                                   err_msg=f"mode {mode + 1} left branch {branch}")


def test_through_zero_speed_the_label_keeps_the_physical_mode_and_whirl_flips():
    """Across Omega = 0 the two conical modes are degenerate; the tracked mode turning about
    +e rises smoothly through it; judged against the spin it is backward for Omega < 0 and
    forward for Omega > 0."""
    speeds = np.linspace(-1000.0, 1000.0, 41)  # includes 0 exactly
    result = rdm.campbell(crossing_machine(), speeds)
    expected = branches(speeds)
    columns = assign_columns(result, expected)
    up = columns.index(4)
    np.testing.assert_allclose(result.eigenvalues[:, up].imag, expected[:, 4], rtol=1e-10)
    assert set(result.whirl[speeds < 0, up]) == {"backward"}
    assert set(result.whirl[speeds > 0, up]) == {"forward"}
    down = columns.index(5)
    assert set(result.whirl[speeds < 0, down]) == {"forward"}
    assert set(result.whirl[speeds > 0, down]) == {"backward"}


@pytest.mark.parametrize("count", [31, 121])
def test_coarse_and_fine_grids_give_the_same_labels(count):
    speeds = np.linspace(0.0, 3000.0, count)
    result = rdm.campbell(crossing_machine(), speeds)
    expected = branches(speeds)
    columns = assign_columns(result, expected)
    for mode, branch in enumerate(columns):
        np.testing.assert_allclose(result.eigenvalues[:, mode].imag, expected[:, branch], rtol=1e-10)


def test_random_machine_curves_are_smooth_and_shapes_continuous():
    """Coupled machine (veering rather than crossing): every tracked curve is smooth (its
    second differences are of the order of the grid's h^2, not jumps between branches) and
    its mass-weighted shape changes little from one speed to the next."""
    rng = np.random.default_rng(17)
    model = rdm.Model.from_dict(random_description(rng, n_rotors=2, damping=False))
    speeds = np.linspace(-3000.0, 3000.0, 601)
    result = rdm.campbell(model, speeds)
    w = result.eigenvalues.imag
    gaps = np.diff(np.sort(w, axis=1), axis=1).min()  # smallest distance between modes anywhere
    second = np.abs(np.diff(w, n=2, axis=0)).max(axis=0)
    first = np.abs(np.diff(w, axis=0)).max(axis=0)
    assert np.all(second < 0.2 * first + 1e-9 * np.abs(w).max()), (second, first, gaps)
    M = model.matrices().M
    shapes = result.shapes
    num = np.abs(np.einsum("kmi,ij,kmj->km", shapes[:-1].conj(), M, shapes[1:])) ** 2
    den = (np.einsum("kmi,ij,kmj->km", shapes[:-1].conj(), M, shapes[:-1]).real
           * np.einsum("kmi,ij,kmj->km", shapes[1:].conj(), M, shapes[1:]).real)
    mac = num / den
    away_from_zero = np.abs(0.5 * (speeds[:-1] + speeds[1:])) > 20.0
    assert mac[away_from_zero].min() > 0.9


def test_veering_pair_is_followed_by_shape():
    """The crossing machine with its y-only mount tilted by 0.02 rad and moved off the centre
    of mass couples translations and tilts: crossings become veerings (the z-translation and
    conical curves stay ~6 rad/s apart instead of touching). Each tracked curve stays smooth."""
    model = crossing_machine()
    data = model.to_dict()
    data["suspensions"][2]["axes"] = [[1.0, 0.0, 0.0], [0.0, np.cos(0.02), np.sin(0.02)],
                                      [0.0, -np.sin(0.02), np.cos(0.02)]]
    data["suspensions"][2]["position"] = [0.05, 0.0, 0.0]
    veering = rdm.Model.from_dict(data)
    speeds = np.linspace(0.0, 3000.0, 241)
    result = rdm.campbell(veering, speeds)
    w = result.eigenvalues.imag
    second = np.abs(np.diff(w, n=2, axis=0))
    step = np.abs(np.diff(w, axis=0)).max()
    assert second.max() < 0.5 * step


C_MOUNT, CX_MOUNT, C_ROLL = 150.0, 300.0, 2.0


def damped_crossing_machine():
    mounts = [rdm.Suspension(f"m{s}", [s * A, 0.0, 0.0], [KX, K, K, K_ROLL, 0.0, 0.0],
                             [CX_MOUNT, C_MOUNT, C_MOUNT, C_ROLL, 0.0, 0.0]) for s in (1, -1)]
    mounts.append(rdm.Suspension("y-only", [0.0, 0.0, 0.0], [0.0, KY_EXTRA, 0.0]))
    return rdm.Model(stator=rdm.Stator(mass=MS, inertia=[JX, JT_S, JT_S]),
                     rotors=[rdm.Rotor("rotor", MR, [0.0, 0.0, 0.0], JP, JD, speed_ratio=1.0)],
                     suspensions=mounts)


def damped_branches(speeds):
    """Closed-form eigenvalues (Im > 0) of every branch, shape (N, 6), complex.

    Tilts, z = theta_y + i theta_z: Jt z'' + (ct - i Omega Jp) z' + kt z = 0. A root with
    Im > 0 is an orbit turning about +e; the conjugate of the root with Im < 0 is the
    upper eigenvalue of the orbit turning about -e."""
    m, jt, kt, ct = MS + MR, JT_S + JD, 2 * K * A**2, 2 * C_MOUNT * A**2

    def upper(a, b, c):
        return (-b + np.emath.sqrt(b * b - 4 * a * c)) / (2 * a) * np.ones_like(speeds)

    out = [upper(m, 2 * CX_MOUNT, 2 * KX), upper(m, 2 * C_MOUNT, 2 * K + KY_EXTRA),
           upper(m, 2 * C_MOUNT, 2 * K), upper(JX + JP, 2 * C_ROLL, 2 * K_ROLL)]
    b = ct - 1j * speeds * JP
    disc = np.sqrt(b * b - 4 * jt * kt + 0j)
    roots = np.stack([(-b + disc) / (2 * jt), (-b - disc) / (2 * jt)], axis=1)
    plus = np.where(roots[:, 0].imag > 0, roots[:, 0], roots[:, 1])
    minus = np.where(roots[:, 0].imag > 0, roots[:, 1], roots[:, 0])
    return np.column_stack(out + [plus, minus.conj()])


def test_damped_machine_tracked_through_crossings_and_zero_speed():
    speeds = np.linspace(-3000.0, 3000.0, 121)
    expected = damped_branches(speeds)
    assert np.all(expected.imag > 0)
    result = rdm.campbell(damped_crossing_machine(), speeds)
    lam = result.eigenvalues
    columns = [int(np.argmin(np.abs(expected - lam[:, [m]]).sum(axis=0))) for m in range(6)]
    assert sorted(columns) == list(range(6))
    for mode, branch in enumerate(columns):
        np.testing.assert_allclose(lam[:, mode], expected[:, branch], rtol=1e-10)
    up = columns.index(4)
    assert set(result.whirl[speeds < 0, up]) == {"backward"} and set(result.whirl[speeds > 0, up]) == {"forward"}


def test_through_a_point_of_undefined_shapes_modes_are_matched_to_their_last_sure_shape():
    """Two modes of shapes a = (1, 0) and b = (0, 1) meet at speed 2, where their eigenvalue
    is double and LAPACK may return any basis of the plane (here the two 45-degree mixtures),
    and part again at speed 3 a hair apart (1.099 and 1.101), where the linear extrapolation
    of the frequencies cannot tell them apart (its cost favours each wrong root by 0.09, the
    MAC's term weighs up to 1). Matched against the mixtures at speed 2, both roots look alike (MAC 0.5 each);
    matched against each mode's last sure shape (speed 1), mode 1 is the root of shape a."""
    lam = 1j * np.array([[1.0, 1.2], [1.05, 1.15], [1.1, 1.1], [1.101, 1.099]])
    a, b = np.array([1.0, 0.0], complex), np.array([0.0, 1.0], complex)
    mixed = np.array([a + b, a - b]) / np.sqrt(2.0)
    shapes = np.array([[a, b], [a, b], mixed, [b, a]])            # speed 3: the root of shape a second
    order = track_modes(lam, shapes)
    assert order[3].tolist() == [1, 0]
    assert order[:2].tolist() == [[0, 1], [0, 1]]


def test_a_real_pair_turning_complex_takes_no_mode_and_no_other_real_root():
    """Two real roots (-3.02, -2.98) meet into a pair that does not oscillate (-3 + 0.01i);
    the place it leaves in the kept half (one of each pair, the smaller half of the real
    roots) takes the next real root, -60. Beside them two well separated modes and their real
    partners (-4.5, -4), whose shapes are the modes' own (as a Maxwell branch's relaxation
    root carries its mode's motion). Every mode keeps its root (its shape and eigenvalue do not
    change); the partners keep theirs; the label whose root left takes the newcomer."""
    a, b, c, d = np.eye(4, dtype=complex)
    mode_a, mode_b = -0.5 + 10j, -0.8 + 15j
    before = [-4.5, -4.0, -3.02, -2.98, mode_a, mode_b]
    after = [-60.0, -4.5, -4.0, -3.0 + 0.01j, mode_a, mode_b]       # sorted as the kept half is
    lam = np.array([before, before, after, after], dtype=complex)
    shapes = np.array([[b, a, c, d, a, b]] * 2 + [[d, b, a, (c + d) / np.sqrt(2.0), a, b]] * 2)
    order = track_modes(lam, shapes)
    tracked = lam[np.arange(4)[:, None], order]
    assert (tracked[:, 4] == mode_a).all() and (tracked[:, 5] == mode_b).all()
    assert (tracked[:, 0] == -4.5).all() and (tracked[:, 1] == -4.0).all()
    assert sorted(tracked[2:, 2:4].ravel().tolist(), key=abs) == [-3.0 + 0.01j] * 2 + [-60.0] * 2


def _followed(model, rpm, roots):
    """``roots`` (m,) at ``rpm[0]`` followed over the fine grid ``rpm`` by the nearest root of
    scipy's eigenvalues of the state matrix, each step unambiguous (the nearest root 100
    times nearer than the next). Returns (len(rpm), m)."""
    path = [np.asarray(roots)]
    for matrix in state_matrices(model, rpm[1:] * np.pi / 30.0):
        roots = scipy.linalg.eigvals(matrix)
        gaps = np.abs(path[-1][:, None] - roots[None, :])
        nearest = np.sort(gaps, axis=1)
        assert np.all(nearest[:, 0] < 0.01 * nearest[:, 1])
        path.append(roots[gaps.argmin(axis=1)])
    return np.array(path)


def test_modes_keep_their_roots_where_the_kept_real_roots_change(examples_dir):
    """rubber_mounts.toml: between 9,150 and 9,200 rpm two real roots at -38.6 1/s meet into
    a pair that does not oscillate, and a real root at -492.7 1/s enters the kept half. Each
    mode (well apart, 9.7 to 29.6 Hz, barely moving) is what it was: its tracked eigenvalues
    are those of the root followed by nearest distance over a grid ten times finer."""
    model = rdm.load_model(examples_dir / "rubber_mounts.toml")
    rpm = np.linspace(9000.0, 9400.0, 9)
    lam = rdm.campbell(model, rpm * np.pi / 30.0, critical=False).eigenvalues
    modes = np.nonzero(is_oscillating(lam[0]))[0]
    assert len(modes) == 6
    truth = _followed(model, np.linspace(9000.0, 9400.0, 81), lam[0, modes])[::10]
    np.testing.assert_allclose(lam[:, modes], truth, rtol=1e-9)


def _continued(model, rpm, roots):
    """``roots`` (m,) at ``rpm[0]`` continued over the fine grid ``rpm``: at each speed each
    takes a root of scipy's eigenvalues of the state matrix (all of them, both halves), the
    assignment of least total distance (roots of one value, a relaxation root -1/tau as many
    times as the branches, are interchangeable). Returns (len(rpm), m)."""
    from scipy.optimize import linear_sum_assignment

    path = [np.asarray(roots)]
    for matrix in state_matrices(model, rpm[1:] * np.pi / 30.0):
        roots = scipy.linalg.eigvals(matrix)
        rows, columns = linear_sum_assignment(np.abs(path[-1][:, None] - roots[None, :]))
        path.append(roots[columns[np.argsort(rows)]])
    return np.array(path)


def test_real_roots_keep_their_tracks_where_the_kept_real_roots_change(examples_dir):
    """rubber_mounts.toml, 9,000-9,400 rpm: the mounts' Maxwell branches give a relaxation root
    -1/tau = -50 1/s eighteen times (as many as the branches' states: six with a motion, as any
    basis of their eigenspace, twelve without); between 9,150 and 9,200 rpm two real roots at
    -38.6 1/s meet into a pair that does not oscillate and a real root at -492.7 1/s enters the
    kept half. Each label's root is the one continued by least distance over a grid 25 times
    finer, but for the two that meet (one of them continues in the pair's other half, not
    kept): the newcomer took a -50 1/s label, and a -50 1/s root the label of -38.64 1/s."""
    model = rdm.load_model(examples_dir / "rubber_mounts.toml")
    tau = np.concatenate([np.ravel(mount.maxwell_time) for mount in model.suspensions
                          if mount.maxwell_time is not None]).astype(float)
    rpm = np.linspace(9000.0, 9400.0, 9)
    lam = rdm.campbell(model, rpm * np.pi / 30.0, critical=False).eigenvalues
    assert np.sum(np.abs(lam[0] + 1.0 / tau.max()) < 1e-9) == 18
    truth = _continued(model, np.linspace(9000.0, 9400.0, 201), lam[0])[::25]
    meeting = (truth[0].imag == 0) & (np.abs(truth[-1].imag) > 1e-9 * np.abs(truth[-1]))     # not round-off
    assert meeting.sum() == 2
    np.testing.assert_allclose(lam[:, ~meeting], truth[:, ~meeting], rtol=1e-9, atol=1e-9)
    assert sorted(lam[-1, meeting], key=abs)[-1] == pytest.approx(-492.74, abs=0.01)


def test_a_far_root_of_a_modes_shape_does_not_take_its_label_when_its_root_turns_overdamped():
    """Two roots of one shape: a mode of |lambda| = 10 1/s whose damping ratio rises through
    the overdamped limit (0.985, 0.988, 0.991: from speed 2 on a pair that does not
    oscillate), and an overdamped pair of |lambda| = 40 1/s whose damping falls below it
    (0.995, 0.993, 0.985). At speed 2 the one mode of that shape lies four times farther out
    than the label's root; each label keeps the root of its own |lambda|."""
    def root(size, zeta):
        return size * (-zeta + 1j * np.sqrt(1.0 - zeta**2))

    a, b = np.eye(2, dtype=complex)
    lam = np.array([[root(10.0, z10), root(40.0, z40), 30j] for z10, z40 in
                    ((0.985, 0.995), (0.988, 0.993), (0.991, 0.985), (0.994, 0.98))])
    shapes = np.array([[a, a, b]] * 4)
    order = track_modes(lam, shapes)
    tracked = lam[np.arange(4)[:, None], order]
    np.testing.assert_allclose(np.abs(tracked), [[10.0, 40.0, 30.0]] * 4)


def _nearly(a, b):
    """A unit shape of MAC 1 / (1 + 0.05**2) = 0.9975 with ``a``."""
    return (a + 0.05 * b) / np.sqrt(1.0 + 0.05**2)


@pytest.mark.parametrize("case", ["two labels, one root of their shape", "one label, two roots of its shape"])
def test_roots_of_nearly_one_shape_are_matched_once_each(case):
    """Where two labels share a shape (MAC 0.9975) and one root of it follows them, or one
    label and two roots of its shape, no label is kept on a root that another could take: each
    speed's order is a permutation, and each label keeps the root nearest its own."""
    a, b, c = np.eye(3, dtype=complex)
    if case == "two labels, one root of their shape":
        before, after = [10j, 10.3j, 20j], [10.1j, 10.25j, 20j]
        shapes = [[a, _nearly(a, b), c], [a, c / 1j, _nearly(c, b)]]
    else:
        before, after = [10j, 10.3j, 20j], [10.1j, 10.25j, 20j]
        shapes = [[a, b, c], [a, _nearly(a, b), c]]
    lam = np.array([before, before, after]) - 0.1
    order = track_modes(lam, np.array([shapes[0], shapes[0], shapes[1]]))
    assert all(sorted(row) == [0, 1, 2] for row in order.tolist())
    np.testing.assert_array_equal(lam[np.arange(3)[:, None], order][2], lam[2])
