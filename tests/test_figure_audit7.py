"""Figures of the seventh audit (issue 27, section 3: figures that cannot mislead), measured on
the drawn figure, independent of the code that draws it: the 3-D mode shapes of ``modes
--shape``, the model-over-measurement FRF of ``frf --measured``, the study figures and the
run-up of ``simulate --ramp``.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("model, mode", [("spring_block_rotor.toml", 1), ("fan_on_bearings.toml", 5)])
def test_mode_shape_legend_names_every_displaced_colour(model, mode):
    """The legend's 'displaced' entries show exactly the colours the displaced bodies are drawn
    in: a machine of rotors only (the spring block's rotor, the compressor's shaft: orange) had
    one blue 'displaced' entry and no orange one; a stator (blue) and rotors (orange) get one
    entry each."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    machine = rdm.load_model(EXAMPLES / model)
    view = mode_shape_3d(rdm.modal(machine, rdm.rpm(3000.0)), machine, mode)
    fig = plot_mode_shape(view, orbits=False, labels=False, projections=False)
    ax = fig.axes[0]
    drawn = {matplotlib.colors.to_hex(line.get_color()) for line in ax.get_lines()
             if str(line.get_gid()).startswith("displaced") and not str(line.get_gid()).startswith("displaced-")
             or str(line.get_gid()).startswith("displaced-bracket")}
    keyed = {matplotlib.colors.to_hex(handle.get_color()) for handle in ax.get_legend().legend_handles
             if "displaced" in handle.get_label()}
    assert drawn and keyed == drawn


@pytest.fixture(scope="module")
def gear_frf():
    """The gear machine's accelerances at standstill, 1-60 Hz (60 frequencies), and a
    'measurement' equal to them but for a phase error of +-2 deg, alternating."""
    import dataclasses

    model = rdm.frf(rdm.load_model(EXAMPLES / "gear_machine.toml"), 0.0, np.linspace(1.0, 60.0, 60),
                    quantity="accelerance")
    error = np.exp(1j * np.radians(2.0) * (-1.0) ** np.arange(60))
    return model, dataclasses.replace(model, H=model.H * error)


def _phase_curves(ax):
    """{colour: (model line's x, y), measured dots' x, y} of an FRF phase panel."""
    lines, dots = {}, {}
    for line in ax.get_lines():
        colour = matplotlib.colors.to_hex(line.get_color())
        xy = (np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
        (dots if line.get_linestyle() in ("None", "", " ") else lines)[colour] = xy
    return lines, dots


def test_frf_phase_lines_do_not_jump_across_the_panel(gear_frf):
    """A phase that wraps from -180 to 180 deg is not joined by a line across the panel (it
    read as a curve of its own crossing the others): no segment drawn between neighbouring
    frequencies of a model phase line spans more than 180 deg; the green accelerance
    (acc-side-y / hammer-z) wraps near 12 Hz."""
    model, measured = gear_frf
    fig = model.plot(measured=measured)
    lines, _ = _phase_curves(fig.axes[1])
    assert len(lines) >= 3
    wrapped = 0
    for colour, (x, y) in lines.items():
        finite = np.isfinite(y)
        steps = np.abs(np.diff(y))[finite[1:] & finite[:-1]]
        assert np.all(steps <= 180.0), colour
        wrapped += np.sum(~finite[1:-1])
    assert wrapped >= 1                                  # a wrap is there, drawn as a break


def test_measured_phase_lies_on_its_model_line(gear_frf):
    """A measurement within 2 deg of the model everywhere is drawn within 2 deg of the model's
    line at every frequency, also where the phase is near +-180 deg (the accelerances below
    the first mode): the dots of -179 deg under a line at 179 deg stood at the panel's other
    edge, 358 deg away, reading as another curve."""
    model, measured = gear_frf
    fig = model.plot(measured=measured)
    lines, dots = _phase_curves(fig.axes[1])
    near_180 = 0
    for colour, (x, y) in dots.items():
        lx, ly = lines[colour]
        keep = np.isfinite(ly)
        if not keep.any():                              # round-off: no phase line drawn
            continue
        on_line = np.interp(x, lx[keep], ly[keep])     # same frequencies: the line's own points
        difference = np.abs((y - on_line))
        assert np.all(difference <= 2.0 + 1e-9), (colour, x[difference > 2.0 + 1e-9])
        near_180 += np.sum(np.abs(on_line) > 175.0)
    assert near_180 >= 20
