"""Run the command line in a forked child, as a user would run it, with limits on what it may
use; shared by the tests of failed writes and of studies under a memory limit."""

from __future__ import annotations

import contextlib
import os
import resource
import signal
import sys


def run_forked(argv, limit_bytes=None, before=None):
    """Run ``rotordyn-modal argv`` in a forked child; returns (exit code, stderr text).

    ``limit_bytes`` sets the child's RLIMIT_FSIZE (writes past it fail with EFBIG, as a
    full disk fails with ENOSPC); ``before`` is called in the child first."""
    read_end, write_end = os.pipe()  # a pipe: not subject to the file-size limit
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        code = 99
        try:
            os.close(read_end)
            sys.stderr = os.fdopen(write_end, "w", buffering=1)
            sys.stdout = open(os.devnull, "w")
            os.environ["ROTORDYN_MODAL_THREADS"] = "1"
            if before is not None:
                before()
            if limit_bytes is not None:
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))
            from rotordyn_modal.cli import main

            code = main(argv)
        except BaseException:  # noqa: BLE001 - reported to the parent as a traceback
            import traceback

            traceback.print_exc()
        finally:
            with contextlib.suppress(Exception):
                sys.stderr.flush()
            os._exit(code)
    os.close(write_end)
    with os.fdopen(read_end) as pipe:
        text = pipe.read()
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), text
