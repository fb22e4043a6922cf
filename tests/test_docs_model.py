"""The complete short model file that README.md and docs/model-file.md open with is the
bundled ``examples/motor_fan_minimal.toml`` to the letter, and it loads."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import rotordyn_modal as rdm

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "motor_fan_minimal.toml"


def first_toml_block(path: Path) -> str:
    found = re.search(r"```toml\n(.*?)```", path.read_text(encoding="utf-8"), re.S)
    assert found, f"{path.name} shows no model file"
    return found.group(1)


@pytest.mark.parametrize("page", ["README.md", "docs/model-file.md"])
def test_the_page_opens_with_the_bundled_short_model(page):
    assert first_toml_block(ROOT / page) == EXAMPLE.read_text(encoding="utf-8")


def test_the_short_model_is_complete_and_valid(tmp_path):
    shown = tmp_path / "shown.toml"
    shown.write_text(first_toml_block(ROOT / "README.md"), encoding="utf-8")
    model = rdm.load_model(shown)
    assert sorted(model.speed_ratios) == ["fan", "motor"]
    assert model.speed_ratios["fan"] == pytest.approx(1 / 1.6, rel=1e-15)   # belt: same direction
    assert model.dofs.n == 6
