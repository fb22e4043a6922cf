"""A mode's test depends on that mode and the model's own scales, never on an unrelated root
(issue 27 §1.1; docs/theory.md section 8). A symmetric rigid rotor (centre of mass midway between
two equal isotropic bearings at +-a) of 1e6 kg on 1e-6 N/m bearings has, at speed Omega, the
cylindrical pair ``sqrt(2 k / m)`` (1.414e-6 rad/s) and the conical whirls ``Id w^2 -+ Ip Omega w
- 2 k a^2 = 0``: a forward one near ``Ip Omega / Id`` and a backward one ``2 k_t / (Ip Omega + ...)``
(8.9e-15 rad/s at 100 rad/s), far below the solve's round-off (5.7e-12 1/s at 100 rad/s), which the
forward whirl sets. Each is checked against these closed forms, and the stability threshold of a
cross-coupled slow mode against ``q = c w``."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import mode_numbers

from test_slow_modes27h import _conical, _cylindrical, _load, _rotor

MASS, STIFFNESS = 1e6, 1e-6


@pytest.fixture(scope="module")
def rotor(tmp_path_factory):
    return _load(tmp_path_factory.mktemp("slow"), MASS, STIFFNESS)[0]


@pytest.mark.parametrize("speed", [100.0, 1000.0, 1e4])
def test_the_backward_conical_root_below_round_off_is_kept(rotor, speed):
    """It was zeroed (a root below the solve's round-off was a zero root whatever its shape);
    its value comes from its shape's own equation, to 1e-9 of the closed form (numpy's root is
    9e-7 off at 1e4 rad/s), and it whirls backward."""
    backward = _conical(MASS, STIFFNESS, speed)[1]
    result = rdm.modal(rotor, speed)
    listed = result.eigenvalues[result.oscillatory]
    near = np.isclose(listed.imag, backward, rtol=1e-9, atol=0.0)
    assert near.sum() == 1, (listed, backward)
    assert listed[near][0].real == 0.0
    assert result.whirl[result.oscillatory][near][0] == "backward"
    sweep = rdm.campbell(rotor, np.array([speed]))
    row = sweep.eigenvalues[0][sweep.oscillatory[0]]
    near = np.isclose(row.imag, backward, rtol=1e-9, atol=0.0)
    assert near.sum() == 1, row
    assert sweep.whirl[0][sweep.oscillatory[0]][near][0] == "backward"


@pytest.mark.parametrize("speed", [1000.0, 1e4])
def test_the_cylindrical_pair_whirls_backward_and_forward(rotor, speed):
    """At 1000 rad/s (9549 rpm) the pair was labelled whirl none: a repeated-root tolerance of
    1e-9 of the largest root (1.8e-6 1/s) joined the pair with the backward conical root into a
    group of three, and the solver's planar shapes were kept. A repeated root's shapes are its
    circular whirls: ratios -1 and +1."""
    cylindrical = _cylindrical(MASS, STIFFNESS)
    result = rdm.modal(rotor, speed)
    near = np.isclose(result.eigenvalues.imag, cylindrical, rtol=1e-9, atol=0.0) & result.oscillatory
    assert sorted(result.whirl[near]) == ["backward", "forward"]
    np.testing.assert_allclose(np.sort(result.whirl_ratios[near]), [-1.0, 1.0], atol=1e-6)
    sweep = rdm.campbell(rotor, np.array([speed]))
    near = np.isclose(sweep.eigenvalues[0].imag, cylindrical, rtol=1e-9, atol=0.0) & sweep.oscillatory[0]
    assert sorted(sweep.whirl[0][near]) == ["backward", "forward"]


def test_mode_numbers_count_the_slow_modes(rotor):
    """The number ``modes`` gives the forward conical whirl at 100 rad/s is 4 (below it: the
    backward conical root and the cylindrical pair); the numbering's own solve (no shapes) gave 1,
    its slow roots below the square root of round-off all zero."""
    speed = 100.0
    forward = _conical(MASS, STIFFNESS, speed)[0]
    numbers = mode_numbers._solved_numbers(rotor, np.array([speed]), np.array([1j * forward]))
    assert numbers.tolist() == [4]
    result = rdm.modal(rotor, speed)
    assert int(np.flatnonzero(np.isclose(result.eigenvalues[result.oscillatory].imag, forward))[0]) + 1 == 4


def _cross_coupled(tmp_path, q_max):
    """The rotor with ``c`` = 1e-3 N s/m and a cross-coupled stiffness growing linearly from 0 to
    ``q_max`` between 0 and 2000 rpm in both bearings."""
    text = _rotor(MASS, STIFFNESS).replace(
        "stiffness = 1e-06\n",
        f"stiffness = [[[1e-6, 0.0], [0.0, 1e-6]], [[1e-6, {q_max!r}], [{-q_max!r}, 1e-6]]]\n"
        "damping = [1e-3, 1e-3]\nspeeds_rpm = [0.0, 2000.0]\n")
    path = tmp_path / "cross_coupled.toml"
    path.write_text(text)
    return rdm.load_model(path)


def test_the_stability_threshold_of_a_slow_mode(tmp_path):
    """The cylindrical forward whirl ``m lam^2 + 2 c lam + 2 k - 2 i q = 0`` loses stability where
    ``q = c sqrt(2 k / m)`` (lam = i w): at 100 rad/s here. The threshold's refinement solved
    without shapes, found every root there zero and stopped at the grid's 110 rad/s."""
    q_max = 2.9619219587e-9
    model = _cross_coupled(tmp_path, q_max)
    expected = 1e-3 * _cylindrical(MASS, STIFFNESS) / q_max * 2000.0 * np.pi / 30.0
    result = rdm.stability(model, np.linspace(0.0, 200.0, 21))
    assert len(result.thresholds) == 1
    np.testing.assert_allclose(result.thresholds[0], expected, rtol=1e-6)


def test_the_table_prints_a_whirl_ratio_within_its_round_off_as_0(tmp_path, monkeypatch):
    """The Campbell table's whirl-ratio column printed as 0 only what was within a fixed 1e-9,
    while the labels use each ratio's own round-off: rubber_mounts with a 1e-12 s Maxwell branch
    (round-off 3e-2 on the mount modes' ratios, no root polished: a polish budget of 0, as past a
    big machine's) printed ratios of 2e-3..1.2e-2 beside whirl 'none'. Every ratio labelled none by
    its round-off now prints 0 on the terminal."""
    import warnings
    from pathlib import Path

    from rotordyn_modal.analysis import _eigensolve

    monkeypatch.setattr(_eigensolve, "polish_budget", lambda n: 0.0)

    text = (Path(__file__).resolve().parent.parent / "examples" / "rubber_mounts.toml").read_text()
    path = tmp_path / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.campbell(rdm.load_model(path), rdm.rpm(np.linspace(0.0, 3000.0, 7)), orders=(1,), critical=False)
    table = result.to_dataframe()
    level = result.round_off_rows()["whirl_ratio"]          # row by row (attrs keep one number a column)
    ratio = table["whirl_ratio"].to_numpy(dtype=float)
    by_round_off = (table["whirl"].to_numpy() == "none") & (np.abs(ratio) > 1e-3)
    assert by_round_off.sum() >= 6           # mode 1 at 0-3000 rpm
    assert (np.abs(ratio[by_round_off]) <= level[by_round_off]).all()
    whirling = table["whirl"].to_numpy() != "none"
    assert (np.abs(ratio[whirling]) > level[whirling]).all()


def test_the_lowest_route_labels_whirl_as_the_full_diagram(tmp_path):
    """``campbell --lowest`` labelled whirl by the ratio's sign beyond WHIRL_TOLERANCE alone; on
    rubber_mounts with a 1e-12 s Maxwell branch (mount modes' ratios within their round-off, 3e-2)
    it said forward/backward where ``modes`` and the full diagram say none. Now each carried
    root's label and round-off are the full diagram's (the round-off to 2 %, the same rule)."""
    import warnings
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "examples" / "rubber_mounts.toml").read_text()
    path = tmp_path / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    speeds = rdm.rpm(np.linspace(0.0, 3000.0, 7))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.load_model(path)
        full = rdm.campbell(model, speeds, orders=(1,), critical=False)
        lowest = rdm.campbell(model, speeds, orders=(1,), critical=False, modes=6)
    # the same roots (the 1e-12 s branch's state matrix knows them to about 1e-4 only)
    np.testing.assert_allclose(lowest.eigenvalues, full.eigenvalues[:, :6], rtol=1e-3)
    assert (lowest.whirl == full.whirl[:, :6]).all(), (lowest.whirl, full.whirl[:, :6])
    assert (np.abs(full.whirl_ratios[:, :6]) > 1e-3).sum() >= 7          # the round-off decided
    np.testing.assert_allclose(lowest.whirl_round_off, full.whirl_round_off[:, :6], rtol=0.02)


def test_a_damped_slow_root_goes_on_smoothly_over_speed(tmp_path):
    """With damping and cross-coupling the solve's backward conical root at 100 rad/s is 2.6e-3
    from its shape's own (at 50 rad/s they agree to 4e-6): it was a zero root at 75-125 rad/s and
    a mode beside them. Its frequency is the undamped closed form's to 1e-4 (damping moves it by
    about the square of its tiny damping ratio) and it whirls backward at every speed, in the full
    diagram and the lowest modes' route alike."""
    model = _cross_coupled(tmp_path, 2.9619219587e-9)
    speeds = np.array([50.0, 75.0, 100.0, 125.0, 150.0])
    for sweep in (rdm.campbell(model, speeds, critical=False), rdm.campbell(model, speeds, modes=4, critical=False)):
        for row, speed in enumerate(speeds):
            backward = _conical(MASS, STIFFNESS, speed)[1]
            near = np.isclose(sweep.eigenvalues[row].imag, backward, rtol=1e-4, atol=0.0) & sweep.oscillatory[row]
            assert near.sum() == 1, (speed, sweep.eigenvalues[row])
            assert sweep.whirl[row][near][0] == "backward", (speed, sweep.whirl[row])


def test_a_root_its_shape_does_not_resolve_is_zero_and_counted(rotor):
    """A root below the round-off whose value disagrees with its own shape's equation (here the
    solve's backward conical pair, 8.9e-15 1/s, made 3 times too large; its shapes, loaded by
    the bearings' tilt stiffness, kept) is no mode it can tell: a zero root, counted (and said on
    `modes`' stderr), never a mode at a wrong frequency nor dropped without a word. As solved,
    nothing is unresolved."""
    from rotordyn_modal.analysis import _roots
    from rotordyn_modal.linear_system import speed_linear_form

    form = speed_linear_form(rotor)
    matrix = form.at(100.0)
    values, vectors = np.linalg.eig(matrix)
    noise = float(_roots.round_off(matrix))
    small = np.abs(values) <= noise
    assert small.sum() == 2 and np.allclose(np.abs(values[small]), _conical(MASS, STIFFNESS, 100.0)[1], rtol=1e-6)
    args = (matrix, vectors, form.n_dof, form.matrices.M)
    assert _roots.unresolved_roots(values, noise, *args) == 0
    assert not _roots.zero_roots(values, noise, *args)[small].any()
    wrong = np.where(small, 3.0 * values, values)
    assert _roots.unresolved_roots(wrong, noise, *args) == 2
    assert _roots.zero_roots(wrong, noise, *args)[small].all()
    assert rdm.modal(rotor, 100.0).unresolved_roots == 0
