"""A binary file given as a measured CSV or a mapping table is refused on one line of visible
text (redteam44): the message about a cell beyond the header's columns showed the "header" as
read, NUL bytes and terminal escape sequences included (``--outline`` said "no text: control
character ..."). Ordinary headers are shown as before."""

from __future__ import annotations

from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: what a terminal acts on, not prints: C0 and C1 control characters (ESC, NUL, CSI...)
CONTROL = {chr(c) for c in (*range(0x20), *range(0x7f, 0xa0))}


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(EXAMPLES / "gear_machine.toml")


@pytest.mark.parametrize("header", [b"\x1b[2J\x00head,er\x9b", b"\x07ab\x01,\x7fcd"])
def test_a_binary_header_is_shown_escaped(tmp_path, model, header):
    path = tmp_path / "binary.csv"
    path.write_bytes(header + b"\n1,2,3\n")
    with pytest.raises(InputError) as info:
        rdm.read_measured(path, model)
    message = str(info.value)
    assert "beyond the header's 2 column(s)" in message and "line 2" in message
    assert not CONTROL & set(message), repr(message)


def test_a_mapping_table_of_binary_is_shown_escaped(tmp_path, model):
    from rotordyn_modal.io.csv_tables import read_csv_table

    with pytest.raises(InputError) as info:
        read_csv_table(b"na\x00me,no\x1bde\n1,2,3\n", tmp_path / "map.csv", "the mapping table")
    message = str(info.value)
    assert r"na\x00me, no\x1bde" in message and not CONTROL & set(message)


def test_a_plain_header_is_shown_as_written(tmp_path):
    from rotordyn_modal.io.csv_tables import read_csv_table

    with pytest.raises(InputError, match=r"beyond the header's 2 column\(s\) \(x \[mm\], ÿ µm\)"):
        read_csv_table("x [mm],ÿ µm\n1,2,3\n".encode(), tmp_path / "t.csv", "as CSV")
