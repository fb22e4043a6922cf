"""Running the variants: chunks through ``Executor.map``, one BLAS thread per worker,
failures recorded, finished chunks saved so that an interrupted study resumes.

The worker function :func:`run_chunk` is a plain module-level function of a
picklable :class:`ChunkTask`, so any ``concurrent.futures`` executor serves:
``None`` (serial, in this process), ``ProcessPoolExecutor``,
``dask.distributed.Client.get_executor()``, ``mpi4py.futures.MPIPoolExecutor``.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import logging
import os
import socket
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._limits import MEMORY_ENVIRONMENT, memory_room
from ..errors import InputError, OutputError
from .analyses import batch_caches, run_analyses

__all__ = ["ChunkTask", "run_chunk", "make_tasks", "execute", "Checkpoint", "finished_chunks", "ResultsLock", "limit_threads",
           "worker_initializer", "default_chunk_size", "remove_checkpoint", "check_memory", "check_disk",
           "check_cpu_time", "check_analyses_fit", "check_spool", "variant_bound", "variant_parts"]


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


def variant_model(model_data, source, keys, applies, values, base=None):
    """The validated model of one variant.

    Parameters
    ----------
    model_data : dict
        Base model description.
    keys, applies : see :class:`ChunkTask`
    values : array_like, shape (n_parameters,)
    base : Model, optional
        The base model (built from ``model_data``): the variant is made from it with
        :meth:`~rotordyn_modal.model.machine.Model.variant`, which validates only the tables the
        parameters change. The model is the same either way.

    Returns
    -------
    Model
    """
    if base is not None:
        return base.variant([(key, apply, float(value))
                             for group, apply, value in zip(keys, applies, values) for key in group])
    from ..model._validation import plain_copy
    from ..model.machine import Model
    from ..model.parameters import scale_value, set_value

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
        ``index``, ``start``, ``error`` (ndarray of str, '' where it worked),
        ``warning`` (ndarray of str: the first line :func:`~rotordyn_modal.plausibility.implausible`
        says of the variant's model, as ``check`` would warn; '' for none) and each output
        variable stacked over the chunk's variants.
    """
    context = limit_threads() if task.single_thread else contextlib.nullcontext()
    n = len(task.values)
    out = {name: np.full((n,) + shape, np.nan) for name, shape in task.shapes.items()}
    errors, warned = [""] * n, [""] * n
    with context:
        base = _base_model(task)
        models = [_try(variant_model, errors, row, task.model_data, task.model_source, task.keys, task.applies,
                       values, base) for row, values in enumerate(task.values)]
        built = [row for row, model in enumerate(models) if model is not None]
        for row in built:
            warned[row] = first_implausible(models[row])
        caches = dict(zip(built, batch_caches([models[row] for row in built], task.analyses)))
        for row in built:
            analysed = _try(run_analyses, errors, row, models[row], task.analyses, task.layouts, caches[row])
            for name, array in (analysed or {}).items():
                out[name][row] = array
    return {"index": task.index, "start": task.start, "error": np.array(errors, dtype=str),
            "warning": np.array(warned, dtype=str), **out}


def first_implausible(model) -> str:
    """The first warning ``load_model`` would give of ``model`` (legal but probably not meant:
    :func:`~rotordyn_modal.plausibility.implausible`), or '' (none, or a check that fails: the
    analyses then say what is wrong)."""
    from ..plausibility import implausible

    try:
        lines = implausible(model)
    except Exception:  # noqa: BLE001 - a warning only; the variant's analyses refuse what is wrong
        return ""
    return lines[0] if lines else ""


def _base_model(task: ChunkTask):
    """The base model the chunk's variants are made from, or None when it cannot be built
    (then each variant is built from the description alone and records its own error)."""
    from ..model.machine import Model

    try:
        return Model.from_dict(task.model_data, task.model_source)
    except Exception:  # noqa: BLE001 - the variants report it
        return None


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


def worker_initializer(parent=None):
    """Initializer of the study's process pool: one thread per library, Ctrl-C left
    to the parent (which saves finished chunks and stops the pool); on Linux the
    worker ends with its parent (``parent``: the parent's process id)."""
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
    if _die_with_parent(parent):  # SIGTERM/SIGHUP sent to the process group: the parent stops
        for name in ("SIGTERM", "SIGHUP"):  # the study, and the worker ends with it
            signal.signal(getattr(signal, name), signal.SIG_IGN)


def _die_with_parent(parent=None) -> bool:
    """Linux: end this worker when the study's process ends, even by ``kill -9`` (which
    leaves it no chance to stop its pool), rather than finish a chunk nobody will save.
    Returns whether it is so."""
    import signal

    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        return False
    if parent is not None and os.getppid() != parent:  # the parent died before prctl
        os._exit(1)
    return parent is not None


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
_LOG = logging.getLogger("rotordyn_modal.study")


class Checkpoint:
    """A folder of finished chunks and the study's fingerprint.

    Each finished chunk is two files, each written atomically (temporary file in the
    folder, then renamed): ``chunk-NNNNNN.npz`` (the arrays) and then
    ``chunk-NNNNNN.json``, its manifest (study fingerprint, index, first variant,
    number of variants, size and SHA-256 of the ``.npz``). A chunk counts as finished
    only when its manifest is there and every item of it matches; anything else (no
    manifest: the process died between the two renames; a truncated, altered or
    foreign file) is deleted and computed again, never trusted.

    Parameters
    ----------
    folder : path-like
    fingerprint : str
        Hash of everything that determines the results; a folder written by a
        different study is refused, not mixed in.
    seed : int, optional
        The seed the samples were drawn with (kept so that a study without a
        seed of its own resumes with the same samples).
    chunk_size : int, optional
        The variants per chunk (kept so that a study whose chunk size was chosen
        for its executor resumes with the same chunks: :meth:`saved_chunk_size`).
    """

    @staticmethod
    def saved_seed(folder):
        """The seed recorded in a checkpoint folder (None if there is none or it is unreadable)."""
        recorded = _read_json(Path(folder) / "study.json")
        return recorded.get("seed") if recorded else None

    @staticmethod
    def saved_chunk_size(folder):
        """The chunk size recorded in a checkpoint folder (None if there is none, it is unreadable
        or was written before chunk sizes were recorded), so that a study whose chunk size was
        chosen for its executor resumes with the same chunks on another one (a pool of fewer
        workers after one died, another ``--workers``)."""
        recorded = _read_json(Path(folder) / "study.json")
        size = recorded.get("chunk_size") if recorded else None
        return size if isinstance(size, int) and not isinstance(size, bool) and size >= 1 else None

    def __init__(self, folder, fingerprint: str, seed=None, chunk_size=None):
        self.folder = Path(folder)
        self.fingerprint = fingerprint
        _check_folder(self.folder)
        manifest = self.folder / "study.json"
        recorded = _read_json(manifest)
        if recorded is None and manifest.exists():
            _LOG.warning("%s is unreadable: the chunks of %s are discarded and computed again",
                         manifest, self.folder)
            remove_checkpoint(self.folder, keep_folder=True)
        if recorded is not None and recorded.get("fingerprint") != fingerprint:
            raise InputError(f"{self.folder}: holds the chunks of a different study (other model, "
                             "study file or chunk size); delete the folder to start afresh")
        if recorded is None:
            self.folder.mkdir(parents=True, exist_ok=True)
            _atomic_bytes(manifest, json.dumps({"fingerprint": fingerprint, "seed": seed,
                                                "chunk_size": chunk_size}).encode())

    def done(self, tasks=None) -> dict:
        """Finished chunks whose files check out: index -> chunk result.

        Parameters
        ----------
        tasks : list of ChunkTask, optional
            When given, a chunk must also match its task (first variant, count).
        """
        return dict(self.each_done(tasks))

    def each_done(self, tasks=None, indices=None):
        """Like :meth:`done`, one ``(index, chunk)`` at a time (memory holds one chunk);
        ``indices``: only these chunks."""
        expected = {task.index: task for task in tasks} if tasks is not None else None
        for path in sorted(self.folder.glob("chunk-*.npz")):
            index = _chunk_index(path)
            if indices is not None and index not in indices:
                continue
            task = None if expected is None or index is None else expected.get(index)
            try:
                chunk = self._verified(path, index, task, expected is not None)
            except _Untrusted as reason:
                _LOG.warning("chunk %s in %s discarded (%s); it is computed again", index, self.folder, reason)
                for stale in (path, path.with_suffix(".json")):
                    with contextlib.suppress(OSError):
                        stale.unlink()
                continue
            yield index, chunk

    def _verified(self, path, index, task, need_task) -> dict:
        if index is None:
            raise _Untrusted(f"unexpected file name {path.name}")
        if need_task and task is None:
            raise _Untrusted("no such chunk in this study")
        manifest = _read_json(path.with_suffix(".json"))
        if manifest is None:
            raise _Untrusted("no readable manifest: the chunk was not finished")
        payload = path.read_bytes()
        found = {"fingerprint": self.fingerprint, "index": index, **_digest(payload)}
        for key, value in found.items():
            if manifest.get(key) != value:
                raise _Untrusted(f"{key} {value!r} differs from its manifest's {manifest.get(key)!r}")
        chunk = _unpack(payload)
        if int(chunk["index"]) != index or int(chunk["start"]) != manifest.get("start") \
                or len(chunk["error"]) != manifest.get("n"):
            raise _Untrusted("its contents differ from its manifest")
        if task is not None and (task.start != manifest["start"] or len(task.values) != manifest["n"]):
            raise _Untrusted("it covers other variants than this study's chunk")
        chunk["index"], chunk["start"] = index, int(chunk["start"])
        return chunk

    def save(self, chunk: dict) -> None:
        """Write one finished chunk: its arrays, then its manifest (each atomically)."""
        import io

        buffer = io.BytesIO()
        np.savez(buffer, **chunk)
        payload = buffer.getvalue()
        path = self.folder / f"chunk-{chunk['index']:06d}.npz"
        _atomic_bytes(path, payload)
        manifest = {"fingerprint": self.fingerprint, "index": int(chunk["index"]), "start": int(chunk["start"]),
                    "n": int(len(chunk["error"])), **_digest(payload)}
        _atomic_bytes(path.with_suffix(".json"), json.dumps(manifest).encode())

    def saved(self) -> int:
        """The chunk files in the folder (those :meth:`each_done` reads; some may not check out)."""
        return sum(1 for _ in self.folder.glob("chunk-*.npz"))

    def remove(self) -> None:
        remove_checkpoint(self.folder)


def _check_folder(folder: Path) -> None:
    """Refuse a checkpoint folder that cannot be one: a file (or a link to one) in its place,
    a parent that is not a folder."""
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{folder}: a file is where the study keeps its checkpoint folder; move or "
                          "delete it (or give another --out)")
    if folder.is_symlink() and not folder.exists():
        raise OutputError(f"{folder}: a symbolic link to {os.readlink(folder)}, which {_dangling(folder)}, is where "
                          "the study keeps its checkpoint folder; remove the link or create its folder "
                          "(or give another --out)")
    if folder.parent.exists() and not folder.parent.is_dir():
        raise OutputError(f"{folder}: {folder.parent} is not a folder")


def _dangling(link: Path) -> str:
    """What a link that leads to no file leads to: "does not exist", or a loop of links (its
    target exists, a link itself: it was said not to exist)."""
    try:
        os.stat(link)
    except OSError as error:
        if error.errno == errno.ELOOP:
            return "leads back to it (a loop of links)"
    return "does not exist"


def _digest(payload: bytes) -> dict:
    """What a chunk's manifest records of its ``.npz`` bytes: size and SHA-256."""
    return {"bytes": len(payload), "sha256": hashlib.sha256(payload).hexdigest()}


def finished_chunks(folder) -> int:
    """Number of chunks of a checkpoint folder with a manifest (for messages;
    :meth:`Checkpoint.done` checks them)."""
    return len(list(Path(folder).glob("chunk-*.json")))


class _Untrusted(Exception):
    """A checkpoint file that is not a finished chunk of this study."""


def _chunk_index(path: Path):
    digits = path.stem[len("chunk-"):]
    return int(digits) if digits.isdigit() else None


def _unpack(payload: bytes) -> dict:
    import io
    import zipfile

    try:
        with np.load(io.BytesIO(payload), allow_pickle=False) as data:
            return {name: data[name] for name in data.files}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
        raise _Untrusted(f"unreadable ({type(error).__name__})") from None


#: the largest manifest read [bytes]; the package writes a few hundred
_MANIFEST_BYTES = 65536


def _read_json(path: Path):
    """The object in a JSON file, or None when it is missing, unreadable, larger than any
    manifest the package writes or nested too deeply to parse."""
    try:
        with open(path, "rb") as handle:
            payload = handle.read(_MANIFEST_BYTES + 1)
        if len(payload) > _MANIFEST_BYTES:
            return None
        value = json.loads(payload)
    except (OSError, ValueError, RecursionError):
        return None
    return value if isinstance(value, dict) else None


def remove_checkpoint(folder, keep_folder: bool = False) -> None:
    """Delete a checkpoint folder's chunks, manifests and leftover temporary files
    (and the folder when empty)."""
    folder = Path(folder)
    for pattern in ("chunk-*.npz", "chunk-*.json", ".chunk-*", ".study.json.*", "study.json"):
        for path in folder.glob(pattern):
            with contextlib.suppress(OSError):
                path.unlink()
    if not keep_folder:
        with contextlib.suppress(OSError):
            folder.rmdir()


def _atomic_bytes(path: Path, payload: bytes) -> None:
    from ..io import atomic_write

    with atomic_write(path, "wb", together=False, tidy=False) as handle:  # in place at once, for a resume
        handle.write(payload)


# ---------------------------------------------------------------------------- memory
def check_memory(n_variants: int, per_variant: int, chunk_size: int, definition, outputs: str,
                 held: int | None = None) -> None:
    """Refuse, before any work, a study whose results cannot fit in memory.

    Assembled in memory (:class:`~rotordyn_modal.study.results.Assembly`), the results are held
    once and written a block at a time; written to their file chunk by chunk
    (:class:`~rotordyn_modal.study.results.ResultsWriter`), only ``held`` bytes per variant stay
    (:func:`~rotordyn_modal.study.results.held_bytes`). A chunk is held a few times more while
    it is saved.

    Parameters
    ----------
    n_variants, per_variant : int
        Variants, and bytes of one variant's results.
    chunk_size : int
    definition : StudyDefinition
        The study (its file and the key that sets the number of variants, for the message).
    outputs : str
        The largest outputs per variant, for the message ('frequency_hz 201 x 6, ... per variant').
    held : int, optional
        Bytes per variant kept in memory (default ``per_variant``: the results in memory).

    Raises
    ------
    InputError
        ``STUDY: samples = N: N variants x X kB (...) = Y GB of results need about Z GB of memory,
        more than the W GB left (LIMIT): ADVICE``, one line.
    """
    streamed = held is not None
    held = per_variant if held is None else held
    needed = n_variants * held + 4 * chunk_size * per_variant + 2**26
    available, limit = memory_room()
    if needed <= available:
        return
    results = n_variants * per_variant
    if streamed:
        what = (f"{n_variants:,} variants need about {needed / 1e9:.4g} GB of memory ({held:,} bytes each of "
                f"numbers read whole after the run; their {results / 1e9:.4g} GB of results go to the file chunk "
                f"by chunk)")
    else:
        what = (f"{n_variants:,} variants x {per_variant / 1e3:.4g} kB ({outputs}) = {results / 1e9:.4g} GB "
                f"of results need about {needed / 1e9:.4g} GB of memory")
    fit = int(max(available - 4 * chunk_size * per_variant - 2**26, 0) // max(held, 1))
    raise InputError(f"{_where(definition)}{what}, more than the {max(available, 0) / 1e9:.4g} GB left ({limit}): "
                     f"run fewer variants (about {fit:,} fit){'' if streamed else ', write the results to a file as they come (out=)'}, "
                     f"or split the study into several ({MEMORY_ENVIRONMENT} sets the memory to count on)")


def _where(definition) -> str:
    """``'STUDY: samples = 1000000: '``: the study file and the key that sets its variants."""
    from .definition import count_key

    key, value = count_key(definition.parameters, definition.samples)
    return f"{definition.source}: {key} = {value!r}: "


def check_disk(folder, n_variants: int, per_variant: int, definition, outputs: str) -> None:
    """Refuse, before any work, a study whose checkpoint and results file cannot fit on the
    disk of its checkpoint ``folder``: both hold the results (the checkpoint is removed only
    once the results file is written); chunks already saved there count as room.

    Raises
    ------
    InputError
        ``STUDY: samples = N: N variants x X kB (...) need about Y GB on the disk of FOLDER (...),
        more than the Z GB free there: ADVICE``, one line.
    """
    import shutil

    folder = Path(folder)
    place = next((p for p in (folder, *folder.parents) if p.exists()), None)
    try:
        free = shutil.disk_usage(place).free if place is not None else None
    except OSError:
        free = None
    if free is None:
        return
    saved = sum(p.stat().st_size for p in folder.glob("chunk-*.npz")) if folder.is_dir() else 0
    needed = 2 * n_variants * per_variant - saved
    if needed > free:
        fit = int(max(free + saved, 0) // max(2 * per_variant, 1))
        raise InputError(f"{_where(definition)}{n_variants:,} variants x {per_variant / 1e3:.4g} kB ({outputs}) need "
                         f"about {needed / 1e9:.4g} GB on the disk of {folder} (the checkpoint and the results file, "
                         f"each {n_variants * per_variant / 1e9:.4g} GB), more than the {free / 1e9:.4g} GB free "
                         f"there: run fewer variants (about {fit:,} fit), free space, or give an --out on a larger disk")


def check_spool(folder, n_variants: int, per_variant: int, definition, outputs: str) -> None:
    """Refuse, before any work, a study of ``rdm.study`` without ``out=`` whose results, too large
    for memory (``SPOOL_BYTES``), would not fit in the free space of the temporary ``folder``.

    Raises
    ------
    InputError
        ``STUDY: samples = N: N variants x X kB (...) = Y GB of results, kept in a temporary file in
        FOLDER (...), more than the Z GB free there: ADVICE``, one line.
    """
    import shutil

    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    needed = n_variants * per_variant
    if needed <= free:
        return
    fit = int(free // max(per_variant, 1))
    raise InputError(f"{_where(definition)}{n_variants:,} variants x {per_variant / 1e3:.4g} kB ({outputs}) = "
                     f"{needed / 1e9:.4g} GB of results, kept in a temporary file in {folder} (rdm.study without "
                     f"out=, results too large for memory), more than the {free / 1e9:.4g} GB free there: give "
                     f"out= a file on a larger disk (or set TMPDIR), or run fewer variants (about {fit:,} fit)")


def check_cpu_time(model, definition, n_variants: int, first=None) -> None:
    """Refuse, before any work, a study estimated to take more CPU time than the limit the other
    commands keep (``ROTORDYN_MODAL_MAX_CPU_MINUTES``, 30 min by default), unless long work is
    allowed (``--allow-long``, ``with rdm.long_work_allowed():`` in Python): its variants times
    the estimate of one variant's analyses on the base model (:func:`variant_parts`) and of making
    it (``first``: the first variant's parameter values, ndarray (n_parameters,), timed).

    Raises
    ------
    InputError
        ``STUDY: samples = N: N variants x about X s of CPU time each (PARTS; MODEL as the
        study's base model) = about Y h of CPU time, more than the limit of 30 min: ADVICE``, one
        line.
    """
    from ..analysis import _cost

    if _cost.long_work_is_allowed() or n_variants == 0:
        return
    limit = _cost.limit_seconds()
    if limit == float("inf") or n_variants * variant_bound(model, definition.analyses) <= limit:
        return
    parts = variant_parts(model, definition.analyses)
    if first is not None:
        parts.append(_making_part(model, definition, first))
    each = sum(seconds for _, seconds in parts)
    if n_variants * each <= limit:
        return
    fit = int(limit // max(each, 1e-12))
    fewer = (f"run fewer variants (about {fit:,} fit)" if fit else
             "one variant alone takes longer than the limit: ask its analyses for fewer speeds")
    text = "; ".join(text for text, _ in parts)
    raise InputError(f"{_where(definition)}{n_variants:,} variants x about {_cost.duration(each)} of CPU time each "
                     f"({text}; {model.source} as the study's base model) = about {_cost.duration(n_variants * each)} "
                     f"of CPU time, more than the limit of {_cost.duration(limit)}: {fewer}, or add --allow-long "
                     f"(rdm.long_work_allowed() in Python; {_cost.ENVIRONMENT} sets the limit)")


def variant_bound(model, analyses) -> float:
    """A pessimistic bound of one variant's CPU time [s] from the sizes alone (no timing, no
    matrices): of :func:`variant_parts` and of making the variant. It passes small studies
    before anything is measured."""
    from ..analysis import _work

    seconds = _MAKING_BOUND * (1 + model.dofs.n / 100)
    seconds += sum(_work._quick_bound(model, *run) for _, run in _variant_runs(analyses))
    if "unbalance" in analyses:
        seconds += _unbalance_bound(model, analyses["unbalance"])
    return seconds


def variant_parts(model, analyses) -> list:
    """What one variant's analyses cost on the base model: ``(text, seconds)`` per part.

    - the eigen-solutions and crossings of the Campbell sweep (shared by ``campbell`` and
      ``critical_speeds``), the stability sweep and the modes' one speed: the estimate of the
      commands that run them (:func:`rotordyn_modal.analysis._work.estimate`, docs/theory.md,
      "How long a sweep takes");
    - the unbalance responses, which solve no eigenproblem (a linear system per speed and
      source, and the peaks of every curve): the study's own analysis timed on the base model
      (:func:`_unbalance_seconds`).
    """
    from ..analysis import _work

    parts = []
    for name, run in _variant_runs(analyses):
        work = _work.estimate(model, *run)
        parts.append((f"{name}: {work.text().replace(' of CPU time', '')}", work.seconds))
    if "unbalance" in analyses:
        options = analyses["unbalance"]
        seconds = _unbalance_seconds(model, options)
        parts.append((f"unbalance at {len(options['speeds']):,} speeds: about {_duration(seconds)}, timed on the "
                      "base model", seconds))
    return parts


def _making_part(model, definition, values) -> tuple:
    """``(text, seconds)`` of making one variant from the base model and checking it
    (:func:`variant_model`, :func:`first_implausible`), timed on the variant of parameter values
    ``values`` (the shortest of three timings); 0 where it fails (the variants record why)."""
    import time

    keys, applies = tuple(p.keys for p in definition.parameters), tuple(p.apply for p in definition.parameters)
    try:
        best = float("inf")
        for _ in range(3):
            start = time.process_time()
            first_implausible(variant_model(None, model.source, keys, applies, values, model))
            best = min(best, time.process_time() - start)
    except Exception:  # noqa: BLE001 - the variants record what fails
        best = 0.0
    return f"making and checking the variant: about {_duration(best)}", best


def _duration(seconds: float) -> str:
    from ..analysis._cost import duration

    return duration(seconds)


def _variant_runs(analyses) -> list:
    """The eigen-solutions of one variant's analyses: ``(name, arguments of _work.estimate after
    the model: (speeds, orders, critical, numbers, solutions))``."""
    runs = []
    if "campbell" in analyses or "critical_speeds" in analyses:  # one sweep, shared, with its crossings
        options = analyses.get("campbell") or analyses["critical_speeds"]
        name = " and ".join(n.replace("_", " ") for n in ("campbell", "critical_speeds") if n in analyses)
        runs.append((name, (options["speeds"], options["orders"], True, False, len(options["speeds"]))))
    if "stability" in analyses:
        speeds = analyses["stability"]["speeds"]
        runs.append(("stability", (speeds, (), False, False, len(speeds))))
    if "modes" in analyses:
        runs.append(("modes", (np.array([analyses["modes"]["speed"]]), (), False, False, 1)))
    return runs


#: pessimistic CPU seconds of one unbalance analysis's fixed part (its forces, sensors' rows,
#: force rows, tables) and of each speed and source beside its solve, for a bound without timing
#: (measured about 5 ms and 30 us on the bundled examples, one thread)
_UNBALANCE_CALL_BOUND, _UNBALANCE_SPEED_BOUND = 0.1, 1e-3
#: pessimistic CPU seconds of making and checking a variant of 100 coordinates, for a bound without
#: timing (measured 0.3-0.7 ms on the gear machine's 6)
_MAKING_BOUND = 0.01
#: speeds of the longer timing of :func:`_unbalance_seconds` (the shorter takes 2)
_TIMED_SPEEDS = 32


def _unbalance_bound(model, options) -> float:
    """A pessimistic bound of :func:`_unbalance_seconds` from the sizes alone: a fixed part and, per
    speed and source, a dense complex solve (four real ones) of every coordinate."""
    from ..analysis._cost import _PESSIMISTIC

    per = _UNBALANCE_SPEED_BOUND + 4 * _PESSIMISTIC * float(model.dofs.n) ** 3
    return _UNBALANCE_CALL_BOUND + len(options["speeds"]) * max(len(model.unbalances), 1) * per


def _unbalance_seconds(model, options) -> float:
    """CPU seconds of one variant's unbalance analysis, timed on the base model (one BLAS thread,
    as a study's workers run): the analysis at 2 of its speeds and at up to ``_TIMED_SPEEDS``
    (spread over its range; each the shortest of a few timings), the time per speed taken from the
    two and scaled to every speed. 0 where the base model's analysis fails (each variant then
    records its own failure)."""
    import time

    from .analyses import ANALYSES

    speeds = options["speeds"]
    n = len(speeds)

    def timed(count: int) -> float:
        chosen = dict(options, speeds=speeds[np.unique(np.linspace(0, n - 1, count).round().astype(int))])
        _, _, layout = ANALYSES["unbalance"].describe(model, chosen)
        best = float("inf")
        for _ in range(3):
            start = time.process_time()
            ANALYSES["unbalance"].run(model, chosen, layout, {})
            best = min(best, time.process_time() - start)
            if best > 1.0:                                  # long enough to be measured once
                break
        return best

    few, more = min(n, 2), min(n, _TIMED_SPEEDS)
    try:
        with limit_threads():
            short = timed(few)
            if more == few:
                return short
            long = timed(more)
    except Exception:  # noqa: BLE001 - the variants record what fails; nothing to count
        return 0.0
    return short + max(long - short, 0.0) / (more - few) * (n - few)


def check_analyses_fit(model, definition) -> None:
    """Refuse, before any work, a study whose analyses cannot fit in memory for one variant: the
    Campbell sweep (shared by ``campbell`` and ``critical_speeds``, with its crossings) and the
    stability sweep, estimated on the base model as :func:`rotordyn_modal.analysis.campbell.campbell`
    estimates its own (``memory_estimate``; the variants have the base model's sizes). Each variant
    would otherwise fail with campbell's own refusal. The unbalance responses are solved a few MB
    at a time, the modes at one speed.

    Raises
    ------
    InputError
        ``STUDY: [analyses.campbell] speeds_rpm = '0:3000:101': one variant's Campbell sweep of
        606 coordinates at 101 speeds (MODEL as the study's base model) needs about X GiB of
        memory, Y GiB is available: ADVICE``, one line.
    """
    from .._limits import memory_problem
    from ..analysis._work import _n_states
    from ..analysis.campbell import _CHECKED_BYTES, memory_estimate

    sweeps = [(name, critical) for name, critical in (("campbell", True), ("critical_speeds", True),
                                                      ("stability", False)) if name in definition.analyses]
    if not sweeps:
        return
    n_dof, n_states = model.dofs.n, _n_states(model)
    for name, critical in sweeps:
        n_speeds = len(definition.analyses[name]["speeds"])
        needed = memory_estimate(n_dof, n_states, n_speeds, 1, critical)
        if needed < _CHECKED_BYTES:
            continue
        fixed = memory_estimate(n_dof, n_states, 0, 1, critical)
        per_speed = memory_estimate(n_dof, n_states, 1, 1, critical) - fixed
        fitting = int(max(0.0, memory_room()[0] - fixed) // max(per_speed, 1.0))
        advice = (f"ask [analyses.{name}] for fewer speeds (about {fitting:,} fit)" if fitting >= 2 else
                  "the base model is too large for this machine's memory at any number of speeds")
        sweep = "stability sweep" if name == "stability" else "Campbell sweep"
        problem = memory_problem(needed, f"{_analysis_where(definition, name)}one variant's {sweep} of {n_dof:,} "
                                 f"coordinates at {n_speeds:,} speeds ({model.source} as the study's base model)",
                                 advice)
        if problem:
            raise InputError(problem)


def _analysis_where(definition, name) -> str:
    """``'STUDY: [analyses.NAME] speeds_rpm = VALUE: '``: the study file and the key that sets the
    analysis's speeds (the Campbell sweep's, for critical speeds without their own)."""
    tables = definition.raw.get("analyses") or {}
    table = tables.get(name) or {}
    if "speeds_rpm" not in table and name == "critical_speeds":
        name, table = "campbell", tables.get("campbell") or {}
    return f"{definition.source}: [analyses.{name}] speeds_rpm = {table.get('speeds_rpm')!r}: "


# ---------------------------------------------------------------------------- one writer
def results_file(path) -> Path:
    """The file a study's results named ``path`` go to: symbolic links followed (a link, a
    linked folder), unless they lead to a device (``/dev/null``), which keeps its name."""
    import stat

    real = Path(os.path.realpath(path))
    try:
        special = not stat.S_ISREG(os.stat(real).st_mode)
    except (OSError, ValueError):
        special = False
    return Path(os.path.abspath(path)) if special else real


class ResultsLock:
    """Only one study at a time writes a results file (and its checkpoint folder).

    The lock is ``RESULTS.nc.lock`` holding the owner's process id and host, locked with
    an operating-system record lock (``fcntl.lockf``), which the system releases when
    its process ends in any way, ``kill -9`` included: a lock file left by a killed
    study is stale and taken over; one held by a running study makes the second study
    stop at once with an error naming the owner (studies are refused, not queued).
    Without ``fcntl`` (Windows) the file is created exclusively and a stale one is
    recognised by its process id no longer running.

    A results file that exists already is one file however it is named: symbolic links
    lead to one lock file, but hard links (one file, by its device and inode, under
    several names) do not, so the existing file itself is locked too (``fcntl.flock``,
    held by the file's device and inode, released as the record lock is): a second study
    writing it by any name is refused.

    Parameters
    ----------
    results : path-like
        The results file.
    """

    def __init__(self, results):
        self.results = Path(results)
        real = results_file(self.results)  # links followed: one lock per file, however named
        self.path = real.with_name(real.name + ".lock")
        self._fd = None
        self._file_fd = None
        self.previous_owner = None

    def __enter__(self):
        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows
            self._fd = self._acquire_exclusive()
        else:
            self._fd = self._acquire_record_lock(fcntl)
            try:
                self._file_fd = self._lock_existing_file(fcntl)
            except BaseException:
                self.__exit__()
                raise
        with contextlib.suppress(OSError):  # the owner's name is for messages only
            os.ftruncate(self._fd, 0)
            os.write(self._fd, f"{os.getpid()} {socket.gethostname()}\n".encode())
        if self.previous_owner:
            _LOG.info("lock %s of process %s (no longer running) taken over", self.path, self.previous_owner)
        return self

    def _acquire_record_lock(self, fcntl):
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as error:
                raise OutputError(f"cannot write {self.path}: {error.strerror}") from None
            try:
                fcntl.lockf(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                owner = _owner(fd)
                os.close(fd)
                raise self._busy(owner) from None
            try:  # the owner before us may have removed the file after we opened it
                same = os.path.samestat(os.fstat(fd), os.stat(self.path))
            except FileNotFoundError:
                same = False
            if same:
                self.previous_owner = _owner(fd)
                return fd
            os.close(fd)

    def _lock_existing_file(self, fcntl):
        """A lock on the existing results file itself (its device and inode: every name of
        it, hard links included), or None when there is no such regular file yet."""
        import stat

        real = results_file(self.results)
        try:
            fd = os.open(real, os.O_RDONLY)
        except OSError:
            return None     # not there yet (or unreadable: then it cannot be written either)
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                os.close(fd)
                return None
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            owner = _flock_owner(os.fstat(fd))
            os.close(fd)
            raise self._busy(owner, real) from None
        return fd

    def _acquire_exclusive(self):  # pragma: no cover - Windows
        from ..io.atomic import pid_alive

        while True:
            try:
                return os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                owner = _owner_of(self.path)
                pid = owner.split()[0] if owner else ""
                if pid.isdigit() and pid_alive(int(pid)):
                    raise self._busy(owner) from None
                self.previous_owner = owner
                with contextlib.suppress(OSError):
                    os.unlink(self.path)

    def _busy(self, owner, lock=None):
        who = f"process {owner}" if owner else "another process"
        return OutputError(f"{self.results}: another study ({who}) is writing it (lock {lock or self.path}); "
                           "wait for it to finish or give another --out")

    def __exit__(self, *exc):
        with contextlib.suppress(OSError):
            os.unlink(self.path)
        for fd in (self._file_fd, self._fd):
            if fd is not None:
                os.close(fd)
        self._fd = self._file_fd = None
        return False


def _owner(fd) -> str:
    try:
        os.lseek(fd, 0, os.SEEK_SET)
        return os.read(fd, 200).decode(errors="replace").strip()
    except OSError:
        return ""


def _flock_owner(status) -> str:
    """The process id holding a ``flock`` on the file of ``status`` (os.stat_result), from
    ``/proc/locks`` (Linux), or '' where that cannot be read."""
    inode = f"{os.major(status.st_dev):02x}:{os.minor(status.st_dev):02x}:{status.st_ino}"
    with contextlib.suppress(OSError):
        with open("/proc/locks") as locks:
            for line in locks:
                fields = line.split()      # 1: FLOCK ADVISORY WRITE 1234 08:02:5678 0 EOF
                if len(fields) > 5 and fields[1] == "FLOCK" and fields[3] == "WRITE" and fields[5] == inode:
                    return fields[4]
    return ""


def _owner_of(path) -> str:  # pragma: no cover - Windows
    try:
        return Path(path).read_text(errors="replace").strip()
    except OSError:
        return ""


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
            total: int | None = None, sink=None):
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
    sink : callable, optional
        Given every chunk (resumed or computed) as it comes, which is then let go: memory
        holds one chunk at a time (per worker), not all of them. The saved chunks come first,
        each read once, before the pool's workers start.

    Returns
    -------
    chunks : list of dict
        Every chunk's result, in chunk order (empty with ``sink``).
    resumed : int
        Chunks taken from the checkpoint rather than computed.
    """
    kept = {} if sink is None else None
    resumed = set()
    if checkpoint is not None:
        saved = _saved_bar(progress, checkpoint.each_done(tasks), checkpoint.saved(), "reading saved chunks")
        for index, chunk in saved:  # each read once: checked, handed on and let go before the pool starts
            resumed.add(index)
            if kept is not None:
                kept[index] = chunk
            else:
                sink(chunk)
    todo = [task for task in tasks if task.index not in resumed]
    mapper = map if executor is None else executor.map
    bar = None
    try:
        computed = mapper(run_chunk, todo)
        # after the saved chunks' own bar: one bar on the terminal at a time
        bar = _bar(progress, total, sum(len(t.values) for t in tasks if t.index in resumed))
        for task in tasks:
            if task.index in resumed:
                _LOG.info("chunk %d resumed (variants %d-%d)", task.index, task.start,
                          task.start + len(task.values) - 1)
        for chunk in computed:
            if checkpoint is not None:
                checkpoint.save(chunk)
            if kept is not None:
                kept[chunk["index"]] = chunk
            else:
                sink(chunk)
            _LOG.info("chunk %d computed (variants %d-%d)", chunk["index"], chunk["start"],
                      chunk["start"] + len(chunk["error"]) - 1)
            if bar is not None:
                bar.update(len(chunk["error"]))
    finally:
        if bar is not None:
            bar.close()
    return ([kept[task.index] for task in tasks] if kept is not None else []), len(resumed)


def _saved_bar(enabled, chunks, total: int, description: str):
    """``chunks`` (the ``(index, chunk)`` pairs of :meth:`Checkpoint.each_done`) as they come, with
    a bar over them where ``enabled`` (``total`` chunk files; gone when done): a resumed study reads
    and checks every saved chunk before the work (each once; it was twice, 33 s for 439 chunks of
    30,000 variants, with no sign of progress)."""
    if not enabled or not total:
        return chunks
    from .._progress import tqdm

    return tqdm(chunks, total=total, desc=description, unit="chunk", leave=False)


def _bar(enabled, total, initial):
    if not enabled:
        return None
    from .._progress import tqdm

    return tqdm(total=total, initial=initial, desc="study", unit="variant")
