"""The ``rotordyn-modal`` command line (``../shared/spec/cli.md``).

One module per sub-command, each with ``NAME``, ``HELP``, ``add_arguments``
and ``run``; :data:`SUBCOMMANDS` lists them in ``--help`` order.
"""

from __future__ import annotations

from . import campbell, check, critical_speeds, modes, simulate, stability
from . import fit, frf, unbalance
from . import study
from .main import main

SUBCOMMANDS = [check, modes, campbell, critical_speeds, stability, simulate]
SUBCOMMANDS += [frf, unbalance, fit]
SUBCOMMANDS += [study]

__all__ = ["main", "SUBCOMMANDS"]
