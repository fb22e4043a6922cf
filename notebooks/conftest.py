"""The notebooks' kernels (nbmake) start with OpenBLAS held to one thread.

pytest-xdist runs a worker per core, and a kernel's BLAS threads took the other worker's core,
mostly spinning while they waited for work (as in the test processes: tests/conftest.py).
What the notebooks compute does not depend on BLAS's threads; the environment is restored after
each notebook."""

from __future__ import annotations

import os

import pytest

#: the variable OpenBLAS (numpy's and scipy's) reads when a kernel loads it
_ONE_THREAD = ("OPENBLAS_NUM_THREADS",)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    before = {name: os.environ.get(name) for name in _ONE_THREAD}
    os.environ.update(dict.fromkeys(_ONE_THREAD, "1"))
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
