"""The banded Newton solves of a lowest-modes sweep (``_lowest_pencils``, issue 28, speed): the band
storage made by one product of M, C, G, K laid out once (``_Pencils._band_storage``), ``Q'(s) x``
(``_Pencils.derivative_times``), and LAPACK's banded LU called so that other threads run meanwhile
(``_lowest_pencils._zgbsv``). Truth from outside the code under test: the model's dense matrices
from its stack (``Stack.damping_stiffness``), numpy's dense products and solves, and whether a
second thread gets to run while the solves go on."""

from __future__ import annotations

import sys
import threading
import time

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest_pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor

SPEED_TABLES = "tests/data/ross/speed_tables.toml"


def _dense_pencils(stack, speeds, lam):
    """``s^2 M + s (C + Omega G + C_b) + K + K_b`` (P, n, n) from the stack's dense matrices."""
    damping, stiffness = stack.damping_stiffness(np.zeros(len(speeds), int), speeds)
    return lam[:, None, None] ** 2 * stack.M[0] + lam[:, None, None] * damping + stiffness


def test_band_storage_and_derivative_equal_the_dense_pencils():
    """ROSS's speed_tables rotor (44 coordinates, bearings tabulated over speed: their entries
    change with the speed): every pencil's band storage holds its dense matrix's entries on the
    band (``ab[j, kl + ku + i - j] = Q[i, j]`` in the band's order) and zeros elsewhere, and
    ``Q'(s) x = (2 s M + C + Omega G + C_b) x`` to round-off."""
    model = rdm.Model.from_dict(read_ross_rotor(SPEED_TABLES))
    stack = Stack([model])
    rng = np.random.default_rng(3)
    speeds = np.linspace(100.0, 1000.0, 4)
    pencils = _lowest_pencils._Pencils(stack, speeds)
    band = pencils.band
    assert band is not None and band.size == stack.n_dof                # a shaft: no border
    index = np.array([0, 1, 2, 3, 3, 0])
    lam = rng.normal(size=6) * 30 + 1j * rng.uniform(100, 3000, 6)
    ab, border = pencils._band_storage(index, lam)
    assert border.shape == (6, 0)
    Q = _dense_pencils(stack, speeds[index], lam)[:, band.order][:, :, band.order]
    n, kl, ku = stack.n_dof, band.lower, band.upper
    expected = np.zeros_like(ab)
    i, j = np.indices((n, n))
    inside = (i - j <= kl) & (j - i <= ku)
    expected[:, j[inside], kl + ku + i[inside] - j[inside]] = Q[:, inside]
    scale = np.abs(Q).max(axis=(1, 2))[:, None, None]
    assert np.all(np.abs(ab - expected) <= 1e-14 * scale)
    assert not np.any(Q[:, ~inside])                                     # the band holds every entry

    x = rng.normal(size=(6, n)) + 1j * rng.normal(size=(6, n))
    damping, _ = stack.damping_stiffness(np.zeros(6, int), speeds[index])
    derivative = 2 * lam[:, None, None] * stack.M[0] + damping
    exact = np.einsum("pij,pj->pi", derivative, x)
    found = pencils.derivative_times(index, lam, x)
    assert np.max(np.abs(found - exact)) <= 1e-13 * np.max(np.abs(exact))


def test_banded_solves_let_other_threads_run():
    """A sweep's banded solves are shared between threads: LAPACK's ``zgbsv`` must release the
    GIL while it works (scipy's wrapper does not: a second thread then starts only after the
    first's solves are done). With the interpreter's switch interval at 5 s, a thread started
    while another runs 400 solves, then goes on solving for up to 2 s until that thread has run,
    gets to run before they end; the solutions are numpy's. (The 2 s keep the test from reading
    a loaded machine's slow scheduling of the second thread as a held GIL: 400 solves take a few
    ms; a wrapper that holds the GIL keeps the second thread out for the whole 2 s, under the 5 s
    switch interval.)"""
    rng = np.random.default_rng(8)
    count, n, kl, ku = 400, 100, 7, 7
    width = 2 * kl + ku + 1
    ab = np.zeros((count, n, width), complex)
    ab[:, :, kl:] = rng.normal(size=(count, n, kl + ku + 1)) + 1j * rng.normal(size=(count, n, kl + ku + 1))
    ab[:, :, kl + ku] += 20.0                                            # well conditioned
    dense = np.zeros((2, n, n), complex)                                 # the first two, dense
    for p in range(2):
        for j in range(n):
            for i in range(max(0, j - ku), min(n, j + kl + 1)):
                dense[p, i, j] = ab[p, j, kl + ku + i - j]
    y = rng.normal(size=(count, 1, n)) + 0j
    rhs = y[:2, 0].copy()
    # small systems to go on solving (copies of under numpy's 500 elements: numpy's own copy,
    # like scipy's wrapper, keeps the GIL, so only the solve itself can let the other thread in)
    small_ab = np.zeros((4, 12), complex, order="F")                     # kl = ku = 1
    small_ab[1:] = rng.normal(size=(3, 12))
    small_ab[2] += 20.0
    small_y = np.asfortranarray(rng.normal(size=(12, 1)) + 0j)
    stamps = {}

    def solves():
        stamps["start"] = time.perf_counter()
        for p in range(count):
            assert _lowest_pencils._zgbsv(kl, ku, ab[p].T, y[p].T, overwrite_ab=1, overwrite_b=1)[3] == 0
        while "other" not in stamps and time.perf_counter() < stamps["start"] + 2.0:
            a, b = small_ab.copy(order="F"), small_y.copy(order="F")
            assert _lowest_pencils._zgbsv(1, 1, a, b, overwrite_ab=1, overwrite_b=1)[3] == 0
        stamps["end"] = time.perf_counter()

    def other():
        stamps["other"] = time.perf_counter()

    interval = sys.getswitchinterval()
    sys.setswitchinterval(5.0)
    try:
        first = threading.Thread(target=solves)
        first.start()
        while "start" not in stamps:
            time.sleep(0.001)
        second = threading.Thread(target=other)
        second.start()
        first.join()
        second.join()
    finally:
        sys.setswitchinterval(interval)
    assert stamps["other"] < stamps["end"]
    exact = np.linalg.solve(dense, rhs[..., None])[..., 0]
    assert np.allclose(y[:2, 0], exact, rtol=1e-12, atol=0)
