"""Campbell sweeps and critical speeds of large machines: memory bounded per crossing, what
cannot fit refused before the work with its estimate, the refinement's progress shown.

A machine of 500 geared rotors on bearings (2,006 coordinates) crosses the orders of its
rotors and gear meshes about a million times: each crossing once kept every root at both ends
of its bracket (57 GiB asked for after 263 s of sweep) and its shape at the root."""

from __future__ import annotations

import os
import subprocess
import sys
import tracemalloc

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal import _limits
from rotordyn_modal.analysis import campbell as campbell_module
from rotordyn_modal.analysis import critical_speeds as critical_module
from rotordyn_modal.cli import main
from test_large_machine_cli import _watch_high_water, chained_gear_toml
from recorded_bars import RecordedBars

GIB = 2**30


def test_brackets_do_not_keep_the_roots_of_every_crossing():
    """30,000 crossings of a sweep of 400 roots: the brackets' arrays grow with the crossings,
    not with the crossings times the roots (two sets of 400 complex roots per crossing would
    be 384 MB)."""
    n_speeds, m = 11, 400
    speeds = np.linspace(0.0, 300.0, n_speeds)
    frequencies = np.linspace(10.0, 4000.0, m)                        # at rest [rad/s]
    rising = 1 + 1e-4 * speeds                                          # each root rises 3 % over the sweep
    values = (-0.01 * frequencies + 1j * frequencies)[None, None, :] * rising[None, :, None]
    sources = [critical_module.ExcitationSources(tuple(f"s{i}" for i in range(100)),
                                                 np.linspace(0.5, 14.0, 100))]
    tracemalloc.start()
    try:
        brackets = critical_module._crossing_brackets(speeds, values, sources, (1.0,))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    crossings = len(brackets.k)
    # each line slope * speed crosses once every root below it at the top speed (it starts below them all)
    expected = sum(int(np.count_nonzero(frequencies * rising[-1] < slope * speeds[-1]))
                   for slope in sources[0].multipliers)
    assert crossings == expected > 20_000
    whole_ends = crossings * 3 * m * 16                                 # the roots at both ends and travels
    print(f"{crossings} crossings: traced peak {peak / 2**20:.1f} MB (ends of all: {whole_ends / 2**20:.0f} MB)")
    assert peak < 1024 * crossings + 64 * 2**20


def _refused_one_line(capsys, argv):
    assert main(argv) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1, err
    return err[0]


def _gib_in(message):
    import re

    return [float(x) for x in re.findall(r"([0-9.]+) GiB", message)]


def test_a_sweep_that_cannot_fit_is_refused_before_its_work_with_the_estimate(tmp_path, capsys, monkeypatch):
    """406 coordinates at 2,001 speeds: the mode shapes kept alone are 2,001 x 406 x 406 complex
    numbers, 4.9 GiB (their mass-weighted copy is made a part at a time since lowest28g); with 4
    GiB at hand it is refused at once."""
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(100, 100))
    measured = _limits.available_memory
    monkeypatch.setattr(_limits, "available_memory", lambda: 4.0 * GIB)
    monkeypatch.setattr(campbell_module, "solve_sweeps", lambda *a, **k: pytest.fail("the sweep started"))
    message = _refused_one_line(capsys, ["campbell", str(path), "--speeds", "0:3000:2001", "--quiet"])
    needed, available = _gib_in(message)
    assert needed >= 2001 * 406 * 406 * 16 / GIB and available == 4.0
    assert "2,001 speeds" in message and "fewer speeds (about" in message and "--no-critical" in message
    fit = int(message.split("(about ")[1].split(" fit")[0].replace(",", ""))
    assert 2 * fit * 406 * 406 * 16 < 4.0 * GIB                        # what it proposes does fit
    assert fit > 100
    # the environment variable sets the memory to count on
    monkeypatch.setattr(_limits, "available_memory", measured)
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "3")
    message = _refused_one_line(capsys, ["critical-speeds", str(path), "--speeds", "0:3000:2001", "--quiet"])
    assert _gib_in(message)[1] == 3.0 and "ROTORDYN_MODAL_MEMORY_GB" in message
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "lots")
    assert "ROTORDYN_MODAL_MEMORY_GB='lots': expected a number of GiB" in _refused_one_line(
        capsys, ["campbell", str(path), "--speeds", "0:3000:2001", "--quiet"])


def test_the_available_memory_counts_the_address_space_limit():
    """In a child limited to 3 GiB of address space, at most that much less what it maps."""
    code = ("import resource; resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, resource.RLIM_INFINITY)); "
            "from rotordyn_modal import _limits; print(_limits.available_memory(), _limits._virtual_size())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "ROTORDYN_MODAL_MEMORY_GB": ""}).stdout.split()
    available, mapped = float(out[0]), float(out[1])
    assert 0 < mapped and available <= 3 * GIB - mapped + 2**20


def test_crossings_that_cannot_fit_are_refused_before_their_refinement(examples_dir, capsys, monkeypatch):
    """The sweep fits exactly; its crossings (a few kB each) do not: refused after the sweep,
    before any crossing is refined, with their number."""
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speeds = np.linspace(0.0, rdm.rpm(12000.0), 121)
    expected = len(rdm.campbell(model, speeds, orders=(1, 2)).critical)
    n, states = model.dofs.n, len(model.state_space(0.0).A)
    monkeypatch.setattr(campbell_module, "_CHECKED_BYTES", 0)
    sweep = campbell_module.memory_estimate(n, states, len(speeds), 1, True)
    monkeypatch.setattr(_limits, "available_memory", lambda: sweep)
    monkeypatch.setattr(critical_module, "_refined", lambda *a, **k: pytest.fail("the refinement started"))
    with pytest.raises(rdm.InputError) as refused:
        rdm.campbell(model, speeds, orders=(1, 2))
    message = str(refused.value)
    assert f"refining the {expected:,} critical speeds found over 121 speeds" in message
    assert "--orders" in message and "--no-critical" in message and _gib_in(message)[0] > sweep / GIB
    # without the critical speeds the same sweep is done
    result = rdm.campbell(model, speeds, orders=(1, 2), critical=False)
    assert len(result.critical) == 0 and result.eigenvalues.shape[0] == 121


def test_no_critical_gives_the_same_sweep(examples_dir, tmp_path):
    model = str(examples_dir / "gear_machine.toml")
    with_critical, without = tmp_path / "a.csv", tmp_path / "b.csv"
    assert main(["campbell", model, "--speeds", "0:12000:61", "--out", str(with_critical), "--quiet"]) == 0
    assert main(["campbell", model, "--speeds", "0:12000:61", "--out", str(without), "--quiet",
                 "--no-critical", "--plot", str(tmp_path / "c.png")]) == 0
    assert with_critical.read_text() == without.read_text()


def test_the_refinement_shows_its_progress_over_every_crossing(tmp_path, monkeypatch):
    """A bar over the sweep's crossings when asked, advanced as parts end (brackets crowded
    with crossings, swept again, by their share) up to the number of crossings; no bar when not
    asked."""
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(40, 4))
    model = rdm.load_model(path)
    speeds = rdm.rpm(np.linspace(0, 6000, 31))
    bars = RecordedBars(monkeypatch)
    crowded = []
    real_crowded = critical_module._crowded
    monkeypatch.setattr(critical_module, "_crowded", lambda *a: crowded.append(real_crowded(*a)) or crowded[-1])
    monkeypatch.setattr(critical_module, "_CROWDED", 4)          # some brackets swept again at once
    monkeypatch.setattr(_batches_module(), "CHUNK_BYTES", 64 * 22**2 * 200)   # parts of 200 crossings
    monkeypatch.setattr(campbell_module, "_PROGRESS_BYTES", 0)   # the sweep shown in parts too
    quiet = rdm.campbell(model, speeds, progress=False)
    assert bars.made == []
    brackets = len(crowded[0])
    assert crowded[0].sum() > 0
    crowded.clear()
    shown = rdm.campbell(model, speeds, progress=True)
    sweep = [bar for desc, bar in bars.made if desc == "eigen-solve"]
    assert len(sweep) == 1 and sweep[0].total == 16                 # 31 speeds, two at a time
    for name in ("eigenvalues", "shapes", "whirl_ratios"):          # the bars change no number
        np.testing.assert_array_equal(getattr(shown, name), getattr(quiet, name))
    np.testing.assert_array_equal(shown.critical.speeds, quiet.critical.speeds)
    critical = [bar for desc, bar in bars.made if desc == "critical speeds"]
    assert len(critical) == 1
    bar = critical[0]
    assert bar.total == brackets > 1000
    assert bar.counted == brackets and len(bar.steps) > 5 and min(bar.steps) > 0


def _batches_module():
    from rotordyn_modal.analysis import _batches

    return _batches


@pytest.mark.skipif(not hasattr(os, "wait4"), reason="needs wait4 (POSIX)")
def test_a_machine_of_hundreds_of_coordinates_under_an_address_space_limit(tmp_path):
    """246 coordinates under a 2.5 GiB address-space limit: a sweep of 5 speeds is done within
    it; 2,000 speeds (5.8 GiB of mode shapes) are refused at once with the estimate, where they
    once died of MemoryError (exit 1) after the eigen-solutions. The peak is the child's own
    (``VmHWM`` read while it runs, as ``test_large_machine_cli.run_measured``): ``wait4``'s
    ru_maxrss starts at the pytest worker's peak, which exec does not reset."""
    import resource
    import threading

    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(60, 60))
    limit = int(2.5 * GIB)

    def run(*argv):
        def limited():
            resource.setrlimit(resource.RLIMIT_AS, (limit, resource.RLIM_INFINITY))

        env = {**os.environ, "ROTORDYN_MODAL_MEMORY_GB": ""}
        process = subprocess.Popen([sys.executable, "-c", "import sys; from rotordyn_modal.cli import main; "
                                    "sys.exit(main())", *argv], stderr=subprocess.PIPE, text=True,
                                   preexec_fn=limited, env=env)
        seen = [0]
        watch = threading.Thread(target=_watch_high_water, args=(process.pid, seen), daemon=True)
        watch.start()
        err = process.stderr.read()
        watch.join()
        _, status, usage = os.wait4(process.pid, 0)
        # Linux's ru_maxrss starts at the parent's peak (not reset by exec: the pytest worker's):
        # the child's own high-water mark (VmHWM), read while it runs, where the system has it
        peak = seen[0] if seen[0] else usage.ru_maxrss * (1 if sys.platform == "darwin" else 1024)
        return os.waitstatus_to_exitcode(status), err, peak

    code, err, peak = run("campbell", str(path), "--speeds", "0:3000:5", "--no-critical", "--quiet",
                          "--out", str(tmp_path / "c.csv"))
    assert code == 0, err
    assert peak < limit
    code, err, _ = run("campbell", str(path), "--speeds", "0:3000:2000", "--quiet", "--out", str(tmp_path / "d.csv"))
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "GiB of memory" in lines[0] and "fewer speeds" in lines[0], err
    assert _gib_in(lines[0])[0] >= 2000 * 246 * 246 * 16 / GIB        # the shapes kept
    assert not (tmp_path / "d.csv").exists()


def test_double_roots_take_their_whirl_forms_a_part_at_a_time(monkeypatch):
    """200 double roots of 200 coordinates with forms per variant (a sweep's path): each pair
    once took its own copy of the three n x n forms at once (3 x 200 x 200^2 x 8 bytes, 183 MB,
    and as much again for those that span a plane); in parts the peak follows the part, and
    the parts change no number."""
    from rotordyn_modal.analysis import _batches, _eigensolve, _vectors, _whirl

    rng = np.random.default_rng(5)
    n, pairs = 200, 200
    k = np.arange(1, pairs + 1)
    lam = np.repeat(-0.01 * k + 1j * k, 2)[None]                          # (1, 2 pairs)
    shapes = _vectors.unit_rows(rng.standard_normal((1, 2 * pairs, n)) + 1j * rng.standard_normal((1, 2 * pairs, n)))
    a = rng.standard_normal((n, n))
    skew = rng.standard_normal((n, n))
    forms = _whirl.WhirlForms((skew - skew.T)[None], np.eye(n)[None], (a @ a.T + n * np.eye(n))[None])
    variants = np.zeros(1, dtype=int)
    tracemalloc.start()
    try:
        parts = _eigensolve.resolve_repeated(lam, shapes, forms, variants)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    at_once = 3 * pairs * n * n * 8
    print(f"peak {peak / 2**20:.0f} MB, the forms of all pairs at once {at_once / 2**20:.0f} MB")
    assert peak < at_once / 2
    assert not np.array_equal(parts, shapes)                                # pairs were combined
    monkeypatch.setattr(_batches, "_PART_BYTES", 2**40)
    np.testing.assert_array_equal(parts, _eigensolve.resolve_repeated(lam, shapes, forms, variants))
