"""The ``spectex`` command line: a thin layer over the library.

Each subcommand lives in its own module here with a ``register(subparsers)``
function; the modules import nothing heavy at the top, so that ``spectex
--help`` answers at once. Library errors (``ValueError``, ``TypeError``,
``OSError``) become one line on standard error and exit status 2.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import re
import sys

from ._common import UsageError

__all__ = ["main", "build_parser", "UsageError"]

# Subcommand modules, in the order they appear in ``spectex --help``.
_COMMANDS = (
    "demo",
    "noise",
    "tile",
    "spectrum",
    "render",
    "view",
    "export",
    "synth",
    "text",
    "compare",
    "fit",
    "bake",
)


def _noting(base):
    """An argparse action class like ``base`` that also notes which options were given.

    The names go to the namespace's ``given`` attribute, a dict from ``dest``
    to the option string as typed (``--gain``), so that a command can refuse
    an option that does not apply to what was asked (see
    :func:`spectex.cli._common.refuse`) while keeping its default otherwise.
    """

    class Noting(base):
        def __call__(self, parser, namespace, values, option_string=None):
            if option_string is not None:
                given = vars(namespace).setdefault("given", {})
                given[self.dest] = option_string
                # its long name (--output for -o), for messages: see _as_option
                vars(namespace).setdefault("long_names", {})[self.dest] = max(self.option_strings, key=len)
            super().__call__(parser, namespace, values, option_string)

    Noting.__name__ = f"Noting{base.__name__}"
    return Noting


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line and exit status 2.

    A value that starts with a minus sign and a digit (``--size -5x10``,
    ``--beta -1e3``) is taken as the option's value, so that its own check
    says what is wrong with it (argparse would otherwise say "expected one
    argument"); no spectex option name starts with a digit. The options given
    on the command line are noted in ``args.given`` (``dest`` to the option
    string typed).
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-\.?\d")
        self.register("action", None, _noting(argparse._StoreAction))
        self.register("action", "store", _noting(argparse._StoreAction))
        self.register("action", "store_true", _noting(argparse._StoreTrueAction))

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    from spectex._version import __version__

    parser = _Parser(
        prog="spectex",
        description="Spectral texturing, procedural noise and texture synthesis from examples.",
    )
    parser.add_argument("--version", action="version", version=f"spectex {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in _COMMANDS:
        try:
            module = importlib.import_module(f"spectex.cli._{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"spectex.cli._{name}":
                continue  # not built yet
            raise
        module.register(sub)
    return parser


def main(argv=None) -> int:
    """Run the command line; return the exit status.

    The command runs in a :func:`spectex._output.session`: every file it
    reads is recorded, so that no output can replace one, and SIGTERM or
    SIGHUP get the clean-up of Ctrl-C (exit status 128 + the signal's number:
    130 for Ctrl-C, 143 for SIGTERM).
    """
    from spectex._output import Terminated, check_interrupted, session

    who = "spectex"
    args = None
    try:
        with session():
            parser = build_parser()
            args = parser.parse_args(argv)
            if not getattr(args, "func", None):
                parser.print_help()
                return 2
            who = f"spectex {args.command}"
            result = args.func(args)
            check_interrupted()  # a Ctrl-C that a library swallowed still ends the run as one
    except (UsageError, ValueError, TypeError) as exc:
        print(f"{who}: error: {_as_option(_one_line(exc), args)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (spectex text | head): stop quietly, as C tools do
        import os

        with contextlib.suppress(OSError, ValueError, AttributeError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error at exit
        return 141
    except OSError as exc:
        print(f"{who}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"{who}: error: out of memory (try smaller sizes)", file=sys.stderr)
        return 2
    except Terminated as exc:
        print(f"{who}: terminated (signal {exc.signum})", file=sys.stderr)
        return 128 + exc.signum
    except KeyboardInterrupt:
        print(f"{who}: interrupted", file=sys.stderr)
        return 130
    return 0 if result is None else int(result)


def _as_option(message: str, args) -> str:
    """``message`` with a leading library parameter name (``cutoff must be <= 0.5``) written as the
    option the user gave for it, by its long name (``--cutoff must be <= 0.5``; ``--output`` for
    ``-o``): the library's errors name its parameters, and on the command line the option is the
    name the user knows. Only an option given on the command line is renamed, so a library message
    about a parameter the user did not set keeps its own words."""
    names = getattr(args, "long_names", None) or {}
    word = message.split(" ", 1)[0]
    if word in names:
        return names[word] + message[len(word):]
    return message


def _one_line(exc: BaseException) -> str:
    text = str(exc) or type(exc).__name__
    if isinstance(exc, OSError) and exc.strerror and exc.filename is None:
        text = exc.strerror  # "[Errno 28] No space left on device": the number says nothing more
    return " ".join(text.split())


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
