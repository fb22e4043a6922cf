"""The lowest modes of a machine whose bearing modes crowd right above the wanted ones (issue 28
item 4, issue 27 item 1.9): a chain of geared rotors, each on two bearings, in a casing on mounts.
Its reduced basis would hold every mode, so shift-invert Arnoldi serves it (``_arnoldi``), with its
own count of the roots below a gap (Sylvester's inertia of ``K_s - w^2 M + i w D_g``).

Truth from outside the code under test: scipy's dense eigenvalues of the full state matrix, and
the invariant of an undamped gyroscopic machine (its roots purely imaginary)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from threadpoolctl import threadpool_limits

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _arnoldi, _lowest, _lowest_bound
from rotordyn_modal.analysis.campbell import lowest_stack

from test_flexible_large import _on_bearings


def _chain(count, damping=1e-4, seed=1, coupled=0):
    """``count`` rigid rotors in a row, each driving the next by a gear, each on two bearings
    (1e7-5e7 N/m, damping ``damping`` s times the stiffness), in a casing twice their mass on six
    mounts (damped as the bearings): ``6 + 5 count`` coordinates (``benchmarks/_machines.py``'s
    ``gear_chain``, its damping a parameter). The bearings of the first ``coupled`` rotors are
    speed-dependent and cross-coupled (a table over +-8,000 rpm of their own speed)."""
    rng = np.random.default_rng(seed)
    rotors, bearings, gears, log_speed = [], [], [], 0.0
    for j in range(count):
        mass = rng.uniform(5.0, 30.0)
        polar = mass * rng.uniform(0.002, 0.01)
        centre = [rng.uniform(-0.1, 0.1), (j - (count - 1) / 2) * 0.3, 0.2]
        rotor = {"name": f"r{j:02d}", "mass": mass, "center_of_mass": centre, "polar_inertia": polar,
                 "diametral_inertia": polar * rng.uniform(0.6, 2.0)}
        if j == 0:
            rotor["speed_ratio"] = 1.0
        else:
            step = float(np.clip(rng.uniform(-0.22, 0.22), -0.5 - log_speed, 0.5 - log_speed))
            log_speed += step
            gears.append({"type": "gear", "driver": f"r{j - 1:02d}", "driven": rotor["name"],
                          "ratio": float(np.exp(-step))})
        rotors.append(rotor)
        k = rng.uniform(1e7, 5e7)
        for side, offset in (("DE", rng.uniform(0.08, 0.15)), ("NDE", -rng.uniform(0.08, 0.15))):
            bearing = {"name": f"{rotor['name']}-{side}", "rotor": rotor["name"],
                       "position": [centre[0] + offset, centre[1], centre[2]], "stiffness": k, "damping": damping * k}
            if side == "DE":
                bearing["axial_stiffness"] = 0.5 * k
            if j < coupled:
                bearing.update(speeds_rpm=[-8000.0, 8000.0], stiffness=[[[k, 0.0], [0.0, k]], [[k, 0.2 * k], [-0.2 * k, 1.1 * k]]],
                               damping=[damping * k, 2 * damping * k])
                if "axial_stiffness" in bearing:
                    bearing["axial_stiffness"] = [0.5 * k, 0.5 * k]
            bearings.append(bearing)
    casing = 2 * sum(r["mass"] for r in rotors)
    length = count * 0.3
    inertia = casing / 12 * np.diag([length ** 2 + 0.16, 0.36 + 0.16, length ** 2 + 0.36])
    mounts = [{"name": f"mount-{i}", "position": [x, y, -0.1], "stiffness": [3e6, 3e6, 6e6],
               "damping": [damping * 3e6, damping * 3e6, damping * 6e6]}
              for i, (x, y) in enumerate((x, y) for y in (length / 2, 0.0, -length / 2) for x in (0.3, -0.3))]
    return rdm.Model.from_dict({
        "name": "chain", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "r00",
        "stator": {"mass": casing, "center_of_mass": [0.0, 0.0, 0.1], "inertia": inertia.tolist()},
        "rotors": rotors, "transmissions": gears, "bearings": bearings, "suspensions": mounts})


@pytest.fixture
def arnoldi_calls(monkeypatch):
    """The number of sweeps served by shift-invert Arnoldi, counted."""
    calls = []
    real = _arnoldi.lowest

    def counted(*args, **kwargs):
        calls.append(len(args[0].speeds))
        return real(*args, **kwargs)

    monkeypatch.setattr(_arnoldi, "lowest", counted)
    return calls


def _dense_lowest(stack, speed, count):
    """The ``count`` lowest-frequency roots of the full state matrix at ``speed`` by scipy (Im > 0)."""
    with threadpool_limits(1):              # BLAS's threads only wait for a core on a loaded machine
        roots = scipy.linalg.eigvals(stack.sweep(np.array([speed]))[0][0])
    roots = roots[roots.imag > 0]
    return roots[np.argsort(roots.imag)][:count]


def test_a_chain_of_24_rotors_takes_arnoldi_and_equals_the_dense_roots(arnoldi_calls):
    """24 rotors (126 coordinates): the 12 lowest roots at 0, 1,500 and 3,000 rpm (6 mount modes,
    6 of the crowded bearing modes) are scipy's roots of the full state matrix to 1e-9 relative,
    none of the speeds solved whole."""
    model = _chain(24)
    stack = lowest_stack(model)
    speeds = rdm.rpm(np.array([0.0, 1500.0, 3000.0]))
    lam, shapes, full = _lowest.lowest_roots(stack, speeds, 12)
    assert arnoldi_calls == [3] and not full.any(), (arnoldi_calls, full)
    M, C, G, K = (np.asarray(x) for x in (stack.M[0], stack.C[0], stack.G[0], stack.K[0]))
    for p, speed in enumerate(speeds):
        dense = _dense_lowest(stack, speed, 12)
        assert np.max(np.abs(lam[p] - dense) / np.abs(dense)) < 1e-9
        # each shape is its root's: the pencil's residual at round-off
        s, x = lam[p][:, None], shapes[p]
        with threadpool_limits(1):
            residual = s * s * (x @ M.T) + s * (x @ (C + speed * G).T) + x @ K.T
        scale = np.abs(s[:, 0]) ** 2 * np.abs(M).sum(0).max() + np.abs(s[:, 0]) * np.abs(C + speed * G).sum(0).max() \
            + np.abs(K).sum(0).max()
        assert np.all(np.linalg.norm(residual, axis=1) <= 1e-10 * scale)


def test_an_undamped_gyroscopic_chain_keeps_its_roots_imaginary(arnoldi_calls):
    """Without damping (bearings and mounts), the gyroscopic chain is conservative: every root is
    purely imaginary. The 12 lowest by Arnoldi keep ``|Re s| <= 1e-9 |s|`` and equal scipy's to
    1e-9; the count by inertia of the conservative pencil equals the number of roots below."""
    model = _chain(20, damping=0.0)
    stack = lowest_stack(model)
    speeds = rdm.rpm(np.array([1000.0, 3000.0]))
    lam, _, full = _lowest.lowest_roots(stack, speeds, 12)
    assert arnoldi_calls == [2] and not full.any()
    assert np.all(np.abs(lam.real) <= 1e-9 * np.abs(lam))
    for p, speed in enumerate(speeds):
        dense = _dense_lowest(stack, speed, 12)
        assert np.max(np.abs(lam[p].imag - dense.imag) / np.abs(dense)) < 1e-9


def test_the_inertia_count_is_the_number_of_roots_below():
    """``count_below`` at frequencies between the roots of an undamped chain (from scipy's dense
    eigenvalues) counts the roots below each, and at a frequency past all the mount modes the six."""
    model = _chain(20, damping=0.0)
    stack = lowest_stack(model)
    speed = rdm.rpm(2000.0)
    pencils = _lowest._Pencils(stack, np.array([speed]))
    parts = _arnoldi._Parts(pencils)
    roots = np.sort(_dense_lowest(stack, speed, 40).imag)
    middles = 0.5 * (roots[:-1] + roots[1:])
    for j in (0, 3, 5, 6, 11, 25, 38):
        assert _arnoldi.count_below(parts, 0, middles[j]) == j + 1
    assert _arnoldi.count_below(parts, 0, 0.5 * roots[0]) == 0


def test_a_root_the_arnoldi_step_misses_is_caught(monkeypatch, arnoldi_calls):
    """Where ARPACK's roots lack one at the first speed (the lowest pair removed, as a Krylov
    method can miss a root), the count below the gap disagrees at every try: that speed is solved
    whole, the next one (speed-dependent cross-coupled bearings) by Arnoldi, and the roots of both
    are scipy's."""
    model = _chain(20, coupled=6)
    stack = lowest_stack(model)
    real, tries = _arnoldi._arnoldi, []

    def missing(*args):
        lam, x = real(*args)
        tries.append(len(lam))
        if len(tries) > 2:                  # the first speed's tries only
            return lam, x
        keep = np.abs(lam) > np.min(np.abs(lam)) * (1 + 1e-9)
        return lam[keep], x[:, keep]

    monkeypatch.setattr(_arnoldi, "_arnoldi", missing)
    monkeypatch.setattr(_arnoldi, "_TRIES", 2)        # each try misses it: two show it (and cost less)
    speeds = rdm.rpm(np.array([1500.0, 2500.0]))
    with pytest.warns(UserWarning, match="solved whole"), threadpool_limits(1):
        lam, _, full = _lowest.lowest_roots(stack, speeds, 12)
    assert arnoldi_calls == [2] and list(full) == [True, False]
    for p, speed in enumerate(speeds):
        dense = _dense_lowest(stack, speed, 12)
        assert np.max(np.abs(lam[p] - dense) / np.abs(dense)) < 1e-9


def test_models_whose_basis_is_small_keep_the_reduced_route(arnoldi_calls):
    """A flexible shaft of 30 elements (124 coordinates, its bending modes spread) keeps the
    reduced basis: Arnoldi is never called."""
    model = _on_bearings(30)
    assert model.dofs.n >= _arnoldi.MIN_DOF
    rdm.campbell(model, rdm.rpm(np.array([600.0, 3000.0])), modes=6, critical=False)
    assert arnoldi_calls == []
    assert _arnoldi.takes(60, 100) and not _arnoldi.takes(50, 100) and not _arnoldi.takes(99, 99)


def test_mode_numbers_after_a_lowest_sweep_come_from_the_lowest_roots(monkeypatch):
    """The number ``modes --speed`` gives a crossing's root after ``--lowest 12`` (where the
    sweep's interpolation cannot tell it) is its rank among the lowest roots at that speed, as
    scipy's dense roots rank it, without the state matrix's every root (its eigen-solution is never
    called: about a minute per speed at 5,000 states)."""
    from rotordyn_modal.analysis import _eigensolve, mode_numbers

    model = _chain(20)
    stack = lowest_stack(model)
    speeds = rdm.rpm(np.array([700.0, 2300.0]))
    dense = [_dense_lowest(stack, speed, 12) for speed in speeds]

    def refused(*args, **kwargs):
        raise AssertionError("every root of the state matrix solved")

    monkeypatch.setattr(_eigensolve, "eigenvalues_of", refused)
    wanted = [(0, 2), (0, 7), (1, 11), (1, 0)]
    numbers = mode_numbers._solved_numbers(model, speeds[[p for p, _ in wanted]],
                                           np.array([dense[p][j] for p, j in wanted]), lowest=12)
    assert list(numbers) == [j + 1 for _, j in wanted]


def test_the_modes_below_a_frequency_of_a_crowded_chain_take_arnoldi(monkeypatch):
    """``campbell(max_frequency=F)`` of the 24-rotor chain (its basis would hold every mode): by
    Arnoldi, not the full eigen-solve of every speed. Below 700 and 1,000 rad/s (9 and 19 or 20 roots;
    with ``modes=5``, the lowest 5 of them) the roots are scipy's roots of the full state matrix
    below F, as many and each to 1e-9 relative; the roots found are doubled from 12 until they pass F."""
    def refused(*args, **kwargs):
        raise AssertionError("a speed was solved whole")

    monkeypatch.setattr(_lowest, "_full_lowest", refused)
    model = _chain(24)
    stack = lowest_stack(model)
    speeds = rdm.rpm(np.array([0.0, 1500.0, 3000.0]))
    dense = [_dense_lowest(stack, speed, stack.n_dof) for speed in speeds]
    for limit, count in ((700.0, None), (1000.0, None), (1000.0, 5)):
        values, _, wanted, full = _lowest.roots_below(stack, speeds, limit, count)
        assert not full.any()
        for p in range(len(speeds)):
            expected = dense[p][dense[p].imag <= limit][:count]
            got = values[p][wanted[p]]
            assert len(got) == len(expected) == (count or len(expected)) and len(expected) >= 5
            assert np.max(np.abs(got - expected) / np.abs(expected)) < 1e-9
    result = rdm.campbell(model, speeds, critical=False, max_frequency=700.0 / (2 * np.pi))
    assert np.allclose(np.sort(result.frequencies_hz[0][np.isfinite(result.frequencies_hz[0])]),
                       np.sort(dense[0][dense[0].imag <= 700.0].imag) / (2 * np.pi), rtol=1e-9)


def test_a_crowded_chain_is_told_before_the_dense_set_up(monkeypatch):
    """The cheap test (``_lowest_route._crowded``: one mode from the middle of the spectrum by inertia
    counts and sparse Lanczos, a lower bound of the completeness bound) sends the 24-rotor chain to
    Arnoldi without the reduced route's ``eigh`` of every mode (``_lowest_bound._basis``), and says
    so only where that route's own rule (the bound from every mode) does too; the flexible shaft of 124 coordinates is not told
    crowded (its set-up decides, as before). Its 12 lowest roots are still scipy's to 1e-9."""
    from rotordyn_modal.analysis._lowest import _MARGIN, _Pencils, _needed_size, _projected_starts, _stack_bound
    from rotordyn_modal.analysis._lowest_route import _crowded

    speeds = rdm.rpm(np.array([0.0, 3000.0]))
    for model, crowded in ((_chain(24), True), (_on_bearings(30), False)):
        stack = lowest_stack(model)
        pencils = _Pencils(stack, speeds)
        assert _crowded(stack, pencils, count=12) == crowded
        assert _crowded(stack, pencils, limit=700.0) == crowded
        if not crowded:
            continue
        # the reduced route's own rule from every undamped mode
        bound = _stack_bound(stack, pencils)
        n = stack.n_dof
        rho = _MARGIN * np.max(np.abs(_projected_starts(pencils, bound.modes[:, :36], 13)[0]))
        size = min(n, max(_needed_size(bound, rho, 36), 13))
        attached = bound.shares(size, rho)[1] if size < n else np.zeros((n, 0))
        assert _arnoldi.takes(size + attached.shape[1], n)

    def refused(*args, **kwargs):
        raise AssertionError("the dense set-up was made")

    monkeypatch.setattr(_lowest_bound, "_basis", refused)
    stack = lowest_stack(_chain(24))
    lam, _, full = _lowest.lowest_roots(stack, speeds, 12)
    assert not full.any()
    for p, speed in enumerate(speeds):
        dense = _dense_lowest(stack, speed, 12)
        assert np.max(np.abs(lam[p] - dense) / np.abs(dense)) < 1e-9
