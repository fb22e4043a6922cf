"""Functions compiled by numba together (``simulation._jit.compile_together``, the one way the
simulation's kernels are compiled): they call each other in machine code, give the plain
functions' numbers, and a second process loads them from numba's on-disk cache instead of
compiling them again (the ~20 s first-run wait is paid once)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytest.importorskip("numba")

ROOT = Path(__file__).resolve().parents[1]

#: two kernels, the first calling the second through a module global, and a constant
KERNELS = textwrap.dedent('''
    import numpy as np

    SCALE = 3.0


    def outer(x):
        return inner(x) + SCALE * x[0]


    def inner(x):
        total = 0.0
        for value in x:
            total += np.sin(value)
        return total
''')

#: run in a fresh interpreter: compile together, call, report the results and numba's cache stats
RUN = textwrap.dedent('''
    import json, sys
    import numpy as np
    sys.path.insert(0, sys.argv[1])
    import kernels
    from rotordyn_modal.simulation._jit import compile_together

    namespace = compile_together([kernels.outer, kernels.inner], {"np": np, "SCALE": kernels.SCALE},
                                 kernels.__name__)
    x = np.linspace(0.1, 2.0, 7)
    value = namespace["outer"](x)
    stats = {name: [sum(namespace[name].stats.cache_hits.values()),
                    sum(namespace[name].stats.cache_misses.values())] for name in ("outer", "inner")}
    print(json.dumps({"value": value.hex(), "plain": kernels.outer(x).hex(), "stats": stats}))
''')


def _run(folder: Path, cache: Path) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), PYTHONPATH=os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    done = subprocess.run([sys.executable, "-c", RUN, str(folder)], env=env, capture_output=True, text=True,
                          timeout=300, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_functions_compiled_together_are_compiled_once_then_loaded_from_the_disk_cache(tmp_path):
    """First process: every function compiled (cache misses, no hits), the compiled call
    equal to the plain one to the bit. Second process, same cache folder: the function
    called loaded from it (a hit), none compiled (no miss)."""
    folder, cache = tmp_path / "src", tmp_path / "cache"
    folder.mkdir()
    (folder / "kernels.py").write_text(KERNELS)
    first = _run(folder, cache)
    assert first["value"] == first["plain"]
    assert all(hits == 0 and misses >= 1 for hits, misses in first["stats"].values()), first
    second = _run(folder, cache)
    assert second["value"] == first["value"]
    assert second["stats"]["outer"][0] >= 1, second        # the caller's machine code holds the callee's
    assert all(misses == 0 for _, misses in second["stats"].values()), second
