"""The renderers: GL against the CPU reference, alias-freedom against a
supersampled reference, camera conventions and bad input."""

import numpy as np
import pytest

from helpers import SIZE, VIEWS, psnr
from spectex.render import Atmosphere, Camera, check_size
from spectex.render.cpu import render_cpu
from spectex.shading.tables import anchor_coords
from spectex.texture import Layer, SpectralTexture
from spectex.tiles import make_tile


@pytest.fixture(scope="module")
def full_contrast():
    """The paper's texture on a tile whose colour channels span [0, 1]."""
    tile = make_tile(256, rng=2)
    lo = tile[..., :3].min(axis=(0, 1))
    hi = tile[..., :3].max(axis=(0, 1))
    tile[..., :3] = (tile[..., :3] - lo) / (hi - lo)
    return SpectralTexture.paper_preset(tile)


@pytest.mark.gl
@pytest.mark.parametrize("name", list(VIEWS))
def test_render_gl_matches_cpu(gl, full_contrast, name):
    from spectex.render.gl import GLRenderer

    cam = VIEWS[name]
    with GLRenderer(full_contrast, ctx=gl) as r:
        g = r.render(cam, SIZE)
    c = render_cpu(full_contrast, cam, SIZE)
    assert g.shape == c.shape == SIZE + (3,)
    assert psnr(g, c) >= 40.0


@pytest.mark.gl
@pytest.mark.parametrize("blend", ["detail", "variance", "overlay"])
def test_render_gl_matches_cpu_blends_anisotropy_toggles(gl, blend):
    tex = SpectralTexture.paper_preset(make_tile(128, rng=4), blend=blend)
    from spectex.render.gl import GLRenderer

    cam = VIEWS["grazing"]
    kw = dict(anisotropy=8.0, enabled=[True, False, True, True, False, True])  # the last: the fine detail layer
    with GLRenderer(tex, ctx=gl) as r:
        g = r.render(cam, SIZE, **kw)
        full = r.render(cam, SIZE)
    c = render_cpu(tex, cam, SIZE, **kw)
    assert psnr(g, c) >= 40.0
    assert psnr(g, full) < 35.0  # the toggles and anisotropy did change the picture


@pytest.mark.gl
def test_render_gl_rows_are_top_down(gl):
    """An asymmetric scene: sky at the top, ground at the bottom, and a tile
    half black, half white across t; the flip to GL's bottom-left origin
    happens once, in gl.py, so GL and CPU agree pixel by pixel."""
    tile = np.zeros((8, 8, 4), np.float32)
    tile[:4, :, :3] = 1.0  # rows t in [0, 0.5): white
    tile[..., 3] = 1.0
    tex = SpectralTexture(tile, [Layer(size=40.0)], bits=8)
    from spectex.render.gl import GLRenderer

    cam = Camera((10.0, 10.0, 30.0), yaw=0.0, pitch=-20.0)
    with GLRenderer(tex, ctx=gl) as r:
        g = r.render(cam, (36, 64), filter="nearest")
    c = render_cpu(tex, cam, (36, 64), filter="nearest")
    atm = Atmosphere()
    assert g[0, 0, 2] > g[0, 0, 0] + 0.1 and g[0, 0, 2] > atm.zenith[2]  # blue sky on top
    assert g[18:].min() < 0.1 and g[18:].max() > 0.9  # the black and white ground below
    assert np.mean(np.abs(g - c) > 0.1) < 0.02  # same picture (edges may flip a texel)


@pytest.mark.gl
def test_render_gl_supersample_matches_cpu(gl, full_contrast):
    from spectex.render.gl import GLRenderer

    cam = VIEWS["aerial"]
    with GLRenderer(full_contrast, ctx=gl) as r:
        g = r.render(cam, (45, 80), supersample=3, filter="linear")
    c = render_cpu(full_contrast, cam, (45, 80), supersample=3, filter="linear")
    assert psnr(g, c) >= 40.0


@pytest.mark.parametrize("pitch", [-90.0, -60.0, -12.0, -3.0, 0.0, 10.0, 29.0, 45.0, 90.0])
def test_render_gl_sky_rows_see_only_sky(pitch):
    """The rows gl.py draws with the sky-only program: every pixel there has
    d_z > 0 (docs/sampling.md, section 7, in float64), and the count is at
    most margin + 1 rows short of the true horizon row."""
    from spectex.render.gl import sky_row_count

    h, w = 180, 320
    cam = Camera((0.0, 0.0, 2.0), yaw=30.0, pitch=pitch, fov=60.0)
    fwd, right, up = cam.basis()
    tan_x, tan_y = cam.tangents(h, w)
    py, px = np.mgrid[0:h, 0:w] + 0.5
    dz = fwd[2] + (2 * px / w - 1) * tan_x * right[2] + (1 - 2 * py / h) * tan_y * up[2]
    sky = np.all(dz > 0.0, axis=1)
    true_rows = int(np.argmin(sky)) if not sky.all() else h
    n = sky_row_count(cam, h, w)
    assert sky[:n].all()
    assert true_rows - 3 <= n <= true_rows


@pytest.mark.gl
def test_render_gl_horizon_split_is_seamless(gl, full_contrast):
    """The sky-only rows and the full program meet without a seam: the GL
    picture matches the CPU one row by row around the horizon."""
    from spectex.render.gl import GLRenderer, sky_row_count

    cam = VIEWS["grazing"]
    n = sky_row_count(cam, *SIZE)
    assert 10 < n < SIZE[0] - 10
    with GLRenderer(full_contrast, ctx=gl) as r:
        g = r.render(cam, SIZE)
    c = render_cpu(full_contrast, cam, SIZE)
    rows = np.abs(g - c)[n - 4:n + 6].max(axis=(1, 2))
    assert rows.max() < 0.05, rows


@pytest.mark.slow
@pytest.mark.gl
def test_render_mipmapping_is_alias_free(gl, full_contrast):
    """Mip-mapped renders against 8 x 8 supersampled, box-filtered CPU
    renders without mip-maps; a single-sample render without mip-maps, on
    the same views, must be clearly worse (the test can fail).

    On the paper's composite (alpha blend, no detail layer), which these
    thresholds were set for: the sampler's alias-freedom. The preset's
    defaults keep about 3x the contrast, and trilinear filtering's
    difference from the box-filtered truth grows with it (measured 37.5,
    41.9, 42.6, 37.0, 35.9 dB on these views); their own check is
    ``test_first_picture.py::test_demo_views_are_alias_free_at_the_defaults``."""
    from spectex.render.gl import GLRenderer

    paper = SpectralTexture.paper_preset(full_contrast.tiles[0], blend="alpha", detail=False)
    mip, gl_mip, plain = [], [], []
    with GLRenderer(paper, ctx=gl) as r:
        for cam in VIEWS.values():
            ref = render_cpu(paper, cam, SIZE, filter="linear", supersample=8)
            mip.append(psnr(render_cpu(paper, cam, SIZE), ref))
            gl_mip.append(psnr(r.render(cam, SIZE), ref))
            plain.append(psnr(render_cpu(paper, cam, SIZE, filter="linear"), ref))
    assert min(mip) >= 38.0, mip
    assert min(gl_mip) >= 38.0, gl_mip
    assert np.mean(plain) <= np.mean(mip) - 3.0, (mip, plain)
    minified = [k for k, name in enumerate(VIEWS) if name != "close"]  # close-up: magnification only
    assert all(plain[k] < mip[k] for k in minified), (mip, plain)


#: Issue 18's four views for the defaults' alias proof: close-up, grazing, 30 m and 300 m up.
DEFAULT_VIEWS = {
    "close": Camera((3.0, 4.0, 1.5), yaw=20.0, pitch=-50.0),
    "grazing": Camera((50.0, -20.0, 1.7), yaw=100.0, pitch=-3.0),
    "30 m": Camera((0.0, 0.0, 30.0), yaw=10.0, pitch=-20.0),
    "300 m": Camera((0.0, 0.0, 300.0), yaw=10.0, pitch=-25.0),
}


@pytest.mark.slow
@pytest.mark.gl
def test_render_defaults_are_alias_free_on_a_full_contrast_tile(gl):
    """The renderers at their defaults (trilinear with anisotropy 8) against
    an 8 x 8 supersampled, box-filtered CPU render without mip-maps, with the
    paper preset's tile stretched to its 1st-99th percentiles: >= 40 dB on
    every view, CPU and GL (measured 44.9 to 72 dB). Trilinear alone
    (anisotropy 1, the old default) must be clearly worse on the oblique views
    that minify (measured 36.6 and 38.2 dB at 30 m and 300 m): the test can
    fail, and it is what made anisotropic filtering the default."""
    from spectex.render import DEFAULT_ANISOTROPY
    from spectex.render.gl import GLRenderer

    assert DEFAULT_ANISOTROPY > 1.0
    tile = make_tile(256, rng=2)
    lo, hi = np.percentile(tile[..., :3], [1.0, 99.0], axis=(0, 1))
    tile[..., :3] = np.clip((tile[..., :3] - lo) / (hi - lo), 0.0, 1.0)
    # the paper's composite, which these thresholds were set for (the preset's defaults: 35.5, 39.6,
    # 35.4, 34.9 dB here, their 3x contrast; test_first_picture.py checks them on the demo's views)
    tex = SpectralTexture.paper_preset(tile, blend="alpha", detail=False)
    cpu, gl_default, trilinear = {}, {}, {}
    with GLRenderer(tex, ctx=gl) as r:
        for name, cam in DEFAULT_VIEWS.items():
            ref = render_cpu(tex, cam, SIZE, filter="linear", supersample=8)
            cpu[name] = psnr(render_cpu(tex, cam, SIZE), ref)
            gl_default[name] = psnr(r.render(cam, SIZE), ref)
            trilinear[name] = psnr(render_cpu(tex, cam, SIZE, anisotropy=1.0), ref)
    assert min(cpu.values()) >= 40.0, cpu
    assert min(gl_default.values()) >= 40.0, gl_default
    for name in ("grazing", "30 m", "300 m"):
        assert trilinear[name] <= cpu[name] - 3.0, (name, cpu, trilinear)
    assert min(trilinear.values()) < 38.0, trilinear  # the old default broke the promise here


@pytest.mark.parametrize("blend", ["alpha", "detail", "variance", "overlay"])
def test_render_cpu_fast_path_matches_general(blend):  # each with the preset's fine detail layer
    """The fast kernel (REPEAT, square power-of-two tile, trilinear, isotropic)
    against the general sampler on random views: positions near and far
    from the origin, altitudes from 0.3 m to 3 km, any heading, pitches down
    to straight down and up to the horizon, so that the coordinates and the
    footprints (magnification to the 1 x 1 level) are spread widely;
    supersampling and layer toggles included."""
    from spectex.shading import pack, view_params
    from spectex.shading.view import render_kernel, render_kernel_fast, row_order

    rng = np.random.default_rng(7)
    tex = SpectralTexture.paper_preset(make_tile(64, rng=3), blend=blend)
    assert pack(tex).fast
    for k in range(6):
        cam = Camera((rng.uniform(-1e5, 1e5), rng.uniform(-1e5, 1e5), 10 ** rng.uniform(-0.5, 3.5)),
                     yaw=rng.uniform(0.0, 360.0), pitch=rng.uniform(-90.0, 5.0), fov=rng.uniform(20.0, 90.0))
        n = 1 + k % 2
        tables = pack(tex, enabled=rng.random(len(tex.layers)) < 0.8 if k >= 3 else None)
        view = view_params(cam, (24, 40), supersample=n)
        anchor = anchor_coords(tex.layers, *cam.position[:2])
        fast = np.empty((24, 40, 3), np.float32)
        general = np.empty((24, 40, 3), np.float32)
        render_kernel_fast(tables, anchor, view, row_order(24), fast)
        render_kernel(tables, anchor, view, row_order(24), general)
        np.testing.assert_array_equal(render_cpu(tex, cam, (24, 40), supersample=n, anisotropy=1.0,
                                                 enabled=[bool(v) for v in tables.on]), fast)
        assert np.abs(fast - general).max() <= 1e-5, (k, np.abs(fast - general).max())
        assert general.std() > 0.01  # a textured picture, not a blank one


def test_render_cpu_fast_log2_exp_match_numpy():
    """The fast path's call-free log2 and exp against NumPy's, over the
    ranges it uses them on (footprints of 1e-150..1e150 squared metres;
    haze and sky exponents 0 down to -700), including the mantissa edges."""
    import numba

    from spectex.shading.view import _exp, _log2

    @numba.njit
    def both(x, y, a, b):
        for i in range(x.shape[0]):
            a[i] = _log2(x[i])
            b[i] = _exp(y[i])

    rng = np.random.default_rng(3)
    x = np.concatenate([10.0 ** rng.uniform(-300, 300, 20000), [1.0, 2.0, 0.5, np.sqrt(2.0), 1e-300, 3.0]])
    y = np.concatenate([-rng.uniform(0.0, 700.0, 20000), [0.0, -1e-12, -np.log(2.0), -1.0, -700.0, -20.0]])
    a, b = np.empty_like(x), np.empty_like(y)
    both(x, y, a, b)
    assert np.abs(a - np.log2(x)).max() < 1e-9
    assert (np.abs(b - np.exp(y)) / np.exp(y)).max() < 1e-8


def test_render_cpu_fast_path_only_where_it_applies():
    from spectex.shading import pack

    tex = SpectralTexture.paper_preset(make_tile(64, rng=3))
    assert pack(tex).fast
    assert not pack(tex, filter="linear").fast
    assert not pack(tex, anisotropy=4.0).fast
    odd = SpectralTexture.plain(make_tile(64, rng=3)[:, :48], 5.0)
    assert not pack(odd).fast


def test_render_cpu_haze_and_sky():
    tex = SpectralTexture.plain(make_tile(32, rng=1), 5.0)
    atm = Atmosphere(horizon=(0.5, 0.5, 0.5), zenith=(0.0, 0.0, 1.0), haze_distance=1.0)
    up = render_cpu(tex, Camera((0.0, 0.0, 1.0), pitch=89.0, fov=10.0), (8, 8), atmosphere=atm)
    assert np.all(up[..., 2] > 0.9) and np.all(up[..., 0] < 0.1)
    far = render_cpu(tex, Camera((0.0, 0.0, 1.0), pitch=-1.5, fov=1.0), (8, 8), atmosphere=atm)
    np.testing.assert_allclose(far, 0.5, atol=1e-3)  # hazed out to the horizon colour


@pytest.mark.parametrize("position, match", [
    ((0.0, 0.0, 0.0), "z must be > 0"),
    ((0.0, 0.0, -5.0), "z must be > 0"),
    ((np.nan, 0.0, 5.0), "camera x"),
    ((0.0, 0.0, np.inf), "camera z"),
])
def test_render_camera_bad_position(position, match):
    with pytest.raises(ValueError, match=match):
        Camera(position)


def test_render_camera_bad_angles_and_sizes():
    with pytest.raises(ValueError, match="pitch"):
        Camera((0.0, 0.0, 1.0), pitch=120.0)
    with pytest.raises(ValueError, match="fov"):
        Camera((0.0, 0.0, 1.0), fov=0.0)
    with pytest.raises(ValueError, match="budget|limit"):
        check_size((20000, 20000))
    with pytest.raises(ValueError, match="budget"):
        check_size((1080, 1920), supersample=8)
    assert check_size((180, 320)) == (180, 320)


def test_render_camera_basis_conventions():
    f, r, u = Camera((0.0, 0.0, 1.0), yaw=90.0, pitch=0.0).basis()
    np.testing.assert_allclose(f, [1, 0, 0], atol=1e-12)  # yaw 90: east
    np.testing.assert_allclose(r, [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(u, [0, 0, 1], atol=1e-12)
    f, r, u = Camera((0.0, 0.0, 1.0), yaw=0.0, pitch=-90.0).basis()
    np.testing.assert_allclose(f, [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(u, [0, 1, 0], atol=1e-12)  # looking down, north is up


def test_render_no_gl_falls_back_to_cpu(monkeypatch):
    import spectex.render.gl as glmod
    from spectex.render import render

    def unavailable(**kw):
        raise glmod.GLUnavailable("no OpenGL 3.3 context (EGL): test")

    monkeypatch.setattr(glmod, "create_context", unavailable)
    tex = SpectralTexture.plain(make_tile(32, rng=1), 5.0)
    result = render(tex, VIEWS["ground"], (18, 32))
    assert result.backend == "cpu" and result.image.shape == (18, 32, 3)
    with pytest.raises(OSError, match="no OpenGL"):
        render(tex, VIEWS["ground"], (18, 32), backend="gl")


@pytest.mark.parametrize("h", [1, 7, 16, 17, 180, 1080])
def test_row_order_is_a_permutation_spread_over_the_picture(h):
    from spectex.shading.view import row_order

    rows = row_order(h)
    assert rows.dtype == np.int64
    np.testing.assert_array_equal(np.sort(rows), np.arange(h))
    if h >= 180:  # each half of the order (one thread's share of two) covers the picture evenly
        for half in (rows[: h // 2], rows[h // 2:]):
            counts = np.histogram(half, bins=4, range=(0, h))[0]
            assert counts.min() >= 0.6 * counts.mean(), counts


def test_gl_renderer_draws_with_its_own_context_after_another_was_made(full_contrast):
    """moderngl sends calls to the current context: a renderer used after a second
    one was made (which made its context current) must still draw its own picture."""
    from spectex.render.gl import GLRenderer

    cam = VIEWS["ground"]
    with GLRenderer(full_contrast) as first:
        before = first.render(cam, (36, 64))
        with GLRenderer(SpectralTexture.plain(make_tile(32, rng=5), 3.0)) as second:
            other = second.render(cam, (36, 64))
            after = first.render(cam, (36, 64))
    np.testing.assert_array_equal(after, before)
    assert np.abs(other - before).mean() > 0.01  # the control: the other texture looks different
