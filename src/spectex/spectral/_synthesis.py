"""Spectral synthesis (Blythe et al., 1999, 6.21.4).

Two ways to make noise with a prescribed spectrum:

* :func:`octave_sum`: a sum of octaves made by filtering under
  magnification (:func:`spectex.spectral.octave`), each with its own
  amplitude: ``1/f`` (Perlin's ``fractalsum``), a spectral exponent, or a
  list.
* :func:`spectral_noise`: the FFT route, a periodic Gaussian field whose
  power spectrum goes as ``1 / f^beta`` between optional low and high
  cut-offs.
* :func:`band_limit` and :func:`band_limit_planes`: an exact radial
  band-pass by FFT (what makes tiles low-pass, see :mod:`spectex.tiles`).

The tools to check them, power spectra and their slopes, are in
:mod:`spectex.spectrum`.

Frequencies are in cycles per pixel throughout: 0.5 is the Nyquist
frequency, and a frequency ``f`` in an ``N``-pixel period is ``f N`` cycles
per period. Radial frequency is ``sqrt(fy^2 + fx^2)``.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._parallel import fft_workers as _workers
from .._validate import check_choice, check_float, check_image, check_int, check_rng, check_shape
from ._octaves import octave


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
                   rng=None, dtype=np.float32) -> np.ndarray:
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
        randomness.
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
    rng = check_rng(rng)
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


def band_limit_planes(planes, *, low: float | None = None, high: float | None = None,
                      shape=None) -> np.ndarray:
    """:func:`band_limit` of channel-first planes ``(C, h, w)``, without moving the channel axis.

    The same band-pass and Fourier upsampling as :func:`band_limit`, for
    planes stored one channel after the other (what the tile maker works
    on), which saves the copies that moving the channel axis would make.

    Parameters
    ----------
    planes : ndarray, shape (C, h, w)
        Float values (taken as finite: they are not checked, for speed).
    low, high : float or None
        Band edges in cycles per (output) pixel.
    shape : None or (int, int)
        Output ``(H, W)``, at least ``(h, w)``; default ``(h, w)``.

    Returns
    -------
    ndarray, float32, shape (C, H, W)
    """
    if not isinstance(planes, np.ndarray) or planes.ndim != 3 or not np.issubdtype(planes.dtype, np.floating):
        raise ValueError(f"planes must be a float array of shape (C, h, w), got "
                         f"{getattr(planes, 'dtype', type(planes).__name__)} of shape {np.shape(planes)}")
    low, high = _check_band(low, high)
    h, w = planes.shape[1:]
    big_h, big_w = (h, w) if shape is None else check_shape("shape", shape)
    if big_h < h or big_w < w:
        raise ValueError(f"shape must be at least the planes' size {h}x{w} (rows x columns), "
                         f"got {big_h}x{big_w}")
    return _band_limit_planes(planes, low, high, (big_h, big_w))


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
               kernel: str = "bspline", sigma: float = 0.5, rng=None, dtype=np.float32) -> np.ndarray:
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
    kernel, sigma
        See :func:`spectex.spectral.magnify`.
    rng : int, numpy.random.Generator or None
        Randomness (SPEC 7): an int gives ``numpy.random.default_rng(rng)``;
        a Generator is used and advanced; None (the default) draws fresh
        randomness.
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
    rng = check_rng(rng)
    total = np.zeros((h, w), dtype=dtype)
    for c, a in zip(cells, amp):
        part = octave((h, w), c, kernel=kernel, sigma=sigma, rng=rng, dtype=dtype)
        # A random whole-pixel shift per octave, so that the octaves' lattices
        # do not all line up (at the wrap edge, or anywhere else).
        shift = (int(rng.integers(0, h)), int(rng.integers(0, w)))
        total += dtype.type(a) * np.roll(part, shift, axis=(0, 1))
    return total
