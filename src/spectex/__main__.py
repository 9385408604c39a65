"""``python -m spectex``: the command line."""

import sys

try:
    import signal

    from spectex._output import _raise_terminated

    # SIGTERM and SIGHUP from the first moment, not only once a command runs (cli.main's session
    # does the same); a signal that is ignored (nohup) stays ignored.
    for sig in (signal.SIGTERM, getattr(signal, "SIGHUP", None)):
        if sig is not None and signal.getsignal(sig) is not signal.SIG_IGN:
            signal.signal(sig, _raise_terminated)
    from spectex.cli import main

    status = main()
except KeyboardInterrupt as exc:  # a signal while Python was still importing
    signum = getattr(exc, "signum", None)
    if signum is None:
        print("spectex: interrupted", file=sys.stderr)
        status = 130
    else:
        print(f"spectex: terminated (signal {signum})", file=sys.stderr)
        status = 128 + signum
# The run is over and its status decided: a Ctrl-C or SIGTERM during the interpreter's exit is ignored.
# Python puts the default action back for the signals it handles as it exits, so such a signal killed the
# process (status -2, nothing said) or, arriving while native libraries' threads were torn down, crashed
# it (status -11): seen under load in tests/test_hostile.py. Ignored signals stay ignored through the exit.
for sig in (signal.SIGINT, signal.SIGTERM, getattr(signal, "SIGHUP", None)):
    if sig is not None:
        signal.signal(sig, signal.SIG_IGN)
sys.exit(status)
