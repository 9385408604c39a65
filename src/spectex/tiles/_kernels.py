"""The tiles' numba pixel kernels, compiled on first use and cached on disk.

Imported only where an image is large enough to need them (``from_noise.NUMPY_MAX``,
``ops._NUMPY_MAX`` values and up); below that the same steps run in NumPy
(``from_noise._ramp_numpy``, ``_interleave_numpy``, ``ops._gradient_numpy``), so
making or checking a small tile, and every refusal, imports no numba.
"""

from __future__ import annotations

import math

import numba

from ..color import LUMA_REC709

__all__ = ["ramp", "interleave", "gradient"]

# Rec. 709 luma weights as numba sees them (module globals are constants to it).
_LUMA_R, _LUMA_G, _LUMA_B = LUMA_REC709


@numba.njit(cache=True, parallel=True)
def ramp(field, pos, col, out):  # pragma: no cover - compiled
    """out[c, i, j] = ramp_c(Phi(field[i, j])), ramp piecewise linear (np.interp)."""
    h, w = field.shape
    k = pos.shape[0]
    for i in numba.prange(h):
        for j in range(w):
            t = 0.5 * math.erfc(-field[i, j] * 0.7071067811865476)
            if t <= pos[0]:
                for c in range(3):
                    out[c, i, j] = col[0, c]
            elif t >= pos[k - 1]:
                for c in range(3):
                    out[c, i, j] = col[k - 1, c]
            else:
                s = 1
                while pos[s] < t:
                    s += 1
                # pos[s-1] < t <= pos[s], as np.interp
                d = pos[s] - pos[s - 1]
                u = (t - pos[s - 1]) / d if d > 0 else 1.0
                for c in range(3):
                    out[c, i, j] = col[s - 1, c] + u * (col[s, c] - col[s - 1, c])


@numba.njit(cache=True, parallel=True)
def interleave(planes, lo, scale, out, lum):  # pragma: no cover - compiled
    """out[i, j, c] = (planes[c, i, j] - lo[c]) scale[c], clipped; lum = Rec. 709 luma."""
    nc, h, w = planes.shape
    for i in numba.prange(h):
        for j in range(w):
            for c in range(nc):
                v = (planes[c, i, j] - lo[c]) * scale[c]
                out[i, j, c] = min(max(v, 0.0), 1.0)
            lum[i, j] = _LUMA_R * out[i, j, 0] + _LUMA_G * out[i, j, 1] + _LUMA_B * out[i, j, 2]


@numba.njit(cache=True, parallel=True)
def gradient(h, cx, cy, g):  # pragma: no cover - compiled
    """g = cx (h[i, j+1] - h[i, j-1]) + cy (h[i-1, j] - h[i+1, j]), wrapping."""
    n0, n1 = h.shape
    for i in numba.prange(n0):
        up = i - 1 if i > 0 else n0 - 1
        dn = i + 1 if i < n0 - 1 else 0
        for j in range(n1):
            lf = j - 1 if j > 0 else n1 - 1
            rt = j + 1 if j < n1 - 1 else 0
            g[i, j] = cx * (h[i, rt] - h[i, lf]) + cy * (h[up, j] - h[dn, j])
