"""Campbell sweep of the lowest modes only (``campbell(modes=N)``) against the full solve.

For flexible rotors of growing mesh (``element_length`` of ``examples/compressor_rotor.toml``,
alone; ``examples/flexible_pump_on_mounts.toml``, inside a casing on mounts), times
``campbell(model, speeds, critical=False, modes=N)`` and a dense batched ``numpy.linalg.eig``
of the full state matrices at the same speeds (same run, interleaved repeats), prints the
ratio (min / median / max over repeats), the peak memory of each (tracemalloc) and the largest
relative difference of the N lowest roots from the dense solve's. With ``--max-frequency HZ``,
``campbell(..., max_frequency=HZ)`` instead: every mode below HZ at each speed (``--modes`` unused),
compared with the dense solve's roots below HZ.

With ``--long NODES,...`` instead: a uniform 4 m shaft (a disk, two anisotropic damped bearings)
meshed with that many elements, 4 coordinates per node (500 and 1,000 nodes: 2,004 and 4,004
coordinates); for each, min / median / max over ``--repeat`` runs of the time of the machine's
matrices from the sparse node matrices against the dense route they replaced (dense 6N x 6N node
matrices times dense node motions, as before issue 28's "Size and speed"; below ``--dense-nodes``
nodes), of ``campbell(..., modes=N, critical=False)`` at ``--speeds`` speeds, of the critical
speeds of those N modes (orders 1 and 2), of an FRF at 20
frequencies and of ``check``'s first bending frequencies, each with its peak traced memory.

With ``--coordinates 20,100,400`` instead (issue 28's sizes): a uniform steel fan shaft 0.8 m long,
40 mm thick, with a 4 kg fan wheel at mid-span on two damped bearings (2e7 N/m, 500 N s/m) at its
ends, meshed so that the rotor has exactly that many coordinates (4 per node: two sections of
``elements = n`` each, the wheel on their joint), either alone (grounded bearings, ``--in-casing
none``) or inside the casing of ``examples/gear_machine.toml`` (``--in-casing gear``): the gear
machine's fan rotor replaced by this shaft on its bearings in the casing (the 150 kg skid on its
four inclined mounts, the rigid motor driving the fan through the 2.5:1 gear, spinning with the
casing), so the model has 6 more coordinates. For each size, ``--repeat`` interleaved runs of
``campbell(model, speeds, critical=False, modes=N)`` and of the dense floor (one batched
``numpy.linalg.eigvals`` of the full state matrices), wall and CPU time (``time.process_time``)
min / median / max, their CPU ratio, the peak traced memory of one more run of each, the largest
relative difference of the N lowest roots from the dense floor's, and at the end the growth
exponent of each (the log-log slope of CPU time against the model's coordinates, between
consecutive sizes and by least squares over all). The dense floor's cost per speed is the same at
every speed, so above ``--dense-speeds`` speeds (default 201; one number, or one per size) it is
timed on that many of the speeds, evenly picked, and its time scaled by (speeds / dense speeds) --
a chunked dense solve (chunks of that many speeds) -- and the output says so; its peak memory is
that of one chunk, printed beside the size of the stack of all speeds' state matrices that one
batched eig of every speed would hold. Run it with ``OPENBLAS_NUM_THREADS=1`` on a shared machine:
CPU time is then the work (BLAS threads waiting for a core spin, and count).

Usage::

    python benchmarks/bench_flexible.py [--speeds 201] [--modes 12] [--repeat 3] [--sizes 0.2,0.05,0.012]
                                        [--max-frequency HZ]
    python benchmarks/bench_flexible.py --long 500,1000 [--speeds 11] [--repeat 3] [--dense-nodes 1100]
                                        [--cases matrices,check,campbell,critical,frf,unbalance]
    python benchmarks/bench_flexible.py --coordinates 20,100,400 [--in-casing none|gear] [--speeds 201]
                                        [--modes 12] [--repeat 3] [--dense-speeds 201[,201,21]]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.io.model_file import read_toml


def _model(path, element_length):
    data = read_toml(path, "model")
    for rotor in data["rotors"]:
        if "shaft" in rotor:
            rotor["element_length"] = element_length
    return rdm.Model.from_dict(data)


def _dense(model, speeds, count, limit=None):
    M, C, G, K = model.matrices()
    n = len(M)
    A = np.zeros((len(speeds), 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, :n] = -np.linalg.solve(M, K)
    A[:, n:, n:] = -np.linalg.solve(M, C)[None] - speeds[:, None, None] * np.linalg.solve(M, G)[None]
    roots = np.linalg.eigvals(A)
    roots = np.where(is_oscillating(roots) & (roots.imag > 1e-9 * np.abs(roots)), roots, np.nan + 1e300j)
    roots = np.sort_complex(roots * -1j) * 1j                         # by imaginary part
    if limit is None:
        return roots[:, :count]
    return np.where(roots.imag <= 2 * np.pi * limit, roots, np.nan + 1e300j)


def _timed(function):
    start = time.perf_counter()
    out = function()
    return out, time.perf_counter() - start


def _peak(function):
    """Peak traced memory [bytes] of one more run (apart: tracemalloc slows Python-heavy code)."""
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def _lowest(model, speeds, count, limit=None):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if limit is not None:
            return rdm.campbell(model, speeds, critical=False, max_frequency=limit)
        return rdm.campbell(model, speeds, critical=False, modes=count)


def _critical(model, speeds, count):
    """The critical speeds (orders 1 and 2) of the ``count`` lowest modes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.critical_speeds(model, speeds, orders=(1, 2), modes=count)


def _long_shaft(count):
    """A uniform steel shaft 4 m long, 0.1 m thick, of ``count`` elements: a disk at 1.2 m, two
    bearings (1e8 and 1.2e8 N/m, 2 kN s/m) at 0.2 and 3.8 m, a sensor, an excitation and an
    unbalance at the disk."""
    steel = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
    at_disk = {"rotor": "s", "axial_position": 1.2, "direction": [0.0, 1.0, 0.0]}
    return rdm.Model.from_dict({
        "materials": [steel],
        "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0], "element_length": 4.0 / count,
                    "shaft": [{"length": 4.0, "outer_diameter": 0.1, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": 1.2, "mass": 20.0, "polar_inertia": 0.3,
                               "diametral_inertia": 0.16}]}],
        "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": [1e8, 1.2e8], "damping": 2000.0}
                     for n, z in (("a", 0.2), ("b", 3.8))],
        "sensors": [dict(at_disk, name="p")], "excitations": [dict(at_disk, name="f")],
        "unbalances": [{"rotor": "s", "axial_position": 1.2, "amount": 1e-3}]})


def _dense_matrices(model):
    """The flexible rotor's part of M, G, K by the dense route replaced: dense node matrices
    (6N x 6N) times dense node motions (6N x n)."""
    from rotordyn_modal.assembly import flexible_rotor_matrices

    parts = flexible_rotor_matrices(model, model.rotors[0])
    motion, relative = parts.motion.toarray(), parts.relative.toarray()
    M, K, G = (matrix.toarray() for matrix in (parts.M, parts.K, parts.G))
    return motion.T @ M @ motion, relative.T @ K @ relative, motion.T @ G @ motion


def _bending(model):
    from rotordyn_modal.model.flexible import bending_frequencies

    shaft = model.rotors[0].flexible
    return bending_frequencies(shaft, [(shaft.z_of(b.position), b.coefficients.stiffness[0]) for b in model.bearings])


_FAN_LENGTH = 0.8          # [m]


def _fan_shaft(coordinates, start):
    """The fan shaft of ``coordinates`` (a multiple of 4, at least 12) lateral coordinates: two
    0.4 m sections of ``elements`` each (``coordinates / 4 - 1`` elements in all), the wheel on
    their joint."""
    if coordinates % 4 or coordinates < 12:
        raise SystemExit(f"--coordinates {coordinates}: expected a multiple of 4, at least 12 (4 per node)")
    elements = coordinates // 4 - 1
    half = _FAN_LENGTH / 2
    return {"name": "fan", "start": start,
            "shaft": [{"length": half, "outer_diameter": 0.04, "material": "steel", "elements": elements // 2},
                      {"length": half, "outer_diameter": 0.04, "material": "steel",
                       "elements": elements - elements // 2}],
            "disks": [{"name": "wheel", "axial_position": half, "mass": 4.0, "polar_inertia": 0.25,
                       "diametral_inertia": 0.13}]}


def _fan_bearings():
    return [{"name": name, "rotor": "fan", "axial_position": z, "stiffness": 2e7, "damping": 500.0}
            for name, z in (("fan-A", 0.0), ("fan-B", _FAN_LENGTH))]


_STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}


def _fan_model(coordinates, casing):
    """The fan shaft alone (``casing`` "none": grounded bearings, spinning at the reference speed)
    or in the gear machine's casing (``casing`` "gear": ``examples/gear_machine.toml`` with its
    rigid fan rotor replaced by the shaft, centred where the fan's centre of mass was)."""
    if casing == "none":
        return rdm.Model.from_dict({"name": f"fan shaft, {coordinates} coordinates", "spin_axis": [1.0, 0.0, 0.0],
                                    "materials": [_STEEL],
                                    "rotors": [dict(_fan_shaft(coordinates, [0.0, 0.0, 0.0]), speed_ratio=1.0)],
                                    "bearings": _fan_bearings()})
    data = read_toml("examples/gear_machine.toml", "model")
    fan = next(rotor for rotor in data["rotors"] if rotor["name"] == "fan")
    centre = fan["center_of_mass"]
    data["materials"] = [_STEEL]
    data["rotors"] = [rotor if rotor is not fan else _fan_shaft(coordinates, [centre[0] - _FAN_LENGTH / 2,
                                                                               *centre[1:]])
                      for rotor in data["rotors"]]
    data["bearings"] = _fan_bearings()
    data["unbalances"] = [dict(u, axial_position=_FAN_LENGTH / 2) if u["rotor"] == "fan" else u
                          for u in data["unbalances"]]
    return rdm.Model.from_dict(data)


def _cpu_timed(function):
    """``function()``, its wall and CPU time [s] (CPU: this process's, every thread)."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = function()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def _lowest_roots(result):
    """The oscillating roots of a Campbell result sorted by frequency, shape (speeds, modes)."""
    return np.sort_complex(np.where(result.oscillatory, result.eigenvalues, np.nan + 1e300j) * -1j) * 1j


def _slopes(sizes, times):
    """Log-log slopes of ``times`` against ``sizes``: between consecutive sizes, and the least-squares
    fit over all."""
    x, y = np.log(np.asarray(sizes, float)), np.log(np.asarray(times, float))
    pairs = [(y[i + 1] - y[i]) / (x[i + 1] - x[i]) for i in range(len(x) - 1)]
    return pairs, (np.polyfit(x, y, 1)[0] if len(x) > 1 else np.nan)


def _coordinates(args):
    """The ``--coordinates`` benchmark (see the module docstring)."""
    speeds = np.linspace(0.0, 1500.0, args.speeds)
    sizes_asked = [int(x) for x in args.coordinates.split(",")]
    chunks = [int(x) for x in str(args.dense_speeds).split(",")]
    chunks = chunks + chunks[-1:] * (len(sizes_asked) - len(chunks))
    casing = {"none": "alone (grounded)", "gear": "in the gear machine's casing"}[args.in_casing]
    print(f"fan shaft {casing}; {args.speeds} speeds 0-1500 rad/s, lowest {args.modes}, {args.repeat} repeats; "
          "times: wall and CPU [s], ratio = dense CPU / lowest CPU. 'dense on' = the speeds the dense floor was "
          "timed on (evenly picked; below all speeds its time is scaled by speeds / that, its cost per speed being "
          "constant: a dense solve in chunks of that many speeds, whose peak memory is one chunk's); 'batch MB' = "
          "the stack of all speeds' state matrices one batched eig of every speed holds (computed)")
    print(f"{'rotor n':>7s} {'model n':>7s} {'dense on':>8s} | {'dense wall/cpu [s] med':>22s} | "
          f"{'lowest wall [s] min/med/max':>27s} {'cpu med':>7s} | {'cpu ratio min/med/max':>21s} | "
          f"{'peak MB dense/low':>17s} {'batch MB':>8s} | {'max rel diff':>12s}")
    sizes, dense_cpu, low_cpu = [], [], []
    for coordinates, chunk in zip(sizes_asked, chunks):
        model = _fan_model(coordinates, args.in_casing)
        n = model.dofs.n
        picked = np.unique(np.round(np.linspace(0, args.speeds - 1, min(chunk, args.speeds))).astype(int))
        scale = args.speeds / len(picked)
        d_wall, d_cpu, l_wall, l_cpu = [], [], [], []
        for _ in range(args.repeat):
            reference, wall, cpu = _cpu_timed(lambda: _dense(model, speeds[picked], args.modes))
            d_wall.append(wall * scale)
            d_cpu.append(cpu * scale)
            result, wall, cpu = _cpu_timed(lambda: _lowest(model, speeds, args.modes))
            l_wall.append(wall)
            l_cpu.append(cpu)
        m_dense = _peak(lambda: _dense(model, speeds[picked], args.modes))
        m_low = _peak(lambda: _lowest(model, speeds, args.modes))
        got = _lowest_roots(result)[picked, :args.modes]
        missing = np.isnan(got) != np.isnan(reference)
        diff = np.nanmax(np.where(missing, np.inf, np.abs(got - reference) / np.abs(reference)))
        ratios = np.array(d_cpu) / np.array(l_cpu)
        sizes.append(n)
        dense_cpu.append(np.median(d_cpu))
        low_cpu.append(np.median(l_cpu))
        batch = args.speeds * (2 * n) ** 2 * 8 / 2**20
        print(f"{coordinates:7d} {n:7d} {len(picked):8d} | {np.median(d_wall):10.2f}/{np.median(d_cpu):<11.2f} | "
              f"{_stats(l_wall):>27s} {np.median(l_cpu):7.2f} | {min(ratios):6.1f}/{np.median(ratios):6.1f}/"
              f"{max(ratios):6.1f} | {m_dense / 2**20:8.0f}/{m_low / 2**20:<8.0f} {batch:8.0f} | {diff:12.1e}", flush=True)
    if len(set(sizes)) == len(sizes) > 1:
        for what, times in (("dense floor", dense_cpu), (f"lowest {args.modes}", low_cpu)):
            pairs, fit = _slopes(sizes, times)
            steps = ", ".join(f"{a}->{b}: n^{p:.2f}" for a, b, p in zip(sizes[:-1], sizes[1:], pairs))
            print(f"growth of the {what}'s CPU time (median) with the model's coordinates: {steps}; "
                  f"least squares n^{fit:.2f}")


def _stats(values):
    return f"{min(values):7.2f}/{np.median(values):7.2f}/{max(values):7.2f}"


def _long(args):
    """The ``--long`` benchmark (see the module docstring)."""
    speeds = np.linspace(0.0, 600.0, args.speeds)
    print(f"{'nodes':>6s} {'n':>6s}  {'what':28s} {'time [s] min/med/max':>24s} {'peak MB':>9s}")
    for count in (int(x) for x in args.long.split(",")):
        model = _long_shaft(count)
        n = model.dofs.n
        cases = [("matrices (sparse)", lambda: model.matrices())]
        if count + 1 <= args.dense_nodes:
            cases.append(("matrices (dense route)", lambda: _dense_matrices(model)))
        cases += [("check's bending frequencies", lambda: _bending(model)),
                  (f"campbell lowest {args.modes}, {args.speeds} speeds",
                   lambda: _lowest(model, speeds, args.modes)),
                  (f"critical lowest {args.modes}, orders 1,2", lambda: _critical(model, speeds, args.modes)),
                  ("frf 20 frequencies", lambda: rdm.frf(model, 300.0, np.linspace(1.0, 200.0, 20))),
                  ("unbalance 20 speeds", lambda: rdm.unbalance_response(model, np.linspace(30.0, 600.0, 20)))]
        for what, function in cases:
            if args.cases and not any(word in what for word in args.cases.split(",")):
                continue
            times = []
            for _ in range(args.repeat):
                model.rotors[0].flexible.__dict__.pop("_node_matrices", None)      # nothing kept between runs
                times.append(_timed(function)[1])
            peak = _peak(function)
            print(f"{count + 1:6d} {n:6d}  {what:28s} {_stats(times):>24s} {peak / 2**20:9.0f}", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=201)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="0.2,0.05,0.012", help="element lengths [m] of the compressor shaft")
    parser.add_argument("--max-frequency", type=float, help="every mode below this [Hz] instead of the lowest N")
    parser.add_argument("--long", help="element counts of a long uniform shaft (e.g. 500,1000): see the docstring")
    parser.add_argument("--dense-nodes", type=int, default=1100, help="largest mesh timed by the dense route too")
    parser.add_argument("--coordinates", help="issue 28's sizes: the fan shaft with this many coordinates "
                                              "(multiples of 4, e.g. 20,100,400): see the docstring")
    parser.add_argument("--in-casing", choices=("none", "gear"), default="none",
                        help="with --coordinates: the shaft alone (none) or in the gear machine's casing (gear)")
    parser.add_argument("--dense-speeds", default="201",
                        help="with --coordinates: time the dense floor on at most this many of the speeds and "
                             "scale its time to all of them (one number, or one per size: 201,201,21)")
    parser.add_argument("--cases", help="with --long: only the cases whose name holds one of these words "
                                        "(comma-separated: matrices, check, campbell, critical, frf, unbalance)")
    args = parser.parse_args(argv)
    if args.long:
        return _long(args)
    if args.coordinates:
        return _coordinates(args)
    limit = args.max_frequency
    cases = [("examples/compressor_rotor.toml", float(x)) for x in args.sizes.split(",")]
    cases += [("examples/flexible_pump_on_mounts.toml", x) for x in (0.05, 0.01)]
    speeds = np.linspace(0.0, 1500.0, args.speeds)
    print(f"{'model':40s} {'n':>5s} {'full [s]':>9s} {'lowest [s]':>10s} {'ratio min/med/max':>20s} "
          f"{'peak MB full/low':>17s} {'max rel diff':>12s}")
    for path, length in cases:
        model = _model(path, length)
        n = len(model.matrices()[0])
        ratios, full_t, low_t = [], [], []
        for _ in range(args.repeat):
            reference, t_full = _timed(lambda: _dense(model, speeds, args.modes, limit))
            result, t_low = _timed(lambda: _lowest(model, speeds, args.modes, limit))
            ratios.append(t_full / t_low)
            full_t.append(t_full)
            low_t.append(t_low)
        m_full = _peak(lambda: _dense(model, speeds, args.modes, limit))
        m_low = _peak(lambda: _lowest(model, speeds, args.modes, limit))
        got = np.sort_complex(np.where(result.oscillatory, result.eigenvalues, np.nan + 1e300j) * -1j) * 1j
        k = max(got.shape[1], reference.shape[1])
        got, reference = (np.pad(x, ((0, 0), (0, k - x.shape[1])), constant_values=np.nan + 1e300j)
                          for x in (got, reference))
        # a root missing from either side (a root against the padding): an infinite difference
        missing = np.isnan(got) != np.isnan(reference)
        diff = np.nanmax(np.where(missing, np.inf, np.abs(got - reference) / np.abs(reference)))
        name = f"{path.split('/')[-1]} el={length:g}"
        print(f"{name:40s} {n:5d} {np.median(full_t):9.2f} {np.median(low_t):10.2f} "
              f"{min(ratios):6.1f}/{np.median(ratios):5.1f}/{max(ratios):5.1f}     "
              f"{m_full / 2**20:7.0f}/{m_low / 2**20:<7.0f} {diff:12.1e}", flush=True)


if __name__ == "__main__":
    main()
