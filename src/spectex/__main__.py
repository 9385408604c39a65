"""``python -m spectex``: the command line."""

import sys

try:
    from spectex.cli import main

    status = main()
except KeyboardInterrupt:  # Ctrl-C before a command started (while Python imports)
    print("spectex: interrupted", file=sys.stderr)
    status = 130
sys.exit(status)
