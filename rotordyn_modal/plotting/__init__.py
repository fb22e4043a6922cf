"""Figures of the analyses' results. Plotting never computes: it draws result objects.

Every function returns the matplotlib ``Figure`` it drew; matplotlib is imported
only when a function is called.
"""

from .campbell import plot_campbell
from .modes import plot_modes
from .simulation import plot_runup, plot_simulation
from .stability import plot_stability, plot_stability_map
from .ucs_map import plot_ucs_map
from .level1 import plot_csr_chart, plot_level1
from .correlation import plot_correlation, plot_fit_correlation, plot_rigid_body
from .frf import plot_frf, plot_overlay, plot_unbalance
from .orbits import plot_orbits
from .identification import plot_stabilization
from .measurement import plot_coherence, plot_time_records
from .shapes3d import animate_mode_shape, plot_mode_shape, plot_mode_shapes
from .shaft_modes import plot_shaft_modes
from .study import plot_critical_histograms, plot_sensitivity, plot_study_campbell, plot_study_stability_map

__all__ = ["plot_campbell", "plot_modes", "plot_stability", "plot_stability_map", "plot_simulation", "plot_runup",
           "plot_frf", "plot_overlay", "plot_unbalance", "plot_orbits", "plot_correlation", "plot_fit_correlation",
           "plot_rigid_body", "plot_study_campbell", "plot_critical_histograms", "plot_study_stability_map",
           "plot_sensitivity", "plot_stabilization", "plot_coherence", "plot_time_records", "plot_mode_shape",
           "plot_mode_shapes", "animate_mode_shape", "plot_ucs_map", "plot_level1", "plot_shaft_modes",
           "plot_csr_chart"]
