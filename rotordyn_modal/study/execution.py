"""Running the variants: chunks through ``Executor.map``, one BLAS thread per worker,
failures recorded, finished chunks saved so that an interrupted study resumes.

The worker function :func:`run_chunk` is a plain module-level function of a
picklable :class:`ChunkTask`, so any ``concurrent.futures`` executor serves:
``None`` (serial, in this process), ``ProcessPoolExecutor``,
``dask.distributed.Client.get_executor()``, ``mpi4py.futures.MPIPoolExecutor``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from .analyses import batch_caches, run_analyses

__all__ = ["ChunkTask", "run_chunk", "make_tasks", "execute", "Checkpoint", "limit_threads",
           "worker_initializer", "default_chunk_size", "remove_checkpoint"]


@dataclass(frozen=True)
class ChunkTask:
    """Everything a worker needs for a run of consecutive variants.

    Attributes
    ----------
    index : int
        Chunk number.
    start : int
        Index of its first variant.
    values : ndarray, shape (n, n_parameters)
        Parameter values of its variants.
    keys : tuple of tuple of str
        Dotted keys of each parameter.
    applies : tuple of str
        'value' or 'scale' for each parameter.
    model_data : dict
        Base model description; ``model_source`` names it in messages.
    analyses : dict
        Validated analysis options.
    layouts : dict
        Per-analysis layouts from the base model.
    shapes : dict
        Output variable -> shape per variant (for NaN rows of failed variants).
    single_thread : bool
        Limit BLAS/LAPACK and the eigen-solver to one thread while running.
    """

    index: int
    start: int
    values: np.ndarray
    keys: tuple
    applies: tuple
    model_data: dict
    model_source: str
    analyses: dict
    layouts: dict
    shapes: dict
    single_thread: bool = False


def variant_model(model_data, source, keys, applies, values):
    """The validated model of one variant.

    Parameters
    ----------
    model_data : dict
        Base model description.
    keys, applies : see :class:`ChunkTask`
    values : array_like, shape (n_parameters,)

    Returns
    -------
    Model
    """
    from .._validation import plain_copy
    from ..model import Model
    from ..parameters import scale_value, set_value

    data = plain_copy(model_data, source)
    for group, apply, value in zip(keys, applies, values):
        for key in group:
            (set_value if apply == "value" else scale_value)(data, key, float(value), source)
    return Model.from_dict(data, source)


def run_chunk(task: ChunkTask) -> dict:
    """Run every variant of a chunk; a failing variant gets NaNs and its reason.

    Returns
    -------
    dict
        ``index``, ``start``, ``error`` (ndarray of str, '' where it worked) and
        each output variable stacked over the chunk's variants.
    """
    context = limit_threads() if task.single_thread else contextlib.nullcontext()
    n = len(task.values)
    out = {name: np.full((n,) + shape, np.nan) for name, shape in task.shapes.items()}
    errors = [""] * n
    with context:
        models = [_try(variant_model, errors, row, task.model_data, task.model_source, task.keys, task.applies,
                       values) for row, values in enumerate(task.values)]
        built = [row for row, model in enumerate(models) if model is not None]
        caches = dict(zip(built, batch_caches([models[row] for row in built], task.analyses)))
        for row in built:
            analysed = _try(run_analyses, errors, row, models[row], task.analyses, task.layouts, caches[row])
            for name, array in (analysed or {}).items():
                out[name][row] = array
    return {"index": task.index, "start": task.start, "error": np.array(errors, dtype=str), **out}


def _try(function, errors, row, *args):
    """``function(*args)``, or None with the reason recorded in ``errors[row]``."""
    try:
        return function(*args)
    except Exception as error:  # noqa: BLE001 - recorded, the study goes on
        errors[row] = f"{type(error).__name__}: {error}"
        return None


# ---------------------------------------------------------------------------- threads
_THREAD_LOCK = threading.Lock()
_THREAD_USERS = [0, None]


@contextlib.contextmanager
def limit_threads():
    """One BLAS/LAPACK thread and no eigen-solver thread pool while inside.

    Sets ``ROTORDYN_MODAL_THREADS=1`` (read by the core's batched eigen-solver)
    and, through threadpoolctl when installed, limits BLAS/OpenMP pools to one
    thread. Re-entrant across the threads of one worker process.
    """
    with _THREAD_LOCK:
        if _THREAD_USERS[0] == 0:
            _THREAD_USERS[1] = os.environ.get("ROTORDYN_MODAL_THREADS")
            os.environ["ROTORDYN_MODAL_THREADS"] = "1"
        _THREAD_USERS[0] += 1
    try:
        try:
            from threadpoolctl import threadpool_limits
        except ImportError:  # pragma: no cover
            limits = contextlib.nullcontext()
        else:
            limits = threadpool_limits(1)
        with limits:
            yield
    finally:
        with _THREAD_LOCK:
            _THREAD_USERS[0] -= 1
            if _THREAD_USERS[0] == 0:
                if _THREAD_USERS[1] is None:
                    os.environ.pop("ROTORDYN_MODAL_THREADS", None)
                else:
                    os.environ["ROTORDYN_MODAL_THREADS"] = _THREAD_USERS[1]


def worker_initializer():
    """Initializer of the study's process pool: one thread per library, Ctrl-C left
    to the parent (which saves finished chunks and stops the pool)."""
    import signal

    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "ROTORDYN_MODAL_THREADS"):
        os.environ[name] = "1"  # for libraries loaded from now on
    try:  # and for those already loaded (a forked worker inherits numpy's OpenBLAS)
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        pass
    else:
        threadpool_limits(1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


# ---------------------------------------------------------------------------- chunks
def default_chunk_size(n_variants: int, executor) -> int:
    """Variants per chunk: 1 chunk per ~20 variants serially; for an executor at least
    8 chunks per worker (load balance, resume granularity), at most 64 variants each."""
    workers = getattr(executor, "_max_workers", None) or 2
    if executor is None:
        return max(1, min(64, n_variants // 8 or 1))
    return max(1, min(64, -(-n_variants // (8 * workers))))


def make_tasks(values, chunk_size, base) -> list:
    """Split the variants into :class:`ChunkTask` s.

    Parameters
    ----------
    values : ndarray, shape (n_variants, n_parameters)
    chunk_size : int
    base : dict
        The other :class:`ChunkTask` fields (keys, applies, model_data, ...).
    """
    return [ChunkTask(index=i, start=start, values=values[start:start + chunk_size], **base)
            for i, start in enumerate(range(0, len(values), chunk_size))]


# ---------------------------------------------------------------------------- checkpoint
class Checkpoint:
    """A folder of finished chunks (``chunk-NNNNNN.npz``) and the study's fingerprint.

    Parameters
    ----------
    folder : path-like
    fingerprint : str
        Hash of everything that determines the results; a folder written by a
        different study is refused, not mixed in.
    seed : int, optional
        The seed the samples were drawn with (kept so that a study without a
        seed of its own resumes with the same samples).
    """

    @staticmethod
    def saved_seed(folder):
        """The seed recorded in a checkpoint folder (None if there is none)."""
        manifest = Path(folder) / "study.json"
        return json.loads(manifest.read_text()).get("seed") if manifest.exists() else None

    def __init__(self, folder, fingerprint: str, seed=None):
        self.folder = Path(folder)
        self.fingerprint = fingerprint
        manifest = self.folder / "study.json"
        if manifest.exists():
            found = json.loads(manifest.read_text()).get("fingerprint")
            if found != fingerprint:
                raise InputError(f"{self.folder}: holds the chunks of a different study (other model, "
                                 "study file or chunk size); delete the folder to start afresh")
        else:
            self.folder.mkdir(parents=True, exist_ok=True)
            _atomic_bytes(manifest, json.dumps({"fingerprint": fingerprint, "seed": seed}).encode())

    def done(self) -> dict:
        """Finished chunks: index -> chunk result."""
        out = {}
        for path in sorted(self.folder.glob("chunk-*.npz")):
            with np.load(path, allow_pickle=False) as data:
                chunk = {name: data[name] for name in data.files}
            chunk["index"], chunk["start"] = int(chunk["index"]), int(chunk["start"])
            out[chunk["index"]] = chunk
        return out

    def save(self, chunk: dict) -> None:
        """Write one finished chunk (atomically: a chunk is there whole or not at all)."""
        import io

        buffer = io.BytesIO()
        np.savez(buffer, **chunk)
        _atomic_bytes(self.folder / f"chunk-{chunk['index']:06d}.npz", buffer.getvalue())

    def remove(self) -> None:
        remove_checkpoint(self.folder)


def remove_checkpoint(folder) -> None:
    """Delete a checkpoint folder's chunks and manifest (and the folder when empty)."""
    folder = Path(folder)
    for path in folder.glob("chunk-*.npz"):
        path.unlink()
    with contextlib.suppress(OSError):
        (folder / "study.json").unlink()
    with contextlib.suppress(OSError):
        folder.rmdir()


def _atomic_bytes(path: Path, payload: bytes) -> None:
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    temporary.write_bytes(payload)
    os.replace(temporary, path)


def fingerprint(*parts) -> str:
    """SHA-256 of a JSON rendering of ``parts`` (arrays as lists)."""
    def default(value):
        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, np.generic):
            return value.item()
        return repr(value)

    text = json.dumps(parts, sort_keys=True, default=default)
    return hashlib.sha256(text.encode()).hexdigest()


# ---------------------------------------------------------------------------- running
def execute(tasks, executor=None, checkpoint: Checkpoint | None = None, progress: bool = False,
            total: int | None = None):
    """Run the chunks not yet in ``checkpoint``; save each as it arrives.

    Parameters
    ----------
    tasks : list of ChunkTask
    executor : concurrent.futures.Executor or None
        ``None`` runs serially in this process; otherwise ``executor.map`` is used.
    checkpoint : Checkpoint, optional
    progress : bool
        tqdm progress bar over variants.
    total : int, optional
        Number of variants (for the bar).

    Returns
    -------
    chunks : list of dict
        Every chunk's result, in chunk order.
    resumed : int
        Chunks taken from the checkpoint rather than computed.
    """
    done = checkpoint.done() if checkpoint is not None else {}
    todo = [task for task in tasks if task.index not in done]
    bar = _bar(progress, total, sum(len(t.values) for t in tasks if t.index in done))
    mapper = map if executor is None else executor.map
    try:
        for chunk in mapper(run_chunk, todo):
            if checkpoint is not None:
                checkpoint.save(chunk)
            done[chunk["index"]] = chunk
            if bar is not None:
                bar.update(len(chunk["error"]))
    finally:
        if bar is not None:
            bar.close()
    return [done[task.index] for task in tasks], len(tasks) - len(todo)


def _bar(enabled, total, initial):
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, desc="study", unit="variant")
