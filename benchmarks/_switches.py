"""Switches the benchmarks compare a route with and without (one home for each)."""

from __future__ import annotations

from contextlib import contextmanager


@contextmanager
def without_free_cells():
    """Within the block, tiles get no free cell map (``spectex.shading._cells.free_cell_map`` answers None), as
    before free cells existed; the shading cache is emptied on the way in and out, so nothing made inside is
    kept after it, nor anything from before used inside it."""
    from spectex.shading import _cells, resources

    original = _cells.free_cell_map
    _cells.free_cell_map = lambda tile: None
    resources.clear_cache()
    try:
        yield
    finally:
        _cells.free_cell_map = original
        resources.clear_cache()


@contextmanager
def without_courses():
    """Within the block, main's code before courses (2026-11-27): a tile snapped along one axis gets no course map
    (``spectex.shading._cells.course_map`` answers None: its layer is drawn with the triangle grid's blend) and a
    fit's period tile gets no joint at its wrap edge (``spectex.fitting._auto._joints_at_wrap`` leaves it); the
    shading cache is emptied on the way in and out."""
    from spectex.fitting import _auto
    from spectex.shading import _cells, resources

    course_map, joints = _cells.course_map, _auto._joints_at_wrap
    _cells.course_map = lambda tile, snap: None
    _auto._joints_at_wrap = lambda tile, snap: tile
    resources.clear_cache()
    try:
        yield
    finally:
        _cells.course_map, _auto._joints_at_wrap = course_map, joints
        resources.clear_cache()


@contextmanager
def grain_blind():
    """Within the block, main's code before a large photo's grain was read (2026-11-27): a large photo without
    structure is cropped at full resolution whatever the size of its stones (``_core.MIN_TILE_GRAINS`` 0; the
    structure's rule stays)."""
    from spectex.fitting import _core

    original = _core.MIN_TILE_GRAINS
    _core.MIN_TILE_GRAINS = 0
    try:
        yield
    finally:
        _core.MIN_TILE_GRAINS = original


@contextmanager
def without_coursed_walls():
    """Within the block, main's code before walls of courses of their own heights (2026-11-28): the fit offers
    its trial no coursed way (``spectex.fitting._auto._coursed_way`` answers None) and a photo with a period along
    one axis only keeps the largest tile side whatever its courses' joints (``_auto._joint_side`` keeps its
    pick)."""
    from spectex.fitting import _auto

    coursed, side = _auto._coursed_way, _auto._joint_side
    _auto._coursed_way = lambda exemplar: None
    _auto._joint_side = lambda found, pick, joints: pick
    try:
        yield
    finally:
        _auto._coursed_way, _auto._joint_side = coursed, side


@contextmanager
def without_course_bands():
    """Within the block, a wall of courses of their own heights is drawn as before its bands of courses
    (2026-11-28): every band starts at the tile's first course (the course-start table,
    ``spectex.shading.stochastic.course_starts_row``, of that one course), so the tile's courses come back in
    their order once a tile across them; the shading cache is emptied on the way in and out."""
    from spectex.shading import resources, stochastic

    original = stochastic.course_starts_row

    def one_course(course_map):
        out = original(course_map)
        out[0, :, 0] = out[0, 0, 0]
        return out

    stochastic.course_starts_row = one_course
    resources.clear_cache()
    try:
        yield
    finally:
        stochastic.course_starts_row = original
        resources.clear_cache()
