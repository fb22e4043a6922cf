"""Start-up: ``import rotordyn_modal`` and ``rotordyn-modal check MODEL``, a user's first contact.

Times fresh interpreters (each a subprocess) side by side with the floor, ``python -c "import
numpy"`` (the package cannot start faster than its one eager dependency), and prints
min/median/max over repeats. ``--source DIR`` times the package of another checkout (e.g. an
older commit in a git worktree) the same way, for a before/after comparison::

    python benchmarks/bench_startup.py [--repeat 15] [--source /path/to/other/checkout]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "examples" / "gear_machine.toml"


#: import the package from a given folder even when another checkout is installed in editable
#: mode (setuptools' editable finder sits in sys.meta_path, ahead of sys.path)
_FROM = ("import sys; sys.meta_path[:] = [f for f in sys.meta_path if 'editable' not in repr(f)]; "
         "sys.path.insert(0, {source!r}); ")


def _times(code: str, source: Path, repeat: int) -> list[float]:
    env = dict(os.environ, MPLBACKEND="Agg")
    out = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", _FROM.format(source=str(source)) + code], env=env, check=True,
                       capture_output=True)
        out.append(time.perf_counter() - start)
    return out


def _row(label: str, values: list[float], floor: float) -> str:
    low, mid, high = min(values), statistics.median(values), max(values)
    return f"{label:<40} {low * 1e3:7.0f} {mid * 1e3:7.0f} {high * 1e3:7.0f} ms   median / floor {mid / floor:5.2f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--source", type=Path, help="another checkout whose package is timed too")
    args = parser.parse_args()
    check = ("import sys; from rotordyn_modal.cli import main; "
             f"sys.exit(main(['check', {str(MODEL)!r}]))")
    sources = [("this checkout", REPO)] + ([("--source", args.source)] if args.source else [])
    print(f"{'':<40} {'min':>7} {'median':>7} {'max':>7}     ({args.repeat} fresh interpreters each)")
    for _ in range(2):                                    # interleave, so that load hits both alike
        floor = statistics.median(_times("import numpy", REPO, args.repeat))
        print(_row("floor: import numpy", _times("import numpy", REPO, args.repeat), floor))
        for label, source in sources:
            print(_row(f"import rotordyn_modal ({label})", _times("import rotordyn_modal", source, args.repeat), floor))
            print(_row(f"rotordyn-modal check ({label})", _times(check, source, args.repeat), floor))


if __name__ == "__main__":
    main()
