"""How much of an image a structure's lattice holds: the variance its folding by the lattice's periods keeps.

The private home shared by :func:`spectex.metrics.cell_splits` (whether a
render shows cells at all) and the fit (``spectex.fitting._auto``: whether a
turned structure's lattice holds better along its own lines than along the
photo's axes).
"""

from __future__ import annotations

import numpy as np

__all__ = ["lattice_strength", "lattice_strength_2d"]


def lattice_strength(level, period) -> float:
    """The smallest, over the axes with a period, of the variance of ``level``'s mean line profile folded by
    the period (``round(p)`` phases) as a fraction of ``level``'s variance."""
    out = []
    for ax, p in enumerate(period):
        if p is None:
            continue
        profile = level.mean(axis=1 - ax)
        bins = max(2, int(round(p)))
        phase = np.floor((np.arange(profile.size) % p) * bins / p).astype(np.int64) % bins
        folded = np.bincount(phase, weights=profile, minlength=bins) / np.maximum(np.bincount(phase, minlength=bins), 1)
        out.append(float(folded.var()) / max(float(level.var()), 1e-12))
    return min(out)


def lattice_strength_2d(level, period) -> float:
    """The variance of ``level`` folded by both periods at once (its mean over the period cell, ``round(py)``
    by ``round(px)`` phases) as a fraction of ``level``'s variance: a lattice of grout of any shape, where
    :func:`lattice_strength`'s line profiles see only straight grout (a hexagon floor: 0.07 by lines, 0.77
    folded; the grid floor 0.96; the same rows and columns shuffled 0.06-0.18)."""
    py, px = period
    by, bx = max(2, int(round(py))), max(2, int(round(px)))
    fy = np.floor((np.arange(level.shape[0]) % py) * by / py).astype(np.int64) % by
    fx = np.floor((np.arange(level.shape[1]) % px) * bx / px).astype(np.int64) % bx
    phase = (fy[:, None] * bx + fx[None, :]).ravel()
    counts = np.bincount(phase, minlength=by * bx)
    means = np.bincount(phase, weights=level.ravel(), minlength=by * bx) / np.maximum(counts, 1)
    between = float(np.sum(counts * (means - level.mean()) ** 2)) / counts.sum()
    return between / max(float(level.var()), 1e-12)
