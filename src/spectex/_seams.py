"""The minimum-error boundary cut's path (Efros and Freeman 2001, section 2.1), a numba kernel.

Shared by image quilting (``synthesis._cut``: a block's overlaps with what is already placed) and
the fit's fill of one-off content (``fitting._one_off``: the ring around the filled region).
Compiled on first use, cached on disk.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["min_cut_path"]


@numba.njit(cache=True, nogil=True)
def min_cut_path(cost):
    """Column index per row of the cheapest top-to-bottom 8-connected path.

    ``cost`` has shape ``(n, m)``; the path moves at most one column between
    consecutive rows (Efros and Freeman 2001, section 2.1). Ties go to the
    smaller column, so the result is deterministic.
    """
    n, m = cost.shape
    acc = np.empty((n, m), dtype=np.float64)
    for j in range(m):
        acc[0, j] = cost[0, j]
    for i in range(1, n):
        for j in range(m):
            best = acc[i - 1, j]
            if j > 0 and acc[i - 1, j - 1] < best:
                best = acc[i - 1, j - 1]
            if j < m - 1 and acc[i - 1, j + 1] < best:
                best = acc[i - 1, j + 1]
            acc[i, j] = cost[i, j] + best
    path = np.empty(n, dtype=np.int64)
    j = 0
    for k in range(1, m):
        if acc[n - 1, k] < acc[n - 1, j]:
            j = k
    path[n - 1] = j
    for i in range(n - 2, -1, -1):
        best_j = j
        if j > 0 and acc[i, j - 1] <= acc[i, best_j]:
            best_j = j - 1
        if j < m - 1 and acc[i, j + 1] < acc[i, best_j]:
            best_j = j + 1
        j = best_j
        path[i] = j
    return path
