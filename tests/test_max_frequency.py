"""campbell(max_frequency=F), campbell --max-frequency: at every speed every mode of damped natural
frequency at most F, each the full model's root (issue 28, item 4). Truth from outside the code
under test: numpy's eigenvalues of the linear system's state matrices at each speed, and the full
sweep's critical speeds and mode numbers."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from threadpoolctl import threadpool_limits

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import OVERDAMPED_LIMIT
from rotordyn_modal.errors import InputError
from rotordyn_modal.linear_system import state_matrices

COMPRESSOR = "examples/compressor_rotor.toml"


@pytest.fixture(autouse=True)
def one_blas_thread():
    """The references' dense eigen-solves: BLAS threads only wait for a second core on a loaded machine."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _below_by_numpy(model, speeds, limit_hz):
    """Every oscillating root of frequency at most ``limit_hz`` at each speed, by frequency (a
    list of arrays): all eigenvalues of the state matrix, the upper ones of each pair, damping
    ratio at most OVERDAMPED_LIMIT."""
    out = []
    for A in state_matrices(model, speeds):
        roots = np.linalg.eigvals(A)
        zeta = -roots.real / np.abs(roots)
        keep = (roots.imag > 1e-9 * np.abs(roots)) & (zeta <= OVERDAMPED_LIMIT) & (roots.imag <= 2 * np.pi * limit_hz)
        roots = roots[keep]
        out.append(roots[np.lexsort((roots.real, roots.imag))])
    return out


def _assert_same_roots(result, reference):
    """Each speed's roots of ``result`` (NaN where none) are the reference's, none missing, to 1e-9."""
    for row, expected in zip(result.eigenvalues, reference):
        got = row[np.isfinite(row)]
        got = got[np.lexsort((got.real, got.imag))]
        assert len(got) == len(expected)
        assert np.all(np.abs(got - expected) <= 1e-9 * np.abs(expected))


def _quiet(function, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)        # speed 0's double roots are solved whole
        return function(*args, **kwargs)


@pytest.mark.parametrize("path, limit_hz, dense_below", [
    (COMPRESSOR, 450.0, None),                              # 53 coordinates: the reduced basis
    ("examples/flexible_pump_on_mounts.toml", 600.0, None),  # 68, a shaft in a casing on mounts
    ("examples/motor_pump_on_mounts.toml", 20.0, None),      # rigid rotors, 16: every root solved
    ("examples/motor_pump_on_mounts.toml", 20.0, 0),         # the same by the reduced basis
    ("examples/rubber_mounts.toml", 30.0, None),             # Maxwell branches: every root solved
])
def test_roots_below_the_limit_equal_the_full_models(monkeypatch, path, limit_hz, dense_below):
    from rotordyn_modal.analysis import _lowest

    if dense_below is not None:
        monkeypatch.setattr(_lowest, "DENSE_BELOW", dense_below)
    model = rdm.load_model(path)
    speeds = np.linspace(0.0, 1300.0, 6)
    result = _quiet(rdm.campbell, model, speeds, critical=False, max_frequency=limit_hz)
    reference = _below_by_numpy(model, speeds, limit_hz)
    assert min(len(r) for r in reference) >= 3
    _assert_same_roots(result, reference)
    # each column a tracked mode below the limit at some speed, NaN (not a mode) where above it
    assert np.isfinite(result.eigenvalues).any(axis=0).all()
    assert np.array_equal(result.oscillatory, np.isfinite(result.eigenvalues))
    assert np.array_equal(np.isnan(result.frequencies_hz), ~result.oscillatory)
    assert np.nanmax(result.frequencies_hz) <= limit_hz


def test_the_number_of_modes_below_the_limit_follows_the_speed():
    """Compressor rotor, 450 Hz: the bending pair at 443.6 Hz at rest splits, its forward mode
    rising above the limit: seven modes at rest, six at speed; the forward one's column is NaN there."""
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(0.0, 1200.0, 13)
    result = _quiet(rdm.campbell, model, speeds, critical=False, max_frequency=450.0)
    reference = _below_by_numpy(model, speeds, 450.0)
    counts = [len(r) for r in reference]
    assert counts[0] == 7 and counts[-1] == 6
    assert list(result.oscillatory.sum(axis=1)) == counts
    assert result.eigenvalues.shape[1] == 7
    leaving = ~result.oscillatory[-1]
    assert leaving.sum() == 1 and result.oscillatory[0, leaving].all()
    assert np.isnan(result.frequencies_hz[-1, leaving]).all()
    assert result.whirl[1, leaving][0] == "forward"              # the forward bending mode rises


def test_a_basis_too_small_for_the_limit_is_caught(monkeypatch):
    """A basis of two undamped modes lacks roots below 450 Hz: the checks (the completeness bound,
    no projected root left unrefined below the limit) find every speed unserved and solve it whole,
    and no root is missing."""
    from rotordyn_modal.analysis import _lowest

    monkeypatch.setattr(_lowest, "_needed_size", lambda *args: 2)
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(100.0, 1200.0, 3)
    with pytest.warns(UserWarning, match="3 of 3 speeds solved whole"):
        result = rdm.campbell(model, speeds, critical=False, max_frequency=450.0)
    _assert_same_roots(result, _below_by_numpy(model, speeds, 450.0))


def test_with_modes_the_lowest_of_those_below_the_limit():
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(200.0, 1200.0, 4)
    for count, limit_hz in ((4, 450.0), (9, 450.0)):
        result = rdm.campbell(model, speeds, critical=False, modes=count, max_frequency=limit_hz)
        reference = [roots[:count] for roots in _below_by_numpy(model, speeds, limit_hz)]
        _assert_same_roots(result, reference)


def test_table_rows_and_mode_numbers_are_the_full_sweeps():
    """Every row of the table below the limit is the full sweep's row of that root, with the
    number ``modes --speed`` gives it (tests/test_mode_numbering.py's numbering)."""
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(0.0, 1200.0, 7)
    full = rdm.campbell(model, speeds, critical=False).to_dataframe()
    full = full[full["frequency_hz"] <= 450.0]
    below = _quiet(rdm.campbell, model, speeds, critical=False, max_frequency=450.0).to_dataframe()
    assert len(below) == len(full)
    key = ["speed_rpm", "mode_at_speed"]
    merged = below.sort_values(key).reset_index(drop=True), full.sort_values(key).reset_index(drop=True)
    assert np.array_equal(merged[0]["mode_at_speed"], merged[1]["mode_at_speed"])
    assert np.allclose(merged[0]["frequency_hz"], merged[1]["frequency_hz"], rtol=1e-9, atol=0)
    assert (merged[0]["whirl"] == merged[1]["whirl"]).all()


def test_critical_speeds_below_the_limit_equal_the_full_ones():
    """The crossings at frequencies up to the limit, and only those: also a crossing just below the
    limit whose mode lies above it at the end of its bracket, and none just above it whose mode lies
    below it at the start."""
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(0.0, 1300.0, 27)
    sweep = rdm.campbell(model, speeds, orders=(1, 2))
    full = sweep.critical
    # the lowest crossing of 1X: its mode's frequency changes across its bracket by more than 2e-5 Hz
    j = int(np.argmin(np.where(full.order == 1.0, full.frequencies_hz, np.inf)))
    k = int(np.searchsorted(speeds, full.speeds[j])) - 1
    ends = sweep.frequencies_hz[k:k + 2, full.mode[j] - 1]
    crossing = full.frequencies_hz[j]
    assert ends.min() < crossing - 1e-5 and ends.max() > crossing + 1e-5
    for limit_hz in (190.0, crossing + 1e-5, crossing - 1e-5):
        below = _quiet(rdm.critical_speeds, model, speeds, orders=(1, 2), max_frequency=limit_hz)
        inside = full.frequencies_hz <= limit_hz
        assert len(below) == inside.sum()
        assert np.allclose(np.sort(below.speeds), np.sort(full.speeds[inside]), rtol=1e-7, atol=0)
        assert np.all(below.frequencies_hz <= limit_hz)
    assert (full.frequencies_hz <= 190.0).sum() >= 3 and (full.frequencies_hz > 190.0).any()


def test_no_speed_solved_whole_where_the_basis_serves():
    """Away from the double roots at rest, the basis chosen from the limit passes its checks at every
    speed: no full eigen-solve (the fallback would hide a basis, or a start above the limit, missing)."""
    for path, limit_hz in ((COMPRESSOR, 450.0), ("examples/flexible_pump_on_mounts.toml", 600.0)):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            rdm.campbell(rdm.load_model(path), np.linspace(100.0, 1300.0, 4), critical=False, max_frequency=limit_hz)


def test_a_start_that_could_stand_for_a_root_below_the_limit_fails_the_speed():
    """docs/theory.md, "The modes below a frequency": a speed passes only where its highest start
    refined, less the largest move from a start to its root, lies above the limit (or above the
    ``count``-th root found, where lower): else a projected root left unrefined, as near its root
    as the farthest one moved, could stand for a root below the limit."""
    from rotordyn_modal.analysis._lowest import _unmissed_below

    values = np.array([[-1 + 100j, -1 + 200j, -1 + 300j]] * 3)
    starts = values + np.array([[0.0], [0.0], [3.0j]])      # the last speed's starts moved 3 to their roots
    starts[:, -1] = -1 + 302j
    assert list(_unmissed_below(starts, values, 299.5, None)) == [True, True, False]
    assert list(_unmissed_below(starts, values, 303.0, None)) == [False, False, False]
    # the lowest two below 250: their limit is the second root found, 200
    assert list(_unmissed_below(starts, values, 250.0, 2)) == [True, True, True]
    assert list(_unmissed_below(starts - 100j, values, 250.0, 2)) == [False, False, False]
    values[:, -1] = -1 + 230j                                 # refined from starts there: above 200, below 250
    assert list(_unmissed_below(values, values, 250.0, 2)) == [True, True, True]
    assert list(_unmissed_below(values, values, 250.0, None)) == [False, False, False]


def test_no_mode_below_and_every_mode_below():
    """A limit below every mode: no column, no crossing; one above every mode: every mode of the
    full sweep, solved whole without a warning (a basis of every mode would gain nothing)."""
    model = rdm.load_model(COMPRESSOR)
    speeds = np.linspace(100.0, 1200.0, 3)
    none = rdm.campbell(model, speeds, max_frequency=1.0)
    assert none.eigenvalues.shape == (3, 0) and len(none.critical) == 0 and len(none.to_dataframe()) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        every = rdm.campbell(model, speeds, critical=False, max_frequency=1e12)
    _assert_same_roots(every, _below_by_numpy(model, speeds, 1e12))


@pytest.mark.parametrize("bad", [0, -5.0, float("nan"), float("inf"), "450", True, [100.0, 200.0]])
def test_max_frequency_must_be_one_frequency_above_zero(bad):
    model = rdm.load_model("examples/motor_pump_on_mounts.toml")
    with pytest.raises(InputError, match="max_frequency"):
        rdm.campbell(model, [0.0, 10.0], max_frequency=bad)


def test_command_line_max_frequency(tmp_path, capsys):
    from rotordyn_modal.cli.main import main

    out, critical = tmp_path / "c.csv", tmp_path / "k.csv"
    assert main(["campbell", "examples/motor_pump_on_mounts.toml", "--speeds", "0:3000:4", "--max-frequency", "20",
                 "--no-critical", "--out", str(out)]) == 0
    table = pd.read_csv(out)
    model = rdm.load_model("examples/motor_pump_on_mounts.toml")
    reference = _below_by_numpy(model, np.linspace(0.0, 3000.0, 4) * np.pi / 30, 20.0)
    assert len(table) == sum(len(r) for r in reference) and table["frequency_hz"].max() <= 20.0
    arguments = ["critical-speeds", "examples/motor_pump_on_mounts.toml", "--speeds", "0:3000:31", "--orders", "1,2"]
    assert main(arguments + ["--max-frequency", "20", "--out", str(critical)]) == 0
    assert main(arguments + ["--out", str(tmp_path / "all.csv")]) == 0
    below, every = pd.read_csv(critical), pd.read_csv(tmp_path / "all.csv")
    every = every[every["frequency_hz"] <= 20.0]
    assert len(every) >= 2 and len(below) == len(every)
    below, every = (t.sort_values("speed_rpm").reset_index(drop=True) for t in (below, every))
    assert np.allclose(below["speed_rpm"], every["speed_rpm"], rtol=1e-9, atol=0)
    assert (below["mode_at_speed"] == every["mode_at_speed"]).all()
    for command, bads in (("campbell", ("0", "-3", "nan", "inf", "fast")), ("critical-speeds", ("-0.5", "x"))):
        for bad in bads:
            capsys.readouterr()
            assert main([command, "examples/motor_pump_on_mounts.toml", "--speeds", "0:3000:4",
                         "--max-frequency", bad]) == 2
            err = capsys.readouterr().err.strip()
            assert len(err.splitlines()) == 1 and f"--max-frequency {bad!r}" in err
