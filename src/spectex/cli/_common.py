"""Argument types and helpers shared by the subcommands (no heavy imports)."""

from __future__ import annotations

import argparse
from pathlib import Path

from spectex._numbers import parse_float, parse_int


class UsageError(Exception):
    """A command-line mistake: reported in one line, exit status 2."""


def whole_number(text: str) -> int:
    """Any whole number in ASCII digits (:func:`spectex._numbers.parse_int`): the base of the int options."""
    try:
        return parse_int(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def size(text: str) -> tuple[int, int]:
    """Parse ``WxH`` (or ``N`` for a square) into ``(height, width)``; ASCII digits only."""
    parts = text.lower().split("x")
    try:
        if len(parts) == 1:
            w = h = parse_int(parts[0])
        elif len(parts) == 2:
            w, h = parse_int(parts[0]), parse_int(parts[1])
        else:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxH such as 512x256, got '{text}'") from None
    if w < 1 or h < 1:
        raise argparse.ArgumentTypeError(f"width and height must be >= 1, got '{text}'")
    return h, w


def positive_int(text: str) -> int:
    value = whole_number(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def nonneg_int(text: str) -> int:
    value = whole_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


#: The largest --seed (numpy's seeds go further, but the library takes a non-negative int64).
MAX_SEED = 2 ** 63 - 1


def seed(text: str) -> int:
    """A ``--seed``: a whole number from 0 to :data:`MAX_SEED` (the CLI's word for the library's ``rng``)."""
    value = nonneg_int(text)
    if value > MAX_SEED:
        raise argparse.ArgumentTypeError(f"must be at most {MAX_SEED}, got {text}")
    return value


def finite_float(text: str) -> float:
    """A finite number in ASCII digits (:func:`spectex._numbers.parse_float`): the base of the float options."""
    try:
        return parse_float(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def bit_depth(text: str) -> int:
    """A PNG ``--bit-depth``: 8 or 16."""
    value = whole_number(text)
    if value not in (8, 16):
        raise argparse.ArgumentTypeError(f"must be 8 or 16, got {value}")
    return value


def haze(text: str) -> float:
    """A haze distance in metres: >= 0 (0: no haze), at most 1e30."""
    value = finite_float(text)
    if value < 0 or value > 1e30:
        raise argparse.ArgumentTypeError(f"must be 0 (no haze) or a distance in metres up to 1e30, got {text}")
    return value


def add_haze(p) -> None:
    """The ``--haze`` option of the commands that draw a view."""
    from spectex.shading.constants import DEFAULT_HAZE

    p.add_argument("--haze", type=haze, default=DEFAULT_HAZE, metavar="METRES",
                   help=f"haze distance: the ground keeps exp(-distance / METRES) of its colour; 0 turns the "
                        f"haze off, as an engine export draws the texture (default: {DEFAULT_HAZE:g})")


def positive_float(text: str) -> float:
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def floats(count: int):
    """An argument type for ``count`` comma-separated numbers (spaces around the commas are allowed)."""

    def parse(text: str) -> tuple[float, ...]:
        parts = text.split(",")
        if len(parts) != count:
            raise argparse.ArgumentTypeError(f"expected {count} comma-separated numbers, got '{text}'")
        return tuple(finite_float(p.strip()) for p in parts)

    return parse


def existing_file(text: str) -> Path:
    """An existing regular file; the error says what the path is instead (missing, a folder, a pipe...)."""
    from spectex._output import check_input_file

    try:
        return check_input_file("", text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).strip()) from None


def output_name(text: str) -> str:
    """An output file or folder name: not empty (an empty name would mean the current folder)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"expected a file or folder name, got '{text}'")
    return text


def require_stdout(what: str) -> None:
    """Refuse to run when standard output is closed and ``what`` would be printed there (and lost)."""
    import sys

    if sys.stdout is None:
        raise ValueError(f"standard output is closed: {what}")


def given(args, dest: str) -> bool:
    """Whether the option stored in ``dest`` was typed on the command line (not left at its default)."""
    return dest in getattr(args, "given", {})


def refuse(args, dests, why: str) -> None:
    """Refuse, in one line, the first of the options ``dests`` that was given: it does not apply ``why``.

    ``why`` completes the sentence "--gain does not apply ...", e.g. ``"to
    marble (only to fbm and turbulence)"``.
    """
    typed = getattr(args, "given", {})
    for dest in dests:
        if dest in typed:
            raise UsageError(f"{typed[dest]} does not apply {why}")


def report(message: str) -> None:
    """Print a progress or result line (standard output)."""
    print(message, flush=True)


def say_if_compiling(what: str, *kernels) -> None:
    """One line before a run whose first step compiles a numba kernel (``cache=True``): the first run after
    an install waits for it, without the line, on a bar that does not move. ``kernels``: the one the run
    calls, or those it may call (said only when none of them is on disk: the first run's case)."""
    from spectex._numba_cache import compiled

    if kernels and all(compiled(kernel) is False for kernel in kernels):
        report(f"compiling {what} (numba, once per install: about half a minute on 2 cores; later runs "
               "start at once)")


class Progress:
    """A progress bar on standard error for long library calls.

    Use as a context manager; pass the instance (a callable ``(done, total)``)
    as the ``progress`` argument of a library function. The bar appears only
    when standard error is a terminal, and only once the work has taken more
    than ``delay`` seconds.
    """

    def __init__(self, description: str, *, delay: float = 0.5):
        self.description = description
        self.delay = delay
        self._bar = None
        self._task = None
        self._start = None

    def __enter__(self):
        import time

        self._start = time.perf_counter()
        return self

    def __call__(self, done: int, total: int) -> None:
        import sys
        import time

        if self._bar is None:
            if not sys.stderr.isatty() or time.perf_counter() - self._start < self.delay:
                return
            from rich.console import Console
            from rich.progress import BarColumn, TextColumn, TimeRemainingColumn
            from rich.progress import Progress as _RichProgress

            self._bar = _RichProgress(TextColumn("{task.description}"), BarColumn(),
                                      TextColumn("{task.percentage:>3.0f}%"), TimeRemainingColumn(),
                                      transient=True, console=Console(stderr=True))
            self._bar.start()
            self._task = self._bar.add_task(self.description, total=total)
        self._bar.update(self._task, completed=done, total=total)

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.stop()
        return False


class Steps:
    """The named steps of a long command, shown on standard error while they run.

    Use as a context manager and call :meth:`step` before each step (``"computing
    fbm"``, ``"writing PNG"``). On a terminal, once the command has taken more than
    ``delay`` seconds, one transient line shows a spinner, the step's name, the
    step count and the time taken, refreshed while a step runs (so that a long PNG
    encoding is seen to be working); it is gone when the command ends. Not on a
    terminal (a pipe, a file, a test), nothing is shown.
    """

    def __init__(self, total: int, *, delay: float = 0.5):
        self.total = total
        self.delay = delay
        self._done = 0
        self._description = ""
        self._bar = None
        self._task = None
        self._timer = None
        self._lock = None

    def __enter__(self):
        import sys
        import threading

        self._lock = threading.Lock()
        if sys.stderr is not None and sys.stderr.isatty():
            self._timer = threading.Timer(self.delay, self._start)
            self._timer.daemon = True
            self._timer.start()
        return self

    def _start(self) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, SpinnerColumn, TextColumn, TimeElapsedColumn
        from rich.progress import Progress as _RichProgress

        with self._lock:
            if self._timer is None:  # finished meanwhile
                return
            self._bar = _RichProgress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                                      TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                                      transient=True, console=Console(stderr=True))
            self._task = self._bar.add_task(self._description, total=self.total, completed=self._done)
            self._bar.start()

    def step(self, description: str) -> None:
        """Begin the next step, called ``description``."""
        with self._lock:
            if self._description:
                self._done += 1
            self._description = description
            if self._bar is not None:
                self._bar.update(self._task, description=description, completed=self._done)

    def __exit__(self, *exc):
        with self._lock:
            timer, self._timer = self._timer, None
            if timer is not None:
                timer.cancel()
            if self._bar is not None:
                self._bar.stop()
                self._bar = None
        return False


def add_normalize(parser) -> None:
    """The ``--normalize`` option of the commands that read a photo or exemplar (fit, synth, tile, compare)."""
    parser.add_argument("--normalize", action="store_true",
                        help="map a float image's minimum..maximum to 0..1 (without it, float images "
                             "(.npy, float TIFF) outside [0, 1] are refused)")


def read_unit_image(args, path, name: str, *, max_pixels=None, check_header=None):
    """Read an image for ``args.command``, in [0, 1]: refused outside it unless ``--normalize`` rescales it.

    ``max_pixels`` and ``check_header`` are :func:`spectex.io.read_image`'s: checks from the header, before
    the image is decoded.
    """
    import numpy as np

    from spectex._validate import check_unit_range, normalize_image
    from spectex.io import read_image

    image = read_image(path, name=name, max_pixels=max_pixels, check_header=check_header)
    if not np.all(np.isfinite(image)):
        raise ValueError(f"{name} must hold finite values, got NaN or infinity")
    if getattr(args, "normalize", False):
        return normalize_image(image)
    return check_unit_range(name, image, remedy="--normalize maps its minimum..maximum to 0..1")
