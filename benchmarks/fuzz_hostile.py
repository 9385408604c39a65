"""A hostile trial of the command line: many bad inputs across every command (issue 26).

Not a test (it takes minutes and its cases are generated, not chosen): a
tool that finds what the table-driven ``tests/test_hostile.py`` should
learn. Every case runs ``python -m spectex ...`` in a fresh folder of
hostile inputs and is judged *answered well* when

* it exits 0, or 2 with exactly one line on standard error;
* no traceback is printed;
* a refusal (exit 2) comes within 5 s and 1 GB of peak memory;
* nothing runs past 120 s (numba's kernels are compiled by a warm-up first, as
  for a user's second run; ``--cold`` leaves that out);
* every file that was there before is byte-identical afterwards (except the
  file ``-o`` names, or the file a link there points to, when the run succeeds
  and it is none of the run's inputs: the user asked for it to be replaced);
* a value no option may take (``٣``, ``1_000``, ``nan``, ``1e999``, ...) is refused, not run with.

Run::

    PYTHONPATH=src python benchmarks/fuzz_hostile.py [--workers 2] [--start K] [--limit N] [--log fuzz.tsv]

It prints every case that was not answered well as it comes, then a summary:
the cases, the share answered well, tracebacks, unbounded runs (a timeout, a
refusal after 5 s, a peak over 1 GB), inputs lost or changed, and the time to
refusal (the maximum and the 95th percentile) and peak memory. The log gets
one line per case as soon as it is done (appended), so that a long trial can
run in chunks (``--start 0 --limit 300``, then ``--start 300 ...``) into one
log, and ``--summary LOG`` prints the summary of a log (the last line of each
case index counts, so that a case run again after a fix replaces its first
result).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import itertools
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

CAMERA = ("--camera", "0,0,2,0,-10")
#: Seconds a case may run before it is killed and counted as unbounded.
TIMEOUT = 120
BAD_INTS = ("0", "-1", "-99999999999999999999", "99999999999999999999", "1e3", "nan", "abc", "", "0x10", "٣",
            # digits that Python's int() takes but a command line should not: full-width, Devanagari,
            # underscores, spaces, a sign, a float spelling, a 5000-digit number, negative zero
            "３", "१", "1_000", " 3 ", "+3", "3.0", "9" * 5000, "-0")
BAD_FLOATS = ("nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-0", "abc", "", "1,2",
              "1e999", "１.５", "1_0.5", " 0.5 ", "infinity", "0x1p3", "-0.0")
BAD_SIZES = ("0x0", "-1x5", "100000x100000", "1x1", "x", "5x", "3x4x5", "1e3x1e3", "nan", "65536x1", "2x99999999")
BAD_PATHS = ("", "/", "/dev/null/x.png", "/proc/self/x.png", "nofolder/x.png", "a" * 300 + ".png", "x.unknown",
             "dir.png", "link.png", "tex.toml", "img.png", ".", "..", "\x7f.png", "-o")

#: Values no option may accept (a run that exits 0 with one of them is not answered well).
MUST_REFUSE = frozenset(("٣", "３", "१", "1_000", " 3 ", "3.0", "9" * 5000, "nan", "inf", "-inf", "abc", "", "1e999",
                         "１.５", "1_0.5", " 0.5 ", "infinity", "0x1p3", "1,2", "0x10", "1e3", "x", "5x", "3x4x5",
                         "1e3x1e3", "0x0", "-1x5"))


#: Texture-file fields and hostile values for them (each a file m<i>.toml).
MUTATIONS = [(f, v) for f, vs in {
    "size": ("-1.0", "0.0", "inf", "nan", "1e300", '"big"', "[1.0]", "true"),
    "opacity": ("-5.0", "2.0", "nan", '"x"'),
    "rotation": ("inf", "1e308", '"x"'),
    "offset": ("[1.0]", "[nan, 0.0]", "[1e300, 0.0]", '"x"', "[[1.0], [2.0]]"),
    "blend": ('"nope"', "1", '""'),
    "tiling": ('"nope"', '"stochastic"'),
    "tile": ("5", "-1", "1.5", "99999999999999999999"),
    "version": ("99", "0", '"2"'),
    "bits": ("16", "true"),
    "tiles": ('[]', '["../x.png"]', '["/etc/passwd"]', '[1]', '["tex.toml"]'),
}.items() for v in vs]


def _mutate(toml: str, field: str, value: str) -> str:
    """``toml`` with the first line ``field = ...`` given ``value`` (added to the first layer if absent)."""
    lines = toml.splitlines()
    for k, line in enumerate(lines):
        if line.split("=")[0].strip() == field:
            lines[k] = f"{field} = {value}"
            return "\n".join(lines) + "\n"
    return toml.replace("[[layers]]", f"[[layers]]\n{field} = {value}", 1)


def make_inputs(folder: Path) -> None:
    from spectex import io
    from spectex.texture import SpectralTexture

    rng = np.random.default_rng(26)
    io.write_image(folder / "img.png", rng.random((48, 48, 3)).astype(np.float32))
    SpectralTexture.paper_preset(tile_size=16).save(folder / "tex.toml")
    np.save(folder / "big.npy", (rng.random((32, 32, 3)) * 4 - 1).astype(np.float32))
    np.save(folder / "c.npy", np.ones((16, 16), np.complex64))
    np.save(folder / "i.npy", np.ones((16, 16), np.int32))
    np.save(folder / "b.npy", np.ones((16, 16), bool))
    np.save(folder / "one.npy", np.ones((1, 1, 3), np.float32))
    np.save(folder / "five.npy", np.ones((8, 8, 5), np.float32))
    np.save(folder / "f16.npy", rng.random((16, 16)).astype(np.float16))
    (folder / "nest.toml").write_text("a = " + "[" * 1000 + "]" * 1000)
    toml = (folder / "tex.toml").read_text()
    (folder / "many.toml").write_text(toml + "\n[[layers]]\ntile = 0\nsize = 1.0\n" * 20)
    (folder / "tiny.toml").write_text(toml.replace("size = ", "size = 1e-308 #", 1))
    (folder / "neg.toml").write_text(toml.replace("opacity = ", "opacity = -5 #", 1))
    (folder / "bin.toml").write_bytes(b"\xff\xfe\x00garbage")
    for i, (field, value) in enumerate(MUTATIONS):
        (folder / f"m{i}.toml").write_text(_mutate(toml, field, value))
    (folder / "c.txt").write_text("the cat sat on the mat. " * 50)
    (folder / "dir.png").mkdir()
    os.symlink("img.png", folder / "link.png")
    (folder / "empty.png").write_bytes(b"")


def cases() -> list[tuple[str, ...]]:
    out: list[tuple[str, ...]] = []
    # numbers and sizes, per command and option
    per_command = {
        "noise": (("perlin", "-o", "x.png"), {"--size": BAD_SIZES, "--scale": BAD_FLOATS, "--octaves": BAD_INTS,
                                               "--seed": BAD_INTS, "--frames": BAD_INTS, "--fps": BAD_FLOATS}),
        "tile": (("-o", "x.png"), {"--size": BAD_SIZES, "--cutoff": BAD_FLOATS, "--beta": BAD_FLOATS,
                                   "--seed": BAD_INTS, "--strength": BAD_FLOATS}),
        "spectrum": (("img.png",), {"--fmax": BAD_FLOATS}),
        "render": (("tex.toml", *CAMERA, "-o", "x.png"), {"--size": BAD_SIZES, "--frames": BAD_INTS,
                                                           "--supersample": BAD_INTS}),
        "synth": (("img.png", "-o", "x.png"), {"--size": BAD_SIZES, "--block": BAD_INTS, "--overlap": BAD_INTS,
                                               "--tolerance": BAD_FLOATS, "--seed": BAD_INTS}),
        "text": (("c.txt",), {"--length": BAD_INTS, "--order": BAD_INTS, "--seed": BAD_INTS}),
        "compare": (("img.png", "--reference", "img.png"), {"--block": BAD_INTS}),
        "fit": (("img.png", "-o", "fitout"), {"--pixel-size": BAD_FLOATS, "--layers": BAD_INTS,
                                              "--ratio": BAD_FLOATS, "--opacity": BAD_FLOATS}),
        "bake": (("tex.toml", "-o", "b.zarr", "--size", "32x32", "--pixel-size", "0.1"),
                 {"--pixel-size": BAD_FLOATS, "--size": BAD_SIZES, "--chunk": BAD_INTS, "--shard": BAD_INTS,
                  "--levels": BAD_INTS, "--origin": ("nan,0", "1e300,0", "1", "a,b"),
                  "--scheduler": ("inproc://x", "tcp://", "tcp://h", "tcp://h:0", "x", "tcp://127.0.0.1:9"),
                  "--connect-timeout": BAD_FLOATS}),
        "export": (("tex.toml", "-o", "exp"), {"--format": ("", "web,", "nope", "web,web", ",")}),
    }
    for command, (base, options) in per_command.items():
        for option, values in options.items():
            for value in values:
                if option == "--connect-timeout":
                    out.append((command, *base, "--scheduler", "tcp://127.0.0.1:9", option, value))
                else:
                    out.append((command, *base, option, value))
    for kind, option, value in itertools.product(("fbm", "turbulence"), ("--gain", "--lacunarity"), BAD_FLOATS):
        out.append(("noise", kind, option, value, "--size", "16", "-o", "x.png"))
    for kind, value in itertools.product(("perlin", "value", "marble", "wood"), BAD_FLOATS):
        out.append(("noise", kind, "--scale", value, "--size", "16", "-o", "x.png"))
    # hostile inputs to every command that reads one
    readers = {
        "spectrum": lambda f: ("spectrum", f),
        "synth": lambda f: ("synth", f, "--method", "histogram", "--size", "16", "-o", "x.png"),
        "tile": lambda f: ("tile", "--from", f, "-o", "x.png"),
        "compare": lambda f: ("compare", f, "--reference", "img.png"),
        "fit": lambda f: ("fit", f, "-o", "fitout"),
    }
    images = ("big.npy", "c.npy", "i.npy", "b.npy", "one.npy", "five.npy", "f16.npy", "empty.png", "dir.png",
              "link.png", "tex.toml", "c.txt", "nothere.png", "/dev/zero", "/dev/null")
    out += [make(f) for make, f in itertools.product(readers.values(), images)]
    textures = ("nest.toml", "many.toml", "tiny.toml", "neg.toml", "bin.toml", "img.png", "c.txt", "nothere.toml",
                "/dev/zero")
    for t in textures:
        out += [("render", t, *CAMERA, "--size", "16x16", "-o", "x.png"), ("export", t, "-o", "exp"),
                ("bake", t, "-o", "b.zarr", "--size", "16x16", "--pixel-size", "0.1"), ("view", t)]
    for i in range(len(MUTATIONS)):
        out += [("render", f"m{i}.toml", *CAMERA, "--size", "16x16", "-o", "x.png"),
                ("bake", f"m{i}.toml", "-o", "b.zarr", "--size", "16x16", "--pixel-size", "0.1")]
    # output paths, for every command that writes
    writers = {
        "noise": ("noise", "perlin", "--size", "16", "-o"), "tile": ("tile", "--size", "16", "-o"),
        "spectrum": ("spectrum", "img.png", "-o"), "synth": ("synth", "img.png", "--size", "16", "-o"),
        "render": ("render", "tex.toml", *CAMERA, "--size", "16x16", "-o"), "text": ("text", "c.txt", "-o"),
        "compare": ("compare", "img.png", "--reference", "img.png", "-o"), "fit": ("fit", "img.png", "-o"),
        "export": ("export", "tex.toml", "-o"), "demo": ("demo", "-o"),
        "bake": ("bake", "tex.toml", "--size", "16x16", "--pixel-size", "0.1", "-o"),
    }
    out += [(*w, p) for w, p in itertools.product(writers.values(), BAD_PATHS)]
    # unknown options and missing arguments
    for command in writers:
        out += [(command,), (command, "--nope"), (command, "--help-me"), (command, "-o")]
    return out


#: Commands run once before the trial, not counted: numba compiles each kernel on its first use and
#: caches it, so that the trial measures what a user sees from the second run on, not a cold compile.
WARM_UP = (("fit", "img.png", "-o", "warm_fit"), ("render", "tex.toml", *CAMERA, "--size", "16x16", "-o", "w.png"),
           ("bake", "tex.toml", "-o", "w.zarr", "--size", "32x32", "--pixel-size", "0.1"),
           ("synth", "img.png", "--size", "16", "-o", "w.png"), ("tile", "--size", "16", "-o", "w.png"),
           ("synth", "img.png", "--method", "efros-leung", "--size", "16", "-o", "w.png"),
           ("noise", "fbm", "--size", "16", "-o", "w.png"), ("spectrum", "img.png"),
           ("compare", "img.png", "--reference", "img.png"), ("text", "c.txt", "--length", "20"))


def warm_up(base: Path, work: Path) -> float:
    """Run :data:`WARM_UP` in a copy of ``base``; return the seconds it took."""
    folder = work / "warm"
    shutil.copytree(base, folder, symlinks=True)
    start = time.perf_counter()
    for argv in WARM_UP:
        subprocess.run([sys.executable, "-m", "spectex", *argv], cwd=folder, stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=1800)
    shutil.rmtree(folder, ignore_errors=True)
    return time.perf_counter() - start


def run(argv, base: Path, work: Path, index: int) -> dict:
    folder = work / f"c{index}"
    shutil.copytree(base, folder, symlinks=True)
    before = snapshot(folder)
    env = dict(os.environ, PYTHONWARNINGS="", DISPLAY="", WAYLAND_DISPLAY="")
    start = time.perf_counter()
    rss_file = work / f"c{index}.rss"
    proc = subprocess.Popen([sys.executable, "-c", _WRAP, str(rss_file), sys.executable, "-m", "spectex", *argv],
                            cwd=folder, env=env,
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            errors="replace", start_new_session=True)
    try:
        out, err = proc.communicate(timeout=TIMEOUT)
        timeout = False
    except subprocess.TimeoutExpired:
        hwm = _session_peak(proc.pid)  # what the run had held when it was stopped
        # the whole group: killing the wrapper alone would leave spectex running, holding the pipes open
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        timeout = True
    elapsed = time.perf_counter() - start
    # the child's peak memory: getrusage of children is cumulative, so wait4 is used through the pid's status
    try:
        kib, cpu = rss_file.read_text().split()
        rss, cpu = int(kib) * 1024, float(cpu)  # ru_maxrss is in KiB on Linux
    except (OSError, ValueError):
        rss = cpu = None
    if timeout:
        rss = hwm
    after = snapshot(folder)
    named = _named_output(argv, folder) if proc.returncode == 0 else set()
    lost = [p for p in before if after.get(p) != before[p] and p not in named]
    shutil.rmtree(folder, ignore_errors=True)
    lines = [ln for ln in err.splitlines() if ln.strip() and "rendering on the CPU instead" not in ln]
    problems = []
    if timeout:
        problems.append("timeout")
    if "Traceback" in err:
        problems.append("traceback")
    if proc.returncode not in (0, 2):
        problems.append(f"rc {proc.returncode}")
    if proc.returncode == 2 and len(lines) != 1:
        problems.append(f"{len(lines)} lines")
    if proc.returncode == 2 and elapsed > 5.0:
        problems.append(f"refused after {elapsed:.1f} s")
    if rss is not None and rss > 1 << 30:
        problems.append(f"peak {rss >> 20} MiB")
    if lost:
        problems.append(f"changed {lost[:3]}")
    if proc.returncode == 0 and MUST_REFUSE.intersection(argv):
        problems.append("accepted " + repr(sorted(MUST_REFUSE.intersection(argv))[0][:20]))
    return {"index": index, "argv": argv, "rc": proc.returncode,
            "err": err.strip().splitlines()[-1:] if err.strip() else [], "elapsed": elapsed,
            "rss": rss, "cpu": cpu, "problems": problems}


def _named_output(argv, folder: Path) -> set[str]:
    """The file that ``-o`` names (and the file a link there points to), relative to ``folder``: a run that
    succeeds may replace it, as the user asked, unless it is also one of the run's inputs (named in argv)."""
    if "-o" not in argv or argv.index("-o") + 1 >= len(argv):
        return set()
    k = argv.index("-o")
    name = argv[k + 1]
    others = {os.path.realpath(folder / a) for j, a in enumerate(argv) if j not in (k, k + 1) and a}
    out = set()
    for path in (folder / name, Path(os.path.realpath(folder / name))):
        try:
            rel = str(path.relative_to(folder.resolve()) if path.is_absolute() and path.is_relative_to(
                folder.resolve()) else path.relative_to(folder))
        except ValueError:
            continue
        if os.path.realpath(path) not in others:
            out.add(rel)
    return out


def _session_peak(sid: int) -> int | None:
    """The largest peak resident memory (VmHWM, bytes) of the processes in session ``sid`` (Linux)."""
    peak = None
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[3]) != sid:  # the session id, after state, ppid and pgrp
                continue
            for line in (stat.parent / "status").read_text().splitlines():
                if line.startswith("VmHWM:"):
                    peak = max(peak or 0, int(line.split()[1]) * 1024)
        except (OSError, ValueError, IndexError):
            continue
    return peak


#: Runs the command as a child and writes the child's peak resident memory (KiB) and its CPU seconds
#: (user + system: what the run cost, whatever the machine's load) to argv[1].
_WRAP = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[2:]); "
         "u = resource.getrusage(resource.RUSAGE_CHILDREN); "
         "open(sys.argv[1], 'w').write(f'{u.ru_maxrss} {u.ru_utime + u.ru_stime}'); "
         "sys.exit(r.returncode)")


def snapshot(folder: Path) -> dict:
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            p = Path(root) / name
            rel = str(p.relative_to(folder))
            if p.is_symlink():
                out[rel] = ("link", os.readlink(p))
            elif p.is_file():
                out[rel] = ("file", hashlib.sha1(p.read_bytes()).hexdigest())
            else:
                out[rel] = ("dir",)
    return out


def _log_line(r: dict) -> str:
    clean = [a.replace("\t", " ").replace("\n", " ")[:200] for a in r["argv"]]
    err = " ".join(r["err"]).replace("\t", " ")[:300]
    rss = -1 if r["rss"] is None else r["rss"]
    cpu = -1 if r.get("cpu") is None else r["cpu"]
    return (f"{r['index']}\t{r['rc']}\t{r['elapsed']:.3f}\t{rss}\t{';'.join(r['problems'])}\t"
            f"{' '.join(clean)}\t{err}\t{cpu:.3f}\n")


def read_log(path) -> list[dict]:
    """The results of a log written by ``--log`` (the last line of each case index)."""
    out = {}
    for line in Path(path).read_text(errors="replace").splitlines():
        parts = line.split("\t")
        if len(parts) < 6 or not parts[0].isascii() or not parts[0].isdigit():
            continue
        out[int(parts[0])] = {"index": int(parts[0]), "rc": int(parts[1]), "elapsed": float(parts[2]),
                              "rss": None if parts[3] == "-1" else int(parts[3]),
                              "problems": [p for p in parts[4].split(";") if p], "argv": parts[5].split(" "),
                              "err": parts[6:7],
                              "cpu": float(parts[7]) if len(parts) > 7 and parts[7] != "-1.000" else None}
    return [out[k] for k in sorted(out)]


def summary(results: list[dict], total: int | None = None) -> str:
    """The counts of a trial, in the words of issue 26's targets."""
    n = len(results)
    if n == 0:
        return "0 cases"
    bad = [r for r in results if r["problems"]]
    tracebacks = sum("traceback" in r["problems"] for r in results)
    unbounded = sum(any(p == "timeout" or p.startswith(("refused after", "peak")) for p in r["problems"])
                    for r in results)
    timeouts = [r for r in results if "timeout" in r["problems"]]
    timeout_words = ""
    if timeouts:
        peaks = [r["rss"] for r in timeouts if r["rss"]]
        timeout_words = f" ({len(timeouts)} still running at {TIMEOUT} s"
        timeout_words += f", peak memory when stopped up to {max(peaks) / 2 ** 20:.0f} MiB)" if peaks else ")"
    lost = sum(any(p.startswith("changed") for p in r["problems"]) for r in results)
    other_rc = sum(any(p.startswith("rc ") for p in r["problems"]) for r in results)
    lines_bad = sum(any(p.endswith(" lines") for p in r["problems"]) for r in results)
    refusals = sorted(r["elapsed"] for r in results if r["rc"] == 2)
    p95 = refusals[min(len(refusals) - 1, int(0.95 * len(refusals)))] if refusals else 0.0
    rss_refused = max((r["rss"] or 0 for r in results if r["rc"] == 2), default=0)
    rss_all = max((r["rss"] or 0 for r in results), default=0)
    cpus = sorted(r["cpu"] for r in results if r["rc"] == 2 and r.get("cpu") is not None)
    cpu_words = (f"; CPU seconds of a refusal (user + system, whatever the load) max {cpus[-1]:.2f}, "
                 f"p95 {cpus[min(len(cpus) - 1, int(0.95 * len(cpus)))]:.2f}" if cpus else "")
    of = f" of {total}" if total is not None and total != n else ""
    return (f"{n} cases{of}: {n - len(bad)} answered well ({100 * (n - len(bad)) / n:.1f} %); "
            f"{tracebacks} tracebacks, {other_rc} other exit statuses, {lines_bad} refusals not one line, "
            f"{unbounded} unbounded (timeout, refusal > 5 s or peak > 1 GiB){timeout_words}, {lost} with inputs "
            "lost or changed\n"
            f"{len(refusals)} refusals (exit 2): time to refusal max {refusals[-1] if refusals else 0:.2f} s, "
            f"p95 {p95:.2f} s, median {refusals[len(refusals) // 2] if refusals else 0:.2f} s; "
            f"peak memory of a refusal {rss_refused / 2 ** 20:.0f} MiB, of any case {rss_all / 2 ** 20:.0f} MiB; "
            f"{sum(r['rc'] == 0 for r in results)} ran to the end (exit 0){cpu_words}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--start", type=int, default=0, help="the first case index to run (default: 0)")
    parser.add_argument("--limit", type=int, default=None, help="run at most N cases")
    parser.add_argument("--log", default=None, help="append one tab-separated line per case to LOG")
    parser.add_argument("--every", type=int, default=1, help="run every N-th case only (a sample of each kind)")
    parser.add_argument("--only", default=None, help="run only the case indices in this file (one a line), "
                                                     "e.g. those a log found wanting")
    parser.add_argument("--summary", default=None, metavar="LOG", help="print the summary of LOG and stop")
    parser.add_argument("--count", action="store_true", help="print the number of cases and stop")
    parser.add_argument("--cold", action="store_true", help="no warm-up: the first cases compile numba's kernels")
    args = parser.parse_args()
    every = cases()
    if args.count:
        print(len(every))
        return 0
    if args.summary:
        results = read_log(args.summary)
        print(summary(results, len(every)))
        for r in results:
            if r["problems"]:
                print(f"  {r['index']}  {r['problems']}  spectex {' '.join(a[:40] for a in r['argv'])}  ->  "
                      f"{' '.join(r['err'])}")
        return 0
    indices = list(range(len(every)))[args.start::args.every][: args.limit]
    if args.only:
        wanted = {int(t) for t in Path(args.only).read_text().split()}
        indices = [i for i in indices if i in wanted]
    log = open(args.log, "a", encoding="utf-8") if args.log else None  # noqa: SIM115 - held for the run
    started = time.perf_counter()
    load = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="spectex-fuzz-") as tmp:
        base = Path(tmp) / "base"
        base.mkdir()
        make_inputs(base)
        work = Path(tmp) / "work"
        work.mkdir()
        if not args.cold:
            print(f"warm-up (numba's caches): {warm_up(base, work):.0f} s", flush=True)
        started = time.perf_counter()
        with ThreadPoolExecutor(args.workers) as pool:
            results = []
            for r in pool.map(lambda i: run(every[i], base, work, i), indices):
                results.append(r)
                if log is not None:
                    log.write(_log_line(r))
                    log.flush()
                if r["problems"]:  # as they come: a long trial shows what it finds early
                    print(f"  {r['index']}  {r['problems']}  spectex {' '.join(a[:40] for a in r['argv'])}  ->  "
                          f"{r['err']}", flush=True)
    if log is not None:
        log.close()
    print(summary(results, len(every)))
    print(f"{time.perf_counter() - started:.0f} s with {args.workers} workers; load average at the start "
          f"{load[0]:.1f}, at the end {os.getloadavg()[0]:.1f} ({os.cpu_count()} CPUs)")
    return 0 if not any(r["problems"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
