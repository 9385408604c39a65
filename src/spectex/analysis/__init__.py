"""Analysis of texture exemplars: the statistics a fit matches.

The future work of Berger's sketch (seed 000): "analyze a given image for
its statistical properties, and use these properties to generate texture
tiles and mixing parameters for a similar-looking spectral texture".

Analysis
    :func:`analyse` (an :class:`ExemplarStats`), :func:`octave_power`,
    :func:`colour_stats`, :func:`cross_scale`, :func:`dog_bands`.
Fitting
    has its own module, :mod:`spectex.fitting` (:func:`spectex.fit`). The
    names ``spectex.analysis.fit``, ``fit_report``, ``FitResult``,
    ``fit_result``, ``FitReport``, ``prepare_exemplar``, ``structure_peak`` and ``STRUCTURED_PEAK`` still
    work for one release, with a ``DeprecationWarning`` naming their home.

See ``docs/fitting.md``.
"""

from ._stats import (ColourStats, CrossScale, ExemplarStats, OctavePower, analyse, colour_stats, cross_scale,
                     dog_bands, octave_power)

__all__ = ["ExemplarStats", "OctavePower", "ColourStats", "CrossScale", "analyse", "octave_power", "colour_stats", "cross_scale", "dog_bands"]

# Names that moved to spectex.fitting: still found here for one release, with a warning.
_MOVED_TO_FITTING = ("fit", "fit_result", "fit_report", "FitResult", "FitReport", "prepare_exemplar", "structure_peak", "STRUCTURED_PEAK")


def __getattr__(name):
    if name in _MOVED_TO_FITTING:
        import warnings

        from .. import fitting

        warnings.warn(f"spectex.analysis.{name} has moved to spectex.fitting.{name} (the old name goes "
                      f"in the next release)", DeprecationWarning, stacklevel=2)
        return getattr(fitting, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
