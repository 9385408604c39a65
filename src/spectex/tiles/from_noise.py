"""Tiles from noise: :func:`make_tile`, the seamless low-pass RGBA tile of Berger (2006).

The spectral texture of Berger (2006) is built from one tile: low-pass
filtered random noise, coloured through a ramp, seamless, with an alpha
channel derived from the colour by an emboss filter (:func:`spectex.tiles.emboss`).

How a tile is made (:func:`make_tile`)
--------------------------------------
1. A zero-mean scalar field on a *working grid* ``m`` times coarser than the
   tile, ``m`` the largest whole number with ``m <= 1 / (2 cutoff)`` that
   divides both sides (2 for the default cut-off of 0.25 cycles per pixel;
   1 for odd sizes). The working grid's Nyquist frequency is then at or above
   the cut-off, so it holds everything the tile may hold. The field comes
   from ``method``: ``'spectral'`` (FFT ``1/f^beta`` noise,
   :func:`spectex.spectral.spectral_noise`), ``'octaves'`` (a sum of octaves
   by filtering under magnification, :func:`spectex.spectral.octave_sum`) or
   ``'noise'`` (fractal Perlin noise from :mod:`spectex.procedural`).
2. Colour: the field is standardised and mapped to ``t = Phi(field)`` (the
   normal CDF: uniform for Gaussian noise, so every colour of the ramp is
   used equally, a full-contrast tile) and through the colour ramp (the
   piecewise-linear interpolation of :func:`spectex.color.apply_colormap`,
   fused with ``Phi`` in one numba kernel; the tests check they agree).
3. Low-pass and upsample: each channel is band-limited to radial frequency
   ``cutoff`` and sampled on the tile's grid by Fourier interpolation
   (:func:`spectex.spectral.band_limit`); if a channel then leaves [0, 1]
   (ringing) it is mapped back by an affine map (:func:`fit_range`), which
   keeps the band limit.
4. Alpha (``alpha=``): ``'emboss'`` (the paper's choice, :func:`emboss` of
   the colour's luma), ``'luminance'`` (the colour's Rec. 709 luma),
   ``'noise'`` (an independent field through the same steps) or ``'none'``
   (the constant ``alpha_value``: plain detail texturing).

Every step is periodic (FFTs, wrap-around differences), so the tile is
seamless.

The cut-off
-----------
No colour or alpha energy lies above the radial frequency ``cutoff``
(default 0.25 cycles per pixel, half the Nyquist frequency: no wavelength
shorter than 4 texels). Bilinear magnification multiplies the spectrum by
``sinc^2(f)`` (``f`` in cycles per texel) and adds images of it at
``1 - f``, ``1 + f``, ...: a component at the cut-off keeps 81 % of its
amplitude and its strongest image, at 0.75, has ``sinc^2(0.75) = 0.09``
(-21 dB), whereas content at the Nyquist frequency would have an image as
strong as itself (0.41 each), which is what the facets and the diamond
pattern of bilinear magnification are. So the tile shows no magnification
artefacts (Berger: "low-pass filtered to such a degree that they do not
produce artifacts when magnified"). This holds for the float tile; quantisation to 8 bits adds a
white noise floor about 59 dB below full scale. An emboss ``strength``
above 1 clips the alpha channel, which is band-limited again after
clipping.

References
----------
D. R. Berger, "Spectral texturing for real-time applications", SIGGRAPH
2006 sketch.
"""

from __future__ import annotations

import numpy as np

from .._limits import MAX_TILE_SIDE
from .._parallel import threads_for as _threads_for
from .._validate import check_choice, check_float, check_int, check_rng, check_shape
from ..color import LUMA_REC709
from .ops import _emboss, fit_range

__all__ = ["METHODS", "ALPHAS", "MAX_SIZE", "make_tile"]

METHODS = ("spectral", "octaves", "noise")
ALPHAS = ("emboss", "luminance", "noise", "none")

#: Largest tile side accepted by :func:`make_tile` (memory at 8192 x 8192:
#: 1 GiB for the tile, about 3 GiB at the peak with the FFT work space); its home is
#: :mod:`spectex._limits`, so that the command line checks it before importing numba.
MAX_SIZE = MAX_TILE_SIDE

# Rec. 709 luma weights for the NumPy steps (``tiles._kernels`` takes the same from spectex.color).
_LUMA_R, _LUMA_G, _LUMA_B = LUMA_REC709


#: Below this many values, make_tile's pixel steps run in NumPy: on a 512 x 512
#: tile (the demo's) they take milliseconds, while loading three cached parallel
#: numba kernels took 2 s, and compiling them on a fresh install most of a minute.
NUMPY_MAX = 1 << 21


def _kernels():
    """The numba pixel kernels (``tiles._kernels``), imported only where a tile is large enough to use them."""
    from . import _kernels

    return _kernels


def _ramp_numpy(field, pos, col, out):
    """``tiles._kernels.ramp`` in NumPy (``np.interp`` in float64, the same numbers to float32 rounding)."""
    from scipy.special import erfc

    t = 0.5 * erfc(-field.astype(np.float64) * 0.7071067811865476)
    p = pos.astype(np.float64)
    for c in range(3):
        out[c] = np.interp(t, p, col[:, c].astype(np.float64))


def _interleave_numpy(planes, lo, scale, out, lum):
    """``tiles._kernels.interleave`` in NumPy."""
    nc = planes.shape[0]
    for c in range(nc):
        np.clip((planes[c] - lo[c]) * scale[c], 0.0, 1.0, out=out[:, :, c])
    lum[...] = _LUMA_R * out[:, :, 0].astype(np.float64) + _LUMA_G * out[:, :, 1] + _LUMA_B * out[:, :, 2]


# --------------------------------------------------------------------------
# Tiles from noise
# --------------------------------------------------------------------------

def _working_factor(h: int, w: int, cutoff: float) -> int:
    """Largest m <= 1 / (2 cutoff) dividing h and w (the working grid step).

    The search starts at most at ``min(h, w) // 4`` (the grid keeps at least
    4 cells a side), so its cost is bounded by the tile size, not by
    ``1 / cutoff``.
    """
    top = max(1, min(int(min(0.5 / cutoff + 1e-9, 1 << 30)), min(h, w) // 4))
    for m in range(top, 0, -1):
        if h % m == 0 and w % m == 0 and min(h, w) // m >= 4:
            return m
    return 1


def _standardise(field: np.ndarray) -> np.ndarray:
    field = field.astype(np.float32, copy=False)
    field = field - np.float32(field.mean(dtype=np.float64))
    std = float(np.sqrt(np.mean(np.square(field, dtype=np.float64))))
    if std > 0:
        field *= np.float32(1.0 / std)
    return field


def _to_unit(field: np.ndarray) -> np.ndarray:
    """Standardise and map through the normal CDF: uniform for Gaussian noise."""
    from scipy.special import ndtr

    return ndtr(_standardise(field)).astype(np.float32, copy=False)


def _field(method, shape, m, rng, *, beta, low, octaves, kernel, noise_scale):
    """The scalar field on the working grid ``shape``; frequencies per tile pixel."""
    from ..spectral import octave_sum, spectral_noise

    if method == "spectral":
        return spectral_noise(shape, beta=beta, low=None if low is None else low * m, rng=rng)
    if method == "octaves":
        return octave_sum(shape, amplitudes=beta, octaves=octaves, kernel=kernel, rng=rng)
    try:
        from ..procedural import noise_image
    except ImportError as exc:
        raise ValueError(f"method='noise' needs spectex.procedural, which is not available ({exc})") from None
    seed = int(rng.integers(0, 2**31 - 1))
    field = noise_image(shape, kind="fbm", scale=noise_scale, octaves=octaves if octaves else 6,
                        seed=seed, tileable=True)
    # Lattice noise is not stationary (zero on lattice lines): a random
    # periodic shift keeps the lattice lines off the wrap edge.
    return np.roll(field, (int(rng.integers(0, shape[0])), int(rng.integers(0, shape[1]))), axis=(0, 1))


def _check_octave_size(h, w, small, octaves):
    n = min(small)
    count = octaves
    if count is None:
        count = 0
        while 4 * 2 ** count <= n // 2:
            count += 1
    finest = 4 * 2 ** max(count - 1, 0)
    if count == 0 or small[0] % finest or small[1] % finest:
        step = finest * (h // small[0])
        raise ValueError(f"shape {w}x{h} does not suit method='octaves' with {max(count, 1)} octaves: "
                         f"each side must be a multiple of {step} (powers of two always work); "
                         f"method='spectral' takes any size")


def make_tile(shape=512, *, rng=0, method: str = "spectral", alpha: str = "emboss",
              colormap="earth", cutoff: float = 0.25, beta: float = 2.0, low: float | None = None,
              octaves: int | None = None, kernel: str = "bspline", noise_scale: float = 4.0,
              azimuth: float = 135.0, strength: float = 1.0, alpha_value: float = 0.5) -> np.ndarray:
    """A seamless, low-pass RGBA tile of coloured random noise (Berger 2006).

    See the module docstring for the steps and the cut-off.

    Parameters
    ----------
    shape : int or (int, int)
        Tile side, or ``(height, width)``; 8 to ``MAX_SIZE`` (8192).
        ``method='octaves'`` needs sides that are multiples of its finest
        octave's cells on the working grid (powers of two always work).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
        The colour field and the alpha noise use independent streams
        spawned from it.
    method : {'spectral', 'octaves', 'noise'}
        Where the scalar field comes from (step 1).
    alpha : {'emboss', 'luminance', 'noise', 'none'}
        How the alpha channel is made (step 4).
    colormap : str or sequence of (float, (r, g, b))
        A ramp for :func:`spectex.color.apply_colormap` (``'earth'``,
        ``'stone'``, ``'moss'``, ... or any Matplotlib name, or stops).
    cutoff : float
        The low-pass cut-off in cycles per pixel, in [1 / max(H, W), 0.5]:
        no energy above it (below one cycle across the tile, nothing but the
        mean would be left). The default 0.25 is half the Nyquist frequency.
    beta : float
        Spectral exponent of the field (power ``~ 1/f^beta``) for
        ``'spectral'`` and ``'octaves'``.
    low : float or None
        Low cut-off of the field, cycles per pixel (``'spectral'`` only):
        removes the largest blobs, which make repetition easier to see.
    octaves : int or None
        Number of octaves for ``'octaves'`` and ``'noise'``.
    kernel : str
        Magnification kernel for ``'octaves'`` (see
        :func:`spectex.spectral.magnify`).
    noise_scale : float
        Lattice cells across the tile for ``'noise'``.
    azimuth, strength : float
        Emboss light direction (degrees) and contrast (see :func:`emboss`).
    alpha_value : float
        The constant alpha of ``alpha='none'``, in [0, 1].

    Returns
    -------
    ndarray, shape (H, W, 4), float32 in [0, 1]
        Straight (not premultiplied) RGBA.
    """
    from ..color import get_ramp
    from ..spectral import band_limit_planes

    h, w = check_shape("shape", shape)
    if min(h, w) < 8 or max(h, w) > MAX_SIZE:
        raise ValueError(f"shape must be between 8 and {MAX_SIZE} on each side, got {w}x{h}")
    rng = check_rng(rng)
    method = check_choice("method", method, METHODS)
    alpha = check_choice("alpha", alpha, ALPHAS)
    from ..spectral import FILTERS

    kernel = check_choice("kernel", kernel, FILTERS)
    cutoff = check_float("cutoff", cutoff, minimum=0.0, maximum=0.5, exclusive_minimum=True)
    if cutoff * max(h, w) < 1.0:
        raise ValueError(f"cutoff must be at least 1/{max(h, w)} = {1.0 / max(h, w):.4g} cycles per pixel "
                         f"(one cycle across the {w}x{h} tile; below it the tile is flat), got {cutoff:g}")
    beta = check_float("beta", beta, minimum=-2.0, maximum=8.0)
    if low is not None:
        low = check_float("low", low, minimum=0.0, maximum=0.5)
        if not low < cutoff:
            raise ValueError(f"low must be below cutoff={cutoff}, got {low}")
    if octaves is not None:
        octaves = check_int("octaves", octaves, minimum=1, maximum=16)
    noise_scale = check_float("noise_scale", noise_scale, minimum=0.0, exclusive_minimum=True,
                              maximum=float(min(h, w)))
    azimuth = check_float("azimuth", azimuth)
    strength = check_float("strength", strength, minimum=0.0, maximum=1e6)
    alpha_value = check_float("alpha_value", alpha_value, minimum=0.0, maximum=1.0)

    m = _working_factor(h, w, cutoff)
    small = (h // m, w // m)
    rng_colour, rng_alpha = rng.spawn(2)
    kw = dict(beta=beta, low=low, octaves=octaves, kernel=kernel, noise_scale=noise_scale)
    if method == "octaves":
        _check_octave_size(h, w, small, octaves)
    field = _field(method, small, m, rng_colour, **kw)
    pos, col = get_ramp(colormap)
    nplanes = 4 if alpha == "noise" else 3
    planes = np.empty((nplanes,) + small, dtype=np.float32)
    ramp = _ramp_numpy if planes.size <= NUMPY_MAX else _kernels().ramp
    with _threads_for(planes.size):
        ramp(_standardise(field), pos.astype(np.float32), col[:, :3].astype(np.float32), planes)
    if alpha == "noise":
        planes[3] = _to_unit(_field(method, small, m, rng_alpha, **kw))
    planes = band_limit_planes(planes, high=cutoff, shape=(h, w))
    # fit_range per channel, fused with the interleaving.
    lo = np.zeros(4, dtype=np.float32)
    scale = np.ones(4, dtype=np.float32)
    for c in range(nplanes):
        a, b = float(planes[c].min()), float(planes[c].max())
        if a < 0.0 or b > 1.0:
            lo[c], scale[c] = min(a, 0.0), 1.0 / (max(b, 1.0) - min(a, 0.0))
    out = np.empty((h, w, 4), dtype=np.float32)
    lum = np.empty((h, w), dtype=np.float32)
    interleave = _interleave_numpy if out.size <= NUMPY_MAX else _kernels().interleave
    with _threads_for(out.size):
        interleave(planes, lo, scale, out, lum)
    del planes
    if alpha == "emboss":
        a = _emboss(lum, azimuth, strength)
        if strength > 1.0:  # clipped: band-limit again
            a = fit_range(band_limit_planes(a[None], high=cutoff, shape=(h, w))[0])
        out[:, :, 3] = a
    elif alpha == "luminance":
        out[:, :, 3] = lum
    elif alpha == "none":
        out[:, :, 3] = alpha_value
    return out
