"""Reproductions of issue 27 that the review of 2026-11-29 (docs/verification.md, "Issue 27: what
an engineer reads") found still wrong on re-running them, each as the issue words it:

* an overdamped machine (every root real, §1.7's "no oscillating modes: 4 real roots"): ``modes``
  printed two lines of numpy's "Casting complex values to real discards the imaginary part"
  under its sentence (the shapes of a repeated real root, combined into complex whirl pairs,
  were stored in LAPACK's real eigenvector array);
* §1.8, a study worker killed from outside (what the out-of-memory killer does): the study
  computed the chunks left, wrote its results, and then never ended (the broken pool waited
  for its other worker, which ignores SIGTERM so that the study's parent stops it);
* §1.1, a free direction's double zero root split by round-off: the gear machine on one vertical
  spring listed an undamped "mode 1" at 5e-8 Hz on this machine's OpenBLAS (the zero-root test
  allowed the stiffness rows one round-off, not what the damping rows carry into them).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

ROOT = Path(__file__).resolve().parent.parent

# a rigid rotor on two isotropic bearings damped far past critical: each of its four whirl
# coordinates has the same two real roots, s = (-c +- sqrt(c^2 - 4 k m)) / (2 m) per motion
_OVERDAMPED = """
name = "rigid rotor on two overdamped bearings"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "r"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.05
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "r"
position = [0.2, 0.0, 0.0]
stiffness = 100.0
damping = 1000.0

[[bearings]]
name = "B"
rotor = "r"
position = [-0.2, 0.0, 0.0]
stiffness = 100.0
damping = 1000.0
"""
K, C, MASS, ID, ARM = 100.0, 1000.0, 1.0, 0.05, 0.2


@pytest.fixture
def overdamped(tmp_path):
    path = tmp_path / "overdamped.toml"
    path.write_text(_OVERDAMPED)
    return path


def _real_roots(m, c, k):
    """The two real roots of m s^2 + c s + k = 0 [1/s], written without cancellation."""
    big = -(c + np.sqrt(c * c - 4 * k * m)) / (2 * m)
    return np.array([big, k / (m * big)])


def test_an_overdamped_machine_lists_no_mode_and_no_numpy_warning(overdamped, capsys):
    """``modes --speed 0``: one sentence on stdout, nothing on stderr, exit 0."""
    assert main(["modes", str(overdamped), "--speed", "0"]) == 0
    out, err = capsys.readouterr()
    # four coordinates (bounce and tilt, y and z), each overdamped: 8 real roots of the state matrix,
    # the 4 nearest zero kept (one of each coordinate's pair; the count since scale27)
    assert out.strip() == ("no oscillating modes at 0 rpm: 8 real roots (relaxation, rigid-body; the 4 nearest "
                           "zero kept as the result's half, docs/theory.md section 8)")
    assert err == ""


def test_the_real_roots_shapes_solve_their_pencil(overdamped):
    """At rest every root is real (checked on the state matrix), the roots listed are the closed
    form's (bounce: 2k, 2c on m; tilt: 2k a^2, 2c a^2 on Id, each twice: y and z) and each shape
    is a null vector of ``s^2 M + s C + K``; no ComplexWarning on the way."""
    from rotordyn_modal.linear_system import speed_linear_form

    model = rdm.load_model(overdamped)
    form = speed_linear_form(model)
    roots = scipy.linalg.eigvals(form.at(0.0))
    assert np.all(np.abs(roots.imag) <= 1e-9 * np.abs(roots).max())     # all real: the premise
    with warnings.catch_warnings():
        warnings.simplefilter("error", np.exceptions.ComplexWarning)
        result = rdm.modal(model, 0.0)
    assert not result.oscillatory.any() and len(result.eigenvalues) == 4   # one root of each pair of states
    expected = np.r_[_real_roots(MASS, 2 * C, 2 * K), _real_roots(ID, 2 * C * ARM**2, 2 * K * ARM**2)]
    mats = form.matrices
    for s, shape in zip(result.eigenvalues, result.shapes):
        assert np.min(np.abs(expected - s)) <= 1e-9 * abs(s)
        terms = abs(s) ** 2 * np.linalg.norm(mats.M, 2) + abs(s) * np.linalg.norm(mats.C, 2) + np.linalg.norm(mats.K, 2)
        residual = (s * s * mats.M + s * mats.C + mats.K) @ shape
        assert np.linalg.norm(residual) <= 1e-12 * terms * np.linalg.norm(shape)


# ------------------------------------------------------------------------- §1.8: a killed worker
#: the study command in a process of its own whose worker starting chunk 1 (while the other
#: computes chunk 0) kills itself with SIGKILL (once; the out-of-memory killer's signal), never
#: the study's own process
_KILLED_WORKER = r"""
import os, signal, sys
from pathlib import Path
from rotordyn_modal.cli import main
from rotordyn_modal.study import execution

marker, parent, real = Path(sys.argv[1]), os.getpid(), execution.run_chunk

def killing(task):
    if task.index == 1 and os.getpid() != parent and not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return real(task)

execution.run_chunk = killing
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL and fork: POSIX")
def test_a_study_whose_worker_is_killed_ends_with_its_results(tmp_path):
    pytest.importorskip("xarray")
    spec = tmp_path / "s.toml"
    # chunks whose results outgrow a pipe's 64 kB: the other worker, busy when the pool broke,
    # then waited to send its result to a pool that no longer read it (a small result went
    # through, and that worker ended)
    spec.write_text('seed = 5\nsamples = 24\nchunk_size = 6\n[[parameters]]\nkey = "stator.mass"\n'
                    'distribution = "uniform"\nlow = 140.0\nhigh = 160.0\n[analyses.campbell]\n'
                    'speeds_rpm = "0:6000:241"\n')
    out = tmp_path / "r.nc"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "ROTORDYN_MODAL_THREADS": "1"}
    process = subprocess.Popen(
        [sys.executable, "-c", _KILLED_WORKER, str(tmp_path / "killed"), "study", str(ROOT / "examples" / "gear_machine.toml"),
         "--spec", str(spec), "--out", str(out), "--workers", "2", "--quiet"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
    try:
        _, err = process.communicate(timeout=90)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        pytest.fail(f"the study did not end (results written: {out.exists()})")
    assert (tmp_path / "killed").exists()                         # a worker was killed
    assert process.returncode == 0, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "warning: a worker process died" in lines[0], err
    assert out.exists() and not (tmp_path / "r.nc.partial").exists()


# ------------------------------------------------------------------------- §1.1: a free direction
@pytest.mark.parametrize("seed", range(5))
def test_a_free_directions_split_pair_is_a_zero_root_whatever_the_perturbation(seed):
    """Two coordinates, M = I: the first free (no stiffness, no damping), the second on a spring
    k and a damper c. A perturbation E of the state matrix of the size of the solve's round-off
    (what LAPACK may add) splits the first's double zero root into a pair near sqrt(||E||); the
    second's damping carries E into the stiffness rows, ``||A_vq phi|| ~ c ||E||`` (here 1000
    round-offs), so a bound of one round-off made the pair an undamped "mode" (on this machine's
    OpenBLAS, tests/test_root_scales.py's gear machine on one spring). The pair is a zero root
    and the second coordinate's two real roots are not."""
    from rotordyn_modal.analysis import _roots

    k, c = 1.0e4, 1.0e3
    a = np.zeros((4, 4))
    a[0, 2] = a[1, 3] = 1.0
    a[3, 1], a[3, 3] = -k, -c
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((4, 4))
    perturbed = a + float(_roots.round_off(a)) * e / np.linalg.norm(e)
    noise = np.asarray(_roots.round_off(perturbed))
    values, vectors = scipy.linalg.eig(perturbed)
    small = np.abs(values) < 1.0
    assert small.sum() == 2 and np.all(np.abs(values[small]) > noise)     # the split pair, above the round-off
    zero = _roots.zero_roots(values, noise, perturbed, vectors, 2)
    assert zero[small].all() and not zero[~small].any()
    np.testing.assert_allclose(np.sort(values[~small].real), np.sort(_real_roots(1.0, c, k)), rtol=1e-9)
