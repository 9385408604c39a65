"""Spectral synthesis: octaves by filtering under magnification, 1/f noise.

Octaves (Blythe et al. 1999, 6.21.3)
    :func:`magnify`, :func:`octave`, :func:`discrete_filter`,
    :func:`filter_passes`, ``FILTERS``; the seed's multi-pass GPU route
    :func:`magnify_gl` (returns a :class:`GLMagnification`).
Spectral synthesis (6.21.4)
    :func:`octave_sum`, :func:`octave_amplitudes`, :func:`spectral_noise`,
    :func:`band_limit`.
Analysis
    :func:`radial_power_spectrum`, :func:`spectral_slope` (returns a
    :class:`SlopeFit`), :func:`periodic_smooth_decomposition`,
    :func:`hann_window`.

Frequencies are in cycles per pixel (Nyquist is 0.5). See ``docs/tiles.md``.
"""

from ._magnify_gl import GLMagnification, magnify_gl
from ._octaves import FILTERS, discrete_filter, filter_passes, magnify, octave
from ._synthesis import (
    PeriodicSmooth,
    RadialSpectrum,
    SlopeFit,
    band_limit,
    hann_window,
    octave_amplitudes,
    octave_sum,
    periodic_smooth_decomposition,
    radial_power_spectrum,
    spectral_noise,
    spectral_slope,
)

__all__ = [
    "FILTERS",
    "GLMagnification",
    "PeriodicSmooth",
    "RadialSpectrum",
    "SlopeFit",
    "band_limit",
    "discrete_filter",
    "filter_passes",
    "hann_window",
    "magnify",
    "magnify_gl",
    "octave",
    "octave_amplitudes",
    "octave_sum",
    "periodic_smooth_decomposition",
    "radial_power_spectrum",
    "spectral_noise",
    "spectral_slope",
]
