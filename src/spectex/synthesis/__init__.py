"""Texture synthesis from an example.

Seed 002's road from simple statistics to neighbourhoods and blocks:

* :func:`sample_histogram`, :func:`match_histogram`: pixels drawn
  independently from the exemplar's colour distribution, and exact
  histogram matching (per channel or joint colour);
* :func:`efros_leung`: non-parametric sampling pixel by pixel (Efros and
  Leung 1999), with a fast k-coherence candidate search by default and the
  exact exhaustive search on request;
* :func:`quilt`: image quilting with minimum-error boundary cuts (Efros and
  Freeman 2001);
* :func:`train_markov`, :func:`generate_text`, :func:`markov_text`: letter
  and word n-gram models of text, the 1-D texture of Shannon (1948).

The quality measures live in :mod:`spectex.metrics`.
"""

from ._efros_leung import efros_leung
from ._histogram import match_histogram, sample_histogram
from ._markov import MAX_TEXT_LENGTH, MarkovModel, generate_text, markov_text, train_markov
from ._quilting import quilt

__all__ = [
    "sample_histogram",
    "match_histogram",
    "efros_leung",
    "quilt",
    "MarkovModel",
    "train_markov",
    "generate_text",
    "markov_text",
    "MAX_TEXT_LENGTH",
]
