"""Peak memory and time of reading measured FRFs (``rdm.read_measured``): CSV, UFF 58 ASCII and
UFF 58b binary files of the same FRFs, at two sizes, in this checkout and, with ``--base REV``, in
a clone of the repository at that revision, run in turn ``--repeat`` times (each read in a fresh
process: its peak resident memory from ``resource.getrusage``, less the same process's peak after
loading the model alone; the files are written by a process of their own, as a child starts with
its parent's peak).

    python benchmarks/bench_measured_memory.py [--lines 50000] [--repeat 3] [--base 4d8efe31]

The files: the gear machine's 2 sensors x 2 excitations at 3 speeds, ``--lines`` frequency lines
each (12 FRFs; 600,000 lines at the default), and twice as many lines.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent

_READ = """
import resource, sys, time, warnings
sys.path.insert(0, {root!r})
import rotordyn_modal as rdm
model = rdm.load_model({model!r})
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
start = time.perf_counter()
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    rdm.read_measured({path!r}, model)
seconds = time.perf_counter() - start
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before, seconds)
"""


def _write_files(folder: Path, lines: int) -> list:
    sys.path.insert(0, str(REPO))
    import warnings

    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import default_mapping, write_csv
    from rotordyn_modal.io.uff import write_uff58

    model = rdm.load_model(REPO / "examples" / "gear_machine.toml")
    files = []
    for size in (lines, 2 * lines):
        sets = [rdm.frf(model, speed, np.linspace(1.0, 500.0, size)) for speed in (0.0, 100.0, 300.0)]
        csv, ascii_uff, binary_uff = (folder / f"m{size}.csv", folder / f"m{size}.uff", folder / f"m{size}b.uff")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            write_csv(sets, csv)
            write_uff58(sets, ascii_uff, default_mapping(model), binary=False)
            write_uff58(sets, binary_uff, default_mapping(model), binary=True)
        files += [(f"CSV, {12 * size:,} lines", csv), (f"UFF 58, {12 * size:,} lines", ascii_uff),
                  (f"UFF 58b, {12 * size:,} lines", binary_uff)]
    return files


def _read(root: Path, path: Path) -> tuple:
    code = _READ.format(root=str(root), model=str(REPO / "examples" / "gear_machine.toml"), path=str(path))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]) / 1024, float(out[1])          # MB (ru_maxrss is in kB on Linux), s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lines", type=int, default=50000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--base", help="a revision to compare with (cloned into a temporary folder)")
    parser.add_argument("--write", help=argparse.SUPPRESS)    # the files' writer, run in a process of its own
    args = parser.parse_args()
    if args.write:
        for name, path in _write_files(Path(args.write), args.lines):
            print(f"{name}\t{path}")
        return
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        trees = [("this", REPO)]
        if args.base:
            base = folder / "base"
            subprocess.run(["git", "clone", "-q", str(REPO), str(base)], check=True)
            subprocess.run(["git", "-C", str(base), "checkout", "-q", args.base], check=True)
            trees.insert(0, (args.base, base))
        # written by another process: a child inherits its parent's peak resident memory (Linux keeps
        # it across fork and exec), and the writer's would hide the readers'
        written = subprocess.run([sys.executable, __file__, "--write", str(folder), "--lines", str(args.lines)],
                                 capture_output=True, text=True, check=True).stdout.splitlines()
        for name, path in (line.split("\t") for line in written):
            path = Path(path)
            size = path.stat().st_size / 1e6
            runs = {tree: [_read(root, path) for _ in range(args.repeat)] for tree, root in trees}
            parts = []
            for tree, found in runs.items():
                memory, seconds = np.array(found).T
                parts.append(f"{tree}: {np.median(memory):6.0f} MB ({np.median(memory) / size:4.1f} x the file), "
                             f"{seconds.min():.2f}/{np.median(seconds):.2f}/{seconds.max():.2f} s")
            print(f"{name:24s} {size:6.1f} MB | " + " | ".join(parts), flush=True)


if __name__ == "__main__":
    main()
