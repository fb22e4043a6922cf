"""The command line run in this process with its terminal output captured, for tests that ask
what it says (the tests that only need the exit code call ``main`` directly)."""
from __future__ import annotations

import contextlib
import io

from rotordyn_modal.cli import main


def run_quietly(argv) -> tuple[int, str]:
    """``rotordyn-modal ARGV`` here: (exit code, everything it wrote to stderr); stdout is
    discarded, and an argparse exit is an exit code like any other."""
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exit_:
            code = exit_.code
    return code, err.getvalue()
