"""``rotordyn-modal report``: the HTML of the smallest examples and a casing on mounts builds,
parses, holds every section of its standard, embeds valid PNGs only, and each verdict of its
summary equals the verdict of the analysis function called here on its own; bad input exits 2;
a real browser (headless Chromium, when installed) renders it with no broken image; the same
report in US units (``--units us``) has the same verdicts and every number with a unit equals
the SI one times the exact factor, to the printed precision.

Speed: each report is built once (module fixture) and shared; the figures of the journal rotor
(every kind of figure of an API 617 report) are drawn to PNG, those of the other examples are
built by the plotting functions but not rasterised (``figure_png`` is the slow part: the
layout of each figure takes seconds on a loaded machine), and their texts are kept to check
the units of the US figures."""

from __future__ import annotations

import base64
import re
import shutil
import subprocess
import tempfile
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.analysis.level1 import level1
from rotordyn_modal.analysis.unbalance import api_unbalance_response, required_separation_margin, unbalance_response
from rotordyn_modal.cli import main
from rotordyn_modal.io import load_model
from rotordyn_modal.report import SECTIONS, STANDARDS

ROOT = Path(__file__).resolve().parent.parent
POINTS, MCS_RPM = 15, 3000.0
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

#: example -> (standard, extra options): a rotor on journal bearings (api617 with Level I),
#: a rotor on one bearing (api684), counter-rotating rotors with no sensor (api617 without a
#: station: Level I and the response not evaluated), the casing on mounts (iso zones)
CASES = {
    "journal_rotor": ("api617", ["--operating", "2000:3000", "--station", "rotor", "--qa", "2e5"]),
    "spring_block_rotor": ("api684", []),
    "counter_rotating": ("api617", []),
    "motor_pump_on_mounts": ("iso", ["--iso-group", "2", "--iso-support", "flexible"]),
}


def _argv(name, out, standard, extra):
    """The report's command line, made cheap: ``--stiffness`` (the UCS map's grid) only for the
    standards with the map (the ISO report refuses it: it has no map)."""
    cheap = ["--points", str(POINTS)] + (["--stiffness", "1e5:1e10:9"] if standard != "iso" else [])
    return ["report", str(ROOT / "examples" / f"{name}.toml"), "--standard", standard, "--mcs", str(MCS_RPM),
            *cheap, "--out", str(out), "--quiet", *extra]


#: the example whose figures are drawn to PNG (journal bearings, API 617: every kind of figure)
DRAWN = "journal_rotor"


def _figure_texts(fig):
    """Every text of a figure: axis labels, titles, legends, annotations."""
    from matplotlib.text import Text

    return [t.get_text() for t in fig.findobj(Text) if t.get_text()]


@pytest.fixture(scope="module")
def tiny_png():
    """A valid PNG data URI standing for a figure that is not rasterised."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.report.render import figure_png

    return figure_png(plt.figure(figsize=(2, 2)), dpi=60)


@pytest.fixture(scope="module")
def built(tmp_path_factory, tiny_png):
    """name -> (SI report file, its ReportData, the texts of its figures): each report built once."""
    import rotordyn_modal.report as report
    from rotordyn_modal.report import render

    folder = tmp_path_factory.mktemp("reports")
    done, collect = {}, report.collect
    for name, (standard, extra) in CASES.items():
        out, captured, texts = folder / f"{name}.html", [], []
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(report, "collect", lambda *a, **k: captured.append(collect(*a, **k)) or captured[-1])
            if name != DRAWN:
                patch.setattr(render, "figure_png", _fake_png(texts, tiny_png))
            assert main(_argv(name, out, standard, extra)) == 0
        done[name] = (out, captured[0], texts)
    return done


def _fake_png(texts, uri):
    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt

        texts.append(_figure_texts(fig))
        plt.close(fig)
        return uri
    return fake


@pytest.fixture(scope="module")
def reports(built):
    return {name: out for name, (out, _, _) in built.items()}


class _Page(HTMLParser):
    """Ids, images' sources, and the summary table's rows (criterion, value, limit, verdict, note)."""

    def __init__(self):
        super().__init__()
        self.ids, self.images, self.summary = set(), [], []
        self._in_summary = self._in_cell = False
        self._row, self._cell, self._tables_after = None, "", 0

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
            self._in_summary = attrs["id"] == "summary"
        if tag == "img":
            self.images.append(attrs.get("src", ""))
        if self._in_summary and tag == "tr":
            self._row = []
        if self._in_summary and tag == "td":
            self._in_cell, self._cell = True, ""

    def handle_endtag(self, tag):
        if self._in_summary and tag == "td":
            self._row.append(self._cell.strip())
            self._in_cell = False
        if self._in_summary and tag == "tr" and self._row:
            self.summary.append(self._row)
        if tag == "table":
            self._in_summary = False

    def handle_data(self, data):
        if self._in_cell:
            self._cell += data


def _page(path):
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    page.close()
    return page


def _verdicts(page):
    return {row[0]: row[3] for row in page.summary}


@pytest.mark.parametrize("name", list(CASES))
def test_report_parses_with_every_section_and_valid_pngs(name, reports, built):
    page = _page(reports[name])
    standard = CASES[name][0]
    assert {"summary", "contents", *STANDARDS[standard]} <= page.ids
    others = set(SECTIONS) - set(STANDARDS[standard])
    assert not others & page.ids                      # no section of another standard
    assert page.images
    if name != DRAWN:
        assert len(page.images) == len(built[name][2])     # each figure was built by its plotting function
    for source in page.images:
        assert source.startswith("data:image/png;base64,")
        data = base64.b64decode(source.split(",", 1)[1], validate=True)
        assert data[:8] == PNG_SIGNATURE
        width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        assert width > 100 and height > 100
    text = reports[name].read_text(encoding="utf-8")
    assert f"{name}.toml" in text and "<figcaption>" in text
    assert re.search(r"[0-9a-f]{64}", text)            # the model file's SHA-256
    import hashlib

    assert hashlib.sha256((ROOT / "examples" / f"{name}.toml").read_bytes()).hexdigest() in text


def _speeds(low_rpm=MCS_RPM):
    """The MCS and the report's sweep [rad/s]: POINTS from 2 % to 150 % of the MCS, with the MCS
    and the operating range's bottom ``low_rpm`` added (docs/report.md)."""
    mcs = MCS_RPM * np.pi / 30
    return mcs, np.union1d(np.linspace(0.02 * mcs, 1.5 * mcs, POINTS), [low_rpm * np.pi / 30, mcs])


def _probe_verdict(model):
    """(verdict, largest peak-to-peak displacement [um]) of the probes over the API cases."""
    mcs, speeds = _speeds(2000.0)
    response = api_unbalance_response(model, speeds, mcs)
    checked = np.abs(response.speeds) <= mcs
    relative = {s.name for s in model.sensors if s.measure == "relative"}
    probes = [i for i, name in enumerate(response.outputs) if name in relative]
    largest = 2 * np.abs(response.response[probes][..., checked]).max()      # each case alone: 2 |x|
    # the API 617 limit, written here from its formula: 25.4 um sqrt(12000 / N), at most 25.4 um
    limit = min(25.4e-6, 25.4e-6 * np.sqrt(12000 / MCS_RPM))
    return ("pass" if largest <= limit else "fail"), largest * 1e6


def _margin_verdict(response, operating, outputs):
    """API 684 separation margins written out here: each peak against the nearer end of the range."""
    low, high = operating
    verdicts = []
    for peak in response.peaks().itertuples():
        if peak.output not in outputs:
            continue
        speed = peak.speed_rpm * np.pi / 30
        margin = 100 * (low - speed) / low if speed < low else (100 * (speed - high) / high if speed > high else 0)
        required = required_separation_margin(peak.amplification_factor, "above" if speed > high else "below")
        if np.isnan(required):          # AF unknown: the most API 684 asks, 16 % below, 26 % above
            verdicts.append("pass" if margin >= (26.0 if speed > high else 16.0) else "not evaluated")
            continue
        verdicts.append("pass" if margin >= required else "fail")
    return "fail" if "fail" in verdicts else ("not evaluated" if "not evaluated" in verdicts else "pass")


def test_journal_rotor_verdicts_equal_the_analyses(reports):
    model = load_model(ROOT / "examples" / "journal_rotor.toml")
    verdicts = _verdicts(_page(reports["journal_rotor"]))
    mcs, speeds = _speeds(2000.0)
    result = level1(model, mcs, ["rotor"], 2e5)
    assert verdicts["API 617 Level I: log decrement at Qa"] == ("pass" if result.log_decrement_at_qa >= 0.1
                                                                else "fail")
    assert verdicts["API 617 Level I: Q0/Qa"] == ("pass" if result.q0 / result.qa >= 2 or np.isnan(result.q0)
                                                  else "fail")
    verdict, largest = _probe_verdict(model)
    assert verdicts["API 617 probe vibration limit"] == verdict
    row = next(r for r in _page(reports["journal_rotor"]).summary if r[0] == "API 617 probe vibration limit")
    assert float(row[1].split()[0]) == pytest.approx(largest, rel=5e-3)     # printed to 3 digits
    assert float(row[2].split()[1]) == pytest.approx(25.4, rel=1e-3)
    response = api_unbalance_response(model, speeds, mcs)
    operating = (2000 * np.pi / 30, mcs)
    assert verdicts["API 684 separation margin"] == _margin_verdict(response, operating, ("DE-x", "DE-y"))


def test_api_report_without_station_or_probe_says_why_not_evaluated(reports):
    page = _page(reports["counter_rotating"])
    rows = {row[0]: row for row in page.summary}
    for name in ("API 617 Level I: log decrement at Qa", "API 617 Level I: Q0/Qa"):
        assert rows[name][3] == "not evaluated" and "--station" in rows[name][4]
    for name in ("API 617 probe vibration limit", "API 684 separation margin"):
        assert rows[name][3] == "not evaluated" and "[[sensors]]" in rows[name][4]


def test_casing_on_mounts_iso_zone_verdict_equals_the_analysis(reports):
    model = load_model(ROOT / "examples" / "motor_pump_on_mounts.toml")
    verdicts = _verdicts(_page(reports["motor_pump_on_mounts"]))
    mcs, speeds = _speeds()
    table = unbalance_response(model, speeds).checks(model, mcs=mcs, iso_group=2,
                                                     iso_support="flexible").to_dataframe()
    table = table[table["check"].str.startswith("ISO")]
    assert len(table)
    # ISO 20816-3 group 2, flexible: boundary B/C 4.5 mm/s RMS (the standard's table)
    assert verdicts["ISO 20816-3 zone (casing velocity)"] == ("pass" if (table["value"] <= 4.5e-3).all()
                                                              else "fail")


@pytest.mark.parametrize("extra, fragment", [
    (["--standard", "api999"], "invalid choice"),
    (["--mcs", "-5"], "--mcs"),
    (["--operating", "3000:1000"], "--operating"),
    (["--points", "2"], "--points"),
    (["--iso-group", "2"], "--iso-group"),
    (["--qa", "1e5"], "--station"),
    (["--station", "nowhere", "--qa", "1e5"], "nowhere"),
])
def test_bad_input_exits_2_with_one_line(extra, fragment, tmp_path, capsys):
    out = tmp_path / "r.html"
    argv = _argv("motor_fan_minimal", out, "api617", [])
    for option in extra[::2]:                      # the bad value replaces the good one
        if option in argv:
            at = argv.index(option)
            del argv[at:at + 2]
    argv += extra
    try:
        code = main(argv)
    except SystemExit as stop:                    # argparse's usage errors
        code = stop.code
    err = capsys.readouterr().err
    assert code == 2 and fragment in err
    assert not out.exists()


def test_the_model_file_is_never_overwritten(tmp_path, capsys):
    model = tmp_path / "m.toml"
    shutil.copy(ROOT / "examples" / "motor_fan_minimal.toml", model)
    before = model.read_bytes()
    code = main(["report", str(model), "--standard", "api684", "--mcs", "3000", "--out", str(model)])
    assert code == 2 and "input" in capsys.readouterr().err
    assert model.read_bytes() == before


_BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")
_CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                   "--disable-background-networking", "--disable-component-update", "--disable-sync"]
#: appended to a copy of the page: the body's data-broken attribute counts images not decoded
_PROBE = ("<script>window.addEventListener('load', function () { var n = 0; for (const i of document.images) "
          "{ if (!(i.complete && i.naturalWidth > 0)) n++; } document.body.setAttribute('data-broken', n); "
          "document.body.setAttribute('data-images', document.images.length); "
          "document.body.setAttribute('data-overflow', document.documentElement.scrollWidth - "
          "document.documentElement.clientWidth); });</script>")


def _chromium(*args, folder):
    return subprocess.run([_BROWSER, *_CHROMIUM_FLAGS, f"--user-data-dir={folder}/profile", *args],
                          capture_output=True, text=True, timeout=120)


#: why the real-browser check is skipped (tests/test_report_browser_all.py says the same)
NO_BROWSER = ("no chromium on the PATH: the real-browser check of the report needs headless Chromium "
              "(apt-get install chromium)")


def assert_a_real_browser_renders(report):
    """Headless Chromium opens ``report``: every image decoded (``naturalWidth > 0``), as many as
    the HTML holds, nothing wider than a 1280-pixel window (no sideways scroll), not blank."""
    from matplotlib.image import imread

    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "page.html"
        page.write_text(report.read_text(encoding="utf-8").replace("</body>", _PROBE + "</body>"),
                        encoding="utf-8")
        shot = Path(folder) / "shot.png"          # one launch: the DOM after load, and the screenshot
        dom = _chromium("--virtual-time-budget=5000", "--window-size=1280,3000", f"--screenshot={shot}",
                        "--dump-dom", page.as_uri(), folder=folder).stdout
        found = re.search(r'data-broken="(\d+)" data-images="(\d+)" data-overflow="(-?\d+)"', dom)
        assert found, dom[:300]
        assert int(found.group(1)) == 0 and int(found.group(2)) == len(_page(report).images)
        assert int(found.group(3)) <= 0                  # nothing wider than the window: no sideways scroll
        pixels = imread(shot)
        assert pixels.shape[0] == 3000 and pixels.shape[1] == 1280
        assert pixels[..., :3].std() > 0.05          # not a blank page


@pytest.mark.skipif(_BROWSER is None, reason=NO_BROWSER)
@pytest.mark.parametrize("name", [DRAWN])
def test_a_real_browser_renders_the_report_with_every_image(name, reports):
    """The journal rotor's report, every figure drawn; every other example's report:
    tests/test_report_browser_all.py."""
    assert_a_real_browser_renders(reports[name])


@pytest.mark.parametrize("name", ["spring_block_rotor", "motor_pump_on_mounts"])
def test_separation_margin_verdict_equals_the_api_684_rule(name, reports):
    model = load_model(ROOT / "examples" / f"{name}.toml")
    mcs, speeds = _speeds()
    standard = CASES[name][0]
    response = unbalance_response(model, speeds) if standard == "iso" else api_unbalance_response(model, speeds, mcs)
    probes = tuple(s.name for s in model.sensors if s.measure == "relative") or tuple(s.name for s in model.sensors)
    rows = {row[0]: row for row in _page(reports[name]).summary}
    key = "API 684 separation margin" + (" (informative)" if standard == "iso" else "")
    assert len(response.peaks())                      # a margin to judge
    assert rows[key][3] == _margin_verdict(response, (mcs, mcs), probes)


def test_separation_margins_of_each_peak_follow_the_api_684_rule():
    """Peaks below, inside and above the operating range, passing, failing and without an AF."""
    from rotordyn_modal.report.collect import separation_margins

    model = load_model(ROOT / "examples" / "fan_on_bearings.toml")
    mcs = MCS_RPM * np.pi / 30
    response = unbalance_response(model, np.linspace(0.02 * mcs, 1.5 * mcs, 61))
    low, high = 0.5 * mcs, mcs
    table = separation_margins(response, (low, high))
    assert len(table) == len(response.peaks())
    for row in table.itertuples():
        expected = _margin_verdict(_One(response, row), (low, high), (row.output,))
        assert row.verdict == expected, row
    assert {"pass", "fail", "not evaluated"} <= set(table["verdict"])


class _One:
    """A response whose peaks() is one row of ``table``'s source (for :func:`_margin_verdict`)."""

    def __init__(self, response, row):
        peaks = response.peaks()
        self._peak = peaks[(peaks["output"] == row.output) & (peaks["source"] == row.source)
                           & np.isclose(peaks["speed_rpm"], row.speed_rpm)]
        assert len(self._peak) == 1

    def peaks(self):
        return self._peak


@pytest.mark.skipif(_BROWSER is None, reason="no chromium on the PATH: --pdf prints the report with headless Chromium")
def test_pdf_is_printed_beside_the_html(tmp_path):
    out, pdf = tmp_path / "r.html", tmp_path / "r.pdf"
    assert main(_argv("counter_rotating", out, "api684", ["--pdf", str(pdf)])) == 0
    data = pdf.read_bytes()
    assert data[:5] == b"%PDF-" and data.count(b"/Type /Page") + data.count(b"/Type/Page") >= 3  # A4 pages
    assert out.stat().st_size > 0


def test_pdf_without_a_browser_is_refused_before_the_work(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    out, pdf = tmp_path / "r.html", tmp_path / "r.pdf"
    assert main(_argv("counter_rotating", out, "api684", ["--pdf", str(pdf)])) == 2
    assert "Chromium" in capsys.readouterr().err and not out.exists() and not pdf.exists()


# -- US customary units -----------------------------------------------------------------------
#: exact definitions (NIST SP 811 appendix B), written here, not taken from the package
INCH, POUND, STANDARD_GRAVITY = 0.0254, 0.45359237, 9.80665
POUND_FORCE = POUND * STANDARD_GRAVITY
#: (unit the SI report shows, unit the US report shows) -> factor from the SI number to the US number
FACTORS = {("µm", "mil"): 1e-6 / (INCH / 1000), ("µm", "in"): 1e-6 / INCH, ("mm/s", "in/s"): 1e-3 / INCH,
           ("N", "lbf"): 1 / POUND_FORCE, ("N/m", "lbf/in"): INCH / POUND_FORCE, ("kg", "lb"): 1 / POUND}
SI_UNITS = {"µm", "mm/s", "N", "N/m", "kg", "m"}
US_UNITS = {"mil", "in", "in/s", "lbf", "lbf/in", "lb"}


class _Tables(HTMLParser):
    """Every table of a page: a list of (headers, rows), cells as text."""

    def __init__(self):
        super().__init__()
        self.tables, self._cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append(([], []))
        elif tag == "tr":
            self._row = []
        elif tag in ("th", "td"):
            self._cell = ""

    def handle_endtag(self, tag):
        if tag in ("th", "td"):
            self._row.append(self._cell.strip())
            self._cell = None
        elif tag == "tr":
            headers, rows = self.tables[-1]
            (rows if headers else headers).extend([self._row] if headers else self._row)

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


def _tables(html):
    parser = _Tables()
    parser.feed(html)
    parser.close()
    return parser.tables


_NUMBER = r"-?\d+(?:\.\d*)?(?:e[-+]?\d+)?"
_QUANTITY = re.compile(rf"({_NUMBER})(?: (µm|mil|mm/s|in/s|lbf/in|N/m|lbf|N|kg|lb|in)\b)?")


def _half_digit(text):
    """Half a unit of the last digit printed in ``text`` (a number as printed)."""
    mantissa, _, exponent = text.partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def _same_number(si, us, factor):
    """``us`` (text) is ``si`` (text) times ``factor``, to the precision both are printed to."""
    a, b = float(si), float(us)
    return abs(b - a * factor) <= _half_digit(us) + _half_digit(si) * factor + 1e-12 * abs(b)


def _unit_in(header):
    found = re.search(r"\[([^\]]+)\]", header)
    return found.group(1).split()[0] if found else None


def _compare_text(si, us):
    """Texts equal but for their quantities with a unit, converted by FACTORS; returns the number
    converted."""
    assert _QUANTITY.sub("#", si) == _QUANTITY.sub("#", us), (si, us)
    converted = 0
    for (a, unit_a), (b, unit_b) in zip(_QUANTITY.findall(si), _QUANTITY.findall(us)):
        if unit_a == unit_b:
            assert a == b, (si, us)
        else:
            assert unit_a in SI_UNITS and unit_b in US_UNITS, (si, us)
            assert _same_number(a, b, FACTORS[unit_a, unit_b]), (si, us)
            converted += 1
    return converted


def _compare_cells(si, us, factor):
    if factor is None or not re.fullmatch(_NUMBER, si):
        assert si == us
        return 0
    assert _same_number(si, us, factor), (si, us, factor)
    return 1


def _compare_table(si, us):
    """Same table in SI and US: headers equal but for their unit, each converted cell = SI x factor."""
    (si_headers, si_rows), (us_headers, us_rows) = si, us
    assert len(si_headers) == len(us_headers) and len(si_rows) == len(us_rows)
    factors, converted = [], 0
    for a, b in zip(si_headers, us_headers):
        unit_a, unit_b = _unit_in(a), _unit_in(b)
        assert unit_b not in SI_UNITS, b
        factors.append(None if a == b else FACTORS[unit_a, unit_b])
        if a != b:
            assert a.replace(unit_a, unit_b, 1) == b
    for row_a, row_b in zip(si_rows, us_rows):
        label_a, label_b = row_a[0], row_b[0]      # a row named with its unit (Level I: "Qa [N/m]")
        row_factor = None if label_a == label_b else FACTORS[_unit_in(label_a), _unit_in(label_b)]
        if row_factor is not None:
            assert _unit_in(label_b) in US_UNITS
            converted += sum(_compare_cells(x, y, row_factor) for x, y in zip(row_a[1:2], row_b[1:2]))
            row_a, row_b = row_a[2:], row_b[2:]
            heads = factors[2:]
        else:
            heads = factors
        converted += sum(_compare_cells(x, y, f) for x, y, f in zip(row_a, row_b, heads))
    return converted


@pytest.mark.parametrize("name", ["journal_rotor", "motor_pump_on_mounts"])
def test_us_report_says_the_same_as_the_si_one(name, built, tiny_png, monkeypatch):
    """The US page of the same results: same criteria and verdicts, every number with a unit the SI
    one times the exact factor (summary and every table), US units in the headers and figures."""
    from rotordyn_modal.report import render, render_html

    texts = []
    monkeypatch.setattr(render, "figure_png", _fake_png(texts, tiny_png))
    out, data, _ = built[name]
    si_tables, us_tables = _tables(out.read_text(encoding="utf-8")), _tables(render_html(data, units="us"))
    assert len(si_tables) == len(us_tables)
    (_, si_summary), (_, us_summary) = si_tables[0], us_tables[0]
    assert [(r[0], r[3]) for r in si_summary] == [(r[0], r[3]) for r in us_summary]     # names, verdicts
    assert {r[3] for r in us_summary} & {"pass", "fail"}
    summary = sum(_compare_text(a, b) for row_a, row_b in zip(si_summary, us_summary)
                  for a, b in zip(row_a[1:], row_b[1:]))
    assert summary >= 2                                   # value and limit (ISO, probe) or Qa (Level I)
    converted = sum(_compare_table(a, b) for a, b in zip(si_tables[1:], us_tables[1:]))
    headers = [h for table, _ in us_tables for h in table]
    assert {"mass [lb]", "u_x [in]", "F_z [lbf]"} <= set(headers)
    assert converted >= len(data.model_info["rotors"]) + 6          # masses, sag and reactions at least
    if name == "motor_pump_on_mounts":
        assert {"value [in/s RMS]", "amplitude, peak-to-peak [mil]"} <= set(headers)     # the report's default
    else:
        assert "value [mil pk-pk]" in headers
    labels = " ".join(t for figure in texts for t in figure)
    assert "mil" in labels and "µm" not in labels and "N/m" not in labels
    if name == "journal_rotor":
        assert "lbf/in" in labels                          # UCS map and Level I axes


def test_units_us_on_the_command_line(built, tmp_path):
    """``--units us`` before the sub-command: masses in lb, same verdicts as the SI report."""
    out = tmp_path / "us.html"
    standard, extra = CASES["counter_rotating"]
    assert main(["--units", "us", *_argv("counter_rotating", out, standard, extra)]) == 0
    si_tables, us_tables = _tables(built["counter_rotating"][0].read_text(encoding="utf-8")), _tables(
        out.read_text(encoding="utf-8"))
    assert [(r[0], r[3]) for r in si_tables[0][1]] == [(r[0], r[3]) for r in us_tables[0][1]]
    rotors = next(i for i, (h, _) in enumerate(si_tables) if "mass [kg]" in h)
    assert "mass [lb]" in us_tables[rotors][0] and _compare_table(si_tables[rotors], us_tables[rotors]) >= 2


def test_units_us_options_are_read_in_us_units():
    """With --units us the options are in US units, as in 'level1' and 'ucs-map': --qa and
    --stiffness lbf/in, a station's OFFSET in in (1 lbf/in = 4.4482216152605 N / 0.0254 m)."""
    from rotordyn_modal.cli.main import build_parser
    from rotordyn_modal.cli.report import _inputs

    def inputs(units, *extra):
        args = build_parser().parse_args(["report", "m.toml", "--standard", "api617", "--mcs", "3000", "--out", "r.html",
                                          "--station", "rotor@2", "--qa", "1000", *extra])
        args.units = units
        return _inputs(args)

    si, us = inputs("si"), inputs("us", "--stiffness", "100:1e6:3")
    assert us.level1["qa"] == pytest.approx(1000 * POUND_FORCE / INCH, rel=1e-12) and si.level1["qa"] == 1000
    assert us.level1["stations"][0].offset == pytest.approx(2 * INCH, rel=1e-12)
    assert si.level1["stations"][0].offset == 2
    assert us.stiffness == pytest.approx(np.array([1e2, 1e4, 1e6]) * POUND_FORCE / INCH, rel=1e-12)
    assert si.stiffness is None and inputs("us").stiffness is None        # the default, in N/m in every system:
    from rotordyn_modal.report.collect import UCS_STIFFNESS                # widened to the bearings' (test_report_review)

    assert UCS_STIFFNESS == pytest.approx(np.geomspace(1e5, 1e10, 41), rel=1e-12)


def test_rigid_rotor_report_shows_the_lowest_modes_when_none_is_near_the_range(reports):
    """The journal rotor (rigid) has no mode and no 1X critical speed within 17 % of its range
    2000:3000 rpm: the report shows the lowest 4 modes at the MCS (it has fewer), numbered,
    captioned and listed as ``modal`` gives them, in one mode-shape figure."""
    from rotordyn_modal.analysis.campbell import campbell
    from rotordyn_modal.analysis.modal import modal

    model = load_model(ROOT / "examples" / "journal_rotor.toml")
    mcs, speeds = _speeds(2000.0)
    low, high = 0.83 * 2000, 1.17 * MCS_RPM
    table = modal(model, mcs).to_dataframe()
    assert not ((table["frequency_hz"] * 60 >= low) & (table["frequency_hz"] * 60 <= high)).any()
    critical = campbell(model, speeds, orders=(1,)).critical.to_dataframe()["speed_rpm"]
    assert not ((critical >= low) & (critical <= high)).any()
    html = reports["journal_rotor"].read_text(encoding="utf-8")
    start = html.index('<h2 id="modes">')
    section = html[start:html.index("<h2 id=", start + 1)]
    shown = [int(m) for m in re.findall(r"<tr><td class=\"text\">(\d+)</td>", section)]
    assert shown == list(table["mode"][:4])
    for mode in table.itertuples():
        assert f"mode {mode.mode}: {mode.frequency_hz:.4g} Hz, {mode.whirl} whirl, log dec {mode.log_decrement:.3g}" \
            in section
    assert section.count("<img ") == 1


def _table_after(text, heading):
    """(headers, rows) of the first table after the heading ``heading`` in a report's HTML."""
    start = text.index(heading)
    table = text[text.index("<table>", start):text.index("</table>", start)]
    cells = lambda html, tag: [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(rf"<{tag}[^>]*>(.*?)</{tag}>", html)]
    rows = re.findall(r"<tr>(.*?)</tr>", table)
    return cells(rows[0], "th"), [cells(r, "td") for r in rows[1:]]


def test_journal_bearings_static_position_is_the_films(reports):
    """The sag table of a rotor in journal bearings shows the linear film's displacement (across
    the load); the journal's position at its load, the short bearing's eccentricity ratio and
    attitude angle, is in the reactions table, as the closed form gives it (Ocvirk: W =
    mu U L^3 / (4 c^2) eps / (1 - eps^2)^2 sqrt(16 eps^2 + pi^2 (1 - eps^2)), U = omega D / 2,
    tan(phi) = pi sqrt(1 - eps^2) / (4 eps))."""
    from scipy.optimize import brentq

    text = reports["journal_rotor"].read_text(encoding="utf-8")
    assert "linear film" in text and "eccentricity ratio" in text
    headers, rows = _table_after(text, "Reactions (force of each support")
    assert headers[-2:] == ["eccentricity ratio [-]", "attitude angle [deg]"]
    # examples/journal_rotor.toml: 50 kg on two journals 0.3 m either side of the centre of mass
    mu, diameter, length, clearance, load = 0.02, 0.05, 0.025, 5.0e-5, 50.0 * 9.81 / 2
    scale = mu * (MCS_RPM * np.pi / 30) * diameter / 2 * length ** 3 / (4 * clearance ** 2)
    eps = brentq(lambda e: scale * e / (1 - e * e) ** 2 * np.sqrt(16 * e * e + np.pi ** 2 * (1 - e * e)) - load,
                 1e-9, 1 - 1e-9, xtol=1e-14)
    phi = np.degrees(np.arctan(np.pi * np.sqrt(1 - eps * eps) / (4 * eps)))
    assert len(rows) == 2
    for row in rows:                                   # printed to 4 digits
        assert float(row[-2]) == pytest.approx(eps, rel=1e-3) and float(row[-1]) == pytest.approx(phi, rel=1e-3)


def test_a_model_without_gravity_says_why_nothing_sags(reports):
    """examples/counter_rotating.toml gives no gravity: its zero sag and reactions are explained."""
    assert not np.any(load_model(ROOT / "examples" / "counter_rotating.toml").gravity)
    without, with_gravity = (reports[n].read_text(encoding="utf-8") for n in ("counter_rotating", "journal_rotor"))
    assert "gives no gravity" in without and "gives no gravity" not in with_gravity
    # and does not open by saying 'Under the model's gravity' (it read so above the note)
    assert "Under the model's gravity" not in without and "Under the model's gravity" in with_gravity


_SYMMETRIC_ROTOR = """
name = "symmetric rigid rotor on two equal bearings"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = 50.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.5
diametral_inertia = 4.0
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "rotor"
position = [0.3, 0.0, 0.0]
stiffness = 2.0e6
damping = 300.0
axial_stiffness = 2.0e6

[[bearings]]
name = "B"
rotor = "rotor"
position = [-0.3, 0.0, 0.0]
stiffness = 2.0e6
damping = 300.0
""" + "".join(f"""
[[sensors]]
name = "{name}"
rotor = "rotor"
measure = "relative"
position = [{x}, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
""" for name, x in (("centre-z", 0.0), ("A-z", 0.3)))


def test_unbalance_peaks_leave_out_a_curve_at_round_off(tmp_path):
    """A rigid rotor mirror-symmetric about its centre of mass on two equal bearings: the API
    couple case (opposite unbalances at the outermost bearings) excites only the tilting motion,
    so the centre does not move; its computed curve is round-off (~1e-21 m) and ``peaks`` (the
    table of ``unbalance --api-unbalance``) lists no resonance of it, while the couple's
    resonance at the bearing and the static case's at the centre stay."""
    path = tmp_path / "symmetric.toml"
    path.write_text(_SYMMETRIC_ROTOR, encoding="utf-8")
    model = load_model(path)
    mcs = MCS_RPM * np.pi / 30
    response = api_unbalance_response(model, np.linspace(0.02 * mcs, 1.5 * mcs, 61), mcs)
    centre, couple = response.outputs.index("centre-z"), response.sources.index("api-couple:rotor")
    assert response.amplitude[centre, couple].max() < 1e-12 * response.amplitude.max()     # symmetry: no motion
    peaks = response.peaks(mcs)
    listed = set(zip(peaks["output"], peaks["case"]))
    assert ("centre-z", "api-couple:rotor") not in listed
    assert {("A-z", "api-couple:rotor"), ("centre-z", "api-static:rotor")} <= listed
