"""Timoshenko shaft elements (rotordyn_modal.elements.shaft) against closed forms, rigid-body
invariants and an independent Rayleigh-Ritz build that shares no code with the package."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq
from threadpoolctl import threadpool_limits

from rotordyn_modal.elements.shaft import (Material, element_matrices, free_free_frequencies, material_problem,
                                           section_problem, shaft_mass_properties, shaft_matrices,
                                           shear_coefficient)
from rotordyn_modal.errors import ModelError

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


def timoshenko_free_free(count, L, d, bore, material, kappa, upper):
    """The lowest ``count`` elastic roots omega [rad/s] below ``upper`` of the free-free
    Timoshenko beam's exact frequency equation (Huang 1961): with c = rho A w^2 / (kappa G A),
    w = sum of cosh(a z), sinh(a z), cos(b z), sin(b z) where a^2 and -b^2 are the roots x of
    kappa G A E I x^2 + (kappa G A rho I + rho A E I) w^2 x + rho A w^2 (rho I w^2 - kappa G A) = 0,
    and psi' = w'' + c w term by term; free ends: E I psi' = 0 and kappa G A (w' - psi) = 0 at
    z = 0 and L (the shear rows divided by c, which vanishes with w). Below the cut-off
    rho I w^2 < kappa G A."""
    A, I = area(d, bore), second_moment(d, bore)
    kga, ei, rho = kappa * material.shear_modulus * A, material.young_modulus * I, material.density

    def det(w):
        w2 = w * w
        p, q, r = kga * ei, (kga * rho * I + rho * A * ei) * w2, rho * A * w2 * (rho * I * w2 - kga)
        root = math.sqrt(q * q - 4 * p * r)
        a, b = math.sqrt((-q + root) / (2 * p)), math.sqrt((q + root) / (2 * p))
        c = rho * A * w2 / kga

        def rows(z):          # [psi', (w' - psi) / c] of cosh, sinh, cos, sin
            return [[(a * a + c) * math.cosh(a * z), (a * a + c) * math.sinh(a * z),
                     (c - b * b) * math.cos(b * z), (c - b * b) * math.sin(b * z)],
                    [-math.sinh(a * z) / a, -math.cosh(a * z) / a, -math.sin(b * z) / b, math.cos(b * z) / b]]
        return np.linalg.det(np.array(rows(0.0) + rows(L)))

    grid = np.linspace(upper * 1e-3, upper, 4000)
    values = [det(w) for w in grid]
    roots = [brentq(det, grid[i], grid[i + 1], xtol=1e-14 * upper, rtol=1e-15)
             for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0]
    return np.array(roots[:count])


def test_timoshenko_free_free_exact():
    """Free-free Timoshenko: for a stubby hollow shaft (L/d = 4) the elements (Cowper,
    Hutchinson) converge to the roots of the exact frequency equation above from above, within
    the bound of the simply supported tests, (k h)^4 / 1000 + 0.15 (k h)^2 (k r)^2 with
    k = beta_n / L (beta_n L the Euler-Bernoulli roots of cos cosh = 1)."""
    L, d, bore, n = 0.4, 0.1, 0.04, 40
    eb = [euler_bernoulli(beta / L, d, bore) for beta in (4.7300407449, 7.8532046241)]
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    for shear, coefficient in (("cowper", cowper_hollow), ("hutchinson", hutchinson_hollow)):
        exact = timoshenko_free_free(3, L, d, bore, STEEL, coefficient(nu, bore / d), 1.5 * eb[1])
        assert exact[0] < 0.92 * eb[0]                    # shear and rotary inertia: 8 % and more
        got = free_free_frequencies([L / n] * n, [d] * n, [bore] * n, STEEL, shear, count=len(exact))
        k = np.array([4.7300407449, 7.8532046241, 10.9956078380])[:len(exact)] / L
        kh = k * L / n
        bound = kh ** 4 / 1000 + 0.15 * kh ** 2 * (k * math.sqrt(second_moment(d, bore) / area(d, bore))) ** 2
        error = got / exact - 1
        assert np.all(error > 0) and np.all(error < bound), (shear, error, bound)


def test_timoshenko_free_free_equation_is_euler_bernoulli_without_shear_and_rotary_inertia():
    """The frequency equation above reduces to cos(bL) cosh(bL) = 1 (4.7300407449,
    7.8532046241) as kappa G A -> inf and rho I -> 0: a material of huge G on a very slender
    shaft (L / d = 2000: the rotary inertia's share (k r)^2 ~ 1e-6 ... 4e-6 of the frequency
    squared) gives the Euler-Bernoulli frequencies to 1e-5; a check of the equation, which the
    test above trusts."""
    from rotordyn_modal.elements.shaft import Material

    L, d = 100.0, 0.05
    stiff = Material("stiff", STEEL.density, STEEL.young_modulus, STEEL.shear_modulus * 1e8)
    eb = [euler_bernoulli(beta / L, d) for beta in (4.7300407449, 7.8532046241)]
    got = timoshenko_free_free(2, L, d, 0.0, stiff, 1.0, 1.2 * eb[1])
    np.testing.assert_allclose(got, eb, rtol=1e-5)
    assert np.all(got < eb)


def timoshenko_spinning(k, omega_spin, d, material, kappa):
    """Forward and backward whirl [rad/s] of a simply supported spinning Timoshenko shaft in
    the mode w = W sin(k z), psi = Psi cos(k z) (complex r = u_a + i u_b ~ e^{i w t}): the
    root w > 0 and the magnitude of the root w < 0 of
    det [[kGA k^2 - rho A w^2, -kGA k], [-kGA k, EI k^2 + kGA - rho I w^2 + 2 rho I Omega w]] = 0
    (I_p = 2 I), the lowest branch; as kGA -> inf this is the Rayleigh shaft's
    (rho A + rho I k^2) w^2 - 2 rho I k^2 Omega w - E I k^4 = 0 (rayleigh_spinning)."""
    A, I = area(d), second_moment(d)
    kga, ei, rho = kappa * material.shear_modulus * A, material.young_modulus * I, material.density

    def det(w):
        return ((kga * k * k - rho * A * w * w) * (ei * k * k + kga - rho * I * w * w + 2 * rho * I * omega_spin * w)
                - (kga * k) ** 2)

    forward, backward = rayleigh_spinning(k, omega_spin, d, material)    # bounds: shear lowers both
    return (brentq(det, 0.0, forward * (1 + 1e-9), xtol=1e-13 * forward, rtol=1e-15),
            -brentq(det, -backward * (1 + 1e-9), 0.0, xtol=1e-13 * forward, rtol=1e-15))


@pytest.mark.parametrize("shear", ["cowper", "hutchinson"])
def test_spinning_timoshenko_shaft_forward_and_backward_whirl(shear):
    """The spinning test above with shear deformation (L/d = 3.75, fast: shear lowers the first
    mode by 5 %, the gyroscopic moments split it by 6 %): forward and backward whirl of the
    first two modes against the Timoshenko closed form, within the bound of the simply
    supported Timoshenko test; purely imaginary eigenvalues."""
    n, L, d, spin = 24, 0.3, 0.08, 10000.0
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    kappa = (cowper_hollow if shear == "cowper" else hutchinson_hollow)(nu, 0.0)
    M, K, G = uniform(n, L, d, shear=shear)
    keep = np.array([i for i in lateral_dofs(n + 1) if i not in (0, 1, 6 * n, 6 * n + 1)])
    M, K, G = (X[np.ix_(keep, keep)] for X in (M, K, G))
    size = keep.size
    A = np.block([[np.zeros((size, size)), np.eye(size)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, spin * G)]])
    values = np.linalg.eigvals(A)
    assert np.max(np.abs(values.real)) < 1e-9 * np.max(np.abs(values))
    freqs = np.sort(values.imag[values.imag > 0])[:4]
    expected, bounds = [], []
    r = math.sqrt(second_moment(d) / area(d))
    for mode in (1, 2):
        k = mode * math.pi / L
        forward, backward = timoshenko_spinning(k, spin, d, STEEL, kappa)
        expected += [backward, forward]
        kh = k * L / n
        bounds += [kh ** 4 / 1000 + 0.15 * kh ** 2 * (k * r) ** 2] * 2
    rayleigh = rayleigh_spinning(math.pi / L, spin, d)
    assert expected[1] < 0.95 * rayleigh[0] and expected[0] < 0.95 * expected[1]
    error = freqs / np.array(expected) - 1
    assert np.all(error > 0) and np.all(error < np.array(bounds)), (error, bounds)


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
    key, value, expected = material_problem(7800.0, 2e11, poisson_ratio=0.6)
    assert str(ModelError("m.toml", f"materials.steel.{key}", value, expected)) == (
        "m.toml: materials.steel.poisson_ratio = 0.6: expected a number in (-1, 0.5]")
    assert section_problem(0.1, 0.05) is None and section_problem(0.1, [0.05, 0.07], [0.0, 0.02]) is None
    assert section_problem(0.0, 0.05)[0] == "length"
    assert section_problem(0.1, 0.05, 0.05)[0] == "inner_diameter"
    assert section_problem(0.1, [0.05, 0.02], [0.0, 0.03])[0] == "inner_diameter"
    assert section_problem(0.1, [0.05, 0.0])[0] == "outer_diameter"
    with pytest.raises(ValueError, match="inner_diameter"):
        element_matrices(0.1, 0.05, 0.06, STEEL)


# ---------------------------------------------------------------------------------------------
# ROSS's element (Genta and Gugliotta 1988, as ROSS 3.x writes it), written out here

def ross_lateral(L, od, bore, material, kappa, rotary=True):
    """ROSS's ShaftElement M, K, G on its lateral motions [x0, y0, alpha0, beta0, x1, y1,
    alpha1, beta1]: the Timoshenko shape functions with Phi of the mid-element section and the
    frustum's area A = A_l (1 + a1 xi + b1 xi^2) and second moment
    I = I_l (1 + a2 xi + b2 xi^2 + g xi^3 + d xi^4) integrated in closed form. kappa None:
    no shear (Phi = 0)."""
    rho, E, Gs = material.density, material.young_modulus, material.shear_modulus
    (odl, odr), (idl, idr) = od, bore
    roj, rok, rij, rik = odl / 2, odr / 2, idl / 2, idr / 2
    A_l, I_l = math.pi * (roj ** 2 - rij ** 2), math.pi / 4 * (roj ** 4 - rij ** 4)
    dro, dri = rok - roj, rik - rij
    a1 = 2 * math.pi * (roj * dro - rij * dri) / A_l
    b1 = math.pi * (dro ** 2 - dri ** 2) / A_l
    a2 = math.pi * (roj ** 3 * dro - rij ** 3 * dri) / I_l
    b2 = 1.5 * math.pi * (roj ** 2 * dro ** 2 - rij ** 2 * dri ** 2) / I_l
    g = math.pi * (roj * dro ** 3 - rij * dri ** 3) / I_l
    d = math.pi * (dro ** 4 - dri ** 4) / (4 * I_l)
    A = A_l * (1 + a1 / 2 + b1 / 4)
    Ie = I_l * (1 + a2 / 2 + b2 / 4 + g / 8 + d / 16)
    p = 0.0 if kappa is None else 12 * E * Ie / (Gs * kappa * A * L * L)

    # translational mass, one plane (x0, beta0, x1, beta1)
    def q(c):                                    # c0 + c1 p + c2 p^2
        return c[0] + c[1] * p + c[2] * p * p
    m = {1: q((468, 882, 420)) + a1 * q((108, 210, 105)) + b1 * q((38, 78, 42)),
         2: (q((66, 115.5, 52.5)) + a1 * q((21, 40.5, 21)) + b1 * q((8.5, 18, 10.5))) * L,
         3: q((162, 378, 210)) + a1 * q((81, 189, 105)) + b1 * q((46, 111, 63)),
         4: (q((39, 94.5, 52.5)) + a1 * q((18, 40.5, 21)) + b1 * q((9.5, 21, 10.5))) * L,
         5: (q((12, 21, 10.5)) + a1 * q((4.5, 9, 5.25)) + b1 * q((2, 4.5, 3))) * L * L,
         6: (q((39, 94.5, 52.5)) + a1 * q((21, 54, 31.5)) + b1 * q((12.5, 34.5, 21))) * L,
         7: (q((9, 21, 10.5)) + a1 * q((4.5, 10.5, 5.25)) + b1 * q((2.5, 6, 3))) * L * L,
         8: q((468, 882, 420)) + a1 * q((360, 672, 315)) + b1 * q((290, 540, 252)),
         9: (q((66, 115.5, 52.5)) + a1 * q((45, 75, 31.5)) + b1 * q((32.5, 52.5, 21))) * L,
         10: (q((12, 21, 10.5)) + a1 * q((7.5, 12, 5.25)) + b1 * q((5, 7.5, 3))) * L * L}
    mt = np.array([[m[1], m[2], m[3], -m[4]], [m[2], m[5], m[6], -m[7]],
                   [m[3], m[6], m[8], -m[9]], [-m[4], -m[7], -m[9], m[10]]]) * rho * A_l * L / (1260 * (1 + p) ** 2)

    def rq(c):                                   # the rotary/gyroscopic coefficients
        return (q(c[0]) + a2 * q(c[1]) + b2 * q(c[2]) + g * q(c[3]) + d * q(c[4]))
    r11 = rq(((252, 0, 0), (126, 0, 0), (72, 0, 0), (45, 0, 0), (30, 0, 0)))
    r12 = rq(((21, -105, 0), (21, -42, 0), (15, -21, 0), (10.5, -12, 0), (7.5, -7.5, 0))) * L
    r13 = rq(((21, -105, 0), (0, -63, 0), (-6, -42, 0), (-7.5, -30, 0), (-7.5, -22.5, 0))) * L
    r14 = rq(((28, 35, 70), (7, -7, 17.5), (4, -7, 7), (2.75, -5, 3.5), (2, -3.5, 2))) * L * L
    r15 = rq(((7, 35, -35), (3.5, 17.5, -17.5), (3, 10.5, -10.5), (2.75, 7, -7), (2.5, 5, -5))) * L * L
    r16 = rq(((28, 35, 70), (21, 42, 52.5), (18, 42, 42), (16.25, 40, 35), (15, 37.5, 30))) * L * L
    scale = rho * I_l / (210 * L * (1 + p) ** 2)
    mr = np.array([[r11, r12, -r11, r13], [r12, r14, -r12, -r15],
                   [-r11, -r12, r11, -r13], [r13, -r15, -r13, r16]]) * scale

    k1 = 1260 + 630 * a2 + 504 * b2 + 441 * g + 396 * d
    shear_t = p * (105 * a2 + 105 * b2 + 94.5 * g + 84 * d)
    k2 = (630 + 210 * a2 + 147 * b2 + 126 * g + 114 * d - shear_t) * L
    k3 = (630 + 420 * a2 + 357 * b2 + 315 * g + 282 * d + shear_t) * L
    k4 = rq(((420, 210, 105), (105, 0, 52.5), (56, -35, 35), (42, -42, 26.25), (36, -42, 21))) * L * L
    k5 = rq(((210, -210, -105), (105, -105, -52.5), (91, -70, -35), (84, -52.5, -26.25), (78, -42, -21))) * L * L
    k6 = rq(((420, 210, 105), (315, 210, 52.5), (266, 175, 35), (231, 147, 26.25), (204, 126, 21))) * L * L
    k7, k8, k9 = 12 + 6 * a1 + 4 * b1, (6 + 3 * a1 + 2 * b1) * L, (3 + 1.5 * a1 + b1) * L * L
    bend = np.array([[k1, k2, -k1, k3], [k2, k4, -k2, k5], [-k1, -k2, k1, -k3], [k3, k5, -k3, k6]]) * I_l / 105
    shear = np.array([[k7, k8, -k7, k8], [k8, k9, -k8, k9], [-k7, -k8, k7, -k8], [k8, k9, -k8, k9]]) * Ie * p * A_l / A
    kk = E / (L ** 3 * (1 + p) ** 2) * (bend + shear)

    # x-plane (x0, beta0, x1, beta1) at [0, 3, 4, 7]; ROSS's y-plane (y0, alpha0, y1, alpha1)
    # at [1, 2, 5, 6] is the x-plane with alpha's sign turned: entries times (+, -, +, -)
    def both_planes(plane):
        out = np.zeros((8, 8))
        x, y, s = [0, 3, 4, 7], [1, 2, 5, 6], np.array([1, -1, 1, -1])
        out[np.ix_(x, x)] = plane
        out[np.ix_(y, y)] = np.outer(s, s) * plane
        return out

    M = both_planes(mt + (mr if rotary else 0.0))
    K = both_planes(kk)
    g1, g2, g3, g4, g5, g6 = r11, r12, r13, r14, r15, r16
    G = np.array([[0, g1, -g2, 0, 0, -g1, -g3, 0],
                  [-g1, 0, 0, -g2, g1, 0, 0, -g3],
                  [g2, 0, 0, g4, -g2, 0, 0, -g5],
                  [0, g2, -g4, 0, 0, -g2, g5, 0],
                  [0, -g1, g2, 0, 0, g1, g3, 0],
                  [g1, 0, 0, g2, -g1, 0, 0, g3],
                  [g3, 0, 0, -g5, -g3, 0, 0, g6],
                  [0, g3, g5, 0, 0, -g3, -g6, 0]]) * 2 * scale
    return M, K, G


#: ROSS's per-node [x, y, z, alpha, beta, theta] -> this package's [u_a, u_b, u_e, theta_a,
#: theta_b, theta_e]: x = a, y = b, z = e, and alpha, beta are the rotation vector's x and y
#: components (alpha = -dy/dz, beta = +dx/dz), as here: the identity. The lateral motions
#: in ROSS_LATERAL's order are ours at:
ROSS_LATERAL = [0, 1, 3, 4, 6, 7, 9, 10]


def ross_hutchinson(nu, m):
    """ROSS 3.x's 'hutchinson' coefficient: Hutchinson's hollow-circle formula with (1 + nu)
    in the numerator instead of (1 + nu)^2 (0.71 for a solid steel shaft, against the 0.93
    of Hutchinson's paper)."""
    m2 = m * m
    return (6 * (1 + nu) * (1 + m2) ** 2
            / ((7 + 12 * nu + 4 * nu ** 2) * (1 + m2) ** 2 + 4 * m2 * (5 + 6 * nu + 2 * nu ** 2)))


def test_ross_convention_is_this_packages():
    """ROSS's element (written out above) obeys this package's kinematics: its K has no
    stiffness for a rigid rotation theta_b with u_a = +theta_b z or theta_a with u_b = -theta_a z
    (alpha = -dy/dz, beta = +dx/dz), and its G on a rigid tilt is -J_p skew(e)."""
    L, od, bore = 0.3, (0.1, 0.15), (0.02, 0.05)
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    M, K, G = ross_lateral(L, od, bore, STEEL, cowper_hollow(nu, 0.035 / 0.125))
    for theta_a, theta_b in ((0.0, 1.0), (1.0, 0.0)):
        q = np.array([0, 0, theta_a, theta_b, theta_b * L, -theta_a * L, theta_a, theta_b])
        assert np.max(np.abs(K @ q)) < 1e-12 * np.max(np.abs(K))
    jp = frustum_properties([L], [od], [bore], STEEL.density)[2]
    tilt = np.zeros((8, 2))
    tilt[[2, 6], 0] = 1.0                         # theta_a; u_b = -theta_a z
    tilt[5, 0] = -L
    tilt[[3, 7], 1] = 1.0                         # theta_b; u_a = +theta_b z
    tilt[4, 1] = L
    np.testing.assert_allclose(tilt.T @ G @ tilt, -jp * np.array([[0, -1], [1, 0]]), rtol=1e-12)


@pytest.mark.parametrize("od, bore", [((0.1, 0.1), (0.05, 0.05)), ((0.1, 0.15), (0.05, 0.05)),
                                      ((0.12, 0.07), (0.0, 0.03)), ((0.08, 0.08), (0.0, 0.0))])
@pytest.mark.parametrize("shear, rotary", [("cowper", True), ("none", True), ("none", False),
                                           ("ross-hutchinson", True)])
def test_element_equals_ross(od, bore, shear, rotary):
    """Uniform and tapered elements equal ROSS's ShaftElement (same options: Cowper or no
    shear, rotary inertia on or off; ROSS's 'hutchinson' through its coefficient given as a
    number) on the lateral motions, and on the axial and torsional ones for uniform sections."""
    L = 0.25
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    ratio = (bore[0] + bore[1]) / (od[0] + od[1])
    kappa = {"cowper": cowper_hollow(nu, ratio), "none": None, "ross-hutchinson": ross_hutchinson(nu, ratio)}[shear]
    ours = element_matrices(L, od, bore, STEEL, kappa if shear == "ross-hutchinson" else shear,
                            rotary_inertia=rotary)
    for mine, theirs in zip(ours, ross_lateral(L, od, bore, STEEL, kappa, rotary)):
        lateral = mine[np.ix_(ROSS_LATERAL, ROSS_LATERAL)]
        np.testing.assert_allclose(lateral, theirs, rtol=1e-12, atol=1e-13 * np.max(np.abs(theirs)))
    if od[0] == od[1] and bore[0] == bore[1]:       # ROSS: rho A L / 6 [[2, 1], [1, 2]], E A / L, ...
        A, J = area(od[0], bore[0]), 2 * second_moment(od[0], bore[0])
        rod = np.array([[2, 1], [1, 2]]) / 6 * L
        spring = np.array([[1, -1], [-1, 1]]) / L
        M, K, _ = ours
        np.testing.assert_allclose(M[np.ix_([2, 8], [2, 8])], STEEL.density * A * rod, rtol=1e-13)
        np.testing.assert_allclose(M[np.ix_([5, 11], [5, 11])], STEEL.density * J * rod, rtol=1e-13)
        np.testing.assert_allclose(K[np.ix_([2, 8], [2, 8])], STEEL.young_modulus * A * spring, rtol=1e-13)
        np.testing.assert_allclose(K[np.ix_([5, 11], [5, 11])], STEEL.shear_modulus * J * spring, rtol=1e-13)


def test_ross_documented_values():
    """The tapered Timoshenko element of ROSS's docstrings (L = 0.5, bore 0.05, outer 0.1 ->
    0.15, steel), its printed lateral entries at node 1 (6 decimals; K in MN/m)."""
    M, K, G = element_matrices(0.5, (0.1, 0.15), 0.05, STEEL)
    lateral = [0, 1, 3, 4]
    np.testing.assert_array_equal(np.round(M[np.ix_(lateral, lateral)], 6),
                                  [[11.369864, 0, 0, 0.861976], [0, 11.369864, -0.861976, 0],
                                   [0, -0.861976, 0.086675, 0], [0.861976, 0, 0, 0.086675]])
    np.testing.assert_array_equal(np.round(K[np.ix_(lateral, lateral)] / 1e6, 4),
                                  [[219.9614, 0, 0, 41.2975], [0, 219.9614, -41.2975, 0],
                                   [0, -41.2975, 12.2353, 0], [41.2975, 0, 0, 12.2353]])
    np.testing.assert_array_equal(np.round(G[np.ix_(lateral, lateral)], 6) + 0.0,
                                  [[0, 0.309408, -0.010859, 0], [-0.309408, 0, 0, -0.010859],
                                   [0.010859, 0, 0, 0.006721], [0, 0.010859, -0.006721, 0]])


# ---------------------------------------------------------------------------------------------
# an independent route: Rayleigh-Ritz with Legendre polynomials over the whole shaft

def ritz_matrices(L, od, ratio, material, kappa, supported, degree=14, rotary=True):
    """Rayleigh-Ritz M, K, G of a conical shaft (outer diameter linear from od[0] to od[1],
    bore = ratio * outer, so kappa is one number along it) with Legendre series of the given
    degree on [0, L], times z (L - z) for the displacements when simply supported.

    Coordinates: plane a (u_a; with shear also psi_a = theta_b), then plane b (u_b; psi_b =
    -theta_a); without shear psi = u'. Energies: T = 1/2 int rho A |u.|^2 + rho I |psi.|^2,
    V = 1/2 int E I |psi'|^2 + kappa G A |u' - psi|^2; the spinning sections' gyroscopic
    term is Omega int rho I_p (theta_a theta_b. - theta_b theta_a.) written as G q.:
    G = [[0, g], [-g, 0]], g = int rho I_p psi_i psi_j (theta_a = -psi_b, theta_b = psi_a)."""
    z, w = np.polynomial.legendre.leggauss(60)          # exact: integrands of degree <= 40
    z, w = (z + 1) * L / 2, w * L / 2
    outer = od[0] + (od[1] - od[0]) * z / L
    A = math.pi / 4 * outer ** 2 * (1 - ratio ** 2)
    I = math.pi / 64 * outer ** 4 * (1 - ratio ** 4)
    rho, E, Gs = material.density, material.young_modulus, material.shear_modulus
    psi_basis = [np.polynomial.Legendre.basis(j, domain=[0, L]) for j in range(degree + 1)]
    bubble = np.polynomial.Legendre.fromroots([0, L], domain=[0, L]) if supported else 1
    u_basis = [b * bubble for b in psi_basis]
    U, U1, U2 = (np.array([b.deriv(k)(z) if k else b(z) for b in u_basis]) for k in (0, 1, 2))
    P, P1 = (np.array([b.deriv(k)(z) if k else b(z) for b in psi_basis]) for k in (0, 1))

    def gram(f, X, Y):
        return (X * (f * w)) @ Y.T

    if kappa is None:
        m = gram(rho * A, U, U) + (gram(rho * I, U1, U1) if rotary else 0)
        k = gram(E * I, U2, U2)
        g = gram(2 * rho * I, U1, U1)
    else:
        Z = np.zeros((U.shape[0], P.shape[0]))
        m = np.block([[gram(rho * A, U, U), Z], [Z.T, gram(rho * I, P, P) if rotary else 0 * Z.T @ Z]])
        kga = kappa * Gs * A
        k = np.block([[gram(kga, U1, U1), -gram(kga, U1, P)], [-gram(kga, P, U1), gram(E * I, P1, P1) + gram(kga, P, P)]])
        g = np.block([[0 * Z @ Z.T, Z], [Z.T, gram(2 * rho * I, P, P)]])
    Z = np.zeros_like(m)
    return np.block([[m, Z], [Z, m]]), np.block([[k, Z], [Z, k]]), np.block([[Z, g], [-g, Z]])


def whirl_frequencies(M, K, G, spin, count):
    """The lowest `count` positive frequencies of M q.. + spin G q. + K q = 0 [rad/s]."""
    size = M.shape[0]
    state = np.block([[np.zeros((size, size)), np.eye(size)],
                      [-np.linalg.solve(M, K), -np.linalg.solve(M, spin * G)]])
    values = np.linalg.eigvals(state)
    return np.sort(values.imag[values.imag > 0])[:count]


shafts = st.tuples(st.floats(0.2, 1.2), st.floats(0.03, 0.15), st.floats(0.03, 0.15), st.floats(0.0, 0.8))


@settings(max_examples=8, deadline=None, derandomize=True)
@given(shafts, st.sampled_from(["cowper", "none"]))
def test_free_free_against_rayleigh_ritz(shaft, shear):
    """free_free_frequencies of random conical shafts (L/d >= 3) equal an independent
    Rayleigh-Ritz solution (degree 14: converged to ~1e-10 for these smooth problems). The
    FE error bound: (k h)^4 / 1000 + 0.15 (k h)^2 (k r)^2 (see the simply supported tests),
    with k = 7.853 / L the uniform free-free second mode's wavenumber, times 1.5 for the
    taper, r the largest radius of gyration."""
    L, d0, d1, ratio = shaft
    L = max(L, 3 * max(d0, d1))
    nu = STEEL.young_modulus / (2 * STEEL.shear_modulus) - 1
    kappa = None if shear == "none" else cowper_hollow(nu, ratio)
    n = 24
    fe = free_free_frequencies([L / n] * n, [(d0 + (d1 - d0) * i / n, d0 + (d1 - d0) * (i + 1) / n) for i in range(n)],
                               [(ratio * (d0 + (d1 - d0) * i / n), ratio * (d0 + (d1 - d0) * (i + 1) / n)) for i in range(n)],
                               STEEL, shear, count=2)
    M, K, _ = ritz_matrices(L, (d0, d1), ratio, STEEL, kappa, supported=False)
    half = M.shape[0] // 2
    values = scipy.linalg.eigh(K[:half, :half], M[:half, :half], eigvals_only=True)
    ritz = np.sqrt(values[2:4])                       # two rigid motions of the plane first
    kh, kr = 1.5 * 7.853 / n, 1.5 * 7.853 / L * max(d0, d1) * math.sqrt(1 + ratio ** 2) / 4
    bound = kh ** 4 / 1000 + (0.15 * kh ** 2 * kr ** 2 if kappa else 0.0)
    error = fe / ritz - 1
    assert np.all(error > -1e-9) and np.all(error < bound), (error, bound)


@settings(max_examples=6, deadline=None, derandomize=True)
@given(shafts, st.floats(0.0, 1.0))
def test_spinning_supported_against_rayleigh_ritz(shaft, speed):
    """Forward and backward whirl of random spinning conical Rayleigh shafts, simply
    supported, against the Rayleigh-Ritz model at the same speed (up to 10 times the first
    frequency at rest: strong gyroscopic coupling). FE error bound (k h)^4 / 1000 with k the
    second mode's wavenumber 2 pi / L, times 1.5 for the taper."""
    L, d0, d1, ratio = shaft
    L = max(L, 3 * max(d0, d1))
    n = 24
    outers = [(d0 + (d1 - d0) * i / n, d0 + (d1 - d0) * (i + 1) / n) for i in range(n)]
    M, K, G = shaft_matrices([L / n] * n, outers, [(ratio * a, ratio * b) for a, b in outers], STEEL, "none")
    keep = np.array([i for i in lateral_dofs(n + 1) if i not in (0, 1, 6 * n, 6 * n + 1)])
    M, K, G = (X[np.ix_(keep, keep)] for X in (M, K, G))
    Mr, Kr, Gr = ritz_matrices(L, (d0, d1), ratio, STEEL, None, supported=True)
    first = whirl_frequencies(Mr, Kr, Gr, 0.0, 1)[0]
    spin = speed * 10 * first
    fe, ritz = whirl_frequencies(M, K, G, spin, 4), whirl_frequencies(Mr, Kr, Gr, spin, 4)
    kh = 1.5 * 2 * math.pi / n
    error = fe / ritz - 1
    assert np.all(error > -1e-9) and np.all(error < kh ** 4 / 1000), error


def test_rigid_limit_is_the_packages_rigid_rotor():
    """On rigid motions about its centre of mass, a tapered shaft's M and G are the rigid
    rotor's of assembly.rotor_matrices with the shaft's computed mass properties (spin axis
    z, whose transverse axes are x, y: local and model axes coincide)."""
    from types import SimpleNamespace

    from rotordyn_modal.assembly import rotor_matrices
    from rotordyn_modal.model.geometry import transverse_axes

    np.testing.assert_array_equal(transverse_axes([0.0, 0.0, 1.0]), [[1, 0, 0], [0, 1, 0]])
    lengths, outers, inners = TAPERED
    M, _, G = shaft_matrices(lengths, outers, inners, STEEL)
    props = shaft_mass_properties(lengths, outers, inners, STEEL)
    positions = np.concatenate([[0.0], np.cumsum(lengths)]) - props.center_of_mass
    R = rigid_motions(positions)
    rotor = SimpleNamespace(mass=props.mass, polar_inertia=props.polar_inertia,
                            diametral_inertia=props.diametral_inertia, speed_ratio=1.0)
    mass, gyroscopic = rotor_matrices([0.0, 0.0, 1.0], [rotor])[0]
    np.testing.assert_allclose(R.T @ M @ R, mass, rtol=1e-12, atol=1e-13 * props.mass)
    np.testing.assert_allclose(R.T @ G @ R, gyroscopic, rtol=1e-12, atol=1e-13 * props.polar_inertia)
