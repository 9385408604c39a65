"""Courses of boards or bricks snapped along one axis change patch at their joints (issue 22): the course map,
the samplers (CPU and GL), the fit's period tile with a joint at its wrap edge, and a fitted floor of planks."""

import re

import numpy as np
import pytest

from helpers import SIZE, VIEWS, assert_gl_matches_cpu, fast_path_against_general, psnr

JOINT = 0.08  # the joints' and the grout's grey


def _planks(n=256, course=32, rng=4, grain=0.0, shift=0, heights=None):
    """A seamless floor of boards: ``n // course`` courses along x, each ``course`` texels high with a dark
    grout line 3 texels wide at its top, its boards of random lengths (40 to 120 texels, on the torus) ended by
    dark joints 2 texels wide, each board one flat colour (plus ``grain``). Returns the RGB tile, per texel its
    board's index (-1 in grout and joints) and the boards' colours. ``shift``: the courses start this many
    texels down (the grout off the tile's edge). ``heights``: courses of these heights instead (adding up to
    ``n``: a wall of courses of their own heights)."""
    gen = np.random.default_rng(rng)
    board = np.full((n, n), -1, np.int64)
    colours = []
    heights = [course] * (n // course) if heights is None else list(heights)
    tops = np.concatenate([[0], np.cumsum(heights)])
    for c in range(len(heights)):
        x = int(gen.integers(0, n))
        cuts = [x]
        while True:
            step = int(gen.integers(40, 121))
            if x + step > cuts[0] + n - 40:
                break
            x += step
            cuts.append(x)
        for k, a in enumerate(cuts):
            b = cuts[k + 1] if k + 1 < len(cuts) else cuts[0] + n
            cols = np.arange(a + 2, b) % n  # the joint: its first 2 texels
            rows = (np.arange(tops[c] + 3, tops[c + 1]) + shift) % n
            board[np.ix_(rows, cols)] = len(colours)
            colours.append(gen.uniform(0.3, 0.9, 3))
    colours = np.array(colours)
    img = np.where(board[:, :, None] >= 0, colours[np.maximum(board, 0)], JOINT)
    img = img + grain * gen.standard_normal(img.shape)
    return np.clip(img, 0.0, 1.0).astype(np.float32), board, colours


def _exemplars():
    """``benchmarks/exemplars.py`` (the planks photo the benchmarks measure), imported from there."""
    import sys
    from pathlib import Path

    path = str(Path(__file__).resolve().parents[1] / "benchmarks")
    if path not in sys.path:
        sys.path.insert(0, path)
    import exemplars

    return exemplars


def _texture(tile, snap):
    from spectex.texture import Layer, SpectralTexture

    rgba = np.concatenate([tile, np.ones(tile.shape[:2] + (1,), np.float32)], axis=2)
    return SpectralTexture([rgba], [Layer(size=2.0, tile=0, tiling="stochastic", patch=0.5, snap=snap)], bits=None)


def _two_toned(img, along_x=True, tol=0.08):
    """The share of an image's boards (runs between dark joints along each course's lines, a third of the way
    into every course) whose colour changes by more than ``tol`` along them: boards made of two."""
    if not along_x:
        img = img.transpose(1, 0, 2)
    split = total = 0
    for y in range(img.shape[0]):
        line = img[y]
        dark = line.max(axis=1) < 0.2
        if dark.mean() > 0.5:
            continue
        edges = np.flatnonzero(np.diff(dark.astype(np.int8)) != 0)
        for a, b in zip(edges[:-1], edges[1:]):
            run = line[a + 3:b - 1]  # (off the joints' filtered edges)
            if dark[a + 1] or len(run) < 8:
                continue
            total += 1
            split += bool(np.abs(run - run[0]).max() > tol)
    return split / max(total, 1)


#: Bake corners: one where a segment starts on a texel edge (the grid's origin: a start computed per point
#: landed either side of it, and a board's lines took their cuts from one or the other, line by line), one not.
ORIGINS = ((0.0, 0.0), (0.37, 0.81))


def _bake(tex, side=512, origin=ORIGINS[1]):
    from spectex.bake._block import bake_window

    return bake_window(tex, (0, side, 0, side), pixel_size=2.0 / 256, origin=origin)


# ------------------------------------------------------------------ the course map
def test_course_map_reads_every_board_from_joint_to_joint():
    from spectex.shading._cells import cell_map, course_map
    from spectex.shading.constants import NO_JOINT

    tile, board, _ = _planks(shift=5)
    cells = cell_map(tile, (0, 8))
    assert cells is not None and cells.shape == (256, 256, 4) and cells.dtype == np.float32
    assert np.array_equal(cells, cells.astype(np.float16).astype(np.float32))  # exact in half floats
    xx = np.arange(256)
    for y in (10, 40, 100, 200):
        a, b = cells[y, :, 0], cells[y, :, 1]
        assert np.all(a <= 0) and np.all(b >= 1) and np.all(a > -NO_JOINT)
        # every texel of a board lies in one unit, the joint before it to the next: the unit's start is the
        # board's joint (its first texel 2 before the board's)
        for k in np.unique(board[y][board[y] >= 0]):
            on = xx[board[y] == k]
            starts = np.unique((on + a[on]) % 256)
            assert len(starts) == 1, (y, k, starts)
    # the courses' centre lines: the middle of each course between the grout lines' centres
    centre = np.arange(256) + 0.5 + cells[:, 0, 2]
    assert np.all(np.abs(((centre - 5 - 1.5) % 32) - 16.0) <= 0.5), centre[:40]
    assert np.all(cells[:, :, 3] == cells[0, 0, 3]) and 100 <= cells[0, 0, 3] <= 160
    # columns (snapped along x): the same map turned
    turned = course_map(np.ascontiguousarray(tile.transpose(1, 0, 2)), (8, 0))
    assert np.array_equal(turned, cells.transpose(1, 0, 2))


HEIGHTS = (24, 48, 32, 56, 40, 56)  # a wall of courses of their own heights (adding up to 256)


def test_course_map_reads_courses_of_their_own_heights():
    """Snapped one period across (``(0, 1)``: each patch offset along its courses only), the map reads each
    course between its own grout lines, whatever its height; folded into courses of one height (the
    control, ``(0, 6)``: six courses a tile) the grout falls into no single run and there is no map."""
    from spectex.shading._cells import cell_map, course_map

    tile, board, _ = _planks(shift=5, heights=HEIGHTS)
    cells = cell_map(tile, (0, 1))
    assert cells is not None and cells.shape == (256, 256, 4)
    tops = 5 + np.concatenate([[0], np.cumsum(HEIGHTS)[:-1]])
    centre = np.arange(256) + 0.5 + cells[:, 0, 2]  # each line's course's centre line
    for top, height in zip(tops, HEIGHTS):
        lines = (np.arange(top + 3, top + height)) % 256  # the course's lines below its grout
        # the centre between the grout lines' centres (1.5 texels into each)
        off = (centre[lines] - (top + 1.5 + height / 2.0) + 128.0) % 256.0 - 128.0  # on the torus
        assert np.all(np.abs(off) <= 0.5), (top, centre[lines])
    xx = np.arange(256)
    for y in (10, 40, 100, 200):
        a = cells[y, :, 0]
        for k in np.unique(board[y][board[y] >= 0]):
            on = xx[board[y] == k]
            assert len(np.unique((on + a[on]) % 256)) == 1, (y, k)
    assert course_map(tile, (0, 6)) is None
    turned = course_map(np.ascontiguousarray(tile.transpose(1, 0, 2)), (1, 0))
    assert np.array_equal(turned, cells.transpose(1, 0, 2))


def test_course_map_refuses_tiles_without_joints_or_courses():
    from spectex.shading._cells import cell_map

    tile, board, _ = _planks()
    # courses without joints: bands of one colour between the grout lines
    bands = np.repeat(np.where((board >= 0)[:, :, None], 0.6, JOINT), 3, axis=2).astype(np.float32)
    rows = np.arange(256) % 32 >= 3
    bands[rows] = 0.6
    assert cell_map(bands, (0, 8)) is None
    noise = np.random.default_rng(0).random((256, 256, 3)).astype(np.float32)
    assert cell_map(noise, (0, 8)) is None
    assert cell_map(tile, (0, 8)) is not None  # the control


# ------------------------------------------------------------------ the samplers
def test_courses_change_patch_at_joints_only(monkeypatch):
    """A floor of flat-coloured boards snapped along y: with its course map, each course changes patch at a
    joint of the new patch, so no board shows two colours (measured 0 %, with the map, a render at 1.3 texels
    a pixel); the control, without the map: the triangle grid's patch boundaries run through boards (32 %)."""
    from spectex.shading import _cells, resources

    tile = _planks()[0]
    with_map = max(_two_toned(_bake(_texture(tile, (0, 8)), origin=o)) for o in ORIGINS)
    monkeypatch.setattr(_cells, "course_map", lambda tile, snap: None)
    resources.clear_cache()
    try:
        without = _two_toned(_bake(_texture(tile, (0, 8))))
    finally:
        resources.clear_cache()
    assert with_map <= 0.02 and without >= 0.15, (with_map, without)


def test_columns_change_patch_at_joints_only():
    """The same floor turned (columns of bricks along y, snapped along x): the same rule along the other axis."""
    tile = np.ascontiguousarray(_planks()[0].transpose(1, 0, 2))
    for origin in ORIGINS:
        img = _bake(_texture(tile, (8, 0)), origin=origin)
        assert _two_toned(img, along_x=False) <= 0.02, (origin, _two_toned(img, along_x=False))


def _patch_changes(tex, tile, rows, length=1536):
    """Along the texel rows ``rows`` of a texture with one layer of ``tile`` (courses along x, snapped along y;
    a texel a pixel, no rotation), every place ``x`` where :func:`course_vertex` changes patch, and whether it
    is *clean* there: both the patch before and the new one (each with its shift) start a unit at ``x`` (a
    joint and the board after it), so that neither board is cut."""
    from spectex.shading._cells import course_map
    from spectex.shading.stochastic import course_vertex, vertex_offset
    from spectex.shading.tables import anchor_coords, pack

    cmap = course_map(tile, tex.layers[0].snap)
    tables = pack(tex)
    anchor = anchor_coords(tables, 0.0, 0.0)
    n = tile.shape[0]
    w0 = float(n)
    g, key, (nx, ny) = tables.grid[0], tables.key[0], tables.snap[0]
    bi, bj = int(anchor[0, 4]), int(anchor[0, 5])

    def patch(s, t):
        ci, cj, shift = course_vertex(tables.lut, tables.cell_row[0], s, t, anchor[0, 2] + g[0, 0] * (s - anchor[0, 0])
                                      + g[0, 1] * (t - anchor[0, 1]), anchor[0, 3] + g[1, 0] * (s - anchor[0, 0])
                                      + g[1, 1] * (t - anchor[0, 1]), g, w0, w0, bi, bj, key, nx, ny)
        return ci, cj, shift

    def starts_unit(vertex, s, t):
        ox, oy = vertex_offset(bi + vertex[0], bj + vertex[1], key, w0, w0, nx, ny)
        x = int(np.floor(s * w0) + np.floor(ox * w0 + 0.5) + vertex[2]) % n
        y = int(np.floor(t * w0) + np.floor(oy * w0 + 0.5)) % n
        return cmap[y, x, 0] == 0.0

    out = []
    for row in rows:
        t = anchor[0, 1] + (row + 0.5) / w0
        prev = None
        for col in range(length):
            s = anchor[0, 0] + (col + 0.5) / w0
            here = patch(s, t)
            if prev is not None and here != prev:
                out.append((row, col, starts_unit(prev, s, t) and starts_unit(here, s, t)))
            prev = here
    return out


def test_aligned_segments_change_patch_where_both_patches_start_a_board():
    """Every other segment of a course is shifted onto the patch before's joint: of the patch changes along the
    floor's courses, about half are clean (both boards whole: measured 0.5); by chance alone (the segments
    before, cut at the least hiding of the new patch's first 3 joints) a change is clean only where the
    patch before has a joint exactly there, about 3 in 80 texels."""
    tile = _planks()[0]
    changes = _patch_changes(_texture(tile, (0, 8)), tile, rows=range(17, 256, 32))
    assert len(changes) >= 40
    clean = np.mean([c for _, _, c in changes])
    assert 0.4 <= clean <= 0.7, clean


def test_an_aligned_change_never_shows_the_same_course_on():
    """An odd segment's patch is shifted so that one of its joints meets the patch before's; where the joint it
    would shift there is the patch before's own (the new patch offset by less than the board before it), the
    course would run on unchanged (and come back a tile on, a repeat along the courses from afar): its next
    joint is taken instead. Checked on the map of a floor of boards: the new patch 3 texels on from the patch
    before, its aligned shift leaves it showing other texels than the patch before (the code before answered
    -3, the same texels, at every joint)."""
    from spectex.shading import _cells, stochastic

    tile = _planks()[0]
    cells = _cells.course_map(tile, (0, 8))
    lut = stochastic.cell_rows(cells).astype(np.float64)
    w = float(tile.shape[1])
    vrow = 17.0  # a line inside the first course
    starts = np.flatnonzero(cells[int(vrow), :, 0] == 0.0)
    assert len(starts) >= 2
    for j0 in starts:
        j, shift = stochastic._course_align(lut, 0.0, float(j0), float(j0) + 64.0, 0.0, 0.0, 3.0, 0.0, vrow, True,
                                            w, w)
        assert j == j0 and shift > 0.0 and (3.0 + shift) % w != 0.0, (j0, j, shift)


def _course_heights_down(tex, tiles=16):
    """The heights of the courses a bake of ``tex`` (a 2 m tile of 256 texels, courses along x) shows down a
    strip ``tiles`` tiles tall, one texel a pixel: from one grout line's first row to the next's."""
    from spectex.render.cpu import bake

    img = bake(tex, (256 * tiles, 48), pixel_size=2.0 / 256, origin=(0.37, 0.11))
    rows = img[:, :, :3].mean(axis=(1, 2))
    grout = rows < 0.5 * (JOINT + float(np.median(rows)))
    first = np.flatnonzero(grout & ~np.roll(grout, 1))
    return np.diff(first)


def test_walls_of_courses_of_their_own_heights_change_their_courses_order_band_by_band(monkeypatch):
    """A wall of courses of their own heights (snap ``(0, 1)``) is drawn in bands one tile high, each starting
    the tile's courses at one of its courses (``stochastic.course_band_shift``): down a strip 16 tiles tall every
    course is one of the tile's, whole (each band boundary on grout), but the heights do not come back once a
    tile (six courses on): a fifth of them equal the one six courses before. The control, every band started at
    the same course (a course-start table of one course), repeats once a tile: all of them."""
    from spectex.shading import resources, stochastic

    tile = _planks(shift=5, heights=HEIGHTS, grain=0.02)[0]
    tex = _texture(tile, (0, 1))
    resources.clear_cache()
    heights = _course_heights_down(tex)
    assert set(heights.tolist()) <= set(HEIGHTS), sorted(set(heights.tolist()))
    assert len(heights) >= 15 * len(HEIGHTS)
    again = float(np.mean(heights[len(HEIGHTS):] == heights[:-len(HEIGHTS)]))
    assert again <= 0.5, again
    real = stochastic.course_starts_row

    def one_course(course_map):
        out = real(course_map)
        out[0, :, 0] = out[0, 0, 0]
        return out

    monkeypatch.setattr(stochastic, "course_starts_row", one_course)
    resources.clear_cache()
    try:
        control = _course_heights_down(tex)
    finally:
        resources.clear_cache()
    assert set(control.tolist()) <= set(HEIGHTS)
    assert np.mean(control[len(HEIGHTS):] == control[:-len(HEIGHTS)]) == 1.0


@pytest.mark.parametrize("snap", [(0, 8), (0, 1)])
def test_courses_cpu_fast_path_matches_the_general_sampler(snap):
    tile = _planks(grain=0.02, heights=None if snap[1] > 1 else HEIGHTS)[0]
    fast, general = fast_path_against_general(_texture(tile, snap))
    diff = np.abs(fast - general)
    assert np.mean(diff.max(axis=2) > 1e-5) <= 0.005 and diff.mean() <= 1e-3, (np.mean(diff > 1e-5), diff.mean())


@pytest.mark.gl
@pytest.mark.parametrize("snap", [(0, 8), (8, 0), (0, 1), (1, 0)])
def test_gl_matches_cpu_on_courses(gl, snap, monkeypatch):
    from spectex.render.cpu import render_cpu
    from spectex.shading import _cells, resources

    tile = _planks(grain=0.02, heights=None if max(snap) > 1 else HEIGHTS)[0]
    if snap[1] == 0:
        tile = np.ascontiguousarray(tile.transpose(1, 0, 2))
    tex = _texture(tile, snap)
    assert_gl_matches_cpu(tex, gl)
    # the control: the course map changed the picture
    cam = VIEWS["close"]
    with_map = render_cpu(tex, cam, SIZE)
    monkeypatch.setattr(_cells, "course_map", lambda tile, snap: None)
    resources.clear_cache()
    try:
        without = render_cpu(tex, cam, SIZE)
    finally:
        resources.clear_cache()
    assert psnr(with_map, without) < 35.0, psnr(with_map, without)


# ------------------------------------------------------------------ the fit's period tile
def test_period_tile_gets_a_joint_where_its_wrap_edge_joins_two_boards():
    """A course read straight across a photo joins two boards at the tile's wrap edge without a joint; one of
    the course's own joints is put over it. A course with a joint at its edge, or joined within one board,
    is left alone (the control)."""
    from spectex.fitting._auto import _joints_at_wrap

    tile = _planks(n=256)[0]
    cut = tile.copy()
    rows = np.arange(256) // 32 == 1
    course = np.full((256, 3), JOINT)
    course[0:100], course[102:200], course[202:256] = (0.8, 0.5, 0.3), (0.4, 0.6, 0.5), (0.3, 0.3, 0.7)
    cut[35:64] = course  # its boards: 0-99 and 202-255 meet at the edge, two colours without a joint
    out = _joints_at_wrap(cut, (0, 8))
    assert np.allclose(out[35:64][:, [255, 0]], JOINT), out[40, [253, 254, 255, 0, 1, 2]]
    assert np.array_equal(out[35:64][:, 2:254], cut[35:64][:, 2:254])  # only the joint put in
    # every other course unchanged: its boards run across the edge whole
    assert np.array_equal(out[~rows], cut[~rows])
    # turned (columns along y, snapped along x): the same
    turned = _joints_at_wrap(np.ascontiguousarray(cut.transpose(1, 0, 2)), (8, 0))
    assert np.array_equal(turned, out.transpose(1, 0, 2))
    # a course joined within one board (the tile as made: no step at its edge) is left alone
    assert np.array_equal(_joints_at_wrap(tile, (0, 8)), tile)
    # two boards of one brightness and another hue (an orange brick beside a brown one: the channels' mean the
    # same to 0.003, as a running bond's bricks at the edges of a tile cut across them) meet there too
    hue = cut.copy()
    course[0:100], course[202:256] = (0.62, 0.33, 0.12), (0.45, 0.32, 0.30)
    hue[35:64] = course
    out = _joints_at_wrap(hue, (0, 8))
    assert np.allclose(out[35:64][:, [255, 0]], JOINT), out[40, [253, 254, 255, 0, 1, 2]]


# ------------------------------------------------------------------ a fitted floor
@pytest.mark.slow
def test_fit_of_planks_keeps_its_boards_whole(monkeypatch, tmp_path, capsys):
    """``spectex.fit`` on a floor of planks (``benchmarks/exemplars.py``: courses 46 pixels high, boards of
    random lengths with dark joints): its finest layer is snapped across the courses and drawn with its
    course map (params ``courses``; ``spectex fit``'s summary says so). metrics.cell_splits (boards changing
    colour partway) on bakes at two places measured 1.07 / 1.15, against 1.56 / 1.32 for the same texture
    drawn without the map (the control)."""
    exemplars = _exemplars()
    from spectex import io
    from spectex.bake._block import bake_window
    from spectex.cli import main
    from spectex.fitting import fit_result, structure_period
    from spectex.metrics import cell_splits
    from spectex.shading.resources import cell_maps

    photo = exemplars.load("planks")
    result = fit_result(photo)
    layer = result.texture.layers[0]
    assert layer.tiling == "stochastic" and layer.snap[0] == 0 and layer.snap[1] > 0
    assert result.params["courses"] is True and result.params["free_cells"] is False
    # the summary says so; the control, a photo without a structure: no courses, nothing said
    io.write_image(tmp_path / "planks.png", photo)
    assert main(["fit", str(tmp_path / "planks.png"), "-o", str(tmp_path / "out")]) == 0
    assert "its courses change patch at their joints" in capsys.readouterr().out
    assert fit_result(exemplars.load("gravel")).params["courses"] is False
    cells = cell_maps(result.texture)[layer.tile]
    assert cells is not None and cells.shape[2] == 4
    period = structure_period(photo)

    def splits(tex):
        return np.mean([cell_splits(bake_window(tex, (0, 1024, 0, 1024), pixel_size=result.pixel_size,
                                                origin=o), photo, period=period).ratio
                        for o in ((0.0, 0.0), (37.3, 11.1))])

    from spectex.shading import _cells, resources

    mapped = splits(result.texture)
    monkeypatch.setattr(_cells, "course_map", lambda tile, snap: None)
    resources.clear_cache()
    try:
        without = splits(result.texture)
    finally:
        resources.clear_cache()
    assert mapped <= 1.25 and mapped <= without - 0.15, (mapped, without)


@pytest.mark.slow
def test_fit_of_a_running_bond_with_few_bricks_across_cuts_each_row_at_its_joints(monkeypatch):
    """A running bond whose bricks are too long for their length to be read as a period (2.6 across the
    photo) is snapped along its rows and drawn row by row with the course map: every brick whole. Read by its
    bond's two rows (the highest peak down the wall, what the fit took before) the tile had two rows a period,
    no course map, and its patches cut bricks: cell_splits measured 0.05 / 0.06 against 1.78 / 1.70."""
    from spectex.bake._block import bake_window
    from spectex.fitting import _auto, fit_result, structure_period
    from spectex.metrics import cell_splits
    from test_snap import subpixel_wall

    photo = subpixel_wall(384, brick=150.0, row=40.3, mortar=3.0, rng=3)
    period = structure_period(photo)

    def fitted():
        result = fit_result(photo)
        splits = [cell_splits(bake_window(result.texture, (0, 768, 0, 768), pixel_size=result.pixel_size,
                                          origin=o), photo, period=period).image
                  for o in ((17.3, 5.1), (0.0, 0.0))]
        return result, float(np.mean(splits))

    result, rows = fitted()
    assert result.params["period_px"][1] is None and abs(result.params["period_px"][0] - 40.3) <= 0.2
    assert result.params["courses"] is True
    monkeypatch.setattr(_auto, "structure_period", lambda image: (80.6, None))  # the bond's two rows
    control, pairs = fitted()
    assert control.params["courses"] is False
    assert rows <= 0.5 and pairs >= rows + 0.6, (rows, pairs)


@pytest.mark.slow
def test_fit_of_a_wall_few_bricks_across_takes_a_side_its_courses_wrap_at_their_joints(monkeypatch):
    """A wall of bricks of random lengths (75-225 px) in a 512-pixel photo, rows of 85.3: at the largest tile
    side (5 rows, 425 texels) some course has no stretch of the photo joint to joint that long, so its wrap edge
    falls inside a brick and gets a joint there, two short bricks a course in every patch. The fit takes the
    side at which every course wraps at its own joints (3 rows here): fewer bricks cut short in its bakes
    (short_cells 0.28-0.33 against 0.35-0.57 at three places; the photo's own 0.23); the control is the side
    chosen as before."""
    from spectex.bake._block import bake_window
    from spectex.fitting import _auto, fit_result, structure_period
    from spectex.metrics import short_cells
    from test_snap import subpixel_wall

    photo = subpixel_wall(512, brick=150.0, row=85.3, mortar=4.0, rng=0, random_length=True)
    period = structure_period(photo)
    assert period[1] is None and abs(period[0] - 85.3) <= 0.2, period

    def fitted():
        result = fit_result(photo)
        shares = [short_cells(bake_window(result.texture, (0, 768, 0, 768), pixel_size=result.pixel_size,
                                          origin=o), photo, period=period)
                  for o in ((17.3, 5.1), (0.0, 0.0), (3.3, 9.1))]
        return result, float(np.mean([s.image for s in shares])), shares[0].reference

    every = re.compile(r"\b(\d+) of its \1 courses cut at their own joints")
    result, short, own = fitted()
    assert every.search(result.params["tile_method"]), result.params["tile_method"]
    monkeypatch.setattr(_auto, "_joint_side", lambda found, pick, joints: pick)
    control, before, _ = fitted()
    assert control.params["tile_px"] > result.params["tile_px"]
    assert not every.search(control.params["tile_method"]), control.params["tile_method"]
    assert short <= before - 0.1 and short <= own + 0.12, (short, before, own)


@pytest.mark.slow
def test_fit_of_a_wall_of_courses_of_their_own_heights_keeps_its_stones_whole(monkeypatch):
    """Coursed ashlar: courses 30 to 60 pixels high, stones of random lengths. Its rows read a period of 30 (the
    short courses), and drawn snapped to it, patches cut the tall stones through and cross-fade stones of two
    courses (the control: structure / floor 1.25-1.35 at three places). Read as a wall of courses of their own
    heights, the tile runs from one grout line to another and each patch is offset along the courses only:
    1.08-1.25 at the three places (mean 1.17), every stone of the photo's height (1.01-1.10 before the wall was
    drawn in bands of courses starting at other courses, ``stochastic.course_band_shift``: each band boundary
    pairs two courses the photo does not, about 0.04 more over ten places)."""
    from spectex.bake._block import bake_window
    from spectex.fitting import _auto, fit_result
    from spectex.metrics import structural_distance

    heights = (30, 60, 30, 30, 60, 45, 30, 60, 39)
    photo = _planks(n=384, heights=heights, rng=7, grain=0.03)[0]

    def fitted():
        result = fit_result(photo)
        ratios = [structural_distance(bake_window(result.texture, (0, 768, 0, 768), pixel_size=result.pixel_size,
                                                  origin=o), photo).ratio
                  for o in ((17.3, 5.1), (0.0, 0.0), (3.3, 9.1))]
        return result, float(np.mean(ratios))

    result, coursed = fitted()
    assert result.params["tile_method"].startswith("a wall of courses of their own heights"), \
        result.params["tile_method"]
    assert result.params["snap"] == (0, 1) and result.params["courses"] is True
    assert result.params["trial"]["choice"] == "coursed"
    monkeypatch.setattr(_auto, "_coursed_way", lambda exemplar: None)
    control, before = fitted()
    assert control.params["snap"] != (0, 1) and "coursed" not in control.params["trial"]
    assert coursed <= 1.2 and coursed <= before - 0.1, (coursed, before)


@pytest.mark.slow
def test_fit_of_coursed_ashlar_without_a_period_is_judged_by_its_courses_lines():
    """``benchmarks/exemplars.py``'s ashlar (courses 28, 44 and 64 pixels high in a random order: no period).
    Its trial weighs the stochastic way (the photo's own crop) against the courses, and measures the courses'
    grout lines holding their places (line_continuity): the stochastic way breaks them (0.79; the courses 0.94),
    its picture courses ending in stubs, stones cut and cross-faded. The structural distance barely sees it
    (0.985 against 0.976 here; 1.05 against 1.07 over four bakes of an earlier tile): with the courses' trial
    bake a few percent further than the stochastic one, the lines decide, and without them (the control: the
    stochastic way's lines read as kept) the structural distance takes the stochastic way."""
    from spectex.fitting import _auto, fit_result

    photo = _exemplars().load("ashlar")
    result = fit_result(photo)
    trial = result.params["trial"]
    assert trial["choice"] == "coursed" and result.params["snap"] == (0, 1), trial
    assert trial["stochastic"]["continuity"] < _auto.CONTINUITY_LIMIT <= trial["coursed"]["continuity"], trial
    ways = {k: dict(v) for k, v in trial.items() if k in ("stochastic", "coursed")}
    ways["coursed"]["structure"] = 1.04 * ways["stochastic"]["structure"]
    assert _auto._choose_courses(ways, trial["photo_repeat"]) == "coursed"
    ways["stochastic"]["continuity"] = 1.0
    assert _auto._choose_courses(ways, trial["photo_repeat"]) == "stochastic"


@pytest.mark.slow
def test_fitted_columns_take_one_cut_per_segment():
    """The planks turned a quarter (columns along y, snapped along x), their fit baked from the world's origin,
    where a segment starts exactly on a texel edge: every line of a column takes the same cut, so along a
    column the patch changes once per segment at most (the rounding ``COURSE_ROUND`` guards: measured 1
    change over 240 lines; before it, a segment's start computed per line fell either side of the edge and
    its lines alternated between two patches, 67 changes on one column, a board drawn in stripes)."""
    exemplars = _exemplars()
    from spectex.fitting import fit_result
    from spectex.shading.stochastic import course_vertex
    from spectex.shading.tables import anchor_coords, pack

    result = fit_result(np.ascontiguousarray(exemplars.load("planks").transpose(1, 0, 2)))
    tex = result.texture
    assert tex.layers[0].snap[1] == 0 and tex.layers[0].snap[0] > 0
    tables = pack(tex)
    anchor = anchor_coords(tables, 0.0, 0.0)
    w0 = float(tex.tiles[0].shape[0])
    step = float(tex.layers[0].size) / w0
    g = tables.grid[0]
    for column in (25, 65, 140):
        seen = []
        for row in range(90, 330):
            dx, dy = (column + 0.5) * step, (row + 0.5) * step
            sr = tables.mats[0, 0, 0] * dx + tables.mats[0, 0, 1] * dy
            tr = tables.mats[0, 1, 0] * dx + tables.mats[0, 1, 1] * dy
            seen.append(course_vertex(tables.lut, tables.cell_row[0], anchor[0, 0] + sr, anchor[0, 1] + tr,
                                      anchor[0, 2] + g[0, 0] * sr + g[0, 1] * tr,
                                      anchor[0, 3] + g[1, 0] * sr + g[1, 1] * tr, g, w0, w0, int(anchor[0, 4]),
                                      int(anchor[0, 5]), tables.key[0], tables.snap[0, 0], tables.snap[0, 1]))
        changes = sum(a != b for a, b in zip(seen[:-1], seen[1:]))
        assert changes <= 2, (column, changes)


@pytest.mark.slow
@pytest.mark.gl
def test_fitted_planks_gl_matches_cpu_and_is_alias_free(gl):
    """Issue 22's targets on a fitted floor of planks drawn with its course map (the default fit of
    ``benchmarks/exemplars.py``'s planks at 3 cm a pixel): GL = CPU >= 40 dB on every view, and alias-free
    against 16 x 16 supersampled renders without mip-maps: >= 38 dB full-band (measured 39.6 on the aerial
    view, 42.3 without the map: each pixel takes one patch at its centre, where the reference averages the
    patches its footprint covers), >= 45 low-passed (48.3); the control, without mip-maps, far worse."""
    exemplars = _exemplars()
    from helpers import psnr_low, views_against_reference
    from spectex.fitting import fit
    from spectex.shading.resources import cell_maps

    tex = fit(exemplars.load("planks"), pixel_size=0.03)
    assert cell_maps(tex)[0] is not None and min(tex.layers[0].snap) == 0 < max(tex.layers[0].snap)
    full, low, plain = {}, {}, {}
    for name, _, c, g, ref, no_mip in views_against_reference(tex, gl):
        full[name], low[name] = min(psnr(c, ref), psnr(g, ref)), min(psnr_low(c, ref), psnr_low(g, ref))
        plain[name] = psnr_low(no_mip, ref)
    assert min(full.values()) >= 38.0 and min(low.values()) >= 45.0, (full, low)
    assert all(plain[k] <= low[k] - 8.0 for k in VIEWS if k != "close"), (low, plain)


@pytest.mark.slow
def test_fit_of_planks_at_a_fractional_period_keeps_its_courses():
    """A floor of planks photographed at 27.06 pixels a course (``benchmarks/exemplars.py``'s planks at 900
    pixels, resampled to 530): its trial bakes of the finest layer alone read the snapped courses at 1.16 and
    a stochastic jumble of cross-faded boards without a course at 0.91 (the structural distance does not see
    the jumble; over larger bakes of the whole fits, 1.08 and 1.12), so the jumble was drawn. The trial now
    leaves out a way that splits the photo's cells (``metrics.cell_splits`` over ``SPLIT_LIMIT`` times the
    photo's; a bake without the photo's cells at all, as the jumble: infinite), and the courses are drawn
    with their course map. The control: the same trial's numbers without the splits choose the jumble."""
    from PIL import Image

    exemplars = _exemplars()
    from spectex.fitting import _auto, fit_result

    big = exemplars.planks(900, board=46.0, rng=11)
    photo = np.asarray(Image.fromarray((big * 255).astype(np.uint8)).resize((530, 530), Image.LANCZOS))
    result = fit_result(photo)
    trial = result.params["trial"]
    assert trial["choice"] == "snapped" and result.params["courses"] is True, trial
    assert trial["stochastic"]["splits"] > _auto.SPLIT_LIMIT >= trial["snapped"]["splits"], trial
    blind = {k: ({m: x for m, x in v.items() if m != "splits"} if isinstance(v, dict) else v)
             for k, v in trial.items() if k not in ("choice", "photo_repeat")}
    assert _auto._choose(blind, trial["photo_repeat"]) == "stochastic", blind
