"""Run thousands of mutated inputs through the command line, outside pytest, and count outcomes.

    MPLBACKEND=Agg python tests/fuzz_many.py --count 2000 [--kinds model,study,measured,option]
        [--seed 0] [--keep crashes/]

Each input is judged as ``tests/fuzzing.py`` describes: valid (exit 0), refused (exit 2, one
line naming the file or option, no output left behind) or crash (anything else: exit 1, a
traceback, several lines, a leftover output file, or no answer within --timeout seconds).
Prints the counts per kind and the first crash of each kind of reason; ``--keep FOLDER``
saves every crashing input there. Exit code 1 when anything crashed.
"""

from __future__ import annotations

import argparse
import collections
import random
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import fuzzing  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=1000, help="inputs per kind (default 1000)")
    parser.add_argument("--kinds", default=",".join(fuzzing.CASES), help="comma-separated kinds (default all)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a run counts as a hang")
    parser.add_argument("--keep", metavar="FOLDER", help="save the crashing inputs here")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")  # numpy's warnings of the valid runs; refusals are judged on their own lines
    fuzzing.TIME_LIMIT = args.timeout
    crashed = 0
    for kind in args.kinds.split(","):
        crashed += _run_kind(kind, args)
    return 1 if crashed else 0


def _run_kind(kind, args) -> int:
    case = fuzzing.CASES[kind]
    rng = random.Random(f"{args.seed}-{kind}")
    counts, first = collections.Counter(), {}
    folder = Path(tempfile.mkdtemp(prefix=f"fuzz-{kind}-"))
    start = time.perf_counter()
    try:
        for i in range(args.count):
            for outcome in case(rng, folder):
                counts[outcome.verdict] += 1
                if outcome.verdict == "crash":
                    reason = outcome.reason.strip().splitlines()[-1][:120] if outcome.reason.strip() else "?"
                    first.setdefault(reason, outcome)
                    _keep(args.keep, kind, i, folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    tried = sum(counts.values())
    print(f"{kind}: {args.count} inputs, {tried} runs in {time.perf_counter() - start:.0f} s: "
          f"{counts['valid']} valid, {counts['refused']} refused, {counts['crash']} crashed", flush=True)
    for outcome in first.values():
        print("  " + outcome.describe().replace("\n", "\n  "), flush=True)
    return counts["crash"]


def _keep(keep, kind, index, folder):
    if not keep:
        return
    target = Path(keep)
    target.mkdir(parents=True, exist_ok=True)
    for entry in folder.iterdir():
        if entry.is_file() and not entry.name.startswith("valid"):
            shutil.copy(entry, target / f"{kind}-{index}-{entry.name}")


if __name__ == "__main__":
    sys.exit(main())
