"""Structural texture measures: Portilla-Simoncelli statistics, clipping, coarse-scale structure.

The private home of :func:`spectex.metrics.texture_statistics`,
:func:`~spectex.metrics.structural_distance`,
:func:`~spectex.metrics.clipped_fraction`, :func:`~spectex.metrics.clipping`
and :func:`~spectex.metrics.coarse_structure` (issue 22): measures that see
what band power per octave and colour histograms cannot, cross-faded double
images, random phases, broken structure, magnified copies and clipped
colours.

The statistics are those of Portilla and Simoncelli [1]_, computed here on a
complex steerable pyramid from ``pyrtools`` [2]_ (4 orientations, up to 4
scales): marginal statistics of the pixels and of the low-pass images at each
scale, central autocorrelations of the low-pass images and of the band
magnitudes, cross-orientation correlations of the magnitudes, cross-scale
correlations of the magnitudes and of the real parts against the
phase-doubled coarser band, and for colour images the correlations between a
luma and two chroma channels at each scale. Each statistic is expressed in a
unit where a difference of about 0.1 is noticeable (correlation
coefficients, logarithms of standard deviations, standardised moments), and
each group is one root-mean-square, so that the groups weigh alike.

References
----------
.. [1] J. Portilla, E. P. Simoncelli, "A parametric texture model based on
   joint statistics of complex wavelet coefficients", IJCV 40(1), 49-71, 2000.
.. [2] E. P. Simoncelli, W. T. Freeman, "The steerable pyramid: a flexible
   architecture for multi-scale derivative computation", ICIP 1995.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._results import AsDict
from ._validate import check_float, check_image, check_int

#: Orientations of the steerable pyramid.
ORIENTATIONS = 4
#: Side of the central autocorrelation window (lags -3..3), as in Portilla and Simoncelli.
LAGS = 7
#: Largest analysis window side, pixels.
MAX_WINDOW = 256
#: Smallest analysis window side, pixels.
MIN_WINDOW = 32
#: The statistics' groups, in order.
GROUPS = ("marginal", "energy", "lowpass_autocorrelation", "magnitude_autocorrelation",
          "cross_orientation", "cross_scale_magnitude", "cross_scale_phase", "colour")
#: A channel holds colour (and the colour group is used) when the reference's chroma
#: standard deviation is at least this fraction of its luma's.
_CHROMA_MIN = 0.02

#: Smallest group floor used as a weight (a group that does not vary across the photo's windows).
_FLOOR_MIN = 0.01

_KR, _KB = 0.2126, 0.0722  # Rec. 709 luma weights of R and B


# --------------------------------------------------------------------------
# Pieces
# --------------------------------------------------------------------------

def _levels(shape) -> int:
    """Pyramid scales for a window: the coarsest band keeps at least 8 samples a side (at most 4)."""
    side = min(shape)
    return int(max(1, min(4, int(np.floor(np.log2(side))) - 4)))


def _pyramid(x: np.ndarray, levels: int):
    """``(bands, lowpass)`` of a complex steerable pyramid; ``bands[s][o]`` complex, finest first."""
    import pyrtools as pt

    pyr = pt.pyramids.SteerablePyramidFreq(x, height=levels, order=ORIENTATIONS - 1, is_complex=True)
    bands = [[pyr.pyr_coeffs[(s, o)] for o in range(ORIENTATIONS)] for s in range(levels)]
    return bands, pyr.pyr_coeffs["residual_highpass"], pyr.pyr_coeffs["residual_lowpass"]


def _half_down(x: np.ndarray) -> np.ndarray:
    """Low-pass to half the Nyquist frequency and keep every second sample (in the Fourier domain:
    a raised-cosine fall-off from 1/8 to 1/4 cycle per pixel, then the central quarter of the spectrum)."""
    h, w = x.shape
    f = np.fft.fft2(x)
    fy = np.abs(np.fft.fftfreq(h))[:, None]
    fx = np.abs(np.fft.fftfreq(w))[None, :]
    r = np.maximum(fy, fx)
    mask = np.clip((0.25 - r) / 0.125, 0.0, 1.0)
    mask = 0.5 - 0.5 * np.cos(np.pi * mask)
    f *= mask
    hh, hw = h // 2, w // 2
    ky = np.r_[0:hh // 2, h - (hh - hh // 2):h]
    kx = np.r_[0:hw // 2, w - (hw - hw // 2):w]
    return np.real(np.fft.ifft2(f[np.ix_(ky, kx)])) / 4.0


def _expand(band: np.ndarray) -> np.ndarray:
    """Twice the size by zero-padding the spectrum (periodic interpolation), complex in, complex out."""
    h, w = band.shape
    f = np.fft.fft2(band)
    out = np.zeros((2 * h, 2 * w), dtype=complex)
    ky = np.r_[0:h - h // 2, 2 * h - h // 2:2 * h]
    kx = np.r_[0:w - w // 2, 2 * w - w // 2:2 * w]
    src_y = np.r_[0:h - h // 2, h - h // 2:h]
    src_x = np.r_[0:w - w // 2, w - w // 2:w]
    out[np.ix_(ky, kx)] = f[np.ix_(src_y, src_x)]
    return np.fft.ifft2(out) * 4.0


def _moments(x: np.ndarray):
    """``(mean, standard deviation, skewness, kurtosis)`` of all values."""
    x = x.ravel()
    m = x.mean()
    d = x - m
    d2 = d * d
    v = np.mean(d2)
    if v <= 1e-30:
        return float(m), 0.0, 0.0, 3.0
    return float(m), float(np.sqrt(v)), float(np.mean(d2 * d) / v ** 1.5), float(np.mean(d2 * d2) / v ** 2)


def _acf(x: np.ndarray, m: int = LAGS) -> np.ndarray:
    """Central autocorrelation coefficients (circular), lags in an ``m x m`` window, one of each
    symmetric pair and lag 0 left out: ``(m * m - 1) / 2`` values (fewer for small arrays)."""
    h, w = x.shape
    r = min(m // 2, (min(h, w) - 1) // 2)
    d = x - x.mean()
    f = np.fft.fft2(d)
    a = np.real(np.fft.ifft2(f * np.conj(f)))
    zero = a[0, 0]
    if zero <= 1e-30:
        return np.zeros((2 * r + 1) ** 2 // 2)
    out = []
    for dy in range(r + 1):
        for dx in range(-r, r + 1):
            if dy == 0 and dx <= 0:
                continue
            out.append(a[dy % h, dx % w] / zero)
    return np.asarray(out)


def _z(a: np.ndarray) -> np.ndarray:
    """Values standardised to mean 0 and mean square 1 (all 0 for a constant array), flat."""
    a = np.ravel(a) - np.mean(a)
    ms = float(np.mean(a * a))
    return a / np.sqrt(ms) if ms > 1e-30 else np.zeros_like(a)


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    """Correlation coefficient of two arrays of one shape (0 when either is constant).

    Arguments already standardised by :func:`_z` (flat) are used as they are. Sums of products,
    not ``np.dot``: on a shared machine BLAS threads made each call 100 times slower.
    """
    a = a if a.ndim == 1 else _z(a)
    b = b if b.ndim == 1 else _z(b)
    return float(np.mean(a * b))


def _log_sd(sd: float) -> float:
    return float(np.log(max(sd, 1e-6)))


# --------------------------------------------------------------------------
# The statistics of one window
# --------------------------------------------------------------------------

@dataclass(frozen=True)
class _Standard:
    """What both images are standardised by: the reference's luma mean and standard deviation, its
    chroma means, and whether it has colour."""

    mean: float
    sd: float
    chroma_mean: tuple
    colour: bool


def _opponent(image: np.ndarray):
    """Luma and two chroma channels (B - Y, R - Y) in float64; chroma None for grey."""
    img = image.astype(np.float64)
    if img.ndim == 2 or img.shape[2] < 3:
        grey = img if img.ndim == 2 else img[:, :, 0]
        return grey, None
    r, g, b = img[:, :, 0], img[:, :, 1], img[:, :, 2]
    y = _KR * r + (1.0 - _KR - _KB) * g + _KB * b
    return y, (b - y, r - y)


def _standard(reference: np.ndarray) -> _Standard:
    y, chroma = _opponent(reference)
    sd = float(y.std())
    if sd <= 1e-6:
        raise ValueError("reference is flat (constant luma): it has no texture to compare with")
    if chroma is None:
        return _Standard(float(y.mean()), sd, (0.0, 0.0), False)
    colour = max(float(c.std()) for c in chroma) >= _CHROMA_MIN * sd
    return _Standard(float(y.mean()), sd, tuple(float(c.mean()) for c in chroma), colour)


def _pixel_and_lowpass(y: np.ndarray, levels: int, groups: dict) -> None:
    """Marginals of the pixels (mean, log sd, skewness, log kurtosis, 1 % and 99 % quantiles) and of
    the low-pass image at each coarser scale (skewness, log kurtosis); the low-pass images'
    autocorrelations."""
    m, sd, sk, ku = _moments(y)
    q01, q99 = np.quantile(y, [0.01, 0.99])
    groups["marginal"] += [m, _log_sd(sd), sk, np.log(ku), q01, q99]
    low = y
    groups["lowpass_autocorrelation"].append(_acf(low))
    for _ in range(levels):
        low = _half_down(low)
        _, _, lsk, lku = _moments(low)
        groups["marginal"] += [lsk, np.log(lku)]
        groups["lowpass_autocorrelation"].append(_acf(low))


def _band_statistics(bands, mags, levels: int, groups: dict) -> None:
    """Each scale's band marginals, energies, magnitude autocorrelations and cross-orientation
    correlations; each pair of neighbouring scales' cross-scale magnitude and phase correlations."""
    zmags = [[_z(m_) for m_ in scale] for scale in mags]
    for s in range(levels):
        # the bands' own marginals (orientations pooled): log kurtosis of the real parts and the
        # magnitudes' coefficient of variation; a cross-fade of two copies pulls both towards a
        # Gaussian's (3 and 0.52)
        real = np.concatenate([b.real.ravel() for b in bands[s]])
        mag = np.concatenate([m_.ravel() for m_ in mags[s]])
        groups["marginal"] += [np.log(_moments(real)[3]), float(mag.std() / max(mag.mean(), 1e-12))]
        for o in range(ORIENTATIONS):
            groups["energy"].append(_log_sd(float(np.sqrt(np.mean(mags[s][o] ** 2)))))
            groups["magnitude_autocorrelation"].append(_acf(mags[s][o]))
            groups["cross_orientation"] += [_corr(zmags[s][o], zmags[s][p]) for p in range(o + 1, ORIENTATIONS)]
    for s in range(levels - 1):
        zreal = [_z(b.real) for b in bands[s]]
        for p in range(ORIENTATIONS):
            parent = _expand(bands[s + 1][p])
            amp = np.abs(parent)
            doubled = np.where(amp > 1e-12, parent * parent / np.maximum(amp, 1e-12), 0.0)
            zamp, zdr, zdi = _z(amp), _z(doubled.real), _z(doubled.imag)
            for o in range(ORIENTATIONS):
                groups["cross_scale_magnitude"].append(_corr(zmags[s][o], zamp))
                groups["cross_scale_phase"] += [_corr(zreal[o], zdr), _corr(zreal[o], zdi)]


def _colour_statistics(y, chroma, mags, std: _Standard, levels: int, groups: dict) -> None:
    """Chroma marginals, luma-chroma correlations at each scale, luma-chroma band magnitude
    correlations at each scale."""
    cs = [(c - cm) / std.sd for c, cm in zip(chroma, std.chroma_mean)]
    for c in cs:
        cm_, csd, csk, cku = _moments(c)
        groups["colour"] += [cm_, _log_sd(csd)]
        groups["colour"] += [csk, np.log(cku)] if csd >= _CHROMA_MIN else [0.0, np.log(3.0)]
    chans = [y, *cs]
    for s in range(levels + 1):
        groups["colour"] += [_corr(chans[0], chans[1]), _corr(chans[0], chans[2]), _corr(chans[1], chans[2])]
        if s < levels:
            chans = [_half_down(c) for c in chans]
    # band structure shared by luma and chroma: magnitudes per scale (orientations pooled)
    for c in cs:
        cb, _, _ = _pyramid(c, levels)
        for s in range(levels):
            cmag = np.concatenate([np.abs(b).ravel() for b in cb[s]])
            ymag = np.concatenate([m_.ravel() for m_ in mags[s]])
            groups["colour"].append(_corr(_z(ymag), _z(cmag)))


def _window_statistics(window: np.ndarray, std: _Standard, levels: int) -> dict:
    """The statistics of one analysis window, by group (1-D float64 arrays)."""
    y, chroma = _opponent(window)
    y = (y - std.mean) / std.sd
    groups = {g: [] for g in GROUPS}
    _pixel_and_lowpass(y, levels, groups)
    bands, highpass, lowpass = _pyramid(y, levels)
    mags = [[np.abs(b) for b in scale] for scale in bands]
    groups["energy"] += [_log_sd(float(highpass.std())), _log_sd(float(lowpass.std()))]
    _band_statistics(bands, mags, levels, groups)
    if std.colour and chroma is not None:
        _colour_statistics(y, chroma, mags, std, levels, groups)
    return {g: np.concatenate([np.atleast_1d(np.asarray(v, dtype=np.float64)) for v in vals])
            if vals else np.zeros(0) for g, vals in groups.items()}


def _distance(a: dict, b: dict) -> dict:
    """Per-group root-mean-square difference of two windows' statistics (groups present in both)."""
    return {g: float(np.sqrt(np.mean((a[g] - b[g]) ** 2))) for g in GROUPS if a[g].size and b[g].size}


def _total(groups: dict, weights: dict) -> float:
    """The groups' distances combined: root mean square over the groups of the weighted distances."""
    return float(np.sqrt(np.mean([(weights[g] * v) ** 2 for g, v in groups.items()]))) if groups else 0.0


# --------------------------------------------------------------------------
# Windows
# --------------------------------------------------------------------------

def _window_shape(reference_shape, window) -> tuple:
    h, w = reference_shape[:2]
    if window is None:
        side = (min(MAX_WINDOW, h // 2), min(MAX_WINDOW, w // 2))
    else:
        side = (window, window)
    levels = _levels(side)
    q = 2 ** (levels + 1)
    return (side[0] // q * q, side[1] // q * q), levels


def _grid(shape, window, count: int):
    """Top-left corners of up to ``count`` non-overlapping windows, spread evenly over ``shape``."""
    h, w = shape[:2]
    ny, nx = h // window[0], w // window[1]
    corners = []
    for i in range(ny):
        for j in range(nx):
            # spread the grid's leftover margin evenly
            y0 = i * window[0] + (h - ny * window[0]) * (2 * i + 1) // (2 * ny)
            x0 = j * window[1] + (w - nx * window[1]) * (2 * j + 1) // (2 * nx)
            corners.append((y0, x0))
    if len(corners) > count:
        pick = np.round(np.linspace(0, len(corners) - 1, count)).astype(int)
        corners = [corners[k] for k in pick]
    return corners


def _common_channels(image, reference):
    """Both as RGB when both have colour, else both as grey (luma); alpha dropped."""
    def colour(img):
        if img.ndim == 2:
            return img
        return img[:, :, :3] if img.shape[2] >= 3 else img[:, :, 0]

    a, b = colour(image), colour(reference)
    if a.ndim != b.ndim:
        a, b = _opponent(a)[0], _opponent(b)[0]
    return a, b


# --------------------------------------------------------------------------
# Public: statistics and the structural distance
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class TextureStatistics(AsDict):
    """Portilla-Simoncelli statistics of one image (:func:`texture_statistics`).

    Attributes
    ----------
    groups : dict of str to ndarray
        One 1-D float64 array per group of :data:`GROUPS` (``colour`` empty for grey
        images); the units are described in :func:`texture_statistics`.
    levels : int
        Scales of the steerable pyramid.
    """

    groups: dict
    levels: int


def texture_statistics(image, *, reference=None) -> TextureStatistics:
    """Portilla-Simoncelli texture statistics of an image.

    The image's luma (Rec. 709; grey as it is) is standardised by the mean
    and standard deviation of the ``reference``'s luma (the image's own
    without one) and analysed with a complex steerable pyramid of 4
    orientations and ``min(4, log2(side) - 4)`` scales. The groups:

    ``marginal``
        Mean, log standard deviation, skewness, log kurtosis and the 1 % and
        99 % quantiles of the pixels; skewness and log kurtosis of the
        low-pass image at each coarser scale.
    ``energy``
        Log root-mean-square of the high-pass residual, of every band's
        magnitude and of the low-pass residual.
    ``lowpass_autocorrelation``
        Autocorrelation coefficients of the low-pass image at each scale,
        lags within 7 x 7.
    ``magnitude_autocorrelation``
        The same for every band's magnitude.
    ``cross_orientation``
        Correlation coefficients of the magnitudes of each pair of
        orientations at each scale.
    ``cross_scale_magnitude``
        Of each band's magnitude with the magnitude of every orientation one
        scale coarser (upsampled).
    ``cross_scale_phase``
        Of each band's real part with the real and imaginary parts of the
        phase-doubled coarser band: what makes edges and lines sharp, and
        what a cross-fade or random phases destroy.
    ``colour``
        For a colour reference: the chroma channels' (B - Y, R - Y, in units
        of the reference luma's standard deviation) mean, log standard
        deviation, skewness and log kurtosis; the correlations between luma
        and the two chroma channels at each scale; the correlation of luma and
        chroma band magnitudes at each scale.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 32 x 32 pixels; values in [0, 1].
    reference : ndarray, optional
        The image whose luma mean and standard deviation standardise this one
        (and whose colour decides whether the colour group is used).

    Returns
    -------
    TextureStatistics

    References
    ----------
    Portilla and Simoncelli, IJCV 2000.
    """
    image = check_image("image", image, min_size=MIN_WINDOW)
    if reference is None:
        reference = image
    else:
        reference = check_image("reference", reference)
        image, reference = _common_channels(image, reference)
    std = _standard(reference)
    levels = _levels(image.shape[:2])
    return TextureStatistics(_window_statistics(image, std, levels), levels)


@dataclass(frozen=True, eq=False)
class StructuralDistance(AsDict):
    """A structural distance of an image to a reference (:func:`structural_distance`).

    Attributes
    ----------
    distance : float
        Mean over pairs (image window, reference window) of the statistics'
        distance.
    floor : float
        Mean over pairs of disjoint reference windows: how far the photo is
        from itself.
    ratio : float
        ``distance / floor``: about 1 is as close as the photo is to itself;
        a cross-faded or random-phase version of the photo gives well over 1.
    groups : dict of str to float
        ``distance`` per group of statistics.
    group_floors : dict of str to float
        ``floor`` per group.
    group_ratios : dict of str to float
        Their ratios: which statistics are off.
    window : tuple of int
        ``(h, w)`` of the analysis windows.
    windows : tuple of int
        ``(image windows, reference windows)`` used.
    copies : int
        Pairs of reference windows left out of ``floor`` as copies of one
        another (the reference repeats itself; 0 for a photo).
    """

    distance: float
    floor: float
    ratio: float
    groups: dict
    group_floors: dict
    group_ratios: dict
    window: tuple
    windows: tuple
    copies: int = 0


#: Two of the reference's windows whose lumas correlate by at least this are copies of one another (a photo
#: made by tiling a smaller one, or by repeating its content at a shift: game textures; JPEG leaves 0.97-1.0),
#: not two parts of a texture: their distance is not the photo's own spread and is left out of the floor. A
#: floor of random-coloured tiles on an exact grid reads 0.89-0.90, its windows' own cells different.
COPY_CORRELATION = 0.95


def _reference_windows(reference, window, levels, std, max_windows):
    corners = _grid(reference.shape, window, max_windows)
    return [_window_statistics(reference[y:y + window[0], x:x + window[1]], std, levels) for y, x in corners]


def _distinct_pairs(reference, window, max_windows):
    """The pairs ``(i, j)`` of the reference's windows (:func:`_grid`) that are not copies of one another
    (:data:`COPY_CORRELATION`)."""
    from .color import luma

    lum = luma(reference, dtype=np.float64)  # (grey as it is)
    cuts = []
    for y, x in _grid(reference.shape, window, max_windows):
        w = lum[y:y + window[0], x:x + window[1]]
        w = w - w.mean()
        cuts.append(w / max(float(np.sqrt(np.mean(w * w))), 1e-12))
    return [(i, j) for i in range(len(cuts)) for j in range(i + 1, len(cuts))
            if float(np.mean(cuts[i] * cuts[j])) < COPY_CORRELATION]


def reference_statistics(reference, *, window=None, max_windows: int = 9):
    """The reference's windows and their statistics, for several :func:`structural_distance` calls.

    Returns an opaque object to pass as ``structural_distance(image, reference,
    prepared=...)`` (the same reference, window and ``max_windows``).
    """
    reference = check_image("reference", reference)
    window, levels, std, stats, pairs = _prepare(reference, window, max_windows)
    return (reference.shape, reference.ndim, window, levels, std, stats, pairs)


def _prepare(reference, window, max_windows):
    if window is not None:
        window = check_int("window", window, minimum=MIN_WINDOW)
    max_windows = check_int("max_windows", max_windows, minimum=2)
    shape, levels = _window_shape(reference.shape, window)
    if min(shape) < MIN_WINDOW or len(_grid(reference.shape, shape, 2)) < 2:
        raise ValueError(f"reference must hold two disjoint windows of at least {MIN_WINDOW}x{MIN_WINDOW} "
                         f"pixels, got {reference.shape[1]}x{reference.shape[0]}"
                         + (f" for window={window}" if window is not None else ""))
    pairs = _distinct_pairs(reference, shape, max_windows)
    if window is None:
        # a reference whose windows are all copies of one another (a photo of four copies of one tile) has no
        # spread at that size: smaller windows, while two of them differ
        while not pairs:
            smaller, smaller_levels = _window_shape(shape, None)  # half of it, rounded as every window is
            if min(smaller) < MIN_WINDOW:
                break
            shape, levels = smaller, smaller_levels
            pairs = _distinct_pairs(reference, shape, max_windows)
    std = _standard(reference)
    stats = _reference_windows(reference, shape, levels, std, max_windows)
    if not pairs:  # copies at every size: their distances are all there is
        pairs = [(i, j) for i in range(len(stats)) for j in range(i + 1, len(stats))]
    return shape, levels, std, stats, pairs


def structural_distance(image, reference, *, window: int | None = None, max_windows: int = 9,
                        prepared=None) -> StructuralDistance:
    """How far an image's texture statistics are from a reference's, in units of the reference's own spread.

    The reference is cut into disjoint analysis windows (a grid of at most
    ``max_windows``; by default each half the reference's side, at most
    256 pixels), the image into windows of the same shape (at most
    ``max_windows``, spread evenly over it), and the Portilla-Simoncelli
    statistics of every window are computed (:func:`texture_statistics`,
    all standardised by the reference's luma). The distance of two windows
    is the root mean square over the groups of each group's root-mean-square
    difference; ``distance`` is its mean over all pairs (image window,
    reference window), ``floor`` its mean over the pairs of distinct
    reference windows, so that an image that is another part of the same
    photo scores ``ratio`` about 1. Two windows that are copies of one
    another (lumas correlated by :data:`COPY_CORRELATION` or more: a photo
    made of copies of a smaller tile) are no measure of the photo's spread
    and their pair is left out of the floor; where every pair is such
    (four copies of one tile), the default windows are halved until two
    differ. Deterministic.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture judged, at least one window in size.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo, at least two windows in size (64 x 32 pixels). Grey
        against colour compares lumas; alpha is ignored.
    window : int, optional
        Window side in pixels (>= 32) instead of the default.
    max_windows : int
        Most windows taken from each image (>= 2).
    prepared : optional
        :func:`reference_statistics` of this reference (same ``window`` and
        ``max_windows``), to save recomputing them.

    Returns
    -------
    StructuralDistance

    References
    ----------
    Portilla and Simoncelli, IJCV 2000.
    """
    image = check_image("image", image)
    reference = check_image("reference", reference)
    image, reference = _common_channels(image, reference)
    if prepared is not None and prepared[0] == reference.shape and prepared[1] == reference.ndim:
        _, _, shape, levels, std, ref_stats, distinct = prepared
    else:
        shape, levels, std, ref_stats, distinct = _prepare(reference, window, max_windows)
    max_windows = check_int("max_windows", max_windows, minimum=2)
    if image.shape[0] < shape[0] or image.shape[1] < shape[1]:
        raise ValueError(f"image must be at least the analysis window {shape[1]}x{shape[0]}, got "
                         f"{image.shape[1]}x{image.shape[0]}")
    img_stats = [_window_statistics(image[y:y + shape[0], x:x + shape[1]], std, levels)
                 for y, x in _grid(image.shape, shape, max_windows)]
    pairs = [_distance(a, b) for a in img_stats for b in ref_stats]
    floors = [_distance(ref_stats[i], ref_stats[j]) for i, j in distinct]
    names = [g for g in GROUPS if g in pairs[0]]
    groups = {g: float(np.mean([p[g] for p in pairs])) for g in names}
    group_floors = {g: float(np.mean([f[g] for f in floors])) for g in names}
    # each group in units of its own floor (the photo's own spread), so that none dominates by
    # being noisy and a sensitive one is not diluted; a floor under _FLOOR_MIN is held there
    weights = {g: 1.0 / max(group_floors[g], _FLOOR_MIN) for g in names}
    distance = float(np.mean([_total(p, weights) for p in pairs]))
    floor = float(np.mean([_total(f, weights) for f in floors]))
    return StructuralDistance(
        distance=distance, floor=floor, ratio=distance / floor if floor > 0 else float("inf"),
        groups=groups, group_floors=group_floors,
        group_ratios={g: groups[g] / group_floors[g] if group_floors[g] > 0 else float("inf") for g in names},
        window=tuple(shape), windows=(len(img_stats), len(ref_stats)),
        copies=len(ref_stats) * (len(ref_stats) - 1) // 2 - len(distinct))


# --------------------------------------------------------------------------
# Clipping
# --------------------------------------------------------------------------

def clipped_fraction(image, *, tolerance: float = 0.5 / 255.0) -> float:
    """Fraction of an image's channel values at 0 or 1 (within ``tolerance``).

    Every colour channel value counts (alpha, the fourth channel, is left
    out); an 8-bit value of 0 or 255 is clipped with the default tolerance
    of half a step.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
    tolerance : float
        In [0, 0.5).

    Returns
    -------
    float
        In [0, 1].
    """
    image = check_image("image", image)
    tolerance = check_float("tolerance", tolerance, minimum=0.0, maximum=0.49)
    img = image if image.ndim == 2 else image[:, :, :3] if image.shape[2] >= 3 else image[:, :, :1]
    return float(np.mean((img <= tolerance) | (img >= 1.0 - tolerance)))


@dataclass(frozen=True, eq=False)
class Clipping(AsDict):
    """Clipped values of an image against its reference (:func:`clipping`).

    Attributes
    ----------
    image, reference : float
        :func:`clipped_fraction` of each.
    margin : float
        How much more than the reference's the image may have.
    excess : float
        ``image - reference`` (negative: less clipping than the photo).
    within : bool
        ``image <= reference + margin``.
    """

    image: float
    reference: float
    margin: float
    excess: float
    within: bool


def clipping(image, reference, *, margin: float = 0.01, tolerance: float = 0.5 / 255.0) -> Clipping:
    """The image's clipped fraction against the reference's own plus ``margin`` (1 point by default).

    Parameters
    ----------
    image, reference : ndarray, shape (H, W) or (H, W, C)
    margin : float
        In [0, 1].
    tolerance : float
        As in :func:`clipped_fraction`.

    Returns
    -------
    Clipping
    """
    margin = check_float("margin", margin, minimum=0.0, maximum=1.0)
    a = clipped_fraction(image, tolerance=tolerance)
    b = clipped_fraction(reference, tolerance=tolerance)
    return Clipping(image=a, reference=b, margin=margin, excess=a - b, within=bool(a <= b + margin))


# --------------------------------------------------------------------------
# Magnified copies of the photo in a zoomed-out view
# --------------------------------------------------------------------------

#: Side of the template, pixels, at the scale where the search is made.
_TEMPLATE = 48
#: Band of the search (a difference of Gaussians, pixels at the template's scale).
_BAND = (1.0, 3.0)


def _resample(x: np.ndarray, factor: float) -> np.ndarray:
    """``x`` scaled by ``factor`` (a Gaussian pre-filter of ``0.5 / factor`` pixels when shrinking)."""
    from scipy import ndimage

    if factor < 1.0:
        x = ndimage.gaussian_filter(x, 0.5 / factor, mode="reflect")
    shape = (max(1, round(x.shape[0] * factor)), max(1, round(x.shape[1] * factor)))
    zy, zx = shape[0] / x.shape[0], shape[1] / x.shape[1]
    return ndimage.zoom(x, (zy, zx), order=1, mode="reflect", grid_mode=True)


def _bandpass(x: np.ndarray) -> np.ndarray:
    from scipy import ndimage

    return ndimage.gaussian_filter(x, _BAND[0], mode="reflect") - ndimage.gaussian_filter(x, _BAND[1], mode="reflect")


def _disc(t: int) -> np.ndarray:
    yy, xx = np.mgrid[0:t, 0:t] - (t - 1) / 2.0
    return (yy * yy + xx * xx) <= (t / 2.0) ** 2


def _pieces(image: np.ndarray, count: int, angles: int):
    """Up to ``count`` pieces of ``image`` (a grid), each rotated by ``angles`` angles over the full
    turn, as float32 stacks ``(angles, t, t)`` of unit-norm zero-mean templates inside the disc of
    :data:`_TEMPLATE` pixels (a rotation that leaves a piece flat is dropped)."""
    from scipy import ndimage, special

    t = _TEMPLATE
    mask = _disc(t)
    h, w = image.shape
    n = max(1, int(np.ceil(np.sqrt(count))))  # overlapping where the image holds fewer disjoint pieces
    ys = [int(round((h - t) * (i + 0.5) / n)) for i in range(n)]
    xs = [int(round((w - t) * (j + 0.5) / n)) for j in range(n)]
    pad = int(np.ceil(t * 0.21)) + 1  # a disc of t rotated stays inside t + 2 pad
    padded = np.pad(image, pad, mode="reflect")
    side = t + 2 * pad
    regions = np.stack([padded[y:y + side, x:x + side] for y in ys for x in xs][:count])
    centre = (side - 1) / 2.0
    rotated = np.empty((len(regions), angles, t, t))
    for k in range(angles):
        # scipy.ndimage.rotate's mapping (output pixel o reads input M o + offset about the centre),
        # all pieces at once and only the central t x t that the disc uses
        angle = 360.0 * k / angles
        c, s = special.cosdg(angle), special.sindg(angle)
        rot = np.array([[c, s], [-s, c]])
        offset = centre - rot @ np.array([centre, centre]) + rot @ np.array([pad, pad], dtype=np.float64)
        matrix = np.eye(3)
        matrix[1:, 1:] = rot
        ndimage.affine_transform(regions, matrix, np.array([0.0, *offset]), output_shape=(len(regions), t, t),
                                 output=rotated[:, k], order=1, mode="reflect")
    rotated *= mask
    inside = rotated[:, :, mask]
    inside -= inside.mean(axis=2, keepdims=True)
    norm = np.sqrt(np.sum(inside * inside, axis=2))
    rotated[:, :, mask] = inside
    out = []
    for piece, norms in zip(rotated, norm):
        keep = norms > 1e-12
        if np.any(keep):
            out.append((piece[keep] / norms[keep, None, None]).astype(np.float32))
    return out, mask


@dataclass(frozen=True, eq=False)
class _Target:
    """A target image of :func:`_best_match`, prepared once for all templates."""

    #: Its FFT (``rfft2``, complex64).
    spectrum: np.ndarray
    #: At each place, the inverse norm of its zero-mean values under the disc (0 where flat), float32.
    inv: np.ndarray
    #: Where it is flat under the disc (no correlation defined), or None.
    flat: np.ndarray | None


def _search_targets(images, mask) -> list:
    """The targets of :func:`_best_match` (one shape), each prepared once (:class:`_Target`)."""
    import scipy.fft as sfft

    h, w = images[0].shape
    fm = np.conj(sfft.rfft2(mask.astype(np.float64), s=(h, w)))
    n = float(mask.sum())
    out = []
    for image in images:
        f = sfft.rfft2(image)
        s1 = sfft.irfft2(fm * f, s=(h, w))
        s2 = sfft.irfft2(fm * sfft.rfft2(image * image), s=(h, w))
        var = np.maximum(s2 - s1 * s1 / n, 0.0)
        ok = var > 1e-6 * max(float(var.max()), 1e-30)
        inv = np.where(ok, 1.0 / np.sqrt(np.maximum(var, 1e-30)), 0.0).astype(np.float32)
        out.append(_Target(f.astype(np.complex64), inv, None if ok.all() else ~ok))
    return out


#: Elements of one batch of correlations in :func:`_best_match` (bounds its memory: about 16 bytes each).
_BATCH = 1 << 22


def _best_match(targets, templates) -> list:
    """For each target (:func:`_search_targets`), the highest normalised cross-correlation of any
    template (a stack ``(k, t, t)``) at any place in it, wrapping around its borders (a fitted
    texture's tile is the photo made periodic, so a piece of it may hold the photo's opposite
    borders side by side). The correlations are float32 FFTs, batched over the templates, on one
    thread (``fit_report`` runs this search beside its other measures, ``spectex fit`` beside the fit)."""
    import scipy.fft as sfft

    h, w = targets[0].inv.shape
    step = max(1, _BATCH // (h * w))
    best = [-1.0] * len(targets)
    for start in range(0, len(templates), step):
        chunk = templates[start:start + step]
        # the templates are zero outside their t rows: rows first (t of them), then the columns
        ft = sfft.fft(sfft.rfft(chunk, n=w, axis=2), n=h, axis=1)
        np.conjugate(ft, out=ft)
        for k, target in enumerate(targets):
            num = sfft.irfft2(ft * target.spectrum, s=(h, w), axes=(1, 2))
            num *= target.inv
            if target.flat is not None:
                num[:, target.flat] = -1.0
            best[k] = max(best[k], float(num.max()))
    return best


def _random_phase(x: np.ndarray) -> np.ndarray:
    """The same amplitude spectrum with random phases (a fixed seed: deterministic), mean kept."""
    f = np.fft.fft2(x)
    phase = np.angle(np.fft.fft2(np.random.default_rng(0x22).random(x.shape)))
    phase[0, 0] = 0.0
    return np.real(np.fft.ifft2(np.abs(f) * np.exp(1j * phase)))


#: The photo is searched at a half and a quarter of its resolution (a piece is 96 or 192 photo pixels
#: across): the finer sees edges, the coarser the shapes of stones and bricks, away from the view's
#: own fine layer.
_SEARCH_SCALES = (2.0, 4.0)
#: ... and at its full resolution for the magnifications neither of those can hold a piece of: the
#: largest a view shows (the legacy fit's layer at 64 times, 8 times in a view at zoom 8, was missed,
#: 0.01 for a copy at 30 %); there a piece is the photo's 48 pixels, a stone or two.
_FULL_SCALE = 1.0


#: Offsets (fractions of the photo's side, down and across) of the photo's own zoom-outs whose scores make
#: its range (:func:`coarse_copies`): the first always, the others where the view is over the first.
_OWN_ROLLS = ((0.0, 0.0), (0.25, 0.5), (0.5, 0.25), (0.75, 0.75))
#: Seeds of the photo's own zoom-outs laid as a mosaic (:func:`_own_mosaic`), searched with the other offsets.
_OWN_MOSAICS = (0x51, 0x52)
#: Whether the photo with its lighting evened out (where it has lighting: ``_lighting.is_lighting``) is its
#: own too, its zoom-out searched at the same offsets and as the same mosaics (:func:`_own_evened`).
_OWN_EVENED = True


def _photo_targets(photo: np.ndarray) -> dict:
    """For each search scale at which the photo holds enough places, the photo and the photo with
    random phases there, band-passed, as targets of :func:`_best_match` (computed once per photo)."""
    out = {}
    for scale in (*_SEARCH_SCALES, _FULL_SCALE):
        if min(photo.shape) / scale < 2 * _TEMPLATE:
            continue  # too few places in the photo for a best match to mean anything
        small = _resample(photo, 1.0 / scale) if scale != 1.0 else photo
        out[scale] = _search_targets([_bandpass(small), _bandpass(_random_phase(small))], _disc(_TEMPLATE))
    return out


def _search(view: np.ndarray, targets: dict, zoom: float, magnifications, angles: int, pieces: int):
    """Array ``(search scales, magnifications)``: for pieces of the view brought to the photo's scale
    as if they were the photo magnified that much, the median over pieces of how much better their best
    match anywhere in the photo, at any angle, is than their best match in the photo with random phases
    (the same spectrum, no shapes: the search's chance level for these very pieces); nan where the view
    is too small to hold a piece. The last row is the photo's full resolution (:data:`_FULL_SCALE`),
    searched only for the magnifications the rows before leave at nan. ``targets``: :func:`_photo_targets`."""
    scales = (*_SEARCH_SCALES, _FULL_SCALE)
    out = np.full((len(scales), len(magnifications)), np.nan)
    for i, scale in enumerate(scales):
        if scale not in targets:
            continue
        todo = [j for j in range(len(magnifications))
                if min(view.shape) * zoom / (magnifications[j] * scale) >= _TEMPLATE + 2
                and (scale != _FULL_SCALE or not np.any(np.isfinite(out[:i, j])))]
        for j in todo:
            factor = zoom / (magnifications[j] * scale)
            work = _bandpass(_resample(view, factor))
            groups, _ = _pieces(work, pieces, angles)
            gains = []
            for rotated in groups:
                real, chance = _best_match(targets[scale], rotated)
                gains.append(real - chance)
            out[i, j] = float(np.median(gains))
    return out


@dataclass(frozen=True, eq=False)
class _CoarseReference:
    """What :func:`coarse_copies` computes of the photo alone (:func:`coarse_reference`)."""

    key: tuple       #: (photo digest, view shape, zoom, magnifications, angles, pieces)
    targets: dict    #: :func:`_photo_targets`
    own: np.ndarray  #: the photo's own search at the first offset (nan where not searched)


def _own_view(small: np.ndarray, shape, roll) -> np.ndarray:
    """The photo zoomed out (``small``) repeated over ``shape``, from the offset ``roll`` (fractions of its side)."""
    reps = (-(-shape[0] // small.shape[0]) + 1, -(-shape[1] // small.shape[1]) + 1)
    dy, dx = round(roll[0] * small.shape[0]), round(roll[1] * small.shape[1])
    return np.tile(small, reps)[dy:dy + shape[0], dx:dx + shape[1]]


def _own_mosaic(small: np.ndarray, shape, seed: int) -> np.ndarray:
    """The photo zoomed out (``small``) over ``shape`` in cells of half its size, each cell a piece of the
    photo from a random place (wrapping), every other row of cells shifted by half a cell: the photo's
    content at its own scale with no lattice of copies, as a texture that does not repeat shows it (the
    stochastic layer's patches are half a tile)."""
    rng = np.random.default_rng(seed)
    sh, sw = small.shape
    ch, cw = max(1, sh // 2), max(1, sw // 2)
    ny, nx = -(-shape[0] // ch), -(-shape[1] // cw) + 1
    out = np.empty((ny * ch, nx * cw))
    for i in range(ny):
        for j in range(nx):
            out[i * ch:(i + 1) * ch, j * cw:(j + 1) * cw] = np.roll(
                small, (-int(rng.integers(sh)), -int(rng.integers(sw))), axis=(0, 1))[:ch, :cw]
        if i % 2:
            out[i * ch:(i + 1) * ch] = np.roll(out[i * ch:(i + 1) * ch], cw // 2, axis=1)
    return out[:shape[0], :shape[1]]


def _own_evened(p: np.ndarray):
    """The photo's luma ``p`` with its lighting divided out where it has lighting (a drift the fit evens
    out, ``spectex._lighting.is_lighting``), else None: light is not the texture, and a texture made of the
    photo evened out is as much the photo's own as one that keeps its light."""
    from ._lighting import even_lighting

    if not _OWN_EVENED:
        return None
    flat, light = even_lighting(p)
    return None if light is None else flat


def _own_search(p: np.ndarray, shape, zoom, mags, angles, pieces, targets) -> np.ndarray:
    """The photo's own scores at the first of :data:`_OWN_ROLLS` (not yet held at 0 or more)."""
    # The photo's own: the photo repeated at its own scale, seen from as far (nothing but what the
    # photo shows, continued): a structured photo's lattice matches itself at some magnifications.
    return _search(_own_view(_resample(p, 1.0 / zoom), shape, _OWN_ROLLS[0]), targets, zoom, mags, angles, pieces)


def _digest(x: np.ndarray) -> str:
    import hashlib

    return hashlib.blake2b(np.ascontiguousarray(x).tobytes(), digest_size=16).hexdigest() + str(x.shape)


def _coarse_args(reference, zoom, magnifications, angles, pieces):
    reference = check_image("reference", reference, min_size=192)
    zoom = check_float("zoom", zoom, minimum=1.0)
    angles = check_int("angles", angles, minimum=1)
    pieces = check_int("pieces", pieces, minimum=1, maximum=64)
    try:
        mags = tuple(check_float("magnifications[]", m, minimum=1.5) for m in magnifications)
    except TypeError:
        raise TypeError(f"magnifications must be a sequence of numbers, got {magnifications!r}") from None
    if not mags:
        raise ValueError("magnifications must not be empty")
    p = _opponent(reference if reference.ndim == 2 else reference[:, :, :3] if reference.shape[2] >= 3
                  else reference[:, :, 0])[0]
    return p, zoom, mags, angles, pieces


def coarse_reference(reference, *, view_shape, zoom: float, magnifications=(2, 4, 8, 16, 32, 64, 128, 256),
                     angles: int = 36, pieces: int = 9):
    """What :func:`coarse_copies` computes of the photo alone, for views of ``view_shape`` (H, W).

    Half of :func:`coarse_copies`' work is the photo's own range (the same
    search on the photo repeated at its own scale) and the photo's
    transforms; they need no texture, so they can be made before a fit is
    done (``spectex fit`` makes them while it fits). Returns an opaque object
    to pass as ``coarse_copies(view, reference, prepared=...)`` with the same
    reference and the same other arguments, for a view of that shape.
    """
    p, zoom, mags, angles, pieces = _coarse_args(reference, zoom, magnifications, angles, pieces)
    try:
        shape = (int(view_shape[0]), int(view_shape[1]))
    except (TypeError, ValueError, IndexError):
        raise TypeError(f"view_shape must be (H, W), got {view_shape!r}") from None
    if min(shape) < 2 * _TEMPLATE:
        raise ValueError(f"view_shape must be at least {2 * _TEMPLATE} pixels a side, got {shape}")
    targets = _photo_targets(p)
    return _CoarseReference(key=(_digest(p), shape, zoom, mags, angles, pieces), targets=targets,
                            own=_own_search(p, shape, zoom, mags, angles, pieces, targets))


@dataclass(frozen=True, eq=False)
class CoarseCopies(AsDict):
    """Magnified copies of a photo found in a zoomed-out view (:func:`coarse_copies`).

    Attributes
    ----------
    value : float
        How much better pieces of the view match the photo magnified (the best
        normalised cross-correlation anywhere in the photo, at any angle) than
        they match the photo with random phases (the search's chance level
        for those pieces): the median over pieces, the largest over the
        magnifications. About 0 for a view without copies; 0.3 to 0.7 for a
        copy blended with other content.
    reference : float
        The photo's own at the magnification that decides ``value``: the same
        search on the photo repeated at its own scale and seen from as far
        (at least 0); where the view is over it, the highest of that search
        at four offsets of the photo and on two mosaics of it, and of the
        photo with its lighting evened out where it has lighting (the top
        of its own range).
    within : bool
        ``value <= reference + tolerance`` at every magnification: no
        magnified copies.
    tolerance : float
        The allowance over the photo's own.
    magnifications : tuple of float
        Magnifications searched, relative to the photo.
    per_magnification : tuple of float
        For each magnification, ``value`` found there less the photo's own
        (nan where the view cannot show a copy of that size).
    zoom : float
        The view's pixel size in photo pixels.
    """

    value: float
    reference: float
    within: bool
    tolerance: float
    magnifications: tuple
    per_magnification: tuple
    zoom: float


def coarse_copies(view, reference, *, zoom: float, magnifications=(2, 4, 8, 16, 32, 64, 128, 256),
                  angles: int = 36, pieces: int = 9, tolerance: float = 0.06, prepared=None) -> CoarseCopies:
    """Search a zoomed-out view of a texture for the photo magnified (giant copies of its stones).

    A texture fitted to a photo shows, far away, what the photo says about
    larger scales; a texture whose coarse layers are the photo magnified
    4 to 256 times shows giant copies of its stones and bricks instead. This
    searches for them directly. For each of ``magnifications`` (relative to
    the photo), the view is resampled as if it were the photo magnified that
    much, brought back to the photo's scale (at a half and at a quarter of
    the photo's resolution: edges, and the shapes of stones; at its full
    resolution for the largest magnifications, which the view is too small
    to show at the others), band-passed
    (luma, a difference of Gaussians of 1 and 3 pixels); ``pieces`` discs of
    48 pixels from a grid over it, each at ``angles`` rotations over the
    full turn (layers are rotated by any angle), are matched everywhere in
    the photo by normalised cross-correlation, and everywhere in the photo
    with random phases (the same spectrum, no shapes): a piece's gain is the
    difference, the magnification's score the median gain over the pieces.
    A copy scores its correlation less chance; anything else about 0,
    however smooth or busy it is. Magnifications whose pieces the view is
    too small to hold are skipped (nan).

    The photo's own range is the same search made on the photo repeated at
    its own scale and seen from as far (what the photo shows, and nothing
    else, continued): a structured photo's lattice matches itself at some
    magnifications (bricks at 16 times: about 0.07), a texture similar
    across scales (rock, moon's craters) scores higher, gravel about 0; the
    view is judged magnification by magnification against it. Where the
    view is over it by more than ``tolerance``, the search is made again on
    the photo's zoom-out at three other offsets (its pieces then fall on
    other parts of the photo) and on two mosaics of it (pieces of half its
    side from random places: the photo's content with no lattice of copies,
    as a texture that does not repeat shows it), and, where the photo has
    lighting (a drift the fit evens out), on the same views of the photo
    with its lighting evened out (light is not the texture); the highest is
    kept: on a self-similar photo one offset is not the photo's range (moon
    at 4 times: 0.15 to 0.28 between offsets, and one offset flagged
    another), nor is a lattice (moon's craters at random cluster like a
    larger one: 0.04 against 0.055 at 16 times), nor the photo as lit (moon
    evened out: up to 0.097 at 16 times against 0.055).

    Parameters
    ----------
    view : ndarray, shape (H, W) or (H, W, C)
        The texture rendered at ``zoom`` times the photo's pixel size (e.g.
        ``bake(texture, (512, 512), pixel_size=8 * p)``), at least 96 pixels a side.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo, at least 192 pixels a side.
    zoom : float
        The view's pixel size over the photo's (>= 1).
    magnifications : sequence of float
        Magnifications searched (each >= 1.5).
    angles : int
        Rotations searched over 360 degrees (>= 1).
    pieces : int
        Pieces of the view matched per magnification (1 to 64).
    tolerance : float
        Allowance over the photo's own (>= 0): the scatter of the median gain
        of views without copies is about 0.02 (512-pixel photos) to 0.04 (256).
    prepared : optional
        :func:`coarse_reference` of this reference for views of this shape,
        with the same ``zoom``, ``magnifications``, ``angles`` and ``pieces``
        (the photo's half of the work, made once; another one is refused).

    Returns
    -------
    CoarseCopies

    References
    ----------
    J. P. Lewis, "Fast normalized cross-correlation", Vision Interface 1995.
    """
    view = check_image("view", view, min_size=2 * _TEMPLATE)
    p, zoom, mags, angles, pieces = _coarse_args(reference, zoom, magnifications, angles, pieces)
    tolerance = check_float("tolerance", tolerance, minimum=0.0)
    v = _opponent(view)[0]
    key = (_digest(p) if prepared is not None else None, v.shape, zoom, mags, angles, pieces)
    if isinstance(prepared, _CoarseReference) and prepared.key == key:
        targets, own = prepared.targets, prepared.own.copy()
    else:
        if prepared is not None:
            raise ValueError("prepared is coarse_reference() of another reference, view shape or arguments")
        targets = _photo_targets(p)
        own = _own_search(p, v.shape, zoom, mags, angles, pieces, targets)
    per = _search(v, targets, zoom, mags, angles, pieces)
    # Its range: where the view is over it by more than the tolerance, the same search on the photo's
    # zoom-out at other offsets (its pieces fall on other parts of the photo), the highest kept. On a
    # photo similar across scales (moon's craters) the median gain over 9 pieces is large and its
    # scatter between offsets too (0.15 to 0.28 at 4 times): one offset flagged the photo's own
    # zoom-out at another.
    # The photo's zoom-out laid as a mosaic (each cell the photo from a random offset) is the photo's own
    # too: what a texture that does not repeat shows of it from afar. On moon the lattice of copies scored
    # about 0.02 at a magnification of 16 where the default fit's finest layer alone, the photo's content
    # at its own scale with no coarse layer at all, scored 0.07-0.10: clusters of small craters placed at
    # random look like a large one, a lattice of them does not.
    # The photo with its lighting evened out is its own too, where it has lighting (the fit draws it so):
    # moon's fit, its finest layer alone, read 0.08-0.13 at 16 times against 0.02-0.06 for the photo's own
    # views as it is, and 0.04-0.10 for the same views of the photo evened out.
    views = None  # the photo's other zoom-outs, made once, where a magnification first needs them
    for j in range(len(mags)):
        if not np.any(per[:, j] - own[:, j] > tolerance):
            continue
        if views is None:
            small = _resample(p, 1.0 / zoom)
            views = [_own_view(small, v.shape, roll) for roll in _OWN_ROLLS[1:]]
            views += [_own_mosaic(small, v.shape, seed) for seed in _OWN_MOSAICS]
            evened = _own_evened(p)
            if evened is not None:
                flat = _resample(evened, 1.0 / zoom)
                views += [_own_view(flat, v.shape, roll) for roll in _OWN_ROLLS]
                views += [_own_mosaic(flat, v.shape, seed) for seed in _OWN_MOSAICS]
        for own_view in views:
            again = _search(own_view, targets, zoom, (mags[j],), angles, pieces)[:, 0]
            own[:, j] = np.where(np.isfinite(again), np.fmax(own[:, j], again), own[:, j])
    own = np.where(np.isfinite(own), np.maximum(own, 0.0), np.nan)  # below 0 is the search's scatter
    excess = per - own
    if not np.any(np.isfinite(excess)):
        raise ValueError(f"view of {view.shape[1]}x{view.shape[0]} pixels at zoom={zoom:g} cannot show any of "
                         f"the magnifications {mags}")
    i, j = np.unravel_index(np.nanargmax(excess), excess.shape)
    value, ref = float(per[i, j]), float(own[i, j])
    return CoarseCopies(value=value, reference=ref, within=bool(value <= ref + tolerance), tolerance=tolerance,
                        magnifications=mags, per_magnification=tuple(_nanmax_columns(excess)), zoom=zoom)


def _nanmax_columns(a: np.ndarray):
    """Largest finite value of each column, nan for a column without one (no warning)."""
    return [float(np.max(c[np.isfinite(c)])) if np.any(np.isfinite(c)) else float("nan") for c in a.T]


# --------------------------------------------------------------------------
# One-off content of the photo, repeated in a texture
# --------------------------------------------------------------------------

#: The photo's rarity is measured at about this many pixels on its longer side.
_RARE_WORK = 160
#: Patch side (pixels at that scale), the step between patches, and PCA dimensions of a patch.
_RARE_PATCH, _RARE_STEP, _RARE_DIMS = 8, 3, 16
#: A patch's rarity is its distance to its 4th-nearest patch elsewhere in the photo ...
_RARE_K = 4
#: ... at least this many patch sides away (so that an object a few patches across is not its own neighbour).
_RARE_APART = 2
#: Smallest side of a piece of the one-off region at the view's scale that can be searched for.
_RARE_MIN_TEMPLATE = 8
#: Pieces of the one-off region searched for (its rarest patches, twice a patch's side, apart).
_RARE_TEMPLATES = 4
#: The view is searched over at most this many pixels a side (its top-left corner): bounded work.
_RARE_MAX_VIEW = 2048


@dataclass(frozen=True, eq=False)
class OneOffRepeats(AsDict):
    """Content a photo shows once, and how often a texture shows it (:func:`one_off_repeats`).

    Attributes
    ----------
    rarity : float
        The photo's rarest patch: its distance to the nearest patches
        elsewhere in the photo, less the median patch's, in units of the
        spread of those distances (90th percentile less median). Ground,
        grass, bricks, craters and stars: under 8; a tripod's leg on a
        lawn: about 20 to 30.
    threshold : float
        Rarity above which a patch is one-off content.
    box : tuple of int or None
        ``(y0, x0, y1, x1)`` in photo pixels: the largest region of one-off
        patches; None where the photo has none.
    copies : int
        Places where the view shows that region (normalised correlation of
        the luma at least ``min_correlation``; the view's top-left 2048 x
        2048 pixels at most): a texture that tiles the photo shows it once
        per photo area, a faithful texture at most once.
    per_photo_area : float
        ``copies`` over the searched area in photo areas.
    within : bool
        No one-off content, or shown at most once.
    """

    rarity: float
    threshold: float
    box: tuple | None
    copies: int
    per_photo_area: float
    within: bool


def _rarity(photo: np.ndarray):
    """Per patch of the photo at :data:`_RARE_WORK` pixels, its rarity (:class:`OneOffRepeats`); the patches'
    corners and the factor from that scale to the photo's pixels."""
    from scipy import ndimage
    from scipy.spatial import cKDTree

    x = photo[:, :, None] if photo.ndim == 2 else photo[:, :, :3]
    x = x.astype(np.float64)
    f = max(1.0, max(x.shape[:2]) / _RARE_WORK)
    if f > 1.0:
        x = ndimage.gaussian_filter(x, (0.5 * f, 0.5 * f, 0.0), mode="reflect")
        x = ndimage.zoom(x, (1.0 / f, 1.0 / f, 1.0), order=1, grid_mode=True, mode="reflect")
    p = _RARE_PATCH
    ys = np.arange(0, x.shape[0] - p + 1, _RARE_STEP)
    xs = np.arange(0, x.shape[1] - p + 1, _RARE_STEP)
    windows = np.lib.stride_tricks.sliding_window_view(x, (p, p), axis=(0, 1))[ys][:, xs]
    patches = windows.reshape(len(ys) * len(xs), -1)
    corners = np.stack(np.meshgrid(ys, xs, indexing="ij"), axis=-1).reshape(-1, 2)
    centred = patches - patches.mean(axis=0)
    # the principal components from the patches' covariance (a 192 x 192 eigenproblem, not an SVD of
    # thousands of patches: 0.1 s against 1.3 s)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    features = centred @ vectors[:, ::-1][:, :_RARE_DIMS]
    n = min(len(features), 12 * _RARE_K + 1 + (2 * (-(-_RARE_APART * p // _RARE_STEP)) + 1) ** 2)  # past the near ones
    _, idx = cKDTree(features).query(features, k=n)
    # the candidates' distances over the whole patch, not the components alone: what sets a rare patch
    # apart (a colour no other patch has) is little of the photo's variance, so little of its components
    # (by the patches' Gram matrix, one product: |a - b|^2 = |a|^2 + |b|^2 - 2 a.b about the patches' mean, in
    # float64; gathering every candidate's 192 values instead moved 0.4 GB and took 1.5 s of a fit)
    gram = centred @ centred.T
    norms = np.diagonal(gram)
    dist = np.sqrt(np.maximum(norms[:, None] + norms[idx] - 2.0 * np.take_along_axis(gram, idx, axis=1), 0.0))
    apart = np.max(np.abs(corners[idx] - corners[:, None, :]), axis=2) >= _RARE_APART * p
    ranked = np.where(apart, dist, np.inf)
    ranked.sort(axis=1)
    d = ranked[:, _RARE_K - 1]
    d = np.where(np.isfinite(d), d, dist[:, -1])
    median = float(np.median(d))
    spread = float(np.percentile(d, 90)) - median
    rarity = (d - median) / spread if spread > 1e-9 * max(median, 1e-12) else np.zeros_like(d)
    return rarity, corners, f


def _one_off_region(rarity, corners, f, shape, threshold):
    """The largest connected region of patches over ``threshold``: its bounding box in photo pixels and,
    inside it, up to :data:`_RARE_TEMPLATES` squares of twice a patch's side (photo pixels, ``(y0, x0,
    y1, x1)``) around its rarest patches, apart from each other; ``(None, [])`` without one."""
    from scipy import ndimage

    rare = rarity > threshold
    if not np.any(rare):
        return None, []
    p = _RARE_PATCH
    h = int(corners[:, 0].max()) + p
    w = int(corners[:, 1].max()) + p
    mask = np.zeros((h, w), bool)
    for y, x in corners[rare]:
        mask[y:y + p, x:x + p] = True
    labels, count = ndimage.label(mask, structure=np.ones((3, 3)))
    sizes = ndimage.sum(mask, labels, index=np.arange(1, count + 1))
    largest = int(np.argmax(sizes)) + 1
    ys, xs = ndimage.find_objects(labels)[largest - 1]
    box = (int(np.floor(ys.start * f)), int(np.floor(xs.start * f)),
           min(shape[0], int(np.ceil(ys.stop * f))), min(shape[1], int(np.ceil(xs.stop * f))))
    inside = np.flatnonzero(rare & (labels[corners[:, 0], corners[:, 1]] == largest))
    squares, taken = [], []
    for i in inside[np.argsort(-rarity[inside])]:
        cy, cx = corners[i] + p / 2.0
        if any(max(abs(cy - ty), abs(cx - tx)) < 2 * p for ty, tx in taken):
            continue
        taken.append((cy, cx))
        side = 2 * p * f
        y0 = int(round(min(max(cy * f - side / 2, 0), shape[0] - side)))
        x0 = int(round(min(max(cx * f - side / 2, 0), shape[1] - side)))
        squares.append((y0, x0, y0 + int(round(side)), x0 + int(round(side))))
        if len(squares) == _RARE_TEMPLATES:
            break
    return box, squares


def one_off_content(photo: np.ndarray, *, threshold: float = 8.0):
    """``(box, squares, rarity)``: the photo's largest region of one-off content (photo pixels, ``(y0, x0,
    y1, x1)``, or None), the squares around its rarest patches, and the rarest patch's rarity
    (:func:`one_off_repeats`; the fit leaves the region out of its tile)."""
    rarity, corners, f = _rarity(photo)
    box, squares = _one_off_region(rarity, corners, f, photo.shape, threshold)
    return box, squares, float(rarity.max())


def _count_copies(view: np.ndarray, template: np.ndarray, min_correlation: float) -> int:
    """Places where ``template`` (wholly inside the view) correlates with the view at least
    ``min_correlation`` (normalised, zero-mean), at least a template's size apart."""
    import scipy.fft as sfft

    th, tw = template.shape
    h, w = view.shape
    t = template - template.mean()
    norm = float(np.sqrt(np.sum(t * t)))
    if norm <= 1e-9:
        return 0
    shape = (h + th, w + tw)  # no wrap-around into the valid places
    fv = sfft.rfft2(view, s=shape)
    num = sfft.irfft2(fv * np.conj(sfft.rfft2(t, s=shape)), s=shape)[:h - th + 1, :w - tw + 1]
    box = np.ones((th, tw))
    fb = np.conj(sfft.rfft2(box, s=shape))
    s1 = sfft.irfft2(fv * fb, s=shape)[:h - th + 1, :w - tw + 1]
    s2 = sfft.irfft2(sfft.rfft2(view * view, s=shape) * fb, s=shape)[:h - th + 1, :w - tw + 1]
    var = np.maximum(s2 - s1 * s1 / (th * tw), 0.0)
    ok = var > 1e-9 * max(float(var.max()), 1e-30)
    ncc = np.where(ok, num / (norm * np.sqrt(np.where(ok, var, 1.0))), -1.0)
    copies = 0
    while copies < 10000:
        i = int(np.argmax(ncc))
        y, x = divmod(i, ncc.shape[1])
        if ncc[y, x] < min_correlation:
            break
        copies += 1
        ncc[max(0, y - th + 1):y + th, max(0, x - tw + 1):x + tw] = -1.0
    return copies


def one_off_repeats(view, reference, *, zoom: float = 1.0, threshold: float = 8.0,
                    min_correlation: float = 0.8) -> OneOffRepeats:
    """Find content the photo shows once (a tripod's leg on a lawn, a leaf on gravel) and count it in a view.

    A texture made of pieces of a photo repeats every piece, which is
    invisible where every piece looks like many others (gravel, grass) and
    plain where one does not: a foreign object, repeated at random places,
    is the first thing a viewer sees. The band-power, histogram, structure
    and ``repeat_peak`` measures do not see it (the copies are not on a
    lattice, and their density is the photo's). This measure looks for it
    directly. Each 8 x 8 patch of the photo (at about 160 pixels on its
    longer side) is compared with every patch elsewhere in it (colour or
    luma values, 16 principal components): its rarity is its distance to
    its 4th-nearest, in units of the photo's own spread of those distances
    (90th percentile less median; :class:`OneOffRepeats`). Patches over
    ``threshold`` are one-off content; the largest connected region of them
    is cut from the photo and searched for in the view (normalised
    correlation of the luma, at the view's scale), and its copies counted.

    Parameters
    ----------
    view : ndarray, shape (H, W) or (H, W, C)
        The texture rendered at ``zoom`` times the photo's pixel size (e.g.
        ``bake(texture, (1448, 1448), pixel_size=p)``: 8 times the area of a
        512-pixel photo at its own scale).
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo, at least 32 pixels a side.
    zoom : float
        The view's pixel size over the photo's (>= 1).
    threshold : float
        Rarity over which a patch is one-off content (> 0).
    min_correlation : float
        Correlation from which a place of the view counts as a copy (0 to 1).

    Returns
    -------
    OneOffRepeats
    """
    view = check_image("view", view, min_size=_RARE_MIN_TEMPLATE)
    reference = check_image("reference", reference, min_size=32)
    zoom = check_float("zoom", zoom, minimum=1.0, maximum=1e6)
    threshold = check_float("threshold", threshold, minimum=0.0, exclusive_minimum=True)
    min_correlation = check_float("min_correlation", min_correlation, minimum=0.0, maximum=1.0)
    box, squares, top = one_off_content(reference, threshold=threshold)
    view = view[:_RARE_MAX_VIEW, :_RARE_MAX_VIEW]
    photo_areas = view.shape[0] * view.shape[1] * zoom * zoom / (reference.shape[0] * reference.shape[1])
    if box is None:
        return OneOffRepeats(rarity=top, threshold=threshold, box=None, copies=0, per_photo_area=0.0,
                             within=True)
    luma_photo, v = _opponent(reference)[0], _opponent(view)[0]
    copies = 0
    for y0, x0, y1, x1 in squares:
        template = luma_photo[y0:y1, x0:x1]
        if zoom > 1.0:
            template = _resample(template, 1.0 / zoom)
        if min(template.shape) < _RARE_MIN_TEMPLATE or template.shape[0] > v.shape[0] \
                or template.shape[1] > v.shape[1]:
            raise ValueError(f"the photo's one-off content, {x1 - x0}x{y1 - y0} pixels, is "
                             f"{template.shape[1]}x{template.shape[0]} view pixels at zoom={zoom:g}: a view of "
                             f"{v.shape[1]}x{v.shape[0]} cannot be searched for it (at least "
                             f"{_RARE_MIN_TEMPLATE} and at most the view)")
        copies = max(copies, _count_copies(v, template, min_correlation))
    return OneOffRepeats(rarity=top, threshold=threshold, box=box, copies=copies,
                         per_photo_area=copies / photo_areas, within=copies <= 1)
