"""Otsu's threshold: the one split of a sample in two classes that both the cell maps
(:mod:`spectex.shading._cells`) and the cell measure (:func:`spectex.metrics.cell_splits`) use.

Imports nothing but NumPy, so that any layer of the package may use it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["otsu"]


def otsu(values: np.ndarray, bins: int = 256) -> tuple[float, float]:
    """Otsu's threshold of a 1-D sample and the fraction of its variance the split explains.

    The sample's histogram (``bins`` equal bins over its range) is cut at
    the bin edge that maximises the between-class variance ``w0 w1 (m0 -
    m1)^2`` (Otsu 1979); values above the threshold are the upper class.

    Returns
    -------
    threshold : float
        The bin edge of the best cut.
    explained : float
        The between-class variance of that cut over the sample's variance
        (0 for a constant sample, up to 1 for two spikes).
    """
    values = np.asarray(values, dtype=np.float64).ravel()
    hist, edges = np.histogram(values, bins=bins)
    centres = 0.5 * (edges[:-1] + edges[1:])
    w0 = np.cumsum(hist).astype(np.float64)
    w1 = w0[-1] - w0
    s0 = np.cumsum(hist * centres)
    m0 = s0 / np.maximum(w0, 1.0)
    m1 = (s0[-1] - s0) / np.maximum(w1, 1.0)
    between = w0 * w1 * (m0 - m1) ** 2
    k = int(np.argmax(between[:-1]))
    return float(edges[k + 1]), float(between[k] / w0[-1] ** 2 / max(values.var(), 1e-12))
