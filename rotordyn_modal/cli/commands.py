"""The sub-commands in ``--help`` order: one module each, with ``NAME``, ``HELP``,
``DESCRIPTION``, ``add_arguments`` and ``run``."""

from __future__ import annotations

from . import campbell, check, critical_speeds, fit, frf, import_ross, level1, modes, report, simulate, stability, static, study, ucs_map, unbalance

SUBCOMMANDS = [check, static, modes, campbell, critical_speeds, stability, ucs_map, level1, simulate, frf, unbalance, fit, study, import_ross, report]

__all__ = ["SUBCOMMANDS"]
