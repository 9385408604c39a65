"""numba kernels shared by the CPU renderer and ``SpectralTexture.bake``.

The compositing of layers (:func:`shade_ground`) and the camera model of
:func:`render_kernel` are the executable form of ``docs/sampling.md``; the
GLSL shader ``shaders/ground.frag.glsl`` implements the same text. Compiled
on first use (``cache=True``), never at import.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..sampling import sample_grad

_jit = numba.njit(cache=True, nogil=True, fastmath=True)
_jit_inline = numba.njit(cache=True, nogil=True, fastmath=True, inline="always")

_ALPHA, _DETAIL, _VARIANCE = 0, 1, 2


@_jit_inline
def shade_ground(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
                 min_lod, max_lod, tile_idx, mats, blends, means, opacity, on, anchor, dx, dy, jxx, jyx, jxy, jyy):
    """The spectral texture's colour at a ground point.

    ``(dx, dy)``: world displacement (metres) from the anchor whose per-layer
    tile coordinates are ``anchor``; ``(jxx, jyx)`` and ``(jxy, jyy)``: the
    world derivatives of the point along the screen's x and y.
    Returns RGB clamped to [0, 1].
    """
    first = True
    cr = 0.0
    cg = 0.0
    cb = 0.0
    for k in range(tile_idx.shape[0]):
        if not on[k]:
            continue
        m00 = mats[k, 0, 0]
        m01 = mats[k, 0, 1]
        m10 = mats[k, 1, 0]
        m11 = mats[k, 1, 1]
        s = anchor[k, 0] + (m00 * dx + m01 * dy)
        t = anchor[k, 1] + (m10 * dx + m11 * dy)
        dsdx = m00 * jxx + m01 * jyx
        dtdx = m10 * jxx + m11 * jyx
        dsdy = m00 * jxy + m01 * jyy
        dtdy = m10 * jxy + m11 * jyy
        r, g, b, a = sample_grad(data, tile_idx[k] * stride, offsets, widths, heights, wrap_s, wrap_t, min_filter,
                                 mag_filter, max_aniso, bias, min_lod, max_lod, s, t, dsdx, dtdx, dsdy, dtdy)
        a *= opacity[k]
        if first:
            cr = r
            cg = g
            cb = b
            first = False
        elif blends[k] == _ALPHA:
            cr = a * r + (1.0 - a) * cr
            cg = a * g + (1.0 - a) * cg
            cb = a * b + (1.0 - a) * cb
        elif blends[k] == _DETAIL:
            cr = 2.0 * r * cr
            cg = 2.0 * g * cg
            cb = 2.0 * b * cb
        else:
            n = 1.0 / math.sqrt(a * a + (1.0 - a) * (1.0 - a))
            mr = means[k, 0]
            mg = means[k, 1]
            mb = means[k, 2]
            cr = mr + (a * (r - mr) + (1.0 - a) * (cr - mr)) * n
            cg = mg + (a * (g - mg) + (1.0 - a) * (cg - mg)) * n
            cb = mb + (a * (b - mb) + (1.0 - a) * (cb - mb)) * n
    return min(max(cr, 0.0), 1.0), min(max(cg, 0.0), 1.0), min(max(cb, 0.0), 1.0)


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def bake_kernel(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
                min_lod, max_lod, tile_idx, mats, blends, means, opacity, on, anchor, pixel_size, n, out):
    """Top-down orthographic bake; ``n x n`` box-filtered samples per pixel."""
    h, w = out.shape[0], out.shape[1]
    step = pixel_size / n
    inv = 1.0 / (n * n)
    for r in numba.prange(h):
        for c in range(w):
            ar = 0.0
            ag = 0.0
            ab = 0.0
            for j in range(n):
                dy = (r + (j + 0.5) / n) * pixel_size
                for i in range(n):
                    dx = (c + (i + 0.5) / n) * pixel_size
                    sr, sg, sb = shade_ground(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter,
                                              mag_filter, max_aniso, bias, min_lod, max_lod, tile_idx, mats,
                                              blends, means, opacity, on, anchor, dx, dy, step, 0.0, 0.0, step)
                    ar += sr
                    ag += sg
                    ab += sb
            out[r, c, 0] = ar * inv
            out[r, c, 1] = ag * inv
            out[r, c, 2] = ab * inv


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def render_kernel(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
                  min_lod, max_lod, tile_idx, mats, blends, means, opacity, on, anchor, height, fwd, right, up,
                  tan_x, tan_y, ddx, ddy, horizon, zenith, haze_distance, far, n, rows, out):
    """Perspective view of the textured ground plane with sky and haze.

    Pixel ``(r, c)`` and sub-sample ``(j, i)`` look along ``d = fwd + ndc_x
    tan_x right + ndc_y tan_y up`` with ``ndc_x = 2 px / W - 1``, ``ndc_y = 1 -
    2 py / H``, ``px = c + (i + 0.5) / n``, ``py = r + (j + 0.5) / n``.
    Rows are drawn in the order ``rows`` (:func:`row_order`).
    """
    H, W = out.shape[0], out.shape[1]
    inv = 1.0 / (n * n)
    inv_n = 1.0 / n
    inv_haze = 1.0 / haze_distance
    ddx0, ddx1, ddx2 = ddx[0], ddx[1], ddx[2]  # Camera.ray_steps: the ray's change per pixel
    ddy0, ddy1, ddy2 = ddy[0], ddy[1], ddy[2]
    for ir in numba.prange(H):
        r = rows[ir]
        for c in range(W):
            ar = 0.0
            ag = 0.0
            ab = 0.0
            for j in range(n):
                py = r + (j + 0.5) / n
                ny = (1.0 - 2.0 * py / H) * tan_y
                for i in range(n):
                    px = c + (i + 0.5) / n
                    nx = (2.0 * px / W - 1.0) * tan_x
                    d0 = fwd[0] + nx * right[0] + ny * up[0]
                    d1 = fwd[1] + nx * right[1] + ny * up[1]
                    d2 = fwd[2] + nx * right[2] + ny * up[2]
                    dlen = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                    sr = horizon[0]
                    sg = horizon[1]
                    sb = horizon[2]
                    if d2 < 0.0 and height * dlen < -d2 * far:
                        tt = height / -d2
                        dist = tt * dlen
                        # ground point G = C + tt d; dG/dp = -height (d_z dd_xy - d_xy dd_z) / d_z^2
                        q = -height / (d2 * d2)
                        jxx = q * (d2 * ddx0 - d0 * ddx2) / n
                        jyx = q * (d2 * ddx1 - d1 * ddx2) / n
                        jxy = q * (d2 * ddy0 - d0 * ddy2) / n
                        jyy = q * (d2 * ddy1 - d1 * ddy2) / n
                        gr, gg, gb = shade_ground(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter,
                                                  mag_filter, max_aniso, bias, min_lod, max_lod, tile_idx, mats,
                                                  blends, means, opacity, on, anchor, tt * d0, tt * d1,
                                                  jxx, jyx, jxy, jyy)
                        f = math.exp(-dist / haze_distance)
                        sr = horizon[0] + f * (gr - horizon[0])
                        sg = horizon[1] + f * (gg - horizon[1])
                        sb = horizon[2] + f * (gb - horizon[2])
                    elif d2 > 0.0:
                        e = 1.0 - math.exp(-4.0 * d2 / dlen)
                        sr = horizon[0] + e * (zenith[0] - horizon[0])
                        sg = horizon[1] + e * (zenith[1] - horizon[1])
                        sb = horizon[2] + e * (zenith[2] - horizon[2])
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


# --------------------------------------------------------------------------
# The fast path: REPEAT, square power-of-two tiles, trilinear, isotropic,
# bias 0 and OpenGL's default lod clamps (what every render and bake of a
# spectral texture uses). The same numbers as the general path above (to
# float rounding; tests/test_render.py compares them), organised for speed:
# per row of samples, the camera geometry first (one lambda per sample: the
# world footprint's, docs/sampling.md section 3), then one straight loop
# over the row per layer, with bitmask wrapping and both trilinear levels
# fetched unconditionally (weight 0 when not needed), then haze and output.
# --------------------------------------------------------------------------


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


@_jit_inline
def _bilinear(flat, off, wd, s, t):
    """OpenGL LINEAR with REPEAT on the level of width ``wd`` (a power of two)
    whose first texel is ``off`` in ``flat`` (RGBA float32, row-major):
    returns (r, g, b, a). Unsigned indices and no branches, so that a loop
    around it can be vectorised (gathers)."""
    mask = wd - 1
    u = s * wd - 0.5
    v = t * wd - 0.5
    fu = math.floor(u)
    fv = math.floor(v)
    a = np.float32(u - fu)
    b = np.float32(v - fv)
    i0 = np.int64(fu)
    j0 = np.int64(fv)
    i1 = (i0 + 1) & mask
    j1 = (j0 + 1) & mask
    i0 = i0 & mask
    j0 = j0 & mask
    r0 = off + j0 * wd
    r1 = off + j1 * wd
    k00 = np.uint64((r0 + i0) * 4)
    k10 = np.uint64((r0 + i1) * 4)
    k01 = np.uint64((r1 + i0) * 4)
    k11 = np.uint64((r1 + i1) * 4)
    one = np.float32(1.0)
    w00 = (one - a) * (one - b)
    w10 = a * (one - b)
    w01 = (one - a) * b
    w11 = a * b
    u1 = np.uint64(1)
    u2 = np.uint64(2)
    u3 = np.uint64(3)
    return (w00 * flat[k00] + w10 * flat[k10] + w01 * flat[k01] + w11 * flat[k11],
            w00 * flat[k00 + u1] + w10 * flat[k10 + u1] + w01 * flat[k01 + u1] + w11 * flat[k11 + u1],
            w00 * flat[k00 + u2] + w10 * flat[k10 + u2] + w01 * flat[k01 + u2] + w11 * flat[k11 + u2],
            w00 * flat[k00 + u3] + w10 * flat[k10 + u3] + w01 * flat[k01 + u3] + w11 * flat[k11 + u3])


@_jit_inline
def _sample_row(flat, base, offsets, size0, m00, m01, m10, m11, a0, a1, off_k, px, py, lamw, lr, lg, lb, la, m,
                two):
    """Sections 3-4, trilinear, for one layer on ``m`` samples: the layer's
    lambda is the world lambda plus ``off_k``. With ``two``, both levels
    are always fetched (the second with weight 0 at and beyond the last
    level and in magnification, where lambda is clamped to 0); without, the
    caller knows that every lambda of the row is <= 0 or >= q, where the
    second level has weight 0, and it is skipped (the same numbers)."""
    q = offsets.shape[0] - 1
    qf = np.float64(q)
    if two == 0:
        for x in range(m):
            s = a0 + (m00 * px[x] + m01 * py[x])
            t = a1 + (m10 * px[x] + m11 * py[x])
            lam = min(max(lamw[x] + off_k, 0.0), qf)
            d1 = np.int64(math.floor(lam))
            r, g, b, a = _bilinear(flat, base + offsets[d1], size0 >> d1, s, t)
            lr[x] = r
            lg[x] = g
            lb[x] = b
            la[x] = a
        return 0
    for x in range(m):
        s = a0 + (m00 * px[x] + m01 * py[x])
        t = a1 + (m10 * px[x] + m11 * py[x])
        lam = min(max(lamw[x] + off_k, 0.0), qf)
        fd = math.floor(lam)
        beta = np.float32(lam - fd)
        d1 = np.int64(fd)
        d2 = min(d1 + 1, q)
        r, g, b, a = _bilinear(flat, base + offsets[d1], size0 >> d1, s, t)
        r2, g2, b2, a2 = _bilinear(flat, base + offsets[d2], size0 >> d2, s, t)
        lr[x] = r + beta * (r2 - r)
        lg[x] = g + beta * (g2 - g)
        lb[x] = b + beta * (b2 - b)
        la[x] = a + beta * (a2 - a)
    return 0


@_jit_inline
def _shade_row(flat, stride, offsets, size0, tile_idx, mats, blends, means, opacity, on, lod_off, anchor,
               px, py, lamw, lam_lo, lam_hi, cr, cg, cb, lr, lg, lb, la, m):
    """Section 6 on ``m`` samples of a row: world points ``(px, py)``
    relative to the anchor, world lambda ``lamw`` (between ``lam_lo`` and
    ``lam_hi`` on the ground); colours into ``cr, cg, cb``; ``lr .. la``
    are scratch (float32)."""
    first = 1  # ints, not bools, here: numba's alias analysis counts bools as mutable, and any
    # alias in the parallel loop stops it marking the arrays noalias (and LLVM from vectorising)
    for k in range(tile_idx.shape[0]):
        if on[k] == 0:
            continue
        q = offsets.shape[0] - 1
        two = 0 if lam_hi + lod_off[k] <= 0.0 or lam_lo + lod_off[k] >= q else 1
        _sample_row(flat, tile_idx[k] * stride, offsets, size0, mats[k, 0, 0], mats[k, 0, 1], mats[k, 1, 0],
                    mats[k, 1, 1], anchor[k, 0], anchor[k, 1], lod_off[k], px, py, lamw, lr, lg, lb, la, m, two)
        op = opacity[k]
        if first:
            for x in range(m):
                cr[x] = lr[x]
                cg[x] = lg[x]
                cb[x] = lb[x]
            first = 0
        elif blends[k] == _ALPHA:
            for x in range(m):
                a = la[x] * op
                cr[x] = a * lr[x] + (1.0 - a) * cr[x]
                cg[x] = a * lg[x] + (1.0 - a) * cg[x]
                cb[x] = a * lb[x] + (1.0 - a) * cb[x]
        elif blends[k] == _DETAIL:
            for x in range(m):
                cr[x] = 2.0 * lr[x] * cr[x]
                cg[x] = 2.0 * lg[x] * cg[x]
                cb[x] = 2.0 * lb[x] * cb[x]
        else:
            mr = means[k, 0]
            mg = means[k, 1]
            mb = means[k, 2]
            for x in range(m):
                a = la[x] * op
                nn = 1.0 / math.sqrt(a * a + (1.0 - a) * (1.0 - a))
                cr[x] = mr + (a * (lr[x] - mr) + (1.0 - a) * (cr[x] - mr)) * nn
                cg[x] = mg + (a * (lg[x] - mg) + (1.0 - a) * (cg[x] - mg)) * nn
                cb[x] = mb + (a * (lb[x] - mb) + (1.0 - a) * (cb[x] - mb)) * nn
    if first == 1:  # no layer enabled: black, as in shade_ground
        for x in range(m):
            cr[x] = 0.0
            cg[x] = 0.0
            cb[x] = 0.0
    return 0


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def render_kernel_fast(flat, stride, offsets, size0, tile_idx, mats, blends, means, opacity, on, lod_off, anchor,
                       height, fwd, right, up, tan_x, tan_y, ddx, ddy, horizon, zenith, haze_distance, far, n, rows, out):
    """:func:`render_kernel` for the fast path's sampler state (see above).

    ``flat``: the texel store as one flat float32 array (RGBA per texel), so
    that no array in the parallel loop aliases another: numba then marks
    them ``noalias`` and LLVM vectorises the texel loops with gathers.
    """
    H, W = out.shape[0], out.shape[1]
    inv = 1.0 / (n * n)
    inv_n = 1.0 / n
    inv_haze = 1.0 / haze_distance
    ddx0, ddx1, ddx2 = ddx[0], ddx[1], ddx[2]  # Camera.ray_steps: the ray's change per pixel
    ddy0, ddy1, ddy2 = ddy[0], ddy[1], ddy[2]
    m = W * n
    for ir in numba.prange(H):
        r = rows[ir]
        px = np.empty(m)
        py = np.empty(m)
        lamw = np.empty(m)
        fog = np.empty(m)
        sky = np.empty(m)
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
            e0 = fwd[0] + ny * up[0]
            e1 = fwd[1] + ny * up[1]
            e2 = fwd[2] + ny * up[2]
            # camera geometry: a straight loop (vectorised), then log2 and exp (libm calls)
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
                    tt = height / -dz
                    q = tt / dz * inv_n  # -height / d_z^2, for the sample's footprint
                    jxx = q * (dz * ddx0 - d0 * ddx2)
                    jyx = q * (dz * ddx1 - d1 * ddx2)
                    jxy = q * (dz * ddy0 - d0 * ddy2)
                    jyy = q * (dz * ddy1 - d1 * ddy2)
                    # the world lambda: log2 of the longer footprint edge (metres), below
                    rho2 = max(jxx * jxx + jyx * jyx, jxy * jxy + jyy * jyy)
                    px[x] = tt * d0 if ground else 0.0
                    py[x] = tt * d1 if ground else 0.0
                    lamw[x] = rho2 if ground else 1.0
                    gnd[x] = 1 if ground else 0
                    n_ground += 1 if ground else 0
                    # exponent of the haze factor on the ground, of the sky factor (1 - exp) above
                    fog[x] = -tt * dlen * inv_haze if ground else (-4.0 * d2 / dlen if d2 > 0.0 else 0.0)
            # log2 and exp without libm calls (each a call costs as much as a texture layer),
            # in separate straight loops so that each vectorises: lambda to ~3e-11, the
            # haze and sky factors to ~3e-10
            for x in range(m):
                lamw[x] = 0.5 * _log2(max(lamw[x], 1e-300))
            for x in range(m):
                fog[x] = _exp(fog[x])
            for x in range(m):
                # ground: haze factor v, sky factor 0; sky: haze factor 0, sky factor 1 - v
                v = fog[x]
                sky[x] = 0.0 if gnd[x] == 1 else 1.0 - v
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
                _shade_row(flat, stride, offsets, size0, tile_idx, mats, blends, means, opacity, on, lod_off,
                           anchor, px, py, lamw, lam_lo, lam_hi, cr, cg, cb, lr, lg, lb, la, m)
            for i in range(n):
                for c in range(W):
                    x = c * n + i
                    # branch-free (vectorised): one of the two factors is 0, the sum is exact
                    f = fog[x]
                    e = sky[x]
                    acc[c, 0] += (horizon[0] + f * (min(max(cr[x], 0.0), 1.0) - horizon[0])
                                  + e * (zenith[0] - horizon[0]))
                    acc[c, 1] += (horizon[1] + f * (min(max(cg[x], 0.0), 1.0) - horizon[1])
                                  + e * (zenith[1] - horizon[1]))
                    acc[c, 2] += (horizon[2] + f * (min(max(cb[x], 0.0), 1.0) - horizon[2])
                                  + e * (zenith[2] - horizon[2]))
        for c in range(W):
            out[r, c, 0] = acc[c, 0] * inv
            out[r, c, 1] = acc[c, 1] * inv
            out[r, c, 2] = acc[c, 2] * inv
