"""The first run after an install, against the next run: what numba's compile costs a user, in one run.

Each command runs in a subprocess twice with ``NUMBA_CACHE_DIR`` pointing at a new, empty folder:
*cold* (numba compiles every kernel the command calls, as on a fresh install) and then *warm* (the
same folder: every kernel loaded from disk). Printed per command: wall seconds and peak memory
(the subprocess's maximum resident set) of both, and the ratio cold / warm.

``--against COMMIT`` runs the same commands on another commit too (a temporary ``git worktree``,
its ``src`` on ``PYTHONPATH``), one after the other in this run, and prints each cold run's ratio
to it: e.g. ``--against e7ee4b1``, the shading steps still inlined by numba's IR inliner (2026-11-27:
``docs/rendering.md``, "Without OpenGL").

The commands: ``spectex fit`` of a 512-pixel gravel photo (scikit-image's), and ``spectex demo
--backend cpu`` (the demo without OpenGL). Run from the repository root::

    python benchmarks/bench_first_run.py [--against COMMIT] [--only fit,demo]

The cold runs take minutes on a 2-core machine before the change: nothing else should run.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _machine import cpu_name

ROOT = Path(__file__).resolve().parents[1]


def _run(argv, env, cwd) -> tuple[float, float]:
    """Wall seconds and peak resident memory (MB) of one subprocess."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(map(str, argv))} failed: {proc.stderr.read().decode()[-400:]}")
    proc.stderr.close()
    return seconds, usage.ru_maxrss / 1024.0


def _commands(folder: Path) -> dict:
    import numpy as np
    import skimage.data
    from PIL import Image

    photo = folder / "gravel.png"
    Image.fromarray(np.asarray(skimage.data.gravel())).save(photo)
    py = sys.executable
    return {"fit": [py, "-m", "spectex", "fit", str(photo), "-o", str(folder / "fit")],
            "demo": [py, "-m", "spectex", "demo", "--backend", "cpu", "-o", str(folder / "demo")]}


def _measure(src: Path, commands: dict, folder: Path) -> dict:
    out = {}
    for name, argv in commands.items():
        cache = Path(tempfile.mkdtemp(prefix="numba-", dir=folder))
        env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
        out[name] = (_run(argv, env, folder), _run(argv, env, folder))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", help="another commit to run the same commands on (a git worktree)")
    parser.add_argument("--only", default="fit,demo", help="commands, comma-separated (fit, demo)")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="spectex-first-run-") as tmp:
        folder = Path(tmp)
        commands = {k: v for k, v in _commands(folder).items() if k in args.only.split(",")}
        results = {"this checkout": _measure(ROOT / "src", commands, folder)}
        if args.against:
            tree = folder / "against"
            subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-f", "--detach", str(tree), args.against],
                           check=True, capture_output=True)
            try:
                results[args.against] = _measure(tree / "src", commands, folder)
            finally:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)],
                               check=True, capture_output=True)
    print(f"{cpu_name()}, {os.cpu_count()} CPUs, load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    print("| code | command | cold s | cold MB | warm s | warm MB | cold / warm |")
    print("|---|---|---|---|---|---|---|")
    for code, rows in results.items():
        for name, ((cs, cm), (ws, wm)) in rows.items():
            print(f"| {code} | {name} | {cs:.1f} | {cm:.0f} | {ws:.1f} | {wm:.0f} | {cs / ws:.1f} |")
    if args.against:
        for name in commands:
            here, there = results["this checkout"][name][0][0], results[args.against][name][0][0]
            print(f"{name}: the cold run {there / here:.1f} times faster than {args.against}'s "
                  f"({there:.1f} -> {here:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
