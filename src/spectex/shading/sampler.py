"""A CPU reference texture sampler with OpenGL's semantics.

This module is the executable form of sections 1-5 of the sampling
specification written down in ``docs/sampling.md`` (one texture: texels,
wrapping, filters, level of detail, anisotropy); the GLSL layer library
(``shading/shaders/spectex_layers.glsl``) leaves the same steps to the GPU's
texture unit, and the tests compare the two. It is the bottom of the
shading core: ``shading._layers`` samples each layer through it.

What it implements, from the OpenGL 4.6 core specification, section 8.14
("Texture Minification") and 8.15 ("Texture Magnification"):

* wrap modes ``REPEAT``, ``CLAMP_TO_EDGE`` and ``MIRRORED_REPEAT``, applied to
  integer texel coordinates as in the specification's table 8.20;
* texel centres at half-integers: a coordinate ``s`` in [0, 1] maps to
  ``u = s * width`` and the texel ``i`` covers ``[i, i + 1)``;
* filters ``NEAREST`` and ``LINEAR`` and the four mip-map minification
  filters ``NEAREST_MIPMAP_NEAREST``, ``LINEAR_MIPMAP_NEAREST``,
  ``NEAREST_MIPMAP_LINEAR`` and ``LINEAR_MIPMAP_LINEAR`` (trilinear);
* the level of detail from screen-space derivatives,
  ``rho = max(|d(u,v)/dx|, |d(u,v)/dy|)`` (Euclidean lengths, in texels of
  the base level), ``lambda = log2(rho) + bias`` clamped to
  ``[min_lod, max_lod]``; ``lambda <= 0`` selects the magnification filter;
* optional anisotropic filtering as recommended by
  ``EXT_texture_filter_anisotropic`` (core in OpenGL 4.6): ``N = min(ceil(Pmax /
  Pmin), max_anisotropy)`` samples along the major axis of the footprint at
  ``lambda = log2(Pmax / N)``.

The texels are the mip levels given (usually ``spectex.tiles.mip_chain`` of
a tile), optionally quantised to 8 bits the way an ``RGBA8`` texture stores
them, so that the CPU and the GPU sample identical data.

The hot loops are numba kernels (``parallel=True``, ``cache=True``),
compiled on first use, never at import.

References
----------
.. [1] M. Segal and K. Akeley, "The OpenGL Graphics System: A Specification
   (Version 4.6 Core Profile)", Khronos, 2019, sections 8.14-8.15.
.. [2] "EXT_texture_filter_anisotropic", OpenGL extension registry.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..tiles.mipmap import gl_level_shapes, quantize
from ._jit import jit as _jit
from ._jit import jit_inline as _jit_inline
from ._mip_texture import MAX_TEXELS, MipTexture, default_mip_chain, filter_code, wrap_code  # noqa: F401
from .constants import (
    DEFAULT_MAX_LOD,
    DEFAULT_MIN_LOD,
    FILTER_LINEAR,
    FILTER_LINEAR_MIPMAP_LINEAR,
    FILTER_LINEAR_MIPMAP_NEAREST,
    FILTER_NEAREST_MIPMAP_NEAREST,
    FILTERS,
    LOD_FLOOR,
    WRAP_CLAMP_TO_EDGE,
    WRAP_MODES,
    WRAP_REPEAT,
)

__all__ = [
    "WRAP_MODES",
    "FILTERS",
    "MipTexture",
    "sample",
    "level_of_detail",
    "gl_level_shapes",
    "quantize",
    "filter_code",
    "wrap_code",
]


def level_of_detail(dudx, dvdx, dudy, dvdy, *, bias=0.0, min_lod=DEFAULT_MIN_LOD, max_lod=DEFAULT_MAX_LOD):
    """OpenGL's level of detail from derivatives in texels of the base level.

    ``lambda = clamp(log2(max(hypot(dudx, dvdx), hypot(dudy, dvdy))) + bias,
    min_lod, max_lod)`` (OpenGL 4.6, equations 8.6-8.9, with the exact
    Euclidean lengths). Zero derivatives give ``min_lod``.
    """
    px = np.hypot(dudx, dvdx)
    py = np.hypot(dudy, dvdy)
    rho = np.maximum(px, py)
    with np.errstate(divide="ignore"):
        lam = np.log2(rho) + bias
    return np.clip(lam, min_lod, max_lod)


def sample(texture: MipTexture, s, t, *, dsdx=None, dtdx=None, dsdy=None, dtdy=None, lod=None):
    """Sample ``texture`` at normalised coordinates ``(s, t)`` as OpenGL would.

    Parameters
    ----------
    texture : MipTexture
        The texels and the sampler state.
    s, t : array_like
        Normalised texture coordinates (``s`` along the columns, ``t`` along
        the rows of level 0); broadcast together with the derivatives.
    dsdx, dtdx, dsdy, dtdy : array_like, optional
        Screen-space derivatives of ``s`` and ``t`` (as GLSL's ``textureGrad``);
        give all four or none.
    lod : array_like, optional
        An explicit level of detail (as GLSL's ``textureLod``); the texture's
        bias is still added and its clamps applied. Without derivatives and
        ``lod``, the level of detail is 0 (magnification, level 0).

    Returns
    -------
    ndarray, shape ``broadcast_shape + (4,)``, float32
        RGBA in [0, 1].
    """
    if not isinstance(texture, MipTexture):
        raise TypeError(f"texture must be a MipTexture, got {type(texture).__name__}")
    derivs = (dsdx, dtdx, dsdy, dtdy)
    given = [d is not None for d in derivs]
    if any(given) and not all(given):
        raise ValueError("give all four derivatives dsdx, dtdx, dsdy, dtdy or none")
    if all(given) and lod is not None:
        raise ValueError("give derivatives or lod, not both")
    arrays = [np.asarray(s, dtype=np.float64), np.asarray(t, dtype=np.float64)]
    if all(given):
        arrays += [np.asarray(d, dtype=np.float64) for d in derivs]
        mode = 1
    else:
        arrays.append(np.asarray(0.0 if lod is None else lod, dtype=np.float64))
        mode = 0
    for name, a in zip(("s", "t", "dsdx" if mode else "lod"), arrays):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite, got NaN or infinity")
    b = np.broadcast_arrays(*arrays)
    shape = b[0].shape
    flat = [np.ascontiguousarray(x.reshape(-1)) for x in b]
    out = np.empty((flat[0].size, 4), dtype=np.float32)
    if mode == 1:
        s_, t_, a, bb, c, d = flat
        lod_ = np.zeros(1)
    else:
        s_, t_, lod_ = flat
        a = bb = c = d = np.zeros(1)
    _sample_kernel(texture.data, texture.offsets, texture.widths, texture.heights, *texture.state(),
                  mode, s_, t_, a, bb, c, d, lod_, out)
    return out.reshape(shape + (4,))


# --------------------------------------------------------------------------
# numba kernels: the specification, one function per step. They take the
# flattened texel store of a MipTexture (data, offsets, widths, heights) and
# integer codes for the sampler state. Compiled on first use.
# --------------------------------------------------------------------------


@_jit
def wrap_index(i, size, mode):
    """Table 8.20: an integer texel coordinate wrapped into [0, size)."""
    if mode == WRAP_REPEAT:
        if (size & (size - 1)) == 0:
            return i & (size - 1)
        r = i % size
        return r + size if r < 0 else r
    if mode == WRAP_CLAMP_TO_EDGE:
        return min(max(i, 0), size - 1)
    m = i % (2 * size)
    if m < 0:
        m += 2 * size
    m -= size
    mir = m if m >= 0 else -(1 + m)
    return size - 1 - mir


@_jit_inline
def sample_level(data, base, offsets, widths, heights, d, s, t, linear, wrap_s, wrap_t):
    """Equations 8.10-8.13: one level, NEAREST or LINEAR; returns (r, g, b, a)."""
    w = widths[d]
    h = heights[d]
    off = base + offsets[d]
    u = s * w
    v = t * h
    if not linear:
        i = wrap_index(np.int64(math.floor(u)), w, wrap_s)
        j = wrap_index(np.int64(math.floor(v)), h, wrap_t)
        k = off + j * w + i
        return data[k, 0], data[k, 1], data[k, 2], data[k, 3]
    uu = u - 0.5
    vv = v - 0.5
    fu = math.floor(uu)
    fv = math.floor(vv)
    a = uu - fu
    b = vv - fv
    i0 = np.int64(fu)
    j0 = np.int64(fv)
    i1 = wrap_index(i0 + 1, w, wrap_s)
    j1 = wrap_index(j0 + 1, h, wrap_t)
    i0 = wrap_index(i0, w, wrap_s)
    j0 = wrap_index(j0, h, wrap_t)
    k00 = off + j0 * w + i0
    k10 = off + j0 * w + i1
    k01 = off + j1 * w + i0
    k11 = off + j1 * w + i1
    w00 = np.float32((1.0 - a) * (1.0 - b))
    w10 = np.float32(a * (1.0 - b))
    w01 = np.float32((1.0 - a) * b)
    w11 = np.float32(a * b)
    r = w00 * data[k00, 0] + w10 * data[k10, 0] + w01 * data[k01, 0] + w11 * data[k11, 0]
    g = w00 * data[k00, 1] + w10 * data[k10, 1] + w01 * data[k01, 1] + w11 * data[k11, 1]
    bl = w00 * data[k00, 2] + w10 * data[k10, 2] + w01 * data[k01, 2] + w11 * data[k11, 2]
    al = w00 * data[k00, 3] + w10 * data[k10, 3] + w01 * data[k01, 3] + w11 * data[k11, 3]
    return r, g, bl, al


@_jit_inline
def sample_at_lod(data, base, offsets, widths, heights, s, t, lam, min_filter, mag_filter, wrap_s, wrap_t):
    """Sections 8.14.3-8.15: filter selection and mip-map level(s) for a clamped lambda.

    Written with two level look-ups at most (one call site each), so that
    it inlines compactly.
    """
    q = widths.shape[0] - 1
    d1 = 0
    d2 = 0
    beta = 0.0
    if lam <= 0.0:
        lin = mag_filter == FILTER_LINEAR
    elif min_filter < FILTER_NEAREST_MIPMAP_NEAREST:
        lin = min_filter == FILTER_LINEAR
    else:
        lin = min_filter == FILTER_LINEAR_MIPMAP_NEAREST or min_filter == FILTER_LINEAR_MIPMAP_LINEAR
        if min_filter <= FILTER_LINEAR_MIPMAP_NEAREST:  # *_MIPMAP_NEAREST
            if lam > 0.5:
                d1 = min(np.int64(math.ceil(lam + 0.5)) - 1, q)
        elif lam >= q:
            d1 = q
        else:
            d1 = np.int64(math.floor(lam))
            d2 = d1 + 1
            beta = lam - d1
    r1, g1, b1, a1 = sample_level(data, base, offsets, widths, heights, d1, s, t, lin, wrap_s, wrap_t)
    if beta > 0.0:
        r2, g2, b2, a2 = sample_level(data, base, offsets, widths, heights, d2, s, t, lin, wrap_s, wrap_t)
        r1 += beta * (r2 - r1)
        g1 += beta * (g2 - g1)
        b1 += beta * (b2 - b1)
        a1 += beta * (a2 - a1)
    return r1, g1, b1, a1


@_jit_inline
def clamp_lod(lam, bias, min_lod, max_lod):
    lam = lam + bias
    return min(max(lam, min_lod), max_lod)


@_jit_inline
def anisotropic_footprint(widths, heights, min_filter, max_aniso, bias, min_lod, max_lod, dsdx, dtdx, dsdy, dtdy):
    """Level of detail and sample count from derivatives (8.14.1 and the anisotropic recipe).

    Returns ``(lam, n, ds, dt)``: the clamped level of detail, the number of
    samples ``n`` along the footprint's major axis and that axis's
    derivative ``(ds, dt)``. With ``max_aniso > 1`` and a mip-map
    minification filter, the EXT_texture_filter_anisotropic recommendation:
    ``N`` samples along the major axis at ``lambda = log2(Pmax / N)``;
    otherwise ``n = 1`` and ``lambda = log2(Pmax)``. Sample ``i`` of ``n``
    (1-based) lies at ``f = i / (n + 1) - 1/2`` times ``(ds, dt)`` from the
    centre (``f = 0`` for ``n = 1``). The one home of the recipe: the
    periodic and the stochastic samplers both call it.
    """
    w0 = widths[0]
    h0 = heights[0]
    dudx = dsdx * w0
    dvdx = dtdx * h0
    dudy = dsdy * w0
    dvdy = dtdy * h0
    px = math.sqrt(dudx * dudx + dvdx * dvdx)
    py = math.sqrt(dudy * dudy + dvdy * dvdy)
    pmax = max(px, py)
    n = np.int64(1)
    if max_aniso > 1.0 and min_filter >= FILTER_NEAREST_MIPMAP_NEAREST:
        pmin = min(px, py)
        n_max = np.int64(math.floor(max_aniso))
        if pmin * n_max <= pmax:
            n = n_max
        else:
            n = min(np.int64(math.ceil(pmax / pmin)), n_max)
    lam = clamp_lod(math.log2(max(pmax / n, LOD_FLOOR)), bias, min_lod, max_lod)
    if px >= py:
        return lam, n, dsdx, dtdx
    return lam, n, dsdy, dtdy


@_jit_inline
def sample_grad(data, base, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso,
                bias, min_lod, max_lod, s, t, dsdx, dtdx, dsdy, dtdy):
    """Level of detail from derivatives (8.14.1), then :func:`sample_at_lod`.

    :func:`anisotropic_footprint` gives the level and the ``n`` sample
    points along the major axis; their RGBA results are averaged. (One call
    site of :func:`sample_at_lod`, so that it inlines compactly.)
    """
    lam, n, ds, dt = anisotropic_footprint(widths, heights, min_filter, max_aniso, bias, min_lod, max_lod,
                                           dsdx, dtdx, dsdy, dtdy)
    r = 0.0
    g = 0.0
    b = 0.0
    a = 0.0
    for i in range(1, n + 1):
        f = i / (n + 1.0) - 0.5 if n > 1 else 0.0
        r1, g1, b1, a1 = sample_at_lod(data, base, offsets, widths, heights, s + f * ds, t + f * dt,
                                       lam, min_filter, mag_filter, wrap_s, wrap_t)
        r += r1
        g += g1
        b += b1
        a += a1
    inv = 1.0 / n
    return r * inv, g * inv, b * inv, a * inv


@numba.njit(cache=True, parallel=True, nogil=True)
def _sample_kernel(data, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso,
                   bias, min_lod, max_lod, mode, s, t, dsdx, dtdx, dsdy, dtdy, lod, out):
    n = s.shape[0]
    for k in numba.prange(n):
        if mode == 1:
            r, g, b, a = sample_grad(data, 0, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter,
                                     max_aniso, bias, min_lod, max_lod, s[k], t[k], dsdx[k], dtdx[k],
                                     dsdy[k], dtdy[k])
        else:
            lam = clamp_lod(lod[k], bias, min_lod, max_lod)
            r, g, b, a = sample_at_lod(data, 0, offsets, widths, heights, s[k], t[k], lam, min_filter,
                                       mag_filter, wrap_s, wrap_t)
        out[k, 0] = r
        out[k, 1] = g
        out[k, 2] = b
        out[k, 3] = a
