"""A structured photo taken in perspective, rectified before its period is read (issue 22).

A wall or a floor photographed at an angle shows its two families of
lines (a brick wall's joints along its columns and along its rows) fanning
out towards two vanishing points. Cut into one tile, its left and right
carry lines at different angles, and the snapped patches of such a tile
meet at V-shaped breaks in the mortar. Here the photo is made square-on
first (a plane homography, Hartley and Zisserman's affine rectification
from two vanishing points followed by the affine map that puts the two
families along the image axes):

1. the local line direction of each family, per window (:func:`line_field`:
   the gradients split into the near-horizontal and near-vertical ones,
   each family's direction the energy-weighted mean of its doubled angle);
2. each family's vanishing point, the homogeneous point closest to all its
   windows' lines (:func:`vanishing_point`, weighted least squares);
3. the vanishing line through the two points sent to infinity, the two
   families' directions then sent to the axes, scaled so that the photo's
   centre keeps one pixel per pixel along each family
   (:func:`rectifying_map`);
4. the largest axis-aligned rectangle of the mapped photo resampled (cubic)
   through the inverse map (:func:`rectify`), read again and refined, then
   the lines' spacing evened out across it (equally spaced lines on the
   plane fix the vanishing line where the second family's vanishing point,
   read from short joints, is poor: :func:`_spacing_map`).

References
----------
R. Hartley and A. Zisserman, *Multiple View Geometry in Computer Vision*,
2nd ed., 2004, sections 2.7 (affine rectification from the vanishing line)
and 8.6 (vanishing points).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Side of the windows the line directions are read in (pixels).
LINE_WINDOW = 32
#: Fewest windows a family needs for its vanishing point; with fewer its lines are taken as
#: parallel to the image axis they are nearest.
MIN_WINDOWS = 6
#: Least and most relative change of a rectified crop's line spacing across it that :func:`_spacing_map`
#: evens out: less is within the period's reading, more is not a residual of the vanishing line.
SPACING_MIN = 0.01
SPACING_MAX = 0.3
#: Least side of the rectified crop (pixels; the fit's smallest photo), and at least half the photo's.
MIN_CROP = 32
#: Largest ratio of the most to the least magnification across the rectified crop (brick 1.8, the
#: synthetic walls and floor of the tests 3.2 to 3.4).
MAX_SCALE_SPREAD = 4.0
#: Largest aspect ratio of the rectified crop (its longer side over its shorter).
MAX_ASPECT = 1.5


@dataclass(frozen=True)
class Rectification:
    """A photo made square-on (:func:`rectify`).

    Attributes
    ----------
    image : ndarray, shape (h, w, C)
        The rectified crop.
    homography : ndarray, shape (3, 3)
        Maps a photo pixel ``(x, y, 1)`` (column, row; centres at whole
        numbers) to the rectified crop's pixel, homogeneous.
    vanishing : tuple of ndarray
        The two families' vanishing points (homogeneous ``(x, y, w)`` in
        photo pixels, unit length; ``w`` about 0 for parallel lines): the
        lines along the columns (near vertical) first.
    scale_range : (float, float)
        The least and most magnification over the crop (rectified pixels
        per photo pixel, geometric mean of the two axes): how much of the
        crop is resampled up or down.
    """

    image: np.ndarray
    homography: np.ndarray
    vanishing: tuple
    scale_range: tuple


def line_field(lum, *, window: int = LINE_WINDOW):
    """The local direction of the near-vertical and near-horizontal lines, per window.

    The luma's gradients (Gaussian derivatives, sigma 1) are split by
    direction: those nearer horizontal are the edges of near-vertical lines
    (family 0), the others those of near-horizontal lines (family 1). In
    each ``window`` x ``window`` block a family's direction is its
    gradients' mean doubled angle, weighted by their squared magnitude.

    Returns
    -------
    centres : ndarray, shape (N, 2)
        Window centres ``(x, y)``, pixels.
    fields : list of two (ndarray (N, 2), ndarray (N,))
        Per family: the unit line direction ``(dx, dy)`` in each window and
        its weight (the length of the summed doubled-angle vector: strong,
        consistent lines weigh most).
    """
    from scipy import ndimage

    lum = np.asarray(lum, dtype=np.float64)
    gy = ndimage.gaussian_filter(lum, 1.0, order=(1, 0))
    gx = ndimage.gaussian_filter(lum, 1.0, order=(0, 1))
    r2 = gx * gx + gy * gy
    z2 = r2 * np.exp(2j * np.arctan2(gy, gx))
    h, w = lum.shape
    ny, nx = h // window, w // window
    oy, ox = (h - ny * window) // 2, (w - nx * window) // 2
    yc, xc = np.meshgrid(oy + (np.arange(ny) + 0.5) * window - 0.5, ox + (np.arange(nx) + 0.5) * window - 0.5,
                         indexing="ij")
    centres = np.stack([xc.ravel(), yc.ravel()], axis=1)
    vertical_lines = np.abs(gx) >= np.abs(gy)
    fields = []
    for mask in (vertical_lines, ~vertical_lines):
        z = np.where(mask, z2, 0.0)[oy:oy + ny * window, ox:ox + nx * window]
        s = z.reshape(ny, window, nx, window).sum(axis=(1, 3)).ravel()
        t = np.angle(s) / 2.0  # the gradients' mean direction; the line runs across it
        fields.append((np.stack([-np.sin(t), np.cos(t)], axis=1), np.abs(s)))
    return centres, fields


def vanishing_point(centres, directions, weights):
    """The homogeneous point nearest to the lines through ``centres`` along ``directions``.

    Each window's line ``l = (x, y, 1) x (dx, dy, 0)`` (unit normal); the
    point ``v`` (unit length) minimises ``sum(weights (l . v)^2)``: the
    smallest eigenvector of ``sum(weights l l^T)``. Coordinates are taken
    about the centres' mean and scaled by their spread, so the system is
    well conditioned; the point is returned in the input's pixels. Parallel
    lines give ``w`` about 0 (a point at infinity along them).
    """
    c = centres.mean(axis=0)
    s = max(float(np.abs(centres - c).max()), 1.0)
    p = (centres - c) / s
    lines = np.stack([-directions[:, 1], directions[:, 0], p[:, 0] * directions[:, 1] - p[:, 1] * directions[:, 0]],
                     axis=1)
    m = (lines * weights[:, None]).T @ lines
    v = np.linalg.eigh(m)[1][:, 0]
    v = np.array([s * v[0] + c[0] * v[2], s * v[1] + c[1] * v[2], v[2]])
    return v / np.linalg.norm(v)


def _family_point(centres, field, axis):
    """A family's vanishing point, or the point at infinity along image ``axis`` (0: y, 1: x) where it has too
    few strong windows."""
    directions, weights = field
    strong = weights >= 0.1 * float(weights.max()) if weights.size else weights.astype(bool)
    if int(np.count_nonzero(strong)) < MIN_WINDOWS:
        return np.array([1.0, 0.0, 0.0]) if axis == 1 else np.array([0.0, 1.0, 0.0])
    return vanishing_point(centres[strong], directions[strong], weights[strong])


def rectifying_map(shape, vanishing):
    """The homography that makes a photo of ``shape`` with the two ``vanishing`` points square-on.

    The vanishing line ``l = v0 x v1`` is sent to infinity (``H_a`` with
    last row ``l``, scaled to 1 at the photo's centre), then the affine map
    ``A`` sends the images of ``v0`` and ``v1`` (now directions) to the y
    and x axes, each scaled to one pixel per photo pixel at the centre, and
    the centre to itself. Returns None where the vanishing line crosses the
    photo (no plane is seen that way).
    """
    h, w = shape
    c = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
    shift = np.array([[1.0, 0.0, -c[0]], [0.0, 1.0, -c[1]], [0.0, 0.0, 1.0]])
    v0, v1 = (shift @ v for v in vanishing)
    line = np.cross(v0, v1)
    corners = np.array([[x, y, 1.0] for x in (-c[0] - 0.5, c[0] + 0.5) for y in (-c[1] - 0.5, c[1] + 0.5)])
    sides = corners @ line
    if abs(line[2]) < 1e-12 or np.any(np.sign(sides) != np.sign(line[2])):
        return None
    ha = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], line / line[2]])
    d0, d1 = (ha @ v for v in (v0, v1))
    ay, ax = d0[:2], d1[:2]  # the columns' direction (to y), the rows' (to x)
    if np.linalg.norm(ay) < 1e-12 or np.linalg.norm(ax) < 1e-12:
        return None
    ay = ay / np.linalg.norm(ay) * (1.0 if ay[1] >= 0 else -1.0)
    ax = ax / np.linalg.norm(ax) * (1.0 if ax[0] >= 0 else -1.0)
    basis = np.stack([ax, ay], axis=1)
    if abs(np.linalg.det(basis)) < 0.5:  # the two families less than 30 degrees apart
        return None
    a = np.eye(3)
    a[:2, :2] = np.linalg.inv(basis)
    back = np.array([[1.0, 0.0, c[0]], [0.0, 1.0, c[1]], [0.0, 0.0, 1.0]])
    return back @ a @ ha @ shift


def _largest_rectangle(valid):
    """The largest axis-aligned rectangle ``(y0, y1, x0, x1)`` (end exclusive) inside the convex ``valid``
    mask, at most ``MAX_ASPECT`` long; None if the mask is empty."""
    rows = np.flatnonzero(valid.any(axis=1))
    if rows.size == 0:
        return None
    left = np.full(valid.shape[0], valid.shape[1], dtype=np.int64)
    right = np.zeros(valid.shape[0], dtype=np.int64)
    left[rows] = valid[rows].argmax(axis=1)
    right[rows] = valid.shape[1] - valid[rows, ::-1].argmax(axis=1)
    # convex: a rectangle spanning rows i..j fits where it fits in rows i and j
    i, j = np.meshgrid(rows, rows, indexing="ij")
    x0 = np.maximum(left[i], left[j])
    x1 = np.minimum(right[i], right[j])
    height = j - i + 1
    width = np.clip(x1 - x0, 0, None)
    side = np.minimum(height, width)
    usable = (j >= i) & (np.maximum(height, width) <= MAX_ASPECT * side)
    area = np.where(usable, height * width, 0)
    k = np.unravel_index(int(np.argmax(area)), area.shape)
    if area[k] <= 0:
        return None
    return int(i[k]), int(j[k]) + 1, int(x0[k]), int(x1[k])


def _estimated_map(image, window):
    """:func:`rectifying_map` of ``image`` from its own line field, or None."""
    from ._core import _luma

    centres, fields = line_field(_luma(image), window=window)
    vanishing = (_family_point(centres, fields[0], 0), _family_point(centres, fields[1], 1))
    return rectifying_map(image.shape[:2], vanishing)


def _resampled(image, hom):
    """The largest axis-aligned rectangle of ``image`` mapped by ``hom``, resampled (cubic): ``(crop, to_crop,
    (least, most magnification))``, ``to_crop`` mapping photo pixels to the crop's; or None."""
    from scipy import ndimage

    h, w = image.shape[:2]
    # the photo's outline in the rectified plane, rasterised (a convex quadrilateral: the vanishing
    # line is outside the photo)
    corners = np.array([[-0.5, -0.5, 1.0], [w - 0.5, -0.5, 1.0], [w - 0.5, h - 0.5, 1.0], [-0.5, h - 0.5, 1.0]]).T
    mapped = hom @ corners
    if np.any(mapped[2] <= 0):
        return None
    mapped = mapped[:2] / mapped[2]
    lo = np.floor(mapped.min(axis=1)).astype(np.int64)
    hi = np.ceil(mapped.max(axis=1)).astype(np.int64)
    if np.any(hi - lo > 4 * max(h, w)):
        return None
    inverse = np.linalg.inv(hom)
    gy, gx = np.mgrid[lo[1]:hi[1] + 1, lo[0]:hi[0] + 1].astype(np.float64)
    src = np.tensordot(inverse, np.stack([gx, gy, np.ones_like(gx)]), axes=1)
    sx, sy = src[0] / src[2], src[1] / src[2]
    valid = (src[2] > 0) & (sx >= 0) & (sx <= w - 1) & (sy >= 0) & (sy <= h - 1)
    box = _largest_rectangle(valid)
    if box is None or min(box[1] - box[0], box[3] - box[2]) < max(MIN_CROP, min(h, w) // 2):
        return None
    y0, y1, x0, x1 = box
    sx, sy = sx[y0:y1, x0:x1], sy[y0:y1, x0:x1]
    out = np.stack([ndimage.map_coordinates(image[:, :, c].astype(np.float64), [sy, sx], order=3, mode="nearest")
                    for c in range(image.shape[2])], axis=2)
    out = np.clip(out, image.min(axis=(0, 1)), image.max(axis=(0, 1))).astype(image.dtype)
    to_crop = np.array([[1.0, 0.0, -float(lo[0] + x0)], [0.0, 1.0, -float(lo[1] + y0)], [0.0, 0.0, 1.0]]) @ hom
    # magnification: the Jacobian's determinant of the crop-to-photo map, per crop pixel
    jac = np.abs(np.gradient(sx, axis=1) * np.gradient(sy, axis=0) - np.gradient(sx, axis=0) * np.gradient(sy, axis=1))
    scale = 1.0 / np.sqrt(np.maximum(jac, 1e-12))
    return out, to_crop, (float(scale.min()), float(scale.max()))


def _spacing_map(crop):
    """The homography (about the crop's centre) that evens out the spacing of a rectified crop's lines.

    Parallel lines equally spaced on the plane are equally spaced in the
    image only once the vanishing line is at infinity; a vanishing line
    read a little off (the rows' vanishing point of short joints is read
    poorly) leaves their spacing changing across the crop. The period
    (:func:`spectex.fitting._structure.structure_period`) is read in each half
    along an axis; spacing ``s(x) = s0 (1 + k x)`` is evened by
    ``x' = x / (1 + e x)`` (local scale ``1 - 2 e x``), ``e = k / 2``, and
    the same along y. Returns None where no axis changes by more than
    ``SPACING_MIN`` across the crop.
    """
    from ._structure import structure_period

    h, w = crop.shape[:2]
    third = [0.0, 0.0]
    for axis, (a, b), n in ((1, (crop[:, : w // 2], crop[:, w // 2:]), w), (0, (crop[: h // 2], crop[h // 2:]), h)):
        pa, pb = structure_period(a)[axis], structure_period(b)[axis]
        if pa is None or pb is None:
            continue
        k = (pb - pa) / (n / 2.0) / (0.5 * (pa + pb))
        if SPACING_MIN < abs(k * n) <= SPACING_MAX:
            third[1 - axis] = k / 2.0
    if third == [0.0, 0.0]:
        return None
    c = ((w - 1) / 2.0, (h - 1) / 2.0)
    shift = np.array([[1.0, 0.0, -c[0]], [0.0, 1.0, -c[1]], [0.0, 0.0, 1.0]])
    back = np.array([[1.0, 0.0, c[0]], [0.0, 1.0, c[1]], [0.0, 0.0, 1.0]])
    even = np.eye(3)
    even[2, :2] = third
    return back @ even @ shift


def rectify(image, *, window: int = LINE_WINDOW, refine: int = 1):
    """``image`` made square-on: its two line families along the axes, parallel, the centre at its scale.

    Parameters
    ----------
    image : ndarray, shape (H, W, C)
        A photo of a plane structure with lines along two directions (a
        brick wall, a tiled floor), float.
    window : int
        Side of the windows the line directions are read in (pixels).
    refine : int
        Times the map is refined: the lines' vanishing points read again
        on the rectified crop and the two maps composed, the photo then
        resampled once. The gradients' directions lean towards the pixel
        grid's axes, so one reading takes a fanning line about 10% less
        turned than it is; measured again, the rest is read (a synthetic
        wall's vanishing point 38 px off in 400 before, 7 after). Last, the
        spacing of the lines is evened out across the crop
        (:func:`_spacing_map`: scikit-image's brick, its columns 36.6 px
        apart on the left and 34.7 on the right once parallel).

    Returns
    -------
    Rectification or None
        None where no rectifying map exists (the vanishing line crosses the
        photo, the families are less than 30 degrees apart), its crop is
        under half the photo's shorter side (or ``MIN_CROP``), or is
        magnified more than ``MAX_SCALE_SPREAD`` times as much in one place
        as in another.
    """
    from ._core import _luma

    hom = _estimated_map(image, window)
    if hom is None:
        return None
    # the map is read on the luma only (one channel resampled, not three); the photo resampled once
    lum = _luma(image)[:, :, None]
    for _ in range(refine):
        found = _resampled(lum, hom)
        if found is None:
            return None
        again = _estimated_map(found[0], window)
        if again is None:
            break
        hom = again @ found[1]
    found = _resampled(lum, hom)
    if found is None:
        return None
    even = _spacing_map(found[0])
    if even is not None:
        hom = even @ found[1]
    found = _resampled(image, hom)
    if found is None:
        return None
    out, to_crop, scale_range = found
    if scale_range[1] > MAX_SCALE_SPREAD * scale_range[0]:
        return None  # seen so obliquely that its far side is only a blur of the near one
    inverse = np.linalg.inv(to_crop)
    vanishing = tuple(v / np.linalg.norm(v) for v in (inverse @ np.array([0.0, 1.0, 0.0]),
                                                      inverse @ np.array([1.0, 0.0, 0.0])))
    return Rectification(image=out, homography=to_crop, vanishing=vanishing, scale_range=scale_range)


#: Times the scale drift of an unstructured photo is read and its map refined (:func:`level`): the local
#: frequency, blurred on the far side, reads about half the tilt each time.
LEVEL_ROUNDS = 5


def tilt_map(shape, slope):
    """The homography that undoes a scale drift of ``slope`` (:func:`spectex._scale.scale_drift`) on a photo
    of ``shape``: its last row ``(a, b, 1)`` about the centre, with the log magnification ``1.5 log(1 + a x +
    b y)`` the drift (to first order); the centre keeps its scale."""
    h, w = shape
    a = -slope[0] / (1.5 * w / 2.0)
    b = -slope[1] / (1.5 * h / 2.0)
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    shift = np.array([[1.0, 0.0, -cx], [0.0, 1.0, -cy], [0.0, 0.0, 1.0]])
    back = np.array([[1.0, 0.0, cx], [0.0, 1.0, cy], [0.0, 0.0, 1.0]])
    return back @ np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [a, b, 1.0]]) @ shift


def level(image, *, drift=None):
    """An unstructured photo taken at an angle made square-on in scale: its far side magnified to the near
    side's grain.

    The scale drift (:func:`spectex._scale.scale_drift`) is read, undone by
    :func:`tilt_map`, read again on the resampled crop and the maps
    composed, :data:`LEVEL_ROUNDS` times (the luma only), then the photo is
    resampled once. What it does not undo: the foreshortening along the
    tilt that is the same everywhere (grain squashed alike over the whole
    crop: no blotches, a texture slightly flattened along one axis), and
    detail the far side never had (its grain magnified is blurred).

    Parameters
    ----------
    image : ndarray, shape (H, W, C)
        A photo of unstructured ground (gravel, grass, soil), float.
    drift : tuple, optional
        The photo's :func:`spectex._scale.scale_drift`, where already read.

    Returns
    -------
    Rectification or None
        None where the photo shows no tilt (:func:`spectex._scale.is_oblique`),
        is under the scale drift's least side, or the map has no crop of at
        least half the photo's shorter side, or magnifies more than
        ``MAX_SCALE_SPREAD`` times as much in one place as in another.
        ``vanishing`` holds the vanishing line (homogeneous, photo pixels)
        twice.
    """
    from .._scale import MIN_SCALE_SIDE, is_oblique, scale_drift
    from ._core import _luma

    if min(image.shape[:2]) < MIN_SCALE_SIDE:
        return None
    slope, spread, significance, foreshortening = scale_drift(image) if drift is None else drift
    if not is_oblique(spread, significance, foreshortening):
        return None
    lum = _luma(image)[:, :, None]
    hom = tilt_map(image.shape[:2], slope)
    for _ in range(LEVEL_ROUNDS):
        found = _resampled(lum, hom)
        if found is None:
            return None
        if min(found[0].shape[:2]) < MIN_SCALE_SIDE:
            break
        slope, spread = scale_drift(found[0])[:2]
        if spread < 1.02:
            break
        hom = tilt_map(found[0].shape[:2], slope) @ found[1]
    found = _resampled(image, hom)
    if found is None:
        return None
    out, to_crop, scale_range = found
    if scale_range[1] > MAX_SCALE_SPREAD * scale_range[0]:
        return None
    line = to_crop[2] / np.linalg.norm(to_crop[2])
    return Rectification(image=out, homography=to_crop, vanishing=(line, line), scale_range=scale_range)
