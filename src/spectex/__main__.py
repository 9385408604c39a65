"""``python -m spectex``: the command line."""

import sys

from spectex.cli import main

sys.exit(main())
