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
One test per example: pytest-xdist spreads them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from test_report import CASES as REPORT_CASES
from test_report import MCS_RPM
from test_report_browser_all import EXAMPLES as BROWSER_EXAMPLES
from test_report_units import IN, NEUTRAL, SI_ONLY, _compare, _visible

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
    axis's values."""
    si, us = (list(dict.fromkeys(t for t in texts if not _TICK.fullmatch(t))) for texts in (si, us))
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
