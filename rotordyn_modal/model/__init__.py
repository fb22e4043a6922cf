"""The machine model: what a model file describes, checked before anything is computed.

* :mod:`.machine`: the :class:`Model` (stator, rotors, transmissions, suspensions, bearings,
  sensors, excitations), its speed ratios and its variants;
* :mod:`.components`: one dataclass per table of the model file;
* :mod:`._validation` and :mod:`._table`: the model-wide rules (names, references, speed
  ratios) and those of the tables that are no element, and the reading of one table with
  messages that name the file, key, value and what was expected;
* :mod:`.parameters`: dotted parameter keys (``suspensions.mount-FL.stiffness[2]``);
* :mod:`.geometry`: shift matrices (``docs/theory.md`` section 1);
* :mod:`.dofs`: the generalized coordinates (stator, rotors on bearings).

The elements that connect the bodies and compute their own coefficients (mounts, bearings,
journal bearings) are in :mod:`rotordyn_modal.elements`, each with its table's rules.
"""

from .machine import Model

__all__ = ["Model"]
