"""Model files in TOML (``docs/model-file.md``): read, validate, write."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

from ..errors import ModelError, ModelWarning
from ..model._table import LARGEST
from ..model.machine import Model
from .atomic import atomic_write, check_not_input
from .limits import input_path, read_limited
from .text import decode_text

__all__ = ["load_model", "save_model", "read_toml", "MAX_NESTING"]

#: deepest nesting of arrays and tables in a model or study file: a model needs 5 (a table in
#: an array of tables, a list of 2x2 matrices); more is a mistake, and Python's parser would
#: exhaust its recursion limit on a few hundred
MAX_NESTING = 32
#: an integer beyond this cannot become a float (it is refused as any number beyond LARGEST)
_LARGEST_INTEGER = 10**308


def load_model(path, units: str = "si") -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or path-like
        A TOML file as ``docs/model-file.md`` describes.
    units : {'si', 'us'}
        Unit system of the values computed in the warnings (a sag in m or in; docs/units.md).
        The file itself is SI whatever this says.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        The file does not exist, is not TOML, or fails validation (the message
        names the file, table, key, value and what was expected), or a support so much
        stiffer than what it holds that the low modes keep no digit
        (:func:`rotordyn_modal.stiffness_spread.stiffness_spread_lines`).

    Warns
    -----
    ModelWarning
        One per thing that is legal but probably not meant
        (:func:`rotordyn_modal.plausibility.implausible`: a static sag of metres under
        gravity, a mount mode below 0.5 Hz, a long journal bearing, a support that costs the
        low modes more than six digits: docs/theory.md §8, "Stiffness spread").
    """
    from ..plausibility import implausible

    data = read_toml(path, "model file")
    _not_a_ross_file(data, path)
    model = Model.from_dict(data, source=str(path))
    for line in implausible(model, units):
        warnings.warn(line, ModelWarning, stacklevel=2)
    return model


def _not_a_ross_file(data: dict, path) -> None:
    """Refuse a rotor saved by ROSS given where a model file is expected, with the command that
    reads it (it was refused by its first key, 'ross_version = 3.1.0: unknown key')."""
    if "ross_version" in data or any(str(key).startswith("ShaftElement_") for key in data):
        raise ModelError(str(path), "<file>", "a rotor saved by ROSS (ross_version, ShaftElement_... tables)",
                         f"a model file: read it into one first, rotordyn-modal import-ross {path} --out "
                         "MODEL.toml (docs/ross.md)")
    if "parameters" in data and not {"rotors", "stator"} & set(data):   # a study file given as the model
        raise ModelError(str(path), "<file>", "a study file ([[parameters]], no [[rotors]] or [stator])",
                         f"a model file: a study runs as rotordyn-modal study MODEL --spec {path} --out "
                         "RESULTS.nc (docs/study-file.md)")


def read_toml(path, what: str, error=ModelError) -> dict:
    """The tables of a TOML file (a model or study file), or one line saying why not.

    A byte-order mark (UTF-8's, what some Windows editors write; UTF-16's or UTF-32's) is
    skipped, and UTF-16 without one is read as UTF-16 (:func:`.text.decode_text`).

    Parameters
    ----------
    path : str or path-like
    what : str
        Named in messages: ``'model file'``, ``'study file'``.
    error : type
        The exception raised, called as ``error(source, '<file>', value, expected)``
        (:class:`~rotordyn_modal.errors.ModelError` or the study's ``StudyError``).

    Raises
    ------
    error
        The file does not exist, is a folder, is not readable UTF-8 text, is not TOML,
        or nests arrays and tables more than :data:`MAX_NESTING` deep.
    """
    path = input_path(path, what)
    source = str(path)
    try:
        text = decode_text(read_limited(path, "model", what), fallback=None)
    except FileNotFoundError:
        raise error(source, "<file>", source, f"an existing {what} (no such file)") from None
    except IsADirectoryError:
        raise error(source, "<file>", source, f"a {what}, not a folder") from None
    except UnicodeDecodeError as problem:    # no UTF-8, or UTF-16 without a mark that is no UTF-16
        said = f": {problem.reason}" if problem.encoding.startswith("utf-16") else ""
        raise error(source, "<file>", f"byte {problem.start}", f"UTF-8 text (TOML){said}") from None
    except OSError as problem:
        raise error(source, "<file>", source, f"a readable file ({problem.strerror})") from None
    nested = f"TOML with arrays and tables nested at most {MAX_NESTING} deep"
    try:
        data = tomllib.loads(text, parse_float=_representable_float)
    except _Unrepresentable as literal:
        line, key = _literal_line(text, literal.text)
        raise error(source, f"line {line}: {key}" if key else f"line {line}", _Typed(literal.text),
                    f"a number of magnitude at most {LARGEST:g} (SI units)" if literal.overflow else
                    "a number a double can hold (magnitude at least 5e-324; write 0 for zero)") from None
    except tomllib.TOMLDecodeError as problem:
        if (twice := _given_twice(text, problem)) is not None:
            raise error(source, *twice) from None
        raise error(source, "<file>", str(problem), "valid TOML" + _unseen_character(text, problem)) from None
    except RecursionError:
        raise error(source, "<file>", "arrays or tables nested too deep to parse", nested) from None
    if not data:        # was refused for its first missing table ('rotors = []', 'no ShaftElement tables')
        raise error(source, "<file>", "an empty file" if not text.strip() else "no table or key (comments only)",
                    f"a {what} (TOML tables and keys)")
    if (deep := _too_deep(data)) is not None:
        where, value = deep
        where = where if len(where) <= 60 else where[:57] + "..."
        if isinstance(value, int):
            raise error(source, where or "<file>", f"<an integer of {len(str(abs(value)))} digits>",
                        f"a number of magnitude at most {LARGEST:g} (SI units)")
        raise error(source, where, f"<nested more than {MAX_NESTING} deep>", nested)
    return data


class _Unrepresentable(ValueError):
    """A float literal of a TOML file that a double does not hold: beyond 1.8e308 (read as inf)
    or a non-zero literal below 4.9e-324 (read as 0.0)."""

    def __init__(self, text: str, overflow: bool):
        super().__init__(text)
        self.text, self.overflow = text, overflow


class _Typed(str):
    """A literal shown in a message as typed (``1e400``, not ``'1e400'`` or ``inf``)."""

    def __repr__(self):
        return str(self)


def _representable_float(text: str) -> float:
    """``float(text)`` of a TOML float literal, refused where the double is not the number typed:
    ``1e400`` (was read as inf and refused as 'stiffness = inf') or ``1e-400`` (was read as 0.0
    silently, a zero stiffness or gravity the file does not say)."""
    value = float(text)
    digits = text.lower().split("e")[0]
    if value in (float("inf"), float("-inf")) and "inf" not in text:
        raise _Unrepresentable(text, overflow=True)
    if value == 0 and any(c in "123456789" for c in digits):
        raise _Unrepresentable(text, overflow=False)
    return value


def _literal_line(text: str, literal: str):
    """``(line number, key)`` of the first line of ``text`` holding the literal ``literal`` (the
    key: the text before its '=', or '' on a line of an array's continuation)."""
    import re

    pattern = re.compile(r"(?<![\w.])" + re.escape(literal) + r"(?![\w.])")
    key = ""
    for number, line in enumerate(text.splitlines(), start=1):
        code = line.split("#", 1)[0]
        name, equals, _ = code.partition("=")
        if equals and not name.strip().startswith("["):
            key = name.strip()          # an array over several lines: the key of its first
        elif code.strip().startswith("["):
            key = ""
        if pattern.search(code):
            return number, key
    return 0, ""


def _given_twice(text: str, problem):
    """``(where, value, expected)`` of a TOML error that is a key or table given twice, naming
    the key, its table and the second value (tomllib says only "Cannot overwrite a value (at
    line 8, column 12)" or "Cannot declare ('stator',) twice"); None for any other error."""
    import re

    said = str(problem)
    at = re.search(r"at line (\d+), column \d+\)", said)
    lines = text.split("\n")
    if at is None or not 0 < int(at.group(1)) <= len(lines):
        return None
    number = int(at.group(1))
    code = lines[number - 1].split("#", 1)[0].strip()
    if said.startswith("Cannot declare") or (said.startswith("Cannot overwrite") and code.startswith("[")):
        header = _Typed(code)
        return (f"line {number}: table header", header,
                f"each table once: {header} is declared a second time here, or names a key given a value before "
                "(TOML cannot reopen a table; one [[...]] per element of an array of tables)")
    if not said.startswith("Cannot overwrite"):
        return None
    key, equals, value = lines[number - 1].partition("=")
    if not equals:
        return None
    key, value = key.strip(), value.strip()
    if value[:1] in ("'", '"') and value.find(value[0], 1) > 0:      # a string: to its closing quote ('#' inside)
        value = value[:value.find(value[0], 1) + 1]
    else:
        value = value.split("#", 1)[0].strip()
    table = next((line.split("#", 1)[0].strip() for line in reversed(lines[:number - 1])
                  if line.lstrip().startswith("[")), "")
    where = f"line {number}: {table} {key}" if table else f"line {number}: {key}"
    return (where, _Typed(value.strip()),
            f"each key once in its table: {key} is given a second time here (TOML cannot overwrite a value)")


def _unseen_character(text: str, problem) -> str:
    """What a TOML error's position holds when it is a character no one sees (a second byte-order
    mark, a zero-width space, a no-break space): ``" (the character at line 1, column 1 is
    U+FEFF, zero width no-break space, invisible)"``; else ''."""
    import unicodedata

    import re

    at = re.search(r"at line (\d+), column (\d+)\)", str(problem))   # Python 3.14 has lineno, colno
    line, column = (int(at.group(1)), int(at.group(2))) if at else (0, 0)
    lines = text.split("\n")
    if not (0 < line <= len(lines) and 0 < column <= len(lines[line - 1])) or "Illegal character" in str(problem):
        return ""           # tomllib names an illegal character itself
    char = lines[line - 1][column - 1]
    if char.isprintable() and not char.isspace() or char in " \t\r":
        return ""
    name = unicodedata.name(char, "").lower() or "a control character"
    return f" (the character at line {line}, column {column} is U+{ord(char):04X}, {name}, invisible)"


def _too_deep(data):
    """``(dotted key, value)`` of the first value nested deeper than :data:`MAX_NESTING`, or
    of an integer beyond any float (TOML's integers have no limit; ``float()`` of one of 400
    digits raises OverflowError), or None (an iterative walk: the data may be as deep as the
    parser allowed)."""
    stack = [("", data, 0)]
    while stack:
        where, value, depth = stack.pop()
        if depth > MAX_NESTING:
            return where, None
        if isinstance(value, int) and not isinstance(value, bool) and abs(value) > _LARGEST_INTEGER:
            return where, value
        if isinstance(value, dict):
            stack.extend((f"{where}.{k}" if where else str(k), v, depth + 1) for k, v in value.items())
        elif isinstance(value, list):
            stack.extend((f"{where}[{i}]", v, depth + 1) for i, v in enumerate(value))
    return None


def save_model(model: Model, path, inputs=()) -> None:
    """Write a model file atomically (never over one of ``inputs`` or the model's source).

    Parameters
    ----------
    model : Model
    path : str or path-like
    inputs : iterable of path-like
        Files that must not be overwritten.
    """
    import tomli_w

    check_not_input(path, [*inputs, model.source if Path(model.source).exists() else None])
    data = {k: v for k, v in model.to_dict().items() if v not in ([], None, "")}
    with atomic_write(path, "wb") as handle:
        tomli_w.dump(data, handle)
