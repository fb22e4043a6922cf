"""Plain short journal bearing (rotordyn_modal.elements.journal_bearing) against independent results.

``journal_reference.py`` shares no code with the package: it integrates the short-bearing
pressure by quadrature over the positive-pressure arc, finds the static equilibrium by
root-finding on that force and differentiates it numerically. The closed forms used below
(load capacity, attitude angle, light-load limits, Lund's threshold) are derived in
docs/theory.md section 12.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from scipy import optimize

import journal_reference as reference
from rotordyn_modal.elements.journal_bearing import short_journal_bearing
from rotordyn_modal.errors import InputError

GEOMETRY = dict(diameter=0.05, length=0.02, clearance=50e-6, viscosity=0.03)
BEARING = reference.Bearing(**GEOMETRY)
SPEED = 300.0  # [rad/s]
MIRROR = np.array([[1.0, -1.0], [-1.0, 1.0]])  # y -> -y applied to a 2x2 coefficient matrix


def reference_load(eps, speed=SPEED):
    """Load [N] that puts the journal at eccentricity ``eps``, by quadrature of the pressure."""
    return np.hypot(*reference.film_force(BEARING, (eps * BEARING.clearance, 0.0), (0.0, 0.0), speed))


def bearing_at(speed, load, **changes):
    return short_journal_bearing(np.atleast_1d(speed), load=load, **{**GEOMETRY, **changes})


def scaled_error(value, expected):
    return np.abs(value - expected).max() / np.abs(expected).max()


# --- coefficients against finite differences of the quadrature force ---

@pytest.mark.parametrize("direction", [1.0, -1.0])
@pytest.mark.parametrize("eps", [0.05, 0.2, 0.4, 0.6, 0.8, 0.95])
def test_coefficients_equal_finite_differences_of_the_film_force(eps, direction):
    """All eight coefficients, the eccentricity and the attitude angle, both spin directions.

    The reference's finite-difference error is about 1e-10 of the largest coefficient
    (fourth-order differences, step 1e-3 of the force's length scale; quadrature to 1e-12
    relative divided by the step gives about 1e-9), so 1e-7 leaves a margin of 100.
    """
    speed = direction * SPEED
    load = reference_load(eps, speed)
    stiffness, damping, eps_ref, attitude_ref = reference.coefficients_by_differences(
        BEARING, load, speed)
    result = bearing_at(speed, load)
    assert eps_ref == pytest.approx(eps, abs=1e-13)
    assert result.eccentricity[0] == pytest.approx(eps_ref, abs=1e-13)
    assert result.attitude_angle[0] == pytest.approx(attitude_ref, abs=1e-12)
    assert scaled_error(result.stiffness[0], stiffness) < 1e-7
    assert scaled_error(result.damping[0], damping) < 1e-7
    # the short bearing's damping is symmetric (docs eq. 12.10): here from the differences alone
    assert abs(damping[0, 1] - damping[1, 0]) < 1e-7 * np.abs(damping).max()
    # the reference's fast route (derivatives of the pressure integrand, used by lund_threshold)
    _, stiffness_q, damping_q, attitude_q = reference.coefficients_by_quadrature(BEARING, eps, speed)
    assert scaled_error(stiffness_q, stiffness) < 1e-7
    assert scaled_error(damping_q, damping) < 1e-7
    assert attitude_q == pytest.approx(attitude_ref, abs=1e-12)


# --- closed forms of the static equilibrium ---

@pytest.mark.parametrize("eps", [1e-3, 0.1, 0.5, 0.9, 0.99])
def test_load_capacity_and_attitude_angle_closed_forms(eps):
    """Quadrature force = mu w R L³ eps sqrt(16 eps² + pi² (1 - eps²)) / (4 c² (1 - eps²)²),
    at tan(phi) = pi sqrt(1 - eps²) / (4 eps) from the load line (docs eqs. 12.7, 12.8)."""
    mu, c, L, R = BEARING.viscosity, BEARING.clearance, BEARING.length, BEARING.radius
    force = reference.film_force(BEARING, (eps * c, 0.0), (0.0, 0.0), SPEED)
    s = 1 - eps**2
    load = mu * SPEED * R * L**3 * eps * np.sqrt(16 * eps**2 + np.pi**2 * s) / (4 * c**2 * s**2)
    assert np.hypot(*force) == pytest.approx(load, rel=1e-11)
    # the load is -force; the journal (on +x) sits at angle phi from it in the spin direction
    load_direction = -force / np.hypot(*force)
    phi = np.arctan2(-load_direction[1], load_direction[0])
    assert phi == pytest.approx(np.arctan2(np.pi * np.sqrt(s), 4 * eps), abs=1e-12)


@pytest.mark.parametrize("speed", [1e-6, 1e-3, 1.0, 300.0, 1e5, 1e9, -300.0])
def test_eccentricity_solves_the_load_capacity_to_round_off(speed):
    """The Raimondi-Boyd Sommerfeld number from the data, and the Ocvirk relation
    S (L/D)² = (1 - eps²)² / (pi eps sqrt(16 eps² + pi² (1 - eps²))) at the returned eps,
    to round-off (relative condition of the right side ~ 1 + 4 eps² / (1 - eps²))."""
    load = 500.0
    result = bearing_at(speed, load)
    mu, D, L, c = (GEOMETRY[k] for k in ("viscosity", "diameter", "length", "clearance"))
    sommerfeld = mu * abs(speed) / (2 * np.pi) * D * L / load * (0.5 * D / c)**2
    assert result.sommerfeld[0] == pytest.approx(sommerfeld, rel=1e-14)
    eps = result.eccentricity[0]
    s = (1 - eps) * (1 + eps)
    capacity = s**2 / (np.pi * eps * np.sqrt(16 * eps**2 + np.pi**2 * s))
    condition = 1 + 4 * eps**2 / s
    assert capacity == pytest.approx(sommerfeld * (L / D)**2, rel=20 * np.finfo(float).eps * condition)
    assert 0 < eps < 1


def test_light_load_limits():
    """A centred journal (eps -> 0): the film force is the tangential force
    k0 e × r - (2 k0 / w) r', k0 = pi mu w R L³ / (4 c³), plus the load's own terms
    (W/c) diag(4/pi, 8/pi) in K and (W/(c w)) 8/pi in c_xy = c_yx; remainders O(eps²)
    (docs eq. 12.12)."""
    mu, c, L, R = BEARING.viscosity, BEARING.clearance, BEARING.length, BEARING.radius
    load = 1e-4 * np.pi * mu * SPEED * R * L**3 / (4 * c**2)  # eps ~ 1e-4
    result = bearing_at(SPEED, load)
    assert result.eccentricity[0] == pytest.approx(1e-4, rel=1e-6)
    k0 = np.pi * mu * SPEED * R * L**3 / (4 * c**3)
    stiffness = k0 * np.array([[0.0, 1.0], [-1.0, 0.0]]) + load / c * np.diag([4 / np.pi, 8 / np.pi])
    damping = 2 * k0 / SPEED * np.eye(2) + load / (c * SPEED) * 8 / np.pi * np.array([[0, 1], [1, 0]])
    np.testing.assert_allclose(result.stiffness[0], stiffness, rtol=1e-6)
    np.testing.assert_allclose(result.damping[0], damping, rtol=1e-6)
    assert result.attitude_angle[0] == pytest.approx(np.pi / 2, abs=1e-3)


# --- properties over random bearings ---

positive = st.floats(0.1, 10.0)


@settings(max_examples=60, deadline=None)
@given(diameter=st.floats(0.01, 0.5), ratio=st.floats(0.1, 0.6), clearance=st.floats(1e-3, 3e-3),
       viscosity=st.floats(1e-3, 0.2), load=st.floats(1.0, 1e5), speed=st.floats(1.0, 3000.0),
       factor=positive, factor2=positive)
@example(diameter=0.01, ratio=0.1, clearance=0.001953125, viscosity=0.001953125, load=2442.0, speed=1.0,
         factor=1.0, factor2=1.0)     # a film of 1 nm: refused, outside the domain
def test_scaling_and_mirror(diameter, ratio, clearance, viscosity, load, speed, factor, factor2):
    """K = W/c k(sigma), C = W/(c |w|) c(sigma), sigma = mu |w| D L³ / (8 W c²):
    load and speed scaled together scale K and leave C; viscosity up and speed down by the same
    factor leave K and scale C; turning the other way mirrors y -> -y. C is positive definite."""
    data = dict(diameter=diameter, length=ratio * diameter, clearance=clearance * diameter,
                viscosity=viscosity)
    try:
        base = short_journal_bearing([speed, -speed], load=load, **data)
        faster = short_journal_bearing([factor * speed], load=factor * load, **data)
        thicker = short_journal_bearing([speed / factor2], load=load,
                                        **{**data, "viscosity": viscosity * factor2})
    except InputError as error:   # outside the film theory's domain: a film under 1 nm is refused
        assume("thinnest film" not in str(error))
        raise
    np.testing.assert_allclose(faster.stiffness[0], factor * base.stiffness[0], rtol=1e-10,
                               atol=1e-12 * factor * np.abs(base.stiffness[0]).max())
    np.testing.assert_allclose(faster.damping[0], base.damping[0], rtol=1e-10,
                               atol=1e-12 * np.abs(base.damping[0]).max())
    np.testing.assert_allclose(thicker.stiffness[0], base.stiffness[0], rtol=1e-10,
                               atol=1e-12 * np.abs(base.stiffness[0]).max())
    np.testing.assert_allclose(thicker.damping[0], factor2 * base.damping[0], rtol=1e-10,
                               atol=1e-12 * factor2 * np.abs(base.damping[0]).max())
    np.testing.assert_array_equal(base.stiffness[1], MIRROR * base.stiffness[0])
    np.testing.assert_array_equal(base.damping[1], MIRROR * base.damping[0])
    assert base.attitude_angle[1] == -base.attitude_angle[0]
    assert base.eccentricity[1] == base.eccentricity[0]
    assert (np.linalg.eigvalsh(base.damping) > 0).all()


def test_vectorised_over_speeds_equals_one_at_a_time():
    speeds = np.geomspace(0.5, 5e4, 200) * np.where(np.arange(200) % 3, 1, -1)
    together = bearing_at(speeds, 800.0)
    for i in (0, 57, 133, 199):
        alone = bearing_at(speeds[i], 800.0)
        for field in together._fields:
            np.testing.assert_array_equal(getattr(together, field)[i], getattr(alone, field)[0])


# --- bad input ---

@pytest.mark.parametrize("speed", [0.0, [100.0, 0.0, 200.0]])
def test_zero_speed_is_refused(speed):
    with pytest.raises(InputError, match=r"speed = 0 rpm.*no oil film.*above zero"):
        short_journal_bearing(speed, load=100.0, **GEOMETRY)


def test_film_that_cannot_carry_the_load_is_refused():
    with pytest.raises(InputError, match=r"at speed 9\.5\d*e-33 rpm the oil film cannot carry the "
                                         r"load of 100 N: eccentricity 1 \(expected < 1"):
        short_journal_bearing([300.0, 1e-33], load=100.0, **GEOMETRY)


def test_overflowing_coefficients_are_refused():
    with pytest.raises(InputError, match=r"at speed 9\.5\d*e\+305 rpm the coefficients overflow"):
        short_journal_bearing([1e305], load=1.0, **GEOMETRY)


@pytest.mark.parametrize("name, value", [
    ("clearance", 0.0), ("clearance", -1e-5), ("load", float("nan")), ("viscosity", float("inf")),
    ("diameter", "big"), ("length", [0.02, 0.03]), ("load", None)])
def test_bad_data_is_refused_naming_argument_and_value(name, value):
    data = {**GEOMETRY, "load": 100.0, name: value}
    expected = re.escape(f"{name} = {value!r}: expected a finite number > 0")
    with pytest.raises(InputError, match=expected):
        short_journal_bearing([100.0], **data)


@pytest.mark.parametrize("speed", [float("nan"), [1.0, float("inf")]])
def test_non_finite_speed_is_refused(speed):
    with pytest.raises(InputError, match="speed = .* expected finite speeds"):
        short_journal_bearing(speed, load=100.0, **GEOMETRY)


# --- Lund's stability threshold ---

@settings(max_examples=60, deadline=None)
@given(diagonal=st.lists(st.floats(1, 2), min_size=4, max_size=4),
       cross=st.lists(st.floats(2, 10), min_size=2, max_size=2),
       damping_cross=st.lists(st.floats(-0.05, 0.05), min_size=2, max_size=2))
def test_lund_parameters_solve_the_characteristic_determinant(diagonal, cross, damping_cross):
    """m = K_eq / w² makes det(K + i w C - w² m I) = 0 (docs eq. 12.14-12.15), for bearing-like
    2x2 K and C: positive diagonals, cross-coupled stiffness of opposite signs (so that w² > 0),
    small non-symmetric cross damping."""
    stiffness = np.array([[diagonal[0], cross[0]], [-cross[1], diagonal[1]]])
    damping = np.array([[diagonal[2], damping_cross[0]], [damping_cross[1], diagonal[3]]])
    k_eq, w2 = reference.lund_parameters(stiffness, damping)
    assert k_eq > 0 and w2 > 0
    w, mass = np.sqrt(w2), k_eq / w2
    determinant = np.linalg.det(stiffness + 1j * w * damping - w2 * mass * np.eye(2))
    scale = (np.abs(stiffness).max() + w * np.abs(damping).max() + k_eq)**2
    assert abs(determinant) < 1e-12 * scale


def largest_eigenvalue(mass, speed):
    """Eigenvalue of largest real part of the cylindrical mode, m x'' + C x' + K x = 0 per bearing,
    with the package's coefficients for the load m g."""
    result = bearing_at(speed, mass * reference.GRAVITY)
    stiffness, damping = result.stiffness[0], result.damping[0]
    state = np.block([[np.zeros((2, 2)), np.eye(2)], [-stiffness / mass, -damping / mass]])
    eigenvalues = np.linalg.eigvals(state)
    return eigenvalues[np.argmax(eigenvalues.real)]


@pytest.mark.parametrize("mass", [1.0, 50.0, 400.0])
def test_lund_threshold_equals_the_eigenvalue_crossing(mass):
    """The speed at which the 4x4 system built from the package's coefficients loses stability
    (root of the largest real part by Brent) equals the reference threshold. The eigenvalues'
    round-off (~1e-13 of |lambda| ~ 600 rad/s) over the real part's slope (~1e-2 per rad/s)
    moves the crossing by ~1e-11 rad/s, far below the 1e-9 relative asserted."""
    speed, ratio = reference.lund_threshold(mass, **GEOMETRY)
    assert largest_eigenvalue(mass, 0.999 * speed).real < 0
    assert largest_eigenvalue(mass, 1.001 * speed).real > 0
    crossing = optimize.brentq(lambda w: largest_eigenvalue(mass, w).real,
                               0.99 * speed, 1.01 * speed, xtol=1e-12, rtol=1e-15)
    assert crossing == pytest.approx(speed, rel=1e-9)
    assert abs(largest_eigenvalue(mass, crossing).imag) / crossing == pytest.approx(ratio, rel=1e-9)


def test_lund_threshold_light_rotor_whirls_at_half_speed():
    """Light load: gamma -> 1/2 and K_eq -> (6/pi) W/c, so the threshold tends to
    sqrt(24 g / (pi c)), twice the natural frequency sqrt(K_eq / m) (docs); remainder O(eps²)."""
    speed, ratio = reference.lund_threshold(1e-3, **GEOMETRY)
    assert ratio == pytest.approx(0.5, abs=1e-8)
    assert speed == pytest.approx(np.sqrt(24 * reference.GRAVITY / (np.pi * GEOMETRY["clearance"])),
                                  rel=1e-8)


def test_short_bearing_stable_for_every_mass_above_eccentricity_0756():
    """gamma² changes sign at eps ~ 0.7564 (the figure usually quoted as 0.756): above it no
    whirl frequency solves the threshold condition, whatever the rotor's mass."""
    def whirl_squared(eps):
        _, stiffness, damping, _ = reference.coefficients_by_quadrature(BEARING, eps, SPEED)
        return reference.lund_parameters(stiffness, damping)[1]

    assert whirl_squared(0.755) > 0 > whirl_squared(0.758)



def _speed_at_eccentricity(gap_ratio, load=100.0):
    """Speed [rad/s] putting the journal at eccentricity 1 - gap_ratio, from the Ocvirk load
    capacity sigma = (1 - eps²)² / (eps sqrt(16 eps² + pi² (1 - eps²))) written in gap_ratio."""
    eps, v = 1.0 - gap_ratio, gap_ratio * (2.0 - gap_ratio)          # v = 1 - eps², exactly
    sigma = v**2 / (eps * np.sqrt(16 * eps**2 + np.pi**2 * v))
    mu, D, L, c = (GEOMETRY[k] for k in ("viscosity", "diameter", "length", "clearance"))
    return sigma * 8 * load * c**2 / (mu * D * L**3)


@pytest.mark.parametrize("gap_ratio", [2e-14, 1e-8, 1.9e-5])
def test_a_film_thinner_than_a_nanometre_is_refused(gap_ratio):
    """At eccentricity 1 - 2e-14 the film is 1e-18 m thin (clearance 50 um): the continuum film
    means nothing there, so the coefficients are refused as at eccentricity 1 (they were given,
    ~1e18 N/m)."""
    speed = _speed_at_eccentricity(gap_ratio)
    with pytest.raises(InputError, match=r"oil film cannot carry the load of 100 N: eccentricity 0\.99.*"
                                         r"\(thinnest film .* m, expected at least 1e-09 m"):
        short_journal_bearing([300.0, speed], load=100.0, **GEOMETRY)


def test_a_film_of_a_few_nanometres_is_still_given():
    speed = _speed_at_eccentricity(2.1e-5)                # thinnest film 1.05 nm
    result = short_journal_bearing([speed], load=100.0, **GEOMETRY)
    assert 1 - result.eccentricity[0] == pytest.approx(2.1e-5, rel=1e-6)
