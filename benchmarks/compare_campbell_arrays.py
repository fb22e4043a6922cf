"""Every ``rdm.campbell`` array of the examples, the ROSS rotors of tests/data/ross and the
benchmarks' one-rotor machines and a chain of three geared rotors (51 and 201 speeds, orders 1
and 2; all modes, and the lowest 12 where a model has more than 30 coordinates or is a ROSS
rotor), saved, or two saves compared: a speed change must leave them bit for bit (or within
round-off, printed ``ROUNDOFF``)::

    PYTHONPATH=/path/to/base python benchmarks/compare_campbell_arrays.py /tmp/before.npz
    PYTHONPATH=$PWD python benchmarks/compare_campbell_arrays.py /tmp/after.npz
    python benchmarks/compare_campbell_arrays.py /tmp/before.npz /tmp/after.npz

Run from the repository root (the examples are read by relative path).
"""

from __future__ import annotations

import glob
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: the attributes of a CampbellResult and of its critical speeds' table that are compared
RESULT = ("eigenvalues", "shapes", "whirl_ratios", "whirl", "modes", "frequencies_hz", "log_decrements")
CRITICAL = ("speeds", "frequencies_hz", "mode", "whirl_ratios", "damping_ratios")


def models() -> dict:
    """The models compared, by name."""
    import rotordyn_modal as rdm
    from _machines import gear_chain
    from bench_campbell import one_rotor_models
    from rotordyn_modal.io.ross_file import read_ross_rotor

    out = dict(one_rotor_models())
    out["chain3"] = gear_chain(3)
    for path in sorted(glob.glob("examples/*.toml")):
        if "study" not in path:
            out[path] = rdm.load_model(path)
    for path in sorted(glob.glob("tests/data/ross/*.toml")):
        if "damping" not in path:          # proportional damping: not read (docs/ross.md)
            out[path] = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    return out


def speeds_of(name: str, count: int) -> np.ndarray:
    """``count`` speeds [rad/s]: 300-6000 rpm, a ROSS rotor's over its reference speeds."""
    import rotordyn_modal as rdm

    if "data/ross" in name:
        reference = [case["speed"] for case in json.loads(Path(name.replace(".toml", ".json")).read_text())["modal"]]
        return np.linspace(min(reference), max(reference), count)
    return rdm.rpm(np.linspace(300.0, 6000.0, count))


def collect() -> dict:
    """Every compared array, by ``name|speeds|all or low|attribute``."""
    import rotordyn_modal as rdm

    out = {}
    for name, model in models().items():
        for count in (51, 201):
            speeds = speeds_of(name, count)
            variants = [("all", {})]
            if model.dofs.n > 30 or "data/ross" in name:
                variants = [("low", {"modes": 12})] + (variants if count == 51 and model.dofs.n < 400 else [])
            for tag, keywords in variants:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = rdm.campbell(model, speeds, orders=(1, 2), **keywords)
                key = f"{name}|{count}|{tag}"
                for attribute in RESULT:
                    value = np.asarray(getattr(result, attribute))
                    out[f"{key}|{attribute}"] = value.astype(str) if attribute == "whirl" else value
                for attribute in CRITICAL:
                    out[f"{key}|crit.{attribute}"] = np.asarray(getattr(result.critical, attribute))
                print(key, model.dofs.n, flush=True)
    return out


def compare(first: str, second: str) -> int:
    """Print the arrays that differ; return how many differ beyond round-off (1e-10 relative)."""
    a, b = np.load(first), np.load(second)
    if set(a.files) != set(b.files):
        print("different keys:", sorted(set(a.files) ^ set(b.files)))
        return 1
    bad = 0
    for key in a.files:
        x, y = a[key], b[key]
        if x.shape != y.shape:
            print("SHAPE", key, x.shape, y.shape)
            bad += 1
        elif x.dtype.kind in "US":
            if not (x == y).all():
                print("DIFF", key, int((x != y).sum()))
                bad += 1
        elif not np.array_equal(x, y, equal_nan=True):
            worst = np.nanmax(np.abs(x - y) / np.maximum(np.abs(x), 1e-300)) if x.size else 0.0
            print("ROUNDOFF" if worst < 1e-10 else "DIFF", key, "max rel", worst)
            bad += worst >= 1e-10
    print("compared", len(a.files), "arrays; real differences:", bad)
    return bad


def main() -> None:
    if len(sys.argv) == 2:
        np.savez(sys.argv[1], **collect())
    elif len(sys.argv) == 3:
        sys.exit(1 if compare(sys.argv[1], sys.argv[2]) else 0)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
