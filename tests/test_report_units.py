"""A report in US customary units says what the SI report says, for every quantity it prints.

Issue 29: "every quantity in and out round-trips between unit systems to 1e-12; a report in US
units says the same as the SI one". ``tests/test_report.py`` compares the tables of two reports;
here the whole visible text of two pages is compared, word by word (summary, tables, paragraphs,
captions, the Level I and ISO sentences), so that no number escapes: every number is either
printed alike in both pages or is the SI one times the exact factor of its unit (from NIST SP 811,
written here), to the precision both are printed to. The pages cover every kind of quantity the
report shows: a flexible rotor under gravity with close clearances, API 617 Level I from the stage
data with the critical speed ratio chart (sag, forces, moments, stresses, positions, vibration,
stiffness, density, masses), and a casing on mounts judged in ISO 20816-3 zones (velocity). A
hypothesis test round-trips the summary's quantities of every kind through both systems to 1e-12.
"""

from __future__ import annotations

import math
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotordyn_modal.cli import main
from rotordyn_modal.report import Criterion
from rotordyn_modal.report.collect import SHOWN_UNITS

ROOT = Path(__file__).resolve().parent.parent

# exact definitions (NIST SP 811, appendix B), written here, not taken from the package
IN, LB, GN = 0.0254, 0.45359237, 9.80665
LBF, FT = LB * GN, 12 * 0.0254
#: (unit of the SI page, unit of the US page) -> factor from the SI number to the US number
FACTORS = {("µm", "mil"): 1e-6 / (IN / 1000), ("µm", "in"): 1e-6 / IN, ("mm/s", "in/s"): 1e-3 / IN,
           ("m", "in"): 1 / IN, ("N", "lbf"): 1 / LBF, ("N m", "lbf in"): 1 / (LBF * IN),
           ("N/m", "lbf/in"): IN / LBF, ("kg", "lb"): 1 / LB, ("kg/m³", "lb/ft³"): FT ** 3 / LB,
           ("MPa", "psi"): 1e6 * IN ** 2 / LBF,
           ("W", "hp"): 1 / (550 * FT * LBF)}     # the Level I stage data (report33): 1 hp = 550 ft lbf/s
#: units printed alike in both systems
NEUTRAL = {"rpm", "Hz", "%", "deg", "-"}
SI_ONLY = {si for si, _ in FACTORS} - {"m"}
#: size of each unit in the SI unit of its kind (m, m/s, N, N/m, kg, kg/m³, Pa)
SIZES = {"µm": 1e-6, "mm/s": 1e-3, "N": 1.0, "N/m": 1.0, "kg": 1.0, "kg/m³": 1.0, "MPa": 1e6, "mil": IN / 1000,
         "in": IN, "in/s": IN, "lbf": LBF, "lbf/in": LBF / IN, "lb": LB, "lb/ft³": LB / FT ** 3, "psi": LBF / IN ** 2,
         "W": 1.0, "hp": 550 * FT * LBF}
#: each report kind's unit in SI and US (docs/report.md, "Units")
KIND_UNITS = {"vibration": ("µm", "mil"), "velocity": ("mm/s", "in/s"), "sag": ("µm", "in"), "force": ("N", "lbf"),
              "stiffness": ("N/m", "lbf/in"), "mass": ("kg", "lb"), "density": ("kg/m³", "lb/ft³"),
              "stress": ("MPa", "psi")}

_UNIT = "|".join(re.escape(u) for u in sorted({u for pair in FACTORS for u in pair} | NEUTRAL, key=len, reverse=True))
_NUMBER = r"(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]?\d+)?"
_TOKEN = re.compile(rf"({_NUMBER})(?:\s?({_UNIT})(?![\w/²³]))?")
#: the API residual unbalance formula, written in each system's units (one amount: 4 oz in/lb = 6350 g mm/kg)
FORMULAS = ("6350 W/N g mm (W in kg", "4 W/N oz in (W in lb")


def test_the_two_formulas_of_the_api_unbalance_are_one_amount():
    """4 oz in per lb (US page) is 6350 g mm per kg (SI page), exactly."""
    assert math.isclose(4 * (LB / 16) * IN / LB, 6350e-6, rel_tol=1e-12)


class _Text(HTMLParser):
    """The visible text of a page as a list of items: ``(text, unit)`` where ``unit`` is the unit
    the item's bare numbers are in (a table cell's column or row label, ``[...]``), or None."""

    def __init__(self):
        super().__init__()
        self.items, self._skip, self._cell, self._row, self._headers = [], 0, None, None, []
        self._text = ""

    def handle_starttag(self, tag, attrs):
        if tag in ("style", "script"):
            self._skip += 1
        elif tag == "table":
            self._flush()
            self._headers = []
        elif tag == "tr":
            self._row = []
        elif tag in ("td", "th"):
            self._flush()
            self._cell = ""

    def handle_endtag(self, tag):
        if tag in ("style", "script"):
            self._skip -= 1
        elif tag in ("td", "th") and self._cell is not None:
            self._row.append((tag, self._cell.strip()))
            self._cell = None
        elif tag == "tr" and self._row is not None:
            if all(kind == "th" for kind, _ in self._row):
                self._headers = [text for _, text in self._row]
                self.items.extend((text, None) for text in self._headers)
            else:
                label = next((_unit_of(text) for _, text in self._row if _unit_of(text)), None)
                for k, (_, text) in enumerate(self._row):
                    column = _unit_of(self._headers[k]) if k < len(self._headers) else None
                    self.items.append((text, column or label))
            self._row = None
        elif tag in ("p", "li", "h1", "h2", "h3", "figcaption", "div", "ul", "ol", "body"):
            self._flush()

    def handle_data(self, data):
        if self._skip:
            return
        if self._cell is not None:
            self._cell += data
        else:
            self._text += data

    def _flush(self):
        if self._text.strip():
            self.items.append((" ".join(self._text.split()), None))
        self._text = ""


def _bare(unit):
    """A unit without the amplitude convention the report writes after it."""
    return unit.replace(" pk-pk", "").replace(" RMS", "")


def _unit_of(text):
    found = re.search(r"\[([^\]]+)\]", text)
    return _bare(found.group(1)) if found else None


def _visible(page):
    parser = _Text()
    parser.feed(page)
    parser.close()
    return parser.items


def _half_digit(text):
    mantissa, _, exponent = text.partition("e")
    return 0.5 * 10.0 ** (int(exponent or 0) - len(mantissa.partition(".")[2]))


def _same(si, us, factor):
    """``us`` (printed) is ``si`` (printed) times ``factor``, to the precision both are printed to."""
    a, b = float(si), float(us)
    return abs(b - a * factor) <= _half_digit(us) + _half_digit(si) * abs(factor) + 1e-12 * abs(b)


#: what may stand between the numbers of one list or range that share the unit written after
#: the last: "2.3, B/C 4.5, C/D 7.1 mm/s", "1e+05 to 1e+10 N/m"
_CONNECTOR = re.compile(r"\s*(?:,|to|and)?\s*(?:[A-Z]/[A-Z]\s*)?")


def _units_of(tokens, text, context):
    """The unit pair of each number of ``text`` (its ``_TOKEN`` matches): its own unit; else that
    of the number ending the list or range it starts ("2.3, B/C 4.5 mm/s"); else the item's
    column or row unit ``context``; else None (a number without a unit)."""
    out = []
    for k, token in enumerate(tokens):
        j = k
        while token.group(2) is None and j + 1 < len(tokens) \
                and _CONNECTOR.fullmatch(text[tokens[j].end():tokens[j + 1].start()]):
            j += 1
            if tokens[j].group(2) is not None:
                break
        out.append(tokens[j].group(2) if tokens[j].group(2) is not None else None)
    return out


def _compare(si, us, context, seen):
    """One item of each page: the same words; each number with a unit that differs between the
    systems (its own, the one ending its list or range, or the item's column or row unit) is the
    SI number times the exact factor, every other number printed alike. Records in ``seen`` the
    unit pairs converted."""
    for formula in FORMULAS:
        si, us = si.replace(formula, "#formula"), us.replace(formula, "#formula")
    for a, b in zip(re.findall(r"\[([^\]]+)\]", si), re.findall(r"\[([^\]]+)\]", us)):     # headers' units
        pair = (_bare(a), _bare(b)) if a != b else None
        assert pair is None or pair in FACTORS and a.replace(pair[0], pair[1], 1) == b, (si, us)
    si, us = (re.sub(r"\[[^\]]+\]", "[#]", x) for x in (si, us))
    assert _TOKEN.sub("#", si) == _TOKEN.sub("#", us), (si, us)
    tokens_si, tokens_us = list(_TOKEN.finditer(si)), list(_TOKEN.finditer(us))
    for a, b, unit_a, unit_b in zip(tokens_si, tokens_us, _units_of(tokens_si, si, None), _units_of(tokens_us, us, None)):
        pair = (unit_a, unit_b) if unit_a is not None else context
        if pair is None or pair[0] in NEUTRAL or pair[0] == pair[1]:
            assert (a.group(1), unit_a) == (b.group(1), unit_b), (si, us)
            continue
        assert pair in FACTORS, (si, us, pair)
        assert _same(a.group(1), b.group(1), FACTORS[pair]), (si, us, pair)
        seen.add(pair)


def _fake_png(texts):
    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt
        from matplotlib.text import Text

        texts.append(" ".join(t.get_text() for t in fig.findobj(Text)))
        plt.close(fig)
        return "data:image/png;base64,"
    return fake


#: a flexible rotor under gravity (sag, shear, moments, stresses) with close clearances, judged
#: to API 617 with Level I from stage data and the CSR chart; a casing on mounts judged to ISO
CASES = {
    "flexible": ("api617", ["--operating", "4000:5000", "--mcs", "5000", "--station", "shaft@0.1", "--power", "5e5",
                            "--impeller-diameter", "0.4", "--restriction-height", "0.02", "--density-ratio", "1.1",
                            "--gas-density", "20,30"]),
    "motor_pump_on_mounts": ("iso", ["--mcs", "3000", "--iso-group", "2", "--iso-support", "flexible"]),
}
#: sections left out (their figures take seconds to build): the flexible page holds them all
LEFT_OUT = {"motor_pump_on_mounts": ("campbell", "modes", "unbalance")}


def _model(name, folder):
    if name != "flexible":
        return ROOT / "examples" / f"{name}.toml"
    text = (ROOT / "tests" / "data" / "flexible_with_seals.toml").read_text(encoding="utf-8")
    text = text.replace('spin_axis = [1.0, 0.0, 0.0]', 'spin_axis = [1.0, 0.0, 0.0]\ngravity = [0.0, 0.0, -9.81]')
    text = text.replace("poisson_ratio = 0.3", "poisson_ratio = 0.3\nallowable_stress = 2.0e8")
    path = folder / "flexible_under_gravity.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """name -> {units: (page HTML, texts of its figures)}: the analyses run once by the command
    line (SI), the page rendered in each system from them."""
    import rotordyn_modal.report as report
    from rotordyn_modal.report import render

    folder, done, collect = tmp_path_factory.mktemp("units"), {}, report.collect
    for name, (standard, options) in CASES.items():
        out, captured, texts = folder / f"{name}.html", [], []
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(report, "collect", lambda *a, **k: captured.append(collect(*a, **k)) or captured[-1])
            patch.setattr(render, "figure_png", _fake_png(texts))
            for section in LEFT_OUT.get(name, ()):
                patch.setitem(render._SECTION_RENDERERS, section, lambda data, units: "")
            grid = ["--stiffness", "1e5:1e10:5"] if standard != "iso" else []     # the ISO report has no UCS map
            assert main(["report", str(_model(name, folder)), "--standard", standard, "--points", "15",
                         *grid, "--out", str(out), "--quiet", *options]) == 0
            us_texts = []
            patch.setattr(render, "figure_png", _fake_png(us_texts))
            us = render.render_html(captured[0], date="DATE", units="us")
        si = re.sub(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", "DATE", out.read_text(encoding="utf-8"))
        done[name] = {"si": (si, texts), "us": (us, us_texts)}
    return done


def test_the_us_pages_say_what_the_si_pages_say(pages):
    """Every item of the visible text: same words, numbers alike or converted exactly; together
    the pages convert every kind of quantity the report shows."""
    seen = set()
    for name, by_units in pages.items():
        si, us = (_visible(by_units[u][0]) for u in ("si", "us"))
        assert len(si) == len(us), name
        for (text_si, context_si), (text_us, context_us) in zip(si, us):
            if text_si.startswith("rotordyn-modal "):           # the command line as given
                continue
            context = (context_si, context_us) if context_si else None
            if context_si in NEUTRAL or context_si == context_us:
                context = None
            _compare(text_si, text_us, context, seen)
        assert not [(unit, text) for text, _ in us for unit in SI_ONLY
                    if re.search(rf"(?:\d |\[){re.escape(unit)}(?![\w/²³])", text)]
    assert seen == set(FACTORS)                                   # every kind of quantity compared


def test_the_us_figures_say_us_units(pages):
    """The figures of the US pages carry no SI unit but the CSR chart's second density axis."""
    for name, by_units in pages.items():
        for text in by_units["us"][1]:
            text = text.replace("[kg/m³]", "")            # the CSR chart's top axis, in the other system
            assert not re.search(r"µm|mm/s|N/m\b|\bMPa|\[N\]|\[N m\]|\[kg\]", text), (name, text)


@pytest.mark.parametrize("kind", sorted(SHOWN_UNITS))
@settings(max_examples=40, deadline=None)
@given(value=st.floats(min_value=-1e12, max_value=1e12, allow_nan=False).filter(lambda v: v == 0 or abs(v) > 1e-12))
def test_a_summary_quantity_round_trips_through_both_systems(kind, value):
    """A criterion's value written in either system and read back with the exact unit is the SI
    value to 1e-12; its unit is the documented one."""
    criterion = Criterion.of("c", "pass", "summary", value="", quantities=[("value", "{0!r} {unit}", kind, (value,))])
    for system, unit in zip(("si", "us"), KIND_UNITS[kind]):
        number, _, shown = criterion.in_system(system).value.partition(" ")
        assert shown == unit
        size = SIZES[unit]
        assert math.isclose(float(number) * size, value, rel_tol=1e-12, abs_tol=0.0), (kind, system)


def _summary_rows(page):
    """The summary table's body rows, cells as text."""
    table = page[page.index('<h2 id="summary">'):]
    table = table[table.index("<tbody>"):table.index("</tbody>")]
    return [[re.sub(r"<[^>]+>", "", cell).strip() for cell in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", table)]


def test_every_criterion_names_the_source_of_its_rule(pages):
    """Each line of the summary says where its rule comes from: a standard (or the model file's
    material), and the page of the docs that writes the rule out with its sources; the same in
    both unit systems."""
    for name, by_units in pages.items():
        si, us = (_summary_rows(by_units[u][0]) for u in ("si", "us"))
        assert si and [row[5] for row in si] == [row[5] for row in us]
        for row in si:
            source = row[5]
            assert re.search(r"\b(API|ISO)\b|allowable_stress", source), row
            documents = re.findall(r"docs/[\w]+\.md", source)
            assert documents and all((ROOT / d).is_file() for d in documents), row


def test_the_level1_station_names_the_unit_of_its_offset(pages):
    """``--station shaft@0.1`` is 0.1 m along the spin axis: the page and the Level I figure say
    'shaft@0.1 m' in SI and 'shaft@3.93701 in' in US units (a bare 3.93701 reads as metres)."""
    for units, named in (("si", "shaft@0.1 m"), ("us", f"shaft@{0.1 / IN:g} in")):
        page, figures = pages["flexible"][units]
        assert f"Stations: {named};" in page
        assert any(f"Q at {named}\n" in text for text in figures), units


def test_a_section_not_evaluated_names_the_model_file_not_its_path():
    """The UCS map of a model without bearings is refused by the analysis with the model file's
    path; the report gives the file's name, as its Model section does (a report sent to a client
    does not carry the directories of the machine that wrote it)."""
    from types import SimpleNamespace

    import numpy as np

    import importlib

    from rotordyn_modal.io import load_model

    collect = importlib.import_module("rotordyn_modal.report.collect")     # the module, not the function
    path = ROOT / "examples" / "counter_rotating.toml"
    data = SimpleNamespace(model=load_model(path), skipped={}, results={},
                           inputs=SimpleNamespace(stiffness=np.array([1e6, 1e8]), range=(300.0, 314.0)))
    collect._ucs(data)
    reason = data.skipped["ucs"]
    assert reason.startswith("counter_rotating.toml: ") and "[[bearings]]" in reason
    assert str(path.parent) not in reason
