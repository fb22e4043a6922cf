"""Mutation of valid input files and the judge of what the command line made of them.

Shared by the generating tests (``tests/test_fuzz_inputs.py``, driven by hypothesis through
``st.randoms()``, so that failures shrink) and by the stand-alone run of thousands of inputs
(``tests/fuzz_many.py``, driven by ``random.Random``). A mutator takes any object with the
``random.Random`` methods ``random``, ``randrange``, ``choice`` and ``sample``.

The judge runs ``rotordyn_modal.cli.main(argv)`` in this process and sorts the outcome:

- ``valid``: exit 0;
- ``refused``: exit 2 with one line on stderr naming the file (or option) that is wrong, and
  no output file left behind;
- anything else is a crash: exit 1 (the last line of defence caught an exception), a traceback,
  several lines, a refused run that left an output file, or a run longer than the time limit.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import signal
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import tomli_w

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: model files whose mutations are judged (every example model)
MODEL_FILES = sorted(p for p in EXAMPLES.glob("*.toml") if not p.name.endswith(".study.toml"))
#: study files, each with the example model it varies
STUDY_FILES = {
    "mount_tolerance.study.toml": "gear_machine.toml",
    "mount_sobol.study.toml": "gear_machine.toml",
    "stability_map.study.toml": "unstable_cross_coupled.toml",
}

#: numbers that break naive validation
SPECIAL_NUMBERS = (math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 1e308, -1e308, 1e-308, 5e-324,
                   1e-300, 1e300, 1e20, -1e-12, 2**63 - 1, -(2**63), 0, 1, -1, 3)
#: strings, many of them names
SPECIAL_TEXT = ("", " ", "x", "fan", "disk", "stator", "rotors", "ротор", "ロータ", "\u200b", "é",
                "a.b", "a[0]", "🙂", "mount-FL", "\t", "NaN", "1e3", "0:3000:5", "gear", "belt", "journal",
                "relative", "moment", "scale", "normal", "saltelli", "-1")
#: keys that a mutation may rename to (known keys of other tables, and junk)
KEY_NAMES = ("name", "mass", "stiffness", "damping", "position", "rotor", "speed_ratio", "inertia",
             "polar_inertia", "diametral_inertia", "center_of_mass", "axes", "ratio", "type", "driver",
             "driven", "spin_axis", "reference_rotor", "gravity", "loss_factor", "maxwell_stiffness",
             "maxwell_time", "speeds_rpm", "moment_stiffness", "direction", "measure", "kind", "amount",
             "key", "keys", "values", "scale", "distribution", "samples", "seed", "design", "analyses",
             "Mass", "ímass", "stiffness ", "名前", "")


# ----------------------------------------------------------------------------------------------
# mutations of a parsed TOML document (dicts, lists, scalars)
# ----------------------------------------------------------------------------------------------
def _places(doc, path=()):
    """Every (container, key) pair of the document, depth first."""
    items = doc.items() if isinstance(doc, dict) else enumerate(doc) if isinstance(doc, list) else ()
    for key, value in items:
        yield doc, key, path + (key,)
        yield from _places(value, path + (key,))


def _numbers(doc):
    return [(c, k) for c, k, _ in _places(doc) if isinstance(c[k], (int, float)) and not isinstance(c[k], bool)]


def _random_value(rng, depth=0):
    kind = rng.randrange(8 if depth < 2 else 5)
    if kind == 0:
        return rng.choice(SPECIAL_NUMBERS)
    if kind == 1:
        return rng.choice(SPECIAL_TEXT)
    if kind == 2:
        return rng.choice((True, False))
    if kind == 3:
        return rng.random() * 10 ** rng.randrange(-6, 7) * rng.choice((1, -1))
    if kind == 4:
        return []
    if kind == 5:
        return [_random_value(rng, depth + 1) for _ in range(rng.randrange(1, 7))]
    if kind == 6:
        return {rng.choice(KEY_NAMES) or "k": _random_value(rng, depth + 1)}
    return [[rng.choice(SPECIAL_NUMBERS) for _ in range(3)] for _ in range(rng.randrange(1, 4))]


def delete_key(doc, rng):
    places = list(_places(doc))
    if places:
        container, key, _ = rng.choice(places)
        del container[key]


def rename_key(doc, rng):
    places = [(c, k) for c, k, _ in _places(doc) if isinstance(c, dict)]
    if places:
        container, key = rng.choice(places)
        container[rng.choice(KEY_NAMES)] = container.pop(key)


def retype_value(doc, rng):
    places = list(_places(doc))
    if places:
        container, key, _ = rng.choice(places)
        container[key] = _random_value(rng)


def special_number(doc, rng):
    numbers = _numbers(doc)
    if numbers:
        container, key = rng.choice(numbers)
        value = rng.choice(SPECIAL_NUMBERS + ("negate", "tiny", "huge"))
        old = container[key]
        container[key] = {"negate": -old, "tiny": old * 1e-200, "huge": old * 1e200}.get(value, value) \
            if isinstance(value, str) else value


def wrong_shape(doc, rng):
    lists = [(c, k) for c, k, _ in _places(doc) if isinstance(c[k], list)]
    if not lists:
        return
    container, key = rng.choice(lists)
    value = container[key]
    choice = rng.randrange(6)
    if choice == 0 and value:
        value.pop(rng.randrange(len(value)))
    elif choice == 1 and value:
        value.append(value[rng.randrange(len(value))])
    elif choice == 2:
        container[key] = [value]
    elif choice == 3 and value:
        container[key] = value[0]
    elif choice == 4:
        container[key] = [v for row in value for v in (row if isinstance(row, list) else [row])]
    else:
        container[key] = value[: rng.randrange(len(value) + 1)] + [rng.choice(SPECIAL_NUMBERS)]


def duplicate_table(doc, rng):
    """Copy one table of an array of tables, or give it another table's name."""
    arrays = [(c, k) for c, k, _ in _places(doc)
              if isinstance(c[k], list) and c[k] and all(isinstance(t, dict) for t in c[k])]
    if not arrays:
        return
    container, key = rng.choice(arrays)
    tables = container[key]
    import copy

    source = rng.choice(tables)
    if rng.random() < 0.5 or len(tables) < 2:
        tables.insert(rng.randrange(len(tables) + 1), copy.deepcopy(source))
    elif "name" in source:
        rng.choice(tables)["name"] = source["name"]


def rename_name(doc, rng):
    """Give a named thing another name (unicode, empty, another thing's), breaking references."""
    named = [(c, k) for c, k, _ in _places(doc) if k in ("name", "rotor", "driver", "driven", "reference_rotor",
                                                         "key", "keys") and isinstance(c, dict)]
    if named:
        container, key = rng.choice(named)
        container[key] = rng.choice(SPECIAL_TEXT) + (rng.choice(SPECIAL_TEXT) if rng.random() < 0.3 else "")


def scale_number(doc, rng):
    """Multiply a number by a factor from 1e-3 to 1e3: mostly still a valid, if odd, machine."""
    numbers = _numbers(doc)
    if numbers:
        container, key = rng.choice(numbers)
        container[key] = container[key] * 10 ** (6 * rng.random() - 3)


DOC_MUTATIONS = (scale_number, scale_number, delete_key, rename_key, retype_value, special_number, special_number, wrong_shape,
                 duplicate_table, rename_name)


# ----------------------------------------------------------------------------------------------
# mutations of the bytes of a file
# ----------------------------------------------------------------------------------------------
def truncate(data: bytes, rng) -> bytes:
    return data[: rng.randrange(len(data) + 1)]


def flip_bytes(data: bytes, rng) -> bytes:
    out = bytearray(data)
    for _ in range(1 + rng.randrange(4)):
        if out:
            out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def insert_bytes(data: bytes, rng) -> bytes:
    at = rng.randrange(len(data) + 1)
    junk = rng.choice((b"\x00", b"\xff\xfe", b"\n", b"[", b"]]", b"=", b'"', b"nan", b"-1", "é".encode(),
                       b"\r\n", b"    -1\n", b"58\n", b",", b"inf"))
    return data[:at] + junk + data[at:]


BYTE_MUTATIONS = (truncate, flip_bytes, insert_bytes)


def mutate_toml(text: str, rng) -> bytes:
    """A mutated TOML file: 1-3 changes of its structure, sometimes followed by a byte-level change."""
    doc = tomllib.loads(text)
    for _ in range(1 + rng.randrange(3)):
        rng.choice(DOC_MUTATIONS)(doc, rng)
    try:
        data = tomli_w.dumps(doc).encode()
    except (TypeError, ValueError):  # an unwritable document (e.g. a list mixing tables and numbers)
        data = text.encode()
    if rng.random() < 0.25:
        data = rng.choice(BYTE_MUTATIONS)(data, rng)
    return data


# ----------------------------------------------------------------------------------------------
# the judge
# ----------------------------------------------------------------------------------------------
class Timeout(BaseException):
    """A run longer than the limit (not an Exception: the command line's last line of defence
    must not catch it)."""


#: the wall-clock backstop of :func:`time_limit`, in multiples of its CPU seconds (a run waiting
#: on something that takes no CPU, a lock or a pipe, is a hang too)
WALL_FACTOR = 10.0


@contextlib.contextmanager
def time_limit(seconds: float):
    """Raise :class:`Timeout` after ``seconds`` of this process's CPU time (all its threads;
    SIGPROF), or after ``WALL_FACTOR * seconds`` of wall-clock time (SIGALRM); main thread only,
    no limit elsewhere. CPU time, not wall-clock time: on a machine shared with other work (two
    cores, eight test runs) a 12 s run took over 60 s of wall-clock time and counted as a hang."""
    if not hasattr(signal, "setitimer") or seconds <= 0:
        yield
        return

    def fire(signum, frame):
        what = "CPU" if signum == signal.SIGPROF else "wall-clock"
        limit = seconds if signum == signal.SIGPROF else WALL_FACTOR * seconds
        raise Timeout(f"no answer within {limit:g} s of {what} time")

    try:
        previous = {number: signal.signal(number, fire) for number in (signal.SIGPROF, signal.SIGALRM)}
    except ValueError:  # not the main thread
        yield
        return
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, WALL_FACTOR * seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        for number, handler in previous.items():
            signal.signal(number, handler)


@dataclass
class Outcome:
    argv: list
    code: int | None
    stdout: str
    stderr: str
    verdict: str = ""          # 'valid', 'refused' or 'crash'
    reason: str = ""
    extras: list = field(default_factory=list)

    def describe(self) -> str:
        return (f"{self.verdict}: {self.reason}\n  argv: {self.argv}\n  exit: {self.code}\n"
                f"  stderr: {self.stderr[-2000:]!r}")


#: CPU seconds before a run counts as a hang (:func:`time_limit`)
TIME_LIMIT = 60.0
#: the memory the runs count on [GiB] (``ROTORDYN_MODAL_MEMORY_GB``), whatever the machine has free at
#: the moment: a mutated mesh of 6,805 coordinates was refused for 65 GiB against the memory at hand,
#: so that whether a run was refused (and by which message) depended on the other work running
MEMORY_GB = "4"


def run_cli(argv, seconds: float | None = None):
    """Run the command line in this process; returns (exit code, stdout, stderr, error or None)."""
    from rotordyn_modal.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    code, problem = None, None
    seconds = TIME_LIMIT if seconds is None else seconds
    env = os.environ.pop("ROTORDYN_MODAL_DEBUG", None)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), time_limit(seconds), \
                _environment("ROTORDYN_MODAL_MEMORY_GB", os.environ.get("ROTORDYN_MODAL_MEMORY_GB", MEMORY_GB)):
            code = main([str(a) for a in argv])
    except SystemExit as stop:  # argparse
        code = stop.code if isinstance(stop.code, int) else 2
    except Timeout as error:
        problem = f"hang: {error}"
    except BaseException as error:  # noqa: BLE001 - whatever escapes main is a crash
        import traceback

        problem = "".join(traceback.format_exception(error))
    finally:
        if env is not None:
            os.environ["ROTORDYN_MODAL_DEBUG"] = env
    return code, out.getvalue(), err.getvalue(), problem


#: a refusal of a model or study file: ``FILE: WHERE KEY = VALUE: expected ...``
HOUSE_STYLE = re.compile(r": \S.* = .*: expected \S")


def judge(argv, named: str, outputs=(), folder=None, seconds: float | None = None, usage_ok=False,
          failure_ok: str = "", style: re.Pattern | None = None) -> Outcome:
    """Run ``argv`` and sort the outcome (see the module docstring).

    Parameters
    ----------
    argv : list
    named : str or tuple of str
        Text the one-line message of a refusal must contain (the file name, or the option; one of
        several).
    outputs : sequence of path-like
        Files that a refused run must not leave behind.
    folder : path-like, optional
        Folder whose new files after a refusal are leftovers (temporary files of atomic writes).
    usage_ok : bool
        Accept argparse's refusal (usage lines, then one 'error:' line) as well.
    failure_ok : str
        Exit 1 with one line containing this text is a documented outcome ('valid'), e.g. the
        'not converged' of ``fit``.
    style : re.Pattern, optional
        The message of a refusal must match it (:data:`HOUSE_STYLE` for model and study files).
    """
    names = (named,) if isinstance(named, str) else tuple(named)
    before = set(os.listdir(folder)) if folder is not None else set()
    code, stdout, stderr, problem = run_cli(argv, seconds)
    outcome = Outcome(list(map(str, argv)), code, stdout, stderr)
    # a model that is legal but implausible draws warning lines before any refusal: not part of it
    lines = [line for line in stderr.splitlines() if line.strip() and ": warning: " not in line]
    left = [str(p) for p in outputs if Path(p).exists()]
    if folder is not None:
        left += sorted(set(os.listdir(folder)) - before - {Path(p).name for p in outputs})
    if problem is not None:
        outcome.verdict, outcome.reason = "crash", problem.splitlines()[0] if problem.startswith("hang") else problem
    elif code == 0 or (failure_ok and code == 1 and len(lines) == 1 and failure_ok in lines[0]):
        outcome.verdict, outcome.reason = "valid", ""
    elif code != 2:
        outcome.verdict, outcome.reason = "crash", f"exit code {code}"
    elif "Traceback" in stderr:
        outcome.verdict, outcome.reason = "crash", "traceback on stderr"
    elif not lines:
        outcome.verdict, outcome.reason = "crash", "exit 2 without a message"
    elif usage_ok and lines[-1].startswith("rotordyn-modal") and ": error: " in lines[-1] \
            and lines[0].startswith("usage:"):
        outcome.verdict, outcome.reason = "refused", "usage"
    elif len(lines) != 1:
        outcome.verdict, outcome.reason = "crash", f"{len(lines)} lines on stderr"
    elif not any(name in lines[0] for name in names):
        outcome.verdict, outcome.reason = "crash", f"the message does not name {' or '.join(names)!r}"
    elif style is not None and not style.search(lines[0].split(names[0], 1)[-1]):
        outcome.verdict, outcome.reason = "crash", "the message does not say where, the value and what was expected"
    elif left:
        outcome.verdict, outcome.reason = "crash", f"refused but left {left}"
    else:
        outcome.verdict, outcome.reason = "refused", lines[0]
    outcome.extras = left
    return outcome


def clean(folder):
    """Remove the files a run wrote into ``folder`` (outputs of valid runs)."""
    import shutil

    for entry in Path(folder).iterdir():
        if entry.is_dir():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink()


# ----------------------------------------------------------------------------------------------
# cases: one generated input and the commands run on it
# ----------------------------------------------------------------------------------------------
#: a small speed grid keeps every accepted model's run short
SPEEDS = "60:3000:5"  # from 60 rpm: a journal bearing has no oil film at standstill


def model_case(rng, folder) -> list:
    """Mutate one example model; run ``check`` and ``campbell`` on it."""
    folder = Path(folder)
    base = rng.choice(MODEL_FILES)
    model = folder / "model.toml"
    model.write_bytes(mutate_toml(base.read_text(encoding="utf-8"), rng))
    out = folder / "out"
    out.mkdir(exist_ok=True)
    outcomes = []
    for argv, outputs in ((["check", model], ()),
                          (["campbell", model, "--speeds", SPEEDS, "--out", out / "campbell.csv", "--quiet"],
                           (out / "campbell.csv",))):
        outcomes.append(judge(argv, str(model), outputs, out, style=HOUSE_STYLE if argv[0] == "check" else None))
        clean(out)
    return outcomes


def _tiny_study(doc):
    """The example study made small: few samples, short grids and sweeps."""
    if "samples" in doc:
        doc["samples"] = 4
    for p in doc.get("parameters", []):
        if isinstance(p.get("scale"), str):
            p["scale"] = ":".join(p["scale"].split(":")[:2] + ["2"])
    for options in doc.get("analyses", {}).values():
        if "speeds_rpm" in options:
            options["speeds_rpm"] = ":".join(options["speeds_rpm"].split(":")[:2] + ["5"])
    return doc


#: the largest count (speeds, variants) a fuzzed study may ask for before it is refused
STUDY_LIMIT = 48


def study_case(rng, folder) -> list:
    """Mutate one example study file (made tiny first); run ``study`` on it with a small count limit."""
    folder = Path(folder)
    name = rng.choice(sorted(STUDY_FILES))
    doc = _tiny_study(tomllib.loads((EXAMPLES / name).read_text(encoding="utf-8")))
    spec = folder / "study.toml"
    spec.write_bytes(mutate_toml(tomli_w.dumps(doc), rng))
    out = folder / "out"
    out.mkdir(exist_ok=True)
    argv = ["study", EXAMPLES / STUDY_FILES[name], "--spec", spec, "--out", out / "results.nc", "--quiet"]
    with _environment("ROTORDYN_MODAL_MAX_POINTS", str(STUDY_LIMIT)):
        outcome = judge(argv, str(spec), (out / "results.nc",), out, style=HOUSE_STYLE)
    clean(out)
    return [outcome]


@contextlib.contextmanager
def _environment(name, value):
    old = os.environ.get(name)
    os.environ[name] = value
    try:
        yield
    finally:
        if old is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = old


# ----------------------------------------------------------------------------------------------
# measured data: UFF 58/58b and CSV files of the gear machine's FRFs, mutated
# ----------------------------------------------------------------------------------------------
MEASURED_MODEL = EXAMPLES / "gear_machine.toml"
MEASURED_RPM = 3000.0
MEASURED_FREQS = "1:40:12"


def _measured_sets():
    """The gear machine's receptances at 3000 rpm, as the frf sub-command computes them."""
    import numpy as np

    import rotordyn_modal as rdm
    from rotordyn_modal.analysis.frf import FRFResult

    model = rdm.load_model(MEASURED_MODEL)
    res = rdm.frf(model, rdm.rpm(MEASURED_RPM), np.linspace(1.0, 40.0, 12))
    coherence = np.linspace(0.5, 1.0, res.H.size).reshape(res.H.shape)
    return model, FRFResult(**{**res.__dict__, "coherence": coherence})


def _uff_sets(binary: bool):
    """The FRF and coherence sets of ``_measured_sets`` as pyuff dictionaries (written by pyuff
    after mutation: ``write_uff58`` writes bytes, not dictionaries)."""
    import numpy as np
    import pyuff

    from rotordyn_modal.io.measured import default_mapping
    from rotordyn_modal.io.uff import _TYPE_OF, _label

    model, res = _measured_sets()
    mapping, rpm = default_mapping(model), res.speed * 30 / np.pi
    sets = []
    for a, out in enumerate(res.outputs):
        for b, inp in enumerate(res.inputs):
            (rsp_node, rsp_dir, rsp_sign), (ref_node, ref_dir, ref_sign) = mapping.node_of(out), mapping.node_of(inp)
            common = dict(binary=int(binary), rsp_node=rsp_node, rsp_dir=rsp_dir, ref_node=ref_node, ref_dir=ref_dir,
                          abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz",
                          x=np.asarray(res.frequencies_hz, float), z_axis_value=float(rpm), id1=f"{out} / {inp}")
            sets.append(pyuff.prepare_58(func_type=4, ordinate_spec_data_type=_TYPE_OF[res.quantity],
                                         ordinate_len_unit_exp=1, ordinate_axis_units_lab=_label(res.quantity),
                                         orddenom_spec_data_type=13, orddenom_force_unit_exp=1,
                                         orddenom_axis_units_lab="N",
                                         data=np.asarray(res.H[a, b] * rsp_sign * ref_sign, complex), **common))
            sets.append(pyuff.prepare_58(func_type=6, ordinate_spec_data_type=0, orddenom_spec_data_type=0,
                                         data=np.asarray(res.coherence[a, b], float), **common))
    return sets


_UFF_FIELDS = {
    "func_type": (1, 0, 6, 99, 4),
    "ordinate_spec_data_type": (0, 8, 12, 13, 99),
    "ordinate_axis_units_lab": ("g", "mm/s", "NONE", "", "m/s^2", "inch", "é"),
    "orddenom_spec_data_type": (0, 8, 99),
    "orddenom_axis_units_lab": ("lbf", "", "kN", "NONE"),
    "abscissa_spec_data_type": (17, 0, 99),
    "rsp_node": (0, 3, 99999, -1),
    "rsp_dir": (0, 4, -3, 7),
    "ref_node": (0, 1, 101, 99999),
    "ref_dir": (0, 3, -3, 9),
    "z_axis_value": (math.nan, math.inf, -3000.0, 0.0, 1e300),
}


def _mutate_uff_sets(sets, rng):
    import copy

    import numpy as np

    sets = copy.deepcopy(sets)
    for _ in range(1 + rng.randrange(3)):
        choice = rng.randrange(6)
        at = rng.randrange(len(sets))
        target = sets[at]
        if choice == 0:
            key = rng.choice(sorted(_UFF_FIELDS))
            target[key] = rng.choice(_UFF_FIELDS[key])
        elif choice == 1 and len(target["data"]):  # NaN, inf or huge data
            data = np.array(target["data"])
            data[rng.randrange(len(data))] = rng.choice((np.nan, np.inf, 1e300, -np.inf))
            target["data"] = data
        elif choice == 2 and len(sets) > 1:  # a missing channel
            del sets[at]
        elif choice == 3:  # a duplicated channel
            sets.insert(rng.randrange(len(sets) + 1), copy.deepcopy(target))
        elif choice == 4 and len(target["x"]):  # odd frequencies
            x = np.array(target["x"], dtype=float)
            which = rng.randrange(4)
            if which == 0:
                x[rng.randrange(len(x))] = rng.choice((np.nan, np.inf, -1.0, 0.0))
            elif which == 1:
                x = x[::-1].copy()
            elif which == 2:
                x[:] = x[0]
            else:
                x = x * rng.choice((-1.0, 1e300, 1e-300))
            target["x"] = x
        elif choice == 5 and len(target["data"]):  # fewer values than frequencies
            target["data"] = np.array(target["data"])[: rng.randrange(len(target["data"]))]
    return sets


def _write_uff(sets, path, fallback):
    import pyuff

    try:
        pyuff.UFF(str(path)).write_sets(sets, mode="add")
    except Exception:  # noqa: BLE001 - pyuff cannot write this mutation: keep the valid sets
        if Path(path).exists():
            Path(path).unlink()
        pyuff.UFF(str(path)).write_sets(fallback, mode="add")


def _mutate_csv(text: str, rng) -> bytes:
    import pandas as pd
    import numpy as np

    table = pd.read_csv(io.StringIO(text)).astype(object)
    for _ in range(1 + rng.randrange(3)):
        if not len(table.columns):
            break
        table = table.astype(object)  # any value in any cell
        choice = rng.randrange(7)
        column = rng.choice(list(table.columns))
        if choice == 0:
            table = table.drop(columns=[column])
        elif choice == 1:
            table = table.rename(columns={column: rng.choice(("real", "imag", "Output", "x", "", "speed_rpm"))})
        elif choice == 2 and len(table):
            table.loc[rng.randrange(len(table)), column] = rng.choice((np.nan, np.inf, "x", "", -1.0, 1e300))
        elif choice == 3 and len(table):
            rows = rng.sample(range(len(table)), max(1, len(table) // 4))
            table = table.drop(index=rows).reset_index(drop=True)
        elif choice == 4 and len(table):  # duplicated channel lines
            table = pd.concat([table, table.iloc[: rng.randrange(1, len(table) + 1)]], ignore_index=True)
        elif choice == 5 and len(table):
            table[column] = rng.choice(("nosuch", "acc-top-z", "hammer-z", "receptance", "ünïcode", 0, np.nan))
        else:
            table = table.iloc[:0]
    return table.to_csv(index=False).encode()


#: the default mapping of the gear machine, written out (sensor k is node k, excitation k node 100 + k)
_MAPPING = "name,node,direction,sign\nacc-top-z,1,3,1\nacc-side-y,2,2,1\nhammer-z,101,-3,1\nshaker-y,102,2,1\n"

_VALID_MEASURED = {}


def _valid_measured(folder) -> dict:
    """Valid files (ASCII UFF, binary UFF, CSV) written once per folder."""
    folder = Path(folder)
    if folder in _VALID_MEASURED:
        return _VALID_MEASURED[folder]
    from rotordyn_modal.io.measured import write_csv

    _, res = _measured_sets()
    files = {}
    for name, binary in (("ascii.uff", False), ("binary.uff", True)):
        files[name] = folder / f"valid-{name}"
        _write_uff(_uff_sets(binary), files[name], _uff_sets(binary))
    files["valid.csv"] = folder / "valid.csv"
    write_csv([res], files["valid.csv"])
    files["mapping.csv"] = folder / "valid-mapping.csv"
    files["mapping.csv"].write_text(_MAPPING)
    _VALID_MEASURED[folder] = files
    return files


def measured_case(rng, folder, fit: bool | None = None) -> list:
    """Mutate one measured-data file (bytes, UFF fields, CSV columns); run ``frf --measured``
    (and ``fit`` when asked; None: on one file in ten) on it."""
    folder = Path(folder)
    fit = rng.random() < 0.1 if fit is None else fit
    valid = _valid_measured(folder)
    kind = rng.choice(("ascii.uff", "binary.uff", "valid.csv"))
    path = folder / ("measured.csv" if kind.endswith(".csv") else "measured.uff")
    if rng.random() < 0.4:
        path.write_bytes(rng.choice(BYTE_MUTATIONS)(valid[kind].read_bytes(), rng))
    elif kind.endswith(".csv"):
        path.write_bytes(_mutate_csv(valid[kind].read_text(), rng))
    else:
        if path.exists():
            path.unlink()
        sets = _uff_sets(kind == "binary.uff")
        _write_uff(_mutate_uff_sets(sets, rng), path, sets)
    out = folder / "out"
    out.mkdir(exist_ok=True)
    mapping = []
    if not kind.endswith(".csv") and rng.random() < 0.3:  # a mapping table, mutated most of the time
        table = folder / "mapping.csv"
        text = valid["mapping.csv"].read_text()
        table.write_bytes(_mutate_csv(text, rng) if rng.random() < 0.8 else text.encode())
        mapping = ["--mapping", table]
    runs = [(["frf", MEASURED_MODEL, "--speed", MEASURED_RPM, "--freqs", MEASURED_FREQS, "--measured", path,
              *mapping, "--out", out / "frf.csv", "--quiet"], (out / "frf.csv",))]
    if fit:
        runs.append((["fit", MEASURED_MODEL, "--measured", path, "--params", "suspensions.mount-FL.stiffness",
                      "--starts", "1", "--out", out / "fitted.toml", "--quiet"], (out / "fitted.toml",)))
    outcomes = []
    for argv, outputs in runs:
        named = (str(path), str(mapping[1])) if mapping else str(path)
        outcomes.append(judge(argv, named, outputs, out, failure_ok="not converged"))
        clean(out)
    return outcomes


# ----------------------------------------------------------------------------------------------
# options of every sub-command
# ----------------------------------------------------------------------------------------------
def _number_text(rng) -> str:
    return rng.choice(("0", "-0", "1", "-1", "3000", "-3000", "1e300", "-1e300", "1e-300", "nan", "inf", "-inf",
                       "NaN", "x", "", " ", "1,2", "1:2", "0x10", "1_000", "٣", "1e", "+5", ".5", "5."))


def _count_text(rng) -> str:
    return rng.choice(("0", "1", "2", "5", "-1", "-5", "100000000", "1000000000000000000000", "1.5", "x", "", "nan",
                       "1e3", "3"))


def _range_text(rng) -> str:
    kind = rng.randrange(5)
    if kind == 0:
        return f"{_number_text(rng)}:{_number_text(rng)}:{_count_text(rng)}"
    if kind == 1:
        return rng.choice(("0:3000", "0:3000:5:1", ":", "::", "", "0:0:1", "3000:0:5", "0:3000:0",
                           "0:3000:100000000", "-3000:3000:5", "1e308:1.7e308:3", "0:1e-300:3"))
    if kind == 2:
        return f"0:3000:{_count_text(rng)}"
    return f"{rng.choice(('0', '-3000', '1', '1e-9'))}:{rng.choice(('3000', '1', '1e300', '2'))}:{rng.choice(('2', '5', '3'))}"


def _list_text(rng) -> str:
    return rng.choice(("", ",", "1,,2", "1,nan", "1,inf", "0", "-1", "1,2,3", "x", "1e300", "0.5,1e-300",
                       ",".join(["1"] * 50), "2", "1:3"))


def _name_text(rng, known=()) -> str:
    return rng.choice(tuple(known) + ("nosuch", "", ",", "ünï", "acc-top-z,acc-top-z", "a,b", " ", "-x"))


_UNITS = ("rpm", "RPM", "rad/s", "hz", "Hz", "nosuch", "")


def _plot_text(rng) -> str:
    """A figure file in the output folder ({out}), or a bad one."""
    return rng.choice(("{out}/figure.png", "{out}/figure.svg", "{out}/figure.txt", "{out}/no-folder/figure.png",
                       "{out}/table.csv", "", "{out}"))

#: sub-command -> (model, fixed arguments, option -> generator of a value)
OPTION_SPACE = {
    "check": ("gear_machine.toml", [], {}),
    "modes": ("gear_machine.toml", ["--quiet"],
              {"--speed": _number_text, "--speed-unit": lambda r: r.choice(_UNITS),
               "--shape": _count_text, "--frames": _count_text, "--plot": _plot_text}),
    "campbell": ("gear_machine.toml", ["--speeds", SPEEDS, "--quiet"],
                 {"--speeds": _range_text, "--orders": _list_text, "--speed-unit": lambda r: r.choice(_UNITS),
                  "--color-by": lambda r: r.choice(("log_decrement", "damping_ratio", "x", "")),
                  "--freq-range": lambda r: r.choice(("0:40", "5:2", "1:1", "-1:5", "x", "", "0:1e308", "1e-300:1e12",
                                                      "nan:3", "2:3:4", _range_text(r))),
                  "--freq-max": lambda r: r.choice(("40", "0", "-3", "inf", "x", "1e-300", _number_text(r))),
                  "--max-frequency": lambda r: r.choice(("40", "0", "-3", "nan", "x", "1e-300", "1e300",
                                                         _number_text(r))),
                  "--freq-scale": lambda r: r.choice(("auto", "linear", "log", "LOG", "x", "")),
                  "--plot": _plot_text}),
    "static": ("gear_machine.toml", ["--quiet"],
               {"--speed": _number_text, "--speed-unit": lambda r: r.choice(_UNITS),
                "--power": lambda r: r.choice(("1000", "-1000", "0", "motor->fan=10", "nosuch=1", "=", "1e300",
                                               _number_text(r))),
                "--force": lambda r: r.choice(("stator:0,0,0:0,0,-100", "fan:0.1,0,0:1,2,3", "nosuch:0,0,0:1,0,0",
                                               "stator:0,0:1,0,0", ":", "", "stator:nan,0,0:1,0,0",
                                               "motor:0,0,0:1e300,1e300,1e300", "stator::")),
                "--moment": lambda r: r.choice(("fan:0,0,5", "stator:1,2", "x", "", "motor:1e308,0,0")),
                "--plot": _plot_text}),
    "critical-speeds": ("gear_machine.toml", ["--speeds", SPEEDS, "--quiet"],
                        {"--speeds": _range_text, "--orders": _list_text,
                         "--max-frequency": lambda r: r.choice(("40", "0", "nan", "x", "1e300", _number_text(r)))}),
    "stability": ("unstable_cross_coupled.toml", ["--speeds", SPEEDS, "--quiet"],
                  {"--speeds": _range_text, "--vary": lambda r: r.choice(
                      ("suspensions.bearing-A.damping", "suspensions.bearing-A.stiffness[1][2]", "nosuch",
                       "suspensions.bearing-A.damping[9]", "", "rotors")),
                   "--scale": lambda r: r.choice((_list_text(r), _range_text(r))),
                   "--values": lambda r: r.choice((_list_text(r), _range_text(r)))}),
    "ucs-map": ("journal_rotor.toml", ["--stiffness", "1e5:1e8:5", "--modes", "2", "--quiet"],
                {"--stiffness": _range_text, "--modes": _count_text, "--speeds": _range_text,
                 "--bearings": lambda r: _name_text(r, ("DE", "NDE", "DE,NDE")),
                 "--operating": lambda r: r.choice(("1000:3000", "3000:1000", "x", "0:inf", "-1:5", "1:2:3", "")),
                 "--plot": _plot_text}),
    "level1": ("journal_rotor.toml", ["--speed", "3000", "--station", "rotor", "--qa", "1e4", "--quiet"],
               {"--speed": _number_text, "--qa": _list_text, "--factor": _number_text,
                "--station": lambda r: r.choice(("rotor", "rotor@0.1", "rotor@x", "@", "nosuch", "")),
                "--forward-mode": _count_text, "--plot": _plot_text}),
    "simulate": ("spring_block_rotor.toml", ["--duration", "0.05", "--quiet", "--backend", "numpy"],
                 {"--duration": lambda r: r.choice(("0", "-1", "nan", "inf", "x", "", "1e-300", "0.01", "1e-9")),
                  "--speed": _number_text, "--ramp": _number_text,
                  "--samples": lambda r: r.choice(("0", "1", "-5", "2", "100000000000", "x", "3")),
                  "--rtol": lambda r: r.choice(("0", "-1", "nan", "1", "1e-300", "x", "1e-6")),
                  "--atol": lambda r: r.choice(("0", "-1", "nan", "1e300", "x", "1e-9")),
                  "--impulse": lambda r: _name_text(r), "--impulse-size": _number_text,
                  "--sensor": lambda r: _name_text(r, ("disk-centre-z",))}),
    "frf": ("gear_machine.toml", ["--freqs", "1:40:5", "--quiet"],
            {"--speed": _number_text, "--freqs": _range_text,
             "--input": lambda r: _name_text(r, ("hammer-z",)),
             "--output": lambda r: _name_text(r, ("acc-top-z", "acc-side-y")),
             "--quantity": lambda r: r.choice(("receptance", "mobility", "x")),
             "--forces": lambda r: r.choice(("suspensions", "bearings", "rotors", "x"))}),
    "unbalance": ("fan_on_bearings.toml", ["--speeds", SPEEDS, "--quiet"],
                  {"--speeds": _range_text, "--operating-speed": _number_text,
                   "--output": lambda r: _name_text(r),
                   "--quantity": lambda r: r.choice(("displacement", "velocity", "x")),
                   "--orbits": lambda r: r.choice(("{out}/orbits.csv", "{out}/table.csv", "{out}/no-folder/o.csv", "")),
                   "--orbit-plot": _plot_text,
                   "--mcs": _number_text, "--min-speed": _number_text,
                   "--amplitude": lambda r: r.choice(("peak", "pk-pk", "rms", "x", "")),
                   "--iso-group": lambda r: r.choice(("1", "2", "3", "0", "x", "")),
                   "--iso-support": lambda r: r.choice(("rigid", "flexible", "x", "")),
                   "--checks": lambda r: r.choice(("{out}/checks.csv", "{out}/table.csv", "{out}/c.txt", ""))}),
    "study": ("gear_machine.toml", ["--spec", "{spec}", "--quiet"],
              {"--workers": lambda r: r.choice(("0", "-1", "1", "2", "1000000", "x", "")),
               "--chunk-size": _count_text,
               "--band": lambda r: r.choice(("3000:3500", "3500:3000", "x", ":", "nan:1", "0:inf", "1:2:3", "")),
               "--scheduler": lambda r: r.choice(("", "nosuch:1", "tcp://127.0.0.1:1"))}),
    "fit": ("gear_machine.toml", ["--measured", "{measured}", "--params", "suspensions.mount-FL.stiffness",
                                  "--starts", "1", "--band", "1:40", "--quiet"],
            {"--params": lambda r: r.choice(("gain", "", ",", "nosuch", "suspensions.mount-FL.stiffness[9]",
                                            "rotors.fan.mass,rotors.fan.mass", "name", "stator.mass")),
             "--band": lambda r: r.choice(("1:40", "40:1", "0:0", "x", "1:2:3", "-5:10", "nan:3", "")),
             "--bound-factor": lambda r: r.choice(("1", "0", "-2", "nan", "inf", "1e300", "x", "2")),
             "--starts": _count_text}),
}

#: a study file small enough for option runs: 4 variants of the mounts' stiffness at one speed
_TINY_STUDY = """seed = 1
samples = 4
[[parameters]]
key = "suspensions.mount-FL.stiffness"
apply = "scale"
distribution = "uniform"
low = 0.9
high = 1.1
[analyses.modes]
speed_rpm = 0.0
"""


def _placeholders(folder, fixed):
    spec = Path(folder) / "tiny.study.toml"
    if "{spec}" in fixed and not spec.exists():
        spec.write_text(_TINY_STUDY)
    measured = _valid_measured(folder)["valid.csv"] if "{measured}" in fixed else None
    return [{"{spec}": spec, "{measured}": measured}.get(a, a) for a in fixed]


def option_case(rng, folder) -> list:
    """One sub-command with 1-3 of its options given generated values."""
    folder = Path(folder)
    command = rng.choice(sorted(OPTION_SPACE))
    model, fixed, space = OPTION_SPACE[command]
    argv = [command, EXAMPLES / model, *_placeholders(folder, fixed)]
    for option in rng.sample(sorted(space), min(len(space), 1 + rng.randrange(3))) if space else ():
        if option in argv:
            at = argv.index(option)
            del argv[at:at + 2]
        argv += [option, space[option](rng)]
    out = folder / "out"
    out.mkdir(exist_ok=True)
    argv = [a.replace("{out}", str(out)) if isinstance(a, str) else a for a in argv]
    target = out / {"study": "results.nc", "fit": "fitted.toml"}.get(command, "table.csv")
    argv += ["--out", target] if command != "check" else []
    outcome = judge(argv, "", (target,), out, usage_ok=True, failure_ok="not converged")
    clean(out)
    return [outcome]


CASES = {"model": model_case, "study": study_case, "measured": measured_case, "option": option_case}
