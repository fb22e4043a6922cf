"""Result of a time simulation: arrays sampled at the output times."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SimulationResult"]


@dataclass
class SimulationResult:
    """Sampled motion of the machine (arrays and labels only: it pickles).

    Attributes
    ----------
    time : ndarray, shape (N,) [s]
    displacement : ndarray, shape (N, 6)
        ``[u, theta]`` of the stator at the model's reference point, model axes [m, rad];
        ``theta = gamma + psi e`` (transverse Euler vector plus roll angle). Zeros when the
        bearings stand on the ground (no ``[stator]``).
    velocity : ndarray, shape (N, 6)
        Velocity of the reference point [m/s] and angular velocity of the stator [rad/s].
    gamma : ndarray, shape (N, 3)
        Stator's transverse Euler vector [rad] (normal to the spin axis).
    drive_angle, drive_speed : ndarray, shape (N,)
        Reference rotor's angle [rad] and speed [rad/s] relative to the stator.
    spin_speed : ndarray, shape (N,)
        Reference rotor's axial angular velocity ``omega_phi`` (docs/theory-large-rotations.md, paper eq. 8) [rad/s]:
        the stator's roll rate plus the relative speed.
    rotor_angles : ndarray, shape (N, n_rotors)
        Axial angle of every rotor (roll of the stator plus its own turn relative to the
        stator, ``r_j phi``) [rad].
    drive_torque : ndarray, shape (N,)
        Torque of the ideal drive on the reference rotor (reacted by the stator) [N m]; 0 in
        free spin.
    rotor_centers : ndarray, shape (N, n_rotors, 3)
        Position of every rotor's centre of mass, model axes [m].
    rotor_displacements, rotor_tilts : ndarray, shape (N, n_rotors, 3)
        Each rotor's motion relative to the stator (or the ground) in its bearings, stator
        axes: translation of its axis point (at ``center_of_mass``) [m] and transverse Euler
        vector ``gamma_j`` [rad]; zeros for a rotor without bearings.
    bearing_forces : ndarray, shape (N, n_bearings, 6)
        ``[F, C]`` each bearing passes to the stator (or the ground) at its point, stator
        axes [N, N m]: its springs and dampers on the relative motion there.
    sensors : ndarray, shape (N, n_sensors)
        Displacement of each sensor's point along its direction [m]: a point of the stator or
        a rotor along a direction fixed in the ground; a ``relative`` sensor (proximity probe)
        reads the rotor point's motion relative to the stator point at the same place along
        a direction fixed in the stator.
    kinetic_energy, elastic_energy, gravity_energy : ndarray, shape (N,) [J]
        Gravity energy is ``-sum m g . r`` (zero at the model-axes origin).
    states : ndarray, shape (N, 2 n_dof)
        Raw states ``[q, dq/dt]``, ``q = [x, g1, g2, (psi), phi]`` (see
        ``rotordyn_modal.simulation._kernels``).
    sensor_names, rotor_names, bearing_names : list of str
    speed_ratios : ndarray, shape (n_rotors,)
    drive : str
        ``'constant'``, ``'ramp'`` or ``'free'``.
    model_name : str
    frame : str
        What the bearings and suspensions stand on (``model.dofs.frame``): ``'stator'``, the
        massless ``'frame'`` of a machine with neither stator nor bearings, or ``'ground'``
        (bearings without a ``[stator]``: ``displacement`` and ``gamma`` are zero by definition).

    A model with a flexible rotor is simulated as its linear model
    (:mod:`rotordyn_modal.simulation.flexible`): then ``states`` are ``[q, dq/dt]`` in the
    coordinates ``model.dofs`` (``phi`` is ``drive_angle``), the rotations are small (``theta``
    the stator's rotation vector, ``gamma`` its part normal to the spin axis), a flexible rotor's
    centre, displacement and tilt are those of its node nearest its centre of mass, and the
    energies are those of the small motions (docs/simulate.md, "Flexible rotors").
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    gamma: np.ndarray
    drive_angle: np.ndarray
    drive_speed: np.ndarray
    spin_speed: np.ndarray
    rotor_angles: np.ndarray
    drive_torque: np.ndarray
    rotor_centers: np.ndarray
    rotor_displacements: np.ndarray
    rotor_tilts: np.ndarray
    bearing_forces: np.ndarray
    sensors: np.ndarray
    kinetic_energy: np.ndarray
    elastic_energy: np.ndarray
    gravity_energy: np.ndarray
    states: np.ndarray
    sensor_names: list
    rotor_names: list
    bearing_names: list
    speed_ratios: np.ndarray
    drive: str
    model_name: str = ""
    frame: str = "stator"

    @property
    def total_energy(self) -> np.ndarray:
        """Kinetic + elastic + gravity energy [J], shape (N,)."""
        return self.kinetic_energy + self.elastic_energy + self.gravity_energy

    @property
    def gamma_deg(self) -> np.ndarray:
        """Size of the stator's transverse rotation, ``|gamma|`` [deg], shape (N,): the angle its
        spin axis is tilted by (zero without a stator)."""
        return np.degrees(np.linalg.norm(self.gamma, axis=1))

    @property
    def rotor_tilts_deg(self) -> np.ndarray:
        """Size of each rotor's tilt in its bearings, ``|gamma_j|`` [deg], shape (N, n_rotors)
        (zero for a rotor without bearings)."""
        return np.degrees(np.linalg.norm(self.rotor_tilts, axis=2))

    @property
    def spin_frequencies_hz(self) -> np.ndarray:
        """Each rotor's spin frequency relative to the stator, ``r_j * drive_speed / (2 pi)``
        [Hz], shape (N, n_rotors) (signed: negative where it turns against the reference)."""
        return np.asarray(self.drive_speed, dtype=float)[:, None] * np.asarray(self.speed_ratios, dtype=float) \
            / (2 * np.pi)

    @property
    def highest_spin_frequency_hz(self) -> float:
        """The fastest any rotor spins during the run, ``max |r_j| * max |drive_speed| / (2 pi)``
        [Hz] (0 for an empty record)."""
        if not np.size(self.drive_speed) or not np.size(self.speed_ratios):
            return 0.0
        return float(np.abs(self.drive_speed).max() * np.abs(self.speed_ratios).max() / (2 * np.pi))

    def sensor(self, name: str) -> np.ndarray:
        """Signal of the sensor ``name`` [m], shape (N,)."""
        from ..errors import InputError

        if name not in self.sensor_names:
            known = (f"the model's sensors are {', '.join(self.sensor_names)}" if self.sensor_names else
                     "the model has no [[sensors]]")
            raise InputError(f"unknown sensor {name!r}: {known}")
        return self.sensors[:, self.sensor_names.index(name)]

    def to_dataframe(self):
        """One row per output time (``pandas.DataFrame``); columns start with
        ``time_s,u_x,u_y,u_z,theta_x,theta_y,theta_z,spin_speed_rad_s,drive_torque_nm``, then
        the drive speed, the sensors [m], the rotor centres [m], each bearing's force and
        moment on the stator (``NAME_Fx`` ... [N], ``NAME_Mx`` ... [N m]) and the energies [J]."""
        import pandas as pd

        columns = {"time_s": self.time}
        for i, label in enumerate(("u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z")):
            columns[label] = self.displacement[:, i]
        columns["spin_speed_rad_s"] = self.spin_speed
        columns["drive_torque_nm"] = self.drive_torque
        columns["drive_speed_rad_s"] = self.drive_speed
        for j, name in enumerate(self.sensor_names):
            columns[name] = self.sensors[:, j]
        for j, name in enumerate(self.rotor_names):
            for k, axis in enumerate("xyz"):
                columns[f"{name}_center_{axis}"] = self.rotor_centers[:, j, k]
        for j, name in enumerate(self.bearing_names):
            for k, component in enumerate(("Fx", "Fy", "Fz", "Mx", "My", "Mz")):
                columns[f"{name}_{component}"] = self.bearing_forces[:, j, k]
        columns["kinetic_energy_j"] = self.kinetic_energy
        columns["potential_energy_j"] = self.elastic_energy + self.gravity_energy
        columns["total_energy_j"] = self.total_energy
        return pd.DataFrame(columns)

    def order_track(self, sensor: str, order: float = 1.0, rotor: str | None = None, revolutions: int | None = None):
        """Order-tracked amplitude and phase of a sensor; see :func:`order_track`."""
        from .runup import order_track

        return order_track(self, sensor, order=order, rotor=rotor, revolutions=revolutions)

    def waterfall(self, sensor: str, segments: int = 60):
        """Spectrum of a sensor against speed; see :func:`waterfall`."""
        from .runup import waterfall

        return waterfall(self, sensor, segments=segments)

    def plot(self, sensor: str | None = None, critical=None, title: str | None = None, units: str = "si",
             steady=None):
        """Time histories (constant speed, free spin) or run-up figures (ramp).

        Parameters
        ----------
        sensor : str, optional
            Sensor of the run-up figures (default: the first).
        critical : CriticalSpeeds, optional
            Critical speeds overlaid on the run-up figures.
        units : {'si', 'us'}
            Unit system of the displacements drawn (docs/units.md).
        steady : dict of str to SteadyOrder, optional
            The steady unbalance response beside the run-up's order tracks:
            ``runup.steady_orders(model, result, sensor)``.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting.simulation import plot_runup, plot_simulation

        if self.drive == "ramp" and self.sensor_names:
            return plot_runup(self, sensor or self.sensor_names[0], critical=critical, title=title, units=units,
                              steady=steady)
        return plot_simulation(self, title=title, units=units)

    @classmethod
    def from_states(cls, model, system, times, states, drive, outputs):
        """Derived outputs of the raw states (``outputs``: their ``kn.sample_outputs`` of the kernels
        that produced them, made in parts with the signals heeded by :func:`.simulate._sampled_outputs`)."""
        from scipy.spatial.transform import Rotation

        n = system.n_dof
        count = len(times)
        q, dq = states[:, :n], states[:, n:]
        frame = system.nf > 0
        gamma = q[:, 3:5] @ system.E2.T if frame else np.zeros((count, 3))
        psi = q[:, 5] if system.s else np.zeros(count)
        psi_dot = dq[:, 5] if system.s else np.zeros(count)
        x = q[:, :3] if frame else np.zeros((count, 3))
        theta = gamma + psi[:, None] * system.e
        stator = Rotation.from_rotvec(gamma) * Rotation.from_rotvec(psi[:, None] * system.e)
        kinetic, elastic, weight, torque, omega, wrenches = outputs
        moves, tilts = _relative_motions(system, q)
        centers = np.empty((count, len(model.rotors), 3))
        for j, b in enumerate(system.rotor_index):
            spin = Rotation.from_rotvec((system.ratio[b] * q[:, n - 1])[:, None] * system.e).apply(system.offset[b])
            local = system.center[b] + moves[:, j] + Rotation.from_rotvec(tilts[:, j]).apply(spin)
            centers[:, j] = system.reference_point + x + stator.apply(local)
        ratios = np.array([r.speed_ratio for r in model.rotors])
        weight = weight - system.gravity @ system.reference_point * system.mass.sum()
        return cls(
            time=np.asarray(times), displacement=np.hstack([x, theta]),
            velocity=np.hstack([dq[:, :3] if frame else np.zeros((count, 3)), omega]), gamma=gamma,
            drive_angle=q[:, n - 1], drive_speed=dq[:, n - 1], spin_speed=psi_dot + dq[:, n - 1],
            rotor_angles=psi[:, None] + q[:, n - 1][:, None] * ratios, drive_torque=torque,
            rotor_centers=centers, rotor_displacements=moves, rotor_tilts=tilts, bearing_forces=wrenches,
            sensors=_sensor_signals(model, system, x, stator, moves, tilts), kinetic_energy=kinetic,
            elastic_energy=elastic, gravity_energy=weight, states=np.asarray(states),
            sensor_names=[s.name for s in model.sensors], rotor_names=[r.name for r in model.rotors],
            bearing_names=[b.name for b in model.bearings], speed_ratios=ratios, drive=drive,
            model_name=model.name, frame=_frame_name(model, frame))


def _frame_name(model, moves) -> str:
    """``model.dofs.frame`` of the simulated machine: 'stator', 'frame' (massless) or 'ground'
    (``moves``: whether the frame has coordinates)."""
    if not moves:
        return "ground"
    return "stator" if model.stator is not None else "frame"


def _relative_motions(system, q):
    """Each rotor's translation and transverse Euler vector relative to the frame, frame
    axes, shape (N, n_rotors, 3) each [m, rad] (zeros for a rotor fixed to the frame)."""
    count = q.shape[0]
    moves = np.zeros((count, len(system.rotor_index), 3))
    tilts = np.zeros_like(moves)
    for j, b in enumerate(system.rotor_index):
        first, kt = system.slot[b], system.ntrans[b]
        if first >= 0:
            moves[:, j] = q[:, first:first + kt] @ system.A3[:, :kt].T
            tilts[:, j] = q[:, first + kt:first + kt + 2] @ system.A3[:, :2].T
    return moves, tilts


def _sensor_signals(model, system, x, stator, moves, tilts):
    """Every sensor's reading, shape (N, n_sensors) [m] (see :class:`SimulationResult`)."""
    from scipy.spatial.transform import Rotation

    rotors = [r.name for r in model.rotors]
    out = np.empty((x.shape[0], len(model.sensors)))
    for k, sensor in enumerate(model.sensors):
        point = np.asarray(sensor.position, dtype=float) - system.reference_point
        direction = np.asarray(sensor.direction, dtype=float)
        if sensor.rotor is None:
            out[:, k] = (x + stator.apply(point) - point) @ direction
            continue
        j = rotors.index(sensor.rotor)
        arm = point - system.center[system.rotor_index[j]]
        relative = moves[:, j] + Rotation.from_rotvec(tilts[:, j]).apply(arm) - arm   # frame axes
        if sensor.measure == "relative":
            out[:, k] = relative @ direction
        else:
            out[:, k] = (x + stator.apply(point + relative) - point) @ direction
    return out
