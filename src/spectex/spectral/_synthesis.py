"""Spectral synthesis and spectral analysis (Blythe et al., 1999, 6.21.4).

Two ways to make noise with a prescribed spectrum, and the tools to check it:

* :func:`octave_sum`: a sum of octaves made by filtering under
  magnification (:func:`spectex.spectral.octave`), each with its own
  amplitude: ``1/f`` (Perlin's ``fractalsum``), a spectral exponent, or a
  list.
* :func:`spectral_noise`: the FFT route, a periodic Gaussian field whose
  power spectrum goes as ``1 / f^beta`` between optional low and high
  cut-offs.
* :func:`band_limit`: an exact radial band-pass by FFT (what makes tiles
  low-pass, see :mod:`spectex.tiles`).
* :func:`radial_power_spectrum` and :func:`spectral_slope`: the radially
  averaged power spectrum of an image and its log-log slope, with optional
  windowing for non-periodic photographs. This is the one home of that
  concept in spectex.
* :func:`periodic_smooth_decomposition`: Moisan's periodic-plus-smooth
  decomposition, used to make photographs tile and as a leak-free
  alternative to windowing.

Frequencies are in cycles per pixel throughout: 0.5 is the Nyquist
frequency, and a frequency ``f`` in an ``N``-pixel period is ``f N`` cycles
per period. Radial frequency is ``sqrt(fy^2 + fx^2)``.
"""

from __future__ import annotations

import numbers
from typing import NamedTuple

import numpy as np

from ..color import LUMA_REC709
from .._validate import DEPRECATED, check_choice, check_float, check_image, check_int, check_rng, check_shape
from ._octaves import octave

#: Rec. 709 luma weights (on stored values), for colour images; their home is :mod:`spectex.color`.
LUMA = np.array(LUMA_REC709)

#: Arrays of at least this many elements are transformed with every core;
#: smaller ones with one thread, which is faster for them, and much faster
#: when the cores are busy with other work (thread start-up and waiting).
PARALLEL_MIN = 1 << 20


def _workers(n: int) -> int:
    """scipy.fft ``workers`` for a transform over ``n`` elements."""
    return -1 if n >= PARALLEL_MIN else 1




def _radial_frequency(h: int, w: int, *, half: bool = True) -> np.ndarray:
    """Radial frequency (cycles per pixel) of the rfft2 (or fft2) layout."""
    fy = np.fft.fftfreq(h)[:, None]
    fx = (np.fft.rfftfreq(w) if half else np.fft.fftfreq(w))[None, :]
    return np.sqrt(fy * fy + fx * fx)


def _check_band(low, high):
    if low is not None:
        low = check_float("low", low, minimum=0.0, maximum=1.0)
    if high is not None:
        high = check_float("high", high, minimum=0.0, maximum=1.0, exclusive_minimum=True)
    if low is not None and high is not None and not high > low:
        raise ValueError(f"high must be greater than low, got low={low}, high={high}")
    return low, high


def _dtype(dtype):
    dtype = np.dtype(dtype)
    if dtype not in (np.float32, np.float64):
        raise ValueError(f"dtype must be float32 or float64, got {dtype}")
    return dtype


# --------------------------------------------------------------------------
# The FFT route
# --------------------------------------------------------------------------

def spectral_noise(shape, *, beta: float = 2.0, low: float | None = None, high: float | None = None,
                   rng=None, dtype=np.float32, seed=DEPRECATED) -> np.ndarray:
    """Periodic Gaussian noise whose power spectrum goes as ``1 / f^beta``.

    Every Fourier coefficient is an independent complex normal value scaled
    by ``f^(-beta/2)``, so the expected power at radial frequency ``f`` is
    ``f^-beta`` (up to a constant) for ``low <= f <= high`` and zero outside.
    The mean (``f = 0``) is zero. The field is real, periodic with period
    ``shape``, and scaled to unit standard deviation.

    Parameters
    ----------
    shape : int or (int, int)
        ``(height, width)``; any size of at least 2 x 2.
    beta : float
        Spectral exponent of the power spectrum, in [-2, 8]: 0 is white
        noise, 1 pink, 2 the ``1/f`` amplitude spectrum of natural images
        (brown noise in 2-D), 3 smoother still.
    low, high : float or None
        Band edges in cycles per pixel (``None``: no edge). Frequencies with
        ``f < low`` or ``f > high`` get no power. The band must hold at least
        one frequency of the grid.
    rng : int, numpy.random.Generator or None
        Randomness (SPEC 7): an int gives ``numpy.random.default_rng(rng)``;
        a Generator is used and advanced; None (the default) draws fresh
        randomness. ``seed=``, the old name, still works for one release
        with a ``DeprecationWarning``.
    dtype : float32 or float64

    Returns
    -------
    ndarray, shape (H, W)
        Zero mean, unit standard deviation.

    References
    ----------
    R. F. Voss, "Random fractal forgeries", in Fundamental Algorithms for
    Computer Graphics, Springer 1985 (spectral synthesis of fBm); D. Blythe
    et al., SIGGRAPH 1999 course, section 6.21.4.
    """
    import scipy.fft as sfft

    h, w = check_shape("shape", shape)
    if min(h, w) < 2:
        raise ValueError(f"shape must be at least 2x2, got {w}x{h}")
    beta = check_float("beta", beta, minimum=-2.0, maximum=8.0)
    low, high = _check_band(low, high)
    dtype = _dtype(dtype)
    rng = check_rng(rng, seed=seed, where="spectral_noise")
    fy = np.fft.fftfreq(h).astype(np.float32)[:, None]
    fx = np.fft.rfftfreq(w).astype(np.float32)[None, :]
    f2 = fy * fy + fx * fx
    band = f2 > 0
    if low is not None:
        band &= f2 >= np.float32(low) ** 2
    if high is not None:
        band &= f2 <= np.float32(high) ** 2
    if not band.any():
        raise ValueError(f"the band low={low}, high={high} holds no frequency of a {w}x{h} grid "
                         f"(its lowest non-zero frequency is {1 / max(h, w):.3g} cycles per pixel)")
    f2[~band] = 1.0
    amp = f2 ** np.float32(-0.25 * beta)
    amp[~band] = 0.0
    # irfft2 keeps only the Hermitian part of the columns kx = 0 (and the
    # Nyquist column for even widths), which halves their variance: sqrt(2)
    # restores it, so every frequency gets the same expected power.
    amp[:, 0] *= np.float32(np.sqrt(2.0))
    if w % 2 == 0:
        amp[:, -1] *= np.float32(np.sqrt(2.0))
    coef = rng.standard_normal(f2.shape + (2,), dtype=np.float32 if dtype == np.float32 else np.float64)
    spec = coef.view(np.complex64 if dtype == np.float32 else np.complex128)[..., 0]
    spec *= amp
    field = sfft.irfft2(spec, s=(h, w), workers=_workers(h * w), overwrite_x=True)
    field -= field.mean(dtype=np.float64)
    std = float(np.sqrt(np.mean(np.square(field, dtype=np.float64))))
    if std > 0:
        field *= dtype.type(1.0 / std)
    return field.astype(dtype, copy=False)


def _band_limit_planes(planes: np.ndarray, low, high, shape) -> np.ndarray:
    """Band-limit (and optionally Fourier-upsample) planes ``(C, h, w)``.

    Returns float32 planes ``(C, H, W)``. Frequencies are in cycles per
    *output* pixel. When upsampling, the input grid's Nyquist row and column
    (ambiguous between +k and -k) are dropped.
    """
    import scipy.fft as sfft

    c, h, w = planes.shape
    big_h, big_w = shape
    fy = np.fft.fftfreq(h, d=1.0 / h)[:, None] / big_h      # cycles per output pixel
    fx = np.fft.rfftfreq(w, d=1.0 / w)[None, :] / big_w
    f = np.sqrt(fy * fy + fx * fx)
    keep = np.ones(f.shape, dtype=bool)
    if low is not None:
        keep &= f >= low
    if high is not None:
        keep &= f <= high
    if big_h > h and h % 2 == 0:
        keep[h // 2, :] = False
    if big_w > w and w % 2 == 0:
        keep[:, w // 2] = False
    if not keep.any():
        return np.zeros((c, big_h, big_w), dtype=np.float32)
    # Pruned transforms: only the columns holding kept frequencies go
    # through the column FFTs.
    cols = int(np.nonzero(keep.any(axis=0))[0].max()) + 1
    workers = _workers(c * big_h * big_w)
    spec = sfft.rfft(planes, axis=-1, workers=workers)[..., :cols]
    spec = sfft.fft(spec, axis=-2, workers=workers, overwrite_x=True)
    spec *= keep[None, :, :cols]
    if big_h > h:
        padded = np.zeros((c, big_h, cols), dtype=spec.dtype)
        top = (h + 1) // 2
        padded[:, :top] = spec[:, :top]
        padded[:, big_h - (h - top):] = spec[:, top:]
        spec = padded
    spec = sfft.ifft(spec, axis=-2, workers=workers, overwrite_x=True)
    out = sfft.irfft(spec, n=big_w, axis=-1, workers=workers)  # zero-pads the columns
    if (big_h, big_w) != (h, w):
        out *= (big_h * big_w) / (h * w)
    return out.astype(np.float32, copy=False)


def band_limit(image, *, low: float | None = None, high: float | None = None, shape=None) -> np.ndarray:
    """Exact radial band-pass of a periodic image by FFT, optionally upsampled.

    Fourier coefficients with radial frequency above ``high`` (and, if
    given, below ``low``; ``low > 0`` removes the mean too) are set to zero
    and the others kept unchanged. The image is taken as one period, so the
    result still tiles.

    With ``shape`` larger than the image, the band-limited periodic function
    is sampled on the finer grid (Fourier interpolation): input pixel
    ``(i, j)`` lands on output pixel ``(i H / h, j W / w)`` when those are
    whole numbers; the input grid's own Nyquist row and column, ambiguous
    between positive and negative frequency, are dropped.

    Parameters
    ----------
    image : ndarray, shape (h, w) or (h, w, C)
    low, high : float or None
        Band edges in cycles per (output) pixel; ``None`` leaves that side
        open.
    shape : None or (int, int)
        Output ``(H, W)``, at least the image's size; default: the image's.

    Returns
    -------
    ndarray, float32, shape (H, W) or (H, W, C)
        Values may leave [0, 1] (ringing); see :func:`spectex.tiles.fit_range`.
    """
    image = check_image("image", image)
    low, high = _check_band(low, high)
    h, w = image.shape[:2]
    if shape is None:
        shape = (h, w)
    big_h, big_w = check_shape("shape", shape)
    if big_h < h or big_w < w:
        raise ValueError(f"shape must be at least the image's size {h}x{w} (rows x columns), "
                         f"got {big_h}x{big_w}")
    if low is None and high is None and (big_h, big_w) == (h, w):
        return image.copy()
    planes = image[None] if image.ndim == 2 else np.ascontiguousarray(np.moveaxis(image, 2, 0))
    out = _band_limit_planes(planes, low, high, (big_h, big_w))
    return out[0] if image.ndim == 2 else np.ascontiguousarray(np.moveaxis(out, 0, 2))


# --------------------------------------------------------------------------
# Sums of octaves
# --------------------------------------------------------------------------

def octave_amplitudes(cells, amplitudes="1/f") -> np.ndarray:
    """Per-octave amplitudes for :func:`octave_sum`.

    Parameters
    ----------
    cells : sequence of int
        The octaves' cell counts (input image sizes), coarsest first.
    amplitudes : '1/f', float or sequence of float
        ``'1/f'``: amplitude ``cells[0] / cells[k]`` (halving per octave, as
        in Perlin's ``fractalsum``, ``noise(x f) / f``). A float ``beta``:
        the amplitudes that give a power spectrum ``f^-beta``. An octave of
        ``c x c`` cells spreads its variance ``a^2`` over the ``~c^2``
        frequencies below ``c / 2`` cycles per period, so its 2-D power
        spectral density is ``~a^2 / c^2``; equating that to ``c^-beta``
        gives ``a ∝ c^(1 - beta/2)`` (so ``'1/f'`` is ``beta = 4`` in 2-D, and
        ``beta = 2`` is equal amplitudes). A sequence: the amplitudes, one
        per octave.

    Returns
    -------
    ndarray of float64, shape (len(cells),)
        Normalised so that the first (coarsest) is 1, except for an explicit
        list, which is returned as given.
    """
    try:
        cells = np.asarray(cells, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"cells must be a sequence of cell counts, got {cells!r}"[:200]) from None
    if cells.ndim != 1 or cells.size == 0 or not np.all(np.isfinite(cells) & (cells >= 1)):
        raise ValueError(f"cells must be a non-empty sequence of cell counts >= 1, got {cells.tolist()!r}"[:200])
    if isinstance(amplitudes, str):
        check_choice("amplitudes", amplitudes, ("1/f",))
        return cells[0] / cells
    if isinstance(amplitudes, numbers.Real) and not isinstance(amplitudes, bool):
        beta = check_float("amplitudes", amplitudes, minimum=-2.0, maximum=8.0)
        return (cells / cells[0]) ** (1.0 - 0.5 * beta)
    try:
        values = np.array([float(a) for a in amplitudes], dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"amplitudes must be '1/f', a spectral exponent or a list of numbers, "
                        f"got {amplitudes!r}"[:200]) from None
    if len(values) != len(cells):
        raise ValueError(f"amplitudes must have one value per octave ({len(cells)}), got {len(values)}")
    if not np.all(np.isfinite(values)):
        raise ValueError("amplitudes must be finite numbers")
    return values


def octave_sum(shape, *, amplitudes="1/f", octaves: int | None = None, base_cells: int = 4,
               filter: str = "bspline", sigma: float = 0.5, rng=None, dtype=np.float32,
               seed=DEPRECATED) -> np.ndarray:
    """Spectral synthesis by summing octaves made under magnification.

    Octave ``k`` is :func:`spectex.spectral.octave` with
    ``base_cells * 2^k`` cells along each axis (independent random input per
    octave), weighted by :func:`octave_amplitudes` and shifted by a random
    whole number of pixels (periodically), so that the octaves' lattices do
    not line up: lattice noise is not stationary (its local smoothness
    depends on the position within a cell), and aligned lattices would make
    every cell boundary of the coarsest octave, the wrap edge among them,
    statistically different from the rest. The sum tiles.

    Parameters
    ----------
    shape : int or (int, int)
        Output ``(height, width)``: each must be a multiple of the finest
        octave's cells, ``base_cells * 2^(octaves - 1)``.
    amplitudes : '1/f', float or sequence of float
        See :func:`octave_amplitudes`.
    octaves : int or None
        Number of octaves. ``None``: the length of an explicit amplitude
        list, else every octave with a magnification of at least 2 (finest
        cells at most half the shorter side).
    base_cells : int
        Cells of the coarsest octave (4 in the seed).
    filter, sigma
        See :func:`spectex.spectral.magnify`.
    rng : int, numpy.random.Generator or None
        Randomness (SPEC 7): an int gives ``numpy.random.default_rng(rng)``;
        a Generator is used and advanced; None (the default) draws fresh
        randomness. ``seed=``, the old name, still works for one release
        with a ``DeprecationWarning``.
    dtype : float32 or float64

    Returns
    -------
    ndarray, shape (H, W)
        The weighted sum (not normalised).
    """
    h, w = check_shape("shape", shape)
    base_cells = check_int("base_cells", base_cells, minimum=1)
    if octaves is None:
        if not isinstance(amplitudes, (str, numbers.Real)) and hasattr(amplitudes, "__len__"):
            octaves = len(amplitudes)
        else:
            octaves = 0
            while base_cells * 2 ** octaves <= min(h, w) // 2:
                octaves += 1
            if octaves == 0:
                raise ValueError(f"shape {w}x{h} is too small for octaves of base_cells={base_cells}: "
                                 f"the shorter side must be at least {2 * base_cells}")
    octaves = check_int("octaves", octaves, minimum=1, maximum=24)
    cells = [base_cells * 2 ** k for k in range(octaves)]
    finest = cells[-1]
    if h % finest or w % finest:
        raise ValueError(f"shape {w}x{h} must be a multiple of {finest} (the finest of {octaves} octaves "
                         f"from base_cells={base_cells}); use spectral_noise for any size")
    amp = octave_amplitudes(cells, amplitudes)
    dtype = _dtype(dtype)
    rng = check_rng(rng, seed=seed, where="octave_sum")
    total = np.zeros((h, w), dtype=dtype)
    for c, a in zip(cells, amp):
        part = octave((h, w), c, filter=filter, sigma=sigma, rng=rng, dtype=dtype)
        # A random whole-pixel shift per octave, so that the octaves' lattices
        # do not all line up (at the wrap edge, or anywhere else).
        shift = (int(rng.integers(0, h)), int(rng.integers(0, w)))
        total += dtype.type(a) * np.roll(part, shift, axis=(0, 1))
    return total


# --------------------------------------------------------------------------
# Analysis
# --------------------------------------------------------------------------

class PeriodicSmooth(NamedTuple):
    """The two parts of :func:`periodic_smooth_decomposition` (unpacks as ``periodic, smooth``)."""

    periodic: np.ndarray  #: periodic-looking part, the image's mean kept
    smooth: np.ndarray    #: smooth part, zero mean


class RadialSpectrum(NamedTuple):
    """The result of :func:`radial_power_spectrum` (unpacks as ``freqs, power``)."""

    freqs: np.ndarray  #: mean radial frequency of each ring, cycles per pixel
    power: np.ndarray  #: mean power in each ring, ``(K,)`` or ``(K, C)``


def periodic_smooth_decomposition(image):
    """Moisan's periodic-plus-smooth decomposition ``image = p + s``.

    ``s`` is the smooth image (a discrete harmonic function inside) whose
    Laplacian equals that of the image's jumps across the wrap edges; ``p``
    is periodic-looking: its step across the wrap edge is like any interior
    step, and its Fourier transform is free of the cross of leakage that the
    edges put into the transform of ``image``. ``s`` has zero mean, so ``p``
    keeps the image's mean.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)

    Returns
    -------
    PeriodicSmooth
        A named tuple ``(periodic, smooth)``: ndarray, float32, each the
        shape of ``image``.

    References
    ----------
    L. Moisan, "Periodic plus smooth image decomposition", Journal of
    Mathematical Imaging and Vision 39(2), 161-179, 2011.
    """
    image = check_image("image", image, min_size=2)
    u = (image[:, :, None] if image.ndim == 2 else image).astype(np.float64)
    h, w = u.shape[:2]
    s = _solve_periodic_poisson(_edge_source(u, u[0] - u[-1], u[:, 0] - u[:, -1]))
    p = u - s
    if image.ndim == 2:
        p, s = p[:, :, 0], s[:, :, 0]
    return PeriodicSmooth(p.astype(np.float32), s.astype(np.float32))


def _edge_source(u: np.ndarray, row_step: np.ndarray, col_step: np.ndarray) -> np.ndarray:
    """Boundary source image for steps across the wrap edges.

    ``row_step`` (shape (W, C)) is a step from the last row to the first,
    ``col_step`` (shape (H, C)) from the last column to the first. The
    periodic solution of ``Laplacian s = source`` has (about) these steps
    across the wrap edges and is smooth elsewhere; with the image's own
    jumps it is Moisan's smooth component.
    """
    v = np.zeros(u.shape, dtype=np.float64)
    v[0] -= row_step
    v[-1] += row_step
    v[:, 0] -= col_step
    v[:, -1] += col_step
    return v


def _solve_periodic_poisson(v: np.ndarray) -> np.ndarray:
    """Zero-mean periodic ``s`` with the 5-point Laplacian ``v``; (H, W, C) float64."""
    import scipy.fft as sfft

    h, w = v.shape[:2]
    vh = sfft.rfft2(v, axes=(0, 1), workers=_workers(v.size))
    cy = np.cos(2.0 * np.pi * np.arange(h) / h)[:, None]
    cx = np.cos(2.0 * np.pi * np.arange(w // 2 + 1) / w)[None, :]
    den = 2.0 * cx + 2.0 * cy - 4.0
    den[0, 0] = 1.0
    vh /= den[:, :, None]
    vh[0, 0] = 0.0
    return sfft.irfft2(vh, s=(h, w), axes=(0, 1), workers=_workers(v.size))


_WINDOWS = ("none", "hann", "periodic")


def hann_window(shape) -> np.ndarray:
    """Separable 2-D Hann window, positive on every pixel.

    Along each axis of ``n`` pixels the weights are
    ``0.5 - 0.5 cos(2 pi (i + 1) / (n + 1))`` for ``i = 0 .. n - 1``: the
    ``n + 2``-point Hann window without its two zero end points, so that no
    pixel is discarded. The 2-D window is the outer product of the two.
    Multiply an image with its mean removed by it before an FFT, and divide
    the power by ``mean(window ** 2)`` to keep the estimate unbiased, as
    :func:`radial_power_spectrum` and :func:`spectex.metrics.band_power` do.

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


def radial_power_spectrum(image, *, window: str | None = None):
    """Radially averaged power spectrum.

    The image's mean is removed, the optional window applied, and the power
    ``P(k) = |F(k)|^2 / (H W)^2`` (its sum over all frequencies is the
    variance) divided by the window's mean square, so that the estimate is
    unbiased for a stationary texture. ``P`` is averaged over rings of
    radial frequency one frequency step wide, ``1 / min(H, W)`` cycles per
    pixel, up to the Nyquist frequency of the shorter side.

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
        :func:`periodic_smooth_decomposition`, which removes the same leak
        without the window's loss of resolution.

    Returns
    -------
    RadialSpectrum
        A named tuple ``(freqs, power)``: ``freqs``, shape (K,), the mean
        radial frequency of each ring, cycles per pixel, increasing, in
        (0, 0.5]; ``power``, shape (K,) or (K, C), the mean power in each
        ring.

    References
    ----------
    F. J. Harris, "On the use of windows for harmonic analysis with the
    discrete Fourier transform", Proc. IEEE 66(1), 1978; D. J. Field,
    "Relations between the statistics of natural images and the response
    properties of cortical cells", JOSA A 4(12), 1987.
    """
    import scipy.fft as sfft

    image = check_image("image", image, min_size=4)
    window = "none" if window is None else check_choice("window", window, _WINDOWS)
    x = (image[:, :, None] if image.ndim == 2 else image).astype(np.float64)
    if window == "periodic":
        x = periodic_smooth_decomposition(x)[0].astype(np.float64)
        if x.ndim == 2:
            x = x[:, :, None]
    h, w = x.shape[:2]
    x = x - x.mean(axis=(0, 1))
    msq = 1.0
    if window == "hann":
        win = hann_window((h, w))
        x = x * win[:, :, None]
        msq = float(np.mean(win ** 2))
    spec = sfft.rfft2(x, axes=(0, 1), workers=_workers(x.size))
    p2 = (spec.real ** 2 + spec.imag ** 2) / (float(h * w) ** 2 * msq)
    f = _radial_frequency(h, w)
    # Columns 1 .. W/2-1 of the half spectrum stand for two frequencies each.
    mult = np.full(f.shape[1], 2.0)
    mult[0] = 1.0
    if w % 2 == 0:
        mult[-1] = 1.0
    n = min(h, w)
    ring = np.rint(f * n).astype(np.int64)
    kmax = n // 2
    sel = (ring >= 1) & (ring <= kmax)
    idx = ring[sel] - 1
    wts = np.broadcast_to(mult[None, :], f.shape)[sel]
    count = np.bincount(idx, weights=wts, minlength=kmax)
    freqs = np.bincount(idx, weights=wts * f[sel], minlength=kmax)
    good = count > 0
    freqs = freqs[good] / count[good]
    power = np.empty((int(good.sum()), x.shape[2]))
    for c in range(x.shape[2]):
        power[:, c] = np.bincount(idx, weights=wts * p2[:, :, c][sel], minlength=kmax)[good] / count[good]
    return RadialSpectrum(freqs, power[:, 0] if image.ndim == 2 else power)


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
