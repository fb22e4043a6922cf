"""Nonlinear large-rotation time simulation (Sorokin & Zhang 2018, docs/theory-large-rotations.md) and its run-up analyses.

:func:`simulate` integrates the machine's exact equations of motion; :func:`linearize`
differentiates them about steady spin (to check the linear model (docs/theory.md));
:func:`order_track` and :func:`waterfall` analyse a run-up.
"""

from .linearize import linearize
from .result import SimulationResult
from .runup import OrderTrack, Waterfall, order_track, waterfall
from .simulate import BACKENDS, DRIVES, simulate

__all__ = ["simulate", "SimulationResult", "linearize", "order_track", "waterfall", "OrderTrack",
           "Waterfall", "DRIVES", "BACKENDS"]
