"""Figures of the analyses' results. Plotting never computes: it draws result objects.

Every function returns the matplotlib ``Figure`` it drew; matplotlib is imported
only when a function is called.
"""

from .campbell import plot_campbell
from .modes import plot_modes
from .simulation import plot_runup, plot_simulation
from .stability import plot_stability, plot_stability_map

__all__ = ["plot_campbell", "plot_modes", "plot_stability", "plot_stability_map", "plot_simulation", "plot_runup"]
