"""Analyses: each a plain function taking a model and returning a result object.

One module per analysis (``modal``, ``campbell``, ``critical_speeds``, ``stability``, ``frf``,
``unbalance``, ...). The functions are public from the package root (``rdm.campbell``) or their
module (``rotordyn_modal.analysis.campbell.campbell``); here a name that is also a module's name
(``modal``, ``campbell``, ``critical_speeds``, ``stability``, ``frf``, ``fit``) is that module.
The other names are imported from their module when first used, so that one analysis does not
load the others.
"""

from __future__ import annotations

import importlib

_API = {
    "ModalResult": "modal", "mac": "modal",
    "CampbellResult": "campbell",
    "CriticalSpeeds": "critical_speeds", "excitation_sources": "critical_speeds",
    "stability_map": "stability", "StabilityResult": "stability", "StabilityMap": "stability",
    "FRFResult": "frf", "force_frf": "forces",
    "unbalance_response": "unbalance", "UnbalanceResult": "unbalance",
    "FitResult": "fit",
    "correlate": "correlation", "Correlation": "correlation", "fit_measured_modes": "correlation",
    "identify_modes": "identification", "MeasuredModes": "identification",
    "StabilizationChart": "identification",
    "stator_motion": "experimental", "RigidBodyMotion": "experimental",
    "transformation_matrix": "experimental",
}

__all__ = sorted(_API)


def __getattr__(name: str):
    if name not in _API:
        raise AttributeError(f"module 'rotordyn_modal.analysis' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_API[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))
