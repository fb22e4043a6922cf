"""Issue 29 §6: every amplitude column and axis says whether it is 0-peak, peak-to-peak or RMS.
The unbalance command's printed response table (whose `amplitude` column the CSV contract fixes
as 0-peak) and its orbit table get a heading that says so; the run-up figure's order-tracked
amplitude and waterfall say 0-peak, and draw the 0-peak amplitude of a signal built here."""

import types

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from rotordyn_modal.cli import main
from rotordyn_modal.plotting.simulation import plot_runup

MODEL = "examples/compressor_on_journals.toml"


@pytest.mark.parametrize("amplitude, words", [("peak", "amplitude 0-peak;"),
                                              ("pk-pk", "amplitude 0-peak, amplitude_pkpk peak-to-peak;"),
                                              ("rms", "amplitude 0-peak, amplitude_rms RMS;")])
@pytest.mark.parametrize("units", ["si", "us"])
def test_the_printed_response_table_says_its_amplitude_conventions(capsys, amplitude, words, units):
    code = main(["unbalance", MODEL, "--speeds", "3000:6000:4", "--amplitude", amplitude, "--units", units])
    out, err = capsys.readouterr()
    assert code == 0
    heading = [line for line in err.splitlines() if line.startswith("unbalance response (")]
    assert len(heading) == 1 and words in heading[0]
    assert out.splitlines()[0].split()[:6] == ["speed_rpm", "output", "source", "frequency_hz", "amplitude", "phase_deg"]


def test_the_orbit_table_says_its_semi_axes_are_0_peak(capsys):
    assert main(["unbalance", MODEL, "--speeds", "3000:6000:4"]) == 0
    err = capsys.readouterr().err
    assert "largest orbit of each probe pair (major, minor: semi-axes, 0-peak):" in err


def _constant_speed_run(amplitude, rpm=3000.0, seconds=4.0, samples=40001):
    """A run at constant speed whose sensor reads amplitude cos(phi): the 1X order's 0-peak
    amplitude is ``amplitude``."""
    time = np.linspace(0.0, seconds, samples)
    speed = rpm * np.pi / 30.0
    angle = speed * time
    return types.SimpleNamespace(
        time=time, drive_speed=np.full_like(time, speed), rotor_angles=angle[:, None], rotor_names=["r"],
        speed_ratios=np.array([1.0]), model_name="test", sensor=lambda name: amplitude * np.cos(angle))


@pytest.mark.parametrize("units, scale", [("si", 1e6), ("us", 1 / 25.4e-6)])
def test_the_run_up_figure_says_and_draws_0_peak(units, scale):
    amplitude = 2e-6
    figure = plot_runup(_constant_speed_run(amplitude), "probe", units=units)
    tracked = figure.axes[1]
    assert "1X amplitude, 0-peak [" in tracked.get_ylabel()
    drawn = tracked.get_lines()[0].get_ydata()
    # the 4-revolution windows end at samples (200 a revolution): the average is off by a sample's share
    np.testing.assert_allclose(drawn, amplitude * scale, rtol=2 / 800)
    colour_bar = [ax for ax in figure.axes if "amplitude" in ax.get_ylabel() and ax is not tracked]
    assert colour_bar and "amplitude, 0-peak [" in colour_bar[0].get_ylabel()
    image = figure.axes[3].collections[0].get_array()
    assert np.max(image) == pytest.approx(amplitude * scale, rel=0.2)      # Hann window: within its scalloping loss


def test_a_studys_unbalance_peak_amplitudes_say_0_peak(examples_dir):
    """The study's netCDF variables of unbalance and force peak amplitudes carry the attribute
    amplitude = '0-peak', and hold the 0-peak response's largest value."""
    import rotordyn_modal as rdm

    gear = rdm.load_model(examples_dir / "gear_machine.toml")
    spec = {"seed": 1, "samples": 2, "design": "monte-carlo",
            "parameters": [{"key": "suspensions.mount-FL.stiffness", "apply": "scale", "distribution": "uniform",
                            "low": 0.9, "high": 1.1}],
            "analyses": {"unbalance": {"speeds_rpm": "500:4000:8", "forces": "suspensions"}}}
    ds = rdm.study(gear, spec).dataset
    assert ds["unbalance_peak_amplitude"].attrs["amplitude"] == "0-peak"
    assert ds["force_peak_amplitude"].attrs["amplitude"] == "0-peak"
    factor = ds["sample_value"].values[0, 0]
    response = rdm.unbalance_response(gear.scaled({"suspensions.mount-FL.stiffness": factor}),
                                      rdm.rpm(np.linspace(500, 4000, 8)))
    np.testing.assert_allclose(np.nanmax(ds["unbalance_peak_amplitude"].values[0]), response.amplitude.max(), rtol=1e-12)
