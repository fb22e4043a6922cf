"""FRF speed: ``rdm.frf`` against ``control.frequency_response`` on the same state-space model.

20,000 frequencies, two inputs and two outputs of the gear machine
(examples/gear_machine.toml) at 3000 rpm. Times

* ``rdm.frf`` on the viscous model (modal superposition, one eigen-decomposition),
* ``rdm.frf`` on the same model with a loss factor (batched direct solve of 6x6 systems),
* ``control.frequency_response`` on ``model.state_space(speed)`` (viscous),

checks that the viscous results agree, and prints best-of-N times and the ratios. Run::

    python benchmarks/bench_frf.py [--freqs 20000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import control
import numpy as np

import rotordyn_modal as rdm
from _timing import best_time  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

MODEL = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"




def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--freqs", type=int, default=20000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)

    model = rdm.load_model(MODEL)
    data = model.to_dict()
    for s in data["suspensions"]:
        s["loss_factor"] = 0.05
    hysteretic = rdm.Model.from_dict(data)
    speed = rdm.rpm(3000)
    freqs = np.linspace(0.1, 100.0, args.freqs)
    omega = 2 * np.pi * freqs
    system = model.state_space(speed)

    def python_control():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return control.frequency_response(system, omega)

    ours = rdm.frf(model, speed, freqs)
    reference = python_control()
    H = np.asarray(getattr(reference, "frdata", None) if hasattr(reference, "frdata") else reference.fresp)
    error = np.abs(ours.H - H).max() / np.abs(H).max()

    t_modal = best_time(lambda: rdm.frf(model, speed, freqs), args.repeat)
    t_direct = best_time(lambda: rdm.frf(hysteretic, speed, freqs), args.repeat)
    t_control = best_time(python_control, args.repeat)
    print(f"model: {MODEL.name}, {args.freqs} frequencies, 2 inputs x 2 outputs, 3000 rpm, best of {args.repeat}")
    print(f"rdm.frf, viscous (modal superposition)      : {1e3 * t_modal:8.2f} ms")
    print(f"rdm.frf, loss factor (batched direct solve)  : {1e3 * t_direct:8.2f} ms")
    print(f"control.frequency_response (StateSpace)      : {1e3 * t_control:8.2f} ms")
    print(f"control / rdm viscous     = {t_control / t_modal:6.1f}  (target >= 10)")
    print(f"control / rdm loss factor = {t_control / t_direct:6.1f}")
    print(f"max |difference| / max |H| (viscous) = {error:.1e}")


if __name__ == "__main__":
    main()
