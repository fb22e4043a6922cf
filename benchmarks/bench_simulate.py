"""Time-simulation speed: the seed 001 example and a batch of run-ups.

1. ``examples/spring_block_rotor.toml`` over 10 s (free spin, 50 rad/s) at rtol 1e-10,
   atol 1e-12, 2001 output times, with:

   * baseline: ``scipy.integrate.solve_ivp`` (DOP853) driving the plain numpy right-hand side,
   * ``solve_ivp`` (DOP853) driving the readable kernels compiled by numba, and the
     allocation-free compiled right-hand side (``_fast``),
   * scipy's Fortran DOP853 (``scipy.integrate.ode``, what ``rdm.simulate`` uses with numba)
     and LSODA (``odeint``) with the compiled right-hand side,

   each with its relative energy drift and its largest difference from the baseline.
2. A batch of run-ups of ``examples/gear_machine.toml`` (0 -> 3000 rpm in 2 s) with random
   unbalance phases (default 64), serial and on a ``ProcessPoolExecutor`` with 2 workers.

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
from rotordyn_modal.simulation._fast import pack
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
    extra = (_kernels.FREE, 0.0, 0.0, DURATION)
    arguments = system.kernel_arguments() + extra
    plain, fast = kernels("numpy"), kernels("numba")
    packed = pack(system, *extra)

    def ivp(function):
        return solve_ivp(function, (0, DURATION), y0, method="DOP853", t_eval=times, rtol=RTOL, atol=ATOL).y.T

    def fortran_dop853():
        solver = ode(fast.rhs_flat).set_integrator("dop853", rtol=RTOL, atol=ATOL, nsteps=10**8)
        solver.set_initial_value(y0, 0.0).set_f_params(*packed)
        return np.array([y0] + [solver.integrate(t) for t in times[1:]])

    def lsoda():
        return odeint(lambda y, t: fast.rhs_flat(t, y, *packed), y0, times, rtol=RTOL, atol=ATOL, mxstep=10**7)

    return {
        "baseline: solve_ivp DOP853 + numpy RHS": lambda: ivp(lambda t, y: plain.rhs(t, y, *arguments)),
        "solve_ivp DOP853 + numba RHS (readable)": lambda: ivp(lambda t, y: fast.assemble and _readable(
            fast, t, y, arguments)),
        "solve_ivp DOP853 + numba RHS (fast)": lambda: ivp(lambda t, y: fast.rhs_flat(t, y, *packed)),
        "Fortran DOP853 (scipy ode) + numba RHS (fast)": fortran_dop853,
        "LSODA (scipy odeint) + numba RHS (fast)": lsoda,
    }


def _readable(fast, t, y, arguments):
    """The readable kernels compiled (``accelerations``), as first measured."""
    n = len(y) // 2
    out = np.empty_like(y)
    out[:n] = y[n:]
    out[n:] = fast.accelerations(t, y, *arguments)[0]
    return out


def bench_example(repeat):
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    system = system_arrays(model)
    n = system.n_dof
    y0 = np.zeros(2 * n)
    y0[-1] = SPEED
    times = np.linspace(0, DURATION, 2001)
    fast = kernels("numba")
    fast.rhs_flat(0.0, y0, *pack(system, 0, 0.0, 0.0, 1.0))  # compile (or load the cache)
    fast.accelerations(0.0, y0, *system.kernel_arguments(), 0, 0.0, 0.0, 1.0)
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
        print(f"{label:46s}: {min(elapsed):7.3f} s  speed-up {baseline_time / min(elapsed):5.1f}x  "
              f"energy drift {drift:.1e}  |x - baseline| {difference:.1e} m")
    example = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    end_to_end = min(_timed(lambda: rdm.simulate(example, DURATION, SPEED, drive="free", samples=2001,
                                                 rtol=RTOL, atol=ATOL)) for _ in range(repeat))
    print(f"{'rdm.simulate end to end (with derived outputs)':46s}: {end_to_end:7.3f} s  "
          f"speed-up {baseline_time / end_to_end:5.1f}x")


def _run_up(phases):
    """One run-up with the given unbalance phases [deg]; returns the sensor's peak [m]."""
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    res = rdm.simulate(model, 2.0, 0.0, drive="ramp", final_speed=rdm.rpm(3000.0), samples=4001,
                       unbalance_phases_deg=phases, rtol=1e-8)
    return np.abs(res.sensor("acc-top-z")).max()


def bench_batch(count):
    from concurrent.futures import ProcessPoolExecutor

    rng = np.random.default_rng(1)
    phases = [rng.uniform(0, 360, 2) for _ in range(count)]
    _run_up(phases[0])  # compile (or load the cache)
    label = "run-ups of gear_machine (0 -> 3000 rpm in 2 s, rtol 1e-8, 4001 samples)"
    start = time.perf_counter()
    peaks = [_run_up(p) for p in phases]
    serial = time.perf_counter() - start
    print(f"{count} {label}, serial: {serial:.2f} s ({serial / count * 1e3:.0f} ms each); "
          f"peak acc-top-z {min(peaks) * 1e6:.2f}..{max(peaks) * 1e6:.2f} um")
    with ProcessPoolExecutor(2) as pool:
        list(pool.map(_run_up, phases[:2]))  # start the workers, load the compiled cache
        start = time.perf_counter()
        parallel_peaks = list(pool.map(_run_up, phases, chunksize=max(1, count // 8)))
        parallel = time.perf_counter() - start
    assert np.allclose(parallel_peaks, peaks, rtol=1e-12)
    print(f"{count} {label}, ProcessPoolExecutor(2): {parallel:.2f} s")


def _timed(function):
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    bench_example(args.repeat)
    bench_batch(args.batch)


if __name__ == "__main__":
    main()
