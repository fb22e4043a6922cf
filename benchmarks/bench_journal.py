"""Cost of the short journal bearing coefficients next to the eigen-solve they feed.

``rotordyn_modal.elements.journal_bearing.short_journal_bearing`` for 10,001 speeds (1 to 100,000 rad/s, both
spin directions) against one batched ``numpy.linalg.eigvals`` of 10,001 16x16 matrices (the
size of a two-rotor machine on flexible bearings), and against a loop of
``scipy.optimize.brentq`` on the load capacity, one speed at a time (the obvious alternative
for the eccentricity). Prints best-of-N times and the ratios. Run::

    python benchmarks/bench_journal.py [--speeds 10001] [--repeat 7]
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy import optimize

from _timing import best_time  # noqa: E402  (benchmarks/ is on sys.path when run as a script)
from rotordyn_modal.elements.journal_bearing import short_journal_bearing

BEARING = dict(diameter=0.05, length=0.02, clearance=50e-6, viscosity=0.03, load=500.0)


def eccentricity_by_brentq(speeds):
    """The eccentricity at each speed by Brent's method on the load capacity, one at a time."""
    d, l, c, mu, w = (BEARING[k] for k in ("diameter", "length", "clearance", "viscosity", "load"))
    out = np.empty(len(speeds))
    for i, speed in enumerate(np.abs(speeds)):
        sigma = mu * speed * d * l**3 / (8 * w * c**2)
        out[i] = optimize.brentq(
            lambda e: (1 - e * e)**2 / (e * np.sqrt(16 * e * e + np.pi**2 * (1 - e * e))) - sigma,
            1e-12, 1 - 1e-15, xtol=1e-300, rtol=4 * np.finfo(float).eps)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--speeds", type=int, default=10001)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args(argv)

    speeds = np.geomspace(1.0, 1e5, args.speeds) * np.where(np.arange(args.speeds) % 2, 1, -1)
    matrices = np.random.default_rng(0).standard_normal((args.speeds, 16, 16))

    bearing = short_journal_bearing(speeds, **BEARING)
    error = np.abs(bearing.eccentricity - eccentricity_by_brentq(speeds)).max()

    t_bearing = best_time(lambda: short_journal_bearing(speeds, **BEARING), args.repeat)
    t_eig = best_time(lambda: np.linalg.eigvals(matrices), max(1, args.repeat // 2))
    t_brentq = best_time(lambda: eccentricity_by_brentq(speeds), 1)

    print(f"{args.speeds} speeds, eccentricity {bearing.eccentricity.min():.2e} to "
          f"{bearing.eccentricity.max():.4f}, best of {args.repeat}")
    print(f"short_journal_bearing (eccentricity + 8 coefficients): {1e3 * t_bearing:8.2f} ms")
    print(f"batched numpy.linalg.eigvals, {args.speeds} x 16x16     : {1e3 * t_eig:8.2f} ms")
    print(f"loop: scipy brentq on the eccentricity per speed       : {1e3 * t_brentq:8.2f} ms")
    print(f"bearing / eigvals = {t_bearing / t_eig:.4f}")
    print(f"brentq loop / bearing = {t_brentq / t_bearing:.1f}   "
          f"(max |eps - eps_brentq| = {error:.1e})")


if __name__ == "__main__":
    main()
