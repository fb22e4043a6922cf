"""Flexible shafts: materials, shear coefficients and Timoshenko beam finite elements.

A shaft is a chain of elements along the spin axis ``e``; each element is a hollow circular
section, uniform or a conical frustum (outer and inner diameters varying linearly from the
left end to the right end). Per node the six motions are ordered like every rigid body's in
this package, ``[u_a, u_b, u_e, theta_a, theta_b, theta_e]`` (``a, b`` the transverse axes
with ``a x b = e``, theta the small rotation vector): a rigid rotation ``theta_b`` moves
``u_a = +theta_b z``, ``theta_a`` moves ``u_b = -theta_a z`` (``docs/theory.md``, "Flexible
shafts: Timoshenko beam elements").

The lateral interpolation is the Timoshenko element of Nelson (1980) and Friswell et al.
(2010, section 5.4): cubic displacements and quadratic rotations that solve the static
Timoshenko beam with nodal loads, with the shear parameter ``Phi = 12 E I / (kappa G A L^2)``
of the section at mid-element. Tapered elements keep these shape functions and integrate
the energies with the frustum's exact area and second moment along the element (Genta and
Gugliotta 1988), as ROSS does: the lateral matrices equal ROSS's ``ShaftElement`` (same
per-node order and signs). Axial and torsional motions are linear rods, integrated exactly
(ROSS takes the mean of the end sections: the same for uniform elements).

Pure numpy: nothing here knows the model; :mod:`rotordyn_modal.io.model_file` and the
assembly call it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

__all__ = ["Material", "SHEAR_METHODS", "MassProperties", "material_problem", "section_problem",
           "shear_coefficient", "element_matrices", "shaft_matrices", "shaft_mass_properties",
           "free_free_frequencies", "lateral_deflection"]

#: the shear coefficients a shaft may use (``shear_coefficient``'s ``method``)
SHEAR_METHODS = ("cowper", "hutchinson", "none")

#: Gauss-Legendre points and weights on [0, 1]: 5 points integrate every energy of a
#: frustum element exactly (highest degree 8: a cubic squared times a quadratic area, a
#: quadratic rotation squared times a quartic second moment).
_XI, _WEIGHTS = (lambda x, w: ((x + 1.0) / 2.0, w / 2.0))(*np.polynomial.legendre.leggauss(5))

# per-node offsets of the two bending planes: (a, e) carries (u_a, theta_b) with
# theta_b = +du_a/dz; (b, e) carries (u_b, -theta_a) since theta_a = -du_b/dz.
_PLANE_A = (np.array([0, 4, 6, 10]), np.array([1.0, 1.0, 1.0, 1.0]))
_PLANE_B = (np.array([1, 3, 7, 9]), np.array([1.0, -1.0, 1.0, -1.0]))


@dataclass(frozen=True)
class Material:
    """An isotropic, linear elastic shaft material.

    Parameters
    ----------
    name : str
    density : float
        [kg/m^3]
    young_modulus : float
        E [Pa]
    shear_modulus : float
        G [Pa]
    allowable_stress : float or None
        [Pa] the largest von Mises stress the static check allows in a shaft of this material
        (``static``'s stress verdict); None: not judged.
    """

    name: str
    density: float
    young_modulus: float
    shear_modulus: float
    allowable_stress: float | None = None

    @classmethod
    def from_poisson(cls, name: str, density: float, young_modulus: float, poisson_ratio: float) -> "Material":
        """The material with ``G = E / (2 (1 + nu))``.

        Parameters
        ----------
        name : str
        density : float
            [kg/m^3]
        young_modulus : float
            [Pa]
        poisson_ratio : float
            [-], in (-1, 0.5]
        """
        return cls(name, float(density), float(young_modulus), float(young_modulus) / (2.0 * (1.0 + float(poisson_ratio))))

    @property
    def poisson_ratio(self) -> float:
        """``nu = E / (2 G) - 1`` [-]."""
        return self.young_modulus / (2.0 * self.shear_modulus) - 1.0


#: densities [kg/m^3] of solids, balsa to osmium: outside, a value in g/cm^3 (7.85) or t/mm^3
#: (7.85e-9, finite element tools' unit) typed for kg/m^3 is likely
PLAUSIBLE_DENSITY = (100.0, 25_000.0)
#: Young's moduli [Pa] of solids, soft rubber to diamond: outside, a value in GPa (200) or MPa
#: = N/mm^2 (210000) typed for Pa is likely
PLAUSIBLE_YOUNG_MODULUS = (1e6, 1.5e12)


def material_implausible(material) -> list[tuple[str, float, str]]:
    """A material's legal numbers that no solid has, each ``(key, value, why)``: a density or
    Young's modulus outside :data:`PLAUSIBLE_DENSITY` / :data:`PLAUSIBLE_YOUNG_MODULUS`,
    most likely a value in other units (the model file is SI: kg/m^3 and Pa)."""
    out = []
    for key, value, (low, high), unit, hint in (
            ("density", material.density, PLAUSIBLE_DENSITY, "kg/m^3", "g/cm^3 or t/mm^3"),
            ("young_modulus", material.young_modulus, PLAUSIBLE_YOUNG_MODULUS, "Pa", "GPa or MPa (N/mm^2)")):
        if not low <= value <= high:
            out.append((key, value, f"outside the {low:g} to {high:g} {unit} of solids; a value in {hint} "
                                    f"typed for {unit}? (model files are SI)"))
    return out


def material_problem(density, young_modulus, shear_modulus=None, poisson_ratio=None):
    """The first thing wrong with a material's numbers, or None.

    The numbers are assumed finite and of a sane magnitude already (the model file's reader
    checks that); this checks the physics.

    Parameters
    ----------
    density, young_modulus : float or None
        [kg/m^3], [Pa]; None when missing.
    shear_modulus, poisson_ratio : float or None
        Exactly one of the two must be given.

    Returns
    -------
    tuple (key, value, expected) or None
        ``expected`` is a fragment for ``ModelError(source, where + "." + key, value, expected)``.
    """
    for key, value, unit in (("density", density, "kg/m^3"), ("young_modulus", young_modulus, "Pa")):
        if value is None:
            return key, value, f"a number > 0 [{unit}] (a material needs density and young_modulus)"
        if not value > 0:
            return key, value, f"a number > 0 [{unit}]"
    if (shear_modulus is None) == (poisson_ratio is None):
        key = "shear_modulus" if shear_modulus is not None else "poisson_ratio"
        return key, shear_modulus, "exactly one of shear_modulus [Pa] and poisson_ratio"
    if poisson_ratio is not None:
        if not -1.0 < poisson_ratio <= 0.5:
            return "poisson_ratio", poisson_ratio, "a number in (-1, 0.5]"
        return None
    if not shear_modulus > 0:
        return "shear_modulus", shear_modulus, "a number > 0 [Pa]"
    nu = young_modulus / (2.0 * shear_modulus) - 1.0
    if not nu <= 0.5:
        return ("shear_modulus", shear_modulus,
                f"a shear modulus >= young_modulus / 3 = {young_modulus / 3.0:.6g} Pa (Poisson's ratio "
                f"young_modulus / (2 shear_modulus) - 1 = {nu:.4g} must not exceed 0.5)")
    if not nu > -1.0:   # a shear modulus so large that 1 + nu rounds to 0: the shear coefficient is 0
        return ("shear_modulus", shear_modulus,
                f"a shear modulus that leaves Poisson's ratio young_modulus / (2 shear_modulus) - 1 above -1 "
                f"(here {young_modulus:.6g} / (2 x {shear_modulus:.6g}) rounds it to -1; solids have G below "
                f"about young_modulus = {young_modulus:.6g} Pa)")
    return None


def section_problem(length, outer, inner=0.0):
    """The first thing wrong with a shaft section's geometry, or None.

    Parameters
    ----------
    length : float
        [m]
    outer, inner : float or (left, right)
        Diameters [m].

    Returns
    -------
    tuple (key, value, expected) or None
        Keys ``length``, ``outer_diameter``, ``inner_diameter``.
    """
    if not length > 0:
        return "length", length, "a length > 0 [m]"
    outer_pair, inner_pair = _pair(outer), _pair(inner)
    if not min(outer_pair) > 0:
        return "outer_diameter", outer, "diameters > 0 [m]"
    if not min(inner_pair) >= 0:
        return "inner_diameter", inner, "diameters >= 0 [m]"
    if not (inner_pair[0] < outer_pair[0] and inner_pair[1] < outer_pair[1]):
        return "inner_diameter", inner, f"an inner diameter below the outer diameter {outer!r} at both ends"
    return None


def shear_coefficient(outer: float, inner: float, poisson: float, method: str = "cowper") -> float:
    """Shear coefficient ``kappa`` of a hollow circular section.

    Parameters
    ----------
    outer, inner : float
        Diameters [m] (only their ratio ``m = inner / outer`` matters).
    poisson : float
        Poisson's ratio [-].
    method : {'cowper', 'hutchinson', 'none'}
        * ``'cowper'`` (Cowper 1966, as ROSS's default):
          ``6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2)``;
        * ``'hutchinson'`` (Hutchinson 2001, hollow circle):
          ``6 (1 + nu)^2 (1 + m^2)^2 / ((7 + 12 nu + 4 nu^2) (1 + m^2)^2 + 4 m^2 (5 + 6 nu + 2 nu^2))``,
          ``6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2)`` for a solid circle;
        * ``'none'``: no shear deformation (Euler-Bernoulli): ``inf``.

    Returns
    -------
    float
        [-]
    """
    m2 = (inner / outer) ** 2
    r12 = (1.0 + m2) ** 2
    nu = poisson
    if method == "cowper":
        return 6.0 * (1.0 + nu) * r12 / ((7.0 + 6.0 * nu) * r12 + (20.0 + 12.0 * nu) * m2)
    if method == "hutchinson":
        return (6.0 * (1.0 + nu) ** 2 * r12
                / ((7.0 + 12.0 * nu + 4.0 * nu ** 2) * r12 + 4.0 * m2 * (5.0 + 6.0 * nu + 2.0 * nu ** 2)))
    if method == "none":
        return math.inf
    raise ValueError(f"shear method {method!r}: expected one of {', '.join(SHEAR_METHODS)}")


def element_matrices(length: float, outer, inner, material: Material, shear: str = "cowper", *,
                     rotary_inertia: bool = True):
    """Mass, stiffness and gyroscopic matrices of one Timoshenko shaft element.

    Parameters
    ----------
    length : float
        L [m] > 0.
    outer, inner : float or (left, right)
        Outer and inner (bore) diameters [m]; a pair makes a tapered element (a conical
        frustum, diameters linear along the element).
    material : Material
    shear : {'cowper', 'hutchinson', 'none'} or float
        Shear coefficient of :func:`shear_coefficient` (of the mean diameters); ``'none'``
        drops shear deformation (``Phi = 0``); a number > 0 is the coefficient itself (e.g.
        what another code computed for this element).
    rotary_inertia : bool
        Keep the sections' rotary inertia in M (False: the Euler-Bernoulli beam's mass).

    Returns
    -------
    M, K, G : ndarray, shape (12, 12)
        On ``[node1 (6), node2 (6)]``, each node ``[u_a, u_b, u_e, theta_a, theta_b, theta_e]``
        [kg, kg m, kg m^2; N/m, N, N m; kg m^2]. G is per unit spin speed of the shaft
        (``M q'' + Omega G q' + K q = f``); for a rigid rotation of the element it equals
        ``-J_p skew(e)`` on the rotations.
    """
    geometry = _Frustum(length, outer, inner)
    plane_mass, plane_stiffness, G = _bending(geometry, material, _shear_parameter(geometry, material, shear),
                                              rotary_inertia)
    M, K = np.zeros((12, 12)), np.zeros((12, 12))
    for index, sign in (_PLANE_A, _PLANE_B):
        block, signs = np.ix_(index, index), np.outer(sign, sign)
        M[block] += signs * plane_mass
        K[block] += signs * plane_stiffness
    for index, (mass, stiffness) in zip(([2, 8], [5, 11]), _rods(geometry, material)):
        M[np.ix_(index, index)] += mass
        K[np.ix_(index, index)] += stiffness
    return M, K, G


def lateral_deflection(length: float, outer, inner, material: Material, node_values, xi, shear: str = "cowper"):
    """Lateral displacement inside one element from its nodes' motions, with the element's own
    (Timoshenko) shape functions: the line the element's matrices assume.

    Parameters
    ----------
    length, outer, inner, material, shear
        As :func:`element_matrices`.
    node_values : array_like, shape (8,) or (8, ...), real or complex
        ``[u_a1, u_b1, theta_a1, theta_b1, u_a2, u_b2, theta_a2, theta_b2]`` [m, rad] of the
        left and right node (local axes ``a, b``).
    xi : array_like, shape (P,)
        Positions in the element, ``z / L`` in [0, 1].

    Returns
    -------
    ndarray, shape (2, P) + node_values.shape[1:]
        ``u_a`` and ``u_b`` [m] at each ``xi``: equal to the nodes' values at ``xi = 0, 1``,
        and exact for every rigid motion (a line ``u = c + theta z``).
    """
    geometry = _Frustum(length, outer, inner)
    w = _plane_functions(np.asarray(xi, dtype=float), length, _shear_parameter(geometry, material, shear))[0]
    q = np.asarray(node_values)
    plane_a = q[[0, 3, 4, 7]]                                   # (u_a, theta_b): theta_b = +du_a/dz
    plane_b = q[[1, 2, 5, 6]] * np.array([1.0, -1.0, 1.0, -1.0]).reshape((4,) + (1,) * (q.ndim - 1))
    return np.stack([np.tensordot(w.T, plane_a, axes=1), np.tensordot(w.T, plane_b, axes=1)])


def _bending(geometry: "_Frustum", material: Material, phi: float, rotary_inertia: bool):
    """One bending plane's mass and stiffness (4 x 4 on ``(w1, psi1, w2, psi2)``) and the
    element's gyroscopic matrix (12 x 12), integrated exactly over the frustum."""
    rho, E, length = material.density, material.young_modulus, geometry.length
    dz = _WEIGHTS * length
    area, moment = geometry.area(_XI), geometry.second_moment(_XI)
    w, psi, dpsi, gamma = _plane_functions(_XI, length, phi)          # each (4, points)
    # kappa G = 12 E I_mid / (Phi A_mid L^2): the shear energy kappa G A gamma^2 written with
    # gamma / Phi (finite as Phi -> 0, when the shear term vanishes).
    shear_factor = 12.0 * E * geometry.second_moment(0.5) / (geometry.area(0.5) * length ** 2)
    mass = (w * (dz * rho * area)) @ w.T
    if rotary_inertia:
        mass += (psi * (dz * rho * moment)) @ psi.T
    stiffness = (dpsi * (dz * E * moment)) @ dpsi.T + (gamma * (dz * shear_factor * phi * area)) @ gamma.T
    theta_a, theta_b = np.zeros((12, _XI.size)), np.zeros((12, _XI.size))
    theta_b[_PLANE_A[0]] = _PLANE_A[1][:, None] * psi
    theta_a[_PLANE_B[0]] = -_PLANE_B[1][:, None] * psi
    # -rho I_p N^T skew(e) N with skew(e) = [[0, -1], [1, 0]] on (theta_a, theta_b)
    cross = (theta_a * (dz * rho * 2.0 * moment)) @ theta_b.T
    return _symmetric(mass), _symmetric(stiffness), cross - cross.T


def _rods(geometry: "_Frustum", material: Material):
    """(mass, stiffness) 2 x 2 of the axial rod and of torsion, linear shape functions,
    integrated exactly over the frustum."""
    dz = _WEIGHTS * geometry.length
    n = np.array([1.0 - _XI, _XI])
    spring = np.array([[1.0, -1.0], [-1.0, 1.0]]) / geometry.length ** 2
    out = []
    for section, modulus in ((geometry.area(_XI), material.young_modulus),
                             (2.0 * geometry.second_moment(_XI), material.shear_modulus)):
        out.append((_symmetric((n * (dz * material.density * section)) @ n.T), spring * modulus * float(dz @ section)))
    return out


def _symmetric(matrix: np.ndarray) -> np.ndarray:
    """The symmetric part: a product ``(X f) @ X.T`` is symmetric only to round-off."""
    return 0.5 * (matrix + matrix.T)


def shaft_matrices(lengths, outers, inners, materials, shear: str = "cowper", *, rotary_inertia: bool = True):
    """M, K, G of a chain of shaft elements on its nodes.

    Element ``i`` joins node ``i`` (its left end) to node ``i + 1``.

    Parameters
    ----------
    lengths : sequence of float, length n
        Element lengths [m].
    outers, inners : sequence, length n
        Each a diameter [m] or a (left, right) pair (see :func:`element_matrices`).
    materials : Material or sequence of Material, length n
    shear : {'cowper', 'hutchinson', 'none'} or float
    rotary_inertia : bool

    Returns
    -------
    M, K, G : ndarray, shape (6 (n + 1), 6 (n + 1))
        Node ``j``'s motions ``[u_a, u_b, u_e, theta_a, theta_b, theta_e]`` at rows
        ``6 j ... 6 j + 5``.
    """
    lengths = [float(v) for v in lengths]
    materials = _per_element(materials, len(lengths))
    size = 6 * (len(lengths) + 1)
    out = [np.zeros((size, size)) for _ in range(3)]
    for i, (length, outer, inner, material) in enumerate(zip(lengths, outers, inners, materials, strict=True)):
        block = slice(6 * i, 6 * i + 12)
        for total, part in zip(out, element_matrices(length, outer, inner, material, shear,
                                                     rotary_inertia=rotary_inertia)):
            total[block, block] += part
    return tuple(out)


def free_free_frequencies(lengths, outers, inners, materials, shear: str = "cowper", count: int = 1, *,
                          rotary_inertia: bool = True) -> np.ndarray:
    """The lowest bending natural frequencies of a bare shaft, free at both ends, at rest.

    One bending plane is solved (the section is round: the other plane repeats the same
    frequencies); its two rigid-body modes (translation and tilt) are left out.

    Parameters
    ----------
    lengths, outers, inners, materials, shear, rotary_inertia
        As :func:`shaft_matrices`.
    count : int
        How many frequencies, at most ``2 n`` for ``n`` elements.

    Returns
    -------
    ndarray, shape (count,)
        [rad/s], ascending.
    """
    import scipy.linalg

    M, K, _ = shaft_matrices(lengths, outers, inners, materials, shear, rotary_inertia=rotary_inertia)
    plane = np.concatenate([6 * j + np.array([0, 4]) for j in range(M.shape[0] // 6)])
    count = min(int(count), plane.size - 2)
    values = scipy.linalg.eigh(K[np.ix_(plane, plane)], M[np.ix_(plane, plane)], eigvals_only=True,
                               subset_by_index=[2, 1 + count])
    return np.sqrt(np.maximum(values, 0.0))


class MassProperties(NamedTuple):
    """Rigid-body mass properties of a shaft.

    Attributes
    ----------
    mass : float
        [kg]
    center_of_mass : float
        [m] along the axis from the shaft's start (its first node).
    polar_inertia : float
        About the spin axis [kg m^2].
    diametral_inertia : float
        About a transverse axis through the centre of mass [kg m^2].
    """

    mass: float
    center_of_mass: float
    polar_inertia: float
    diametral_inertia: float


def shaft_mass_properties(lengths, outers, inners, materials) -> MassProperties:
    """Mass, centre of mass and inertias of a chain of (hollow, possibly conical) sections.

    Exact integrals over each frustum (Gauss-Legendre on polynomials of degree <= 4).

    Parameters
    ----------
    lengths, outers, inners, materials
        As :func:`shaft_matrices`.

    Returns
    -------
    MassProperties
    """
    lengths = [float(v) for v in lengths]
    materials = _per_element(materials, len(lengths))
    mass = first = second = polar = own = 0.0
    start = 0.0
    for length, outer, inner, material in zip(lengths, outers, inners, materials, strict=True):
        geometry = _Frustum(length, outer, inner)
        rho = material.density
        for xi, weight in zip(_XI, _WEIGHTS):
            dm = rho * geometry.area(xi) * weight * length
            z = start + xi * length
            mass += dm
            first += dm * z
            second += dm * z * z
            polar += rho * 2.0 * geometry.second_moment(xi) * weight * length
            own += rho * geometry.second_moment(xi) * weight * length
        start += length
    center = first / mass
    return MassProperties(mass, center, polar, own + second - mass * center * center)


class _Frustum:
    """A hollow conical frustum: diameters linear in ``xi = z / L`` in [0, 1]."""

    def __init__(self, length, outer, inner):
        problem = section_problem(length, outer, inner)
        if problem:
            key, value, expected = problem
            raise ValueError(f"shaft element {key} = {value!r}: expected {expected}")
        self.length = float(length)
        self.outer, self.inner = _pair(outer), _pair(inner)

    def diameters(self, xi):
        """Outer and inner diameter at ``xi`` [m]."""
        (ol, orr), (il, ir) = self.outer, self.inner
        return ol + (orr - ol) * xi, il + (ir - il) * xi

    def area(self, xi) -> float:
        """Cross-section area at ``xi`` [m^2]."""
        do, di = self.diameters(xi)
        return math.pi / 4.0 * (do * do - di * di)

    def second_moment(self, xi) -> float:
        """Second moment of area about a diameter at ``xi`` [m^4] (polar: twice this)."""
        do, di = self.diameters(xi)
        return math.pi / 64.0 * (do ** 4 - di ** 4)


def _shear_parameter(geometry: _Frustum, material: Material, shear: str) -> float:
    """``Phi = 12 E I / (kappa G A L^2)`` of the mid-element section (0 for ``'none'``);
    ``kappa`` of the mean diameters (those of the mid-element section), as ROSS."""
    if isinstance(shear, str):
        if shear not in SHEAR_METHODS:
            raise ValueError(f"shear method {shear!r}: expected one of {', '.join(SHEAR_METHODS)}")
        if shear == "none":
            return 0.0
        outer, inner = geometry.diameters(0.5)
        kappa = shear_coefficient(outer, inner, material.poisson_ratio, shear)
    elif not float(shear) > 0:
        raise ValueError(f"shear coefficient {shear!r}: expected a number > 0 or one of {', '.join(SHEAR_METHODS)}")
    else:
        kappa = float(shear)
    return (12.0 * material.young_modulus * geometry.second_moment(0.5)
            / (kappa * material.shear_modulus * geometry.area(0.5) * geometry.length ** 2))


def _plane_functions(xi, length: float, phi: float):
    """Timoshenko shape functions of one bending plane on ``(w1, psi1, w2, psi2)``.

    Returns
    -------
    w, psi, dpsi, gamma : ndarray, shape (4,) + shape of ``xi``
        Displacement [-, m], rotation [1/m, -], its derivative along z [1/m^2, 1/m], and the
        shear strain ``w' - psi`` divided by ``Phi`` (constant along the element).
    """
    L, x, p = length, np.asarray(xi, dtype=float), phi
    c = 1.0 / (1.0 + p)
    x2, x3 = x * x, x ** 3
    w = c * np.array([1.0 - 3.0 * x2 + 2.0 * x3 + p * (1.0 - x),
                      L * (x - 2.0 * x2 + x3 + 0.5 * p * (x - x2)),
                      3.0 * x2 - 2.0 * x3 + p * x,
                      L * (-x2 + x3 - 0.5 * p * (x - x2))])
    psi = c * np.array([6.0 * (x2 - x) / L,
                        1.0 - 4.0 * x + 3.0 * x2 + p * (1.0 - x),
                        -6.0 * (x2 - x) / L,
                        -2.0 * x + 3.0 * x2 + p * x])
    dpsi = c / L * np.array([6.0 * (2.0 * x - 1.0) / L, -4.0 + 6.0 * x - p, -6.0 * (2.0 * x - 1.0) / L,
                             -2.0 + 6.0 * x + p])
    gamma = np.multiply.outer(c * np.array([-1.0 / L, -0.5, 1.0 / L, -0.5]), np.ones_like(x))
    return w, psi, dpsi, gamma


def _pair(value) -> tuple[float, float]:
    """A diameter or a (left, right) pair as (left, right)."""
    if np.ndim(value) == 0:
        return float(value), float(value)
    left, right = value
    return float(left), float(right)


def _per_element(materials, count: int) -> list:
    """One material per element (a single material serves them all)."""
    if isinstance(materials, Material):
        return [materials] * count
    materials = list(materials)
    if len(materials) != count:
        raise ValueError(f"{len(materials)} materials for {count} elements: expected one per element")
    return materials
