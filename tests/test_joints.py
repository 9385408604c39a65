"""A photo with a period along one axis only (columns or courses of bricks of random lengths): the fit's period
tile cuts each strip at its own joints, so no brick of the tile is made of two of the photo's (issue 22)."""

import numpy as np
import pytest

#: Inside a brick: every channel under this (the walls' mortar is 0.85, their bricks at most 0.55).
BRICK_MAX = 0.7
#: A step between two texels inside bricks larger than this is two bricks' colours (the noise's steps are
#: about 0.015 on average, two random bricks differ by 0.1 on average).
STEP = 0.05


def column_wall(side=384, width=31.6, mortar=3.0, rng=5):
    """Columns of bricks ``width`` pixels wide (mortar ``mortar`` px at their left), each column's bricks of
    random lengths (40 to 100 px) between horizontal joints of their own, every brick its own colour, a little
    noise: a period along x, none along y. RGB float32."""
    rng = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side] + 0.5
    col = np.floor(xx / width).astype(np.int64)
    ident = np.empty((side, side), dtype=np.int64)
    joint = np.zeros((side, side), dtype=bool)
    for c in range(col.max() + 1):
        edges = np.cumsum(rng.uniform(40.0, 100.0, side // 30 + 2)) - rng.uniform(0.0, 100.0)
        m = col == c
        k = np.searchsorted(edges, yy[m])
        ident[m] = c * 1000 + k
        joint[m] = yy[m] - np.concatenate([[-1e9], edges])[k] < mortar
    _, index = np.unique(ident, return_inverse=True)
    colours = rng.uniform(0.25, 0.55, (index.max() + 1, 1)) * np.array([1.0, 0.8, 0.7])
    img = colours[index.reshape(side, side)] + 0.01 * rng.standard_normal((side, side, 3))
    img[(xx - col * width < mortar) | joint] = 0.85
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def brick_breaks(tile):
    """Per texel across the tile, how many places down it (wrap edge included) two texels inside bricks, one
    under the other, differ by more than ``STEP``: where a strip's bricks are cut across, a brick made of two
    photo bricks. 0 where every brick of the tile is whole; about the share of a row inside bricks where one
    straight cut crosses the strips. Inside: the two texels and two more each side of them down (the resampled
    mortar's edges blend into the bricks by a texel)."""
    below = np.roll(tile, -1, axis=0)
    brick = tile.max(axis=2) < BRICK_MAX
    inside = np.logical_and.reduce([np.roll(brick, k, axis=0) for k in range(-3, 3)])
    step = np.abs(below - tile).mean(axis=2)
    return float(np.sum(inside & (step > STEP)) / tile.shape[1])


def wrap_step(tile):
    """The mean colour step across the tile's wrap edge down (last row to first) between texels both inside
    bricks (``tests/test_cells.py``'s wrap-edge measure, along one axis)."""
    a, b = tile[-1], tile[0]
    inside = (a.max(axis=1) < BRICK_MAX) & (b.max(axis=1) < BRICK_MAX)
    assert inside.sum() > 0.3 * tile.shape[1]
    return float(np.abs(a - b)[inside].mean())


def _tiles(photo, monkeypatch):
    """The period tile with the strips cut at their joints, and the straight cut's as before 2026-11-26 (the
    control: no joint put where its wrap edge joins two bricks, ``_auto._joints_at_wrap``)."""
    from spectex.fitting import _auto

    period = _auto.structure_period(photo)
    cut = _auto._period_tile(photo, period)
    with monkeypatch.context() as m:
        m.setattr(_auto, "_strip_tile", lambda *args: None)  # the straight cut, as before
        m.setattr(_auto, "_joints_at_wrap", lambda tile, snap: tile)  # (and no joint put at its wrap edge)
        straight = _auto._period_tile(photo, period)
    return period, cut, straight


@pytest.mark.parametrize("rng", [5, 6])
def test_period_tile_cuts_each_column_of_bricks_at_its_own_joints(rng, monkeypatch):
    photo = column_wall(rng=rng)
    period, cut, straight = _tiles(photo, monkeypatch)
    assert period[0] is None and abs(period[1] - 31.6) < 0.5, period
    tile, side, counts, whole, scale = cut
    # the periodic axis as before: the same side, counts, texel period and scale
    assert (side, counts, whole, scale) == straight[1:]
    fixed, plain = brick_breaks(tile), brick_breaks(straight[0])
    # measured: 0.0 for both walls against 0.41 and 0.34 (the straight cut crosses most columns inside a brick)
    assert fixed <= 0.02 and plain >= 0.3, (fixed, plain)
    # the wrap edge itself: the noise's step (0.010) against two bricks' colours (0.074, 0.060)
    assert wrap_step(tile) < 0.025 < 0.04 < wrap_step(straight[0]), (wrap_step(tile), wrap_step(straight[0]))
    # still a tile of the photo's bricks: its mean colour the photo's
    assert np.abs(tile.mean(axis=(0, 1)) - photo.mean(axis=(0, 1))).max() < 0.03


def test_period_tile_cuts_each_course_of_bricks_at_its_own_joints(monkeypatch):
    # the same wall turned: courses of bricks, a period along y only
    photo = np.ascontiguousarray(np.swapaxes(column_wall(rng=7), 0, 1))
    period, cut, straight = _tiles(photo, monkeypatch)
    assert period[1] is None and period[0] is not None, period
    fixed = brick_breaks(np.swapaxes(cut[0], 0, 1))
    plain = brick_breaks(np.swapaxes(straight[0], 0, 1))
    assert fixed <= 0.02 and plain >= 0.3, (fixed, plain)


@pytest.mark.parametrize("rng", [1, 2])
def test_period_tile_of_a_running_bond_of_random_lengths_has_no_seam_across_its_courses(rng, monkeypatch):
    # tests/test_snap.py's wall, bricks of random length in regular courses (a period down only), brick-red
    # with grain, anti-aliased: the colour step across the tile's wrap edge (along the courses) inside bricks is
    # the grain's, the step between neighbours inside bricks elsewhere (measured 0.019-0.022 against 0.019),
    # where the straight cut puts two bricks' colours side by side (0.093-0.109)
    from test_snap import subpixel_wall

    photo = subpixel_wall(320, random_length=True, rng=rng)
    period, cut, straight = _tiles(photo, monkeypatch)
    assert period[1] is None and abs(period[0] - 15.3) < 0.2, period
    steps = []
    for tile in (cut[0], straight[0]):
        tile = np.swapaxes(tile, 0, 1)  # the courses down
        brick = tile[:, :, 1] < 0.45  # the mortar is light grey (green 0.7), the bricks red (green 0.25)
        inside = np.logical_and.reduce([np.roll(brick, k, axis=0) for k in range(-3, 3)])
        jump = np.abs(np.roll(tile, -1, axis=0) - tile).mean(axis=2)
        assert inside[-1].sum() > 100
        steps.append((float(jump[-1][inside[-1]].mean()), float(jump[:-1][inside[:-1]].mean())))
    (wrap, grain), (wrap_straight, grain_straight) = steps
    assert wrap <= 1.3 * grain and wrap_straight >= 3.0 * grain_straight, steps


def test_period_tile_without_joints_is_the_straight_cut(monkeypatch):
    # columns without joints (stripes of grout and plain bands): no strip to cut, the tile byte for byte the
    # straight cut's
    from spectex.fitting import _auto

    rng = np.random.default_rng(3)
    side = 256
    xx = np.arange(side)[None, :] + 0.5
    col = np.floor(xx / 29.3).astype(np.int64)
    band = rng.uniform(0.25, 0.55, col.max() + 1)[col]
    img = np.where(xx - col * 29.3 < 3.0, 0.85, band) * np.ones((side, 1))
    img = np.clip(img[:, :, None] + 0.01 * rng.standard_normal((side, side, 3)), 0.0, 1.0).astype(np.float32)
    period = (None, 29.3)
    tile = _auto._period_tile(img, period)
    monkeypatch.setattr(_auto, "_strip_tile", lambda *args: None)
    straight = _auto._period_tile(img, period)
    assert np.array_equal(tile[0], straight[0]) and tile[1:] == straight[1:]


def test_strip_segments_prefer_one_stretch_then_two_that_share_no_brick_then_copies_far_apart():
    from spectex.fitting._joints import _strip_segments

    # one stretch: joints 10 and 110 for a side of 102 (2% stretch)
    assert _strip_segments([10.0, 60.0, 110.0, 200.0], 102) == [(10.0, 110.0)]
    # none alone within 10% of 200 (230 is 13% off): two sharing no brick, the short brick 100-130 left out
    assert _strip_segments([0.0, 100.0, 130.0, 230.0], 200) == [(0.0, 100.0), (130.0, 230.0)]
    # three bricks of 100 for a side of 400: one brick shown twice, its copies half the loop apart (A B C B),
    # not twice in a row (A B B C, A B C A)
    assert _strip_segments([0.0, 100.0, 200.0, 300.0], 400) == [(0.0, 300.0), (100.0, 200.0)]
    # too few joints for the side
    assert _strip_segments([0.5, 20.5], 300) is None
    assert _strip_segments([0.5, 20.5, 30.5], 300) is None
    assert _strip_segments([], 300) is None
    # more joints than bricks in mortar have (thin runs of the grout's colour every few lines): none
    assert _strip_segments(list(np.arange(40) * 5.0 + 0.5), 100) is None


def test_strip_joints_are_thin_runs_of_mortar_off_the_photos_ends():
    from spectex.fitting._joints import _strip_joints

    profile = np.zeros(60)
    profile[0:3] = 1.0  # touches the photo's top: it may be cut, no joint
    profile[10:13] = 1.0  # a joint, its centre at 11
    profile[30:45] = 1.0  # too long for mortar: a light brick
    profile[50] = 0.9
    profile[51] = 0.7  # a joint, centred towards its stronger line
    assert _strip_joints(profile, 4) == pytest.approx([11.0, 50.0 + 0.2 / 0.6])


def test_fit_says_its_columns_were_cut_at_their_joints():
    from spectex.fitting import fit_result

    result = fit_result(column_wall(256, rng=5), pixel_size=0.01, layers=2, iterations=1)
    assert result.params["period_px"][0] is None
    assert "columns cut at their own joints" in result.params["tile_method"], result.params["tile_method"]
    # the control: a wall with a period along both axes (floor tiles) is cut as before, nothing said
    from helpers import floor_photo as _floor

    result = fit_result(_floor(256, 64)[0], pixel_size=0.01, layers=2, iterations=1)
    assert result.params["period_px"][0] is not None and "joints" not in result.params["tile_method"]
