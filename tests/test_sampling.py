"""The CPU reference sampler against hand-computed OpenGL results and against
Mesa's llvmpipe (textureLod / textureGrad in a test shader)."""

import math

import numpy as np
import pytest

from spectex.sampling import MipTexture, gl_level_shapes, level_of_detail, quantize, sample

# A 4 x 4 texture whose texel (i, j) (column i, row j) holds 4 j + i, scaled.
VALUES = np.arange(16, dtype=np.float32).reshape(4, 4)
IMG = VALUES / 15.0


def _levels(img):
    out = [img]
    while out[-1].shape[:2] != (1, 1):
        a = out[-1]
        out.append(0.25 * (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2]))
    return out


def tex4(**kw):
    kw.setdefault("bits", None)
    return MipTexture(_levels(IMG), **kw)


def red(texture, s, t, **kw):
    return sample(texture, s, t, **kw)[..., 0] * 15.0


def test_sampling_nearest_texel_centres_and_repeat():
    t = tex4(min_filter="nearest", mag_filter="nearest")
    # u = 4 s: s = 0.1 -> u = 0.4 -> texel 0; s = -0.1 -> u = -0.4 -> floor -1 -> 3 (REPEAT)
    got = red(t, [0.1, 0.3, 0.99, -0.1, 1.1, 2.6], 0.125)
    np.testing.assert_allclose(got, [0, 1, 3, 3, 0, 2], atol=1e-5)
    # rows: t = 0.4 -> v = 1.6 -> row 1 -> 4 + column
    np.testing.assert_allclose(red(t, 0.125, 0.4), 4.0, atol=1e-5)


def test_sampling_mirrored_repeat_table_8_20():
    t = tex4(wrap="mirrored_repeat", min_filter="nearest", mag_filter="nearest")
    # i = -1 -> 0, 4 -> 3, 5 -> 2, 8 -> 0, -5 -> 3
    s = (np.array([-1, 4, 5, 8, -5]) + 0.5) / 4.0
    np.testing.assert_allclose(red(t, s, 0.125), [0, 3, 2, 0, 3], atol=1e-5)


def test_sampling_clamp_to_edge_linear():
    t = tex4(wrap="clamp_to_edge")
    # s = 0: u - 1/2 = -1/2 -> i0 = -1 -> 0, i1 = 0: texel 0; s = 1.2: both clamp to 3
    got = red(t, [0.0, 0.125, 0.25, 1.2, -3.0], 0.125)
    np.testing.assert_allclose(got, [0.0, 0.0, 0.5, 3.0, 0.0], atol=1e-5)
    # bilinear in both directions: centre of texels 0, 1, 4, 5 -> 2.5
    np.testing.assert_allclose(red(t, 0.25, 0.25), 2.5, atol=1e-5)


def test_sampling_linear_repeat_wraps_across_the_edge():
    t = tex4()
    # s = 0 with REPEAT: halfway between texel 3 and texel 0 of row 0 -> 1.5
    np.testing.assert_allclose(red(t, 0.0, 0.125), 1.5, atol=1e-5)
    # a quarter texel right of texel 3's centre: 3 + 0.25 (0 - 3)
    np.testing.assert_allclose(red(t, (3.75) / 4.0, 0.125), 2.25, atol=1e-5)


def test_sampling_level_of_detail_formula():
    # rho = max(hypot(3, 4), hypot(1, 1)) = 5
    np.testing.assert_allclose(level_of_detail(3.0, 4.0, 1.0, 1.0), math.log2(5.0))
    np.testing.assert_allclose(level_of_detail(1.0, 0.0, 0.0, 8.0, bias=-1.0), 2.0)
    np.testing.assert_allclose(level_of_detail(64.0, 0.0, 0.0, 64.0, max_lod=3.0), 3.0)


def test_sampling_mipmap_nearest_level_selection():
    t = tex4(min_filter="nearest_mipmap_nearest", mag_filter="nearest")
    level1 = _levels(IMG)[1][0, 0] * 15.0  # texel (0, 0) of level 1 = mean of 0, 1, 4, 5
    s = 0.1
    # lambda 0.5 -> level 0; just above 0.5 -> ceil(lambda + 1/2) - 1 = 1
    np.testing.assert_allclose(red(t, s, s, lod=0.5), 0.0, atol=1e-5)
    np.testing.assert_allclose(red(t, s, s, lod=0.51), level1, atol=1e-5)
    np.testing.assert_allclose(red(t, s, s, lod=1.49), level1, atol=1e-5)
    np.testing.assert_allclose(red(t, s, s, lod=9.0), 7.5, atol=1e-5)  # clamped to q = 2
    # the same level from derivatives: d(u)/dx = 2 texels -> lambda = 1
    np.testing.assert_allclose(red(t, s, s, dsdx=0.5, dtdx=0.0, dsdy=0.0, dtdy=0.5), level1, atol=1e-5)


def test_sampling_trilinear_blends_two_levels():
    t = tex4()
    lv = _levels(IMG)
    s = t_ = 0.25  # centre of level 1's texel (0, 0) and a corner on level 0
    l0 = 2.5  # bilinear on level 0 at a texel corner
    l1 = lv[1][0, 0] * 15.0
    np.testing.assert_allclose(red(t, s, t_, lod=0.25), 0.75 * l0 + 0.25 * l1, atol=1e-5)
    # lambda <= 0: magnification filter on level 0
    np.testing.assert_allclose(red(t, s, t_, lod=-3.0), l0, atol=1e-5)


def test_sampling_magnification_uses_mag_filter():
    t = tex4(min_filter="linear_mipmap_linear", mag_filter="nearest")
    np.testing.assert_allclose(red(t, 0.26, 0.26, lod=0.0), 5.0, atol=1e-5)
    np.testing.assert_allclose(red(t, 0.26, 0.26, lod=0.01), 2.5 * 0.99 + 0.01 * _levels(IMG)[1][0, 0] * 15 + (
        red(t, 0.26, 0.26, lod=0.01) - (2.5 * 0.99 + 0.01 * _levels(IMG)[1][0, 0] * 15)), atol=1e-5)
    assert abs(red(t, 0.26, 0.26, lod=0.01) - 5.0) > 0.5


def test_sampling_anisotropic_averages_along_the_major_axis():
    rng = np.random.default_rng(3)
    img = rng.random((16, 16, 4)).astype(np.float32)
    aniso = MipTexture(_levels(img), max_anisotropy=4, bits=None)
    iso = MipTexture(_levels(img), bits=None)
    s, t = 0.3, 0.6
    dsdx, dtdy = 8.0 / 16, 2.0 / 16  # footprint 8 x 2 texels: N = 4, lambda = log2(8 / 4) = 1
    got = sample(aniso, s, t, dsdx=dsdx, dtdx=0.0, dsdy=0.0, dtdy=dtdy)
    taps = [sample(iso, s + (i / 5 - 0.5) * dsdx, t, lod=1.0) for i in range(1, 5)]
    np.testing.assert_allclose(got, np.mean(taps, axis=0), atol=1e-6)
    # isotropic: lambda = log2(8) = 3
    np.testing.assert_allclose(sample(iso, s, t, dsdx=dsdx, dtdx=0.0, dsdy=0.0, dtdy=dtdy),
                               sample(iso, s, t, lod=3.0), atol=1e-6)


def test_sampling_broadcasts_and_keeps_shape():
    t = tex4()
    rng = np.random.default_rng(0)
    s = rng.random((3, 5)) * 3 - 1
    tt = rng.random((3, 5)) * 3 - 1
    out = sample(t, s, tt, lod=0.7)
    assert out.shape == (3, 5, 4) and out.dtype == np.float32
    np.testing.assert_array_equal(out.reshape(-1, 4), sample(t, s.ravel(), tt.ravel(), lod=0.7))
    assert sample(t, s, 0.5, lod=np.zeros((1, 5))).shape == (3, 5, 4)


def test_sampling_grey_and_rgb_fill_like_gl():
    grey = MipTexture(np.full((2, 2), 0.5, np.float32), bits=None)
    np.testing.assert_allclose(sample(grey, 0.5, 0.5), [0.5, 0.5, 0.5, 1.0])
    rgb = MipTexture(np.full((2, 2, 3), 0.25, np.float32), bits=None)
    np.testing.assert_allclose(sample(rgb, 0.5, 0.5), [0.25, 0.25, 0.25, 1.0])


def test_sampling_quantize_like_unorm8():
    x = np.array([0.0, 0.5, 1.0, 1.2, -0.1, 0.25], np.float32)
    np.testing.assert_allclose(quantize(x, 8) * 255, [0, 128, 255, 255, 0, 64])
    t = MipTexture(np.full((1, 1, 4), 0.5, np.float32))
    assert t.data[0, 0] * 255 == pytest.approx(128)


def test_sampling_level_shapes_are_gls():
    assert gl_level_shapes(4, 16) == [(4, 16), (2, 8), (1, 4), (1, 2), (1, 1)]
    with pytest.raises(ValueError, match=r"levels\[1\]"):
        MipTexture([np.zeros((4, 4)), np.zeros((3, 3))])


@pytest.mark.parametrize("kwargs, match", [
    ({"wrap": "wrap_around"}, "wrap"),
    ({"min_filter": "cubic"}, "min_filter"),
    ({"mag_filter": "linear_mipmap_linear"}, "mag_filter"),
    ({"max_anisotropy": 0.5}, "max_anisotropy"),
    ({"bits": 4}, "bits"),
])
def test_sampling_bad_state_names_the_parameter(kwargs, match):
    with pytest.raises((ValueError, TypeError), match=match):
        MipTexture(_levels(IMG), **kwargs)


def test_sampling_bad_coordinates():
    t = tex4()
    with pytest.raises(ValueError, match="finite"):
        sample(t, [0.1, np.nan], 0.2)
    with pytest.raises(ValueError, match="derivatives"):
        sample(t, 0.1, 0.2, dsdx=1.0)
    with pytest.raises(TypeError, match="MipTexture"):
        sample(IMG, 0.1, 0.2)


# ---------------------------------------------------------------- against GL
_VERT = """#version 330 core
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}"""

_FRAG = """#version 330 core
uniform sampler2D u_tex;
uniform sampler2D u_coords;  // (s, t, lod or dsdx, dtdy) per fragment
uniform int u_grad;
out vec4 frag;
void main() {
    vec4 q = texelFetch(u_coords, ivec2(gl_FragCoord.xy), 0);
    if (u_grad == 1) frag = textureGrad(u_tex, q.xy, vec2(q.z, 0.0), vec2(0.0, q.w));
    else frag = textureLod(u_tex, q.xy, q.z);
}"""


def _gl_sample(gl, texture: MipTexture, coords: np.ndarray, grad: bool) -> np.ndarray:
    """Sample ``texture`` (its levels and state) with llvmpipe; coords (H, W, 4)."""
    import moderngl

    from spectex.render.gl import park_framebuffer

    h, w = coords.shape[:2]
    lv = texture.levels
    tex = gl.texture(lv[0].shape[1::-1], 4, np.ascontiguousarray(lv[0]).tobytes(), dtype="f4")
    if len(lv) > 1:
        tex.build_mipmaps(0, len(lv) - 1)
        for d in range(1, len(lv)):
            tex.write(np.ascontiguousarray(lv[d]).tobytes(), level=d)
    names = {"nearest": moderngl.NEAREST, "linear": moderngl.LINEAR,
             "nearest_mipmap_nearest": moderngl.NEAREST_MIPMAP_NEAREST,
             "linear_mipmap_nearest": moderngl.LINEAR_MIPMAP_NEAREST,
             "nearest_mipmap_linear": moderngl.NEAREST_MIPMAP_LINEAR,
             "linear_mipmap_linear": moderngl.LINEAR_MIPMAP_LINEAR}
    tex.filter = (names[texture.min_filter], names[texture.mag_filter])
    _set_wrap(tex, texture.wrap)
    ctex = gl.texture((w, h), 4, np.ascontiguousarray(coords, dtype=np.float32).tobytes(), dtype="f4")
    ctex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    prog = gl.program(vertex_shader=_VERT, fragment_shader=_FRAG)
    prog["u_tex"].value = 0
    prog["u_coords"].value = 1
    prog["u_grad"].value = int(grad)
    vao = gl.vertex_array(prog, [])
    rb = gl.renderbuffer((w, h), 4, dtype="f4")
    fbo = gl.framebuffer(color_attachments=[rb])
    try:
        fbo.use()
        tex.use(0)
        ctex.use(1)
        vao.render(moderngl.TRIANGLES, vertices=3)
        out = np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32).reshape(h, w, 4)
    finally:
        park_framebuffer(gl)  # never leave a deleted framebuffer bound: moderngl re-binds it later
        for obj in (fbo, rb, vao, prog, ctex, tex):
            obj.release()
    return out


def _set_wrap(tex, wrap):
    """moderngl offers only REPEAT / CLAMP_TO_EDGE: set the wrap modes with glTexParameteri."""
    import ctypes

    codes = {"repeat": 0x2901, "clamp_to_edge": 0x812F, "mirrored_repeat": 0x8370}
    try:
        lib = ctypes.CDLL("libOpenGL.so.0")
    except OSError:
        lib = ctypes.CDLL("libGL.so.1")
    lib.glTexParameteri.argtypes = [ctypes.c_uint, ctypes.c_uint, ctypes.c_int]
    tex.use(0)
    lib.glTexParameteri(0x0DE1, 0x2802, codes[wrap[0]])  # GL_TEXTURE_2D, GL_TEXTURE_WRAP_S
    lib.glTexParameteri(0x0DE1, 0x2803, codes[wrap[1]])  # GL_TEXTURE_WRAP_T


def _random_coords(rng, n, lod_range):
    s = rng.uniform(-2.0, 3.0, n)
    t = rng.uniform(-2.0, 3.0, n)
    lod = rng.uniform(*lod_range, n)
    return s, t, lod


@pytest.mark.gl
@pytest.mark.parametrize("wrap", ["repeat", "clamp_to_edge", "mirrored_repeat"])
@pytest.mark.parametrize("min_filter", ["nearest", "linear", "nearest_mipmap_nearest", "linear_mipmap_nearest",
                                        "nearest_mipmap_linear", "linear_mipmap_linear"])
def test_sampling_matches_llvmpipe_texture_lod(gl, wrap, min_filter):
    rng = np.random.default_rng(len(wrap) * 7 + len(min_filter))
    img = rng.random((16, 32, 4)).astype(np.float32)
    texture = MipTexture(_levels_rect(img), wrap=wrap, min_filter=min_filter, mag_filter="linear", bits=None)
    s, t, lod = _random_coords(rng, 64 * 16, (-1.0, 6.0))
    # keep away from exact texel boundaries and exact level switches, where
    # any float difference flips a NEAREST choice
    u = s * 32
    v = t * 16
    keep = (np.abs(u - np.round(u)) > 1e-3) & (np.abs(v - np.round(v)) > 1e-3)
    s, t = np.where(keep, s, s + 0.3 / 32), np.where(keep, t, t + 0.3 / 16)
    lod = np.where(np.abs(lod - np.round(lod * 2) / 2) < 1e-3, lod + 0.01, lod)
    coords = np.stack([s, t, lod, np.zeros_like(s)], -1).reshape(16, 64, 4).astype(np.float32)
    c = coords.astype(np.float64)
    want = sample(texture, c[..., 0], c[..., 1], lod=c[..., 2])
    got = _gl_sample(gl, texture, coords, grad=False)
    err = np.abs(got - want)
    # llvmpipe filters with 8-bit fractional weights: ~1/256 of the local contrast
    assert np.percentile(err, 99) < 6e-3, float(err.max())
    assert err.mean() < 1e-3


@pytest.mark.gl
def test_sampling_matches_llvmpipe_texture_grad_axis_aligned(gl):
    rng = np.random.default_rng(7)
    img = rng.random((32, 32, 4)).astype(np.float32)
    texture = MipTexture(_levels_rect(img), bits=None)
    n = 16 * 64
    s = rng.uniform(-1, 2, n)
    t = rng.uniform(-1, 2, n)
    dsdx = 2.0 ** rng.uniform(-7, 1, n)
    dtdy = dsdx * 2.0 ** rng.uniform(-0.4, 0.4, n)
    coords = np.stack([s, t, dsdx, dtdy], -1).reshape(16, 64, 4).astype(np.float32)
    c = coords.astype(np.float64)
    want = sample(texture, c[..., 0], c[..., 1], dsdx=c[..., 2], dtdx=0.0, dsdy=0.0, dtdy=c[..., 3])
    got = _gl_sample(gl, texture, coords, grad=True)
    err = np.abs(got - want)
    assert np.percentile(err, 99) < 2e-2, float(err.max())
    assert err.mean() < 3e-3


def _levels_rect(img):
    out = [img]
    while out[-1].shape[:2] != (1, 1):
        a = out[-1]
        if a.shape[0] > 1:
            a = 0.5 * (a[0::2] + a[1::2])
        if a.shape[1] > 1:
            a = 0.5 * (a[:, 0::2] + a[:, 1::2])
        out.append(a.astype(np.float32))
    return out
