"""The test suite's cold run on a clean clone: wall and CPU time, the compile share, the costliest files.

Clones this checkout's HEAD into a temporary folder (no numba cache, no
``__pycache__``: what CI starts from), runs the pytest part of the README's
test command there (``python3 -m pytest -n 2 --dist loadfile``, with
``PYTHONPATH`` pointing at the clone's ``src``; the install step is left
out, so spectex's dependencies must already be installed), and prints:

* the wall time, and the CPU time of the whole run (user + system of pytest,
  its workers and every process they waited for, from ``getrusage``);
* CPU / cores: the shortest wall time the run could take on that many idle
  cores. On a shared machine the wall time follows the other jobs; the
  CPU time much less (it still grows a little with the load: caches, page
  faults), so the load averages before and after are printed too;
* numba's compile time (``SPECTEX_TEST_COMPILE_LOG``, ``tests/conftest.py``),
  per kernel, and its share of the CPU time (compiles inside the tests'
  subprocesses are not in it);
* the CPU time per test file and the costliest tests (``SPECTEX_TEST_CPU_LOG``:
  the worker's own CPU time plus its waited-for subprocesses', per test).

``tests/js/node_modules`` (the engine tests' npm packages, ``npm ci`` in
``.ci/run``) is linked into the clone from this checkout when it is here.
``SPECTEX_BPY_PYTHON`` is passed on as it is; where it is not set and this
checkout has the ``.venv-bpy`` that ``.ci/run`` makes, its Python is used (else
Blender's tests fail, as in CI without it). ``CI=true``, so a test that
cannot run fails instead of skipping.

Run: ``python benchmarks/bench_tests.py [--workers N] [--keep] [-- PYTEST ARGS]``
(one cold run takes all the cores for several minutes: run one at a time).
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

try:
    from _machine import cpu_name
except ImportError:  # run as a module from elsewhere
    from benchmarks._machine import cpu_name

ROOT = Path(__file__).resolve().parent.parent


def readme_pytest(root: Path, workers: int) -> list[str]:
    """The pytest part of the README's test command, with ``-n`` set to ``workers``."""
    text = (root / "README.md").read_text(encoding="utf-8")
    match = re.search(r"<!-- test-command -->\n```bash\n(.*?)\n```", text, flags=re.DOTALL)
    if not match:
        raise SystemExit("bench_tests: no test command in README.md")
    command = match.group(1).split("&&")[-1].split()
    if command[:3] != ["python3", "-m", "pytest"]:
        raise SystemExit(f"bench_tests: the README's test command does not end with pytest: {match.group(1)}")
    if "-n" in command:
        command[command.index("-n") + 1] = str(workers)
    return [sys.executable, *command[1:]]


def children_cpu() -> tuple[float, float]:
    """User and system CPU seconds of the waited-for child processes so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime, usage.ru_stime


def read_tsv(path: Path) -> list[list[str]]:
    if not path.exists():
        return []
    return [line.rstrip("\n").split("\t") for line in path.read_text(encoding="utf-8").splitlines() if line]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2, help="pytest-xdist workers (the README's -n); default 2")
    parser.add_argument("--keep", action="store_true", help="keep the clone and the logs (printed)")
    parser.add_argument("--top", type=int, default=15, help="how many files and tests to list; default 15")
    parser.add_argument("pytest_args", nargs="*", help="more pytest arguments, after --")
    args = parser.parse_args(argv)

    folder = Path(tempfile.mkdtemp(prefix="spectex-cold-"))
    clone = folder / "clone"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    head = subprocess.run(["git", "-C", str(clone), "log", "-1", "--format=%h %s"], capture_output=True, text=True,
                          check=True).stdout.strip()
    modules = ROOT / "tests" / "js" / "node_modules"
    if modules.is_dir():
        (clone / "tests" / "js" / "node_modules").symlink_to(modules.resolve())
    compile_log, cpu_log = folder / "compile.log", folder / "cpu.log"
    env = dict(os.environ, PYTHONPATH=str(clone / "src"), CI="true", SPECTEX_TEST_COMPILE_LOG=str(compile_log),
               SPECTEX_TEST_CPU_LOG=str(cpu_log))
    env.pop("NUMBA_CACHE_DIR", None)  # numba's cache beside the clone's sources: empty
    bpy = ROOT / ".venv-bpy" / "bin" / "python"  # made by .ci/run
    if "SPECTEX_BPY_PYTHON" not in env and bpy.is_file():
        env["SPECTEX_BPY_PYTHON"] = str(bpy)
    command = readme_pytest(clone, args.workers) + ["-q", *args.pytest_args]
    print(f"bench_tests: {head}\n  {' '.join(command[1:])} in {clone}", flush=True)
    load_before = os.getloadavg()
    cpu0, wall0 = children_cpu(), time.perf_counter()
    run = subprocess.run(command, cwd=clone, env=env, capture_output=True, text=True, check=False)
    wall, cpu1 = time.perf_counter() - wall0, children_cpu()
    user, system = cpu1[0] - cpu0[0], cpu1[1] - cpu0[1]
    cpu = user + system
    load_after = os.getloadavg()
    summary = [line for line in run.stdout.splitlines() if re.search(r"\d+ (passed|failed|error)", line)]

    compiles = read_tsv(compile_log)
    per_kernel: dict = collections.defaultdict(lambda: [0, 0.0])
    for row in compiles:
        per_kernel[row[3]][0] += 1
        per_kernel[row[3]][1] += float(row[2])
    compile_cpu = sum(cpu for _, cpu in per_kernel.values())
    tests = read_tsv(cpu_log)
    per_file: dict = collections.defaultdict(float)
    for row in tests:
        per_file[row[4].split("::")[0]] += float(row[1]) + float(row[2])

    print(f"CPU: {cpu_name()}, {os.cpu_count()} cores; load average {load_before[0]:.1f} before, "
          f"{load_after[0]:.1f} after")
    print(f"result: {summary[-1] if summary else run.stdout[-500:]} (exit status {run.returncode})")
    print(f"wall {wall:.0f} s ({wall / 60:.1f} min); CPU {cpu:.0f} s, / {args.workers} = {cpu / args.workers:.0f} s "
          f"({cpu / args.workers / 60:.1f} min) on {args.workers} idle cores; {user:.0f} s user, {system:.0f} s system")
    print(f"numba compiling in the workers: {compile_cpu:.0f} CPU s ({100 * compile_cpu / max(cpu, 1e-9):.0f} %), "
          f"{len(compiles)} compilations of {len(per_kernel)} kernels")
    for name, (n, seconds) in sorted(per_kernel.items(), key=lambda kv: -kv[1][1])[:args.top]:
        print(f"  {seconds:7.1f} s  {n} x {name}")
    print(f"CPU per test file (the worker's and its subprocesses'; {sum(per_file.values()):.0f} s in tests):")
    for name, seconds in sorted(per_file.items(), key=lambda kv: -kv[1])[:args.top]:
        print(f"  {seconds:7.1f} s  {name}")
    print("costliest tests:")
    for row in sorted(tests, key=lambda r: -(float(r[1]) + float(r[2])))[:args.top]:
        print(f"  {float(row[1]) + float(row[2]):7.1f} s  {row[4]}")
    if run.returncode != 0:
        print(run.stdout[-3000:], run.stderr[-2000:], sep="\n")
    if args.keep:
        print(f"kept: {folder}")
    else:
        shutil.rmtree(folder, ignore_errors=True)
    return run.returncode


if __name__ == "__main__":
    sys.exit(main())
