"""Follow ``spectex render``'s camera through the code: the modules a GL render passes through.

Runs the command's work in-process (``spectex.cli.main`` with a texture file, a
camera and an output) under ``sys.setprofile`` and records every call into a
spectex module (``spectex.*``, numba's compiled kernels excepted: they are not
Python frames). Consecutive calls within one module are one visit. Printed:

* ``rooms``: the distinct modules visited;
* ``visits``: the visits in order (a walk through the rooms);
* ``returns``: visits to a module already visited before (coming back);
* ``climbs``: calls from a module into one that imports it (a call against the
  direction of the imports: the callee sits above the caller).

The command line's own modules (``spectex.cli.*``) and the leaf utilities every
module calls (argument checks ``_validate`` and ``_numbers``, file handling
``io`` and ``_output``, ``shading.constants``) are left out: the walk is the
camera's, from the texture file to the frame.

Run from the repository root::

    python benchmarks/trace_render.py [--cpu] [--src OTHER_CHECKOUT/src]
"""

from __future__ import annotations

import argparse
import ast
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))


SKIP = {"spectex._validate", "spectex._numbers", "spectex.io", "spectex._output", "spectex.shading.constants"}


def _imports(module: str) -> set[str]:
    """The spectex modules ``module`` imports (anywhere in the file), resolved to module names."""
    parts = module.split(".")
    path = ROOT / "src" / Path(*parts)
    file = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
    if not file.exists():
        return set()
    package = parts if file.name == "__init__.py" else parts[:-1]
    found = set()
    for node in ast.walk(ast.parse(file.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            name = ".".join(base + (node.module.split(".") if node.module else []))
            if name.startswith("spectex"):
                found.add(name)
                found.update(f"{name}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("spectex"))
    return found


def main(argv=None):
    global ROOT
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cpu", action="store_true", help="the CPU renderer instead of OpenGL")
    parser.add_argument("--src", default=str(ROOT / "src"), help="the spectex sources to follow (another checkout's)")
    args = parser.parse_args(argv)
    ROOT = Path(args.src).resolve().parent
    sys.path.insert(0, str(ROOT / "src"))

    from spectex.cli import main as cli
    from spectex.texture import SpectralTexture
    from spectex.tiles import make_tile

    with tempfile.TemporaryDirectory() as tmp:
        texture = SpectralTexture.paper_preset(make_tile(64, rng=0), tile_size=64)
        texture.save(Path(tmp) / "t.toml")
        argv = ["render", str(Path(tmp) / "t.toml"), "--camera", "0,0,3,30,-20", "--size", "64x48",
                "-o", str(Path(tmp) / "v.png"), "--backend", "cpu" if args.cpu else "gl"]
        cli(argv)  # once, so that imports and compilation are not followed
        visits = []

        def profile(frame, event, arg):
            if event != "call":
                return
            name = frame.f_globals.get("__name__", "")
            if (name.startswith("spectex") and not name.startswith("spectex.cli") and name not in SKIP
                    and (not visits or visits[-1] != name)):
                visits.append(name)

        sys.setprofile(profile)
        try:
            cli(argv)
        finally:
            sys.setprofile(None)
    seen, returns, climbs = set(), 0, 0
    imports = {}
    for k, name in enumerate(visits):
        if name in seen:
            returns += 1
        seen.add(name)
        if k:
            caller = visits[k - 1]
            callee_imports = imports.setdefault(name, _imports(name))
            if caller in callee_imports:
                climbs += 1
    print(f"rooms {len(seen)}, visits {len(visits)}, returns {returns}, climbs {climbs}")
    print(" -> ".join(v.removeprefix("spectex.") for v in visits))


if __name__ == "__main__":
    main()
