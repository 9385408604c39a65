"""Alias measure of fitted textures: mip-mapped renders against 16 x 16 supersampled ones without mip-maps.

Run from the repository root::

    python benchmarks/bench_alias.py                  # tiles and gravel, a few minutes
    python benchmarks/bench_alias.py --only tiles --pictures /tmp/alias

Per texture and test view (``tests/helpers.py``'s ``VIEWS``, 320 x 180): GL against the CPU
renderer, and the CPU and GL mip-mapped renders and a single-sample render without mip-maps (the
control) against ``render_cpu(..., filter="linear", supersample=16)``, as PSNR over the full band
and with both pictures low-passed by a Gaussian of one pixel (``psnr_low``: what aliasing folds
below the Nyquist, without the trilinear filter's shape against the reference's box; see
``docs/fitting.md``, "GL = CPU and aliasing"). ``tiles periodic`` is the fitted tiles with the
finest layer periodic: textbook mip-mapping of the same tile, the measure's floor for it. The
textures: ``fit_result`` of ``exemplars.tiles()`` (rng 0) and of scikit-image's gravel (its 64 x 64
corner at 0.06 m per pixel, one iteration: the texture of ``test_render_stochastic.py``).
``--pictures DIR`` writes, per tiles view, the GL render, the reference and 4 x their difference
side by side.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

from _machine import cpu_name  # noqa: E402
from exemplars import tiles  # noqa: E402

from helpers import SIZE, VIEWS, psnr, psnr_low  # noqa: E402


def textures(only):
    import skimage.data

    from spectex.fitting import fit_result
    from spectex.texture import Layer, SpectralTexture

    out = {}
    if only in (None, "tiles"):
        tex = fit_result(tiles(), rng=0).texture
        out["tiles"] = tex
        first = tex.layers[0]
        periodic = Layer(**{**first.__dict__, "tiling": "periodic", "snap": (0, 0)})
        out["tiles periodic"] = SpectralTexture(tex.tiles, [periodic] + list(tex.layers[1:]))
    if only in (None, "gravel"):
        out["gravel"] = fit_result(skimage.data.gravel()[:64, :64], pixel_size=0.06, iterations=1).texture
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=("tiles", "gravel"))
    parser.add_argument("--pictures", type=Path, help="folder for the tiles' error pictures")
    args = parser.parse_args(argv)

    from spectex._gl import create_context
    from spectex.io import write_image
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer

    ctx = create_context(what="bench_alias")
    print(f"CPU: {cpu_name()}; GL: {ctx.info['GL_RENDERER']}")
    print("texture | view | GL vs CPU | CPU full / low | GL full / low | no mip-maps full / low")
    for name, tex in textures(args.only).items():
        with GLRenderer(tex, ctx=ctx) as r:
            for view, cam in VIEWS.items():
                if name == "tiles periodic" and view in ("aerial", "high"):
                    continue
                ref = render_cpu(tex, cam, SIZE, filter="linear", supersample=16)
                c = render_cpu(tex, cam, SIZE)
                g = r.render(cam, SIZE)
                p = render_cpu(tex, cam, SIZE, filter="linear")
                cols = [f"{psnr(im, ref):.1f} / {psnr_low(im, ref):.1f}" for im in (c, g, p)]
                print(f"{name} | {view} | {psnr(g, c):.1f} | " + " | ".join(cols), flush=True)
                if args.pictures is not None and name == "tiles":
                    diff = np.clip(4.0 * np.abs(g.astype(np.float64) - ref), 0.0, 1.0).astype(np.float32)
                    args.pictures.mkdir(parents=True, exist_ok=True)
                    write_image(args.pictures / f"tiles_{view}.png", np.concatenate([g, ref, diff], axis=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
