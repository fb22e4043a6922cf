"""rotordyn_modal: linear dynamics and modal analysis of multi-rotor machines.

A rigid stator on suspensions carrying rigid rotors with parallel spin axes,
coupled by gears or belts::

    import rotordyn_modal as rdm
    model = rdm.load_model("examples/gear_machine.toml")
    M, C, G, K = model.matrices()
    res = rdm.campbell(model, rdm.rpm(np.linspace(0, 12000, 241)))
    res.plot()
"""

from .analysis import (
    CampbellResult, CriticalSpeeds, ModalResult, StabilityMap, StabilityResult, campbell,
    critical_speeds, excitation_sources, mac, modal, stability, stability_map,
)
from .assembly import Matrices, matrices
from .errors import InputError, ModelError
from .geometry import shift_cross, shift_matrix, skew
from .io import load_model, save_model
from .linear_system import state_matrices, state_space
from .model import Excitation, Model, Rotor, Sensor, Stator, Suspension, Transmission, Unbalance
from .units import hz, rpm, to_hz, to_rpm
from . import kinematics, simulation
from .simulation import SimulationResult, simulate
from .analysis import (Correlation, FitResult, FRFResult, RigidBodyMotion, UnbalanceResult,  # issue 4
                       correlate, fit, force_frf, frf, stator_motion, unbalance_response)
from .io.measured import read_measured, write_csv as write_measured_csv
from .io.uff import write_uff58
from . import study  # issue 7: parameter studies; the module is callable: rdm.study(model, spec)
from .study import StudyResult, load_study

# measurement side and pictures: time records and H1/H2, UFF geometry and time records, TDMS
# ('tdms' extra), modal identification (LSCF: 'ema' extra), 3D mode shapes
from .analysis.identification import MeasuredModes, StabilizationChart, identify_modes
from .analysis.mode_shapes import ModeShape3D, mode_shape_3d
from .analysis.spectra import TimeRecords, estimate_frf
from .io.tdms import read_tdms_records
from .io.uff import place_channels, read_uff_info, read_uff_nodes, read_uff_time_records

__version__ = "0.1.0"

__all__ = [
    "Model", "Stator", "Rotor", "Transmission", "Suspension", "Unbalance", "Sensor", "Excitation",
    "load_model", "save_model", "matrices", "Matrices", "state_space", "state_matrices",
    "modal", "ModalResult", "mac", "campbell", "CampbellResult", "critical_speeds", "CriticalSpeeds",
    "excitation_sources", "stability", "stability_map", "StabilityResult", "StabilityMap",
    "shift_matrix", "shift_cross", "skew", "rpm", "to_rpm", "hz", "to_hz",
    "InputError", "ModelError", "__version__",
    "kinematics", "simulation", "simulate", "SimulationResult",
    "frf", "FRFResult", "force_frf", "unbalance_response", "UnbalanceResult", "fit", "FitResult",
    "read_measured", "write_measured_csv", "write_uff58", "correlate", "Correlation", "stator_motion",
    "RigidBodyMotion",
    "study", "StudyResult", "load_study",
]
__all__ += ["identify_modes", "MeasuredModes", "StabilizationChart", "ModeShape3D", "mode_shape_3d", "TimeRecords",
            "estimate_frf", "read_tdms_records", "place_channels", "read_uff_info", "read_uff_nodes",
            "read_uff_time_records"]
