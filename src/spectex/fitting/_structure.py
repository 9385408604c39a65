"""The structure of a photo of bricks, tiles or paving: its period along each axis and its angle.

Read by the fit (:mod:`spectex.fitting._auto`), which cuts a tile of whole
periods and straightens a turned photo, and by the rectification of a photo
in perspective (:mod:`spectex.fitting._perspective`), which evens out the
spacing of its lines; one home for both, below either.
"""

from __future__ import annotations

import math

import numpy as np

#: Autocorrelation a lag must reach to count as the structure's period (:func:`structure_period`).
PERIOD_MIN_CORRELATION = 0.15
#: Least rise of the autocorrelation at a period above its trough before it (:func:`structure_period`).
PERIOD_MIN_PROMINENCE = 0.1
#: Least height of the autocorrelation's peak at twice a period, as a fraction of the period's own.
PERIOD_MULTIPLE = 0.4
#: Fewest times a period must fit across the photo along its axis to be believed: the autocorrelation
#: is circular, so a crop of 1.5 periods of 64-pixel tiles showed a false 34.6-pixel period (the gap
#: its wrap-around leaves), which no second or third repeat confirmed.
PERIOD_MIN_REPEATS = 3.0
#: The drift across the axis :func:`structure_period` allows per pixel of lag (about 6 degrees).
TILT = 0.1
#: Correlation (over the whole overlap, every channel) at which a photo shifted by a lag is taken for a copy
#: of itself (:func:`repeat_cell`): a tiled texture, JPEG-compressed, reads 0.98-1.0; photographed
#: structure, bricks and tiles made by hand, 0.6-0.9 at its period.
REPEAT_EXACT = 0.95
#: Least fall of the correlation between lag 0 and a repeat (:func:`repeat_cell`): a smooth photo's
#: correlation stays high at every short lag without repeating anything.
REPEAT_DIP = 0.3
#: Correlation at which a lag on a reduced preview of a large photo is a candidate repeat, confirmed on the
#: photo itself (``fitting._core._one_repeat``): three copies of a 700-pixel texture read 0.94 at the whole
#: preview lag nearest their 170.7, and 1.000 on the photo.
REPEAT_CANDIDATE = 0.8


def structure_period(exemplar, *, min_lag: int = 8):
    """The period of a structured exemplar along its columns and rows, to a fraction of a pixel.

    The luma's circular autocorrelation (mean removed, divided by its value
    at lag 0) is read along the y axis (lag ``(dy, 0)``) and the x axis
    (``(0, dx)``), lags ``min_lag`` to half the side, each lag ``d`` taking
    the best over a drift of ``TILT d`` across the axis (a photo a few
    degrees off the structure's axes). On each axis the highest local
    maximum wins, unless a shorter lag reaches 90% of it (a multiple of the
    true period is as high as the period itself).

    A period is accepted only if it fits :data:`PERIOD_MIN_REPEATS` times
    (3) across the photo along its axis (fewer repeats cannot confirm it,
    and the circular autocorrelation of a crop of one or two periods has
    false peaks at the gap its wrap-around leaves), and if it stands above
    the autocorrelation's own floor: correlation :data:`PERIOD_MIN_CORRELATION` or more, and a peak
    :data:`PERIOD_MIN_PROMINENCE` above the lowest value between half the
    lag and the lag, and (where twice the lag is under half the side) a
    peak again at twice the lag, at least :data:`PERIOD_MULTIPLE` of the
    first's height. Bricks of random length along an axis give a weak bump
    at their mean length that does not come back at twice it: no period.

    A running bond's rows are offset by half a brick, so its highest peak
    down the wall is two rows. Where the other axis has no period (bricks
    of random length, or too few across the photo to be believed), an axis
    whose half period stands out on its own (a peak within a pixel of the
    half, believed as a period is) gives that half: the row, which the fit
    cuts at its own joints. With a period across, the two rows stay (the
    lattice's period).

    The whole-pixel lag is then refined (:func:`_refine_period`): a
    parabola through each peak at the period's multiples, the period the
    least-squares slope of the peaks' places against their multiples (a
    tile of ``k`` periods is cut ``k`` times more precisely than one peak
    is read).

    Returns
    -------
    (py, px) : tuple of float or None
        Pixels (not necessarily whole; rounded to 0.01); an entry is None
        where that axis has no period.
    """
    from ..color import luma

    lum = luma(exemplar, dtype=np.float64)  # (Rec. 709, as fitting._core._luma)
    lum = lum - lum.mean()
    spec = np.fft.rfft2(lum)
    acf = np.fft.irfft2(np.abs(spec) ** 2, s=lum.shape)
    acf /= acf[0, 0]
    # the linear autocorrelation (pairs of pixels both inside the photo, not across its wrap-around)
    h, w = lum.shape
    pad = (2 * h, 2 * w)
    overlap = np.fft.irfft2(np.abs(np.fft.rfft2(np.ones_like(lum), s=pad)) ** 2, s=pad)
    linear = np.fft.irfft2(np.abs(np.fft.rfft2(lum, s=pad)) ** 2, s=pad) / np.maximum(overlap, 1.0)
    linear /= linear[0, 0]
    full, course = [], []
    for a, b in ((acf, linear), (acf.T, linear.T)):
        found = _axis_period(a, b, min_lag)
        full.append(found[0])
        course.append(found[1])
    # a running bond whose bricks do not repeat across (random lengths, or too few across the photo):
    # its rows offset by half a brick correlate less at one row than at two, so the highest peak is
    # the bond's two rows; with no period across, each row is cut at its own joints and the row is the
    # period (a lattice keeps the bond's two rows: its tile is cut at whole periods of both axes)
    out = [c if c is not None and full[1 - i] is None else f for i, (f, c) in enumerate(zip(full, course))]
    return out[0], out[1]


def _axis_period(a, b, min_lag):
    """Along ``a``'s first axis (circular autocorrelation ``a``, linear ``b``): ``(period, course)``, the
    period as :func:`structure_period` reads it and the half of it where that half stands out as a period
    of its own (a running bond's row), each None where not found or not believed."""
    line = _axis_line(a, a.shape[0] // 2)
    half = len(line)
    v = line[min_lag:half]
    peaks = [i for i in range(1, len(v) - 1) if v[i] >= v[i - 1] and v[i] >= v[i + 1]]
    best = max(peaks, key=lambda i: v[i]) if peaks else None
    if best is None or v[best] < PERIOD_MIN_CORRELATION:
        return None, None
    p = next(i for i in peaks if v[i] >= 0.9 * v[best]) + min_lag
    if not _period_stands_out(line, p):
        return None, None
    inside = _axis_line(b, half)

    def believed(q):
        period = _refine_period(line, q)
        return round(period, 2) if a.shape[0] >= PERIOD_MIN_REPEATS * period and _seen_inside(inside, q) else None

    # the half: a peak within a pixel of p / 2 that stands out on its own
    lo, hi = max(min_lag, (p - 2) // 2), (p + 3) // 2
    q = lo + int(np.argmax(line[lo:hi + 1])) if hi > lo else None
    course = None
    if (q is not None and lo < q < hi and line[q] >= PERIOD_MIN_CORRELATION
            and _period_stands_out(line, q)):
        course = believed(q)
    return believed(p), course


def _axis_line(a, lags):
    """Autocorrelation ``a`` (lag 0 at index 0, negative lags wrapped) along its first axis, lags 0 to
    ``lags - 1``, each lag ``d`` the best over a drift of ``TILT d`` across the axis."""
    return np.array([max(a[d, e % a.shape[1]] for e in range(-int(math.ceil(TILT * d)), int(math.ceil(TILT * d)) + 1))
                     for d in range(lags)])


def _seen_inside(line, p):
    """Whether the linear autocorrelation ``line`` (pairs inside the photo) has its peak at lag ``p``
    (or next to it) :data:`PERIOD_MIN_PROMINENCE` above the lowest value between half the lag and the lag."""
    top = float(np.max(line[p - 1:p + 2]))
    return top >= PERIOD_MIN_CORRELATION and top - float(np.min(line[p // 2:p + 1])) >= PERIOD_MIN_PROMINENCE


def _period_stands_out(line, p):
    """Whether lag ``p`` of the autocorrelation ``line`` is a period (see :func:`structure_period`)."""
    if line[p] - float(np.min(line[p // 2:p + 1])) < PERIOD_MIN_PROMINENCE:
        return False
    if 2 * p + 1 < len(line):
        again = float(np.max(line[2 * p - 1:2 * p + 2]))
        if again < PERIOD_MULTIPLE * line[p] or again - float(np.min(line[p:2 * p + 1])) < PERIOD_MIN_PROMINENCE / 2:
            return False
    return True


def _peak_place(line, j):
    """Sub-pixel place of the local maximum of ``line`` at or next to lag ``j`` (a parabola through three lags)."""
    j = int(np.argmax(line[j - 1:j + 2])) + j - 1
    if j < 1 or j + 1 >= len(line):
        return float(j)
    a, b, c = line[j - 1], line[j], line[j + 1]
    den = a - 2.0 * b + c
    if den >= 0.0:  # not a maximum
        return float(j)
    return j + float(np.clip(0.5 * (a - c) / den, -0.5, 0.5))


def _refine_period(line, p):
    """The period to a fraction of a pixel from the autocorrelation ``line``'s peaks at ``p, 2p, ...``.

    Each peak is placed by a parabola (:func:`_peak_place`), the next
    multiple looked for at the estimate so far; the estimate is the least
    squares slope through the origin of the places against the multiples.
    Stops at the first multiple that is no longer a peak standing
    :data:`PERIOD_MIN_PROMINENCE` / 2 above the trough before it.
    """
    places = [(1, _peak_place(line, p))]
    est = places[0][1]
    m = 2
    while round(m * est) + 2 < len(line):
        j = int(round(m * est))
        x = _peak_place(line, j)
        jj = int(round(x))
        trough = float(np.min(line[int((m - 1) * est):jj + 1]))
        if abs(x - m * est) > 1.5 or line[jj] - trough < PERIOD_MIN_PROMINENCE / 2:
            break
        places.append((m, x))
        ms = np.array([q[0] for q in places], dtype=np.float64)
        xs = np.array([q[1] for q in places])
        est = float(np.sum(ms * xs) / np.sum(ms * ms))
        m += 1
    return est


def structure_orientation(exemplar) -> float:
    """The angle (degrees, in (-45, 45]) of a structure's lines from the image axes.

    The luma's gradients, each weighted by its squared magnitude, vote for
    their direction taken four times (``atan2`` of the sums of ``r^2 sin 4t``
    and ``r^2 cos 4t``, divided by four): lines along x and along y (a brick
    or tile grid) vote alike, so the angle is the grid's, not its longer
    lines' only. Positive: the lines turn anticlockwise in the image
    (row index down). How firmly they vote: :func:`line_coherence`.
    """
    return orientation_vote(exemplar)[0]


def line_coherence(exemplar) -> float:
    """How firmly a structure's gradients vote for one grid of lines (0 to 1): the length of the vote of
    :func:`structure_orientation` (the sum of ``r^2 e^(4it)``) over the votes' total weight.

    Lines along two perpendicular directions (a brick wall, floor tiles, square-on or turned) vote as one:
    0.8 to 0.9. Cells without such lines do not: hexagons' three directions of edges cancel in the vote
    taken four times (a reptile's scales 0.07), irregular cobbles (0.13) and gravel (0.04) vote every way.
    Below :data:`MIN_LINE_COHERENCE` the structure has no lines to straighten or to rectify, and its
    angle is chance.
    """
    return orientation_vote(exemplar)[1]


#: Least :func:`line_coherence` of a structure whose lines are straightened or rectified (0.07-0.13 for
#: hexagonal scales and irregular cobbles, 0.8-0.9 for walls and floor tiles at any angle).
MIN_LINE_COHERENCE = 0.3


def orientation_vote(exemplar):
    """``(angle, coherence)``: :func:`structure_orientation` and :func:`line_coherence` from one pass over the
    gradients."""
    from scipy import ndimage

    from ..color import luma

    lum = luma(exemplar, dtype=np.float64)  # (Rec. 709, as fitting._core._luma)
    gy = ndimage.sobel(lum, 0)
    gx = ndimage.sobel(lum, 1)
    r2 = gx * gx + gy * gy
    t = 4.0 * np.arctan2(gy, gx)
    vy, vx, total = float(np.sum(r2 * np.sin(t))), float(np.sum(r2 * np.cos(t))), float(np.sum(r2))
    return math.degrees(math.atan2(vy, vx)) / 4.0, (math.hypot(vy, vx) / total if total > 0.0 else 0.0)


def _shift_correlation(image, axis):
    """The correlation of ``image`` (``(h, w, c)``, mean removed) with itself shifted by each whole lag along
    ``axis``, over the overlap only (no wrap): an array over lags 0 to half the side."""
    n = image.shape[axis]
    x = np.moveaxis(image, axis, 0).reshape(n, -1)
    spectrum = np.fft.rfft(x, n=2 * n, axis=0)
    products = np.fft.irfft(spectrum * np.conj(spectrum), n=2 * n, axis=0)[: n // 2 + 1].sum(axis=1)
    energy = np.concatenate([[0.0], np.cumsum((x * x).sum(axis=1))])
    lags = np.arange(n // 2 + 1)
    head = energy[n - lags]  # rows 0 .. n - lag - 1
    tail = energy[n] - energy[lags]  # rows lag .. n - 1
    return products / np.sqrt(np.maximum(head * tail, 1e-30))


def lag_correlation(level, axis, lag):
    """The correlation of ``level`` (a 2-D array, mean removed) with itself shifted by ``lag`` whole pixels
    along ``axis``, over the overlap: :func:`_shift_correlation`'s value at one lag, summed directly in blocks of
    rows, so that a large photo needs no copy of itself (the FFT reads every lag of a preview; this, a few of
    the photo's own)."""
    x = level if axis == 0 else level.T
    n = x.shape[0]
    ab = aa = bb = 0.0
    for r in range(0, n - lag, 256):
        a = x[r:min(r + 256, n - lag)].astype(np.float64)
        b = x[r + lag:min(r + 256, n - lag) + lag].astype(np.float64)
        ab, aa, bb = ab + float(np.sum(a * b)), aa + float(np.sum(a * a)), bb + float(np.sum(b * b))
    return ab / max(math.sqrt(aa * bb), 1e-30)


def repeat_cell(image, *, min_lag: int = 4, threshold: float | None = None):
    """The photo's exact repeat along each axis: ``((lag_y, lag_x), (corr_y, corr_x))``, a lag None where the
    photo does not repeat along that axis.

    A texture tiled before it was saved (two by two, three by three, a strip of copies) holds only one cell
    of content: its copies add nothing. Along each axis the shortest whole lag from ``min_lag`` to half the
    side at which the photo matches itself shifted (every channel, over the overlap only) with correlation
    :data:`REPEAT_EXACT` or more, as a local maximum :data:`REPEAT_DIP` above the lowest correlation at a
    shorter lag, is the repeat. Photographed structure does not repeat that exactly; a pattern drawn on
    a computer (a grid, a tile floor) does, at its own period, which the caller tells apart by the cell's
    size and content. A repeat at a fraction of a pixel (a tiled texture resampled) is read only as far as
    the nearest whole lag matches; ``threshold`` (default :data:`REPEAT_EXACT`) lower reads candidates (on a
    preview, a whole photo's repeat falls between its pixels) for the caller to confirm.
    """
    least = REPEAT_EXACT if threshold is None else float(threshold)
    x = np.asarray(image, dtype=np.float64)
    if x.ndim == 2:
        x = x[:, :, None]
    x = x - x.reshape(-1, x.shape[2]).mean(axis=0)
    lags, scores = [], []
    for axis in (0, 1):
        c = _shift_correlation(x, axis)
        found = None
        for lag in range(max(min_lag, 1), len(c) - 1):
            if c[lag] >= least and c[lag] >= c[lag - 1] and c[lag] >= c[lag + 1] \
                    and c[1:lag].min() <= c[lag] - REPEAT_DIP:
                found = lag
                break
        if found is None and len(c) > 2 and c[-1] >= least and c[1:-1].min() <= c[-1] - REPEAT_DIP:
            found = len(c) - 1  # two copies exactly: the repeat at half the side, the last lag read
        lags.append(found)
        scores.append(None if found is None else float(c[found]))
    return tuple(lags), tuple(scores)
