"""``python -m rubdiag.cli``: the ``rubdiag`` command line."""

import sys

from rubdiag.cli import main

if __name__ == "__main__":
    sys.exit(main())
