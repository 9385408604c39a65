"""The wheel carries every file the package reads at run time (templates, shaders)."""

from __future__ import annotations

import glob
import os
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "spectex"


def _data_files():
    """Files under src/spectex that are not Python source or caches."""
    out = set()
    for path in PACKAGE.rglob("*"):
        if not path.is_file() or "__pycache__" in path.parts:
            continue
        if path.suffix in (".py", ".pyc", ".nbi", ".nbc"):
            continue
        out.add(path.relative_to(PACKAGE).as_posix())
    return out


def _covered(patterns):
    """The files setuptools' package-data globs select (files only, as it does)."""
    out = set()
    for pattern in patterns:
        for name in glob.glob(pattern, root_dir=PACKAGE, recursive=True):
            if os.path.isfile(PACKAGE / name):
                out.add(Path(name).as_posix())
    return out


def test_package_data_covers_every_file_read_at_run_time():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = config["tool"]["setuptools"]["package-data"]["spectex"]
    files = _data_files()
    assert any(f.startswith("export/templates/godot/") for f in files)  # the check sees sub-folders
    missing = sorted(files - _covered(patterns))
    assert not missing, f"not in the wheel (pyproject package-data): {missing}"


def test_the_coverage_check_sees_a_folder_left_out():
    # control: the pattern the project used to have misses the templates' sub-folders
    files = _data_files()
    old = ["py.typed", "**/*.glsl", "export/templates/*"]
    assert any(f.startswith("export/templates/hlsl/") for f in files - _covered(old))
