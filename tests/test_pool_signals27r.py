"""A command stopped by SIGTERM or SIGHUP while the batches' thread pool runs its parts ends within
seconds (issue 27 §1.9, issue 29 §7).

A sweep's eigen-solutions run in parts on a pool of threads (``analysis/_batches.py``). A part
started runs compiled LAPACK code that no signal stops; on main the main thread took the signal
and cleaned up, but the interpreter's exit joined the pool's threads, so the process lived until
their parts ended: more than a minute on the 60-rotor report on the shared machine (est27p's
SIGTERM). Here every part the pool is given is made to last a minute (a sleep before the part:
like LAPACK it holds no lock a signal could break) and says so on stderr; the process is signalled
once a part has started. It must end within seconds, with the exit code of the signal (``main``'s
docstring: 128 + N after signal N), its one line, and no file in its output folder (outputs
written whole or not at all).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "gear_machine.toml"

#: the command line, every part submitted to a thread pool made a minute longer and announced
RUNNER = """
import signal, sys, time
import concurrent.futures.thread as pools
submit = pools.ThreadPoolExecutor.submit
def slow_submit(self, function, *args, **kwargs):
    def slow(*a, **k):
        print("PART", file=sys.stderr, flush=True)
        time.sleep(60.0)
        return function(*a, **k)
    return submit(self, slow, *args, **kwargs)
pools.ThreadPoolExecutor.submit = slow_submit
signal.signal(signal.SIGINT, signal.default_int_handler)
from rotordyn_modal.cli.main import main
sys.exit(main(sys.argv[1:]))
"""

#: seconds the process may take to end after the signal (about 1 s here; on main the minute of
#: the parts under way)
PROMPT = 15.0


def _start(out):
    """The sweep, under way: started and waited for until a part runs in the pool."""
    command = [sys.executable, "-c", RUNNER, "campbell", str(EXAMPLE), "--speeds", "0:12000:201",
               "--speed-unit", "rpm", "--out", str(out / "campbell.csv"), "--plot", str(out / "campbell.png")]
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               ROTORDYN_MODAL_THREADS="2")
    process = subprocess.Popen(command, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True,
                               env=env, cwd=out)
    lines = []
    for line in process.stderr:       # the compile notice (empty numba cache) may come first
        lines.append(line.strip())
        if "PART" in line:            # two threads' notices can share a line ("PARTPART")
            return process, lines
    process.wait()
    pytest.fail(f"the sweep ended without a part in the pool (exit {process.returncode}): {lines}")


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_signal_stops_the_pools_parts_within_seconds(tmp_path, signum):
    process, lines = _start(tmp_path)
    time.sleep(0.3)
    start = time.monotonic()
    process.send_signal(signum)
    try:
        _, rest = process.communicate(timeout=PROMPT)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        pytest.fail(f"still running {PROMPT} s after {signal.Signals(signum).name}: the pool's parts were joined")
    took = time.monotonic() - start
    text = "\n".join(lines) + "\n" + rest
    assert process.returncode == 128 + signum, text
    assert f"terminated by {signal.Signals(signum).name}" in rest and "Traceback" not in text, text
    assert took < PROMPT
    assert list(tmp_path.iterdir()) == [], "an output written in part"          # whole or not at all
