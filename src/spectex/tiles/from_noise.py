"""Seamless RGBA tiles, their alpha channels and their mip-map chains.

The spectral texture of Berger (2006) is built from one tile: low-pass
filtered random noise, coloured through a ramp, seamless, with an alpha
channel derived from the colour by an emboss filter. :func:`make_tile` makes
it; :func:`make_seamless` makes a user's photograph into such a tile;
:func:`mip_chain` reduces a tile to the mip-map levels the renderer uploads.

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
2006 sketch. L. Moisan, "Periodic plus smooth image decomposition", JMIV
39(2), 2011. L. Williams, "Pyramidal parametrics", SIGGRAPH 1983 (mip-maps).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ._parallel import threads_for as _threads_for
from ._validate import DEPRECATED, check_choice, check_float, check_image, check_int, check_rng, check_shape
from .color import LUMA_REC709, linear_to_srgb, luma, srgb_to_linear  # re-exported: their home is color

__all__ = [
    "METHODS",
    "ALPHAS",
    "make_tile",
    "make_seamless",
    "emboss",
    "luma",
    "fit_range",
    "mip_chain",
    "preview",
    "srgb_to_linear",
    "linear_to_srgb",
]

METHODS = ("spectral", "octaves", "noise")
ALPHAS = ("emboss", "luminance", "noise", "none")

#: Largest tile side accepted by :func:`make_tile` (memory at 8192 x 8192:
#: 1 GiB for the tile, about 3 GiB at the peak with the FFT work space).
MAX_SIZE = 8192

# Rec. 709 luma weights as numba sees them (module globals are constants to it).
_LUMA_R, _LUMA_G, _LUMA_B = LUMA_REC709


# --------------------------------------------------------------------------
# Pixel kernels (numba; compiled on first use, cached on disk)
# --------------------------------------------------------------------------

@numba.njit(cache=True, parallel=True)
def _ramp_kernel(field, pos, col, out):  # pragma: no cover - compiled
    """out[c, i, j] = ramp_c(Phi(field[i, j])), ramp piecewise linear (np.interp)."""
    h, w = field.shape
    k = pos.shape[0]
    for i in numba.prange(h):
        for j in range(w):
            t = 0.5 * math.erfc(-field[i, j] * 0.7071067811865476)
            if t <= pos[0]:
                for c in range(3):
                    out[c, i, j] = col[0, c]
            elif t >= pos[k - 1]:
                for c in range(3):
                    out[c, i, j] = col[k - 1, c]
            else:
                s = 1
                while pos[s] < t:
                    s += 1
                # pos[s-1] < t <= pos[s], as np.interp
                d = pos[s] - pos[s - 1]
                u = (t - pos[s - 1]) / d if d > 0 else 1.0
                for c in range(3):
                    out[c, i, j] = col[s - 1, c] + u * (col[s, c] - col[s - 1, c])


@numba.njit(cache=True, parallel=True)
def _interleave_kernel(planes, lo, scale, out, lum):  # pragma: no cover - compiled
    """out[i, j, c] = (planes[c, i, j] - lo[c]) scale[c], clipped; lum = Rec. 709 luma."""
    nc, h, w = planes.shape
    for i in numba.prange(h):
        for j in range(w):
            for c in range(nc):
                v = (planes[c, i, j] - lo[c]) * scale[c]
                out[i, j, c] = min(max(v, 0.0), 1.0)
            lum[i, j] = _LUMA_R * out[i, j, 0] + _LUMA_G * out[i, j, 1] + _LUMA_B * out[i, j, 2]


@numba.njit(cache=True, parallel=True)
def _gradient_kernel(h, cx, cy, g):  # pragma: no cover - compiled
    """g = cx (h[i, j+1] - h[i, j-1]) + cy (h[i-1, j] - h[i+1, j]), wrapping."""
    n0, n1 = h.shape
    for i in numba.prange(n0):
        up = i - 1 if i > 0 else n0 - 1
        dn = i + 1 if i < n0 - 1 else 0
        for j in range(n1):
            lf = j - 1 if j > 0 else n1 - 1
            rt = j + 1 if j < n1 - 1 else 0
            g[i, j] = cx * (h[i, rt] - h[i, lf]) + cy * (h[up, j] - h[dn, j])


# --------------------------------------------------------------------------
# Channel helpers
# --------------------------------------------------------------------------

def fit_range(values) -> np.ndarray:
    """Map values into [0, 1] by an affine map, only if they leave it.

    ``(v - lo) / (hi - lo)`` with ``lo = min(0, v.min())`` and
    ``hi = max(1, v.max())``: values already in [0, 1] are returned
    unchanged (as float32); otherwise the range is compressed just enough.
    An affine map adds no frequencies (except at zero), so a band-limited
    channel stays band-limited, which clipping would not.
    """
    v = np.asarray(values, dtype=np.float32)
    if v.size == 0:
        return v
    lo, hi = float(v.min()), float(v.max())
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"values must be finite to be fitted into [0, 1], got a range of {lo} to {hi}")
    if lo >= 0.0 and hi <= 1.0:
        return v
    lo, hi = min(lo, 0.0), max(hi, 1.0)
    out = (v - np.float32(lo)) * np.float32(1.0 / (hi - lo))
    np.clip(out, 0.0, 1.0, out=out)  # rounding only
    return out


def emboss(image, *, azimuth: float = 135.0, strength: float = 1.0) -> np.ndarray:
    """Emboss filter: the image lit as a relief from direction ``azimuth``.

    The image (its luma for colour) is taken as a height field ``h``. With
    the light at ``L = (cos a, sin a)`` (``a`` in degrees counter-clockwise
    from the +x axis, y pointing up, so the default 135 lights from the top
    left), the shading of a gently sloping relief is ``g = -(L . grad h)``,
    with the gradient by central differences that wrap around (so a
    seamless image gives a seamless result)::

        d/dx h[i, j] = (h[i, j+1] - h[i, j-1]) / 2
        d/dy h[i, j] = (h[i-1, j] - h[i+1, j]) / 2      (row 0 is the top)

    and ``alpha = 0.5 + 0.5 strength g / max|g|``, clipped to [0, 1]: slopes
    facing the light are above 0.5. With ``strength <= 1`` nothing is
    clipped and the map is linear, so a band-limited image gives a
    band-limited result; ``strength = 1`` reaches 0 or 1 at the steepest
    slope.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 3 x 3.
    azimuth : float
        Direction of the light, degrees.
    strength : float
        Contrast, >= 0 (0 gives a constant 0.5).

    Returns
    -------
    ndarray, shape (H, W), float32 in [0, 1]
    """
    image = check_image("image", image, min_size=3)
    azimuth = check_float("azimuth", azimuth)
    strength = check_float("strength", strength, minimum=0.0, maximum=1e6)
    return _emboss(luma(image), azimuth, strength)


def _emboss(h: np.ndarray, azimuth: float, strength: float) -> np.ndarray:
    a = math.radians(azimuth)
    g = np.empty(h.shape, dtype=np.float32)
    with _threads_for(h.size):
        _gradient_kernel(np.ascontiguousarray(h, dtype=np.float32), np.float32(-0.5 * math.cos(a)),
                         np.float32(-0.5 * math.sin(a)), g)
    top = max(float(g.max()), -float(g.min()))
    if top == 0.0 or strength == 0.0:
        return np.full(h.shape, 0.5, dtype=np.float32)
    g *= np.float32(0.5 * strength / top)
    g += np.float32(0.5)
    if strength > 1.0:
        np.clip(g, 0.0, 1.0, out=g)
    return g.astype(np.float32, copy=False)


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


def _field(method, shape, m, rng, *, beta, low, octaves, filter, noise_scale):
    """The scalar field on the working grid ``shape``; frequencies per tile pixel."""
    from .spectral import octave_sum, spectral_noise

    if method == "spectral":
        return spectral_noise(shape, beta=beta, low=None if low is None else low * m, rng=rng)
    if method == "octaves":
        return octave_sum(shape, amplitudes=beta, octaves=octaves, filter=filter, rng=rng)
    try:
        from .procedural import noise_image
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
        raise ValueError(f"size {w}x{h} does not suit method='octaves' with {max(count, 1)} octaves: "
                         f"each side must be a multiple of {step} (powers of two always work); "
                         f"method='spectral' takes any size")


def make_tile(size=512, *, rng=0, method: str = "spectral", alpha: str = "emboss",
              colormap="earth", cutoff: float = 0.25, beta: float = 2.0, low: float | None = None,
              octaves: int | None = None, filter: str = "bspline", noise_scale: float = 4.0,
              azimuth: float = 135.0, strength: float = 1.0, alpha_value: float = 0.5,
              seed=DEPRECATED) -> np.ndarray:
    """A seamless, low-pass RGBA tile of coloured random noise (Berger 2006).

    See the module docstring for the steps and the cut-off.

    Parameters
    ----------
    size : int or (int, int)
        Tile side, or ``(height, width)``; 8 to ``MAX_SIZE`` (8192).
        ``method='octaves'`` needs sides that are multiples of its finest
        octave's cells on the working grid (powers of two always work).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
        ``seed=``, the old name, still works for one release with a
        ``DeprecationWarning``.
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
    filter : str
        Magnification filter for ``'octaves'`` (see
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
    from .color import get_ramp
    from .spectral import band_limit_planes

    h, w = check_shape("size", size)
    if min(h, w) < 8 or max(h, w) > MAX_SIZE:
        raise ValueError(f"size must be between 8 and {MAX_SIZE} on each side, got {w}x{h}")
    rng = check_rng(rng, seed=seed, where="make_tile")
    method = check_choice("method", method, METHODS)
    alpha = check_choice("alpha", alpha, ALPHAS)
    from .spectral import FILTERS

    filter = check_choice("filter", filter, FILTERS)
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
    kw = dict(beta=beta, low=low, octaves=octaves, filter=filter, noise_scale=noise_scale)
    if method == "octaves":
        _check_octave_size(h, w, small, octaves)
    field = _field(method, small, m, rng_colour, **kw)
    pos, col = get_ramp(colormap)
    nplanes = 4 if alpha == "noise" else 3
    planes = np.empty((nplanes,) + small, dtype=np.float32)
    with _threads_for(planes.size):
        _ramp_kernel(_standardise(field), pos.astype(np.float32), col[:, :3].astype(np.float32), planes)
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
    with _threads_for(out.size):
        _interleave_kernel(planes, lo, scale, out, lum)
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


# --------------------------------------------------------------------------
# Tiles from photographs
# --------------------------------------------------------------------------

#: Pixels on each side of a wrap edge that make the seam's local reference.
SEAM_BAND = 8
_MAX_GAIN = 3.0


def _edge_ratio(q: np.ndarray, band: int) -> float:
    """Mean |step| across the wrap of (H, W) ``q``'s columns over the mean
    |step| within ``band`` columns on either side."""
    w = q.shape[1]
    idx = np.r_[w - band - 1:w, 0:band + 1]
    steps = np.abs(np.diff(q[:, idx], axis=1))
    inner = np.delete(steps, band, axis=1).mean()
    return float(steps[:, band].mean() / inner) if inner > 0 else 1.0


def _seamless(u: np.ndarray, seam: str, band: int = SEAM_BAND) -> np.ndarray:
    """Periodic version of (H, W, C) ``u``: Moisan's, or with matched seams.

    ``'moisan'``: the periodic component. ``'matched'``: the periodic image
    whose steps across the wrap edges are ``lambda`` times the natural
    step there (the mean of the two steps beside the edge) and otherwise
    as close to the image's as Moisan's, which is Moisan's periodic
    component plus ``lambda`` times the solution for that step alone
    (linear). ``lambda`` in [0, 3], per channel and edge, is set by
    bisection so that the mean step across the edge equals the mean step
    within ``band`` pixels of it (the seam looks like its neighbourhood);
    where Moisan's seam is already as rough as its neighbourhood, lambda
    is 0.
    """
    from .periodic import solve_periodic_poisson, wrap_step_source

    u = u.astype(np.float64)
    p = u - solve_periodic_poisson(wrap_step_source(u.shape, u[0] - u[-1], u[:, 0] - u[:, -1]))
    h, w = u.shape[:2]
    if seam == "moisan" or min(h, w) < 2 * band + 2:
        return p
    zero_r, zero_c = np.zeros((w, u.shape[2])), np.zeros((h, u.shape[2]))
    d_row = 0.5 * ((u[1] - u[0]) + (u[-1] - u[-2]))
    d_col = 0.5 * ((u[:, 1] - u[:, 0]) + (u[:, -1] - u[:, -2]))
    p_row = -solve_periodic_poisson(wrap_step_source(u.shape, d_row, zero_c))
    p_col = -solve_periodic_poisson(wrap_step_source(u.shape, zero_r, d_col))
    for c in range(u.shape[2]):
        gains = [0.0, 0.0]  # rows (top/bottom edge), columns (left/right edge)
        for _sweep in range(2):
            for axis in (1, 0):
                other = gains[1 - axis] * (p_row if axis == 1 else p_col)[:, :, c]
                base = p[:, :, c] + other
                extra = (p_col if axis == 1 else p_row)[:, :, c]
                if axis == 0:
                    base, extra = base.T, extra.T

                def ratio(g):
                    return _edge_ratio(base + g * extra, band)

                if ratio(0.0) >= 1.0:
                    g = 0.0
                elif ratio(_MAX_GAIN) <= 1.0:
                    g = _MAX_GAIN
                else:
                    lo, hi = 0.0, _MAX_GAIN
                    for _ in range(24):
                        mid = 0.5 * (lo + hi)
                        lo, hi = (mid, hi) if ratio(mid) < 1.0 else (lo, mid)
                    g = 0.5 * (lo + hi)
                gains[axis] = g
        p[:, :, c] += gains[0] * p_row[:, :, c] + gains[1] * p_col[:, :, c]
    return p


def make_seamless(image, *, size=None, alpha: str = "none", cutoff: float | None = None, rng=0,
                  seam: str = "matched", azimuth: float = 135.0, strength: float = 1.0,
                  alpha_value: float = 1.0, seed=DEPRECATED) -> np.ndarray:
    """Make a photograph into a seamless RGBA tile.

    The photograph (cropped about its centre to ``size`` if given) is
    replaced by a periodic image that keeps its interior detail and changes
    only by a smooth image, the harmonic image that takes up the jumps
    across the wrap edges: Moisan's periodic-plus-smooth decomposition
    (:func:`spectex.periodic.periodic_smooth_decomposition`).

    ``seam='moisan'`` is that periodic component. It removes the step, but
    it also removes the pixel-scale detail across the edge: the seam becomes
    a soft line, its mean step 0.4 to 0.76 of the steps beside it on
    scikit-image's pictures. ``seam='matched'`` (default) puts the detail
    back: it asks for ``lambda`` times the natural step at the edge (the
    mean of the two steps beside it) instead of no step, which by linearity
    adds ``lambda`` times one more smooth solution, and sets ``lambda`` in
    [0, 3] per channel and edge by bisection so that the mean step across
    the edge equals the mean step within 8 pixels of it (the seam looks like
    its neighbourhood; ``lambda = 0`` where Moisan's seam is already as
    rough). Measured (see ``docs/tiles.md``): edge-to-neighbourhood ratios
    of 1.00 instead of 0.41 to 0.76, and the issue's global metric (wrap
    step over all interior steps) 0.99 and 1.06 instead of 0.65 and 0.67 on
    the stationary textures grass and gravel.

    Conversions: grey is repeated into R, G and B; a photograph's own alpha
    channel (grey + alpha, RGBA) is dropped unless ``alpha='keep'``; integer
    images are scaled by their dtype's maximum (so 16-bit images keep their
    precision). Values that the decomposition pushes out of [0, 1] are
    clipped, or, when ``cutoff`` is given, compressed by :func:`fit_range`
    so that the band limit holds. ``alpha='emboss'`` embosses the
    photograph (see :func:`emboss`; one-sided differences at its edges) and
    makes that seamless the same way; ``'luminance'`` is the luma of the
    seamless colour.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C), C in 1..4
        At least 8 x 8.
    size : None, int or (int, int)
        Tile ``(height, width)`` cropped from the centre; the photograph
        must be at least that large (it is never upsampled).
    alpha : {'none', 'emboss', 'luminance', 'noise', 'keep'}
        As in :func:`make_tile`; ``'keep'`` makes the photograph's own alpha
        channel seamless too (and needs one). ``'none'`` gives
        ``alpha_value`` (default 1, opaque).
    cutoff : float or None
        Optional low-pass, cycles per pixel (see :func:`make_tile`).
    rng : int, numpy.random.Generator or None
        For ``alpha='noise'``.
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
        ``seed=``, the old name, still works for one release with a
        ``DeprecationWarning``.
    seam : {'matched', 'moisan'}
        How the wrap edges are joined (see above).
    azimuth, strength, alpha_value
        As in :func:`make_tile`.

    Returns
    -------
    ndarray, shape (h, w, 4), float32 in [0, 1]
    """
    from .spectral import band_limit, spectral_noise

    image = check_image("image", image, channels=(None, 1, 2, 3, 4), min_size=8)
    alpha = check_choice("alpha", alpha, ALPHAS + ("keep",))
    seam = check_choice("seam", seam, ("matched", "moisan"))
    rng = check_rng(rng, seed=seed, where="make_seamless")
    if cutoff is not None:
        cutoff = check_float("cutoff", cutoff, minimum=0.0, maximum=0.5, exclusive_minimum=True)
    azimuth = check_float("azimuth", azimuth)
    strength = check_float("strength", strength, minimum=0.0, maximum=1e6)
    alpha_value = check_float("alpha_value", alpha_value, minimum=0.0, maximum=1.0)
    img = image[:, :, None] if image.ndim == 2 else image
    nch = img.shape[2]
    own_alpha = img[:, :, nch - 1] if nch in (2, 4) else None
    colour = img[:, :, :3] if nch >= 3 else np.repeat(img[:, :, :1], 3, axis=2)
    if alpha == "keep" and own_alpha is None:
        raise ValueError(f"alpha='keep' needs an image with an alpha channel, got {nch} channel(s)")
    H, W = img.shape[:2]
    if size is not None:
        th, tw = check_shape("size", size)
        if th > H or tw > W:
            raise ValueError(f"image of {W}x{H} is smaller than the tile size {tw}x{th}; "
                             f"choose a smaller size (the image is never upsampled)")
        if min(th, tw) < 8:
            raise ValueError(f"size must be at least 8x8, got {tw}x{th}")
        y0, x0 = (H - th) // 2, (W - tw) // 2
        colour = colour[y0:y0 + th, x0:x0 + tw]
        if own_alpha is not None:
            own_alpha = own_alpha[y0:y0 + th, x0:x0 + tw]
        H, W = th, tw
    if max(H, W) > MAX_SIZE:
        raise ValueError(f"image of {W}x{H} is larger than {MAX_SIZE} on a side; pass size= "
                         f"(--size) to crop a tile from it")

    def finish(channel_stack):
        p = _seamless(channel_stack[:, :, None] if channel_stack.ndim == 2 else channel_stack, seam)
        p = (p[:, :, 0] if channel_stack.ndim == 2 else p).astype(np.float32)
        if cutoff is None:
            return np.clip(p, 0.0, 1.0)
        p = band_limit(p, high=cutoff)
        if p.ndim == 2:
            return fit_range(p)
        return np.stack([fit_range(p[:, :, c]) for c in range(p.shape[2])], axis=2)

    out = np.empty((H, W, 4), dtype=np.float32)
    out[:, :, :3] = finish(colour)
    if alpha == "keep":
        out[:, :, 3] = finish(own_alpha)
    elif alpha == "emboss":
        # Emboss the photograph itself (one-sided differences at its edges,
        # no wrap), then make the result seamless like the colour: the
        # gradient of the periodic component jumps at the wrap edge.
        lum = luma(colour)
        a = math.radians(azimuth)
        gy, gx = np.gradient(lum.astype(np.float64))
        g = -(math.cos(a) * gx - math.sin(a) * gy)  # y up: d/dy = -d/d(row)
        top = float(np.abs(g).max())
        g = 0.5 + (0.5 * strength / top) * g if top > 0 and strength > 0 else np.full(g.shape, 0.5)
        out[:, :, 3] = finish(g.astype(np.float32))
    elif alpha == "luminance":
        out[:, :, 3] = luma(out[:, :, :3])
    elif alpha == "noise":
        field = spectral_noise((H, W), beta=2.0, rng=rng, high=cutoff)
        a = _to_unit(field)
        out[:, :, 3] = a if cutoff is None else fit_range(band_limit(a, high=cutoff))
    else:
        out[:, :, 3] = alpha_value
    return out


# --------------------------------------------------------------------------
# Mip-map chains
# --------------------------------------------------------------------------

def _reduce_matrix(n: int) -> np.ndarray:
    """(floor(n/2) or 1) x n area weights: output texel i averages [i r, (i+1) r)."""
    m = max(1, n // 2)
    r = n / m
    a = np.zeros((m, n))
    for i in range(m):
        lo, hi = i * r, (i + 1) * r
        for k in range(int(math.floor(lo)), min(n, int(math.ceil(hi)))):
            a[i, k] = (min(hi, k + 1) - max(lo, k)) / r
    return a


def _reduce(level: np.ndarray) -> np.ndarray:
    """One mip reduction of an (h, w, C) float32 level."""
    h, w, c = level.shape
    if h % 2 == 0 and w % 2 == 0:
        out = np.empty((h // 2, w // 2, c), dtype=np.float32)
        step = max(1, (1 << 22) // max(1, w * c))  # output rows per block: bounded float64 work space
        for r0 in range(0, h // 2, step):
            r1 = min(h // 2, r0 + step)
            x = level[2 * r0:2 * r1].reshape(r1 - r0, 2, w // 2, 2, c).astype(np.float64)
            out[r0:r1] = (x[:, 0, :, 0] + x[:, 0, :, 1] + x[:, 1, :, 0] + x[:, 1, :, 1]) * 0.25
        return out
    x = level.astype(np.float64)
    if h > 1:
        x = np.einsum("ik,kjc->ijc", _reduce_matrix(h), x)
    if w > 1:
        x = np.einsum("jk,ikc->ijc", _reduce_matrix(w), x)
    return x.astype(np.float32)


def mip_chain(tile, *, space: str = "stored") -> list[np.ndarray]:
    """The mip-map chain of a tile: box reductions down to 1 x 1.

    Level 0 is the tile itself (as float32); level ``k + 1`` has
    ``max(1, floor(n / 2))`` texels along each side of ``n`` texels
    (OpenGL's rule for the sizes of mip levels), and is computed from level
    ``k`` (not from the tile), as ``glGenerateMipmap`` does.

    Filtering. For even sides, each texel of the next level is the mean of a
    2 x 2 block (exactly). For an odd side ``n``, texel ``i`` of the next
    level averages the interval ``[i r, (i + 1) r)`` of the level, with
    ``r = n / floor(n / 2)``, weighting the texels it covers partly by the
    part covered: the footprints of a level's texels partition one period
    of the tile exactly, so every level tiles with the same world period and
    keeps the tile's mean (no row or column is dropped, as a plain 2 x 2 box
    on an odd side would drop one; OpenGL leaves the filter for
    non-power-of-two sides to the implementation, so the renderer uploads
    these levels rather than calling ``glGenerateMipmap``). Because the
    footprints never cross the wrap edge, the chain is exact for a
    repeating texture: a texel straddling the edge would mix the last and
    the first texels, which is the same thing for a seamless tile.

    Averaging space. ``'stored'`` (default) averages the stored values, as
    ``glGenerateMipmap`` does for non-sRGB formats such as ``GL_RGBA8``: use
    it when the tile is uploaded as a plain (linear-format) texture, so that
    these levels are exactly what the GPU would make. ``'linear'`` decodes
    the colour channels from sRGB, averages in linear light and encodes
    again, as GL does for ``GL_SRGB8_ALPHA8`` textures; use it with sRGB
    textures. Alpha is always averaged as stored. Averaging in linear light
    keeps the perceived brightness of fine contrast at a distance (a
    black-and-white checkerboard becomes sRGB 0.735, not 0.5); averaging
    stored values darkens high-contrast detail in the distance but matches
    the plain-texture pipeline.

    Parameters
    ----------
    tile : ndarray, shape (H, W) or (H, W, C)
    space : {'stored', 'linear'}
        Averaging space (see above). ``'linear'`` treats channels 0-2 of an
        RGB(A) tile, or channel 0 of a grey(+alpha) tile, as sRGB.

    Returns
    -------
    list of ndarray, each float32 of shape (h_k, w_k, C)
        ``1 + floor(log2(max(H, W)))`` levels, the last 1 x 1. A 2-D tile
        gives levels of shape (h_k, w_k, 1).
    """
    tile = check_image("tile", tile)
    space = check_choice("space", space, ("stored", "linear"))
    level = tile[:, :, None] if tile.ndim == 2 else tile
    c = level.shape[2]
    colour = slice(0, 3) if c >= 3 else slice(0, 1)
    chain = [level]
    while level.shape[0] > 1 or level.shape[1] > 1:
        if space == "linear":
            lin = level.copy()
            lin[:, :, colour] = srgb_to_linear(level[:, :, colour])
            nxt = _reduce(lin)
            nxt[:, :, colour] = linear_to_srgb(nxt[:, :, colour])
        else:
            nxt = _reduce(level)
        chain.append(nxt)
        level = nxt
    return chain


def preview(tile, *, repeat: int = 3, max_side: int = 1024) -> np.ndarray:
    """A picture that shows whether a tile is seamless.

    The colour repeated ``repeat x repeat`` times, a white gap, and the
    alpha channel (as grey) repeated the same way, side by side. Tiles with
    a side above ``max_side`` are shown by the first level of
    :func:`mip_chain` that fits.

    Parameters
    ----------
    tile : ndarray, shape (H, W, 4), (H, W, 3) or (H, W)
        Without alpha, only the colour part is drawn.
    repeat : int
        Repetitions along each axis, 1 to 8.
    max_side : int
        Largest tile side drawn at full resolution.

    Returns
    -------
    ndarray, float32, shape (repeat h, repeat w [+ gap + repeat w], 3)
    """
    tile = check_image("tile", tile)
    repeat = check_int("repeat", repeat, minimum=1, maximum=8)
    max_side = check_int("max_side", max_side, minimum=1)
    if tile.ndim == 2:
        tile = tile[:, :, None]
    if max(tile.shape[:2]) > max_side:
        tile = next(level for level in mip_chain(tile) if max(level.shape[:2]) <= max_side)
    c = tile.shape[2]
    colour = tile[:, :, :3] if c >= 3 else np.repeat(tile[:, :, :1], 3, axis=2)
    parts = [np.tile(colour, (repeat, repeat, 1))]
    if c in (2, 4):
        gap = np.ones((parts[0].shape[0], max(4, tile.shape[1] // 16), 3), dtype=np.float32)
        parts += [gap, np.repeat(np.tile(tile[:, :, c - 1:c], (repeat, repeat, 1)), 3, axis=2)]
    return np.concatenate(parts, axis=1).astype(np.float32, copy=False)
