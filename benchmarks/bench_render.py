"""Rendering benchmark: the five-layer spectral texture against one plain layer.

Side by side in one run (STYLE.md: ratios, not timed tests):

* OpenGL frames per second at 1920 x 1080 (offscreen, no read-back) for the
  paper's five-layer texture and for one plain textured layer, trilinear,
  on whatever the EGL context gives (Mesa llvmpipe on the dev machine and in
  CI; the GPU where there is one); targets: >= 30 fps for five layers on
  llvmpipe on the 2-core dev machine, and five layers <= 5 x one layer;
* the CPU reference renderer's throughput (Mpx/s) for the same two
  textures, trilinear; target: >= 20 Mpx/s for five layers.

All at anisotropy 1 (trilinear only, the renderers' fast path); the
renderers' default is anisotropy 8, whose cost ``bench_anisotropy.py``
measures.

Wall-clock numbers on a shared machine follow its load; the CPU time per
frame (GL, llvmpipe's threads included) and per pixel (CPU renderer) are
printed too: they move much less with other jobs, and 2 free cores turn
them into wall-clock rates (fps ~ 2 / CPU seconds per frame).

Run: ``python benchmarks/bench_render.py [--frames N] [--repeats N]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="GL frames per measurement (default 20)")
    parser.add_argument("--repeats", type=int, default=3, help="best of this many measurements (default 3)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    args = parser.parse_args(argv)

    import numba

    from spectex.render import Camera
    from spectex.render.cpu import render_cpu
    from spectex.texture import Layer, SpectralTexture
    from spectex.tiles import make_tile

    size = (args.height, args.width)
    tile = make_tile(512, rng=0)
    five = SpectralTexture.paper_preset(tile, blend="alpha", detail=False)  # the paper's five layers
    one = SpectralTexture(tile, [Layer(size=15.625)])
    camera = Camera((0.0, 0.0, 2.5), yaw=35.0, pitch=-9.0, fov=60.0)  # the demo's ground view
    rows = []

    # ---- OpenGL
    gl_fps = {}
    gl_cpu = {}
    device = "no OpenGL"
    try:
        from spectex.render.gl import GLRenderer, GLUnavailable

        for name, tex in (("five layers", five), ("one layer", one)):
            with GLRenderer(tex) as r:
                device = r.ctx.info["GL_RENDERER"]
                best = cpu_best = float("inf")
                for _ in range(args.repeats):
                    c0 = time.process_time()  # llvmpipe's threads included
                    best = min(best, r.time_frames(camera, size, frames=args.frames, anisotropy=1.0))
                    cpu_best = min(cpu_best, (time.process_time() - c0) / (args.frames + 1))
                gl_fps[name] = 1.0 / best
                gl_cpu[name] = cpu_best
    except GLUnavailable as exc:  # pragma: no cover - depends on the machine
        device = f"no OpenGL ({exc})"

    # ---- CPU reference renderer
    cpu = {}
    cpu_ns = {}
    render_cpu(five, camera, (16, 16), anisotropy=1.0)  # compile (cached) outside the timing
    render_cpu(one, camera, (16, 16), anisotropy=1.0)
    for name, tex in (("five layers", five), ("one layer", one)):
        best = cpu_best = float("inf")
        for _ in range(args.repeats):
            t = time.perf_counter()
            c0 = time.process_time()
            render_cpu(tex, camera, size, anisotropy=1.0)
            best = min(best, time.perf_counter() - t)
            cpu_best = min(cpu_best, time.process_time() - c0)
        cpu[name] = size[0] * size[1] / best / 1e6
        cpu_ns[name] = cpu_best / (size[0] * size[1]) * 1e9

    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    print(f"spectex render benchmark, {args.width}x{args.height}, ground view to the horizon, trilinear")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"numba threads {numba.get_num_threads()}, load average {load[0]:.2f} (other work slows every number)")
    print(f"OpenGL: {device}")
    print()
    print(f"{'':24s}{'five layers':>14s}{'one layer':>14s}{'ratio 5/1':>12s}{'target':>24s}")
    if gl_fps:
        f5, f1 = gl_fps["five layers"], gl_fps["one layer"]
        print(f"{'OpenGL fps':24s}{f5:14.1f}{f1:14.1f}{f1 / f5:12.2f}x{'>= 30 fps, <= 5x':>23s}")
        print(f"{'OpenGL ms per frame':24s}{1000 / f5:14.1f}{1000 / f1:14.1f}")
        print(f"{'OpenGL CPU ms per frame':24s}{1000 * gl_cpu['five layers']:14.1f}{1000 * gl_cpu['one layer']:14.1f}"
              f"{'(all cores; load-robust)':>36s}")
    c5, c1 = cpu["five layers"], cpu["one layer"]
    print(f"{'CPU reference Mpx/s':24s}{c5:14.2f}{c1:14.2f}{c1 / c5:12.2f}x{'>= 20 Mpx/s (five)':>24s}")
    print(f"{'CPU ns per px, CPU time':24s}{cpu_ns['five layers']:14.0f}{cpu_ns['one layer']:14.0f}"
          f"{'(all cores; load-robust)':>36s}")
    if gl_fps:
        print(f"{'OpenGL Mpx/s':24s}{f5 * size[0] * size[1] / 1e6:14.2f}{f1 * size[0] * size[1] / 1e6:14.2f}")
        mpx = size[0] * size[1] / 1e6
        print(f"{'OpenGL / CPU speed':24s}{f5 * mpx / c5:14.2f}x{f1 * mpx / c1:13.2f}x")
    return rows


if __name__ == "__main__":
    main()
