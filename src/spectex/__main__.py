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
sys.exit(status)
