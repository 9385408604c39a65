"""Stochastic layers in the renderers and bakes: GL against the CPU reference, alias-freedom
against a supersampled reference (with a control that must be worse), and what they are for."""

import numpy as np
import pytest

from helpers import SIZE, VIEWS, floor_photo, psnr, psnr_low, views_against_reference
from spectex.metrics import repeat_peak
from spectex.render import Camera, bake
from spectex.render.cpu import render_cpu
from spectex.shading.resources import stochastic_tables
from spectex.shading.tables import anchor_coords
from spectex.texture import Layer, SpectralTexture
from spectex.tiles import make_tile


@pytest.fixture(scope="module")
def stochastic():
    """The paper's texture, every layer stochastic, on a tile whose colour channels span [0, 1]."""
    tile = make_tile(256, rng=2)
    lo = tile[..., :3].min(axis=(0, 1))
    hi = tile[..., :3].max(axis=(0, 1))
    tile[..., :3] = (tile[..., :3] - lo) / (hi - lo)
    return SpectralTexture.paper_preset(tile, tiling="stochastic")


@pytest.mark.gl
@pytest.mark.parametrize("name", list(VIEWS))
def test_stochastic_gl_matches_cpu(gl, stochastic, name):
    from spectex.render.gl import GLRenderer

    cam = VIEWS[name]
    with GLRenderer(stochastic, ctx=gl) as r:
        g = r.render(cam, SIZE)
    c = render_cpu(stochastic, cam, SIZE)
    assert psnr(g, c) >= 40.0


@pytest.mark.gl
def test_stochastic_gl_matches_cpu_mixed_anisotropy_toggles(gl):
    # periodic and stochastic layers mixed, variance blend, anisotropy, a layer off
    base = SpectralTexture.paper_preset(make_tile(128, rng=4), blend="variance", tiling="stochastic")
    layers = [Layer(**{**lay.__dict__, "tiling": "periodic"}) if k in (1, 3) else lay
              for k, lay in enumerate(base.layers)]
    tex = SpectralTexture(base.tiles, layers)
    from spectex.render.gl import GLRenderer

    cam = VIEWS["grazing"]
    kw = dict(anisotropy=8.0, enabled=[True, True, False, True, True, True])
    with GLRenderer(tex, ctx=gl) as r:
        g = r.render(cam, SIZE, **kw)
        full = r.render(cam, SIZE)
    c = render_cpu(tex, cam, SIZE, **kw)
    assert psnr(g, c) >= 40.0
    assert psnr(g, full) < 35.0  # the toggles and anisotropy did change the picture


@pytest.mark.gl
def test_gl_constants_and_uniforms_draw_the_same(gl):
    # the renderer writes the texture's static uniforms into the shader as constants; the exports set
    # them as uniforms: two routes to the same picture (periodic and stochastic layers, variance blend,
    # anisotropy, a layer off), and a control that changes one constant must change it
    from spectex.render.gl import GLRenderer
    from spectex.shading import glsl

    base = SpectralTexture.paper_preset(make_tile(128, rng=4), blend="variance", tiling="stochastic")
    layers = [Layer(**{**lay.__dict__, "tiling": "periodic"}) if k == 2 else lay for k, lay in enumerate(base.layers)]
    tex = SpectralTexture(base.tiles, layers)
    cam = VIEWS["grazing"]
    kw = dict(anisotropy=4.0, enabled=[True, True, True, False, True, True])
    with GLRenderer(tex, ctx=gl) as a, GLRenderer(tex, ctx=gl, constants=False) as b:
        ga = a.render(cam, SIZE, **kw)
        gb = b.render(cam, SIZE, **kw)
        # the same picture; the sharpened stochastic weights (w^8) let a last-bit difference of the
        # constant-folded route flip one 8-bit step in a very few values (1 in 170,000 on llvmpipe)
        diff = np.abs(ga.astype(np.float64) - gb.astype(np.float64))
        assert diff.max() <= 1.0 / 255.0 + 1e-6 and np.mean(diff > 0) <= 1e-4
    from spectex.shading.tables import pack

    tables = pack(tex)
    text = glsl.fragment_source(tables, 1, constants=True)
    assert "uniform mat3 u_basis" not in text and "const mat3 u_basis[N_LAYERS] = mat3[](" in text
    assert "uniform vec2 u_anchor[N_LAYERS];" in text  # what moves with the camera stays a uniform
    changed = tables._replace(opacity=tables.opacity * 0.5)
    assert glsl.fragment_source(changed, 1, constants=True) != text
    assert glsl.fragment_source(changed, 1) == glsl.fragment_source(tables, 1)


@pytest.mark.gl
def test_stochastic_mipmapping_is_alias_free(gl, stochastic):
    """Mip-mapped stochastic renders against 8 x 8 supersampled, box-filtered
    CPU renders without mip-maps (level 0 and its level-0 table); a
    single-sample render without mip-maps must be clearly worse."""
    from spectex.render.gl import GLRenderer

    # the paper's composite, which the thresholds were set for (with the preset's variance blend and
    # fine layer: 37.5, 41.9, 42.6, 37.0, 35.9 dB, its 3x contrast)
    paper = SpectralTexture.paper_preset(stochastic.tiles[0], tiling="stochastic", blend="alpha", detail=False)
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
    minified = [k for k, name in enumerate(VIEWS) if name != "close"]
    assert all(plain[k] < mip[k] for k in minified), (mip, plain)


def test_bake_stochastic_layer_agrees_with_the_sampler(stochastic):
    # the bake kernel (anchored grid, split vertex index) and the standalone sampler (grid from the
    # true coordinates) are two routes to the same layer, far from the origin too
    from spectex.shading.stochastic import sample_stochastic

    layer = Layer(size=7.0, offset=(1.5, -2.0), rotation=33.0, tiling="stochastic", patch=0.4, seed=9)
    tex = SpectralTexture(stochastic.tiles, [layer])
    p = 0.05
    origin = (123456.0, -98765.0)
    baked = bake(tex, (64, 80), origin=origin, pixel_size=p)
    r, c = np.mgrid[0:64, 0:80]
    s, t = layer.coords(origin[0] + (c + 0.5) * p, origin[1] + (r + 0.5) * p)
    m = layer.matrix()
    ref = sample_stochastic(stochastic_tables(tex)[0], s, t, patch=0.4, seed=9, dsdx=m[0, 0] * p,
                            dtdx=m[1, 0] * p, dsdy=m[0, 1] * p, dtdy=m[1, 1] * p)
    assert np.max(np.abs(baked - ref[..., :3])) < 2e-3
    # blocks bake to the same bits as the whole region
    block = bake(tex, (32, 40), origin=origin, pixel_size=p, start=(32, 40))
    assert np.array_equal(block, baked[32:, 40:])


def test_paper_preset_stochastic_never_repeats():
    for px in (64, 256):
        values = {}
        for tiling in ("periodic", "stochastic"):
            tex = SpectralTexture.paper_preset(rng=1, tiling=tiling)
            values[tiling] = repeat_peak(bake(tex, (1024, 1024), pixel_size=tex.layers[0].size / px))
        assert values["stochastic"] <= 0.1, (px, values)
        assert values["periodic"] >= 0.7, (px, values)  # the control: the paper's method repeats


def test_layer_tiling_options_are_checked():
    with pytest.raises(ValueError, match="tiling"):
        Layer(size=1.0, tiling="random")
    with pytest.raises(ValueError, match="patch"):
        Layer(size=1.0, tiling="stochastic", patch=0.0)
    with pytest.raises(ValueError, match="seed"):
        Layer(size=1.0, seed=2 ** 32)
    with pytest.raises(TypeError, match="seed"):
        Layer(size=1.0, seed=1.5)
    assert Layer(size=1.0).tiling == "periodic"


@pytest.mark.parametrize("blend", ["alpha", "variance"])
def test_render_cpu_fast_path_matches_general_stochastic(blend):
    """The fast kernel with stochastic layers (mixed with periodic ones) against the general
    sampler on random views (near and far from the origin, 0.3 m to 3 km up, straight down to
    the horizon; supersampling and toggles). The two compute the Gaussian blend in different
    precisions, so a table entry can flip where the blend falls on a bin's edge: equal to 1e-5
    but for a few such samples, none far off."""
    from spectex.shading import pack, view_params
    from spectex.shading.view import render_kernel, render_kernel_fast, row_order

    rng = np.random.default_rng(11)
    base = SpectralTexture.paper_preset(make_tile(64, rng=3), blend=blend, tiling="stochastic")
    layers = [Layer(**{**lay.__dict__, "tiling": "periodic"}) if k in (1, 3) else lay
              for k, lay in enumerate(base.layers)]
    tex = SpectralTexture(base.tiles, layers)
    assert pack(tex).fast
    assert not pack(tex, filter="bilinear").fast  # the control: another sampler state takes the general kernel
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
        # render_cpu takes the fast kernel for this sampler state (trilinear, no anisotropy)
        np.testing.assert_array_equal(render_cpu(tex, cam, (24, 40), supersample=n, anisotropy=1.0,
                                                 enabled=[bool(v) for v in tables.on]), fast)
        diff = np.abs(fast - general)
        assert np.mean(diff > 1e-5) <= 0.01 and diff.max() <= 0.03, (k, np.mean(diff > 1e-5), diff.max())
        assert general.std() > 0.01  # a textured picture, not a blank one


@pytest.fixture(scope="module")
def fitted():
    """spectex.fit's default on a gravel crop (a sharpened stochastic finest layer, periodic coarse
    layers on their own noise tile), at a scale like the paper texture's (a 15 m finest tile: the
    256-pixel crop is its own tile; until 2026-11-26 a 64-pixel crop quilted to 256 texels)."""
    import skimage.data

    from spectex.fitting import fit

    return fit(skimage.data.gravel()[:256, :256], pixel_size=0.06, iterations=1)


@pytest.fixture(scope="module")
def fitted_small():
    """The same for a 64-pixel crop, its own tile since 2026-11-26: a 3.84 m finest tile, patches of 32
    texels, so every view but the close one sees it minified by more than the 15 m tile."""
    import skimage.data

    from spectex.fitting import fit

    return fit(skimage.data.gravel()[:64, :64], pixel_size=0.06, iterations=1)


@pytest.mark.slow
@pytest.mark.gl
def test_fitted_texture_gl_matches_cpu_and_is_alias_free(gl, fitted):
    """Issue 22's targets on a fitted texture: GL = CPU >= 40 dB, and alias-free >= 38 dB on every
    view, CPU and GL, against 16 x 16 supersampled renders without mip-maps.

    Why 16 x 16 and not 8 x 8: the fitted gravel tile is nearly white (as much power in its finest
    octave as in its coarsest), and on the aerial and high views a pixel covers up to 150 x 150
    texels of the finest layer, so 64 point samples do not average it: the 8 x 8 reference is itself
    aliased, 36.5-38.1 dB from the 16 x 16 one there (below 39 dB and the mip-mapped render's
    figure: asserted), and the mip-mapped renders
    scored 36.3 and 37.3 dB against it (the same with the finest layer periodic, 36.6 and 37.5: not
    the stochastic weights). Against 16 x 16 they score 39.6 and 44.3 dB (39.5 and 44.7 for the quilted tile
    of a 64-pixel crop this fixture was until 2026-11-26); the 16 x 16 reference
    agrees with an independent one (8 x 8 mip-mapped samples) to 45 dB. The controls: a single
    sample per pixel without mip-maps is far worse (17-26 dB), and so is the 8 x 8 reference on the
    high view."""
    assert fitted.layers[0].tiling == "stochastic" and len(fitted.tiles) == 2
    mip, gl_mip, plain = {}, {}, {}
    for name, cam, c, g, ref, no_mip in views_against_reference(fitted, gl):
        mip[name], gl_mip[name] = psnr(c, ref), psnr(g, ref)
        plain[name] = psnr(no_mip, ref)
        if name == "high":
            ref8 = render_cpu(fitted, cam, SIZE, filter="linear", supersample=8)
            # the 8 x 8 reference aliases here: further from the 16 x 16 one than the render is
            assert psnr(ref8, ref) < min(mip[name], 39.0), (psnr(ref8, ref), mip[name])
    assert min(mip.values()) >= 38.0 and min(gl_mip.values()) >= 38.0, (mip, gl_mip)
    assert all(plain[k] <= mip[k] - 3.0 for k in VIEWS if k != "close"), (mip, plain)


@pytest.mark.slow
def test_fitted_texture_at_mid_distance_keeps_one_patch_per_place(fitted):
    """A view from 100 m (pitch -35 degrees: pixels of 6 to 60 texels) of the fitted 15 m tile, whose
    patches (128 texels) are 2 to 20 pixels wide there: the blend's weights stay sharp until a patch
    shrinks to a pixel (``stochastic.sharpen_weights``), so each place shows one patch, as the
    supersampled level 0 does. Measured against 16 x 16 supersampled renders without mip-maps: 34.9 dB
    full-band and 46.9 low-passed; the rule before 2026-11-26 (barycentric weights from lambda = 3,
    three patches cross-faded over most of each triangle) scored 32.8 and 43.2. The control: the render
    without mip-maps, far worse."""
    cam = Camera((0.0, 0.0, 100.0), yaw=10.0, pitch=-35.0)
    c = render_cpu(fitted, cam, SIZE)
    ref = render_cpu(fitted, cam, SIZE, filter="linear", supersample=16)
    plain = render_cpu(fitted, cam, SIZE, filter="linear")
    assert psnr(c, ref) >= 34.0 and psnr_low(c, ref) >= 45.5, (psnr(c, ref), psnr_low(c, ref))
    assert psnr_low(plain, ref) <= psnr_low(c, ref) - 10.0, (psnr_low(plain, ref), psnr_low(c, ref))


@pytest.mark.slow
@pytest.mark.gl
def test_small_photos_fit_gl_matches_cpu_and_is_alias_free(gl, fitted_small):
    """A 64-pixel photo's own tile (3.84 m): GL = CPU >= 40 dB, and alias-free where aliasing shows
    (both pictures low-passed, as the fitted floor's test measures). Full-band the aerial view (400 m)
    scores 37.3 dB against 39.5 for the 15 m tile: the view sees the small tile minified 4 times more,
    where the trilinear filter's shape, not aliasing, decides a nearly white tile's full band (the same
    15 m tile scores 32.7 and 35.3 full-band at 100 and 200 m, drawn periodic with plain mip-mapping
    35.6 and 37.2: docs/fitting.md, "A small photo is its own tile"). Low-passed it scores 47.3 (15 m:
    49.3), every view >= 43; the control, without mip-maps, 18-30 dB less on every minified view."""
    assert fitted_small.layers[0].tiling == "stochastic" and fitted_small.tiles[0].shape[0] == 64
    low, gl_low, plain = {}, {}, {}
    for name, _, c, g, ref, no_mip in views_against_reference(fitted_small, gl):
        low[name], gl_low[name] = psnr_low(c, ref), psnr_low(g, ref)
        plain[name] = psnr_low(no_mip, ref)
    assert min(low.values()) >= 40.0 and min(gl_low.values()) >= 40.0, (low, gl_low)
    assert all(plain[k] <= low[k] - 8.0 for k in VIEWS if k != "close"), (low, plain)



@pytest.fixture(scope="module")
def fitted_tiles():
    """spectex.fit's default on a procedural floor of 64-texel tiles in grout (a snapped stochastic finest
    layer whose tile has a cell map: each floor tile from one patch)."""
    from spectex.fitting import fit

    return fit(floor_photo(384, 64)[0], rng=0)


@pytest.mark.slow
@pytest.mark.gl
def test_fitted_tiles_gl_matches_cpu_and_is_alias_free(gl, fitted_tiles):
    """Issue 22's targets on a fitted floor: GL = CPU >= 40 dB, and alias-free against 16 x 16 supersampled
    renders without mip-maps, measured where aliasing shows and a filter's shape does not: both pictures
    low-passed (helpers.psnr_low, a Gaussian of one pixel).

    Full-band, the trilinear filter's grout lines differ from the reference's box over the pixel by design:
    the same tile drawn periodic (plain mip-mapping of its colours, nothing stochastic) scores 37.7 / 36.3 /
    38.4 dB close / ground / grazing on the 448-texel fit of benchmarks' tiles, and one patch over the whole
    close view (no blending, no cells) 34.5 as three patches do: the rest is the Gaussian tile's filtering
    through the histogram table. Low-passed, that periodic tile scores 50-51 dB and a render without mip-maps
    29-34 on the minified views. Before the cells' tables were made per level and the cells kept to a
    4-pixel period, this floor scored 37.8 / 37.3 / 39.0 low-passed (full band 31.1 / 30.9 / 32.5): floor
    tiles in other colours than the supersampled level 0, and cut by the triangle grid's cross-fades where
    they were still 8 to 16 pixels wide."""
    from spectex.shading.resources import cell_maps

    layer = fitted_tiles.layers[0]
    assert layer.tiling == "stochastic" and max(layer.snap) > 0
    assert cell_maps(fitted_tiles)[layer.tile] is not None  # the cells' path is what is measured
    low, gl_low, full, plain = {}, {}, {}, {}
    for name, _, c, g, ref, no_mip in views_against_reference(fitted_tiles, gl):
        low[name], gl_low[name] = psnr_low(c, ref), psnr_low(g, ref)
        full[name] = min(psnr(c, ref), psnr(g, ref))
        plain[name] = psnr_low(no_mip, ref)
    assert min(low.values()) >= 40.0 and min(gl_low.values()) >= 40.0, (low, gl_low)
    assert min(full.values()) >= 32.0, full
    # the control: without mip-maps the low-passed figure is far worse wherever the view minifies
    assert all(plain[k] <= low[k] - 8.0 for k in VIEWS if k != "close"), (low, plain)


def _two_toned_floor(n=128, rng=5):
    """Four square tiles of different colours (2 x 2 periods of 64 texels), each with a little noise,
    between light grout lines 6 texels wide: a fitted floor's tile, drawn with its offsets snapped."""
    rng = np.random.default_rng(rng)
    y, x = np.mgrid[0:n, 0:n]
    cell = (y // 64) * 2 + (x // 64)
    colours = np.array([[0.55, 0.30, 0.25], [0.65, 0.40, 0.25], [0.50, 0.25, 0.30], [0.70, 0.35, 0.30]])
    tile = colours[cell] + 0.02 * rng.standard_normal((n, n, 1))
    grout = ((y % 64) < 6) | ((x % 64) < 6)
    tile[grout] = 0.85 + 0.02 * rng.standard_normal((int(grout.sum()), 1))
    return np.clip(tile, 0.0, 1.0).astype(np.float32), grout


def test_stochastic_blend_makes_no_value_none_of_its_patches_has():
    from spectex.shading.stochastic import keep_between, sample_stochastic
    from spectex.shading.stochastic import stochastic_tables as tile_tables

    # the rule itself: the blended Gaussian value stays between the three sources
    assert keep_between(0.9, 0.6, 0.7, 0.65) == 0.7 and keep_between(0.1, 0.6, 0.7, 0.65) == 0.6
    assert keep_between(0.66, 0.6, 0.7, 0.65) == 0.66
    tile, grout = _two_toned_floor()
    tables = tile_tables(tile)
    # at texel centres (the offsets are whole periods): the bilinear filter does not mix grout in
    s, t = np.meshgrid(np.arange(0.5, 1024) / 128, np.arange(0.5, 1024) / 128)
    out = sample_stochastic(tables, s.ravel(), t.ravel(), patch=0.4, seed=3, snap=(2, 2),
                            lod=np.zeros(s.size)).reshape(1024, 1024, 4)
    inside = ~np.tile(grout, (8, 8))
    inside &= np.tile(~np.roll(grout, 1, 0) & ~np.roll(grout, -1, 0) & ~np.roll(grout, 1, 1)
                      & ~np.roll(grout, -1, 1), (8, 8))
    # Inside the tiles (a texel away from the grout) no patch has the grout's light grey. The
    # variance-preserving blend divides by |w| < 1 between the vertices: where two tiles of
    # different colours are both above the mean in a decorrelated channel it pushed the value
    # into the Gaussian's tail, which the table maps to the grout (light specks inside the tiles:
    # 0.54 % of the inside measured before the blend was kept between its sources).
    light = out[..., :3].mean(axis=2) > 0.7
    assert float(np.mean(light[inside])) < 1e-4, float(np.mean(light[inside]))
    # the tiles keep their own colours' spread (the blend is not flattened to a mean)
    assert float(np.std(out[..., 0][inside])) > 0.5 * float(np.std(tile[..., 0][~grout]))
