"""FRF files that hold more than FRFs (issue 27 §4, the FRF reader's side of
``tests/test_uff_mixed_records.py``): analysers export the time records, their PSDs and auto- and
cross-spectra beside the FRFs and coherence. ``read_measured`` (``frf --measured``, ``fit
--measured``) reads the FRFs and the coherence of their pairs and names the sets it skipped in one
warning (they were skipped without a word); a file of time records alone is refused in one line
that says what it holds and how FRFs are computed from it (it was refused as 'function types
found: [1]'), and following that advice gives a file ``frf --measured`` reads. A spectrum of a pair
without its FRF is still refused (``tests/test_input_families6.py``), while auto-spectra (one
channel's power, never an FRF's pair) beside FRFs are skipped and named."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import default_mapping, read_measured
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"
N, DT = 256, 1.0 / 512.0
FRF_ARGS = ["--speed", "600", "--freqs", "2:40:5"]


def _time(node, direction, kind, label, data):
    return pyuff.prepare_58(binary=0, func_type=1, rsp_node=node, rsp_dir=direction, ref_node=0, ref_dir=0,
                            ordinate_spec_data_type=kind, ordinate_axis_units_lab=label, orddenom_spec_data_type=0,
                            abscissa_spec_data_type=17, abscissa_axis_units_lab="s", data=np.asarray(data, float),
                            x=np.arange(N) * DT, abscissa_spacing=1, abscissa_inc=DT, abscissa_min=0.0)


def _spectrum(func_type, node, direction, ref_node, ref_dir, data, ordinate=12, denominator=13):
    return pyuff.prepare_58(binary=0, func_type=func_type, rsp_node=node, rsp_dir=direction, ref_node=ref_node,
                            ref_dir=ref_dir, ordinate_spec_data_type=ordinate, orddenom_spec_data_type=denominator,
                            abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz", data=np.asarray(data),
                            x=np.linspace(2.0, 40.0, 5), abscissa_spacing=1, abscissa_inc=9.5, abscissa_min=2.0,
                            z_axis_value=600.0)


def _write(path, sets):
    open(path, "w").close()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _impact_records():
    """A hammer hit (an exponential pulse of 6 samples, a spectrum without zeros) on node 101 +Z
    and the acceleration it rings at node 1 +Z (a decaying 40 Hz sine), two records; as a
    recorder writes them."""
    t = np.arange(N) * DT
    pulse = np.zeros(N)
    pulse[:6] = 100.0 * np.exp(-np.arange(6) / 1.5)
    ring = 3.0 * np.exp(-8.0 * t) * np.sin(2 * np.pi * 40.0 * t)
    return [_time(101, 3, 13, "N", scale * pulse) for scale in (1.0, 1.1)], \
        [_time(1, 3, 12, "m/s^2", scale * ring) for scale in (1.0, 1.1)]


@pytest.fixture(scope="module")
def frf_file(tmp_path_factory):
    """The gear machine's FRFs and coherence-free sets at 600 rpm, 2 to 40 Hz in 5 lines, as
    ``frf --out`` writes them (default mapping: sensors at nodes 1, 2, excitations at 101, 102)."""
    path = tmp_path_factory.mktemp("frf") / "g.uff"
    assert main(["frf", str(GEAR), *FRF_ARGS, "--out", str(path), "--quiet"]) == 0
    return path


@pytest.fixture(scope="module")
def analyser_export(frf_file, tmp_path_factory):
    """Time records first (datasets 1-4: two hits of hammer and response, as a recorder interleaves
    them), then the four FRFs (5-8), then a cross-spectrum of a pair whose FRF is there (9), a
    coherence of a pair that has none (10) and a PSD (11). (Auto-spectra beside the FRFs:
    ``test_auto_spectra_beside_the_frfs_are_skipped_and_named``.)"""
    forces, responses = _impact_records()
    sets = pyuff.UFF(str(frf_file)).read_sets()
    frfs = [sets] if isinstance(sets, dict) else list(sets)
    rng = np.random.default_rng(27)
    extra = [_spectrum(3, 1, 3, 101, 3, rng.normal(size=5) + 1j * rng.normal(size=5)),
             _spectrum(6, 5, 3, 101, 3, rng.uniform(size=5), ordinate=0, denominator=0),
             _spectrum(9, 2, 2, 0, 0, np.abs(rng.normal(size=5)), ordinate=0, denominator=0)]
    sets = [forces[0], responses[0], forces[1], responses[1], *frfs, *extra]
    return _write(tmp_path_factory.mktemp("mixed") / "export.uff", sets)


def _alone(frf_file, tmp_path):
    """The FRFs of ``frf_file`` read from a file of them alone, written by pyuff as the exports
    here are (pyuff's ASCII holds 12 digits, ``frf --out`` 13)."""
    sets = pyuff.UFF(str(frf_file)).read_sets()
    plain, = read_measured(_write(tmp_path / "alone.uff", [sets] if isinstance(sets, dict) else list(sets)),
                           rdm.load_model(GEAR))
    return plain


def test_the_frfs_are_read_and_the_other_sets_named_in_one_warning(frf_file, analyser_export, tmp_path):
    """The FRFs read from the export are those of the file of FRFs alone, bit for bit; one warning
    line names the 7 sets skipped by their places in the file, function types and nodes."""
    model = rdm.load_model(GEAR)
    plain = _alone(frf_file, tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mixed, = read_measured(analyser_export, model)
    assert mixed.outputs == plain.outputs and mixed.inputs == plain.inputs
    np.testing.assert_array_equal(mixed.frequencies_hz, plain.frequencies_hz)
    np.testing.assert_array_equal(mixed.H, plain.H)
    assert mixed.coherence is None                      # the coherence of no FRF's pair is not theirs
    assert len(caught) == 1, [str(w.message) for w in caught]
    line = str(caught[0].message)
    assert "\n" not in line and str(analyser_export) in line
    assert "read the 4 FRFs (dataset 58, function type 4) and skipped 7 dataset 58 sets" in line
    for words in ("function type 1 (time response): datasets 1, 2, 3, 4 at 101:+3, 1:+3",
                  "function type 3 (cross-spectrum): dataset 9 at 1:+3 / 101:+3",
                  "function type 6 (coherence): dataset 10 at 5:+3 / 101:+3",
                  "function type 9 (power spectral density): dataset 11 at 2:+2",
                  "FRFs are computed from time records by rdm.estimate_frf"):
        assert words in line, (words, line)


def test_the_command_line_prints_the_warning_as_one_line(tmp_path, capsys, analyser_export):
    assert main(["frf", str(GEAR), *FRF_ARGS, "--measured", str(analyser_export), "--out",
                 str(tmp_path / "f.csv"), "--quiet"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("rotordyn-modal frf: warning: ") and "skipped 7 dataset 58" in err[0]
    assert (tmp_path / "f.csv").is_file()


def test_a_file_of_frfs_alone_reads_without_a_warning(frf_file):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_measured(frf_file, rdm.load_model(GEAR))


def test_a_cross_spectrum_without_its_frf_is_still_refused_beside_time_records(tmp_path, frf_file):
    """The refusal of a spectrum in place of a pair's FRF comes before any warning (the file is
    refused, not read with a warning)."""
    sets = pyuff.UFF(str(frf_file)).read_sets()
    sets = [sets] if isinstance(sets, dict) else list(sets)
    sets[1]["func_type"] = 3
    forces, responses = _impact_records()
    path = _write(tmp_path / "spectrum.uff", [forces[0], responses[0], *sets])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match="dataset 4 .*function type 3 \\(cross-spectrum\\) is not an FRF"):
            read_measured(path, rdm.load_model(GEAR))


@pytest.fixture(scope="module")
def time_file(tmp_path_factory):
    forces, responses = _impact_records()
    return _write(tmp_path_factory.mktemp("time") / "hits.uff", [forces[0], responses[0], forces[1], responses[1]])


def test_a_file_of_time_records_alone_is_refused_saying_how_to_get_frfs(time_file):
    with pytest.raises(InputError) as info:
        read_measured(time_file, rdm.load_model(GEAR))
    message = str(info.value)
    assert "\n" not in message and str(time_file) in message
    assert "no FRF (dataset 58, function type 4) in the file" in message
    assert "function type 1 (time response): datasets 1, 2, 3, 4 at 101:+3, 1:+3" in message
    for words in ("frf = rdm.estimate_frf(rdm.read_uff_time_records(FILE, mapping, speed)",
                  "rdm.write_measured_csv([frf], FILE.csv)"):
        assert words in message, (words, message)


@pytest.mark.parametrize("command", ["frf", "fit"])
def test_frf_and_fit_refuse_a_time_record_file_in_one_line(tmp_path, capsys, time_file, command):
    argv = {"frf": ["frf", str(GEAR), *FRF_ARGS, "--measured", str(time_file)],
            "fit": ["fit", str(GEAR), "--measured", str(time_file), "--params", "suspensions.mount-FL.damping",
                    "--out", str(tmp_path / "fit.toml")]}[command]
    assert main(argv + ["--quiet"]) == 2
    _one_line_error(capsys, str(time_file), "function type 1 (time response)", "rdm.estimate_frf")
    assert not (tmp_path / "fit.toml").exists()


def test_the_advice_of_the_refusal_gives_a_file_frf_reads(tmp_path, time_file):
    """What the message says, done: the time records named after the model by its mapping (at the
    speed frf is asked for), H1 of
    the two hits, written as CSV; ``frf --measured`` reads that file. The FRF is the ratio of the
    two spectra, each hit's response being the same multiple of its force (1.0 and 1.1 of both)."""
    model = rdm.load_model(GEAR)
    records = rdm.read_uff_time_records(time_file, default_mapping(model), speed=rdm.rpm(600.0))
    assert records.channels == ("hammer-z", "acc-top-z")
    frf = rdm.estimate_frf(records, ["hammer-z"], ["acc-top-z"], estimator="H1")
    force, response = records.signals[0]
    expected = np.fft.rfft(response) / np.fft.rfft(force)
    np.testing.assert_allclose(frf.H[0, 0], expected[1:], rtol=1e-9)
    rdm.write_measured_csv([frf], tmp_path / "frf.csv")
    assert main(["frf", str(GEAR), *FRF_ARGS, "--quantity", "accelerance", "--measured", str(tmp_path / "frf.csv"),
                 "--out", str(tmp_path / "model.csv"), "--quiet"]) == 0


@pytest.mark.parametrize("reader", ["time records", "FRFs"])
def test_a_refused_mixed_file_draws_its_error_alone(tmp_path, frf_file, reader):
    """The warning naming the skipped sets comes once the file is read: a file refused for what its
    read sets hold (a time record or an FRF in volts) gets its one error line and no warning beside it
    (the time-record reader warned first, then refused: two lines on the command line)."""
    forces, responses = _impact_records()
    sets = pyuff.UFF(str(frf_file)).read_sets()
    frfs = [sets] if isinstance(sets, dict) else list(sets)
    if reader == "time records":
        responses[0]["ordinate_axis_units_lab"] = "V"
    else:
        frfs[0]["ordinate_axis_units_lab"] = "V"
    path = _write(tmp_path / "mixed.uff", [forces[0], responses[0], *frfs])
    read = {"time records": rdm.read_uff_time_records,
            "FRFs": lambda p: read_measured(p, rdm.load_model(GEAR))}[reader]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(InputError, match="ordinate unit 'V' is not understood"):
            read(path)
    assert [str(w.message) for w in caught] == []


def test_auto_spectra_beside_the_frfs_are_skipped_and_named(frf_file, tmp_path):
    """An analyser exports the FRFs with the auto-spectra of the hammer and of each response they
    were computed from (function type 2, each channel referred to itself). The FRFs are read bit
    for bit as from the file of FRFs alone, and the two auto-spectra are named in the one warning
    (the reader refused the whole file as 'a spectrum of a pair without its FRF')."""
    model = rdm.load_model(GEAR)
    plain = _alone(frf_file, tmp_path)
    sets = pyuff.UFF(str(frf_file)).read_sets()
    frfs = [sets] if isinstance(sets, dict) else list(sets)
    power = np.abs(np.random.default_rng(2).normal(size=5)) + 0j
    autos = [_spectrum(2, 101, 3, 101, 3, power, ordinate=13, denominator=13),
             _spectrum(2, 1, 3, 1, 3, power, ordinate=12, denominator=12)]
    path = _write(tmp_path / "autos.uff", [*frfs, *autos])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mixed, = read_measured(path, model)
    np.testing.assert_array_equal(mixed.H, plain.H)
    assert len(caught) == 1, [str(w.message) for w in caught]
    line = str(caught[0].message)
    assert "skipped 2 dataset 58 sets" in line and "function type 2 (auto-spectrum): datasets 5, 6" in line, line


def test_auto_spectra_alone_are_refused_naming_what_the_file_holds(tmp_path):
    """Auto-spectra without any FRF: no FRF to read, refused in one line naming the function type."""
    power = np.abs(np.random.default_rng(3).normal(size=5)) + 0j
    path = _write(tmp_path / "only_autos.uff", [_spectrum(2, 1, 3, 1, 3, power, ordinate=12, denominator=12)])
    with pytest.raises(InputError, match=r"no FRF .*function type 2 \(auto-spectrum\)"):
        read_measured(path, rdm.load_model(GEAR))
