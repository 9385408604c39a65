"""Snapped stochastic layers keep whole bricks and floor tiles (issue 22): the cell map, the samplers, the measure."""

import numpy as np
import pytest

from helpers import SIZE, VIEWS, assert_gl_matches_cpu, fast_path_against_general, psnr
from helpers import floor_photo as _floor


def _running_bond(periods=4, rng=2):
    """Bricks 32 x 8 texels (mortar 2 texels at their left and top), every second course shifted by half a
    brick: a period cell of 32 x 16 texels whose second course's brick straddles its edge."""
    rng = np.random.default_rng(rng)
    n = 32 * periods
    yy, xx = np.mgrid[0:n, 0:n]
    course = yy // 8
    shift = np.where(course % 2 == 1, 16, 0)
    brick = course * 64 + (xx + shift) // 32
    colour = rng.uniform(0.2, 0.6, brick.max() + 1)[brick]
    mortar = ((xx + shift) % 32 < 2) | (yy % 8 < 2)
    img = np.where(mortar, 0.9, colour)[:, :, None] + 0.01 * rng.standard_normal((n, n, 3))
    return np.clip(img, 0.0, 1.0).astype(np.float32), mortar


# ------------------------------------------------------------------ the cell map
def test_cell_map_points_every_texel_of_a_floor_tile_to_its_centre():
    from spectex.shading._cells import cell_map

    tile, grout = _floor(256, 64)
    cells = cell_map(tile, (4, 4))
    assert cells.shape == (256, 256, 2) and cells.dtype == np.float32
    yy, xx = np.mgrid[0:256, 0:256]
    cx, cy = xx + cells[:, :, 0], yy + cells[:, :, 1]
    # interior texels: the centre of their own floor tile (its interior's mean position, 31.5 in its period)
    inside = ~grout
    assert np.all(np.abs(cx[inside] - (xx[inside] // 64 * 64 + 31.5)) <= 0.5)
    assert np.all(np.abs(cy[inside] - (yy[inside] // 64 * 64 + 31.5)) <= 0.5)
    # the grout goes to its nearest floor tile: no texel further than half a period from its centre
    assert np.abs(cells).max() <= 32.5
    # half texels, exact in half floats
    assert np.array_equal(cells, cells.astype(np.float16).astype(np.float32))
    assert np.array_equal(2 * cells, np.round(2 * cells))


def test_cell_map_joins_a_brick_across_the_period_cells_edge():
    """Running bond: the shifted course's brick straddles the period cell's edge; on the torus it is one
    cell, so its two ends (left and right of the period cell) point to one centre, a period apart."""
    from spectex.shading._cells import cell_map

    tile, mortar = _running_bond()
    cells = cell_map(tile, (4, 8))
    assert cells is not None
    y = 8 + 4  # the shifted course
    left = 4 + cells[y, 4, 0]
    right = 28 + cells[y, 28, 0]
    assert abs((right - left) - 32.0) <= 0.5, (left, right)
    # an unshifted course's brick is whole inside the period cell: one centre for both ends
    assert abs((4 + cells[4, 4, 0]) - (28 + cells[4, 28, 0])) <= 0.5


def test_cell_map_refuses_a_tile_without_grout_or_with_stripes():
    from spectex.shading._cells import cell_map

    rng = np.random.default_rng(0)
    noise = rng.random((256, 256, 3)).astype(np.float32)
    assert cell_map(noise, (4, 4)) is None
    # unsnapped, (0, 0), the cells are read on the tile itself (free_cell_map): the floor tiles, as snapped
    floor, grout = _floor(256, 64)
    free, snapped = cell_map(floor, (0, 0)), cell_map(floor, (4, 4))
    assert free is not None and np.abs(free - snapped)[~grout].max() <= 0.5
    assert cell_map(_floor(256, 64)[0], (3, 4)) is None  # folded by 3 periods across a floor of 4: no cells
    # horizontal grout only: the interiors run around along x, bands, not cells to keep whole
    tile, grout = _floor(256, 64)
    stripes = tile.copy()
    yy = np.arange(256)[:, None] % 64
    stripes[(np.minimum(yy, 63 - yy) >= 2.5) & np.broadcast_to(grout, grout.shape)] = tile[10, 10]
    assert cell_map(stripes, (4, 4)) is None
    assert cell_map(tile, (4, 4)) is not None  # (the control: the same floor with its vertical grout)


def _mosaic(n=256, period=32, grout=2, rng=0):
    """A mosaic: square tiles of any colour (each channel uniform over 0.05-0.95) in thin grey grout, 8 x 8
    periods of 32 texels: the tiles' own colours vary far more than the grout stands out of their mean."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:n, 0:n]
    k = (yy // period) * (n // period) + xx // period
    img = gen.uniform(0.05, 0.95, (k.max() + 1, 3))[k] + 0.02 * gen.standard_normal((n, n, 3))
    fy, fx = yy % period, xx % period
    g = (np.minimum(fy, period - 1 - fy) < grout / 2) | (np.minimum(fx, period - 1 - fx) < grout / 2)
    img[g] = 0.4 + 0.02 * gen.standard_normal((int(g.sum()), 3))
    return np.clip(img, 0.0, 1.0).astype(np.float32), g


@pytest.mark.parametrize("rng", [0, 1, 2])
def test_cell_map_finds_the_cells_of_a_mosaic_of_many_colours(rng):
    """A tile's own colour is its colouring, not an absence of structure: the structure's strength is weighed
    against the texture within the cells, each cell of each period at its own level. The control: against the
    texels about the mean period cell alone (the rule before), each tile's colour counts as noise and the
    mosaic's structure is under ``MIN_CONTRAST`` of it (no map, so the patches' straight boundaries cut tiles)."""
    from spectex.shading._cells import MIN_CONTRAST, cell_map

    tile, grout = _mosaic(rng=rng)
    level = tile.reshape(8, 32, 8, 32, 3)
    mean = level.mean(axis=(0, 2))
    axis = np.linalg.svd((mean - mean.mean(axis=(0, 1))).reshape(-1, 3), full_matrices=False)[2][0]
    about_mean = float(np.mean(((level - mean[None, :, None]) @ axis) ** 2))
    assert float(np.var(mean @ axis)) < MIN_CONTRAST * about_mean  # the rule before refused it
    cells = cell_map(tile, (8, 8))
    assert cells is not None
    yy, xx = np.mgrid[0:256, 0:256]
    inside = ~grout
    assert np.all(np.abs(xx + cells[:, :, 0] - (xx // 32 * 32 + 15.5))[inside] <= 0.5)
    assert np.all(np.abs(yy + cells[:, :, 1] - (yy // 32 * 32 + 15.5))[inside] <= 0.5)


# ------------------------------------------------------------------ the sampler
def _sample(tile, cells, shape=(768, 768), lod=0.0, seed=3):
    from spectex.shading.stochastic import sample_stochastic, stochastic_tables

    n = tile.shape[0]
    s, t = np.meshgrid((np.arange(shape[1]) + 0.5) / n, (np.arange(shape[0]) + 0.5) / n)
    return sample_stochastic(stochastic_tables(tile), s, t, patch=0.5, seed=seed, snap=(4, 4), cells=cells,
                             lod=np.full(s.shape, lod))[:, :, :3]


def _tile_spread(image, period=64, margin=6):
    """Per floor tile of a picture on the tile's grid, the largest distance of its quadrants' mean colours."""
    h, w = image.shape[:2]
    out = []
    for y0 in range(0, h - period + 1, period):
        for x0 in range(0, w - period + 1, period):
            cell = image[y0 + margin:y0 + period - margin, x0 + margin:x0 + period - margin]
            m = cell.shape[0] // 2
            q = [cell[:m, :m], cell[:m, m:], cell[m:, :m], cell[m:, m:]]
            means = np.array([c.reshape(-1, 3).mean(axis=0) for c in q])
            out.append(np.linalg.norm(means[:, None] - means[None], axis=2).max())
    return np.array(out)


def test_snapped_sample_draws_each_floor_tile_from_one_patch():
    from spectex.shading._cells import cell_map

    tile, _ = _floor(256, 64, spread=0.12, mottle=0.01)
    cells = cell_map(tile, (4, 4))
    whole = _tile_spread(_sample(tile, cells))
    split = _tile_spread(_sample(tile, None))
    own = _tile_spread(tile)
    # with cells, a floor tile's quadrants differ no more than the tile's own (its mottling); without,
    # the triangle grid's patch boundaries cross tiles: some are made of two (the control)
    assert whole.max() <= 1.2 * own.max() + 0.005, (whole.max(), own.max())
    assert np.mean(split > 2.0 * own.max()) >= 0.05, np.mean(split > 2.0 * own.max())
    # the cells hold while a period (64 texels) spans 4 pixels or more, lambda <= 6 - CELL_LOD_MARGIN; from
    # one level further on they are not used: the same numbers as without them
    from spectex.shading.constants import CELL_LOD_MARGIN, SHARP_LOD

    lc = max(SHARP_LOD, 6.0 - CELL_LOD_MARGIN)
    assert lc > SHARP_LOD  # (a floor tile of 64 texels is 16 pixels wide at SHARP_LOD: kept whole there)
    far = lc + 1.0
    np.testing.assert_array_equal(_sample(tile, cells, (64, 64), far), _sample(tile, None, (64, 64), far))
    assert not np.array_equal(_sample(tile, cells, (64, 64), lc), _sample(tile, None, (64, 64), lc))
    # in between, a mix of the two: between them (no popping)
    mid = _sample(tile, cells, (128, 128), lc + 0.5)
    lo, hi = _sample(tile, cells, (128, 128), lc), _sample(tile, None, (128, 128), lc + 0.5)
    assert np.abs(mid - lo).mean() < np.abs(lo - hi).mean() and np.abs(mid - hi).mean() < np.abs(lo - hi).mean()


def _texture(tile, snap):
    from spectex.texture import Layer, SpectralTexture

    coarse = np.full(tile.shape[:2] + (4,), 0.5, np.float32)
    rgba = np.concatenate([tile, np.ones(tile.shape[:2] + (1,), np.float32)], axis=2)
    return SpectralTexture([rgba, coarse], [Layer(size=2.0, tile=0, tiling="stochastic", patch=0.5, snap=snap),
                                            Layer(size=8.0, tile=1, opacity=0.2)])


def test_pack_uses_cells_only_for_the_stochastic_layers_tile(monkeypatch):
    from spectex.shading import _cells, resources
    from spectex.shading.resources import cell_rows, stochastic_store
    from spectex.shading.tables import pack

    tile, _ = _floor(256, 64)
    snapped = _texture(tile, (4, 4))
    plain = _texture(tile, (0, 0))
    t1, tf = pack(snapped), pack(plain)
    # unsnapped, the floor's cells are read on the tile itself (free_cell_map): rows for them too
    assert tf.cell_row[0] == cell_rows(plain)[0] >= 0 and tf.cell_row[1] == -1.0
    # the control: the same unsnapped texture without its free cells
    monkeypatch.setattr(_cells, "free_cell_map", lambda tile: None)
    resources.clear_cache()
    try:
        t0 = pack(_texture(tile, (0, 0)))
    finally:
        resources.clear_cache()  # (nothing kept that was made without the free cells)
    assert t1.cell_row[0] == cell_rows(snapped)[0] == t0.lut.shape[0] and t1.cell_row[1] == -1.0
    assert np.all(t0.cell_row == -1.0)
    assert t1.lut.shape[0] == t0.lut.shape[0] + 256 * 256 // 1024 == tf.lut.shape[0]
    # the tile with cells has its levels Gaussianised one by one (stochastic_tables(per_level=True)):
    # the same level-0 table, the coarser ones its own
    np.testing.assert_array_equal(t1.lut[0], t0.lut[0])
    assert not np.array_equal(t1.lut[1: t0.lut.shape[0]], t0.lut[1:])
    # a snapped layer on a tile without cells: no rows, no cells
    noise = np.random.default_rng(1).random((256, 256, 3)).astype(np.float32)
    assert pack(_texture(noise, (4, 4))).cell_row[0] == -1.0
    assert stochastic_store(_texture(noise, (4, 4))).lut.shape == stochastic_store(_texture(noise, (0, 0))).lut.shape


def test_gl_matches_cpu_on_a_snapped_floor(gl):
    from spectex.render.cpu import render_cpu

    tile, _ = _floor(256, 64)
    tex = _texture(tile, (4, 4))
    assert_gl_matches_cpu(tex, gl)
    # the cells changed the picture (the control: the same texture unsnapped differs)
    cam = VIEWS["close"]
    assert psnr(render_cpu(tex, cam, SIZE), render_cpu(_texture(tile, (0, 0)), cam, SIZE)) < 35.0


# ------------------------------------------------------------------ the measure
def test_cell_splits_sees_floor_tiles_made_of_two():
    from spectex.metrics import cell_splits
    from spectex.shading._cells import cell_map

    photo, _ = _floor(512, 64)
    period = (64.0, 64.0)
    # the photo against a disjoint crop of itself: about 1
    own = cell_splits(photo[:, :256], photo[:, 256:], period=period)
    assert 0.75 <= own.ratio <= 1.3, own  # (its noise: 0.97-1.21 over three floors)
    tile = photo[:256, :256]
    today = cell_splits(_sample(tile, None, (512, 512)), photo, period=period)
    new = cell_splits(_sample(tile, cell_map(tile, (4, 4)), (512, 512)), photo, period=period)
    # the triangle grid's patches cross the tiles (2.1-2.8 over three floors and two seeds); with the
    # cells within the measure's noise of the photo's own (1.0-1.3; the tile itself 1.06-1.17)
    assert today.ratio >= 1.6, today
    assert new.ratio <= 1.35 and new.ratio <= today.ratio - 0.5, (new, today)
    assert today.cells_image >= 40 and new.cells_image >= 40
    # no structure: no number
    noise = np.random.default_rng(0).random((256, 256, 3)).astype(np.float32)
    assert cell_splits(noise, noise, period=None) is None
    assert cell_splits(noise, noise, period=(32.0, 32.0)) is None  # no grout to find cells by
    with pytest.raises(ValueError, match="period"):
        cell_splits(photo, photo, period=64)


def _cut_short(wall, row, brick, every, rng):
    """``wall`` (a running bond, courses ``row`` pixels high) with a joint of its mortar's colour put across
    every ``every``-th brick, at a third of a brick's length from a random place: bricks cut short."""
    out = wall.copy()
    gen = np.random.default_rng(rng)
    mortar = wall[0, 0]  # the wall's top line is mortar
    for k in range(int(wall.shape[0] // row)):
        for x in gen.uniform(0.0, wall.shape[1], int(wall.shape[1] / brick / every) + 1):
            out[int(k * row):int((k + 1) * row), int(x):int(x) + 3] = mortar
    return out


def test_short_cells_sees_bricks_cut_short():
    """:func:`spectex.metrics.short_cells`: a wall against a disjoint crop of itself reads about its own share;
    the same wall with an extra joint in about every second brick (pieces of random length) reads clearly more
    (0.37-0.45 over three seeds; its own 0.0)."""
    from spectex.metrics import SHORT_CELL, short_cells
    from test_snap import subpixel_wall

    wall = subpixel_wall(512, brick=60.0, row=20.0, mortar=3.0, rng=4)
    period = (20.0, None)
    own = short_cells(wall[:, :256], wall[:, 256:], period=period)
    assert abs(own.excess) <= 0.06 and own.cells_image >= 60, own
    cut = _cut_short(wall, 20.0, 60.0, 2, rng=1)
    short = short_cells(cut[:, :256], wall[:, 256:], period=period)
    # about half the bricks get a joint at a random place: most leave a piece under SHORT_CELL
    assert SHORT_CELL == 0.6
    assert short.excess >= 0.25 and short.excess >= own.excess + 0.25, (short, own)
    # no structure: no number; a bad period: one line naming it
    noise = np.random.default_rng(0).random((256, 256, 3)).astype(np.float32)
    assert short_cells(noise, noise, period=None) is None
    assert short_cells(noise, noise, period=(32.0, 32.0)) is None
    with pytest.raises(ValueError, match="period"):
        short_cells(wall, wall, period=20)


def test_compare_prints_the_cells_of_a_structured_reference(tmp_path, capsys):
    from spectex.cli import main
    from spectex.io import write_image
    from spectex.shading._cells import cell_map

    photo, _ = _floor(512, 64)
    tile = photo[:256, :256]
    write_image(tmp_path / "photo.png", photo)
    write_image(tmp_path / "split.png", _sample(tile, None, (512, 512)))
    write_image(tmp_path / "whole.png", _sample(tile, cell_map(tile, (4, 4)), (512, 512)))
    ratios = {}
    for name in ("split", "whole"):
        assert main(["compare", str(tmp_path / f"{name}.png"), "--reference", str(tmp_path / "photo.png")]) == 0
        out = capsys.readouterr().out.splitlines()
        line = [ln for ln in out if ln.startswith("cells split")]
        assert len(line) == 1, line
        assert len([ln for ln in out if ln.startswith("cells cut short")]) == 1, out
        ratios[name] = float(line[0].split("=")[1].split("x")[0])
    assert ratios["split"] >= 1.6 and ratios["whole"] <= 1.35, ratios
    # an unstructured reference: no line
    noise = np.random.default_rng(0).random((256, 256, 3)).astype(np.float32)
    write_image(tmp_path / "noise.png", noise)
    assert main(["compare", str(tmp_path / "noise.png"), "--reference", str(tmp_path / "noise.png")]) == 0
    out = capsys.readouterr().out
    assert "cells split" not in out and "cells cut short" not in out


def _hexagons(side=512, radius=30.0, grout=2.0, rng=5):
    """Hexagonal floor tiles, each its own colour, in light grout: no straight line runs along its grout."""
    from scipy.spatial import cKDTree

    gen = np.random.default_rng(rng)
    dx, dy = radius * np.sqrt(3.0), 1.5 * radius
    centres = np.array([(i * dx + (j % 2) * dx / 2, j * dy)
                        for j in range(-2, int(side / dy) + 3) for i in range(-2, int(side / dx) + 3)])
    y, x = np.mgrid[0:side, 0:side].astype(np.float64)
    d, idx = cKDTree(centres).query(np.stack([x.ravel(), y.ravel()], 1), k=2)
    colours = gen.uniform(0.25, 0.6, (len(centres), 3))
    image = colours[idx[:, 0]].reshape(side, side, 3) + 0.02 * gen.standard_normal((side, side, 1))
    inside = np.clip(((d[:, 1] - d[:, 0]).reshape(side, side) - grout) / 2.0, 0.0, 1.0)[..., None]
    return np.clip(image * inside + (1.0 - inside) * 0.8, 0.0, 1.0).astype(np.float32)


def _wrap_jumps(tile):
    """The mean colour step across the tile's wrap edges (last column to first, last row to first) between
    texels both inside cells (every channel under the grout's 0.8): the noise's alone where every cell there is
    one hexagon, a step between two hexagons' colours where a cell is made of two."""
    a = np.concatenate([tile[:, -1, :3], tile[-1, :, :3]])
    b = np.concatenate([tile[:, 0, :3], tile[0, :, :3]])
    inside = (a.max(axis=1) < 0.68) & (b.max(axis=1) < 0.68)
    assert inside.sum() > 100
    return float(np.abs(a - b)[inside].mean())


def test_period_tile_keeps_the_cells_across_its_wrap_edges_whole(monkeypatch):
    """A hexagon floor's period tile cannot be cut along its grout: the cells its wrap edges cross are read
    whole from the photo (one colour each), where the plain cut made them of two hexagons (control)."""
    from spectex.fitting import _auto

    photo = _hexagons()
    period = _auto.structure_period(photo)
    assert period is not None
    tile, *_ = _auto._period_tile(photo, period)
    fixed = _wrap_jumps(tile)
    monkeypatch.setattr(_auto, "_whole_edge_cells", lambda tile, *args: tile)
    plain, *_ = _auto._period_tile(photo, period)
    split = _wrap_jumps(plain)
    assert fixed < 0.05 < split, (fixed, split)


def test_cell_splits_sees_hexagons_made_of_two(monkeypatch):
    """Grout of any shape: a hexagon floor's cells are found from the photo folded by both its periods, so
    hexagons made of two (bands of another colouring of the same floor) score far above a disjoint crop of
    the photo. The control: by straight grout lines alone (the measure before), the floor shows no cells."""
    from spectex import metrics
    from spectex.fitting import _auto

    photo = _hexagons()
    other = _hexagons(rng=9)  # the same hexagons, other colours
    period = _auto.structure_period(photo)
    own = metrics.cell_splits(photo[:, :256], photo[:, 256:], period=period)
    banded = photo.copy()
    for x0 in range(0, 512, 80):
        banded[:, x0:x0 + 40] = other[:, x0:x0 + 40]
    split = metrics.cell_splits(banded[:, :256], photo[:, 256:], period=period)
    assert own is not None and split is not None
    assert 0.5 < own.ratio < 2.0 and split.ratio > 3.0 * own.ratio, (own.ratio, split.ratio)
    assert own.cells_image >= 30  # the hexagons themselves, not a few merged regions
    monkeypatch.setattr(metrics, "_lattice_strength_2d", lambda level, period: 0.0)
    assert metrics.cell_splits(photo[:, :256], photo[:, 256:], period=period) is None


# ------------------------------------------------------------------ the tables of a tile with cells
def _mapped_levels(tables):
    """Each Gaussian level taken back to RGB through its own table (as the samplers read a texel of it)."""
    from spectex.shading.constants import LUT_SIZE

    out = []
    for d, g in enumerate(tables.gaussian):
        idx = np.floor(np.clip(g[..., :3], 0.0, 1.0) * (LUT_SIZE - 1) + 0.5).astype(int)
        v = np.stack([tables.lut[d, idx[..., c], c] for c in range(3)], axis=-1)
        out.append(np.clip(tables.origin + v @ tables.basis.T, 0.0, 1.0))
    return out


def test_tables_of_a_tile_with_cells_are_exact_at_every_level():
    """Gaussianised level by level (stochastic_tables(per_level=True), what a tile with a cell map gets), every
    level's texels go back to the colour's own mip level; the pooled regression of the filtered colour on the
    filtered Gaussian (the paper's prefiltering, the control) cannot: the grout in the Gaussian's tail mixed
    into a dark floor tile reads as a lighter tile, and one monotone table per channel shifts the tiles' colours."""
    from spectex.shading.stochastic import stochastic_tables
    from spectex.tiles import mip_chain

    tile, _ = _floor(256, 64)
    colour = mip_chain(tile)
    exact = _mapped_levels(stochastic_tables(tile, per_level=True))
    pooled = _mapped_levels(stochastic_tables(tile))
    for d in range(1, 4):
        assert psnr(exact[d], colour[d]) >= 50.0, (d, psnr(exact[d], colour[d]))
        assert psnr(pooled[d], colour[d]) <= 36.0, (d, psnr(pooled[d], colour[d]))
    # level 0 is the same either way
    a, b = stochastic_tables(tile, per_level=True), stochastic_tables(tile)
    np.testing.assert_array_equal(a.gaussian[0], b.gaussian[0])
    np.testing.assert_array_equal(a.lut[0], b.lut[0])


# ------------------------------------------------------------------ free cells: cobbles drawn unsnapped
def _cobbles(n=256, cell=32, mortar=3.0, rng=1, grain=0.02):
    """Seamless cobbles: a jittered lattice of ``cell`` texels on the torus, each Voronoi cell one flat
    colour (plus ``grain``), in dark mortar about ``2 mortar`` texels wide. Returns the RGB tile, each
    texel's stone, the mortar's mask and the stones' colours."""
    from scipy.spatial import cKDTree

    gen = np.random.default_rng(rng)
    k = n // cell
    gy, gx = np.mgrid[0:k, 0:k]
    points = (np.stack([gy.ravel(), gx.ravel()], 1) + gen.uniform(0.2, 0.8, (k * k, 2))) * cell
    copies = np.concatenate([points + np.array([dy, dx]) * n for dy in (-1, 0, 1) for dx in (-1, 0, 1)])
    yy, xx = np.mgrid[0:n, 0:n]
    d, idx = cKDTree(copies).query(np.stack([yy.ravel() + 0.5, xx.ravel() + 0.5], 1), k=2)
    stone = np.tile(np.arange(k * k), 9)[idx[:, 0]].reshape(n, n)
    palette = gen.uniform(0.35, 0.85, (k * k, 3))
    img = palette[stone] + grain * gen.standard_normal((n, n, 1))
    joint = (d[:, 1] - d[:, 0]).reshape(n, n) < mortar
    img[joint] = 0.08
    return np.clip(img, 0.0, 1.0).astype(np.float32), stone, joint, palette


def test_free_cell_map_finds_cobbles_and_nothing_in_textures_without_grout():
    import skimage.data

    from helpers import make_test_tile
    from spectex.shading._cells import cell_map, free_cell_map

    tile, stone, joint, _ = _cobbles()
    cells = cell_map(tile, (0, 0))
    assert cells is not None and np.array_equal(cells, free_cell_map(tile))
    assert np.array_equal(2 * cells, np.round(2 * cells))  # half texels, exact in half floats
    # each stone's texels point to one centre (merged stones aside: measured 49 of 64)
    yy, xx = np.mgrid[0:256, 0:256]
    cx, cy = xx + cells[:, :, 0], yy + cells[:, :, 1]
    whole = sum(np.ptp(cx[(stone == k) & ~joint]) <= 1.0 and np.ptp(cy[(stone == k) & ~joint]) <= 1.0
                for k in range(64))
    assert whole >= 40, whole
    # textures without a grout network: none (filtered noise, gravel, grass)
    grey = [skimage.data.gravel()[:256, :256], skimage.data.grass()[:256, :256]]
    for other in [make_test_tile(256)[..., :3]] + [np.repeat(g[:, :, None] / 255.0, 3, axis=2) for g in grey]:
        assert free_cell_map(np.asarray(other, np.float32)) is None


def test_free_cell_map_reads_a_large_tile_as_the_fit_analysed_it():
    """A tile of 1024 texels (a fit's tile at a photo's full resolution, each analysed texel 2 x 2) is read
    area-averaged to 512, where its mortar is as wide as in the tile the fit analysed: the same cells as
    that tile's, the vectors doubled (a texel of the large tile lies half a texel off its small texel's
    centre), every texel of a stone pointing at one centre. (Read at 1024 texels, these thin joints are
    found too, 99 % of the vectors within a texel, in twice the time: 0.78 s against 0.39 on an AMD EPYC;
    a photo's joints as wide as its stones are large would not be, ``FREE_WIDTHS`` counting texels.)"""
    from spectex.shading._cells import FREE_READ_SIDE, _cell_step, free_cell_map

    small, stone, joint, _ = _cobbles(n=512, cell=64)
    big = np.repeat(np.repeat(small, 2, axis=0), 2, axis=1)
    assert FREE_READ_SIDE == 512 and _cell_step(1024, 1024) == 2 and _cell_step(1536, 1536) == 3
    assert _cell_step(512, 512) == 1 and _cell_step(1030, 1030) == 1  # no whole factor: read as it is
    cells, cells_small = free_cell_map(big), free_cell_map(small)
    assert cells is not None and cells_small is not None and cells.shape == (1024, 1024, 2)
    np.testing.assert_allclose(cells[::2, ::2], 2 * cells_small + 0.5, atol=0.5)
    yy, xx = np.mgrid[0:1024, 0:1024]
    cx, cy = xx + cells[:, :, 0], yy + cells[:, :, 1]
    stone2 = np.repeat(np.repeat(stone, 2, axis=0), 2, axis=1)
    inner = ~np.repeat(np.repeat(joint, 2, axis=0), 2, axis=1)
    whole = sum(np.ptp(cx[(stone2 == k) & inner]) <= 1.0 and np.ptp(cy[(stone2 == k) & inner]) <= 1.0
                for k in range(64))
    assert whole >= 40, whole


def _mixed(rgb, palette, tol=0.1):
    """The fraction of ``rgb``'s pixels further than ``tol`` from every stone colour and the mortar's: blends."""
    colours = np.concatenate([palette, [[0.08, 0.08, 0.08]]])
    return float(np.mean(np.min(np.linalg.norm(rgb[:, :, None, :] - colours[None, None], axis=3), axis=2) > tol))


def test_free_cells_draw_cobbles_whole_instead_of_cross_faded():
    """Unsnapped cobbles: with their free cell map, each point shows the patch whose own cobble there lies in
    its region, so cobbles are whole and patches meet in the mortar; blends only where no patch's cobble
    does (measured 1.2 % of the pixels blended against 4.0 % without the map, the control: the triangle
    grid's cross-fades through the cobbles). Free cells hold at every level (stochastic.cell_mix): far
    away the cells still choose the patches, not the blend."""
    from spectex.shading._cells import free_cell_map
    from spectex.shading.constants import SHARP_LOD
    from spectex.shading.stochastic import sample_stochastic, stochastic_tables

    tile, _, _, palette = _cobbles()
    cells = free_cell_map(tile)
    tables = stochastic_tables(np.concatenate([tile, np.ones((256, 256, 1), np.float32)], axis=2))
    yy, xx = np.mgrid[0:512, 0:512]
    s, t = (xx + 0.5) / 256, (yy + 0.5) / 256
    whole = sample_stochastic(tables, s, t, patch=0.5, seed=3, cells=cells, lod=0.0)[..., :3]
    faded = sample_stochastic(tables, s, t, patch=0.5, seed=3, cells=None, lod=0.0)[..., :3]
    _, stone, _, flat = _cobbles(grain=0.0)
    assert _mixed(whole, flat) <= 0.5 * _mixed(faded, flat) and _mixed(faded, flat) >= 0.02, \
        (_mixed(whole, flat), _mixed(faded, flat))
    far = SHARP_LOD + 2.0
    assert not np.array_equal(sample_stochastic(tables, s[:64, :64], t[:64, :64], patch=0.5, seed=3, cells=cells,
                                                lod=far),
                              sample_stochastic(tables, s[:64, :64], t[:64, :64], patch=0.5, seed=3, cells=None,
                                                lod=far))


@pytest.mark.gl
def test_gl_matches_cpu_on_unsnapped_cobbles(gl, monkeypatch):
    from spectex.render.cpu import render_cpu
    from spectex.shading import _cells, resources

    tex = _texture(_cobbles()[0], (0, 0))
    assert_gl_matches_cpu(tex, gl)
    # the control: the cells changed the picture (the same texture without its free cells)
    cam = VIEWS["close"]
    with_cells = render_cpu(tex, cam, SIZE)
    monkeypatch.setattr(_cells, "free_cell_map", lambda tile: None)
    resources.clear_cache()
    try:
        without = render_cpu(tex, cam, SIZE)
    finally:
        resources.clear_cache()  # (nothing kept that was made without the free cells)
    assert psnr(with_cells, without) < 35.0, psnr(with_cells, without)


def test_free_cells_cpu_fast_path_matches_the_general_sampler():
    fast, general = fast_path_against_general(_texture(_cobbles()[0], (0, 0)))
    # the same numbers to float rounding, which may move a point on a cell's edge into the other cell: a
    # pixel or two of another cobble's colour (measured 2 of 3072, 0.20 off)
    diff = np.abs(fast - general)
    assert np.mean(diff.max(axis=2) > 1e-5) <= 0.005 and diff.mean() <= 1e-3, (np.mean(diff > 1e-5), diff.mean())


@pytest.mark.slow
def test_fit_of_cobbles_draws_them_with_free_cells_and_says_so(tmp_path, capsys):
    """spectex fit on a photo of cobbles: its finest layer unsnapped, its tile's grout found (params
    ``free_cells``), and the summary says so; the control, gravel (no grout network), does not."""
    import skimage.data

    from spectex import io
    from spectex.cli import main
    from spectex.fitting import fit_result

    cobbles = _cobbles(rng=4)[0]
    gravel = skimage.data.gravel()[:256, :256]
    assert fit_result(cobbles).params["free_cells"] is True
    assert fit_result(gravel).params["free_cells"] is False
    path = tmp_path / "cobbles.png"
    io.write_image(path, cobbles)
    assert main(["fit", str(path), "-o", str(tmp_path / "out")]) == 0
    assert "drawn with free cells" in capsys.readouterr().out


@pytest.mark.slow
def test_stochastic_way_of_a_structured_photo_as_large_as_a_tile_is_its_own_crop(monkeypatch):
    """A structured photo of STRUCTURED_CROP_MIN pixels or more (a 512-pixel wall straightened by a degree is
    504) gives the stochastic way its own seamless crop, as an unstructured photo does: its cells whole, so
    that free cells are read on it. A quilt of 512 cut its stones by straight block seams, and a wall of
    irregular stones (a coursed ashlar of Debian's supertuxkart-data, rows of 31 pixels) was drawn snapped
    row by row, its stones taller than a row cut in two (docs/fitting.md, "A structured photo's own crop").
    The control: a smaller photo keeps the quilt; so does this one with the rule off."""
    from spectex.fitting import _auto, fit_result

    floor = _floor(512, rng=3)[0]
    assert _auto.STRUCTURED_CROP_MIN == 384

    def tile_of(photo):
        result = fit_result(photo, tiling="stochastic")
        assert result.params["period_px"] is not None  # a structured photo
        return result.params["tile_method"], result.texture.tile_shape[0], result.params["free_cells"]

    how, side, free = tile_of(floor[:448, :448])
    assert how == "seamless crop" and side == 448 and free is True, (how, side, free)
    # a photo longer than wide gives its central square, and the notes say what is left out, as for an
    # unstructured photo (a square one says nothing)
    assert not any("finest tile is the central" in note for note in fit_result(floor[:448, :448],
                                                                                tiling="stochastic").notes)
    wide = fit_result(floor[:400, :448], tiling="stochastic")
    assert wide.params["tile_method"] == "seamless crop" and wide.texture.tile_shape[0] == 400
    assert any("finest tile is the central 400x400 crop of the 448x400 photo" in note for note in wide.notes)
    how, side, _ = tile_of(floor[:320, :320])
    assert how.startswith("tileable quilt") and side == 512, (how, side)
    monkeypatch.setattr(_auto, "STRUCTURED_CROP_MIN", 10 ** 6)
    how, side, _ = tile_of(floor[:448, :448])
    assert how.startswith("tileable quilt") and side == 512, (how, side)
