"""Timoshenko shaft elements (rotordyn_modal.elements.shaft) against closed forms, rigid-body
invariants and an independent Rayleigh-Ritz build that shares no code with the package."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq
from threadpoolctl import threadpool_limits

from rotordyn_modal.elements.shaft import (Material, element_matrices, free_free_frequencies, material_problem,
                                           section_problem, shaft_mass_properties, shaft_matrices,
                                           shear_coefficient)

STEEL = Material("steel", 7810.0, 2.11e11, 8.12e10)      # ROSS's steel


@pytest.fixture(autouse=True)
def one_blas_thread():
    """Small dense solves: BLAS threads only wait for a second core on a loaded machine."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def area(d, bore=0.0):
    return math.pi / 4.0 * (d * d - bore * bore)


def second_moment(d, bore=0.0):
    return math.pi / 64.0 * (d ** 4 - bore ** 4)


def plane_dofs(nodes):
    """(u_a, theta_b) of every node: one bending plane."""
    return np.concatenate([6 * j + np.array([0, 4]) for j in range(nodes)])


def lateral_dofs(nodes):
    return np.concatenate([6 * j + np.array([0, 1, 3, 4]) for j in range(nodes)])


def uniform(n, length=1.0, d=0.05, bore=0.0, **options):
    return shaft_matrices([length / n] * n, [d] * n, [bore] * n, STEEL, **options)


def simply_supported(n, count, length=1.0, d=0.05, bore=0.0, **options):
    """Lowest `count` frequencies [rad/s] of one plane, u_a = 0 at both ends."""
    M, K, _ = uniform(n, length, d, bore, **options)
    keep = np.array([i for i in plane_dofs(n + 1) if i not in (0, 6 * n)])
    values = scipy.linalg.eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)
    return np.sqrt(values[:count])


def assert_converged(got, exact, kh):
    """Consistent-mass FE frequencies lie above the exact ones by the element's error,
    about (k h)^4 / 1440 for the cubic element (k the mode's wavenumber, h the element
    length): here bounded by (k h)^4 / 1000."""
    error = np.asarray(got) / np.asarray(exact) - 1.0
    assert np.all(error > -1e-12) and np.all(error < np.asarray(kh) ** 4 / 1000.0), error


def euler_bernoulli(k, d=0.05, bore=0.0, material=STEEL):
    """omega of a uniform EB beam with wavenumber k [1/m]."""
    return k * k * math.sqrt(material.young_modulus * second_moment(d, bore) / (material.density * area(d, bore)))


# ---------------------------------------------------------------------------------------------
# closed forms

def test_euler_bernoulli_simply_supported_and_free_free():
    """EB beam (no shear, no rotary inertia): omega_n = (n pi / L)^2 sqrt(EI / rho A) simply
    supported; beta L = 4.7300407449, 7.8532046241 free-free (roots of cos(bL) cosh(bL) = 1)."""
    L = 1.2
    got = simply_supported(40, 3, L, shear="none", rotary_inertia=False)
    exact = [euler_bernoulli(n * math.pi / L) for n in (1, 2, 3)]
    assert_converged(got, exact, [n * math.pi / 40 for n in (1, 2, 3)])
    roots = [brentq(lambda x: math.cos(x) * math.cosh(x) - 1.0, a, b) for a, b in ((4.0, 5.0), (7.5, 8.0))]
    assert roots[0] == pytest.approx(4.7300407449, abs=1e-9)
    got = free_free_frequencies([L / 40] * 40, [0.05] * 40, [0.0] * 40, STEEL, "none", count=2,
                                rotary_inertia=False)
    assert_converged(got, [euler_bernoulli(r / L) for r in roots], [r / 40 for r in roots])


def timoshenko_simply_supported(n_mode, L, d, bore, material, kappa):
    """Lower root omega of the simply supported Timoshenko beam's frequency equation for the
    exact mode w = W sin(k z), psi = Psi cos(k z), k = n pi / L:
    det [[kGA k^2 - rho A w^2, -kGA k], [-kGA k, EI k^2 + kGA - rho I w^2]] = 0."""
    k = n_mode * math.pi / L
    A, I = area(d, bore), second_moment(d, bore)
    kga, ei, rho = kappa * material.shear_modulus * A, material.young_modulus * I, material.density

    def det(w2):
        return (kga * k * k - rho * A * w2) * (ei * k * k + kga - rho * I * w2) - (kga * k) ** 2

    upper = (ei * k ** 4) / (rho * A)             # the EB value: shear and rotary inertia lower it
    return math.sqrt(brentq(det, 0.0, upper, xtol=1e-14 * upper, rtol=1e-15))


def cowper_hollow(nu, m):
    """Cowper (1966), hollow circle, m = inner / outer."""
    m2 = m * m
    return 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)


def hutchinson_hollow(nu, m):
    """Hutchinson (2001), hollow circle."""
    m2 = m * m
    return (6 * (1 + nu) ** 2 * (1 + m2) ** 2
            / ((7 + 12 * nu + 4 * nu ** 2) * (1 + m2) ** 2 + 4 * m2 * (5 + 6 * nu + 2 * nu ** 2)))


@pytest.mark.parametrize("shear", ["cowper", "hutchinson"])
def test_timoshenko_simply_supported_exact(shear):
    """A stubby hollow shaft (L/d = 4: shear and rotary inertia lower the first mode by 9 %)
    against the exact frequency equation of the simply supported Timoshenko beam.

    With shear the element's error gains a term ~ c (k h)^2 (k r)^2 (r = sqrt(I/A)), c
    measured 0.03-0.13 over stubby to slender, solid to thin shafts (docs/theory.md): bounded
    here by (k h)^4 / 1000 + 0.15 (k h)^2 (k r)^2."""
    L, d, bore, n = 0.4, 0.1, 0.04, 40
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    kappa = (cowper_hollow if shear == "cowper" else hutchinson_hollow)(nu, bore / d)
    exact = np.array([timoshenko_simply_supported(m, L, d, bore, STEEL, kappa) for m in (1, 2, 3)])
    assert exact[0] < 0.92 * euler_bernoulli(math.pi / L, d, bore)
    kh, kr = np.array([m * math.pi / n for m in (1, 2, 3)]), np.array([m * math.pi / L for m in (1, 2, 3)]) * math.sqrt(
        second_moment(d, bore) / area(d, bore))
    error = simply_supported(n, 3, L, d, bore, shear=shear) / exact - 1.0
    assert np.all(error > 0) and np.all(error < kh ** 4 / 1000 + 0.15 * kh ** 2 * kr ** 2), error


def convergence_slope(counts, errors):
    return -np.polyfit(np.log(counts), np.log(errors), 1)[0]


@pytest.mark.parametrize("rotary", [False, True])
def test_convergence_rate_is_h4_without_shear(rotary):
    """Without shear (Euler-Bernoulli, Rayleigh) the cubic element's frequency error falls as
    h^4 (docs/theory.md): the log-log slope of the 3rd simply supported mode's error over
    4..32 elements against the exact omega^2 = E I k^4 / (rho A + rho I k^2 [Rayleigh])."""
    L, d = 0.5, 0.05
    k = 3 * math.pi / L
    exact = euler_bernoulli(k, d) / math.sqrt(1 + (k * k * second_moment(d) / area(d) if rotary else 0.0))
    counts = np.array([4, 8, 16, 32])
    errors = [simply_supported(n, 3, L, d, shear="none", rotary_inertia=rotary)[2] / exact - 1 for n in counts]
    assert min(errors) > 0                              # consistent mass: from above
    assert 3.7 <= convergence_slope(counts, errors) <= 4.3, errors


def test_convergence_rate_with_shear_is_h2_once_elements_are_short():
    """With shear the element's rotation becomes linear as Phi = 12 E I / (kappa G A h^2)
    grows (elements shorter than about the diameter): the error then falls as h^2
    (docs/theory.md). Slope over 16..128 elements (Phi 5.6 .. 360) of the 3rd mode."""
    L, d = 0.5, 0.05
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    exact = timoshenko_simply_supported(3, L, d, 0.0, STEEL, cowper_hollow(nu, 0.0))
    counts = np.array([16, 32, 64, 128])
    errors = [simply_supported(n, 3, L, d, shear="cowper")[2] / exact - 1 for n in counts]
    assert min(errors) > 0
    assert 1.8 <= convergence_slope(counts, errors) <= 2.2, errors


def rayleigh_spinning(k, omega_spin, d, material=STEEL):
    """Forward and backward whirl [rad/s] of a simply supported spinning Rayleigh shaft in
    the mode sin(k z): with r = u_a + i u_b ~ e^{i w t},
    (rho A + rho I k^2) w^2 - 2 rho I k^2 Omega w - E I k^4 = 0 (I_p = 2 I); forward w > 0."""
    A, I, rho, E = area(d), second_moment(d), material.density, material.young_modulus
    a, b, c = rho * A + rho * I * k * k, -2 * rho * I * k * k * omega_spin, -E * I * k ** 4
    root = math.sqrt(b * b - 4 * a * c)
    return (-b + root) / (2 * a), (b + root) / (2 * a)


def test_spinning_shaft_forward_and_backward_whirl():
    """Simply supported spinning Rayleigh shaft (rotary inertia and gyroscopic, no shear):
    forward and backward whirl of the first two modes against the closed form; the
    undamped gyroscopic eigenvalues are purely imaginary; the forward mode whirls a -> b."""
    n, L, d, spin = 24, 0.3, 0.08, 10000.0           # stubby and fast: the split is 8 %
    M, K, G = uniform(n, L, d, shear="none")
    keep = np.array([i for i in lateral_dofs(n + 1) if i not in (0, 1, 6 * n, 6 * n + 1)])
    M, K, G = (X[np.ix_(keep, keep)] for X in (M, K, G))
    size = keep.size
    A = np.block([[np.zeros((size, size)), np.eye(size)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, spin * G)]])
    values, vectors = np.linalg.eig(A)
    assert np.max(np.abs(values.real)) < 1e-9 * np.max(np.abs(values))
    upper = values.imag > 0
    order = np.argsort(values.imag[upper])
    freqs, shapes = values.imag[upper][order], vectors[:size, upper][:, order]
    expected = []
    for mode in (1, 2):
        forward, backward = rayleigh_spinning(mode * math.pi / L, spin, d)
        expected += [(backward, -1), (forward, +1)]
    assert expected[0][0] < 0.95 * expected[1][0]
    for i, (frequency, direction) in enumerate(expected):
        kh = (i // 2 + 1) * math.pi / n
        assert 0 < freqs[i] / frequency - 1 < kh ** 4 / 1000
        largest = 2 * np.argmax(np.abs(shapes[0::2, i]) * (keep[0::2] % 6 == 0))    # largest u_a
        ratio = shapes[largest + 1, i] / shapes[largest, i]                           # its node's u_b
        # forward: u_a = cos wt, u_b = sin wt, i.e. u_b = -i u_a; backward u_b = +i u_a
        assert ratio == pytest.approx(-1j * direction, abs=1e-8)


# ---------------------------------------------------------------------------------------------
# rigid-body invariants and symmetry

def rigid_motions(positions):
    """(6 n, 6): the nodes' motions under a rigid translation t and rotation theta about the
    shaft's start, u(z) = t + theta x (z e) with e = (0, 0, 1) in (a, b, e) axes."""
    R = np.zeros((6 * len(positions), 6))
    for j, z in enumerate(positions):
        R[6 * j:6 * j + 3, :3] = np.eye(3)
        R[6 * j:6 * j + 3, 3:] = -z * np.array([[0, -1, 0], [1, 0, 0], [0, 0, 0.0]])   # -skew(z e)
        R[6 * j + 3:6 * j + 6, 3:] = np.eye(3)
    return R


def frustum_properties(lengths, outers, inners, rho):
    """Mass, centre, polar and diametral (about the centre) inertia of a chain of hollow
    conical frusta, from the textbook integrals of r(xi) = a + b xi."""
    mass = first = second = polar = 0.0
    start = 0.0
    for L, (o0, o1), (i0, i1) in zip(lengths, outers, inners):
        for (r0, r1), sign in (((o0 / 2, o1 / 2), 1.0), ((i0 / 2, i1 / 2), -1.0)):
            a, b = r0, r1 - r0
            m = sign * rho * math.pi * L * (a * a + a * b + b * b / 3)
            s1 = sign * rho * math.pi * L * L * (a * a / 2 + 2 * a * b / 3 + b * b / 4)
            s2 = sign * rho * math.pi * L ** 3 * (a * a / 3 + a * b / 2 + b * b / 5)
            r4 = (r0 ** 4 + r0 ** 3 * r1 + r0 ** 2 * r1 ** 2 + r0 * r1 ** 3 + r1 ** 4) / 5   # mean of r^4
            mass += m
            first += s1 + start * m
            second += s2 + 2 * start * s1 + start * start * m
            polar += sign * rho * math.pi / 2 * L * r4
        start += L
    center = first / mass
    diametral = polar / 2 + second - mass * center * center
    return mass, center, polar, diametral


TAPERED = ([0.1, 0.25, 0.15], [(0.06, 0.06), (0.06, 0.11), (0.09, 0.04)], [(0.0, 0.0), (0.02, 0.05), (0.0, 0.03)])


def test_mass_properties_of_frusta():
    lengths, outers, inners = TAPERED
    got = shaft_mass_properties(lengths, outers, inners, STEEL)
    np.testing.assert_allclose(got, frustum_properties(lengths, outers, inners, STEEL.density), rtol=1e-13)
    # a solid cylinder: m = rho pi r^2 L, J_p = m r^2 / 2, J_d = m (3 r^2 + L^2) / 12
    r, L = 0.03, 0.7
    m = STEEL.density * math.pi * r * r * L
    got = shaft_mass_properties([0.2, 0.5], [2 * r, 2 * r], [0.0, 0.0], [STEEL, STEEL])
    np.testing.assert_allclose(got, [m, L / 2, m * r * r / 2, m * (3 * r * r + L * L) / 12], rtol=1e-13)


@pytest.mark.parametrize("shear", ["cowper", "hutchinson", "none"])
def test_rigid_motions(shear):
    """K on any rigid motion is 0; M reproduces the rigid body's kinetic energy (mass,
    centre, inertias of the frusta); G on rigid motions is the rigid rotor's diag(0, -J_p skew(e))."""
    lengths, outers, inners = TAPERED
    M, K, G = shaft_matrices(lengths, outers, inners, STEEL, shear)
    positions = np.concatenate([[0.0], np.cumsum(lengths)])
    R = rigid_motions(positions)
    assert np.max(np.abs(K @ R)) < 1e-12 * np.max(np.abs(K)) * positions[-1]
    mass, c, jp, jd = frustum_properties(lengths, outers, inners, STEEL.density)
    skew_c = np.array([[0, -c, 0], [c, 0, 0], [0, 0, 0.0]])
    rigid_mass = np.block([[mass * np.eye(3), -mass * skew_c],
                           [mass * skew_c, np.diag([jd + mass * c * c, jd + mass * c * c, jp])]])
    np.testing.assert_allclose(R.T @ M @ R, rigid_mass, rtol=1e-12, atol=1e-12 * mass)
    rigid_gyro = np.zeros((6, 6))
    rigid_gyro[3:, 3:] = -jp * np.array([[0, -1, 0], [1, 0, 0], [0, 0, 0.0]])
    np.testing.assert_allclose(R.T @ G @ R, rigid_gyro, atol=1e-13 * jp)


@pytest.mark.parametrize("shear, rotary", [("cowper", True), ("none", False), ("hutchinson", True)])
def test_symmetry_and_definiteness(shear, rotary):
    lengths, outers, inners = TAPERED
    M, K, G = shaft_matrices(lengths, outers, inners, STEEL, shear, rotary_inertia=rotary)
    np.testing.assert_array_equal(M, M.T)
    np.testing.assert_array_equal(K, K.T)
    np.testing.assert_array_equal(G, -G.T)
    assert np.linalg.eigvalsh(M)[0] > 0
    stiffness = np.linalg.eigvalsh(K)
    assert np.all(stiffness[:6] < 1e-9 * stiffness[-1])          # six rigid motions
    assert stiffness[6] > 1e-6 * stiffness[-1] and stiffness[0] > -1e-9 * stiffness[-1]


# ---------------------------------------------------------------------------------------------
# coefficients, materials, input

def test_shear_coefficients_limits():
    nu = 0.3
    assert shear_coefficient(1.0, 0.0, nu, "cowper") == pytest.approx(6 * (1 + nu) / (7 + 6 * nu), rel=1e-15)
    # Cowper's thin-walled tube: 2 (1 + nu) / (4 + 3 nu)
    assert shear_coefficient(1.0, 1.0 - 1e-9, nu, "cowper") == pytest.approx(2 * (1 + nu) / (4 + 3 * nu), rel=1e-8)
    # Hutchinson's solid circle, the value "widely accepted to be best": 6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2)
    assert shear_coefficient(0.2, 0.0, nu, "hutchinson") == pytest.approx(6 * 1.3 ** 2 / (7 + 3.6 + 0.36), rel=1e-15)
    assert shear_coefficient(1.0, 0.5, nu, "none") == math.inf
    with pytest.raises(ValueError, match="expected one of cowper, hutchinson, none"):
        shear_coefficient(1.0, 0.5, nu, "timoshenko")


def test_material_and_section_problems():
    steel = Material.from_poisson("s", 7800.0, 2.0e11, 0.25)
    assert steel.shear_modulus == pytest.approx(8.0e10) and steel.poisson_ratio == pytest.approx(0.25)
    assert material_problem(7800.0, 2e11, shear_modulus=8e10) is None
    assert material_problem(7800.0, 2e11, poisson_ratio=0.3) is None
    assert material_problem(7800.0, None, poisson_ratio=0.3)[0] == "young_modulus"
    assert material_problem(-1.0, 2e11, poisson_ratio=0.3)[:2] == ("density", -1.0)
    assert "exactly one" in material_problem(7800.0, 2e11, 8e10, 0.3)[2]
    assert "exactly one" in material_problem(7800.0, 2e11)[2]
    assert material_problem(7800.0, 2e11, poisson_ratio=0.6)[:2] == ("poisson_ratio", 0.6)
    assert material_problem(7800.0, 2e11, shear_modulus=6e10)[0] == "shear_modulus"    # nu = 0.67
    assert section_problem(0.1, 0.05) is None and section_problem(0.1, [0.05, 0.07], [0.0, 0.02]) is None
    assert section_problem(0.0, 0.05)[0] == "length"
    assert section_problem(0.1, 0.05, 0.05)[0] == "inner_diameter"
    assert section_problem(0.1, [0.05, 0.02], [0.0, 0.03])[0] == "inner_diameter"
    assert section_problem(0.1, [0.05, 0.0])[0] == "outer_diameter"
    with pytest.raises(ValueError, match="inner_diameter"):
        element_matrices(0.1, 0.05, 0.06, STEEL)
