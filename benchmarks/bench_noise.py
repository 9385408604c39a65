"""Noise speed, side by side with the peers, in one run.

ns per sample at 4 M arbitrary float32 coordinates (uniform in [0, 512)),
frequency 1, for 2-D and 3-D Perlin noise and 8-octave fBm (gain 0.5,
lacunarity 2), at 1 and 2 threads:

* spectex (numba; ``numba.set_num_threads``),
* FastNoiseSIMD through pyfastnoisesimd ``genFromCoords`` (C++, AVX-512 or
  AVX2 as the CPU allows; ``numWorkers`` threads). pyfastnoisesimd builds only
  against NumPy 1.x, so it runs in its own virtual environment, as a worker
  process that this script drives: ``--fns-python PATH`` (or the environment
  variable ``SPECTEX_FNS_PYTHON``) names that environment's python. Build it
  with::

      python3 -m venv fns-venv
      fns-venv/bin/pip install "numpy<2" setuptools wheel
      fns-venv/bin/pip install --no-build-isolation pyfastnoisesimd

  FastNoiseSIMD has no 2-D ``genFromCoords``: the 2-D rows compare with its
  3-D time.
* pyfastnoiselite ``gen_from_coords`` (FastNoiseLite in C++, one thread),
* the ``noise`` package (C, called per point from Python; timed on a 200 k
  subset because the loop is slow).

Every timing is repeated ``--repeats`` times; within each repeat the methods
run one after the other (the FastNoiseSIMD worker process and this process
alternate, never running at once), so that a burst of load on a shared
machine hits them alike. The best repeat counts. Run:
``python benchmarks/bench_noise.py --fns-python fns-venv/bin/python``
(``pip install -e .[bench]`` for the other peers).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

# The FastNoiseSIMD worker, run by the other virtual environment's python: it
# loads the coordinates once, then times one configuration per request line
# ("dims octaves threads") and answers with the best time in seconds.
_FNS_WORKER = r"""
import json, sys, time
import numpy as np
import pyfastnoisesimd as fns
src = np.load(sys.argv[1])
coords = fns.empty_coords(src.shape[1])
coords[:, :] = src
print(json.dumps({"version": fns.__version__, "simd": str(fns.extension.SIMD_LEVEL)}), flush=True)
gens = {}
clock = time.process_time if sys.argv[2] == "cpu" else time.perf_counter
for line in sys.stdin:
    octaves, threads = (int(v) for v in line.split())
    key = (octaves, threads)
    if key not in gens:
        gen = fns.Noise(seed=0, numWorkers=threads)
        gen.frequency = 1.0
        if octaves == 1:
            gen.noiseType = fns.NoiseType.Perlin
        else:
            gen.noiseType = fns.NoiseType.PerlinFractal
            gen.fractal.fractalType = fns.FractalType.FBM
            gen.fractal.octaves = octaves
            gen.fractal.gain = 0.5
            gen.fractal.lacunarity = 2.0
        gen.genFromCoords(coords)  # warm-up
        gens[key] = gen
    t = clock()
    gens[key].genFromCoords(coords)
    print(json.dumps({"seconds": clock() - t}), flush=True)
"""

_PAUSE = 0.05  # seconds between two timings

_BUILD_HINT = ('python3 -m venv fns-venv && fns-venv/bin/pip install "numpy<2" setuptools wheel '
               '&& fns-venv/bin/pip install --no-build-isolation pyfastnoisesimd')


class FastNoiseSIMD:
    """The pyfastnoisesimd worker process (one per run)."""

    def __init__(self, python, coords, clock):
        self._dir = tempfile.TemporaryDirectory()
        path = os.path.join(self._dir.name, "coords.npy")
        np.save(path, coords)
        self._proc = subprocess.Popen([python, "-c", _FNS_WORKER, path, clock],
                                      stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        first = self._proc.stdout.readline()
        if not first:
            self.close()
            raise RuntimeError(f"the FastNoiseSIMD worker ({python}) did not start; "
                               f"is pyfastnoisesimd installed there? Build: {_BUILD_HINT}")
        self.info = json.loads(first)

    def time(self, octaves, threads):
        self._proc.stdin.write(f"{octaves} {threads}\n")
        self._proc.stdin.flush()
        return json.loads(self._proc.stdout.readline())["seconds"]

    def close(self):
        if self._proc.poll() is None:
            self._proc.stdin.close()
            self._proc.wait(timeout=30)
        self._dir.cleanup()


def _time(fn, clock=time.perf_counter):
    t = clock()
    fn()
    return clock() - t


def _parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=4_000_000,
                        help="number of points (a multiple of 16 for FastNoiseSIMD)")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--loop-points", type=int, default=200_000)
    parser.add_argument("--fns-python", default=os.environ.get("SPECTEX_FNS_PYTHON"),
                        help="python of a virtual environment with pyfastnoisesimd")
    parser.add_argument("--threads", default="1,2", help="thread counts, comma-separated")
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall: elapsed time (the default); cpu: the process's CPU time, "
                             "which a busy machine disturbs less (meaningful with --threads 1)")
    parser.add_argument("--cases", default="p2,p3,f2,f3",
                        help="p2, p3: Perlin 2-D, 3-D; f2, f3: 8-octave fBm 2-D, 3-D")
    args = parser.parse_args(argv)
    if args.points % 16:
        parser.error(f"--points must be a multiple of 16, got {args.points}")
    return args


def _fns_worker(args, coords):
    """The FastNoiseSIMD worker process, or None (with a note on stderr) where there is none."""
    if args.fns_python is None:
        print("FastNoiseSIMD column skipped: pass --fns-python PATH (or set SPECTEX_FNS_PYTHON) "
              f"to a python with pyfastnoisesimd. Build one: {_BUILD_HINT}", file=sys.stderr)
        return None
    if not os.path.exists(args.fns_python):
        print(f"FastNoiseSIMD column skipped: --fns-python {args.fns_python} does not exist. "
              f"Build one: {_BUILD_HINT}", file=sys.stderr)
        return None
    return FastNoiseSIMD(args.fns_python, coords, args.clock)


def _fnl_timer(FastNoiseLite, FractalType, NoiseType, data, octaves):
    gen = FastNoiseLite(0)
    gen.noise_type = NoiseType.NoiseType_Perlin
    gen.frequency = 1.0
    if octaves > 1:
        gen.fractal_type = FractalType.FractalType_FBm
        gen.fractal_octaves = octaves
        gen.fractal_gain = 0.5
        gen.fractal_lacunarity = 2.0
    return lambda: gen.gen_from_coords(data)


def _best_times(fns, fns_gen, octaves, repeats, clock):
    """Best of ``repeats`` seconds per method, the methods taking turns within each repeat."""
    for f in fns.values():
        if f is not None:
            f()  # warm-up (compilation, caches)
    best = {k: float("inf") for k in fns}
    for _ in range(repeats):
        for k, f in fns.items():
            # numba's OpenMP threads spin for some milliseconds after a
            # parallel loop; on a machine with few cores that would slow
            # whatever runs next, so each timing starts after a pause.
            time.sleep(_PAUSE)
            if k[0] == "FastNoiseSIMD":
                s = fns_gen.time(octaves, k[1])
            else:
                s = _time(f, clock)
            best[k] = min(best[k], s)
    return best


def _print_table(results, thread_counts, n, args, fns_gen):
    load = os.getloadavg()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    if fns_gen is not None:
        print(f"pyfastnoisesimd {fns_gen.info['version']}, {fns_gen.info['simd']}")
    print(f"{n:,} float32 points in [0, 512), frequency 1, best of {args.repeats} "
          f"({args.clock} clock); "
          "ns per sample (lower is better); 'vs FNS' = FastNoiseSIMD's time / spectex's "
          "(above 1: spectex is faster)\n")
    print("| case | threads | spectex | FastNoiseSIMD | vs FNS | FastNoiseLite (1 thread) "
          "| vs FNL | noise (loop) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    nan = float("nan")
    for name, dims, octaves, ns in results.values():
        for t in thread_counts:
            ours = ns[("spectex", t)]
            # FastNoiseSIMD has no 2-D genFromCoords: compare with its 3-D time.
            peer = results.get("p3" if octaves == 1 else "f3")
            fns_ns = peer[3].get(("FastNoiseSIMD", t), nan) if peer else nan
            fns_txt = f"{fns_ns:.2f}" + (" (3-D)" if dims == 2 else "")
            fnl_ns = ns.get(("FastNoiseLite", 1), nan)
            loop_ns = ns.get(("noise", 1), nan)
            print(f"| {name} | {t} | {ours:.2f} | {fns_txt} | **{fns_ns / ours:.2f}x** | "
                  f"{fnl_ns:.2f} | {fnl_ns / ours:.1f}x | {loop_ns:.0f} |")


def main(argv=None):
    args = _parse_args(argv)
    thread_counts = [int(t) for t in args.threads.split(",")]

    import numba

    import spectex.noise as sn

    try:
        from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, FractalType, NoiseType
    except ImportError:  # pragma: no cover
        FastNoiseLite = None
    try:
        import noise as noise_pkg
    except ImportError:  # pragma: no cover
        noise_pkg = None

    n = args.points
    rng = np.random.default_rng(0)
    coords = rng.random((3, n), dtype=np.float32) * np.float32(512)
    x, y, z = (np.ascontiguousarray(c) for c in coords)
    c2 = np.ascontiguousarray(coords[:2])

    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    fns_gen = _fns_worker(args, coords)

    def loop(dims, octaves):
        m = args.loop_points
        xs, ys, zs = x[:m].tolist(), y[:m].tolist(), z[:m].tolist()
        if dims == 2:
            f = noise_pkg.pnoise2
            return lambda: [f(a, b, octaves) for a, b in zip(xs, ys)]
        f = noise_pkg.pnoise3
        return lambda: [f(a, b, c, octaves) for a, b, c in zip(xs, ys, zs)]

    all_cases = {
        "p2": ("Perlin 2-D", lambda: sn.perlin(x, y), 2, 1),
        "p3": ("Perlin 3-D", lambda: sn.perlin(x, y, z), 3, 1),
        "f2": ("fBm 2-D, 8 octaves", lambda: sn.fbm(x, y, octaves=8), 2, 8),
        "f3": ("fBm 3-D, 8 octaves", lambda: sn.fbm(x, y, z, octaves=8), 3, 8),
    }
    default_threads = numba.get_num_threads()
    results = {}
    try:
        for key in args.cases.split(","):
            name, ours, dims, octaves = all_cases[key]
            fns = {}
            for t in thread_counts:
                fns[("spectex", t)] = (lambda t=t, f=ours: (numba.set_num_threads(t), f()))
                if fns_gen is not None:
                    fns[("FastNoiseSIMD", t)] = None  # timed in the worker
            if FastNoiseLite is not None:
                fns[("FastNoiseLite", 1)] = _fnl_timer(FastNoiseLite, FractalType, NoiseType,
                                                       c2 if dims == 2 else coords, octaves)
            best = _best_times(fns, fns_gen, octaves, args.repeats, clock)
            numba.set_num_threads(default_threads)
            ns = {k: v / n * 1e9 for k, v in best.items()}
            if noise_pkg is not None:
                ns[("noise", 1)] = min(_time(loop(dims, octaves), clock) for _ in range(1)) \
                    / args.loop_points * 1e9
            results[key] = (name, dims, octaves, ns)
    finally:
        if fns_gen is not None:
            fns_gen.close()

    _print_table(results, thread_counts, n, args, fns_gen)

if __name__ == "__main__":
    main()
