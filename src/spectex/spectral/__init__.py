"""Spectral synthesis: octaves by filtering under magnification, 1/f noise.

Octaves (Blythe et al. 1999, 6.21.3)
    :func:`magnify`, :func:`octave`, :func:`discrete_filter`,
    :func:`filter_passes`, ``FILTERS``; the seed's multi-pass GPU route
    :func:`magnify_gl` (returns a :class:`GLMagnification`).
Spectral synthesis (6.21.4)
    :func:`octave_sum`, :func:`octave_amplitudes`, :func:`spectral_noise`,
    :func:`band_limit`, :func:`band_limit_planes`.

Frequencies are in cycles per pixel (Nyquist is 0.5). See ``docs/tiles.md``.

Power spectra and their slopes are measured in :mod:`spectex.spectrum`,
Moisan's decomposition is :mod:`spectex.periodic`.
"""

from ._filters import FILTERS, discrete_filter, filter_passes
from ._magnify_gl import GLMagnification, magnify_gl
from ._octaves import magnify, octave
from ._synthesis import band_limit, band_limit_planes, octave_amplitudes, octave_sum, spectral_noise

__all__ = [
    "FILTERS",
    "GLMagnification",
    "band_limit",
    "band_limit_planes",
    "discrete_filter",
    "filter_passes",
    "magnify",
    "magnify_gl",
    "octave",
    "octave_amplitudes",
    "octave_sum",
    "spectral_noise",
]
