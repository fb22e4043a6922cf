"""A root is a mode by its own numbers and the round-off of its own eigen-solve, never by the size
of another root (issue 27 §1.1; docs/theory.md section 8): a Maxwell branch of 1e-8 s (roots of
-1e8 1/s) or a rotor spinning at 3e6 rpm must not hide the slow modes."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.linear_system import speed_linear_form

_RIGID_ROTOR = """
name = "rigid rotor on two soft isotropic bearings"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "rotor"

[[rotors]]
name = "rotor"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.05

[[bearings]]
name = "A"
rotor = "rotor"
position = [0.2, 0.0, 0.0]
stiffness = 0.01

[[bearings]]
name = "B"
rotor = "rotor"
position = [-0.2, 0.0, 0.0]
stiffness = 0.01
"""
K, MASS, IP, ID, ARM = 0.01, 1.0, 0.05, 0.05, 0.2


def _rubber(examples_dir, tmp_path, times):
    """rubber_mounts.toml with other relaxation times of the mounts' two Maxwell branches."""
    text = (examples_dir / "rubber_mounts.toml").read_text()
    path = tmp_path / "rubber.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", f"maxwell_time = {times}"))
    return path


@pytest.fixture
def fast_branch(examples_dir, tmp_path):
    return _rubber(examples_dir, tmp_path, "[0.02, 1e-8]")


def _csv(argv, capsys):
    assert main([str(a) for a in argv]) == 0
    captured = capsys.readouterr()
    return pd.read_csv(io.StringIO(captured.out)), captured.err


def test_a_fast_maxwell_branch_hides_no_mount_mode(fast_branch, examples_dir, tmp_path):
    """A branch of 1e-8 s adds roots near -1e8 1/s and, as a damper, only K_b tau = 6e-4 N s/m:
    the six mount modes are those of the mounts without that branch, and the state matrix's
    own complex roots are the modes listed: its exact roots (30 digits, mpmath), as scipy's
    double-precision ``eigvals`` is not to 1e-9 here (the model loses about 6 of 16 digits, and
    with OpenBLAS's Haswell kernels one of its roots is 3.6e-9 off; session 46)."""
    import mpmath

    speed = rdm.rpm(1000)
    model = rdm.load_model(fast_branch)
    result = rdm.modal(model, speed)
    assert result.oscillatory.sum() == 6
    mpmath.mp.dps = 30
    state = speed_linear_form(model).at(speed)
    roots = np.array([complex(e) for e in mpmath.eig(mpmath.matrix(state.tolist()), left=False, right=False)])
    upper = np.sort_complex(roots[roots.imag > 1.0])          # every complex root above 0.16 Hz
    listed = result.eigenvalues[result.oscillatory]
    # each root to 1e-9 of its size (issue 28 §4): its real part alone, 2 % of it, is no better than
    # the model's lost digits allow (1.7e-10 of the root: 7e-9 of the real part)
    np.testing.assert_allclose(listed[np.argsort(listed.imag)], upper[np.argsort(upper.imag)], rtol=1e-9)
    # the physics: a branch that fast is no stiffness at these frequencies, only its tiny damping
    text = (examples_dir / "rubber_mounts.toml").read_text()
    slow_only = tmp_path / "slow_only.toml"
    slow_only.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02]").replace(
        "maxwell_stiffness = [[6.0e4, 4.5e4, 1.2e5], [3.0e4, 2.0e4, 6.0e4]]", "maxwell_stiffness = [[6.0e4, 4.5e4, 1.2e5]]"))
    without = rdm.modal(rdm.load_model(slow_only), speed)
    np.testing.assert_allclose(result.frequencies_hz[result.oscillatory],
                               without.frequencies_hz[without.oscillatory], rtol=1e-5)


def test_modes_lists_the_mount_modes_and_counts_the_other_roots(fast_branch, capsys):
    table, err = _csv(["modes", fast_branch, "--speed", "1000", "--out", "-"], capsys)
    assert list(table["mode"]) == [1, 2, 3, 4, 5, 6]
    # 60 states: 6 modes, their conjugates and 48 real roots (relaxations of the branches), of which
    # the 24 nearest zero are in the kept half (every real root counted: tests/test_real_root_count.py)
    assert "48 real roots" in err and "the 24 nearest zero kept" in err and "not listed as modes" in err


def test_the_fast_branch_keeps_the_critical_speeds_of_the_mount_modes(fast_branch, capsys):
    """Each of the six mount modes (all below 50 Hz) crosses the motor's 1X line at 60 f rpm (the
    modes hardly move with speed): 581, 614, 923, 1119, 1609 and 1764 rpm; at each crossing the
    frequency is a root of the state matrix at that speed."""
    table, _ = _csv(["critical-speeds", fast_branch, "--speeds", "0:3000:31", "--out", "-"], capsys)
    motor = table[table["source"] == "motor"].sort_values("speed_rpm")
    model = rdm.load_model(fast_branch)
    mounts = rdm.modal(model, rdm.rpm(1000))
    below = mounts.frequencies_hz[mounts.oscillatory & (mounts.frequencies_hz < 50)]
    assert len(below) == 6 and len(motor) == 6
    np.testing.assert_allclose(motor["speed_rpm"], 60 * below, rtol=2e-3)
    np.testing.assert_allclose(motor["frequency_hz"], motor["speed_rpm"] / 60, rtol=1e-9)
    form = speed_linear_form(model)
    for rpm, hz in zip(motor["speed_rpm"], motor["frequency_hz"]):
        roots = scipy.linalg.eigvals(form.at(rdm.rpm(rpm)))
        assert np.min(np.abs(roots.imag / (2 * np.pi) - hz)) < 1e-6 * hz


@pytest.fixture
def rigid_rotor(tmp_path):
    path = tmp_path / "rigid.toml"
    path.write_text(_RIGID_ROTOR)
    return path


def _conical(speed):
    """Backward and forward conical whirl [rad/s] of the rotor: Id w^2 -+ Ip Omega w - k_theta = 0
    (the backward root written without cancellation)."""
    k_theta = 2 * K * ARM**2
    root = np.sqrt((IP * speed) ** 2 + 4 * ID * k_theta)
    return 2 * k_theta / (root + IP * speed), (root + IP * speed) / (2 * ID)


@pytest.mark.parametrize("rpm", [0.0, 3e4, 3e6])
def test_the_cylindrical_pair_of_a_fast_rotor_on_soft_bearings_stays(rigid_rotor, rpm):
    """The cylindrical whirl of a rigid rotor on isotropic springs is sqrt(2 k / m) at every
    speed, a double root; the conical pair splits with speed (gyroscopic)."""
    speed = rdm.rpm(rpm)
    result = rdm.modal(rdm.load_model(rigid_rotor), speed)
    modes = np.sort(result.eigenvalues[result.oscillatory].imag)
    cylindrical = np.sqrt(2 * K / MASS)
    expected = np.sort(np.r_[cylindrical, cylindrical, _conical(speed)])
    assert len(modes) == 4
    np.testing.assert_allclose(modes, expected, rtol=1e-7)


def test_the_cylindrical_pair_is_on_the_whole_campbell_diagram(rigid_rotor):
    sweep = rdm.campbell(rdm.load_model(rigid_rotor), rdm.rpm(np.linspace(0, 3e6, 7)))
    at = np.isclose(sweep.eigenvalues.imag, np.sqrt(2 * K / MASS), rtol=1e-9) & sweep.oscillatory
    assert np.all(at.sum(axis=1) == 2)


def test_a_free_direction_split_by_round_off_is_no_mode(examples_dir, tmp_path):
    """The gear machine on one spring (vertical) with dampers: five directions without
    suspension, three of them undamped, double zero roots that round-off splits into pairs of
    about sqrt(eps ||A||) (here 1e-7 1/s) that would read as undamped modes. The modes are the
    state matrix's complex roots above 1e-4 1/s: the spring's mode, and at speed the nutation of
    the free machine with its spinning rotors (0.013 1/s at 100 rpm); the other roots are real.
    The modes' values are checked against 50-digit Newton roots of the model's matrices
    (``notes/reports17/roots27r_scripts/mp50.py``): scipy's nutation root is 2.1e-9 off them."""
    text = (examples_dir / "gear_machine.toml").read_text()
    head, tail = text[:text.index("[[suspensions]]")], text[text.index("[[unbalances]]"):]
    spring = ('[[suspensions]]\nname = "spring"\nposition = [0.4, 0.3, -0.2]\n'
              'stiffness = [0.0, 0.0, 4.0e5]\ndamping = [100.0, 100.0, 300.0]\n\n')
    path = tmp_path / "one_spring.toml"
    path.write_text(head + spring + tail)
    model = rdm.load_model(path)
    for rpm in (0.0, 100.0):
        result = rdm.modal(model, rdm.rpm(rpm))
        roots = scipy.linalg.eigvals(speed_linear_form(model).at(rdm.rpm(rpm)))
        pairs = np.sort_complex(roots[roots.imag > 1e-4])
        assert len(pairs) == (1 if rpm == 0 else 2)
        assert result.oscillatory.sum() == len(pairs) and result.real_roots.sum() == 6 - len(pairs)
        np.testing.assert_allclose(np.sort_complex(result.eigenvalues[result.oscillatory]), _ONE_SPRING_ROOTS[rpm],
                                   rtol=1e-9)
        np.testing.assert_allclose(pairs, _ONE_SPRING_ROOTS[rpm], rtol=1e-8)


#: the one-spring gear machine's complex roots [1/s] at 0 and 100 rpm (as ``np.sort_complex`` orders them), by 50-digit Newton on its
#: ``M``, ``C + Omega G``, ``K`` from ``modal``'s roots (steps below 1e-44 relative)
_ONE_SPRING_ROOTS = {
    0.0: np.array([complex(-3.7664188013662103588, 95.98131263987219166)]),
    100.0: np.array([complex(-3.7664188959621651322, 95.981316223953826341),
                     complex(-0.00010569424162770620594, 0.012861038327270941004)])}


def test_stability_reads_the_mount_modes_of_the_fast_branch(fast_branch):
    """The least damped root is a mount mode (real part -5.27 1/s, from scipy's roots of the
    state matrix), not hidden as a rigid-body zero because another root is -1e8 1/s."""
    model = rdm.load_model(fast_branch)
    speeds = rdm.rpm(np.array([0.0, 1000.0, 3000.0]))
    result = rdm.stability(model, speeds)
    assert result.stable.all()
    form = speed_linear_form(model)
    for speed, largest in zip(speeds, _largest_real_parts(result)):
        roots = scipy.linalg.eigvals(form.at(speed))
        np.testing.assert_allclose(largest, roots.real.max(), rtol=1e-9)


def _largest_real_parts(result):
    from rotordyn_modal.analysis.stability import _significant_real_parts

    return _significant_real_parts(result.eigenvalues).max(axis=1)


# ------------------------------------------------------------------- round-off of a graded matrix
def test_balanced_norm_is_lapacks_balanced_norm():
    """``_roots.balanced_norm`` against LAPACK's own balancing (``dgebal``, scaling only) on
    graded random matrices whose rows and columns span 1e-18 to 1e18: within 10 %."""
    from rotordyn_modal.analysis._roots import balanced_norm

    rng = np.random.default_rng(7)
    for _ in range(20):
        n = int(rng.integers(2, 30))
        a = rng.standard_normal((n, n)) * np.exp2(rng.integers(-60, 60, n))[:, None] \
            * np.exp2(rng.integers(-60, 60, n))[None, :]
        reference = np.linalg.norm(scipy.linalg.lapack.dgebal(a, scale=1, permute=0)[0])
        assert balanced_norm(a) == pytest.approx(reference, rel=0.1)
        assert balanced_norm(a) < 1e-3 * np.linalg.norm(a) or reference > 1e-3 * np.linalg.norm(a)


def test_a_whirl_root_beside_a_film_of_glass_stays_a_mode(examples_dir, tmp_path):
    """A journal rotor with a film of 1e9 Pa s: the film's roots reach 4e14 1/s and ||A|| is
    1.8e17, so eps ||A|| (4e3 1/s) would swallow the rotor's whirl root at half the running
    speed (261.8 rad/s at 5000 rpm, its frequency exact to 1e-9 in the eigen-solve). LAPACK
    balances first; the round-off read from the balanced matrix (15 1/s) keeps it a mode."""
    text = (examples_dir / "journal_rotor.toml").read_text()
    path = tmp_path / "glass.toml"
    path.write_text(text.replace("viscosity = 0.02", "viscosity = 1e9"))
    model = rdm.load_model(path)
    speed = rdm.rpm(5000.0)
    every = np.linalg.eigvals(speed_linear_form(model).at(speed))
    slow = every[(np.abs(every) < 1e6) & (every.imag > 0)]
    assert len(slow) == 2 and np.allclose(slow.imag, speed / 2, rtol=1e-7)     # the half-speed whirl
    from rotordyn_modal.analysis.modal import is_oscillating

    result = rdm.modal(model, speed)
    modes = is_oscillating(result.eigenvalues)
    assert modes.sum() == 2
    np.testing.assert_allclose(result.frequencies_hz[modes], speed / 2 / (2 * np.pi), rtol=1e-7)
