"""Analysis of texture exemplars and fitting spectral textures to them.

The future work of Berger's sketch (seed 000): "analyze a given image for
its statistical properties, and use these properties to generate texture
tiles and mixing parameters for a similar-looking spectral texture".

Analysis
    :func:`analyse` (an :class:`ExemplarStats`), :func:`octave_power`,
    :func:`colour_stats`, :func:`cross_scale`, :func:`dog_bands`.
Fitting
    :func:`fit` (also ``spectex.fit``): exemplar in, :class:`spectex.SpectralTexture`
    out; :func:`fit_result` the same fit with its numbers (a :class:`FitResult`); :func:`fit_report` for the numbers of a fit; :func:`prepare_exemplar`
    for the input conversions (grey, alpha, 16-bit, crop of huge images).

See ``docs/fitting.md``.
"""

from ._stats import (ColourStats, CrossScale, ExemplarStats, OctavePower, analyse, colour_stats, cross_scale,
                     dog_bands, octave_power)

__all__ = ["ExemplarStats", "OctavePower", "ColourStats", "CrossScale", "analyse", "octave_power", "colour_stats", "cross_scale", "dog_bands",
           "fit", "fit_result", "fit_report", "FitResult", "FitReport", "prepare_exemplar", "structure_peak", "STRUCTURED_PEAK"]


def __getattr__(name):
    # the fitting module pulls in the texture and the sampler (numba): load it on first use
    if name in ("fit", "fit_result", "fit_report", "FitResult", "FitReport", "FitReport", "prepare_exemplar", "structure_peak", "STRUCTURED_PEAK"):
        from . import _fit

        return getattr(_fit, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
