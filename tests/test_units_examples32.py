"""Issue 29 §6/§7 for every example: "a report in US units says the same as the SI one", and the
command line's outputs in US units are its SI outputs converted.

The report: each model of examples/ is reported with the standard its kind of machine takes (the
table of ``tests/test_report_browser_all.py``, the journal rotor's API 617 with Level I of
``tests/test_report.py``), cheaply (``--points 15``, a 5-point stiffness grid), its figures faked
(their texts kept, no PNG drawn). The analyses run once (the command line, SI page); the US page is
rendered from the same results. The two pages are compared item by item with the rules of
``tests/test_report_units.py`` (same words; every number alike or the SI one times the exact factor
of its unit, NIST SP 811, to the digits both show), and so are the texts of every figure (tick
labels aside: their values differ by design); no SI unit is left on a US page or figure.

The command line: ``critical-speeds``, ``modes --speed``, ``campbell``, ``unbalance`` and
``static`` on every example in both systems, their printed tables and sentences compared by the
same rules (each table cell by its column's unit or its row's ``unit``), their CSVs back in SI to
1e-12 (the helpers of ``tests/test_csv_round_trip29.py``), every CSV column naming its unit; and
``static``'s loads typed in US units (``--force``, ``--moment``, ``--transmitted-power``) against
the same loads typed in SI.

One test per example: pytest-xdist spreads them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from test_csv_round_trip29 import ENDINGS, ROW_UNITS, UNITLESS, _back_to_si, share_analyses
from test_csv_round_trip29 import _same as _same_table
from test_report import CASES as REPORT_CASES
from test_report import MCS_RPM
from test_report_browser_all import EXAMPLES as BROWSER_EXAMPLES
from test_report_units import IN, NEUTRAL, SI_ONLY, _compare, _same, _visible

from rotordyn_modal.cli import main

ROOT = Path(__file__).resolve().parent.parent

#: example -> (standard, options): the browser check's, and the journal rotor's of test_report
REPORTS = dict(BROWSER_EXAMPLES)
REPORTS["journal_rotor"] = (REPORT_CASES["journal_rotor"][0], ["--mcs", str(MCS_RPM), *REPORT_CASES["journal_rotor"][1]])

#: a figure's tick label: a number or a mathtext power of ten (their values differ between systems)
_TICK = re.compile(r"\s*(?:\$\\mathdefault\{[^$]*\}\$|[−-]?\d+(?:\.\d*)?(?:e[-+]?\d+)?)\s*")
#: the unit kinds a figure's axis may name in brackets, with the prefixes its scale picks
_AXIS_KINDS = {
    "stiffness": ({"N/m", "kN/m", "MN/m", "GN/m"}, {"lbf/in", "klbf/in", "Mlbf/in"}),
    "vibration": ({"µm", "mm", "m", "nm"}, {"mil", "in"}),
    "velocity": ({"mm/s", "m/s"}, {"in/s"}),
    "force": ({"N", "kN"}, {"lbf", "klbf"}),
    "moment": ({"N m", "kN m"}, {"lbf in", "klbf in"}),
    "stress": ({"MPa", "Pa"}, {"psi", "ksi"}),
    "mass": ({"kg"}, {"lb"}),
}
#: an SI unit named on a figure of a US page (the CSR chart's second density axis aside)
_SI_ON_FIGURE = re.compile(r"µm|mm/s|\bN/m\b|\bMPa\b|\[(?:N|N m|kg|m|m/s|Pa|mm|kN/m|MN/m|GN/m)\]")


def _fake_png(figures):
    """``render.figure_png`` keeping each figure's texts (a list of strings), drawing nothing."""
    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt
        from matplotlib.text import Text

        figures.append([t.get_text() for t in fig.findobj(Text) if t.get_text().strip()])
        plt.close(fig)
        return "data:image/png;base64,"
    return fake


def _pages(name, folder):
    """(SI page, US page, SI figures' texts, US figures' texts) of ``name``'s report: the analyses
    run once by the command line (which writes the SI page); the US page rendered from them."""
    import rotordyn_modal.report as report
    from rotordyn_modal.report import render

    standard, options = REPORTS[name]
    out, captured, si_figures, us_figures, collect = folder / f"{name}.html", [], [], [], report.collect
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(report, "collect", lambda *a, **k: captured.append(collect(*a, **k)) or captured[-1])
        patch.setattr(render, "figure_png", _fake_png(si_figures))
        grid = ["--stiffness", "1e5:1e10:5"] if standard != "iso" else []     # the ISO report has no UCS map
        assert main(["report", str(ROOT / "examples" / f"{name}.toml"), "--standard", standard, "--points", "15",
                     *grid, "--out", str(out), "--quiet", *options]) == 0
        patch.setattr(render, "figure_png", _fake_png(us_figures))
        us = render.render_html(captured[0], date="DATE", units="us")
    si = re.sub(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", "DATE", out.read_text(encoding="utf-8"))
    return si, us, si_figures, us_figures


def _axis_units(si, us):
    """The texts with their bracketed units replaced by ``[#]``, after checking each pair names
    one kind, SI on the SI side and US on the US side (or one neutral unit in both)."""
    a, b = re.findall(r"\[([^\]]+)\]", si), re.findall(r"\[([^\]]+)\]", us)
    assert len(a) == len(b), (si, us)
    for x, y in zip(a, b):
        x, y = (u.replace(" pk-pk", "").replace(" RMS", "") for u in (x, y))
        assert x == y and not any(x in kinds[0] for kinds in _AXIS_KINDS.values()) \
            or any(x in s and y in u for s, u in _AXIS_KINDS.values()), (si, us)
    return tuple(re.sub(r"\[[^\]]+\]", "[#]", t) for t in (si, us))


def _same_figure(si, us, where):
    """The distinct texts of two figures (tick labels aside) correspond one to one: equal, or the
    same words with every number alike or converted exactly (``_compare``). Distinct: a label
    placed beside a line where it finds room is also in the legend, and room depends on the
    axis's values; the speeds of crossings whose circles overlap share one label, '52517/56625/62212',
    or not, as the labels' widths leave room (the UCS map of motor_pump_on_mounts: shared in SI,
    apart in US): split, and like a lone speed's label (a number) left out with the ticks."""
    si, us = (list(dict.fromkeys(part for t in texts for part in (t.split("/") if re.fullmatch(r"\d+(?:/\d+)+", t)
                                                                  else [t]) if not _TICK.fullmatch(part)))
              for texts in (si, us))
    assert len(si) == len(us), (where, set(si) ^ set(us))
    left = list(us)
    for text in si:
        if text in left:
            left.remove(text)
            continue
        for other in left:
            try:
                _compare(*_axis_units(text, other), None, set())
            except AssertionError:
                continue
            left.remove(other)
            break
        else:
            raise AssertionError(f"{where}: no US text says {text!r} (left: {left})")


def test_every_example_has_its_report_compared():
    """No model of examples/ is left out (a new example must be added to the browser check)."""
    models = {p.stem for p in (ROOT / "examples").glob("*.toml") if not p.stem.endswith(".study")}
    assert models == set(REPORTS)


@pytest.mark.parametrize("name", sorted(REPORTS))
def test_the_us_report_of_every_example_says_what_the_si_one_says(name, tmp_path):
    si_page, us_page, si_figures, us_figures = _pages(name, tmp_path)
    si, us = _visible(si_page), _visible(us_page)
    assert len(si) == len(us)
    seen = set()
    for (text_si, context_si), (text_us, context_us) in zip(si, us):
        if text_si.startswith("rotordyn-modal "):           # the command line as given
            continue
        context = (context_si, context_us) if context_si else None
        if context_si in NEUTRAL or context_si == context_us:
            context = None
        _compare(text_si, text_us, context, seen)
    assert ("kg", "lb") in seen                               # the model's masses, at least
    assert not [(unit, text) for text, _ in us for unit in SI_ONLY
                if re.search(rf"(?:\d |\[){re.escape(unit)}(?![\w/²³])", text)]
    assert len(si_figures) == len(us_figures) > 0
    for k, (a, b) in enumerate(zip(si_figures, us_figures)):
        _same_figure(a, b, f"{name} figure {k + 1}")
        for text in b:
            found = _SI_ON_FIGURE.search(text.replace("[kg/m³]", ""))
            assert found is None, (name, k + 1, text)


def test_the_mode_shape_bars_in_us_units_divide_inches():
    """The participation bars of a US page or ``modes --units us --plot``: each translation in
    inches (the SI metres / 0.0254, exact), each rotation in radians, over the mode's largest;
    the axis says '[in]'. They said '|u| [m]' on a US page, the bars the SI ones."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from rotordyn_modal.analysis.modal import modal
    from rotordyn_modal.io import load_model

    result = modal(load_model(ROOT / "examples" / "motor_fan_minimal.toml"), 3000 * np.pi / 30)
    translation = np.array([name.rsplit(".", 1)[1].startswith("u") for name in result.dof_names])
    assert translation.any() and not translation.all()
    numbers = [1, 2, 3]
    fig = result.plot(modes=numbers, units="us")
    try:
        for number, ax in zip(numbers, fig.axes):
            shape = np.abs(result.shapes[np.nonzero(result.oscillatory)[0][number - 1]])
            inches = np.where(translation, shape / IN, shape)
            heights = [p.get_height() for p in ax.patches if isinstance(p, Rectangle)]
            np.testing.assert_allclose(heights, inches / inches.max(), rtol=1e-12)
        assert fig.axes[0].get_ylabel().startswith("|u| [in], |θ| [rad]")
    finally:
        plt.close(fig)



def test_modes_plot_draws_the_bars_in_inches_with_units_us(monkeypatch, tmp_path):
    """``modes --units us --plot`` (the bars, without --shape) is the chart of ``units='us'``."""
    import matplotlib.pyplot as plt

    import rotordyn_modal.cli.modes as command

    drawn = []
    monkeypatch.setattr(command, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    for system in ("si", "us"):
        assert main(["--units", system, "modes", str(ROOT / "examples" / "motor_fan_minimal.toml"), "--speed", "3000",
                     "--plot", str(tmp_path / "bars.png"), "--quiet"]) == 0
    assert [fig.axes[0].get_ylabel().partition(",")[0] for fig in drawn] == ["|u| [m]", "|u| [in]"]
    plt.close("all")

# ---- the command line: every example's outputs in both systems ----

EXAMPLE_FILES = sorted(p.stem for p in (ROOT / "examples").glob("*.toml") if not p.stem.endswith(".study"))
_NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?$")
#: the units a printed sentence names in a list, without a number ("checks (...; m, m/s)")
_UNIT_WORDS = re.compile(r"(?<=; |, )(?:m/s²|m/s|m|N m|N|lbf in|lbf|mil|in/s|in|g)(?![\w/²])")


def _columns(header):
    """(name, end) of each column of a printed (pandas, right-aligned) table's header line."""
    return [(m.group(), m.end()) for m in re.finditer(r"\S+", header)]


def _column_at(columns, end):
    """The column whose right edge is at or right of ``end`` (right-aligned cells), nearest."""
    return next((name for name, right in columns if right >= end), None)


def _header(line):
    words = line.split()
    return len(words) > 1 and not any(_NUMBER.match(w) for w in words) and all(
        re.fullmatch(r"[\w\[\],:.|-]+", w) for w in words)


def _factor(si_column, us_column, row_unit):
    """The factor from the SI column's number to the US column's: by the US column's unit
    ending (the SI one's matching it), by the row's ``unit`` for the columns without a unit
    in their name, else 1."""
    for ending, (si_endings, size) in ENDINGS.items():
        if us_column.endswith(ending):
            assert any(us_column[:-len(ending)] + e == si_column for e in si_endings), (si_column, us_column)
            return 1.0 / size
    assert si_column == us_column, (si_column, us_column)
    if row_unit and us_column.split("_")[0] in UNITLESS + ("response",):     # a clearance's unscaled response
        return 1.0 / ROW_UNITS[row_unit]
    return 1.0


def _same_printout(si_text, us_text, what):
    """The printed SI and US outputs say the same: line by line, each table's cells alike or
    converted exactly (by their columns' units, or the row's ``unit``) to the digits printed,
    each sentence's numbers as ``_compare`` (test_report_units) checks them, the units named
    without a number the only other difference."""
    si_lines, us_lines = si_text.splitlines(), us_text.splitlines()
    assert len(si_lines) == len(us_lines), what
    columns = None
    for si, us in zip(si_lines, us_lines):
        if _header(si) and _header(us):
            columns = (_columns(si), _columns(us))
            assert len(si) == columns[0][-1][1] and len(us) == columns[1][-1][1], (what, si, us)
            continue
        if si == us:
            continue
        words_si, words_us = list(re.finditer(r"\S+", si)), list(re.finditer(r"\S+", us))
        if columns and len(si) == len(columns[0][-1][1] * " ") and len(us) == columns[1][-1][1]:     # a row (padded)
            row_unit = None
            if columns[1][-1][0] == "unit" and columns[0][-1][0] != "unit":
                row_unit = us[columns[1][-2][1]:].strip()
                words_us = [w for w in words_us if w.start() < columns[1][-2][1]]
            assert [w.group() for w in words_si if not _NUMBER.match(w.group())] == \
                [w.group() for w in words_us if not _NUMBER.match(w.group())], (what, si, us)
            numbers_si = [w for w in words_si if _NUMBER.match(w.group())]
            numbers_us = [w for w in words_us if _NUMBER.match(w.group())]
            assert len(numbers_si) == len(numbers_us), (what, si, us)
            for a, b in zip(numbers_si, numbers_us):
                factor = _factor(_column_at(columns[0], a.end()), _column_at(columns[1], b.end()), row_unit)
                if factor == 1.0:
                    assert a.group() == b.group(), (what, si, us)
                else:
                    assert _same(a.group(), b.group(), factor), (what, si, us, a.group(), b.group())
            continue
        columns = None
        _compare(_UNIT_WORDS.sub("#u", si), _UNIT_WORDS.sub("#u", us), None, set())


#: the sub-commands of issue 29 §6 run on every example (cheap grids), with the CSV they write
_COMMANDS = {"critical-speeds": ["--speeds", "100:6000:13"], "modes": ["--speed", "3000"],
             "campbell": ["--speeds", "100:6000:5"],
             "unbalance": ["--speeds", "1000:5000:3", "--mcs", "5000", "--forces", "all", "--amplitude", "pk-pk"],
             "static": ["--speed", "3000"]}
#: the columns of their CSVs that have no unit in any system (ratios, counts, names; ``modes``'
#: ``real_part`` is the eigenvalue's, 1/s in both, as the spec names it); ``*_energy``: a body's
#: share of a mode's energy (a fraction); every other
#: column's name ends in its unit (``_rpm``, ``_hz``, ``_deg`` ...) or has its row's ``unit``
_NO_UNIT = {"source", "order", "mode", "whirl", "whirl_ratio", "damping_ratio", "mode_at_speed", "log_decrement",
            "real_part", "output", "table", "kind", "name", "body", "on", "eccentricity", "case", "utilization", "side",
            "unit"}
_UNIT_ENDINGS = ("_rpm", "_hz", "_deg", "_rad", "_m", "_N", "_Nm", "_Pa", "_in", "_lbf", "_lbfin", "_psi")


def _printed(argv):
    """Exit code, stdout and stderr of the command line."""
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exit_:
            code = exit_.code
    return code, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("example", EXAMPLE_FILES)
def test_every_example_prints_and_writes_the_same_in_us_units(example, tmp_path, monkeypatch, shared_analyses):
    """``critical-speeds``, ``modes --speed``, ``campbell``, ``unbalance`` and ``static`` run in SI
    and in US units: the same exit code; printed tables and sentences (stdout and stderr) alike or
    converted exactly to the digits printed; every CSV back in SI (its columns times their units)
    the SI one to 1e-12; where nothing has a unit to convert (critical speeds, modes, Campbell
    tables) the files are the same bytes; every column of every CSV names its unit (or has none)."""
    import pandas as pd

    monkeypatch.setenv("NUMBA_NUM_THREADS", "1")
    share_analyses(shared_analyses)          # each analysis computed once for both systems
    written = []
    for command in _COMMANDS:
        outs = {s: tmp_path / f"{command}.{s}.csv" for s in ("si", "us")}
        runs = {s: _printed(["--units", s, command, str(ROOT / "examples" / f"{example}.toml"), *_COMMANDS[command],
                             "--out", str(outs[s])]) for s in ("si", "us")}
        assert runs["si"][0] == runs["us"][0], (example, command, runs)
        if runs["si"][0]:
            assert runs["si"][0] == 2 and runs["si"][2] == runs["us"][2], (example, command)      # refused alike
            continue
        _same_printout(runs["si"][1], runs["us"][1], f"{example} {command} stdout")
        _same_printout(runs["si"][2], runs["us"][2], f"{example} {command} stderr")
        si, us = (pd.read_csv(outs[s]) for s in ("si", "us"))
        if command in ("critical-speeds", "modes", "campbell"):
            assert outs["si"].read_bytes() == outs["us"].read_bytes(), (example, command)
        else:
            _same_table(si, _back_to_si(us, list(si.columns)), f"{example} {command}")
        for column in us.columns:
            assert column in _NO_UNIT or column.endswith(_UNIT_ENDINGS + ("_energy",)) or column.split("_")[0] in UNITLESS \
                and "unit" in us, (example, command, column)
        written.append(command)
    assert {"critical-speeds", "modes", "campbell", "static"} <= set(written), written


def _us_loads(example):
    """(US options, the SI options of the same doubles) of ``static``: a force at the last rotor's
    centre of mass and a moment on it, the power of every transmission where it has a force (a
    gear; a belt with its pulley's radius)."""
    from rotordyn_modal.io import load_model
    from rotordyn_modal.units import from_system

    model = load_model(ROOT / "examples" / f"{example}.toml")
    rotor = model.rotors[-1]
    point = [repr(float(x) / IN) for x in rotor.center_of_mass]
    force, moment = ["12.5", "-20", "-45"], ["7", "-3", "11"]
    us = ["--force", f"{rotor.name}:{','.join(point)}:{','.join(force)}", "--moment", f"{rotor.name}:{','.join(moment)}"]

    def si(values, kind):
        return ",".join(repr(float(from_system(float(v), kind, "us"))) for v in values)
    si_options = ["--force", f"{rotor.name}:{si(point, 'length')}:{si(force, 'force')}",
                  "--moment", f"{rotor.name}:{si(moment, 'moment')}"]
    if model.transmissions and all(t.type == "gear" or t.driver_radius is not None for t in model.transmissions):
        us += ["--transmitted-power", "20"]
        si_options += ["--transmitted-power", repr(float(from_system(20.0, "power", "us")))]
    return us, si_options


@pytest.mark.parametrize("example", EXAMPLE_FILES)
def test_static_loads_typed_in_us_units_are_their_si_equivalents(example, tmp_path, monkeypatch):
    """``static --force``, ``--moment`` (in, lbf, lbf in) and ``--transmitted-power`` (hp) typed in
    US units give the results of the same loads typed in SI (the doubles the US numbers convert
    to, NIST SP 811 factors): every CSV cell back in SI to 1e-12, every printed number converted."""
    import pandas as pd

    monkeypatch.setenv("NUMBA_NUM_THREADS", "1")
    us_options, si_options = _us_loads(example)
    runs, tables = {}, {}
    for system, options in (("si", si_options), ("us", us_options)):
        out = tmp_path / f"static.{system}.csv"
        runs[system] = _printed(["--units", system, "static", str(ROOT / "examples" / f"{example}.toml"),
                                 "--speed", "3000", *options, "--out", str(out)])
        assert runs[system][0] == 0, (example, system, runs[system][2])
        tables[system] = pd.read_csv(out)
    _same_table(tables["si"], _back_to_si(tables["us"], list(tables["si"].columns)), example)
    _same_printout(runs["si"][1], runs["us"][1], f"{example} static stdout")
    loads = tables["si"][tables["si"]["table"] == "load"]
    assert (loads["kind"] != "weight").any(), (example, sorted(set(loads["kind"])))       # the typed loads act
