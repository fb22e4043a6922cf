"""Modal identification (LSCF + LSFD through sdypy-ema, refined) against known poles and shapes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.analysis.identification import fit_measured_modes, identify_modes
from rotordyn_modal.errors import InputError

pytest.importorskip("sdypy.EMA")

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"

#: two modes 1 % apart in frequency, damping 1 % and 2 %: their half-power bands overlap
FREQS_HZ = np.array([20.0, 20.2])
ZETAS = np.array([0.01, 0.02])
PHI = np.array([[1.0, 0.6, -0.4], [0.5, -0.8, 0.9]])          # (mode, output)
L = np.array([[1.0, 0.3], [-0.4, 1.0]])                         # (mode, input)
LINES = np.arange(10.0, 30.0001, 0.02)


def _poles(freqs_hz, zetas):
    """Poles whose damped frequency is ``freqs_hz`` and damping ratio ``zetas``."""
    return 2 * np.pi * freqs_hz * (-zetas / np.sqrt(1 - zetas ** 2) + 1j)


def _close_modes(noise=0.0, seed=0):
    """Accelerance of two modes (closed form: pole-residue pairs), proportional complex noise."""
    lam = _poles(FREQS_HZ, ZETAS)
    A = np.einsum("mo,mi->moi", PHI, L) * (1 + 0.05j) * 1e-3
    s = 2j * np.pi * LINES
    H = sum(A[m][..., None] / (s - lam[m]) + A[m].conj()[..., None] / (s - lam[m].conj()) for m in range(2))
    H = H * s ** 2
    rng = np.random.default_rng(seed)
    H = H * (1 + noise * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape)) / np.sqrt(2))
    measured = FRFResult(H=H, frequencies_hz=LINES, speed=0.0, inputs=("a", "b"), outputs=("x", "y", "z"),
                         quantity="accelerance", engine="measured")
    return measured, lam, A


def test_close_modes_noise_free_to_1e_6():
    measured, lam, A = _close_modes()
    modes = identify_modes(measured, method="lscf")
    assert modes.method == "lscf" and len(modes.poles) == 2
    np.testing.assert_allclose(modes.frequencies_hz, FREQS_HZ, rtol=1e-6)
    np.testing.assert_allclose(modes.damping_ratios, ZETAS, rtol=1e-6)
    np.testing.assert_allclose(modes.poles, lam, rtol=1e-6)
    np.testing.assert_allclose(modes.shapes, A, rtol=0, atol=1e-6 * np.abs(A).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_close_modes_with_noise_within_the_promise(seed):
    """1 % complex noise on every line: frequency within 0.1 %, damping within 5 %."""
    measured, _, _ = _close_modes(noise=0.01, seed=seed)
    modes = identify_modes(measured, method="lscf")
    assert len(modes.poles) == 2
    np.testing.assert_allclose(modes.frequencies_hz, FREQS_HZ, rtol=1e-3)
    np.testing.assert_allclose(modes.damping_ratios, ZETAS, rtol=0.05)


def test_single_pole_fit_misses_close_modes():
    """What the LSCF route replaces: one pole per peak cannot see two overlapping modes."""
    measured, _, _ = _close_modes()
    modes = fit_measured_modes(measured)
    assert modes.method == "single-pole" and len(modes.poles) == 1
    assert abs(modes.damping_ratios[0] / ZETAS[0] - 1) > 0.05


def test_machine_modes_from_its_own_frfs():
    """The gear machine's FRFs give back its eigenvalues (computed by the eigen-solver, no FRFs)."""
    model = rdm.load_model(EXAMPLE)
    speed = rdm.rpm(3000)
    measured = rdm.frf(model, speed, np.linspace(1, 40, 800), quantity="mobility")
    modes = identify_modes(measured, method="lscf")
    truth = rdm.modal(model, speed)
    np.testing.assert_allclose(modes.poles, truth.eigenvalues[truth.oscillatory], rtol=1e-6)
    chart = modes.stabilization
    assert set(chart.status) <= {"new", "frequency", "stable"}
    assert chart.to_dataframe().columns.tolist() == ["order", "frequency_hz", "damping_ratio", "status"]
    fig = modes.plot()
    assert fig.axes[0].get_xlabel() == "Frequency [Hz]"


def test_correlation_reports_the_method():
    model = rdm.load_model(EXAMPLE)
    measured = rdm.frf(model, rdm.rpm(3000), np.linspace(1, 40, 800))
    result = rdm.correlate(model, measured)
    assert result.identification == "lscf"
    np.testing.assert_allclose(result.modes.difference_pct, 0.0, atol=1e-6)
    np.testing.assert_allclose(result.modes.mac, 1.0, rtol=1e-9)
    single = rdm.correlate(model, measured, identification="single-pole")
    assert single.identification == "single-pole"


def test_uneven_lines_refused_by_lscf_and_auto_falls_back():
    measured, _, _ = _close_modes()
    uneven = FRFResult(**{**measured.__dict__, "frequencies_hz": LINES ** 1.001})
    with pytest.raises(InputError, match="needs at least 8 equally spaced frequency lines"):
        identify_modes(uneven, method="lscf")
    assert identify_modes(uneven).method == "single-pole"
    with pytest.raises(InputError, match="identification method 'polymax'"):
        identify_modes(measured, method="polymax")
    with pytest.raises(InputError, match="band 5..25 Hz: expected inside the measured lines"):
        identify_modes(measured, method="lscf", band_hz=(5, 25))
    with pytest.raises(InputError, match="cannot identify modes of 'force' FRFs: expected receptance, mobility"):
        identify_modes(FRFResult(**{**measured.__dict__, "quantity": "force"}), method="lscf")
    holes = measured.H.copy()
    holes[..., 7] = np.nan                                         # every FRF misses a line
    with pytest.raises(InputError, match="no complete measured FRF to identify modes from"):
        identify_modes(FRFResult(**{**measured.__dict__, "H": holes}), method="lscf")
    with pytest.raises(InputError, match="modes identified by 'single-pole' have no stabilization chart"):
        identify_modes(measured, method="single-pole").plot()


def test_identified_modes_table_lists_them_by_frequency():
    measured, lam, _ = _close_modes()
    modes = identify_modes(measured, method="lscf")
    table = modes.to_dataframe()
    assert list(table.columns) == ["mode", "frequency_hz", "damping_ratio", "real_part", "method"]
    assert table["mode"].tolist() == [1, 2] and set(table["method"]) == {"lscf"}
    np.testing.assert_allclose(table["frequency_hz"], FREQS_HZ, rtol=1e-6)
    np.testing.assert_allclose(table["damping_ratio"], ZETAS, rtol=1e-4)
    np.testing.assert_allclose(table["real_part"], lam.real, rtol=1e-4)


def test_missing_sdypy_named_in_the_message(without_module):
    without_module("sdypy")
    measured, _, _ = _close_modes()
    with pytest.raises(InputError, match=r"pip install 'rotordyn_modal\[ema\]'"):
        identify_modes(measured, method="lscf")


def test_measured_modes_as_rigid_body_shapes():
    """Nine channels of three triaxial accelerometers: the identified modes' rigid-body shapes are
    the model's own (MAC 1 with the mass matrix), and their whirl labels agree."""
    from rotordyn_modal.analysis.experimental import measured_modal_result

    data = rdm.load_model(EXAMPLE).to_dict()
    points = ([0.3, 0.3, 0.45], [0.3, -0.3, 0.45], [-0.3, 0.0, -0.15])
    data["sensors"] = [{"name": f"s{k}{a}", "position": p, "direction": d}
                       for k, p in enumerate(points) for a, d in zip("xyz", np.eye(3).tolist())]
    model = rdm.Model.from_dict(data)
    speed = rdm.rpm(1500)
    measured = rdm.frf(model, speed, np.linspace(2, 40, 609))
    result = measured_modal_result(model, identify_modes(measured, method="lscf"), speed=speed)
    truth = rdm.modal(model, speed)
    M = model.matrices().M
    np.testing.assert_allclose(np.diag(rdm.mac(result.shapes, truth.shapes[truth.oscillatory], M)), 1.0, atol=1e-9)
    np.testing.assert_allclose(result.frequencies_hz, truth.frequencies_hz[truth.oscillatory], rtol=1e-9)
    assert list(result.whirl) == list(truth.whirl[truth.oscillatory])


def test_modes_are_listed_by_frequency_each_with_its_own_constants():
    """However the identification returns its poles, the modes come out by frequency and each
    keeps its own modal constants (one output, two inputs here)."""
    from rotordyn_modal.analysis.identification import _from_poles

    measured = FRFResult(H=np.zeros((1, 2, 3), complex), frequencies_hz=np.array([1.0, 2.0, 3.0]), speed=0.0,
                         inputs=("a", "b"), outputs=("x",), quantity="receptance", engine="H1")
    poles = np.array([-1 + 30j, -1 + 10j, -1 + 20j])
    constants = np.array([[3.0, 30.0], [1.0, 10.0], [2.0, 20.0]], dtype=complex)
    modes = _from_poles(poles, constants, measured, "lscf")
    np.testing.assert_array_equal(modes.poles, poles[[1, 2, 0]])
    np.testing.assert_array_equal(modes.shapes[:, 0, :], constants[[1, 2, 0]])
    np.testing.assert_allclose(modes.frequencies_hz, [10 / (2 * np.pi), 20 / (2 * np.pi), 30 / (2 * np.pi)])
