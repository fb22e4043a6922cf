"""The inexact-root warning names modes as the tables number them (issue 27 §2: one mode numbering).

rubber_mounts with a 1e-12 s Maxwell branch (tests/test_roots30.py): two real roots sit at the pole
of the 0.02 s branch, s = -1/0.02 = -50 1/s, which no Newton step on the pencil reaches, so they are
left inexact and warned of. The modes are polished. Before, the warning counted every root of the
solve as a mode, so `modes` said "mode(s) 1, 18" of a table with 6 modes (mode 1 there is a
polished, exact mode) and `campbell` "mode(s) 7, 8, 9, 24" of a table whose modes are 1 to 6.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
POLE = -1 / 0.02                    # 1/s: the 0.02 s branch's pole


@pytest.fixture(scope="module")
def fast_branch(tmp_path_factory):
    text = (EXAMPLES / "rubber_mounts.toml").read_text()
    assert "maxwell_time = [0.02, 0.002]" in text
    path = tmp_path_factory.mktemp("inexact30") / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.load_model(path)


def _inexact_warnings(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call()
    return result, [str(w.message) for w in caught if "exact only to about" in str(w.message)]


def _named_modes(text):
    found = re.search(r"mode\(s\) ([0-9, .]+?) (?:and|at) ", text)
    return [int(k) for k in found.group(1).replace("...", "").split(",") if k.strip()] if found else []


def test_modes_warning_names_the_real_roots_at_the_pole_not_modes(fast_branch):
    result, said = _inexact_warnings(lambda: rdm.modal(fast_branch, rdm.rpm(1000.0)))
    table = result.to_dataframe()
    real = result.eigenvalues[~result.oscillatory]
    near_pole = real[np.abs(real - POLE) < 1e-3 * abs(POLE)]
    assert len(near_pole) >= 2                                        # the mounts' relaxations at the pole
    assert len(said) == 1, said
    # how many of the roots at the pole Newton leaves is the round-off's (2 with OpenBLAS's SkylakeX
    # kernels, 4 with its Haswell kernels): at least two, and no more than lie there
    found = re.search(r"(\d+) real root\(s\) \(-50 1/s; not modes\)", said[0])
    assert found and 2 <= int(found.group(1)) <= len(near_pole), said
    assert set(_named_modes(said[0])) <= set(table["mode"]), (said, len(table))


def test_campbell_warning_names_only_the_table_s_modes(fast_branch):
    result, said = _inexact_warnings(lambda: rdm.campbell(fast_branch, rdm.rpm(np.array([0.0, 1000.0, 3000.0]))))
    table = result.to_dataframe()
    assert len(said) == 1, said
    assert "real root(s) (-50 1/s; not modes)" in said[0], said
    assert set(_named_modes(said[0])) <= set(table["mode"]), (said, sorted(set(table["mode"])))
