"""Quality measures for textures: the single home for them.

Used by the tests, the benchmarks, ``spectex compare`` and the fitting code
(:mod:`spectex.analysis`). Every function takes float images in [0, 1],
``(H, W)`` or ``(H, W, C)`` (integer images are scaled by their dtype's
maximum, as everywhere in spectex), and returns plain numbers or arrays.

===========================  ==============================================  ==============
measure                      what it says                                    good value
===========================  ==============================================  ==============
:func:`histogram_w1`         per-channel Wasserstein-1 distance of values    <= 0.03
:func:`band_power`           windowed, radially averaged power per octave    --
:func:`band_power_distance`  RMS difference of the above, in dB              <= 1.5 dB
:func:`seam_energy`          gradient energy on block boundaries / interior  about 1
:func:`verbatim_copy`        largest region copied with one offset           small
:func:`repetition`           fraction of patches repeated at one period      about 0
:func:`repeat_peak`          highest autocorrelation of fine detail at a     <= 0.1
                             long lag, any period and direction
:func:`tileability`          step across the wrap edge / interior steps      about 1
:func:`structural_distance`  Portilla-Simoncelli statistics' distance over   about 1
                             the photo's own (``ratio``)
:func:`clipped_fraction`     channel values at 0 or 1                        photo's + 0.01
:func:`coarse_copies`        the photo, magnified, found in a zoomed-out     photo's own
                             view (normalised cross-correlation)
:func:`line_breaks`          kinks of the local line direction between       about the
                             neighbouring windows (V-shaped breaks)          photo's own
:func:`line_continuity`      lines along one axis kept at their places       >= 0.9 of the
                             along it (boards' edges moved aside)            photo's
:func:`local_contrast`       mean luminance std in windows (a view against   >= 0.6 of the
                             its tile: how much contrast survives)           tile's
:func:`mean_chroma`          mean max(RGB) - min(RGB)                        --
:func:`mean_gradient`        mean |luminance step| between neighbours        --
===========================  ==============================================  ==============

:func:`band_power` is estimated in :mod:`spectex.spectrum`, the home of power
spectra, and listed here as the measure it is (the same function).

References
----------
.. [1] Y. Rubner, C. Tomasi, L. J. Guibas, "The Earth Mover's Distance as a
   metric for image retrieval", IJCV 40(2), 2000 (W1 between histograms).
.. [2] F. J. Harris, "On the use of windows for harmonic analysis with the
   discrete Fourier transform", Proc. IEEE 66(1), 1978 (the Hann window).
.. [3] A. A. Efros, W. T. Freeman, "Image quilting for texture synthesis and
   transfer", SIGGRAPH 2001 (block boundaries, the seams measured here).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._lattice import lattice_strength as _lattice_strength  # (shared with the fit's turned structures)
from ._lattice import lattice_strength_2d as _lattice_strength_2d
from ._lighting import LightingBlotches, lighting_blotches  # the photo's lighting (issue 22)
from ._otsu import otsu
from ._pixels import principal_axis
from ._results import AsDict
from ._scale import ScaleBlotches, scale_blotches  # a photo taken at an angle (issue 22)
from ._texture_stats import (  # structural measures (issue 22), in their own module
    Clipping,
    CoarseCopies,
    OneOffRepeats,
    StructuralDistance,
    TextureStatistics,
    clipped_fraction,
    clipping,
    coarse_copies,
    coarse_reference,
    one_off_repeats,
    reference_statistics,
    structural_distance,
    texture_statistics,
)
from ._validate import check_float, check_image, check_int
from .color import luma
from .spectrum import (  # the estimator's home is spectex.spectrum; a measure of this table
    BandPower,
    band_power,
)

__all__ = [
    "histogram_w1",
    "band_power",
    "band_power_distance",
    "seam_energy",
    "verbatim_copy",
    "repetition",
    "repeat_peak",
    "tileability",
    "local_contrast",
    "mean_chroma",
    "mean_gradient",
    "compare",
    "Comparison",
    "BandPower",
    "texture_statistics",
    "TextureStatistics",
    "structural_distance",
    "StructuralDistance",
    "reference_statistics",
    "clipped_fraction",
    "clipping",
    "Clipping",
    "coarse_copies",
    "coarse_reference",
    "CoarseCopies",
    "one_off_repeats",
    "OneOffRepeats",
    "line_breaks",
    "LineBreaks",
    "line_continuity",
    "lines_axis",
    "lines_or_none",
    "LineContinuity",
    "cell_splits",
    "short_cells",
    "CellSplits",
]


def _channels(image: np.ndarray) -> np.ndarray:
    """``(H, W, C)`` view of an image (grey gets C = 1)."""
    return image[:, :, None] if image.ndim == 2 else image


def _luma(image: np.ndarray) -> np.ndarray:
    """One float64 channel: grey as is, RGB(A) by Rec. 709 luma (:func:`spectex.color.luma`), alpha ignored."""
    return luma(image, dtype=np.float64)


# --------------------------------------------------------------------------
# What a first look sees: contrast, colour, sharpness
# --------------------------------------------------------------------------

def local_contrast(image, *, window: int = 32) -> float:
    """Mean standard deviation of the luminance in non-overlapping ``window`` x ``window`` blocks.

    The contrast a viewer sees at the scale of a few dozen pixels, whatever
    the picture does at larger scales: compare a rendered view with its
    tile's own (``local_contrast(view) / local_contrast(tile)``) to see how
    much of the tile's contrast the layers, the filtering and the haze left.
    The picture is cropped to whole blocks (at least one).
    """
    y = _luma(check_image("image", image))
    window = check_int("window", window, minimum=2)
    h, w = (y.shape[0] // window) * window, (y.shape[1] // window) * window
    if h == 0 or w == 0:
        raise ValueError(f"window must be at most the image's sides {y.shape[:2]}, got {window}")
    blocks = y[:h, :w].reshape(h // window, window, w // window, window)
    return float(blocks.std(axis=(1, 3)).mean())


def mean_chroma(image) -> float:
    """Mean chroma ``max(R, G, B) - min(R, G, B)`` (HSV's C) over the pixels of an RGB(A) image (alpha ignored)."""
    image = check_image("image", image, channels=(3, 4))
    rgb = np.asarray(image[..., :3], dtype=np.float64)
    return float((rgb.max(axis=-1) - rgb.min(axis=-1)).mean())


def mean_gradient(image) -> float:
    """Mean absolute luminance step between neighbouring pixels, per pixel (rows and columns averaged).

    A sharpness measure: a magnified, blurred texture has small steps.
    """
    y = _luma(check_image("image", image))
    return float(0.5 * (np.abs(np.diff(y, axis=0)).mean() + np.abs(np.diff(y, axis=1)).mean()))


# --------------------------------------------------------------------------
# Histogram distance
# --------------------------------------------------------------------------

def _w1_1d(u: np.ndarray, v: np.ndarray) -> float:
    """Exact W1 between two empirical distributions (any sizes)."""
    u = np.sort(u.ravel().astype(np.float64))
    v = np.sort(v.ravel().astype(np.float64))
    allv = np.concatenate([u, v])
    allv.sort(kind="mergesort")
    deltas = np.diff(allv)
    cu = np.searchsorted(u, allv[:-1], side="right") / u.size
    cv = np.searchsorted(v, allv[:-1], side="right") / v.size
    return float(np.sum(np.abs(cu - cv) * deltas))


def histogram_w1(a, b) -> np.ndarray:
    """Per-channel Wasserstein-1 (earth mover's) distance between two images.

    The distance between the empirical distributions of the values of each
    channel: the integral of ``|F_a(t) - F_b(t)|`` over ``t``, computed exactly
    from the sorted values. The images may differ in size; with values in
    [0, 1] the distance is in [0, 1] too (0 for identical histograms, 1 for
    an all-black against an all-white image).

    Parameters
    ----------
    a, b : ndarray, shape (H, W) or (H, W, C)
        Two images with the same number of channels.

    Returns
    -------
    ndarray of float64, shape (C,)
        One distance per channel (``C = 1`` for grey images).

    References
    ----------
    Rubner, Tomasi and Guibas, IJCV 2000.
    """
    a = check_image("a", a)
    b = check_image("b", b)
    ca, cb = _channels(a), _channels(b)
    if ca.shape[2] != cb.shape[2]:
        raise ValueError(f"a and b must have the same number of channels, got shapes {a.shape} and {b.shape}")
    out = []
    for i in range(ca.shape[2]):
        # a grey picture repeated into RGB: the same channel's distance once (the sorts are the cost)
        same = next((j for j in range(i) if np.array_equal(ca[:, :, i], ca[:, :, j])
                     and np.array_equal(cb[:, :, i], cb[:, :, j])), None)
        out.append(out[same] if same is not None else _w1_1d(ca[:, :, i], cb[:, :, i]))
    return np.array(out)


# --------------------------------------------------------------------------
# Power per octave band
# --------------------------------------------------------------------------

def _common_bands(a, b, min_cycles):
    """Band powers of two images at the same resolution (the smaller size)."""
    seg = (min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1]))
    bands, pa = band_power(a, min_cycles=min_cycles, segment=seg)
    _, pb = band_power(b, min_cycles=min_cycles, segment=seg)
    return bands, pa, pb


def band_power_distance(a, b, *, min_cycles: int = 4) -> float:
    """RMS difference in dB between two images' power per octave band.

    Both images are analysed in segments of the same size, the smaller of
    the two in each direction (see :func:`band_power`, ``segment``): the
    larger image's spectrum is averaged over overlapping crops, so both
    estimates have the same frequency resolution and window leakage.

    Parameters
    ----------
    a, b : ndarray, shape (H, W) or (H, W, C)
    min_cycles : int
        As in :func:`band_power`.

    Returns
    -------
    float
        ``sqrt(mean((P_a - P_b)^2))`` over the bands, in dB.
    """
    a = check_image("a", a)
    b = check_image("b", b)
    _, pa, pb = _common_bands(a, b, min_cycles)
    return float(np.sqrt(np.mean((pa - pb) ** 2)))


# --------------------------------------------------------------------------
# Seams and wrap edges
# --------------------------------------------------------------------------

def seam_energy(image, block: int, overlap: int = 0) -> float:
    """Gradient energy along block boundaries against the interior's.

    For a texture assembled from blocks of ``block`` pixels placed every
    ``block - overlap`` pixels from the top-left corner (the layout of
    :func:`spectex.synthesis.quilt` and of plain tiling, ``overlap=0``), the
    boundary between two blocks lies somewhere in the overlap band. This is
    the mean squared step between neighbouring pixels across those bands
    (the ``overlap + 1`` steps from the last pixel before a band to its last
    pixel, horizontally for vertical bands and vertically for horizontal
    ones) divided by the mean squared step everywhere else.

    A seamless texture gives about 1; visible seams give more (abutting
    unrelated blocks: about ``2 / (1 - rho)`` for a neighbour correlation
    ``rho``).

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
    block : int
        Block size in pixels, >= 2.
    overlap : int
        Overlap between neighbouring blocks, ``0 <= overlap < block``.

    Returns
    -------
    float
        The ratio; ``nan`` if the image holds no block boundary.

    References
    ----------
    Efros and Freeman, SIGGRAPH 2001.
    """
    image = check_image("image", image)
    block = check_int("block", block, minimum=2)
    overlap = check_int("overlap", overlap, minimum=0)
    if overlap >= block:
        raise ValueError(f"overlap must be smaller than block={block}, got {overlap}")
    img = _channels(image).astype(np.float64)
    step = block - overlap
    energies = []
    masks = []
    for axis in (0, 1):
        d = np.diff(img, axis=axis)
        e = np.sum(d * d, axis=2)  # (H-1, W) or (H, W-1)
        n = e.shape[axis]
        band = np.zeros(n, dtype=bool)
        for start in range(step, n + 1, step):
            band[max(start - 1, 0):min(start + overlap, n)] = True
        energies.append(e)
        masks.append(band[:, None] if axis == 0 else band[None, :])
    band_sum = band_n = rest_sum = rest_n = 0.0
    for e, m in zip(energies, masks):
        m = np.broadcast_to(m, e.shape)
        band_sum += e[m].sum()
        band_n += m.sum()
        rest_sum += e[~m].sum()
        rest_n += (~m).sum()
    if band_n == 0 or rest_n == 0 or rest_sum == 0:
        return float("nan")
    return float((band_sum / band_n) / (rest_sum / rest_n))


def tileability(image, *, axis: int | None = None) -> float:
    """Step across the wrap edge against the steps inside the image.

    The mean squared difference between the last and the first row (the step
    a viewer sees where two copies of the image meet) divided by the mean
    squared difference between neighbouring rows inside the image; the same
    for columns. A texture that tiles seamlessly gives about 1 (its wrap edge
    looks like any other pair of neighbouring rows); a crop of a photograph
    usually gives several times more.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 3 x 3 pixels.
    axis : {None, 0, 1}
        0: the top/bottom edge only; 1: the left/right edge only; None: the
        larger (worse) of the two.

    Returns
    -------
    float
        The ratio (``nan`` for an image without interior steps, such as a
        constant one, unless its wrap step is not zero either: then ``inf``).
    """
    image = check_image("image", image, min_size=3)
    if axis is not None:
        axis = check_int("axis", axis, minimum=0, maximum=1)
    img = _channels(image).astype(np.float64)
    ratios = []
    for ax in ((0, 1) if axis is None else (axis,)):
        inner = np.mean(np.sum(np.diff(img, axis=ax) ** 2, axis=2))
        if ax == 0:
            wrap = np.mean(np.sum((img[0] - img[-1]) ** 2, axis=1))
        else:
            wrap = np.mean(np.sum((img[:, 0] - img[:, -1]) ** 2, axis=1))
        if inner == 0:
            ratios.append(float("nan") if wrap == 0 else float("inf"))
        else:
            ratios.append(float(wrap / inner))
    return max(ratios) if len(ratios) > 1 else ratios[0]


# --------------------------------------------------------------------------
# Copies and repetition
# --------------------------------------------------------------------------

def _patch_hashes(image: np.ndarray, patch: int) -> np.ndarray:
    """A 64-bit hash of every ``patch x patch`` window (8-bit quantised).

    Returns shape ``(H - patch + 1, W - patch + 1)``, uint64. The hash is a
    random linear combination modulo 2^64 of the quantised values, the same
    for every image in a run (fixed seed), so equal patches get equal hashes
    and different ones collide with probability about 2^-64.
    """
    img = _channels(image)
    q = np.rint(np.clip(img, 0.0, 1.0) * 255.0).astype(np.uint64)
    h, w, c = q.shape
    weights = np.random.default_rng(0x5EC7E).integers(1, 2**63, size=(patch, patch, 4), dtype=np.uint64)
    weights |= np.uint64(1)
    out = np.zeros((h - patch + 1, w - patch + 1), dtype=np.uint64)
    for dy in range(patch):
        for dx in range(patch):
            for ch in range(c):
                out += q[dy:dy + h - patch + 1, dx:dx + w - patch + 1, ch] * weights[dy, dx, ch]
    # mix so that nearby linear combinations spread (splitmix64 finaliser)
    out ^= out >> np.uint64(30)
    out *= np.uint64(0xBF58476D1CE4E5B9)
    out ^= out >> np.uint64(27)
    return out


def verbatim_copy(image, exemplar, *, patch: int = 5) -> float:
    """The largest region of ``image`` copied from ``exemplar`` with one offset.

    Every ``patch x patch`` window of the image (values quantised to 8 bits)
    is looked up among the exemplar's windows; where it occurs exactly once
    there, the pixel gets that source position, hence an offset (source minus
    position). Pixels whose neighbours (4-connected) have the same offset form
    one copied region. The result is the largest region's area as a fraction
    of the image's windows: 1.0 for a crop of the exemplar, ``1/n`` for the
    exemplar tiled ``n`` times, about ``(block / size)^2`` for a quilt.

    Windows that occur more than once in the exemplar (flat areas) match
    nothing, so the measure never overstates a copy.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
    exemplar : ndarray, shape (h, w) or (h, w, C)
        Same number of channels as ``image``.
    patch : int
        Odd window size >= 1 used to identify a source position.

    Returns
    -------
    float
        Fraction in [0, 1].
    """
    image = check_image("image", image)
    exemplar = check_image("exemplar", exemplar)
    patch = check_int("patch", patch, minimum=1)
    if patch % 2 == 0:
        raise ValueError(f"patch must be odd, got {patch}")
    ci, ce = _channels(image), _channels(exemplar)
    if ci.shape[2] != ce.shape[2]:
        raise ValueError(f"image and exemplar must have the same number of channels, got shapes "
                         f"{image.shape} and {exemplar.shape}")
    if min(image.shape[:2]) < patch or min(exemplar.shape[:2]) < patch:
        raise ValueError(f"patch={patch} is larger than the image or the exemplar")
    he = _patch_hashes(ce, patch)
    hi = _patch_hashes(ci, patch)
    ekeys = he.ravel()
    order = np.argsort(ekeys, kind="stable")
    sorted_keys = ekeys[order]
    uniq, first, counts = np.unique(sorted_keys, return_index=True, return_counts=True)
    pos = np.searchsorted(uniq, hi.ravel())
    pos = np.minimum(pos, len(uniq) - 1)
    found = (uniq[pos] == hi.ravel()) & (counts[pos] == 1)
    src = np.where(found, order[first[pos]], -1)
    ew = he.shape[1]
    hh, ww = hi.shape
    sy, sx = np.divmod(src, ew)
    yy, xx = np.divmod(np.arange(hh * ww), ww)
    # offset code: unique per (dy, dx); -1 where unmatched
    code = np.where(found, (sy - yy + hh) * (2 * ww + ew + 1) + (sx - xx + ww), -1).reshape(hh, ww)
    if not found.any():
        return 0.0
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    idx = np.arange(hh * ww).reshape(hh, ww)
    right = (code[:, :-1] == code[:, 1:]) & (code[:, :-1] >= 0)
    down = (code[:-1, :] == code[1:, :]) & (code[:-1, :] >= 0)
    rows = np.concatenate([idx[:, :-1][right], idx[:-1, :][down]])
    cols = np.concatenate([idx[:, 1:][right], idx[1:, :][down]])
    graph = coo_matrix((np.ones(rows.size, dtype=np.int8), (rows, cols)), shape=(hh * ww, hh * ww))
    _, labels = connected_components(graph, directed=False)
    labels = labels[found]
    largest = np.bincount(labels).max()
    return float(largest / (hh * ww))


def repetition(image, period, *, patch: int = 5) -> float:
    """Fraction of the image's windows repeated exactly one period away.

    A window (``patch x patch``, values quantised to 8 bits) at ``(y, x)``
    counts as repeated if the window at ``(y + py, x)`` or at ``(y, x + px)``
    is identical. The exemplar tiled with period ``(py, px)`` gives 1; a
    synthesis that does not repeat the exemplar at its own period gives
    about 0.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
    period : int or (int, int)
        ``(py, px)``, usually the exemplar's ``(height, width)``.
    patch : int
        Odd window size >= 1.

    Returns
    -------
    float
        Fraction in [0, 1] of the windows that have a partner one period
        away inside the image (0 if none has).
    """
    image = check_image("image", image)
    patch = check_int("patch", patch, minimum=1)
    if patch % 2 == 0:
        raise ValueError(f"patch must be odd, got {patch}")
    if np.ndim(period) == 0:
        period = (period, period)
    if len(period) != 2:
        raise ValueError(f"period must be an int or a (py, px) pair, got {period!r}")
    py = check_int("period[0]", period[0], minimum=1)
    px = check_int("period[1]", period[1], minimum=1)
    if min(image.shape[:2]) < patch:
        raise ValueError(f"patch={patch} is larger than the image ({image.shape[1]}x{image.shape[0]})")
    hs = _patch_hashes(image, patch)
    hh, ww = hs.shape
    rep = np.zeros((hh, ww), dtype=bool)
    has = np.zeros((hh, ww), dtype=bool)
    if py < hh:
        rep[:-py] |= hs[:-py] == hs[py:]
        has[:-py] = True
    if px < ww:
        rep[:, :-px] |= hs[:, :-px] == hs[:, px:]
        has[:, :-px] = True
    if not has.any():
        return 0.0
    return float(rep[has].mean())


def repeat_peak(image, *, min_lag: int = 24, sigma: float = 3.0, period=None) -> float:
    """How strongly the image's fine detail repeats, at any period and angle.

    The luminance (Rec. 709 luma for colour, alpha ignored) minus its
    Gaussian blur of ``sigma`` pixels (wrapping at the borders) keeps the
    fine detail, where a repeat shows; its mean is removed, and its circular
    autocorrelation is computed by FFT and divided by its value at lag 0.
    The result is the largest correlation over all lags ``(dy, dx)`` (each
    wrapped into ``[-H/2, H/2) x [-W/2, W/2)``) whose length
    ``sqrt(dy^2 + dx^2)`` is at least ``min_lag`` pixels, in any direction.

    Plain tiling gives 1.0 at the tile's period (and its multiples, so any
    period above about ``min_lag / 2`` is seen); the same tiling rotated or
    offset keeps a high peak (about 0.8 at 30 degrees, the interpolation of
    the rotation costs the rest); white noise gives about ``sqrt(2 ln N) /
    sqrt(N)`` for ``N = H W`` pixels (0.005 for 1024 x 1024), good quilting
    0.02 to 0.04. Unlike :func:`repetition` (exact copies one period away,
    axis-aligned) it also sees a repeat that coarser variation dilutes,
    because the blur subtraction removes that variation first.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least ``2 * min_lag`` pixels on its shorter side.
    min_lag : int
        Shortest lag counted, pixels (>= 1): shorter lags see the texture's
        own correlation length, not a repeat.
    sigma : float
        Standard deviation of the blur removed, pixels (> 0).
    period : (float or None, float or None), optional
        The period ``(py, px)`` in pixels (not necessarily whole) of a
        structure the image is meant to have, e.g. the mortar grid of a
        brick wall (``spectex.fitting.structure_period`` of its photo): the
        fine detail's mean over that lattice (its value averaged over all
        the periods, at each of ``round(py) x round(px)`` phases) is removed
        before the autocorrelation, so what is left is how much the
        *content* repeats (a tile of whole periods repeated: about 1; the
        same structure with other content in every period: near the
        photo's own). None on an axis: no period along it; where the
        other axis has one, the structure's lines run along this axis
        unbroken (mortar columns), and the detail's running mean along it
        (a Gaussian of ``2 min_lag`` pixels) is removed as well: a straight
        line correlates with itself at every lag along it without
        repeating anything. With a period on both axes (a floor's grout
        grid) the running means along both are removed: at a fractional
        period the lattice's mean (whole-pixel phases) leaves a line beside
        each grout line.

    References
    ----------
    Heitz and Neyret, "High-performance by-example noise using a
    histogram-preserving blending operator", Proc. ACM CGIT 1(2), 2018 (the
    repetition that tiling-and-blending removes); Wiener-Khinchin theorem
    (the autocorrelation as the inverse transform of the power spectrum).
    """
    from scipy import ndimage

    image = check_image("image", image)
    min_lag = check_int("min_lag", min_lag, minimum=1)
    sigma = check_float("sigma", sigma, minimum=0.0, exclusive_minimum=True)
    h, w = image.shape[:2]
    if min(h, w) < 2 * min_lag:
        raise ValueError(f"image must be at least {2 * min_lag} pixels on its shorter side for "
                         f"min_lag={min_lag}, got {w}x{h}")
    lum = _luma(image)
    detail = lum - ndimage.gaussian_filter(lum, sigma, mode="wrap")
    detail -= detail.mean()
    if period is not None:
        detail = detail - _lattice_mean(detail, period)
        # an axis without a period is one the structure runs along unbroken (a wall's mortar columns
        # the height of the photo): a line left by the lattice's removal (a column a pixel off the
        # mean one) correlates with itself at every lag along it, a straight line and not a repeat.
        # Its running mean along that axis is removed too, so only content that comes back counts
        # (a wall square-on with bricks of random length: 0.31 without this, 0.0x with it).
        # A lattice along both axes (a floor's grout grid) has lines along both: where its period is
        # fractional (85.33 pixels), the grout's sub-pixel phase drifts from period to period, the
        # lattice's mean (whole-pixel phases) leaves a line beside each, and a floor of random tiles
        # read 0.35 (its own content repeating nowhere); both running means removed, 0.0x.
        both = all(p is not None for p in period)
        for axis, p in enumerate(period):
            if both or (p is None and period[1 - axis] is not None):
                detail = detail - ndimage.gaussian_filter1d(detail, 2.0 * min_lag, axis=axis, mode="wrap")
    spec = np.fft.rfft2(detail)
    acf = np.fft.irfft2(spec.real ** 2 + spec.imag ** 2, s=(h, w))
    zero = acf[0, 0]
    if not zero > 1e-12 * h * w * max(float(np.max(np.abs(lum))), 1e-30) ** 2:
        return float("nan")
    dy = np.fft.fftfreq(h) * h
    dx = np.fft.fftfreq(w) * w
    far = (dy[:, None] ** 2 + dx[None, :] ** 2) >= float(min_lag) ** 2
    return float(np.max(acf[far]) / zero)


def _lattice_mean(detail, period):
    """``detail``'s mean over the lattice of ``period = (py, px)`` (pixels, None: no period), at every pixel."""
    if not isinstance(period, (tuple, list)) or len(period) != 2:
        raise ValueError(f"period must be a pair (py, px) of pixels or None, got {period!r}")
    h, w = detail.shape
    bins = []
    for name, p, n in (("period[0]", period[0], h), ("period[1]", period[1], w)):
        if p is None:
            bins.append(np.zeros(n, dtype=np.int64))
            continue
        p = check_float(name, p, minimum=2.0, maximum=n / 2.0)
        k = max(1, int(round(p)))
        bins.append(np.minimum((np.mod(np.arange(n) + 0.5, p) / p * k).astype(np.int64), k - 1))
    ky, kx = int(bins[0].max()) + 1, int(bins[1].max()) + 1
    cell = bins[0][:, None] * kx + bins[1][None, :]
    sums = np.bincount(cell.ravel(), weights=detail.ravel(), minlength=ky * kx)
    counts = np.bincount(cell.ravel(), minlength=ky * kx)
    return (sums / np.maximum(counts, 1))[cell]


# --------------------------------------------------------------------------
# Breaks in a structure's lines
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class LineBreaks(AsDict):
    """How sharply the lines of an image turn between neighbouring windows, against a reference's
    (:func:`line_breaks`).

    Attributes
    ----------
    image, reference : float
        Each one's :func:`line_breaks` kink: the RMS turn, in degrees, of
        the local line direction's change from one window to the next
        (about 0 for straight or evenly fanning lines; several degrees
        where lines meet at V-shaped breaks; tens of degrees for a texture
        without lines).
    ratio : float
        ``image / max(reference, floor)``: about 1 or below keeps the
        reference's lines as straight as they are; clearly above shows
        breaks the reference does not have.
    window : int
        The windows' side, pixels.
    """

    image: float
    reference: float
    ratio: float
    window: int


def _line_kinks(image, window):
    """The RMS second difference (degrees) of the local line direction over windows ``window`` apart."""
    from scipy import ndimage

    lum = _luma(image)
    gy = ndimage.gaussian_filter(lum, 1.0, order=(1, 0))
    gx = ndimage.gaussian_filter(lum, 1.0, order=(0, 1))
    # the gradients' direction taken four times: the two directions of a grid (a brick wall's joints
    # along and across) vote alike, so the field is the grid's, not its stronger family's only
    z = (gx * gx + gy * gy) * np.exp(4j * np.arctan2(gy, gx))
    step = window // 2
    h, w = lum.shape
    ny, nx = h // step, w // step
    cells = z[: ny * step, : nx * step].reshape(ny, step, nx, step).sum(axis=(1, 3))
    # windows of `window` pixels, every half window; triples of windows a window apart
    f = cells[:-1, :-1] + cells[1:, :-1] + cells[:-1, 1:] + cells[1:, 1:]
    turns, weights = [], []
    for a, b, c in ((f[:, 4:], f[:, 2:-2], f[:, :-4]), (f[4:], f[2:-2], f[:-4])):
        if a.size == 0:
            continue
        turns.append(np.degrees(np.angle(a * np.conj(b) ** 2 * c)).ravel() / 4.0)
        weights.append(np.minimum(np.minimum(np.abs(a), np.abs(b)), np.abs(c)).ravel())
    if not turns:
        raise ValueError(f"image must be at least {3 * window} pixels on one side for window={window}, "
                         f"got {w}x{h}")
    t, wt = np.concatenate(turns), np.concatenate(weights)
    if not float(wt.sum()) > 0.0:
        return float("nan")
    return float(np.sqrt(np.sum(wt * t * t) / np.sum(wt)))


def line_breaks(image, reference, *, window: int = 64, floor: float = 0.5) -> LineBreaks:
    """V-shaped breaks in a structure's lines (mortar, grout): the image's kinks against the reference's.

    The local line direction is read in windows of ``window`` pixels, one
    every half window: the luma's gradients (Gaussian derivatives, sigma 1
    pixel) summed as ``|g|^2 exp(4i theta)`` (the direction taken four
    times, so a grid's two families vote alike; modulo 90 degrees). Along
    rows and columns of windows, each window's direction is compared with
    its neighbours' a window away on either side: the second difference
    ``arg(z_a conj(z_b)^2 z_c) / 4``, how sharply the direction turns there.
    The kink is its RMS in degrees, each weighted by the weakest of the
    three windows' summed vector (strong, consistent lines weigh most; a
    window without lines little).

    Straight lines give about 0, and so do lines fanning out evenly (a wall
    photographed in perspective: the direction changes linearly across the
    photo, its second difference is 0); lines made of pieces at different
    angles (patches cut from the left and right of a photo in perspective,
    meeting at V-shaped breaks) give several degrees; a texture without
    lines gives tens of degrees, as its reference does.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture judged, e.g. a bake at the reference's pixel size.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo. Both at least ``3 window`` pixels on one side.
    window : int
        Windows' side, pixels (>= 8, even); a few of the structure's
        periods (64 for bricks of about 35 px).
    floor : float
        Least reference kink the ratio divides by, degrees (> 0): a drawn,
        perfectly straight reference has about 0.

    Returns
    -------
    LineBreaks
        ``ratio`` about 1 or below: the lines as straight as the
        reference's.

    References
    ----------
    H. Knutsson, "Representing local structure using tensors", Proc. 6th
    SCIA, 1989 (the orientation as an angle taken several times, weighted
    by the gradient energy); J. Bigun and G. H. Granlund, "Optimal
    orientation detection of linear symmetry", ICCV 1987.
    """
    image = check_image("image", image)
    reference = check_image("reference", reference)
    window = check_int("window", window, minimum=8)
    if window % 2:
        raise ValueError(f"window must be even, got {window}")
    floor = check_float("floor", floor, minimum=0.0, exclusive_minimum=True)
    mine = _line_kinks(image, window)
    own = _line_kinks(reference, window)
    return LineBreaks(image=mine, reference=own, ratio=mine / max(own, floor), window=window)


@dataclass(frozen=True, eq=False)
class LineContinuity(AsDict):
    """How far lines running along one axis keep their places along it, against a reference's
    (:func:`line_continuity`).

    Attributes
    ----------
    image, reference : float
        Each one's continuity: the coefficient of variation, across the
        lines, of the luma's gradient across them averaged over ``length``
        pixels along them (a block), the mean over its blocks. Lines that
        run the block's whole length at one place give a peaked profile
        (high); lines that end and go on a few pixels aside (pieces of
        boards put side by side at other places) smear it (lower).
    ratio : float
        ``image / reference``: about 1 or above, the lines as continuous as
        the reference's; clearly below, lines broken and moved.
    axis : int
        0: lines running down the columns (boards or a wall's columns along
        y); 1: along the rows.
    length : int
        The blocks' length along the lines, pixels.
    """

    image: float
    reference: float
    ratio: float
    axis: int
    length: int


def _continuity(image, axis, length):
    """:func:`line_continuity`'s score of one image."""
    from scipy import ndimage

    lum = _luma(image).astype(np.float64)
    if axis == 1:
        lum = lum.T
    across = np.abs(ndimage.sobel(lum, 1))  # the gradient across lines that run down the columns
    blocks = max(1, across.shape[0] // length)
    scores = []
    for b in range(blocks):
        profile = across[b * length:(b + 1) * length].mean(axis=0)
        scores.append(float(profile.std() / max(float(profile.mean()), 1e-12)))
    return float(np.mean(scores))


def line_continuity(image, reference, *, axis: int, length: int | None = None) -> LineContinuity:
    """Whether lines along one axis (boards' edges, a wall's columns) run on where they run in the reference.

    A texture drawn in patches of a photo of boards side by side moves each
    board's edge to where the patch's own board has it: the edges end at the
    patch's border and go on a few pixels aside, or anywhere (patches at
    random places). :func:`line_breaks` reads the lines' direction, which
    stays the same, and the structural distance their statistics, which do
    too; neither sees it. Here the luma's gradient across the lines (Sobel)
    is averaged along them over blocks of ``length`` pixels: where the edges
    hold their places through the block the profile across keeps their
    peaks, where they move it smears. The score is the profile's coefficient
    of variation, averaged over the blocks; the ratio is the image's over the
    reference's.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture judged, e.g. a bake at the reference's pixel size.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo.
    axis : {0, 1}
        0: the lines run down the columns (along y); 1: along the rows.
    length : int, optional
        The blocks' length along the lines, pixels, at least 8; default half
        the shorter of the two images' extents along the lines. Both must be
        at least that long.

    Returns
    -------
    LineContinuity
        ``ratio`` about 1 or above: the lines as continuous as the
        reference's.
    """
    image = check_image("image", image)
    reference = check_image("reference", reference)
    axis = check_int("axis", axis, minimum=0, maximum=1)
    extent = min(image.shape[axis], reference.shape[axis])
    length = max(8, extent // 2) if length is None else check_int("length", length, minimum=8)
    if length > extent:
        raise ValueError(f"length must be at most the images' extent along the lines ({extent}), got {length}")
    mine = _continuity(image, axis, length)
    own = _continuity(reference, axis, length)
    return LineContinuity(image=mine, reference=own, ratio=mine / max(own, 1e-12), axis=axis, length=length)


# --------------------------------------------------------------------------
# Bricks and floor tiles that change colour partway across
# --------------------------------------------------------------------------

#: The least fraction of the colour variance the grout / interior split must explain (Otsu's criterion).
CELL_SEPARATION = 0.5
#: The least fraction of the colour variance (along its principal axis) the image's mean line profile,
#: folded by the period, must hold along each axis with a period: a lattice of grout, not a texture (white
#: noise about 0.0004, gravel 0.001; the tiles and brick photos and their bakes 0.45-0.65).
LATTICE_STRENGTH = 0.1
#: The least number of whole cells (not touching the border) an image must show.
MIN_CELLS = 6


@dataclass(frozen=True, eq=False)
class CellSplits(AsDict):
    """How much a structure's cells (bricks, floor tiles) change colour partway across, against a reference's
    (:func:`cell_splits`).

    Attributes
    ----------
    image, reference : float
        Each one's split: the mean, over its 25 % most split cells, of the
        larger difference between the mean colours of a cell's halves
        (left / right, top / bottom), relative to the spread of the mean
        colour from cell to cell.
    ratio : float
        ``image / reference``: about 1 is as uniform within a cell as the
        reference's; clearly above, cells made of two different ones.
    cells_image, cells_reference : int
        The whole cells measured in each.
    """

    image: float
    reference: float
    ratio: float
    cells_image: int
    cells_reference: int


def _cell_components(image, period):
    """The whole cells of one image (:func:`cell_splits`): ``(rgb, labels, count, ok)`` with ``ok`` (count + 1,)
    True for the components not touching the border and of 16 pixels or more; None where it shows no separate
    cells."""
    from scipy import ndimage

    rgb = _channels(image).astype(np.float64)
    smooth = np.stack([ndimage.gaussian_filter(rgb[:, :, c], 1.0) for c in range(rgb.shape[2])], axis=2)
    flat = smooth.reshape(-1, rgb.shape[2])
    level = ((flat - flat.mean(axis=0)) @ principal_axis(flat, sample=20000)).reshape(rgb.shape[:2])
    strength = _lattice_strength(level, period)
    if None not in period:  # a lattice along both axes: grout of any shape (hexagons) is seen folded in 2-D
        strength = max(strength, _lattice_strength_2d(level, period))
    if strength < LATTICE_STRENGTH:
        return None
    threshold, explained = otsu(level.ravel())
    if explained < CELL_SEPARATION:
        return None
    high = level > threshold
    inside = high if high.mean() >= 0.5 else ~high  # the grout is the thinner class
    inside = ndimage.binary_erosion(inside)
    labels, count = ndimage.label(inside)
    if count == 0:
        return None
    border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    areas = np.bincount(labels.ravel(), minlength=count + 1).astype(np.float64)
    ok = np.ones(count + 1, dtype=bool)
    ok[0] = False
    ok[border] = False
    ok &= areas >= 16
    if ok.sum() < MIN_CELLS:
        return None
    return rgb, labels, count, ok


def _cell_split(image, period):
    """``(score, cells)`` of :func:`cell_splits` for one image, or None where it shows no separate cells."""
    from scipy import ndimage

    found = _cell_components(image, period)
    if found is None:
        return None
    rgb, labels, count, ok = found
    areas = np.bincount(labels.ravel(), minlength=count + 1).astype(np.float64)
    ok &= areas >= 0.25 * np.median(areas[ok])
    ids = np.flatnonzero(ok)
    if ids.size < MIN_CELLS:
        return None
    yy, xx = np.indices(labels.shape, dtype=np.float64)
    cy = ndimage.mean(yy, labels, ids)
    cx = ndimage.mean(xx, labels, ids)
    lut = np.zeros(count + 1, dtype=np.int64)
    lut[ids] = np.arange(ids.size)
    member = ok[labels]
    k = lut[labels][member]
    colours = rgb[member]
    n = ids.size
    means = np.stack([np.bincount(k, weights=colours[:, c], minlength=n) for c in range(rgb.shape[2])], axis=1)
    means /= np.bincount(k, minlength=n)[:, None]
    spread = float(np.sqrt(np.mean(np.sum((means - means.mean(axis=0)) ** 2, axis=1))))
    if spread <= 1e-9:
        return None
    split = np.zeros(n)
    for first in (xx[member] < cx[k], yy[member] < cy[k]):
        halves = []
        for side in (first, ~first):
            counts = np.bincount(k[side], minlength=n)
            sums = np.stack([np.bincount(k[side], weights=colours[side, c], minlength=n)
                             for c in range(rgb.shape[2])], axis=1)
            halves.append((sums, counts))
        (s1, c1), (s2, c2) = halves
        both = (c1 > 0) & (c2 > 0)
        diff = np.zeros(n)
        diff[both] = np.linalg.norm(s1[both] / c1[both, None] - s2[both] / c2[both, None], axis=1)
        split = np.maximum(split, diff)
    top = np.sort(split)[-max(1, n // 4):]
    return float(top.mean() / spread), n


def _cells_of_both(image, reference, period, measure):
    """The checked inputs of :func:`cell_splits` and :func:`short_cells` measured: ``(measure(image, period),
    measure(reference, period))``, or None without a structure (``period`` None or ``(None, None)``) or where
    either shows no separate cells; a bad ``period`` is one line of ValueError naming it."""
    image = check_image("image", image)
    reference = check_image("reference", reference)
    if period is not None:
        if not isinstance(period, (tuple, list)) or len(period) != 2:
            raise ValueError(f"period must be None or a pair (py, px), got {period!r}")
        period = tuple(None if p is None else check_float("period", p, minimum=2.0) for p in period)
    if period is None or period == (None, None):
        return None
    mine = measure(image, period)
    own = measure(reference, period)
    if mine is None or own is None:
        return None
    return mine, own


def cell_splits(image, reference, *, period) -> CellSplits | None:
    """Bricks or floor tiles that change colour partway across: the image's cells against the reference's.

    A structure's cells are found on each image itself: its colours along
    their principal axis (lightly smoothed) split in two by Otsu's
    threshold, the thinner class the grout or mortar, the other the cells'
    interiors, whose connected components (not touching the border) are the
    cells. Per cell, the mean colours of its halves, left / right and top /
    bottom of its centre, and the larger of the two differences; the image's
    split is the mean of its 25 % largest, relative to the spread of the
    cells' mean colours. A floor drawn from patches whose boundaries cross
    the tiles (half a tile from one patch, half from another) has many cells
    split as much as two cells differ; the photo's own cells differ between
    their halves only by their texture.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture judged, e.g. a bake at the reference's pixel size.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo (square-on: straightened or rectified as a fit reads it).
    period : (py, px) or None
        The reference's structure period in pixels, either None where it has
        none along that axis (``spectex.fitting.structure_period``). None, or
        (None, None): a photo without a structure, nothing to measure.

    Returns
    -------
    CellSplits or None
        None where there is no structure (``period``), or where either image
        shows no separate cells: its mean line profile folded by the period
        holds less than ``LATTICE_STRENGTH`` of its colour variance along an
        axis with a period, and, with a period along both axes, so does the
        image folded by both at once (its mean period cell: grout of any
        shape, hexagons too) (no lattice of grout), its two colour classes
        explain less than ``CELL_SEPARATION`` of it, or it has fewer than
        ``MIN_CELLS`` whole cells.
    """
    found = _cells_of_both(image, reference, period, _cell_split)
    if found is None:
        return None
    mine, own = found
    return CellSplits(image=mine[0], reference=own[0], ratio=mine[0] / max(own[0], 1e-9), cells_image=mine[1],
                      cells_reference=own[1])


#: A cell (brick, floor tile) is short when its area is under this share of the reference's median cell's
#: (:func:`short_cells`): a brick cut to 60% of its length where patches meet.
SHORT_CELL = 0.6
#: Components under this share of the reference's median cell's area are specks of the cells' colour in the
#: grout, not cells (:func:`short_cells`).
SHORT_CELL_FLOOR = 0.1


@dataclass(frozen=True, eq=False)
class ShortCells(AsDict):
    """Cells (bricks, floor tiles) cut short, against a reference's (:func:`short_cells`).

    Attributes
    ----------
    image, reference : float
        Each one's share of its whole cells whose area is under
        ``SHORT_CELL`` of the reference's median cell's (the median by
        area: half the reference's cell area lies in larger cells).
    excess : float
        ``image - reference``: about 0 is as many short cells as the
        reference has (a wall's own half bricks); clearly above, cells cut
        where patches meet.
    cells_image, cells_reference : int
        The whole cells counted in each.
    """

    image: float
    reference: float
    excess: float
    cells_image: int
    cells_reference: int


def short_cells(image, reference, *, period) -> ShortCells | None:
    """Bricks or floor tiles cut short: the share of the image's cells much smaller than the reference's.

    The cells are found on each image as :func:`cell_splits` finds them
    (the thinner of two colour classes is the grout; the other's connected
    components not touching the border are the cells). A cell is short
    when its area is under ``SHORT_CELL`` of the reference's median cell's
    (weighted by area, so that specks do not move it);
    components under ``SHORT_CELL_FLOOR`` of it are specks, not cells. A
    wall drawn from patches that change at the wrong place shows bricks a
    third or half as long as the photo's, which the colour measures and
    :func:`cell_splits` (cells of one colour, whatever their length) do not
    see.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture judged, e.g. a bake at the reference's pixel size.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo (square-on, as a fit reads it).
    period : (py, px) or None
        The reference's structure period in pixels (either None where it has
        none along that axis).

    Returns
    -------
    ShortCells or None
        None where there is no structure (``period``), either image shows
        no separate cells (:func:`cell_splits`) or the reference no cell
        its frame does not cut.
    """
    found = _cells_of_both(image, reference, period, _cell_components)
    if found is None:
        return None
    mine, own = found

    def areas(found):
        _, labels, count, ok = found
        ok = ok.copy()
        # cells the frame cuts (the erosion leaves them a pixel short of the border) are not short
        frame = np.concatenate([labels[:2].ravel(), labels[-2:].ravel(), labels[:, :2].ravel(),
                                labels[:, -2:].ravel()])
        ok[np.unique(frame)] = False
        return np.bincount(labels.ravel(), minlength=count + 1)[ok].astype(np.float64)

    ref_areas = np.sort(areas(own))
    if ref_areas.size == 0:  # every cell of the reference cut by its frame
        return None
    # the area-weighted median: the cell size half of the reference's cell area lies in (specks, many and
    # small, move a plain median far down)
    weight = np.cumsum(ref_areas)
    median = float(ref_areas[np.searchsorted(weight, 0.5 * weight[-1])])
    shares = []
    for a in (areas(mine), ref_areas):
        cells = a[a >= SHORT_CELL_FLOOR * median]
        shares.append((float(np.mean(cells < SHORT_CELL * median)) if cells.size else 0.0, int(cells.size)))
    (mine_share, n_mine), (own_share, n_own) = shares
    return ShortCells(image=mine_share, reference=own_share, excess=mine_share - own_share, cells_image=n_mine,
                      cells_reference=n_own)


# --------------------------------------------------------------------------
# Everything at once
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Comparison(AsDict):
    """The measures of an image against a reference (:func:`compare`).

    Attributes
    ----------
    histogram_w1 : tuple of float
        :func:`histogram_w1`, one per channel.
    bands : ndarray, shape (K, 2), or None
        Octave bands, cycles per pixel, finest first (``None``: an image too
        small for two bands).
    band_power_image_db, band_power_reference_db : ndarray, shape (K,), or None
        :func:`band_power` of both at the common size (as in
        :func:`band_power_distance`).
    band_power_distance_db : float or None
        RMS of their difference.
    tileability_image, tileability_reference : float or None
        :func:`tileability` (``None`` under 3 x 3 pixels).
    verbatim_copy : float or None
        :func:`verbatim_copy` of the reference in the image.
    repeat_peak_image, repeat_peak_reference : float or None
        :func:`repeat_peak` of each: how strongly fine detail repeats, at any
        period and angle (<= 0.1 does not repeat); ``min_lag`` is 24 pixels,
        or half the shorter side of a smaller image (``None`` under 2 pixels).
    exact_repetition : float or None
        :func:`repetition` of the image at the reference's period (exact
        8-bit copies one period away, axis-aligned; blind to a repeat that
        filtering or blending changed).
    seam_energy : float or None
        :func:`seam_energy` for the ``block`` layout, if one was given.
    structure : StructuralDistance or None
        :func:`structural_distance` of the image to the reference: ``ratio``
        about 1 is as close as the photo is to itself (``None`` for a
        reference without two 32 x 32 windows, or a flat one).
    clipping : Clipping
        :func:`clipping`: the image's clipped values against the reference's
        own plus 1 point.
    coarse : CoarseCopies or None
        With ``zoom``: :func:`coarse_copies`, the image taken as a view at
        ``zoom`` times the reference's pixel size.
    cells : CellSplits or None
        With the reference's structure ``period``: :func:`cell_splits`, its
        bricks or floor tiles changing colour partway across (None without a
        period or where either image shows no separate cells).
    short : ShortCells or None
        With the reference's structure ``period``: :func:`short_cells`, its
        bricks or floor tiles cut short against the reference's own (None
        without a period or where either image shows no separate cells).
    lines : LineContinuity or None
        With a ``period`` along one axis only (boards side by side, columns
        or courses of bricks): :func:`line_continuity` of the lines along the
        other (None otherwise).
    one_off : OneOffRepeats or None
        :func:`one_off_repeats`: content the reference shows once, and how
        often the image shows it (at ``zoom``, else at the reference's pixel
        size; None where the image is too small to be searched for it).
    lighting : LightingBlotches or None
        :func:`lighting_blotches`: blotches at the reference's scale in the
        image (at ``zoom``, else at the reference's pixel size) beyond the
        reference's own, its lighting divided out (None where either is too
        small).
    scale : ScaleBlotches or None
        :func:`scale_blotches`: patches of large and small grain in the
        image beyond the reference's own variation of scale, its tilt taken
        out (None where either is too small).

    ``as_dict()`` gives plain Python values (lists for arrays), for JSON.
    """

    histogram_w1: tuple
    bands: np.ndarray | None
    band_power_image_db: np.ndarray | None
    band_power_reference_db: np.ndarray | None
    band_power_distance_db: float | None
    tileability_image: float | None
    tileability_reference: float | None
    verbatim_copy: float | None
    repeat_peak_image: float | None
    repeat_peak_reference: float | None
    exact_repetition: float | None
    seam_energy: float | None = None
    structure: StructuralDistance | None = None
    clipping: Clipping | None = None
    coarse: CoarseCopies | None = None
    cells: CellSplits | None = None
    one_off: OneOffRepeats | None = None
    lighting: LightingBlotches | None = None
    scale: ScaleBlotches | None = None
    lines: LineContinuity | None = None
    short: ShortCells | None = None


def _scale_or_none(image, reference, zoom):
    """:func:`scale_blotches`, None where the reference is under 128 pixels, the zoom beyond its blocks or
    the image under two of them."""
    try:
        return scale_blotches(image, reference, zoom=1.0 if zoom is None else zoom)
    except ValueError:
        return None


def _lighting_or_none(image, reference, zoom):
    """:func:`lighting_blotches`, None where the reference is under 32 pixels, the zoom beyond its scale or
    the image under it."""
    try:
        return lighting_blotches(image, reference, zoom=1.0 if zoom is None else zoom)
    except ValueError:
        return None


def _one_off_or_none(image, reference, zoom):
    """:func:`one_off_repeats`, None where the reference is under 32 pixels or the image too small to search."""
    try:
        return one_off_repeats(image, reference, zoom=1.0 if zoom is None else zoom)
    except ValueError:  # a reference under 32 pixels, or one-off content larger than the image
        return None


def _repeat_peak_or_none(image):
    side = min(image.shape[:2])
    if side < 2:
        return None
    return repeat_peak(image, min_lag=min(24, side // 2))


def _structure_or_none(image, reference):
    """:func:`structural_distance`, or None where the reference cannot give a floor (too small, flat)
    or the image is smaller than a window."""
    from ._texture_stats import MIN_WINDOW

    if min(reference.shape[:2]) < MIN_WINDOW or max(reference.shape[:2]) < 2 * MIN_WINDOW:
        return None
    if float(np.std(_luma(reference))) <= 1e-6:
        return None
    try:
        return structural_distance(image, reference)
    except ValueError:  # the image under one window, or a reference without two
        return None


def compare(image, *, reference, block: int | None = None, overlap: int = 0,
            zoom: float | None = None, period=None) -> Comparison:
    """All the measures of ``image`` against a ``reference`` (an exemplar).

    Call it as ``compare(image, reference=exemplar)``: the image judged
    first, the reference named (the convention of ``docs/conventions.md``,
    with a name so that the two cannot be swapped by mistake).

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The texture to judge.
    reference : ndarray, shape (h, w) or (h, w, C)
        The exemplar (or any reference image); the same number of channels.
    block, overlap : int, optional
        With ``block``, also the seam energy for that block layout.
    zoom : float, optional
        The image is a zoomed-out view of a texture, rendered at ``zoom``
        times the reference's pixel size: also search it for magnified
        copies of the reference (:func:`coarse_copies`).
    period : (py, px), optional
        The reference's structure period in pixels
        (``spectex.fitting.structure_period``): also measure its cells
        changing colour partway across (:func:`cell_splits`) and, where one
        entry is None (a structure along one axis), whether its lines keep
        their places (:func:`line_continuity`).

    Returns
    -------
    Comparison
        Measures an image is too small for are ``None``.
    """
    image = check_image("image", image)
    reference = check_image("reference", reference)
    if zoom is not None:
        zoom = check_float("zoom", zoom, minimum=1.0)
    w1 = tuple(float(v) for v in histogram_w1(image, reference))
    try:
        bands, pr, pi = _common_bands(reference, image, 4)
        distance = float(np.sqrt(np.mean((pr - pi) ** 2)))
    except ValueError:
        bands = pr = pi = distance = None
    tile_i, tile_r = ((tileability(img) if min(img.shape[:2]) >= 3 else None) for img in (image, reference))
    if min(image.shape[:2]) >= 5 and min(reference.shape[:2]) >= 5:
        copy = verbatim_copy(image, reference)
        exact = repetition(image, reference.shape[:2])
    else:
        copy = exact = None
    return Comparison(
        histogram_w1=w1, bands=bands, band_power_image_db=pi, band_power_reference_db=pr,
        band_power_distance_db=distance, tileability_image=tile_i, tileability_reference=tile_r,
        verbatim_copy=copy, repeat_peak_image=_repeat_peak_or_none(image),
        repeat_peak_reference=_repeat_peak_or_none(reference), exact_repetition=exact,
        seam_energy=seam_energy(image, block, overlap) if block is not None else None,
        structure=_structure_or_none(image, reference), clipping=clipping(image, reference),
        coarse=coarse_copies(image, reference, zoom=zoom) if zoom is not None else None,
        cells=cell_splits(image, reference, period=period) if period is not None else None,
        short=short_cells(image, reference, period=period) if period is not None else None,
        one_off=_one_off_or_none(image, reference, zoom), lighting=_lighting_or_none(image, reference, zoom),
        scale=_scale_or_none(image, reference, zoom), lines=lines_or_none(image, reference, period))


def lines_axis(period):
    """The ``axis`` of :func:`line_continuity` for a structure of ``period = (py, px)`` (pixels, None where an
    axis has none): 0 where it runs across x only (boards side by side, columns of bricks: the lines run
    down the columns), 1 where across y only (courses), None for a lattice or no period."""
    if period is None or (period[0] is None) == (period[1] is None):
        return None
    return 0 if period[1] is not None else 1


def lines_or_none(image, reference, period):
    """:func:`line_continuity` of ``image`` against ``reference`` for a structure of ``period`` along one axis
    only (:func:`lines_axis`), else None (or where either image is under 16 pixels along the lines)."""
    axis = lines_axis(period)
    if axis is None or min(image.shape[axis], reference.shape[axis]) < 16:
        return None
    return line_continuity(image, reference, axis=axis)
