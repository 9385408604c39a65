"""Noise speed, side by side with the peers, in one run.

ns per sample at about 4 M arbitrary float32 coordinates (uniform in
[0, 100)), for 2-D and 3-D Perlin noise and 8-octave fBm:

* spectex (numba, all cores),
* pyfastnoiselite ``gen_from_coords`` (FastNoiseLite in C++, one thread),
* the ``noise`` package (C, called per point from Python; timed on a 200 k
  subset because the loop is slow).

Each configuration is run ``--repeats`` times, the methods interleaved so
that a burst of load on the shared machine hits them alike; the best run
counts. Run: ``python benchmarks/bench_noise.py`` (``pip install -e .[bench]``).
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np


def _best(fn, repeats):
    fn()  # warm-up (compilation, caches)
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=4_000_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--loop-points", type=int, default=200_000)
    args = parser.parse_args(argv)

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
    coords = (rng.random((3, n), dtype=np.float32) * 100).astype(np.float32)
    x, y, z = (np.ascontiguousarray(c) for c in coords)
    c2 = np.ascontiguousarray(coords[:2])

    def fnl(dims, octaves):
        gen = FastNoiseLite(0)
        gen.noise_type = NoiseType.NoiseType_Perlin
        gen.frequency = 1.0
        if octaves > 1:
            gen.fractal_type = FractalType.FractalType_FBm
            gen.fractal_octaves = octaves
            gen.fractal_gain = 0.5
            gen.fractal_lacunarity = 2.0
        data = c2 if dims == 2 else coords
        return lambda: gen.gen_from_coords(data)

    def loop(dims, octaves):
        m = args.loop_points
        xs, ys, zs = x[:m].tolist(), y[:m].tolist(), z[:m].tolist()
        if dims == 2:
            f = noise_pkg.pnoise2
            return lambda: [f(a, b, octaves) for a, b in zip(xs, ys)]
        f = noise_pkg.pnoise3
        return lambda: [f(a, b, c, octaves) for a, b, c in zip(xs, ys, zs)]

    cases = [
        ("Perlin 2-D", lambda: sn.perlin(x, y), 2, 1),
        ("Perlin 3-D", lambda: sn.perlin(x, y, z), 3, 1),
        ("fBm 2-D, 8 octaves", lambda: sn.fbm(x, y, octaves=8), 2, 8),
        ("fBm 3-D, 8 octaves", lambda: sn.fbm(x, y, z, octaves=8), 3, 8),
    ]
    rows = []
    threads = numba.get_num_threads()

    def one_thread(f):
        def run():
            numba.set_num_threads(1)
            try:
                return f()
            finally:
                numba.set_num_threads(threads)
        return run

    for name, ours, dims, octaves in cases:
        fns = {"spectex": ours, "spectex, 1 thread": one_thread(ours)}
        if FastNoiseLite is not None:
            fns["pyfastnoiselite"] = fnl(dims, octaves)
        best = {k: float("inf") for k in fns}
        for f in fns.values():
            f()  # warm-up
        for _ in range(args.repeats):
            for k, f in fns.items():
                t = time.perf_counter()
                f()
                best[k] = min(best[k], time.perf_counter() - t)
        ns = {k: v / n * 1e9 for k, v in best.items()}
        if noise_pkg is not None:
            ns["noise (loop)"] = _best(loop(dims, octaves), 1) / args.loop_points * 1e9
        rows.append((name, ns))

    load = os.getloadavg()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"numba threads {numba.get_num_threads()}, load average {load[0]:.2f}")
    print(f"{n:,} float32 points, best of {args.repeats}; ns per sample (lower is better)\n")
    print(f"| case | spectex ({threads} threads) | spectex (1 thread) | pyfastnoiselite (1 thread) "
          f"| noise (loop) | speed-up vs FastNoiseLite | per core |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, ns in rows:
        fnl_ns = ns.get("pyfastnoiselite", float("nan"))
        loop_ns = ns.get("noise (loop)", float("nan"))
        one = ns["spectex, 1 thread"]
        print(f"| {name} | {ns['spectex']:.2f} | {one:.2f} | {fnl_ns:.2f} | {loop_ns:.0f} | "
              f"**{fnl_ns / ns['spectex']:.1f}x** | {fnl_ns / one:.1f}x |")


if __name__ == "__main__":
    main()
