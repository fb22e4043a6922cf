"""A disk whose width reaches beyond its shaft's end draws one warning line (redteam44: a disk of
width 0.05 m centred at the end of a 0.5 m shaft, half of it over nothing, was taken without a
word, where a disk off the shaft is refused and one wider than the whole shaft draws a warning)."""

from __future__ import annotations

import pytest

from quiet_cli import run_quietly
from test_probe42 import BASE


def _with_disk(tmp_path, position, width):
    disk = ('\n[[rotors.disks]]\nname = "hub"\n'
            f'axial_position = {position}\nmass = 10.0\npolar_inertia = 0.05\ndiametral_inertia = 0.03\nwidth = {width}\n')
    path = tmp_path / "m.toml"
    path.write_text((BASE + "amount = 1e-4\n").replace("[[bearings]]", disk + "\n[[bearings]]", 1), encoding="utf-8")
    return path


@pytest.mark.parametrize("position, width, beyond", [(0.5, 0.05, 0.025), (0.49, 0.04, 0.01), (0.0, 0.1, 0.05),
                                                     (0.01, 0.1, 0.04)])
def test_a_disk_reaching_beyond_its_shafts_end_draws_one_line(tmp_path, position, width, beyond):
    code, err = run_quietly(["check", str(_with_disk(tmp_path, position, width))])
    warned = [line for line in err.splitlines() if "beyond the end of its shaft" in line]
    assert code == 0 and len(warned) == 1, err
    assert "[rotors.r.disks.hub]" in warned[0] and f"reaches {beyond:.3g} m beyond" in warned[0], warned[0]


@pytest.mark.parametrize("position, width", [(0.475, 0.05), (0.025, 0.05), (0.25, 0.5), (0.25, 0.3)])
def test_a_disk_within_its_shafts_ends_draws_none(tmp_path, position, width):
    code, err = run_quietly(["check", str(_with_disk(tmp_path, position, width))])
    assert code == 0 and "beyond the end" not in err, err
