"""An undamped resonance's amplification factor is infinite, not unknown (review of af29r): the
spring block rotor has no damping, so its 1X resonance at 100 rpm has AF = inf and is judged
against the 16 % an infinite AF requires (margin 0 %: fail). The report said "AF unknown" and
"2 peak(s) of unknown AF pass" beside that fail, and `unbalance` printed the unknown-AF line."""
from pathlib import Path

from rotordyn_modal.cli.main import main

MODEL = str(Path(__file__).resolve().parents[1] / "examples" / "spring_block_rotor.toml")
OPERATING = ["--api-unbalance", "--mcs", "1000", "--operating-range", "100:1000"]


def test_unbalance_does_not_call_an_infinite_af_unknown(tmp_path, capsys):
    assert main(["unbalance", MODEL, "--speeds", "0:3000:61", *OPERATING, "--out", str(tmp_path / "u.csv")]) == 0
    said = capsys.readouterr()
    err = said.out + said.err
    rows = [line for line in err.splitlines() if "api-static:disk" in line and line.split()[0].startswith("disk-centre")]
    assert len(rows) == 2 and all(" inf " in row and row.split()[-1] == "fail" for row in rows), rows
    assert "AF unknown" not in err


def test_the_report_calls_an_infinite_af_infinite(tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["report", MODEL, "--standard", "api684", *OPERATING[1:], "--points", "41", "--out", str(out)]) == 0
    page = out.read_text()
    assert "0.0 % (AF inf)" in page
    assert "of unknown AF pass" not in page and "(AF unknown)" not in page
