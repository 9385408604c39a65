"""All-or-nothing output folders: stage beside the target, swap in at the end.

An export writes many files. They are written into a hidden temporary
folder beside the target (same file system, so the final step is a rename);
only when every file is complete is the folder moved into place. A failure
anywhere removes the staging folder and leaves the target as it was.

A target that already exists is replaced only if it is empty or was written
by an earlier export (it holds :data:`MANIFEST`) and holds nothing else than
what that export lists: an export never deletes files it did not write.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

__all__ = ["MANIFEST", "check_output_dir", "staged_dir"]

#: The file every export writes at the top of its folder (what it holds, and
#: the mark that lets a later export replace the folder).
MANIFEST = "spectex-export.json"


def check_output_dir(name: str, path) -> Path:
    """Check that ``path`` can receive an export; return it as a Path.

    Its parent must exist; ``path`` itself must not exist, or be an empty
    folder, or a folder written by an earlier export.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path, got {type(path).__name__}")
    path = Path(path)
    if not str(path) or path.name in ("", ".", ".."):
        raise ValueError(f"{name} must name a folder, got '{path}'")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"{name} is in a folder that does not exist: '{path}'")
    if path.exists() or path.is_symlink():
        if path.is_symlink() or not path.is_dir():
            raise ValueError(f"{name} exists and is not a folder: '{path}'")
        if any(path.iterdir()):
            if not (path / MANIFEST).is_file():
                raise ValueError(f"{name} '{path}' exists, is not empty and was not written by spectex export "
                                 f"(no {MANIFEST}); choose a new or empty folder")
            stray = _unlisted(path)
            if stray:
                raise ValueError(f"{name} '{path}' holds a file the earlier export did not write ('{stray}'); "
                                 "move it away or choose another folder")
    return path


def _unlisted(path: Path) -> str | None:
    """The first file under an earlier export's folder that its manifest does not list, if any."""
    import json

    try:
        manifest = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
        listed = {MANIFEST, *(name for files in manifest["formats"].values() for name in files)}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return MANIFEST  # not a manifest this module wrote
    for item in sorted(path.rglob("*")):
        if (item.is_file() or item.is_symlink()) and item.relative_to(path).as_posix() not in listed:
            return item.relative_to(path).as_posix()
    return None


@contextlib.contextmanager
def staged_dir(path):
    """Yield a fresh temporary folder beside ``path``; move it to ``path`` on success.

    On success an existing ``path`` (checked by :func:`check_output_dir`) is
    moved aside, the staged folder renamed to ``path``, and the old one
    removed. On any exception the staged folder is removed and ``path`` is
    untouched.
    """
    path = check_output_dir("output", path)
    parent = path.parent if str(path.parent) else Path(".")
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".part", dir=parent))
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes it 0700
        check_output_dir("output", path)  # again: it may have changed while we wrote
        old = None
        if path.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".old", dir=parent))
            os.replace(path, old / "previous")
        try:
            os.replace(tmp, path)
        except BaseException:
            if old is not None:
                os.replace(old / "previous", path)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
