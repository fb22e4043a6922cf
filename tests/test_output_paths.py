"""Output paths as users name them: an output never replaces an input file (every file option
of every sub-command, through links, hard links and linked folders), a symbolic link is
written through, and a write ended by a signal or ``kill -9`` leaves no temporary file behind
(SIGTERM and SIGHUP clean up at once; a later write of the same file removes what ``kill -9``
left). The commands run as a user runs them: ``main`` in-process for refusals, real
processes for signals."""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rotordyn_modal.cli.main import build_parser, main

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "gear_machine.toml"

#: options every sub-command needs besides its file options (values never read: refused first)
REQUIRED = {"campbell": ["--speeds", "0:100:3"], "critical-speeds": ["--speeds", "0:100:3"],
            "stability": ["--speeds", "0:100:3"], "unbalance": ["--speeds", "0:100:3"],
            "simulate": ["--duration", "0.1"], "frf": ["--freqs", "1:10:3"], "fit": ["--params", "gain"],
            "modes": [], "study": [], "check": [], "static": [], "import-ross": [], "ucs-map": ["--stiffness", "1e5:1e6:3"],
            "level1": ["--speed", "100", "--station", "r", "--qa", "1e4"],
            "report": ["--standard", "api684", "--mcs", "3000"]}


#: every file option of every sub-command: (inputs, outputs); a new one goes here
FILE_OPTIONS = {
    "check": (["MODEL"], []),
    "static": (["MODEL"], ["--out", "--plot"]),
    "modes": (["MODEL", "--outline", "--measured", "--mapping"], ["--out", "--plot", "--plot-shaft"]),
    "campbell": (["MODEL"], ["--out", "--plot"]),
    "critical-speeds": (["MODEL"], ["--out", "--plot"]),
    "stability": (["MODEL"], ["--out", "--plot"]),
    "ucs-map": (["MODEL"], ["--out", "--plot"]),
    "level1": (["MODEL"], ["--out", "--plot", "--plot-csr"]),
    "simulate": (["MODEL"], ["--out", "--plot"]),
    "frf": (["MODEL", "--measured", "--mapping"], ["--out", "--plot"]),
    "unbalance": (["MODEL"], ["--out", "--plot", "--orbits", "--plot-orbits", "--checks"]),
    "fit": (["MODEL", "--measured", "--mapping"], ["--out", "--plot"]),
    "study": (["MODEL", "--spec"], ["--out", "--table", "--plot", "--plot-histogram", "--plot-map",
                                    "--plot-sensitivity"]),
    "import-ross": (["ROSS.toml"], ["--out"]),
    "report": (["MODEL"], ["--out", "--pdf"]),
}


def _subparsers():
    parser = build_parser()
    return parser._subparsers._group_actions[0].choices


def _name(action):
    return action.option_strings[0] if action.option_strings else action.metavar


def test_every_option_that_names_a_file_is_listed_here():
    """A file option missing from FILE_OPTIONS would escape the tests below."""
    looks_like_file = re.compile(r"FILE|MODEL|STUDY|RESULTS|FITTED|\.(toml|csv|nc|png|uff)", re.I)
    assert set(_subparsers()) == set(FILE_OPTIONS)
    for name, sub in _subparsers().items():
        listed = set(FILE_OPTIONS[name][0]) | set(FILE_OPTIONS[name][1])
        found = {_name(a) for a in sub._actions if looks_like_file.search(str(a.metavar or ""))
                 and not getattr(a, "alias_of", None)}      # an earlier spelling is its shown option
        assert found <= listed, (name, found - listed)


def test_every_file_option_is_declared_input_or_output_for_the_check_in_main():
    """``main`` compares the outputs with the inputs the sub-command declares."""
    for name, sub in _subparsers().items():
        declared = sub.get_default("file_options")
        assert [option for _, option in declared["input"]] == FILE_OPTIONS[name][0], name
        assert sorted(option for _, option in declared["output"]) == sorted(FILE_OPTIONS[name][1]), name


def _pairs():
    for command, (inputs, outputs) in FILE_OPTIONS.items():
        for input_option in inputs:
            for output_option in outputs:
                yield command, input_option, output_option


def _argv(command, files, output_option, output_path, folder):
    """The command line with every input option naming its file and ``output_option``
    naming ``output_path`` (other required outputs elsewhere)."""
    inputs, outputs = FILE_OPTIONS[command]
    argv = [command]
    for option in inputs:
        argv += [str(files[option])] if not option.startswith("-") else [option, str(files[option])]
    argv += REQUIRED[command]
    if output_option != "--out" and "--out" in outputs:
        argv += ["--out", str(folder / ("other.nc" if command == "study" else "other.toml" if command == "fit"
                                        else "other.csv"))]
    return argv + [output_option, str(output_path)]


@pytest.mark.parametrize("spelling", ["same", "symlink", "hardlink", "linked-folder"])
@pytest.mark.parametrize("command,input_option,output_option", list(_pairs()),
                         ids=[f"{c}:{i}->{o}" for c, i, o in _pairs()])
def test_no_output_replaces_an_input_file(command, input_option, output_option, spelling, tmp_path, capsys):
    data = tmp_path / "data"
    data.mkdir()
    files = {}
    for option in FILE_OPTIONS[command][0]:
        files[option] = data / f"input{len(files)}.toml"
        shutil.copyfile(EXAMPLE, files[option])
    victim = files[input_option]
    if spelling == "same":
        target = victim
    elif spelling == "symlink":
        target = tmp_path / "alias"
        target.symlink_to(victim)
    elif spelling == "hardlink":
        target = tmp_path / "hard"
        os.link(victim, target)
    else:
        (tmp_path / "linked").symlink_to(data)
        target = tmp_path / "linked" / victim.name
    before = {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in files.values()}
    listing = sorted(os.listdir(data))
    code = main(_argv(command, files, output_option, target, tmp_path))
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "refusing to write over the input file" in lines[0], err
    assert str(victim) in lines[0]
    assert {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in files.values()} == before
    assert sorted(os.listdir(data)) == listing


def test_two_outputs_naming_one_file_through_a_link_are_refused(tmp_path, capsys):
    (tmp_path / "alias.png").symlink_to(tmp_path / "c.png")
    code = main(["campbell", str(EXAMPLE), "--speeds", "0:100:3", "--out", str(tmp_path / "c.png"),
                 "--plot", str(tmp_path / "alias.png")])
    err = capsys.readouterr().err
    assert code == 2 and "--out and --plot name the same file" in err, err
    assert sorted(os.listdir(tmp_path)) == ["alias.png"]


@pytest.mark.parametrize("dangling", [False, True], ids=["existing-target", "dangling-link"])
def test_an_output_named_by_a_symbolic_link_is_written_through_the_link(dangling, tmp_path, capsys):
    target = tmp_path / "results" / "c.csv"
    target.parent.mkdir()
    if not dangling:
        target.write_text("old\n")
    link = tmp_path / "c.csv"
    link.symlink_to(target)
    code = main(["campbell", str(EXAMPLE), "--speeds", "0:3000:7", "--out", str(link), "--quiet"])
    assert code == 0, capsys.readouterr().err
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text().startswith("speed_rpm,mode,frequency_hz")
    assert sorted(os.listdir(tmp_path)) == ["c.csv", "results"]
    assert sorted(os.listdir(target.parent)) == ["c.csv"]


# ------------------------------------------------------------------------- signals during a write
#: the command line in a process of its own whose CSV writer writes 2 MB, says so and waits
SLOW_WRITER = r"""
import sys, time
import pandas
from rotordyn_modal.cli.main import main

def slow(self, handle=None, *args, **kwargs):
    handle.write("x" * 2_000_000)
    handle.flush()
    print("writing", flush=True)
    time.sleep(60)

pandas.DataFrame.to_csv = slow
sys.exit(main(sys.argv[1:]))
"""


def _start_slow_writer(out):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "ROTORDYN_MODAL_THREADS": "1"}
    process = subprocess.Popen([sys.executable, "-c", SLOW_WRITER, "campbell", str(EXAMPLE), "--speeds",
                                "0:3000:7", "--out", str(out), "--quiet"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env=env)
    line = process.stdout.readline()  # returns at "writing" or when the process ends
    assert line.strip() == "writing", process.communicate(timeout=30)
    return process


def _hidden(folder):
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith("."))


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_sigterm_or_sighup_during_a_write_removes_the_temporary_file(signum, tmp_path):
    process = _start_slow_writer(tmp_path / "c.csv")
    temporaries = _hidden(tmp_path)
    assert len(temporaries) == 1 and ".rdm-tmp." in temporaries[0]  # the write was under way
    assert (tmp_path / temporaries[0]).stat().st_size >= 2_000_000
    process.send_signal(signum)
    _, err = process.communicate(timeout=30)
    assert process.returncode == 128 + signum, err
    assert err.strip().splitlines() == [f"rotordyn-modal campbell: terminated by {signal.Signals(signum).name}"]
    assert os.listdir(tmp_path) == []


def test_what_kill_9_leaves_is_removed_by_the_next_write_of_the_file(tmp_path):
    process = _start_slow_writer(tmp_path / "c.csv")
    process.kill()
    process.communicate(timeout=30)
    left = _hidden(tmp_path)
    assert len(left) == 1  # nothing can clean up after kill -9 at once
    other = tmp_path / "other.csv"  # another file's write leaves it alone
    assert main(["campbell", str(EXAMPLE), "--speeds", "0:3000:7", "--out", str(other), "--quiet"]) == 0
    assert _hidden(tmp_path) == left
    assert main(["campbell", str(EXAMPLE), "--speeds", "0:3000:7", "--out", str(tmp_path / "c.csv"),
                 "--quiet"]) == 0
    assert sorted(os.listdir(tmp_path)) == ["c.csv", "other.csv"]


def test_a_running_writers_temporary_file_is_left_alone(tmp_path):
    process = _start_slow_writer(tmp_path / "c.csv")
    try:
        mine = _hidden(tmp_path)
        assert main(["campbell", str(EXAMPLE), "--speeds", "0:3000:7", "--out", str(tmp_path / "c.csv"),
                     "--quiet"]) == 0
        assert _hidden(tmp_path) == mine  # its process still runs: not stale
    finally:
        process.terminate()
        process.communicate(timeout=30)
    assert sorted(os.listdir(tmp_path)) == ["c.csv"]


def test_a_command_that_ends_itself_quickly_keeps_default_signal_handling():
    """The handlers are the command's only: after ``main`` returns, SIGTERM is as before."""
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGHUP)
    main(["check", str(EXAMPLE)])
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGHUP)) == before
    time.sleep(0)
