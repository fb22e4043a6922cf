"""rotordyn_modal: linear dynamics and modal analysis of multi-rotor machines.

A rigid stator on suspensions carrying rigid rotors with parallel spin axes, rigidly
attached or on flexible bearings, coupled by gears or belts::

    import rotordyn_modal as rdm
    model = rdm.load_model("examples/gear_machine.toml")
    M, C, G, K = model.matrices()
    res = rdm.campbell(model, rdm.rpm(np.linspace(0, 12000, 241)))
    res.plot()

The public names below are grouped by concept. Each is imported from its module the first
time it is used (:pep:`562`), so ``import rotordyn_modal`` and ``rotordyn-modal check`` load
numpy and the model only, not scipy, python-control, pandas, matplotlib or the rest.
"""

from __future__ import annotations

import importlib

from ._version import __version__
from .errors import InputError, ModelError
from .units import hz, rpm, to_hz, to_rpm

#: public name -> module that defines it, by concept
_API = {
    # the model: components, files
    "Model": "model", "Stator": "model.components", "Rotor": "model.components",
    "Transmission": "model.components", "Suspension": "model.components",
    "Bearing": "model.components", "Unbalance": "model.components",
    "Sensor": "model.components", "Excitation": "model.components",
    "load_model": "io", "save_model": "io",
    # geometry, matrices and the linear system
    "shift_matrix": "model.geometry", "shift_cross": "model.geometry", "skew": "model.geometry",
    "matrices": "assembly", "Matrices": "assembly",
    "state_space": "linear_system", "state_matrices": "linear_system",
    # modal analyses
    "modal": "analysis.modal", "ModalResult": "analysis.modal", "mac": "analysis.modal",
    "campbell": "analysis.campbell", "CampbellResult": "analysis.campbell",
    "critical_speeds": "analysis.campbell", "CriticalSpeeds": "analysis.critical_speeds",
    "excitation_sources": "analysis.critical_speeds",
    "stability": "analysis.stability", "stability_map": "analysis.stability",
    "StabilityResult": "analysis.stability", "StabilityMap": "analysis.stability",
    "mode_shape_3d": "analysis.mode_shapes", "ModeShape3D": "analysis.mode_shapes",
    "shaft_lines": "analysis.mode_shapes", "ShaftLines": "analysis.mode_shapes",
    # standards' screenings: undamped critical speed map, API 617 Level I
    "ucs_map": "analysis.ucs_map", "UcsMap": "analysis.ucs_map",
    "level1": "analysis.level1", "Level1Result": "analysis.level1", "Station": "analysis.level1",
    "anticipated_cross_coupling": "analysis.level1",
    # responses and forces
    "frf": "analysis.frf", "FRFResult": "analysis.frf", "force_frf": "analysis.forces",
    "unbalance_response": "analysis.unbalance", "UnbalanceResult": "analysis.unbalance",
    # static loads, displacements and reactions
    "static": "analysis.static", "StaticResult": "analysis.static", "ShaftStatics": "analysis.shaft_statics",
    # model versus measurement
    "read_measured": "io.measured", "write_measured_csv": "io.measured", "write_uff58": "io.uff",
    "read_uff_info": "io.uff", "read_uff_nodes": "io.uff", "read_uff_time_records": "io.uff",
    "place_channels": "io.uff", "read_tdms_records": "io.tdms", "read_uff_modes": "io.uff_modes",
    "TimeRecords": "analysis.spectra", "estimate_frf": "analysis.spectra",
    "identify_modes": "analysis.identification", "MeasuredModes": "analysis.identification",
    "StabilizationChart": "analysis.identification",
    "correlate": "analysis.correlation", "Correlation": "analysis.correlation",
    "correlate_modes": "analysis.correlation",
    "fit": "analysis.fit", "FitResult": "analysis.fit",
    "stator_motion": "analysis.experimental", "RigidBodyMotion": "analysis.experimental",
    # large rotations and time simulation
    "kinematics": None, "simulation": None,  # modules (see _MODULES)
    "simulate": "simulation", "SimulationResult": "simulation",
    # parameter studies (the module is callable: rdm.study(model, spec))
    "study": None, "StudyResult": "study", "load_study": "study",
    # work over the CPU-time limit run anyway (the command line's --allow-long)
    "long_work_allowed": "analysis._cost",
}
_RENAMED = {"write_measured_csv": "write_csv"}
#: public module names -> where the module lives
_MODULES = {"kinematics": "simulation.kinematics", "simulation": "simulation", "study": "study"}

__all__ = sorted(_API) + ["InputError", "ModelError", "rpm", "to_rpm", "hz", "to_hz", "__version__"]


def __getattr__(name: str):
    if name not in _API:
        raise AttributeError(f"module 'rotordyn_modal' has no attribute {name!r}")
    module = _API[name]
    if module is None:
        value = importlib.import_module(f".{_MODULES[name]}", __name__)
    else:
        value = getattr(importlib.import_module(f".{module}", __name__), _RENAMED.get(name, name))
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))
