import sys

from rubdiag.cli import main

sys.exit(main())
