"""Multi-scale statistics of a texture exemplar (the analysis half of fitting).

Three families, each a plain function of an image:

* :func:`octave_power`: power per octave band of the luma, windowed so that a
  non-periodic photograph does not leak its edges (the estimator of
  :func:`spectex.spectrum.band_power`), with the least-squares slope in dB
  per octave that the fit uses to continue the spectrum to coarser scales;
* :func:`colour_stats`: mean colour, covariance, principal colours (the
  mean moved one standard deviation each way along the principal axes of
  the covariance) and per-channel histograms;
* :func:`cross_scale`: how the local amplitude of a fine band depends on the
  *value* (phase) and on the local *amplitude* of the band two octaves
  coarser, the dependence that the alpha channel of a spectral texture
  models (Berger [1]_), measured like the cross-scale magnitude
  correlations of Portilla and Simoncelli [2]_.

:func:`analyse` gathers them in an :class:`ExemplarStats`.

References
----------
.. [1] D. R. Berger, "Spectral texturing for real-time applications",
   SIGGRAPH 2003 Sketches and Applications.
.. [2] J. Portilla and E. P. Simoncelli, "A parametric texture model based
   on joint statistics of complex wavelet coefficients", IJCV 40(1), 2000.
.. [3] P. J. Burt and E. H. Adelson, "The Laplacian pyramid as a compact
   image code", IEEE Trans. Comm. 31(4), 1983 (differences of Gaussians).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._results import AsDict
from .._validate import check_image, check_int
from ..color import luma

__all__ = ["ExemplarStats", "analyse", "octave_power", "colour_stats", "cross_scale", "dog_bands",
           "OctavePower", "ColourStats", "CrossScale"]

def _luma64(image: np.ndarray) -> np.ndarray:
    return luma(image, dtype=np.float64)


# --------------------------------------------------------------------------
# Power per octave
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class OctavePower(AsDict):
    """The result of :func:`octave_power`."""

    bands: np.ndarray      #: (K, 2) band edges, cycles per pixel, finest first
    power_db: np.ndarray   #: (K,) power per band, dB
    slope_db: float        #: dB per octave, towards coarser bands
    intercept_db: float    #: the line's value at band 0, dB


def octave_power(image, *, min_cycles: int = 4, segment=None) -> OctavePower:
    """Power per octave band of the luma and its slope in dB per octave.

    The bands and the estimator are those of :func:`spectex.spectrum.band_power`
    (mean removed, separable Hann window, power normalised so that the bands
    sum to the variance; optional Welch segments). The slope is the
    least-squares line through the band powers in dB against the band index
    (one octave coarser per step): about 0 dB per octave for a ``1/f^2``
    spectrum, positive where the coarse bands hold more power.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least ``8 * min_cycles`` pixels on the shorter side.
    min_cycles, segment
        As in :func:`spectex.spectrum.band_power`.

    Returns
    -------
    OctavePower
        ``bands`` (K, 2) edges in cycles per pixel, finest first;
        ``power_db`` (K,); ``slope_db`` (dB per octave, towards coarser
        bands); ``intercept_db`` (the line's value at band 0).
    """
    from ..spectrum import band_power

    bands, power = band_power(image, min_cycles=min_cycles, segment=segment)
    k = np.arange(len(power), dtype=np.float64)
    slope, intercept = np.polyfit(k, power, 1)
    return OctavePower(bands=bands, power_db=power, slope_db=float(slope), intercept_db=float(intercept))


# --------------------------------------------------------------------------
# Colour
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class ColourStats(AsDict):
    """The result of :func:`colour_stats`."""

    mean: np.ndarray               #: (C,)
    covariance: np.ndarray         #: (C, C)
    principal_axes: np.ndarray     #: (C, C), eigenvectors as columns, largest variance first
    principal_std: np.ndarray      #: (C,)
    principal_colours: np.ndarray  #: (2, C), mean -/+ one standard deviation along the first axis
    histograms: np.ndarray         #: (C, bins), each summing to 1
    bin_edges: np.ndarray          #: (bins + 1,)


def colour_stats(image, *, bins: int = 64) -> ColourStats:
    """Colour distribution: mean, covariance, principal colours, histograms.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        Values in [0, 1]; all channels are counted (pass RGB without alpha).
    bins : int
        Histogram bins over [0, 1].

    Returns
    -------
    ColourStats
        ``mean`` (C,); ``covariance`` (C, C); ``principal_axes`` (C, C), the
        eigenvectors of the covariance as columns, largest variance first;
        ``principal_std`` (C,), the standard deviation along each;
        ``principal_colours`` (2, C), the mean minus and plus one standard
        deviation along the first axis (clipped to [0, 1]): the two colours
        the texture varies between; ``histograms`` (C, bins), densities
        that sum to 1 per channel; ``bin_edges`` (bins + 1,).
    """
    image = check_image("image", image)
    bins = check_int("bins", bins, minimum=2, maximum=4096)
    x = (image[:, :, None] if image.ndim == 2 else image).reshape(-1, 1 if image.ndim == 2 else image.shape[2])
    x = x.astype(np.float64)
    mean = x.mean(axis=0)
    cov = np.atleast_2d(np.cov(x, rowvar=False, bias=True))
    evals, evecs = np.linalg.eigh(cov)
    order = np.argsort(evals)[::-1]
    evals = np.maximum(evals[order], 0.0)
    evecs = evecs[:, order]
    # a sign convention: the first axis points towards brighter colours
    for i in range(evecs.shape[1]):
        if evecs[:, i].sum() < 0:
            evecs[:, i] = -evecs[:, i]
    std = np.sqrt(evals)
    principal = np.clip(np.stack([mean - std[0] * evecs[:, 0], mean + std[0] * evecs[:, 0]]), 0.0, 1.0)
    edges = np.linspace(0.0, 1.0, bins + 1)
    hist = np.stack([np.histogram(np.clip(x[:, c], 0, 1), bins=edges)[0] / x.shape[0] for c in range(x.shape[1])])
    return ColourStats(mean=mean, covariance=cov, principal_axes=evecs, principal_std=std,
                       principal_colours=principal, histograms=hist, bin_edges=edges)


# --------------------------------------------------------------------------
# Cross-scale dependence
# --------------------------------------------------------------------------

def _sigma(j: int) -> float:
    """Gaussian scale below band ``j``: 0 for band 0, then 1, 2, 4, ... pixels."""
    return 0.0 if j == 0 else float(2 ** (j - 1))


def dog_bands(image, levels: int) -> list[np.ndarray]:
    """Differences of Gaussians of the luma: ``levels`` octave bands at full size.

    Band ``j`` is ``G_{s_j} L - G_{s_{j+1}} L`` with ``s_0 = 0`` (the image
    itself) and ``s_j = 2^(j-1)`` pixels, so band 0 holds the pixel-scale
    detail (about 0.2 to 0.5 cycles per pixel) and each next band one octave
    coarser (a Laplacian pyramid without the subsampling, Burt and Adelson
    [3]_). Edges are reflected.

    Returns
    -------
    list of ndarray, each (H, W) float64, finest first
    """
    from scipy import ndimage

    image = check_image("image", image)
    levels = check_int("levels", levels, minimum=1, maximum=12)
    lum = _luma64(image)
    smooth = [lum] + [ndimage.gaussian_filter(lum, _sigma(j), mode="reflect") for j in range(1, levels + 1)]
    return [smooth[j] - smooth[j + 1] for j in range(levels)]


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    a = a - a.mean()
    b = b - b.mean()
    den = float(np.sqrt(np.sum(a * a) * np.sum(b * b)))
    return float(np.sum(a * b) / den) if den > 0 else 0.0


@dataclass(frozen=True, eq=False)
class CrossScale(AsDict):
    """The result of :func:`cross_scale`."""

    value: float                  #: mean over the fine bands of corr(fine amplitude, coarse value)
    amplitude: float              #: mean over the fine bands of corr(fine amplitude, coarse amplitude)
    value_bands: np.ndarray       #: per fine band
    amplitude_bands: np.ndarray   #: per fine band
    fine: tuple                   #: the fine band indices
    step: int                     #: octaves between fine and coarse


def cross_scale(image, *, fine=None, step: int = 2) -> CrossScale:
    """Cross-scale dependence: fine-band amplitude against the coarser band.

    The luma is split into octave bands by differences of Gaussians
    (:func:`dog_bands`). For each fine band ``j`` in ``fine`` and the
    coarser band ``c = j + step``, the local amplitude of the fine band is
    ``A_j = sqrt(G_{s_c} * b_j^2)`` (its energy averaged over the coarse
    band's scale), and

    * ``value[j] = corr(A_j, b_c)``: does the fine detail grow where the
      coarse band is bright (positive) or dark (negative)? This is the
      dependence of the fine bands' amplitude on the coarse bands' phase
      that an alpha channel derived from the colour creates (Berger) and
      that detail texturing lacks;
    * ``amplitude[j] = corr(A_j, A_c)`` with ``A_c = sqrt(G_{s_{c+1}} *
      b_c^2)``: does the fine detail grow where the coarse band is strong?
      (Portilla and Simoncelli's cross-scale magnitude correlation.)

    Pixels within ``2 s_{c+1}`` of the border are left out. Both measures
    are correlation coefficients in [-1, 1]; their means over ``fine`` are
    the summary values.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least ``8 s_{c+1}`` pixels on the shorter side for the coarsest
        pair (32 for the default).
    fine : sequence of int, optional
        Fine band indices. Default ``(0, 1)``, or ``(0,)`` for an image
        under 64 pixels on a side (the coarse pair needs 64).
    step : int
        Octaves between the fine and the coarse band (>= 1).

    Returns
    -------
    CrossScale
        ``value`` and ``amplitude`` (floats, the means), ``value_bands`` and
        ``amplitude_bands`` (per fine band), ``fine`` and ``step``.

    References
    ----------
    Portilla and Simoncelli, IJCV 2000 (cross-scale statistics); Berger 2003.
    """
    from scipy import ndimage

    image = check_image("image", image)
    step = check_int("step", step, minimum=1, maximum=8)
    if fine is None:
        fine = (0, 1) if min(image.shape[:2]) >= 8 * _sigma(step + 2) else (0,)
    fine = tuple(check_int(f"fine[{i}]", j, minimum=0, maximum=8) for i, j in enumerate(fine))
    if not fine:
        raise ValueError("fine must name at least one band, got none")
    top = max(fine) + step
    border = int(np.ceil(2 * _sigma(top + 1)))
    if min(image.shape[:2]) < 4 * border:
        raise ValueError(f"image must be at least {4 * border}x{4 * border} pixels for the cross-scale "
                         f"measure with fine={fine} and step={step}, got {image.shape[1]}x{image.shape[0]}")
    bands = dog_bands(image, top + 1)
    crop = (slice(border, -border), slice(border, -border))
    value, amplitude = [], []
    for j in fine:
        c = j + step
        amp_f = np.sqrt(ndimage.gaussian_filter(bands[j] ** 2, _sigma(c), mode="reflect"))
        amp_c = np.sqrt(ndimage.gaussian_filter(bands[c] ** 2, _sigma(c + 1), mode="reflect"))
        value.append(_corr(amp_f[crop], bands[c][crop]))
        amplitude.append(_corr(amp_f[crop], amp_c[crop]))
    return CrossScale(value=float(np.mean(value)), amplitude=float(np.mean(amplitude)),
                      value_bands=np.array(value), amplitude_bands=np.array(amplitude), fine=fine, step=step)


# --------------------------------------------------------------------------
# Everything
# --------------------------------------------------------------------------

@dataclass
class ExemplarStats:
    """The statistics :func:`spectex.fit` matches (see :func:`analyse`)."""

    shape: tuple
    power: OctavePower = field(repr=False)
    colour: ColourStats = field(repr=False)
    cross: CrossScale = field(repr=False)

    def summary(self) -> dict:
        """Plain numbers (JSON-friendly) for reports."""
        return {
            "shape": list(self.shape),
            "power_db": [round(float(p), 3) for p in self.power.power_db],
            "slope_db_per_octave": round(self.power.slope_db, 3),
            "mean": [round(float(m), 4) for m in self.colour.mean],
            "principal_std": [round(float(s), 4) for s in self.colour.principal_std],
            "cross_scale_value": round(self.cross.value, 3),
            "cross_scale_amplitude": round(self.cross.amplitude, 3),
        }


def analyse(image, *, min_cycles: int = 4, bins: int = 64) -> ExemplarStats:
    """All the statistics of an exemplar: octave power, colour, cross-scale.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        Float in [0, 1] (integers scaled by their dtype's maximum); at least
        32 x 32. Colour statistics use the colour channels (an alpha channel
        is ignored).

    Returns
    -------
    ExemplarStats
    """
    image = check_image("image", image, min_size=32)
    colour = image if image.ndim == 2 else image[:, :, :3] if image.shape[2] >= 3 else image[:, :, 0]
    return ExemplarStats(shape=tuple(image.shape), power=octave_power(image, min_cycles=min_cycles),
                         colour=colour_stats(colour, bins=bins), cross=cross_scale(image))


