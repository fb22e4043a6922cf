"""The sub-commands in ``--help`` order: one module each, with ``NAME``, ``HELP``,
``DESCRIPTION``, ``add_arguments`` and ``run``."""

from __future__ import annotations

from . import campbell, check, critical_speeds, fit, frf, import_ross, modes, simulate, stability, study, unbalance

SUBCOMMANDS = [check, modes, campbell, critical_speeds, stability, simulate, frf, unbalance, fit, study, import_ross]

__all__ = ["SUBCOMMANDS"]
