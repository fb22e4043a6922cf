"""Mode-shape bar charts say whose motion they show (issue 27 §3, redteam28's "Plotting").

``modes --plot`` and the report's modes figure of a machine of rigid bodies drew bars
``u_x`` ... ``θ_z`` without saying which body they belong to (gear_machine's and
counter_rotating's six coordinates are the stator's, its rotors rigidly attached to it;
motor_pump_on_mounts' sixteen are the stator's, the motor's and the pump's), and titled a mode
"none (ratio 0)" where the report's modes table says "no whirl" for the same mode.

The bodies are the model's own (its stator and its rotors, read from the model file), each body's
coordinates are those ``dof_names`` give it, and the table's wording is the report's modes table
(``report.render``), not the figure's code.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import numpy as np
import pytest
from matplotlib.patches import Rectangle
from matplotlib.text import Text

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SPEED = rdm.rpm(3000.0)


def _bodies(model) -> list[str]:
    """The model's bodies by name: its stator (when it has one) and every rotor."""
    return (["stator"] if model.stator is not None else []) + [r.name for r in model.rotors]


def _panels(fig):
    """The bar panels: the figure's axes titled 'mode N: ...'."""
    return [ax for ax in fig.axes if ax.get_visible() and ax.get_title().startswith("mode ")]


def _texts(ax):
    """Every non-empty text drawn with the panel (tick labels, its top axis', labels), its title
    left out (a body's name there would not label the bars)."""
    return [t for t in ax.findobj(Text) if t.get_text() and t.get_visible() and t is not ax.title]


@pytest.mark.parametrize("name", ["gear_machine", "counter_rotating", "motor_pump_on_mounts"])
def test_the_bars_name_every_body_of_the_model_over_its_own_bars(name):
    """Every panel's labels name every body of the model (a rotor without coordinates of its
    own, rigidly attached to the stator, named with the stator's bars), each body's name stands
    over its own bars (the columns ``dof_names`` gives it), and the units are said (m, rad)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / f"{name}.toml")
    result = rdm.modal(model, SPEED)
    fig = result.plot(modes=[1, 2, 6])              # three panels: every panel is labelled alike
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = _panels(fig)
    assert len(panels) == 3
    owners = [n.split(".")[0] for n in result.dof_names]
    for ax in panels:
        texts = _texts(ax)
        words = " ".join(t.get_text() for t in texts)
        missing = [body for body in _bodies(model) if not re.search(rf"\b{re.escape(body)}\b", words)]
        assert not missing, (name, ax.get_title(), missing, words)
        bars = [p for p in ax.patches if isinstance(p, Rectangle)]
        assert len(bars) == len(owners)
        for body in dict.fromkeys(owners):
            spans = [b.get_window_extent(renderer) for b, o in zip(bars, owners) if o == body]
            left, right = min(s.x0 for s in spans), max(s.x1 for s in spans)
            named = [t for t in texts if re.match(rf"{re.escape(body)}\b", t.get_text())]
            assert named, (name, body, words)
            centres = [(t.get_window_extent(renderer).x0 + t.get_window_extent(renderer).x1) / 2 for t in named]
            assert any(left <= c <= right for c in centres), (name, body, left, right, centres)
    everything = " ".join(t.get_text() for t in fig.findobj(Text))
    assert "[m]" in everything and "[rad]" in everything
    plt.close(fig)


@pytest.mark.parametrize("name", ["gear_machine", "counter_rotating"])
def test_the_panel_titles_say_the_whirl_as_the_report_table_does(name, monkeypatch):
    """The report's modes section of a rigid machine: each panel of its bar chart says the
    mode's whirl in the words of the table's whirl cell for that mode ('no whirl', not
    'none')."""
    import matplotlib.pyplot as plt

    import rotordyn_modal.report.render as render

    collect = importlib.import_module("rotordyn_modal.report.collect")   # the package exports a function of that name

    model = rdm.load_model(EXAMPLES / f"{name}.toml")
    data = collect.ReportData(collect.ReportInputs("api684", SPEED), model, {}, ("modes",))
    collect._modes(data)
    titles = []

    def fake(fig, dpi=110):
        titles.extend(ax.get_title() for ax in _panels(fig))
        plt.close(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", fake)
    html = render._modes(data, "si")
    body = html[html.index("<tbody>"):html.index("</tbody>")]
    rows = [[re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", body)]
    assert rows and len(titles) == len(rows)
    table = {int(row[0]): row[2] for row in rows}
    assert "no whirl" in table.values()             # the machines have modes without whirl
    for title in titles:
        number = int(title.split(":")[0].split()[1])
        whirl = title.split("\n")[1].split(" (")[0]
        assert whirl == table[number], (name, title, table[number])
    assert np.all([t.count("none") == 0 for t in titles])
