"""Procedural textures from noise (seed 002).

Images of noise, fractal sums and turbulence; non-linear mappings (marble:
``sin(k x + a * turbulence)``, wood rings); spatial regularities (noise
times ``sin`` of x); animation by moving through slices of 3-D noise. Every
function returns a scalar field, ``(H, W)`` float32; colour comes from
:func:`spectex.color.apply_colormap` (or :func:`colorize` here).

Coordinates: ``scale`` is the number of noise lattice cells across the
image width; pixel centres sit at ``(j + 0.5) / W * scale``. With
``tileable=True`` the noise is made periodic with the image: the period is
``round(scale)`` cells across and ``max(1, round(scale * H / W))`` down, so
the image tiles seamlessly (the cells are then very slightly non-square where
``scale * H / W`` is not a whole number).
"""

from __future__ import annotations

import math

import numpy as np

from . import noise
from ._validate import check_choice, check_float, check_int, check_seed, check_shape

__all__ = ["KINDS", "noise_image", "marble", "wood", "stripes", "clouds", "ring_profile", "texture",
           "value_range", "contrast_range", "colorize", "animate"]

KINDS = ("perlin", "value", "fbm", "turbulence", "marble", "wood", "stripes", "clouds")
_TIME_PERIOD = 1 << 16  # period of the time axis of tileable animations (lattice cells)


def _grid(shape, scale, tileable, time):
    """Broadcastable coordinates (and the period) for an image of ``shape``."""
    h, w = shape
    if tileable:
        px = int(round(scale))
        if px < 1:
            raise ValueError(f"scale must be >= 0.5 for a tileable image, got {scale}")
        py = max(1, int(round(scale * h / w)))
        sx, sy = px / w, py / h
        period = (px, py) if time is None else (px, py, _TIME_PERIOD)
    else:
        sx = sy = scale / w
        period = None
    x = ((np.arange(w, dtype=np.float64) + 0.5) * sx).astype(np.float32)[None, :]
    y = ((np.arange(h, dtype=np.float64) + 0.5) * sy).astype(np.float32)[:, None]
    if time is None:
        return (x, y), period
    t = np.float32(time)
    return (x, y, t), period


def _check_common(shape, scale, octaves, seed, time):
    shape = check_shape("shape", shape)
    scale = check_float("scale", scale, minimum=0.0, exclusive_minimum=True, maximum=1e6)
    octaves = check_int("octaves", octaves, minimum=1, maximum=32)
    seed = check_seed("seed", seed)
    if time is not None:
        time = check_float("time", time)
    return shape, scale, octaves, seed, time


def noise_image(shape, *, kind="fbm", scale=4.0, octaves=6, lacunarity=2.0, gain=0.5, seed=0,
                basis="perlin", tileable=False, time=None):
    """An image of noise.

    Parameters
    ----------
    shape : int or (int, int)
        ``(height, width)`` in pixels.
    kind : {"perlin", "value", "fbm", "turbulence"}
        Single-octave Perlin or value noise, or a fractal sum of ``basis``.
    scale : float
        Lattice cells (first octave) across the image width.
    octaves, lacunarity, gain : int, float, float
        Fractal parameters (see :func:`spectex.noise.fbm`); ignored for the
        single-octave kinds.
    seed : int or None
        ``None`` gives Ken Perlin's permutation.
    basis : {"perlin", "value"}
        The noise summed by ``"fbm"`` and ``"turbulence"``.
    tileable : bool
        Make the image tile seamlessly (see the module docstring).
    time : float, optional
        Take the image as the slice ``z = time`` of 3-D noise, for animation.

    Returns
    -------
    ndarray, shape (H, W), float32
        In [-1, 1] (turbulence in [0, 1]; 3-D Perlin reaches about +-1.04).
    """
    kind = check_choice("kind", kind, ("perlin", "value", "fbm", "turbulence"))
    shape, scale, octaves, seed, time = _check_common(shape, scale, octaves, seed, time)
    coords, period = _grid(shape, scale, tileable, time)
    if kind == "perlin":
        return noise.perlin(*coords, seed=seed, period=period)
    if kind == "value":
        return noise.value(*coords, seed=0 if seed is None else seed, period=period)
    fn = noise.fbm if kind == "fbm" else noise.turbulence
    return fn(*coords, basis=basis, octaves=octaves, lacunarity=lacunarity, gain=gain, seed=seed,
              period=period)


def marble(shape, *, scale=4.0, stripes=3.0, strength=1.2, octaves=6, seed=0, tileable=False,
           time=None):
    """Marble: ``sin(2 pi (stripes * u + strength * turbulence))`` (seed 002).

    ``u`` runs from 0 to 1 across the image; the turbulence (Perlin, ``octaves``
    octaves, ``scale`` cells across) bends the stripes into veins. With
    ``tileable=True``, ``stripes`` is rounded to a whole number so the image
    tiles. Returns values in [-1, 1].
    """
    shape, scale, octaves, seed, time = _check_common(shape, scale, octaves, seed, time)
    stripes = check_float("stripes", stripes, minimum=0.0)
    strength = check_float("strength", strength, minimum=0.0)
    if tileable:
        stripes = float(round(stripes))
    turb = noise_image(shape, kind="turbulence", scale=scale, octaves=octaves, seed=seed,
                       tileable=tileable, time=time)
    u = ((np.arange(shape[1], dtype=np.float32) + np.float32(0.5)) / np.float32(shape[1]))[None, :]
    phase = np.float32(stripes) * u + np.float32(strength) * turb
    return np.sin(np.float32(2 * np.pi) * phase).astype(np.float32)


def wood(shape, *, scale=2.0, rings=10.0, strength=1.0, octaves=3, seed=0, time=None):
    """Wood: concentric rings ``frac(rings * r + strength * fbm)``.

    ``r`` is the distance from the image centre in image widths. The ring
    profile is sharpened (early wood light, late wood dark): ``p(x) = 2 x^3
    - 1`` of the ring phase ``x = frac(t)``, which jumps from 1 back to -1 at
    each ring edge. Each pixel gets the mean of ``p`` over the phases its
    footprint covers (an analytic box filter: ``P(t) = floor(t) P(1) +
    P(frac(t))`` with ``P(x) = x^4 / 2 - x`` the integral of ``p``, over the
    footprint width ``|grad t|``), so the ring edges are anti-aliased
    instead of stair-stepped. Radial, so not tileable. Returns values in
    [-1, 1].
    """
    shape, scale, octaves, seed, time = _check_common(shape, scale, octaves, seed, time)
    rings = check_float("rings", rings, minimum=0.0)
    strength = check_float("strength", strength, minimum=0.0)
    h, w = shape
    n = noise_image(shape, kind="fbm", scale=scale, octaves=octaves, seed=seed, time=time)
    u = ((np.arange(w, dtype=np.float64) + 0.5) / w - 0.5)[None, :]
    v = ((np.arange(h, dtype=np.float64) + 0.5) / w - 0.5 * h / w)[:, None]
    t = rings * np.sqrt(u * u + v * v) + strength * n.astype(np.float64)
    return ring_profile(t, _footprint(t)).astype(np.float32)


def _footprint(t: np.ndarray) -> np.ndarray:
    """Per pixel, how far ``t`` moves across one pixel: the longer of its
    central differences along the rows and the columns (one-sided at the
    edges, 0 for a single row or column)."""
    widths = [np.abs(np.gradient(t, axis=a)) if t.shape[a] > 1 else np.zeros_like(t) for a in (0, 1)]
    return np.maximum(widths[0], widths[1])


def ring_profile(t, width):
    """The wood ring profile ``2 frac(t)^3 - 1``, box-filtered over ``[t - width/2, t + width/2]``.

    ``width = 0`` gives the profile itself; the result is exact for any
    width (the integral of the profile is known in closed form). A
    non-finite ``t`` gives NaN; ``width`` must be finite.
    """
    t = np.asarray(t, dtype=np.float64)
    width = np.asarray(width, dtype=np.float64)
    if not np.all(np.isfinite(width)):
        raise ValueError(f"width must be finite, got {width.ravel()[~np.isfinite(width.ravel())][0]}")
    with np.errstate(invalid="ignore"):  # inf - floor(inf): NaN, the defined result
        return _ring_profile(t, width)


def _ring_profile(t: np.ndarray, width: np.ndarray) -> np.ndarray:

    def integral(x):  # of 2 frac^3 - 1 from 0 to x: -1/2 per whole ring, then P(frac)
        f = x - np.floor(x)
        return -0.5 * np.floor(x) + 0.5 * f ** 4 - f

    frac = t - np.floor(t)
    point = 2.0 * frac ** 3 - 1.0
    wide = width > 1e-6
    safe = np.where(wide, width, 1.0)
    box = (integral(t + 0.5 * safe) - integral(t - 0.5 * safe)) / safe
    return np.where(wide, box, point)


def stripes(shape, *, scale=4.0, frequency=8.0, octaves=5, seed=0, tileable=False, time=None):
    """Spatial regularity (seed 002): noise intensity times ``sin`` of x.

    ``(fbm + 1) / 2 * sin(2 pi frequency u)``, ``u`` from 0 to 1 across; with
    ``tileable=True`` the frequency is rounded to a whole number. Values in [-1, 1].
    """
    shape, scale, octaves, seed, time = _check_common(shape, scale, octaves, seed, time)
    frequency = check_float("frequency", frequency, minimum=0.0)
    if tileable:
        frequency = float(round(frequency))
    n = noise_image(shape, kind="fbm", scale=scale, octaves=octaves, seed=seed, tileable=tileable,
                    time=time)
    u = ((np.arange(shape[1], dtype=np.float32) + 0.5) / shape[1])[None, :]
    wave = np.sin(np.float32(2 * np.pi * frequency) * u)
    return (np.float32(0.5) * (n + np.float32(1.0)) * wave).astype(np.float32)


def clouds(shape, *, scale=3.0, cover=0.5, sharpness=3.0, octaves=7, seed=0, tileable=False,
           time=None):
    """Clouds: fBm through a soft threshold (a non-linear mapping).

    ``cover`` in [0, 1] is roughly the fraction of sky covered; ``sharpness``
    steepens the cloud edges. Returns values in [-1, 1] (-1 clear sky).
    """
    shape, scale, octaves, seed, time = _check_common(shape, scale, octaves, seed, time)
    cover = check_float("cover", cover, minimum=0.0, maximum=1.0)
    sharpness = check_float("sharpness", sharpness, minimum=0.0, exclusive_minimum=True)
    n = noise_image(shape, kind="fbm", scale=scale, octaves=octaves, seed=seed, tileable=tileable,
                    time=time)
    # fBm of Perlin noise has a standard deviation of about 0.2; centre the
    # threshold so that roughly `cover` of the pixels lie above it.
    threshold = np.float32(0.25 * (0.5 - cover) * 2.0)
    return np.tanh(np.float32(sharpness * 4.0) * (n - threshold)).astype(np.float32)


_FIELDS = {"marble": marble, "wood": wood, "stripes": stripes, "clouds": clouds}


def texture(kind, shape, **params):
    """Any of :data:`KINDS` by name: ``texture("marble", (256, 256), seed=3)``."""
    kind = check_choice("kind", kind, KINDS)
    if kind in _FIELDS:
        return _FIELDS[kind](shape, **params)
    return noise_image(shape, kind=kind, **params)


def value_range(kind) -> tuple[float, float]:
    """The documented range of :func:`texture` for ``kind`` (for colour mapping)."""
    kind = check_choice("kind", kind, KINDS)
    return (0.0, 1.0) if kind == "turbulence" else (-1.0, 1.0)


def contrast_range(field, *, kind="fbm") -> tuple[float, float]:
    """The range to map to a colour ramp's ends so the image has full contrast.

    Single-octave noise, fBm and turbulence rarely approach their theoretical
    bounds (fBm of Perlin noise has a standard deviation of about 0.2), so
    mapping the bounds washes the image out. Their range is taken from the
    0.5 and 99.5 percentiles of ``field``; the other kinds use
    :func:`value_range`. Use the same range for every frame of an animation.
    """
    kind = check_choice("kind", kind, KINDS)
    if kind in ("perlin", "value", "fbm", "turbulence"):
        lo, hi = np.nanpercentile(np.asarray(field, dtype=np.float64), [0.5, 99.5])
        if np.isfinite(lo) and np.isfinite(hi) and hi > lo:
            return float(lo), float(hi)
    return value_range(kind)


def colorize(field, colormap="grey", *, kind="fbm", vrange=None):
    """Map a field from :func:`texture` to RGB in [0, 1] through ``colormap``.

    ``vrange=(lo, hi)`` sets the values mapped to the ramp's ends; by default
    :func:`contrast_range`.
    """
    from .color import apply_colormap

    if vrange is None:
        lo, hi = contrast_range(field, kind=kind)
    else:
        try:
            lo, hi = (float(v) for v in vrange)
        except (TypeError, ValueError):
            raise ValueError(f"vrange must be a pair of numbers (lo, hi), got {vrange!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ValueError(f"vrange must be two finite numbers with lo < hi, got {vrange!r}")
    return apply_colormap(field, colormap, vmin=lo, vmax=hi)


def animate(kind, shape, frames, *, speed=0.05, **params):
    """Frames of an animated texture: slices ``z = k * speed`` of 3-D noise.

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    shape : int or (int, int)
        Frame size.
    frames : int
        Number of frames (1 to 10000).
    speed : float
        Lattice units moved along the time axis per frame.
    **params
        Passed to :func:`texture`.

    Returns
    -------
    list of ndarray, each (H, W) float32
    """
    frames = check_int("frames", frames, minimum=1, maximum=10000)
    speed = check_float("speed", speed)
    if "time" in params:
        raise ValueError("time is set per frame by animate; pass speed instead")
    return [texture(kind, shape, time=k * speed, **params) for k in range(frames)]
