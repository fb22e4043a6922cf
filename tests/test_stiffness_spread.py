"""A support far stiffer than what it holds (issues 27 §1.6, 28): the digits its spread costs the
low modes (docs/theory.md §8, "Stiffness spread"), a warning beyond six, a refusal where none is
left. Truths from outside the code: the pinned-pinned Timoshenko beam, and the same mesh with
its supported coordinates removed (the exact limit of infinitely stiff bearings, no spread)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg
import tomli_w

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError
from rotordyn_modal.plausibility import implausible
from rotordyn_modal.stiffness_spread import SPREAD_REFUSE_DIGITS, support_spreads

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}
LENGTH, DIAMETER = 25.0, 0.05           # L/D = 500


def _shaft(stiffness):
    return {"materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0],
                        "shaft": [{"length": LENGTH, "outer_diameter": DIAMETER, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": stiffness}
                         for n, z in (("a", 0.0), ("b", LENGTH))]}


def _pinned_timoshenko():
    """The lowest bending frequency [rad/s] of the pinned-pinned Timoshenko beam (Cowper's
    shear coefficient of a solid circle): the lower root of
    (rho^2 I / (kappa G)) w^4 - (rho A + (rho I + E I rho / (kappa G)) k^2) w^2 + E I k^4 = 0, k = pi / L."""
    E, G, rho = STEEL["young_modulus"], STEEL["shear_modulus"], STEEL["density"]
    nu = E / (2 * G) - 1
    kappa = 6 * (1 + nu) / (7 + 6 * nu)
    area, second, k = np.pi / 4 * DIAMETER ** 2, np.pi / 64 * DIAMETER ** 4, np.pi / LENGTH
    a, b, c = rho ** 2 * second / (kappa * G), rho * area + (rho * second + E * second * rho / (kappa * G)) * k ** 2, \
        E * second * k ** 4
    return np.sqrt((b - np.sqrt(b * b - 4 * a * c)) / (2 * a))


def _run(tmp_path, capsys, data, command="modes"):
    path = tmp_path / "m.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    code = main([command, str(path)])
    return code, capsys.readouterr().err.strip().splitlines()


def test_stiff_but_sensible_bearings_give_the_pinned_timoshenko_frequency_without_a_word(tmp_path, capsys):
    code, err = _run(tmp_path, capsys, _shaft(1e12), "check")
    assert code == 0 and err == []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = rdm.Model.from_dict(_shaft(1e12))
        assert implausible(model) == []
    modes = rdm.modal(model, 0.0)
    lowest = np.abs(modes.eigenvalues[modes.oscillatory].imag).min()
    assert lowest == pytest.approx(_pinned_timoshenko(), rel=1e-5)       # the mesh's accuracy (20 elements)


def test_too_stiff_bearings_warn_in_one_line(tmp_path, capsys):
    code, err = _run(tmp_path, capsys, _shaft(1e18), "check")
    assert code == 0
    warned = [line for line in err if "warning" in line]
    assert len(warned) == 1
    assert "m.toml" in warned[0] and "[bearings." in warned[0] and "stiffness = 1e+18" in warned[0]
    assert "acts as rigid" in warned[0] and "(and 1 other support)" in warned[0]


@pytest.mark.parametrize("stiffness", [1e25, 1e30])
def test_bearings_that_leave_no_digit_are_refused_in_one_line(tmp_path, capsys, stiffness):
    for command in ("check", "modes"):
        code, err = _run(tmp_path, capsys, _shaft(stiffness), command)
        assert code == 2 and len(err) == 1
        assert "m.toml" in err[0] and "[bearings.a] stiffness" in err[0] and f"{stiffness:.3g}" in err[0]
        assert "at most about" in err[0]


def _rigid_in_casing(bearing=1e7, mount=1e5):
    return {"stator": {"mass": 200.0, "inertia": [10.0, 12.0, 14.0], "center_of_mass": [0.3, 0.0, 0.1]},
            "rotors": [{"name": "r", "speed_ratio": 1.0, "mass": 20.0, "center_of_mass": [0.3, 0.0, 0.3],
                        "polar_inertia": 0.1, "diametral_inertia": 0.4}],
            "bearings": [{"name": n, "rotor": "r", "position": [x, 0.0, 0.3], "stiffness": bearing}
                         for n, x in (("A", 0.0), ("B", 0.6))],
            "suspensions": [{"name": f"m{i}", "position": p, "stiffness": [mount] * 3} for i, p in
                            enumerate([[0, 0.3, 0], [0, -0.3, 0], [0.6, 0.3, 0], [0.6, -0.3, 0]])]}


def test_rigid_rotor_on_bearings_of_1e30_in_a_casing_is_refused(tmp_path, capsys):
    assert implausible(rdm.Model.from_dict(_rigid_in_casing())) == []
    with pytest.raises(ModelError, match=r"\[bearings\.[AB]\] stiffness"):
        implausible(rdm.Model.from_dict(_rigid_in_casing(bearing=1e30)))
    code, err = _run(tmp_path, capsys, _rigid_in_casing(bearing=1e30))
    assert code == 2 and len(err) == 1


def test_mounts_of_1e20_warn(tmp_path, capsys):
    """Mounts of 1e20 N/m under a 200 kg casing holding a rotor on 1e7 N/m bearings: 12 digits."""
    code, err = _run(tmp_path, capsys, _rigid_in_casing(mount=1e20))
    assert code == 0
    warned = [line for line in err if "warning" in line]
    assert len(warned) == 1 and "[suspensions.m" in warned[0] and "stiffness = 1e+20" in warned[0]


def test_digits_lost_by_the_lowest_mode_stay_within_the_predicted_ones():
    """Over a sweep of bearing stiffness, the lowest mode's relative error (at most 1: no digit),
    in units of eps, against the exact limit (the same mesh pinned: the bearing coordinates
    removed) is at most the predicted loss, log10(lam_e / lam_1) = (the support's digits) + log10(lam_h / lam_1), plus half a
    decade (measured 2-3.6 decades below, the Weyl bound's slack: a criterion optimistic by 2.5
    decades fails); and not below it by more than four (the criterion is no blanket)."""
    eps = np.finfo(float).eps
    base = rdm.Model.from_dict(_shaft(1.0))
    M, _, _, K = base.matrices()
    pinned = [i for i, name in enumerate(base.dofs.names) if name.startswith(("s.n0.u", "s.n20.u"))]
    free = np.setdiff1d(np.arange(len(M)), pinned)
    exact = np.sqrt(scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True)[0])
    assert exact == pytest.approx(_pinned_timoshenko(), rel=1e-5)
    for stiffness in 10.0 ** np.arange(12, 19):
        model = rdm.Model.from_dict(_shaft(stiffness))
        (_, _, _, digits, rigid, unit), _ = support_spreads(model)
        assert unit == "N/m"
        m_node = M[pinned[0], pinned[0]]
        predicted = min(digits + np.log10(rigid / m_node / exact ** 2), SPREAD_REFUSE_DIGITS)
        M_k, _, _, K_k = model.matrices()
        found = [np.sqrt(abs(scipy.linalg.eigh(K_k, M_k, eigvals_only=True)[0]))]    # the Hermitian solve
        if stiffness == 1e18:                                                         # the package's modes
            modes = rdm.modal(model, 0.0)
            found.append(np.abs(modes.eigenvalues[modes.oscillatory].imag).min())
        lost = [np.log10(np.clip(abs(value - exact) / exact, eps, 1.0) / eps) for value in found]
        assert max(lost) <= predicted + 0.5, (stiffness, lost, predicted)
        assert lost[0] >= predicted - 4.0, (stiffness, lost, predicted)


def test_a_very_stiff_journal_film_draws_no_line(examples_dir, tmp_path, capsys):
    """journal_rotor.toml at 1e9 Pa s (film roots of -4e14 1/s; its whirl roots exact to 1e-9,
    docs/theory.md §8): a film's stiffness is no typed support stiffness."""
    text = (examples_dir / "journal_rotor.toml").read_text()
    path = tmp_path / "thick.toml"
    path.write_text(text.replace("viscosity = 0.02", "viscosity = 1e9"))
    assert path.read_text().count("viscosity = 1e9") == 2
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err   # only the two viscosity lines (1e9 Pa s is no oil: test_hidden35)
    lines = err.splitlines()
    assert len(lines) == 2 and all("viscosity = 1e+09: over 5 Pa s" in line for line in lines), err


@pytest.mark.parametrize("form", ["matrix", "table"])
def test_matrix_and_table_forms_are_checked_as_the_scalar(form):
    """A 2x2 matrix and a speed table's stiffest row count as the scalar does (rigid rotor in a
    casing on mounts)."""
    data = _rigid_in_casing()
    for bearing in data["bearings"]:
        if form == "matrix":
            bearing["stiffness"] = [[1e30, 0.0], [0.0, 1e30]]
        else:
            bearing.update(speeds_rpm=[0.0, 3000.0], stiffness=[1e7, 1e30])
    with pytest.raises(ModelError, match=r"\[bearings\.[AB]\] stiffness = '1e\+30'.*times the scale"):
        implausible(rdm.Model.from_dict(data))


def test_a_tilt_stiffness_far_above_the_shafts_warns_in_n_m_per_rad():
    """moment_stiffness = 1e18 N m/rad at both ends of the slender shaft (the bearing rules
    refuse 1e20 already: the rotor's motions are no longer independent in double precision)."""
    data = _shaft(1e8)
    for bearing in data["bearings"]:
        bearing["moment_stiffness"] = 1e18
    lines = implausible(rdm.Model.from_dict(data))
    assert len(lines) == 1 and "moment_stiffness = 1e+18" in lines[0] and "N m/rad" in lines[0]
