"""Power spectra of images: one estimator, its radial and octave averages, slopes.

The one home of spectrum estimation in spectex: the metrics
(:func:`spectex.metrics.band_power`), the exemplar analysis
(:func:`spectex.analysis.octave_power`), the fit and the ``spectex spectrum``
command all call it.

The estimator (:func:`power_spectrum`)
--------------------------------------
Each channel has its mean removed and is multiplied by a window ``w`` (1 for
none); its periodogram is

    P(k) = |F(k)|^2 / ((H W)^2 mean(w^2))

at each frequency ``k`` of the ``H x W`` grid, ``F`` the discrete Fourier
transform. This is the one normalisation: without a window, ``P`` summed over
all frequencies is the variance of the image (Parseval); with a window,
dividing by the window's mean square makes the sum an unbiased estimate of
the variance of a stationary texture. With ``segment``, ``P`` is the mean of
the periodograms of half-overlapping crops (Welch's method).

Its reductions:

* :func:`radial_power_spectrum`: the *mean* of ``P`` over rings of radial
  frequency one frequency step wide, a power per frequency (what a log-log
  plot and :func:`spectral_slope` want);
* :func:`band_power`: the *sum* of ``P`` over octave bands, in dB, the
  variance each band contributes, which does not depend on the image size
  (what measures comparing two images want).

Frequencies are in cycles per pixel throughout: 0.5 is the Nyquist
frequency; radial frequency is ``sqrt(fy^2 + fx^2)``.

Windows: ``'none'`` takes the image as one period (right for tiles and
synthesised noise); ``'hann'`` (:func:`hann_window`) is the classical window
for photographs, whose edges otherwise leak a ``1/f^2`` cross into the
spectrum; ``'periodic'`` analyses Moisan's periodic component
(:func:`spectex.periodic.periodic_smooth_decomposition`), which removes the
same leak without the window's loss of resolution.

References
----------
F. J. Harris, "On the use of windows for harmonic analysis with the discrete
Fourier transform", Proc. IEEE 66(1), 1978; P. D. Welch, IEEE Trans. Audio
Electroacoustics 15(2), 1967 (averaged segments); D. J. Field, "Relations
between the statistics of natural images and the response properties of
cortical cells", JOSA A 4(12), 1987.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._parallel import fft_workers
from ._validate import check_choice, check_float, check_image, check_int, check_shape
from .color import luma

__all__ = [
    "WINDOWS",
    "BandPower",
    "PowerSpectrum",
    "RadialSpectrum",
    "SlopeFit",
    "band_power",
    "correlation_length",
    "hann_window",
    "power_spectrum",
    "radial_power_spectrum",
    "spectral_slope",
]

#: The windows of :func:`power_spectrum` (``None`` means ``'none'``).
WINDOWS = ("none", "hann", "periodic")


def hann_window(shape) -> np.ndarray:
    """Separable 2-D Hann window, positive on every pixel.

    Along each axis of ``n`` pixels the weights are
    ``0.5 - 0.5 cos(2 pi (i + 1) / (n + 1))`` for ``i = 0 .. n - 1``: the
    ``n + 2``-point Hann window without its two zero end points, so that no
    pixel is discarded. The 2-D window is the outer product of the two.
    Multiply an image with its mean removed by it before an FFT, and divide
    the power by ``mean(window ** 2)`` to keep the estimate unbiased, as
    :func:`power_spectrum` does.

    Parameters
    ----------
    shape : int or (int, int)
        ``(height, width)`` of the window (an int for a square one), each at
        least 1.

    Returns
    -------
    ndarray of float64, shape (height, width)
        Weights in (0, 1], symmetric about the centre (1 at the centre
        pixel of an odd size).

    References
    ----------
    F. J. Harris, "On the use of windows for harmonic analysis with the
    discrete Fourier transform", Proc. IEEE 66(1), 1978.
    """
    h, w = check_shape("shape", shape)
    return np.outer(np.hanning(h + 2)[1:-1], np.hanning(w + 2)[1:-1])


# --------------------------------------------------------------------------
# The estimator
# --------------------------------------------------------------------------

class RadialSpectrum(NamedTuple):
    """The result of :func:`radial_power_spectrum` (unpacks as ``freqs, power``)."""

    freqs: np.ndarray  #: mean radial frequency of each ring, cycles per pixel
    power: np.ndarray  #: mean power in each ring, ``(K,)`` or ``(K, C)``


class BandPower(NamedTuple):
    """The result of :func:`band_power` (unpacks as ``bands, power_db``)."""

    bands: np.ndarray     #: (K, 2) lower and upper edge of each band, cycles per pixel, finest first
    power_db: np.ndarray  #: (K,) 10 log10 of each band's power


class PowerSpectrum(NamedTuple):
    """The periodogram of :func:`power_spectrum`, on the half plane of a real FFT.

    ``frequency``, ``weight`` and ``power`` share their first two axes,
    ``(h, w // 2 + 1)`` for an analysed size (image or segment) of
    ``h x w``: row ``i`` is vertical frequency ``fftfreq(h)[i]``, column
    ``j`` horizontal frequency ``j / w``.
    """

    #: Radial frequency of each entry, cycles per pixel.
    frequency: np.ndarray
    #: How many frequencies of the full plane each entry stands for (1 or 2):
    #: ``(weight * power).sum()`` over the first two axes is the sum over all frequencies.
    weight: np.ndarray
    #: ``P(k)``, shape ``(h, w // 2 + 1)`` or ``(h, w // 2 + 1, C)``.
    power: np.ndarray


def _half_plane(h: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Radial frequency and multiplicity of the rfft2 layout of an h x w grid."""
    fy = np.fft.fftfreq(h)[:, None]
    fx = np.fft.rfftfreq(w)[None, :]
    f = np.sqrt(fy * fy + fx * fx)
    # Columns 1 .. W/2-1 of the half spectrum stand for two frequencies each.
    mult = np.full(f.shape[1], 2.0)
    mult[0] = 1.0
    if w % 2 == 0:
        mult[-1] = 1.0
    return f, np.broadcast_to(mult[None, :], f.shape)


def _segment_starts(size: int, seg: int) -> list[int]:
    """Starts of half-overlapping segments covering ``size`` (the last one flush with the end)."""
    pos = list(range(0, size - seg + 1, max(1, seg // 2)))
    if pos[-1] != size - seg:
        pos.append(size - seg)
    return pos


def _periodogram(x: np.ndarray, window: str, segment) -> np.ndarray:
    """Mean periodogram, (sh, sw // 2 + 1, C), of float64 ``x`` (H, W, C); see the module docstring."""
    import scipy.fft as sfft

    from .periodic import periodic_smooth_decomposition

    h, w = x.shape[:2]
    sh, sw = (h, w) if segment is None else segment
    win = hann_window((sh, sw)) if window == "hann" else None
    msq = 1.0 if win is None else float(np.mean(win ** 2))
    total = np.zeros((sh, sw // 2 + 1, x.shape[2]))
    count = 0
    for y0 in _segment_starts(h, sh):
        for x0 in _segment_starts(w, sw):
            crop = x[y0:y0 + sh, x0:x0 + sw]
            if window == "periodic":
                crop = periodic_smooth_decomposition(crop)[0].astype(np.float64)
            crop = crop - crop.mean(axis=(0, 1))
            if win is not None:
                crop = crop * win[:, :, None]
            spec = sfft.rfft2(crop, axes=(0, 1), workers=fft_workers(crop.size))
            total += spec.real ** 2 + spec.imag ** 2
            count += 1
    total /= float(sh * sw) ** 2 * msq * count
    return total


def _check_segment(segment, h: int, w: int):
    if segment is None:
        return None
    if np.ndim(segment) != 1 or len(segment) != 2:
        raise ValueError(f"segment must be a (height, width) pair, got {segment!r}")
    return (check_int("segment[0]", segment[0], minimum=1, maximum=h),
            check_int("segment[1]", segment[1], minimum=1, maximum=w))


def power_spectrum(image, *, window: str | None = None, segment=None) -> PowerSpectrum:
    """The periodogram of an image: the estimator every spectrum in spectex comes from.

    Each channel has its mean removed, is multiplied by the window, and
    ``P(k) = |F(k)|^2 / ((H W)^2 mean(w^2))`` (see the module docstring):
    summed over all frequencies, the variance.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 2 x 2. Each channel is analysed separately (pass
        :func:`spectex.color.luma` for one spectrum of a colour image).
    window : {None, 'none', 'hann', 'periodic'}
        Leakage control (module docstring); ``None`` is ``'none'``.
    segment : (int, int), optional
        ``(height, width)`` of Welch segments, at most the image's size:
        the image is cut into half-overlapping crops, each windowed and
        transformed, and their periodograms averaged.

    Returns
    -------
    PowerSpectrum
        ``frequency``, ``weight`` and ``power`` on the half plane of the
        analysed size.
    """
    image = check_image("image", image, min_size=2)
    window = "none" if window is None else check_choice("window", window, WINDOWS)
    h, w = image.shape[:2]
    segment = _check_segment(segment, h, w)
    x = (image[:, :, None] if image.ndim == 2 else image).astype(np.float64)
    p = _periodogram(x, window, segment)
    f, mult = _half_plane(*((h, w) if segment is None else segment))
    return PowerSpectrum(f, np.array(mult), p[:, :, 0] if image.ndim == 2 else p)


# --------------------------------------------------------------------------
# Rings: a power per frequency
# --------------------------------------------------------------------------

def radial_power_spectrum(image, *, window: str | None = None):
    """Radially averaged power spectrum.

    The periodogram of :func:`power_spectrum` (mean removed, optional
    window, ``P(k) = |F(k)|^2 / (H W)^2`` divided by the window's mean
    square: its sum over all frequencies is the variance), averaged over
    rings of radial frequency one frequency step wide, ``1 / min(H, W)``
    cycles per pixel, up to the Nyquist frequency of the shorter side.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 4 x 4. Each channel is analysed separately (pass the luma
        for one curve of a colour image).
    window : {None, 'none', 'hann', 'periodic'}
        ``None``/``'none'``: the image is taken as periodic (right for tiles
        and synthesised noise). ``'hann'``: :func:`hann_window`, for
        non-periodic photographs, whose edges otherwise leak a ``1/f^2``
        cross into the spectrum. ``'periodic'``: the periodic component of
        :func:`spectex.periodic.periodic_smooth_decomposition`, which removes
        the same leak without the window's loss of resolution.

    Returns
    -------
    freqs : ndarray, shape (K,)
        Mean radial frequency of each ring, cycles per pixel, increasing,
        in (0, 0.5].
    power : ndarray, shape (K,) or (K, C)
        Mean power in each ring.

    References
    ----------
    F. J. Harris, "On the use of windows for harmonic analysis with the
    discrete Fourier transform", Proc. IEEE 66(1), 1978; D. J. Field,
    "Relations between the statistics of natural images and the response
    properties of cortical cells", JOSA A 4(12), 1987.
    """
    image = check_image("image", image, min_size=4)
    window = "none" if window is None else check_choice("window", window, WINDOWS)
    x = (image[:, :, None] if image.ndim == 2 else image).astype(np.float64)
    h, w = x.shape[:2]
    p2 = _periodogram(x, window, None)
    f, mult = _half_plane(h, w)
    n = min(h, w)
    ring = np.rint(f * n).astype(np.int64)
    kmax = n // 2
    sel = (ring >= 1) & (ring <= kmax)
    idx = ring[sel] - 1
    wts = mult[sel]
    count = np.bincount(idx, weights=wts, minlength=kmax)
    freqs = np.bincount(idx, weights=wts * f[sel], minlength=kmax)
    good = count > 0
    freqs = freqs[good] / count[good]
    power = np.empty((int(good.sum()), x.shape[2]))
    for c in range(x.shape[2]):
        power[:, c] = np.bincount(idx, weights=wts * p2[:, :, c][sel], minlength=kmax)[good] / count[good]
    return RadialSpectrum(freqs, power[:, 0] if image.ndim == 2 else power)


def correlation_length(image, *, level: float = 0.25, detail: float = 8.0) -> float:
    """Lag (pixels) at which an image's detail stops resembling itself: the grain size of a texture.

    The luma of ``image`` less its Gaussian blur of ``min(H, W) / detail``
    (the photo's lighting and its largest shapes left out: what stays is the
    texture's grain, its stones, blades or cells; the blur taken in the
    frequency domain on the image mirrored to twice its size, its edges
    reflected), its mean removed, times
    :func:`hann_window` (a photo is not periodic); its autocorrelation, the
    inverse transform of its power spectrum zero-padded to twice the size
    (no wrap-around), divided by the window's own autocorrelation (the
    estimate unbiased at every lag the window reaches) and by its value at lag
    0, averaged over rings one pixel wide. The first ring whose mean falls
    under ``level`` gives the length, interpolated linearly between rings.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 16 x 16; one or three channels (three are taken as RGB and
        reduced to their luma).
    level : float
        In (0, 1): the correlation the length is read at (0.25: a quarter of
        a grain's width for stones in mortar or gravel, about 5 pixels for
        gravel 22 pixels across).
    detail : float
        At least 2: the blur taken away is ``min(H, W) / detail`` pixels.

    Returns
    -------
    float
        The lag, in pixels, at least 1; ``min(H, W) / 4`` at most (where
        the correlation stays above ``level`` that far: a texture of no
        grain but one large shape).
    """
    image = check_image("image", image, min_size=16, channels=(None, 1, 3))
    level = check_float("level", level, minimum=0.0, exclusive_minimum=True)
    if level >= 1.0:
        raise ValueError(f"level must be < 1, got {level}")
    detail = check_float("detail", detail, minimum=2.0)
    x = image if image.ndim == 2 else (image[:, :, 0] if image.shape[2] == 1 else luma(image))
    from scipy import fft as sfft

    x = np.asarray(x, dtype=np.float64)
    h, w = x.shape
    workers = fft_workers(4 * h * w)
    # less its Gaussian blur, in the frequency domain on the image mirrored to twice its size (its edges
    # reflected, as ndimage's "reflect" mode; a direct filter of sigma 128 on a 1024-pixel photo took 1 s)
    sigma = min(h, w) / detail
    f = sfft.rfft2(np.pad(x, ((0, h), (0, w)), mode="symmetric"), workers=workers)
    fy = np.fft.fftfreq(2 * h)[:, None]
    fx = np.fft.rfftfreq(2 * w)[None, :]
    f *= -np.expm1(-2.0 * (np.pi * sigma) ** 2 * (fy * fy + fx * fx))
    x = sfft.irfft2(f, s=(2 * h, 2 * w), workers=workers)[:h, :w]
    x -= x.mean()
    win = hann_window((h, w))

    def autocorrelation(a):
        f = sfft.rfft2(a, s=(2 * h, 2 * w), workers=workers)
        return sfft.irfft2(f.real ** 2 + f.imag ** 2, s=(2 * h, 2 * w), workers=workers)

    reach = max(2, min(h, w) // 4)
    ac = np.fft.fftshift(autocorrelation(x * win))[h - reach:h + reach + 1, w - reach:w + reach + 1]
    aw = np.fft.fftshift(autocorrelation(win))[h - reach:h + reach + 1, w - reach:w + reach + 1]
    if ac[reach, reach] <= 0.0:
        return 1.0  # (no detail at all: the caller's own check refuses flat images)
    ac = ac / np.maximum(aw, 1e-12 * aw[reach, reach]) * (aw[reach, reach] / ac[reach, reach])
    yy, xx = np.indices(ac.shape)
    ring = np.rint(np.hypot(yy - reach, xx - reach)).astype(np.int64)
    inside = ring <= reach
    profile = (np.bincount(ring[inside], weights=ac[inside], minlength=reach + 1)
               / np.bincount(ring[inside], minlength=reach + 1))
    below = np.flatnonzero(profile < level)
    if below.size == 0:
        return float(reach)
    k = int(below[0])
    if k == 0:
        return 1.0
    a, b = profile[k - 1], profile[k]
    return float(max(1.0, k - 1 + (a - level) / (a - b)))


# --------------------------------------------------------------------------
# Octave bands: the variance per band
# --------------------------------------------------------------------------

def band_power(image, *, min_cycles: int = 4, segment=None):
    """Windowed power per octave band, in dB.

    The image (its Rec. 709 luma for colour, :func:`spectex.color.luma`;
    alpha is ignored) goes through :func:`power_spectrum` with the Hann
    window (so that a non-periodic photograph does not leak its edges into
    the high frequencies), and the periodogram is summed over octave bands
    of radial frequency ``r`` in cycles per pixel::

        band 0: 1/4  <= r          (up to the corners of the spectrum)
        band k: 2^-(k+2) <= r < 2^-(k+1)

    Band ``k`` is kept while its lower edge holds at least ``min_cycles``
    cycles across the analysed size's shorter side. The band power is the
    variance the band contributes, so it does not depend on the image size.

    With ``segment``, the image is cut into ``segment``-sized crops that
    overlap by half (Welch's method), each analysed as above, and their
    spectra averaged. Comparing two images of different sizes this way, at
    the smaller one's size, gives both estimates the same frequency
    resolution: the window smears about 2 frequency bins, so a spectral peak
    near a band edge leaks differently at different sizes (2 to 4 dB for the
    brick period at 4 cycles across); :func:`spectex.metrics.band_power_distance`
    does this.

    Like any spectral estimate it scatters: for white noise the standard
    deviation is about ``4.3 sqrt(2 / (0.27 N))`` dB for a band holding
    ``N`` frequency bins (the Hann window keeps about 27% of the pixels'
    information), so about 0.1 dB for the finest band of a 128 x 128 image
    but 0.7 to 0.9 dB for a lowest band with 4 cycles across (less when
    several segments are averaged). Raise ``min_cycles`` for steadier (fewer)
    bands.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least ``8 * min_cycles`` pixels on its (or the segment's) shorter
        side, for two bands.
    min_cycles : int
        Cycles across the shorter side that the lowest band must hold.
    segment : (int, int), optional
        ``(height, width)`` of the Welch segments, at most the image's size.

    Returns
    -------
    bands : ndarray, shape (K, 2)
        Lower and upper edge of each band in cycles per pixel, finest first
        (the upper edge of band 0 is reported as 0.5).
    power_db : ndarray, shape (K,)
        ``10 log10`` of each band's power (floored at 1e-20, -200 dB, for a
        flat image).

    References
    ----------
    Harris, Proc. IEEE 1978 (windowing); P. D. Welch, IEEE Trans. Audio
    Electroacoustics 15(2), 1967 (averaged segments); Portilla and
    Simoncelli, IJCV 2000 (texture statistics per scale).
    """
    image = check_image("image", image)
    min_cycles = check_int("min_cycles", min_cycles, minimum=1)
    h, w = image.shape[:2]
    segment = _check_segment(segment, h, w)
    sh, sw = (h, w) if segment is None else segment
    n = min(sh, sw)
    k_count = 0
    while 2.0 ** -(k_count + 2) >= min_cycles / n:
        k_count += 1
    if k_count < 2:
        raise ValueError(f"image must be at least {8 * min_cycles} pixels on its shorter side for "
                         f"two octave bands, got {sw}x{sh}")
    lum = luma(image, dtype=np.float64)
    p = _periodogram(lum[:, :, None], "hann", (sh, sw))[:, :, 0]
    r, mult = _half_plane(sh, sw)
    p = p * mult
    bands = np.empty((k_count, 2))
    power = np.empty(k_count)
    for k in range(k_count):
        lo, hi = 2.0 ** -(k + 2), 2.0 ** -(k + 1)
        sel = (r >= lo) if k == 0 else ((r >= lo) & (r < hi))
        bands[k] = lo, hi
        power[k] = p[sel].sum()
    return BandPower(bands, 10.0 * np.log10(np.maximum(power, 1e-20)))


# --------------------------------------------------------------------------
# Slopes
# --------------------------------------------------------------------------

class SlopeFit(NamedTuple):
    """Least-squares line through ``log10(power)`` against ``log10(freq)``."""

    slope: float | np.ndarray
    intercept: float | np.ndarray
    fmin: float
    fmax: float


_WEIGHTINGS = ("octave", "none")


def _log_widths(x: np.ndarray) -> np.ndarray:
    """Trapezoid weights of sorted points ``x``: the stretch of ``x`` each one stands for."""
    if x.size < 2:
        return np.ones_like(x)
    gaps = np.diff(x)
    w = np.empty_like(x)
    w[0], w[-1] = gaps[0] / 2.0, gaps[-1] / 2.0
    w[1:-1] = (gaps[:-1] + gaps[1:]) / 2.0
    return w


def spectral_slope(freqs, power, *, fmin: float | None = None, fmax: float | None = None,
                   weighting: str = "octave") -> SlopeFit:
    """Log-log slope of a power spectrum (``-beta`` for ``1/f^beta`` noise).

    Parameters
    ----------
    freqs : array_like, shape (K,)
        Frequencies, cycles per pixel (from :func:`radial_power_spectrum`).
    power : array_like, shape (K,) or (K, C)
    fmin, fmax : float or None
        The range fitted (inclusive); default: all of it. Rings whose power
        is zero, or below ``1e-12`` of the channel's largest (what an exact
        band limit leaves), are left out of the fit.
    weighting : {'octave', 'none'}
        ``'octave'`` (the default): each point counts for the stretch of
        ``log f`` it stands for (trapezoid weights in ``log f``), so every
        octave of the range counts alike, the least-squares line through the
        log-log curve as a whole. Rings of :func:`radial_power_spectrum`
        are evenly spaced in ``f``: the octave from 0.25 to 0.5 holds as many
        rings as all the octaves below it, and an unweighted fit (``'none'``)
        follows the highest octave and misses the low frequencies.

    Returns
    -------
    SlopeFit
        ``slope`` and ``intercept`` of ``log10 P = slope log10 f +
        intercept`` (floats, or arrays of shape (C,) for a (K, C) power), and
        the range fitted.
    """
    freqs = np.asarray(freqs, dtype=np.float64)
    power = np.asarray(power, dtype=np.float64)
    if freqs.ndim != 1 or power.shape[:1] != freqs.shape or power.ndim not in (1, 2):
        raise ValueError(f"freqs must have shape (K,) and power (K,) or (K, C), got {freqs.shape} "
                         f"and {power.shape}")
    weighting = check_choice("weighting", weighting, _WEIGHTINGS)
    lo = float(np.nanmin(freqs)) if fmin is None else check_float("fmin", fmin, minimum=0.0)
    hi = float(np.nanmax(freqs)) if fmax is None else check_float("fmax", fmax, minimum=0.0)
    if not hi > lo:
        raise ValueError(f"fmax must be greater than fmin, got fmin={lo}, fmax={hi}")
    p2 = power[:, None] if power.ndim == 1 else power
    slopes, intercepts = [], []
    for c in range(p2.shape[1]):
        pc = p2[:, c]
        top = np.max(pc[np.isfinite(pc)], initial=0.0)
        use = (freqs >= lo) & (freqs <= hi) & (freqs > 0) & np.isfinite(freqs) & np.isfinite(pc) \
            & (pc > 1e-12 * top)
        if use.sum() < 2:
            raise ValueError(f"fewer than two frequencies with power in the fit range {lo:.4g} to {hi:.4g}")
        x, y = np.log10(freqs[use]), np.log10(pc[use])
        order = np.argsort(x, kind="stable")
        x, y = x[order], y[order]
        if weighting == "octave" and x[-1] > x[0]:
            w = _log_widths(x)
        else:
            w = np.ones_like(x)
        # Weighted least squares (np.polyfit weighs the residuals: sqrt of the weights).
        a, b = np.polyfit(x, y, 1, w=np.sqrt(w))
        slopes.append(float(a))
        intercepts.append(float(b))
    if power.ndim == 1:
        return SlopeFit(slopes[0], intercepts[0], lo, hi)
    return SlopeFit(np.array(slopes), np.array(intercepts), lo, hi)
