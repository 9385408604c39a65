"""Layer sampling and compositing (``docs/sampling.md``, section 6), in numba.

The one home of a layer's maths on the CPU:

* :func:`layer_coords`: a ground point and its footprint in a layer's tile
  coordinates, relative to the per-layer anchor;
* :func:`sample_layer`: one layer's RGBA at a point, by its tiling mode
  (periodic: the OpenGL-exact sampler of ``shading.sampler``; stochastic:
  ``shading.stochastic``); a new tiling mode is a new branch here and in
  ``shaders/spectex_layers.glsl``;
* :func:`blend_alpha`, :func:`blend_detail`, :func:`blend_variance` and
  :func:`blend`: how a layer goes over the colour of the layers before it;
* :func:`shade_ground` (one point, any sampler state) and :func:`shade_row`
  (a row of points, the fast path's sampler state), which both composite
  through the functions above.

The GLSL side is ``shaders/spectex_layers.glsl``; its codes come from the
same ``shading.constants``. Compiled on first use, never at import.
"""

from __future__ import annotations

import math

import numpy as np

from ._jit import jit_call as _jit_call
from ._jit import jit_inline as _jit_inline
from .constants import (
    BLEND_ALPHA,
    BLEND_COVER,
    BLEND_DETAIL,
    BLEND_FINE,
    BLEND_FIRST,
    BLEND_OVERLAY,
    FADE_END,
    FADE_START,
    LOD_FLOOR,
    TILING_STOCHASTIC,
)
from .sampler import sample_grad
from .stochastic import (
    blend_patches,
    cell_mix,
    cell_vertex,
    course_band_shift,
    lut_lookup,
    patch_lod,
    sample_stochastic_grad,
    sharpen_weights,
    triangle_vertices,
    vertex_offset,
)

__all__ = ["layer_coords", "sample_layer", "blend_alpha", "blend_detail", "blend_variance", "fade", "blend",
           "shade_ground", "shade_row", "bilinear_repeat"]


@_jit_inline
def layer_coords(mats, anchor, k, dx, dy):
    """Tile coordinates ``(s, t)`` of layer ``k`` at world displacement ``(dx, dy)`` from the anchor."""
    return (anchor[k, 0] + (mats[k, 0, 0] * dx + mats[k, 0, 1] * dy),
            anchor[k, 1] + (mats[k, 1, 0] * dx + mats[k, 1, 1] * dy))


@_jit_inline
def sample_layer(T, anchor, k, s, t, dsdx, dtdx, dsdy, dtdy):
    """Layer ``k``'s RGBA at tile coordinates ``(s, t)`` with footprint derivatives (sections 3-6b).

    ``T``: :class:`~spectex.shading.tables.ShadingTables`; ``anchor``: per
    layer, :func:`~spectex.shading.tables.anchor_coords` of the point that
    ``(s, t)`` are relative to. By the layer's tiling:

    * periodic: the tile repeats (``REPEAT``), sampled by the OpenGL-exact
      sampler;
    * stochastic (section 6b): histogram-preserving tiling and blending of
      the tile's Gaussianised texels (``T.gauss``) through its inverse
      tables (``T.lut``), the grid position from the anchor's
      (``anchor[k, 2:6]``) plus ``T.grid[k]`` times the displacement in
      tile coordinates.

    A layer with the fine blend is sampled isotropically (anisotropy 1: one
    sample at the longer footprint edge's lambda): it fades out before a
    footprint is long enough for anisotropic filtering to matter, and the
    anisotropic loop would cost the GL frame most where it is invisible.
    """
    aniso = 1.0 if T.blend[k] == BLEND_FINE else T.max_aniso
    if T.tiling[k] == TILING_STOCHASTIC:
        sr = s - anchor[k, 0]
        tr = t - anchor[k, 1]
        g = T.grid
        kx = anchor[k, 2] + (g[k, 0, 0] * sr + g[k, 0, 1] * tr)
        ky = anchor[k, 3] + (g[k, 1, 0] * sr + g[k, 1, 1] * tr)
        return sample_stochastic_grad(T.gauss, T.tile[k] * T.stride, T.offsets, T.widths, T.heights, T.wrap_s,
                                      T.wrap_t, T.min_filter, T.mag_filter, aniso, T.bias, T.min_lod,
                                      T.max_lod, T.lut, T.tile[k] * T.lut_rows, T.basis[k], T.origin[k],
                                      T.grid[k], np.int64(anchor[k, 4]), np.int64(anchor[k, 5]), T.key[k],
                                      (T.snap[k, 0], T.snap[k, 1], T.cell_row[k]), s, t, kx, ky, dsdx, dtdx, dsdy,
                                      dtdy)
    return sample_grad(T.data, T.tile[k] * T.stride, T.offsets, T.widths, T.heights, T.wrap_s, T.wrap_t,
                       T.min_filter, T.mag_filter, aniso, T.bias, T.min_lod, T.max_lod,
                       s, t, dsdx, dtdx, dsdy, dtdy)


@_jit_inline
def blend_alpha(c, x, a):
    """The paper's blend: ``a x + (1 - a) c``."""
    return a * x + (1.0 - a) * c


@_jit_inline
def blend_detail(c, x):
    """Detail texturing: ``2 x c`` (modulate around mid-grey; no alpha)."""
    return 2.0 * x * c


@_jit_inline
def blend_overlay(c, x, a):
    """The overlay blend at alpha ``a``: ``c (1 + d)`` below mid-grey, ``1 - (1 - c)(1 - d)`` from it,
    ``d = a (2 x - 1)`` (``a`` of the way from ``c`` to the overlay of ``x`` on ``c``): black and white
    stay where they are and the contrast below is kept, scaled by ``1 +- d``."""
    d = a * (2.0 * x - 1.0)
    if c < 0.5:
        return c * (1.0 + d)
    return 1.0 - (1.0 - c) * (1.0 - d)


@_jit_inline
def variance_norm(a):
    """``1 / sqrt(a^2 + (1 - a)^2)``, the variance-preserving blend's normalisation."""
    return 1.0 / math.sqrt(a * a + (1.0 - a) * (1.0 - a))


@_jit_inline
def blend_variance(c, x, a, mu, norm):
    """Heitz and Neyret's variance-preserving blend around the tile mean ``mu``; ``norm = variance_norm(a)``."""
    return mu + (a * (x - mu) + (1.0 - a) * (c - mu)) * norm


@_jit_inline
def fade(lam):
    """The fine blend's fade at a layer's isotropic lambda: 1 up to ``FADE_START``, 0 from ``FADE_END``."""
    return min(max((FADE_END - lam) * (1.0 / (FADE_END - FADE_START)), 0.0), 1.0)


@_jit_inline
def cover(a, f):
    """The cover blend's alpha: ``a`` (opacity included) raised towards 1 as the fade ``f`` falls to 0."""
    return 1.0 - (1.0 - a) * f


@_jit_inline
def fade_lod(w0, h0, dsdx, dtdx, dsdy, dtdy):
    """The isotropic lambda (log2 of the longer footprint edge, level-0 texels) of derivatives of (s, t)."""
    px = math.sqrt((dsdx * w0) ** 2 + (dtdx * h0) ** 2)
    py = math.sqrt((dsdy * w0) ** 2 + (dtdy * h0) ** 2)
    return math.log2(max(max(px, py), LOD_FLOOR))


@_jit_inline
def blend(code, cr, cg, cb, r, g, b, a, mr, mg, mb):
    """The colour after a layer with blend ``code`` (``constants.BLEND_*``) goes over ``c``.

    ``BLEND_FINE`` and ``BLEND_COVER`` are the variance blend; the caller has
    faded ``a`` (:func:`fade`) or raised it (:func:`cover`)."""
    if code == BLEND_FIRST:
        return r, g, b
    if code == BLEND_ALPHA:
        return blend_alpha(cr, r, a), blend_alpha(cg, g, a), blend_alpha(cb, b, a)
    if code == BLEND_DETAIL:
        return blend_detail(cr, r), blend_detail(cg, g), blend_detail(cb, b)
    if code == BLEND_OVERLAY:
        return blend_overlay(cr, r, a), blend_overlay(cg, g, a), blend_overlay(cb, b, a)
    nn = variance_norm(a)
    return blend_variance(cr, r, a, mr, nn), blend_variance(cg, g, a, mg, nn), blend_variance(cb, b, a, mb, nn)


@_jit_call
def shade_ground(T, anchor, dx, dy, jxx, jyx, jxy, jyy, fade_bias):
    """The spectral texture's colour at a ground point, any sampler state.

    ``(dx, dy)``: world displacement (metres) from the anchor whose per-layer
    tile coordinates are ``anchor``; ``(jxx, jyx)`` and ``(jxy, jyy)``: the
    world derivatives of the point along the screen's x and y (of one
    sample); ``fade_bias``: ``log2`` of the samples per pixel along a side,
    so that the fine blend fades by the pixel's footprint. Returns RGB clamped to [0, 1] (black if no layer is drawn).
    """
    cr = 0.0
    cg = 0.0
    cb = 0.0
    mats = T.mats
    for k in range(T.tile.shape[0]):
        if T.on[k] == 0:
            continue
        s, t = layer_coords(mats, anchor, k, dx, dy)
        dsdx = mats[k, 0, 0] * jxx + mats[k, 0, 1] * jyx
        dtdx = mats[k, 1, 0] * jxx + mats[k, 1, 1] * jyx
        dsdy = mats[k, 0, 0] * jxy + mats[k, 0, 1] * jyy
        dtdy = mats[k, 1, 0] * jxy + mats[k, 1, 1] * jyy
        r, g, b, a = sample_layer(T, anchor, k, s, t, dsdx, dtdx, dsdy, dtdy)
        a = a * T.opacity[k]
        if T.blend[k] == BLEND_FINE:
            a = a * fade(fade_lod(T.widths[0], T.heights[0], dsdx, dtdx, dsdy, dtdy) + fade_bias)
        elif T.blend[k] == BLEND_COVER:
            a = cover(a, fade(fade_lod(T.widths[0], T.heights[0], dsdx, dtdx, dsdy, dtdy) + fade_bias))
        cr, cg, cb = blend(T.blend[k], cr, cg, cb, r, g, b, a, T.mean[k, 0], T.mean[k, 1], T.mean[k, 2])
    return min(max(cr, 0.0), 1.0), min(max(cg, 0.0), 1.0), min(max(cb, 0.0), 1.0)


# --------------------------------------------------------------------------
# The fast path (docs/sampling.md, section 10): REPEAT, square power-of-two
# tiles, trilinear, isotropic, default lod clamps, periodic tiling. The same
# numbers as shade_ground (to float rounding), organised for speed: one
# straight loop over a row of samples per layer, each layer's lambda from
# the row's world lambda plus the layer's offset (section 3).
# --------------------------------------------------------------------------


@_jit_inline
def bilinear_repeat(flat, off, wd, s, t):
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
def _sample_row(flat, base, offsets, size0, mats, anchor, k, off_k, px, py, lamw, lr, lg, lb, la, m, two):
    """Sections 3-4, trilinear, for layer ``k`` on ``m`` samples: the layer's
    lambda is the world lambda plus ``off_k``. With ``two``, both levels
    are always fetched (the second with weight 0 at and beyond the last
    level and in magnification, where lambda is clamped to 0); without, the
    caller knows that every lambda of the row is <= 0 or >= q, where the
    second level has weight 0, and it is skipped (the same numbers)."""
    q = offsets.shape[0] - 1
    qf = np.float64(q)
    if two == 0:
        for x in range(m):
            s, t = layer_coords(mats, anchor, k, px[x], py[x])
            lam = min(max(lamw[x] + off_k, 0.0), qf)
            d1 = np.int64(math.floor(lam))
            r, g, b, a = bilinear_repeat(flat, base + offsets[d1], size0 >> d1, s, t)
            lr[x] = r
            lg[x] = g
            lb[x] = b
            la[x] = a
        return 0
    for x in range(m):
        s, t = layer_coords(mats, anchor, k, px[x], py[x])
        lam = min(max(lamw[x] + off_k, 0.0), qf)
        fd = math.floor(lam)
        beta = np.float32(lam - fd)
        d1 = np.int64(fd)
        d2 = min(d1 + 1, q)
        r, g, b, a = bilinear_repeat(flat, base + offsets[d1], size0 >> d1, s, t)
        r2, g2, b2, a2 = bilinear_repeat(flat, base + offsets[d2], size0 >> d2, s, t)
        lr[x] = r + beta * (r2 - r)
        lg[x] = g + beta * (g2 - g)
        lb[x] = b + beta * (b2 - b)
        la[x] = a + beta * (a2 - a)
    return 0


@_jit_inline
def _trilinear_repeat(flat, base, offsets, size0, q, d1, beta, s, t):
    """Trilinear at levels ``d1`` and ``min(d1 + 1, q)`` (weight ``beta``), REPEAT, square power-of-two levels."""
    r, g, b, a = bilinear_repeat(flat, base + offsets[d1], size0 >> d1, s, t)
    d2 = min(d1 + 1, q)
    r2, g2, b2, a2 = bilinear_repeat(flat, base + offsets[d2], size0 >> d2, s, t)
    return r + beta * (r2 - r), g + beta * (g2 - g), b + beta * (b2 - b), a + beta * (a2 - a)


@_jit_inline
def _row_winner(gflat, base, offsets, size0, q, d1, beta, s, t, ci, cj, ds, dt, bi, bj, key, w0, nx, ny):
    """:func:`~spectex.shading.stochastic.vertex_patch_at` with the fast path's trilinear sampler."""
    ox, oy = vertex_offset(bi + ci, bj + cj, key, w0, w0, nx, ny)
    return _trilinear_repeat(gflat, base, offsets, size0, q, d1, beta, s + ox + ds, t + oy + dt)


@_jit_inline
def _row_patches(gflat, base, offsets, size0, q, d1, beta, s, t, gx, gy, bi, bj, key, w0, nx, ny, lam, plod):
    """:func:`~spectex.shading.stochastic.patches_at` with the fast path's trilinear sampler."""
    i1, j1, w1, i2, j2, w2, i3, j3, w3 = triangle_vertices(gx, gy)
    w1, w2, w3 = sharpen_weights(w1, w2, w3, lam, plod)
    ox, oy = vertex_offset(bi + i1, bj + j1, key, w0, w0, nx, ny)
    r1, g1, b1, a1 = _trilinear_repeat(gflat, base, offsets, size0, q, d1, beta, s + ox, t + oy)
    ox, oy = vertex_offset(bi + i2, bj + j2, key, w0, w0, nx, ny)
    r2, g2, b2, a2 = _trilinear_repeat(gflat, base, offsets, size0, q, d1, beta, s + ox, t + oy)
    ox, oy = vertex_offset(bi + i3, bj + j3, key, w0, w0, nx, ny)
    r3, g3, b3, a3 = _trilinear_repeat(gflat, base, offsets, size0, q, d1, beta, s + ox, t + oy)
    inv = 1.0 / math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    return (blend_patches(r1, r2, r3, w1, w2, w3, inv), blend_patches(g1, g2, g3, w1, w2, w3, inv),
            blend_patches(b1, b2, b3, w1, w2, w3, inv), blend_patches(a1, a2, a3, w1, w2, w3, inv))


@_jit_inline
def _sample_row_stochastic(gflat, base, offsets, size0, mats, anchor, grid, key, snap, cell_rows, lut, row0, basis,
                           origin, k, off_k, px, py, lamw, lr, lg, lb, la, m):
    """Section 6b on ``m`` samples of a row (the fast path's sampler state): layer ``k``'s
    histogram-preserving sample at the world lambda plus ``off_k``, the numbers of
    :func:`~spectex.shading.stochastic.sample_stochastic_at_lod` (to float rounding), with the
    Gaussian levels ``gflat`` (laid out as the texel store) read by :func:`bilinear_repeat`;
    ``snap[k]``: the layer's snap counts, ``cell_rows[k]`` its cell-map row (-1: none)."""
    q = offsets.shape[0] - 1
    qf = np.float64(q)
    w0 = np.float64(size0)
    bi = np.int64(anchor[k, 4])
    bj = np.int64(anchor[k, 5])
    nx = snap[k, 0]
    ny = snap[k, 1]
    cell_row = cell_rows[k]
    gk = grid[k]
    plod = patch_lod(w0, gk)
    for x in range(m):
        dx = px[x]
        dy = py[x]
        sr = mats[k, 0, 0] * dx + mats[k, 0, 1] * dy
        tr = mats[k, 1, 0] * dx + mats[k, 1, 1] * dy
        s = anchor[k, 0] + sr
        t = anchor[k, 1] + tr
        kx = anchor[k, 2] + (grid[k, 0, 0] * sr + grid[k, 0, 1] * tr)
        ky = anchor[k, 3] + (grid[k, 1, 0] * sr + grid[k, 1, 1] * tr)
        # trilinear at a lambda clamped to [0, q] is OpenGL's LINEAR_MIPMAP_LINEAR / LINEAR (section 4)
        lam = min(max(lamw[x] + off_k, 0.0), qf)
        fd = math.floor(lam)
        beta = np.float32(lam - fd)
        d1 = np.int64(fd)
        # weights at the cell's centre (stochastic.cell_point) up to l_c, at the point from l_c + 1 (cell_mix)
        tm = cell_mix(lam, w0, w0, nx, ny)
        cells = cell_row >= 0.0 and tm < 1.0
        v0 = v1 = v2 = v3 = 0.0
        if cell_row >= 0.0:  # a wall of courses of their own heights: its band's courses (else 0)
            sb, tb = course_band_shift(lut, cell_row, kx, ky, gk, w0, w0, bi, bj, key, nx, ny)
            s += sb
            t += tb
        if cells:
            ci, cj, whole, ds, dt = cell_vertex(lut, cell_row, s, t, kx, ky, gk, w0, w0, bi, bj, key, nx, ny)
            if whole:
                v0, v1, v2, v3 = _row_winner(gflat, base, offsets, size0, q, d1, beta, s, t, ci, cj, ds, dt, bi, bj,
                                             key, w0, nx, ny)
            else:
                tm = 1.0  # the blend at the point
        if not cells or tm > 0.0:
            u0, u1, u2, u3 = _row_patches(gflat, base, offsets, size0, q, d1, beta, s, t, kx, ky, bi, bj, key, w0,
                                          nx, ny, lam, plod)
            if cells:
                v0 += tm * (u0 - v0)
                v1 += tm * (u1 - v1)
                v2 += tm * (u2 - v2)
                v3 += tm * (u3 - v3)
            else:
                v0, v1, v2, v3 = u0, u1, u2, u3
        # the table level of LINEAR_MIPMAP_LINEAR (stochastic.lut_level): lambda itself, 0 in magnification
        x0 = lut_lookup(lut, row0, lam, v0, 0)
        x1 = lut_lookup(lut, row0, lam, v1, 1)
        x2 = lut_lookup(lut, row0, lam, v2, 2)
        al = lut_lookup(lut, row0, lam, v3, 3)
        lr[x] = min(max(origin[k, 0] + basis[k, 0, 0] * x0 + basis[k, 0, 1] * x1 + basis[k, 0, 2] * x2, 0.0), 1.0)
        lg[x] = min(max(origin[k, 1] + basis[k, 1, 0] * x0 + basis[k, 1, 1] * x1 + basis[k, 1, 2] * x2, 0.0), 1.0)
        lb[x] = min(max(origin[k, 2] + basis[k, 2, 0] * x0 + basis[k, 2, 1] * x1 + basis[k, 2, 2] * x2, 0.0), 1.0)
        la[x] = min(max(al, 0.0), 1.0)
    return 0


@_jit_inline
def _overlay_row(cr, cg, cb, lr, lg, lb, la, op, m):
    """The overlay blend over ``m`` samples of a row (:func:`shade_row`)."""
    for x in range(m):
        a = la[x] * op
        cr[x] = blend_overlay(cr[x], lr[x], a)
        cg[x] = blend_overlay(cg[x], lg[x], a)
        cb[x] = blend_overlay(cb[x], lb[x], a)


@_jit_inline
def shade_row(flat, stride, offsets, size0, tile, mats, blend_code, mean, opacity, on, lod_off, anchor,
              px, py, lamw, lam_lo, lam_hi, cr, cg, cb, lr, lg, lb, la, m, stochastic, fade_bias):
    """Section 6 on ``m`` samples of a row (the fast path): world points
    ``(px, py)`` relative to the anchor, world lambda ``lamw`` (between
    ``lam_lo`` and ``lam_hi`` on the ground); colours into ``cr, cg, cb``
    (not clamped); ``lr .. la`` are float32 scratch; ``fade_bias`` as in
    :func:`shade_ground`. ``stochastic`` is
    ``(tiling, gflat, grid, key, snap, cell_row, lut, lut_rows, basis, origin)`` (one tuple:
    CPython passes a call of more than 30 arguments as ``*args``, which
    numba cannot inline): stochastic layers (``tiling``) read the Gaussian
    levels ``gflat`` and the tables ``lut`` (:func:`_sample_row_stochastic`).

    The arrays of :class:`ShadingTables` come one by one, unpacked by the
    kernel before its parallel loop: numba marks only plain array arguments
    ``noalias``, and without that LLVM does not vectorise these loops. The
    blend formulas are :func:`blend_alpha` and friends, one loop per code.
    """
    for x in range(m):  # black where no layer is drawn, as shade_ground
        cr[x] = 0.0
        cg[x] = 0.0
        cb[x] = 0.0
    q = offsets.shape[0] - 1
    tiling, gflat, grid, key, snap, cell_row, lut, lut_rows, basis, origin = stochastic
    for k in range(tile.shape[0]):
        if on[k] == 0:
            continue
        if tiling[k] == TILING_STOCHASTIC:
            _sample_row_stochastic(gflat, tile[k] * stride, offsets, size0, mats, anchor, grid, key[k], snap,
                                   cell_row, lut, tile[k] * lut_rows, basis, origin, k, lod_off[k], px, py, lamw, lr,
                                   lg, lb, la, m)
        else:
            two = 0 if lam_hi + lod_off[k] <= 0.0 or lam_lo + lod_off[k] >= q else 1
            _sample_row(flat, tile[k] * stride, offsets, size0, mats, anchor, k, lod_off[k], px, py, lamw,
                        lr, lg, lb, la, m, two)
        op = opacity[k]
        code = blend_code[k]
        if code == BLEND_FIRST:
            for x in range(m):
                cr[x] = lr[x]
                cg[x] = lg[x]
                cb[x] = lb[x]
        elif code == BLEND_ALPHA:
            for x in range(m):
                a = la[x] * op
                cr[x] = blend_alpha(cr[x], lr[x], a)
                cg[x] = blend_alpha(cg[x], lg[x], a)
                cb[x] = blend_alpha(cb[x], lb[x], a)
        elif code == BLEND_DETAIL:
            for x in range(m):
                cr[x] = blend_detail(cr[x], lr[x])
                cg[x] = blend_detail(cg[x], lg[x])
                cb[x] = blend_detail(cb[x], lb[x])
        elif code == BLEND_OVERLAY:
            _overlay_row(cr, cg, cb, lr, lg, lb, la, op, m)
        elif code == BLEND_FINE or code == BLEND_COVER:  # the alpha faded to 0 (fine) or to 1 (cover)
            mr = mean[k, 0]
            mg = mean[k, 1]
            mb = mean[k, 2]
            off_k = lod_off[k] + fade_bias
            to = 1.0 if code == BLEND_COVER else 0.0
            for x in range(m):
                a = to + (la[x] * op - to) * fade(lamw[x] + off_k)
                nn = variance_norm(a)
                cr[x] = blend_variance(cr[x], lr[x], a, mr, nn)
                cg[x] = blend_variance(cg[x], lg[x], a, mg, nn)
                cb[x] = blend_variance(cb[x], lb[x], a, mb, nn)
        else:
            mr = mean[k, 0]
            mg = mean[k, 1]
            mb = mean[k, 2]
            for x in range(m):
                a = la[x] * op
                nn = variance_norm(a)
                cr[x] = blend_variance(cr[x], lr[x], a, mr, nn)
                cg[x] = blend_variance(cg[x], lg[x], a, mg, nn)
                cb[x] = blend_variance(cb[x], lb[x], a, mb, nn)
    return 0
