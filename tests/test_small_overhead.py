"""A small model's Campbell call without repeated work (benchmarks/README.md, "One rigid rotor"):
a crossing of a double root solved once with its shapes, the refinement's starts computed once
for both of its routes, the whirling pairs' forms by matrix products; each against a closed
form or against the general route, bit for bit."""

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _crossing_refinement, _crossing_roots, _eigensolve, _vectors, _whirl

MASS, POLAR, DIAMETRAL, STIFFNESS, DAMPING, HALF_SPAN = 30.0, 0.4, 0.9, 1e6, 100.0, 0.25


def _rotor():
    """A rigid rotor, centre of mass midway between two like damped bearings: its cylindrical
    whirl (translation, no gyroscopic coupling) is a double root at every speed."""
    return rdm.Model.from_dict({
        "name": "rigid rotor on two bearings",
        "rotors": [{"name": "rotor", "mass": MASS, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": POLAR,
                    "diametral_inertia": DIAMETRAL, "speed_ratio": 1.0}],
        "bearings": [{"name": f"brg-{side}", "rotor": "rotor", "position": [x, 0.0, 0.0], "stiffness": STIFFNESS,
                      "damping": DAMPING} for side, x in (("A", -HALF_SPAN), ("B", HALF_SPAN))]})


def _counted(monkeypatch, module, name):
    """Count the calls of ``module.name`` (a list of one int)."""
    calls, original = [0], getattr(module, name)

    def counted(*args, **kwargs):
        calls[0] += 1
        return original(*args, **kwargs)

    monkeypatch.setattr(module, name, counted)
    return calls


def test_a_double_roots_crossing_is_its_closed_form_solved_once(monkeypatch):
    """The cylindrical whirl m x'' + 2c x' + 2k x = 0 (both directions alike) crosses 1X where
    the spin equals its damped frequency; both of its rows (forward and backward) are there, and
    the roots at the refinement's point are solved once, with their shapes (no ``eigvals`` of the
    same matrices before), the cubic start of every crossing once for both routes (the conical
    mode's by joint Newton, the double root's by the secant)."""
    eigvals = _counted(monkeypatch, _eigensolve, "eigenvalues_of")
    starts = _counted(monkeypatch, _crossing_refinement, "_cubic_start")
    newton = _counted(monkeypatch, _crossing_refinement, "_joint_newton")
    together = _counted(monkeypatch, _crossing_refinement, "_refine_together")
    result = rdm.campbell(_rotor(), rdm.rpm(np.linspace(0.0, 3000.0, 201)), orders=(1,))
    decay = DAMPING / MASS                                        # 2c / (2m)
    damped = np.sqrt(2 * STIFFNESS / MASS - decay**2)             # [rad/s]
    table = result.critical
    cylindrical = np.isclose(table.frequencies_hz, damped / (2 * np.pi), rtol=1e-6)
    assert cylindrical.sum() == 2
    assert set(table.whirl[cylindrical]) == {"forward", "backward"}
    assert np.allclose(np.sort(table.whirl_ratios[cylindrical]), [-1.0, 1.0], rtol=0, atol=1e-9)
    assert np.allclose(table.speeds[cylindrical], damped, rtol=1e-12, atol=0)
    assert np.allclose(table.frequencies_hz[cylindrical], damped / (2 * np.pi), rtol=1e-12, atol=0)
    assert np.allclose(table.damping_ratios[cylindrical], decay / np.sqrt(2 * STIFFNESS / MASS), rtol=1e-9, atol=0)
    assert len(table) > 2 and newton[0] == 1 and together[0] == 1   # both routes taken
    assert eigvals[0] == 0
    assert starts[0] == 1


def test_the_double_roots_shortcut_gives_the_general_routes_bits(monkeypatch):
    """With the shortcut (a crossing whose mode is a double root at both ends of its bracket
    solved with its shapes at once) and without it (``eigvals`` first, then the roots again with
    their shapes), every column of the critical speeds is the same to the bit."""
    model, speeds = _rotor(), rdm.rpm(np.linspace(0.0, 3000.0, 51))
    fast = rdm.campbell(model, speeds, orders=(1, 2)).critical
    assert len(fast) >= 4
    monkeypatch.setattr(_crossing_roots, "_repeated_at_ends", lambda values, brackets, rows: np.zeros(len(rows), bool))
    plain = rdm.campbell(model, speeds, orders=(1, 2)).critical
    for column in ("speeds", "frequencies_hz", "whirl_ratios", "damping_ratios", "mode", "order"):
        assert np.array_equal(getattr(fast, column), getattr(plain, column)), column
    assert list(fast.whirl) == list(plain.whirl)


def test_a_repeated_root_is_told_at_both_ends_of_its_bracket_only():
    """A tracked mode that is a double root at one end of its bracket only (two roots that meet
    there) is not taken for a double root inside it."""
    values = np.array([[[1j, 1j, 2j], [1j, 1.5j, 2j], [1j, 1j + 1e-12, 3j]]])          # (1, 3 speeds, 3)
    brackets = _Rows(variant=np.zeros(3, int), k=np.array([0, 1, 1]), mode=np.array([0, 0, 2]))
    found = _crossing_roots._repeated_at_ends(values, brackets, np.arange(3))
    assert found.tolist() == [False, False, False]
    brackets = _Rows(variant=np.zeros(2, int), k=np.array([0, 0]), mode=np.array([0, 1]))
    values[0, 1, 1] = 1j * (1 + 1e-12)
    assert _crossing_roots._repeated_at_ends(values, brackets, np.arange(2)).tolist() == [True, True]


class _Rows:
    def __init__(self, **columns):
        self.__dict__.update(columns)


@pytest.mark.parametrize("n", [4, 12])
def test_whirling_pairs_of_a_shared_form_a_variants_and_a_stack_of_one_are_alike(n):
    """The pairs' extreme-whirl shapes are the same bits whether the forms are one (n, n) form,
    a stack of one variant's (1, n, n) or the pair's own variant's among several; each pair's
    bits are its own (the pairs alone give the same); and they whirl circularly where the
    pair's plane holds a circular orbit (shapes e_x +- i e_y of a form that weighs x and y alike)."""
    rng = np.random.default_rng(n)
    pairs = 7
    skew = np.zeros((n, n))
    skew[0, 1], skew[1, 0] = 1.0, -1.0                                      # x-y angular momentum
    total = np.diag(np.r_[1.0, 1.0, rng.uniform(1, 2, n - 2)])
    x, y = np.eye(n)[0], np.eye(n)[1]
    circular = np.stack([x + 1j * y, x - 1j * y])                            # (2, n)
    mix = rng.standard_normal((pairs, 2, 2)) + 1j * rng.standard_normal((pairs, 2, 2))
    shapes = _vectors.unit_rows(mix @ circular)                              # (pairs, 2, n): any basis of the plane
    lam = np.full((pairs, 2), -1.0 + 10j)                                     # one double root per row
    forms = _whirl.WhirlForms(skew, np.eye(n), total)
    one = _eigensolve.resolve_repeated(lam, shapes, forms)
    stacked = _whirl.WhirlForms(skew[None], np.eye(n)[None], total[None])
    variants = np.zeros(pairs, int)
    assert np.array_equal(_eigensolve.resolve_repeated(lam, shapes, stacked, variants), one)
    other = rng.standard_normal((n, n))
    several = _whirl.WhirlForms(np.stack([other - other.T, skew]), np.stack([np.eye(n)] * 2),
                                np.stack([other @ other.T + n * np.eye(n), total]))
    assert np.array_equal(_eigensolve.resolve_repeated(lam, shapes, several, variants + 1), one)
    for p in range(pairs):
        assert np.array_equal(_eigensolve.resolve_repeated(lam[p:p + 1], shapes[p:p + 1], forms)[0], one[p])
    ratios = np.einsum("pmi,ij,pmj->pm", one.conj(), -1j * skew, one).real / \
        np.einsum("pmi,ij,pmj->pm", one.conj(), total, one).real
    assert np.allclose(np.sort(ratios, axis=1), [[-1.0, 1.0]] * pairs, rtol=0, atol=1e-12)


def _state_matrices(rng, count, n):
    """State matrices ``[[0, I], [-M^-1 K, -M^-1 C]]`` of random machines, badly scaled (stiffnesses
    over ten decades), some with a free direction (a zero root; without damping there a double
    one, split by round-off into a pair near ``+-sqrt(noise)``) or overdamped (real roots)."""
    out = []
    for p in range(count):
        scale = 10.0 ** rng.uniform(-5, 5, n)
        k = rng.standard_normal((n, n))
        k = (k @ k.T + n * np.eye(n)) * np.sqrt(np.outer(scale, scale))
        c = np.diag(rng.uniform(0, 1, n) * np.sqrt(np.diag(k))) * (10.0 ** rng.uniform(-2, 2))
        if p % 3 == 0:                                      # a free direction
            free = rng.integers(n)
            k[free, :], k[:, free] = 0.0, 0.0
            if p % 2 == 0:
                c[free, :], c[:, free] = 0.0, 0.0
        mass = np.diag(rng.uniform(0.5, 2.0, n))
        inverse = np.linalg.inv(mass)
        out.append(np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ k, -inverse @ c]]))
    return np.array(out)


def test_the_balancing_never_raises_the_frobenius_norm():
    """The bound of ``deciding_round_off``: the balanced norm is at most the plain one, on badly
    scaled random matrices and state matrices alike."""
    from rotordyn_modal.analysis import _roots

    rng = np.random.default_rng(11)
    scales = 10.0 ** rng.uniform(-8, 8, size=(40, 1, 9))
    plain = rng.standard_normal((40, 9, 9)) * scales * np.swapaxes(1.0 / scales, 1, 2)
    plain[rng.random(plain.shape) < 0.3] = 0.0
    for matrices in (plain, _state_matrices(rng, 30, 5)):
        norms = np.linalg.norm(matrices, axis=(1, 2))
        assert np.all(_roots.balanced_norm(matrices) <= norms * (1 + 1e-12))


def test_roots_snapped_with_the_deciding_round_off_are_those_snapped_with_the_round_off():
    """Where a root lies within the bound (a zero root, a split double zero root, a real root's
    round-off) the deciding round-off is the round-off itself; every root is snapped to the same
    bits as with the round-off of every matrix."""
    from rotordyn_modal.analysis import _roots

    rng = np.random.default_rng(12)
    n = 4
    matrices = _state_matrices(rng, 60, n)
    values, vectors = np.linalg.eig(matrices)
    exact = _roots.round_off(matrices)
    deciding = _roots.deciding_round_off(values, matrices)
    assert np.all(deciding >= exact)
    near = (np.abs(values) <= _roots.zero_floor(deciding[:, None])).any(axis=1)
    assert near.sum() >= 10                                   # the free directions' roots
    assert np.array_equal(deciding[near], exact[near])
    assert (deciding > exact).sum() >= 10                   # the others take the bound
    for p in (int(np.argmax(near)), int(np.argmin(near))):   # one matrix alone: the same number
        assert _roots.deciding_round_off(values[p], matrices[p]) == deciding[p]
    assert np.array_equal(_roots.snapped(values, deciding, matrices, vectors, n),
                          _roots.snapped(values, exact, matrices, vectors, n))
    assert np.array_equal(_roots.snapped(values, deciding), _roots.snapped(values, exact))
