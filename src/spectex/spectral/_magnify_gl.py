"""Octaves by magnification on the GPU, in multiple passes (Blythe et al. 1999, 6.21.3).

The seed's own route to :func:`spectex.spectral.magnify`, on OpenGL 3.3 core
through moderngl. It computes the same circular convolution of the
zero-stuffed input with the discretised filter ``h`` (see
:mod:`spectex.spectral._octaves`)::

    y[p] = sum_k x[k mod n] h[p - k m]

The filter covers ``T`` input texels along each axis (``T`` is
:func:`~spectex.spectral.filter_passes`), so ``h`` fits in a window of
``T m`` output texels, ``start <= p - k m < start + T m``. Two input texels
``T`` apart therefore have disjoint windows, and the texels of one residue
class ``k = a (mod T)`` can be evaluated in the same pass without
interfering with each other: the seed's observation.

Per axis, and as the product of two axes in 2-D:

1. *Redistribution.* The input's texels are redistributed into ``T x T``
   sub-textures, sub-texture ``(a, b)`` holding
   ``x[(a + T i) mod n0, (b + T j) mod n1]``. When ``T`` divides ``n`` these
   are the seed's ``n/T x n/T`` textures (A-D for its 4 x 4 input and 2 x 2
   footprint), one period each, and ``GL_REPEAT`` wraps them as the octave
   wraps. Otherwise such a sequence repeats only every ``n / gcd(n, T)``
   texels (up to ``T^2`` times the input in all), so the sub-texture holds
   instead just the ``i`` that the pass reaches across the output, about
   ``n / T + 2``, and the wrap happens in the redistribution's ``mod n``.
2. *Filter texture.* ``h`` over its window, ``T m0 x T m1`` float texels
   (the outer product of the two axes' filters), ``GL_NEAREST`` and
   ``GL_REPEAT``.
3. *One pass per footprint position* ``(a, b)``, offset
   ``c = (a m0 + start0, b m1 + start1)`` output texels:

   a. draw the filter texture, shifted by ``c`` and repeated, into the alpha
      plane of a float scratch framebuffer (blending off);
   b. draw sub-texture ``(a, b)``, magnified ``T m`` times with
      ``GL_NEAREST`` and shifted by ``c``, with blending ``GL_FUNC_ADD``,
      source factor ``GL_DST_ALPHA`` and destination factor ``GL_ZERO``:
      colour = texel x filter weight;
   c. accumulate the scratch framebuffer into a float32 accumulation
      framebuffer with additive blending (``GL_FUNC_ADD``, ``GL_ONE``,
      ``GL_ONE``), which stands in for the accumulation buffer that core
      profiles no longer have.

So the pass count is ``T^2`` for a ``T x T`` footprint, whatever the input
and output sizes; each pass touches every output texel three times. With
``multiply='shader'`` steps a-c are one draw instead: the fragment shader
multiplies the sub-texture's texel by the filter texture's weight (same
offsets, same ``GL_NEAREST`` lookups) and the result goes straight into the
accumulation framebuffer with the additive blend; the same passes, one
third of the fill. The colour planes carry three channels at a time (the
alpha plane holds the filter), so an image with ``C`` channels takes
``ceil(C / 3)`` channel groups of ``T^2`` passes each. The arithmetic is
float32 throughout.

All coordinates here are array indices: row ``i`` of every array is GL's
``y = i``, both for the textures uploaded and for the framebuffer read back,
so no flip between top-down images and GL's bottom-left origin is needed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._gl import create_context
from .._validate import check_choice
from ._filters import _check_filter, _check_image, _factors, discrete_filter, filter_passes

#: How a pass multiplies texel by weight: the seed's blend, or the shader.
MULTIPLY = ("blend", "shader")

_VERTEX = """
#version 330 core
in vec2 corner;          // (0, 0) .. (1, 1): the output's corners
uniform vec2 size;       // output size in texels (x = columns, y = rows)
uniform vec2 offset;     // the pass's offset c, in output texels
uniform vec2 period;     // output texels covered by one period of the texture drawn
out vec2 uv;
void main() {
    // Texture coordinates of the rectangle's corners, shifted by the pass's
    // offset: at the centre of output texel p, uv = (p + 1/2 - c) / period.
    uv = (corner * size - offset) / period;
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

# Step a: the filter function into the alpha plane.
_FILTER_FRAGMENT = """
#version 330 core
uniform sampler2D filter_texture;
in vec2 uv;
out vec4 color;
void main() {
    color = vec4(0.0, 0.0, 0.0, texture(filter_texture, uv).r);
}
"""

# Step b: the sub-texture, blended with (GL_DST_ALPHA, GL_ZERO).
_TEXEL_FRAGMENT = """
#version 330 core
uniform sampler2D sub_texture;
in vec2 uv;
out vec4 color;
void main() {
    color = vec4(texture(sub_texture, uv).rgb, 1.0);
}
"""

# Steps a-c in one draw (multiply='shader'): texel times weight, blended
# (GL_ONE, GL_ONE) into the accumulation framebuffer.
_PRODUCT_VERTEX = """
#version 330 core
in vec2 corner;
uniform vec2 size;
uniform vec2 offset;         // of the sub-texture
uniform vec2 period;
uniform vec2 filter_offset;  // of the filter texture
uniform vec2 filter_period;
out vec2 uv;
out vec2 uv_filter;
void main() {
    uv = (corner * size - offset) / period;
    uv_filter = (corner * size - filter_offset) / filter_period;
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

_PRODUCT_FRAGMENT = """
#version 330 core
uniform sampler2D sub_texture;
uniform sampler2D filter_texture;
in vec2 uv;
in vec2 uv_filter;
out vec4 color;
void main() {
    float w = texture(filter_texture, uv_filter).r;
    color = vec4(texture(sub_texture, uv).rgb * w, w);
}
"""

# Step c: the scratch framebuffer, blended with (GL_ONE, GL_ONE) into the
# accumulation framebuffer (texel for texel: same size, no sampling).
_ACCUMULATE_FRAGMENT = """
#version 330 core
uniform sampler2D scratch;
out vec4 color;
void main() {
    color = texelFetch(scratch, ivec2(gl_FragCoord.xy), 0);
}
"""


@dataclass(frozen=True)
class GLMagnification:
    """What :func:`magnify_gl` made, and how many passes it took.

    Attributes
    ----------
    image : ndarray
        The magnified image, as :func:`~spectex.spectral.magnify` returns it.
    passes : int
        Accumulation passes per channel group: ``footprint ** 2``, one per
        position in the filter's footprint (one per sub-texture).
    footprint : int
        ``T``, the input texels under the filter along each axis.
    channel_groups : int
        Groups of up to three channels, each made in ``passes`` passes.
    draws : int
        Draw calls made: per pass and channel group, three
        (``multiply='blend'``) or one (``multiply='shader'``).
    weight_sum : ndarray of float32, shape (H, W)
        The accumulated alpha plane: the sum of the filter weights each
        output texel received, 1 up to rounding (the filter is normalised
        per phase). A missing or misplaced pass shows here.
    """

    image: np.ndarray
    passes: int
    footprint: int
    channel_groups: int
    draws: int
    weight_sum: np.ndarray


def _make_current(ctx):
    """Make ``ctx`` the current context, and leave it current.

    moderngl sends every call to the current context, whichever context
    object it is made through, and making a second context makes that one
    current. ``with ctx:`` would not do here: on leaving, glcontext's EGL
    backend makes *no* context current, not the previous one.
    """
    ctx.__enter__()


_DEFAULT: list = []


def default_context():
    """The context :func:`magnify_gl` uses when given none: made once, kept.

    Making a context makes it the current one, and moderngl sends every call
    to the current context: code that holds another context should pass it
    as ``ctx``, or make it current again before its own calls.
    """
    if not _DEFAULT:
        _DEFAULT.append(create_context(what="magnify(backend='gl')"))
    return _DEFAULT[0]


class _Programs:
    """The four programs and their rectangles, compiled once per context."""

    def __init__(self, ctx):
        self.ctx = ctx
        corners = np.array([0, 0, 1, 0, 0, 1, 1, 1], dtype="f4")
        self.vbo = ctx.buffer(corners.tobytes())
        self.filter = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FILTER_FRAGMENT)
        self.texel = ctx.program(vertex_shader=_VERTEX, fragment_shader=_TEXEL_FRAGMENT)
        self.accumulate = ctx.program(vertex_shader=_VERTEX, fragment_shader=_ACCUMULATE_FRAGMENT)
        self.product = ctx.program(vertex_shader=_PRODUCT_VERTEX, fragment_shader=_PRODUCT_FRAGMENT)
        self.vaos = {
            name: ctx.vertex_array(prog, [(self.vbo, "2f", "corner")])
            for name, prog in (("filter", self.filter), ("texel", self.texel),
                               ("accumulate", self.accumulate), ("product", self.product))
        }
        # The default framebuffer, bound before our framebuffers are released
        # (moderngl re-binds the last one used when it makes new objects).
        self.parking = ctx.detect_framebuffer(0)


_PROGRAMS: dict = {}


def _programs(ctx) -> _Programs:
    entry = _PROGRAMS.get(id(ctx))
    if entry is None or entry.ctx is not ctx:
        entry = _PROGRAMS[id(ctx)] = _Programs(ctx)
    return entry


def _filter_window(kernel: str, m: int, sigma: float, footprint: int):
    """``(h, start)``: the discretised kernel over its window of ``T m`` texels."""
    taps, start = discrete_filter(kernel, m, sigma=sigma)
    window = footprint * m
    if taps.size > window:  # cannot happen: the taps lie within T m texels
        raise AssertionError(f"kernel {kernel!r} has {taps.size} taps for a window of {window}")
    h = np.zeros(window)
    h[:taps.size] = taps
    return h, start


def pass_offsets(footprint: int, factor, start) -> list:
    """The passes: ``((a, b), (c0, c1))`` per footprint position.

    Pass ``(a, b)`` draws sub-texture ``(a, b)`` and the filter shifted by
    ``c = (a m0 + start0, b m1 + start1)`` output texels (rows, columns).
    """
    m0, m1 = factor
    s0, s1 = start
    return [((a, b), (a * m0 + s0, b * m1 + s1))
            for a in range(footprint) for b in range(footprint)]


def _axis_texels(n: int, t: int, a: int, m: int, start: int):
    """Input texels of sub-texture ``a`` along one axis, and the first ``i``."""
    if n % t == 0:  # one period; GL_REPEAT does the wrapping
        return (a + t * np.arange(n // t)) % n, 0
    # Output texel p reads i = floor((p - c) / (T m)), c = a m + start: the
    # i for p = 0 .. n m - 1, in order.
    c = a * m + start
    first, last = -c // (t * m), (n * m - 1 - c) // (t * m)
    return (a + t * np.arange(first, last + 1)) % n, first


def redistribute(x: np.ndarray, footprint: int, factor=(1, 1), start=(0, 0)) -> dict:
    """The input's texels redistributed into ``T x T`` sub-textures.

    Returns ``{(a, b): (sub, origin)}`` with ``sub[i - origin[0], j -
    origin[1]] = x[(a + T i) mod n0, (b + T j) mod n1]``. Along an axis that
    ``T`` divides, ``sub`` is one period, ``n / T`` texels from ``i = 0``
    (``GL_REPEAT`` wraps it); along any other, it holds the ``i`` that pass
    ``(a, b)`` reaches across the output (see :func:`pass_offsets` for
    ``factor`` and ``start``), from ``i = origin``.
    """
    t = footprint
    n0, n1 = x.shape[:2]
    m0, m1 = factor
    s0, s1 = start
    subs = {}
    for a in range(t):
        rows, o0 = _axis_texels(n0, t, a, m0, s0)
        for b in range(t):
            cols, o1 = _axis_texels(n1, t, b, m1, s1)
            subs[a, b] = (np.ascontiguousarray(x[rows][:, cols]), (o0, o1))
    return subs


def magnify_gl(image, factor, *, kernel: str = "bspline", sigma: float = 0.5,
               multiply: str = "blend", ctx=None) -> GLMagnification:
    """Magnify a small periodic image on the GPU, the seed's multi-pass way.

    The same result as :func:`~spectex.spectral.magnify` (to float32
    precision), made as the seed makes it: the input redistributed into
    ``T x T`` sub-textures, a filter texture, and one pass per footprint
    position, each a ``GL_NEAREST``-magnified sub-texture times the filter
    weights (blending with ``GL_DST_ALPHA, GL_ZERO``), accumulated into a
    float32 framebuffer with additive blending. See the module docstring.

    Parameters
    ----------
    image : ndarray, shape (n0, n1) or (n0, n1, C)
        The small image, one period of a periodic signal.
    factor : int or (int, int)
        Magnification ``m`` along rows and columns.
    kernel : {'box', 'tent', 'bspline', 'catmull-rom', 'gaussian'}
        The magnification kernel, as for :func:`~spectex.spectral.magnify`.
    sigma : float
        The Gaussian's standard deviation in input texels.
    multiply : {'blend', 'shader'}
        ``'blend'``: the seed's way, three draws per pass (filter into the
        alpha plane; sub-texture blended with ``GL_DST_ALPHA, GL_ZERO``;
        accumulate). ``'shader'``: the product in the fragment shader, one
        draw per pass. Same passes, offsets and lookups; the same numbers
        to float32 precision (the same bits on llvmpipe).
    ctx : moderngl.Context, optional
        An OpenGL 3.3 context; by default one headless EGL context, made on
        first use and kept. It is made current and stays current afterwards
        (moderngl sends every call to the current context); blending is left
        disabled.

    Returns
    -------
    GLMagnification
        ``image`` has shape ``(n0 m0, n1 m1)`` or ``(n0 m0, n1 m1, C)`` and
        the input's dtype (float32 or float64; other dtypes give float64);
        its values are computed in float32. ``passes`` is ``T^2``.

    Raises
    ------
    OSError
        If no OpenGL context can be made (see :func:`create_context`).
    ValueError
        For the inputs :func:`~spectex.spectral.magnify` refuses, and for an
        output or filter texture larger than the context's
        ``GL_MAX_TEXTURE_SIZE``.

    References
    ----------
    D. Blythe et al., "Advanced Graphics Programming Techniques Using
    OpenGL", SIGGRAPH 1999 course, section 6.21.3.
    """
    kernel, sigma = _check_filter(kernel, sigma)
    multiply = check_choice("multiply", multiply, MULTIPLY)
    m0, m1 = _factors(factor)
    x = _check_image(image)
    out_dtype = x.dtype
    planes = x[:, :, None] if x.ndim == 2 else x
    n0, n1, channels = planes.shape
    t = filter_passes(kernel, sigma=sigma)
    if ctx is None:
        ctx = default_context()
    _make_current(ctx)
    limit = int(ctx.info["GL_MAX_TEXTURE_SIZE"])
    big0, big1 = n0 * m0, n1 * m1
    if max(big0, big1) > limit:
        raise ValueError(f"image {n0}x{n1} magnified {m0}x{m1} gives {big0}x{big1}, over "
                         f"this context's GL_MAX_TEXTURE_SIZE {limit}")
    if t * max(m0, m1) > limit:
        raise ValueError(f"factor {factor!r} needs a filter texture of {t * m0}x{t * m1} "
                         f"texels, over this context's GL_MAX_TEXTURE_SIZE {limit}")

    h0, s0 = _filter_window(kernel, m0, sigma, t)
    h1, s1 = (h0, s0) if m1 == m0 else _filter_window(kernel, m1, sigma, t)
    passes = pass_offsets(t, (m0, m1), (s0, s1))
    groups = -(-channels // 3)
    result = np.empty((big0, big1, channels), dtype=np.float32)
    weight_sum = None
    draws = 0

    import moderngl

    progs = _programs(ctx)
    made = []  # GL objects to release

    def texture(size, components, data=None):
        tex = ctx.texture(size, components, data, dtype="f4")
        made.append(tex)
        return tex

    try:
        filt = texture((t * m1, t * m0), 1, np.outer(h0, h1).astype("f4").tobytes())
        filt.filter = (moderngl.NEAREST, moderngl.NEAREST)
        filt.repeat_x = filt.repeat_y = True
        fbos = {}
        for name in ("accumulation", "scratch") if multiply == "blend" else ("accumulation",):
            fbos[name] = ctx.framebuffer(color_attachments=[texture((big1, big0), 4)])
            fbos[name].viewport = (0, 0, big1, big0)
            made.append(fbos[name])
        accum_fbo, scratch_fbo = fbos["accumulation"], fbos.get("scratch")
        for prog in (progs.filter, progs.texel, progs.product):
            prog["size"].value = (big1, big0)
        progs.filter["filter_texture"].value = 0
        progs.product["filter_texture"].value = 0
        progs.texel["sub_texture"].value = 1
        progs.product["sub_texture"].value = 1
        progs.accumulate["scratch"].value = 2
        progs.filter["period"].value = (t * m1, t * m0)
        progs.product["filter_period"].value = (t * m1, t * m0)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.blend_equation = moderngl.FUNC_ADD
        filt.use(location=0)
        if scratch_fbo is not None:
            scratch_fbo.color_attachments[0].use(location=2)

        for g in range(groups):
            chunk = np.zeros((n0, n1, 3), dtype=np.float32)
            chunk[:, :, :min(3, channels - 3 * g)] = planes[:, :, 3 * g:3 * g + 3]
            subs = {}
            for key, (sub, origin) in redistribute(chunk, t, (m0, m1), (s0, s1)).items():
                tex = texture((sub.shape[1], sub.shape[0]), 3, sub.tobytes())
                tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
                tex.repeat_x = tex.repeat_y = True
                subs[key] = tex, origin
            accum_fbo.clear(0.0, 0.0, 0.0, 0.0)
            for key, (c0, c1) in passes:
                tex, (o0, o1) = subs[key]
                tex.use(location=1)
                # The sub-texture's texel i spans output texels c + i T m ..
                # c + (i + 1) T m - 1: GL_NEAREST magnification by T m.
                sub_offset = (c1 + o1 * t * m1, c0 + o0 * t * m0)
                sub_period = (t * m1 * tex.width, t * m0 * tex.height)
                if multiply == "shader":
                    # a-c in one draw: texel times weight, added in.
                    accum_fbo.use()
                    ctx.enable(moderngl.BLEND)
                    ctx.blend_func = moderngl.ONE, moderngl.ONE
                    progs.product["offset"].value = sub_offset
                    progs.product["period"].value = sub_period
                    progs.product["filter_offset"].value = (c1, c0)
                    progs.vaos["product"].render(moderngl.TRIANGLE_STRIP)
                    draws += 1
                    continue
                # a. the filter into the alpha plane, at the pass's offset.
                scratch_fbo.use()
                ctx.disable(moderngl.BLEND)
                progs.filter["offset"].value = (c1, c0)
                progs.vaos["filter"].render(moderngl.TRIANGLE_STRIP)
                # b. the sub-texture, NEAREST-magnified, times the alpha plane.
                ctx.enable(moderngl.BLEND)
                ctx.blend_func = moderngl.DST_ALPHA, moderngl.ZERO
                progs.texel["offset"].value = sub_offset
                progs.texel["period"].value = sub_period
                progs.vaos["texel"].render(moderngl.TRIANGLE_STRIP)
                # c. accumulate: additive blending into the float32 framebuffer.
                accum_fbo.use()
                ctx.blend_func = moderngl.ONE, moderngl.ONE
                progs.vaos["accumulate"].render(moderngl.TRIANGLE_STRIP)
                draws += 3
            data = np.frombuffer(accum_fbo.read(components=4, dtype="f4"), dtype=np.float32)
            data = data.reshape(big0, big1, 4)
            k = min(3, channels - 3 * g)
            result[:, :, 3 * g:3 * g + k] = data[:, :, :k]
            if weight_sum is None:
                weight_sum = data[:, :, 3].copy()
    finally:
        ctx.disable(moderngl.BLEND)
        ctx.blend_func = moderngl.ONE, moderngl.ZERO
        progs.parking.use()
        for obj in reversed(made):
            obj.release()

    image_out = result[:, :, 0] if x.ndim == 2 else result
    return GLMagnification(
        image=np.ascontiguousarray(image_out, dtype=out_dtype),
        passes=len(passes),
        footprint=t,
        channel_groups=groups,
        draws=draws,
        weight_sum=weight_sum,
    )
