"""Time-simulation speed: the seed 001 example and a batch of run-ups.

1. ``examples/spring_block_rotor.toml`` over 10 s (free spin, 50 rad/s) at rtol 1e-10,
   atol 1e-12, 2001 output times, with:

   * baseline: ``scipy.integrate.solve_ivp`` (DOP853) driving the plain numpy right-hand side,
   * ``solve_ivp`` (DOP853) driving the numba-compiled right-hand side (what ``rdm.simulate``
     uses by default),
   * scipy's Fortran DOP853 (``scipy.integrate.ode``) and LSODA (``odeint``) with the compiled
     right-hand side,

   each with its relative energy drift and its largest difference from the baseline.
2. A batch of run-ups of ``examples/gear_machine.toml`` (0 -> 3000 rpm in 2 s) with random
   unbalance phases (default 64), serial.

Run::

    python benchmarks/bench_simulate.py [--batch 64] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.integrate import ode, odeint, solve_ivp

import rotordyn_modal as rdm
from rotordyn_modal.simulation import _kernels
from rotordyn_modal.simulation._system import system_arrays
from rotordyn_modal.simulation.simulate import kernels

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
RTOL, ATOL, DURATION, SPEED = 1e-10, 1e-12, 10.0, 50.0


def _energy(kn, system, states):
    n = system.n_dof
    out = []
    for y in states:
        M, _ = kn.assemble(0.0, y, *system.kernel_arguments())
        elastic, weight = kn.potential(y, system.e, system.E2, system.s, system.gravity, system.mass,
                                       system.center, system.offset, system.ratio, system.spos, system.sK)
        out.append(0.5 * y[n:] @ M @ y[n:] + elastic + weight)
    return np.array(out)


def _methods(system, y0, times):
    arguments = system.kernel_arguments() + (_kernels.FREE, 0.0, 0.0, DURATION)
    plain, fast = kernels("numpy"), kernels("numba")

    def ivp(kn):
        return solve_ivp(lambda t, y: kn.rhs(t, y, *arguments), (0, DURATION), y0, method="DOP853",
                         t_eval=times, rtol=RTOL, atol=ATOL).y.T

    def fortran_dop853():
        solver = ode(lambda t, y: fast.rhs(t, y, *arguments)).set_integrator(
            "dop853", rtol=RTOL, atol=ATOL, nsteps=10**8)
        solver.set_initial_value(y0, 0.0)
        return np.array([y0] + [solver.integrate(t) for t in times[1:]])

    def lsoda():
        return odeint(lambda y, t: fast.rhs(t, y, *arguments), y0, times, rtol=RTOL, atol=ATOL, mxstep=10**7)

    return {
        "baseline: solve_ivp DOP853 + numpy RHS": lambda: ivp(plain),
        "solve_ivp DOP853 + numba RHS (default)": lambda: ivp(fast),
        "scipy Fortran DOP853 (ode) + numba RHS": fortran_dop853,
        "scipy LSODA (odeint) + numba RHS": lsoda,
    }


def bench_example(repeat):
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    system = system_arrays(model)
    n = system.n_dof
    y0 = np.zeros(2 * n)
    y0[-1] = SPEED
    times = np.linspace(0, DURATION, 2001)
    fast = kernels("numba")
    fast.rhs(0.0, y0, *system.kernel_arguments(), 0, 0.0, 0.0, 1.0)  # compile (or load the cache)
    print(f"seed 001 example, {DURATION:g} s, rtol {RTOL:g}, atol {ATOL:g}, best of {repeat}")
    baseline_time, baseline = None, None
    for label, method in _methods(system, y0, times).items():
        elapsed = []
        for _ in range(repeat if "baseline" not in label else 1):
            start = time.perf_counter()
            states = method()
            elapsed.append(time.perf_counter() - start)
        energy = _energy(fast, system, states)
        drift = np.abs(energy - energy[0]).max() / abs(energy[0])
        if baseline is None:
            baseline_time, baseline = min(elapsed), states
        difference = np.abs(states[:, :3] - baseline[:, :3]).max()
        print(f"{label:42s}: {min(elapsed):7.3f} s  speed-up {baseline_time / min(elapsed):5.1f}x  "
              f"energy drift {drift:.1e}  |x - baseline| {difference:.1e} m")


def bench_batch(count):
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    rng = np.random.default_rng(1)
    rdm.simulate(model, 0.01, 0.0, drive="ramp", final_speed=1.0, samples=3)  # compile
    start = time.perf_counter()
    peaks = []
    for _ in range(count):
        phases = rng.uniform(0, 360, len(model.unbalances))
        res = rdm.simulate(model, 2.0, 0.0, drive="ramp", final_speed=rdm.rpm(3000.0), samples=4001,
                           unbalance_phases_deg=phases, rtol=1e-8)
        peaks.append(np.abs(res.sensor("acc-top-z")).max())
    elapsed = time.perf_counter() - start
    print(f"{count} run-ups of gear_machine (0 -> 3000 rpm in 2 s, rtol 1e-8, 4001 samples), serial: "
          f"{elapsed:.2f} s ({elapsed / count * 1e3:.0f} ms each); peak acc-top-z {min(peaks) * 1e6:.2f}.."
          f"{max(peaks) * 1e6:.2f} um")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    bench_example(args.repeat)
    bench_batch(args.batch)


if __name__ == "__main__":
    main()
