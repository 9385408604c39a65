"""A photo's lighting, and the blotches a texture made from it shows (issue 22).

The private home of :func:`spectex.metrics.lighting_blotches` and of the
estimate the fit evens a photo's lighting out with
(``spectex.fitting``, ``keep_lighting``).

A photo of ground is rarely lit evenly: the sun from one side, a shadow's
edge, the lens's vignetting. Its brightness then drifts smoothly across it,
by 10 to 30 % on a hand-held photo. A texture made of pieces of the photo
carries that drift into every piece: drawn stochastically, each patch shows
its own bright and dark side, and a view over several photo areas is
covered in blotches at the photo's own scale (seamed along the patches'
borders), which no band-power, histogram, structure or repeat measure sees:
the photo's coarse octaves hold the drift's power, its windows the drift.

The lighting is estimated as a smooth, multiplicative field: a polynomial
of degree 2 in the photo's coordinates (a gradient and a vignette),
least-squares fitted to the log of the mean luma of 16 x 16 blocks. A
smooth field of that degree is what light does; the content of a texture at
that scale (a photo's few large stones, moon's maria) is not smooth over
the whole photo and stays mostly in the residual. A drift is taken for
lighting only where it is several times what the blocks' own scatter gives
such a polynomial by chance (:func:`is_lighting`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._results import AsDict
from ._validate import check_float, check_image
from .color import luma

#: Blocks along each side of the photo whose mean log luma the lighting is fitted to.
LIGHT_BLOCKS = 16
#: Degree of the lighting's polynomial (1: a gradient; 2: also a vignette or a shadow's bend).
LIGHT_DEGREE = 2
#: Least block mean luma taken as it is before its logarithm (0-1): a black sky's noise is not a light.
LIGHT_FLOOR = 0.02
#: Smallest photo side the lighting is estimated on (blocks of at least 2 pixels).
MIN_LIGHT_SIDE = 2 * LIGHT_BLOCKS
#: A drift is the photo's lighting (evened out by the fit, divided out of the photo's own contrast by
#: :func:`lighting_blotches`) where its RMS is at least this (1 % of brightness: none shows under it) ...
MIN_LIGHTING = 0.01
#: ... and this many times the RMS the blocks' own scatter gives a polynomial of its kind by chance
#: (:func:`lighting_drift`): evenly lit gravel, brick, paving and floor tiles drift by 1.6-2 times chance,
#: the same photos under a light that varies by 3.5 % RMS by 2.2-5.3 times, by 6 % (whose blotches show)
#: 3.5-10.5 times (``docs/fitting.md``, "Lighting evened out").
LIGHT_SIGNIFICANCE = 3.0
#: The blotches' scale: a Gaussian of this fraction of the photo's longer side.
BLOTCH_SIGMA = 1.0 / 16.0
#: Visible blotches: the view's low-frequency contrast over the photo's own by more than this RMS of luma
#: (0-1, as stored: about lightness), calibrated on fits of evenly and unevenly lit photos
#: (``docs/fitting.md``, "Measuring a fit").
BLOTCH_EXCESS = 0.01
#: The view is measured over at most this many pixels a side (its top-left corner): bounded work.
_MAX_VIEW = 4096


def _terms(u: np.ndarray, v: np.ndarray) -> list:
    return [u ** i * v ** j for i in range(LIGHT_DEGREE + 1) for j in range(LIGHT_DEGREE + 1 - i)]


def lighting_trend(photo: np.ndarray) -> np.ndarray:
    """The photo's lighting: a smooth field of log luma (mean 0) on its pixel grid.

    A polynomial of degree :data:`LIGHT_DEGREE` in the photo's coordinates,
    least-squares fitted to the log of the mean luma of :data:`LIGHT_BLOCKS`
    x :data:`LIGHT_BLOCKS` blocks (see the module's docstring). ``exp`` of it
    is the factor the light multiplied the photo's brightness by, about its
    mean.

    Parameters
    ----------
    photo : ndarray, shape (h, w) or (h, w, C)
        At least :data:`MIN_LIGHT_SIDE` pixels a side.

    Returns
    -------
    ndarray, shape (h, w), float64
    """
    return lighting_drift(photo)[0]


def lighting_drift(photo: np.ndarray):
    """``(trend, rms, chance)``: :func:`lighting_trend`, its RMS, and the RMS a polynomial of its kind
    fitted to block means without any drift would have by chance (the fit's residual over the blocks,
    times the square root of the polynomial's non-constant terms over the blocks' number: the drift is
    real where it is several times that)."""
    photo = check_image("photo", photo, min_size=MIN_LIGHT_SIDE)
    y = np.maximum(luma(photo, dtype=np.float64), 0.0)
    h, w = y.shape
    by, bx = h // LIGHT_BLOCKS, w // LIGHT_BLOCKS
    # the log of each block's mean (not the mean of the logs, which a block's near-black pixels rule): a
    # light that multiplies a block's pixels multiplies their mean
    means = np.log(np.maximum(y[:by * LIGHT_BLOCKS, :bx * LIGHT_BLOCKS]
                              .reshape(LIGHT_BLOCKS, by, LIGHT_BLOCKS, bx).mean(axis=(1, 3)), LIGHT_FLOOR))
    # block centres and pixel centres in the same coordinates, -1 to 1 over the blocks' span
    centres = (np.arange(LIGHT_BLOCKS) + 0.5) / LIGHT_BLOCKS * 2.0 - 1.0
    bv, bu = np.meshgrid(centres, centres, indexing="ij")
    a = np.stack([t.ravel() for t in _terms(bu, bv)], axis=1)
    coef, *_ = np.linalg.lstsq(a, means.ravel(), rcond=None)
    residual = float(np.sqrt(np.mean((means.ravel() - a @ coef) ** 2)))
    chance = residual * float(np.sqrt((a.shape[1] - 1) / a.shape[0]))
    v = ((np.arange(h) + 0.5) / (by * LIGHT_BLOCKS) * 2.0 - 1.0)[:, None]
    u = ((np.arange(w) + 0.5) / (bx * LIGHT_BLOCKS) * 2.0 - 1.0)[None, :]
    trend = sum(c * t for c, t in zip(coef, _terms(u, v)))
    trend = np.broadcast_to(trend, (h, w)).astype(np.float64)
    trend = trend - float(trend.mean())
    return trend, float(np.sqrt(np.mean(trend * trend))), chance


def is_lighting(rms: float, chance: float) -> bool:
    """Whether a drift of ``rms`` (:func:`lighting_drift`) is the photo's lighting, not chance:
    :data:`MIN_LIGHTING` and :data:`LIGHT_SIGNIFICANCE` times ``chance``."""
    return rms >= MIN_LIGHTING and rms >= LIGHT_SIGNIFICANCE * chance


def _low_contrast(values: np.ndarray, sigma: float) -> float:
    """RMS about its mean of ``values`` (a luma) low-passed by a Gaussian of ``sigma`` pixels (block means of
    up to a quarter of ``sigma`` first, so that the work is bounded)."""
    from scipy import ndimage

    k = max(1, int(sigma // 4))
    h, w = (values.shape[0] // k) * k, (values.shape[1] // k) * k
    x = values[:h, :w].reshape(h // k, k, w // k, k).mean(axis=(1, 3)) if k > 1 else values
    return float(np.std(ndimage.gaussian_filter(x, sigma / k, mode="reflect")))


@dataclass(frozen=True, eq=False)
class LightingBlotches(AsDict):
    """A photo's lighting, and the low-frequency blotches of a view of a texture (:func:`lighting_blotches`).

    Attributes
    ----------
    lighting : float
        RMS of the photo's smooth drift (:func:`lighting_trend`, natural log
        of luma: 0.1 is a brightness about 10 % above or below its mean).
    significant : bool
        Whether the drift is lighting, not chance (:func:`is_lighting`: at
        least 1 % and 3 times what the photo's blocks give by chance).
    photo_contrast : float
        RMS of the photo's luma (0-1, as stored) low-passed at the blotches'
        scale (a Gaussian of 1/16 of its longer side), its lighting divided
        out where ``significant``: what the photo itself holds at that
        scale.
    view_contrast : float
        The same of the view, at the same scale in the view's pixels.
    excess : float
        ``sqrt(view_contrast**2 - photo_contrast**2)``, 0 where the view
        holds less: blotches the photo does not show.
    threshold : float
        Excess from which blotches show.
    within : bool
        ``excess <= threshold``.
    """

    lighting: float
    significant: bool
    photo_contrast: float
    view_contrast: float
    excess: float
    threshold: float
    within: bool


def lighting_blotches(view, reference, *, zoom: float = 1.0, threshold: float = BLOTCH_EXCESS) -> LightingBlotches:
    """Blotches at the photo's scale in a view of a texture made from it, against the photo's own.

    A texture made of pieces of an unevenly lit photo repeats the light's
    drift in every piece (see :func:`lighting_trend`): a view of several
    photo areas shows bright and dark blotches about a photo across. This
    measure low-passes the view's log luma at that scale (a Gaussian of 1/16
    of the photo's longer side) and compares its contrast with the photo's
    at the same scale with the photo's lighting taken out (the content the
    photo holds there, which a faithful texture may show).

    Parameters
    ----------
    view : ndarray, shape (H, W) or (H, W, C)
        The texture rendered at ``zoom`` times the photo's pixel size over
        several photo areas (e.g. ``bake(texture, (1448, 1448),
        pixel_size=p)``, 8 times the area of a 512-pixel photo); its top-left
        4096 x 4096 pixels at most are measured.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo, at least 32 pixels a side.
    zoom : float
        The view's pixel size over the photo's (1 to the photo's longer side
        over 32, so that the blotches' scale spans 2 view pixels).
    threshold : float
        Visible excess (RMS of luma, 0-1, > 0).

    Returns
    -------
    LightingBlotches
    """
    reference = check_image("reference", reference, min_size=MIN_LIGHT_SIDE)
    sigma = BLOTCH_SIGMA * max(reference.shape[:2])
    zoom = check_float("zoom", zoom, minimum=1.0, maximum=max(1.0, sigma / 2.0))
    threshold = check_float("threshold", threshold, minimum=0.0, exclusive_minimum=True)
    view_sigma = sigma / zoom
    view = check_image("view", view, min_size=max(2, int(np.ceil(4 * view_sigma))))
    trend, rms, chance = lighting_drift(reference)
    significant = is_lighting(rms, chance)
    own = _low_contrast(luma(reference, dtype=np.float64) * (np.exp(-trend) if significant else 1.0), sigma)
    seen = _low_contrast(luma(view[:_MAX_VIEW, :_MAX_VIEW], dtype=np.float64), view_sigma)
    excess = float(np.sqrt(max(seen * seen - own * own, 0.0)))
    return LightingBlotches(lighting=rms, significant=significant, photo_contrast=own,
                            view_contrast=seen, excess=excess, threshold=threshold, within=excess <= threshold)


def even_out_lighting(photo: np.ndarray, *, trend: np.ndarray | None = None):
    """``(photo with its lighting divided out, lighting RMS)``: every channel scaled by ``exp(-trend)``
    (:func:`lighting_trend`, or the ``trend`` given), clipped to the photo's own range per channel, float64
    (the fit's ``keep_lighting=False``)."""
    if trend is None:
        trend = lighting_trend(photo)
    img = np.asarray(photo, dtype=np.float64)
    factor = np.exp(-trend)
    out = img * (factor[:, :, None] if img.ndim == 3 else factor)
    if img.ndim == 3 and img.shape[2] == 4:
        out[:, :, 3] = img[:, :, 3]  # alpha is not light
    flat = img.reshape(-1, img.shape[2]) if img.ndim == 3 else img.reshape(-1, 1)
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    out = np.clip(out, lo if img.ndim == 3 else lo[0], hi if img.ndim == 3 else hi[0])
    return out, float(np.sqrt(np.mean(trend * trend)))


def even_lighting(photo):
    """The photo as the fit reads it: its lighting divided out where it drifts by more than chance.

    A photo lit unevenly (the sun from one side, a lens's vignetting)
    brightens and darkens smoothly across; every patch of a texture made of
    it would repeat that drift as bright and dark blotches
    (:func:`spectex.metrics.lighting_blotches`). The drift is estimated as
    a smooth field of degree 2 in the photo's coordinates, fitted to the log
    of the mean luma of 16 x 16 blocks, and every colour channel divided by
    it (the result kept inside the photo's range per channel). Only a drift
    that is lighting, not chance (``spectex._lighting.is_lighting``: at least
    1 % RMS and 3 times what the blocks' own scatter gives by chance) is
    evened out.

    Parameters
    ----------
    photo : ndarray, shape (h, w) or (h, w, C), float
        As :func:`spectex.fitting.prepare_exemplar` gives it, or a luma.

    Returns
    -------
    (ndarray, dict or None)
        The photo (the same array where nothing was done) and
        ``{"rms", "chance", "low", "high"}``: the drift's RMS (of natural
        log luma), the RMS of chance, and its lowest and highest factor on
        the brightness; or None where the photo is under 32 pixels or lit
        evenly.
    """
    if min(photo.shape[:2]) < MIN_LIGHT_SIDE:
        return photo, None
    trend, rms, chance = lighting_drift(photo)
    if not is_lighting(rms, chance):
        return photo, None
    flat, _ = even_out_lighting(photo, trend=trend)
    light = {"rms": round(rms, 6), "chance": round(chance, 6), "low": round(float(np.exp(trend.min())), 6),
             "high": round(float(np.exp(trend.max())), 6)}
    return flat.astype(photo.dtype, copy=False), light
