"""Entry point: argument parsing, error handling and exit codes."""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
import warnings

from ..errors import InputError, OutputWriteError
from ._common import (VALUE_OPTIONS, check_files, file_options, join_negative_values, options_as_typed,
                      pipes_copied, say_warnings, shown_as_typed, typed_spellings)

PROGRAM = "rotordyn-modal"


class _StoreOnce(argparse._StoreAction):
    """A value option given twice is refused in one line: argparse keeps the last value without a
    word, so ``frf --sensor a --sensor b`` silently answered for ``b`` alone."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = parser.values_given
        if self.dest in given:
            first, spelling = given[self.dest]
            listed = "[,"in str(self.metavar or "") or "," in str(self.metavar or "")
            hint = f" (several values go in one option: {option_string} a,b)" if listed else ""
            parser.error(f"{option_string} given twice ({spelling} {first!r}, then {values!r}): give it once{hint}")
        given[self.dest] = (values, option_string)
        super().__call__(parser, namespace, values, option_string)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)
        self.values_given = {}

    def parse_known_args(self, args=None, namespace=None):
        self.values_given = {}          # {dest: (value, spelling)} of this parse (_StoreOnce)
        return super().parse_known_args(args, namespace)

    def parse_args(self, args=None, namespace=None):
        """The top parser's parse: an argument no option of the sub-command takes is refused by
        the sub-command's parser (``rotordyn-modal frf: error: ...``, its own --help), naming
        the sub-commands that take such an option, or the option of this one it is a typo of;
        argparse's own refusal named neither (``rotordyn-modal: error: unrecognized arguments``)."""
        parsed, extras = self.parse_known_args(args, namespace)
        commands = self._subparsers._group_actions[0].choices if self._subparsers else {}
        sub = commands.get(getattr(parsed, "command", None))
        if extras:
            (sub or self).error(f"unrecognized arguments: {' '.join(extras)}{_unrecognized_hint(extras, sub, commands)}")
        if sub is not None:
            self._refuse_two_values(sub)
        return parsed

    def _refuse_two_values(self, sub) -> None:
        """An option given before the sub-command and again after it with another value
        (``--units us static M --units si``) is refused as one given twice in one place is
        (:class:`_StoreOnce`); the value after it won without a word."""
        for dest in self.values_given.keys() & sub.values_given.keys():
            (before, spelling), (after, _) = self.values_given[dest], sub.values_given[dest]
            if str(before).strip().lower() != str(after).strip().lower():
                sub.error(f"{spelling} given twice ({before!r} before the sub-command, then {after!r}): give it once")

    def error(self, message):  # usage errors: one line (no usage block before it), exit 2
        if message.startswith("one of the arguments ") and " " not in message[21:-12]:  # a required option
            message = f"the following arguments are required: {message[21:-12]}"     # and its hidden alias
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _unrecognized_hint(extras, sub, commands) -> str:
    """The end of an unrecognized argument's message: for its first option (``--amplitude rms``
    given to ``frf``), the sub-commands that take it (``": --amplitude is an option of
    unbalance, report"``), else the option of ``sub`` it is a typo of (``": did you mean
    '--sensor'?"``), else nothing.

    Parameters
    ----------
    extras : list of str
        The arguments no option took, as typed.
    sub : argparse.ArgumentParser or None
        The sub-command's parser (None: no sub-command was given).
    commands : dict
        Every sub-command's parser, by its name.
    """
    from ..model._table import close_key

    option = next((extra.split("=", 1)[0] for extra in extras if extra.startswith("--")), None)
    if option is None:
        return ""
    takers = [name for name, parser in commands.items() if option in parser._option_string_actions]
    if takers:
        return f": {option} is an option of {', '.join(takers)}"
    own = [known for known in (sub._option_string_actions if sub else ()) if known.startswith("--")]
    meant = close_key(option, own)
    return f": did you mean {meant!r}?" if meant else ""


def build_parser() -> argparse.ArgumentParser:
    from .._version import __version__
    from ._resources import add_verbose
    from ._units import add_units_option
    from .commands import SUBCOMMANDS

    parser = _Parser(prog=PROGRAM, description="Linear dynamics and modal analysis of multi-rotor "
                     "machines: modes, Campbell diagrams, critical speeds, stability, FRFs.",
                     epilog=f"Run '{PROGRAM} SUB --help' for the options of a sub-command.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    add_units_option(parser)
    subparsers = parser.add_subparsers(dest="command", metavar="SUB", required=True, parser_class=_Parser)
    for module in SUBCOMMANDS:
        sub = subparsers.add_parser(module.NAME, help=module.HELP, description=module.DESCRIPTION,
                                    formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(sub)
        if "--verbose" not in sub._option_string_actions:  # every sub-command has --verbose
            add_verbose(sub)
        if "--units" not in sub._option_string_actions:  # --units before or after the sub-command's name
            add_units_option(sub, suppress=True, help=getattr(module, "UNITS_HELP", None))
        # API_NAMES: the Python arguments the command's options set, named as the options in messages
        sub.set_defaults(handler=module.run, file_options=file_options(sub), api_names=getattr(module, "API_NAMES", {}))
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit code: 0 done; 2 bad input, an output path
    that cannot be used (missing or read-only folder, an input file) or is locked by another
    study; 1 any other failure, a full disk included; 130 after Ctrl-C, 128 + N after
    signal N (143 SIGTERM, 129 SIGHUP). A command's output files appear together at its end,
    or none of them (:func:`rotordyn_modal.io.atomic.outputs_together`)."""
    from ..analysis._cost import long_work_allowed
    from ..io.atomic import outputs_together
    from ._resources import report_peak_memory, verbose_log
    from ._units import resolve_units

    from .._progress import program_started

    program_started()             # a start-up line (reading the model) counts its delay from here
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(join_negative_values(argv, VALUE_OPTIONS))
    # an option's earlier spelling (--band for --freq-band), so that messages say it as typed
    args.spelled = typed_spellings(parser._subparsers._group_actions[0].choices[args.command], argv)
    try:
        with _signals_as_interrupts(), _warnings_as_lines(args.command, args):
            args.units = resolve_units(args.units)
            check_files(args)
            # --allow-long: the one switch every check of the CPU time reads (analysis/_cost.py)
            try:
                with (verbose_log(args), outputs_together(), long_work_allowed(getattr(args, "allow_long", False)),
                      pipes_copied(args)):
                    code = int(args.handler(args) or 0)
            except InputError:
                raise                 # the model's warnings held by open_model are moot: one line
            except BaseException:
                say_warnings(getattr(args, "held_warnings", ()))
                raise
            say_warnings(getattr(args, "held_warnings", ()))
            report_peak_memory(args)
            return code
    except InputError as error:   # "duration = -1.0: ..." of the Python API reads "--duration -1: ..."
        message = options_as_typed(shown_as_typed(_one_line(error), args), args, getattr(args, "api_names", {}))
        print(f"{PROGRAM} {args.command}: error: {message}", file=sys.stderr)
        return 2
    except OutputWriteError as error:  # full disk, size limit: the machine's failure, not the input's
        print(f"{PROGRAM} {args.command}: error: {_one_line(error)}", file=sys.stderr)
        return 1
    except BrokenPipeError:  # the reader (e.g. `| head`) closed the pipe: stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except Terminated as error:
        with contextlib.suppress(OSError):  # after SIGHUP the terminal may be gone
            print(f"{PROGRAM} {args.command}: terminated by {signal.Signals(error.signum).name}", file=sys.stderr)
        _exit_without_busy_threads(128 + error.signum)
        return 128 + error.signum
    except KeyboardInterrupt:
        print(f"{PROGRAM} {args.command}: interrupted", file=sys.stderr)
        return 130
    except Exception as error:  # noqa: BLE001 - the last line of defence, exit code 1
        if os.environ.get("ROTORDYN_MODAL_DEBUG"):
            raise
        print(f"{PROGRAM} {args.command}: failed: {type(error).__name__}: {_one_line(error)} "
              "(set ROTORDYN_MODAL_DEBUG=1 for the traceback)", file=sys.stderr)
        return 1


def _one_line(error) -> str:
    """An error's message on one line: a library's text quoted in it (a CSV parser's
    ``... saw 2\n``) may hold line breaks."""
    return " ".join(line.strip() for line in str(error).splitlines() if line.strip())


def _exit_without_busy_threads(code: int):
    """End the process at once with ``code`` where a thread of the batches' pool still runs a part
    after SIGTERM or SIGHUP (:func:`..analysis._batches.stop_pool`: the parts not started are
    cancelled): the exit would join it, a minute or more of a large sweep. Every ``finally`` has
    run by then (the outputs written whole or not at all); the streams are flushed first. Returns
    where no such thread runs."""
    batches = sys.modules.get("rotordyn_modal.analysis._batches")
    if batches is None or not batches.stop_pool():
        return
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP (``timeout``, a batch scheduler, a closed terminal) received by the
    command line: raised in the main thread like Ctrl-C's KeyboardInterrupt, so that every
    ``finally`` runs (temporary files are removed, a study keeps its finished chunks)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


#: signals that end a command the way Ctrl-C does (SIGINT is Python's KeyboardInterrupt already)
_TERMINATING = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))


@contextlib.contextmanager
def _signals_as_interrupts():
    """SIGTERM and SIGHUP raise :class:`Terminated` while inside; a second one ends the
    process at once (the default action). Nothing changes outside the main thread."""
    def interrupt(signum, frame):
        for number in _TERMINATING:
            signal.signal(number, signal.SIG_DFL)
        raise Terminated(signum)

    try:
        previous = {number: signal.signal(number, interrupt) for number in _TERMINATING}
    except ValueError:  # not the main thread: signals are not ours to handle
        previous = {}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, signal.SIG_DFL if handler is None else handler)


@contextlib.contextmanager
def _warnings_as_lines(command, args=None):
    """Warnings printed as one line each, ``rotordyn-modal COMMAND: warning: ...`` (not Python's
    file, line and source line), a pipe's copy named as typed (:func:`._common.shown_as_typed`)."""
    def one_line(message, category, filename, lineno, file=None, line=None):
        print(f"{PROGRAM} {command}: warning: {shown_as_typed(str(message), args)}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = one_line
        yield


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
