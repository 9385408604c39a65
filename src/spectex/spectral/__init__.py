"""Spectral synthesis: octaves by filtering under magnification, 1/f noise.

Octaves (Blythe et al. 1999, 6.21.3)
    :func:`magnify`, :func:`octave`, :func:`discrete_filter`,
    :func:`filter_passes`, ``FILTERS``; the seed's multi-pass GPU route
    :func:`magnify_gl` (returns a :class:`GLMagnification`).
Spectral synthesis (6.21.4)
    :func:`octave_sum`, :func:`octave_amplitudes`, :func:`spectral_noise`,
    :func:`band_limit`, :func:`band_limit_planes`.

Frequencies are in cycles per pixel (Nyquist is 0.5). See ``docs/tiles.md``.

The analysis that used to live here has its own homes: power spectra and
their slopes in :mod:`spectex.spectrum` (``radial_power_spectrum``,
``spectral_slope``, ``SlopeFit``, ``hann_window``), Moisan's decomposition in
:mod:`spectex.periodic` (``periodic_smooth_decomposition``). The old names
here still work for one release, with a ``DeprecationWarning`` naming the
new home.
"""

from ._magnify_gl import GLMagnification, magnify_gl
from ._octaves import FILTERS, discrete_filter, filter_passes, magnify, octave
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

# Names that moved out of spectral: name -> new home.
_MOVED = {
    "radial_power_spectrum": "spectrum",
    "spectral_slope": "spectrum",
    "SlopeFit": "spectrum",
    "hann_window": "spectrum",
    "periodic_smooth_decomposition": "periodic",
}


def __getattr__(name):
    if name in _MOVED:
        import importlib
        import warnings

        home = f"spectex.{_MOVED[name]}"
        warnings.warn(f"spectex.spectral.{name} has moved to {home}.{name} (the old name goes in the next "
                      f"release)", DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module(home), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
