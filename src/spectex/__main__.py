"""``python -m spectex``: the command line."""

import signal
import sys

from spectex._output import Terminated, _raise_terminated

# SIGTERM from the first moment, not only once a command runs (cli.main's session does the same).
signal.signal(signal.SIGTERM, _raise_terminated)
try:
    from spectex.cli import main

    status = main()
except Terminated as exc:  # a signal while Python was still importing
    print(f"spectex: terminated (signal {exc.signum})", file=sys.stderr)
    status = 128 + exc.signum
except KeyboardInterrupt:
    print("spectex: interrupted", file=sys.stderr)
    status = 130
sys.exit(status)
