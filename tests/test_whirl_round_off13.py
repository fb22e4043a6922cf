"""One whirl rule for `modes`, the Campbell diagram and the stability result (issue 27, section 3:
"whirl labels of near-planar modes flip with noise"). A whirl ratio within what round-off can
move it by (the eigen-solve's noise over the gap to the next root, docs/theory.md section 9) is
no whirl in `modes`' table; the Campbell diagram and the stability result labelled the same
ratio by its sign alone, so a nearly repeated pair drawn as backward at rest and forward at
500 rpm was 'none' in `modes` at both speeds.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve
from rotordyn_modal.analysis import campbell as campbell_module

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SPEEDS_RPM = np.linspace(0.0, 3000.0, 7)


@pytest.fixture(scope="module")
def fast_branch(tmp_path_factory):
    """rubber_mounts with a 1e-12 s Maxwell branch: the state matrix's norm is 7e12 1/s and
    round-off moves the mount modes' whirl ratios by about 3e-2 (tests/test_terminal_tables.py);
    with the 2 ms branch the ratios are below 1e-6."""
    text = (EXAMPLES / "rubber_mounts.toml").read_text()
    assert "maxwell_time = [0.02, 0.002]" in text
    path = tmp_path_factory.mktemp("whirl") / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.load_model(path)
        result = rdm.campbell(model, rdm.rpm(SPEEDS_RPM), orders=(1,), critical=False)
    return model, result


def _no_polish(monkeypatch):
    """No root polished (a polish budget of 0, as past the budget of a big machine): every whirl
    ratio's round-off is the solve's."""
    monkeypatch.setattr(_eigensolve, "polish_budget", lambda n: 0.0)


@pytest.fixture(scope="module")
def unpolished(fast_branch):
    """:func:`fast_branch`'s sweep with no root polished (:func:`_no_polish`)."""
    model, _ = fast_branch
    with pytest.MonkeyPatch.context() as patch, warnings.catch_warnings():
        _no_polish(patch)
        warnings.simplefilter("ignore")
        return model, rdm.campbell(model, rdm.rpm(SPEEDS_RPM), orders=(1,), critical=False)


def _modal_label(model, speed, root):
    """`modes`' whirl label of the root nearest ``root`` at ``speed`` [rad/s]."""
    r = rdm.modal(model, speed)
    i = int(np.argmin(np.abs(r.eigenvalues - root)))
    assert abs(r.eigenvalues[i] - root) < 1e-6 * abs(root)
    return r.whirl[i], r.whirl_round_off[i]


def test_campbell_labels_whirl_as_modes_does(fast_branch):
    """At each of 7 speeds every mode's Campbell label equals `modes`' label of the same root
    (`modal` at that speed, the root matched by value). Every mode is polished here, and a
    polished root's whirl round-off is its own (below 1e-6, not the solve's 3e-2): mode 1, whose
    ratio grows linearly from 2.2e-3 at 500 rpm to 1.3e-2 at 3000 rpm (a 50-digit solve's,
    tests/test_roots30.py), reads forward in both, as its ratio says."""
    model, result = fast_branch
    compared = 0
    for k, speed in enumerate(result.speeds):
        for m in np.flatnonzero(result.oscillatory[k]):
            label, noise = _modal_label(model, speed, result.eigenvalues[k, m])
            assert result.whirl[k, m] == label, (SPEEDS_RPM[k], m + 1)
            assert noise < 1e-6 and result.whirl_round_off[k, m] < 1e-6
            compared += 1
    assert compared == 6 * len(SPEEDS_RPM)
    assert (result.whirl[1:, 0] == "forward").all()


def test_campbell_labels_whirl_as_modes_does_without_the_polish(unpolished, monkeypatch):
    """The same with no root polished (the solve's round-off, as past a big machine's polish
    budget): on main before the one rule mode 1 read 'backward' at rest and 'forward' at
    500-3000 rpm while `modes` said 'none' (|ratio| 2e-3-1.2e-2 within its round-off 3e-2): 7
    disagreements."""
    _no_polish(monkeypatch)
    model, result = unpolished
    compared = flipped = 0
    for k, speed in enumerate(result.speeds):
        for m in np.flatnonzero(result.oscillatory[k]):
            label, noise = _modal_label(model, speed, result.eigenvalues[k, m])
            assert result.whirl[k, m] == label, (SPEEDS_RPM[k], m + 1)
            compared += 1
            flipped += abs(result.whirl_ratios[k, m]) > 1e-3 and label == "none"
    assert compared == 6 * len(SPEEDS_RPM)
    # the rule decided: ratios above 1e-3 within the solve's round-off (mode 1 at 0-3000 rpm: at
    # rest its unpolished ratio reads -2e-3)
    assert flipped >= 6


def test_stability_labels_whirl_as_modes_does(fast_branch):
    """The stability result of the same sweep: its whirl labels are `modes`' labels too."""
    model, _ = fast_branch
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.stability(model, rdm.rpm(SPEEDS_RPM))
    for k, speed in enumerate(result.speeds):
        for m in np.flatnonzero(np.isfinite(result.frequencies_hz[k]) & (result.eigenvalues[k].imag > 0)):
            r = rdm.modal(model, speed)
            i = int(np.argmin(np.abs(r.eigenvalues - result.eigenvalues[k, m])))
            if r.oscillatory[i]:
                assert result.whirl[k, m] == r.whirl[i], (SPEEDS_RPM[k], m + 1)


def test_the_figure_draws_no_whirl_change_that_is_round_off(unpolished):
    """Unpolished (:func:`_no_polish`), mode 1's ratio went from -2e-3 at rest to +2e-3 at 500
    rpm, both within its round-off (3e-2): no whirl throughout, so `whirl_changes` has none for it
    (main had backward -> none -> forward inside the first step) and the figure draws it in one
    style, its legend saying that 'no whirl' includes the ratios within round-off."""
    _, result = unpolished
    assert np.all(result.whirl[:, 0] == "none")
    assert len(result.whirl_changes()[0][0]) == 0
    fig = result.plot()
    labels = [t.get_text() for t in fig.legends[0].get_texts()] if fig.legends else \
        [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("round-off" in text for text in labels)
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_an_example_without_round_off_keeps_its_legend():
    """fan_on_bearings: every ratio's round-off is far below 1e-3, the legend says only the
    threshold (as before)."""
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3000.0, 7)), orders=(1,), critical=False)
    assert np.nanmax(result.whirl_round_off) < 1e-6
    assert not result.whirl_none_by_round_off
    fig = result.plot()
    ax = fig.axes[0]
    texts = [t.get_text() for t in (ax.get_legend() or fig.legends[0]).get_texts()]
    assert not any("round-off" in text for text in texts)
    import matplotlib.pyplot as plt

    plt.close(fig)


@pytest.mark.parametrize("a, b, level_a, level_b", [(0.002, 0.05, 0.01, 0.02), (-0.05, 0.03, 0.02, 0.001),
                                                    (0.004, -0.002, 0.001, 0.001)])
def test_level_crossings_with_levels_that_change_over_the_step(a, b, level_a, level_b):
    """Between two speeds the ratio and its level are both linear: the change lies where
    ``a + (b - a) x = +-(level_a + (level_b - level_a) x)`` (closed form, solved here by
    numpy's polynomial roots), the codes at the ends are those of each end at its own level."""
    s0, s1 = 100.0, 200.0
    crossings = campbell_module._level_crossings(s0, s1, a, b, level_a, level_b)

    def code(r, t):
        return 1 if r > t else (-1 if r < -t else 0)

    expected = []
    for side in (-1.0, 1.0):
        # (b - a - side (level_b - level_a)) x + a - side level_a = 0
        x = np.roots([b - a - side * (level_b - level_a), a - side * level_a])
        x = x[(x.real > 0) & (x.real < 1)].real
        expected += [s0 + float(v) * (s1 - s0) for v in x]
    assert sorted(s for s, _ in crossings) == pytest.approx(sorted(expected), rel=1e-12)
    codes = [code(a, level_a)] + [c for _, c in sorted(crossings)]
    assert codes[-1] == code(b, level_b)
    assert all(abs(q - p) == 1 for p, q in zip(codes, codes[1:]))


def test_the_critical_speed_table_labels_whirl_as_modes_does(fast_branch):
    """`critical-speeds` on the same machine (0:3000:31, 1X): each crossing's whirl equals
    `modes`' label of the root at that speed and frequency (`modal` at the crossing's speed). On
    main 5 of the 16 crossings read forward or backward where `modes` says none."""
    model, _ = fast_branch
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3000.0, 31)), orders=(1,)).critical
    assert len(table.speeds) >= 10
    for speed, f, whirl in zip(table.speeds, table.frequencies_hz, table.whirl):
        r = rdm.modal(model, speed)
        i = int(np.argmin(np.where(r.oscillatory, np.abs(r.frequencies_hz - f), np.inf)))
        assert abs(r.frequencies_hz[i] - f) < 1e-3 * f
        assert whirl == r.whirl[i], (speed * 30 / np.pi, f)
