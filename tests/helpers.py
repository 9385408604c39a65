"""Helpers shared by the tests, imported as ``from helpers import ...``.

``tests/`` is on the import path through pytest's ``pythonpath`` setting
(pyproject.toml); fixtures stay in ``conftest.py``.
"""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

from spectex.render import Camera

#: The renderers' test picture, (H, W).
SIZE = (180, 320)

#: The renderers' test views: from a close-up to straight down from 2.5 km.
VIEWS = {
    "close": Camera((3.0, 4.0, 1.5), yaw=20.0, pitch=-50.0),
    "ground": Camera((0.0, 0.0, 2.0), yaw=30.0, pitch=-12.0),
    "grazing": Camera((50.0, -20.0, 1.7), yaw=100.0, pitch=-3.0),
    "aerial": Camera((0.0, 0.0, 400.0), yaw=10.0, pitch=-35.0),
    "high": Camera((100.0, 300.0, 2500.0), yaw=10.0, pitch=-90.0),
}


def make_test_tile(n=256, seed=0, *, cutoff=0.25, beta=1.5):
    """A seamless, full-contrast RGBA tile: FFT-filtered noise, each channel
    stretched to [0, 1]; alpha is an emboss (wrap-around directional
    difference) of the luminance, like the paper's."""
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(n)
    r = np.hypot(f[:, None], f[None, :])
    r[0, 0] = 1.0
    amp = r ** -beta * (r < cutoff * 0.5)
    amp[0, 0] = 0.0

    def field():
        x = np.real(np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * amp))
        return (x - x.min()) / (x.max() - x.min())

    lum = field()
    hue = field()
    col = np.stack([lum, 0.7 * lum + 0.3 * hue, 0.5 * lum + 0.5 * (1 - hue)], axis=-1)
    col = (col - col.min(axis=(0, 1))) / (col.max(axis=(0, 1)) - col.min(axis=(0, 1)))
    emb = (np.roll(lum, 1, 1) - np.roll(lum, -1, 1)) + (np.roll(lum, 1, 0) - np.roll(lum, -1, 0))
    alpha = np.clip(0.5 + emb / (4.0 * emb.std()), 0.0, 1.0)
    return np.concatenate([col, alpha[..., None]], axis=-1).astype(np.float32)


def psnr(image, reference) -> float:
    """Peak signal-to-noise ratio of ``image`` against ``reference`` (values in [0, 1]), dB; inf if equal."""
    mse = float(np.mean((np.asarray(image, np.float64) - np.asarray(reference, np.float64)) ** 2))
    return float("inf") if mse == 0 else 10.0 * np.log10(1.0 / mse)


def psnr_low(image, reference, sigma: float = 1.0) -> float:
    """:func:`psnr` of ``image`` and ``reference`` both low-passed by a Gaussian of ``sigma`` pixels.

    The alias measure of a mip-mapped render against a supersampled one: with ``sigma = 1`` it keeps
    the frequencies below about a quarter of the pixel's Nyquist (at 1/8 cycle per pixel 0.73 of the
    amplitude, at 1/4 0.29, at 1/2 none), where aliasing (energy from above the Nyquist folded down)
    lands as much as anywhere, and where a filter's shape does not count: the trilinear filter and the
    reference's box over the pixel differ by design near the Nyquist, on a sharp edge by several dB
    (``docs/fitting.md``, "GL = CPU and aliasing")."""
    from scipy import ndimage

    def low(a):
        a = np.asarray(a, np.float64)
        return ndimage.gaussian_filter(a, (sigma, sigma) + (0,) * (a.ndim - 2), mode="nearest")

    return psnr(low(image), low(reference))


def floor_photo(side=512, period=64, grout=5, rng=11, spread=0.035, mottle=0.05):
    """Square floor tiles of random terracottas with mottling, in light grout lines centred on the periods'
    edges (a crop from 0 wraps on the grout); RGB float32 (benchmarks/exemplars.py's ``tiles``), and the
    grout's mask."""
    from scipy import ndimage

    rng = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side]
    k = (yy // period) * (side // period + 1) + xx // period
    colour = np.array([0.62, 0.42, 0.30]) + rng.normal(0.0, spread, (k.max() + 1, 3))
    noise = ndimage.gaussian_filter(rng.standard_normal((side, side)), 3.0, mode="wrap")
    img = colour[k] * (1.0 + mottle * noise[:, :, None] / noise.std())
    fy, fx = yy % period, xx % period
    g = (np.minimum(fy, period - 1 - fy) < grout / 2) | (np.minimum(fx, period - 1 - fx) < grout / 2)
    img[g] = (0.78 + 0.02 * rng.standard_normal(int(g.sum())))[:, None] * np.array([1.0, 0.97, 0.92])
    return np.clip(img, 0.0, 1.0).astype(np.float32), g


#: The colour of the leaf :func:`with_leaves` pastes (gravel and grass are grey).
ORANGE = (0.85, 0.55, 0.1)


def with_leaves(grey, leaves):
    """A grey photo as RGB float32 with leaves pasted on it, ``(cy, cx, length, colour)`` each (an ellipse
    0.45 times as wide as long): content the photo shows once, as a leaf on gravel (issue 22's one-off
    content; benchmarks/exemplars.py's ``with_leaf``)."""
    rgb = np.repeat(np.asarray(grey, np.float32)[:, :, None], 3, axis=2)
    yy, xx = np.mgrid[:rgb.shape[0], :rgb.shape[1]]
    for cy, cx, r, colour in leaves:
        rgb[((yy - cy) / r) ** 2 + ((xx - cx) / (0.45 * r)) ** 2 <= 1.0] = colour
    return rgb


def pieces(photo, n=3, rng=0):
    """An n x n mosaic of ``photo``, each copy rolled by its own offset: a texture made of its pieces (every
    piece carries whatever drift of light or scale the photo has; tests of issue 22's photo faults)."""
    rng = np.random.default_rng(rng)
    return np.concatenate([np.concatenate([np.roll(photo, tuple(rng.integers(0, photo.shape[0], 2)), axis=(0, 1))
                                           for _ in range(n)], axis=1) for _ in range(n)], axis=0)


def spectex_fit_says(tmp_path, capsys, photo, flag):
    """``spectex fit`` of ``photo`` (written as ``photo.png``): its output and its report's structure line;
    checks that ``flag`` (``--keep-...``) parses to True and is False without it. Returns ``(output, line,
    path of the photo)``."""
    from spectex import io
    from spectex.cli import build_parser, main

    path = tmp_path / "photo.png"
    io.write_image(path, np.asarray(photo, np.float32))
    assert main(["fit", str(path), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.strip().startswith("structure"))
    parser, dest = build_parser(), flag.lstrip("-").replace("-", "_")
    assert getattr(parser.parse_args(["fit", str(path), "-o", "o", flag]), dest) is True
    assert getattr(parser.parse_args(["fit", str(path), "-o", "o"]), dest) is False
    return out, line, path


def spectex_compare_line(tmp_path, capsys, image, reference, start):
    """The line of ``spectex compare IMAGE --reference REFERENCE`` (the image saved as .npy, the reference a
    path) that starts with ``start``."""
    from spectex.cli import main

    np.save(tmp_path / "image.npy", np.asarray(image, np.float32))
    assert main(["compare", str(tmp_path / "image.npy"), "--reference", str(reference)]) == 0
    return next(x for x in capsys.readouterr().out.splitlines() if x.startswith(start))


def error_line(capsys) -> str:
    """The one line a refused command wrote on standard error."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def run_fails(argv, capsys, *outputs) -> str:
    """``spectex argv`` is refused: exit status 2 (argparse's own errors included), one line on
    standard error that says so, none of ``outputs`` written. Returns the line."""
    from spectex.cli import main

    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1 and "error" in err[0], err
    for path in outputs:
        assert not path.exists(), f"{path} was written"
    return err[0]


def glslang_validator() -> str:
    """Path of Debian's ``glslangValidator`` (glslang-tools): a skip without it, a failure under CI=true."""
    path = shutil.which("glslangValidator")
    if path is None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("glslangValidator is missing: CI must have it (apt-get install glslang-tools)")
        pytest.skip("glslangValidator is missing (apt-get install glslang-tools)")
    return path


def assert_gl_matches_cpu(tex, gl):
    """GL = CPU >= 40 dB on every test view (:data:`VIEWS`) of ``tex``."""
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer

    with GLRenderer(tex, ctx=gl) as r:
        for name, cam in VIEWS.items():
            c = render_cpu(tex, cam, SIZE)
            g = r.render(cam, SIZE)
            assert psnr(g, c) >= 40.0, (name, psnr(g, c))


def views_against_reference(texture, gl):
    """For each of VIEWS: ``(name, camera, CPU render, GL render, reference, render without mip-maps)``,
    the reference 16 x 16 supersampled without mip-maps; GL = CPU >= 40 dB asserted on the way."""
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer

    with GLRenderer(texture, ctx=gl) as r:
        for name, cam in VIEWS.items():
            c = render_cpu(texture, cam, SIZE)
            g = r.render(cam, SIZE)
            assert psnr(g, c) >= 40.0, (name, psnr(g, c))
            ref = render_cpu(texture, cam, SIZE, filter="linear", supersample=16)
            yield name, cam, c, g, ref, render_cpu(texture, cam, SIZE, filter="linear")


def fast_and_general(tex, position, shape):
    """A view of ``tex`` from a camera at ``position`` (yaw 40, pitch -35, fov 60), ``shape`` pixels, drawn by the
    CPU's fast kernel and by its general one: ``(fast, general)``."""
    from spectex.shading import pack, view_params
    from spectex.shading.tables import anchor_coords
    from spectex.shading.view import render_kernel, render_kernel_fast, row_order

    tables = pack(tex)
    cam = Camera(position, yaw=40.0, pitch=-35.0, fov=60.0)
    view = view_params(cam, shape, supersample=1)
    anchor = anchor_coords(tex.layers, *cam.position[:2])
    fast = np.empty(shape + (3,), np.float32)
    general = np.empty(shape + (3,), np.float32)
    render_kernel_fast(tables, anchor, view, row_order(shape[0]), fast)
    render_kernel(tables, anchor, view, row_order(shape[0]), general)
    return fast, general


def fast_path_against_general(tex):
    """A 48 x 64 view of ``tex`` (a layer with a cell map, fast-path sampler state) drawn by the CPU's fast kernel
    and by its general one: ``(fast, general)``."""
    from spectex.shading import pack

    tables = pack(tex)
    assert tables.fast and tables.cell_row[0] >= 0
    return fast_and_general(tex, (3.0e1, -2.0e1, 1.5), (48, 64))
