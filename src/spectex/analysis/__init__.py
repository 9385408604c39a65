"""Analysis of texture exemplars: the statistics a fit matches.

The future work of Berger's sketch (seed 000): "analyze a given image for
its statistical properties, and use these properties to generate texture
tiles and mixing parameters for a similar-looking spectral texture".

Analysis
    :func:`analyse` (an :class:`ExemplarStats`), :func:`octave_power`,
    :func:`colour_stats`, :func:`cross_scale`, :func:`dog_bands`.
Fitting
    has its own module, :mod:`spectex.fitting` (:func:`spectex.fit`).

See ``docs/fitting.md``.
"""

from ._stats import (
                     ColourStats,
                     CrossScale,
                     ExemplarStats,
                     OctavePower,
                     analyse,
                     colour_stats,
                     cross_scale,
                     dog_bands,
                     octave_power,
)

__all__ = ["ExemplarStats", "OctavePower", "ColourStats", "CrossScale", "analyse", "octave_power", "colour_stats",
           "cross_scale", "dog_bands"]
