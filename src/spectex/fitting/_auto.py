"""The fit's default method (issue 22): :func:`fit_auto`, called by :func:`spectex.fitting.fit_result`.

What each layer carries, and why (``docs/fitting.md``):

* **Layer 0** shows the photo's own detail at its own scale: a seamless
  tile made from the photo (its seamless crop; a tileable quilt of it with
  a reuse penalty where a small photo's tile is drawn periodic), drawn
  stochastic with the sharpened blend weights
  of ``spectex.shading.stochastic``. A structured photo gets a tile cut at
  whole periods of its structure instead, drawn stochastic with its patch
  offsets snapped to whole periods (``Layer.snap``: the grid stays, the
  bricks in it change) or periodic, whichever way trial bakes measure best
  (:func:`_trial`, :func:`_choose`: structural distance, and the repeat of
  the content beyond the structure's lattice). The period is read to a
  fraction of a pixel and the tile resampled to whole-texel periods (the
  snapped offsets are whole texels); a photo a few degrees off its lines is
  straightened first, and one in perspective (its lines fanning out) is
  rectified by a homography from its lines' vanishing points, so that
  patches from its left and right carry the same lattice and meet without
  V-shaped breaks (:func:`_straighten_structure`; the trial leaves out a way
  whose bake's lines break, :func:`spectex.metrics.line_breaks`). A wall of
  courses of their own heights (coursed ashlar, no period across them) gets
  a candidate of its own: a tile from one grout line to another, each course
  cut at its own joints, snapped one period across (:func:`_coursed_way`,
  ``fitting._joints``).
* **Layers 1 ..** carry only what the photo says about larger scales: a
  second tile of random-phase noise (Galerne et al. 2011) whose spectrum
  continues the photo's below its lowest frequency (the slope of its three
  coarsest octaves, at most ``AUTO_MAX_SLOPE``) and holds nothing above
  about two cycles across the photo, coloured along the main axis of the
  photo's low-passed colours. They go over the finer layers by the overlay
  blend (``COARSE_BLEND``): they scale the colour below (its distance to
  black under mid-grey, to white above), so black and white stay and the
  detail keeps its contrast. The photo itself is never magnified.
* **Colours** end with the rounds' shift of the tile's means to the photo's
  (the overlay layers keep the finest layer's mean), the tile's extremes
  made the photo's, rank for rank (:func:`_match_tails`: inside the
  photo's range, nothing piled at black or white), its two coarsest bands
  lowered where a bake over twice the photo holds more contrast at the
  photo's scale than the photo (:func:`_even_blotches`), and the coarse
  layers' opacities halved where the bakes still clip more than the photo
  (:func:`_clip_guard`); not the exact histogram step, which fitted a few
  bake regions' pooled histogram and stretched a non-stationary photo's
  flat parts (see the last step in :func:`fit_auto`).
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._lighting import even_lighting
from .._pixels import box_halved
from .._validate import check_choice, check_float, check_int, check_rng
from ..render.cpu import bake
from ._core import (
    FIT_TILINGS,
    MAX_ANALYSIS_SIZE,
    MIN_SIZE,
    STRUCTURED_PEAK,
    FitResult,
    _coarse_slope,
    _prepared_with_source,
    _Problem,
    _shape_spectrum,
    cubic_at,
    finest_tile,
    structure_peak,
)
from ._joints import _strip_joints, _strip_segments, coursed_tile, wall_courses
from ._structure import MIN_LINE_COHERENCE, orientation_vote, structure_orientation, structure_period

#: The photo's assumed width (its longer side), metres, when neither ``pixel_size`` nor
#: ``photo_size`` is given: a photo of ground taken standing, about 1.5 m across.
DEFAULT_PHOTO_SIZE = 1.5
#: Most power per octave the coarse layers' continuation may keep towards coarser scales (dB per
#: octave): a stationary texture of independent objects has a flat 2-D spectrum beyond its objects'
#: size (-6 dB per octave band); -3 leaves room for the slow variation of real ground, where the
#: legacy fit's -1.5 made blotches larger than anything in the photo.
AUTO_MAX_SLOPE = -3.0
#: Most stretch of the photo's period to the tile's whole-texel period (:func:`_tile_counts`).
PERIOD_STRETCH = 0.12
#: A structured photo turned by more than this (degrees, :func:`structure_orientation`) is straightened first.
STRAIGHTEN_MIN = 0.5
#: Largest turn straightened (degrees): more is taken as the structure's own design (herringbone, diagonals).
STRAIGHTEN_MAX = 10.0
#: A structure turned more than ``STRAIGHTEN_MAX`` is cut straightened (and drawn turned back) where its
#: lattice holds this many times better along its lines than along the photo's axes (:func:`_lattice_hold`):
#: a lattice turned so that the axes see only a large, inexact super-lattice, whose snapped patches meet at
#: broken mortar (a running-bond wall turned 11-45 degrees: 8.7-290 times; floor tiles turned 11-37 degrees:
#: 3.5-230). A square grid turned 45 degrees repeats exactly along the axes every 2 cells (1.03): cut as it
#: is, it spares the turn's resampling (bilinear between texels, which blurs: structural distance at half
#: size 1.54 turned, 1.38 as it is). A design whose lattice runs along the axes (herringbone, its bricks at
#: 45 degrees: 0.88 as it is, 0.94 straightened, 1.07 times) stays as it is.
DESIGN_HOLD = 1.5
#: The orientation of a structured photo's halves (left and right, top and bottom) differing by more than
#: this (degrees) says the photo is in perspective (its lines fan out).
PERSPECTIVE_DRIFT = 1.5
#: A photo with a period along one axis only may take a tile side down to this share of the largest where
#: every one of its strips can then be cut at its own joints (:func:`_tile_counts`; the least stretch decides
#: among sides of at least 70% of the largest otherwise).
JOINT_SIDE_SHARE = 0.5
#: Stretch a whole texel period along the tile's second axis may add before a fractional one is taken.
PERIOD_FRACTION_COST = 0.02
#: A structured photo's finest layer is the period-cut tile drawn stochastically with its offsets
#: snapped to whole periods unless another way is closer by more than this fraction of the
#: structural distance (the measure's spread between windows of one photo is about this large;
#: structure kept when in doubt).
TRIAL_MARGIN = 0.1
#: A way of drawing the finest layer repeats when its content (the structure's lattice removed,
#: ``repeat_peak(..., period=)``) correlates with itself by more than this at some lag, or by more
#: than the photo's own plus ``REPEAT_MARGIN``: such a way is chosen only if every way repeats.
REPEAT_LIMIT = 0.1
REPEAT_MARGIN = 0.05
#: A way of drawing the finest layer breaks the structure's lines when its trial bake's kinks
#: (:func:`spectex.metrics.line_breaks`, windows of ``BREAK_WINDOW`` pixels) exceed the photo's by this
#: factor: such a way is chosen only if every way breaks them.
BREAK_LIMIT = 1.5
BREAK_WINDOW = 64
#: A way of drawing the finest layer splits the structure's cells (bricks, boards, floor tiles changing
#: colour partway: :func:`spectex.metrics.cell_splits`) when its trial bake's split exceeds the photo's by
#: this factor: such a way is chosen only if every way splits them. Drawn whole (snapped, with cells or
#: courses) fitted floors read 0.9-1.2, with the patches' boundaries through them 1.3-2.1.
SPLIT_LIMIT = 1.3
#: A way of drawing a structure along one axis (boards, a wall's columns) moves its lines when its trial bake's
#: :func:`spectex.metrics.line_continuity` is under this fraction of the photo's: such a way is chosen only if
#: every way moves them. Boards of uneven widths snapped to whole periods read 0.80, drawn unsnapped 0.71,
#: aligned 1.02; snapped floors of even boards and brick 1.03.
CONTINUITY_LIMIT = 0.9
#: Boards side by side without joints (drawn aligned where their courses have no map): at most this share of the
#: luma's gradient energy runs along the boards (their ends, a brick's joints, knots), the rest across (their
#: edges). Boards of a game's wall 0.10 (knots and grain), drawn ones 0.00; rows of bricks without a course map
#: 0.36 (drawn aligned, their bricks were merged and cut by the patches' edges), brick 0.18, flat bricks of 4:1
#: with thin mortar 0.16 (about the bricks' height over their length plus height), stone walls 0.28-0.50.
BOARD_ALONG_SHARE = 0.12
#: A structured photo (straightened) at least this many pixels a side gives its stochastic way its own seamless
#: crop, as an unstructured photo does; a smaller one a tileable quilt of 512 (a 128-pixel wall's own crop, its
#: patches of 56 pixels, lost 2 dB of its coarsest band). A 512-pixel wall of stones straightened by 0.7 degrees
#: (504 pixels) was quilted, its stones cut by the blocks' straight seams, and no free cells could be read.
STRUCTURED_CROP_MIN = 384
#: Side of the trial's far bake (pixels, at twice the photo's pixel size).
TRIAL_FAR = 512
#: Side of the trial's bake at the photo's scale, and the fewest of the structure's periods it holds (at
#: most the photo's side): each of its 4 windows then holds 3 periods. Windows of 1.5 periods (a floor of
#: 85-pixel tiles in 256 pixels) read the grout's place in the window more than the drawing: the band
#: energies 4-6 times their floor for every way, the snapped floor 2.20 and a stochastic jumble of grout
#: crosses 1.56; in 512 pixels 1.18 and 2.08.
TRIAL_SIDE = 256
TRIAL_PERIODS = 6
#: Along an axis without a period (courses of boards, columns of bricks) the boards' median length counts
#: as a period: a floor of planks 27 pixels a course, boards of 60-160 pixels, read in windows of 128
#: pixels (a board or less) put the snapped courses at 1.25 and a stochastic jumble of cross-faded boards
#: at 1.00, and the jumble was drawn; over 8 windows of 512 of larger bakes, 1.08 and 1.12.
#: Default opacity of the first coarse layer (method "auto"): low, so that the coarse layers veil
#: the photo's detail little (0.25 over four layers took 5 dB of its power, which the band step put
#: back by raising the tile's contrast into clipping).
AUTO_OPACITY = 0.1
#: How the coarse layers go over the finer ones: the overlay blend (``Layer.blend``), which scales
#: the colour below by ``1 + d`` under mid-grey and its distance to white by ``1 - d`` above, so
#: black and white stay where they are and the detail's contrast is kept. The alpha blend (here
#: until 2026-11-26) veiled the detail by the opacity and lifted black towards the coarse colour: a
#: roof of tiles with black gaps read 0.07 in its gaps and a structural distance 3.78 (1.28 with
#: the overlay); the variance-preserving blend kept the contrast but amplified the extremes (9% of
#: the deep-field photo's values clipped at 0, the photo's 0.8%).
COARSE_BLEND = "overlay"
#: The coarse layers' clipping guard: where the finished texture's bakes clip more of their values
#: than the photo (to 0 or 1 within half an 8-bit step) by over this, the coarse layers' opacities
#: are halved, at most ``CLIP_HALVINGS`` times (a dark photo's near-black values darkened by the
#: coarse layers' dark phases round to 0).
CLIP_ROOM = 0.0025
CLIP_HALVINGS = 3
#: Share of the tile's values at each end whose values become the photo's (rank for rank), fading
#: back to the tile's own over as many again (:func:`_match_tails`).
TAIL_SHARE = 0.02
#: Default band-power rounds (method "auto"). One: a second round, answering the first's errors as three bake
#: regions measure them (on a photo whose parts differ, a sample of a few patches), moved the bakes closer in
#: band power and further in structure (structural distance / floor at 4 places, mean over 13 photos, 1.125
#: with two rounds, 1.112 with one; three rounds further again; docs/fitting.md, "One band round").
AUTO_ITERATIONS = 1
#: The coarse tile holds up to this many cycles per tile, times ``ratio`` (a Gaussian roll-off):
#: at 2 and ratio 4, layer 1 reaches two cycles across the finest tile, the photo's lowest octave.
COARSE_CYCLES = 2.0


def _straightened(exemplar, angle):
    """``exemplar`` turned by ``-angle`` degrees (:func:`cubic_at`: no ringing by the mortar) and cropped to
    the largest square inside it."""
    h, w = exemplar.shape[:2]
    a = math.radians(abs(angle))
    side = int(min(h, w) / (math.cos(a) + math.sin(a))) - 2
    y0, x0 = (h - side) // 2, (w - side) // 2
    # the square's pixels at their places in the photo, turned about its centre (scipy.ndimage.rotate's)
    i, j = np.meshgrid(np.arange(y0, y0 + side) - (h - 1) / 2, np.arange(x0, x0 + side) - (w - 1) / 2,
                       indexing="ij")
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    out = cubic_at(exemplar, (h - 1) / 2 + i * c + j * s, (w - 1) / 2 - i * s + j * c)
    return out.astype(exemplar.dtype)


def _straighten_structure(exemplar, structure, notes, keep_perspective=False):
    """A structured photo in perspective rectified, or one turned a few degrees off its lines straightened.

    Returns ``(exemplar, angle, drift, turn)``: the photo, its structure's
    angle and the largest difference of its halves' angles (left and right,
    top and bottom; degrees, None where the photo is not structured; the
    angle is the rectified photo's where it was rectified), and the rotation
    (degrees) the finest layer is drawn with to show a structure the photo
    holds turned as its design (0 where none). Where the drift is
    over ``PERSPECTIVE_DRIFT`` the photo is in perspective: it is rectified
    (:func:`spectex.fitting._perspective.rectify`, a homography from its
    two line families' vanishing points) and the rectified crop kept where
    its own drift is at most ``PERSPECTIVE_DRIFT`` (its lines now run
    parallel); else the notes say the structure is not kept whole. Where
    ``STRAIGHTEN_MIN < |angle| <= STRAIGHTEN_MAX`` (and no perspective) it
    is straightened (:func:`_straightened`); where ``|angle| > STRAIGHTEN_MAX``
    it is straightened where its lattice holds far better along its lines
    (``DESIGN_HOLD``), and ``turn`` turns it back. The notes say what was
    done.
    ``keep_perspective``: a photo in perspective is left as it is.
    """
    h, w = exemplar.shape[:2]
    if structure < STRUCTURED_PEAK or min(h, w) < 64:
        return exemplar, None, None, 0.0
    angle, coherence = orientation_vote(exemplar)  # (the gradients taken once for both)
    if coherence < MIN_LINE_COHERENCE:
        # no grid of lines (hexagonal scales, whose three directions of edges cancel in the vote): its angle
        # and its halves' are chance, nothing to straighten or rectify (a reptile's skin was turned 1.9
        # degrees, or said to be in perspective, and its lattice no longer met its cells)
        return exemplar, angle, None, 0.0
    drift = _orientation_drift(exemplar)
    if drift > PERSPECTIVE_DRIFT and keep_perspective:
        notes.append(f"kept the photo's perspective (its structure's lines turn by {drift:.1f} degrees across it; "
                     "keep_perspective=True / --keep-perspective)")
    elif drift > PERSPECTIVE_DRIFT:
        # lines that fan out are not made parallel by one turn: the photo is rectified (a homography from
        # its two line families' vanishing points) and kept so where its lines then run parallel
        from ._perspective import rectify

        found = rectify(exemplar)
        after = None if found is None else _orientation_drift(found.image)
        if after is not None and after <= PERSPECTIVE_DRIFT:
            rh, rw = found.image.shape[:2]
            lo, hi = found.scale_range
            notes.append(f"rectified the photo's perspective (its structure's lines turned by {drift:.1f} degrees "
                         f"across it, {after:.1f} after; cropped to {rh} x {rw} px, resampled by {lo:.2f} to "
                         f"{hi:.2f})")
            return found.image, structure_orientation(found.image), drift, 0.0
        notes.append(f"the photo looks to be in perspective (its structure's lines turn by {drift:.1f} degrees "
                     "across it) and could not be rectified: patches cut from its sides meet at breaks, the "
                     "structure is not kept whole; photograph it square-on")
    elif STRAIGHTEN_MIN < abs(angle) <= STRAIGHTEN_MAX:
        # a photo of a wall taken a few degrees off its lines: the structure straightened first, so that
        # its period is one along x and y and the tile's wrap meets itself. The gradients' vote is biased
        # towards the axes (the pixel grid's own edges): measured again on the straightened photo, the
        # rest (2.6 then 0.3 of a 3-degree turn) added, from the original
        angle += structure_orientation(_straightened(exemplar, angle))
        exemplar = _straightened(exemplar, angle)
        h, w = exemplar.shape[:2]
        notes.append(f"turned the photo by {-angle:.1f} degrees to straighten its structure "
                     f"(cropped to {h} x {w} px)")
    elif abs(angle) > STRAIGHTEN_MAX:
        # turned further: the structure's own design (a floor laid diagonally, a wall photographed turned),
        # kept as the photo shows it. Where its lattice holds along its lines, not along the photo's axes,
        # the tile is cut from the photo straightened and the finest layer drawn turned back (``turn``);
        # a design whose lattice runs along the axes (herringbone: bricks at 45 degrees, its repeat along x
        # and y; a square grid at 45 degrees, exactly every 2 cells) is cut as it is
        turned = angle + structure_orientation(_straightened(exemplar, angle))
        straight = _straightened(exemplar, turned)
        if _lattice_hold(straight) >= DESIGN_HOLD * _lattice_hold(exemplar, structure):
            exemplar, angle = straight, turned
            h, w = exemplar.shape[:2]
            notes.append(f"cut the tile from the photo turned by {-angle:.1f} degrees, along its structure's "
                         f"lines (cropped to {h} x {w} px), and drew it turned back: the structure's repeat "
                         "runs along its lines, not along the photo's sides")
            return exemplar, angle, drift, angle
    return exemplar, angle, drift, 0.0


def _lattice_hold(exemplar, structure=None):
    """How well the structure's lattice (:func:`structure_period`) holds across the photo: the share of its
    luma's variance that folding by the periods keeps (``spectex._lattice.lattice_strength_2d``; by line
    profiles, ``lattice_strength``, along one axis only); 0 where the photo shows no structure. An exact
    lattice keeps most of it (floor tiles 0.88), one that drifts off the photo's pixels' lattice little.
    ``structure``: the photo's :func:`structure_peak` where already known."""
    from .._lattice import lattice_strength, lattice_strength_2d
    from ..color import luma

    if (structure_peak(exemplar) if structure is None else structure) < STRUCTURED_PEAK:
        return 0.0
    period = structure_period(exemplar)
    if period == (None, None):
        return 0.0
    level = luma(exemplar, dtype=np.float64)
    return lattice_strength(level, period) if None in period else lattice_strength_2d(level, period)


def _orientation_drift(exemplar):
    """The largest difference (degrees) of :func:`structure_orientation` between the photo's halves
    (left and right, top and bottom)."""
    h, w = exemplar.shape[:2]
    halves = ((exemplar[:, : w // 2], exemplar[:, w // 2:]), (exemplar[: h // 2], exemplar[h // 2:]))
    # modulo 90 degrees: a grid turned 45 degrees reads +45 in one half and -44.9 in the other, one angle
    return max(abs((structure_orientation(a) - structure_orientation(b) + 45.0) % 90.0 - 45.0) for a, b in halves)


def _grout_lines(lines, period):
    """Per line (axis 0), whether it lies in the structure's grout or mortar, or None where that is unclear.

    The lines' mean colours along their principal axis, folded by ``period``
    (lines) into ``round(period)`` phases: the grout is the same colour in
    every period, the cells' interiors average out, so the phases far from
    the profile's median (beyond half its largest deviation, on the side of
    that deviation) are the grout's. None where those phases are more than
    half of them (no thin grout to tell).
    """
    n = lines.shape[0]
    means = lines.reshape(n, -1, lines.shape[-1]).mean(axis=1)
    centred = means - means.mean(axis=0)
    axis = np.linalg.svd(centred, full_matrices=False)[2][0]
    profile = centred @ axis
    bins = max(2, int(round(period)))
    phase = np.floor((np.arange(n) % period) * bins / period).astype(np.int64) % bins
    folded = np.bincount(phase, weights=profile, minlength=bins) / np.maximum(np.bincount(phase, minlength=bins), 1)
    dev = folded - np.median(folded)
    peak = dev[np.argmax(np.abs(dev))]
    grout = dev * np.sign(peak) > 0.5 * abs(peak)
    if grout.mean() > 0.5:
        return None
    return grout[phase]


def _best_cut(lines, span, period=None):
    """Start of the ``span`` lines (axis 0) whose wrap edge shows least: line ``start + span`` (the one
    after the cut) closest to line ``start`` in mean squared difference; with the structure's ``period``
    (lines), among the starts in its grout (:func:`_grout_lines`), so that the wrap edge runs along the grout
    and no brick or floor tile of the tile is made of two of the photo's (a speckled grout can differ more
    across a cut than a smooth brick: that cut splits the brick in two colours)."""
    n = lines.shape[0]
    if span >= n:
        return 0
    costs = np.array([float(np.mean((lines[y] - lines[y + span]) ** 2)) for y in range(n - span)])
    if period is not None:
        grout = _grout_lines(lines, period)
        if grout is not None and grout[: n - span].any():
            costs[~grout[: n - span]] = np.inf
    return int(np.argmin(costs))


def _tile_counts(h, w, period, joints=None):
    """The period tile's side and counts: ``(L, (qy, qx), (ky, kx))`` or None.

    ``L`` texels hold ``kx`` periods of ``qx`` whole texels along x and
    ``ky`` of ``qy`` along y (0 and None where that axis has no period).
    Each texel period is the photo's period ``p`` resampled by
    ``q / p``: along x (y where x has none) within half a texel
    (``q = round(p)``), along the other as the square side allows, within
    ``PERIOD_STRETCH``, whole unless a fractional one stretches less by
    ``PERIOD_FRACTION_COST`` (a tile of ``k`` periods whose texel period is not
    whole would put the snapped offsets, whole texels, up to a texel off per
    period). Among the sides whose source crop fits the photo and that are
    at least 70% of the largest, the least stretch wins.

    ``joints`` (a period along one axis only): the joints of the photo's
    strips (:func:`_photo_strip_joints`); where some strip cannot be cut
    at its own joints (:func:`_strip_segments`) at the side above, a side
    at least ``JOINT_SIDE_SHARE`` of the largest at which every strip can
    is taken (the least stretch among them, the larger when equal).
    """
    py, px = period
    strict = "x" if px is not None else "y"
    found = []
    for side in range(min(h, w) - 1, MIN_SIZE - 1, -1):
        if side % max(1, round(px if strict == "x" else py)):
            continue
        best = []
        for name, p, n in (("y", py, h), ("x", px, w)):
            if p is None:
                best.append((0, None, 1.0))
                continue
            options = []
            for k in range(1, side // 2 + 1):
                if side % k:
                    continue
                q = side // k
                if name == strict and q != round(p):
                    continue
                if k * p <= n - 1 and abs(q / p - 1.0) <= PERIOD_STRETCH:
                    options.append((abs(q / p - 1.0), k, q, q / p))
            if name != strict:
                # the other axis may keep a fractional texel period where whole ones stretch it more
                # than PERIOD_FRACTION_COST further: its snapped offsets are then rounded down to
                # texels, each less than a texel off (not accumulating over periods)
                k = max(1, round(side / p))
                if k * p <= n - 1 and abs(side / k / p - 1.0) <= PERIOD_STRETCH:
                    options.append((abs(side / k / p - 1.0) + PERIOD_FRACTION_COST, k, side / k, side / k / p))
            if not options:
                best = None
                break
            best.append(min(options)[1:])
        if best is not None:
            found.append((side, best))
    if not found:
        return None
    # the least stretch among the sides within 70% of the largest (the larger when equal)
    largest = found[0][0]
    pick = _joint_side(found, min((f for f in found if f[0] >= 0.7 * largest), key=_stretch_order), joints)
    side, ((ky, qy, sy), (kx, qx, sx)) = pick
    return side, (qy, qx), (ky, kx), (sy, sx)


def _stretch_order(found):
    """The order of :func:`_tile_counts`'s sides: the least stretch (to a thousandth), then the larger side."""
    side, ((_, _, sy), (_, _, sx)) = found
    return round(max(abs(sy - 1.0), abs(sx - 1.0)), 3), -side


def _joint_side(found, pick, joints):
    """:func:`_tile_counts`'s choice for a period along one axis only: ``pick``, or where some strip cannot be
    cut at its own joints (``joints``, per strip) at its side, the side of ``found`` (at least
    ``JOINT_SIDE_SHARE`` of the largest) at which every strip can, first by :func:`_stretch_order`. A wall 3
    bricks across: 2.5 bricks a course leave a half brick at every wrap edge, 2 bricks none. ``pick`` where
    ``joints`` is None or empty."""

    def whole(f):
        return all(_strip_segments(j, f[0]) is not None for j in joints)

    if not joints or whole(pick):
        return pick
    every = [f for f in found if f[0] >= JOINT_SIDE_SHARE * found[0][0] and whole(f)]
    return min(every, key=_stretch_order) if every else pick


def _period_tile(exemplar, period, words=None):
    """A square tile of whole periods, each a whole number of texels, cut where its wrap edges show least; or None.

    ``period = (py, px)`` in pixels (not necessarily whole), either may be
    None (no period along that axis). The side and counts are
    :func:`_tile_counts`'s; the crop of ``ky py`` by ``kx px`` photo
    pixels (``L`` where an axis has no period), placed along each axis where
    its wrap edge differs least (:func:`_best_cut`), is resampled (cubic,
    wrapping: the crop is periodic) to ``L x L`` texels. Returns
    ``(tile (L, L, 3) float64, L, (ky, kx), (qy, qx), scale)``: ``scale``
    the texels per photo pixel along x (y where x has no period; the other
    axis is stretched by at most ``PERIOD_STRETCH`` more). A photo with a
    period along one axis only has each strip cut at its own joints
    instead of one straight crop along the other (:func:`_strip_tile`);
    a list ``words`` gets the phrase that says how.
    """

    h, w = exemplar.shape[:2]
    if period[0] is None and period[1] is None:
        return None
    one_axis = (period[0] is None) != (period[1] is None)
    found = _tile_counts(h, w, period, _photo_strip_joints(exemplar, period) if one_axis else None)
    if found is None:
        return None
    side, (qy, qx), (ky, kx), (sy, sx) = found
    spans = [ky * period[0] if ky else float(side), kx * period[1] if kx else float(side)]
    iy, ix = int(math.ceil(spans[0])), int(math.ceil(spans[1]))
    x0 = _best_cut(np.moveaxis(exemplar, 1, 0), int(round(spans[1])), period[1])
    x0 = min(x0, w - ix - 1)
    y0 = _best_cut(exemplar[:, x0:x0 + ix], int(round(spans[0])), period[0])
    y0 = min(y0, h - iy - 1)
    if (period[0] is None) != (period[1] is None):
        # a period along one axis only (columns or courses of bricks of random lengths): each strip between
        # the grout lines cut at its own joints, where the straight cut along the other axis crossed bricks
        found = _strip_tile(exemplar, period, side, (y0, x0), spans)
        if found is not None:
            tile, (one, two, strips, most) = found
            if words is not None:
                kind = "columns" if period[1] is not None else "courses"
                words.append(f"{one + two} of its {strips} {kind} cut at their own joints ({one} at one stretch, "
                             f"{two} at two; stretched by at most {100 * most:.0f}%)")
            return _joints_at_wrap(tile, (kx, ky)), side, (ky, kx), (qy, qx), float(sx if period[1] is not None
                                                                                   else sy)
    crop = exemplar[y0:y0 + iy + 1, x0:x0 + ix + 1].astype(np.float64)
    # texel centres (i + 0.5) of the L-texel tile at photo places (i + 0.5) span / L - 0.5 of the crop
    yy = (np.arange(side) + 0.5) * (spans[0] / side) - 0.5
    xx = (np.arange(side) + 0.5) * (spans[1] / side) - 0.5
    gy, gx = np.meshgrid(yy, xx, indexing="ij")
    tile = _whole_edge_cells(cubic_at(crop, gy, gx), exemplar, (kx, ky), (y0, x0), spans)
    if (period[0] is None) != (period[1] is None):
        tile = _joints_at_wrap(tile, (kx, ky))
    return tile, side, (ky, kx), (qy, qx), float(sx if period[1] is not None else sy)


def _strip_layout(photo, period):
    """The strips of a photo with a period along x only (:func:`_strip_cuts`): ``(grout, level, centre, width,
    strip_of)`` or None where no grout is found.

    ``grout`` (w,) bool: the columns of the grout's colour class (:func:`_grout_lines`); ``level`` (h, w): how
    much each pixel's colour is the grout's (0 at the bricks' mean colour, 1 at the grout's); ``centre``: the
    grout lines' centre's phase (pixels) in the period; ``width``: the most lines a joint spans; ``strip_of``
    (w,): each column's strip (between the grout lines' centres).
    """
    w = photo.shape[1]
    photo = photo.astype(np.float64)
    grout = _grout_lines(np.moveaxis(photo, 1, 0), period)
    if grout is None or grout.all() or not grout.any():
        return None
    columns = photo.mean(axis=0)
    toward = columns[grout].mean(axis=0) - columns[~grout].mean(axis=0)
    contrast = float(toward @ toward)
    if contrast < 1e-6:
        return None
    # how much each pixel's colour is the grout's: 0 at the bricks' mean colour, 1 at the grout's
    level = (photo - columns[~grout].mean(axis=0)) @ toward / contrast
    # the strips' boundaries: the centres of the grout lines (the circular mean of the grout's phases)
    phases = np.arange(w) % period
    turn = np.exp(2j * np.pi * phases[grout] / period).mean()
    centre = (np.angle(turn) / (2.0 * np.pi) * period) % period
    # thin: a joint is at most twice as wide as the grout lines between the strips
    width = max(2, int(math.ceil(2.0 * grout.sum() / (w / period))))
    strip_of = np.floor((np.arange(w) - centre) / period).astype(np.int64)
    return grout, level, centre, width, strip_of


def _photo_strip_joints(exemplar, period):
    """The joints of every whole strip of a photo with a period along one axis only (:func:`_strip_layout`,
    :func:`_strip_joints`): a list of lists of positions along the strips, or None where no grout is found.
    A period along y (courses) is the same turned."""
    along_y = period[1] is None
    photo = np.swapaxes(exemplar, 0, 1) if along_y else exemplar
    p = period[0] if along_y else period[1]
    layout = _strip_layout(photo, p)
    if layout is None:
        return None
    grout, level, _, width, strip_of = layout
    out = []
    for s in np.unique(strip_of)[1:-1]:  # the strips the photo's sides do not cut
        inside = (strip_of == s) & ~grout
        if inside.sum() >= 2:
            out.append(_strip_joints(level[:, inside].mean(axis=1), width))
    return out


def _strip_cuts(photo, period, x0, span_x, y0, side):
    """Per tile column, the photo row each texel row reads: every strip cut at its own joints; or None.

    ``photo`` (h, w, 3) has its period ``period`` (pixels) along x only:
    strips (columns of bricks) between grout lines, their joints (mortar
    across the strip) at heights of their own. The tile's ``side`` texels
    across cover ``span_x`` photo pixels from ``x0`` (the cut along x, in
    the grout); down, the straight cut reads ``side`` rows from ``y0``. The
    grout is the colour class :func:`_grout_lines` finds across the
    strips; each strip (its interior, between the centres of its grout
    lines) has a profile down its length (how much each row's colour is the
    grout's, :func:`_strip_joints`) whose thin runs are its joints. Per
    strip, the stretch of the photo from one joint's centre ``a`` to
    another's whose length ``L`` is closest to ``side`` (within
    ``JOINT_STRETCH``; else two such stretches in turn,
    :func:`_strip_segments`) is read as a period of the strip, resampled
    along its length by ``side / L``: texel row ``i`` reads row
    ``a + (v - a) mod L`` with ``v = y0 + (i + 0.5) L / side - 0.5`` (the
    strip where the straight cut had it, the rows past joint ``b`` read from
    joint ``a`` on). So the tile's wrap edge runs through the bricks whole
    (the strip continues across it) and each strip's cut lies in its mortar,
    at the photo's own joint there: the cuts of neighbouring strips are
    staggered as the photo's joints are, and every brick of the tile is one
    of the photo's. A strip with no such joints reads the straight cut's
    rows. The strips meet at the centres of the grout lines between them,
    where joints at different heights are what a wall has.

    Returns ``(rows (side, side) float64, (one, two, strips, most))``:
    ``rows[i, j]`` the photo row texel ``(i, j)`` reads; the strips cut at
    one stretch and at two, the tile's strips and the most stretch; None
    where no strip has such joints (or no grout is found).
    """
    layout = _strip_layout(photo, period)
    if layout is None:
        return None
    grout, level, centre, width, strip_of = layout
    # the tile's columns in the photo, and their strips
    xs = x0 + (np.arange(side) + 0.5) * (span_x / side) - 0.5
    tile_strip = np.floor((xs - centre) / period).astype(np.int64)
    first, last = int(tile_strip[0]), int(tile_strip[-1])
    if last > first:
        # a strip the tile's wrap edge splits: its sliver (under half a strip, grout) reads as the strip it
        # continues across the wrap edge, the one at the tile's other end
        if np.sum(tile_strip == first) < 0.5 * period * side / span_x:
            tile_strip[tile_strip == first] = last
        elif np.sum(tile_strip == last) < 0.5 * period * side / span_x:
            tile_strip[tile_strip == last] = first
    v = y0 + (np.arange(side) + 0.5) - 0.5  # the straight cut's rows (one texel a pixel down)
    rows = np.repeat(v[:, None], side, axis=1)
    counts = [0, 0]
    most = 0.0
    for s in np.unique(tile_strip):
        inside = (strip_of == s) & ~grout
        if inside.sum() < 2:
            continue
        segments = _strip_segments(_strip_joints(level[:, inside].mean(axis=1), width), side)
        if segments is None:
            continue
        starts = np.array([a for a, _ in segments])
        lengths = np.array([b - a for a, b in segments])
        before = np.concatenate([[0.0], np.cumsum(lengths)])
        total = before[-1]
        along = y0 + (np.arange(side) + 0.5) * (total / side) - 0.5
        u = np.mod(along - starts[0], total)
        k = np.minimum(np.searchsorted(before, u, side="right") - 1, len(segments) - 1)
        rows[:, tile_strip == s] = (starts[k] + u - before[k])[:, None]
        counts[len(segments) - 1] += 1
        most = max(most, abs(side / total - 1.0))
    if sum(counts) == 0:
        return None
    return rows, (counts[0], counts[1], len(np.unique(tile_strip)), most)


#: A course's wrap edge joins two boards where the colour step across it is over this many times the
#: course's median step between neighbouring lines (and over ``WRAP_STEP_FLOOR``).
WRAP_STEP = 3.0
WRAP_STEP_FLOOR = 0.01


def _joints_at_wrap(tile, snap):
    """A tile with a period along one axis only (``snap`` ``(0, ny)``: courses along x; ``(nx, 0)``: columns
    along y) with a joint at its wrap edge in every course that joins two boards there.

    Where a course was read straight across the photo (not cut at its own joints, :func:`_strip_tile`),
    its wrap edge joins the end of one board to the middle of another: two tones meet without a joint, in
    every patch, and the sampler, which changes patch along a course at joints only
    (``shading.stochastic.course_vertex``), would keep them. Such a course (a step of its mean colour across
    the edge, the RMS over the channels, over ``WRAP_STEP`` times its median step between neighbouring lines) gets
    one of its own joints (the
    grout between two of its boards, ``shading._cells.course_joints``) over the edge, centred on it: the
    two boards now end at a joint, as boards do. A course whose joint already lies at the edge, or
    without joints, is left alone. Unchanged where no courses are found.
    """
    from ..shading.resources import course_joints

    found = course_joints(tile, snap)
    if found is None:
        return tile
    courses, _, runs = found
    along_x = int(snap[0]) == 0
    out = np.array(tile, copy=True)
    view = out if along_x else out.swapaxes(0, 1)
    w = view.shape[1]
    for c, joints in enumerate(runs):
        lines = courses == c
        if not joints or not lines.any():
            continue
        if any(a <= 2 or a + b >= w - 2 for a, b in joints):  # a joint runs over (or next to) the edge
            continue
        # the course's mean colour per column, its steps the RMS over the channels: two boards of one brightness
        # and another hue (an orange brick beside a brown one) differ in colour, not in the channels' mean (a
        # grey photo's steps are the same either way)
        cols = view[lines][:, :, :3].mean(axis=0)
        steps = np.sqrt(np.mean(np.diff(cols, axis=0) ** 2, axis=1))
        edge = float(np.sqrt(np.mean((cols[0] - cols[-1]) ** 2)))
        if edge <= max(WRAP_STEP * float(np.median(steps)), WRAP_STEP_FLOOR):
            continue
        a, width = max(joints, key=lambda j: j[1])
        src = (a + np.arange(width)) % w
        dst = (np.arange(width) - width // 2) % w
        block = view[lines]
        block[:, dst] = block[:, src]
        view[lines] = block
    return out


def _strip_tile(exemplar, period, side, origin, spans):
    """The period tile of a photo with a period along one axis only, its strips cut at their own joints
    (:func:`_strip_cuts`), and :func:`_strip_cuts`'s counts; or None where no strip has joints to cut at.
    ``origin = (y0, x0)`` and ``spans`` are :func:`_period_tile`'s; a period along y (courses) is the same
    turned."""

    along_y = period[1] is None
    photo = np.swapaxes(exemplar, 0, 1) if along_y else exemplar
    p = period[0] if along_y else period[1]
    y0, x0 = origin[::-1] if along_y else origin
    span_x = spans[0] if along_y else spans[1]
    found = _strip_cuts(photo, p, x0, span_x, y0, side)
    if found is None:
        return None
    rows, counts = found
    xs = x0 + (np.arange(side) + 0.5) * (span_x / side) - 0.5
    cols = np.broadcast_to(xs[None, :], rows.shape)
    tile = cubic_at(photo, rows, cols)
    return (np.swapaxes(tile, 0, 1) if along_y else tile), counts


def _whole_edge_cells(tile, exemplar, snap, origin, spans):
    """The period tile with its cells across the wrap edges made whole from the photo.

    A straight cut runs along the grout only where the grout is straight
    (a grid of floor tiles); across hexagons or staggered cells it crosses
    cells, and a cell across the tile's wrap edge is then made of two of the
    photo's cells (two colours, split by a straight line, in every patch).
    Each texel whose cell's centre (:func:`spectex.shading._cells.cell_map`)
    lies in a neighbouring copy of the tile is read instead from the photo
    where that copy continues the crop (cubic), so the cell is the one
    photo cell its larger part is; texels whose place falls off the photo
    keep their value. Unchanged where the tile has no cell map.
    """

    from ..shading.resources import cell_map

    side = tile.shape[0]
    if min(int(snap[0]), int(snap[1])) == 0:
        return tile  # (a period along one axis: courses, not cells; _joints_at_wrap)
    cells = cell_map(tile, snap)
    if cells is None:
        return tile
    h, w = exemplar.shape[:2]
    i, j = np.meshgrid(np.arange(side, dtype=np.float64), np.arange(side, dtype=np.float64), indexing="ij")
    copy_y = np.floor((i + 0.5 + cells[:, :, 1]) / side)
    copy_x = np.floor((j + 0.5 + cells[:, :, 0]) / side)
    py = origin[0] + (i - side * copy_y + 0.5) * (spans[0] / side) - 0.5
    px = origin[1] + (j - side * copy_x + 0.5) * (spans[1] / side) - 0.5
    move = ((copy_y != 0) | (copy_x != 0)) & (py >= 0) & (py <= h - 1) & (px >= 0) & (px <= w - 1)
    if not move.any():
        return tile
    out = tile.copy()
    out[move] = cubic_at(exemplar, py[move], px[move])
    return out


def _coarse_tile(exemplar, n, ratio, slope_db, rng):
    """The coarse layers' tile: random-phase noise continuing the spectrum, on the photo's main colour axis.

    Spectrum: band power changing by ``slope_db`` per octave towards coarser
    scales (2-D power ``u^(a - 2)``, ``a = -slope_db / 3.01``), times a
    Gaussian roll-off at ``COARSE_CYCLES * ratio`` cycles per tile. Colour:
    the photo's low-passed colours (a Gaussian of 1/16 of its side) give a
    mean and a main axis (the leading eigenvector of their covariance);
    the tile is ``mean + axis * s * N`` with ``N`` the unit-variance noise
    and ``s`` the low-passed colours' spread along the axis. Returns the
    mean, the axis times ``s`` and ``N``, so the fit can scale ``N``.
    """
    from scipy import ndimage

    h, w = exemplar.shape[:2]
    sigma = max(2.0, min(h, w) / 16.0)
    # the low-pass on the photo averaged in blocks of a quarter of sigma (the same colours to within
    # the block mean's own blur, 16 times fewer pixels: 0.3 s of a 3 s fit on a 512 x 512 photo)
    k = max(1, int(sigma // 4))
    small = exemplar[: h // k * k, : w // k * k].astype(np.float64).reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
    low = np.stack([ndimage.gaussian_filter(small[:, :, c], sigma / k, mode="reflect")
                    for c in range(3)], axis=2).reshape(-1, 3)
    mean = exemplar.reshape(-1, 3).astype(np.float64).mean(axis=0)
    cov = np.cov((low - low.mean(axis=0)).T, bias=True)
    values, vectors = np.linalg.eigh(cov)
    axis = vectors[:, -1]
    if axis[np.argmax(np.abs(axis))] < 0:
        axis = -axis
    spread = math.sqrt(max(float(values[-1]), 1e-8))
    a = -slope_db / (10.0 * math.log10(2.0))
    fy = np.fft.fftfreq(n)[:, None] * n
    fx = np.fft.rfftfreq(n)[None, :] * n
    u = np.hypot(fy, fx)
    u[0, 0] = 1.0
    amp = u ** ((a - 2.0) / 2.0) * np.exp(-(u / (COARSE_CYCLES * ratio)) ** 2)
    amp[0, 0] = 0.0
    white = rng.standard_normal((n, n))
    noise = np.fft.irfft2(np.fft.rfft2(white) * amp, s=(n, n))
    noise /= max(float(noise.std()), 1e-12)
    return mean, axis * spread, noise


def _even_blotches(problem, colour, alpha, exemplar, n_bands):
    """The tile's two coarsest bands lowered so that a bake over twice the photo's side holds no more
    contrast at the photo's scale (:func:`spectex.metrics.lighting_blotches`' low-passed luma) than the
    photo: the finest layer's patches, each a different piece of the tile, set pieces of its large-scale
    content side by side, and that adds to the coarse layers' own. Returns the colours and the gain (dB,
    0 or less). The alpha blend's veil took a tenth off this contrast along with the detail's, and the
    band rounds won the detail back, not this (paving: 12% over the photo, blotches 0.014 at its place)."""
    from .._lighting import BLOTCH_SIGMA, _low_contrast
    from ..color import luma
    from ..texture import SpectralTexture

    h, w = exemplar.shape[:2]
    sigma = BLOTCH_SIGMA * max(h, w)
    shape = (min(2 * h, 2048), min(2 * w, 2048))
    if min(shape) < 4 * sigma:
        return colour, 0.0
    full = problem.texture(colour, alpha)
    fine = SpectralTexture(full.tiles, full.layers[:1])
    own = _low_contrast(luma(exemplar, dtype=np.float64), sigma)
    seen, alone = (_low_contrast(luma(bake(t, shape, pixel_size=problem.p), dtype=np.float64), sigma)
                   for t in (full, fine))
    if seen <= own or alone <= 0.0:
        return colour, 0.0
    # the coarse layers' share of the contrast stays; the finest layer's is scaled to leave the photo's
    coarse = max(seen * seen - alone * alone, 0.0)
    factor = max(math.sqrt(max(own * own - coarse, 0.0)), 0.5 * alone) / alone
    gain = 20.0 * math.log10(factor)
    gains = np.zeros(n_bands)
    gains[-2:] = gain
    return _shape_spectrum(colour, gains), gain


def _overlay_tile(deviation, reach, room):
    """The coarse tile's colours for the overlay blend: ``1/2 + deviation / (2 room)`` per channel, the
    deviation held to ``+-reach`` (symmetric, so the modulation averages 0)."""
    return 0.5 + 0.5 * np.clip(np.clip(deviation, -reach, reach) / room, -1.0, 1.0)


def _match_tails(colour, exemplar, share=TAIL_SHARE, photo_clipped=None):
    """The tile's extremes made the photo's: per channel, the tile's values of the lowest and highest
    ``share`` of its ranks become the photo's values of the same ranks, fading back to the tile's own
    over the next ``share``; the middle is the tile's. Monotone (the tile's order is kept) and inside
    the photo's range: where the band rounds sharpened the tile past the photo's black or white, its
    extremes spread over the photo's own darkest and lightest values instead of piling at the limit
    (a clip put 13% of the deep-field tile at 0, which the alpha blend's veil hid; the photo has 0.8%).

    Where that would put more of a channel's values at 0 or 1 (within half an 8-bit step) than
    ``photo_clipped[c]`` (the photo's own share, before its lighting was evened) plus ``CLIP_ROOM``,
    the channel is folded instead (:func:`_fold_range`): the evening of a bright photo's lighting
    clips its highlights at its white (tissue: 1.8% of red at 1, the photo 0.01%), and the tile's
    tail matched to that would keep the pile.
    """
    from ..metrics import clipped_fraction

    h, w = colour.shape[:2]
    u = (np.arange(h * w) + 0.5) / (h * w)
    weight = np.clip(np.maximum(2.0 - u / share, 2.0 - (1.0 - u) / share), 0.0, 1.0)
    photo = exemplar.reshape(-1, 3).astype(np.float64)
    ranks = (np.arange(photo.shape[0]) + 0.5) / photo.shape[0]
    out = np.empty(colour.shape, dtype=np.float64)
    for c in range(3):
        v = colour[:, :, c].astype(np.float64).ravel()
        order = np.argsort(v, kind="stable")
        target = np.interp(u, ranks, np.sort(photo[:, c]))
        values = np.maximum.accumulate(weight * target + (1.0 - weight) * v[order])
        flat = np.empty(h * w)
        flat[order] = np.clip(values, target[0], target[-1])
        out[:, :, c] = flat.reshape(h, w)
        if photo_clipped is not None and clipped_fraction(out[:, :, c]) > photo_clipped[c] + CLIP_ROOM:
            out[:, :, c] = _fold_range(colour[:, :, c], photo[:, c])
    return out


def _fold_range(values, photo, share=TAIL_SHARE / 2):
    """``values`` (one channel) inside the ``photo``'s range: below the photo's quantile ``share`` (above
    ``1 - share``) the values are moved linearly so that their extreme meets the photo's, where they pass
    it; the rest as they are."""
    v = values.astype(np.float64)
    p0, p1 = float(photo.min()), float(photo.max())
    q0, q1 = np.quantile(photo, [share, 1.0 - share])
    out = v.copy()
    v0, v1 = float(v.min()), float(v.max())
    if v0 < p0:
        low = v < q0
        out[low] = p0 + (v[low] - v0) * (q0 - p0) / max(q0 - v0, 1e-12)
    if v1 > p1:
        high = v > q1
        out[high] = p1 - (v1 - v[high]) * (p1 - q1) / max(v1 - q1, 1e-12)
    return np.clip(out, p0, p1)


def _clip_guard(problem, colour, alpha, exemplar, layer_list, tile_px, ratio):
    """The coarse layers' opacities halved while the texture's bakes (the exemplar's place and every
    far one) clip more of their values than the photo by over ``CLIP_ROOM`` (at most
    ``CLIP_HALVINGS`` times); returns the layers and the depth kept (1: as the fit made them)."""
    import dataclasses

    from ..metrics import clipped_fraction
    from ._core import _FAR

    problem.set_regions(len(_FAR) + 1, tile_px=tile_px, ratio=ratio)
    own = clipped_fraction(exemplar)
    depth = 1.0
    for halvings in range(CLIP_HALVINGS + 1):
        bakes = problem.bakes(colour, alpha, extra=False)
        if halvings == CLIP_HALVINGS or float(np.mean([clipped_fraction(b) for b in bakes])) <= own + CLIP_ROOM:
            break
        depth *= 0.5
        layer_list = [layer_list[0]] + [dataclasses.replace(lay, opacity=round(lay.opacity * 0.5, 6))
                                        for lay in layer_list[1:]]
        problem.layers = layer_list
    return layer_list, depth


def _board_length(tile, snap, texel_scale):
    """The median length (photo pixels) of the boards or bricks of a period tile with a period along one axis
    only (``snap`` with one 0; the units between its courses' joints, ``shading.resources.course_joints``), or
    None (no courses or joints found)."""
    from ..shading.resources import course_joints

    if min(int(snap[0]), int(snap[1])) != 0 or max(int(snap[0]), int(snap[1])) == 0:
        return None
    found = course_joints(tile, snap)
    if found is None:
        return None
    side = tile.shape[1] if int(snap[0]) == 0 else tile.shape[0]
    lengths = [np.diff([a for a, _ in joints] + [joints[0][0] + side]) for joints in found[2] if joints]
    if not lengths:
        return None
    return float(np.median(np.concatenate(lengths))) / texel_scale


def _trial(exemplar, pixel_size, candidates, patch, period, along=None, continuity=False, lines=None):
    """The finest layer alone, each way, measured: ``{label: {"structure": ratio, "repeat": peak}}``.

    ``candidates``: ``(label, tiling, tile, snap, scale, lattice)``, ``scale`` the tile's texels per
    photo pixel, ``lattice`` the structure's period in the bake (photo pixels; None: ``period``). ``structure``:
    structural distance / floor (:func:`spectex.metrics.structural_distance`)
    of a bake of the photo's size (at most :data:`TRIAL_SIDE`, or
    :data:`TRIAL_PERIODS` of the structure's periods where that is more) at its
    pixel size, against the photo's central crop of that size (4 windows each; ``along``: the structure's
    scale along an axis without a period, its boards' length in pixels, counted as a period). ``repeat``:
    :func:`spectex.metrics.repeat_peak` with the structure's lattice removed
    (``period``, pixels; the content's repeat beyond the structure's own) of
    a 512 x 512 bake at twice the pixel size (at least two tiles across). ``breaks``, ``splits``: the
    structure's lines kinked (:func:`spectex.metrics.line_breaks`) and its cells split
    (:func:`spectex.metrics.cell_splits`), each against the photo's. ``continuity`` (with ``continuity``,
    boards side by side without joints): :func:`spectex.metrics.line_continuity` of the far bake against
    the photo, both reduced 2 x 2 (a bake of the photo's size holds too few patches); 1 otherwise. ``lines``:
    the axis of that continuity where ``period`` does not say it (a wall of courses of their own heights).
    """
    from ..metrics import (
        cell_splits,
        line_breaks,
        line_continuity,
        lines_axis,
        reference_statistics,
        repeat_peak,
        structural_distance,
    )
    from ..texture import Layer, SpectralTexture

    h, w = exemplar.shape[:2]
    longest = max([p for p in period if p is not None] + ([along] if along else []))
    m = min(h, w, max(TRIAL_SIDE, int(math.ceil(TRIAL_PERIODS * longest))))
    y0, x0 = (h - m) // 2, (w - m) // 2
    reference = exemplar[y0:y0 + m, x0:x0 + m]
    prepared = reference_statistics(reference, max_windows=4)
    cells = cell_splits(reference, reference, period=period) is not None  # the photo shows separate cells
    # with ``continuity``, a structure along one axis only whose lines run along the other (boards side by
    # side without joints: lines down the columns where the period is along x) is judged by them too
    if lines is None:
        lines = lines_axis(period) if continuity else None
    # (the lines' continuity is read on the far bake, which holds several patches, against the photo at its
    # pixel size: both reduced 2 x 2)
    halved = None if lines is None else box_halved(exemplar)
    out = {}
    for label, tiling, tile, snap, scale, lattice in candidates:
        half = tuple(None if p is None else p / 2.0 for p in (lattice or period))
        rgba = np.ones(tile.shape[:2] + (4,), dtype=np.float32)
        rgba[:, :, :3] = np.clip(tile, 0.0, 1.0)
        layer = Layer(size=tile.shape[0] * pixel_size / scale, tiling=tiling, patch=patch, snap=snap)
        texture = SpectralTexture(rgba, [layer])
        baked = bake(texture, (m, m), pixel_size=pixel_size)
        far = bake(texture, (TRIAL_FAR, TRIAL_FAR), pixel_size=2.0 * pixel_size)
        out[label] = {"structure": structural_distance(baked, reference, prepared=prepared, max_windows=4).ratio,
                      "repeat": repeat_peak(far, period=half),
                      "breaks": line_breaks(baked, reference, window=BREAK_WINDOW).ratio if m >= 3 * BREAK_WINDOW
                      else 1.0,
                      "splits": _splits(cell_splits(baked, reference, period=period), cells,
                                        coursed=label == "coursed"),
                      "continuity": 1.0 if lines is None else line_continuity(far, halved, axis=lines).ratio}
    return out


def _along_share(exemplar, period):
    """The share of the luma's gradient energy (Sobel) along the lines of a structure along one axis (the
    boards' ends, bricks' joints), the rest across them (their edges); 1 for a structure along both axes."""
    from scipy import ndimage

    from ..color import luma
    from ..metrics import lines_axis

    axis = lines_axis(period)
    if axis is None:
        return 1.0
    lum = luma(exemplar, dtype=np.float64)
    gx, gy = ndimage.sobel(lum, 1), ndimage.sobel(lum, 0)
    along = gy if axis == 0 else gx  # lines down the columns (axis 0): the gradient along them is along y
    return float(np.sum(along * along) / max(float(np.sum(gx * gx + gy * gy)), 1e-12))


def _courses_unmapped(tile, snap):
    """Whether a tile snapped along one axis has no course map (:func:`spectex.shading.resources.cell_maps`, the
    one its snapped layer's bake reads: shared with it)."""
    from ..shading.resources import cell_maps
    from ..texture import Layer, SpectralTexture

    rgba = np.ones(tile.shape[:2] + (4,), dtype=np.float32)
    rgba[:, :, :3] = np.clip(tile, 0.0, 1.0)
    return cell_maps(SpectralTexture(rgba, [Layer(size=1.0, tiling="stochastic", snap=snap)]))[0] is None


def _aligned_tile(exemplar, period):
    """The aligned way's tile (:func:`_structured_way`): ``(tile, side)``, a square crop of the photo at its own
    pixels holding the most whole periods across its lines that fit (``side`` the nearest whole number of
    pixels: the wrap across is the structure's, within half a pixel), placed across where its wrap edge shows
    least (:func:`_best_cut`), along them about the centre, made seamless (:func:`spectex.tiles.make_seamless`:
    along the lines the photo does not repeat). Nothing is resampled: a patch is never shifted across, so its
    periods need not be whole texels, and the boards keep the photo's sharpness (the period tile, resampled to
    whole-texel periods, read 1.15 times further from the photo than this by the structural distance). None
    where fewer than two periods fit."""
    from ..tiles import make_seamless

    h, w = exemplar.shape[:2]
    across = 1 if period[1] is not None else 0  # the axis the period runs along (x for boards side by side)
    p = period[across]
    count = int(min(h, w) // p)
    side = int(round(count * p))
    if count < 2 or side > min(h, w) or side < MIN_SIZE:
        return None
    lines = np.moveaxis(exemplar, 1, 0) if across == 1 else exemplar
    start = min(_best_cut(lines, side, p), lines.shape[0] - side)
    centre = (exemplar.shape[1 - across] - side) // 2
    y0, x0 = (centre, start) if across == 1 else (start, centre)
    crop = exemplar[y0:y0 + side, x0:x0 + side]
    return make_seamless(crop, shape=(side, side))[:, :, :3].astype(np.float64), side


def _aligned_snap(snap):
    """The snap of a structure along one axis drawn aligned: whole tiles across its lines (the tile's own
    places), whole texels along them."""
    return tuple(1 if count else 0 for count in snap)


def _splits(found, cells, coursed=False):
    """:func:`spectex.metrics.cell_splits`' ratio of a trial bake: 1 where the photo shows no separate cells
    (``cells`` False), infinite where it does and the bake does not (a jumble without the photo's lattice).
    A wall drawn by its courses of their own heights (``coursed``) shows no lattice at the photo's period by
    design, its bands of courses starting at other heights (``shading.stochastic.course_band_shift``), and
    changes patch at joints only: 1 where its cells are not found."""
    if not cells or (coursed and found is None):
        return 1.0
    return math.inf if found is None else float(found.ratio)


def _choose(trial, own_repeat):
    """The finest layer's way from :func:`_trial`: the closest structure among the ways that do not
    repeat (content repeat at most ``max(REPEAT_LIMIT, own_repeat + REPEAT_MARGIN)``), do not break
    the structure's lines (kinks at most ``BREAK_LIMIT`` times the photo's), do not move them (a structure
    along one axis: continuity at least ``CONTINUITY_LIMIT`` of the photo's) and do not split its cells
    (at most ``SPLIT_LIMIT`` times the photo's); without that, those that neither break nor move them,
    then those that do not break them and split no cells, then those that do not break them, then those
    that do not repeat, all of them if none; the snapped one kept while within ``TRIAL_MARGIN`` of it
    (structure kept when in doubt). The aligned way (boards) is a candidate only within ``TRIAL_MARGIN`` of
    the closer of the snapped and stochastic ways."""
    limit = max(REPEAT_LIMIT, own_repeat + REPEAT_MARGIN)
    others = [trial[k]["structure"] for k in ("snapped", "stochastic") if k in trial]
    if "aligned" in trial and others and trial["aligned"]["structure"] > (1.0 + TRIAL_MARGIN) * min(others):
        # the aligned way only where it draws the photo about as closely as a way that moves its patches
        # across: a game's boards with thin butt joints (structure 1.79 aligned, 1.09-1.15 the others) lost
        # their joints and showed the tile's columns as stripes repeating once per tile across
        trial = {k: v for k, v in trial.items() if k != "aligned"}

    def keeps(v, *tests):
        return v["repeat"] <= limit and all(
            {"breaks": v.get("breaks", 1.0) <= BREAK_LIMIT, "splits": v.get("splits", 1.0) <= SPLIT_LIMIT,
             "continuity": v.get("continuity", 1.0) >= CONTINUITY_LIMIT}[t] for t in tests)

    allowed = []
    for tests in (("breaks", "continuity", "splits"), ("breaks", "continuity"), ("breaks", "splits"), ("breaks",),
                  ()):
        allowed = allowed or [k for k, v in trial.items() if keeps(v, *tests)]
    allowed = allowed or list(trial)
    best = min(allowed, key=lambda k: trial[k]["structure"])
    if "snapped" in allowed and trial["snapped"]["structure"] <= (1.0 + TRIAL_MARGIN) * trial[best]["structure"]:
        return "snapped"
    return best


class _TwoTiles(_Problem):
    """The fit's problem with the coarse layers on their own tile (tile 1)."""

    coarse_tile = None

    def texture(self, colour, alpha):
        from ..texture import SpectralTexture

        rgba = np.empty(colour.shape[:2] + (4,), dtype=np.float32)
        rgba[:, :, :3] = np.clip(colour, 0.0, 1.0)
        rgba[:, :, 3] = alpha
        return SpectralTexture([rgba, self.coarse_tile], self.layers)


def _resolve_scale(pixel_size, photo_size, full_side, notes, factor=1.0):
    """The fit's pixel size (metres per pixel of the exemplar, ``factor`` photo pixels) and the report's
    words for it; an assumed scale is noted in ``notes``."""
    if pixel_size is not None and photo_size is not None:
        raise ValueError(f"give pixel_size or photo_size, not both (got {pixel_size!r} and {photo_size!r})")
    if pixel_size is not None:
        pixel_size = check_float("pixel_size", pixel_size, minimum=0.0, exclusive_minimum=True)
        scale = f"pixel size {pixel_size:g} m (given)"
    else:
        assumed = photo_size is None
        photo_size = DEFAULT_PHOTO_SIZE if assumed else check_float("photo_size", photo_size, minimum=0.0,
                                                                    exclusive_minimum=True)
        pixel_size = photo_size / full_side
        scale = (f"photo {photo_size:g} m across its {full_side}-pixel side, pixel size {pixel_size:.4g} m "
                 + ("(assumed: a photo of ground taken standing; pass photo_size= or pixel_size=)" if assumed
                    else "(given)"))
        if assumed:
            notes.append(f"assumed the photo is {photo_size:g} m across (pixel size {pixel_size:.4g} m); "
                         "say it with photo_size= / --photo-size")
    if factor != 1.0:  # the exemplar's pixel is `factor` photo pixels
        pixel_size *= factor
        scale += f"; the photo resampled by 1/{factor:.4g}: {pixel_size:.4g} m per pixel of the tile's photo"
    return pixel_size, scale


def _even_out_lighting(exemplar, notes):
    """:func:`even_lighting`, said in ``notes``: ``(photo, {"rms", "low", "high"})``, or None where nothing was
    done."""
    flat, light = even_lighting(exemplar)
    if light is None:
        return None
    notes.append(f"evened out the photo's lighting (its brightness drifted {100 * (light['low'] - 1):+.0f}% to "
                 f"{100 * (light['high'] - 1):+.0f}% across it, RMS {100 * light['rms']:.0f}%: every patch of the "
                 "texture would repeat it as blotches; keep it with keep_lighting=True / --keep-lighting)")
    return flat, light


def _level_oblique(exemplar, notes):
    """An unstructured photo taken at an angle levelled in scale (``_perspective.level``), said in
    ``notes``: ``(photo, {"spread", "crop", "scale_range"})``, or None where it shows no tilt (or is
    structured: rectified from its lines later)."""
    from .._scale import MIN_SCALE_SIDE, scale_drift
    from ._perspective import level

    if min(exemplar.shape[:2]) < MIN_SCALE_SIDE or structure_peak(exemplar) >= STRUCTURED_PEAK:
        return None
    drift = scale_drift(exemplar)
    found = level(exemplar, drift=drift)
    if found is None:
        return None
    spread = drift[1]
    lh, lw = found.image.shape[:2]
    lo, hi = found.scale_range
    notes.append(f"levelled the photo's perspective (taken at an angle: its grain's scale changed {spread:.2f}-fold "
                 f"across it, which every patch of the texture would show as blotches of large and small grain; "
                 f"cropped to {lh} x {lw} px, resampled by {lo:.2f} to {hi:.2f}; the far side's detail magnified "
                 "is softer: photograph the ground square-on for the sharpest texture; keep it with "
                 "keep_perspective=True / --keep-perspective)")
    return found.image.astype(exemplar.dtype, copy=False), {"spread": round(spread, 6), "crop": [lh, lw],
                                                            "scale_range": [round(lo, 6), round(hi, 6)]}


#: Most regions of one-off content the fit fills, largest first (each found again on the filled photo).
MAX_ONE_OFF = 4


def _leave_out_one_off(exemplar, notes):
    """Content the photo shows once (:func:`spectex.metrics.one_off_repeats`), filled from the rest of it
    (``_one_off.remove_one_off``), region by region, largest first, at most :data:`MAX_ONE_OFF`: the
    filled photo and a list of ``{"box", "source", "rarity"}``, each said in ``notes``; None where there
    is none (or none can be filled)."""
    from .._texture_stats import one_off_content
    from ._one_off import remove_one_off

    if min(exemplar.shape[:2]) < 32:
        return None
    regions = []
    for _ in range(MAX_ONE_OFF):
        box, _, rarity = one_off_content(exemplar)
        if box is None:
            break
        y0, x0, y1, x1 = box
        filled, source = remove_one_off(exemplar, box)
        where = f"x {x0}-{x1}, y {y0}-{y1}"
        if source is None:
            notes.append(f"the photo holds one-off content at {where} (rarity {rarity:.1f}) too large to fill "
                         "from the rest of it: the texture repeats it once per photo area; crop it out")
            break
        notes.append(f"left out one-off content at {where} of the photo (rarity {rarity:.1f}: it would repeat "
                     f"once per photo area), filled from x {source[1]}, y {source[0]} (keep it with "
                     "keep_one_off=True / --keep-one-off)")
        regions.append({"box": box, "source": source, "rarity": rarity})
        exemplar = filled
    return None if not regions else (exemplar, regions)


def _photo_as_ground(exemplar, notes, *, keep_lighting, keep_perspective, keep_one_off):
    """What a photo holds that is not the ground's texture, taken out in order (each unless kept): its
    lighting evened out, an unstructured photo taken at an angle levelled, one-off content filled.
    Returns ``(photo, lighting, levelled, one_off)``, the last three None where nothing was done."""
    found = []
    for keep, step in ((keep_lighting, _even_out_lighting), (keep_perspective, _level_oblique),
                       (keep_one_off, _leave_out_one_off)):
        done = None if keep else step(exemplar, notes)
        if done is not None:
            exemplar, done = done
        found.append(done)
    return (exemplar, *found)


def _at_full_resolution(texture, colour, coarse, source, exemplar, levelled, one_off, notes):
    """``texture`` with its tiles at the photo's full resolution (``_full.full_resolution``), said in the
    notes: ``(texture, texels across)``; as it is, and None, where the photo was not resampled (``source``
    None) or was levelled (its geometry no longer the photo's) or has no more than the tile."""
    from ..texture import SpectralTexture
    from ._full import full_resolution, full_side
    from ._one_off import fill_window

    n = colour.shape[0]
    side = n if source is None or levelled is not None else full_side(n, source)
    if side <= n:
        return texture, None
    h, w = exemplar.shape[:2]
    moves = [] if one_off is None else [(fill_window(r["box"], (h, w)), r["source"]) for r in one_off]
    full, big = full_resolution(colour, coarse, source, (h, w), ((h - n) // 2, (w - n) // 2), moves=moves)
    rgba = np.ones((side, side, 4), dtype=np.float32)
    rgba[:, :, :3] = full
    pixels = n * min(source["step"]) / side
    notes.append(f"the finest tile holds the photo's own detail: {side}x{side} texels, a texel "
                 + ("one photo pixel" if abs(pixels - 1.0) < 0.01 else f"{pixels:.3g} photo pixels")
                 + f" (the fit read the photo at {n}x{n}; pass tile_size={n} / --tile-size {n} for a tile of that "
                 "size)")
    return SpectralTexture([rgba, big], texture.layers), side


def check_options(*, layers=5, ratio=4.0, opacity=None, iterations=None, rng=0, tiling="auto", patch=None,
                  progress=None):
    """The fit's options checked (no image needed: the command line checks them before reading the photo).

    Returns ``(layers, ratio, opacity, iterations, rng, tiling, patch)`` with the defaults filled in and
    ``rng`` a Generator.
    """
    from ..shading.constants import DEFAULT_PATCH

    layers = check_int("layers", layers, minimum=2, maximum=8)
    ratio = check_float("ratio", ratio, minimum=1.0, exclusive_minimum=True, maximum=64.0)
    opacity = AUTO_OPACITY if opacity is None else check_float("opacity", opacity, minimum=0.0, maximum=1.0,
                                                               exclusive_minimum=True)
    iterations = AUTO_ITERATIONS if iterations is None else check_int("iterations", iterations, minimum=1,
                                                                      maximum=50)
    rng = check_rng(rng)
    tiling = check_choice("tiling", tiling, FIT_TILINGS)
    patch = DEFAULT_PATCH if patch is None else check_float("patch", patch, minimum=0.0, exclusive_minimum=True,
                                                             maximum=4.0)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable, got {type(progress).__name__}")
    return layers, ratio, opacity, iterations, rng, tiling, patch


def _stochastic_tile_size(tile_size, tiling, period, h, w):
    """The finest tile's side for :func:`spectex.fitting._core.finest_tile` (None: its default) when the
    finest layer is, or may be, drawn stochastically."""
    if tile_size is None and tiling != "periodic" and period is None and min(h, w) >= MIN_SIZE:
        # Drawn stochastically the finest layer never repeats, so an unstructured photo itself (its
        # seamless crop) is its tile, whatever its size: a quilt four times its side adds no content, only
        # cuts through whatever is larger than its blocks' overlap (stones, coins: fragments with straight
        # edges). On 13 unstructured photos of 64-303 pixels the crop was closer to the photo over a render
        # of twice its side on 10 ("docs/fitting.md", "A small photo is its own tile"). A periodic finest
        # layer keeps the quilt (its tile repeats), and so does the stochastic trial of a structured photo
        # under STRUCTURED_CROP_MIN (a 128-pixel wall's own crop, its patches of 56 pixels, lost 2 dB of its
        # coarsest band).
        tile_size = min(h, w)
    elif tile_size is None and tiling != "periodic" and period is not None and min(h, w) >= STRUCTURED_CROP_MIN:
        # the stochastic way of a structured photo as large as a tile: its own seamless crop (its stones and
        # bricks whole, so that free cells can draw them whole) rather than a quilt a few pixels larger
        tile_size = min(h, w)
    return tile_size


def _copy_side(repeat, factor, shape, analysed_shape):
    """One copy's side ``(y, x)`` in exemplar pixels of a photo tiled before it was saved whose whole the fit
    reads (``repeat["whole"]``), or None (no such repeat, or the exemplar straightened: its pixels turned)."""
    if repeat is None or not repeat.get("whole") or tuple(shape) != tuple(analysed_shape):
        return None
    cy, cx = (round(c / factor) for c in repeat["cell"])
    return (min(cy, shape[0]), min(cx, shape[1])) if min(cy, cx) >= 48 else None  # (repeat_peak reads 48 or more)


def _coursed_way(exemplar):
    """A wall of courses of their own heights (:func:`spectex.fitting._joints.wall_courses`): the way that draws
    it, ``(tile, side, words, "stochastic", snap, 1.0)`` (:func:`spectex.fitting._joints.coursed_tile`, a
    joint put at the wrap edge of each course not cut at its own joints, :func:`_joints_at_wrap`; snapped to
    one period across its courses: each patch offset along them only), or None."""
    found = wall_courses(exemplar)
    if found is None:
        return None
    cut = coursed_tile(exemplar, found)
    if cut is None:
        return None
    tile, side, (one, two, courses, most) = cut
    axis = found[0]
    snap = (0, 1) if axis == 0 else (1, 0)
    heights = np.diff(found[1])
    kind = "rows" if axis == 0 else "columns"
    words = (f"a wall of courses of their own heights ({min(heights):.0f}-{max(heights):.0f} px; {courses} "
             f"{kind} of stones from one grout line to another, {one + two} of them cut at their own joints ({one} "
             f"at one stretch, {two} at two; stretched by at most {100 * most:.0f}%)), drawn stochastically with "
             f"each patch offset along its courses only (snap {snap}), in bands a tile high each starting its "
             f"courses at one of the tile's")
    return np.clip(_joints_at_wrap(tile, snap), 0.0, 1.0), side, words, "stochastic", snap, 1.0


def _coursed_candidate(coursed):
    """The trial's candidate (:func:`_trial`) of :func:`_coursed_way`'s way: its tile repeats across its
    courses once a tile (the lattice its bake shows)."""
    tile, side, _, tiling, snap, scale = coursed
    lattice = (float(side), None) if snap[1] else (None, float(side))
    return "coursed", tiling, tile, snap, scale, lattice


def _unstructured_way(exemplar, pixel_size, patch, stochastic_tile, coursed, cell=None):
    """The trial (:func:`_trial`, :func:`_choose`) of a photo without a period whose grout lines make it a wall of
    courses of their own heights (``coursed``, :func:`_coursed_way`'s way): ``(trial, way)``, ``way`` the
    coursed way's, or None where the stochastic one (``stochastic_tile``) is closer."""
    from ..metrics import repeat_peak

    period = (None, None)
    ways = [("stochastic", "stochastic", stochastic_tile, (0, 0), 1.0, None), _coursed_candidate(coursed)]
    # the courses' grout lines holding their places (lines along x where the courses run along x: axis 1)
    trial = _trial(exemplar, pixel_size, ways, patch, period, along=float(coursed[1]) / 2.0,
                   lines=1 if coursed[4][1] else 0)
    own = repeat_peak(exemplar if cell is None else exemplar[:cell[0], :cell[1]])
    trial["photo_repeat"] = own
    choice = _choose_courses({k: v for k, v in trial.items() if k != "photo_repeat"}, own)
    trial["choice"] = choice
    return trial, (coursed if choice == "coursed" else None)


def _choose_courses(trial, own_repeat):
    """:func:`_unstructured_way`'s choice between its ``"stochastic"`` and ``"coursed"`` trial bakes: :func:`_choose`'s,
    but the stochastic way wherever it keeps the courses' grout lines (continuity at least ``CONTINUITY_LIMIT``)
    and draws the photo closer. The structural distance does not see courses ending in stubs (a wall of
    courses drawn stochastically read 1.05 against 1.07 drawn by its courses, over four bakes); the lines'
    continuity does (0.79 against 0.96)."""
    choice = _choose(trial, own_repeat)
    stochastic = trial["stochastic"]
    if stochastic["continuity"] >= CONTINUITY_LIMIT and trial["coursed"]["structure"] > stochastic["structure"]:
        choice = "stochastic"
    return choice


def _structured_way(exemplar, pixel_size, patch, period, cut, cut_tile, cut_method, stochastic_tile, cell=None,
                    coursed=None):
    """The trial of a structured photo's finest layer (:func:`_trial`, :func:`_choose`): ``(trial, way)``, ``way``
    ``(tile, side, words, tiling, snap, texel scale)`` of the chosen way, None where it is the stochastic one
    (``stochastic_tile``, as the caller has it). ``coursed``: a wall of courses of their own heights
    (:func:`_coursed_way`'s way), a candidate too."""
    from ..metrics import repeat_peak

    _, side, counts, whole, texel_scale = cut
    # the trial bakes: the finest layer alone, each way, measured by the structural distance and by the
    # repeat of its content beyond the structure's lattice
    snap = (counts[1], counts[0])
    # the tile's lattice in the bake (photo pixels): its whole-texel periods over the texel scale
    lattice = tuple(None if q is None else q / texel_scale for q in whole)
    ways = [("periodic", "periodic", cut_tile, (0, 0), texel_scale, lattice),
            ("snapped", "stochastic", cut_tile, snap, texel_scale, lattice),
            ("stochastic", "stochastic", stochastic_tile, (0, 0), 1.0, None)]
    boards = min(snap) == 0 and _along_share(exemplar, period) <= BOARD_ALONG_SHARE and _courses_unmapped(cut_tile,
                                                                                                          snap)
    aligned_tile = _aligned_tile(exemplar, period) if boards else None
    if aligned_tile is not None:
        # a structure along one axis whose courses have no map (boards without joints, running the whole
        # tile: nothing to change patch at): the tile's columns (or rows) kept where they are, each patch
        # shifted along them only (snapped to whole tiles across), so that boards of uneven widths, which no
        # shift by whole periods lines up, keep their edges in line. (Courses with joints keep the snapped
        # way, whose map changes patch at them: drawn aligned, bricks were cut where two patches meet, the
        # mortar in stubs.)
        ways.append(("aligned", "stochastic", aligned_tile[0], _aligned_snap(snap), 1.0, period))
    if coursed is not None:
        ways.append(_coursed_candidate(coursed))
    trial = _trial(exemplar, pixel_size, ways, patch, period, along=_board_length(cut_tile, snap, texel_scale),
                   continuity=aligned_tile is not None)
    # the photo's own repeat beyond its lattice; a photo tiled before it was saved (``cell``: one copy's side in
    # exemplar pixels) read on one copy, or its tiling would pass any way that repeats (a brick wall tiled two by
    # two drawn periodic, repeat 0.80)
    own = repeat_peak(exemplar if cell is None else exemplar[:cell[0], :cell[1]], period=period)
    trial["photo_repeat"] = own
    choice = _choose({k: v for k, v in trial.items() if k != "photo_repeat"}, own)
    trial["choice"] = choice
    if choice == "periodic":
        return trial, (cut_tile, side, cut_method, "periodic", (0, 0), texel_scale)
    if choice == "snapped":
        return trial, (cut_tile, side, cut_method + f", drawn stochastically with offsets snapped to whole periods "
                       f"(snap {snap})", "stochastic", snap, texel_scale)
    if choice == "coursed":
        return trial, coursed
    if choice == "aligned":
        aligned = _aligned_snap(snap)
        along = "columns" if aligned[0] else "rows"
        p = period[1] if aligned[0] else period[0]
        return trial, (aligned_tile[0], aligned_tile[1],
                       f"a seamless crop of {round(aligned_tile[1] / p)} of the structure's periods ({p} px) across "
                       f"its {along} at the photo's own pixels, drawn stochastically with its {along} kept in line, "
                       f"each patch shifted along them only (snap {aligned}: its lines' uneven spacing kept)",
                       "stochastic", aligned, 1.0)
    return trial, None


def fit_auto(image, *, pixel_size=None, photo_size=None, layers=5, ratio=4.0, opacity=None, iterations=None,
             tile_size=None, max_size=MAX_ANALYSIS_SIZE, rng=0, tiling="auto", patch=None, keep_one_off=False,
             keep_lighting=False, keep_perspective=False, progress=None) -> FitResult:
    """Issue 22's fit (see the module's docstring and :func:`spectex.fit`)."""
    start = time.perf_counter()
    layers, ratio, opacity, iterations, rng, tiling, patch = check_options(
        layers=layers, ratio=ratio, opacity=opacity, iterations=iterations, rng=rng, tiling=tiling, patch=patch,
        progress=progress)
    from ..metrics import band_power, clipped_fraction
    from ..texture import Layer, layer_placement

    tile_given = tile_size is not None
    exemplar, notes, factor, source, repeat = _prepared_with_source(image, max_size)
    photo = exemplar  # as the user gave it (its lighting, perspective and one-off content not yet changed)
    full_side = max(np.shape(image)[:2])
    pixel_size, scale = _resolve_scale(pixel_size, photo_size, full_side, notes, factor)
    # a repeat cell's content is in every copy: what it shows once, the photo shows once per cell, as often as
    # the texture will (the one-off rule's premise, content the photo shows once, does not hold)
    exemplar, lighting, levelled, one_off = _photo_as_ground(exemplar, notes, keep_lighting=keep_lighting,
                                                             keep_perspective=keep_perspective,
                                                             keep_one_off=keep_one_off or repeat is not None)
    h, w = exemplar.shape[:2]
    total = 3 + iterations
    done = 0

    def tick():
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    # --- layer 0's tile and tiling
    structure = structure_peak(exemplar)
    analysed = exemplar
    exemplar, angle, drift, turn = _straighten_structure(exemplar, structure, notes, keep_perspective)
    if exemplar.shape[:2] != (h, w):
        h, w = exemplar.shape[:2]
        structure = structure_peak(exemplar)
    period = structure_period(exemplar) if structure >= STRUCTURED_PEAK else None
    if period is not None and period == (None, None):
        period = None
    joint_words = []
    cut = _period_tile(exemplar, period, joint_words) if period is not None and tiling != "stochastic" else None
    tile_size = _stochastic_tile_size(tile_size, tiling, period, h, w)
    # an unstructured photo drawn stochastically: its seamless crop, unless that moved its statistics
    check = tiling != "periodic" and period is None
    tile0, n, tile_method = finest_tile(exemplar, tile_size, rng, reuse=1.0, check=check)
    tilings0 = "periodic" if tiling == "periodic" else "stochastic"
    snap0 = (0, 0)
    scale0 = 1.0  # the finest tile's texels per photo pixel
    trial = None
    # a wall of courses of their own heights (coursed ashlar): a candidate of the trial, period or none
    coursed = _coursed_way(exemplar) if tiling == "auto" and min(h, w) >= 64 else None
    if cut is None and coursed is not None:
        trial, way = _unstructured_way(exemplar, pixel_size, patch, tile0, coursed,
                                       cell=_copy_side(repeat, factor, exemplar.shape[:2], analysed.shape[:2]))
        if way is not None:
            tile0, n, tile_method, tilings0, snap0, scale0 = way
    if cut is not None:
        crop, side, counts, whole, texel_scale = cut
        # the crop as it is: cut where its wrap edges differ least, at whole periods, it is seamless as a
        # structure; make_seamless's smooth correction takes up every brick's colour step along the wrap
        # edges and spreads them into blotches (up to 0.66 on a 240-pixel wall tile; its structural
        # distance 1.98 against 0.86 for the crop itself)
        cut_tile = np.clip(crop, 0.0, 1.0).astype(np.float64)
        cut_method = (f"cut at the structure's period (x {period[1]}, y {period[0]} px; {counts[1]} x "
                      f"{counts[0]} periods, 0 where none) where its wrap edges show least, resampled to "
                      f"whole-texel periods (x {whole[1]}, y {whole[0]} texels)"
                      + "".join(f"; {w}" for w in joint_words))
        if tiling == "periodic" or min(h, w) < 64:  # (too small for two windows of the measure)
            tile0, n, tile_method, tilings0, scale0 = cut_tile, side, cut_method, "periodic", texel_scale
        else:
            trial, way = _structured_way(exemplar, pixel_size, patch, period, cut, cut_tile, cut_method, tile0,
                                         cell=_copy_side(repeat, factor, exemplar.shape[:2], analysed.shape[:2]),
                                         coursed=coursed)
            if way is not None:
                tile0, n, tile_method, tilings0, snap0, scale0 = way
    if not tile_given and tile_method == "seamless crop" and snap0 == (0, 0) and n == min(h, w) and h != w:
        # the finest tile the photo's own crop, structured or not (the stochastic way chosen): what it leaves out
        notes.append(f"the finest tile is the central {n}x{n} crop of the {w}x{h} photo (its shorter side): the "
                     "rest of the photo is not in the texture; a square photo gives it all")
    tick()
    # --- the coarse layers' own tile
    region = (min(h, 256), min(w, 256))
    slope = min(AUTO_MAX_SLOPE, _coarse_slope(band_power(exemplar, segment=region)[1]))
    mean, axis, noise = _coarse_tile(exemplar, n, ratio, slope, rng)

    # the overlay's modulation d = opacity (2 x - 1): x = 1/2 + (the coarse deviation along the colour
    # axis) / (2 room), room the mean's distance to black or white, so that at the mean colour a layer of
    # opacity a moves the colour by a times the deviation, as the alpha blend did; held to [0, 1]
    # symmetrically, so d averages 0 and the layers keep the finest layer's mean
    room = np.maximum(np.minimum(mean, 1.0 - mean), 1.0 / 255.0)
    spread = np.quantile(exemplar.reshape(-1, 3), [0.005, 0.995], axis=0)
    reach = np.maximum(np.minimum(mean - spread[0], spread[1] - mean), 1.0 / 255.0)

    def coarse(g):
        rgba = np.ones((n, n, 4), dtype=np.float32)
        rgba[:, :, :3] = _overlay_tile(g * noise[:, :, None] * axis, reach, room)
        return rgba

    q = float(np.clip(10.0 ** (slope * math.log2(ratio) / 20.0), 0.25, 1.0))
    finest = n * pixel_size / scale0
    layer_list = [Layer(size=finest, tile=0, tiling=tilings0, patch=patch, snap=snap0, rotation=turn)]
    for k in range(1, layers):
        size = finest * ratio ** k
        offset, rotation = layer_placement(k, size, decimals=9)
        layer_list.append(Layer(size=size, tile=1, offset=offset, rotation=rotation, blend=COARSE_BLEND,
                                opacity=round(opacity * q ** (k - 1), 6)))
    problem = _TwoTiles(exemplar, pixel_size, layer_list, n, ratio, region,
                        n_regions=3 if tilings0 == "stochastic" else 2, continuation=slope)
    gain = 2.0
    problem.coarse_tile = coarse(gain)
    alpha = np.ones((n, n))
    colour = tile0
    tick()
    history = []
    n_cont = 2
    photo_mean = exemplar.reshape(-1, 3).astype(np.float64).mean(axis=0)
    for _ in range(iterations):
        # one set of bakes per round: the band step (a radial gain, mean kept) and the means' shift
        # both read it
        bakes = problem.bakes(colour, alpha)
        err = problem.band_error(bakes)
        history.append(err.tolist())
        fine_err = err[:-n_cont]
        shaped = _shape_spectrum(colour, np.concatenate([np.clip(0.8 * fine_err, -6.0, 6.0), [0.0, 0.0]]))
        # the means: the overlay layers keep the finest layer's mean over the plane (d averages 0,
        # independent of the colour below), so the tile's own mean is the texture's; unclipped until
        # the tails below (clipping here piled a dark photo's shaped tile at 0: 13% of deep field's)
        colour = shaped + (photo_mean - shaped.reshape(-1, 3).mean(axis=0))
        if len(history) == 1:
            # the coarse tile's contrast, once (its stochastic tables are then made once more only):
            # its power follows gain^2 until the photo's range clips it
            gain = float(np.clip(gain * 10.0 ** (float(np.mean(err[-n_cont:])) / 20.0), 0.1, 8.0))
            problem.coarse_tile = coarse(gain)
        tick()
    # the tile inside the photo's range per channel (no colour the photo lacks), its extremes the
    # photo's; the means are the rounds'. Not the exact histogram step (the bakes' histograms mapped to
    # the photo's) that was here: a few bake regions of a non-stationary photo (moon's flat maria beside
    # its craters) pool local contrasts 10 dB apart, and the quantile map fitted to that sample stretched
    # the tile's flat parts, raising moon's finest bands by 3 dB with a speckle of grain (structural
    # distance 1.15 against 1.04 without it; tissue 0.88 against 0.81; within 0.03 on the others)
    colour, blotch_db = _even_blotches(problem, colour, alpha, exemplar, len(history[-1]))
    colour = _match_tails(colour, exemplar, photo_clipped=[clipped_fraction(photo[:, :, c]) for c in range(3)])
    layer_list, depth = _clip_guard(problem, colour, alpha, exemplar, layer_list, n, ratio)
    tick()
    texture = problem.texture(colour, alpha)
    # where the tile is the crop of the photo as the fit read it, the photo's finer detail goes back where
    # it belongs ("_full.py")
    crop = not tile_given and tile_method == "seamless crop" and tilings0 == "stochastic" and exemplar is analysed
    texture, full_px = _at_full_resolution(texture, colour, problem.coarse_tile, source if crop else None, exemplar,
                                           levelled, one_off, notes)
    from ..shading.resources import cell_maps

    # an unsnapped finest layer whose tile shows a grout network is drawn with free cells (cobbles whole)
    free_cells = bool(tilings0 == "stochastic" and max(snap0) == 0 and cell_maps(texture)[0] is not None)
    # one snapped along one axis only whose tile's courses have joints changes patch at its joints (boards whole)
    courses = bool(tilings0 == "stochastic" and max(snap0) > 0 and min(snap0) == 0
                   and cell_maps(texture)[0] is not None)
    params = {"method": "auto", "tile_px": texture.tile_shape[0], "analysis_px": n, "full_resolution": full_px,
              "tile_method": tile_method, "free_cells": free_cells,
              "courses": courses,
              "layers": layers, "ratio": ratio,
              "coarse_slope_db_per_octave": slope, "coarse_gain": gain,
              "opacities": [lay.opacity for lay in layer_list], "alpha_gain": 0.0, "coarse_depth": depth,
              "blotch_db": blotch_db,
              "band_error_history_db": history, "tilings": [lay.tiling for lay in layer_list],
              "structure_peak": structure, "orientation_deg": angle, "orientation_drift_deg": drift,
              "turn_deg": turn, "period_px": period,
              "tile_period_px": None if cut is None else cut[3], "trial": trial, "snap": snap0, "patch": patch,
              "scale": scale, "repeat": repeat, "lighting": lighting, "level": levelled, "one_off": one_off}
    return FitResult(texture=texture, exemplar=exemplar, pixel_size=pixel_size, notes=notes, params=params,
                     seconds=time.perf_counter() - start)
