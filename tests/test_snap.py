"""Layer.snap: stochastic patches offset by whole structure periods keep a brick grid and do not repeat.

A running-bond brick tile (rows offset by half a brick, so the lattice along y is two rows) of
whole periods, drawn three ways: periodic (keeps the grid, repeats), stochastic (does not repeat,
breaks the grid), stochastic with ``snap`` (keeps the grid, does not repeat). Every route that
draws a stochastic layer takes the snap: the CPU kernels (general and fast path), GL, and the
exports through their fixtures (tests/test_export*.py, tests/test_engines_real.py,
tests/test_web_viewer.py snap one stochastic layer to 4 x 3 periods).
"""

import tomllib

import numpy as np
import pytest
import tomli_w

from helpers import SIZE, VIEWS, psnr
from spectex import metrics
from spectex.render import bake
from spectex.render.cpu import render_cpu
from spectex.shading.stochastic import layer_key, lowbias32, sample_stochastic, stochastic_tables, triangle_grid_matrix
from spectex.texture import Layer, SpectralTexture

BRICK_W, BRICK_H = 16, 8


def bricks(nx, ny, *, mortar=2, rng=0, mottle=0.0):
    """Running bond: ``ny`` periods of two rows of ``nx`` bricks (16 x 8 px); each brick its own grey
    with grain, mortar 0.1; ``mottle``: that much smooth variation (Gaussian noise of 4 and 24 px)
    over everything, as a photo has. Returns RGBA ``(16 ny, 16 nx, 4)`` and the mortar mask."""
    from scipy import ndimage

    rng = np.random.default_rng(rng)
    h, w = ny * 2 * BRICK_H, nx * BRICK_W
    yy, xx = np.mgrid[0:h, 0:w]
    row = yy // BRICK_H
    shift = (row % 2) * (BRICK_W // 2)
    ident = row * nx + ((xx + shift) // BRICK_W) % nx
    img = rng.uniform(0.45, 0.9, ident.max() + 1)[ident] + 0.05 * rng.standard_normal((h, w))
    is_mortar = (yy % BRICK_H < mortar) | ((xx + shift) % BRICK_W < mortar)
    img[is_mortar] = 0.1
    for sigma in (4.0, 24.0):
        smooth = ndimage.gaussian_filter(rng.standard_normal((h, w)), sigma, mode="wrap")
        img += mottle * smooth / smooth.std()
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[:, :, :3] = np.clip(img, 0.0, 1.0)[:, :, None]
    return rgba, is_mortar


@pytest.fixture(scope="module")
def brick_tile():
    return bricks(8, 8)  # 128 x 128: 8 bricks across, 8 periods of two rows down


def _bake(tile, **kw):
    tex = SpectralTexture(tile, [Layer(size=1.0, **kw)])
    return bake(tex, (512, 512), pixel_size=1.0 / tile.shape[1])


def test_snapped_offsets_are_whole_periods_rounded_down_to_texels():
    # at a grid vertex one patch has weight 1: the texel shown is the un-offset one moved by the
    # vertex's snapped offset, k = (u16 * n) >> 16 periods of 128 / n texels (rounded down)
    tile = bricks(8, 8, rng=3)[0]
    tables = stochastic_tables(tile)
    grid = triangle_grid_matrix(0.5)
    ij = np.random.default_rng(2).integers(-1000, 1000, size=(3000, 2))
    st = ij @ np.linalg.inv(grid).T
    h = lowbias32(ij[:, 0].astype(np.uint32) ^ lowbias32(ij[:, 1].astype(np.uint32) ^ np.uint32(layer_key(7))))

    def expected(nx, ny):
        kx = ((h & 0xFFFF).astype(np.int64) * nx) >> 16
        ky = ((h >> 16).astype(np.int64) * ny) >> 16
        col = (np.floor(st[:, 0] * 128).astype(np.int64) + kx * 128 // nx) % 128
        row = (np.floor(st[:, 1] * 128).astype(np.int64) + ky * 128 // ny) % 128
        return tile[row, col]

    for snap, counts in (((8, 3), (8, 3)), ((0, 5), (128, 5)), ((0, 0), (128, 128))):
        out = sample_stochastic(tables, st[:, 0], st[:, 1], patch=0.5, seed=7, snap=snap, lod=0.0, filter="nearest")
        assert np.abs(out - expected(*counts)).mean() < 0.3 / 255.0, snap
    # control: the snapped layer does not show what the unsnapped offsets point to
    out = sample_stochastic(tables, st[:, 0], st[:, 1], patch=0.5, seed=7, snap=(8, 3), lod=0.0, filter="nearest")
    assert np.abs(out - expected(128, 128)).mean() > 20.0 / 255.0


def test_snap_keeps_the_brick_grid_and_does_not_repeat(brick_tile):
    tile, mortar = brick_tile
    wall = bricks(32, 32, rng=5)[0][:, :, :3]  # "the photo": the same kind of wall, other bricks
    yy, xx = np.mgrid[0:512, 0:512]
    on_mortar = mortar[yy % 128, xx % 128]
    period = (2 * BRICK_H, BRICK_W)
    got = {}
    for name, kw in (("snap", dict(tiling="stochastic", seed=3, snap=(8, 8))),
                     ("periodic", dict(tiling="periodic")), ("free", dict(tiling="stochastic", seed=3))):
        baked = _bake(tile, **kw)
        got[name] = dict(mortar=float(np.mean(baked[..., 0][on_mortar] < 0.2)),
                         brick=float(np.mean(baked[..., 0][~on_mortar] < 0.2)),
                         repeat=metrics.repeat_peak(baked, period=period),
                         exact=metrics.repetition(baked, 128),
                         structure=metrics.structural_distance(baked, wall).ratio)
    snap, periodic, free = got["snap"], got["periodic"], got["free"]
    # the grid: every mortar pixel of the lattice is mortar, no brick pixel is (measured 1.0 / 0.0)
    assert snap["mortar"] >= 0.99 and snap["brick"] <= 0.01, got
    # its content does not repeat: the repeat beyond the structure's own lattice (measured 0.10; the
    # periodic tile 1.0, the photo itself 0.05) and exact copies one tile away (0.01; periodic 1.0)
    assert snap["repeat"] <= 0.25 and snap["exact"] <= 0.05, got
    # the structure measure no worse than the periodic tile's (measured 1.42 against 1.59)
    assert snap["structure"] <= periodic["structure"] * 1.05, got
    # controls: periodic repeats, stochastic without snap breaks the grid (mortar 0.28, ghosts)
    assert periodic["repeat"] >= 0.9 and periodic["exact"] >= 0.9, got
    assert free["mortar"] <= 0.6 and free["structure"] >= snap["structure"] + 0.2, got


def test_repeat_peak_period_removes_the_lattice_only():
    wall = bricks(32, 32, rng=5)[0][:, :, :3]
    plain = metrics.repeat_peak(wall)
    assert plain > 0.8  # the mortar grid is a repeat of its own
    assert metrics.repeat_peak(wall, period=(16, 16)) < 0.1
    # control: the wrong lattice (one row, where the bond repeats every two) leaves the joints
    assert metrics.repeat_peak(wall, period=(8, 16)) > 0.5
    with pytest.raises(ValueError, match="period"):
        metrics.repeat_peak(wall, period=16)
    with pytest.raises(ValueError, match=r"period\[1\]"):
        metrics.repeat_peak(wall, period=(16, 1))


def _snapped_texture(snap):
    tile = bricks(8, 8, rng=1)[0]
    layers = SpectralTexture.paper_preset(tile, tiling="stochastic").layers
    layers = [Layer(**{**lay.__dict__, "snap": snap if k < 3 else (0, 0)}) for k, lay in enumerate(layers)]
    return SpectralTexture(tile, layers)


@pytest.mark.gl
@pytest.mark.parametrize("name", ["close", "grazing"])
def test_snapped_layers_gl_matches_cpu(gl, name):
    from spectex.render.gl import GLRenderer

    tex = _snapped_texture((8, 3))  # 3 does not divide the 128-texel tile: offsets rounded down to texels
    cam = VIEWS[name]
    with GLRenderer(tex, ctx=gl) as r:
        g = r.render(cam, SIZE)
    c = render_cpu(tex, cam, SIZE)
    assert psnr(g, c) >= 40.0
    # control: the same layers unsnapped draw another picture
    with GLRenderer(_snapped_texture((0, 0)), ctx=gl) as r:
        assert psnr(r.render(cam, SIZE), c) < 35.0


def test_snapped_cpu_fast_path_matches_the_general_sampler():
    from helpers import fast_and_general
    from spectex.shading import pack

    tex = _snapped_texture((8, 3))
    assert pack(tex).fast
    fast, general = fast_and_general(tex, (3.0e4, -2.0e4, 2.0), (24, 40))
    diff = np.abs(fast - general)
    assert np.mean(diff > 1e-5) <= 0.01 and diff.max() <= 0.03
    # control: the fast path without the snap is another picture
    unsnapped = fast_and_general(_snapped_texture((0, 0)), (3.0e4, -2.0e4, 2.0), (24, 40))[0]
    assert np.abs(unsnapped - fast).mean() > 0.01
    # the bake (general kernel) agrees with the standalone sampler, snapped
    layer = tex.layers[0]
    p = layer.size / 128
    baked = bake(SpectralTexture(tex.tiles, [layer]), (64, 64), pixel_size=p)
    r, c = np.mgrid[0:64, 0:64]
    s, t = layer.coords((c + 0.5) * p, (r + 0.5) * p)
    m = layer.matrix()
    ref = sample_stochastic(stochastic_tables(tex.tiles[0]), s, t, patch=layer.patch, seed=layer.seed, snap=(8, 3),
                            dsdx=m[0, 0] * p, dtdx=m[1, 0] * p, dsdy=m[0, 1] * p, dtdy=m[1, 1] * p)
    assert np.max(np.abs(baked - ref[..., :3])) < 2e-3


def test_snap_is_saved_loaded_and_checked(tmp_path):
    tex = _snapped_texture((8, 3))
    path = tex.save(tmp_path / "wall.toml")
    doc = tomllib.loads(path.read_text())
    # a layer without snap writes nothing (such files stay readable by a spectex without the field)
    assert [entry.get("snap") for entry in doc["layers"]] == [[8, 3]] * 3 + [None] * (len(tex.layers) - 3)
    back = SpectralTexture.load(path)
    assert [lay.snap for lay in back.layers] == [lay.snap for lay in tex.layers]
    for bad in ((1,), (-1, 0), (1.5, 2), (True, 0), (257, 0), "4x3", 4):
        with pytest.raises(ValueError, match=r"^snap must be a pair \(nx, ny\)"):
            Layer(size=1.0, tiling="stochastic", snap=bad)
    with pytest.raises(ValueError, match="snap"):
        sample_stochastic(stochastic_tables(tex.tiles[0]), 0.0, 0.0, snap=(0, -2))
    doc["layers"][0]["snap"] = [8, 300]
    bad_file = tmp_path / "bad.toml"
    bad_file.write_text(tomli_w.dumps(doc))
    with pytest.raises(ValueError, match=r"layers\[0\]\.snap.*300"):
        SpectralTexture.load(bad_file)


@pytest.fixture(scope="module")
def wall_fits():
    """spectex.fit of a 256 x 256 running-bond wall: the default (the trial picks the snapped way) and
    the control forced periodic (the period-cut tile repeated)."""
    from spectex.fitting import fit_result

    photo = bricks(16, 16, rng=9, mottle=0.05)[0][:, :, :3]
    return photo, {name: fit_result(photo, pixel_size=0.01, layers=3, iterations=1, tiling=tiling)
                   for name, tiling in (("auto", "auto"), ("periodic", "periodic"))}


def test_fit_of_a_brick_wall_keeps_the_grid_without_repeating(wall_fits):
    photo, fits = wall_fits
    auto = fits["auto"]
    assert auto.params["period_px"] == (16, 16)
    assert auto.params["trial"]["choice"] == "snapped" and auto.texture.layers[0].snap == (15, 15)
    got = {}
    for name, result in fits.items():
        near = bake(result.texture, (512, 512), pixel_size=0.01)
        far = bake(result.texture, (512, 512), pixel_size=0.08)
        got[name] = dict(near=metrics.repeat_peak(near, period=(16, 16)), far=metrics.repeat_peak(far, period=(2, 2)),
                         structure=metrics.structural_distance(near[:256, :256], photo).ratio)
    own = metrics.repeat_peak(photo, period=(16, 16))
    # the content does not repeat (the lattice removed; far: 8x out, where the lattice is 2 px)
    assert got["auto"]["near"] <= own + 0.15 and got["auto"]["far"] <= 0.1, (own, got)
    # structure as close as the photo is to itself (about 1), and within the measure's spread between
    # windows of one photo (about 0.1) of the periodic tile's (measured 0.99 against 0.89)
    assert got["auto"]["structure"] <= 1.1 and got["auto"]["structure"] <= got["periodic"]["structure"] + 0.15, got
    # the control: the periodic fit repeats
    assert got["periodic"]["near"] >= 0.5 and got["periodic"]["near"] >= got["auto"]["near"] + 0.3, got


def subpixel_wall(side, *, brick=33.4, row=15.3, mortar=2.5, rng=0, random_length=False, turn=0.0, fan=0.0, ss=4,
                  homography=None):
    """A running-bond wall photo whose bricks are ``brick`` x ``row`` pixels (not whole numbers),
    brick-coloured with grain, rendered at ``ss`` x ``ss`` samples per pixel. ``random_length``:
    every brick its own length (0.5 to 1.5 ``brick``), so no period across, rows still regular.
    ``turn``: the wall turned by that many degrees; ``fan``: in perspective, its bricks' length
    changing by that fraction from top to bottom (the vertical joints fan out); ``homography``:
    a 3 x 3 matrix from the wall's plane to the photo, both in pixels about the photo's centre
    (the photo is the wall seen in perspective)."""
    rng = np.random.default_rng(rng)
    n = side * ss
    yy, xx = (np.mgrid[0:n, 0:n] + 0.5) / ss
    c = side / 2.0
    if homography is not None:
        q = np.tensordot(np.linalg.inv(homography), np.stack([xx - c, yy - c, np.ones_like(xx)]), axes=1)
        xx, yy = c + q[0] / q[2], c + q[1] / q[2]
    if fan:
        xx = c + (xx - c) / (1.0 + fan * (yy - c) / side)
    if turn:
        t = np.deg2rad(turn)
        xx, yy = c + (xx - c) * np.cos(t) - (yy - c) * np.sin(t), c + (xx - c) * np.sin(t) + (yy - c) * np.cos(t)
    r = np.floor(yy / row).astype(np.int64)
    if random_length:
        edges = np.cumsum(rng.uniform(0.5, 1.5, (r.max() + 1, int(2 * side / brick) + 4)) * brick, axis=1)
        edges -= rng.uniform(0.0, brick, (r.max() + 1, 1))
        col = np.empty_like(r)
        u = np.empty_like(xx)
        for k in range(r.max() + 1):
            m = r == k
            j = np.searchsorted(edges[k], xx[m])
            col[m] = j
            u[m] = xx[m] - np.concatenate([[edges[k][0] - 2 * brick], edges[k]])[j]
        vert = u < mortar
    else:
        shift = (r % 2) * brick / 2.0
        col = np.floor((xx + shift) / brick).astype(np.int64)
        vert = np.mod(xx + shift, brick) < mortar
    ident = (r - r.min()) * (col.max() - col.min() + 2) + col - col.min()
    colours = np.clip(np.array([0.55, 0.25, 0.18]) + rng.normal(0.0, 0.07, (ident.max() + 1, 3))
                      + rng.normal(0.0, 0.06, (ident.max() + 1, 1)), 0.0, 1.0)
    img = colours[ident] + 0.03 * rng.standard_normal((n, n))[:, :, None]
    img[vert | (np.mod(yy, row) < mortar)] = (0.72, 0.7, 0.66)
    img = img.reshape(side, ss, side, ss, 3).mean(axis=(1, 3)) + 0.02 * rng.standard_normal((side, side))[:, :, None]
    return np.clip(img, 0.0, 1.0)


def _lattice_share(image, period):
    """Fraction of the luma's variance that its mean over the lattice of ``period`` holds: about the
    photo's own where the mortar lines stay on the lattice, less where patches put them off it."""
    lum = image.mean(axis=2)
    detail = lum - lum.mean()
    return float(np.var(metrics._lattice_mean(detail, period)) / np.var(detail))


def test_structure_period_is_subpixel_and_refuses_a_period_the_bricks_do_not_have():
    from spectex.fitting._structure import structure_period

    py, px = structure_period(subpixel_wall(320))
    # 33.4 across; down, the bond's two rows of 15.3 (a whole-pixel estimate is 0.4 px off across)
    assert abs(px - 33.4) <= 0.05 and abs(py - 30.6) <= 0.15, (py, px)
    # bricks of random length: the rows stay (15.3 px), there is no period across
    py, px = structure_period(subpixel_wall(320, random_length=True, rng=2))
    assert px is None and py is not None and abs(py - 15.3) <= 0.1, (py, px)


def test_structure_period_reads_a_running_bond_with_no_period_across_by_its_row():
    """Bricks too long for three to fit across the photo (2.7 here): no period across, and down the wall the
    highest peak is the bond's two rows (the rows are offset by half a brick). The fit cuts each row at its
    own joints, so the row is the period; with a period across, the bond's two rows stay (the lattice)."""
    from spectex.fitting import _structure
    from spectex.fitting._structure import structure_period

    photo = subpixel_wall(320, brick=120.0, row=27.3, mortar=3.0, rng=3)
    py, px = structure_period(photo)
    assert px is None and py is not None and abs(py - 27.3) <= 0.1, (py, px)
    # what the rows' axis reads on its own: its highest peak two rows, its half the row
    from spectex.color import luma

    lum = luma(photo, dtype=np.float64)
    lum = lum - lum.mean()
    acf = np.fft.irfft2(np.abs(np.fft.rfft2(lum)) ** 2, s=lum.shape)
    acf /= acf[0, 0]
    full, course = _structure._axis_period(acf, acf, 8)
    assert abs(full - 54.6) <= 0.3 and abs(course - 27.3) <= 0.1, (full, course)
    # the control: a bond whose bricks repeat across keeps its two rows
    py, px = structure_period(subpixel_wall(320, brick=33.4, row=15.3, rng=3))
    assert abs(py - 30.6) <= 0.15 and abs(px - 33.4) <= 0.05, (py, px)


def _tile_grid(side, *, period=64, grout=5, rng=11):
    """Square tiles of slightly different colours in light grout, every ``period`` pixels, RGB."""
    rng = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side]
    cells = (yy // period) * (side // period + 1) + xx // period
    img = (np.array([0.7, 0.42, 0.3]) + rng.normal(0.0, 0.03, (cells.max() + 1, 3)))[cells]
    img *= 1.0 + 0.04 * rng.standard_normal((side, side, 1))
    fy, fx = yy % period, xx % period
    line = (np.minimum(fy, period - 1 - fy) < grout / 2) | (np.minimum(fx, period - 1 - fx) < grout / 2)
    img[line] = 0.78
    return np.clip(img, 0.0, 1.0).astype(np.float32)


@pytest.mark.parametrize("origin", [(0, 0), (100, 37), (21, 50)])
def test_structure_period_refuses_a_period_the_crop_shows_too_few_times(origin):
    from spectex.fitting import _structure
    from spectex.fitting._structure import structure_period

    grid = _tile_grid(512)
    y, x = origin
    # 96 pixels hold 1.5 tiles: the circular autocorrelation has a false peak at the gap its
    # wrap-around leaves (34.6 px at the corner, 32 px here and there); nothing confirms it
    assert structure_period(grid[y:y + 96, x:x + 96]) == (None, None)
    # the control: 256 pixels hold four tiles, found on both axes
    py, px = structure_period(grid[y:y + 256, x:x + 256])
    assert abs(py - 64.0) <= 0.5 and abs(px - 64.0) <= 0.5, (py, px)
    # at least PERIOD_MIN_REPEATS periods across: 192 pixels (3 tiles) are enough, 160 (2.5) are not
    assert structure_period(grid[y:y + 192, x:x + 192]) != (None, None)
    assert structure_period(grid[y:y + 160, x:x + 160]) == (None, None)
    assert _structure.PERIOD_MIN_REPEATS == 3.0


def test_snapped_tile_of_a_subpixel_period_keeps_the_mortar_across_patches():
    from spectex.fitting._auto import _period_tile

    photo = subpixel_wall(320, rng=1)
    got = {}
    for name, period in (("subpixel", (30.6, 33.4)), ("whole", (31.0, 33.0))):
        tile, side, (ky, kx), (qy, qx), _ = _period_tile(photo, period)
        # whole periods of whole texels across, so the snapped offsets (whole texels) are whole periods
        assert side == kx * qx and qx == round(period[1]), (side, ky, kx, qy, qx)
        rgba = np.ones((side, side, 4), dtype=np.float32)
        rgba[:, :, :3] = tile
        baked = bake(SpectralTexture(rgba, [Layer(size=1.0, tiling="stochastic", seed=3, snap=(kx, ky))]),
                     (512, 512), pixel_size=1.0 / side)
        got[name] = _lattice_share(baked, (side / ky, side / kx))
    own = _lattice_share(photo, (30.6, 33.4))
    # the mortar stays on the lattice across patches as in the photo (0.758 drawn without cells, the photo
    # 0.745; 0.742 with the cell map of its fractional rows, since 2026-11-26: each brick whole from one
    # patch, whose snapped offset is rounded to whole texels, so a brick's mortar may sit a fraction of a
    # texel off its neighbours', where without cells a patch boundary made bricks of two tones)
    assert got["subpixel"] >= 0.97 * own, (own, got)
    # control: the whole-pixel period (33 for 33.4) puts nine periods 3.6 px off: mortar doubled and
    # offset at patch edges (measured 0.48)
    assert got["whole"] <= 0.7 * own, (own, got)


def test_fit_straightens_a_turned_wall_and_says_when_a_photo_is_in_perspective():
    from spectex.fitting import fit_result
    from spectex.fitting._auto import _period_tile
    from spectex.fitting._structure import structure_period

    turned = subpixel_wall(320, rng=4, turn=3.0)
    result = fit_result(turned, pixel_size=0.01, layers=2, iterations=1)
    # the wall's lines are found 3 degrees off the axes and straightened before the period is read
    assert abs(result.params["orientation_deg"] + 3.0) <= 0.3, result.params["orientation_deg"]
    assert any(n.startswith("turned the photo by") for n in result.notes), result.notes
    py, px = result.params["period_px"]
    assert abs(px - 33.4) <= 0.25 and abs(py - 30.6) <= 0.3, (py, px)
    # its tile keeps the mortar on the lattice across snapped patches (measured 0.71; a square-on
    # wall's photo 0.74)
    tile = result.texture.tiles[0]
    side = tile.shape[0]
    qy, qx = result.params["tile_period_px"]
    kx, ky = side // qx, round(side / qy)
    baked = bake(SpectralTexture(tile, [Layer(size=1.0, tiling="stochastic", seed=3, snap=(kx, ky))]),
                 (512, 512), pixel_size=1.0 / side)
    straight = _lattice_share(baked, (side / ky, side / kx))
    # control: the same wall cut without straightening (its lattice 1.7 px off per period; measured 0.02)
    period = structure_period(turned)
    crude, cside, (cky, ckx), _, _ = _period_tile(turned, period)
    rgba = np.ones((cside, cside, 4), dtype=np.float32)
    rgba[:, :, :3] = crude
    baked = bake(SpectralTexture(rgba, [Layer(size=1.0, tiling="stochastic", seed=3, snap=(ckx, cky))]),
                 (512, 512), pixel_size=1.0 / cside)
    unturned = _lattice_share(baked, (cside / cky, cside / ckx))
    assert straight >= 0.55 and unturned <= 0.5 * straight, (straight, unturned)
    # a wall in perspective (bricks 25% longer at the bottom than the top) is said to be (and rectified,
    # tests/test_perspective.py); a square-on one is not
    fanned = fit_result(subpixel_wall(320, rng=4, fan=0.25), pixel_size=0.01, layers=2, iterations=1)
    assert any("perspective" in n for n in fanned.notes), fanned.notes
    assert fanned.params["orientation_drift_deg"] > 1.5
    square = fit_result(subpixel_wall(320, rng=4), pixel_size=0.01, layers=2, iterations=1)
    assert not any("perspective" in n or "turned" in n for n in square.notes), square.notes
