"""Joints of walls: the joints along a structure's strips (columns or courses of bricks), and walls of courses of
their own heights (issue 22).

A photo with a period along one axis only (``fitting._auto``) has each strip between its grout lines cut at its
own joints (:func:`_strip_joints`, :func:`_strip_segments`). A wall whose courses differ in height (coursed
ashlar: rows of tall and short stones) has no period at all across its courses: :func:`wall_courses` finds its
grout lines running the whole photo, and :func:`coursed_tile` cuts a tile from one grout line to another, each
course cut at its own joints, to be drawn with offsets along the courses only (``Layer.snap`` of one period
across; ``shading._cells.course_map`` reads its courses of their own heights).
"""

from __future__ import annotations

import math

import numpy as np

from .._pixels import principal_axis
from ._core import cubic_at

#: Most stretch of a strip's stretch of the photo, joint to joint, to the period tile's side (:func:`_strip_cuts`:
#: a photo with a period along one axis only, its strips cut at their own joints); a strip with no pair of joints
#: that close keeps the straight cut.
JOINT_STRETCH = 0.1
#: A strip with more joints than this (its thin runs of the grout's colour) is not taken as bricks in mortar.
MAX_JOINTS = 32
#: A line across a wall is grout between courses where at least this share of it is of the grout's colour class
#: within ``COURSE_LINE_WANDER`` lines of it (:func:`wall_courses`; inside a course, only its joints are; a wall
#: of rubble, its stones in a network of mortar, reads 0.6-0.9 there, a coursed wall's mortar line 0.99-1).
COURSE_LINE_SHARE = 0.95
#: A line across a course's middle three fifths with at least this share of grout (not widened) is a grout line
#: missed (:func:`wall_courses`).
MISSED_LINE_SHARE = 0.6
#: A grout line's pixels count in every line within this many lines of them (a real wall's mortar wanders).
COURSE_LINE_WANDER = 2
#: A run of such lines is a grout line when at most this share of the photo's side wide.
COURSE_LINE_WIDTH = 0.06
#: ... and runs unbroken (within two lines either side, gaps of its grain up to 4 pixels closed) over at least this
#: share of the photo: a mortar line, not grout crossed now and then (hexagons, scales, a turned wall's joints).
COURSE_LINE_SPAN = 0.7
#: The least height of a course between two grout lines (pixels), and the least number of grout lines.
MIN_COURSE = 8
MIN_COURSE_LINES = 3
#: Courses are of their own heights where the tallest is at least this many times the shortest; closer, they
#: are rows of one period (a running bond, rough stones in even courses), which the period's way draws.
COURSE_HEIGHT_RATIO = 1.4


def _strip_joints(profile, width):
    """The joints along one strip: the centres (sub-pixel) of its runs of mortar, or an empty list.

    ``profile`` (n,): per line along the strip, how much its colour is the
    grout's (0: the bricks' mean colour, 1: the grout's); a joint is a run of
    lines over 0.5, at most ``width`` lines long (thin: a run longer is a
    light brick, not mortar) and not touching the photo's ends (where it may
    be cut); its centre is the run's centroid weighted by the excess over 0.5.
    """
    n = profile.shape[0]
    above = np.concatenate([[False], profile > 0.5, [False]])
    edges = np.flatnonzero(np.diff(above.astype(np.int8)))
    joints = []
    for start, stop in zip(edges[::2], edges[1::2]):
        if start == 0 or stop == n or stop - start > width:
            continue
        weights = profile[start:stop] - 0.5
        joints.append(float(np.sum(np.arange(start, stop) * weights) / np.sum(weights)))
    return joints


def _strip_segments(joints, side):
    """The stretches of a strip, joint to joint, that one strip of the tile reads in turn: ``[(a, b), ...]``
    or None.

    One stretch ``(a, b)`` (two of ``joints``) whose length is closest to
    ``side``, if within ``JOINT_STRETCH`` of it; else two, one after the
    other, whose lengths add up to it within ``JOINT_STRETCH``: those that
    share no brick first, then those whose shared bricks' two copies lie
    furthest apart along the strip (taken as a loop), at least a third of
    its length (a strip with too few whole bricks in the photo for the
    tile's side shows one of its bricks twice, far apart, rather than a
    brick made of two, or one brick twice in a row), then the least
    stretch; None where none is.
    """
    if len(joints) < 2 or len(joints) > MAX_JOINTS:
        return None
    j = np.asarray(joints, dtype=np.float64)
    k, m = np.triu_indices(j.size, 1)
    a, b = j[k], j[m]  # every stretch, joint to joint
    stretch = np.abs(side / (b - a) - 1.0)
    best = int(np.argmin(stretch))
    if stretch[best] <= JOINT_STRETCH:
        return [(float(a[best]), float(b[best]))]
    # two stretches p and q (every unordered pair of them, p first), q read after p
    p, q = np.meshgrid(np.arange(a.size), np.arange(a.size), indexing="ij")
    p, q = p.ravel(), q.ravel()
    order = (a[p] < a[q]) | ((a[p] == a[q]) & (b[p] < b[q]))
    p, q = p[order], q[order]
    total = (b[p] - a[p]) + (b[q] - a[q])
    stretch = np.abs(side / total - 1.0)
    shared = np.minimum(b[p], b[q]) > np.maximum(a[p], a[q])
    # the shared stretch's first line in p's part and in q's, apart along the loop: |b_p - a_q|
    apart = np.abs(b[p] - a[q])
    apart = np.where(shared, np.minimum(apart, total - apart), total)
    ok = (stretch <= JOINT_STRETCH) & (apart >= total / 3.0)
    if not ok.any():
        return None
    p, q, stretch, shared, apart = p[ok], q[ok], stretch[ok], shared[ok], apart[ok]
    # those sharing no brick first, then the shared copies furthest apart, then the least stretch
    pick = np.lexsort((stretch, np.where(shared, -apart, 0.0), shared))[0]
    return [(float(a[p[pick]]), float(b[p[pick]])), (float(a[q[pick]]), float(b[q[pick]]))]




def _unbroken(mask):
    """The longest run of True in a 1-D mask once its gaps of up to 4 (a grout line's grain) are closed."""
    from scipy import ndimage

    closed = ndimage.binary_closing(np.pad(mask, 8, mode="edge"), structure=np.ones(5, bool))[8:-8]
    return max((b - a for a, b in _runs(closed)), default=0)


def _runs(mask):
    """``[(start, stop), ...]`` of the runs of True in a 1-D mask (stop exclusive)."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def wall_courses(exemplar):
    """A wall of courses of their own heights: ``(axis, edges, level, width)`` or None.

    The photo's colours along their principal axis (lightly smoothed) are
    split in two by Otsu's threshold, each side again while it holds over
    40% of the pixels (:func:`_grout_classes`); either side's class may be
    the grout, the thinner tried first. A grout line between courses is a
    run of lines (rows, or columns) each at least ``COURSE_LINE_SHARE`` of
    the grout's class within ``COURSE_LINE_WANDER`` lines, at most
    ``COURSE_LINE_WIDTH`` of the side wide, not at the photo's ends, and
    unbroken (within two lines either side, gaps up to 4 pixels closed) over
    ``COURSE_LINE_SPAN`` of the photo; a wall has at least
    ``MIN_COURSE_LINES`` of them along one axis only (along both: a grid of floor tiles, which the
    period's way draws), courses at least ``MIN_COURSE`` pixels high
    between them, the tallest at least ``COURSE_HEIGHT_RATIO`` times the
    shortest, no line of ``MISSED_LINE_SHARE`` grout across the middle
    three fifths of a course (a grout line missed: the rows of a floor of
    boards, which are one period's), and a joint (:func:`_strip_joints`) in
    at least half of its courses.

    Returns ``axis`` (0: the courses run along x, the grout lines are rows;
    1: along y), ``edges`` (the grout lines' centres, pixels across the
    courses, sorted), ``level`` (h, w) (how much each pixel's colour is the
    grout's: 0 at the courses' mean colour, 1 at the grout's, turned so
    that the courses run along x) and ``width`` (the most lines a joint
    spans).
    """
    from scipy import ndimage

    rgb = np.asarray(exemplar, np.float64)[:, :, :3]
    h, w = rgb.shape[:2]
    if min(h, w) < 4 * MIN_COURSE:
        return None
    smooth = np.stack([ndimage.gaussian_filter(rgb[:, :, c], 1.0) for c in range(3)], axis=2)
    flat = smooth.reshape(-1, 3) - smooth.reshape(-1, 3).mean(axis=0)
    level = (flat @ principal_axis(smooth)).reshape(h, w)
    for grout in _grout_classes(level):
        found = _wall(grout, smooth)
        if found is not None:
            return found
    return None


def _grout_classes(level):
    """The candidates for :func:`wall_courses`' grout, lighter and darker: each side of Otsu's threshold on the
    colours along their principal axis, split again by Otsu's threshold on that side alone (its more extreme
    part kept) while it holds over 40% of the pixels (light stones fall with a light mortar at the first split),
    at most three times; the thinner side first."""
    from .._otsu import otsu

    values = level.ravel()
    high = level > otsu(values)[0]
    out = []
    for mask, sign in ((high, 1.0), (~high, -1.0)):
        for _ in range(3):
            if mask.mean() <= 0.4 or mask.sum() < 16:
                break
            mask = mask & (sign * level > sign * otsu(level[mask])[0])
        if 0.0 < mask.mean() <= 0.4:
            out.append(mask)
    return sorted(out, key=lambda m: m.mean())


def _wall(grout, smooth):
    """:func:`wall_courses` for one candidate grout class (``grout`` (h, w) bool, ``smooth`` the smoothed
    colours), or None."""
    from scipy import ndimage

    h, w = grout.shape
    found = []
    for axis in (0, 1):
        lines = grout if axis == 0 else grout.T  # the candidate grout lines are its rows
        # a line that wanders (a real wall's mortar, a pixel or two up and down along it) is counted in each
        # row it passes within COURSE_LINE_WANDER rows of
        near = ndimage.maximum_filter1d(lines, 2 * COURSE_LINE_WANDER + 1, axis=0, mode="nearest")
        share = near.mean(axis=1)
        n, length = lines.shape
        runs = [(a, b) for a, b in _runs(share >= COURSE_LINE_SHARE)
                if a > 0 and b < n and b - a <= max(2, COURSE_LINE_WIDTH * min(h, w))
                and _unbroken(near[max(a - 2, 0):b + 2].any(axis=0)) >= COURSE_LINE_SPAN * length]
        found.append(runs)
    if (len(found[0]) >= MIN_COURSE_LINES) == (len(found[1]) >= MIN_COURSE_LINES):
        return None  # no lines, or lines along both axes (a grid)
    axis = 0 if len(found[0]) >= MIN_COURSE_LINES else 1
    runs = found[axis]
    edges = np.array([(a + b - 1) / 2.0 for a, b in runs])
    heights = np.diff(edges)
    if heights.min() < MIN_COURSE or heights.max() < COURSE_HEIGHT_RATIO * heights.min():
        return None
    share = (grout if axis == 0 else grout.T).mean(axis=1)
    for a, b in zip(edges[:-1], edges[1:]):
        inside = share[int(math.ceil(a + 0.2 * (b - a))):int(math.floor(b - 0.2 * (b - a))) + 1]
        if inside.size and inside.max() >= MISSED_LINE_SHARE:
            # a line of grout across the course's middle that was not taken as one (broken by the grain, or
            # too wide): a grout line missed, not a course of its own height (a floor of boards read as
            # courses of one, two and eight boards; its rows are one period's); a tall stone beside two short
            # ones stacked leaves the line between them under half the course's length
            return None
    # the colours turned so that the courses run along x, as each pixel's share of the grout's colour
    turned = smooth if axis == 0 else smooth.transpose(1, 0, 2)
    mask = grout if axis == 0 else grout.T
    cells = turned[~mask].mean(axis=0)
    toward = turned[mask].mean(axis=0) - cells
    contrast = float(toward @ toward)
    if contrast < 1e-6:
        return None
    share = (turned - cells) @ toward / contrast
    width = max(2, int(math.ceil(2.0 * np.mean([b - a for a, b in runs]))))
    jointed = sum(bool(_strip_joints(_course_profile(share, edges, k), width)) for k in range(len(edges) - 1))
    if jointed < 0.5 * (len(edges) - 1):
        return None
    return axis, edges, share, width


def _course_profile(share, edges, k):
    """The profile along course ``k`` (between grout lines ``k`` and ``k + 1``) of :func:`wall_courses`: its
    interior lines' mean share of the grout's colour."""
    a, b = edges[k], edges[k + 1]
    lines = share[int(math.ceil(a + 0.25 * (b - a))):int(math.floor(b - 0.25 * (b - a))) + 1]
    return lines.mean(axis=0)


def coursed_tile(exemplar, found):
    """A square tile of a wall of courses of their own heights (:func:`wall_courses`'s ``found``): ``(tile, side,
    (one, two, courses, most))`` or None.

    Across the courses the tile runs from one grout line's centre to
    another's (the span is the side, one texel a pixel): its wrap edge lies
    in the grout, every course whole. Of the spans at least half the
    photo's shorter side that fit it, the one whose courses can most often
    be cut at their own joints (:func:`_strip_segments`), then the longest.
    Along the courses each is read from one joint to another (the stretch of
    :func:`_strip_segments`, resampled to the side), so its wrap edge falls
    at one of its joints; a course without such joints reads the photo
    straight from its centre. Turned back where the courses run along y.
    ``(one, two, courses, most)``: the courses cut at one stretch and at
    two, the tile's courses and the most stretch.
    """
    axis, edges, share, width = found
    photo = np.asarray(exemplar, np.float64)[:, :, :3]
    if axis == 1:
        photo = photo.transpose(1, 0, 2)
    h, w = photo.shape[:2]
    profiles = [_strip_joints(_course_profile(share, edges, k), width) for k in range(len(edges) - 1)]
    best = None
    for i in range(len(edges)):
        for j in range(i + 2, len(edges)):
            side = int(round(edges[j] - edges[i]))
            if side < 0.5 * min(h, w) or side > w - 1:
                continue
            cut = [_strip_segments(profiles[k], side) for k in range(i, j)]
            score = (sum(c is not None for c in cut) / (j - i), side)
            if best is None or score > best[0]:
                best = (score, i, j, side, cut)
    if best is None:
        return None
    _, i, j, side, cut = best
    span = edges[j] - edges[i]
    ys = edges[i] + (np.arange(side) + 0.5) * (span / side)  # the tile's rows in the photo (edges: line centres)
    course = np.clip(np.searchsorted(edges, ys, side="right") - 1, i, j - 1) - i
    xs = np.empty((side, side))
    straight = (w - side) / 2.0 + np.arange(side)
    counts = [0, 0]
    most = 0.0
    for k, segments in enumerate(cut):
        rows = course == k
        if segments is None:
            xs[rows] = straight
            continue
        starts = np.array([a for a, _ in segments])
        lengths = np.array([b - a for a, b in segments])
        before = np.concatenate([[0.0], np.cumsum(lengths)])
        total = before[-1]
        u = (np.arange(side) + 0.5) * (total / side)
        m = np.minimum(np.searchsorted(before, u, side="right") - 1, len(segments) - 1)
        xs[rows] = starts[m] + u - before[m]
        counts[len(segments) - 1] += 1
        most = max(most, abs(side / total - 1.0))
    tile = cubic_at(photo, np.broadcast_to(ys[:, None], xs.shape), xs)
    if axis == 1:
        tile = tile.transpose(1, 0, 2)
    return np.ascontiguousarray(tile), side, (counts[0], counts[1], j - i, most)
