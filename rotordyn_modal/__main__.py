"""``python -m rotordyn_modal ...``: the ``rotordyn-modal`` command line, for a Python whose
scripts folder is not on the PATH."""

import sys

from rotordyn_modal.cli.main import main

if __name__ == "__main__":
    sys.exit(main())
