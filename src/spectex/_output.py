"""Writing outputs without ever touching an input or losing an earlier output.

Every file spectex writes goes through this module, from the command line
and from the library alike. The rules:

* An output that is the same file as an input is refused, compared by
  device and inode (:func:`os.path.samefile`), so links, hard links and
  ``../`` spellings are caught. Inputs are the paths a command names, plus,
  inside a :func:`session` (the command line runs every command in one),
  every file read through :func:`note_input` (``spectex.io.read_image`` and
  the texture file reader call it).
* An output that is a symbolic link is written through to the link's target;
  the link itself is never replaced.
* An output that is a device, pipe or socket is refused unless the format
  can stream (text can: ``spectex text -o /dev/stdout``); a stream is
  written directly, never replaced.
* The folder is checked to exist and to be writable (by creating and
  removing a probe file) when the output is planned, before the work.
* Each file is written under a temporary name in its final folder
  (``.NAME.XXXXXXXX.partSUFFIX``) and renamed over the target when complete.
* A set of files (a folder output such as ``spectex fit``'s, or a texture
  file with its tile) is staged in a hidden folder and put in place only when
  the whole set is complete; the files it replaces are kept until every new
  file is in place and restored if anything fails, so an interrupted or
  failed run leaves the earlier output exactly as it was. A new output folder
  appears only when complete (the staging folder is renamed to it).
* Inside a :func:`session`, SIGTERM (``kill``, ``timeout``) and SIGHUP raise
  :class:`Terminated`, a ``KeyboardInterrupt``, so they get the same clean-up
  as Ctrl-C. Signals are held back while a temporary name is made (so that
  the clean-up always knows it) and while a set is renamed into place (so
  that it is never left half-replaced); a signal a library swallowed still
  stops every later rename (:func:`check_interrupted`).

The main entry points: :func:`plan_output` (check a single output before the
work), :func:`atomic_path` (write one file), :func:`write_text` (text,
streams allowed), :class:`OutputSet` (several files, all or none) and
:class:`OutputFolder` (a whole folder tree, such as ``spectex export``'s,
replacing an earlier one all or none).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import stat
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

__all__ = ["OutputFolder", "OutputSet", "Target", "Terminated", "atomic_path", "check_input_file", "check_interrupted",
           "note_input",
           "plan_output", "same_file", "session", "write_text"]

#: Prefix and marker of every temporary name this module makes (tests look for them).
TEMP_MARK = ".part"

# (st_dev, st_ino) -> path, for the inputs read inside the current session
_inputs: dict[tuple[int, int], str] | None = None
_lock = threading.Lock()


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised like Ctrl-C so that every clean-up runs."""

    def __init__(self, signum: int):
        super().__init__(f"signal {signum}")
        self.signum = signum


def _raise_terminated(signum, frame):  # noqa: ARG001 - signal handler API
    raise Terminated(signum)


# The signals received in the current session (None outside one). Kept so that an interrupt
# swallowed by some library on its way up still stops every later write (check_interrupted).
_received: list[int] | None = None
_HELD = tuple(s for s in (signal.SIGINT, signal.SIGTERM, getattr(signal, "SIGHUP", None)) if s is not None)


def _session_handler(signum, frame):  # noqa: ARG001 - signal handler API
    if _received is not None:
        _received.append(signum)
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


def _quiet_unraisable(previous):
    """A ``sys.unraisablehook`` that leaves out this session's own interrupts, passing on anything else.

    A signal that arrives while C code is calling back into Python (numba's compiler storing an
    object in its cache through a ctypes callback) runs the handler there; the interrupt it raises
    cannot cross the C frames, and Python prints it with a traceback as "Exception ignored". It is
    not lost: the handler recorded it, and :func:`check_interrupted` raises it again before any write.
    """
    def hook(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt) and _received:
            return
        previous(unraisable)

    return hook


def _interrupt(signum: int) -> KeyboardInterrupt:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def check_interrupted() -> None:
    """Raise the interrupt of a signal received in this session, if any (it may have been swallowed)."""
    if _received:
        raise _interrupt(_received[0])


@contextlib.contextmanager
def session():
    """Run one command: record its inputs, and turn SIGTERM/SIGHUP into :class:`Terminated`.

    SIGINT raises ``KeyboardInterrupt`` as usual. Every signal received is
    also remembered, so that :func:`check_interrupted` (called before every
    rename) stops the writes even if a library swallowed the exception; one
    raised inside a callback from C, which Python would print as an ignored
    exception with its traceback, is left unprinted (:func:`_quiet_unraisable`).
    Any other exception that leaves the session after a signal was received
    is taken as the signal's consequence (a C extension whose import the
    handler broke raises ``ImportError: initialization failed``) and leaves as
    the signal's interrupt, chained to it. The previous handlers, hook and input record are restored on exit.
    """
    global _inputs, _received
    handlers = {}
    if threading.current_thread() is threading.main_thread():
        for sig in _HELD:
            if signal.getsignal(sig) is not signal.SIG_IGN:  # nohup, background jobs: left ignored
                handlers[sig] = signal.signal(sig, _session_handler)
    with _lock:
        saved, _inputs = _inputs, {}
        saved_received, _received = _received, []
    saved_hook = sys.unraisablehook
    if handlers:
        sys.unraisablehook = _quiet_unraisable(saved_hook)
    try:
        yield
    except Exception as exc:
        if _received:  # raised because of the signal (an import it broke): end the run as the signal
            raise _interrupt(_received[0]) from exc
        raise
    finally:
        with _lock:
            _inputs, _received = saved, saved_received
        for sig, old in handlers.items():
            signal.signal(sig, old)
        sys.unraisablehook = saved_hook


def note_input(path) -> None:
    """Record ``path`` as an input of the current session (nothing outside one)."""
    if _inputs is None:
        return
    with contextlib.suppress(OSError):
        st = os.stat(path)
        with _lock:
            if _inputs is not None:
                _inputs.setdefault((st.st_dev, st.st_ino), str(path))


def same_file(a, b) -> bool:
    """Whether ``a`` and ``b`` both exist and are the same file (device and inode)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _show(path) -> str:
    return f"'{os.fspath(path)}'"


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISFIFO(mode):
        return "a pipe"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_input_file(name: str, path) -> Path:
    """Return ``path`` if it is an existing regular file (links followed), else raise naming ``name``.

    The message says what the path is instead: missing, a folder, a device,
    a pipe (``/dev/stdin`` is one) or a socket.
    """
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        if os.path.islink(path):
            raise ValueError(f"{name} {_show(path)} is a symbolic link to a missing file") from None
        raise ValueError(f"{name} file not found: {_show(path)}") from None
    except NotADirectoryError:
        raise ValueError(f"{name} file not found: {_show(path)} (a part of the path is not a folder)") from None
    except OSError as exc:
        raise ValueError(f"{name} {_show(path)} cannot be read: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"{name} {_show(path)} is {_kind(st.st_mode)}, not a file")
    return path


def _check_not_input(name: str, dest, path, inputs) -> None:
    """Refuse ``dest`` (the real file ``path`` would write) if it is an input."""
    try:
        st = os.stat(dest)
    except OSError:
        return  # does not exist yet: it cannot be an input
    for item in inputs:
        if item is not None and same_file(dest, item):
            raise ValueError(f"{name} {_show(path)} is the input {_show(item)}; "
                             "choose another output name (spectex never writes over an input)")
    with _lock:
        seen = None if _inputs is None else _inputs.get((st.st_dev, st.st_ino))
    if seen is not None:
        raise ValueError(f"{name} {_show(path)} is the input {_show(seen)}; "
                         "choose another output name (spectex never writes over an input)")


def _short(text: str, limit: int = 64) -> str:
    """``text`` cut to at most ``limit`` bytes of UTF-8: a temporary name stays legal for a 255-byte output name."""
    data = os.fsencode(text)
    return text if len(data) <= limit else os.fsdecode(data[:limit].decode("utf-8", "ignore").encode())


def _probe_writable(name: str, folder: Path, path) -> None:
    """Create and remove a file in ``folder``: the only sure test of writability."""
    try:
        with _signals_held():  # no interrupt between making the probe and removing it
            fd, probe = tempfile.mkstemp(prefix=".spectex-probe.", suffix=TEMP_MARK, dir=folder)
            os.close(fd)
            os.unlink(probe)
    except OSError as exc:
        why = exc.strerror or str(exc)
        raise ValueError(f"{name} {_show(path)} cannot be written: its folder {_show(folder)} is not "
                         f"writable ({why})") from None


def _is_stream_path(path: str) -> bool:
    real = os.path.abspath(path)
    return real.startswith(("/dev/", "/proc/"))


@dataclass(frozen=True)
class Target:
    """A checked output.

    ``path`` as given; ``dest`` the file really written (a link's target);
    ``stream`` whether it is a device or pipe, written in place.
    """

    path: Path
    dest: Path
    stream: bool = False


def plan_output(path, *, name: str = "output", suffixes=None, inputs=(), stream: bool = False,
                probe: bool = True) -> Target:
    """Check an output before the work; return where it will be written.

    Parameters
    ----------
    path : str or Path
        The output as the user gave it.
    name : str
        How errors name it (``'output'``, ``'--out'``, ...).
    suffixes : sequence of str, optional
        Allowed suffixes (lower case, with the dot); None allows any.
    inputs : sequence of paths
        Files the command reads; the output must be none of them (nor any
        input recorded in the current :func:`session`).
    stream : bool
        Whether the format can be written to a device or pipe in place
        (text can; images cannot).
    probe : bool
        Create and remove a probe file to check that the folder is writable.

    Returns
    -------
    Target

    Raises
    ------
    ValueError
        One line naming ``name`` and the path: wrong suffix, missing or
        unwritable folder, a folder or special file where a file is wanted,
        or the same file as an input.
    """
    if path is None or os.fspath(path) == "":
        raise ValueError(f"{name} must be a file name, got an empty one")
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes and not (stream and _is_stream_path(str(path))):
        raise ValueError(f"{name} must end in one of {', '.join(suffixes)}, got {_show(path)}")
    if stream and _is_stream_path(str(path)) and os.path.exists(path):
        st = os.stat(path)
        if not stat.S_ISDIR(st.st_mode):
            _check_not_input(name, path, path, inputs)
            return Target(path, path, stream=True)
    # Write through symbolic links to their target; never replace the link.
    dest = Path(os.path.realpath(path)) if os.path.islink(path) else path
    try:
        st = os.stat(dest)
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise ValueError(f"{name} {_show(path)} cannot be written: {exc.strerror or exc}") from None
    if st is not None and not stat.S_ISREG(st.st_mode):
        if stat.S_ISDIR(st.st_mode):
            raise ValueError(f"{name} {_show(path)} is a folder; give a file name")
        if stream:
            _check_not_input(name, dest, path, inputs)
            return Target(path, dest, stream=True)
        raise ValueError(f"{name} {_show(path)} is {_kind(st.st_mode)}; this format can only be "
                         "written to a file")
    folder = dest.parent if str(dest.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"{name} is in a folder that does not exist: {_show(path)}")
    _check_not_input(name, dest, path, inputs)
    if probe:
        _probe_writable(name, folder, path)
    return Target(path, dest)


def _umask() -> int:
    with _lock:
        mask = os.umask(0)
        os.umask(mask)
    return mask


def _deliver(signum: int, handler) -> None:
    """Act on a signal that was held back, as ``handler`` would have."""
    if callable(handler):
        handler(signum, None)
    elif handler == signal.SIG_DFL:
        signal.raise_signal(signum)


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT/SIGTERM/SIGHUP back while a few file operations run (main thread only).

    The Python handlers are swapped for one that only notes the signal; the
    first signal noted is acted on at the end, with the handler it would have
    met. (Blocking the signals with ``pthread_sigmask`` is not enough: the
    kernel then hands them to another thread, such as a renderer's, and
    Python still raises in the main thread.)
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending = []

    def note(signum, frame):  # noqa: ARG001 - signal handler API
        pending.append(signum)

    old = {sig: signal.signal(sig, note) for sig in _HELD if signal.getsignal(sig) is not signal.SIG_IGN}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        if pending:
            _deliver(pending[0], old[pending[0]])


@contextlib.contextmanager
def atomic_path(path, *, name: str = "output", inputs=()):
    """Yield a temporary path beside the output; rename it over the output on success.

    The output is checked first (:func:`plan_output`, without a suffix
    check): a symbolic link is written through to its target, a device or
    folder is refused, and so is an input. The temporary name keeps the
    output's suffix last (writers such as imageio choose the format by it).
    On any exception, Ctrl-C and SIGTERM included, the temporary file is
    removed and the output is left as it was.
    """
    target = plan_output(path, name=name, inputs=inputs, probe=False)
    dest = target.dest
    folder = dest.parent if str(dest.parent) else Path(".")
    tmp = None
    try:
        try:
            with _signals_held():  # the clean-up below knows the name as soon as the file exists
                fd, tmp = tempfile.mkstemp(prefix=f".{_short(dest.stem)}.", suffix=TEMP_MARK + _short(dest.suffix),
                                           dir=folder)
                os.close(fd)
        except OSError as exc:
            raise ValueError(f"{name} {_show(path)} cannot be written: its folder {_show(folder)} is not "
                             f"writable ({exc.strerror or exc})") from None
        yield Path(tmp)
        # mkstemp makes the file 0600; give it the usual permissions.
        os.chmod(tmp, 0o666 & ~_umask())
        _check_not_input(name, dest, path, inputs)  # again: an input may have appeared meanwhile
        check_interrupted()
        os.replace(tmp, dest)
    except OSError as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        # name the output, not the hidden temporary file
        raise ValueError(f"{name} {_show(path)} could not be written: {exc.strerror or exc}") from None
    except BaseException:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise


def write_text(path, text: str, *, name: str = "output", inputs=()) -> Target:
    """Write ``text`` (UTF-8) to ``path``: atomically to a file, in place to a device or pipe."""
    target = plan_output(path, name=name, inputs=inputs, stream=True, probe=False)
    if target.stream:
        # Appending: /dev/stdout redirected to a file must not truncate what is already there.
        try:
            with open(target.dest, "a", encoding="utf-8") as fh:
                fh.write(text)
        except OSError as exc:
            raise ValueError(f"{name} {_show(path)} could not be written: {exc.strerror or exc}") from None
        return target
    with atomic_path(path, name=name, inputs=inputs) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return target



def _make_stage(where: Path, prefix: str, name: str, path) -> Path:
    """A new temporary folder in ``where`` (named ``prefix...TEMP_MARK``) to stage outputs in.

    No signal comes between making it and returning it (a signal held back
    is delivered after it is removed again); an OS error is the one-line
    ``ValueError`` naming the output ``name`` and ``path``.
    """
    stage = None
    try:
        with _signals_held():  # no interrupt between making the stage and remembering it
            stage = Path(tempfile.mkdtemp(prefix=_short(prefix), suffix=TEMP_MARK, dir=where))
    except OSError as exc:
        raise ValueError(f"{name} {_show(path)} cannot be written: {exc.strerror or exc}") from None
    except BaseException:  # a signal held back above, delivered as they are let through again
        if stage is not None:
            shutil.rmtree(stage, ignore_errors=True)
        raise
    return stage

class OutputSet:
    """Several output files in one folder, put in place all together or not at all.

    Create it before the work (it checks every file and the folder), then
    write the files into :attr:`stage` inside ``with``::

        outputs = OutputSet("result", ["a.png", "b.toml"], inputs=[photo])
        ...  # the work
        with outputs as stage:
            write_image(stage / "a.png", ...)
            ...

    On a clean exit from ``with``, the files replace the earlier ones in the
    folder (which is made if missing and ``create`` is true); other files in
    the folder are left alone. On any exception, Ctrl-C and SIGTERM included,
    nothing in the folder changes and a folder that did not exist is not made.

    Parameters
    ----------
    folder : str or Path
        The output folder. A symbolic link to a folder is followed.
    names : sequence of str
        The plain file names to be written (no folders).
    name : str
        How errors name the output (``'output'``, ``'--out'``).
    inputs : sequence of paths
        Files the command reads; none of the outputs may be one of them.
    create : bool
        Make the folder if it is missing (otherwise a missing folder is an error).
    """

    def __init__(self, folder, names, *, name: str = "output", inputs=(), create: bool = True):
        folder = Path(folder)
        if os.fspath(folder) == "":
            folder = Path(".")
        self.path = folder
        self.names = tuple(names)
        self.name = name
        self.inputs = tuple(inputs)
        for n in self.names:
            if not n or Path(n).name != n or n in (".", ".."):
                raise ValueError(f"output file names must be plain names, got {n!r}")
        if len(set(self.names)) != len(self.names):
            raise ValueError(f"output file names must differ, got {list(self.names)}")
        if os.path.lexists(folder) and not os.path.isdir(folder):
            raise ValueError(f"{name} must be a folder, got the file {_show(folder)}")
        self.folder = Path(os.path.realpath(folder)) if os.path.islink(folder) else folder
        self.exists = self.folder.is_dir()
        if not self.exists:
            if not create:
                raise ValueError(f"{name} is in a folder that does not exist: {_show(folder)}")
            parent = self.folder.parent if str(self.folder.parent) else Path(".")
            if not parent.is_dir():
                raise ValueError(f"{name} {_show(folder)} cannot be made: its parent folder {_show(parent)} "
                                 "does not exist")
            _probe_writable(name, parent, folder)
        else:
            for n in self.names:
                self._check_member(n)
            _probe_writable(name, self.folder, folder)
        self.stage = None

    def _check_member(self, n: str) -> None:
        member = self.folder / n
        shown = self.path / n
        if os.path.islink(member):
            raise ValueError(f"{self.name} {_show(shown)} is a symbolic link; spectex replaces files in an "
                             "output folder and will not replace a link: remove it or choose another folder")
        if os.path.lexists(member):
            mode = os.stat(member).st_mode
            if not stat.S_ISREG(mode):
                raise ValueError(f"{self.name} {_show(shown)} is {_kind(mode)}; it cannot be replaced by a file")
        _check_not_input(self.name, member, shown, self.inputs)

    def __enter__(self) -> Path:
        if self.exists:
            where, prefix = self.folder, ".spectex-stage."
        else:
            where = self.folder.parent if str(self.folder.parent) else Path(".")
            prefix = f".{self.folder.name}."
        self.stage = _make_stage(where, prefix, self.name, self.path)
        return self.stage

    def __exit__(self, exc_type, exc, tb):
        stage, self.stage = self.stage, None
        if exc_type is not None:
            shutil.rmtree(stage, ignore_errors=True)
            _raise_named(self.name, self.path, stage, exc, "the earlier files are as they were")
            return False
        try:
            self._commit(stage)
        except OSError as exc:
            raise ValueError(f"{self.name} {_show(self.path)} could not be written: {exc.strerror or exc}; "
                             "the earlier files are as they were") from None
        finally:
            if stage.exists():
                shutil.rmtree(stage, ignore_errors=True)
        return False

    def _commit(self, stage: Path) -> None:
        check_interrupted()
        staged = {p.name for p in stage.iterdir()}
        missing = [n for n in self.names if n not in staged]
        extra = sorted(staged - set(self.names))
        if missing or extra:
            raise ValueError(f"{self.name}: the files written ({sorted(staged)}) are not the files "
                             f"planned ({list(self.names)})")
        for n in self.names:
            with contextlib.suppress(OSError):
                os.chmod(stage / n, 0o666 & ~_umask())
        if not self.exists:
            with _signals_held():
                if os.path.lexists(self.folder):
                    raise ValueError(f"{self.name} {_show(self.path)} appeared while spectex was working; "
                                     "nothing was written")
                os.chmod(stage, 0o777 & ~_umask())
                os.rename(stage, self.folder)
            return
        for n in self.names:  # again: the folder may have changed during the work
            self._check_member(n)
        backup = stage / ".spectex-backup"
        backup.mkdir()
        saved, placed = [], []
        with _signals_held():
            try:
                for n in self.names:
                    if os.path.lexists(self.folder / n):
                        os.replace(self.folder / n, backup / n)
                        saved.append(n)
                for n in self.names:
                    os.replace(stage / n, self.folder / n)
                    placed.append(n)
            except BaseException:
                for n in placed:
                    with contextlib.suppress(OSError):
                        os.unlink(self.folder / n)
                for n in saved:
                    with contextlib.suppress(OSError):
                        os.replace(backup / n, self.folder / n)
                raise


def savefig(fig, path, **kwargs) -> None:
    """``fig.savefig(path)``, whose failure to write is the ``OSError`` itself.

    Matplotlib's PDF writer, on a full disk, raises an ``AttributeError``
    from its own clean-up while handling the ``OSError``; the ``OSError`` is
    what happened, so it is raised instead (and named by the caller).
    """
    try:
        fig.savefig(path, **kwargs)
    except OSError:
        raise
    except Exception as exc:
        cause = exc
        while cause is not None and not isinstance(cause, OSError):
            cause = cause.__context__
        if cause is None:
            raise
        raise cause from None


def _raise_named(name, path, stage, exc, after) -> None:
    """Turn a write into ``stage`` that failed (a full disk: no file name, or one in the stage) into one line.

    A ``ValueError`` that names a file in the stage (a nested writer's) is
    raised again naming it where it was going, not the hidden stage.
    """
    if isinstance(exc, ValueError) and os.fspath(stage) in str(exc):
        raise ValueError(str(exc).replace(os.fspath(stage), os.fspath(path))) from None
    if not isinstance(exc, OSError) or isinstance(exc, (BrokenPipeError, InterruptedError)):
        return
    if exc.filename is not None and not os.fspath(exc.filename).startswith(os.fspath(stage)):
        return  # an input or another path: its own message names it
    message = f"{name} {_show(path)} could not be written: {exc.strerror or exc}; {after}"
    raise (OSError(message) if exc.errno is None else OSError(exc.errno, message)) from None


class OutputFolder:
    """A whole folder written as one output: staged beside it, then swapped in.

    For outputs that are a tree of files decided while writing (``spectex
    export``). Check it before the work (the constructor), then write
    anything into the stage inside ``with``::

        out = OutputFolder("ground-export", replaceable=check)
        with out as stage:
            (stage / "index.html").write_text(...)

    On a clean exit the stage is renamed to the folder; an existing folder is
    first moved aside, restored if the rename fails, and removed only once
    the new one is in place. On any exception, Ctrl-C and SIGTERM included,
    the stage is removed and the folder is as it was.

    Parameters
    ----------
    folder : str or Path
        The output folder. Its parent must exist.
    name : str
        How errors name the output.
    inputs : sequence of paths
        Files the command reads: the folder must not be one of them nor hold
        one (replacing it would delete it), nor hold a file read in the
        current :func:`session`.
    replaceable : callable, optional
        ``replaceable(path)`` for an existing, non-empty folder: raises
        ``ValueError`` if it must not be replaced (without it, only an empty
        folder may be). Called again just before the swap.
    """

    def __init__(self, folder, *, name: str = "output", inputs=(), replaceable=None):
        if not isinstance(folder, (str, os.PathLike)):
            raise TypeError(f"{name} must be a path, got {type(folder).__name__}")
        path = Path(folder)
        if not os.fspath(folder) or path.name in ("", ".", ".."):
            raise ValueError(f"{name} must name a folder, got {_show(folder)}")
        self.path = path
        self.name = name
        self.inputs = tuple(inputs)
        self.replaceable = replaceable
        self.parent = path.parent if str(path.parent) else Path(".")
        if not self.parent.is_dir():
            raise ValueError(f"{name} is in a folder that does not exist: {_show(path)}")
        self.check()
        _probe_writable(name, self.parent, path)
        self.stage = None

    def check(self) -> None:
        """Raise ``ValueError`` if the folder cannot (or can no longer) be written or replaced."""
        path, name = self.path, self.name
        if not os.path.lexists(path):
            return
        if os.path.islink(path) or not path.is_dir():
            _check_not_input(name, path, path, self.inputs)
            raise ValueError(f"{name} exists and is not a folder: {_show(path)}")
        if any(path.iterdir()):
            if self.replaceable is None:
                raise ValueError(f"{name} {_show(path)} exists and is not empty; choose a new or empty folder")
            self.replaceable(path)
        for item in path.rglob("*"):  # replacing the folder deletes what is in it
            if item.is_file():
                try:
                    _check_not_input(name, item, item, self.inputs)
                except ValueError:
                    raise ValueError(f"{name} {_show(path)} holds the input {_show(item)}, which replacing the "
                                     "folder would delete; choose another output folder") from None

    def __enter__(self) -> Path:
        self.stage = _make_stage(self.parent, f".{self.path.name}.", self.name, self.path)
        return self.stage

    def __exit__(self, exc_type, exc, tb):
        stage, self.stage = self.stage, None
        try:
            if exc_type is not None:
                _raise_named(self.name, self.path, stage, exc, "the earlier folder is as it was")
                return False
        finally:
            if exc_type is not None and os.path.lexists(stage):
                shutil.rmtree(stage, ignore_errors=True)
        try:
            self._commit(stage)
        except OSError as exc:
            raise ValueError(f"{self.name} {_show(self.path)} could not be written: {exc.strerror or exc}; "
                             "the earlier folder is as it was") from None
        finally:
            if os.path.lexists(stage):
                shutil.rmtree(stage, ignore_errors=True)
        return False

    def _commit(self, stage: Path) -> None:
        os.chmod(stage, 0o777 & ~_umask())  # mkdtemp makes it 0700
        self.check()  # again: the folder may have changed during the work
        check_interrupted()
        old = None
        with _signals_held():  # never left half-swapped
            if os.path.lexists(self.path):
                old = Path(tempfile.mkdtemp(prefix=f".{_short(self.path.name)}.", suffix=".old" + TEMP_MARK,
                                            dir=self.parent))
                os.replace(self.path, old / "previous")
            try:
                os.replace(stage, self.path)
            except BaseException:
                if old is not None:
                    os.replace(old / "previous", self.path)
                    shutil.rmtree(old, ignore_errors=True)
                raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
