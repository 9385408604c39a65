"""Fitting a spectral texture to an exemplar photograph.

The future work of Berger's sketch (seed 000): "analyze a given image for its
statistical properties, and use these properties to generate texture tiles
and mixing parameters for a similar-looking spectral texture".

:func:`fit` (also ``spectex.fit``): exemplar in, :class:`spectex.SpectralTexture`
out; :func:`fit_report` for the numbers of a fit (a :class:`FitResult` holds
both); :func:`prepare_exemplar` for the input conversions (grey, alpha,
16-bit, crop of huge images); :func:`structure_peak` for whether an exemplar
is structured. The statistics it matches are those of :mod:`spectex.analysis`.

See ``docs/fitting.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._results import AsDict
from ._validate import check_choice, check_float, check_image, check_int, check_rng
from .analysis import cross_scale
from .color import luma

__all__ = ["fit", "fit_result", "fit_report", "FitResult", "FitReport", "prepare_exemplar", "structure_peak", "MIN_SIZE", "MAX_ANALYSIS_SIZE",
           "STRUCTURED_PEAK", "FIT_TILINGS", "FIT_METHODS"]

#: Smallest exemplar side: two octave bands of 4 cycles and the cross-scale pairs need 32 pixels.
MIN_SIZE = 32
#: Larger exemplars are analysed on a centre crop of this many pixels a side (the pixel scale is kept).
MAX_ANALYSIS_SIZE = 512
#: Most power per octave the continuation may gain towards coarser scales (dB per octave).
MAX_COARSE_SLOPE = -1.5
#: Far-away bake regions used by the fit, in units of the second coarse layer's size.
_FAR = ((0.618, 0.382), (-1.357, 2.113), (3.141, -0.577), (-2.718, -1.414), (1.732, -3.606))
#: An exemplar whose fine detail repeats by itself (its :func:`spectex.metrics.repeat_peak`)
#: at least this much is *structured* (bricks, tiles, lines): ``tiling="auto"`` keeps its
#: finest layer periodic, because tiling and blending would blur the structure. Between the
#: unstructured photos' highest (0.11, moon's 128 x 128 corner) and brick's lowest (0.18).
STRUCTURED_PEAK = 0.15
#: Band and mean steps on the stochastic texture's bakes, and the regions they are measured on
#: (the exemplar's place and every far one of ``_FAR``). A stochastic texture's coarse layers show
#: a different part of the tile in each region, so a photo with large objects (moon's craters)
#: gives regions whose fine bands differ by several dB; 4 regions left moon's bake 2.2 dB off
#: (its fine bands 3 dB too strong), 6 bring it to 1.0-1.1 dB at any place (docs/fitting.md).
STOCHASTIC_ROUNDS = 2
STOCHASTIC_REGIONS = 6
#: The fit's tiling choices (see :func:`fit`).
FIT_TILINGS = ("auto", "stochastic", "periodic")
#: The fit's methods: ``"auto"`` (the default, issue 22's design) and ``"legacy"`` (the fit before it,
#: kept only so that ``benchmarks/bench_fit_quality.py`` can compare; not for new work).
FIT_METHODS = ("auto", "legacy")


def prepare_exemplar(image, *, max_size: int = MAX_ANALYSIS_SIZE):
    """The exemplar as the fit uses it: RGB float32 in [0, 1], at most ``max_size`` a side.

    Documented conversions: integers are scaled by their dtype's maximum
    (16-bit keeps its precision); grey is repeated into R, G and B; an alpha
    channel (grey + alpha, RGBA) is dropped; an image larger than
    ``max_size`` on a side is cropped about its centre to ``max_size``
    (cropping, not downscaling, keeps ``pixel_size`` meaningful); float
    values outside [0, 1] are clipped.

    Returns
    -------
    exemplar : ndarray, shape (h, w, 3), float32
    notes : list of str
        One line per conversion made (empty if none).

    Raises
    ------
    ValueError
        For an image under 32 pixels on a side, or a flat one (luma standard
        deviation under half an 8-bit step).
    """
    image = check_image("image", image, channels=(None, 1, 2, 3, 4), unit=True)
    max_size = check_int("max_size", max_size, minimum=MIN_SIZE)
    h, w = image.shape[:2]
    notes = []
    if min(h, w) < MIN_SIZE:
        raise ValueError(f"image must be at least {MIN_SIZE}x{MIN_SIZE} pixels to fit a texture to, got {w}x{h}")
    nch = 1 if image.ndim == 2 else image.shape[2]
    if nch in (2, 4):
        notes.append("alpha channel dropped")
    if nch in (1, 2):
        grey = image if image.ndim == 2 else image[:, :, 0]
        rgb = np.repeat(grey[:, :, None], 3, axis=2)
        notes.append("grey repeated into RGB")
    else:
        rgb = image[:, :, :3]
    if max(h, w) > max_size:
        th, tw = min(h, max_size), min(w, max_size)
        y0, x0 = (h - th) // 2, (w - tw) // 2
        rgb = rgb[y0:y0 + th, x0:x0 + tw]
        notes.append(f"analysed on the central {tw}x{th} crop of the {w}x{h} image")
    rgb = np.ascontiguousarray(np.clip(rgb, 0.0, 1.0), dtype=np.float32)
    # the spectral statistics are those of the luma: a picture without luma variation has none
    if float(np.std(_luma(rgb))) < 0.5 / 255.0:
        raise ValueError("image is flat (constant luminance, std under half an 8-bit step): "
                         "it has no texture to fit")
    return rgb, notes


# --------------------------------------------------------------------------
# The pieces
# --------------------------------------------------------------------------

def _luma(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luma (:func:`spectex.color.luma`) in float64."""
    return luma(rgb, dtype=np.float64)


def _band_axis(n_rows: int, n_cols: int) -> np.ndarray:
    """``-log2`` of the radial frequency (cycles per pixel) of an FFT grid; band k's centre is k + 1.5."""
    fy = np.fft.fftfreq(n_rows)[:, None]
    fx = np.fft.fftfreq(n_cols)[None, :]
    r = np.hypot(fy, fx)
    r[0, 0] = 1e-9
    return -np.log2(r)


def _shape_spectrum(tile_rgb: np.ndarray, gains_db: np.ndarray) -> np.ndarray:
    """Filter each channel by a radial gain, piecewise linear in dB against log frequency.

    ``gains_db[k]`` is the gain at the centre of octave band ``k`` (``2^-(k+1.5)``
    cycles per pixel), held beyond the first and last centres. Periodic (FFT),
    so a seamless tile stays seamless; the mean colour is kept.
    """
    h, w = tile_rgb.shape[:2]
    x = _band_axis(h, w)
    centres = np.arange(len(gains_db)) + 1.5
    import scipy.fft as sfft

    gain = 10.0 ** (np.interp(x[:, : w // 2 + 1], centres, gains_db) / 20.0)
    gain[0, 0] = 1.0
    spec = sfft.rfft2(tile_rgb.astype(np.float32), axes=(0, 1), workers=2)
    spec *= gain[:, :, None].astype(np.float32)
    return sfft.irfft2(spec, s=(h, w), axes=(0, 1), workers=2).astype(np.float64)


def _quantile_map(values: np.ndarray, target_sorted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A monotone map (knots x -> y) taking the distribution of ``values`` to the target's."""
    q = np.linspace(0.0, 1.0, 257)
    xs = np.quantile(values, q)
    ys = np.quantile(target_sorted, q)
    xs, idx = np.unique(xs, return_index=True)
    return xs, ys[idx]


def _alpha_field(tile_rgb: np.ndarray) -> np.ndarray:
    """Standardised luma of the tile, band-passed (periodic): the alpha's shape.

    Smoothed by a Gaussian of 1 texel (no pixel noise in the alpha) and with
    the tile's coarsest structure (a Gaussian of 1/16 of the tile) removed,
    so that the first coarse layer's alpha varies within an exemplar-sized
    region instead of shifting whole regions' detail up or down.
    """
    from scipy import ndimage

    lum = _luma(tile_rgb)
    z = ndimage.gaussian_filter(lum, 1.0, mode="wrap")
    z -= ndimage.gaussian_filter(lum, max(1.0, lum.shape[0] / 16.0), mode="wrap")
    z -= z.mean()
    s = z.std()
    return z / s if s > 0 else z


def _alpha(z: np.ndarray, gain: float) -> np.ndarray:
    """Alpha = 0.5 + gain z / 4, clipped: gain > 0 hides the finer layers where the coarse one is bright."""
    return np.clip(0.5 + 0.25 * gain * z, 0.0, 1.0)


def structure_peak(exemplar) -> float:
    """How much the exemplar's own fine detail repeats: :func:`spectex.metrics.repeat_peak` of it.

    ``min_lag`` is 24 pixels, less for exemplars under 48 pixels (half the
    shorter side). At least :data:`STRUCTURED_PEAK` (0.15) marks a
    structured texture. scikit-image's pictures: brick 0.18 (whole) and
    0.45 (128 x 128 corner); grass, gravel, moon, immunohistochemistry 0.02
    to 0.06 whole and 0.05 to 0.11 as 128 x 128 corners (a small picture's
    noise floor is higher: about ``sqrt(2 ln N / N)``, 0.03 for N = 128^2).
    """
    from .metrics import repeat_peak

    h, w = exemplar.shape[:2]
    peak = repeat_peak(exemplar, min_lag=min(24, min(h, w) // 2))
    return 0.0 if not np.isfinite(peak) else float(peak)


def _with_tilings(layer_list, tilings, patch):
    from .texture import Layer

    return [Layer(size=lay.size, offset=lay.offset, rotation=lay.rotation, opacity=lay.opacity, tiling=t,
                  patch=patch, seed=k if t == "stochastic" else 0)
            for k, (lay, t) in enumerate(zip(layer_list, tilings))]


def _layers(n_layers: int, ratio: float, tile_px: int, pixel_size: float, opacity: float):
    from .texture import Layer, layer_placement

    finest = tile_px * pixel_size
    out = []
    for k in range(n_layers):
        size = finest * ratio ** k
        offset, rotation = layer_placement(k, size, decimals=9)
        out.append(Layer(size=size, offset=offset, rotation=rotation, opacity=1.0 if k == 0 else opacity))
    return out


@dataclass
class FitResult:
    """A fitted texture and the numbers of its fit (see :func:`fit_report`)."""

    texture: object
    exemplar: np.ndarray = field(repr=False)
    pixel_size: float = 1.0
    notes: list = field(default_factory=list)
    params: dict = field(default_factory=dict)
    seconds: float = 0.0


class _Problem:
    """The exemplar's targets and the fast evaluation of a candidate tile (small bakes)."""

    def __init__(self, exemplar, pixel_size, layer_list, tile_px, ratio, segment, n_regions=3,
                 continuation=None):
        from .metrics import band_power

        self.exemplar = exemplar
        self.p = pixel_size
        self.layers = layer_list
        self.segment = segment
        # small exemplars: regions of twice the size (Welch segments of the exemplar's size)
        self.region = tuple(2 * s if max(segment) <= 128 else s for s in segment)
        self.target_bands = band_power(exemplar, segment=segment)[1]
        # An exemplar larger than the segment holds coarser bands than a segment sees:
        # those are measured on a bake at twice the pixel size (mip-filtered) against
        # the exemplar reduced 2 x 2, whose band k is the exemplar's band k + 1.
        self.coarse = None
        h, w = exemplar.shape[:2]
        if min(h, w) > min(segment) and min(h, w) // 2 >= 32:
            half = exemplar[: h // 2 * 2, : w // 2 * 2].reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3))
            seg2 = (min(h // 2, 256), min(w // 2, 256))
            full = band_power(exemplar)[1]
            extra = len(full) - len(self.target_bands)
            if extra > 0:
                t2 = band_power(half, segment=seg2)[1]
                self.coarse = (seg2, t2[len(t2) - extra:], extra)
                self.target_bands = np.concatenate([self.target_bands, full[len(full) - extra:]])
        # Continuation: two bands beyond the exemplar's coarsest, on the line of slope
        # ``continuation`` dB per octave, measured on a 128 x 128 bake at 2^m times the
        # pixel size whose bands 2 and 3 are those bands.
        self.cont = None
        if continuation is not None:
            k_full = len(self.target_bands)
            m = max(k_full - 2, 1)
            last = self.target_bands[-1]
            self.cont = (2.0 ** m, np.array([last + continuation, last + 2 * continuation]), k_full - m)
            self.target_bands = np.concatenate([self.target_bands, self.cont[1]])
        self.target_sorted = [np.sort(exemplar[:, :, c].ravel()) for c in range(3)]
        target = cross_scale(exemplar)
        self.target_cross, self.fine = target.value, target.fine
        self.set_regions(n_regions, tile_px=tile_px, ratio=ratio)

    def set_regions(self, n_regions, *, tile_px, ratio):
        """Regions on the pixel grid (layer 0 sampled at its texel centres): the exemplar's own
        place and ``n_regions - 1`` far away in the coarse layers."""
        self.origins = [(0.0, 0.0)] + [(round(tile_px * ratio ** 2 * fx) * self.p,
                                          round(tile_px * ratio ** 2 * fy) * self.p)
                                         for fx, fy in _FAR[:n_regions - 1]]

    def texture(self, colour, alpha):
        from .texture import SpectralTexture

        rgba = np.empty(colour.shape[:2] + (4,), dtype=np.float32)
        rgba[:, :, :3] = np.clip(colour, 0.0, 1.0)
        rgba[:, :, 3] = alpha
        return SpectralTexture(rgba, self.layers)

    def bakes(self, colour, alpha, *, extra=True):
        """Bakes of the regions at the pixel size, then (``extra``) the coarser ones for the bands."""
        tex = self.texture(colour, alpha)
        out = [tex.bake(self.region, origin=o, pixel_size=self.p) for o in self.origins]
        if not extra:
            return out
        if self.coarse is not None:
            out.append(tex.bake(self.coarse[0], pixel_size=2.0 * self.p))
        if self.cont is not None:
            out.append(tex.bake((128, 128), pixel_size=self.cont[0] * self.p))
        return out

    def fine_bakes(self, bakes):
        return bakes[:len(self.origins)]

    def band_error(self, bakes):
        from .metrics import band_power

        fine = self.fine_bakes(bakes)
        power = np.mean([10.0 ** (band_power(b, segment=self.segment)[1] / 10.0) for b in fine], axis=0)
        db = 10.0 * np.log10(np.maximum(power, 1e-20))
        err = self.target_bands[:len(db)] - db
        if self.coarse is not None:
            seg2, target2, extra = self.coarse
            p2 = band_power(bakes[len(self.origins)], segment=seg2)[1]
            err = np.concatenate([err, target2 - p2[len(p2) - extra:]])
        if self.cont is not None:
            _, target_c, first = self.cont
            pc = band_power(bakes[-1])[1]
            err = np.concatenate([err, target_c - pc[first:first + 2]])
        return err

    def bakes_first(self, colour, alpha):
        """The exemplar's own region only (for the alpha-gain search)."""
        tex = self.texture(colour, alpha)
        return [tex.bake(self.region, origin=self.origins[0], pixel_size=self.p)]

    def cross(self, bakes):
        return float(np.mean([cross_scale(b, fine=self.fine).value for b in self.fine_bakes(bakes)]))

    def histogram_step(self, colour, bakes, *, shift_only=False):
        """Map the tile's channels so that the bakes' histograms become the exemplar's."""
        out = np.empty_like(colour)
        if shift_only:
            # the means only (the band step sets the contrast; a full match here would undo it)
            for c in range(3):
                vals = np.concatenate([b[:, :, c].ravel() for b in self.fine_bakes(bakes)]).astype(np.float64)
                t = self.target_sorted[c]
                out[:, :, c] = colour[:, :, c] + (t.mean() - vals.mean())
            return np.clip(out, 0.0, 1.0)
        for c in range(3):
            vals = np.concatenate([b[:, :, c].ravel() for b in self.fine_bakes(bakes)])
            xs, ys = _quantile_map(vals, self.target_sorted[c])
            out[:, :, c] = np.interp(colour[:, :, c], xs, ys, left=None, right=None)
            # beyond the bake's range, continue with unit slope (keeps the tile's extremes ordered)
            lo, hi = colour[:, :, c] < xs[0], colour[:, :, c] > xs[-1]
            out[:, :, c][lo] = ys[0] + (colour[:, :, c][lo] - xs[0])
            out[:, :, c][hi] = ys[-1] + (colour[:, :, c][hi] - xs[-1])
        return np.clip(out, 0.0, 1.0)


def _coarse_slope(power_db: np.ndarray) -> float:
    """dB per octave over the exemplar's three coarsest bands (towards coarser)."""
    tail = power_db[-3:]
    return float(np.polyfit(np.arange(len(tail), dtype=np.float64), tail, 1)[0])


def _pick_gain(gains, values, target) -> float:
    """The alpha gain whose coupling is nearest the target, refined linearly between grid points."""
    values = np.asarray(values)
    err = values - target
    best = int(np.argmin(np.abs(err)))
    for j in (best - 1, best):
        if 0 <= j < len(gains) - 1 and err[j] * err[j + 1] <= 0 and err[j] != err[j + 1]:
            t = err[j] / (err[j] - err[j + 1])
            return float(gains[j] + t * (gains[j + 1] - gains[j]))
    return float(gains[best])


def fit(image, *, pixel_size: float | None = None, photo_size: float | None = None, layers: int = 5,
        ratio: float = 4.0, opacity: float | None = None, iterations: int | None = None,
        tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0, tiling: str = "auto",
        patch: float | None = None, method: str = "auto", progress=None):
    """Fit a spectral texture to an exemplar photograph (Berger's future work).

    **The default, ``method="auto"``** (issue 22; ``spectex._fit_auto`` and
    ``docs/fitting.md``): each layer carries only what the photo says at its
    scale. The finest layer is a tile of the photo: for a structured photo
    (:func:`structure_peak` >= :data:`STRUCTURED_PEAK` and a period along x
    or y in its autocorrelation) a periodic tile of whole periods cut where
    its wrap edges show least, kept unless a trial bake of the stochastic
    alternative is clearly closer by the structural distance
    (:func:`spectex.metrics.structural_distance`); otherwise the photo's
    seamless crop or a tileable quilt with a reuse penalty, drawn
    stochastically with sharpened blend weights (no cross-faded double
    images). The coarser layers draw a second tile, random-phase noise that
    continues the photo's spectrum below its lowest frequency, on the main
    axis of its low-passed colours (never the photo magnified), alpha-blended
    at a low opacity (0.1). The tile's colours end with the exact
    histogram step, inside the photo's range. Scale: ``pixel_size``, or
    ``photo_size`` (metres across the photo's longer side), or, with
    neither, a photo 1.5 m across (``DEFAULT_PHOTO_SIZE``; said in the
    result's notes).

    **``method="legacy"``**, the fit before issue 22, kept only so that
    ``benchmarks/bench_fit_quality.py`` can compare; it is what the rest of
    this text describes (pixel size 1 m by default, opacity 0.2, 3
    iterations). The texture is ``layers`` layers of one seamless RGBA tile made from the
    exemplar. Its finest layer shows the tile texel for exemplar pixel
    (size ``tile_px * pixel_size``, no offset or rotation), each next layer
    is ``ratio`` times larger (rotated by the golden angle and offset, so
    the grids do not line up) and alpha-blended over the finer ones. The
    fit, all on small bakes of the texture at ``pixel_size``:

    1. **Tile**: for an exemplar smaller than 512 pixels, a tile four
       times its side (up to 512) by tileable image quilting
       (:func:`spectex.synthesis.quilt`), so the finest layer does not
       repeat the exemplar at its own period; otherwise the exemplar's
       central square made seamless (:func:`spectex.tiles.make_seamless`,
       matched seams). See ``tile_size``.
    2. **Layer opacities** continue the spectrum: the exemplar's power per
       octave over its three coarsest bands changes by ``s`` dB per octave
       towards coarser scales, clamped to at most ``MAX_COARSE_SLOPE``
       (-1.5: a photograph of a stationary texture holds no more power
       beyond its size, and a texture in [0, 1] cannot hold a rising
       spectrum over many octaves); layer ``k >= 1`` gets opacity
       ``opacity * q^(k-1)`` with ``q = 10^(s log2(ratio) / 20)``, so each
       coarser layer adds the power the slope asks for at its scale.
    3. **Alpha** is ``0.5 + g z / 4`` (clipped), ``z`` the tile's
       standardised luma, smoothed by one texel and without its coarsest
       structure (a Gaussian of 1/16 of the tile): where the coarse layer is
       bright (``g > 0``) or dark (``g < 0``) it hides the finer bands.
       ``g`` is chosen on a grid (-3, -1, 1, 3; refined linearly, checked
       again at +-0.75 after the other steps) so that the bake's
       cross-scale dependence (:func:`spectex.analysis.cross_scale`,
       ``value``) matches the exemplar's.
    4. **Band power and histograms**: ``iterations`` times, the tile's
       colour is filtered by a radial gain (piecewise linear in dB against
       log frequency, periodic) by the difference in dB between the
       exemplar's and the bake's power per octave (damped by 0.8, at most
       6 dB a step), and its channels shifted so that the bake's means
       match; then each tile channel goes through the monotone map that
       takes the bake's histogram to the exemplar's, and a last band-power
       step follows (Heeger and Bergen's alternation [2]_, here through
       the layered texture).
    5. **Never repeat** (``tiling``): the layers are made stochastic
       (histogram-preserving tiling and blending of the tile, Heitz and
       Neyret [6]_; :class:`spectex.texture.Layer`), and the band-power and
       histogram steps run once more, then the last ones, on bakes of the
       stochastic texture (the blending moves the band powers a little).
       Steps 1-4 run on periodic bakes (the same tile, 3x faster). With
       ``"auto"`` (default) every layer is stochastic unless the exemplar
       is *structured*, measured: :func:`structure_peak` (its own
       :func:`~spectex.metrics.repeat_peak`) at least
       :data:`STRUCTURED_PEAK`; then the finest layer stays periodic
       (tiling and blending would blur bricks or lines into ghosts; the
       coarser layers are stochastic still). ``docs/fitting.md`` has the
       numbers.

    Bakes are regions of the exemplar's size (at most 256 x 256; twice the
    size for exemplars of 128 or less) on the pixel grid: the exemplar's
    own place and one or two far away in the coarse layers, so that the fit
    does not tune one lucky region. Bands that such a region cannot hold
    are measured on coarser bakes (mip-filtered): an exemplar larger than
    the region has its coarsest bands matched on a bake at twice the pixel
    size (against the exemplar reduced 2 x 2), and two bands beyond the
    exemplar's coarsest are set on the line of the continuation slope
    ``s`` (a 128 x 128 bake at ``2^m`` times the pixel size), so the
    texture continues the spectrum at larger scales.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The exemplar, values in [0, 1] (integers scaled by their dtype's
        maximum); see :func:`prepare_exemplar` for the conversions (grey,
        alpha, 16-bit, crop of huge images). At least 32 x 32, not flat.
    pixel_size : float, optional
        World size of one exemplar pixel (metres); ``texture.bake(shape,
        pixel_size=pixel_size)`` then renders at the exemplar's scale.
        Default: from ``photo_size`` (``FitResult.pixel_size`` says it).
    photo_size : float, optional
        Metres across the photo's longer side (not with ``pixel_size``);
        default 1.5 (a photo of ground taken standing). Method "auto" only.
    method : {"auto", "legacy"}
        The fit (see above); "legacy" only for comparisons.
    layers : int
        Number of layers, 2 to 8.
    ratio : float
        Size ratio between neighbouring layers, > 1 (4: two octaves).
    opacity : float, optional
        Opacity of the first coarse layer, in (0, 1]; default 0.1 (legacy 0.2).
    iterations : int, optional
        Rounds of the band-power step, >= 1; default 2 (legacy 3).
    tile_size : int, optional
        Tile side in texels. Default ``max(m, min(512, 4 m))`` for the
        exemplar's shorter side ``m``: 512 for exemplars of 128 to 512
        pixels, four times smaller ones. A tile larger than the
        exemplar is synthesised from it by tileable image quilting
        (:func:`spectex.synthesis.quilt`, Efros and Freeman [5]_), so that
        the finest layer does not repeat at the exemplar's period; otherwise
        it is the exemplar's central crop made seamless.
    max_size : int
        Larger exemplars are analysed on a central crop of this size.
    rng : int, numpy.random.Generator or None
        Randomness of the quilting (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, so equal inputs and ``rng`` give
        equal textures; a Generator is used (and advanced); None draws fresh
        randomness.
    tiling : {"auto", "stochastic", "periodic"}
        ``"periodic"``: every layer periodic (the fit before stochastic
        layers; the texture repeats the tile). ``"stochastic"``: every layer
        stochastic. ``"auto"``: stochastic, but a periodic finest layer for
        a structured exemplar (step 5).
    patch : float, optional
        The stochastic layers' triangle side in tiles; default
        ``DEFAULT_PATCH`` (0.5).
    progress : callable, optional
        ``progress(done, total)`` after each step.

    Returns
    -------
    SpectralTexture
        :func:`fit_result` gives it with the numbers of the fit (a :class:`FitResult`).

    References
    ----------
    .. [1] D. R. Berger, "Spectral texturing for real-time applications",
       SIGGRAPH 2003 Sketches and Applications (the model; the fit is its
       future work).
    .. [2] D. J. Heeger and J. R. Bergen, "Pyramid-based texture
       analysis/synthesis", SIGGRAPH 1995.
    .. [3] J. Portilla and E. P. Simoncelli, "A parametric texture model
       based on joint statistics of complex wavelet coefficients", IJCV
       40(1), 2000 (cross-scale dependence).
    .. [4] L. Moisan, "Periodic plus smooth image decomposition", JMIV 39(2),
       2011 (the seamless tile).
    .. [5] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001 (the larger tile).
    .. [6] E. Heitz and F. Neyret, "High-performance by-example noise using
       a histogram-preserving blending operator", Proc. ACM CGIT 1(2), 2018.
    """
    kwargs = dict(pixel_size=pixel_size, photo_size=photo_size, layers=layers, ratio=ratio, opacity=opacity,
                  iterations=iterations, tile_size=tile_size, max_size=max_size, tiling=tiling, patch=patch,
                  method=method, progress=progress, rng=rng)
    return fit_result(image, **kwargs).texture


def fit_result(image, *, pixel_size: float | None = None, photo_size: float | None = None, layers: int = 5,
               ratio: float = 4.0, opacity: float | None = None, iterations: int | None = None,
               tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0, tiling: str = "auto",
               patch: float | None = None, method: str = "auto", progress=None) -> FitResult:
    """Fit a spectral texture as :func:`fit` does, and return it with the numbers of the fit.

    The parameters are :func:`fit`'s; the same inputs (``rng`` an int)
    give the same texture.

    Returns
    -------
    FitResult
        ``texture`` (the :class:`spectex.SpectralTexture`), ``exemplar``
        (as analysed, after :func:`prepare_exemplar`), ``pixel_size``,
        ``notes`` (the input conversions), ``params`` (the fitted
        parameters: tile size and method, layer opacities, alpha gain, band
        gains, the band error of each step, tilings, ...) and ``seconds``.
    """
    method = check_choice("method", method, FIT_METHODS)
    if method == "legacy":
        if photo_size is not None:
            raise ValueError("photo_size is not used by method='legacy' (give pixel_size)")
        return _fit_legacy(image, pixel_size=1.0 if pixel_size is None else pixel_size, layers=layers,
                           ratio=ratio, opacity=0.2 if opacity is None else opacity,
                           iterations=3 if iterations is None else iterations, tile_size=tile_size,
                           max_size=max_size, rng=rng, tiling=tiling, patch=patch, progress=progress)
    from ._fit_auto import fit_auto

    return fit_auto(image, pixel_size=pixel_size, photo_size=photo_size, layers=layers, ratio=ratio,
                    opacity=opacity, iterations=iterations, tile_size=tile_size, max_size=max_size, rng=rng,
                    tiling=tiling, patch=patch, progress=progress)


def _fit_legacy(image, *, pixel_size: float = 1.0, layers: int = 5, ratio: float = 4.0, opacity: float = 0.2,
                iterations: int = 3, tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0,
                tiling: str = "auto", patch: float | None = None, progress=None) -> FitResult:
    """The fit before issue 22 (``method="legacy"``), kept only so that benchmarks can compare."""
    import time

    from .tiles import make_seamless

    start = time.perf_counter()
    pixel_size = check_float("pixel_size", pixel_size, minimum=0.0, exclusive_minimum=True)
    layers = check_int("layers", layers, minimum=2, maximum=8)
    ratio = check_float("ratio", ratio, minimum=1.0, exclusive_minimum=True, maximum=64.0)
    opacity = check_float("opacity", opacity, minimum=0.0, maximum=1.0, exclusive_minimum=True)
    iterations = check_int("iterations", iterations, minimum=1, maximum=50)
    rng = check_rng(rng)
    from .shading.constants import DEFAULT_PATCH

    tiling = check_choice("tiling", tiling, FIT_TILINGS)
    patch = DEFAULT_PATCH if patch is None else check_float("patch", patch, minimum=0.0, exclusive_minimum=True,
                                                             maximum=4.0)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable, got {type(progress).__name__}")
    exemplar, notes = prepare_exemplar(image, max_size=max_size)
    h, w = exemplar.shape[:2]
    structure = structure_peak(exemplar)
    if tiling == "periodic":
        tilings = ["periodic"] * layers
    elif tiling == "stochastic" or structure < STRUCTURED_PEAK:
        tilings = ["stochastic"] * layers
    else:
        tilings = ["periodic"] + ["stochastic"] * (layers - 1)
    stochastic = "stochastic" in tilings
    total = 2 + 4 + 1 + 2 * (iterations + 1) + (2 * STOCHASTIC_ROUNDS if stochastic else 0)
    done = 0

    def tick():
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    if tile_size is None:
        tile_size = max(min(h, w), min(512, 4 * min(h, w)))
    n = check_int("tile_size", tile_size, minimum=MIN_SIZE, maximum=4096)
    if n <= min(h, w):
        tile0 = make_seamless(exemplar, shape=(n, n))[:, :, :3].astype(np.float64)
        tile_method = "seamless crop"
    else:
        from .synthesis import quilt

        block = int(np.clip(min(h, w) // 4, 16, 64))
        tile0 = quilt(exemplar, (n, n), block=block, tileable=True, rng=rng).astype(np.float64)
        tile_method = f"tileable quilt (block {block})"
    tick()
    region = (min(h, 256), min(w, 256))
    from .metrics import band_power

    slope = min(MAX_COARSE_SLOPE, _coarse_slope(band_power(exemplar, segment=region)[1]))
    q = float(np.clip(10.0 ** (slope * math.log2(ratio) / 20.0), 0.25, 1.0))
    from .texture import Layer

    base = _layers(layers, ratio, n, pixel_size, 1.0)
    layer_list = [base[0]] + [Layer(size=lay.size, offset=lay.offset, rotation=lay.rotation,
                                    opacity=round(opacity * q ** (k - 1), 6))
                              for k, lay in enumerate(base) if k >= 1]
    problem = _Problem(exemplar, pixel_size, layer_list, n, ratio, region,
                       n_regions=2 if min(region) >= 256 else 3, continuation=slope)
    z = _alpha_field(tile0)
    tick()
    colour = tile0
    gains_db = np.zeros(len(problem.target_bands))
    history = []  # band-power errors (dB) before each band step

    def spectral_and_histogram(colour, alpha):
        err = problem.band_error(problem.bakes(colour, alpha))
        history.append(err.tolist())
        step = np.clip(0.8 * err, -6.0, 6.0)
        gains_db[:] += step
        colour = np.clip(_shape_spectrum(colour, step), 0.0, 1.0)
        tick()
        colour = problem.histogram_step(colour, problem.bakes(colour, alpha, extra=False), shift_only=True)
        tick()
        return colour

    # one round with a neutral alpha, then the alpha gain on a grid, then the rest
    colour = spectral_and_histogram(colour, _alpha(z, 0.0))
    grid = (-3.0, -1.0, 1.0, 3.0)
    values = []
    for g in grid:
        values.append(problem.cross(problem.bakes_first(colour, _alpha(z, g))))
        tick()
    gain = _pick_gain(grid, values, problem.target_cross)
    alpha = _alpha(z, gain)
    for _ in range(iterations - 1):
        colour = spectral_and_histogram(colour, alpha)
    # the steps move the dependence a little: check the gain's neighbours once more
    near = sorted({float(np.clip(gain + d, grid[0], grid[-1])) for d in (-0.75, 0.0, 0.75)})
    near_values = [problem.cross(problem.bakes_first(colour, _alpha(z, g))) for g in near]
    tick()
    best = int(np.argmin(np.abs(np.asarray(near_values) - problem.target_cross)))
    if near[best] != gain:
        gain = near[best]
        alpha = _alpha(z, gain)
        colour = spectral_and_histogram(colour, alpha)
    else:
        tick()
        tick()
    if stochastic:
        # step 5: the final layers; more regions (a stochastic texture's regions differ more than a
        # periodic one's) and STOCHASTIC_ROUNDS band and mean steps on their bakes
        problem.layers = layer_list = _with_tilings(layer_list, tilings, patch)
        problem.set_regions(STOCHASTIC_REGIONS, tile_px=n, ratio=ratio)
        for _ in range(STOCHASTIC_ROUNDS):
            colour = spectral_and_histogram(colour, alpha)
    # the exact histograms (a monotone map per channel), then a last band-power step
    colour = problem.histogram_step(colour, problem.bakes(colour, alpha, extra=False))
    err = problem.band_error(problem.bakes(colour, alpha))
    history.append(err.tolist())
    colour = np.clip(_shape_spectrum(colour, np.clip(err, -6.0, 6.0)), 0.0, 1.0)
    texture = problem.texture(colour, alpha)
    params = {"tile_px": n, "tile_method": tile_method, "layers": layers, "ratio": ratio,
              "coarse_slope_db_per_octave": slope,
              "opacities": [lay.opacity for lay in layer_list], "alpha_gain": gain,
              "alpha_grid": dict(zip(grid, values)), "band_gains_db": gains_db.tolist(),
              "band_error_history_db": history, "alpha_near": dict(zip(near, near_values)),
              "target_cross_scale": problem.target_cross, "tilings": list(tilings),
              "structure_peak": structure, "patch": patch}
    return FitResult(texture=texture, exemplar=exemplar, pixel_size=pixel_size, notes=notes, params=params,
                     seconds=time.perf_counter() - start)


@dataclass(frozen=True, eq=False)
class FitReport(AsDict):
    """The numbers of :func:`fit_report`."""

    bake_shape: tuple                  #: (H, W) of the bake compared
    band_power_distance_db: float      #: RMS over the exemplar's bands, dB
    band_power_exemplar_db: np.ndarray
    band_power_texture_db: np.ndarray
    histogram_w1: np.ndarray           #: per channel
    cross_scale_exemplar: float
    cross_scale_texture: float
    amplitude_exemplar: float
    amplitude_texture: float
    #: :func:`spectex.metrics.structural_distance` of the bake's exemplar-sized corner (the
    #: photo's own place) to the exemplar: ``ratio`` about 1 is as close as the photo is to itself
    structure: object = None
    #: the same over the whole bake (windows spread over it: every part of the texture, not one)
    structure_far: object = None
    #: :func:`spectex.metrics.clipping` of the bake against the exemplar (its own + 1 point)
    clipping: object = None
    #: :func:`spectex.metrics.coarse_copies` on a view at ``coarse_zoom`` times the pixel size
    coarse: object = None


def fit_report(texture, image, *, pixel_size: float = 1.0, origin=(0.0, 0.0), scale: int = 2,
               bake=None, coarse_zoom: float | None = 8.0) -> FitReport:
    """The fidelity numbers of a texture against an exemplar, at the exemplar's scale.

    The texture is baked over ``scale`` times the exemplar's size (each
    side) at ``pixel_size`` from ``origin`` (keep the origin a whole number
    of pixels, so that the finest layer is sampled at its texel centres as
    the fit did), and compared with the exemplar (prepared as by
    :func:`prepare_exemplar`: grey becomes RGB, alpha is dropped, huge
    images are cropped).

    With ``bake``, a bake of the texture already made (``texture.bake(...)``
    at the exemplar's ``pixel_size``, at least the exemplar's size), that is
    compared instead, and ``origin`` and ``scale`` are not used: ``spectex
    fit`` reports on the render of 8x the area it shows this way.

    Returns
    -------
    FitReport
        ``band_power_distance_db`` (RMS over the bands the exemplar holds,
        Welch segments of the exemplar's size, :func:`spectex.metrics.band_power_distance`),
        ``band_power_exemplar_db`` and ``band_power_texture_db`` (lists),
        ``histogram_w1`` (per channel), ``cross_scale_exemplar`` and
        ``cross_scale_texture`` (the ``value`` of
        :func:`spectex.analysis.cross_scale`), ``amplitude_exemplar`` and
        ``amplitude_texture`` (its ``amplitude``), ``bake_shape``; the
        structural measures of issue 22: ``structure`` (the bake's
        exemplar-sized corner, at the photo's own place) and
        ``structure_far`` (windows spread over the whole bake), both
        :func:`spectex.metrics.structural_distance` with the exemplar's own
        floor (None for an exemplar without two 32 x 32 windows); ``clipping``
        (:func:`spectex.metrics.clipping`); ``coarse``
        (:func:`spectex.metrics.coarse_copies` on a view of the texture,
        the exemplar's shape at ``coarse_zoom`` times ``pixel_size``; None
        without ``coarse_zoom`` or for an exemplar under 192 pixels).
    """
    from .metrics import (
        band_power,
        band_power_distance,
        clipping,
        coarse_copies,
        histogram_w1,
        reference_statistics,
        structural_distance,
    )

    exemplar, _ = prepare_exemplar(image)
    h, w = exemplar.shape[:2]
    if bake is None:
        scale = check_int("scale", scale, minimum=1, maximum=8)
        bake = texture.bake((scale * h, scale * w), origin=origin, pixel_size=pixel_size)
    else:
        bake = check_image("bake", bake, channels=(3,))
        if bake.shape[0] < h or bake.shape[1] < w:
            raise ValueError(f"bake must be at least the exemplar's size {w}x{h}, got "
                             f"{bake.shape[1]}x{bake.shape[0]}")
    if coarse_zoom is not None:
        coarse_zoom = check_float("coarse_zoom", coarse_zoom, minimum=1.0)
    ce = cross_scale(exemplar)
    cb = cross_scale(bake, fine=ce.fine)
    try:  # an exemplar without two 32 x 32 windows (a 512 x 40 strip) has no floor: None
        prepared = reference_statistics(exemplar, max_windows=4)
        structure = structural_distance(bake[:h, :w], exemplar, max_windows=4, prepared=prepared)
        structure_far = structural_distance(bake, exemplar, max_windows=4, prepared=prepared)
    except ValueError:
        structure = structure_far = None
    coarse = None
    if coarse_zoom is not None and min(h, w) >= 192:  # coarse_copies' smallest photo
        view = texture.bake((h, w), origin=origin, pixel_size=coarse_zoom * pixel_size)
        try:
            coarse = coarse_copies(view[:, :, :3], exemplar, zoom=coarse_zoom)
        except ValueError:  # a view too small to show any magnification: nothing measured
            coarse = None
    return FitReport(
        bake_shape=tuple(bake.shape[:2]),
        band_power_distance_db=band_power_distance(exemplar, bake),
        band_power_exemplar_db=band_power(exemplar).power_db,
        band_power_texture_db=band_power(bake, segment=(h, w)).power_db,
        histogram_w1=histogram_w1(exemplar, bake),
        cross_scale_exemplar=ce.value,
        cross_scale_texture=cb.value,
        amplitude_exemplar=ce.amplitude,
        amplitude_texture=cb.amplitude,
        structure=structure,
        structure_far=structure_far,
        clipping=clipping(bake, exemplar),
        coarse=coarse,
    )
