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


DOC_MUTATIONS = (delete_key, rename_key, retype_value, special_number, special_number, wrong_shape,
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
class Timeout(Exception):
    pass


@contextlib.contextmanager
def time_limit(seconds: float):
    """Raise :class:`Timeout` after ``seconds`` (SIGALRM, main thread; no limit elsewhere)."""
    if not hasattr(signal, "setitimer") or seconds <= 0:
        yield
        return

    def fire(signum, frame):
        raise Timeout(f"no answer within {seconds:g} s")

    try:
        previous = signal.signal(signal.SIGALRM, fire)
    except ValueError:  # not the main thread
        yield
        return
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


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


def run_cli(argv, seconds: float = 60.0):
    """Run the command line in this process; returns (exit code, stdout, stderr, error or None)."""
    from rotordyn_modal.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    code, problem = None, None
    env = os.environ.pop("ROTORDYN_MODAL_DEBUG", None)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), time_limit(seconds):
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


def judge(argv, named: str, outputs=(), folder=None, seconds: float = 60.0, usage_ok=False) -> Outcome:
    """Run ``argv`` and sort the outcome (see the module docstring).

    Parameters
    ----------
    argv : list
    named : str
        Text the one-line message of a refusal must contain (the file name, or the option).
    outputs : sequence of path-like
        Files that a refused run must not leave behind.
    folder : path-like, optional
        Folder whose new files after a refusal are leftovers (temporary files of atomic writes).
    usage_ok : bool
        Accept argparse's refusal (usage lines, then one 'error:' line) as well.
    """
    before = set(os.listdir(folder)) if folder is not None else set()
    code, stdout, stderr, problem = run_cli(argv, seconds)
    outcome = Outcome(list(map(str, argv)), code, stdout, stderr)
    lines = [line for line in stderr.splitlines() if line.strip()]
    left = [str(p) for p in outputs if Path(p).exists()]
    if folder is not None:
        left += sorted(set(os.listdir(folder)) - before - {Path(p).name for p in outputs})
    if problem is not None:
        outcome.verdict, outcome.reason = "crash", problem.splitlines()[0] if problem.startswith("hang") else problem
    elif code == 0:
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
    elif named not in lines[0]:
        outcome.verdict, outcome.reason = "crash", f"the message does not name {named!r}"
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
