"""The seed's multi-pass GL route to magnification against the CPU route.

Tolerance: the GL route computes in float32 (texels, filter texture, blending,
accumulation); it is compared with the CPU route in float64 on the same
input, and the largest difference must be at most ``2e-6 * max|x|``, about
17 float32 epsilons (1.19e-7) of the input's magnitude: each output texel
sums at most 36 products (6 x 6 passes, the widest Gaussian here), each
rounded once, of weights whose absolute sum is at most 1.25. Measured:
below 3e-7 in every case here.
"""

import numpy as np
import pytest

import spectex.spectral._magnify_gl as mgl
from spectex.spectral import FILTERS, filter_passes, magnify, magnify_gl

pytestmark = pytest.mark.gl

RTOL = 2e-6

# (input shape, factor): square and not, T dividing n or not, n < T,
# 1, 3 and 4 channels, factor 1, rectangular factors.
CASES = [
    ((4, 4), 16),        # the seed's 4 x 4 input (it magnifies 128 times)
    ((5, 7), 3),         # non-square, odd sizes: T does not divide n
    ((3, 6, 3), (4, 5)),  # three channels, rectangular factor
    ((6, 4, 4), 2),      # RGBA: two channel groups
    ((1, 2), 4),         # fewer input texels than the footprint
    ((2, 9), (1, 7)),    # factor 1 along the rows
]

FILTER_CASES = [(f, 0.5) for f in FILTERS] + [("gaussian", 1.0), ("gaussian", 0.3)]


def _max_error(got, want, x):
    return float(np.abs(got.astype(np.float64) - want).max() / np.abs(x).max())


@pytest.mark.parametrize("multiply", ["blend", "shader"])
@pytest.mark.parametrize("filt,sigma", FILTER_CASES)
@pytest.mark.parametrize("shape,factor", CASES)
def test_gl_equals_cpu_to_float32_precision(gl, filt, sigma, shape, factor, multiply):
    rng = np.random.default_rng(sum(shape))
    x = rng.standard_normal(shape).astype(np.float32)
    got = magnify_gl(x, factor, kernel=filt, sigma=sigma, multiply=multiply, ctx=gl)
    want = magnify(x.astype(np.float64), factor, kernel=filt, sigma=sigma)
    assert got.image.shape == want.shape and got.image.dtype == np.float32
    assert _max_error(got.image, want, x) <= RTOL
    # Every output texel received filter weights summing to one, no more.
    np.testing.assert_allclose(got.weight_sum, 1.0, atol=1e-6, rtol=0)


@pytest.mark.parametrize("filt", ["bspline", "catmull-rom", "gaussian"])
@pytest.mark.parametrize("shape", [(24, 40), (25, 38)])
def test_gl_at_larger_sizes(gl, filt, shape):
    x = np.random.default_rng(3).standard_normal(shape).astype(np.float32)
    got = magnify_gl(x, 13, kernel=filt, ctx=gl).image
    want = magnify(x.astype(np.float64), 13, kernel=filt)
    assert _max_error(got, want, x) <= RTOL


@pytest.mark.parametrize("filt", FILTERS)
def test_blend_and_shader_products_agree(gl, filt):
    """One float32 multiply either way, in the blender or in the shader: on
    llvmpipe the two give the same bits; elsewhere float32 precision."""
    x = np.random.default_rng(7).standard_normal((5, 7, 3)).astype(np.float32)
    blend = magnify_gl(x, 3, kernel=filt, multiply="blend", ctx=gl)
    shader = magnify_gl(x, 3, kernel=filt, multiply="shader", ctx=gl)
    if "llvmpipe" in gl.info["GL_RENDERER"]:
        np.testing.assert_array_equal(blend.image, shader.image)
    assert _max_error(blend.image, shader.image.astype(np.float64), x) <= RTOL
    assert blend.passes == shader.passes and blend.draws == 3 * shader.draws


def test_gl_output_tiles_and_shifts_with_the_input(gl):
    x = np.random.default_rng(4).standard_normal((5, 6)).astype(np.float32)
    y = magnify_gl(x, 4, ctx=gl).image
    shifted = magnify_gl(np.roll(x, (1, 2), axis=(0, 1)), 4, ctx=gl).image
    np.testing.assert_allclose(shifted, np.roll(y, (4, 8), axis=(0, 1)), atol=RTOL * 4, rtol=0)
    # The seam: across the wrap edge, the step is no larger than inside.
    inside = np.abs(np.diff(y, axis=1)).max()
    assert np.abs(y[:, 0] - y[:, -1]).max() <= inside


def test_public_magnify_backend_gl_keeps_dtype(gl):
    x = np.random.default_rng(5).standard_normal((3, 5))
    y = magnify(x, 3, kernel="tent", backend="gl")  # makes and keeps its own context
    assert y.dtype == np.float64 and y.shape == (9, 15)
    assert _max_error(y, magnify(x, 3, kernel="tent"), x) <= RTOL
    y32 = magnify(x.astype(np.float32), 3, backend="gl")
    assert y32.dtype == np.float32
    yi = magnify(np.arange(6).reshape(2, 3), 2, kernel="box", backend="gl")
    assert yi.dtype == np.float64
    np.testing.assert_array_equal(yi, np.kron(np.arange(6).reshape(2, 3), np.ones((2, 2))))
    # magnify_gl makes the context it is given current and leaves it so: the
    # session's context is the current one again, for the fixture's check and
    # the tests after this one.
    assert _max_error(magnify_gl(x, 3, kernel="tent", ctx=gl).image, y, x) <= RTOL


@pytest.mark.parametrize("filt,sigma,t", [("box", 0.5, 1), ("tent", 0.5, 2), ("gaussian", 0.5, 3),
                                          ("bspline", 0.5, 4), ("gaussian", 0.8, 5)])
def test_pass_count_is_footprint_squared_whatever_the_sizes(gl, filt, sigma, t):
    """T^2 passes for a T x T footprint, for any input and output size; the
    draws counted by GL itself (primitives generated: two per rectangle)."""
    assert filter_passes(filt, sigma=sigma) == t
    for shape, factor in [((2, 2), 2), ((4, 4), 16), ((7, 3), 5), ((16, 12), (3, 8))]:
        x = np.ones(shape, dtype=np.float32)
        for multiply, draws_per_pass in (("blend", 3), ("shader", 1)):
            query = gl.query(primitives=True)
            with query:
                got = magnify_gl(x, factor, kernel=filt, sigma=sigma, multiply=multiply, ctx=gl)
            assert got.passes == t * t and got.footprint == t and got.channel_groups == 1
            assert got.draws == draws_per_pass * t * t
            assert query.primitives == 2 * got.draws


def test_channel_groups_repeat_the_passes(gl):
    x = np.zeros((4, 4, 7), dtype=np.float32)
    got = magnify_gl(x, 2, kernel="tent", ctx=gl)
    assert (got.passes, got.channel_groups, got.draws) == (4, 3, 3 * 4 * 3)


def test_redistribution_is_the_seeds():
    """4 x 4 texels numbered 0..15 row by row, 2 x 2 footprint: four 2 x 2
    sub-textures, one period each; texels 5, 7, 13 and 15 go together (their
    regions of the output do not overlap)."""
    x = np.arange(16).reshape(4, 4)
    subs = mgl.redistribute(x, 2, (16, 16), (-16, -16))
    assert sorted(subs) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    np.testing.assert_array_equal(subs[1, 1][0], [[5, 7], [13, 15]])
    np.testing.assert_array_equal(subs[0, 0][0], [[0, 2], [8, 10]])
    assert all(origin == (0, 0) for _, origin in subs.values())


def test_redistribution_when_the_footprint_does_not_divide_the_input():
    """n = 5, T = 2, m = 3, tent (its window starts at -2): pass a = 0 has
    offset c = -2 and reads i = floor((p + 2) / 6) for p = 0..14, i.e.
    i = 0, 1, 2, texels 0, 2, 4; pass a = 1 has c = 1 and reads i = -1..2,
    texels 4, 1, 3, 0 (wrapping both ways). About n / T texels each, not a
    period of n / gcd(n, T)."""
    start = mgl._filter_window("tent", 3, 0.5, 2)[1]
    assert start == -2
    x = np.arange(5)[None, :] * np.ones((4, 1), dtype=int)
    subs = mgl.redistribute(x, 2, (3, 3), (start, start))
    np.testing.assert_array_equal(subs[0, 0][0][0], [0, 2, 4])
    assert subs[0, 0][1] == (0, 0) and subs[0, 0][0].shape == (2, 3)
    np.testing.assert_array_equal(subs[0, 1][0][0], [4, 1, 3, 0])
    assert subs[0, 1][1] == (0, -1)
    # Larger: 101 texels, bspline (T = 4): at most n / T + 2 per axis.
    y = np.zeros((101, 101))
    start = mgl._filter_window("bspline", 7, 0.5, 4)[1]
    for sub, _ in mgl.redistribute(y, 4, (7, 7), (start, start)).values():
        assert max(sub.shape) <= 101 // 4 + 2


def test_pass_offsets():
    got = mgl.pass_offsets(2, (3, 5), (-4, -6))
    assert got == [((0, 0), (-4, -6)), ((0, 1), (-4, -1)), ((1, 0), (-1, -6)), ((1, 1), (-1, -1))]


# Controls: the comparison must see a wrong offset, a missing pass and a
# wrong redistribution.

def _control_error(gl, filt="bspline", multiply="blend"):
    x = np.random.default_rng(6).standard_normal((5, 6)).astype(np.float32)
    got = magnify_gl(x, 4, kernel=filt, multiply=multiply, ctx=gl)
    return _max_error(got.image, magnify(x.astype(np.float64), 4, kernel=filt), x), got


@pytest.mark.parametrize("filt", ["box", "bspline"])
@pytest.mark.parametrize("multiply", ["blend", "shader"])
def test_control_offset_one_texel_off_is_seen(gl, monkeypatch, filt, multiply):
    right = mgl.pass_offsets

    def off_by_one(footprint, factor, start):
        return [(key, (c0 + 1, c1)) for key, (c0, c1) in right(footprint, factor, start)]

    assert _control_error(gl, filt, multiply)[0] <= RTOL
    monkeypatch.setattr(mgl, "pass_offsets", off_by_one)
    assert _control_error(gl, filt, multiply)[0] > 1e-2


def test_control_missing_pass_is_seen(gl, monkeypatch):
    right = mgl.pass_offsets
    monkeypatch.setattr(mgl, "pass_offsets", lambda *a: right(*a)[:-1])
    error, got = _control_error(gl)
    assert got.passes == 15
    assert error > 1e-2
    assert np.abs(got.weight_sum - 1.0).max() > 1e-2


def test_control_wrong_redistribution_is_seen(gl, monkeypatch):
    right = mgl.redistribute

    def swapped(x, footprint, *rest):
        subs = right(x, footprint, *rest)
        subs[0, 1], subs[1, 0] = subs[1, 0], subs[0, 1]
        return subs

    monkeypatch.setattr(mgl, "redistribute", swapped)
    assert _control_error(gl)[0] > 1e-2


def test_another_current_context_does_not_take_the_passes(gl):
    """Making a second context makes it current, and moderngl sends every
    call to the current context; magnify_gl must still draw in the context
    it is given, before and after the other one is released."""
    from spectex._gl import create_context

    x = np.random.default_rng(8).standard_normal((4, 6)).astype(np.float32)
    want = magnify(x.astype(np.float64), 3)
    magnify_gl(x, 3, ctx=gl)  # programs cached in gl
    other = create_context()
    try:
        assert _max_error(magnify_gl(x, 3, ctx=gl).image, want, x) <= RTOL
        assert _max_error(magnify_gl(x, 3, ctx=other).image, want, x) <= RTOL
    finally:
        other.release()
    assert _max_error(magnify_gl(x, 3, ctx=gl).image, want, x) <= RTOL  # gl current again


def test_bad_inputs(gl):
    with pytest.raises(ValueError, match="backend"):
        magnify(np.ones((2, 2)), 2, backend="vulkan")
    with pytest.raises(ValueError, match="^kernel must be"):
        magnify_gl(np.ones((2, 2)), 2, kernel="lanczos", ctx=gl)
    with pytest.raises(ValueError, match="multiply"):
        magnify_gl(np.ones((2, 2)), 2, multiply="accum", ctx=gl)
    with pytest.raises(ValueError, match="image"):
        magnify_gl(np.array([[np.nan, 0.0]]), 2, ctx=gl)
    with pytest.raises(ValueError, match="GL_MAX_TEXTURE_SIZE"):
        magnify_gl(np.ones((2, 2)), 9000, kernel="box", ctx=gl)
    with pytest.raises(ValueError, match="filter texture"):
        magnify_gl(np.ones((1, 1)), (5000, 1), kernel="bspline", ctx=gl)


def test_missing_moderngl_names_what_to_install(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "moderngl", None)
    with pytest.raises(OSError, match=r"pip install 'spectex\[gl\]'"):
        mgl.create_context()
