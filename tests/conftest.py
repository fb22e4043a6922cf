"""Shared fixtures: reference models from examples/ and small factories; figures closed."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(autouse=True)
def _in_the_repository(monkeypatch):
    """Every test starts in the repository's root, whatever folder pytest was started from: many
    name bundled files relative to it (``"examples/gear_machine.toml"``, ``"tests/data/..."``). A
    test that needs another folder changes to it with its own ``monkeypatch.chdir``."""
    monkeypatch.chdir(ROOT)


@pytest.fixture(scope="session", autouse=True)
def _one_blas_thread():
    """OpenBLAS held to one thread in the test process (numpy's library and scipy's, both loaded
    first): pytest-xdist runs a worker per core, and a worker's BLAS threads took the other
    worker's core, mostly spinning while they waited for work (``tests/test_unbalance_markers36.py``
    at -n 1: 37.9 s of CPU against 49.5 s with OpenBLAS's own two threads). The package's results do
    not depend on BLAS's threads (``tests/test_deterministic_results.py``). The tests that check
    the package's own limit, or compare the CPU measured in the test process with the package's
    estimates (their modules marked ``blas_threads``), run with BLAS's own threads
    (:func:`_blas_threads_where_asked`); processes the tests start keep theirs. Yields a
    ``[controller, limiter]`` (None without threadpoolctl)."""
    import importlib

    try:
        for name in ("numpy", "scipy.linalg"):              # their libraries loaded before the limit
            importlib.import_module(name)
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover
        yield None
        return
    controller = ThreadpoolController()
    held = [controller, controller.limit(limits=1, user_api="blas")]
    yield held
    held[1].restore_original_limits()


@pytest.fixture(scope="module", autouse=True)
def _blas_threads_where_asked(request, _one_blas_thread):
    """BLAS's own threads for the tests of a module marked ``blas_threads`` (``pytestmark``), its
    module-scoped fixtures included: one that checks the package's own limit of them, or measures
    the CPU the package's work takes in the test process against its estimates and limits (made
    for the command's process, with OpenBLAS's own threads). The one-thread limit again after it."""
    if _one_blas_thread is None or request.node.get_closest_marker("blas_threads") is None:
        yield
        return
    controller, limiter = _one_blas_thread
    limiter.restore_original_limits()
    try:
        yield
    finally:
        _one_blas_thread[1] = controller.limit(limits=1, user_api="blas")


@pytest.fixture
def examples_dir() -> Path:
    return EXAMPLES


@pytest.fixture(scope="session")
def chain_campbell():
    """``chain_campbell(rotors, speeds_rpm)``: the Campbell sweep (critical speeds included) of
    ``rotors`` geared rotors on bearings (``test_large_machine_cli.chained_gear_toml(rotors,
    rotors)``) at ``speeds_rpm`` [rpm], swept once per worker and shared by the files that
    measure its figures (test_campbell_chain32, test_campbell_labels32): the sweeps are most of
    their time."""
    import tomllib

    import rotordyn_modal as rdm
    from test_large_machine_cli import chained_gear_toml

    cache = {}

    def get(rotors, speeds_rpm):
        key = (rotors, tuple(speeds_rpm))
        if key not in cache:
            model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(rotors, rotors)), source="chain.toml")
            cache[key] = rdm.campbell(model, rdm.rpm(speeds_rpm))
        return cache[key]
    return get


@pytest.fixture(scope="session")
def ucs_figure():
    """``ucs_figure(example, stiffness, units=None, **options)``: ``(result, figure)``, the
    undamped critical speed map of ``examples/EXAMPLE.toml`` over ``numpy.geomspace(*stiffness)``
    [N/m] with ``rdm.ucs_map``'s ``options``, and its ``plot()`` (``plot(units=units)`` where
    given), mapped and plotted once per worker. The plot (its labels' placement) is most of the
    time of the tests that measure one map's figure, and some measure the same figure
    (test_figures33 and test_figures35: the fan with every bearing; test_figure_audit27p and
    test_figure_audit27r: the fan's bearings by default; test_ucs32 and test_figure_audit30:
    flexible_pump_on_mounts over 1e5 .. 1e10 N/m in 41 values, whose map test_figures33 plots
    in both systems). The figure comes on a canvas of its
    own (a figure pyplot closed has none); the tests set its dpi, draw it and measure it, and
    change nothing else (drawn again, its texts' boxes are the same to the last bit)."""
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    import rotordyn_modal as rdm

    maps, figures = {}, {}

    def get(example, stiffness, units=None, **options):
        key = (example, tuple(stiffness), repr(sorted(options.items())))
        if key not in maps:
            maps[key] = rdm.ucs_map(rdm.load_model(EXAMPLES / f"{example}.toml"), np.geomspace(*stiffness), **options)
        if (key, units) not in figures:
            figures[key, units] = maps[key].plot() if units is None else maps[key].plot(units=units)
        fig = figures[key, units]
        if not hasattr(fig.canvas, "get_renderer"):
            FigureCanvasAgg(fig)
        return maps[key], fig
    return get


@pytest.fixture(scope="session")
def _first_results():
    """What :func:`shared_analyses` keeps in this worker: ``{call: (pickled result, warnings)}``."""
    return {}


@pytest.fixture
def shared_analyses(monkeypatch, _first_results):
    """``shared_analyses(module, "name", ...)``: for the rest of the test, each named function of
    ``module`` (a module or its name; an analysis the command line looks up there when it runs)
    computes a call once per worker: a later call with the same arguments (the same pickled bytes: the same model,
    read from the same file, the same doubles) and the same ``ROTORDYN_*`` and ``NUMBA_*``
    environment returns a copy of the first call's result (unpickled: no two callers share an
    object, none can change the kept one) and warns again the warnings the first call showed
    (through the filters and the printer in force, as ``cli._common.say_warnings`` does). Only
    for analyses that say everything they say by warnings: what one prints is not printed again.
    A call whose arguments or result cannot be pickled, or that raises, is computed every time.

    For the files that run one analysis twice, in SI and in US units (the command line
    converts at its edges: both runs compute in SI from the same doubles), and the same
    analysis in several files (test_unbalance_markers36, test_csv_round_trip29,
    test_units_examples32)."""
    import importlib
    import os
    import pickle
    import warnings

    from rotordyn_modal.cli._common import say_warnings

    def environment():
        return tuple(sorted((k, v) for k, v in os.environ.items() if k.startswith(("ROTORDYN", "NUMBA"))))

    def remembering(function):
        def call(*args, **kwargs):
            try:
                key = (function.__module__, function.__qualname__, pickle.dumps((args, kwargs)), environment())
            except Exception:                           # noqa: BLE001 - not picklable: not shared
                return function(*args, **kwargs)
            if key in _first_results:
                kept, caught = _first_results[key]
                say_warnings(caught)
                return pickle.loads(kept)
            caught, show = [], warnings.showwarning
            warnings.showwarning = shown_and_kept(show, caught)     # the filters untouched
            try:
                result = function(*args, **kwargs)
            finally:
                warnings.showwarning = show
            try:
                _first_results[key] = (pickle.dumps(result), caught)
            except Exception:                           # noqa: BLE001 - not picklable: not shared
                return result
            return pickle.loads(_first_results[key][0])
        return call

    def shown_and_kept(show, caught):
        """``warnings.showwarning`` that shows as ``show`` does (in their place among the call's
        other output) and keeps each warning shown in ``caught``."""
        def shown(message, category, filename, lineno, file=None, line=None):
            caught.append(warnings.WarningMessage(message, category, filename, lineno, file, line))
            show(message, category, filename, lineno, file, line)
        return shown

    def share(module, *names):
        module = importlib.import_module(module) if isinstance(module, str) else module
        for name in names:
            monkeypatch.setattr(module, name, remembering(getattr(module, name)))
    return share


@pytest.fixture
def no_solutions(monkeypatch):
    """Any eigen-solution of a sweep fails the test (a refusal must come before the work), with
    the CPU limit at its default (``ROTORDYN_MODAL_MAX_CPU_MINUTES`` unset)."""
    # unbalance_peaks binds eigenvalues_of when first imported: imported here first (a refusal's
    # estimate reads it), so that it never keeps the refusing one, and refused there too
    from rotordyn_modal.analysis import _eigensolve, _work, unbalance_peaks

    def refused(*args, **kwargs):
        raise AssertionError("an eigen-solution was started")

    monkeypatch.setattr(_eigensolve, "upper_shapes", refused)
    monkeypatch.setattr(_eigensolve, "eigenvalues_of", refused)
    monkeypatch.setattr(unbalance_peaks, "eigenvalues_of", refused)
    monkeypatch.delenv(_work.ENVIRONMENT, raising=False)


@pytest.fixture
def without_module(monkeypatch):
    """``without_module("plotly")``: importing that package (or its submodules) fails, as when
    an optional extra is not installed."""
    import builtins

    real_import = builtins.__import__

    def block(prefix):
        def guarded(name, *args, **kwargs):
            if name == prefix or name.startswith(prefix + "."):
                raise ImportError(name)
            return real_import(name, *args, **kwargs)

        monkeypatch.setattr(builtins, "__import__", guarded)

    return block


def pytest_terminal_summary(terminalreporter):
    """How many generated inputs the fuzz tests tried (tests/test_fuzz_inputs.py)."""
    import sys

    fuzz = sys.modules.get("test_fuzz_inputs")
    if fuzz is None or not fuzz.TRIED:
        return
    terminalreporter.section("generated inputs")
    for kind, counts in fuzz.TRIED.items():
        runs = counts["valid"] + counts["refused"] + counts["crash"]
        terminalreporter.write_line(f"fuzz: {counts['inputs']} {kind} tried ({runs} runs: {counts['valid']} valid, "
                                    f"{counts['refused']} refused, {counts['crash']} crashed)")
