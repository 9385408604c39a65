"""A structure the photo holds turned by more than a few degrees (issue 22): a wall photographed turned, a floor laid
at an angle. Its lattice runs along its lines, which the photo's axes see only as a large, inexact super-lattice:
the tile is cut from the photo straightened and the finest layer drawn turned back."""

from dataclasses import replace

import numpy as np
import pytest


def _wall(angle, side=256, rng=8):
    """A running-bond wall of bricks 29 x 13 pixels (mortar 2), each its own red, turned by ``angle`` degrees."""
    from scipy import ndimage

    gen = np.random.default_rng(rng)
    big = int(side * 1.5)
    yy, xx = np.mgrid[0:big, 0:big].astype(np.float64)
    bh, bw = 13, 29
    row = (yy // bh).astype(int)
    shift = np.where(row % 2 == 0, 0.0, bw / 2.0)
    key = row * 1000 + ((xx + shift) // bw).astype(int)
    _, inv = np.unique(key, return_inverse=True)
    colours = np.array([0.62, 0.30, 0.22]) * gen.uniform(0.75, 1.15, (inv.max() + 1, 1))
    img = colours[inv.reshape(big, big)] * (1.0 + 0.04 * gen.standard_normal((big, big, 1)))
    mortar = (yy % bh < 2) | ((xx + shift) % bw < 2)
    img[mortar] = (0.72, 0.70, 0.65)
    turned = np.stack([ndimage.rotate(img[:, :, c], angle, reshape=False, order=1) for c in range(3)], axis=2)
    o = (big - side) // 2
    return np.clip(turned[o:o + side, o:o + side], 0.0, 1.0).astype(np.float32)


@pytest.fixture(scope="module")
def turned_fits():
    """The wall turned 20 degrees fitted by default, and with the straightening of a turned design off (the
    control: the code before, the tile cut along the photo's axes at the super-lattice they see)."""
    from spectex import fitting
    from spectex.fitting import _auto

    photo = _wall(20.0)
    default = fitting.fit_result(photo, rng=0)
    saved = _auto.DESIGN_HOLD
    _auto.DESIGN_HOLD = np.inf
    try:
        control = fitting.fit_result(photo, rng=0)
    finally:
        _auto.DESIGN_HOLD = saved
    return photo, default, control


def test_a_turned_wall_is_cut_straight_and_drawn_turned_back(turned_fits):
    from spectex.fitting._structure import structure_orientation
    from spectex.render import bake

    photo, default, control = turned_fits
    assert control.params["turn_deg"] == 0.0
    turn = default.params["turn_deg"]
    angle = structure_orientation(photo)
    assert abs(turn - angle) < 2.0 and abs(turn) > 15.0, (turn, angle)
    assert any("drew it turned back" in note for note in default.notes)
    # the tile holds the straightened wall's lattice: its period is the bricks' (13 x 2 rows down, 29 across)
    py, px = default.params["period_px"]
    assert abs(px - 29.0) < 1.0 and abs(py - 26.0) < 1.0, (py, px)
    # drawn turned back: the render's lines run as the photo's
    render = bake(default.texture, (512, 512), pixel_size=default.pixel_size)
    assert abs(structure_orientation(render) - angle) < 1.5, (structure_orientation(render), angle)


def test_a_turned_wall_keeps_its_mortar_unbroken(turned_fits):
    """The structure kept whole: the render, straightened by the photo's angle, holds the wall's lattice across
    it as the photo does (the share of its variance that folding by its periods keeps). Cut at the axes'
    inexact super-lattice (the control), its patches meet at broken mortar and the lattice breaks between them.
    (``line_breaks`` does not see this at 256 pixels: a patch's broken mortar is a short stretch of its windows'
    lines, and it scores the straight render's bilinear sampling of its turned mortar as kinks.)"""
    from spectex.fitting._auto import _lattice_hold, _straightened
    from spectex.fitting._structure import structure_orientation
    from spectex.render import bake

    photo, default, control = turned_fits
    angle = structure_orientation(photo)
    angle += structure_orientation(_straightened(photo, angle))
    own = _lattice_hold(_straightened(photo, angle))
    holds = [_lattice_hold(_straightened(bake(r.texture, (512, 512), pixel_size=r.pixel_size), angle))
             for r in (default, control)]
    assert holds[0] > 0.8 * own and holds[1] < 0.3 * own, (holds, own)


def test_a_grid_turned_45_degrees_is_one_design_not_a_perspective():
    """A square grid turned 45 degrees reads +45 in one half and -45 in the other: the same angle (modulo 90
    degrees), not lines fanning out; and its lattice along the axes (every 2 cells, exactly) is cut as it is."""
    from scipy import ndimage

    from helpers import floor_photo
    from spectex.fitting import _auto

    big = floor_photo(600, 40, rng=3)[0]
    turned = np.stack([ndimage.rotate(big[:, :, c], 45.0, reshape=False, order=1) for c in range(3)], axis=2)
    photo = np.clip(turned[172:428, 172:428], 0.0, 1.0).astype(np.float32)
    assert _auto._orientation_drift(photo) < _auto.PERSPECTIVE_DRIFT
    notes = []
    out, angle, drift, turn = _auto._straighten_structure(photo, _auto.structure_peak(photo), notes)
    assert turn == 0.0 and out is photo and not notes, notes


def _scales(side=256, cell=14.0, jitter=0.12, rng=3):
    """A reptile's skin: domed scales on a hexagonal lattice ``cell`` pixels apart (centres jittered by ``jitter``
    of it) in dark crevices, coloured in patches larger than a scale (green to brown)."""
    from scipy import ndimage
    from scipy.spatial import cKDTree

    gen = np.random.default_rng(rng)
    n = int(side / cell) + 4
    pts = np.array([(r * 0.866 * cell, (c + 0.5 * (r % 2)) * cell) for r in range(-2, n) for c in range(-2, n)])
    pts = pts + gen.normal(0.0, jitter * cell, pts.shape)
    yy, xx = np.mgrid[0:side, 0:side]
    d, idx = cKDTree(pts).query(np.stack([yy.ravel(), xx.ravel()], axis=1).astype(np.float64), k=2)
    edge = (d[:, 1] - d[:, 0]).reshape(side, side)
    patches = ndimage.gaussian_filter(gen.standard_normal((side, side)), 20.0, mode="wrap")
    centre = np.clip(pts.astype(int), 0, side - 1)
    t = np.clip(0.5 + 0.5 * patches[centre[:, 0], centre[:, 1]] / patches.std(), 0.0, 1.0)
    colour = np.outer(t, (0.35, 0.42, 0.2)) + np.outer(1.0 - t, (0.45, 0.33, 0.2))
    dome = np.clip(edge / (0.5 * cell), 0.0, 1.0) ** 0.6
    img = colour[idx[:, 0]].reshape(side, side, 3) * (0.55 + 0.45 * dome[:, :, None])
    crevice = np.clip((2.0 - edge) / 2.0, 0.0, 1.0)[:, :, None]
    return np.clip(img * (1.0 - crevice) + 0.1 * crevice, 0.0, 1.0).astype(np.float32)


def test_hexagonal_scales_have_no_lines_to_straighten(monkeypatch):
    """A hexagonal structure's three directions of edges cancel in the orientation's vote (taken four times):
    its angle and its halves' are chance, so it is neither turned nor said to be in perspective (with advice to
    photograph it square-on). The control: without the coherence rule its halves' chance angles read as lines
    fanning out."""
    from spectex.fitting import _auto
    from spectex.fitting._structure import MIN_LINE_COHERENCE, line_coherence

    photo = _scales()
    wall = _wall(20.0)
    assert line_coherence(photo) < 0.5 * MIN_LINE_COHERENCE < 2.0 * MIN_LINE_COHERENCE < line_coherence(wall)
    structure = _auto.structure_peak(photo)
    assert structure >= _auto.STRUCTURED_PEAK
    notes = []
    out, _, _, turn = _auto._straighten_structure(photo, structure, notes)
    assert out is photo and turn == 0.0 and not notes, notes
    monkeypatch.setattr(_auto, "MIN_LINE_COHERENCE", 0.0)
    notes = []
    _auto._straighten_structure(photo, structure, notes)
    assert any("perspective" in note for note in notes), notes


def test_reptile_scales_are_drawn_whole_cell_by_cell():
    """A hexagonal lattice's rows are sqrt(3) times its columns apart, so a square tile of whole periods holds
    a fractional number of texels per period along one axis (here 24.5 down): the cell map folds the tile into
    ``round(period)`` phases, so the fit's snapped layer still keeps each scale whole (one patch per scale)
    where, with no map (the rule before: whole periods on both axes only), its patches' straight boundaries
    cut scales in two. The map's cells are the scales: two per period (the lattice's rectangular cell holds a
    scale and two halves), each about a scale's area."""
    from spectex import fitting
    from spectex.shading import resources

    photo = _scales()
    resources._CACHE.clear()
    result = fitting.fit_result(photo, rng=0)
    nx, ny = result.params["snap"]
    tile = result.texture.tiles[0]
    h, w = tile.shape[:2]
    assert nx > 0 and ny > 0 and h % ny != 0, (result.params["tile_method"], tile.shape)  # fractional rows
    cells = resources.cell_maps(result.texture)[0]
    assert cells is not None
    yy, xx = np.mgrid[0:h, 0:w]
    centre = (np.round(np.mod(yy + cells[:, :, 1], h)).astype(int) * (w + 1)
              + np.round(np.mod(xx + cells[:, :, 0], w)).astype(int))
    _, sizes = np.unique(centre, return_counts=True)
    assert len(sizes) == 2 * nx * ny, (len(sizes), nx, ny)
    scale = h * w / (2 * nx * ny)
    assert np.all(np.abs(sizes / scale - 1.0) < 0.25), (sizes.min(), sizes.max(), scale)


def test_gl_matches_cpu_on_a_turned_fit_with_cells_of_a_fractional_period(gl, turned_fits):
    """Independent routes: the GL renderer against the CPU reference on the turned wall's fit (its finest layer
    rotated, snapped) and on the reptile scales' fit (cells folded from a fractional period), every test view."""
    from helpers import SIZE, VIEWS, psnr
    from spectex import fitting
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer

    textures = [turned_fits[1].texture, fitting.fit_result(_scales(), rng=0).texture]
    assert textures[0].layers[0].rotation != 0.0
    for tex in textures:
        with GLRenderer(tex, ctx=gl) as r:
            for name, cam in VIEWS.items():
                c = render_cpu(tex, cam, SIZE)
                g = r.render(cam, SIZE)
                assert psnr(g, c) >= 40.0, (name, psnr(g, c))


def _herringbone(side=256, unit=8, angle=45.0, rng=2):
    """Herringbone: bricks of 2 x 1 ``unit`` laid in zigzags (a horizontal and a vertical brick per cell of the
    lattice (1, 1), (2, -2) in units), turned by ``angle`` degrees (45: the bricks at +-45 degrees, the zigzags'
    repeat along the photo's axes), each brick its own red in light mortar."""
    from scipy import ndimage

    gen = np.random.default_rng(rng)
    big = int(side * 1.5)
    n = big // unit + 8
    label = -np.ones((n, n), dtype=np.int64)
    k = 0
    for m in range(-2 * n, 2 * n):
        for q in range(-n, n):
            tx, ty = m + 2 * q, m - 2 * q
            for shape in (((0, 0), (1, 0)), ((0, 1), (0, 2))):
                cells = [(x + tx, y + ty) for x, y in shape]
                if all(0 <= x < n and 0 <= y < n for x, y in cells):
                    for x, y in cells:
                        label[y, x] = k
                k += 1
    yy, xx = np.mgrid[0:big, 0:big]
    lab = label[yy // unit, xx // unit]
    _, inv = np.unique(lab, return_inverse=True)
    img = (np.array([0.62, 0.32, 0.24]) * gen.uniform(0.75, 1.15, (inv.max() + 1, 1)))[inv.reshape(big, big)]
    img = img * (1.0 + 0.05 * gen.standard_normal((big, big, 1)))
    edge = (np.diff(lab, axis=0, prepend=lab[:1]) != 0) | (np.diff(lab, axis=1, prepend=lab[:, :1]) != 0)
    img[ndimage.binary_dilation(edge)] = (0.72, 0.70, 0.65)
    turned = np.stack([ndimage.rotate(img[:, :, c], angle, reshape=False, order=1) for c in range(3)], axis=2)
    o = (big - side) // 2
    return np.clip(turned[o:o + side, o:o + side], 0.0, 1.0).astype(np.float32)


def test_herringbone_is_a_design_cut_as_it_is(monkeypatch):
    """Herringbone with its bricks at 45 degrees repeats exactly along the photo's axes: straightened (bricks
    along the axes, the zigzags' lattice diagonal) its lattice holds no better, so it is cut as it is, not
    resampled. The control: a rule that turns wherever the lattice holds at all as well turns it."""
    from spectex.fitting import _auto

    photo = _herringbone()
    structure = _auto.structure_peak(photo)
    assert structure >= _auto.STRUCTURED_PEAK
    assert abs(abs(_auto.structure_orientation(photo)) - 45.0) < 2.0
    notes = []
    out, _, _, turn = _auto._straighten_structure(photo, structure, notes)
    assert out is photo and turn == 0.0 and not notes, notes
    monkeypatch.setattr(_auto, "DESIGN_HOLD", 0.9)
    assert _auto._straighten_structure(photo, structure, [])[3] != 0.0


def test_spectex_fit_says_the_tile_was_cut_turned_and_what_the_resampling_costs(tmp_path, capsys, turned_fits):
    """The command says what it did (a note) and, beside the structural distance, the same with render and
    photo halved (the turned layer's bilinear resampling, which the measure counts as lost detail, weighs
    less there); an unturned fit's line says neither (the control)."""
    import re

    from spectex import io
    from spectex.cli import main

    photo = turned_fits[0]
    io.write_image(tmp_path / "wall.png", photo)
    assert main(["fit", str(tmp_path / "wall.png"), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "drew it turned back" in out
    line = next(x for x in out.splitlines() if x.strip().startswith("structure"))
    found = re.search(r"structure ([0-9.]+)x .*drawn turned by (-?[0-9.]+) degrees.*; ([0-9.]+)x with both halved",
                      line)
    assert found, line
    assert abs(float(found.group(2)) - turned_fits[1].params["turn_deg"]) < 0.1
    assert float(found.group(3)) < float(found.group(1))  # the resampling weighs less at half size
    io.write_image(tmp_path / "square.png", _wall(0.0))
    assert main(["fit", str(tmp_path / "square.png"), "-o", str(tmp_path / "out2")]) == 0
    out = capsys.readouterr().out
    assert "drawn turned" not in out and "drew it turned back" not in out


def test_gl_cells_match_cpu_where_the_layer_coordinates_are_negative(gl, turned_fits):
    """The cell map's texel index in GLSL: ``%`` of a negative int is undefined there, and llvmpipe's disagreed
    with the CPU's floor modulo wherever the layer's s or t was negative (whole bricks from other patches, 39.6 dB
    on this view, all of it in the columns where s < 0). Each side of the view against the CPU, the finest layer
    alone (snapped, with cells), turned each way and not."""
    from helpers import SIZE, VIEWS, psnr
    from spectex.render.cpu import render_cpu
    from spectex.render.gl import GLRenderer
    from spectex.texture import SpectralTexture

    fitted = turned_fits[1].texture
    for rotation in (fitted.layers[0].rotation, 0.0, 20.0):
        tex = SpectralTexture(list(fitted.tiles), [replace(fitted.layers[0], rotation=rotation)])
        with GLRenderer(tex, ctx=gl) as r:
            g = r.render(VIEWS["ground"], SIZE)
        c = render_cpu(tex, VIEWS["ground"], SIZE)
        half = g.shape[1] // 2
        assert min(psnr(g[:, :half], c[:, :half]), psnr(g[:, half:], c[:, half:])) >= 50.0, rotation
