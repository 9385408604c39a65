"""Export folders: what an earlier export may be replaced by a new one.

The mechanics (staging beside the target, the swap, clean-up on failure and
on Ctrl-C or SIGTERM, refusing a folder that holds an input) are the
project's one implementation, :class:`spectex._output.OutputFolder`. This
module adds the export's rule: a target that already exists is replaced
only if it is empty or was written by an earlier export (it holds
:data:`MANIFEST`) and holds nothing else than what that export wrote:
every file is listed in the manifest with its SHA-256 and still has it,
every folder holds such a file, and there are no links. So an export never
deletes a file or folder it did not make, even one a user added to a
hand-edited manifest (its hash would have to match a file the user did not
change, which an export may replace by its own).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from spectex._output import OutputFolder

__all__ = ["MANIFEST", "check_output_dir", "file_hashes", "output_folder", "staged_dir"]

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
        raise ValueError(f"output '{path}' holds '{stray}', which the earlier export did not write (or which "
                         "changed since, by its SHA-256); move it away or choose another folder")


def file_hashes(folder: Path) -> dict[str, str]:
    """SHA-256 of every file under ``folder`` (relative POSIX path -> hex digest), the manifest excepted."""
    out = {}
    for item in sorted(Path(folder).rglob("*")):
        rel = item.relative_to(folder).as_posix()
        if item.is_file() and not item.is_symlink() and rel != MANIFEST:
            out[rel] = _sha256(item)
    return out


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _unlisted(path: Path) -> str | None:
    """The first item under an earlier export's folder that it did not write as it is now, if any.

    A file must be listed in the manifest's ``sha256`` table and still have
    that hash; a folder must hold such a file; a link is never ours.
    """
    try:
        manifest = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
        hashes = manifest["sha256"]
        if not isinstance(hashes, dict) or not all(isinstance(v, str) for v in hashes.values()):
            return MANIFEST
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return MANIFEST  # not a manifest this module wrote (or one from before hashes were kept)
    ours = set()
    for rel in hashes:
        parts = Path(rel).parts
        ours.update(Path(*parts[:k]).as_posix() for k in range(1, len(parts)))
    for root, dirs, files in os.walk(path):
        for name in sorted(dirs) + sorted(files):
            item = Path(root) / name
            rel = item.relative_to(path).as_posix()
            if item.is_symlink():
                return rel
            if name in dirs:
                if rel not in ours:
                    return rel + "/"
            elif rel != MANIFEST and (rel not in hashes or _sha256(item) != hashes[rel]):
                return rel
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
