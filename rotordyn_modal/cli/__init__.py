"""The ``rotordyn-modal`` command line (``../shared/spec/cli.md``).

One module per sub-command, each with ``NAME``, ``HELP``, ``add_arguments``
and ``run``; :data:`SUBCOMMANDS` (from :mod:`.commands`) lists them in ``--help`` order.
"""

from __future__ import annotations

from .commands import SUBCOMMANDS
from .main import main

__all__ = ["main", "SUBCOMMANDS"]
