"""Parameter studies: tolerance Monte Carlo, designs of experiments and grids over
model variants, run serially or through any ``concurrent.futures`` executor.

    >>> import rotordyn_modal as rdm
    >>> from rotordyn_modal.study import parse_study
    >>> model = rdm.load_model("examples/gear_machine.toml")
    >>> spec = parse_study({"seed": 1, "samples": 4, "parameters": [
    ...     {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
    ...     "analyses": {"modes": {"speed_rpm": 0.0}}}, model=model)
    >>> result = rdm.study(model, spec)
    >>> result.dataset["modal_frequency_hz"].shape
    (4, 6)

The study file is described in ``docs/study-file.md``. This module is callable:
``rdm.study(model, spec, ...)`` is :func:`study` (see its docstring for the arguments).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import types
import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError, ModelWarning
from .definition import Parameter, StudyDefinition, StudyError, parse_study, read_study
from .results import StudyResult, load_study
from .sampling import sample_variants

__all__ = ["study", "StudyResult", "StudyDefinition", "StudyError", "Parameter", "read_study", "ImplausibleVariants",
           "parse_study", "load_study", "sample_variants", "checkpoint_folder"]


def checkpoint_folder(out) -> Path:
    """The folder where a study writing ``out`` keeps its finished chunks: ``OUT.partial``
    beside the file ``out`` names (links followed, so that two names of one file share it)."""
    from .execution import results_file

    out = results_file(out)
    return out.with_name(out.name + ".partial")


def study(model, spec, executor=None, checkpoint=None, chunk_size: int | None = None,
          progress: bool = False, out=None) -> StudyResult:
    """Run a parameter study: every variant through the study's analyses.

    Parameters
    ----------
    model : Model
        The base model.
    spec : StudyDefinition, dict or path-like
        The study (``docs/study-file.md``): a parsed definition, a description
        with the file's structure, or the path of a TOML study file.
    executor : concurrent.futures.Executor, optional
        ``None`` runs serially in this process. Otherwise chunks of variants go
        through ``executor.map`` (a ``ProcessPoolExecutor``,
        ``dask.distributed.Client(...).get_executor()``, ...) and each worker
        uses one BLAS thread.
    checkpoint : path-like, optional
        Folder where finished chunks are saved as they complete; running the
        same study again with the same folder computes only the missing chunks.
    chunk_size : int, optional
        Variants per chunk (default: the study file's ``chunk_size``, else
        chosen from the number of variants and workers).
    progress : bool
        Show a progress bar (tqdm) over variants.
    out : path-like, optional
        The netCDF file of the results (``.nc``), written whole or not at all: each chunk goes
        into it as it comes (a temporary file beside it, renamed at the end), so that memory
        holds a chunk, not the results. The result then reads its data set from the file as it
        is used (``xarray``'s lazy loading); the file is the one :meth:`StudyResult.save` writes.
        A device (``/dev/null``) is written once the results are assembled in memory. Without
        it, results up to :data:`SPOOL_BYTES` (256 MiB) are held in memory; larger ones go the
        same way to a temporary file in ``TMPDIR``, unlinked at once, whose space is freed by
        :meth:`StudyResult.close`, the end of a ``with`` block or garbage collection.

    Returns
    -------
    StudyResult
        One data set over (variant, speed, mode, ...); failed variants are NaN
        with their reason in ``error``.

    Raises
    ------
    InputError
        Before any work, in one line with the estimate: results that cannot fit in memory or on
        the disk (of the checkpoint, of the temporary file); a base model whose Campbell or
        stability sweep cannot fit in memory; a study estimated to take more CPU time than the
        limit every command keeps (``ROTORDYN_MODAL_MAX_CPU_MINUTES``, 30 min), unless run inside
        ``with rdm.long_work_allowed():`` (the command line's ``--allow-long``).

    Warns
    -----
    ImplausibleVariants
        Once, when some variants' models are legal but probably not meant (what ``check`` warns
        of, :func:`~rotordyn_modal.plausibility.implausible`: a 35 µm shaft, a sag of metres):
        how many, and the first one's warning. The results are the same either way.
    """
    from .analyses import describe
    from .execution import (Checkpoint, check_analyses_fit, check_cpu_time, check_disk, check_memory,
                            check_spool, default_chunk_size, fingerprint, make_tasks)
    from .results import held_bytes, variant_bytes

    _require_xarray()
    definition = _definition(spec, model)
    if definition.seed is None:  # draw one, record it (results attrs, checkpoint) so the study can be redone
        seed = Checkpoint.saved_seed(checkpoint) if checkpoint is not None else None
        seed = int(np.random.SeedSequence().entropy % 2**31) if seed is None else seed
        definition = dataclasses.replace(definition, seed=seed)
    values = sample_variants(definition)
    variables, coords, layouts = describe(model, definition.analyses)
    shapes = _shapes(variables, coords)
    size = chunk_size or definition.chunk_size or _saved_chunk_size(checkpoint) \
        or default_chunk_size(len(values), executor)
    per_variant = variant_bytes(shapes, values.shape[1])
    spooled = out is None and len(values) * per_variant > SPOOL_BYTES
    streamed = (out is not None and not _device(out)) or spooled
    held = held_bytes(variables, shapes, values.shape[1]) if streamed else None     # None: all of it
    check_memory(len(values), per_variant, size, definition, _outputs_text(shapes), held=held)
    if checkpoint is not None:
        check_disk(checkpoint, len(values), per_variant, definition, _outputs_text(shapes))
    if spooled:
        check_spool(_spool_folder(), len(values), per_variant, definition, _outputs_text(shapes))
    check_analyses_fit(model, definition)        # what cannot fit is refused first: --allow-long runs nothing more
    check_cpu_time(model, definition, len(values), values[0] if len(values) else None)
    base = {"keys": tuple(p.keys for p in definition.parameters),
            "applies": tuple(p.apply for p in definition.parameters),
            "model_data": model.to_dict(), "model_source": model.source, "analyses": definition.analyses,
            "layouts": layouts, "shapes": shapes, "single_thread": executor is not None}
    tasks = make_tasks(values, size, base)
    store = None
    if checkpoint is not None:
        store = Checkpoint(checkpoint, fingerprint(model.to_dict(), definition.raw, size, values), definition.seed,
                           size)
    run = _Run(tasks, executor, store, progress, values, (definition, variables, coords, model, size))
    result = run.spooled(_spool_folder()) if spooled else run.to_file(out) if streamed else run.in_memory()
    if out is not None and not streamed:
        result.save(out, progress=progress)
    if run.tally.count:
        warnings.warn(run.tally.line(len(values)), ImplausibleVariants, stacklevel=2)
    return result


class _Run:
    """The chunks of a study run and handed to where its results are assembled."""

    def __init__(self, tasks, executor, store, progress, values, described):
        self.tasks, self.executor, self.store, self.progress = tasks, executor, store, progress
        self.values, self.described = values, described
        self.tally = _Implausible()

    def _execute(self, target) -> int:
        """Run the chunks into ``target`` (``add(chunk)``); the chunks resumed."""
        from .execution import execute

        def sink(chunk):
            self.tally.add(chunk)
            target.add(chunk)

        return execute(self.tasks, self.executor, self.store, self.progress, len(self.values), sink=sink)[1]

    def _dataset(self, chunks, values):
        from .results import build_dataset

        definition, variables, coords, model, size = self.described
        return build_dataset(chunks, values, definition, variables, coords, model, attrs={"chunk_size": size})

    def in_memory(self) -> StudyResult:
        """The results assembled in memory (:class:`~.results.Assembly`)."""
        from .results import Assembly

        _, variables, coords, _, _ = self.described
        assembly = Assembly(len(self.values), _shapes(variables, coords))
        resumed = self._execute(assembly)
        return StudyResult(self._dataset(assembly, self.values), resumed_chunks=resumed)

    def to_file(self, out) -> StudyResult:
        """The results written to ``out`` chunk by chunk (:class:`~.results.ResultsWriter`), whole
        or not at all. The result holds the per-variant numbers in memory (assembled as the chunks
        come) and reads the variables over speeds from the file as they are used
        (:class:`~.results.FileRecords`)."""
        from ..io import atomic_write
        from ..io.atomic import real_target
        from .results import NewEncoding

        with atomic_write(out, None) as temporary:
            try:
                return self._written(temporary, lambda: {"path": temporary, "reopen": real_target(out)})
            except NewEncoding:  # pragma: no cover - an xarray that lays records out otherwise
                result = self.in_memory()
                result.save(temporary, progress=self.progress)
                return result

    def spooled(self, folder) -> StudyResult:
        """The results written chunk by chunk to a temporary file in ``folder`` (:data:`SPOOL_BYTES`),
        which is unlinked as soon as it is opened: its space is the system's to free once the last
        descriptor closes (:meth:`StudyResult.close`, the result garbage-collected, the process
        ending in any way, ``kill -9`` included), and nothing is left in ``folder``. As
        :meth:`to_file`, the result reads the variables over speeds from it as they are used."""
        import contextlib
        import tempfile

        from .results import NewEncoding

        descriptor, path = tempfile.mkstemp(prefix="rotordyn_modal-study-", suffix=".nc", dir=folder)
        try:
            try:
                return self._written(path, lambda: {"fd": descriptor}, unlink=path)
            except NewEncoding:  # pragma: no cover - an xarray that lays records out otherwise
                return self.in_memory()
        finally:
            os.close(descriptor)
            with contextlib.suppress(OSError):
                os.unlink(path)

    def _written(self, path, reader, unlink=None) -> StudyResult:
        """The chunks written into ``path`` (:class:`~.results.ResultsWriter`), the per-variant
        numbers assembled in memory, the variables over speeds read from the file as they are used
        (:class:`~.results.FileRecords` opened with ``reader()``'s arguments: ``path`` and
        ``reopen``, or ``fd``); ``unlink``: the path removed once the writer has it open."""
        import contextlib

        from xarray.core.indexing import LazilyIndexedArray

        from .results import Assembly, ResultsWriter, file_records, sweep_variables

        _, variables, coords, _, _ = self.described
        sweeps = sweep_variables(variables)
        template = self._dataset([_empty_chunk(variables, coords)], self.values[:1])
        writer = ResultsWriter(path, template, self.values, self.progress)
        if unlink is not None:
            with contextlib.suppress(OSError):
                os.unlink(unlink)
        small = Assembly(len(self.values), _shapes({name: dims for name, dims in variables.items()
                                                    if name not in sweeps}, coords))
        try:
            resumed = self._execute(_Both(writer, small))
            writer.finish()
        finally:
            writer.close()
        small.arrays = small.arrays or {}
        records = [file_records(begin=len(writer.prefix), layout=writer.layout, name=name, n=len(self.values),
                                **reader()) for name in sweeps]
        for name, array in zip(sweeps, records):  # opened before a rename: the descriptor follows the file
            small.arrays[name] = LazilyIndexedArray(array)
        dataset = self._dataset(small, self.values)
        dataset.set_close(_Closer(records))
        return StudyResult(dataset, resumed_chunks=resumed)


class _Closer:
    """Closes the results file's descriptors of a data set (``Dataset.close``, :meth:`StudyResult.close`)."""

    def __init__(self, records):
        self.records = records

    def __call__(self):
        for array in self.records:
            array.close()


class _Both:
    """Hands each chunk to the results file and to the numbers kept in memory."""

    def __init__(self, *targets):
        self.targets = targets

    def add(self, chunk: dict) -> None:
        for target in self.targets:
            target.add(chunk)


def _empty_chunk(variables, coords) -> dict:
    """A chunk of one variant that did not fail, every output NaN (the results file's header)."""
    shapes = _shapes(variables, coords)
    return {"start": 0, "error": np.array([""], dtype=str),
            **{name: np.full((1,) + shape, np.nan) for name, shape in shapes.items()}}


#: results larger than this [bytes] of ``rdm.study`` without ``out=`` go to a temporary file (in
#: :func:`tempfile.gettempdir`: ``TMPDIR``), not memory: :meth:`_Run.spooled`
SPOOL_BYTES = 256 * 2**20


def _spool_folder() -> str:
    """The folder of the temporary results file of a study without ``out=`` (``TMPDIR``, ...)."""
    import tempfile

    return tempfile.gettempdir()


def _saved_chunk_size(checkpoint):
    """The chunk size a checkpoint folder records (None without one): chosen for the first run's
    executor, it holds for the run that resumes it on another (the command's fresh pool of fewer
    workers after one died; another ``--workers``), whose own choice would make other chunks and
    a fingerprint the folder refuses."""
    from .execution import Checkpoint

    return None if checkpoint is None else Checkpoint.saved_chunk_size(checkpoint)


def _shapes(variables, coords) -> dict:
    """Output variable -> its shape per variant (the lengths of its dims after ``variant``).

    Parameters
    ----------
    variables : dict
        Output variable -> dims after ``variant``.
    coords : dict
        Coordinate name -> (dim, values, attrs).
    """
    return {name: tuple(len(coords[d][1]) for d in dims) for name, dims in variables.items()}


def _device(out) -> bool:
    """Whether ``out`` names a device or a pipe (written in place, never replaced)."""
    from ..io.atomic import _is_special, real_target

    return _is_special(real_target(out))


class ImplausibleVariants(ModelWarning):
    """Some variants of a study are legal but probably not meant (one warning for them all)."""


class _Implausible:
    """The variants whose model draws a warning (chunk key ``warning``), counted as chunks come."""

    def __init__(self):
        self.count, self.first = 0, None

    def add(self, chunk: dict) -> None:
        """Count one chunk's warned variants; keep the lowest-numbered one's warning. A chunk
        resumed from a checkpoint written before chunks held warnings counts none."""
        texts = chunk.get("warning")
        rows = [] if texts is None else [i for i, text in enumerate(texts.tolist()) if text]
        self.count += len(rows)
        if rows and (self.first is None or int(chunk["start"]) + rows[0] < self.first[0]):
            self.first = (int(chunk["start"]) + rows[0], texts[rows[0]])

    def line(self, n_variants: int) -> str:
        """``K of N variants are legal but probably not meant (...); the first, variant I: TEXT``."""
        variant, text = self.first
        return (f"{self.count} of {n_variants} variant{'s' * (n_variants != 1)} "
                f"{'is' if self.count == 1 else 'are'} legal but probably not meant (a model warning, as "
                f"check gives); the first, variant {variant}: {text}")


def _outputs_text(shapes) -> str:
    """The study's largest outputs per variant, for the estimates' messages."""
    largest = sorted(shapes.items(), key=lambda item: -int(np.prod(item[1])))[:2]
    parts = ", ".join(f"{name} {' x '.join(map(str, shape)) or '1'}" for name, shape in largest)
    return f"{parts} per variant"


class _MissingExtra(InputError, ImportError):
    """An optional dependency not installed: an ImportError in Python; on the command line one
    line and exit code 2, as for the other extras (tdms, ema, interactive, fast)."""


def _require_xarray():
    """Fail before any work when the results' data set cannot be built."""
    try:
        import xarray  # noqa: F401
    except ImportError:
        raise _MissingExtra("parameter studies store their results as an xarray.Dataset: "
                            "pip install 'rotordyn_modal[study]' (or xarray)") from None


def _definition(spec, model) -> StudyDefinition:
    if isinstance(spec, StudyDefinition):
        return spec
    if isinstance(spec, dict):
        return parse_study(spec, "<study>", model)
    return read_study(spec, model)


class _CallableModule(types.ModuleType):
    """``rdm.study(...)`` calls :func:`study`; submodules import as usual."""

    def __call__(self, model, spec, executor=None, checkpoint=None, chunk_size=None, progress=False, out=None):
        return study(model, spec, executor=executor, checkpoint=checkpoint, chunk_size=chunk_size,
                     progress=progress, out=out)


sys.modules[__name__].__class__ = _CallableModule
