"""An independent computation of rotor-bearing-casing machines, for the tests.

Nothing here calls ``rotordyn_modal``. The package describes a rotor on bearings by its
motion *relative* to the stator at its centre of mass (4 or 5 coordinates); this reference
gives every body six *absolute* coordinates ``[u, theta]`` at the model origin and imposes
what the bearings do not allow as linear constraints, solved by a null-space basis:

* the rotor turns with the stator about the spin axis (its spin is fixed by the drive):
  ``e . (theta_rotor - theta_stator) = 0``;
* without an axial stiffness the rotor follows the stator axially at its centre of mass:
  ``e . (d_rotor(R) - d_stator(R)) = 0``;
* without a stator and with bearings the stator is the ground: ``q_stator = 0``; a rotor
  without bearings moves with the stator (``q_rotor = q_stator``).

Mass from the kinetic energy of particle clouds (``reference_model.particle_cloud``), the
bearings' stiffness and damping from the virtual work of the local force
``-K_loc [R d_rel; R theta_rel]`` at the bearing point (``d_rel`` the rotor point's
displacement minus the stator point's), each rotor's gyroscopic moment ``theta_j' x H_j``
on its own rotation (``H_j = J_p,j r_j Omega e``), suspensions by finite differences of
their energy. Eigenvalues by QZ on the balanced companion pencil.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import scipy.linalg

from reference_model import ReferenceMachine, _jacobian, particle_cloud

__all__ = ["BearingMachine", "random_bearing_description"]


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _local2(value):
    """A 2x2 matrix from a scalar, a 2-list or a 2x2 value."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return arr * np.eye(2)
    if arr.ndim == 1:
        return np.diag(arr)
    return arr


def _transverse(e):
    """The package's documented transverse axes (docs/model-file.md): the model axis after
    e's largest component (x->y->z->x), made normal to e, and e x a."""
    following = np.eye(3)[(int(np.argmax(np.abs(e))) + 1) % 3]
    a = _unit(following - (following @ e) * e)
    return a, np.cross(e, a)


class BearingMachine:
    """Absolute-coordinate reference of a description with ``bearings`` (a dict).

    Attributes
    ----------
    Z : ndarray (6 n_bodies, n_free)
        Null-space basis of the constraints.
    M, C, G, K : reduced matrices (n_free, n_free); G per unit reference speed.
    """

    def __init__(self, data):
        self.data = data
        self.e = _unit(data.get("spin_axis", [1.0, 0.0, 0.0]))
        self.ratios = ReferenceMachine._speed_ratios(self)
        self.rotor_names = [r["name"] for r in data.get("rotors", [])]
        self.bodies = ["stator"] + self.rotor_names
        n = 6 * len(self.bodies)
        self.n_full = n
        M = np.zeros((n, n))
        stator = data.get("stator")
        if stator is not None:
            M[:6, :6] = self._body_mass(stator["mass"], stator.get("center_of_mass", [0, 0, 0]),
                                        stator["inertia"])
        G = np.zeros((n, n))
        for j, rotor in enumerate(data.get("rotors", [])):
            jp, jd = rotor["polar_inertia"], rotor["diametral_inertia"]
            tensor = jd * np.eye(3) + (jp - jd) * np.outer(self.e, self.e)
            block = self._block(j + 1)
            M[block, block] = self._body_mass(rotor["mass"], rotor["center_of_mass"], tensor)
            momentum = jp * self.ratios[rotor["name"]] * self.e
            rot = slice(6 * (j + 1) + 3, 6 * (j + 1) + 6)
            for k in range(3):
                G[rot, 6 * (j + 1) + 3 + k] = np.cross(np.eye(3)[k], momentum)
        K, C = np.zeros((n, n)), np.zeros((n, n))
        mounts = SimpleNamespace(data=data, _springs=ReferenceMachine._springs,
                                 _virtual_work=ReferenceMachine._virtual_work)
        K[:6, :6] += ReferenceMachine._suspension_matrix(mounts, "stiffness")
        C[:6, :6] += ReferenceMachine._suspension_matrix(mounts, "damping")
        for b in data.get("bearings", []):
            K += self._bearing_matrix(b, "stiffness", "axial_stiffness", "moment_stiffness")
            C += self._bearing_matrix(b, "damping", "axial_damping", "moment_damping")
        self.Z = self._free_basis()
        self.M_full, self.G_full, self.K_full, self.C_full = M, G, K, C
        self.M, self.G, self.K, self.C = (self.Z.T @ X @ self.Z for X in (M, G, K, C))

    @staticmethod
    def _block(index):
        return slice(6 * index, 6 * index + 6)

    @staticmethod
    def _body_mass(mass, center, inertia):
        masses, points = particle_cloud(mass, center, inertia)
        jac = np.array([_jacobian(p) for p in points])
        return np.einsum("p,pai,paj->ij", masses, jac, jac)

    # -- bearings ------------------------------------------------------------------------
    def _axes(self, b):
        if "axes" in b:
            a, c = (_unit(v) for v in np.asarray(b["axes"], dtype=float))
        else:
            a, c = _transverse(self.e)
        return np.array([a, c, np.cross(a, c)])

    def _relative(self, b):
        """6 x n_full map from all coordinates to [d_rel, theta_rel] at the bearing point."""
        j = self.rotor_names.index(b["rotor"]) + 1
        point = np.asarray(b["position"], dtype=float)
        out = np.zeros((6, self.n_full))
        jac = _jacobian(point)
        out[:3, self._block(j)] = jac
        out[:3, :6] -= jac
        out[3:, 6 * j + 3:6 * j + 6] = np.eye(3)
        out[3:, 3:6] -= np.eye(3)
        return out

    def _bearing_matrix(self, b, radial_key, axial_key, moment_key):
        local = np.zeros((6, 6))
        if radial_key in b:
            local[:2, :2] = _local2(b[radial_key])
        if axial_key in b:
            local[2, 2] = float(b[axial_key])
        if moment_key in b:
            local[3:5, 3:5] = _local2(b[moment_key])
        axes = self._axes(b)
        relative = self._relative(b)
        out = np.zeros((self.n_full, self.n_full))
        for col in range(self.n_full):
            d = relative[:, col]
            local_force = -local @ np.concatenate([axes @ d[:3], axes @ d[3:]])
            force, moment = axes.T @ local_force[:3], axes.T @ local_force[3:]
            # the force acts on the rotor at the point, its reaction on the stator
            out[:, col] = -(relative[:3].T @ force + relative[3:].T @ moment)
        return out

    # -- constraints ---------------------------------------------------------------------
    def _free_basis(self):
        rows = []
        on_bearings = {b["rotor"] for b in self.data.get("bearings", [])}
        axial = {b["rotor"] for b in self.data.get("bearings", []) if "axial_stiffness" in b}
        if self.data.get("stator") is None and on_bearings:
            rows += list(np.eye(self.n_full)[:6])
        for j, name in enumerate(self.rotor_names, start=1):
            if name not in on_bearings:
                rows += list(np.eye(self.n_full)[6 * j:6 * j + 6] - np.eye(self.n_full)[:6])
                continue
            spin = np.zeros(self.n_full)
            spin[6 * j + 3:6 * j + 6] = self.e
            spin[3:6] = -self.e
            rows.append(spin)
            if name not in axial:
                centre = np.asarray(self.data["rotors"][j - 1]["center_of_mass"], dtype=float)
                row = np.zeros(self.n_full)
                row[6 * j:6 * j + 6] = self.e @ _jacobian(centre)
                row[:6] = -self.e @ _jacobian(centre)
                rows.append(row)
        if not rows:
            return np.eye(self.n_full)
        return scipy.linalg.null_space(np.array(rows))

    # -- solutions -----------------------------------------------------------------------
    def _companion(self, speed):
        """Balanced companion pencil (A, B) in the time unit 1 / gamma, and gamma."""
        n = self.M.shape[0]
        D = self.C + speed * self.G
        gamma = np.sqrt(np.linalg.norm(self.K, 2) / np.linalg.norm(self.M, 2)) or 1.0
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-self.K / gamma**2, -D / gamma]])
        B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), self.M]])
        return A, B, gamma

    def eigenvalues(self, speed):
        """All eigenvalues at ``speed`` [rad/s] (QZ on the balanced companion pencil)."""
        A, B, gamma = self._companion(speed)
        return gamma * scipy.linalg.eigvals(A, B)

    def modes(self, speed):
        """Oscillating roots (Im > 0) by frequency: eigenvalues and shapes (free coordinates)."""
        A, B, gamma = self._companion(speed)
        values, vectors = scipy.linalg.eig(A, B)
        values = gamma * values
        keep = values.imag > 1e-7 * np.abs(values).max()
        order = np.argsort(values.imag[keep])
        return values[keep][order], vectors[:self.M.shape[0], keep][:, order].T

    def whirl_ratio(self, shape, speed):
        """Signed whirl ratio of a shape (free coordinates) against the first rotor's spin:
        the particles' mass-weighted angular momentum about the spin axis over their
        mass-weighted square motion normal to it, every body's particles together."""
        full = self.Z @ shape
        momentum = across = 0.0
        for j, (masses, jacobians) in enumerate(self._clouds()):
            if masses is None:
                continue  # the ground
            D = jacobians @ full[self._block(j)]  # particle displacements (n_p, 3)
            momentum += np.einsum("p,pa,a->", masses, np.real(1j * np.cross(D.conj(), D)), self.e)
            perp = D - np.outer(D @ self.e, self.e)
            across += np.einsum("p,pa->", masses, np.abs(perp) ** 2)
        first = self.ratios[self.rotor_names[0]]
        return (1.0 if speed * first >= 0 else -1.0) * momentum / across

    def _clouds(self):
        """(masses, jacobians (n_p, 3, 6)) of each body's particle cloud; (None, None) for a
        ground stator."""
        if getattr(self, "_cloud_cache", None) is None:
            stator = self.data.get("stator")
            clouds = [(None, None) if stator is None else
                      particle_cloud(stator["mass"], stator.get("center_of_mass", [0, 0, 0]), stator["inertia"])]
            for rotor in self.data.get("rotors", []):
                jp, jd = rotor["polar_inertia"], rotor["diametral_inertia"]
                tensor = jd * np.eye(3) + (jp - jd) * np.outer(self.e, self.e)
                clouds.append(particle_cloud(rotor["mass"], rotor["center_of_mass"], tensor))
            self._cloud_cache = [(None, None) if masses is None else
                                 (masses, np.array([_jacobian(p) for p in points])) for masses, points in clouds]
        return self._cloud_cache

    def receptance(self, speed, omega, force_at, force_dir, force_body, sensor_at, sensor_dir, sensor_body):
        """Displacement of a body point along a direction per unit force at a body point."""
        def rows(point, direction, body):
            j = self.bodies.index(body or "stator")
            out = np.zeros(self.n_full)
            out[self._block(j)] = np.asarray(direction, dtype=float) @ _jacobian(np.asarray(point, dtype=float))
            return out @ self.Z
        Zd = self.K + 1j * omega * (self.C + speed * self.G) - omega**2 * self.M
        return rows(sensor_at, sensor_dir, sensor_body) @ np.linalg.solve(Zd, rows(force_at, force_dir, force_body))


def random_bearing_description(rng, n_rotors=2, stator=True, damping=True, axial=True):
    """A random valid machine: a stator on inclined mounts (or none: bearings to ground),
    rotors with offset centres, some on two bearings with cross-coupled, non-symmetric
    coefficients, some rigidly attached, geared."""
    from reference_model import random_description

    data = random_description(rng, n_rotors=n_rotors, damping=damping)
    if not stator:
        data.pop("stator")
        data["suspensions"] = []
    e = _unit(data["spin_axis"])
    data["bearings"] = []
    for j, rotor in enumerate(data["rotors"]):
        if stator and j == n_rotors - 1 and n_rotors > 1:
            continue  # the last rotor stays rigidly attached
        centre = np.asarray(rotor["center_of_mass"], dtype=float)
        for side, s in (("A", rng.uniform(0.05, 0.3)), ("B", -rng.uniform(0.05, 0.3))):
            k = rng.uniform(2e5, 5e6)
            bearing = {
                "name": f"{rotor['name']}-{side}", "rotor": rotor["name"],
                "position": (centre + s * e).tolist(),
                "stiffness": (k * (np.eye(2) + 0.3 * rng.standard_normal((2, 2)) * [[0.2, 1], [1, 0.2]])).tolist(),
            }
            if damping:
                c = rng.uniform(50, 800)
                bearing["damping"] = (c * (np.eye(2) + 0.1 * rng.standard_normal((2, 2)))).tolist()
            if axial and side == "A":
                bearing["axial_stiffness"] = float(rng.uniform(1e5, 1e6))
            if rng.uniform() < 0.5:
                bearing["moment_stiffness"] = rng.uniform(1e2, 1e4, 2).tolist()
            if rng.uniform() < 0.5:
                angle = rng.uniform(0, np.pi)
                a, b = _transverse(e)
                bearing["axes"] = [(np.cos(angle) * a + np.sin(angle) * b).tolist(),
                                   (-np.sin(angle) * a + np.cos(angle) * b).tolist()]
            data["bearings"].append(bearing)
    return data


def with_mount_channels(data):
    """``data`` with three sensors and three excitations colocated at its first three mounts,
    along x, y and z (stator points: every machine of :func:`random_bearing_description` with a
    stator has them)."""
    points = [(s["position"], axis) for s, axis in zip(data["suspensions"], np.eye(3).tolist())]
    data["sensors"] = [{"name": f"s{i}", "position": p, "direction": d} for i, (p, d) in enumerate(points)]
    data["excitations"] = [{"name": f"e{i}", "position": p, "direction": d} for i, (p, d) in enumerate(points)]
    return data
