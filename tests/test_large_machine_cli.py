"""A machine of 200 rotors chained by gears through the command line, and files too large
to read.

The model file is generated here: a stator on four mounts carrying 200 rotors, each
driving the next through a gear pair (199 meshes), some rotors on bearings of their own.
``campbell`` sweeps 1,001 speeds with ``--verbose`` and reports its peak memory; the
operating system's own account of the process (``wait4``) must agree and stay within
``MEMORY_BUDGET``. CI runs the machine with two rotors on bearings (14 coordinates);
``ROTORDYN_MODAL_LARGE_MODELS=full`` adds the one with twenty (86 coordinates, tens of
thousands of crossings of 399 excitation sources to refine: about 1.5 minutes and 1 GB on two
shared cores; it took 8 minutes and 15 GB before the crossings were refined in parts).

Files over the documented size limits (model and study files 10 MB, measured data 512 MB,
each settable by an environment variable) are refused before they are parsed: a file
made of bytes that are not TOML or UFF at all gets the size message, not a parse error.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

ROOT = Path(__file__).resolve().parent.parent
FULL = os.environ.get("ROTORDYN_MODAL_LARGE_MODELS", "") == "full"
#: peak resident memory allowed for the 1,001-speed sweep of the 200-rotor machine [bytes]:
#: the eigen-solver's parts hold up to ``_batches.CHUNK_BYTES`` (512 MB) of work, plus the
#: sweep's arrays and the interpreter (the 86-coordinate machine peaks near 1 GB)
MEMORY_BUDGET = 2 * 2**30


def relative_speeds(n_rotors):
    """|spin speed| of each rotor relative to the first: bounded, all different."""
    return [math.exp(0.7 * math.sin(0.37 * k)) for k in range(n_rotors)]


def chained_gear_toml(n_rotors=200, n_on_bearings=0):
    """TOML text of a stator on four mounts with ``n_rotors`` rotors chained by gears
    (rotor k drives rotor k+1), ``n_on_bearings`` of them spread along the chain on two
    bearings each."""
    speeds = relative_speeds(n_rotors)
    lines = [f'name = "{n_rotors} rotors chained by gears"', "spin_axis = [1.0, 0.0, 0.0]",
             'reference_rotor = "r000"', "", "[stator]", "mass = 2000.0", "center_of_mass = [0.0, 0.0, 0.3]",
             "inertia = [400.0, 500.0, 450.0]", ""]
    position = {}
    for k in range(n_rotors):
        position[k] = (-2.0 + 4.0 * k / max(n_rotors - 1, 1), 0.2 * ((k % 2) - 0.5), 0.4)
        lines += ["[[rotors]]", f'name = "r{k:03d}"', f"mass = {2.0 + (k % 7) * 0.5}",
                  "center_of_mass = [{:.6f}, {:.3f}, {:.1f}]".format(*position[k]),
                  f"polar_inertia = {0.02 + 0.002 * (k % 5)}", f"diametral_inertia = {0.015 + 0.002 * (k % 5)}"]
        lines += ["speed_ratio = 1.0", ""] if k == 0 else [""]
    for k in range(1, n_rotors):  # ratio = |w_driver| / |w_driven|
        lines += ["[[transmissions]]", 'type = "gear"', f'driver = "r{k - 1:03d}"', f'driven = "r{k:03d}"',
                  f"ratio = {speeds[k - 1] / speeds[k]!r}", f"driver_teeth = {17 + k % 13}", ""]
    for j in sorted({(i * n_rotors) // max(n_on_bearings, 1) for i in range(n_on_bearings)}):
        x, y, z = position[j]
        for side, dx in (("A", -0.05), ("B", 0.05)):
            lines += ["[[bearings]]", f'name = "b{j:03d}{side}"', f'rotor = "r{j:03d}"',
                      f"position = [{x + dx:.6f}, {y:.3f}, {z:.1f}]", f"stiffness = {2e6 + 1e4 * j}",
                      "damping = 300.0", ""]
    for name, (x, y) in {"FL": (1.5, 0.5), "FR": (1.5, -0.5), "RL": (-1.5, 0.5), "RR": (-1.5, -0.5)}.items():
        lines += ["[[suspensions]]", f'name = "m-{name}"', f"position = [{x}, {y}, 0.0]",
                  "stiffness = [2.0e6, 2.0e6, 4.0e6]", "damping = [800.0, 800.0, 1600.0]", ""]
    return "\n".join(lines)


def run_measured(argv):
    """Run the command line in a child process; (exit code, stderr, its peak RSS [bytes] as
    the operating system counted it, wall time [s])."""
    import resource  # noqa: F401 - wait4 needs POSIX

    import threading

    start = time.monotonic()
    process = subprocess.Popen([sys.executable, "-c", "import sys; from rotordyn_modal.cli import main; "
                                "sys.exit(main())", *argv], stderr=subprocess.PIPE, text=True)
    seen = [0]
    watch = threading.Thread(target=_watch_high_water, args=(process.pid, seen), daemon=True)
    watch.start()
    err = process.stderr.read()
    watch.join()
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    # Linux's ru_maxrss starts at the parent's peak (not reset by exec: the pytest worker's, up
    # to 2.4 GB): the child's own high-water mark, read while it runs, where the system has it
    peak = seen[0] if seen[0] else usage.ru_maxrss * (1 if sys.platform == "darwin" else 1024)
    return process.returncode, err, peak, time.monotonic() - start


def _watch_high_water(pid, seen):
    """Keep in ``seen[0]`` the largest ``VmHWM`` [bytes] of process ``pid``'s /proc status, read
    every millisecond until it ends (0 where there is no /proc)."""
    path = f"/proc/{pid}/status"
    while True:
        try:
            with open(path, encoding="ascii") as status:
                lines = [line for line in status if line.startswith("VmHWM:")]
        except OSError:
            return
        if not lines:                      # ended (a zombie has no memory lines)
            return
        seen[0] = max(seen[0], int(lines[0].split()[1]) * 1024)
        time.sleep(0.001)


def test_the_generated_chain_fixes_every_rotor_speed_by_its_gears(tmp_path):
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(200, 2))
    model = rdm.load_model(path)
    assert len(model.rotors) == 200 and len(model.transmissions) == 199
    speeds = relative_speeds(200)
    expected = [(-1) ** k * speeds[k] / speeds[0] for k in range(200)]  # an external gear reverses
    np.testing.assert_allclose([model.speed_ratios[f"r{k:03d}"] for k in range(200)], expected, rtol=1e-12)
    assert model.dofs.n == 6 + 2 * 4


@pytest.mark.skipif(not hasattr(os, "wait4"), reason="needs wait4 (POSIX)")
@pytest.mark.parametrize("on_bearings", [2] + ([20] if FULL else []))
def test_200_rotors_over_1001_speeds_within_the_memory_the_command_reports(tmp_path, on_bearings):
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(200, on_bearings))
    out = tmp_path / "c.csv"
    code, err, peak, seconds = run_measured(["campbell", str(path), "--speeds", "0:6000:1001", "--out", str(out),
                                            "--quiet", "--verbose"])
    assert code == 0, err
    reported = float(re.search(r"peak memory ([0-9.]+) MB", err).group(1)) * 2**20
    print(f"{on_bearings} rotors on bearings: {seconds:.1f} s, peak memory reported {reported / 2**20:.0f} MB, "
          f"counted by the system {peak / 2**20:.0f} MB")
    assert 0.9 * peak <= reported <= peak + 2**20  # the same count, taken just before the end
    assert peak < MEMORY_BUDGET
    table = np.loadtxt(out, delimiter=",", skiprows=1, usecols=(0, 1))
    n_modes = 6 + 4 * on_bearings
    assert len(table) == 1001 * n_modes
    np.testing.assert_array_equal(np.unique(table[:, 0]), np.linspace(0, 6000, 1001).round(10))


# ------------------------------------------------------------------------- size limits
def _big_file(path, megabytes):
    """A sparse file of zero bytes: neither TOML nor UFF, and nothing to parse cheaply."""
    with open(path, "wb") as handle:
        handle.truncate(int(megabytes * 2**20))
    return path


def _refused(capsys, argv, path, limit_mb, variable):
    assert main(argv) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1, err
    assert str(path) in err[0] and f"limit of {limit_mb:g} MB" in err[0] and variable in err[0], err[0]


def test_a_50_mb_model_file_is_refused_before_it_is_parsed(tmp_path, capsys):
    big = _big_file(tmp_path / "big.toml", 50)
    _refused(capsys, ["check", str(big)], big, 10, "ROTORDYN_MODAL_MAX_MODEL_MB")
    _refused(capsys, ["campbell", str(big), "--speeds", "0:100:2"], big, 10, "ROTORDYN_MODAL_MAX_MODEL_MB")


def test_the_model_limit_is_the_documented_one_and_can_be_raised(tmp_path, capsys, monkeypatch):
    """A real model padded with comments just over and just under the limit."""
    model = chained_gear_toml(200, 0)
    limit = 10 * 2**20
    over, under = tmp_path / "over.toml", tmp_path / "under.toml"
    over.write_text(model + "\n#" + "x" * (limit - len(model)) + "\n")
    under.write_text(model + "\n#" + "x" * (limit - len(model) - 10) + "\n")
    assert over.stat().st_size > limit >= under.stat().st_size
    _refused(capsys, ["check", str(over)], over, 10, "ROTORDYN_MODAL_MAX_MODEL_MB")
    assert main(["check", str(under)]) == 0
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", "11")
    assert main(["check", str(over)]) == 0
    capsys.readouterr()
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", "0.04")  # 42 kB: the 49 kB model is over
    small = tmp_path / "small.toml"
    small.write_text(model)
    _refused(capsys, ["check", str(small)], small, 0.04, "ROTORDYN_MODAL_MAX_MODEL_MB")
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", "-1")
    assert main(["check", str(small)]) == 2
    assert "ROTORDYN_MODAL_MAX_MODEL_MB='-1': expected a number of megabytes > 0" in capsys.readouterr().err


@pytest.mark.parametrize("text", ["1e6", "1e13"])
def test_a_file_limit_of_terabytes_reads_a_small_file_as_any_limit(monkeypatch, text):
    """A limit far above the file (1e6 MB, more than the machine's memory; 1e13 MB, more bytes
    than a read may ask for) is only a limit: the model and a measured file are read (one read
    of the limit itself once failed with MemoryError or OverflowError, exit 1)."""
    from rotordyn_modal.io.limits import read_limited

    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", text)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MEASURED_MB", text)
    model = ROOT / "examples" / "fan_on_bearings.toml"
    assert main(["check", str(model)]) == 0
    assert read_limited(model, "measured", "measured-data file") == model.read_bytes()


@pytest.mark.parametrize("text", ["inf", "1e400", "nan"])
def test_a_file_limit_that_is_no_finite_number_is_refused_in_one_line(capsys, monkeypatch, text):
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MODEL_MB", text)
    assert main(["check", str(ROOT / "examples" / "fan_on_bearings.toml")]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1 and f"ROTORDYN_MODAL_MAX_MODEL_MB={text!r}: expected a number of megabytes > 0" in err[0], err


def test_a_study_file_over_the_limit_is_refused(tmp_path, capsys):
    big = _big_file(tmp_path / "big.study.toml", 10.5)
    _refused(capsys, ["study", str(ROOT / "examples" / "gear_machine.toml"), "--spec", str(big),
                      "--out", str(tmp_path / "r.nc")], big, 10, "ROTORDYN_MODAL_MAX_MODEL_MB")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.study.toml"]


@pytest.mark.parametrize("ending", [".uff", ".csv"])
def test_measured_data_over_the_limit_is_refused_before_it_is_read(tmp_path, capsys, monkeypatch, ending):
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MEASURED_MB", "1")
    big = _big_file(tmp_path / f"big{ending}", 1.5)
    _refused(capsys, ["frf", str(ROOT / "examples" / "gear_machine.toml"), "--speed", "3000", "--freqs", "2:40:5",
                      "--measured", str(big), "--quiet"], big, 1, "ROTORDYN_MODAL_MAX_MEASURED_MB")


def test_measured_data_under_the_limit_is_read(tmp_path, monkeypatch):
    from rotordyn_modal.analysis.frf import FRFResult
    from rotordyn_modal.io.measured import default_mapping, read_measured
    from rotordyn_modal.io.uff import write_uff58

    model = rdm.load_model(ROOT / "examples" / "gear_machine.toml")
    res = rdm.frf(model, rdm.rpm(3000), np.linspace(2, 40, 30))
    path = tmp_path / "m.uff"
    write_uff58([FRFResult(**{**res.__dict__, "coherence": np.full(res.H.shape, 0.99)})], path,
                default_mapping(model))
    size_mb = path.stat().st_size / 2**20
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MEASURED_MB", f"{1.01 * size_mb}")
    assert len(read_measured(path, model)) == 1
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_MEASURED_MB", f"{0.99 * size_mb}")
    from rotordyn_modal.errors import InputError

    with pytest.raises(InputError, match="larger than the limit"):
        read_measured(path, model)


# ------------------------------------------------------------------------- bounded memory
def _campbell_traced(model, speeds):
    import tracemalloc

    tracemalloc.start()
    try:
        result = rdm.campbell(model, speeds)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return result, peak


def test_crossings_are_refined_in_parts_of_bounded_memory_with_unchanged_results(tmp_path, monkeypatch):
    """Over a thousand crossings (79 sources x 22 modes): the work memory follows the part
    size, not the number of crossings, and the split changes no number."""
    from rotordyn_modal.analysis import _batches

    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(40, 4))
    model = rdm.load_model(path)
    speeds = rdm.rpm(np.linspace(0, 6000, 61))
    whole, _ = _campbell_traced(model, speeds)
    part = 2**20
    monkeypatch.setattr(_batches, "_PART_BYTES", part)
    monkeypatch.setattr(_batches, "CHUNK_BYTES", part)
    split, peak = _campbell_traced(model, speeds)
    n, m = model.dofs.n, 2 * model.dofs.n
    crossings = len(split.critical.speeds)
    sweep = len(speeds) * m // 2 * n * 16 * 3     # eigenvalues' shapes, weighted shapes, one copy
    print(f"{crossings} crossings, traced peak {peak / 2**20:.1f} MB, sweep arrays {sweep / 2**20:.1f} MB")
    assert crossings > 1000
    assert peak < 2 * sweep + 12 * part
    np.testing.assert_array_equal(split.critical.speeds, whole.critical.speeds)
    np.testing.assert_array_equal(split.critical.whirl_ratios, whole.critical.whirl_ratios)
    np.testing.assert_array_equal(split.whirl_ratios, whole.whirl_ratios)
