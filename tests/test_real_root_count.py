"""``modes`` counts every real root of the state matrix (issue 27 section 1.9's brief, item 3).

The result keeps one root of each conjugate pair; real roots have no partner, so it keeps the
half of them nearest zero (docs/theory.md section 8). ``modes`` printed that half as "N real
roots": a rigid rotor in a block overdamped in its three translations has six real roots of the
state matrix, and it said 3. Counted here against numpy's eigenvalues of the same state matrix
(a real matrix's real eigenvalues come out of LAPACK with an imaginary part of exactly 0).
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.linear_system import speed_linear_form

# translations: c^2 = 1e12 > 4 k m = 4e6, overdamped; rotations: c = 1 against 2 sqrt(k I) = 44.7, modes
_PARTLY_OVERDAMPED = """
name = "a rotor in a block overdamped in its translations"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "rotor"

[[rotors]]
name = "rotor"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.04

[[suspensions]]
name = "block"
position = [0.0, 0.0, 0.0]
stiffness = [1e6, 1e6, 1e6, 1e4, 1e4, 1e4]
damping = [1e6, 1e6, 1e6, 1.0, 1.0, 1.0]
"""


@pytest.fixture
def model_file(tmp_path):
    path = tmp_path / "block.toml"
    path.write_text(_PARTLY_OVERDAMPED)
    return path


def _numpy_real_roots(model, speed):
    roots = np.linalg.eigvals(speed_linear_form(model).at(speed))
    return np.sort(roots[roots.imag == 0].real)


@pytest.mark.parametrize("rpm", [0.0, 3000.0])
def test_modes_counts_every_real_root_of_the_state_matrix(model_file, capsys, rpm):
    model = rdm.load_model(model_file)
    real = _numpy_real_roots(model, rdm.rpm(rpm))
    assert len(real) == 6                                      # two per overdamped translation
    assert main(["modes", str(model_file), "--speed", str(rpm), "--out", "-"]) == 0
    captured = capsys.readouterr()
    assert f"{len(real)} real roots (relaxation, rigid-body; the 3 nearest zero kept as the result's half" \
        in captured.err, captured.err
    result = rdm.modal(model, rdm.rpm(rpm))
    assert result.state_real_roots == len(real)
    # the kept half: numpy's real roots nearest zero
    kept = np.sort(result.eigenvalues[result.real_roots].real)
    np.testing.assert_allclose(kept, np.sort(real[np.argsort(np.abs(real))[:3]]), rtol=1e-9)


def test_no_mode_counts_every_real_root_in_its_sentence(tmp_path, capsys):
    path = tmp_path / "all.toml"
    path.write_text(_PARTLY_OVERDAMPED.replace("damping = [1e6, 1e6, 1e6, 1.0, 1.0, 1.0]",
                                               "damping = [1e6, 1e6, 1e6, 1e4, 1e4, 1e4]"))
    real = _numpy_real_roots(rdm.load_model(path), 0.0)
    assert len(real) == 12
    assert main(["modes", str(path), "--speed", "0"]) == 0
    assert capsys.readouterr().out.strip() == ("no oscillating modes at 0 rpm: 12 real roots (relaxation, rigid-body; "
                                               "the 6 nearest zero kept as the result's half, docs/theory.md section 8)")
