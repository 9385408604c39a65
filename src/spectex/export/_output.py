"""Export folders: what an earlier export may be replaced by a new one.

The mechanics (staging beside the target, the swap, clean-up on failure and
on Ctrl-C or SIGTERM, refusing a folder that holds an input) are the
project's one implementation, :class:`spectex._output.OutputFolder`. This
module adds the export's rule: a target that already exists is replaced
only if it is empty or was written by an earlier export (it holds
:data:`MANIFEST`) and holds nothing else than what that export lists, so
that an export never deletes files it did not write.
"""

from __future__ import annotations

import json
from pathlib import Path

from spectex._output import OutputFolder

__all__ = ["MANIFEST", "check_output_dir", "output_folder", "staged_dir"]

#: The file every export writes at the top of its folder (what it holds, and
#: the mark that lets a later export replace the folder).
MANIFEST = "spectex-export.json"


def _replaceable(path: Path) -> None:
    """Raise unless ``path`` (an existing, non-empty folder) is an earlier export and nothing more."""
    if not (path / MANIFEST).is_file():
        raise ValueError(f"output '{path}' exists, is not empty and was not written by spectex export "
                         f"(no {MANIFEST}); choose a new or empty folder")
    stray = _unlisted(path)
    if stray:
        raise ValueError(f"output '{path}' holds a file the earlier export did not write ('{stray}'); "
                         "move it away or choose another folder")


def _unlisted(path: Path) -> str | None:
    """The first file under an earlier export's folder that its manifest does not list, if any."""
    try:
        manifest = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
        listed = {MANIFEST, *(name for files in manifest["formats"].values() for name in files)}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return MANIFEST  # not a manifest this module wrote
    for item in sorted(path.rglob("*")):
        if (item.is_file() or item.is_symlink()) and item.relative_to(path).as_posix() not in listed:
            return item.relative_to(path).as_posix()
    return None


def output_folder(path, *, name: str = "output", inputs=()) -> OutputFolder:
    """The :class:`~spectex._output.OutputFolder` of an export to ``path`` (checked now)."""
    return OutputFolder(path, name=name, inputs=inputs, replaceable=_replaceable)


def check_output_dir(name: str, path, *, inputs=()) -> Path:
    """Check that ``path`` can receive an export; return it as a Path.

    Its parent must exist; ``path`` itself must not exist, or be an empty
    folder, or a folder written by an earlier export; it must hold no input.
    """
    return output_folder(path, name=name, inputs=inputs).path


def staged_dir(path, *, inputs=()) -> OutputFolder:
    """A context manager: a fresh folder beside ``path`` to write into, swapped in on success."""
    return output_folder(path, inputs=inputs)
