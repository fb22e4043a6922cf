"""``study MODEL --spec STUDY.toml [--workers N | --scheduler ADDRESS] --out RESULTS.nc``."""

from __future__ import annotations

import dataclasses
import os
import re
import sys
from pathlib import Path

import numpy as np

from ..errors import InputError, OutputError, OutputWriteError
from ._common import (add_alias, add_allow_long, as_typed, add_input_file, add_model_argument, add_output_file, check_outputs, open_model, parse_band, print_table,
                      show_progress, shown_as_typed, use_agg, whole_number, write_csv)
from ._resources import add_verbose
from ._units import ENVIRONMENT, key_kind
from ..units import to_system, unit_label

NAME = "study"
HELP = "parameter study (tolerance Monte Carlo, designs of experiments, grids) over model variants"
UNITS_HELP = ("unit system of what is printed, tabled and drawn: si (default) or us (parameters that set a key "
              "in its US unit: lbf/in, lb, in ...; unbalance peak amplitudes in mil, in/s or g; the --table columns "
              f"named with their unit); also set once by {ENVIRONMENT}. Speeds stay rpm (rad/s in --table and "
              "RESULTS.nc), frequencies Hz; the model and study files and RESULTS.nc stay SI (docs/units.md)")
DESCRIPTION = """Runs the analyses of a study file (docs/study-file.md) on every variant of the
model: parameters addressed by dotted keys, as grids or distributions (normal, lognormal,
uniform; truncation, correlation) sampled by Monte Carlo, Latin hypercube, Sobol or a
Saltelli design. Serial by default; --workers N uses a local process pool, --scheduler
ADDRESS a dask.distributed cluster. Results go to one netCDF file over (variant, speed,
mode, ...) that xarray, netCDF4 or ncdump open without this package.

Finished chunks are saved in RESULTS.nc.partial/ as they complete (each with a manifest
of its size and checksum): after Ctrl-C, a crash or kill -9, run the same command again
and only the missing chunks are computed; a damaged chunk file is computed again. A
second study writing the same RESULTS.nc while the first runs is refused (exit 2).
Failed variants (a model that validation refuses, a solver error) are recorded with
their reason and do not stop the study. A worker process the system kills (out of
memory) is replaced once by a fresh pool of half the workers; on dask the scheduler
computes a lost worker's chunk again elsewhere, and a chunk whose workers all died stops
the study with one line (its finished chunks kept: run again). Each chunk goes into
RESULTS.nc as it comes (a temporary file renamed at the end): memory holds a chunk and a few
numbers per variant, not the results. A study that cannot fit in memory or on the disk (or whose
base model's Campbell or stability sweep cannot fit) is refused before any work, in one line with
the estimate (docs/study-file.md); so is one estimated to take more CPU time than the limit (30
min; ROTORDYN_MODAL_MAX_CPU_MINUTES), every analysis counted (the unbalance responses timed on the
base model), unless --allow-long is given.

With --units us the --table CSV and the --plot-map axes give a parameter that sets a key (apply
= "value", a values grid) in the US unit of the key's quantity (lbf/in, lbf s/in, lb, lb in², in,
...; a factor, apply = "scale", has none), and the summary and the --table the unbalance peak
amplitudes in mil, in/s or g; the converted --table columns end in their unit (_lbf_per_in, _lb,
_in, _mil ...). The study
file's numbers, the model file and RESULTS.nc stay SI; speeds stay rpm (rad/s in the files).

--table columns without a unit in their name (docs/units.md), in SI: every speed
(critical_speed[SOURCE,ORDER,MODE], threshold_speed, instability_speed, unbalance_peak_speed[...],
force_peak_speed[...]) is in rad/s, not rpm as in every other CSV (as RESULTS.nc, whose variables
carry a units attribute), with --units us too; unbalance_peak_amplitude[...] is in the sensor's
quantity, m, m/s or m/s^2 (0-peak); force_peak_amplitude[...] in N, a moment's (NAME:Mx) in N m;
a parameter's column (its key or name) in the key's SI unit, or none for a factor (apply =
"scale"). With --units us the amplitudes and a key's values are converted and named with their
unit (..._mil, ..._lbf, stator.mass_lb).

examples:
  rotordyn-modal study examples/gear_machine.toml --spec examples/mount_tolerance.study.toml \\
      --out tolerance.nc --workers 2 --operating-range 3400:3700 --plot campbell.png
  rotordyn-modal study examples/unstable_cross_coupled.toml \\
      --spec examples/stability_map.study.toml --out map.nc --plot-map map.png"""


def add_arguments(parser):
    add_model_argument(parser)
    add_input_file(parser, "--spec", required=True, metavar="STUDY.toml", help="study file (docs/study-file.md)")
    add_output_file(parser, "--out", required=True, metavar="RESULTS.nc", help="netCDF file of the results")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=whole_number, metavar="N", help="run on a local pool of N processes")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a dask.distributed cluster (e.g. tcp://10.0.0.5:8786)")
    parser.add_argument("--chunk-size", type=whole_number, metavar="N", help="variants per chunk (default: chosen)")
    parser.add_argument("--restart", action="store_true",
                        help="discard the finished chunks of an earlier run instead of resuming")
    parser.add_argument("--operating-range", dest="band", metavar="LO:HI",
                        help="operating speed range [rpm]: report P(critical speed inside) (default: the study "
                             "file's operating_band_rpm)")
    add_alias(parser, "--operating-range", "--speed-band", "--band")
    add_output_file(parser, "--table", metavar="FILE.csv", help="write the per-variant table as CSV")
    add_output_file(parser, "--plot", metavar="FILE.png", help="Campbell diagram with tolerance bands (needs [analyses.campbell])")
    add_output_file(parser, "--plot-histogram", metavar="FILE.png", help="histograms of the critical speeds (needs [analyses.critical_speeds])")
    add_output_file(parser, "--plot-map", metavar="FILE.png", help="stability map over a two-parameter grid (needs [analyses.stability])")
    add_output_file(parser, "--plot-sensitivity", metavar="FILE.png", help="sensitivity bar chart")
    add_allow_long(parser)
    parser.add_argument("--quiet", action="store_true", help="no progress (bars, or lines where stderr is a log), no summary on the terminal")
    add_verbose(parser, "also: each chunk as it is computed or resumed, checkpoint files discarded, peak memory")


#: most local worker processes per core (each is a full Python process)
_WORKERS_PER_CORE = 8
#: seconds to wait for a --scheduler to answer
SCHEDULER_TIMEOUT = 10

_PLOTS = (("plot", "plot_campbell"), ("plot_histogram", "plot_critical_histograms"),
          ("plot_map", "plot_stability_map"), ("plot_sensitivity", "plot_sensitivity"))


def run(args) -> int:
    from ..io.atomic import outputs_together
    from ..study import checkpoint_folder, read_study
    from ..study.execution import ResultsLock, remove_checkpoint

    _check_options(args)
    model = open_model(args)   # its warnings held when every analysis refuses it: one line
    definition = read_study(args.spec, model)
    definition = dataclasses.replace(definition, source=shown_as_typed(definition.source, args))   # '-': standard input
    _check_figures(args, definition)
    band = definition.operating_band_rpm if args.band is None else \
        parse_band(args.band, as_typed(args, "--operating-range"), "rpm", low=None, example="2700:3300")
    folder = checkpoint_folder(args.out)  # both follow links: one lock and checkpoint however
    with ResultsLock(args.out):  # the file is named
        if args.restart and folder.exists():
            remove_checkpoint(folder)
        try:
            with outputs_together():  # the results, the table and the figures appear together
                result = _compute(model, definition, args, folder)
                kinds = _column_kinds(result, definition, model, args.units)
                _write(result, args, folder, kinds)
                # the map's axes name a set value's unit in SI too
                _plots(result, args, band, _Kinds(_column_kinds(result, definition, model, "us"), args.units))
        except (OutputError, OutputWriteError) as error:
            raise _kept_chunks(error, folder) from None
    if not args.quiet:            # once the outputs are in place: a reader that closes the pipe
        _report(result, band, kinds)          # early (`| head`) no longer loses the results
    return 0


#: the analysis each figure draws
_FIGURE_ANALYSES = {"plot": "campbell", "plot_histogram": "critical_speeds", "plot_map": "stability"}


def _check_figures(args, definition):
    """Refuse, before the work, a figure of an analysis the study file does not run (it failed
    once the study was computed, with an internal error)."""
    for option, analysis in _FIGURE_ANALYSES.items():
        if getattr(args, option) and analysis not in definition.analyses:
            raise InputError(f"--{option.replace('_', '-')} draws the '{analysis}' analysis, which {args.spec} "
                             f"does not run (add [analyses.{analysis}], docs/study-file.md)")


def _compute(model, definition, args, folder):
    """The study's results; a worker process that dies (the out-of-memory killer) is
    replaced once by a fresh pool that computes the chunks still missing. On dask, the
    scheduler itself computes a lost worker's chunk again elsewhere; a chunk whose workers
    all died (``KilledWorker``) stops the study with one line, its finished chunks kept."""
    from concurrent.futures.process import BrokenProcessPool

    from ..study import study
    from ..study.execution import finished_chunks

    for attempt in (1, 2):
        try:
            with _executor(args, attempt) as executor:
                return study(model, definition, executor=executor, checkpoint=folder,
                             chunk_size=args.chunk_size, progress=show_progress(args), out=args.out)
        except _killed_worker(args) as error:
            died = error.allowed_failures + 1
            raise OutputWriteError(f"every dask worker that ran one chunk died ({died} worker{'s' * (died > 1)}: "
                                   "killed by the system, out of memory? give the workers more memory or a "
                                   "smaller --chunk-size)") from None
        except BrokenProcessPool:
            if attempt == 2:
                raise OutputWriteError("a worker process died twice (killed by the system: out of memory? "
                                       "try fewer --workers)") from None
            print(f"rotordyn-modal {NAME}: warning: a worker process died (killed by the system: out of "
                  f"memory?); {finished_chunks(folder)} finished chunks are saved; computing the others in a "
                  f"fresh pool of {_workers(args, 2)} worker(s)", file=sys.stderr)
        except KeyboardInterrupt:
            print(f"interrupted: {finished_chunks(folder)} finished chunks kept in {folder}; "
                  "run the same command again to resume", file=sys.stderr)
            raise
    raise AssertionError("unreachable")  # pragma: no cover


def _killed_worker(args):
    """dask's ``KilledWorker`` with --scheduler (a tuple that catches nothing without it)."""
    if not args.scheduler:
        return ()
    from distributed import KilledWorker

    return KilledWorker


def _kept_chunks(error, folder):
    """``error`` with the finished chunks kept for the next run named (or the empty
    checkpoint removed)."""
    from ..study.execution import finished_chunks, remove_checkpoint

    kept = finished_chunks(folder)
    if not kept:
        remove_checkpoint(folder)
        return error
    message = f"{error}; {kept} finished chunks kept in {folder} for the next run"
    return OutputError(message) if isinstance(error, OutputError) else OutputWriteError(message, error.errno)


def _check_options(args):
    most = _WORKERS_PER_CORE * (os.cpu_count() or 1)
    if args.workers is not None and not 1 <= args.workers <= most:
        raise InputError(f"--workers {args.workers}: expected a whole number from 1 to {most} "
                         f"({_WORKERS_PER_CORE} per core of this machine)")
    if args.chunk_size is not None and not 1 <= args.chunk_size < 2**31:
        raise InputError(f"--chunk-size {args.chunk_size}: expected a whole number from 1 to {2**31 - 1}")
    for option in ("out", "table", "plot", "plot_histogram", "plot_map", "plot_sensitivity"):
        path = getattr(args, option, None)
        if not path:
            continue
        check_outputs(args, path)
        if not Path(path).parent.exists():
            raise InputError(f"--{option.replace('_', '-')} {path}: the folder {Path(path).parent} does not exist")
        if option.startswith("plot") and Path(path).suffix.lower() not in (".png", ".svg", ".pdf"):
            raise InputError(f"--{option.replace('_', '-')} {path}: expected a file ending in .png, .svg or .pdf")
    if args.table and Path(args.table).suffix.lower() != ".csv":
        raise InputError(f"--table {args.table}: expected a file ending in .csv (the format follows the ending)")
    if Path(args.out).suffix.lower() != ".nc":
        raise InputError(f"--out {args.out}: expected a netCDF file name ending in .nc")
    _check_derived(args)


def _check_derived(args):
    """The lock file and the checkpoint folder beside --out are written too: never an input."""
    from ..io.atomic import check_not_input
    from ..study import checkpoint_folder
    from ..study.execution import ResultsLock

    for derived in (ResultsLock(args.out).path, checkpoint_folder(args.out)):
        check_not_input(derived, [args.model, args.spec])


def _workers(args, attempt: int = 1) -> int:
    """Local worker processes: --workers, halved (at least 1) for a second attempt."""
    workers = args.workers or 1
    return workers if attempt == 1 else max(1, workers // 2)


def _broken_pool():
    from concurrent.futures.process import BrokenProcessPool

    return BrokenProcessPool


def _end_workers(pool):
    """Kill the workers a broken ``pool`` still has (SIGKILL). They ignore SIGTERM, left to the
    study's parent (``worker_initializer``), so the pool's own SIGTERM leaves them running: a
    worker busy when another died then waits forever to send a result (over a pipe's 64 kB)
    that no one reads, and the pool waits for it, so the study never ended once its results
    were written."""
    for worker in list((getattr(pool, "_processes", None) or {}).values()):
        worker.kill()


class _executor:
    """Context manager: None, a process pool, or a dask.distributed executor."""

    def __init__(self, args, attempt: int = 1):
        self.args = args
        self.attempt = attempt
        self.pool = self.client = None

    def __enter__(self):
        if self.args.workers and self.args.workers > 1 and _workers(self.args, self.attempt) > 1:
            from concurrent.futures import ProcessPoolExecutor

            from ..study.execution import worker_initializer

            self.pool = ProcessPoolExecutor(_workers(self.args, self.attempt), initializer=worker_initializer,
                                            initargs=(os.getpid(),))
            return self.pool
        if self.args.scheduler:
            try:
                from distributed import Client
            except ImportError:
                raise InputError("--scheduler needs dask.distributed: pip install 'dask[distributed]'") from None
            try:
                self.client = Client(self.args.scheduler, timeout=SCHEDULER_TIMEOUT)
            except OSError as error:
                raise InputError(f"--scheduler {self.args.scheduler}: cannot connect ({error})") from None
            return self.client.get_executor()
        return None

    def __exit__(self, kind, value, traceback):
        if self.pool is not None:
            if kind is not None and issubclass(kind, _broken_pool()):
                _end_workers(self.pool)
            self.pool.shutdown(wait=kind is None, cancel_futures=True)
        if self.client is not None:
            self.client.close()
        return False


def _write(result, args, folder, kinds=None):
    """The table (its columns in the unit system of ``kinds``, :func:`_column_kinds`); the
    results file is written by the study itself, chunk by chunk; the checkpoint goes once they
    are in place."""
    from ..io.atomic import after_commit
    from ..study.execution import remove_checkpoint

    after_commit(lambda: remove_checkpoint(folder))
    if args.table:
        write_csv(_in_units(result.to_dataframe(), kinds), args.table)


#: said once on the terminal where a study's ``unbalance`` analysis gives AF (docs/study-file.md)
SWEPT_AF = ("unbalance_peak_amplitude, unbalance_peak_speed, amplification_factor, separation_margin_pct, "
            "required_margin_pct (and force_peak_amplitude, force_peak_speed): read off the swept speeds (the "
            "largest swept peak, the AF's half-power points interpolated between them; netCDF attribute "
            "peak_search), not searched on the exact response as `unbalance` and `report` do; a sharp peak "
            "needs fine speeds")


def _report(result, band, kinds=None):
    failed = int(result.failed.sum())
    print(f"{result.n_variants} variants, {failed} failed"
          + (f", {result.resumed_chunks} chunks resumed from an earlier run" if result.resumed_chunks else ""),
          file=sys.stderr)
    if failed:
        first = int(np.flatnonzero(result.failed)[0])         # one text read, not every variant's
        print(f"first failure: {result.dataset['error'][first].values}", file=sys.stderr)
    if "amplification_factor" in result.dataset:
        print(SWEPT_AF, file=sys.stderr)
    table = result.summary()
    if len(table):
        table = _summary_in_units(_in_rpm(table), kinds)
        print_table(table[[c for c in table.columns if not c.endswith(("_low", "_high"))]])
    else:
        print("no scalar output to summarise: the curves (Campbell, responses) are in the results file")
    if band is not None and "critical_speed" in result.dataset:
        p = result.probability_in_band(band[0] * np.pi / 30, band[1] * np.pi / 30)
        print(f"P(critical speed in {band[0]:g}-{band[1]:g} rpm) = {p['probability']:.4g} "
              f"+/- {p['standard_error']:.2g} (95 % {p['low']:.3g}..{p['high']:.3g}, n = {p['n']})")


class _Kinds(dict):
    """Column -> quantity kind of the study's numbers shown in another unit system (its ``system``)."""

    def __init__(self, kinds, system):
        super().__init__(kinds)
        self.system = system


def _column_kinds(result, definition, model, system):
    """The columns of the per-variant table whose numbers ``system`` shows in another unit: each
    parameter that sets its keys (``apply = 'value'``) by their quantity (all alike, else none),
    and the unbalance peak amplitudes by the analysis's quantity; empty in SI."""
    if system == "si":
        return _Kinds({}, system)
    kinds = {}
    for parameter in definition.parameters:
        found = {key_kind(key, model) for key in parameter.keys}
        if parameter.apply == "value" and len(found) == 1 and None not in found:
            kinds[parameter.name] = found.pop()
    quantity = definition.analyses.get("unbalance", {}).get("quantity")
    if quantity:
        kinds |= {column: quantity for column in result.scalar_outputs() if column.startswith("unbalance_peak_amplitude")}
    # the force rows of [analyses.unbalance] forces: force_peak_amplitude[mount-FL:Fx,fan] (N), ...:Mx (N m)
    kinds |= {column: "moment" if re.search(r":M[xyz],", column) else "force"
              for column in result.scalar_outputs() if column.startswith("force_peak_amplitude[")}
    return _Kinds(kinds, system)


def _ending(kind, system) -> str:
    """``_lbf_per_in`` for lbf/in: the unit of ``kind`` as a column name's ending."""
    label = unit_label(kind, system)
    return "_" + label.replace(" s/", "_s_per_").replace("/", "_per_").replace(" ", "").replace("²", "2") \
        .replace("³", "3")


def _in_units(table, kinds):
    """The per-variant table with the columns of ``kinds`` in its system, named with their unit
    (``stator.mass_lb``, ``unbalance_peak_amplitude[probe,rotor]_mil``); SI unchanged."""
    if not kinds:
        return table
    table = table.copy()
    for column, kind in kinds.items():
        if column in table:
            table[column] = to_system(table[column].to_numpy(dtype=float), kind, kinds.system)
    return table.rename(columns={c: c + _ending(k, kinds.system) for c, k in kinds.items()})


def _summary_in_units(table, kinds):
    """The summary's rows of the outputs in ``kinds`` in its system, their names marked with the
    unit (``(mil)``), as the speeds' with ``(rpm)``."""
    if not kinds:
        return table
    numbers = [c for c in table.columns if c not in ("output", "n")]
    for column, kind in kinds.items():
        rows = table["output"] == column
        if rows.any():
            table.loc[rows, numbers] = to_system(table.loc[rows, numbers].to_numpy(dtype=float), kind, kinds.system)
            table.loc[rows, "output"] = f"{column} ({unit_label(kind, kinds.system)})"
    return table


_SPEEDS = ("critical_speed", "threshold_speed", "instability_speed", "unbalance_peak_speed", "force_peak_speed")


def _in_rpm(table):
    """Speeds of the summary [rad/s] -> rpm, their names marked ``(rpm)``."""
    speed = table["output"].str.startswith(_SPEEDS)
    numbers = [c for c in table.columns if c not in ("output", "n")]
    table.loc[speed, numbers] = table.loc[speed, numbers] * 30 / np.pi
    table.loc[speed, "output"] = table.loc[speed, "output"] + " (rpm)"
    return table


def _plots(result, args, band, kinds=None):
    wanted = [(option, method) for option, method in _PLOTS if getattr(args, option)]
    if not wanted:
        return
    use_agg()
    from ..io import atomic_write
    from ..io.atomic import after_commit

    for option, method in wanted:
        kwargs = {"band_rpm": band} if method in ("plot_campbell", "plot_critical_histograms") else {}
        if method == "plot_stability_map" and kinds:
            kwargs["scales"] = {name: (to_system(1.0, kind, kinds.system), unit_label(kind, kinds.system))
                                for name, kind in kinds.items() if name in result.parameters}
        fig = getattr(result, method)(**kwargs)
        path = Path(getattr(args, option))
        with atomic_write(path, None) as temporary:
            fig.savefig(temporary, format=path.suffix.lower()[1:], dpi=150)
        if not args.quiet:
            after_commit(lambda path=path: print(f"figure written to {path}", file=sys.stderr))
