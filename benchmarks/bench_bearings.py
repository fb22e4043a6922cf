"""Campbell diagrams of rotors on flexible bearings: the package against the floor and the loop.

Three machines, each rotor on two flexible bearings (the locating one also axial, so every
rotor has five coordinates of its own):

a. the two-rotor gear machine (``examples/gear_machine.toml``), constant coefficients:
   16 coordinates, 32 states;
b. the same with speed-dependent coefficients tabulated over ``speeds_rpm`` (27 points,
   -13,000..13,000 rpm of each rotor's own speed; stiffness stiffening and cross-coupled
   with speed, as a fluid film);
c. a generated machine: 20 rotors chained by gears, each on two bearings, in a casing on
   six mounts: 106 coordinates, 212 states.

For each it times, side by side in every repetition,

* ``rdm.campbell`` (eigenvalues, shapes, tracking, whirl and the 1X critical speeds of
  every source), and the same without critical speeds (``orders=()``), to split the cost;
* the floor: one bare batched ``numpy.linalg.eig`` of the same state matrices,
  ``speed_linear_form(model).at(speeds)`` (building them included);
* the loop: ``scipy.linalg.eig`` called once per speed on those matrices,

and prints each repetition's ratios and their min / median / max (the machine is shared:
ratios measured side by side are what counts). Run::

    python benchmarks/bench_bearings.py [--machines abc] [--speeds 10001] [--speeds-c 1001]
        [--repeat 5] [--repeat-c 3] [--blas-threads 1] [--chunk 0] [--skip sweep,loop] [--save DIR]

``--blas-threads 1`` (the default) gives every contender one BLAS thread (threadpoolctl);
``--blas-threads default`` leaves BLAS as it is (on a loaded 2-core machine OpenBLAS's own
threads make 212 x 212 eigenproblems several times slower). ``ROTORDYN_MODAL_THREADS=1``
keeps rdm.campbell on one thread too. ``--chunk N`` solves the floor and the loop N speeds at
a time (10,001 speeds of machine (c) would need 11 GB at once). ``--save DIR`` writes the
three models as TOML files.
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import time
from pathlib import Path

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis._eigensolve import select_upper
from rotordyn_modal.linear_system import speed_linear_form

from _machines import bearing_pair, gear_chain

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


# --------------------------------------------------------------------------- machines
def gear_machine_on_bearings() -> rdm.Model:
    """(a) The gear machine with motor and fan each on two bearings (2e7 N/m, 500 N s/m)."""
    data = rdm.load_model(EXAMPLES / "gear_machine.toml").to_dict()
    data["name"] = "gear machine, each rotor on two flexible bearings"
    data["bearings"] = [b for rotor in data["rotors"]
                        for b in bearing_pair(rotor, data["spin_axis"], (0.08, -0.06), 2e7, 500.0, 1e7)]
    return rdm.Model.from_dict(data)


def tabulated(bearing, table_rpm):
    """The bearing with fluid-film-like coefficients over its rotor's own speed: radial
    stiffness growing by 30 % / 50 %, cross-coupling +-20 % changing sign with the spin,
    damping growing by 50 % / 80 % at the table's ends."""
    k0, c0 = bearing["stiffness"], bearing["damping"]
    s = np.asarray(table_rpm) / np.max(np.abs(table_rpm))
    out = dict(bearing, speeds_rpm=[float(x) for x in table_rpm])
    out["stiffness"] = [[[k0 * (1 + 0.3 * x * x), 0.2 * k0 * x], [-0.2 * k0 * x, k0 * (1 + 0.5 * x * x)]]
                        for x in s]
    out["damping"] = [[c0 * (1 + 0.5 * abs(x)), c0 * (1 + 0.8 * abs(x))] for x in s]
    if "axial_stiffness" in bearing:
        out["axial_stiffness"] = [bearing["axial_stiffness"]] * len(s)
    return out


def gear_machine_on_table_bearings() -> rdm.Model:
    """(b) Machine (a) with every bearing tabulated over -13,000..13,000 rpm (27 points)."""
    data = gear_machine_on_bearings().to_dict()
    data["name"] = "gear machine, each rotor on two bearings with speed-dependent coefficients"
    table = np.linspace(-13000.0, 13000.0, 27)
    data["bearings"] = [tabulated(b, table) for b in data["bearings"]]
    return rdm.Model.from_dict(data)


MACHINES = {
    "a": ("gear machine on bearings, constant", gear_machine_on_bearings, 12000.0),
    "b": ("gear machine on bearings, speed tables", gear_machine_on_table_bearings, 12000.0),
    "c": ("20 geared rotors on bearings in a casing", gear_chain, 6000.0),
}


# --------------------------------------------------------------------------- timing
def blas_limit(threads: str):
    """One BLAS thread for everything (threadpoolctl), or BLAS left as it is."""
    if threads == "default":
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(int(threads), user_api="blas")


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def largest_difference(result, eigenvalues) -> float:
    """Largest relative difference between rdm.campbell's eigenvalues and the floor's
    (each speed's upper eigenvalues, both sorted the same way)."""
    floor = np.sort_complex(select_upper(eigenvalues))
    package = np.sort_complex(result.eigenvalues)
    scale = np.abs(floor).max(axis=1, keepdims=True)
    return float(np.max(np.abs(package - floor) / scale))


def parts(speeds, chunk):
    """The speeds in consecutive parts of ``chunk`` (all at once for 0)."""
    chunk = chunk or len(speeds)
    return [speeds[i:i + chunk] for i in range(0, len(speeds), chunk)]


def floor(model, speeds, chunk):
    """The floor: bare batched ``numpy.linalg.eig`` of the state matrices (eigenvalues)."""
    form = speed_linear_form(model)
    return np.concatenate([np.linalg.eig(form.at(part))[0] for part in parts(speeds, chunk)])


def loop(model, speeds, chunk):
    """The obvious loop: ``scipy.linalg.eig`` per speed on the same state matrices."""
    form = speed_linear_form(model)
    for part in parts(speeds, chunk):
        for matrix in form.at(part):
            scipy.linalg.eig(matrix)


def measure(model, speeds, repeat, chunk, skip):
    """Per repetition: seconds of campbell, campbell without critical speeds, floor, loop
    (NaN when skipped)."""
    rows = []
    for _ in range(repeat):
        t_campbell, result = timed(lambda: rdm.campbell(model, speeds))
        t_sweep = np.nan if "sweep" in skip else timed(lambda: rdm.campbell(model, speeds, orders=()))[0]
        t_floor, eigenvalues = timed(lambda: floor(model, speeds, chunk))
        t_loop = np.nan if "loop" in skip else timed(lambda: loop(model, speeds, chunk))[0]
        rows.append((t_campbell, t_sweep, t_floor, t_loop))
        print(f"  campbell {t_campbell:8.3f} s | without critical speeds {t_sweep:8.3f} s | floor "
              f"{t_floor:8.3f} s | loop {t_loop:8.3f} s || campbell/floor {t_campbell / t_floor:5.2f}  "
              f"sweep/floor {t_sweep / t_floor:5.2f}  loop/campbell {t_loop / t_campbell:5.2f}", flush=True)
    return np.array(rows), result, eigenvalues


def spread(values) -> str:
    values = list(values)
    return f"{min(values):5.2f} / {statistics.median(values):5.2f} / {max(values):5.2f}"


def run(key, count, repeat, chunk=0, skip=()):
    title, build, top_rpm = MACHINES[key]
    model = build()
    speeds = rdm.rpm(np.linspace(0.0, top_rpm, count))
    form = speed_linear_form(model)
    print(f"({key}) {title}: {form.n_dof} coordinates, {form.n_states} states, {len(model.rotors)} rotors, "
          f"{len(model.bearings)} bearings; {count} speeds 0..{top_rpm:.0f} rpm; {repeat} repetitions")
    rdm.campbell(model, speeds[:3])  # warm-up (imports, thread pool)
    rows, result, eigenvalues = measure(model, speeds, repeat, chunk, skip)
    campbell, sweep, floor, loop = rows.T
    print(f"  {len(result.critical)} 1X critical speeds of {len(result.sources.names)} sources; "
          f"largest |lam_rdm - lam_floor| / max|lam| = {largest_difference(result, eigenvalues):.1e}")
    print(f"  min / median / max   campbell/floor {spread(campbell / floor)}   (target <= 1.3)")
    print(f"                       sweep/floor    {spread(sweep / floor)}   (campbell without critical speeds)")
    print(f"                       loop/campbell  {spread(loop / campbell)}")
    print(f"  critical speeds: {spread((campbell - sweep) / len(result.critical) * 1e3)} ms each "
          f"(campbell minus sweep, per crossing)\n", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--machines", default="abc", help="which of a, b, c (default: abc)")
    parser.add_argument("--speeds", type=int, default=10001, help="speeds of (a) and (b)")
    parser.add_argument("--speeds-c", type=int, default=1001, help="speeds of (c)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--repeat-c", type=int, default=3)
    parser.add_argument("--blas-threads", default="1", help="a number, or 'default'")
    parser.add_argument("--chunk", type=int, default=0,
                        help="floor and loop on parts of this many speeds (bounded memory; default all at once)")
    parser.add_argument("--skip", default="", help="comma-separated: sweep, loop (not timed)")
    parser.add_argument("--save", type=Path, help="write the machines as TOML files into this folder")
    args = parser.parse_args()
    if args.save:
        args.save.mkdir(parents=True, exist_ok=True)
        for key, (_, build, _) in MACHINES.items():
            rdm.save_model(build(), args.save / f"bench_bearings_{key}.toml")
    print(f"BLAS threads: {args.blas_threads}\n")
    with blas_limit(args.blas_threads):
        for key in args.machines:
            count = args.speeds_c if key == "c" else args.speeds
            run(key, count, args.repeat_c if key == "c" else args.repeat, args.chunk, args.skip.split(","))


if __name__ == "__main__":
    main()
