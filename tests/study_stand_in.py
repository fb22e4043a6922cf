"""A stand-in for ``study.execution.run_chunk`` that runs no analysis, for the tests of a
study's memory, spooling and streaming (shared by several test files)."""
import numpy as np


def stand_in_chunk(task):
    """A chunk as ``run_chunk`` returns it, each value its variant's number (no analysis)."""
    n = len(task.values)
    rows = np.arange(task.start, task.start + n, dtype=float)
    out = {name: np.broadcast_to(rows.reshape((n,) + (1,) * len(shape)), (n,) + shape).copy()
           for name, shape in task.shapes.items()}
    return {"index": task.index, "start": task.start, "error": np.array([""] * n), **out}
