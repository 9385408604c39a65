"""Where numba keeps compiled kernels, when the install is read-only (issue 26).

The kernels are compiled with ``cache=True``: numba writes them to the
``__pycache__`` folder beside each source file, or else to the user's cache
(``$XDG_CACHE_HOME/numba`` or ``~/.cache/numba``), and raises a
``RuntimeError`` at the kernel's definition when it can write to neither (a
read-only install run by a user without a home folder to write to). Then,
before numba is imported, :func:`fall_back` points ``NUMBA_CACHE_DIR`` at a
private temporary folder, removed at exit: kernels are compiled once per
run instead of once per install, and one warning line says so.
"""

from __future__ import annotations

import os
from pathlib import Path


def _writable(folder: Path) -> bool:
    """Whether ``folder`` could be made and written: the nearest existing ancestor decides."""
    folder = Path(folder)
    while not folder.exists():
        if folder.parent == folder:
            return False
        folder = folder.parent
    return folder.is_dir() and os.access(folder, os.W_OK | os.X_OK)


def _probe(folder: Path) -> bool:
    """Whether a file can really be written in ``folder`` (a read-only mount passes ``os.access`` for root)."""
    import tempfile

    folder = Path(folder)
    while not folder.exists():
        if folder.parent == folder:
            return False
        folder = folder.parent
    try:
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


def fall_back(package: Path) -> str | None:
    """Set ``NUMBA_CACHE_DIR`` to a temporary folder if numba could cache nowhere; return it (or None)."""
    if os.environ.get("NUMBA_CACHE_DIR") or "numba" in __import__("sys").modules:
        return None  # the user chose, or it is too late to choose
    if _writable(package) and _probe(package / "__pycache__"):
        return None
    cache_home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    user = Path(cache_home) / "numba"
    if _writable(user) and _probe(user):
        return None
    import atexit
    import shutil
    import sys
    import tempfile

    try:
        folder = tempfile.mkdtemp(prefix="spectex-numba-")
    except OSError:
        return None  # nowhere at all: numba's own error will say so
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    os.environ["NUMBA_CACHE_DIR"] = folder
    print(f"spectex: warning: neither '{package}' nor '{user}' is writable, so compiled kernels are not kept "
          "between runs (set NUMBA_CACHE_DIR to a writable folder to keep them)", file=sys.stderr)
    return folder


def compiled(kernel) -> bool | None:
    """Whether numba's disk cache holds ``kernel`` (a ``cache=True`` dispatcher) compiled for this CPU
    from its current source: False where its first call will compile it (tens of seconds for the
    shading kernels, once per install); None where that cannot be told."""
    try:
        if kernel.signatures:  # compiled or loaded in this process already
            return True
        from numba.core.registry import cpu_target

        magic = cpu_target.target_context.codegen().magic_tuple()
        index = kernel._cache._cache_file._load_index()  # {} when missing or stale
        return any(key[1] == magic for key in index)
    except Exception:  # numba's private layout moved: say nothing rather than something wrong
        return None
