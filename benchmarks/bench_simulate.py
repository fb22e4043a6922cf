"""Time-simulation speed: the seed 001 example, a rotor-bearing-casing machine, a batch of run-ups.

1. ``examples/spring_block_rotor.toml`` (the disk on a bearing to the ground) over 10 s (free
   spin, 50 rad/s) at rtol 1e-10, atol 1e-12, 2001 output times, with:

   * baseline: ``scipy.integrate.solve_ivp`` (DOP853) driving the plain numpy right-hand side,
   * ``solve_ivp`` (DOP853) driving the allocation-light compiled right-hand side (``_fast``),
   * scipy's Fortran DOP853 (``scipy.integrate.ode``, what ``rdm.simulate`` uses with numba)
     and LSODA (``odeint``) with the compiled right-hand side,

   each with its relative energy drift and its largest difference from the baseline; then
   ``rdm.simulate`` end to end for the bearing writing and the suspension writing
   (``spring_block_rotor_suspension.toml``) of the same machine.
2. The rotor-bearing-casing machine ``examples/fan_on_bearings.toml`` (a housing on mounts, two
   rotors each on two bearings, 17 coordinates) at 3000 rpm for 0.5 s: ``rdm.simulate`` with the
   plain numpy backend (baseline) and with numba, their agreement.
3. A batch of run-ups of ``examples/gear_machine.toml`` (0 -> 3000 rpm in 2 s) with random
   unbalance phases (default 64), serial and on a ``ProcessPoolExecutor`` with 2 workers.
4. JAX + diffrax (Dopri8) on the suspension writing of the seed example, when installed (not a
   dependency of the package).

Times are min / median / max over ``--repeat`` runs (the baselines once); ratios use the
minima. Run::

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
    """Total energy per sample [J] (the compiled derived outputs)."""
    kinetic, elastic, weight, *_ = kn.sample_outputs(np.zeros(len(states)), np.ascontiguousarray(states),
                                                     *system.kernel_arguments(), _kernels.FREE, 0.0, 0.0, 1.0)
    return kinetic + elastic + weight


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
        "solve_ivp DOP853 + numba RHS (fast)": lambda: ivp(lambda t, y: fast.rhs_flat(t, y, *packed)),
        "Fortran DOP853 (scipy ode) + numba RHS (fast)": fortran_dop853,
        "LSODA (scipy odeint) + numba RHS (fast)": lsoda,
    }


def example_start(name="spring_block_rotor.toml"):
    """The seed 001 example's arrays and initial state (at rest, spinning at SPEED)."""
    model = rdm.load_model(EXAMPLES / name)
    system = system_arrays(model)
    y0 = np.zeros(2 * system.n_dof)
    y0[-1] = SPEED
    return model, system, y0


def _spread(elapsed):
    """``min / median / max`` of run times [s], as text."""
    return f"{min(elapsed):7.3f} / {np.median(elapsed):7.3f} / {max(elapsed):7.3f} s"


def bench_example(repeat):
    model, system, y0 = example_start()
    times = np.linspace(0, DURATION, 2001)
    fast = kernels("numba")
    fast.rhs_flat(0.0, y0, *pack(system, 0, 0.0, 0.0, 1.0))  # compile (or load the cache)
    print(f"seed 001 example (bearing to the ground), {DURATION:g} s, rtol {RTOL:g}, atol {ATOL:g}; "
          f"min / median / max of {repeat}")
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
        print(f"{label:46s}: {_spread(elapsed)}  speed-up {baseline_time / min(elapsed):5.1f}x  "
              f"energy drift {drift:.1e}  |x - baseline| {difference:.1e} m")
    runs = {}
    for name in ("spring_block_rotor.toml", "spring_block_rotor_suspension.toml"):
        writing = rdm.load_model(EXAMPLES / name)
        elapsed = [_timed(lambda: runs.__setitem__(name, rdm.simulate(
            writing, DURATION, SPEED, drive="free", samples=2001, rtol=RTOL, atol=ATOL))) for _ in range(repeat)]
        print(f"{'rdm.simulate end to end, ' + name.split('.')[0]:46s}: {_spread(elapsed)}  "
              f"speed-up {baseline_time / min(elapsed):5.1f}x")
    apart = np.abs(runs["spring_block_rotor.toml"].rotor_centers
                   - runs["spring_block_rotor_suspension.toml"].rotor_centers).max()
    print(f"the two writings' disk centres differ by {apart:.1e} m at most")


def bench_bearings(repeat):
    """The rotor-bearing-casing machine: plain numpy backend against numba, end to end."""
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    speed, duration, samples = rdm.rpm(3000.0), 0.5, 501
    rdm.simulate(model, 0.001, speed, samples=2)   # compile (or load the cache)
    options = dict(samples=samples, rtol=1e-10, atol=1e-13)
    start = time.perf_counter()
    plain = rdm.simulate(model, duration, speed, backend="numpy", **options)
    baseline = time.perf_counter() - start
    runs = []
    elapsed = [_timed(lambda: runs.append(rdm.simulate(model, duration, speed, backend="numba", **options)))
               for _ in range(repeat)]
    label = f"fan_on_bearings (17 coordinates), 3000 rpm, {duration:g} s, rtol 1e-10, atol 1e-13"
    print(f"{label}\n{'baseline: rdm.simulate backend numpy':46s}: {baseline:7.3f} s"
          f"\n{'rdm.simulate backend numba':46s}: {_spread(elapsed)}  speed-up {baseline / min(elapsed):5.1f}x  "
          f"|states - baseline| {np.abs(runs[0].states - plain.states).max():.1e}  "
          f"|bearing forces - baseline| {np.abs(runs[0].bearing_forces - plain.bearing_forces).max():.1e} N")


def _jax_rhs(system, mode, accel, t_start, t_stop):
    """The right-hand side in jax.numpy (same equations as ``_kernels``, rotors fixed in the
    frame only), for diffrax."""
    import jax
    import jax.numpy as jnp
    jax.config.update("jax_enable_x64", True)

    e, E2, s = jnp.asarray(system.e), jnp.asarray(system.E2), system.s
    n = 6 + s
    g = jnp.asarray(system.gravity)

    def skew(v):
        return jnp.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])

    def coeffs(t2):
        small = t2 < 0.05 ** 2
        ts = jnp.where(small, 1.0, t2)
        t = jnp.sqrt(ts)
        sn, co = jnp.sin(t), jnp.cos(t)
        def pick(series, closed):
            return jnp.where(small, series, closed)
        a = pick(1 - t2 / 6 * (1 - t2 / 20 * (1 - t2 / 42)), sn / t)
        c = pick(0.5 - t2 / 24 * (1 - t2 / 30 * (1 - t2 / 56)), (1 - co) / ts)
        b = pick(1 / 6 - t2 / 120 * (1 - t2 / 42 * (1 - t2 / 72)), (t - sn) / (ts * t))
        da = pick(-1 / 3 + t2 / 30 - t2 * t2 / 840, (t * co - sn) / (ts * t))
        dc = pick(-1 / 12 + t2 / 180 - t2 * t2 / 6720, (t * sn - 2 * (1 - co)) / (ts * ts))
        db = pick(-1 / 60 + t2 / 1260 - t2 * t2 / 60480, (1 - co) / (ts * ts) - 3 * (t - sn) / (ts * ts * t))
        return a, c, b, da, dc, db

    def axial(phi):
        return jnp.cos(phi) * jnp.eye(3) + (1 - jnp.cos(phi)) * jnp.outer(e, e) + jnp.sin(phi) * skew(e)

    def rhs(t, y, args=None):
        q, dq = y[:n], y[n:]
        gamma, gdot = E2 @ q[3:5], E2 @ dq[3:5]
        psi = q[5] if s else 0.0
        psid = dq[5] if s else 0.0
        phi, phid = q[n - 1], dq[n - 1]
        t2 = gamma @ gamma
        a, c, b, da, dc, db = coeffs(t2)
        Lg = (1 - c * t2) * jnp.eye(3) + c * jnp.outer(gamma, gamma) + a * skew(gamma)
        Bg = a * jnp.eye(3) + b * jnp.outer(gamma, gamma) + c * skew(gamma)
        Rs = Lg @ axial(psi)
        eg = Lg @ e
        H = jnp.column_stack([Bg @ E2[:, 0], Bg @ E2[:, 1]] + ([eg] if s else []))
        og = Bg @ gdot
        omega = og + psid * eg
        vw, ww = gamma @ gdot, gdot @ gdot
        wdot0 = (da * vw * gdot + db * vw * vw * gamma + b * (vw * gdot + ww * gamma)
                 + dc * vw * jnp.cross(gamma, gdot) + psid * jnp.cross(og, eg))
        M = jnp.zeros((n, n))
        f = jnp.zeros(n)
        for k in range(len(system.mass)):
            r = float(system.ratio[k])
            Rb = Rs @ axial(r * phi)
            w = Rb @ system.offset[k]
            arm = Rs @ system.center[k]
            d = arm + w
            bo = omega + r * phid * eg
            al = wdot0 + r * phid * jnp.cross(omega, eg)
            a0 = jnp.cross(wdot0, arm) + jnp.cross(omega, jnp.cross(omega, arm)) + jnp.cross(al, w) \
                + jnp.cross(bo, jnp.cross(bo, w))
            P = jnp.concatenate([jnp.eye(3), -skew(d) @ H, (r * jnp.cross(eg, w))[:, None]], axis=1)
            W = jnp.concatenate([jnp.zeros((3, 3)), H, (r * eg)[:, None]], axis=1)
            Ib = Rb @ system.inertia[k] @ Rb.T
            mb = float(system.mass[k])
            M = M + mb * P.T @ P + W.T @ Ib @ W
            f = f + P.T @ (mb * (g - a0)) - W.T @ (Ib @ al + jnp.cross(bo, Ib @ bo))
        theta = gamma + psi * e
        for i in range(len(system.spos)):
            p = system.spos[i]
            rp = Rs @ p
            top = jnp.concatenate([jnp.eye(3), -skew(rp) @ H, jnp.zeros((3, 1))], axis=1)
            bottom = jnp.concatenate([jnp.zeros((3, 3)), E2] + ([e[:, None]] if s else []) + [jnp.zeros((3, 1))], axis=1)
            Z = jnp.concatenate([top, bottom], axis=0)
            z = jnp.concatenate([q[:3] + rp - p, theta])
            f = f - Z.T @ (system.sK[i] @ z + system.sC[i] @ (Z @ dq))
        if mode == 0:
            qdd = jnp.linalg.solve(M, f)
        else:
            alpha = jnp.where((t >= t_start) & (t <= t_stop), accel, 0.0)
            k = n - 1
            q1 = jnp.linalg.solve(M[:k, :k], f[:k] - M[:k, k] * alpha)
            qdd = jnp.concatenate([q1, jnp.array([alpha])])
        return jnp.concatenate([dq, qdd])

    return rhs


def bench_jax(repeat):
    """JAX + diffrax (Dopri8, PID controller) on the example, if both are installed."""
    try:
        import diffrax
        import jax
        import jax.numpy as jnp
    except ImportError:
        print("JAX + diffrax: not installed (pip install 'jax[cpu]' diffrax), skipped")
        return
    jax.config.update("jax_enable_x64", True)
    model, system, y0 = example_start("spring_block_rotor_suspension.toml")   # no bearings in this rhs
    times = jnp.linspace(0, DURATION, 2001)
    term = diffrax.ODETerm(_jax_rhs(system, 0, 0.0, 0.0, DURATION))

    @jax.jit
    def solve(y):
        return diffrax.diffeqsolve(term, diffrax.Dopri8(), t0=0.0, t1=DURATION, dt0=1e-3, y0=y,
                                   saveat=diffrax.SaveAt(ts=times), max_steps=10**6,
                                   stepsize_controller=diffrax.PIDController(rtol=RTOL, atol=ATOL)).ys
    first = _timed(lambda: solve(jnp.asarray(y0)).block_until_ready())
    run = min(_timed(lambda: solve(jnp.asarray(y0)).block_until_ready()) for _ in range(repeat))
    states = np.asarray(solve(jnp.asarray(y0)))
    reference = rdm.simulate(model, DURATION, SPEED, drive="free", samples=2001, rtol=RTOL, atol=ATOL)
    energy = _energy(kernels("numba"), system, states)
    print(f"{'JAX + diffrax Dopri8 (jit), first call':46s}: {first:7.3f} s (compilation included)")
    print(f"{'JAX + diffrax Dopri8 (jit), later calls':46s}: {run:7.3f} s  energy drift "
          f"{np.abs(energy - energy[0]).max() / abs(energy[0]):.1e}  |x - rdm.simulate| "
          f"{np.abs(states[:, :3] - reference.states[:, :3]).max():.1e} m")


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
    bench_bearings(args.repeat)
    bench_batch(args.batch)
    bench_jax(args.repeat)  # last: JAX's threads do not mix with the batch's forked workers


if __name__ == "__main__":
    main()
