"""An independent computation of a machine's linear dynamics, for the tests.

Nothing here calls ``rotordyn_modal`` (its assembly, geometry or analyses): the reference
reads the plain model description (the TOML structure, a dict) and

* replaces every rigid body (stator with its full, possibly non-principal tensor; each
  rotor) by an exactly equivalent cloud of six point masses (same mass, centre of mass and
  inertia tensor) and forms the mass matrix from the kinetic energy of the particles,
  ``T = 1/2 sum_p m_p |u' + theta' x (r_p - O)|^2``, with coordinates at the model origin O
  (not at the stator's centre of mass, as the package uses);
* forms K (and C) from the potential energy (dissipation function) of springs (dashpots)
  along each suspension's own axes, ``V = 1/2 sum_i k_i (a_i . d_P)^2``, by central finite
  differences (exact for a quadratic); matrix-valued (possibly non-symmetric) suspensions by
  virtual work of the local force ``-K_loc [R d_P; R theta]``;
* derives the gyroscopic term from the rotors' spin angular momentum
  ``H = sum_j J_p,j r_j Omega e``: carried by the small rotation theta it becomes
  ``H + theta x H``, whose rate ``theta' x H`` is the gyroscopic moment on the machine;
* solves the quadratic eigenproblem as a generalized eigenproblem (scipy's QZ), not with
  ``M^-1``;
* defines whirl from the particles' orbits: the orbit of a particle with complex amplitude
  D turns about the spin axis e with mean angular momentum proportional to
  ``m e . Re(i conj(D) x D)``; summed over every particle of the machine and divided by the
  particles' ``sum m |D_perp|^2`` it is +1 for a circular orbit turning about +e.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

__all__ = ["ReferenceMachine", "random_description", "rotation", "inertia_tensor"]


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def particle_cloud(mass, center, inertia):
    """Six point masses with the body's mass, centre of mass and inertia tensor.

    The second moment about the centre is ``Q = tr(J)/2 I - J`` with principal values
    ``(J_j + J_k - J_i)/2 >= 0`` (the triangle inequality); m/6 at ``+-a_i`` along each
    principal axis with ``2 (m/6) a_i^2 = Q_i`` reproduces it.
    """
    inertia = np.asarray(inertia, dtype=float)
    if inertia.shape == (3,):
        inertia = np.diag(inertia)
    second = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    values, vectors = np.linalg.eigh(second)
    values = np.clip(values, 0.0, None)
    points, masses = [], []
    for i in range(3):
        a = np.sqrt(3.0 * values[i] / mass)
        for s in (1.0, -1.0):
            points.append(np.asarray(center, dtype=float) + s * a * vectors[:, i])
            masses.append(mass / 6.0)
    return np.array(masses), np.array(points)


def _jacobian(point):
    """3x6 map from q = [u, theta] at the origin to the displacement of ``point``:
    ``u + theta x point``, built column by column with np.cross."""
    out = np.zeros((3, 6))
    for k in range(3):
        out[k, k] = 1.0
        out[:, 3 + k] = np.cross(np.eye(3)[k], point)
    return out


def _as_local_matrix(value):
    """6x6 local matrix from a 3-list, 6-list, 3x3 or 6x6 value."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 1:
        arr = np.diag(arr)
    out = np.zeros((6, 6))
    out[: arr.shape[0], : arr.shape[1]] = arr
    return out


def _quadratic_hessian(energy, n=6, h=1.0):
    """Hessian of a quadratic form by central differences (exact up to round-off)."""
    out = np.zeros((n, n))
    eye = np.eye(n)
    for i in range(n):
        for j in range(n):
            out[i, j] = (energy(h * (eye[i] + eye[j])) - energy(h * (eye[i] - eye[j]))
                         - energy(h * (eye[j] - eye[i])) + energy(-h * (eye[i] + eye[j]))) / (4 * h * h)
    return out


class ReferenceMachine:
    """The machine of a model description (dict), computed independently.

    Attributes
    ----------
    M, C, G, K : ndarray (6, 6), coordinates ``[u, theta]`` at the model origin, model axes
        (G per unit reference speed).
    masses, points : the particles of every body (all bodies together).
    """

    def __init__(self, data):
        self.data = data
        self.e = _unit(data.get("spin_axis", [1.0, 0.0, 0.0]))
        self.ratios = self._speed_ratios()
        masses, points = [], []
        stator = data.get("stator")
        if stator is not None:
            m, p = particle_cloud(stator["mass"], stator.get("center_of_mass", [0, 0, 0]), stator["inertia"])
            masses.append(m)
            points.append(p)
        for rotor in data.get("rotors", []):
            jp, jd = rotor["polar_inertia"], rotor["diametral_inertia"]
            tensor = jd * np.eye(3) + (jp - jd) * np.outer(self.e, self.e)
            m, p = particle_cloud(rotor["mass"], rotor["center_of_mass"], tensor)
            masses.append(m)
            points.append(p)
        self.masses = np.concatenate(masses)
        self.points = np.concatenate(points)
        self.jacobians = np.array([_jacobian(p) for p in self.points])  # (n_p, 3, 6)
        self.M = np.einsum("p,pai,paj->ij", self.masses, self.jacobians, self.jacobians)
        self.K = self._suspension_matrix("stiffness")
        self.C = self._suspension_matrix("damping")
        momentum = sum(r["polar_inertia"] * self.ratios[r["name"]] for r in data.get("rotors", [])) * self.e
        self.G = np.zeros((6, 6))
        for k in range(3):
            # moment theta'_k unit_k x H appears on the left-hand side: G[:, 3+k]
            self.G[3:, 3 + k] = np.cross(np.eye(3)[k], momentum)

    # -- speed ratios from the transmission graph (gear reverses, belt keeps) --------------
    def _speed_ratios(self):
        rotors = self.data.get("rotors", [])
        ratios = {r["name"]: r["speed_ratio"] for r in rotors if "speed_ratio" in r}
        if rotors:
            ref = self.data.get("reference_rotor", rotors[0]["name"])
            ratios.setdefault(ref, 1.0)
        changed = True
        while changed:
            changed = False
            for t in self.data.get("transmissions", []):
                sign = -1.0 if t["type"] == "gear" else 1.0
                a, b = t["driver"], t["driven"]
                if a in ratios and b not in ratios:
                    ratios[b] = sign * ratios[a] / t["ratio"]
                    changed = True
                elif b in ratios and a not in ratios:
                    ratios[a] = sign * ratios[b] * t["ratio"]
                    changed = True
        return ratios

    # -- suspensions ---------------------------------------------------------------------
    def _suspension_matrix(self, key):
        total = np.zeros((6, 6))
        for s in self.data.get("suspensions", []):
            if key not in s:
                continue
            axes = np.asarray(s.get("axes", np.eye(3)), dtype=float)
            axes = axes / np.linalg.norm(axes, axis=1)[:, None]
            position = np.asarray(s["position"], dtype=float)
            value = np.asarray(s[key], dtype=float)
            jac = _jacobian(position)
            if value.ndim == 1:
                total += self._springs(value, axes, jac)
            else:
                total += self._virtual_work(_as_local_matrix(value), axes, jac)
        return total

    @staticmethod
    def _springs(values, axes, jac):
        """Springs along the suspension's axes (translations) and torsion springs about them."""
        def energy(q):
            d = jac @ q
            theta = q[3:]
            v = sum(values[i] * (axes[i] @ d) ** 2 for i in range(3))
            if len(values) == 6:
                v += sum(values[3 + i] * (axes[i] @ theta) ** 2 for i in range(3))
            return 0.5 * v
        return _quadratic_hessian(energy)

    @staticmethod
    def _virtual_work(local, axes, jac):
        """-dQ/dq where Q is the generalized force (virtual work) of -local [R d_P; R theta]."""
        out = np.zeros((6, 6))
        for j in range(6):
            q = np.eye(6)[j]
            d, theta = jac @ q, q[3:]
            f_loc = -local @ np.concatenate([axes @ d, axes @ theta])
            force, moment = axes.T @ f_loc[:3], axes.T @ f_loc[3:]
            for k in range(6):
                dk = jac[:, k]
                tk = np.eye(6)[k][3:]
                out[k, j] = -(force @ dk + moment @ tk)
        return out

    # -- eigen-solution ------------------------------------------------------------------
    def eig(self, speed):
        """All 12 eigenvalues and the displacement parts of their eigenvectors at ``speed``."""
        n = 6
        D = self.C + speed * self.G
        # lam = gamma mu balances the companion pencil (Fan, Lin & Van Dooren 2004)
        gamma = np.sqrt(np.linalg.norm(self.K, 2) / np.linalg.norm(self.M, 2)) or 1.0
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-self.K / gamma**2, -D / gamma]])
        B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), self.M]])
        values, vectors = scipy.linalg.eig(A, B)
        return gamma * values, vectors[:n].T

    def modes(self, speed):
        """Oscillating modes (Im > 0), sorted by frequency: eigenvalues and shapes (q at O)."""
        values, shapes = self.eig(speed)
        scale = np.abs(values).max()
        keep = values.imag > 1e-7 * scale
        values, shapes = values[keep], shapes[keep]
        order = np.argsort(values.imag)
        return values[order], shapes[order]

    def whirl_ratio(self, shape, speed, reference_ratio=1.0):
        """Signed whirl ratio of a mode shape (q at the origin) vs the reference rotor's spin."""
        D = np.einsum("pai,i->pa", self.jacobians, shape)  # particle amplitudes (n_p, 3)
        momentum = np.einsum("p,pa,a->", self.masses, np.real(1j * np.cross(D.conj(), D)), self.e)
        perp = D - np.outer(D @ self.e, self.e)
        across = np.einsum("p,pa->", self.masses, np.abs(perp) ** 2)
        direction = 1.0 if speed * reference_ratio >= 0 else -1.0
        return direction * momentum / across

    def point_motion(self, shape, point):
        """Displacement amplitude (3,) of a stator point for a shape q at the origin."""
        return _jacobian(np.asarray(point, dtype=float)) @ shape


# ----------------------------------------------------------------------------------------
# Random valid descriptions (plain dicts, as TOML gives them)
# ----------------------------------------------------------------------------------------
def rotation(rng):
    """A random proper rotation matrix."""
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    return q


def inertia_tensor(rng, scale=1.0):
    """A random full inertia tensor (principal moments satisfy the triangle inequality)."""
    a, b = rng.uniform(0.3, 1.0, 2) * scale
    c = rng.uniform(abs(a - b) + 0.05 * scale, a + b - 0.05 * scale)
    R = rotation(rng)
    return R @ np.diag([a, b, c]) @ R.T


def random_description(rng, n_rotors=2, damping=True, transmissions=True, matrix_mount=False):
    """A random valid model description with offset rotors, a non-principal stator tensor,
    inclined anisotropic mounts (own ``axes``) and, optionally, damping and a gear or belt."""
    e = _unit(rng.standard_normal(3))
    data = {
        "name": "random machine",
        "spin_axis": e.tolist(),
        "reference_rotor": "r0",
        "stator": {
            "mass": float(rng.uniform(20, 200)),
            "center_of_mass": rng.uniform(-0.2, 0.2, 3).tolist(),
            "inertia": inertia_tensor(rng, rng.uniform(2, 15)).tolist(),
        },
        "rotors": [],
        "transmissions": [],
        "suspensions": [],
    }
    for j in range(n_rotors):
        jd = float(rng.uniform(0.02, 0.3))
        rotor = {
            "name": f"r{j}",
            "mass": float(rng.uniform(2, 30)),
            "center_of_mass": rng.uniform(-0.4, 0.4, 3).tolist(),
            "polar_inertia": float(jd * rng.uniform(0.2, 2.0)),
            "diametral_inertia": jd,
        }
        if j == 0:
            rotor["speed_ratio"] = 1.0
        elif transmissions:
            data["transmissions"].append({
                "type": str(rng.choice(["gear", "belt"])), "driver": f"r{j - 1}", "driven": f"r{j}",
                "ratio": float(rng.uniform(0.3, 3.0)), "driver_teeth": int(rng.integers(10, 40)),
            })
        else:
            rotor["speed_ratio"] = float(rng.uniform(-3, 3))
        data["rotors"].append(rotor)
    corners = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    for i, (sx, sy) in enumerate(corners):
        s = {
            "name": f"mount-{i}",
            "position": (np.array([0.4 * sx, 0.3 * sy, -0.25]) + rng.uniform(-0.05, 0.05, 3)).tolist(),
            "stiffness": rng.uniform(5e4, 5e5, 3).tolist(),
            "axes": rotation(rng).tolist(),
        }
        if damping:
            s["damping"] = rng.uniform(20, 400, 3).tolist()
        data["suspensions"].append(s)
    if matrix_mount:
        k = rng.uniform(1e4, 1e5) * (np.eye(3) + 0.3 * rng.standard_normal((3, 3)))
        data["suspensions"][0]["stiffness"] = (k @ k.T + 1e4 * np.eye(3)).tolist()
    return data


# ----------------------------------------------------------------------------------------
# Moving and turning a description (every position, vector and tensor)
# ----------------------------------------------------------------------------------------
_POSITIONS = {"stator": ("center_of_mass",), "rotors": ("center_of_mass",),
              "suspensions": ("position",), "sensors": ("position",), "excitations": ("position",)}


def translated(data, shift):
    """The same machine with the model origin moved: every position + ``shift``."""
    import copy

    out = copy.deepcopy(data)
    shift = np.asarray(shift, dtype=float)
    for table, keys in _POSITIONS.items():
        if table == "stator":
            items = [out["stator"]] if "stator" in out else []
        else:
            items = out.get(table, [])
        for item in items:
            for key in keys:
                default = [0.0, 0.0, 0.0] if key == "center_of_mass" and table == "stator" else None
                if key in item or default is not None:
                    item[key] = (np.asarray(item.get(key, default), dtype=float) + shift).tolist()
    return out


def rotated(data, R):
    """The same machine described in turned model axes: vectors R v, tensors R J R^T,
    suspension axes (rows) a R^T; local stiffness and damping are unchanged."""
    import copy

    out = copy.deepcopy(data)
    R = np.asarray(R, dtype=float)
    out["spin_axis"] = (R @ np.asarray(data.get("spin_axis", [1, 0, 0]), dtype=float)).tolist()
    if "stator" in out:
        st = out["stator"]
        J = np.asarray(st["inertia"], dtype=float)
        J = np.diag(J) if J.ndim == 1 else J
        st["inertia"] = (R @ J @ R.T).tolist()
        st["center_of_mass"] = (R @ np.asarray(st.get("center_of_mass", [0, 0, 0]), dtype=float)).tolist()
    for rotor in out.get("rotors", []):
        rotor["center_of_mass"] = (R @ np.asarray(rotor["center_of_mass"], dtype=float)).tolist()
    for s in out.get("suspensions", []):
        s["position"] = (R @ np.asarray(s["position"], dtype=float)).tolist()
        s["axes"] = (np.asarray(s.get("axes", np.eye(3)), dtype=float) @ R.T).tolist()
    for table in ("sensors", "excitations"):
        for item in out.get(table, []):
            for key in ("position", "direction"):
                if key in item:
                    item[key] = (R @ np.asarray(item[key], dtype=float)).tolist()
    return out
