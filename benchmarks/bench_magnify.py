"""Benchmark: octaves by magnification, the CPU route against the seed's GL route.

Run from the repository root::

    python benchmarks/bench_magnify.py              # about a minute on llvmpipe
    python benchmarks/bench_magnify.py --large      # adds 4096 x 4096 outputs
    python benchmarks/bench_magnify.py --repeat 7

Peers in the same run, on the same float32 input (issue 17):

* ``magnify(x, m)``: the CPU route (NumPy, separable, ``T`` passes per axis
  over arrays);
* ``magnify_gl(x, m, multiply='blend')``: the seed's method, ``T^2`` passes of
  three draws each (filter into the alpha plane; sub-texture blended with
  ``GL_DST_ALPHA, GL_ZERO``; additive accumulation into a float32
  framebuffer);
* ``magnify_gl(x, m, multiply='shader')``: the same passes with the product
  in the fragment shader, one draw per pass.

The GL times include everything a call does (sub-texture and filter upload,
framebuffers, the passes, the read-back of the float32 result); the context
is made once, before timing. Times are the best of ``--repeat`` runs after
one warm-up call; the ratios are GL over CPU. The OpenGL renderer (Mesa
llvmpipe on a machine without a GPU) and the load average are printed with
them: on a shared machine the best of several runs is the least disturbed.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np


def best_of(fn, repeat):
    fn()  # warm-up: shader compilation, caches, page faults
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


CASES = [
    # (cells, output, filter)
    (4, 16, "bspline"),      # tiny: the GL route's fixed cost per call
    (4, 512, "tent"),        # the seed's example: 4 x 4 input, 512 x 512 output, 2 x 2 footprint
    (4, 512, "bspline"),
    (32, 512, "catmull-rom"),
    (128, 512, "bspline"),
    (16, 2048, "tent"),
    (128, 2048, "bspline"),
]
LARGE = [(64, 4096, "tent"), (64, 4096, "bspline")]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--large", action="store_true", help="add 4096 x 4096 outputs")
    args = parser.parse_args(argv)

    from spectex.spectral import filter_passes, magnify, magnify_gl
    from spectex.spectral._magnify_gl import default_context

    ctx = default_context()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"NumPy {np.__version__}")
    print(f"OpenGL: {ctx.info['GL_RENDERER']} ({ctx.info['GL_VERSION']})")
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print()
    header = (f"{'cells -> output':>18} {'filter':>12} {'passes':>6} {'cpu ms':>8} "
              f"{'gl blend ms':>11} {'gl shader ms':>12} {'blend/cpu':>9} {'shader/cpu':>10}")
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(0)
    for n, big, filt in CASES + (LARGE if args.large else []):
        x = rng.standard_normal((n, n)).astype(np.float32)
        m = big // n
        reps = args.repeat * (3 if big <= 512 else 1)
        cpu = best_of(lambda: magnify(x, m, kernel=filt), reps)
        blend = best_of(lambda: magnify_gl(x, m, kernel=filt, multiply="blend", ctx=ctx), reps)
        shader = best_of(lambda: magnify_gl(x, m, kernel=filt, multiply="shader", ctx=ctx), reps)
        passes = filter_passes(filt) ** 2
        print(f"{n:>7} -> {big:>4}^2   {filt:>12} {passes:>6} {cpu * 1e3:>8.2f} {blend * 1e3:>11.1f} "
              f"{shader * 1e3:>12.1f} {blend / cpu:>9.0f} {shader / cpu:>10.0f}")
    print()
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
