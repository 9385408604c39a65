"""Views of the ground plane: perspective renders and orthographic bakes, in numba.

Sections 7 and 8 of ``docs/sampling.md``: the ray of a pixel, where it meets
the ground and the footprint there (:func:`_ground_footprint`), the haze and
the sky (:func:`_haze`, :func:`_sky`), and the kernels that put a picture
together from them and the layer compositing of ``shading._layers``:

* :func:`bake_kernel`: a top-down orthographic view (``spectex.render.bake``);
* :func:`render_kernel`: a perspective view, any sampler state;
* :func:`render_kernel_fast`: the same for the fast path's sampler state
  (section 10), organised per row so that LLVM vectorises it.

Every kernel takes the texture as one :class:`~spectex.shading.tables.ShadingTables`
and the camera as one :class:`~spectex.shading.camera.ViewParams`. Compiled
on first use (``cache=True``), never at import.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ._jit import jit_inline as _jit_inline
from ._layers import shade_ground, shade_row
from .constants import LOD_FLOOR, SKY_FALLOFF

#: The renderers' entry points (``spectex.render.bake``, ``bake``, ``render.cpu``); the per-pixel steps are private.
__all__ = ["bake_kernel", "render_kernel", "render_kernel_fast", "row_order"]

_LOD_FLOOR2 = LOD_FLOOR * LOD_FLOOR


@_jit_inline
def _ray(V, nx, ny):
    """The (unnormalised) ray ``fwd + nx right + ny up``; ``nx = ndc_x tan_x``, ``ny = ndc_y tan_y``."""
    return (V.fwd[0] + nx * V.right[0] + ny * V.up[0], V.fwd[1] + nx * V.right[1] + ny * V.up[1],
            V.fwd[2] + nx * V.right[2] + ny * V.up[2])


@_jit_inline
def _ground_footprint(height, d0, d1, d2, ddx0, ddx1, ddx2, ddy0, ddy1, ddy2, inv_n):
    """Where the ray ``d`` (``d2 < 0``) from altitude ``height`` meets the ground, and its footprint.

    Returns ``(tt, jxx, jyx, jxy, jyy)``: the ground point is ``C + tt d``;
    ``(jxx, jyx)`` and ``(jxy, jyy)`` are its derivatives along the
    picture's x and y for a sample ``1 / inv_n`` pixels wide,
    ``dG/dp = -height (d_z dd_xy - d_xy dd_z) / d_z^2``.
    """
    tt = height / -d2
    q = tt / d2 * inv_n  # -height / d_z^2, per sample
    return (tt, q * (d2 * ddx0 - d0 * ddx2), q * (d2 * ddx1 - d1 * ddx2), q * (d2 * ddy0 - d0 * ddy2),
            q * (d2 * ddy1 - d1 * ddy2))


@_jit_inline
def _haze(c, horizon, f):
    """Distance haze: ``horizon + f (c - horizon)`` with ``f = exp(-distance / haze_distance)``."""
    return horizon + f * (c - horizon)


@_jit_inline
def _sky(horizon, zenith, e):
    """The sky: ``horizon + e (zenith - horizon)``, ``e = 1 - exp(-SKY_FALLOFF d_z / |d|)``."""
    return horizon + e * (zenith - horizon)


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def bake_kernel(T, anchor, pixel_size, n, row0, col0, out):
    """Top-down orthographic bake (section 8); ``n x n`` box-filtered samples per pixel.

    Pixel ``(r, c)`` of ``out`` is pixel ``(row0 + r, col0 + c)`` of the
    region whose corner the anchor is, so that a bake in blocks gives the
    same bits as one bake of the whole region.
    """
    h, w = out.shape[0], out.shape[1]
    step = pixel_size / n
    inv = 1.0 / (n * n)
    fbias = math.log2(n)
    for r in numba.prange(h):
        for c in range(w):
            ar = 0.0
            ag = 0.0
            ab = 0.0
            for j in range(n):
                dy = ((row0 + r) + (j + 0.5) / n) * pixel_size
                for i in range(n):
                    dx = ((col0 + c) + (i + 0.5) / n) * pixel_size
                    sr, sg, sb = shade_ground(T, anchor, dx, dy, step, 0.0, 0.0, step, fbias)
                    ar += sr
                    ag += sg
                    ab += sb
            out[r, c, 0] = ar * inv
            out[r, c, 1] = ag * inv
            out[r, c, 2] = ab * inv


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def render_kernel(T, anchor, V, rows, out):
    """Perspective view of the textured ground plane with sky and haze (section 7), any sampler state.

    Pixel ``(r, c)`` and sub-sample ``(j, i)`` look along ``d = fwd + ndc_x
    tan_x right + ndc_y tan_y up`` with ``ndc_x = 2 px / W - 1``, ``ndc_y = 1 -
    2 py / H``, ``px = c + (i + 0.5) / n``, ``py = r + (j + 0.5) / n``.
    Rows are drawn in the order ``rows`` (:func:`row_order`).
    """
    H, W = out.shape[0], out.shape[1]
    n = V.supersample
    inv = 1.0 / (n * n)
    inv_n = 1.0 / n
    fbias = math.log2(n)
    height = V.height
    far = V.far
    ddx = V.ddx
    ddy = V.ddy
    hor = V.horizon
    zen = V.zenith
    for ir in numba.prange(H):
        r = rows[ir]
        for c in range(W):
            ar = 0.0
            ag = 0.0
            ab = 0.0
            for j in range(n):
                ny = (1.0 - 2.0 * (r + (j + 0.5) / n) / H) * V.tan_y
                for i in range(n):
                    nx = (2.0 * (c + (i + 0.5) / n) / W - 1.0) * V.tan_x
                    d0, d1, d2 = _ray(V, nx, ny)
                    dlen = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                    sr = hor[0]
                    sg = hor[1]
                    sb = hor[2]
                    if d2 < 0.0 and height * dlen < -d2 * far:
                        tt, jxx, jyx, jxy, jyy = _ground_footprint(height, d0, d1, d2, ddx[0], ddx[1], ddx[2],
                                                                  ddy[0], ddy[1], ddy[2], inv_n)
                        gr, gg, gb = shade_ground(T, anchor, tt * d0, tt * d1, jxx, jyx, jxy, jyy, fbias)
                        f = math.exp(-tt * dlen / V.haze_distance)
                        sr = _haze(gr, hor[0], f)
                        sg = _haze(gg, hor[1], f)
                        sb = _haze(gb, hor[2], f)
                    elif d2 > 0.0:
                        e = 1.0 - math.exp(-SKY_FALLOFF * d2 / dlen)
                        sr = _sky(hor[0], zen[0], e)
                        sg = _sky(hor[1], zen[1], e)
                        sb = _sky(hor[2], zen[2], e)
                    ar += sr
                    ag += sg
                    ab += sb
            out[r, c, 0] = ar * inv
            out[r, c, 1] = ag * inv
            out[r, c, 2] = ab * inv


def row_order(h: int, block: int = 16) -> np.ndarray:
    """The order in which the render kernels draw the ``h`` rows of a picture.

    numba hands each thread one contiguous run of the parallel loop's
    iterations, and the rows of a ground view cost very different amounts
    (sky rows almost nothing): in top-to-bottom order one thread drew the
    sky and idled while the other drew the ground, and two threads were
    only 1.3x as fast as one. Here the picture is cut into runs of
    ``block`` rows (neighbouring rows share texels in the caches), and the
    runs are sorted by the fractional part of ``b phi`` (``phi`` the golden
    ratio), a low-discrepancy order: every contiguous stretch of it spreads
    evenly over the picture, so each thread gets its share of sky and
    ground, for any number of threads.
    """
    n_blocks = -(-h // block)
    order = np.argsort((np.arange(n_blocks) * 0.6180339887498949) % 1.0, kind="stable")
    rows = (order[:, None] * block + np.arange(block)[None, :]).reshape(-1)
    return np.ascontiguousarray(rows[rows < h], dtype=np.int64)




_LN2 = math.log(2.0)
_SQRT2 = math.sqrt(2.0)


@_jit_inline
def _log2(x):
    """log2 of a positive normal float64 to about 3e-11, without a libm call,
    so that a loop around it vectorises (libm's log2 costs as much as a
    texture layer): the exponent from the bits, log2 of the mantissa in
    [1/sqrt2, sqrt2) by the series 2 atanh(z) / ln 2, z = (m - 1) / (m + 1)."""
    bits = np.float64(x).view(np.int64)
    e = ((bits >> 52) & 0x7FF) - 1023
    m = np.int64((bits & 0xFFFFFFFFFFFFF) | 0x3FF0000000000000).view(np.float64)
    big = m > _SQRT2
    m = m * 0.5 if big else m
    e = e + 1 if big else e
    z = (m - 1.0) / (m + 1.0)
    z2 = z * z
    p = 1.0 / 11.0
    p = p * z2 + 1.0 / 9.0
    p = p * z2 + 1.0 / 7.0
    p = p * z2 + 1.0 / 5.0
    p = p * z2 + 1.0 / 3.0
    p = p * z2 + 1.0
    return e + (2.0 / _LN2) * z * p


@_jit_inline
def _exp(y):
    """exp(y) for y in [-700, 0] to about 3e-10 relative, without a libm call
    (see :func:`_log2`): 2^k from the bits times a Taylor polynomial of exp
    on [0, ln 2)."""
    t = max(y, -700.0) * (1.0 / _LN2)
    k = math.floor(t)
    g = (t - k) * _LN2
    p = 1.0 / 3628800.0
    p = p * g + 1.0 / 362880.0
    p = p * g + 1.0 / 40320.0
    p = p * g + 1.0 / 5040.0
    p = p * g + 1.0 / 720.0
    p = p * g + 1.0 / 120.0
    p = p * g + 1.0 / 24.0
    p = p * g + 1.0 / 6.0
    p = p * g + 0.5
    p = p * g + 1.0
    p = p * g + 1.0
    return p * np.int64((k + 1023) << 52).view(np.float64)


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def render_kernel_fast(T, anchor, V, rows, out):
    """:func:`render_kernel` for the fast path's sampler state (section 10; ``T.fast``).

    Per row of samples: the camera geometry in one straight loop, then the
    world lambda and the haze and sky factors with the call-free
    :func:`_log2` and :func:`_exp`, each in its own loop, then one loop per
    layer (:func:`~spectex.shading._layers.shade_row`), then haze and output.
    The tables are unpacked into plain arrays before the parallel loop, so
    that numba marks them ``noalias`` and LLVM vectorises the loops.
    """
    flat = T.flat
    stride = T.stride
    offsets = T.offsets
    size0 = T.size0
    tile = T.tile
    mats = T.mats
    blend_code = T.blend
    mean = T.mean
    opacity = T.opacity
    on = T.on
    lod_off = T.lod_off
    stochastic = (T.tiling, T.gauss.reshape(-1), T.grid, T.key, T.snap, T.cell_row, T.lut, T.lut_rows, T.basis,
                  T.origin)
    height = V.height
    right = V.right
    tan_x = V.tan_x
    tan_y = V.tan_y
    horizon = V.horizon
    zenith = V.zenith
    far = V.far
    n = V.supersample
    H, W = out.shape[0], out.shape[1]
    inv = 1.0 / (n * n)
    inv_n = 1.0 / n
    fbias = math.log2(n)
    inv_haze = 1.0 / V.haze_distance
    ddx0, ddx1, ddx2 = V.ddx[0], V.ddx[1], V.ddx[2]
    ddy0, ddy1, ddy2 = V.ddy[0], V.ddy[1], V.ddy[2]
    m = W * n
    for ir in numba.prange(H):
        r = rows[ir]
        px = np.empty(m)
        py = np.empty(m)
        lamw = np.empty(m)
        fog = np.empty(m)
        skyf = np.empty(m)
        gnd = np.empty(m, dtype=np.int64)
        cr = np.empty(m)
        cg = np.empty(m)
        cb = np.empty(m)
        lr = np.empty(m, dtype=np.float32)
        lg = np.empty(m, dtype=np.float32)
        lb = np.empty(m, dtype=np.float32)
        la = np.empty(m, dtype=np.float32)
        acc = np.zeros((W, 3))
        for j in range(n):
            ny = (1.0 - 2.0 * (r + (j + 0.5) * inv_n) / H) * tan_y
            e0, e1, e2 = _ray(V, 0.0, ny)
            n_ground = 0
            for i in range(n):  # the inner loop runs along the row, so that it is the one vectorised
                for c in range(W):
                    x = c * n + i
                    nx = (2.0 * (c + (i + 0.5) * inv_n) / W - 1.0) * tan_x
                    d0 = e0 + nx * right[0]
                    d1 = e1 + nx * right[1]
                    d2 = e2 + nx * right[2]
                    dlen = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                    ground = (d2 < 0.0) & (height * dlen < -d2 * far)
                    dz = d2 if ground else -1.0
                    tt, jxx, jyx, jxy, jyy = _ground_footprint(height, d0, d1, dz, ddx0, ddx1, ddx2,
                                                              ddy0, ddy1, ddy2, inv_n)
                    # the world lambda: log2 of the longer footprint edge (metres), below
                    rho2 = max(jxx * jxx + jyx * jyx, jxy * jxy + jyy * jyy)
                    px[x] = tt * d0 if ground else 0.0
                    py[x] = tt * d1 if ground else 0.0
                    lamw[x] = rho2 if ground else 1.0
                    gnd[x] = 1 if ground else 0
                    n_ground += 1 if ground else 0
                    # exponent of the haze factor on the ground, of the sky factor (1 - exp) above
                    fog[x] = -tt * dlen * inv_haze if ground else (-SKY_FALLOFF * d2 / dlen if d2 > 0.0 else 0.0)
            # log2 and exp without libm calls (each a call costs as much as a texture layer),
            # in separate straight loops so that each vectorises
            for x in range(m):
                lamw[x] = 0.5 * _log2(max(lamw[x], _LOD_FLOOR2))
            for x in range(m):
                fog[x] = _exp(fog[x])
            for x in range(m):
                # ground: haze factor v, sky factor 0; sky: haze factor 0, sky factor 1 - v
                v = fog[x]
                skyf[x] = 0.0 if gnd[x] == 1 else 1.0 - v
                fog[x] = v if gnd[x] == 1 else 0.0
            lam_lo = 1e300  # finite sentinels: fastmath assumes no infinities
            lam_hi = -1e300
            for x in range(m):
                lam_lo = min(lam_lo, lamw[x] if gnd[x] == 1 else 1e300)
                lam_hi = max(lam_hi, lamw[x] if gnd[x] == 1 else -1e300)
            if n_ground == 0:  # all sky: no texture, but finite colours for the sum below
                for x in range(m):
                    cr[x] = 0.0
                    cg[x] = 0.0
                    cb[x] = 0.0
            else:
                shade_row(flat, stride, offsets, size0, tile, mats, blend_code, mean, opacity, on, lod_off,
                          anchor, px, py, lamw, lam_lo, lam_hi, cr, cg, cb, lr, lg, lb, la, m, stochastic, fbias)
            for i in range(n):
                for c in range(W):
                    x = c * n + i
                    # branch-free (vectorised): one of the two factors is 0, the sum is exact
                    f = fog[x]
                    e = skyf[x]
                    acc[c, 0] += (_haze(min(max(cr[x], 0.0), 1.0), horizon[0], f)
                                    + (_sky(horizon[0], zenith[0], e) - horizon[0]))
                    acc[c, 1] += (_haze(min(max(cg[x], 0.0), 1.0), horizon[1], f)
                                    + (_sky(horizon[1], zenith[1], e) - horizon[1]))
                    acc[c, 2] += (_haze(min(max(cb[x], 0.0), 1.0), horizon[2], f)
                                    + (_sky(horizon[2], zenith[2], e) - horizon[2]))
        for c in range(W):
            out[r, c, 0] = acc[c, 0] * inv
            out[r, c, 1] = acc[c, 1] * inv
            out[r, c, 2] = acc[c, 2] * inv
