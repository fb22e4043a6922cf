"""A Simcenter Testlab text export of FRFs given to --measured: refused on one line saying what
it is and what to export instead (it was "cannot read as CSV (Error tokenizing data ...)").

The file is written here by hand in the layout a public Python reader of Testlab FRF exports
describes (metadata lines, a units row ``Hz  g/N  °`` per FRF, a row ``Linear  Log  Phase``, then
tab-separated numbers with decimal commas); no Testlab file was found to keep."""

from __future__ import annotations

from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
TESTLAB = ("Original project:\tbench\nSection:\tSection1\nFunction class:\tFRF\n\n"
           "Hz\tg/N\t°\tHz\tg/N\t°\nLinear\tLog\tPhase\tLinear\tLog\tPhase\n"
           "1,0\t0,5\t-10,0\t1,0\t0,4\t-12,0\n2,0\t0,6\t-20,0\t2,0\t0,5\t-22,0\n")


@pytest.mark.parametrize("encoding", ["utf-8", "latin-1"])
def test_a_testlab_text_export_is_refused_saying_what_it_is(tmp_path, encoding):
    path = tmp_path / "FRF_S4Y.txt"
    path.write_bytes(TESTLAB.encode(encoding))
    model = rdm.load_model(EXAMPLE)
    with pytest.raises(InputError, match=r"FRF_S4Y.txt: line 5: units Hz, g/N, °, Hz, g/N, ° over display formats "
                                         r"Linear, Log, Phase, Linear, Log, Phase \(line 6\), as Simcenter Testlab's "
                                         r"text export writes them: its columns name no output and input channel of "
                                         r"its 2 function\(s\)"):
        rdm.read_measured(path, model)


def test_the_command_line_exits_2_with_the_same_line(tmp_path, capsys):
    path = tmp_path / "FRF_S4Y.txt"
    path.write_text(TESTLAB, encoding="utf-8")
    assert main(["frf", str(EXAMPLE), "--freqs", "1:2:2", "--measured", str(path)]) == 2
    err = capsys.readouterr().err
    assert "as Simcenter Testlab's text export writes them" in err and "export the FRFs as UFF 58" in err
