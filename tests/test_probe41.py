"""Inputs a new user tries that no earlier test named (session 41, issue 27's hidden checks).

File names no file can have: a name longer than the file system takes (one name over 255 bytes,
a path over 4096) ended every output and ``--measured`` with ``failed: OSError: [Errno 36]``
(exit 1); a file's name followed by '/' (``m.toml/``, tab completion of a folder's habit) was
read as the file itself by the model, study and measured readers (``pathlib`` drops the '/'),
while the mapping and outline readers said "Not a directory". Each is now one line, exit 2,
for every file option of every sub-command, before any work.
"""

from __future__ import annotations

import errno
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from quiet_cli import run_quietly
from test_output_paths import FILE_OPTIONS, REQUIRED

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "gear_machine.toml"

#: an output's ending each option accepts (the ending is checked before the name)
_ENDING = {"--plot": ".png", "--plot-shaft": ".png", "--plot-csr": ".png", "--plot-orbits": ".png",
           "--plot-histogram": ".png", "--plot-map": ".png", "--plot-sensitivity": ".png", "--pdf": ".pdf"}
_OUT_ENDING = {"study": ".nc", "fit": ".toml", "import-ross": ".toml", "report": ".html"}


def _ending(command, option):
    if option == "--out":
        return _OUT_ENDING.get(command, ".csv")
    return _ENDING.get(option, ".csv")


def _argv(command, inputs, folder, output_option=None, output_path=None):
    """``command`` with each input option naming ``inputs[option]``, its required options, and
    ``output_option`` naming ``output_path`` (plus the --out a command requires)."""
    argv = [command]
    for option in FILE_OPTIONS[command][0]:
        argv += [str(inputs[option])] if not option.startswith("-") else [option, str(inputs[option])]
    argv += REQUIRED[command]
    outputs = FILE_OPTIONS[command][1]
    if output_option != "--out" and "--out" in outputs and command in ("study", "fit", "import-ross", "report"):
        argv += ["--out", str(folder / f"other{_OUT_ENDING[command]}")]
    if output_option:
        argv += [output_option, str(output_path)]
    return argv


def _files(folder):
    inputs = {}
    for option in {o for inputs_, _ in FILE_OPTIONS.values() for o in inputs_}:
        inputs[option] = folder / f"input{len(inputs)}.toml"
        shutil.copyfile(EXAMPLE, inputs[option])
    return inputs


def _too_long(name) -> bool:
    """Whether the file system refuses ``name`` as too long (asked of the OS, not of the code)."""
    try:
        os.stat(name)
    except OSError as error:
        return error.errno == errno.ENAMETOOLONG
    return False


def _one_line(code, err):
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, (code, err)
    assert "failed" not in lines[0] and "Traceback" not in err
    return lines[0]


_OUTPUTS = [(c, o) for c, (_, outs) in FILE_OPTIONS.items() for o in outs]
_INPUTS = [(c, i) for c, (ins, _) in FILE_OPTIONS.items() for i in ins]


def test_an_output_name_too_long_for_the_file_system_is_one_line_exit_2_for_every_output(tmp_path):
    inputs = _files(tmp_path)
    listing = sorted(os.listdir(tmp_path))
    for command, option in _OUTPUTS:
        for name in ("x" * 300 + _ending(command, option),                 # one name over 255 bytes
                     "/".join(["d" * 200] * 25) + "/x" + _ending(command, option)):   # a path over 4096
            path = tmp_path / name
            assert _too_long(path)
            line = _one_line(*run_quietly(_argv(command, inputs, tmp_path, option, path)))
            assert option in line and "too long" in line, (command, option, line)
            assert len(line) < 400, line              # the name shown by its ends, not all 5,000 characters
    assert sorted(os.listdir(tmp_path)) == listing   # nothing written


def test_an_input_name_too_long_or_ending_in_a_slash_is_one_line_exit_2_for_every_input(tmp_path):
    inputs = _files(tmp_path)
    for command, option in _INPUTS:
        long_name = tmp_path / ("y" * 300 + ".csv")
        assert _too_long(long_name)
        slashed = f"{inputs[option]}/"
        assert Path(slashed).is_file() and not os.path.isdir(slashed)   # pathlib drops the '/'; the OS refuses it
        with pytest.raises(NotADirectoryError):
            open(slashed).close()
        for bad, said in ((str(long_name), "too long"), (slashed, "ends in '/'")):
            given = dict(inputs, **{option: bad})
            line = _one_line(*run_quietly(_argv(command, given, tmp_path)))
            assert said in line, (command, option, line)


def test_the_readers_refuse_a_file_name_followed_by_a_slash(tmp_path):
    """The Python API alike: ``load_model('m.toml/')`` read m.toml."""
    import rotordyn_modal as rdm
    from rotordyn_modal.errors import InputError

    model = tmp_path / "m.toml"
    shutil.copyfile(EXAMPLE, model)
    for name in (f"{model}/", f"{model}/."):
        with pytest.raises(InputError, match="ends in '/'"):
            rdm.load_model(name)
    with pytest.raises(InputError, match="too long"):
        rdm.load_model(tmp_path / ("m" * 300 + ".toml"))


# --- measured FRFs as spreadsheets in other locales write them ---------------------------------

_FREQS = np.array([5.0, 10.0, 15.0, 20.0])
_H = np.array([7.5225091020702e-07 - 1.32483755216953e-07j, 1.00479714239142e-06 - 3.30749838023595e-07j,
               -2.5e-08 + 3.25e-09j, -6.74809e-08 - 2.74137e-09j])


def _decimal_comma(value: float) -> str:
    """``value`` as a spreadsheet in a German locale writes it: '7,5225091020702E-07'."""
    return f"{value:.14E}".replace(".", ",")


def _read(path):
    from rotordyn_modal.io.measured import read_measured
    import rotordyn_modal as rdm

    (frf,) = read_measured(path, rdm.load_model(EXAMPLE_RUBBER))
    assert frf.outputs == ("acc-top-z",) and frf.inputs == ("hammer-z",)
    return frf.frequencies_hz, frf.H[0, 0]


EXAMPLE_RUBBER = ROOT / "examples" / "rubber_mounts.toml"


@pytest.mark.parametrize("separator", [";", "\t"])
def test_decimal_commas_in_exponent_notation_are_read(tmp_path, separator):
    """Every value of a receptance is small, so such an export writes each in exponent notation;
    the decimal comma was recognised only in cells without an exponent ('1,5'), and the file was
    refused: "column real line 2 = '7,5225091020702E-07': expected a number"."""
    lines = [separator.join(["frequency_hz", "output", "input", "real", "imag"])]
    for f, h in zip(_FREQS, _H):
        lines.append(separator.join([f"{f:g}", "acc-top-z", "hammer-z", _decimal_comma(h.real), _decimal_comma(h.imag)]))
    path = tmp_path / "frf.csv"
    path.write_text("\r\n".join(lines) + "\r\n", encoding="utf-8-sig")    # Windows line ends and a BOM too
    freqs, h = _read(path)
    np.testing.assert_array_equal(freqs, _FREQS)
    np.testing.assert_allclose(h, _H, rtol=1e-14)


@pytest.mark.parametrize("header,factor", [("Frequency [rad/s]", 2 * np.pi), ("Frequency [cpm]", 60.0),
                                           ("Frequency [1/min]", 60.0)])
def test_a_frequency_column_in_rad_s_or_cycles_per_minute_is_converted(tmp_path, header, factor):
    """A frequency axis in rad/s (MATLAB's ``w``) or in cycles per minute (vibration analysers) was
    refused: "unit 'rad/s' not understood: expected one of hz, khz", though the unit says what it is."""
    rows = [f"{float(f * factor)!r},acc-top-z,hammer-z,{float(h.real)!r},{float(h.imag)!r}" for f, h in zip(_FREQS, _H)]
    path = tmp_path / "frf.csv"
    path.write_text("\n".join([f"{header},output,input,real,imag", *rows]) + "\n")
    freqs, h = _read(path)
    np.testing.assert_allclose(freqs, _FREQS, rtol=1e-15)
    np.testing.assert_array_equal(h, _H)


# --- stability thresholds found from a coarse speed grid ---------------------------------------

def _state_roots(model, speed):
    """Every root of the state matrix at ``speed`` [rad/s], scipy's eigenvalues (built here)."""
    import scipy.linalg

    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    return scipy.linalg.eigvals(A)


@pytest.mark.parametrize("grid_rpm", [[0.0, 5e4, 1e5], [0.0, 1e5, 2e5, 1e6], [0.0, 5e4]])
def test_a_threshold_from_a_coarse_grid_is_where_the_largest_real_part_crosses_zero(grid_rpm):
    """``stability unstable_cross_coupled.toml --speeds 0:1e5:3`` said "mode 5 loses stability at
    39990 rpm ... unstable from 39990 rpm" (``0:1e6:11``: 78069 rpm): the mode followed from one
    grid speed to the next falls from 11 to 2 Hz, the interpolated guess moved to another root
    and Brent's method ended on that jump, where the largest real part was +0.72 1/s. The
    machine is unstable from 10886 rpm (the fine grid's answer). Checked here against the zero
    of the largest real part of scipy's roots of the state matrix, and the root named at it."""
    import scipy.optimize

    import rotordyn_modal as rdm

    model = rdm.load_model(ROOT / "examples" / "unstable_cross_coupled.toml")
    largest = lambda speed: _state_roots(model, speed).real.max()        # noqa: E731
    rad = np.pi / 30
    expected = scipy.optimize.brentq(largest, 1.0 * rad, 5e4 * rad, xtol=1e-12)
    assert largest(1.0 * rad) < 0 < largest(2e4 * rad) and largest(4e4 * rad) > 0    # one crossing, no island
    result = rdm.stability(model, np.array(grid_rpm) * rad)
    assert len(result.thresholds) == 1 and result.threshold_onsets[0]
    np.testing.assert_allclose(result.thresholds[0], expected, rtol=1e-9)
    roots = _state_roots(model, expected)
    crossing = roots[np.argmax(roots.real)]
    np.testing.assert_allclose(result.threshold_frequencies_hz[0], abs(crossing.imag) / (2 * np.pi), rtol=1e-6)


def test_a_loop_of_links_where_the_checkpoint_folder_goes_is_named_a_loop(tmp_path):
    """A link in a loop was said to lead to "loopA, which does not exist" (loopA exists: a link)."""
    from rotordyn_modal.errors import OutputError
    from rotordyn_modal.study.execution import _check_folder

    folder, other = tmp_path / "r.nc.partial", tmp_path / "loopA"
    folder.symlink_to(other)
    other.symlink_to(folder)
    assert os.path.lexists(other)
    with pytest.raises(OutputError, match="loop of links") as refused:
        _check_folder(folder)
    assert "does not exist" not in str(refused.value)


def test_a_model_file_given_as_the_study_file_is_named_a_model_file(tmp_path):
    """``study m.toml --spec m.toml`` said "<top level> spin_axis = [1.0, 0.0, 0.0]: expected one of
    the keys seed, samples, ... (unknown key)", as if the study file had a typo."""
    code, err = run_quietly(["study", str(EXAMPLE), "--spec", str(EXAMPLE), "--out", str(tmp_path / "r.nc")])
    line = _one_line(code, err)
    assert "a model file" in line and "--spec" in line and "unknown key" not in line, line


def written_uff(path):
    """``path``, a Universal File the command line wrote: the FRF acc-top-z / hammer-z of
    rubber_mounts.toml at rest at :data:`_FREQS` (one dataset 58)."""
    code, err = run_quietly(["frf", str(EXAMPLE_RUBBER), "--speed", "0", "--freqs", "5:20:4", "--sensor", "acc-top-z",
                             "--excitation", "hammer-z", "--out", str(path)])
    assert code == 0, err
    return path


def test_a_uff_frf_of_even_spacing_and_no_step_is_refused_naming_the_step(tmp_path):
    """Record 7 with even spacing and an increment of 0 puts every line at one frequency; it was
    refused as "given 10 times at 5 Hz ... (a duplicated channel?)", which sends the user looking
    for a channel twice in the file."""
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.io.measured import read_measured
    import rotordyn_modal as rdm

    model = rdm.load_model(EXAMPLE_RUBBER)
    good = written_uff(tmp_path / "good.uff")
    lines = good.read_text().splitlines(keepends=True)
    record7 = next(i for i, line in enumerate(lines)          # ordinate type, count, even spacing, start, step, z
                   if len(line.split()) == 6 and line.split()[1:3] == [str(len(_FREQS)), "1"])
    fields = lines[record7].split()
    assert float(fields[4]) == 5.0                                   # the step, E13.5
    line, step = lines[record7], f"{float(fields[4]):13.5E}"
    at = line.index(step, 10 + 10 + 10 + 13)                        # the 5th field (start and step are both 5 Hz)
    lines[record7] = line[:at] + f"{0.0:13.5E}" + line[at + 13:]
    assert lines[record7].split()[3:] == fields[3:4] + ["0.00000E+00"] + fields[5:]
    bad = tmp_path / "no_step.uff"
    bad.write_text("".join(lines))
    read_measured(good, model)                                       # the file as written reads
    with pytest.raises(InputError, match=r"increment 0 \(record 7\).*frequency step > 0"):
        read_measured(bad, model)


@pytest.mark.parametrize("header,factor", [("Speed [r/min]", 1.0), ("Speed [rev/min]", 1.0), ("Speed [rps]", 1 / 60),
                                           ("Speed [rev/s]", 1 / 60), ("Speed [r/s]", 1 / 60)])
def test_a_speed_column_in_revolutions_per_minute_or_second_is_converted(tmp_path, header, factor):
    """'r/min' (the SI brochure's spelling) and revolutions per second were refused: "unit 'r/min'
    not understood: expected one of rpm, 1/min, rad/s, hz"."""
    rows = [f"{float(1200.0 * factor)!r},{float(f)!r},acc-top-z,hammer-z,{float(h.real)!r},{float(h.imag)!r}"
            for f, h in zip(_FREQS, _H)]
    path = tmp_path / "frf.csv"
    path.write_text("\n".join([f"{header},frequency_hz,output,input,real,imag", *rows]) + "\n")
    from rotordyn_modal.io.measured import read_measured
    import rotordyn_modal as rdm

    (frf,) = read_measured(path, rdm.load_model(EXAMPLE_RUBBER))
    np.testing.assert_allclose(frf.speed * 30 / np.pi, 1200.0, rtol=1e-14)      # rad/s -> rpm
    np.testing.assert_array_equal(frf.H[0, 0], _H)
