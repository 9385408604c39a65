"""Benchmark: the OpenGL renderer's frame on whatever GPU the context gets, side by side in one run.

The renderer's other benchmarks measure CPU time per frame on llvmpipe (the
CI machines have no GPU). This one measures GPU time per frame with OpenGL
timer queries (``GL_TIME_ELAPSED``, ``moderngl.Context.query(time=True)``)
and, beside it, wall-clock time per frame to ``glFinish`` (the two agree on a
real GPU; llvmpipe defers its work, so there only the wall-clock figure
means anything), and checks on that GPU that the picture is still the CPU
renderer's.

Textures, each a row, all timed interleaved (``--repeats`` rounds, each
texture ``--frames`` frames per round, the median round kept):

* ``paper``: ``SpectralTexture.paper_preset(tile, blend="alpha",
  detail=False)``, the paper's five periodic alpha-blended layers: the
  baseline every ratio is against;
* ``paper stochastic``: the same layers drawn stochastically;
* ``defaults``: ``paper_preset(tile)``, the demo's picture (cover blend,
  sixth fine layer);
* every ``--texture PATH`` (a texture file, e.g. a fit's ``texture.toml``),
  labelled by its folder's name.

Views: the demo's ground, close-up and aerial cameras, at 1920 x 1080 and
3840 x 2160, haze 12 km. Then, per texture and view, the PSNR of the GL
frame against the CPU renderer (``render_cpu``) at 480 x 270.

Run from the repository root::

    python benchmarks/bench_gpu.py [--texture fit/texture.toml ...] [--frames 20] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import cpu_name  # noqa: E402


def psnr(a, b):
    mse = float(np.mean((np.asarray(a, np.float64) - np.asarray(b, np.float64)) ** 2))
    return float("inf") if mse == 0 else 10.0 * np.log10(1.0 / mse)


def gpu_seconds(renderer, camera, shape, frames, anisotropy, atmosphere):
    """GPU seconds and wall seconds per frame over ``frames`` draws, after one warm-up draw."""
    import time

    h, w = shape
    renderer._make_current()
    fbo = renderer._framebuffer(h, w)
    fbo.use()
    fbo.viewport = (0, 0, w, h)
    renderer.draw(camera, shape, anisotropy=anisotropy, atmosphere=atmosphere)
    renderer.ctx.finish()
    query = renderer.ctx.query(time=True)
    t0 = time.perf_counter()
    with query:
        for _ in range(frames):
            renderer.draw(camera, shape, anisotropy=anisotropy, atmosphere=atmosphere)
    renderer.ctx.finish()
    wall = time.perf_counter() - t0
    return query.elapsed * 1e-9 / frames, wall / frames


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--texture", action="append", default=[], metavar="PATH",
                        help="a texture file to time beside the built-in ones (repeatable)")
    parser.add_argument("--frames", type=int, default=20, help="frames per timed round (default 20)")
    parser.add_argument("--repeats", type=int, default=5, help="interleaved rounds, median kept (default 5)")
    parser.add_argument("--skip-cpu", action="store_true", help="skip the GL-against-CPU comparison")
    args = parser.parse_args(argv)

    from spectex.cli._demo import views
    from spectex.render import Atmosphere
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer
    from spectex.texture import SpectralTexture
    from spectex.tiles import make_tile

    tile = make_tile(512, rng=0)
    textures = {
        "paper": SpectralTexture.paper_preset(tile, blend="alpha", detail=False),
        "paper stochastic": SpectralTexture.paper_preset(tile, blend="alpha", detail=False,
                                                         tiling="stochastic"),
        "defaults": SpectralTexture.paper_preset(tile),
    }
    for path in args.texture:
        textures[Path(path).resolve().parent.name] = SpectralTexture.load(path)
    atmosphere = Atmosphere()
    shapes = [(1080, 1920), (2160, 3840)]
    renderers = {label: GLRenderer(tex) for label, tex in textures.items()}
    try:
        info = next(iter(renderers.values())).ctx.info
        print(f"GL: {info['GL_RENDERER']} ({info['GL_VERSION']}); host CPU: "
              f"{cpu_name()}, {os.cpu_count()} logical cores")
        cams = views()
        rounds = {(label, view, shape): [] for label in textures for view in cams for shape in shapes}
        for _ in range(args.repeats):
            for view, (cam, an) in cams.items():
                for shape in shapes:
                    for label, r in renderers.items():  # interleaved: every texture sees the same state
                        rounds[label, view, shape].append(gpu_seconds(r, cam, shape, args.frames, an, atmosphere))
        for which, name in ((0, "GPU (timer query)"), (1, "wall clock to glFinish")):
            median = {key: statistics.median(x[which] for x in v) for key, v in rounds.items()}
            print(f"{name}: ms per frame (median of {args.repeats} rounds of {args.frames} frames), "
                  "and the ratio to the paper's texture:")
            print(f"{'':24s}" + "".join(f"{view + ' ' + str(s[1]) + 'x' + str(s[0]):>24s}"
                                        for view in cams for s in shapes))
            for label in textures:
                cells = []
                for view in cams:
                    for shape in shapes:
                        t = median[label, view, shape]
                        cells.append(f"{1e3 * t:9.3f} ({t / median['paper', view, shape]:5.2f}x)")
                print(f"{label:24s}" + "".join(f"{c:>24s}" for c in cells))
        if not args.skip_cpu:
            small = (270, 480)
            print(f"GL against the CPU renderer at {small[1]}x{small[0]}, PSNR dB:")
            for label, r in renderers.items():
                values = []
                for view, (cam, an) in cams.items():
                    gl = r.render(cam, small, anisotropy=an, atmosphere=atmosphere)
                    cpu = render_cpu(textures[label], cam, small, anisotropy=an, atmosphere=atmosphere)
                    values.append(f"{view} {psnr(gl, cpu):6.2f}")
                print(f"  {label:24s} " + "  ".join(values))
    finally:
        for r in renderers.values():
            r.release()


if __name__ == "__main__":
    main()
