"""API 617 Level I critical speed ratio against average gas density (issue 29, item 3): the
dividing line's points as ROSS gives them, the first critical speed on rigid supports of a
uniform shaft against its closed form, the verdict's rule, bad input, the report's line."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.level1 import (CsrScreening, Level1Result, csr_boundary, csr_screening, level1,
                                            rigid_support_critical_speed)
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.model_file import load_model

LENGTH, DIAMETER, ELEMENTS = 1.0, 0.02, 12            # m, m: slender (L/d = 50)
DENSITY, YOUNG = 7810.0, 2.11e11                      # kg/m^3, Pa

SHAFT = f'''name = "uniform shaft on soft end bearings"
spin_axis = [1.0, 0.0, 0.0]
[[materials]]
name = "steel"
density = {DENSITY}
young_modulus = {YOUNG}
poisson_ratio = 0.3
[[rotors]]
name = "shaft"
speed_ratio = 1.0
start = [0.0, 0.0, 0.0]
shear = "none"
[[rotors.shaft]]
length = {LENGTH}
outer_diameter = {DIAMETER}
material = "steel"
elements = {ELEMENTS}
[[bearings]]
name = "left"
rotor = "shaft"
axial_position = 0.0
stiffness = 2e5
damping = 50.0
[[bearings]]
name = "right"
rotor = "shaft"
axial_position = {LENGTH}
stiffness = 2e5
damping = 50.0
'''


@pytest.fixture(scope="module")
def shaft(tmp_path_factory):
    path = tmp_path_factory.mktemp("csr") / "shaft.toml"
    path.write_text(SHAFT)
    return path, load_model(path)


@pytest.fixture(scope="module")
def coarse(tmp_path_factory):
    """The shaft in 4 elements (its first critical within (pi/4)^4/720 = 5e-4 of the closed
    form): the Level I sweeps stay fast."""
    path = tmp_path_factory.mktemp("csr") / "coarse.toml"
    path.write_text(SHAFT.replace(f"elements = {ELEMENTS}", "elements = 4"))
    return path, load_model(path)


def _pinned_pinned_critical_speed() -> float:
    """First forward synchronous critical speed [rad/s] of a uniform shaft simply supported.

    Euler-Bernoulli: ``w = k^2 sqrt(E I / (rho A))``, ``k = pi / L``. The model's beam keeps the
    rotary inertia ``rho I`` and the gyroscopic term ``2 rho I Omega`` (shear off): whirling
    forward at ``w = Omega`` they add ``rho I k^2 (1 - 2)`` to the mass per length, so exactly
    ``w = k^2 sqrt(E I / (rho A (1 - r^2 k^2)))``, ``r^2 = I / A = d^2 / 16`` (a 3e-5 rise here)."""
    k = np.pi / LENGTH
    area, inertia = np.pi * DIAMETER ** 2 / 4, np.pi * DIAMETER ** 4 / 64
    euler_bernoulli = k ** 2 * np.sqrt(YOUNG * inertia / (DENSITY * area))
    return euler_bernoulli / np.sqrt(1 - inertia / area * k ** 2)


def test_dividing_line_has_the_points_ross_gives():
    """ROSS (api_report.py, stability_level_1): CSR 2.5 up to 16.53 kg/m^3, then
    -0.0115 rho + 2.69 (2.0 at 60 kg/m^3), 0 beyond 60 kg/m^3."""
    rho = np.array([0.0, 10.0, 16.53, 30.0, 45.0, 60.0, 60.5, 100.0])
    expected = [2.5, 2.5, 2.5, 2.69 - 0.0115 * 30, 2.69 - 0.0115 * 45, 2.0, 0.0, 0.0]
    np.testing.assert_allclose(csr_boundary(rho), expected, rtol=0, atol=1e-12)
    # the sloped part meets the flat one at the knee (to ROSS's rounding of the constants)
    assert 2.69 - 0.0115 * 16.53 == pytest.approx(2.5, abs=1e-4)
    # Region B strictly above the line
    assert CsrScreening(100.0, 40.0, (10.0,)).region == "A"          # CSR 2.5 on the line
    assert CsrScreening(100.0, 40.0, (20.0,)).region == "B"          # line 2.46 there
    assert CsrScreening(100.0, 60.0, (65.0, 75.0)).density == 70.0


def test_rigid_support_critical_speed_of_a_uniform_shaft_is_the_closed_form(shaft):
    """On rigid supports the shaft on two end bearings is pinned-pinned, whatever the bearings'
    stiffness. Cubic Hermite elements converge from above, the first frequency's error below
    (kh)^4 / 720 (h the element length; 6.5e-6 here, a fifth of the rotary-inertia term)."""
    path, model = shaft
    expected = _pinned_pinned_critical_speed()
    bound = (np.pi / ELEMENTS) ** 4 / 720
    assert 0 <= rigid_support_critical_speed(model) / expected - 1 < bound
    mcs = 1.5 * expected
    screening = csr_screening(model, -mcs, (20.0, 40.0))            # the speed's sign is ignored
    assert screening.csr == pytest.approx(1.5, rel=bound)
    assert screening.density == 30.0 and screening.region == "A"
    # the bearings' own stiffness does not enter it
    stiffer = load_model(path.with_name("stiffer.toml")) if path.with_name("stiffer.toml").write_text(
        SHAFT.replace("stiffness = 2e5", "stiffness = 3e7")) else None
    assert 0 <= rigid_support_critical_speed(stiffer) / expected - 1 < bound


def test_a_rigid_rotor_has_no_critical_speed_on_rigid_supports():
    """Pinned at two bearings and its casing held, a rigid rotor cannot move laterally: CSR 0."""
    rotor = rdm.Rotor("r", 30.0, [0.0, 0.0, 0.0], 0.2, 1.1, speed_ratio=1.0)
    bearings = [dict(name=n, rotor="r", position=[x, 0.0, 0.0], stiffness=1e6) for n, x in (("A", 0.3), ("B", -0.3))]
    casing = dict(stator=rdm.Stator(mass=80.0, inertia=[4.0, 6.0, 7.0], center_of_mass=[0.0, 0.0, -0.1]),
                  suspensions=[rdm.Suspension(f"m{i}", [x, y, -0.3], [3e5, 4e5, 6e5])
                               for i, (x, y) in enumerate([(0.4, 0.3), (0.4, -0.3), (-0.4, 0.3), (-0.4, -0.3)])])
    for extra in ({}, casing):
        model = rdm.Model(rotors=[rotor], bearings=bearings, **extra)
        assert np.isnan(rigid_support_critical_speed(model))
        screening = csr_screening(model, 300.0, 100.0)
        assert screening.csr == 0.0 and screening.region == "A"


def _result(q0, log_dec_at_qa=0.5, csr=None, factor=10.0):
    grid = np.linspace(0.0, factor, int(10 * factor) + 1)
    return Level1Result(speed=100.0, stations=(), shares=np.ones(1), cross_coupling=grid,
                        log_decrements=np.zeros_like(grid), frequencies_hz=np.zeros_like(grid), mode=1, qa=1.0,
                        q0=q0, log_decrement_at_qa=log_dec_at_qa, csr=csr)


def test_verdict_follows_the_rule_region_b_with_q0_over_qa_below_10_requires_level_2():
    """Level II when delta_A < 0.1, or Q0/Qa < 2, or 2 <= Q0/Qa < 10 with the point in Region B."""
    region_b = CsrScreening(100.0, 40.0, (20.0,))                   # CSR 2.5 above 2.46
    region_a = CsrScreening(100.0, 50.0, (20.0,))                   # CSR 2.0
    assert _result(5.0, csr=region_b).level2_required
    assert not _result(5.0, csr=region_a).level2_required
    assert not _result(5.0).level2_required                         # no density: the chart is not used
    assert not _result(12.0, csr=region_b).level2_required          # Q0/Qa >= 10
    assert not _result(np.nan, csr=region_b).level2_required        # Q0 beyond a sweep to 10 Qa
    assert _result(np.nan, csr=region_b, factor=5.0).level2_required  # beyond 5 Qa only: may be < 10
    assert _result(5.0, log_dec_at_qa=0.05, csr=region_a).level2_required
    assert "Region B" in _result(5.0, csr=region_b).verdict()


def test_level1_with_gas_density_places_the_machine(coarse):
    _, model = coarse
    mcs = 2.6 * _pinned_pinned_critical_speed()
    result = level1(model, mcs, ["shaft"], 2e3, gas_density=(10.0, 12.0))
    assert result.csr.csr == pytest.approx(2.6, rel=5e-4) and result.csr.region == "B"
    assert result.level2_required == (not (result.passes_log_decrement and result.passes_ratio)
                                      or result.ratio < 10)


@pytest.mark.parametrize("value", [0.0, -1.0, np.nan, np.inf, (1.0, 2.0, 3.0)])
def test_bad_gas_density_is_refused_by_name(shaft, value):
    _, model = shaft
    with pytest.raises(InputError, match="gas_density"):
        csr_screening(model, 100.0, value)


@pytest.mark.parametrize("extra, fragment", [
    (["--gas-density", "0"], "--gas-density"),
    (["--gas-density", "1,2,3"], "--gas-density"),
    (["--gas-density", "nan"], "--gas-density"),
    (["--gas-density", "10", "--machine", "turbine"], "--machine turbine"),
    (["--csr-plot", "c.png"], "--csr-plot"),
])
def test_command_line_refuses_bad_input_in_one_line(coarse, extra, fragment, capsys):
    path, _ = coarse
    assert main(["level1", str(path), "--speed", "3000", "--station", "shaft", "--qa", "2e3", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0] and "Traceback" not in err[0]


def test_command_line_draws_the_chart_and_reads_us_units(coarse, tmp_path, capsys):
    """--gas-density in lb/ft^3 with --units us (1 lb/ft^3 = 0.45359237 / 0.3048^3 kg/m^3)."""
    import matplotlib.pyplot as plt

    path, model = coarse
    rpm = 2.0 * _pinned_pinned_critical_speed() * 30 / np.pi
    out = tmp_path / "csr.png"
    assert main(["level1", str(path), "--speed", f"{rpm}", "--station", "shaft", "--qa", "11.42", "--units", "us",
                 "--gas-density", "1,3", "--csr-plot", str(out), "--quiet"]) == 0
    assert out.read_bytes().startswith(b"\x89PNG")
    screening = csr_screening(model, rpm * np.pi / 30, (0.45359237 / 0.3048 ** 3) * np.array([1.0, 3.0]))
    fig = screening.plot()
    line = fig.axes[0].lines[0]
    x, y = line.get_xdata(), line.get_ydata()
    np.testing.assert_allclose(y, csr_boundary(x), atol=1e-12)      # the line drawn is the line judged
    point = fig.axes[0].lines[1]
    assert point.get_xdata()[0] == pytest.approx(2 * 16.018463373960138)
    assert point.get_ydata()[0] == pytest.approx(2.0, rel=5e-4)
    plt.close(fig)
    capsys.readouterr()


def test_report_has_the_criterion_line_and_chart_when_a_gas_density_is_given(coarse, monkeypatch):
    import matplotlib.pyplot as plt

    from rotordyn_modal.report import ReportInputs, render
    from rotordyn_modal.report.collect import ReportData, _level1, model_summary
    from rotordyn_modal.report.render import render_html

    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: plt.close(fig) or "data:image/png;base64,")
    _, model = coarse
    mcs = 2.6 * _pinned_pinned_critical_speed()
    names = {}
    for density in (None, (10.0, 12.0)):
        inputs = ReportInputs(standard="api617", mcs=mcs, level1={"stations": ["shaft"], "qa": 2e3, "shares": None,
                                                                   "gas_density": density})
        data = ReportData(inputs, model, model_summary(model), ("level1",))
        _level1(data)
        names[density] = {c.name: c for c in data.criteria}
        html = render_html(data)
        assert ("Critical speed ratio chart" in html) == (density is not None)
    line = names[(10.0, 12.0)]["API 617 Level I: critical speed ratio"]
    assert line.verdict == "fail" and line.value == "2.6" and "Region B" in line.why and "11 kg/m³" in line.why
    assert "API 617 Level I: critical speed ratio" not in names[None]


@pytest.mark.parametrize("critical,density", [(np.nan, 11.0), (100.0 / 2.9, 75.0), (40.0, 20.0)],
                         ids=["rigid-rotor", "upper-right", "region-b"])
def test_the_machine_point_is_drawn_whole_and_uncovered(critical, density):
    """The machine's point on the rendered chart: a rigid rotor's CSR 0 lies on the bottom
    spine (its circle was clipped to a half); a point at CSR 2.9 and 75 kg/m³ lay under the
    legend. The circle is drawn whole (not clipped) and no legend or text box covers it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.level1 import plot_csr_chart

    screening = CsrScreening(100.0, critical, (density,))
    fig = plot_csr_chart(screening)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    point, = [line for line in ax.get_lines() if line.get_marker() == "o"]
    assert not point.get_clip_on()
    centre = ax.transData.transform((screening.density, screening.csr))
    radius = point.get_markersize() / 2 * fig.dpi / 72
    mark = matplotlib.transforms.Bbox.from_extents(*(centre - radius), *(centre + radius))
    assert fig.bbox.x0 <= mark.x0 and mark.x1 <= fig.bbox.x1 and fig.bbox.y0 <= mark.y0 and mark.y1 <= fig.bbox.y1
    covers = [ax.get_legend().get_window_extent(renderer)] + [t.get_window_extent(renderer) for t in ax.texts]
    assert not any(box.overlaps(mark) for box in covers)
    plt.close(fig)
