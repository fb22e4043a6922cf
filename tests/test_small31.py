"""Five small defects (issue 27 §1, §3, §4), each with one clear line or the right answer:

1. a ROSS file whose shaft elements repeat a node number ``n`` where ROSS would join no element
   to the next node (two pieces of shaft) or where the repeat shortens the shaft under a disk or
   bearing: the message names the file, the element, the repeated ``n`` and what was expected;
2. ``import-ross`` of a file that is no ROSS TOML save (JSON, ROSS's own JSON save, text, a model
   file of this package) says what it read and what it reads (exit 2);
3. a study whose grid or distribution range turns a mass or stiffness to zero or below is refused
   as the study is read (the study file, the parameter, the range, the model's reason), before
   any variant runs;
4. an outline in millimetres without its unit warns through the Python API too, once, naming
   its file;
5. the 3-D animation is framed on the whole period: every frame's drawn points lie inside the
   axes' limits, for a mode whose largest excursion is not at phase 0.
"""

from __future__ import annotations

import json
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
import tomli_w

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError, ModelWarning
from rotordyn_modal.io.ross_file import read_ross_rotor

ROOT = Path(__file__).resolve().parent.parent
ROSS = ROOT / "tests" / "data" / "ross"
EXAMPLES = ROOT / "examples"


def _one_line_error(capsys, code):
    assert code == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rotordyn-modal import-ross: error: "), err
    return lines[0]


# ------------------------------------------------------------------ 1. a repeated node number

def _rotor_example() -> dict:
    return tomllib.loads((ROSS / "rotor_example.toml").read_text())


def _with_n(data, key, n):
    data[key] = {**data[key], "n": n}
    return data


def test_a_repeated_shaft_n_that_leaves_a_node_without_an_element_names_the_element(tmp_path, capsys):
    """Shaft elements 0, 1, 1, 3, 4, 5 (element 2 given n = 1, as a typo): ROSS reads a repeated
    n as a parallel element over the same span, so no element would start at node 2 (ROSS would
    join elements 1 and 3 by no element: two pieces). The line names the element that repeats
    n = 1, the one that starts there first and the node left without an element (it said
    'ShaftElement n = 2: expected consecutive nodes', naming no element)."""
    data = _with_n(_rotor_example(), "ShaftElement_Shaft Element 2", 1)
    data = _with_n(data, "DiskElement_Disk 0", 1)
    path = tmp_path / "typo.toml"
    path.write_text(tomli_w.dumps(data))
    with pytest.raises(ModelError) as error:
        read_ross_rotor(path)
    message = str(error.value)
    assert message.startswith(f"{path}: [ShaftElement_Shaft Element 2] n = 1: expected "), message
    assert "[ShaftElement_Shaft Element 1]" in message and "node 2" in message and "parallel" in message
    line = _one_line_error(capsys, main(["import-ross", str(path), "--out", str(tmp_path / "m.toml")]))
    assert "[ShaftElement_Shaft Element 2] n = 1" in line and not (tmp_path / "m.toml").exists()


def test_a_repeated_shaft_n_that_shortens_the_shaft_under_a_bearing_says_why(tmp_path):
    """The last element given the n of the one before (4, 4): the shaft ends at node 5, so ROSS
    refuses the bearing at node 6 ('outside shaft'); the line says so and names the repeat."""
    data = _with_n(_rotor_example(), "ShaftElement_Shaft Element 5", 4)
    path = tmp_path / "short.toml"
    path.write_text(tomli_w.dumps(data))
    with pytest.raises(ModelError) as error:
        read_ross_rotor(path)
    message = str(error.value)
    assert message.startswith(f"{path}: [BearingElement_Bearing 1] n = 6: expected a node of the shaft, 0..5"), message
    assert "n = 4 is repeated" in message and "[ShaftElement_Shaft Element 4]" in message
    assert "[ShaftElement_Shaft Element 5]" in message and "\n" not in message


def test_a_repeated_shaft_n_of_another_length_names_the_node_and_both_elements(tmp_path):
    data = _with_n(_rotor_example(), "ShaftElement_Shaft Element 5", 4)
    data["ShaftElement_Shaft Element 5"]["L"] = 0.3
    data["BearingElement_Bearing 1"]["n"] = 5
    path = tmp_path / "length.toml"
    path.write_text(tomli_w.dumps(data))
    with pytest.raises(ModelError, match=r"\[ShaftElement_Shaft Element 5\] L = 0.3: expected the length 0.25 of "
                                         r"\[ShaftElement_Shaft Element 4\], which starts at the same node n = 4"):
        read_ross_rotor(path)


# ------------------------------------------------------------------ 2. a file that is no ROSS TOML save

def test_import_ross_of_json_says_what_it_read_and_what_it_reads(tmp_path, capsys):
    """It said "<file> = 'Invalid statement (at line 1, column 1)': expected valid TOML"."""
    path = tmp_path / "x.json"
    path.write_text(json.dumps({"rotor": "r", "speeds": [1, 2]}))
    line = _one_line_error(capsys, main(["import-ross", str(path), "--out", str(tmp_path / "m.toml")]))
    assert line.startswith(f"rotordyn-modal import-ross: error: {path}: <file> = 'JSON, not TOML"), line
    assert "Rotor.save('NAME.toml')" in line and "TOML file" in line and "ROSS 0.4 to 3.1" in line


def test_a_rotor_ross_saved_as_json_is_told_how_to_save_it_as_toml(tmp_path, capsys):
    """ROSS 2.1 and later write JSON when the name ends in .json (the same tables)."""
    path = tmp_path / "compressor.json"
    path.write_text(json.dumps(tomllib.loads((ROSS / "rotor_example.toml").read_text())))
    line = _one_line_error(capsys, main(["import-ross", str(path), "--out", str(tmp_path / "m.toml")]))
    assert "a rotor saved by ROSS as JSON" in line and "Rotor.load('compressor.json').save('compressor.toml')" in line


@pytest.mark.parametrize("text, said", [("hello\n", "no TOML: "), ("", "an empty file"),
                                        ("[stuff]\na = 1\n", "no ShaftElement tables (keys stuff)")])
def test_a_file_that_is_no_ross_save_says_what_is_read(tmp_path, capsys, text, said):
    path = tmp_path / "r.toml"
    path.write_text(text)
    line = _one_line_error(capsys, main(["import-ross", str(path), "--out", str(tmp_path / "m.toml")]))
    assert said in line and "Rotor.save('NAME.toml')" in line, line


def test_a_model_file_given_to_import_ross_is_named_as_one(tmp_path, capsys):
    model = EXAMPLES / "fan_on_bearings.toml"
    line = _one_line_error(capsys, main(["import-ross", str(model), "--out", str(tmp_path / "m.toml")]))
    assert "a model file of rotordyn-modal" in line and f"rotordyn-modal check {model}" in line


# ------------------------------------------------------------------ 3. a study's range through zero

@pytest.fixture(scope="module")
def fan():
    return rdm.load_model(EXAMPLES / "fan_on_bearings.toml")


def _study_file(tmp_path, parameter: str) -> Path:
    path = tmp_path / "s.study.toml"
    samples = "samples = 4\n" if "distribution" in parameter else ""
    path.write_text(f"{samples}[[parameters]]\n{parameter}\n[analyses.modes]\nspeed_rpm = 1000.0\n")
    return path


@pytest.mark.parametrize("parameter, key, shown", [
    ('key = "rotors.fan.mass"\nname = "fan mass"\nscale = "-0.5:1.5:5"', "scale", "'-0.5:1.5:5'"),
    ('key = "rotors.fan.mass"\nname = "fan mass"\nvalues = [-2.0, 11.0]', "values", "[-2.0, 11.0]"),
    ('key = "rotors.fan.mass"\nname = "fan mass"\ndistribution = "uniform"\napply = "scale"\nlow = -0.2\nhigh = 1.2',
     "low", "-0.2"),
    ('key = "rotors.fan.mass"\nname = "fan mass"\ndistribution = "normal"\nmean = 11.0\nstd = 4.0\n'
     'truncate = [-1.0, 30.0]', "truncate", "[-1.0, 30.0]"),
])
def test_a_range_through_zero_of_a_mass_is_refused_as_the_study_is_read(fan, tmp_path, monkeypatch, parameter,
                                                                         key, shown):
    """The model refuses a negative mass (checked here on the model itself); the study ran every
    variant and recorded those as failed (exit 0). Now the file is refused as it is read, naming
    it, the parameter, the range and the model's reason, before any variant runs."""
    from rotordyn_modal.study import StudyError, execution

    with pytest.raises(ModelError):
        fan.with_values({"rotors.fan.mass": -1e-3})
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a variant ran"))
    spec = _study_file(tmp_path, parameter)
    with pytest.raises(StudyError) as error:
        rdm.study(fan, str(spec))
    message = str(error.value)
    assert message.startswith(f"{spec}: [[parameters]] 1 {key} = {shown}: expected "), message
    assert "'fan mass'" in message and "[rotors.fan] mass" in message and "expected a finite number > 0" in message


def test_the_command_refuses_the_range_in_one_line_and_writes_nothing(tmp_path, capsys):
    spec = _study_file(tmp_path, 'key = "rotors.fan.mass"\nscale = "-0.5:1.5:5"')
    out = tmp_path / "r.nc"
    code = main(["study", str(EXAMPLES / "fan_on_bearings.toml"), "--spec", str(spec), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and f"{spec}: [[parameters]] 1 scale" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.study.toml"]


@pytest.mark.parametrize("parameter", [
    # the ends of a distribution are drawn with probability 0: a mass stays above zero
    'key = "rotors.fan.mass"\ndistribution = "uniform"\napply = "scale"\nlow = 0.0\nhigh = 1.5',
    'key = "rotors.fan.mass"\ndistribution = "normal"\nmean = 11.0\nstd = 4.0\ntruncate = [0.0, inf]',
    # a coordinate may be negative: the model takes it
    'key = "rotors.fan.center_of_mass[0]"\nscale = "-1:1:3"',
    # a product of inertia may change sign
    'key = "stator.inertia[0][2]"\nvalues = [-0.4, 0.0, 0.4]',
])
def test_a_range_the_model_takes_is_read(fan, tmp_path, parameter):
    from rotordyn_modal.study import read_study

    definition = read_study(_study_file(tmp_path, parameter), fan)
    assert len(definition.parameters) == 1


# ------------------------------------------------------------------ 4. an outline in millimetres

_SKID = "{header}\n-500,-400,-200\n500,-400,-200\n500,400,-200\n-500,400,-200\n-500,-400,-200\n"


@pytest.fixture(scope="module")
def fan_modes(fan):
    return rdm.modal(fan, 1000 * np.pi / 30)


def _drawn(result, model, outline):
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mode_shape_3d(result, model, 1, outline=outline)
    return [str(w.message) for w in caught if issubclass(w.category, ModelWarning)]


@pytest.mark.parametrize("header, warned", [("x,y,z", True), ("x [mm],y [mm],z [mm]", False)])
def test_an_outline_in_millimetres_warns_through_the_python_api(fan, fan_modes, tmp_path, header, warned):
    """The skid is 1000 x 800 mm; the fan's drawing (housing, rotors, mounts) is under 1.1 m, so
    1000 'metres' are more than 30 times it. The CLI alone warned; the Python API said nothing."""
    from rotordyn_modal.analysis.mode_shapes import machine_outline
    from rotordyn_modal.io.outline import read_outline

    path = tmp_path / "skid.csv"
    path.write_text(_SKID.format(header=header))
    points = read_outline(path)
    span = np.nanmax(np.ptp(np.asarray(points), axis=0))
    assert span == pytest.approx(1000.0 if warned else 1.0)
    assert machine_outline(fan).size < 1.1      # the machine's own drawing, without the outline
    said = _drawn(fan_modes, fan, points)
    assert len(said) == int(warned), said
    if warned:
        assert said[0].startswith(f"{path}: the outline spans 1000 m") and "mm" in said[0]
        # the same points as a plain array: the warning without a file's name
        plain = _drawn(fan_modes, fan, np.asarray(points))
        assert len(plain) == 1 and plain[0].startswith("the outline spans 1000 m")


def test_the_command_line_warns_once(tmp_path, capsys):
    path = tmp_path / "skid.csv"
    path.write_text(_SKID.format(header="x,y,z"))
    code = main(["modes", str(EXAMPLES / "fan_on_bearings.toml"), "--speed", "1000", "--shape", "1",
                 "--outline", str(path), "--plot", str(tmp_path / "s.png")])
    err = capsys.readouterr().err
    assert code == 0 and sum("the outline spans" in line for line in err.splitlines()) == 1, err


# ------------------------------------------------------------------ 5. the animation's frame

def _reach(view, phases):
    """Per-axis lowest and highest coordinate [m] of every drawn body point over ``phases``
    [rad], shape (2, 3): points at ``p + Re(d exp(i phase))``, computed here from the motion."""
    moved = np.concatenate([b.vertices[None] + np.real(d[None] * np.exp(1j * np.asarray(phases))[:, None, None])
                            for b, d in zip(view.outline.bodies, view.body_motion)], axis=1).reshape(-1, 3)
    return np.array([moved.min(axis=0), moved.max(axis=0)])


def _outside(axes, lines, limits):
    """How far [fraction of the frame] the farthest point of ``lines`` lies outside ``limits``."""
    worst = 0.0
    for data in lines:
        data = data[:, ~np.isnan(data).any(axis=0)]
        if data.size:
            worst = max(worst, float(np.max(np.maximum(limits[:, :1] - data, data - limits[:, 1:]))))
    return worst / (limits[0, 1] - limits[0, 0])


def test_every_frame_of_the_animation_lies_inside_its_axes(fan):
    """The fan's elliptic forward mode 10 at 3000 rpm (whirl ratio about 0.7), drawn at three times
    the default scale (``result.animate(..., scale=...)``): over the period its points reach
    further than the drawing at phase 0 and at rest (checked on the motion itself), and the frame
    was set on those alone, so at half a period the drawing left the axes by 8 % of their width.
    (At the default scale, the largest motion 15 % of the machine, the frame's margin of 15 %
    held every phase of the examples' modes.)"""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import _arrow_segments, animate_mode_shape

    result = rdm.modal(fan, 3000 * np.pi / 30)
    view = mode_shape_3d(result, fan, 10, scale=3 * mode_shape_3d(result, fan, 10).scale)
    phases = 2 * np.pi * np.arange(24) / 24
    rest = np.concatenate([b.vertices for b in view.outline.bodies])
    at_zero = np.concatenate([rest, *view.at_phase(0.0)])
    seen = np.array([at_zero.min(axis=0), at_zero.max(axis=0)])   # what a frame of phase 0 holds
    cycle = _reach(view, phases)
    assert np.any(cycle[0] < seen[0] - 0.05) or np.any(cycle[1] > seen[1] + 0.05)   # by 5 cm or more
    assert 0.3 < view.whirl_ratio < 0.95 and view.whirl == "forward"               # elliptic, not circular
    animation = animate_mode_shape(view, frames=24)
    fig = animation._fig
    try:
        ax, flat = fig.axes[0], fig.axes[1:4]
        for k, phase in enumerate(phases):
            animation._func(k)                                  # draws frame k, as the writers do
            limits = np.array([ax.get_xlim(), ax.get_ylim(), ax.get_zlim()])
            lines = [np.array(line.get_data_3d(), float) for line in ax.get_lines() if hasattr(line, "get_data_3d")]
            assert lines and _outside(ax, lines, limits) <= 0.0, (k, _outside(ax, lines, limits))
            arrows = _arrow_segments(view, phase).reshape(-1, 3).T
            assert _outside(ax, [arrows], limits) <= 0.0, k
            for panel in flat:
                limits = np.array([panel.get_xlim(), panel.get_ylim()])
                drawn = [np.array(line.get_data(), float) for line in panel.get_lines()]
                assert _outside(panel, drawn, limits) <= 0.0, (k, panel.get_title())
    finally:
        animation._draw_was_started = True                      # no 'deleted without rendering' warning
        plt.close(fig)
