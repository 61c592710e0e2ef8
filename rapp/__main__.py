"""``python -m rapp``: see :mod:`rapp.cli`."""

import sys

from rapp.cli import main

if __name__ == "__main__":
    sys.exit(main())
