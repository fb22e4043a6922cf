"""``--units us`` for ``fit`` and ``study`` (issue 29 §6): what they print and draw in US
customary units, from SI results converted by the exact definitions written here (NIST SP 811
appendix B), the model files read and written SI. Round trips to 1e-12; the US output says the
same as the SI one (the same numbers times the exact factors)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.cli._units import key_kind, key_unit, key_value_in

ROOT = Path(__file__).resolve().parent.parent
#: exact definitions, not taken from the package
INCH, POUND, STANDARD_GRAVITY = 0.0254, 0.45359237, 9.80665
LBF = POUND * STANDARD_GRAVITY
#: one US unit in SI, by the unit shown
US_SIZE = {"lb": POUND, "lbf/in": LBF / INCH, "lbf s/in": LBF / INCH, "lb in²": POUND * INCH**2, "in": INCH,
           "lbf": LBF, "lbf in": LBF * INCH, "psi": LBF / INCH**2, "oz in": POUND / 16 * INCH,
           "lb/ft³": POUND / (12 * INCH) ** 3, "reyn": LBF / INCH**2}


def _six_by_six_mount():
    """A casing on one 6x6 mount (translations, rotations and their coupling) beside a 3-list one."""
    stiffness = np.diag([1e6, 2e6, 3e6, 4e4, 5e4, 6e4])
    stiffness[0, 4] = stiffness[4, 0] = 1e4
    return rdm.Model.from_dict({
        "stator": {"mass": 100.0, "inertia": [5.0, 6.0, 7.0], "center_of_mass": [0.0, 0.0, 0.0]},
        "suspensions": [{"name": "six", "position": [0.0, 0.0, -0.2], "stiffness": stiffness.tolist(),
                         "damping": (stiffness * 1e-3).tolist()},
                        {"name": "three", "position": [0.3, 0.0, -0.2], "stiffness": [1e5, 1e5, 2e5],
                         "maxwell_stiffness": [[1e4, 1e4, 2e4]], "maxwell_time": [0.01]}],
        "rotors": [{"name": "r", "mass": 10.0, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.1,
                    "diametral_inertia": 0.2, "speed_ratio": 1.0}]})


@pytest.mark.parametrize("key, unit", [
    ("stator.mass", "lb"), ("rotors.r.polar_inertia", "lb in²"), ("rotors.r.center_of_mass[2]", "in"),
    ("suspensions.three.stiffness", "lbf/in"), ("suspensions.three.stiffness[1]", "lbf/in"),
    ("suspensions.three.maxwell_stiffness[0]", "lbf/in"), ("suspensions.three.maxwell_time[0]", "s"),
    ("suspensions.six.stiffness[1][1]", "lbf/in"), ("suspensions.six.stiffness[4][4]", "lbf in"),
    ("suspensions.six.stiffness[0][4]", "lbf"), ("suspensions.six.stiffness[4][0]", "lbf"),
    ("suspensions.six.damping[2][2]", "lbf s/in"), ("suspensions.six.damping[4][4]", "SI"),
    ("suspensions.six.stiffness", "SI"), ("suspensions.six.stiffness[0]", "SI"), ("stator.inertia", "lb in²"),
])
def test_a_model_key_round_trips_through_us_units_by_its_quantity(key, unit):
    """Each key's value in its US unit is the SI value over the unit's exact size, and back to
    1e-12; keys of mixed units (a 6x6's whole matrix or row, N m s/rad) and keys without a US
    unit (s) stay as the model file gives them."""
    model = _six_by_six_mount()
    value = model.get(key)
    assert key_unit(key, "us", model) == unit
    shown = key_value_in(key, value, "us", model)
    size = US_SIZE.get(unit, 1.0)
    np.testing.assert_allclose(shown, np.asarray(value, dtype=float) / size, rtol=1e-15)
    back = key_value_in(key, shown, "us", model, inverse=True)
    np.testing.assert_allclose(back, value, rtol=1e-12)
    assert key_value_in(key, value, "si", model) is value


@pytest.mark.parametrize("field, unit", [("young_modulus", "psi"), ("density", "lb/ft³"), ("outer_diameter", "in"),
                                         ("amount", "oz in"), ("viscosity", "reyn"), ("pretension", "lbf"),
                                         ("speed_ratio", "-"), ("phase_deg", "deg")])
def test_the_fields_of_the_other_tables_have_their_us_unit(field, unit):
    assert key_unit(f"materials.steel.{field}" if field in ("young_modulus", "density") else f"x.y.{field}", "us") \
        == unit
    if unit in US_SIZE:
        assert key_value_in(f"x.{field}", 2.5, "us") == pytest.approx(2.5 / US_SIZE[unit], rel=1e-15)
        assert key_kind(f"x.{field}") is not None


# -- fit ------------------------------------------------------------------------------------------
def _fit_inputs(tmp_path):
    """The gear machine's receptance to its hammer at 39 lines of 1 Hz (the truth: a UFF header
    keeps that step exactly), and a start with the front-left mount 1.5 x too stiff and the
    casing 10 % too heavy (SI model file)."""
    from rotordyn_modal.analysis.frf import FRFResult
    from rotordyn_modal.io.measured import default_mapping
    from rotordyn_modal.io.uff import write_uff58

    true = rdm.load_model(ROOT / "examples" / "gear_machine.toml")
    res = rdm.frf(true, rdm.rpm(3000), np.linspace(2, 40, 39), inputs=["hammer-z"])
    measured = tmp_path / "measured.uff"
    write_uff58([FRFResult(**{**res.__dict__, "coherence": np.full(res.H.shape, 0.99)})], measured,
                default_mapping(true))
    start = tmp_path / "start.toml"
    rdm.save_model(true.scaled({"suspensions.mount-FL.stiffness": 1.5, "stator.mass": 1.1}), start)
    return true, start, measured


def _printed_parameters(text):
    """The rows of the fit's parameter table: key -> list of the cells after it."""
    lines = text.splitlines()
    rows = {}
    for line in lines[1:]:
        if not line.strip():
            break
        key, rest = line.split(None, 1)
        rows[key] = rest
    return lines[0].split(), rows


def _numbers(cell):
    return [float(x) for x in cell.strip("[]").split(",")]


def test_fit_prints_and_draws_in_us_units_and_writes_the_si_model(tmp_path, capsys, monkeypatch):
    """``--units us fit``: the start and fitted values of a mount's stiffness in lbf/in and of the
    casing's mass in lb are the SI model files' values over the exact units (6 digits printed),
    with a unit column; the fitted model file is SI (the truth); the overlay's magnitudes are in
    in/lbf, the SI FRFs times LBF / INCH."""
    import matplotlib.pyplot as plt

    true, start, measured = _fit_inputs(tmp_path)
    figures = []
    monkeypatch.setattr("rotordyn_modal.cli.fit.save_figure", lambda fig, args: figures.append(fig))
    out = tmp_path / "fitted.toml"
    keys = ["suspensions.mount-FL.stiffness", "stator.mass"]
    assert main(["--units", "us", "fit", str(start), "--measured", str(measured), "--params", ",".join(keys),
                 "--out", str(out), "--starts", "1", "--plot", str(tmp_path / "fit.png")]) == 0
    headers, rows = _printed_parameters(capsys.readouterr().out)
    assert headers == ["key", "start", "fitted", "factor", "std_relative", "unit"]
    fitted, begun = rdm.load_model(out), rdm.load_model(start)
    for key, unit in zip(keys, ("lbf/in", "lb")):
        np.testing.assert_allclose(fitted.get(key), true.get(key), rtol=1e-6)     # SI file: the truth
        cells = rows[key].rsplit(None, 3)[0]
        first, second = (cells.split("] [") if "[" in cells else cells.split())
        assert rows[key].endswith(f" {unit}")
        for cell, model in ((first, begun), (second, fitted)):
            np.testing.assert_allclose(_numbers(cell), np.ravel(model.get(key)) / US_SIZE[unit], rtol=5e-6)
    (fig,) = figures
    magnitude = fig.axes[0]
    assert magnitude.get_ylabel() == "|H| [in/lbf]"
    si = rdm.frf(fitted, rdm.rpm(3000), np.linspace(2, 40, 39), inputs=["hammer-z"])
    # the curves, not the stretches up to the peaks between computed frequencies (gid 'peak-top')
    drawn = [line.get_ydata() for line in magnitude.get_lines() if line.get_linestyle() == "-" and len(line.get_ydata())
             and line.get_gid() != "peak-top"]
    np.testing.assert_allclose(drawn, np.abs(si.H[:, 0, :]) * LBF / INCH, rtol=1e-9)
    plt.close("all")


# -- study ----------------------------------------------------------------------------------------
def _study_file(tmp_path, name, analysis, settings, *parameters):
    """``tmp_path / NAME.study.toml``: one ``[[parameters]]`` table per dict of ``parameters``, then
    ``[analyses.ANALYSIS]`` with ``settings`` (strings, numbers and lists: TOML writes them as JSON)."""
    import json

    def pairs(table):
        return "".join(f"{key} = {json.dumps(value)}\n" for key, value in table.items())

    spec = tmp_path / f"{name}.study.toml"
    spec.write_text("\n".join([*(f"[[parameters]]\n{pairs(p)}" for p in parameters),
                                f"[analyses.{analysis}]\n{pairs(settings)}"]), encoding="utf-8")
    return spec


def _us_study(tmp_path, model, spec, *extra):
    """``--units us study``'s --table (read back) and the same study's SI result from the API."""
    import pandas as pd

    table = tmp_path / "t.csv"
    assert main(["--units", "us", "study", str(ROOT / "examples" / model), "--spec", str(spec),
                 "--out", str(tmp_path / "r.nc"), "--table", str(table), *extra]) == 0
    return pd.read_csv(table), rdm.study(rdm.load_model(ROOT / "examples" / model), spec)


def _si_table(result):
    """The SI --table as the command writes it (15 significant digits since issue 29), read back."""
    import io

    import pandas as pd

    return pd.read_csv(io.StringIO(result.to_dataframe().to_csv(index=False, float_format="%.15g")))


def test_study_stability_map_in_us_units_says_what_the_si_one_says(tmp_path, capsys, monkeypatch):
    """A grid over a bearing's damping (lbf s/in) and the casing's mass (lb): the US table's
    parameter columns are the SI ones over the exact units, named with them, every other column
    the same; the map's axes are the SI axes over the same units, labelled with them."""
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    from rotordyn_modal.plotting import study as plotting

    spec = _study_file(tmp_path, "map", "stability", {"speeds_rpm": "0:30000:7"},
                       {"name": "damping A", "key": "suspensions.bearing-A.damping[1]", "values": [100.0, 300.0]},
                       {"name": "casing", "key": "stator.mass", "values": [30.0, 50.0]})
    figures, draw = [], plotting.plot_study_stability_map
    monkeypatch.setattr(plotting, "plot_study_stability_map", lambda *a, **k: figures.append(draw(*a, **k)) or figures[-1])
    monkeypatch.setattr(Figure, "savefig", lambda self, path, **k: Path(path).write_bytes(b"figure"))   # not drawn
    us, result = _us_study(tmp_path, "unstable_cross_coupled.toml", spec, "--plot-map", str(tmp_path / "map.png"),
                           "--quiet")
    si = _si_table(result)
    sizes = {"damping A": ("damping A_lbf_s_per_in", LBF / INCH), "casing": ("casing_lb", POUND)}
    assert list(us.columns) == [sizes.get(c, (c,))[0] for c in si.columns]
    for column, (renamed, size) in sizes.items():
        np.testing.assert_allclose(us[renamed], si[column] / size, rtol=1e-12)     # the CSV's every digit
        np.testing.assert_allclose(us[renamed] * size, si[column], rtol=1e-12)     # and back
    others = [c for c in si.columns if c not in sizes]
    assert us[others].equals(si[others])
    us_map, si_map = figures[0].axes[0], result.plot_stability_map().axes[0]
    assert (si_map.get_xlabel(), si_map.get_ylabel()) == ("damping A", "casing")
    assert (us_map.get_xlabel(), us_map.get_ylabel()) == ("damping A [lbf s/in]", "casing [lb]")
    si_mesh, us_mesh = (ax.collections[0].get_coordinates() for ax in (si_map, us_map))
    np.testing.assert_allclose(us_mesh[..., 0], si_mesh[..., 0] / (LBF / INCH), rtol=1e-12,
                               atol=1e-12 * np.abs(us_mesh[..., 0]).max())          # an edge at 0
    np.testing.assert_allclose(us_mesh[..., 1], si_mesh[..., 1] / POUND, rtol=1e-12)
    np.testing.assert_array_equal(us_map.collections[0].get_array(), si_map.collections[0].get_array())
    plt.close("all")


def test_study_unbalance_amplitudes_in_us_units(tmp_path, capsys):
    """The unbalance peak amplitudes of a study: in the US table (columns ending in _mil) and
    summary (rows marked (mil)) the SI numbers over the exact mil; a value parameter (the casing's
    mass) in lb, a factor (a scale grid) and the speeds unchanged."""
    size = INCH / 1000
    spec = _study_file(tmp_path, "unbalance", "unbalance", {"speeds_rpm": "500:3000:6", "quantity": "displacement"},
                       {"key": "stator.mass", "values": [110.0, 130.0]},
                       {"name": "stiffer", "key": "suspensions.mount-FL.stiffness", "scale": [1.0, 1.2]})
    us, result = _us_study(tmp_path, "fan_on_bearings.toml", spec)
    si = _si_table(result)
    printed = capsys.readouterr().out
    amplitudes = [c for c in si.columns if c.startswith("unbalance_peak_amplitude")]
    assert amplitudes
    renamed = {c: c + "_mil" for c in amplitudes} | {"stator.mass": "stator.mass_lb"}
    assert list(us.columns) == [renamed.get(c, c) for c in si.columns]
    for column in amplitudes:
        np.testing.assert_allclose(us[column + "_mil"], si[column] / size, rtol=1e-12)   # every digit written
    np.testing.assert_allclose(us["stator.mass_lb"], si["stator.mass"] / POUND, rtol=1e-12)
    same = [c for c in si.columns if c not in renamed]
    assert us[same].equals(si[same]) and "stiffer" in same and any("speed" in c for c in same)
    summary = result.summary().set_index("output")
    for column in amplitudes:
        row = next(line for line in printed.splitlines() if line.lstrip().startswith(f"{column} (mil)"))
        mean = float(row.split("(mil)")[1].split()[1])
        assert mean == pytest.approx(summary.loc[column, "mean"] / size, rel=1e-5)     # printed to 6 digits
