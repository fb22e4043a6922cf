"""One mode numbering across the report, its figures included (issue 27 section 2; helper num30).

The report's text and tables number a mode as the Campbell diagram does (tracked from the lowest
speed), with the number ``modes --speed MCS`` gives it in brackets where the two differ. Its
figures (the mode-shape panels' titles, the Level I legend) must say the same.

Truth from outside the report: a gyroscopic rigid rotor on two cross-coupled isotropic bearings
placed symmetrically (translation and tilt uncoupled), written out here in complex coordinates
``r = y + i z``, ``psi = theta_z - i theta_y`` (a bearing at ``x`` moves by ``r + x psi``); roots
of positive frequency are the forward modes. The backward tilt mode falls below the forward
translation mode between rest and the MCS, so that mode is 1 at the lowest speed (the tracked
number) and 2 at the MCS (ranks by frequency among the four modes, the numbering rule of
``modal``; the two forward modes never cross). On 80eaeba the mode-shape panels and the Level I
legend read ``mode 2`` where the tables read ``1 (2 at the MCS)``: both tests fail there.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from rotordyn_modal.analysis.level1 import Station
from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs, render
from rotordyn_modal.report.collect import collect

RPM = np.pi / 30
MASS, DIAMETRAL, POLAR, DAMPING = 50.0, 5.0, 8.0, 300.0
STIFFNESS, CROSS = 1.0e6, 2.0e4                   # [N/m]: each bearing [[k, q], [-q, k]]
BEARINGS = (0.4, -0.4)                            # positions x [m]: translation and tilt uncoupled
MCS, QA = 3000 * RPM, 8.0e4

MODEL = f"""
name = "gyroscopic rigid rotor"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = {MASS}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = {POLAR}
diametral_inertia = {DIAMETRAL}
speed_ratio = 1.0
""" + "".join(f"""
[[bearings]]
name = "B{i}"
rotor = "rotor"
position = [{x}, 0.0, 0.0]
stiffness = [[{STIFFNESS}, {CROSS}], [{-CROSS}, {STIFFNESS}]]
damping = {DAMPING}
""" for i, x in enumerate(BEARINGS))


def roots(speed):
    """The four modes' roots [1/s] at ``speed`` [rad/s] (``e^{s t}``): frequency ``Im s``, > 0
    forward. ``M q'' + (C - i speed G) q' + (K - i Q) q = 0`` in ``q = (r, psi)``: a bearing's
    ``[[k, q], [-q, k]]`` acts on ``r`` as ``k - i q``; the forward tilt root rises with speed
    (``-Id w^2 + Ip speed w + k_t = 0``)."""
    K, C, Q = np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2))
    for x in BEARINGS:
        arm = np.outer([1.0, x], [1.0, x])
        K, C, Q = K + STIFFNESS * arm, C + DAMPING * arm, Q + CROSS * arm
    M, G = np.diag([MASS, DIAMETRAL]), np.diag([0.0, POLAR])
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, K - 1j * Q), -np.linalg.solve(M, C - 1j * speed * G)]])
    return np.linalg.eigvals(A)


def ranks(speed):
    """``{forward mode's frequency [rad/s]: its number}``: the numbers :func:`modal` gives, 1, 2,
    ... by frequency, a frequency shared to round-off (the translations': the cross-coupling
    moves only their damping) the least damped first."""
    s = roots(speed)
    order = sorted(s, key=lambda x: (round(abs(x.imag), 6), -x.real))
    return {float(x.imag): 1 + order.index(x) for x in s if x.imag > 0}


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    path = tmp_path_factory.mktemp("numbers30") / "gyroscopic.toml"
    path.write_text(MODEL, encoding="utf-8")
    inputs = ReportInputs("api617", MCS, points=21, level1={"stations": [Station("rotor", 0.0)], "qa": QA})
    return collect(load_model(path), inputs)


def _figures(monkeypatch):
    """Capture the figures a section renders (``render._figure``'s first argument)."""
    figures = []
    original = render._figure
    monkeypatch.setattr(render, "_figure", lambda fig, *a: figures.append(fig) or original(fig, *a))
    return figures


def _expected_label(frequency):
    """The report's name of the forward mode at ``frequency`` [rad/s, at the MCS]: tracked number
    (its rank at the report's lowest speed, 2 % of the MCS), the MCS rank in brackets."""
    at_mcs = ranks(MCS)
    (mcs_rank,) = [n for f, n in at_mcs.items() if abs(f - frequency) < 1e-6 * f]
    lower = sorted(at_mcs).index(min(at_mcs, key=lambda f: abs(f - frequency)))
    low = ranks(0.02 * MCS)
    tracked = low[sorted(low)[lower]]
    return str(tracked) if tracked == mcs_rank else f"{tracked} ({mcs_rank} at the MCS)"


def test_the_machine_numbers_its_forward_translation_two_ways():
    """The premise: the forward translation mode is 1 at the lowest speed and 2 at the MCS (the
    backward tilt mode falls below it); the forward tilt mode is 4 at both."""
    assert sorted(ranks(MCS).values()) == [2, 4]
    assert sorted(ranks(0.02 * MCS).values()) == [1, 4]


def test_mode_shape_panels_carry_the_tables_numbers(report, monkeypatch):
    """Each panel's title names its mode as the table row of the same place does; the forward
    modes' names are the closed form's."""
    figures = _figures(monkeypatch)
    html = render._modes(report, "si")
    cells = re.findall(r'<tr><td class="text">([^<]*)</td><td>([^<]*)</td><td class="text">([^<]*)</td>', html)
    (fig,) = figures
    titles = [ax.get_title() for ax in fig.axes if ax.get_visible() and ax.get_title()]
    named = [re.match(r"mode (.+?): ", t).group(1) for t in titles]
    assert named == [label for label, _, _ in cells]
    forward = [(label, 2 * np.pi * float(hz)) for label, hz, whirl in cells if whirl == "forward whirl"]
    assert len(forward) == 2
    for label, w in forward:
        assert label == _expected_label(min(ranks(MCS), key=lambda f: abs(f - w)))
    assert "1 (2 at the MCS)" in named


def test_level1_legend_names_the_swept_mode_as_the_text(report, monkeypatch):
    """The Level I figure's legend names the swept forward mode (the translation, judged) as the
    section's text and table do, and as the closed form numbers it: "mode 1 (2 at the MCS)"."""
    figures = _figures(monkeypatch)
    html = render._level1(report, "si")
    run = report.results["level1"]
    label = _expected_label(2 * np.pi * run.frequencies_hz[0])
    assert label == "1 (2 at the MCS)"
    assert f"mode {label}" in html
    texts = [t.get_text() for legend in figures[0].legends for t in legend.get_texts()]
    texts += [t.get_text() for ax in figures[0].axes for t in ax.get_legend().get_texts()] if any(
        ax.get_legend() for ax in figures[0].axes) else []
    curves = [t for t in texts if "(forward " in t]
    assert curves and all(t.startswith(f"mode {label} (forward ") for t in curves), curves


def test_study_names_its_swept_af_so():
    """``study``'s ``unbalance`` AF is read off the swept speeds (the exact search of ``unbalance``
    and ``report`` would cost several times the variant's response, docs/study-file.md), and its
    column ``amplification_factor`` (the name scripts read) says so in its netCDF attribute
    ``peak_search``. Its value is the half-power band interpolated
    by hand between the swept speeds of the closed-form response of a rigid rotor on isotropic
    bearings (probe at its centre of mass: the polar inertia the grid varies does not reach it),
    1 % or more off the exact AF there. On 80eaeba the column has no ``peak_search``."""
    import rotordyn_modal as rdm
    from closed_form_machines import C_B, K_B, M_R, rotor_displacement, rotor_on_springs
    from rotordyn_modal.study import parse_study

    amount = 5e-5
    model = rotor_on_springs([{"rotor": "shaft", "amount": amount}])
    spec = parse_study({"parameters": [{"key": "rotors.shaft.polar_inertia", "values": [0.4, 0.5]}],
                        "analyses": {"unbalance": {"speeds_rpm": "100:6000:31", "operating_speed_rpm": 3000.0}}},
                       model=model)
    data = rdm.study(model, spec).dataset
    assert "swept speeds" in data["amplification_factor"].attrs["peak_search"]
    assert "swept speeds" in data["required_margin_pct"].attrs["peak_search"]
    swept = data["amplification_factor"].values.ravel()
    w = np.linspace(100.0, 6000.0, 31) * RPM
    y = rotor_displacement(w, amount)
    k = int(np.argmax(y))
    level = y[k] / np.sqrt(2)
    lo = k - np.argmax(y[k::-1] < level)                       # first swept speed below the level, each side
    hi = k + np.argmax(y[k:] < level)
    n1 = w[lo] + (level - y[lo]) * (w[lo + 1] - w[lo]) / (y[lo + 1] - y[lo])
    n2 = w[hi - 1] + (level - y[hi - 1]) * (w[hi] - w[hi - 1]) / (y[hi] - y[hi - 1])
    by_hand = w[k] / (n2 - n1)
    np.testing.assert_allclose(swept, by_hand, rtol=1e-9)
    kk, c, m = 2 * K_B, 2 * C_B, M_R                          # the exact peak and band (test_exact_af29)
    u = 2 * kk ** 2 / (2 * kk * m - c ** 2)
    peak2 = u ** 2 / ((kk - m * u) ** 2 + c ** 2 * u)
    roots = np.sort(np.roots([peak2 * m ** 2 - 2, peak2 * c ** 2 - 2 * peak2 * kk * m, peak2 * kk ** 2]).real)
    exact = np.sqrt(u) / (np.sqrt(roots[1]) - np.sqrt(roots[0]))
    assert abs(by_hand - exact) > 0.01 * exact


@pytest.mark.parametrize("name, mcs, onsets", [("journal_rotor", 12500.0, 1), ("compressor_rotor", 10000.0, 0)])
def test_estimate_counts_the_stability_rows_thresholds(name, mcs, onsets):
    """The report's estimate counts the stability row's refinement (a few one-speed solves a
    threshold) for as many thresholds as ``stability`` finds over the report's speeds: journal_rotor
    at 12,500 rpm turns unstable once below 1.5 MCS, compressor_rotor never. On 80eaeba the
    estimate counted none (no ``_thresholds_bound``)."""
    from pathlib import Path

    from rotordyn_modal.analysis.stability import stability
    from rotordyn_modal.report.collect import THRESHOLD_SOLVES, _thresholds_bound, estimate_work

    model = load_model(Path(__file__).resolve().parents[1] / "examples" / f"{name}.toml")
    inputs = ReportInputs("api684", mcs * RPM, points=21)
    found = int(np.isfinite(stability(model, inputs.speeds).thresholds).sum())
    assert found == onsets
    assert _thresholds_bound(model, inputs) == found
    text = dict((p[0], p[2]) for p in estimate_work(model, inputs).parts)["campbell"]
    assert (f"the stability row's thresholds: at most {found} refined" in text) == bool(found)
    assert THRESHOLD_SOLVES >= 6                       # measured on journal_rotor (docs/report.md)
