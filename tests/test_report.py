"""``rotordyn-modal report``: the HTML of the smallest examples and a casing on mounts builds,
parses, holds every section of its standard, embeds valid PNGs only, and each verdict of its
summary equals the verdict of the analysis function called here on its own; bad input exits 2;
a real browser (headless Chromium, when installed) renders it with no broken image."""

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
    return ["report", str(ROOT / "examples" / f"{name}.toml"), "--standard", standard, "--mcs", str(MCS_RPM),
            "--points", str(POINTS), "--stiffness", "1e5:1e10:9", "--out", str(out), "--quiet", *extra]


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    folder = tmp_path_factory.mktemp("reports")
    built = {}
    for name, (standard, extra) in CASES.items():
        out = folder / f"{name}.html"
        assert main(_argv(name, out, standard, extra)) == 0
        built[name] = out
    return built


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
def test_report_parses_with_every_section_and_valid_pngs(name, reports):
    page = _page(reports[name])
    standard = CASES[name][0]
    assert {"summary", "contents", *STANDARDS[standard]} <= page.ids
    others = set(SECTIONS) - set(STANDARDS[standard])
    assert not others & page.ids                      # no section of another standard
    assert page.images
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


def _speeds():
    mcs = MCS_RPM * np.pi / 30
    return mcs, np.linspace(0.02 * mcs, 1.5 * mcs, POINTS)


def _probe_verdict(model):
    """(verdict, largest peak-to-peak displacement [um]) of the probes over the API cases."""
    mcs, speeds = _speeds()
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
        required = required_separation_margin(peak.amplification_factor)
        verdicts.append("not evaluated" if np.isnan(required) else ("pass" if margin >= required else "fail"))
    return "fail" if "fail" in verdicts else ("not evaluated" if "not evaluated" in verdicts else "pass")


def test_journal_rotor_verdicts_equal_the_analyses(reports):
    model = load_model(ROOT / "examples" / "journal_rotor.toml")
    verdicts = _verdicts(_page(reports["journal_rotor"]))
    mcs, speeds = _speeds()
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
          "document.body.setAttribute('data-images', document.images.length); });</script>")


def _chromium(*args, folder):
    return subprocess.run([_BROWSER, *_CHROMIUM_FLAGS, f"--user-data-dir={folder}/profile", *args],
                          capture_output=True, text=True, timeout=120)


@pytest.mark.skipif(_BROWSER is None, reason="no chromium on the PATH: the real-browser check of the report "
                                             "needs headless Chromium (apt-get install chromium)")
@pytest.mark.parametrize("name", ["motor_pump_on_mounts"])
def test_a_real_browser_renders_the_report_with_every_image(name, reports):
    from matplotlib.image import imread

    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "page.html"
        page.write_text(reports[name].read_text(encoding="utf-8").replace("</body>", _PROBE + "</body>"),
                        encoding="utf-8")
        dom = _chromium("--virtual-time-budget=5000", "--dump-dom", page.as_uri(), folder=folder).stdout
        found = re.search(r'data-broken="(\d+)" data-images="(\d+)"', dom)
        assert found, dom[:300]
        assert int(found.group(1)) == 0 and int(found.group(2)) == len(_page(reports[name]).images)
        shot = Path(folder) / "shot.png"
        _chromium(f"--screenshot={shot}", "--window-size=1280,3000", reports[name].as_uri(), folder=folder)
        pixels = imread(shot)
        assert pixels.shape[0] == 3000 and pixels.shape[1] == 1280
        assert pixels[..., :3].std() > 0.05          # not a blank page


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
