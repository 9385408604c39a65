"""Anisotropic filtering: how much closer to the truth, and what it costs.

The quality half (what chose the renderers' default ``anisotropy``):
the paper's five-layer texture on a full-contrast tile (the preset's tile
with each colour channel stretched from its 1st to its 99th percentile to
[0, 1] and clipped, so that aliasing is not hidden by a dull tile), rendered
at the default trilinear filtering with maximum anisotropy 1 (off), 2, 4, 8
and 16, on the CPU and with OpenGL, against an 8 x 8 supersampled,
box-filtered CPU render without mip-maps (the truth), on four views: close
(1.5 m up, looking 50 degrees down), grazing (1.7 m, 3 degrees down), 30 m
and 300 m up. PSNR in dB; the renderers promise >= 38 dB.

The cost half: OpenGL milliseconds per 1920 x 1080 frame (the demo's
ground view, offscreen, no read-back) and the CPU reference renderer's
throughput, at each anisotropy, side by side in one run. The anisotropic
path also takes the CPU renderer off its fast kernel (isotropic trilinear
only), so its cost there is larger than in GL.

Run: ``python benchmarks/bench_anisotropy.py [--size HxW] [--frames N]``.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

ANISOTROPIES = (1.0, 2.0, 4.0, 8.0, 16.0)


def full_contrast_texture(side=256, rng=2):
    """The paper preset on its own tile stretched to the tile's 1st-99th percentiles."""
    from spectex.texture import SpectralTexture
    from spectex.tiles import make_tile

    tile = make_tile(side, rng=rng)
    lo, hi = np.percentile(tile[..., :3], [1.0, 99.0], axis=(0, 1))
    tile[..., :3] = np.clip((tile[..., :3] - lo) / (hi - lo), 0.0, 1.0)
    return SpectralTexture.paper_preset(tile, blend="alpha", detail=False)  # the paper's (issue 18's numbers)


def views():
    """The four views of issue 18's measurement."""
    from spectex.render import Camera

    return {
        "close": Camera((3.0, 4.0, 1.5), yaw=20.0, pitch=-50.0),
        "grazing": Camera((50.0, -20.0, 1.7), yaw=100.0, pitch=-3.0),
        "30 m": Camera((0.0, 0.0, 30.0), yaw=10.0, pitch=-20.0),
        "300 m": Camera((0.0, 0.0, 300.0), yaw=10.0, pitch=-25.0),
    }


def psnr(a, b):
    return float(10.0 * np.log10(1.0 / np.mean((np.asarray(a, np.float64) - b) ** 2)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", default="180x320", help="HxW of the quality renders (default 180x320)")
    parser.add_argument("--frames", type=int, default=10, help="GL frames per timing (default 10)")
    parser.add_argument("--repeats", type=int, default=3, help="best of this many timings (default 3)")
    parser.add_argument("--no-quality", action="store_true", help="timings only")
    args = parser.parse_args(argv)
    h, w = (int(v) for v in args.size.lower().split("x"))
    size = (h, w)

    from spectex.render import Camera
    from spectex.render.cpu import render_cpu

    texture = full_contrast_texture()
    try:
        from spectex.render.gl import GLRenderer, GLUnavailable

        renderer = GLRenderer(texture)
        device = renderer.ctx.info["GL_RENDERER"]
    except GLUnavailable as exc:  # pragma: no cover - depends on the machine
        renderer, device = None, f"no OpenGL ({exc})"
    print(f"spectex anisotropy benchmark; OpenGL: {device}; load average {os.getloadavg()[0]:.2f}")

    if not args.no_quality:
        print(f"\nPSNR (dB) against an 8 x 8 supersampled truth, {w}x{h}, full-contrast tile")
        print(f"{'view':10s}" + "".join(f"{'CPU a=' + format(a, 'g'):>10s}" for a in ANISOTROPIES)
              + "".join(f"{'GL a=' + format(a, 'g'):>10s}" for a in ANISOTROPIES))
        worst_cpu = {a: np.inf for a in ANISOTROPIES}
        for name, cam in views().items():
            truth = render_cpu(texture, cam, size, filter="linear", supersample=8)
            cpu = [psnr(render_cpu(texture, cam, size, anisotropy=a), truth) for a in ANISOTROPIES]
            gl = ([psnr(renderer.render(cam, size, anisotropy=a), truth) for a in ANISOTROPIES]
                  if renderer is not None else [float("nan")] * len(ANISOTROPIES))
            for a, v in zip(ANISOTROPIES, cpu):
                worst_cpu[a] = min(worst_cpu[a], v)
            print(f"{name:10s}" + "".join(f"{v:10.2f}" for v in cpu) + "".join(f"{v:10.2f}" for v in gl))
        print(f"{'worst':10s}" + "".join(f"{worst_cpu[a]:10.2f}" for a in ANISOTROPIES))

    # ---- cost
    ground = Camera((0.0, 0.0, 2.5), yaw=35.0, pitch=-9.0, fov=60.0)  # the demo's ground view
    big = (1080, 1920)
    render_cpu(texture, ground, (16, 16))
    render_cpu(texture, ground, (16, 16), anisotropy=8.0)  # compile both kernels outside the timing
    print(f"\ncost, 1920x1080 ground view (best of {args.repeats}; load average {os.getloadavg()[0]:.2f})")
    print(f"{'anisotropy':>12s}{'GL ms/frame':>14s}{'GL ratio':>10s}{'CPU Mpx/s':>12s}{'CPU ratio':>11s}")
    base_gl = base_cpu = None
    for a in ANISOTROPIES:
        gl_ms = float("nan")
        if renderer is not None:
            gl_ms = 1000.0 * min(renderer.time_frames(ground, big, frames=args.frames, anisotropy=a)
                                 for _ in range(args.repeats))
        best = float("inf")
        for _ in range(args.repeats):
            t = time.perf_counter()
            render_cpu(texture, ground, (540, 960), anisotropy=a)
            best = min(best, time.perf_counter() - t)
        mpx = 540 * 960 / best / 1e6
        base_gl = base_gl or gl_ms
        base_cpu = base_cpu or mpx
        print(f"{a:12g}{gl_ms:14.1f}{gl_ms / base_gl:10.2f}{mpx:12.2f}{base_cpu / mpx:11.2f}")
    if renderer is not None:
        renderer.release()


if __name__ == "__main__":
    main()
