"""Tiling and blending, the peer of ``spectex.fit`` in ``bench_fit_quality.py`` (issue 22).

Heitz and Neyret, "High-performance by-example noise using a histogram-preserving blending
operator", Proc. ACM CGIT 1(2), 2018: the output plane is cut into a triangle grid; each
vertex shows the photo at its own random offset, and a pixel is the blend of its triangle's
three vertices' photos with barycentric weights. ``linear`` blends the values (ghosting, lost
contrast); ``histogram`` blends the photo's values made Gaussian (per channel, by their
ranks), keeps the variance (divides by the weights' norm) and maps back through the photo's
quantiles, so the output has the photo's histogram. Patches are placed so that they stay
inside the photo (mirrored at its border where a far corner of a triangle reaches out).
"""

from __future__ import annotations

import numpy as np


def _hash(iy, ix, salt):
    h = (iy.astype(np.int64) * 73856093) ^ (ix.astype(np.int64) * 19349663) ^ (salt * 83492791)
    h = (h ^ (h >> 13)) * 1274126177
    return ((h ^ (h >> 16)) & 0xFFFFFF).astype(np.float64) / float(0x1000000)


def _gaussianise(photo):
    """Per channel: the values' normal scores and the sorted values (for the way back)."""
    from scipy.special import ndtri

    flat = photo.reshape(-1, photo.shape[2])
    ranks = np.argsort(np.argsort(flat, axis=0, kind="stable"), axis=0)
    g = ndtri((ranks + 0.5) / flat.shape[0]).reshape(photo.shape)
    return g.astype(np.float32), np.sort(flat, axis=0)


def tile_and_blend(photo, shape, *, blend: str = "histogram", rng: int = 0, cell: float | None = None):
    """A texture of ``shape = (H, W)`` from ``photo`` by tiling and blending (see the module)."""
    from scipy.special import ndtr

    grey = photo.ndim == 2
    img = (photo[:, :, None] if grey else photo).astype(np.float32)
    h, w = img.shape[:2]
    cell = min(h, w) / 3.464 if cell is None else cell  # Heitz and Neyret's grid: 2 sqrt(3) cells a photo
    src, table = (_gaussianise(img) if blend == "histogram" else (img, None))
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]].astype(np.float64)
    u, v = xx / cell, yy / cell
    su, sv = u - 0.57735027 * v, 1.15470054 * v  # the skewed (triangle) grid
    bu, bv = np.floor(su), np.floor(sv)
    fu, fv = su - bu, sv - bv
    fz = 1.0 - fu - fv
    lower = fz > 0
    verts = [(np.where(lower, bu, bu + 1), np.where(lower, bv, bv + 1)),
             (np.where(lower, bu, bu + 1), np.where(lower, bv + 1, bv)),
             (np.where(lower, bu + 1, bu), np.where(lower, bv, bv + 1))]
    weights = [np.where(lower, fz, -fz), np.where(lower, fv, 1.0 - fv), np.where(lower, fu, 1.0 - fu)]
    out = np.zeros(tuple(shape) + (img.shape[2],), np.float32)
    norm = np.zeros(tuple(shape), np.float32)
    for (vu, vv), wt in zip(verts, weights):
        # the vertex's position in the output and a random centre well inside the photo
        px, py = (vu + 0.5 * vv) * cell, vv * cell / 1.15470054 * 1.0
        cx = w * (0.25 + 0.5 * _hash(vv, vu, 2 * rng + 1))
        cy = h * (0.25 + 0.5 * _hash(vv, vu, 2 * rng + 2))
        sx = np.rint(xx - px + cx).astype(np.int64)
        sy = np.rint(yy - py + cy).astype(np.int64)
        sx = np.abs(sx) % (2 * w)
        sy = np.abs(sy) % (2 * h)
        sx = np.where(sx >= w, 2 * w - 1 - sx, sx)  # mirrored at the border
        sy = np.where(sy >= h, 2 * h - 1 - sy, sy)
        wt = wt.astype(np.float32)
        out += wt[:, :, None] * src[sy, sx]
        norm += wt * wt
    if blend == "histogram":
        out /= np.sqrt(np.maximum(norm, 1e-12))[:, :, None]  # variance kept
        q = ndtr(out.reshape(-1, out.shape[2]))
        n = table.shape[0]
        idx = np.clip((q * n).astype(np.int64), 0, n - 1)
        out = np.take_along_axis(table, idx, axis=0).reshape(out.shape)
    elif blend != "linear":
        raise ValueError(f"blend must be 'histogram' or 'linear', got {blend!r}")
    return out[:, :, 0] if grey else out
