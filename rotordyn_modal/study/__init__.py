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
          progress: bool = False) -> StudyResult:
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

    Returns
    -------
    StudyResult
        One data set over (variant, speed, mode, ...); failed variants are NaN
        with their reason in ``error``.

    Warns
    -----
    ImplausibleVariants
        Once, when some variants' models are legal but probably not meant (what ``check`` warns
        of, :func:`~rotordyn_modal.linear_system.implausible`: a 35 µm shaft, a sag of metres):
        how many, and the first one's warning. The results are the same either way.
    """
    from .analyses import describe
    from .execution import Checkpoint, check_disk, check_memory, default_chunk_size, execute, fingerprint, make_tasks
    from .results import Assembly, build_dataset, variant_bytes

    _require_xarray()
    definition = _definition(spec, model)
    if definition.seed is None:  # draw one, record it (results attrs, checkpoint) so the study can be redone
        seed = Checkpoint.saved_seed(checkpoint) if checkpoint is not None else None
        seed = int(np.random.SeedSequence().entropy % 2**31) if seed is None else seed
        definition = dataclasses.replace(definition, seed=seed)
    values = sample_variants(definition)
    variables, coords, layouts = describe(model, definition.analyses)
    shapes = {name: tuple(len(coords[d][1]) for d in dims) for name, dims in variables.items()}
    size = chunk_size or definition.chunk_size or default_chunk_size(len(values), executor)
    per_variant = variant_bytes(shapes, values.shape[1])
    check_memory(len(values), per_variant, size, _outputs_text(definition, shapes))
    if checkpoint is not None:
        check_disk(checkpoint, len(values), per_variant, _outputs_text(definition, shapes))
    base = {"keys": tuple(p.keys for p in definition.parameters),
            "applies": tuple(p.apply for p in definition.parameters),
            "model_data": model.to_dict(), "model_source": model.source, "analyses": definition.analyses,
            "layouts": layouts, "shapes": shapes, "single_thread": executor is not None}
    tasks = make_tasks(values, size, base)
    store = None
    if checkpoint is not None:
        store = Checkpoint(checkpoint, fingerprint(model.to_dict(), definition.raw, size, values), definition.seed)
    assembly, tally = Assembly(len(values), shapes), _Implausible()

    def sink(chunk):
        tally.add(chunk)
        assembly.add(chunk)

    _, resumed = execute(tasks, executor, store, progress, len(values), sink=sink)
    dataset = build_dataset(assembly, values, definition, variables, coords, model,
                            attrs={"chunk_size": size})
    if tally.count:
        warnings.warn(tally.line(len(values)), ImplausibleVariants, stacklevel=2)
    return StudyResult(dataset, resumed_chunks=resumed)


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


def _outputs_text(definition, shapes) -> str:
    """The study file and its largest outputs per variant, for the memory estimate's message."""
    largest = sorted(shapes.items(), key=lambda item: -int(np.prod(item[1])))[:2]
    parts = ", ".join(f"{name} {' x '.join(map(str, shape)) or '1'}" for name, shape in largest)
    return f"{definition.source} ({parts} per variant)"


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

    def __call__(self, model, spec, executor=None, checkpoint=None, chunk_size=None, progress=False):
        return study(model, spec, executor=executor, checkpoint=checkpoint, chunk_size=chunk_size,
                     progress=progress)


sys.modules[__name__].__class__ = _CallableModule
