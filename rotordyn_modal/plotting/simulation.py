"""Figures of a time simulation: time histories, and run-up (order track, waterfall)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_simulation", "plot_runup"]


def plot_simulation(result, title: str | None = None):
    """Four panels: rotor centres' path, stator (or carrier) motion and the rotors' tilt in
    their bearings, spin speed, energy terms.

    Parameters
    ----------
    result : SimulationResult
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), layout="constrained")
    _draw_paths(axes[0, 0], result)
    _draw_frame_motion(axes[0, 1], result)
    _draw_spin(axes[1, 0], result)
    _draw_energy(axes[1, 1], result)
    fig.suptitle(title or result.model_name or "Simulation")
    return fig


def _draw_paths(ax, result):
    """The rotors' centres in the y-z plane, from where each started."""
    for j, name in enumerate(result.rotor_names):
        path = result.rotor_centers[:, j] - result.rotor_centers[0, j]
        ax.plot(path[:, 1], path[:, 2], lw=0.8, label=name)
    ax.set(xlabel="y displacement of the rotor centre [m]", ylabel="z displacement [m]",
           title="Path of the rotors' centres (y-z)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize="small")


def _draw_frame_motion(ax, result):
    """The stator's (or carrier's) transverse rotation and translation, and each rotor on
    bearings' tilt in them."""
    t = result.time
    if result.displacement.any() or not result.rotor_tilts.any():
        ax.plot(t, np.degrees(np.linalg.norm(result.gamma, axis=1)), label="|γ| transverse rotation")
        for k, axis in enumerate("xyz"):
            ax.plot(t, result.displacement[:, k] * 1e3, lw=0.8, label=f"u_{axis} [mm]")
    for j, name in enumerate(result.rotor_names):
        if result.rotor_tilts[:, j].any():
            ax.plot(t, np.degrees(np.linalg.norm(result.rotor_tilts[:, j], axis=1)), lw=0.8,
                    label=f"|γ| {name} in its bearings")
    ax.set(xlabel="Time [s]", ylabel="[deg] / [mm]", title="Transverse rotation and translation")
    ax.legend(fontsize="small")


def _draw_spin(ax, result):
    ax.plot(result.time, result.spin_speed - result.spin_speed[0])
    ax.set(xlabel="Time [s]", ylabel="ω_φ − ω_φ(0) [rad/s]",
           title=f"Axial angular velocity deviation (ω_φ(0) = {result.spin_speed[0]:.4g} rad/s)")


def _draw_energy(ax, result):
    """Changes of the kinetic, total and potential energy from the start."""
    t = result.time
    potential = result.elastic_energy + result.gravity_energy
    ax.plot(t, result.kinetic_energy - result.kinetic_energy[0], label="1: change of kinetic energy")
    ax.plot(t, result.total_energy - result.total_energy[0], label="2: change of total energy")
    ax.plot(t, potential - potential[0], label="3: change of potential energy")
    ax.set(xlabel="Time [s]", ylabel="[J]", title="Energy")
    ax.legend(fontsize="small")


def plot_runup(result, sensor: str, critical=None, title: str | None = None, segments: int = 60):
    """Run-up: sensor signal, order-tracked amplitude and phase, waterfall, all against speed.

    Parameters
    ----------
    result : SimulationResult
        A ramp (run-up) simulation.
    sensor : str
    critical : CriticalSpeeds, optional
        Drawn as vertical lines (and, on the waterfall, as points at their frequencies).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from ..simulation.runup import order_track, waterfall

    if critical is not None:  # the rotors' own orders (gear-mesh crossings sit at very low speeds)
        critical = _rotor_orders(critical, result.rotor_names)
    rpm = 30.0 / np.pi
    fig, axes = plt.subplots(2, 2, figsize=(12, 8), layout="constrained")
    ax = axes[0, 0]
    ax.plot(result.drive_speed * rpm, result.sensor(sensor) * 1e6, lw=0.5)
    ax.set(xlabel="Speed of the reference rotor [rpm]", ylabel=f"{sensor} [µm]", title="Sensor during the run-up")
    amplitude_ax, phase_ax = axes[0, 1], axes[1, 0]
    for rotor in result.rotor_names:
        track = order_track(result, sensor, rotor=rotor)
        amplitude_ax.plot(track.speeds * rpm, track.amplitude * 1e6, label=f"1X {rotor}")
        phase_ax.plot(track.speeds * rpm, track.phase_deg, ".", ms=3, label=f"1X {rotor}")
    amplitude_ax.set(xlabel="Speed [rpm]", ylabel="Amplitude [µm]", title="Order-tracked amplitude")
    phase_ax.set(xlabel="Speed [rpm]", ylabel="Phase [deg]", title="Order-tracked phase", ylim=(-180, 180))
    amplitude_ax.legend(fontsize="small")
    ax = axes[1, 1]
    fall = waterfall(result, sensor, segments=segments)
    image = ax.pcolormesh(fall.frequencies_hz, fall.speeds * rpm, fall.amplitude * 1e6, shading="nearest",
                          cmap="viridis")
    fig.colorbar(image, ax=ax, label="Amplitude [µm]")
    ax.set(xlabel="Frequency [Hz]", ylabel="Speed [rpm]", title="Waterfall",
           xlim=(0, min(fall.frequencies_hz[-1], 3 * _highest(result, critical))))
    if critical is not None and len(critical):
        for axis in (axes[0, 0], amplitude_ax, phase_ax):
            for speed in critical.speeds:
                axis.axvline(speed * rpm, color="tab:red", lw=0.7, ls="--")
        ax.plot(critical.frequencies_hz, critical.speeds * rpm, "o", mfc="none", color="tab:red",
                label="critical speeds (Campbell)")
        ax.legend(fontsize="small", loc="upper left")
    fig.suptitle(title or f"Run-up of {result.model_name or 'the machine'}")
    return fig


def _rotor_orders(critical, rotor_names):
    from dataclasses import fields, replace

    keep = np.isin(critical.source, rotor_names)
    return replace(critical, **{f.name: getattr(critical, f.name)[keep] for f in fields(critical)})


def _highest(result, critical):
    spin = np.abs(result.drive_speed).max() * np.abs(result.speed_ratios).max() / (2 * np.pi)
    natural = critical.frequencies_hz.max() if critical is not None and len(critical) else 0.0
    return max(spin, natural, 1.0)
