"""Analyses: each a plain function taking a model and returning a result object."""

from .campbell import CampbellResult, CriticalSpeeds, campbell, critical_speeds, excitation_sources
from .modal import ModalResult, mac, modal
from .stability import StabilityMap, StabilityResult, stability, stability_map
from .fit import FitResult, fit
from .forces import force_frf
from .frf import FRFResult, frf
from .unbalance import UnbalanceResult, unbalance_response
from .correlation import Correlation, correlate, fit_measured_modes
from .identification import MeasuredModes, StabilizationChart, identify_modes
from .experimental import RigidBodyMotion, stator_motion, transformation_matrix

__all__ = ["modal", "ModalResult", "mac", "campbell", "CampbellResult", "critical_speeds",
           "CriticalSpeeds", "excitation_sources", "stability", "stability_map", "StabilityResult",
           "StabilityMap",
           "frf", "FRFResult", "force_frf", "unbalance_response", "UnbalanceResult", "fit", "FitResult",
           "correlate", "Correlation", "fit_measured_modes", "identify_modes", "MeasuredModes",
           "StabilizationChart", "stator_motion", "RigidBodyMotion",
           "transformation_matrix"]
