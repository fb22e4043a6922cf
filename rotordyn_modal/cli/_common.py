"""Options and helpers shared by the sub-commands."""

from __future__ import annotations

import argparse
import contextlib
import copy
import math
import os
import sys

import numpy as np

from .._limits import count_problem
from ..errors import InputError
from ..io import atomic_write, check_not_input, load_model
from ..io.atomic import after_commit, check_writable
from ..io.limits import shown_name, unreachable_name
from ..model._table import LARGEST, SMALLEST_POSITIVE
from ..units import SPEED_UNITS
from ..units import speed_to_rad_s as to_rad_s

#: options that take a value which may start with '-' (a negative speed or range)
VALUE_OPTIONS = ("--speed", "--speeds", "--values", "--scale", "--freqs", "--orders", "--impulse",
                 "--ramp", "--duration", "--power", "--freq-range", "--operating-range", "--operating",
                 "--speed-band", "--freq-band", "--band", "--transmitted-power", "--rated-power",
                 "--stiffness", "--qa", "--gas-density", "--impeller-diameter", "--restriction-height",
                 "--density-ratio")


def join_negative_values(argv, options):
    """Turn ``--speeds -6000:6000:13`` into ``--speeds=-6000:6000:13`` for argparse; and any
    ``--option -2e5`` (a negative number argparse does not take for one: an exponent, ``-inf``)
    into ``--option=-2e5``, so that the option's own check names it."""
    out, i = [], 0
    while i < len(argv):
        token = argv[i]
        value = argv[i + 1] if i + 1 < len(argv) else ""
        if (token in options and value.startswith("-") and len(value) > 1
                and (value[1].isdigit() or value[1] == ".")) \
                or (token.startswith("--") and token != "--" and "=" not in token and _negative_number(value)):
            out.append(f"{token}={argv[i + 1]}")
            i += 2
            continue
        out.append(token)
        i += 1
    return out


def _negative_number(text: str) -> bool:
    """True for a token such as ``-2e5``, ``-.5`` or ``-inf``: a number, never an option."""
    if not text.startswith("-") or text.startswith("--"):
        return False
    try:
        float(text)
    except ValueError:
        return False
    return True


def _plain_float(text: str) -> float:
    """``float(text)`` without Python's digit separators and other scripts' digits: ``1_0`` and
    ``５０`` (full-width) are no numbers on a command line (Python reads them as 10 and 50), so
    they raise ValueError as ``x`` does."""
    if "_" in str(text) or not str(text).isascii():
        raise ValueError(text)
    return float(text)


def whole_number(text) -> int:
    """``text`` as an int: digits only, an optional sign and white space around them; raises
    ValueError for anything else, ``5_0`` included (Python's ``int`` reads it as 50)."""
    stripped = str(text).strip()
    digits = stripped[1:] if stripped[:1] in "+-" else stripped
    if not (digits.isascii() and digits.isdigit()):
        raise ValueError(text)
    return int(stripped)


whole_number.__name__ = "whole number"     # argparse's 'argument --shape: invalid whole number value: '1_0''


def parse_number(text: str, option: str, largest: float | None = LARGEST) -> float:
    """A number given to ``option``: finite, of magnitude at most ``largest`` (None: any), as every
    number of a model (1e30: beyond it products with the model's numbers overflow). Python's
    digit separators (``1_0``) are refused, not read as 10."""
    try:
        value = _plain_float(text)
    except ValueError:
        raise InputError(f"{option} {text!r}: expected a number") from None
    if not math.isfinite(value):
        raise InputError(f"{option} {text!r}: expected a finite number")
    if largest is not None and abs(value) > largest:
        raise InputError(f"{option} {text!r}: expected a number of magnitude at most {largest:g}")
    return value


def speed_value(text, unit: str, option: str, largest: float = LARGEST) -> float:
    """A speed option given in ``unit`` (``--speed 3000``) in rad/s, of magnitude at most
    ``largest`` rad/s; refused as typed, with the limit in the unit typed (``--speed 1e308:
    expected a speed of magnitude at most 9.549e+30 rpm``, not the rad/s it converts to)."""
    value = parse_number(text, option, largest=None)
    return float(check_speeds(np.array([value]), text, unit, option, largest)[0])


def mcs_option(args, signed: bool = False) -> float:
    """``--mcs SPEED`` (in ``args.speed_unit``) in rad/s: the one check of the maximum continuous
    speed that ``level1`` and ``report`` share. Refused in one line when its magnitude is below
    ``SMALLEST_POSITIVE`` rad/s (1e-300 rpm: every speed derived from it is 0 to round-off) or,
    unless ``signed`` (``level1``: a machine may run either way), when it is negative."""
    option = as_typed(args, "--mcs")
    speed = speed_value(args.mcs, args.speed_unit, option)
    size = abs(speed) if signed else speed
    if not size >= SMALLEST_POSITIVE:
        rule = "other than 0 (of magnitude at" if signed else "> 0 (at"
        raise InputError(f"{option} {args.mcs}: expected a maximum continuous speed {rule} least "
                         f"{SMALLEST_POSITIVE:g} rad/s)")
    return speed


def check_speeds(values, text, unit: str, option: str, largest: float = LARGEST) -> np.ndarray:
    """``values`` (speeds in ``unit``, as ``option`` gave them in ``text``) in rad/s; refused in
    one line when one is beyond ``largest`` rad/s."""
    speeds = np.asarray(to_rad_s(np.asarray(values, dtype=float), unit), dtype=float)
    if speeds.size and not np.abs(speeds).max() <= largest:
        limit = largest / float(to_rad_s(1.0, unit))
        also = "" if unit == "rad/s" else f" (at most {largest:g} rad/s)"
        raise InputError(f"{option} {text}: expected {'a speed' if speeds.size == 1 else 'speeds'} of magnitude "
                         f"at most {limit:.4g} {unit}{also}")
    return speeds


def options_as_typed(message: str, args, names: dict) -> str:
    """``message`` of a Python entry point that names its argument (``duration = -1.0: expected
    ...``), as the command line's option typed (``--duration -1: expected ...``).

    Parameters
    ----------
    message : str
    args : argparse.Namespace
        The options as typed (strings; a list for an option given several times).
    names : dict
        Argument name -> option (``{"duration": "--duration"}``); an option not given is skipped.
    """
    for name, option in names.items():
        head = f"{name} = "
        if not message.startswith(head) or ": " not in message[len(head):]:
            continue
        typed = getattr(args, option.lstrip("-").replace("-", "_"), None)
        if typed is None:
            continue
        typed = " ".join(map(str, typed)) if isinstance(typed, (list, tuple)) else str(typed)
        value, rest = message[len(head):].split(": ", 1)
        context = value[value.find(" ("):] if " (" in value else ""     # "(excitation 'hammer-z')" stays
        return f"{as_typed(args, option)} {typed}{context}: {rest}"
    return message


def add_alias(parser, new: str, *old: str) -> None:
    """Keep ``old``, earlier spellings of the option ``new`` (declared before), working where
    scripts use them: the same destination, type, choices and value, hidden from ``--help``
    (which, as the docs, shows ``new`` alone). Two spellings together are refused in one line
    (one option given twice); a required ``new`` is satisfied by any. Messages name the
    spelling typed (:func:`as_typed`); each hidden action's ``alias_of`` is ``new``."""
    action = parser._option_string_actions[new]
    group = parser.add_mutually_exclusive_group(required=action.required)
    group._group_actions.append(action)      # argparse adds no existing action to a group
    action.required = False
    for spelling in old:
        alias = copy.copy(action)
        alias.option_strings, alias.help, alias.default = [spelling], argparse.SUPPRESS, argparse.SUPPRESS
        alias.alias_of = new
        alias.__dict__.pop("file_role", None)    # a file option is checked once, by its shown spelling
        group._add_action(alias)


def aliases(parser) -> dict:
    """``{old: new}``: the hidden earlier spellings of a sub-command's options (:func:`add_alias`)."""
    return {a.option_strings[0]: a.alias_of for a in parser._actions if getattr(a, "alias_of", None)}


def typed_spellings(parser, argv) -> dict:
    """``{new: old}`` for each option of ``parser`` given on the command line ``argv`` by an
    earlier spelling (``--band 2:40`` for ``--freq-band``; also ``--band=2:40`` and a unique
    abbreviation, as argparse reads them)."""
    known = aliases(parser)
    spelled = {}
    for token in argv:
        if not token.startswith("--") or token == "--":
            continue
        name = token.split("=", 1)[0]
        if name not in parser._option_string_actions:
            matches = [s for s in parser._option_string_actions if s.startswith(name)]
            name = matches[0] if len(matches) == 1 else name
        if name in known:
            spelled[known[name]] = name
    return spelled


def as_typed(args, option: str) -> str:
    """``option`` as the user spelled it: its earlier spelling when that was typed (``--band``
    for ``--freq-band``), else ``option``."""
    return getattr(args, "spelled", {}).get(option, option)


def parse_count(text, option: str, of: str = "") -> int:
    """A whole number >= 1 given to ``option`` (``of``: what it counts, named in the message)."""
    try:
        value = whole_number(text)
    except ValueError:
        value = 0
    if value < 1:
        raise InputError(f"{option} {text!r}: expected a whole number{' of ' + of if of else ''} >= 1")
    return value


def parse_range(text: str, option: str, largest: float | None = LARGEST) -> np.ndarray:
    """``START:STOP:N`` -> N points from START to STOP, both included (each end of magnitude at most
    ``largest``, see :func:`parse_number`)."""
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"{option} {text!r}: expected START:STOP:N (N points, both ends included), "
                         "e.g. 0:12000:241")
    start, stop = parse_number(parts[0], option, largest), parse_number(parts[1], option, largest)
    try:
        count = whole_number(parts[2])
    except ValueError:
        raise InputError(f"{option} {text!r}: N = {parts[2]!r} must be a whole number >= 1 "
                         "(the number of points, like 50)") from None
    if count < 1 or (count == 1 and start != stop):
        raise InputError(f"{option} {text!r}: N must be >= 2 for a range (or START = STOP with N = 1)")
    if count > 1 and not stop > start:
        raise InputError(f"{option} {text!r}: STOP must be greater than START")
    if problem := count_problem(count):
        raise InputError(f"{option} {text!r}: N must be {problem}")
    return np.linspace(start, stop, count)


def parse_band(text, option: str, unit: str, *, low=0.0, low_open=False, names=("LO", "HI"),
               example="0:40", wording="rule", largest: float | None = LARGEST,
               single: bool = False) -> tuple[float, float]:
    """``LO:HI`` -> (LO, HI): the one parser of the band options (``--freq-range``,
    ``--operating-range``, ``--freq-band``), so that each refuses the same inputs the same way.

    Parameters
    ----------
    text : str
        The option's value: two finite numbers joined by one ':'.
    option : str
        The option, for messages.
    unit : str
        The unit of LO and HI, for messages (e.g. ``"Hz"``, ``"rpm"``).
    low : float or None
        The least LO may be (None: any number, e.g. a band of negative speeds).
    low_open : bool
        LO must be greater than ``low`` (True) or may equal it (False).
    names : (str, str)
        How LO and HI are spelled in the option's ``--help`` (every band's is ``LO:HI``).
    example : str
        A valid value, shown when the form is wrong.
    wording : {"rule", "form"}
        How a band out of order or below ``low`` is refused: "rule" echoes the value quoted and
        names the rule (``expected 0 <= LO < HI [Hz]``); "form" echoes it as typed and names the
        form first (``expected LO:HI in Hz with 0 <= LO < HI``), the wording ``fit`` has used.
    largest : float or None
        The largest magnitude of LO and HI (None: any finite number).
    single : bool
        LO may equal HI (a band of one value: an operating range that is one rated speed).

    Returns
    -------
    (float, float)
        LO < HI (LO <= HI with ``single``), in ``unit``.

    Raises
    ------
    InputError
        Not exactly one ':' (an empty value too), a side that is not a finite number or beyond
        ``largest``, LO >= HI, or LO below ``low``.
    """
    lo, hi = names
    shown = repr(text) if wording == "rule" else text
    parts = text.split(":")
    if len(parts) != 2:
        raise InputError(f"{option} {shown}: expected {lo}:{hi} [{unit}], e.g. {example}")
    values = []
    for part in parts:
        try:
            values.append(_plain_float(part))
        except ValueError:
            raise InputError(f"{option} {shown}: expected {lo}:{hi} [{unit}] of two numbers, e.g. {example} "
                             f"({part!r} is not a number)") from None
        if not math.isfinite(values[-1]):
            raise InputError(f"{option} {shown}: expected {lo}:{hi} [{unit}] of two finite numbers, "
                             f"e.g. {example}")
    if largest is not None and max(map(abs, values)) > largest:
        raise InputError(f"{option} {shown}: expected {lo} and {hi} of magnitude at most {largest:g} [{unit}]")
    low_value, high_value = values
    order = f"{lo} {'<=' if single else '<'} {hi}"
    rule = order if low is None else f"{low:g} {'<' if low_open else '<='} {order}"
    if not ((low_value <= high_value if single else low_value < high_value) and (low is None or low_value > low or (low_value == low and not low_open))):
        raise InputError(f"{option} {shown}: expected {rule} [{unit}]" if wording == "rule" else
                         f"{option} {shown}: expected {lo}:{hi} in {unit} with {rule}")
    return low_value, high_value


def parse_list(text: str, option: str) -> np.ndarray:
    """``1,2,0.5`` -> array; an empty item (``1,,2``, ``1,2,``) is refused, not dropped."""
    items = [item.strip() for item in text.split(",")]
    if not any(items):
        raise InputError(f"{option} {text!r}: expected a comma-separated list of numbers")
    if not all(items):
        raise InputError(f"{option} {text!r}: expected a comma-separated list of numbers, found an empty "
                         "item between commas")
    return np.array([parse_number(item, option) for item in items])


#: how a name holding ',' is written in a list option (the help texts and messages say it)
NAME_LIST_HELP = ("comma-separated; a name holding ',' is given whole, or quoted (\"a,b\"), or with its "
                  "commas escaped (a\\,b)")


def add_sensor_argument(parser) -> None:
    """``--sensor NAME[,NAME]`` (the sensors of ``frf`` and ``unbalance``, default all; read as
    ``args.output`` by :func:`parse_names`), with its earlier spelling ``--output`` kept hidden
    (:func:`add_alias`)."""
    parser.add_argument("--sensor", dest="output", metavar="NAME[,NAME]",
                        help=f"sensor name(s), {NAME_LIST_HELP} (default all)")
    add_alias(parser, "--sensor", "--output")


def parse_names(text, option: str, known=None) -> list[str] | None:
    """The names of a comma-separated list option (``--sensor a,b``), where a name may itself
    hold commas (model names are any text).

    Double quotes keep what they enclose as one name (``"acc, top",probe-x``), a backslash
    escapes the next character (``acc\\, top``); an item so written is taken as written. The
    other items are matched against ``known`` first: the pieces are joined back where the joint
    text (``acc, top``) is a known name, so a name holding commas also works given as it is.

    Parameters
    ----------
    text : str or None
        The option's value (None: not given).
    option : str
        The option, for messages.
    known : collection of str or callable, optional
        The names the option may take (or a test of one): used to join pieces back.

    Returns
    -------
    list of str, or None when ``text`` is None

    Raises
    ------
    InputError
        An unclosed quote, a trailing backslash, nothing named, or pieces that read as known
        names in two ways (``a,b`` where ``a``, ``b`` and ``a,b`` are all names).
    """
    if text is None:
        return None
    is_known = known if callable(known) or known is None else (lambda name, names=set(known): name in names)
    if is_known and ('"' in text or "\\" in text) and is_known(text):
        return [text]           # a name holding a quote or a backslash, given whole
    names, plain = [], []
    for item, protected in _list_items(text, option) + [(None, True)]:
        if not protected:
            plain.append(item)
            continue
        if plain:       # the unprotected pieces since the last protected item
            names.extend(_join_known(plain, text, option, is_known) if is_known and len(plain) > 1 else
                         [piece.strip() for piece in plain])
            plain = []
        if item is not None:
            names.append(item)
    if not any(names):
        raise InputError(f"{option} {text!r}: expected one or more names, {NAME_LIST_HELP}")
    if not all(names):      # --sensor a,,b: a name left out by mistake, not to be dropped in silence
        raise InputError(f"{option} {text!r}: expected one or more names, found an empty item between commas")
    twice = [n for i, n in enumerate(names) if n in names[:i]]
    if twice:   # --sensor a,a wrote every FRF twice: a file the package then refused to read
        from ..model._table import visible

        raise InputError(f"{option} {text!r}: expected each name once ({visible(twice[0])} is given twice)")
    return names


def check_known(names, text, option: str, what: str, known) -> None:
    """Refuse a name of ``names`` (from ``option``'s value ``text``) that is not in ``known``,
    naming the option as typed and the model's names (``--sensor x: unknown sensor 'x': the
    model's sensors are a, b``); ``names`` None (not given) passes."""
    missing = [n for n in names or () if n not in known]
    if missing:
        listed = f"the model's {what}s are {', '.join(known)}" if known else f"the model has no [[{what}s]]"
        raise InputError(f"{option} {text}: unknown {what} {', '.join(map(repr, missing))}: {listed}")


def _list_items(text: str, option: str) -> list[tuple[str, bool]]:
    """``text`` split at its commas outside quotes and not escaped: ``(item, protected)`` pairs.
    A protected item (it used a quote or an escape) is as written, less the white space around
    it outside quotes; an unprotected one is its raw text (joined back by :func:`_join_known`)."""
    items, chars, protected, quoted, i = [], [], False, False, 0
    while i <= len(text):
        char = text[i] if i < len(text) else ","
        if char == "\\" and i + 1 < len(text):
            chars.append((text[i + 1], True))
            protected, i = True, i + 2
            continue
        if char == "\\":
            raise InputError(f"{option} {text!r}: a backslash at the end escapes nothing ({NAME_LIST_HELP})")
        if char == '"' and i < len(text):
            quoted, protected = not quoted, True
        elif char == "," and (not quoted or i == len(text)):
            if quoted:
                raise InputError(f"{option} {text!r}: a quote is not closed ({NAME_LIST_HELP})")
            while protected and chars and not chars[-1][1] and chars[-1][0].isspace():
                chars.pop()
            while protected and chars and not chars[0][1] and chars[0][0].isspace():
                chars.pop(0)
            items.append(("".join(c for c, _ in chars), protected))
            chars, protected = [], False
        else:
            chars.append((char, quoted))
        i += 1
    return items


def _join_known(pieces, text, option, is_known) -> list[str]:
    """``pieces`` (the text between commas) grouped into consecutive runs that each read as a
    known name; as split when no grouping does; refused when two groupings do."""
    count = len(pieces)
    ways = {count: [[]]}          # ways[i]: groupings of pieces[i:] into known names (at most 2 kept)
    for start in range(count - 1, -1, -1):
        found = []
        for stop in range(start + 1, count + 1):
            name = ",".join(pieces[start:stop]).strip()
            if is_known(name):
                found.extend([[name] + rest for rest in ways[stop]][:2 - len(found)])
            if len(found) == 2:
                break
        ways[start] = found
    if not ways[0]:      # some piece is no name: the known names kept whole, the rest as split (refused later)
        return _longest_known(pieces, is_known)
    if len(ways[0]) > 1:
        first, second = ways[0][:2]
        raise InputError(f"{option} {text!r}: reads as {', '.join(map(repr, first))} or as "
                         f"{', '.join(map(repr, second))}: quote the names that hold commas (\"a,b\") or "
                         "escape their commas (a\\,b)")
    return ways[0][0]


def _longest_known(pieces, is_known) -> list[str]:
    """``pieces`` grouped from the left, each group the longest run that reads as a known name
    (a single piece where none does): an unknown name is then named alone in the refusal."""
    names, start = [], 0
    while start < len(pieces):
        stop = next((stop for stop in range(len(pieces), start, -1)
                     if is_known(",".join(pieces[start:stop]).strip())), start + 1)
        names.append(",".join(pieces[start:stop]).strip())
        start = stop
    return names


def add_input_file(parser, *flags, **kwargs):
    """``parser.add_argument`` for a file the command reads: no output may name it
    (:func:`check_files`, run for every command before its work). The help of an input that
    reads '-' (:data:`_STANDARD_INPUTS`) says so."""
    action = parser.add_argument(*flags, **kwargs)
    action.file_role = "input"
    if action.dest in _STANDARD_INPUTS and action.help and STANDARD_INPUT not in action.help:
        action.help += f"; '-' reads it from {STANDARD_INPUT}"
    return action


def add_output_file(parser, *flags, **kwargs):
    """``parser.add_argument`` for a file the command writes ('-' is standard output): it may
    name no input file and no other output (:func:`check_files`)."""
    action = parser.add_argument(*flags, **kwargs)
    action.file_role = "output"
    return action


def file_options(parser) -> dict:
    """``{"input": [(dest, option), ...], "output": [...]}`` of a sub-command's parser: the
    options declared with :func:`add_input_file` and :func:`add_output_file`."""
    found = {"input": [], "output": []}
    for action in parser._actions:  # argparse keeps no public list of its actions
        role = getattr(action, "file_role", None)
        if role:
            found[role].append((action.dest, action.option_strings[0] if action.option_strings
                                else action.metavar or action.dest.upper()))
    return found


def _given(args, role):
    """(option, path) of every file of ``role`` named on the command line."""
    return [(as_typed(args, option), getattr(args, dest)) for dest, option in getattr(args, "file_options", {}).get(role, ())
            if getattr(args, dest, None) not in (None, "", "-")]


#: input options whose readers need a regular file (UFF and TDMS readers open the file by its
#: name and seek): a pipe given to them is copied first (:func:`pipes_copied`)
_COPIED_PIPES = ("measured",)

#: how each input option reads '-', standard input: dest -> (its size limit's kind, what it is,
#: the copy's ending; None: the ending its bytes show). Read once into a temporary file (a
#: mapping table is read twice by ``frf``), except the ROSS file, read once as /dev/stdin (its
#: rotor is named as a pipe's: no file's stem, :func:`rotordyn_modal.io.ross_file.without_name`)
_STANDARD_INPUTS = {"model": ("model", "model file", ".toml"), "spec": ("model", "study file", ".toml"),
                    "measured": ("measured", "measured-data file", None),
                    "mapping": ("model", "mapping table", ".csv"), "outline": ("model", "stator outline", ".csv"),
                    "ross_file": None}
#: how messages name '-'
STANDARD_INPUT = "standard input"


@contextlib.contextmanager
def pipes_copied(args):
    """Each ``--measured`` given a pipe (``<(cat m.uff)``, ``/dev/stdin`` of a pipe, a FIFO a
    program writes to), and the input given ``-`` (standard input, :data:`_STANDARD_INPUTS`), read
    once into a temporary file (:func:`rotordyn_modal.io.limits.pipe_copied`: the format its
    ending or its bytes show), the option then naming it, as models are read from pipes.
    ``args.shown_names`` maps the copy's name back to the name typed, or to "standard input"
    (messages say that one: :func:`shown_as_typed`). The copies are removed at the end."""
    from ..io.limits import is_fifo

    piped = []
    for dest, _ in getattr(args, "file_options", {}).get("input", ()):
        path = getattr(args, dest, None)
        if path == "-" or (dest in _COPIED_PIPES and path not in (None, "") and is_fifo(path)):   # missing: the reader says so
            piped.append((dest, path))
    if not piped:
        yield
        return
    from ..io.measured import piped_copy

    with contextlib.ExitStack() as copies:
        args.shown_names = {}
        for dest, path in piped:
            if path == "-":
                args.shown_names["/dev/stdin"] = STANDARD_INPUT
                if _STANDARD_INPUTS[dest] is None:      # the ROSS file, read once as /dev/stdin
                    setattr(args, dest, "/dev/stdin")
                    continue
                copy, shown = _standard_input_copy(dest), STANDARD_INPUT
            else:
                copy, shown = piped_copy(path), str(path)
            duplicate = str(copies.enter_context(copy))
            args.shown_names[duplicate] = shown
            setattr(args, dest, duplicate)
        yield


def _standard_input_copy(dest):
    """:func:`rotordyn_modal.io.limits.pipe_copied` of standard input for the option ``dest``
    (:data:`_STANDARD_INPUTS`): a pipe or a redirected file, within the limit of its kind."""
    from ..io.limits import pipe_copied
    from ..io.measured import sniffed_ending

    kind, what, ending = _STANDARD_INPUTS[dest]
    return pipe_copied("/dev/stdin", ending or sniffed_ending, kind, what, name="stdin")


def _standard_inputs(args) -> list[str]:
    """The options (as typed) given '-', each refused where standard input cannot be read: more
    than one of them, an option that reads no standard input, standard input closed or a
    terminal (nothing piped in: the command would wait for typing)."""
    dashed = [(dest, f"{as_typed(args, option)} -") for dest, option in getattr(args, "file_options", {}).get("input", ())
              if getattr(args, dest, None) == "-"]
    if len(dashed) > 1:
        raise InputError(f"{' and '.join(typed for _, typed in dashed)}: standard input is read once: give '-' to one "
                         "of them and name files for the others")
    for dest, typed in dashed:
        if dest not in _STANDARD_INPUTS:
            raise InputError(f"{typed}: this option does not read standard input: expected a file name")
        try:
            terminal = os.isatty(0)
            os.fstat(0)
        except OSError:
            raise InputError(f"{typed}: standard input is closed: pipe the file in (... < FILE) or name it") from None
        if terminal:
            raise InputError(f"{typed}: standard input is a terminal, nothing is piped in: pipe the file in "
                             "(... < FILE, or cat FILE | ...) or name it")
    return [typed for _, typed in dashed]


def _standard_input_file(typed):
    """``[(option, the file)]`` when '-' (``typed``: the options given it, :func:`_standard_inputs`)
    reads a regular file redirected into standard input (``< m.toml``): an output may not name it
    either (:func:`check_files`); else ``[]``."""
    import stat

    try:
        regular = typed and stat.S_ISREG(os.fstat(0).st_mode)
    except OSError:
        regular = False
    return [(typed[0], os.path.realpath("/dev/stdin"))] if regular else []


def shown_as_typed(text: str, args) -> str:
    """``text`` (a message) with the names of :func:`pipes_copied`'s copies replaced by the names typed."""
    for duplicate, typed in getattr(args, "shown_names", {}).items():
        text = text.replace(duplicate, typed)
    return text


def check_files(args) -> None:
    """Refuse, before any work, an output that names an input file or another output,
    whatever the spelling: a symbolic link, a hard link, a path through a linked folder.

    Raises
    ------
    InputError
    """
    from ..io.atomic import same_file

    for role in ("input", "output"):
        for dest, option in getattr(args, "file_options", {}).get(role, ()):
            option = as_typed(args, option)      # the spelling typed (--orbit-plot for --plot-orbits)
            if getattr(args, dest, None) == "":   # an empty variable in a script: never "not given"
                raise InputError(f"{option} '': expected a file name")
    inputs, outputs = _given(args, "input") + _standard_input_file(_standard_inputs(args)), _given(args, "output")
    for option, path in inputs + outputs:
        if "\0" in str(path):
            raise InputError(f"{option} {str(path)!r}: a file name cannot hold a NUL character")
    for option, path in inputs:     # every reader alike (the mapping's said "Not a directory", a long name exit 1)
        problem = unreachable_name(path)
        if problem:
            raise InputError(f"{option} {shown_name(path)}: the name {problem}")
    for i, (option, path) in enumerate(outputs):
        for source_option, source in inputs:
            if same_file(path, source):
                raise InputError(f"{option} {path}: refusing to write over the input file {source} "
                                 f"({source_option})")
        for other_option, other in outputs[:i]:
            if same_file(path, other):
                raise InputError(f"{other_option} and {option} name the same file {other}: "
                                 "give two different files")
    for option, path in outputs:  # a missing or read-only folder, a folder in the way: before the work
        try:
            check_writable(path)
        except InputError as error:
            message = str(error)            # "PATH: the folder ... does not exist" reads "--out PATH: ..."
            raise type(error)(f"{option} {message}" if message.startswith(f"{path}:") else
                              f"{option}: {message}") from None


def add_model_argument(parser):
    add_input_file(parser, "model", metavar="MODEL", help="model file (TOML), see docs/model-file.md")


#: the unit of a speed option, in its --help
IN_SPEED_UNIT = "[rpm, or --speed-unit]"


def add_speed_unit(parser):
    parser.add_argument("--speed-unit", choices=sorted(SPEED_UNITS), default="rpm", type=str.lower,
                        help="unit of the speed options (default rpm)")


def add_outputs(parser, table: bool = True, plot: bool = True, out_endings=(".csv",)):
    """--out (a table; ``out_endings``: the file endings the sub-command writes), --plot, --quiet."""
    if table:
        add_output_file(parser, "--out", metavar="FILE" + "|FILE".join(out_endings),
                        help="write the table to this file, in the format of its ending "
                             f"({', '.join(out_endings)}; '-': CSV on standard output)")
        parser.set_defaults(out_endings=tuple(out_endings))
    if plot:
        add_output_file(parser, "--plot", metavar="FILE.png|FILE.svg|FILE.pdf", help="draw the figure to this file")
    parser.add_argument("--quiet", action="store_true", help="no progress (bars, or lines where stderr is a log), no table on the terminal")


def add_allow_long(parser):
    """``--allow-long``: run an analysis estimated to take longer than the CPU-time limit."""
    parser.add_argument("--allow-long", action="store_true",
                        help="run even where the estimate of the work exceeds the limit of CPU time (default 30 "
                             "min; ROTORDYN_MODAL_MAX_CPU_MINUTES sets it); without it such work is refused "
                             "before it starts, with the estimate")


def speeds_option(args) -> np.ndarray:
    """``--speeds START:STOP:N`` in rad/s (refused beyond 1e30 rad/s, said in --speed-unit)."""
    return check_speeds(parse_range(args.speeds, "--speeds", largest=None), args.speeds, args.speed_unit, "--speeds")


def lowest_option(text, model):
    """``--lowest N`` as an int, or None (every mode: also when N is at least the model's number of
    roots, so that the long-work check holds); refused in one line unless a whole number >= 1."""
    from ..analysis.campbell import root_count

    count = None if text is None else parse_count(text, "--lowest", of="modes")
    return None if count is None or count >= root_count(model) else count


def max_frequency_option(text):
    """``--max-frequency HZ`` as a float [Hz], or None (no limit); refused in one line unless a
    finite number > 0."""
    if text is None:
        return None
    value = parse_number(text, "--max-frequency")
    if not value > 0:
        raise InputError(f"--max-frequency {text!r}: expected a frequency > 0 [Hz]")
    return value


def speeds_text(args) -> str:
    """The --speeds range in words, ``between 500 and 15000 rpm`` (``at 3000 rpm`` for one point)."""
    points = parse_range(args.speeds, "--speeds")
    unit = args.speed_unit
    return f"at {points[0]:g} {unit}" if len(points) == 1 else f"between {points[0]:g} and {points[-1]:g} {unit}"


def open_model(args):
    """Check the output options (before any work), then load and validate the model.

    The model's warnings (legal but implausible: a sag of metres, a mode below 0.5 Hz) are said
    at once, unless the model's mass matrix is one that rounding leaves singular, which every
    analysis refuses: then they wait in ``args.held_warnings`` and ``main`` says them only if the
    command does not end in a refusal (``static`` needs no mass matrix), so that a refused model
    reads as one line, not a true but moot warning above it."""
    import warnings

    check_output_options(args)
    with warnings.catch_warnings(record=True) as held, starting(args, "reading and checking the model"):
        warnings.simplefilter("always")
        model = load_model(args.model, units=getattr(args, "units", None) or "si")   # its warnings' unit system
    model.source = shown_as_typed(model.source, args)   # '-': "standard input", not its temporary copy
    if held and _mass_refused(model):
        args.held_warnings = held
    else:
        say_warnings(held)
    return model


def _mass_refused(model) -> bool:
    """True when the analyses refuse ``model``'s mass matrix (``speed_linear_form``'s check, as
    ``check`` and every analysis make it)."""
    from ..errors import ModelError
    from ..linear_system import speed_linear_form

    try:
        speed_linear_form(model)
    except ModelError:
        return True
    return False


def say_warnings(held) -> None:
    """Warn again each of ``held`` (``warnings.catch_warnings(record=True)``'s records), through the
    filters and the one-line printer in force."""
    import warnings

    for record in held:
        warnings.warn_explicit(record.message, record.category, record.filename, record.lineno)


def check_output_options(args):
    """Refuse a bad --plot ending or an output over an input before computing anything."""
    from pathlib import Path

    plot = getattr(args, "plot", None)
    endings = getattr(args, "plot_endings", None)
    if plot and endings and Path(plot).suffix.lower() not in endings:
        raise InputError(f"--plot {plot}: expected a file ending in {', '.join(endings[:-1])} or {endings[-1]}")
    if plot and not endings and Path(plot).suffix.lower() not in _FIGURE_FORMATS:
        raise InputError(f"--plot {plot}: expected a file ending in .png, .svg or .pdf")
    out = getattr(args, "out", None)
    if plot and out and out != "-" and Path(plot).resolve() == Path(out).resolve():
        raise InputError(f"--out and --plot name the same file {out}: give two different files")
    for option in ("out", "plot"):
        path = getattr(args, option, None)
        if path and path != "-":
            check_outputs(args, path)
            if not Path(path).parent.exists():
                raise InputError(f"--{option} {path}: the folder {Path(path).parent} does not exist")
    check_ending(out, getattr(args, "out_endings", None), "--out")


def check_ending(path, endings, option: str, stdout: bool = True):
    """Refuse an output whose file ending is not one of the formats written (``-``: standard output;
    a pipe or device without an ending, where CSV is one of them, is written as CSV). With
    ``stdout=False`` the output is never written to standard output, and ``-`` (which would make a
    file named '-') is refused."""
    from pathlib import Path

    from ..io.atomic import _is_special

    if path == "-" and not stdout:
        raise InputError(f"{option} -: expected a file ending in {' or '.join(endings)} ('-', standard output, "
                         f"is not where {option} writes: give a file name)")
    if path and path != "-" and endings and not Path(path).suffix and ".csv" in endings and _is_special(path):
        return   # a pipe or device without an ending (a shell's >(gzip > f.gz), /dev/stdout): CSV, as '-'
    if path and path != "-" and endings and Path(path).suffix.lower() not in endings:
        raise InputError(f"{option} {path}: expected a file ending in {' or '.join(endings)} (the format "
                         "follows the ending)")


def show_progress(args) -> bool:
    """Whether the command shows its progress: unless ``--quiet``. On a terminal as bars; where
    stderr is a file or a pipe (a log, a batch job) as whole lines, the first after
    :data:`.._progress.LOG_DELAY` s of work (shorter work writes nothing there)."""
    return not getattr(args, "quiet", False)


#: the start-up line of the estimate of the CPU time (a timed eigen-solution, the expected crossings)
ESTIMATING = "estimating the work"


def starting(args, what: str):
    """A context for start-up work without steps to count (reading and checking the model, the
    estimate of the CPU time): on a terminal, without ``--quiet``, one line ``what: [elapsed]``
    once the silence has lasted :data:`.._progress.PHASE_DELAY` (the phases one after another
    count it from the first: a 500-rotor model was read, checked and estimated for 17 s before
    anything showed)."""
    from .._progress import phase

    return phase(show_progress(args), what)


def check_extra_output(args, path, option: str, figure: bool = False):
    """Refuse a bad extra output (``--orbits FILE``) before any work: its ending, its folder,
    an input file, or the same file as --out or --plot."""
    from pathlib import Path

    if not path:
        return
    if figure and Path(path).suffix.lower() not in _FIGURE_FORMATS:
        raise InputError(f"{option} {path}: expected a file ending in .png, .svg or .pdf")
    for other in ("out", "plot"):
        taken = getattr(args, other, None)
        if taken and taken != "-" and Path(taken).resolve() == Path(path).resolve():
            raise InputError(f"{option} and --{other} name the same file {path}: give two different files")
    check_outputs(args, path)
    if not Path(path).parent.exists():
        raise InputError(f"{option} {path}: the folder {Path(path).parent} does not exist")


#: the number format of every CSV the command line writes: 15 significant digits, as many as any
#: decimal keeps through a double (DBL_DIG), so a number read back is the one computed to 5e-15
#: (relative) and a US table converted back is the SI one to 1e-14 (issue 29; the ten digits of
#: before agreed to 5e-10 only), while a sweep's speed prints as typed (100, not the
#: 99.99999999999999 that rpm -> rad/s -> rpm leaves; docs/units.md)
CSV_FLOAT_FORMAT = "%.15g"


def write_csv(table, path, float_format=CSV_FLOAT_FORMAT):
    """Write a DataFrame to a CSV file atomically."""
    with atomic_write(path, "w", newline="") as handle:
        table.to_csv(handle, index=False, float_format=float_format)


def write_table(table, args, float_format=CSV_FLOAT_FORMAT, empty: str | None = None, shown=None):
    """Write a DataFrame to --out (atomic), or print it on the terminal (``empty``: the sentence
    printed instead of a table without rows, see :func:`print_table`; ``shown``: the table the
    terminal shows, when its words differ from the file's). A CSV has its header even without
    rows, never a ``-0``."""
    out = getattr(args, "out", None)
    if out == "-":
        _without_negative_zeros(table).to_csv(sys.stdout, index=False, float_format=float_format)
    elif out:
        check_outputs(args, out)
        with atomic_write(out, "w", newline="") as handle:
            _without_negative_zeros(table).to_csv(handle, index=False, float_format=float_format)
    if out != "-" and not args.quiet:
        print_table(table if shown is None else shown, empty)


_TERMINAL_ROWS = 40

#: a sweep's columns that are zero on a conservative machine (every root imaginary)
_DAMPING_COLUMNS = ("damping_ratio", "log_decrement", "real_part")


def undamped_zeros(table, model, speed: float | None = None):
    """``table`` (a sweep's rows with ``speed_rpm`` in rpm, or the modes at one ``speed`` [rad/s])
    with its damping columns marked as round-off (printed 0 on the terminal, the CSV keeps every
    digit) on the rows where the machine is conservative: no damping and a symmetric positive
    semidefinite stiffness put every root on the imaginary axis (``analysis._roots.conservative``,
    docs/theory.md section 11), so a damping ratio of -1.4e-30 or -6.2e-15 is round-off and must
    not read as unstable. The eigen-solve's error can exceed its backward error by the roots'
    condition (a 10 m shaft meshed with a 1 mm element: log decrements of -2.5e-5 at 0.55 Hz, 15
    times the round-off estimate), so the machine, not that estimate, decides. Only the rows
    printed are tested."""
    from ..assembly import constant_matrices, is_large, sparse_constant_matrices

    if table.empty or (speed is None and "speed_rpm" not in table):
        return table
    # damped: no form built (a large model's damping tested sparse, without its dense matrices)
    if sparse_constant_matrices(model).C.count_nonzero() if is_large(model) else constant_matrices(model).C.any():
        return table
    from ..analysis._roots import conservative
    from ..linear_system import speed_linear_form

    if speed is None:
        speeds = table["speed_rpm"].to_numpy(dtype=float)[:_TERMINAL_ROWS] * (math.pi / 30.0)
    else:
        speeds = np.array([float(speed)])
    noise = np.where(conservative(speed_linear_form(model), speeds), np.inf, 0.0)
    if speed is not None:
        noise = np.full(min(len(table), _TERMINAL_ROWS), noise[0])
    if noise.any():
        table.attrs["round_off"] = {**table.attrs.get("round_off", {}),
                                    **{column: noise for column in _DAMPING_COLUMNS if column in table}}
    return table


def with_round_off_rows(table, result):
    """A copy of ``table`` (``result.to_dataframe()``) whose ``attrs['round_off']`` holds every
    column's round-off row by row (``result.round_off_rows()``) for :func:`print_table`: the
    result's own table keeps only the columns where it is one number (pandas compares attrs)."""
    table = table.copy()
    table.attrs["round_off"] = {**table.attrs.get("round_off", {}), **result.round_off_rows()}
    return table


def print_table(table, empty: str | None = None):
    """Print a table on the terminal, shortened to its first rows when long.

    A table without rows prints ``empty`` (a sentence such as "no critical speed between 500 and
    15000 rpm"; default "nothing to list"), not pandas' ``Empty DataFrame``. Numbers within their
    round-off print as 0: ``table.attrs["round_off"]`` maps a column to what round-off can move
    its values by, row by row (or one number for every row) (see ``ModalResult.to_dataframe``); no number prints as -0.
    """
    if table.empty:
        print(empty or "nothing to list")
        return
    shown = _at_round_off(table.head(_TERMINAL_ROWS), table.attrs.get("round_off", {}))
    print(shown.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    if len(table) > len(shown):
        print(f"... {len(table) - len(shown)} more rows ({len(table)} in all; --out FILE.csv writes them all)")


def _at_round_off(table, round_off: dict):
    """``table`` with the values within their round-off made 0 and every -0 made 0."""
    table = _without_negative_zeros(table)
    for column, noise in round_off.items():
        if column in table:
            values = table[column].to_numpy(dtype=float)
            noise = np.asarray(noise, dtype=float)              # one number for the column, or one a row
            table[column] = np.where(np.abs(values) <= (noise if noise.ndim == 0 else noise[:len(values)]), 0.0, values)
    return table


def _without_negative_zeros(table):
    """A copy of ``table`` whose float columns have no -0 (``-0.0 + 0.0`` is ``0.0``)."""
    table = table.copy()
    floats = [place for place, kind in enumerate(table.dtypes) if kind.kind == "f"]
    if floats:
        # one block assignment: a column at a time costs seconds on a 6,000-column simulate table
        table.iloc[:, floats] = table.iloc[:, floats] + 0.0
    return table


_FIGURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}


def check_outputs(args, path):
    """Refuse an output over an input file, or one that cannot be written (read-only folder)."""
    from pathlib import Path

    inputs = [source for _, source in _given(args, "input")] if hasattr(args, "file_options") else \
        [getattr(args, "model", None), getattr(args, "measured", None), getattr(args, "spec", None)]
    check_not_input(path, inputs)
    if Path(path).parent.exists():  # a missing folder: the callers name the option
        check_writable(path)


def save_figure(fig, args, path=None, option: str = "--plot"):
    """Save ``fig`` to --plot (or ``path``) atomically; the format follows the file ending."""
    from pathlib import Path

    path = Path(args.plot if path is None else path)
    fmt = _FIGURE_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise InputError(f"{option} {path}: expected a file ending in .png, .svg or .pdf")
    check_outputs(args, path)
    with atomic_write(path, None) as temporary:
        fig.savefig(temporary, format=fmt, dpi=150)
    if not args.quiet:
        after_commit(lambda: print(f"figure written to {path}", file=sys.stderr))


def use_agg():
    import matplotlib

    matplotlib.use("Agg")
