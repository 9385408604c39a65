"""The fit's shared pieces: constants, exemplar preparation, the fitting problem, the results."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._pixels import box_halved
from .._results import AsDict
from .._validate import check_float, check_image, check_int
from ..analysis import cross_scale
from ..color import luma
from ..render.cpu import bake

#: Smallest exemplar side: two octave bands of 4 cycles and the cross-scale pairs need 32 pixels.
MIN_SIZE = 32
#: Larger exemplars are analysed on a centre crop of this many pixels a side (the pixel scale is kept).
MAX_ANALYSIS_SIZE = 512
#: Most power per octave the continuation may gain towards coarser scales (dB per octave).
MAX_COARSE_SLOPE = -1.5
#: Far-away bake regions used by the fit, in units of the second coarse layer's size.
_FAR = ((0.618, 0.382), (-1.357, 2.113), (3.141, -0.577), (-2.718, -1.414), (1.732, -3.606))
#: An exemplar whose fine detail repeats by itself (its :func:`spectex.metrics.repeat_peak`)
#: at least this much is *structured* (bricks, tiles, lines): ``tiling="auto"`` keeps its
#: finest layer periodic, because tiling and blending would blur the structure. Between the
#: unstructured photos' highest (0.11, moon's 128 x 128 corner) and brick's lowest (0.18).
STRUCTURED_PEAK = 0.15
#: Band and mean steps on the stochastic texture's bakes, and the regions they are measured on
#: (the exemplar's place and every far one of ``_FAR``). A stochastic texture's coarse layers show
#: a different part of the tile in each region, so a photo with large objects (moon's craters)
#: gives regions whose fine bands differ by several dB; 4 regions left moon's bake 2.2 dB off
#: (its fine bands 3 dB too strong), 6 bring it to 1.0-1.1 dB at any place (docs/fitting.md).
STOCHASTIC_ROUNDS = 2
STOCHASTIC_REGIONS = 6
#: The fit's tiling choices (see :func:`fit`).
FIT_TILINGS = ("auto", "stochastic", "periodic")
#: The fit's methods: ``"auto"`` (the default, issue 22's design) and ``"legacy"`` (the fit before it,
#: kept only so that ``benchmarks/bench_fit_quality.py`` can compare; not for new work).
FIT_METHODS = ("auto", "legacy")


#: The seamless crop is kept while the structural distance between it and the photo (the measure's
#: ratio to the photo's own floor) is at most this: a crop as close to the photo as the photo is to
#: itself. Beyond it (the smooth correction took up steps all along the wrap edges: a wood grain's
#: stripes meeting out of phase, 1.9 on benchmarks/exemplars.py's wood, where scikit-image's gravel,
#: grass, the tissue and the ripples read 0.79-0.85 and the photo against itself 0.75), a tileable quilt
#: is made too, and the closer of the two is the tile.
SEAMLESS_LIMIT = 1.0
#: The fewest pixels a side for that check (two windows of the measure).
SEAMLESS_CHECK_MIN = 128


def finest_tile(exemplar, tile_size, rng, *, reuse: float = 0.0, check: bool = False):
    """The photo's tile for the finest layer: ``(tile, n, how)``.

    ``tile_size`` (None: the photo's shorter side, or four times it up to
    512) is checked; a tile no larger than the photo is its seamless crop,
    a larger one a tileable quilt (block a quarter of the photo, 16 to 64)
    with the reuse penalty ``reuse``. ``how`` says which, for the report.
    With ``check``, a seamless crop further from the photo than
    :data:`SEAMLESS_LIMIT` by the structural distance is weighed against a
    tileable quilt of the same size, and the closer is the tile.
    """
    from ..tiles import make_seamless

    h, w = exemplar.shape[:2]
    if tile_size is None:
        tile_size = max(min(h, w), min(512, 4 * min(h, w)))
    n = check_int("tile_size", tile_size, minimum=MIN_SIZE, maximum=4096)
    if n <= min(h, w):
        crop = make_seamless(exemplar, shape=(n, n))[:, :, :3].astype(np.float64)
        if not check or n < SEAMLESS_CHECK_MIN:
            return crop, n, "seamless crop"
        from ..metrics import reference_statistics, structural_distance

        y0, x0 = (h - n) // 2, (w - n) // 2  # the crop's place in the photo (make_seamless's central crop)
        region = exemplar[y0:y0 + n, x0:x0 + n]
        prepared = reference_statistics(region)
        near = structural_distance(crop, region, prepared=prepared).ratio
        if near <= SEAMLESS_LIMIT:
            return crop, n, "seamless crop"
        quilted, how = _quilted(exemplar, n, rng, reuse)
        other = structural_distance(quilted, region, prepared=prepared).ratio
        if other < near:
            return quilted, n, (f"{how}: the seamless crop's correction along its wrap edges moved the photo's "
                                f"statistics (structure {near:.2f}x the photo's floor, the quilt {other:.2f}x)")
        return crop, n, "seamless crop"
    tile, how = _quilted(exemplar, n, rng, reuse)
    return tile, n, how


def _quilted(exemplar, n, rng, reuse):
    """A tileable quilt of the photo, ``n x n`` (block a quarter of the photo, 16 to 64), and its words."""
    from ..synthesis import quilt

    block = int(np.clip(min(exemplar.shape[:2]) // 4, 16, 64))
    tile = quilt(exemplar, (n, n), block=block, tileable=True, rng=rng, reuse=reuse).astype(np.float64)
    return tile, f"tileable quilt (block {block}" + (f", reuse penalty {reuse:g})" if reuse else ")")


def prepare_exemplar(image, *, max_size: int = MAX_ANALYSIS_SIZE):
    """The exemplar as the fit uses it: RGB float32 in [0, 1], at most ``max_size`` a side.

    Documented conversions: integers are scaled by their dtype's maximum
    (16-bit keeps its precision); grey is repeated into R, G and B; an alpha
    channel (grey + alpha, RGBA) is dropped; a flat frame around the photo
    (a border, letterboxing, the wedges of a rotated photo: ``_frame.py``) is
    cropped away, since every patch of the texture would repeat it; a photo
    that repeats itself exactly (a texture tiled before it was saved:
    ``_one_repeat``) is cut to its top left cell; a
    structured photo over ``max_size`` on both sides whose ``max_size`` crop
    would hold fewer than :data:`MIN_TILE_PERIODS` of its structure's periods
    (floor tiles, paving stones photographed at high resolution; the period
    read on the photo resampled to a shorter side of twice ``max_size``) is
    area-averaged (a box filter) until it holds that many, and no further; any
    other photo over ``max_size`` on both sides whose crop would hold fewer than
    :data:`MIN_TILE_GRAINS` of its grain (:func:`spectex.spectrum.correlation_length`:
    gravel, pebbles or cobbles photographed at high resolution, a crop of a few
    stones that the texture would repeat as landmarks) likewise, up to the whole
    photo's shorter side, and so is one whose spectrum beyond the crop rises
    :data:`COARSE_EXCESS_DB` over the coarsest band the crop holds (large
    features over a fine grain: a beach's ripples, which the coarse layers,
    continuing the crop's spectrum, cannot draw) until the crop holds that
    band (a photo of fine grain and nothing larger keeps its full resolution:
    its detail is what a crop keeps); :func:`exemplar_scale` gives the factor, which the fit's pixel size
    includes; then a side over ``max_size`` is cropped about its centre to
    ``max_size`` (cropping, not downscaling, keeps the detail); float values
    outside [0, 1] are clipped.

    Returns
    -------
    exemplar : ndarray, shape (h, w, 3), float32
    notes : list of str
        One line per conversion made (empty if none).

    Raises
    ------
    ValueError
        For an image under 32 pixels on a side (before or after its frame is
        cropped), or a flat one (luma standard deviation under half an 8-bit
        step).
    """
    rgb, notes, _ = _prepared(image, max_size)
    return rgb, notes


def exemplar_scale(image, *, max_size: int = MAX_ANALYSIS_SIZE) -> float:
    """Photo pixels per pixel of :func:`prepare_exemplar`'s exemplar (1 where it was not resampled): a
    pixel size given for the photo times this is the exemplar's."""
    return _prepared(image, max_size)[2]


def _prepared(image, max_size):
    """:func:`prepare_exemplar`'s exemplar and notes, and the photo pixels per exemplar pixel."""
    return _prepared_with_source(image, max_size)[:3]


def _prepared_with_source(image, max_size):
    """:func:`_prepared`'s three and, for a resampled photo, where the exemplar lies in it: ``{"photo": the
    photo at full resolution (RGB float32, its frame cropped), "step": (photo pixels per exemplar pixel
    along y, along x), "origin": (y, x) of the exemplar's corner in the resampled photo}`` (None at 1)."""
    image = check_image("image", image, channels=(None, 1, 2, 3, 4), unit=True)
    max_size = check_int("max_size", max_size, minimum=MIN_SIZE)
    h, w = image.shape[:2]
    notes = []
    if min(h, w) < MIN_SIZE:
        raise ValueError(f"image must be at least {MIN_SIZE}x{MIN_SIZE} pixels to fit a texture to, got {w}x{h}")
    nch = 1 if image.ndim == 2 else image.shape[2]
    if nch in (2, 4):
        notes.append("alpha channel dropped")
    if nch in (1, 2):
        grey = image if image.ndim == 2 else image[:, :, 0]
        rgb = np.repeat(grey[:, :, None], 3, axis=2)
        notes.append("grey repeated into RGB")
    else:
        rgb = image[:, :, :3]
    _check_not_flat(rgb)  # (before the frame: a flat picture is all frame)
    rgb, h, w = _without_frame(rgb, notes)
    repeat = _one_repeat(rgb, notes)
    if repeat is not None:
        rgb, repeat = repeat
        h, w = rgb.shape[:2]
    factor, why = _analysis_factor(rgb, max_size) if min(h, w) > max_size else (1.0, None)
    source = None
    if factor > 1.0:
        rh, rw = max(max_size, round(h / factor)), max(max_size, round(w / factor))
        source = {"photo": rgb, "step": (h / rh, w / rw), "origin": (0, 0)}
        rgb = _resampled(rgb, rh, rw)
        notes.append(f"resampled the {w}x{h} photo by 1/{factor:.4g} to {rw}x{rh} (a pixel {factor:.4g} photo "
                     f"pixels): {why.format(max_size=max_size)}, to keep its full resolution)")
        h, w = rh, rw
    if max(h, w) > max_size:
        th, tw = min(h, max_size), min(w, max_size)
        y0, x0 = (h - th) // 2, (w - tw) // 2
        rgb = rgb[y0:y0 + th, x0:x0 + tw]
        notes.append(f"analysed on the central {tw}x{th} crop of the {w}x{h} image")
        if source is not None:
            source["origin"] = (y0, x0)
    rgb = np.ascontiguousarray(np.clip(rgb, 0.0, 1.0), dtype=np.float32)
    _check_not_flat(rgb)
    return rgb, notes, factor, source, repeat


def _check_not_flat(rgb):
    """The spectral statistics are those of the luma: a picture without luma variation has none."""
    if float(np.std(_luma(rgb))) < 0.5 / 255.0:
        raise ValueError("image is flat (constant luminance, std under half an 8-bit step): "
                         "it has no texture to fit")


#: Fewest structure periods (bricks, floor tiles) along an axis the analysed photo must hold: a photo
#: over ``max_size`` whose full-resolution crop holds fewer is resampled until it holds this many
#: (a 2048-pixel floor of 256-pixel tiles: 2 in a 512 crop, no period found, grout cut to pieces;
#: a 3072-pixel one of 150-pixel tiles is resampled by 1/1.76, of 96-pixel ones by 1/1.13).
MIN_TILE_PERIODS = 6
#: Fewest grains (:func:`spectex.spectrum.correlation_length`, about a quarter of a stone's width) across
#: the analysed crop of a large photo without structure: one whose ``max_size`` crop at full resolution
#: holds fewer is resampled until it holds this many, or the whole photo's shorter side. A 2048-pixel photo
#: of gravel (a grain of 19 pixels, stones of about 90) cropped at full resolution held 27 grains, 6
#: stones across: its stochastic layer drew those few stones again and again, their shadows a pattern
#: that repeats in a view over several tiles; resampled by 1/4 (the whole photo: 4.8 wanted) it reads
#: as the photo. Fine grain keeps its full resolution (noise of 3.6 pixels, 144 in a crop).
MIN_TILE_GRAINS = 128
#: Least excess (dB) of a band of a large photo that its analysed crop does not hold (fewer than
#: :data:`COARSE_MIN_CYCLES` cycles across the crop) over the coarsest band the crop holds: a photo with
#: more power beyond the crop than at its edge has large features the crop cannot show and the coarse
#: layers, which continue its spectrum without gaining power, cannot draw (a beach's ripples 480 pixels
#: apart on a 2048-pixel photo, a fine grain: +10 dB, where 15 large photos of ground, rock and the
#: benchmarks' magnified photos read -3 to +3). Such a photo is resampled until the crop holds the band.
COARSE_EXCESS_DB = 6.0
#: Cycles across the analysed crop a band needs to be held (:func:`spectex.spectrum.band_power`'s
#: ``min_cycles``).
COARSE_MIN_CYCLES = 4
#: Least side (photo pixels, along each axis it repeats) of the cell of a photo that repeats itself exactly
#: (:func:`_one_repeat`): a shorter repeat is a pattern's own period, the structure's to cut and draw.
MIN_REPEAT_CELL = 64
#: Most of a repeat cell's variance at one or two cycles across the cell (:func:`_motif_share`) for the cell
#: to be read as a texture tiled: a pattern of one large motif per period (a window, a panel, a tile with a
#: border; 0.26-0.5 on a game's window, border and tile textures) keeps its period, drawn as structure.
#: Tiled ground (dirt, gravel, sand, cobbles, bricks, a carpet) reads 0.0-0.14 on 256-pixel cells.
REPEAT_MOTIF_SHARE = 0.2
#: A photo that repeats exactly but whose structure's period is under this fraction of the repeat keeps the whole
#: photo (:func:`_one_repeat`): a structure's tile is cut at its own period, where the copies do no harm.
REPEAT_FINER = 0.75
#: Shorter side of the preview a photo's repeat is read on (:func:`_one_repeat`; the photo itself where smaller).
REPEAT_PREVIEW = 512


def _motif_share(cell):
    """The share of ``cell``'s luma variance (the cell taken as seamless) at spatial frequencies of at most two
    cycles across it: near 0 for texture finer than the cell, large for one motif filling it."""
    level = np.asarray(cell, dtype=np.float64).mean(axis=2)
    power = np.abs(np.fft.fft2(level - level.mean())) ** 2
    power[0, 0] = 0.0
    ky = np.fft.fftfreq(level.shape[0]) * level.shape[0]
    kx = np.fft.fftfreq(level.shape[1]) * level.shape[1]
    low = np.hypot(ky[:, None], kx[None, :]) <= 2.0
    total = float(power.sum())
    return 0.0 if total <= 0.0 else float(power[low].sum()) / total


def _one_repeat(rgb, notes):
    """A photo that repeats itself exactly (``_structure.repeat_cell``: a texture tiled two by two, three by
    three, or a strip of copies, before it was saved) read as one cell of it, the top left one (at the
    photo's corner, so that its places are the photo's): ``(cell, record)``; None where the photo does not
    repeat, or repeats at a pattern's own period (a cell shorter than :data:`MIN_REPEAT_CELL`, or one motif
    per cell: :data:`REPEAT_MOTIF_SHARE`). A structure finer than the repeat (:data:`REPEAT_FINER`) keeps
    the whole photo, its record's ``"whole"`` True, so that the trial does not take the tiling for the
    photo's own repeat.

    Its copies add no content. Drawn from the whole photo, every patch of a stochastic layer carried them
    (the same stones twice, a cell apart), and a structured way cut at the repeat as a period drew it as one
    (repeat 0.83 over a bake of a dirt photo tiled three by three). The repeat is read on a preview of
    shorter side :data:`REPEAT_PREVIEW` (a 2048-pixel photo of two copies: its analysed crop would hold
    less than two; a lag of ``_structure.REPEAT_CANDIDATE`` there is a candidate, its repeat falling between
    the preview's pixels) and confirmed on the photo's luma at the best whole lag within a preview pixel of
    it."""
    from ._structure import REPEAT_CANDIDATE, REPEAT_EXACT, lag_correlation, repeat_cell, structure_period

    h, w = rgb.shape[:2]
    step = min(h, w) / min(min(h, w), REPEAT_PREVIEW)
    preview = rgb if step == 1.0 else np.clip(_resampled(rgb, round(h / step), round(w / step)), 0.0, 1.0)
    lags, scores = repeat_cell(preview, threshold=None if step == 1.0 else min(REPEAT_CANDIDATE, REPEAT_EXACT))
    if lags == (None, None) or any(lag is not None and lag * step < MIN_REPEAT_CELL for lag in lags):
        return None
    cell = preview[:lags[0] or preview.shape[0], :lags[1] or preview.shape[1]]
    share = _motif_share(cell)
    if share > REPEAT_MOTIF_SHARE:
        return None
    period = structure_period(preview) if structure_peak(preview) >= STRUCTURED_PEAK else None
    finer = period is not None and any(q is not None and lag is not None and q < REPEAT_FINER * lag
                                       for q, lag in zip(period, lags))
    if step > 1.0:
        # the lag in photo pixels: the whole one within a preview pixel of the preview's that matches best, and
        # exactly
        level = rgb.mean(axis=2, dtype=np.float32)
        level -= level.mean()
        found = []
        for axis, lag in enumerate(lags):
            if lag is None:
                found.append((None, None))
                continue
            near = [k for k in range(math.floor((lag - 0.5) * step) - 1, math.ceil((lag + 0.5) * step) + 2)
                    if 1 <= k <= rgb.shape[axis] // 2]
            found.append(max(((k, lag_correlation(level, axis, k)) for k in near), key=lambda kc: kc[1]))
        if any(c is not None and c < REPEAT_EXACT for _, c in found):
            return None
        lags, scores = tuple(k for k, _ in found), tuple(c for _, c in found)
    cy, cx = lags[0] or h, lags[1] or w
    along = " and ".join(f"every {lag} px along {axis}" for lag, axis in zip(lags, "yx") if lag is not None)
    record = {"lags": list(lags), "correlation": [None if v is None else round(v, 4) for v in scores],
              "cell": [cy, cx], "motif_share": round(share, 3), "whole": finer}
    said = f"the photo repeats itself exactly ({along}; correlation {min(v for v in scores if v is not None):.3f})"
    if finer:
        # a structure finer than the repeat (a wall of bricks tiled): its tile is cut at whole periods of the
        # whole photo, whose wrap edges it chooses among more places than one cell offers (a tiled wall's cell
        # of three courses read alone gave a tile of two, short bricks where its courses were cut to fit); the
        # repeat is the tiling's, not the texture's, and the fit's trial is told so
        notes.append(f"{said}: its structure is finer, and the fit reads the whole photo, the repeat taken for a "
                     "tiling the texture need not show")
        return rgb, record
    notes.append(f"{said}: the fit reads one repeat of it, its top left {cx}x{cy} pixels; the copies hold nothing "
                 "more, and read as content the texture would repeat them")
    return rgb[:cy, :cx], record


def _analysis_factor(rgb, max_size):
    """Photo pixels per analysed pixel for a photo over ``max_size`` on both sides, and why (a clause of the
    note, ``{max_size}`` in it to be filled; None at 1): 1 (a crop at full resolution, its detail kept)
    unless a ``max_size`` crop would hold too little of the photo, and then just enough to hold it, at
    most the factor that shows the whole photo's shorter side. Both read on the photo resampled to a
    shorter side of ``2 max_size``:

    * a structured photo: its structure's period, of which the crop must hold :data:`MIN_TILE_PERIODS`;
    * any other: its grain (:func:`spectex.spectrum.correlation_length`), of which the crop must hold
      :data:`MIN_TILE_GRAINS`; and its large features (:func:`_coarse_content`): a band of its spectrum
      beyond that crop (fewer than :data:`COARSE_MIN_CYCLES` cycles across it) :data:`COARSE_EXCESS_DB`
      over the coarsest band the crop holds (a beach's ripples over a fine grain) is held too.
    """
    from ..spectrum import correlation_length
    from ._structure import structure_period

    h, w = rgb.shape[:2]
    whole = min(h, w) / max_size  # the factor that shows the whole photo's shorter side
    # read at twice that size where the photo has it, so that periods down to 12 pixels of the whole
    # photo's view are seen (repeat_peak starts at a lag of 24)
    side = min(min(h, w), 2 * max_size)
    step = min(h, w) / side
    preview = np.clip(_resampled(rgb, round(h / step), round(w / step)), 0.0, 1.0)
    periods = []
    if structure_peak(preview) >= STRUCTURED_PEAK:
        periods = [p for p in (structure_period(preview) or (None, None)) if p is not None]
    if periods:
        period = max(periods) * step
        factor = float(np.clip(MIN_TILE_PERIODS * period / max_size, 1.0, whole))
        return factor, (f"its structure repeats every {period:.0f} photo pixels, and the {{max_size}}-pixel tile "
                        f"must hold {MIN_TILE_PERIODS} periods to keep it (crop the photo to fewer periods, or pass "
                        "max_size= / --max-size")
    grain = correlation_length(preview) * step
    factor = float(np.clip(MIN_TILE_GRAINS * grain / max_size, 1.0, whole))
    coarse = _coarse_content(preview, step, max_size, factor)
    if coarse is not None and coarse[0] > factor:
        wanted, low, high, excess = coarse
        return float(min(wanted, whole)), (
            f"it has features of {low:.0f}-{high:.0f} photo pixels ({excess:.0f} dB over the finest scales a "
            f"crop of the photo at full resolution holds), and the {{max_size}}-pixel tile must hold "
            f"{COARSE_MIN_CYCLES} of them, or its texture has none (pass max_size= / --max-size")
    if factor <= 1.0:
        return 1.0, None
    return factor, (f"its grain is {grain:.0f} photo pixels (its correlation length), and the {{max_size}}-pixel "
                    f"tile must hold {MIN_TILE_GRAINS} of them, or its stones and marks repeat as landmarks in a "
                    "view over several tiles (pass max_size= / --max-size")


def _coarse_content(preview, step, max_size, factor):
    """Large features a crop of the photo would not hold: ``(factor, low, high, excess)``, the photo pixels per
    analysed pixel whose crop holds the coarsest band of ``preview`` (the photo resampled by ``1 / step``)
    beyond a crop at ``factor`` that is :data:`COARSE_EXCESS_DB` over the coarsest band that crop holds, the
    band's wavelengths in photo pixels and its excess (dB); None where no band is."""
    from ..spectrum import band_power

    bands, power = band_power(preview, min_cycles=COARSE_MIN_CYCLES)
    crop = max_size * factor / step  # the crop's side, preview pixels
    held = np.flatnonzero(crop * bands[:, 0] >= COARSE_MIN_CYCLES)
    if held.size == 0 or held[-1] + 1 >= len(power):
        return None
    edge = float(power[held[-1]])
    beyond = np.arange(held[-1] + 1, len(power))
    over = beyond[power[beyond] - edge >= COARSE_EXCESS_DB]
    if over.size == 0:
        return None
    k = int(over[-1])
    wanted = COARSE_MIN_CYCLES / bands[k, 0] * step / max_size
    return wanted, step / bands[k, 1], step / bands[k, 0], float(power[k] - edge)


def _resampled(rgb, h, w):
    """``rgb`` resampled to ``h x w`` (area-averaged: no ringing by the grout lines, where Lanczos left
    light specks in the tiles; each channel in float32)."""
    from PIL import Image

    return resized(rgb, (h, w), Image.Resampling.BOX)


def resized(image, shape, how, box=None):
    """``image`` (h, w, c) resampled to ``shape`` (rows, columns) by PIL's filter ``how``, each channel in
    float32; ``box`` (left, top, right, bottom): the part read, in fractional pixels (all by default)."""
    from PIL import Image

    return np.stack([np.asarray(Image.fromarray(np.ascontiguousarray(image[:, :, c], dtype=np.float32))
                                .resize((shape[1], shape[0]), how, box=box), dtype=np.float32)
                     for c in range(image.shape[2])], axis=2)


def cubic_at(image, ys, xs):
    """``image`` (h, w, c) read at photo places ``(ys, xs)`` (pixel centres at whole numbers; places off
    the photo read its edge) by a cubic spline, each value held within the 2 x 2 pixels around its place.

    The spline keeps a resampled photo's grain sharp, but rings by a sharp edge: a floor tile resampled
    from 85.13 to 85 pixels a period by the spline alone had a dark line before its light grout, a light
    one after, and the grout 0.02 lighter than the photo's (its profile across the grout, 6 periods
    folded: 0.451 / 0.780 against the photo's 0.467 / 0.757). Held to the pixels it lies between, a value
    cannot overshoot an edge; in smooth or grainy parts the spline's value lies there anyway, nearly.
    """
    from scipy import ndimage

    h, w = image.shape[:2]
    ys, xs = np.asarray(ys, np.float64), np.asarray(xs, np.float64)
    y0 = np.clip(np.floor(ys), 0, h - 1).astype(np.intp)
    x0 = np.clip(np.floor(xs), 0, w - 1).astype(np.intp)
    y1, x1 = np.minimum(y0 + 1, h - 1), np.minimum(x0 + 1, w - 1)
    y1 = np.where(ys < 0, y0, y1)
    x1 = np.where(xs < 0, x0, x1)
    out = np.empty(ys.shape + (image.shape[2],), np.float64)
    for c in range(image.shape[2]):
        plane = np.asarray(image[:, :, c], np.float64)
        v = ndimage.map_coordinates(plane, [ys, xs], order=3, mode="nearest")
        corners = (plane[y0, x0], plane[y0, x1], plane[y1, x0], plane[y1, x1])
        out[..., c] = np.clip(v, np.minimum.reduce(corners), np.maximum.reduce(corners))
    return out


def _without_frame(rgb, notes):
    """``rgb`` without its flat frame (``_frame.frame_box``), said in ``notes``: ``(rgb, h, w)``."""
    from ._frame import frame_box

    h, w = rgb.shape[:2]
    box = frame_box(rgb)  # (check_image has held it to [0, 1])
    if box is None:
        return rgb, h, w
    y0, y1, x0, x1 = box
    if min(y1 - y0, x1 - x0) < MIN_SIZE:
        raise ValueError(f"image is mostly a flat frame: without it {x1 - x0}x{y1 - y0} pixels of the {w}x{h} "
                         f"are left, under the {MIN_SIZE}x{MIN_SIZE} a fit needs")
    notes.append(f"left out a flat frame around the photo (top {y0}, bottom {h - y1}, left {x0}, right {w - x1} px: "
                 "one colour along its edge, which every patch of the texture would repeat as a bar); "
                 f"fitted to the {x1 - x0}x{y1 - y0} inside")
    return rgb[y0:y1, x0:x1], y1 - y0, x1 - x0


# --------------------------------------------------------------------------
# The pieces
# --------------------------------------------------------------------------

def _luma(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luma (:func:`spectex.color.luma`) in float64."""
    return luma(rgb, dtype=np.float64)


def _band_axis(n_rows: int, n_cols: int) -> np.ndarray:
    """``-log2`` of the radial frequency (cycles per pixel) of an FFT grid; band k's centre is k + 1.5."""
    fy = np.fft.fftfreq(n_rows)[:, None]
    fx = np.fft.fftfreq(n_cols)[None, :]
    r = np.hypot(fy, fx)
    r[0, 0] = 1e-9
    return -np.log2(r)


def _shape_spectrum(tile_rgb: np.ndarray, gains_db: np.ndarray) -> np.ndarray:
    """Filter each channel by a radial gain, piecewise linear in dB against log frequency.

    ``gains_db[k]`` is the gain at the centre of octave band ``k`` (``2^-(k+1.5)``
    cycles per pixel), held beyond the first and last centres. Periodic (FFT),
    so a seamless tile stays seamless; the mean colour is kept.
    """
    h, w = tile_rgb.shape[:2]
    x = _band_axis(h, w)
    centres = np.arange(len(gains_db)) + 1.5
    import scipy.fft as sfft

    gain = 10.0 ** (np.interp(x[:, : w // 2 + 1], centres, gains_db) / 20.0)
    gain[0, 0] = 1.0
    spec = sfft.rfft2(tile_rgb.astype(np.float32), axes=(0, 1), workers=2)
    spec *= gain[:, :, None].astype(np.float32)
    return sfft.irfft2(spec, s=(h, w), axes=(0, 1), workers=2).astype(np.float64)


def _quantile_map(values: np.ndarray, target_sorted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A monotone map (knots x -> y) taking the distribution of ``values`` to the target's."""
    q = np.linspace(0.0, 1.0, 257)
    xs = np.quantile(values, q)
    ys = np.quantile(target_sorted, q)
    xs, idx = np.unique(xs, return_index=True)
    return xs, ys[idx]


def _alpha_field(tile_rgb: np.ndarray) -> np.ndarray:
    """Standardised luma of the tile, band-passed (periodic): the alpha's shape.

    Smoothed by a Gaussian of 1 texel (no pixel noise in the alpha) and with
    the tile's coarsest structure (a Gaussian of 1/16 of the tile) removed,
    so that the first coarse layer's alpha varies within an exemplar-sized
    region instead of shifting whole regions' detail up or down.
    """
    from scipy import ndimage

    lum = _luma(tile_rgb)
    z = ndimage.gaussian_filter(lum, 1.0, mode="wrap")
    z -= ndimage.gaussian_filter(lum, max(1.0, lum.shape[0] / 16.0), mode="wrap")
    z -= z.mean()
    s = z.std()
    return z / s if s > 0 else z


def _alpha(z: np.ndarray, gain: float) -> np.ndarray:
    """Alpha = 0.5 + gain z / 4, clipped: gain > 0 hides the finer layers where the coarse one is bright."""
    return np.clip(0.5 + 0.25 * gain * z, 0.0, 1.0)


def structure_peak(exemplar) -> float:
    """How much the exemplar's own fine detail repeats: :func:`spectex.metrics.repeat_peak` of it.

    ``min_lag`` is 24 pixels, less for exemplars under 48 pixels (half the
    shorter side). At least :data:`STRUCTURED_PEAK` (0.15) marks a
    structured texture. scikit-image's pictures: brick 0.18 (whole) and
    0.45 (128 x 128 corner); grass, gravel, moon, immunohistochemistry 0.02
    to 0.06 whole and 0.05 to 0.11 as 128 x 128 corners (a small picture's
    noise floor is higher: about ``sqrt(2 ln N / N)``, 0.03 for N = 128^2).
    """
    from ..metrics import repeat_peak

    h, w = exemplar.shape[:2]
    peak = repeat_peak(exemplar, min_lag=min(24, min(h, w) // 2))
    return 0.0 if not np.isfinite(peak) else float(peak)


def _with_tilings(layer_list, tilings, patch):
    from ..texture import Layer

    return [Layer(size=lay.size, offset=lay.offset, rotation=lay.rotation, opacity=lay.opacity, tiling=t,
                  patch=patch, seed=k if t == "stochastic" else 0)
            for k, (lay, t) in enumerate(zip(layer_list, tilings))]


def _layers(n_layers: int, ratio: float, tile_px: int, pixel_size: float, opacity: float):
    from ..texture import Layer, layer_placement

    finest = tile_px * pixel_size
    out = []
    for k in range(n_layers):
        size = finest * ratio ** k
        offset, rotation = layer_placement(k, size, decimals=9)
        out.append(Layer(size=size, offset=offset, rotation=rotation, opacity=1.0 if k == 0 else opacity))
    return out


@dataclass
class FitResult:
    """A fitted texture and the numbers of its fit (see :func:`fit_report`)."""

    texture: object
    exemplar: np.ndarray = field(repr=False)  #: the photo as analysed (:func:`prepare_exemplar`)
    pixel_size: float = 1.0  #: metres per pixel of ``exemplar`` (the photo's times :func:`exemplar_scale`)
    notes: list = field(default_factory=list)
    params: dict = field(default_factory=dict)
    seconds: float = 0.0


class _Problem:
    """The exemplar's targets and the fast evaluation of a candidate tile (small bakes)."""

    def __init__(self, exemplar, pixel_size, layer_list, tile_px, ratio, segment, n_regions=3,
                 continuation=None):
        from ..metrics import band_power

        self.exemplar = exemplar
        self.p = pixel_size
        self.layers = layer_list
        self.segment = segment
        # small exemplars: regions of twice the size (Welch segments of the exemplar's size)
        self.region = tuple(2 * s if max(segment) <= 128 else s for s in segment)
        self.target_bands = band_power(exemplar, segment=segment)[1]
        # An exemplar larger than the segment holds coarser bands than a segment sees:
        # those are measured on a bake at twice the pixel size (mip-filtered) against
        # the exemplar reduced 2 x 2, whose band k is the exemplar's band k + 1.
        self.coarse = None
        h, w = exemplar.shape[:2]
        if min(h, w) > min(segment) and min(h, w) // 2 >= 32:
            half = box_halved(exemplar).astype(exemplar.dtype, copy=False)
            seg2 = (min(h // 2, 256), min(w // 2, 256))
            full = band_power(exemplar)[1]
            extra = len(full) - len(self.target_bands)
            if extra > 0:
                t2 = band_power(half, segment=seg2)[1]
                self.coarse = (seg2, t2[len(t2) - extra:], extra)
                self.target_bands = np.concatenate([self.target_bands, full[len(full) - extra:]])
        # Continuation: two bands beyond the exemplar's coarsest, on the line of slope
        # ``continuation`` dB per octave, measured on a 128 x 128 bake at 2^m times the
        # pixel size whose bands 2 and 3 are those bands.
        self.cont = None
        if continuation is not None:
            k_full = len(self.target_bands)
            m = max(k_full - 2, 1)
            last = self.target_bands[-1]
            self.cont = (2.0 ** m, np.array([last + continuation, last + 2 * continuation]), k_full - m)
            self.target_bands = np.concatenate([self.target_bands, self.cont[1]])
        self.target_sorted = [np.sort(exemplar[:, :, c].ravel()) for c in range(3)]
        target = cross_scale(exemplar)
        self.target_cross, self.fine = target.value, target.fine
        self.set_regions(n_regions, tile_px=tile_px, ratio=ratio)

    def set_regions(self, n_regions, *, tile_px, ratio):
        """Regions on the pixel grid (layer 0 sampled at its texel centres): the exemplar's own
        place and ``n_regions - 1`` far away in the coarse layers."""
        self.origins = [(0.0, 0.0)] + [(round(tile_px * ratio ** 2 * fx) * self.p,
                                          round(tile_px * ratio ** 2 * fy) * self.p)
                                         for fx, fy in _FAR[:n_regions - 1]]

    def texture(self, colour, alpha):
        from ..texture import SpectralTexture

        rgba = np.empty(colour.shape[:2] + (4,), dtype=np.float32)
        rgba[:, :, :3] = np.clip(colour, 0.0, 1.0)
        rgba[:, :, 3] = alpha
        return SpectralTexture(rgba, self.layers)

    def bakes(self, colour, alpha, *, extra=True):
        """Bakes of the regions at the pixel size, then (``extra``) the coarser ones for the bands."""
        tex = self.texture(colour, alpha)
        out = [bake(tex, self.region, origin=o, pixel_size=self.p) for o in self.origins]
        if not extra:
            return out
        if self.coarse is not None:
            out.append(bake(tex, self.coarse[0], pixel_size=2.0 * self.p))
        if self.cont is not None:
            out.append(bake(tex, (128, 128), pixel_size=self.cont[0] * self.p))
        return out

    def fine_bakes(self, bakes):
        return bakes[:len(self.origins)]

    def band_error(self, bakes):
        from ..metrics import band_power

        fine = self.fine_bakes(bakes)
        power = np.mean([10.0 ** (band_power(b, segment=self.segment)[1] / 10.0) for b in fine], axis=0)
        db = 10.0 * np.log10(np.maximum(power, 1e-20))
        err = self.target_bands[:len(db)] - db
        if self.coarse is not None:
            seg2, target2, extra = self.coarse
            p2 = band_power(bakes[len(self.origins)], segment=seg2)[1]
            err = np.concatenate([err, target2 - p2[len(p2) - extra:]])
        if self.cont is not None:
            _, target_c, first = self.cont
            pc = band_power(bakes[-1])[1]
            err = np.concatenate([err, target_c - pc[first:first + 2]])
        return err

    def bakes_first(self, colour, alpha):
        """The exemplar's own region only (for the alpha-gain search)."""
        tex = self.texture(colour, alpha)
        return [bake(tex, self.region, origin=self.origins[0], pixel_size=self.p)]

    def cross(self, bakes):
        return float(np.mean([cross_scale(b, fine=self.fine).value for b in self.fine_bakes(bakes)]))

    def histogram_step(self, colour, bakes, *, shift_only=False):
        """Map the tile's channels so that the bakes' histograms become the exemplar's."""
        out = np.empty_like(colour)
        if shift_only:
            # the means only (the band step sets the contrast; a full match here would undo it)
            for c in range(3):
                vals = np.concatenate([b[:, :, c].ravel() for b in self.fine_bakes(bakes)]).astype(np.float64)
                t = self.target_sorted[c]
                out[:, :, c] = colour[:, :, c] + (t.mean() - vals.mean())
            return np.clip(out, 0.0, 1.0)
        for c in range(3):
            vals = np.concatenate([b[:, :, c].ravel() for b in self.fine_bakes(bakes)])
            xs, ys = _quantile_map(vals, self.target_sorted[c])
            out[:, :, c] = np.interp(colour[:, :, c], xs, ys, left=None, right=None)
            # beyond the bake's range, continue with unit slope (keeps the tile's extremes ordered)
            lo, hi = colour[:, :, c] < xs[0], colour[:, :, c] > xs[-1]
            out[:, :, c][lo] = ys[0] + (colour[:, :, c][lo] - xs[0])
            out[:, :, c][hi] = ys[-1] + (colour[:, :, c][hi] - xs[-1])
        return np.clip(out, 0.0, 1.0)


def _coarse_slope(power_db: np.ndarray) -> float:
    """dB per octave over the exemplar's three coarsest bands (towards coarser)."""
    tail = power_db[-3:]
    return float(np.polyfit(np.arange(len(tail), dtype=np.float64), tail, 1)[0])


def _pick_gain(gains, values, target) -> float:
    """The alpha gain whose coupling is nearest the target, refined linearly between grid points."""
    values = np.asarray(values)
    err = values - target
    best = int(np.argmin(np.abs(err)))
    for j in (best - 1, best):
        if 0 <= j < len(gains) - 1 and err[j] * err[j + 1] <= 0 and err[j] != err[j + 1]:
            t = err[j] / (err[j] - err[j + 1])
            return float(gains[j] + t * (gains[j + 1] - gains[j]))
    return float(gains[best])



@dataclass(frozen=True, eq=False)
class FitReport(AsDict):
    """The numbers of :func:`fit_report`."""

    bake_shape: tuple                  #: (H, W) of the bake compared
    band_power_distance_db: float      #: RMS over the exemplar's bands, dB
    band_power_exemplar_db: np.ndarray
    band_power_texture_db: np.ndarray
    histogram_w1: np.ndarray           #: per channel
    cross_scale_exemplar: float
    cross_scale_texture: float
    amplitude_exemplar: float
    amplitude_texture: float
    #: :func:`spectex.metrics.structural_distance` of the bake's exemplar-sized corner (the
    #: photo's own place) to the exemplar: ``ratio`` about 1 is as close as the photo is to itself
    structure: object = None
    #: the same over the whole bake (windows spread over it: every part of the texture, not one)
    structure_far: object = None
    #: :func:`spectex.metrics.clipping` of the bake against the exemplar (its own + 1 point)
    clipping: object = None
    #: :func:`spectex.metrics.coarse_copies` on a view at ``coarse_zoom`` times the pixel size
    coarse: object = None
    #: :func:`spectex.metrics.cell_splits` of the bake against a structured exemplar (bricks, floor tiles
    #: changing colour partway across: about 1 is the photo's own; None for an unstructured photo)
    cells: object = None
    #: :func:`spectex.metrics.one_off_repeats` of the bake: content the photo shows once (a leaf, a tripod's
    #: leg) and how often the texture shows it (None for an exemplar under 32 pixels)
    one_off: object = None
    #: :func:`spectex.metrics.lighting_blotches` of the bake: blotches at the photo's scale against the photo's
    #: own, its lighting divided out (None for an exemplar under 32 pixels)
    lighting: object = None
    #: :func:`spectex.metrics.scale_blotches` of the bake: patches of large and small grain against the photo's
    #: own variation of scale, its tilt taken out (None for an exemplar under 128 pixels)
    scale: object = None
    #: :func:`spectex.metrics.line_continuity` of the bake against an exemplar structured along one axis (boards'
    #: edges holding their places: about 1 or above is the photo's own; None otherwise)
    lines: object = None
    #: :func:`spectex.metrics.short_cells` of the bake against a structured exemplar (bricks, floor tiles cut
    #: short: the share of cells under 0.6 of the photo's median, beside the photo's own; None otherwise)
    short: object = None


@dataclass(frozen=True, eq=False)
class ReportReference:
    """What :func:`fit_report` measures of the exemplar alone (:func:`report_reference`)."""

    exemplar: np.ndarray          #: as :func:`prepare_exemplar` gives it
    cross_scale: object           #: :func:`spectex.analysis.cross_scale` of it
    band_power_db: np.ndarray     #: its power per octave
    statistics: object            #: :func:`spectex.metrics.reference_statistics` (None: too small)
    coarse: object                #: :func:`spectex.metrics.coarse_reference` (None: not measured)
    coarse_zoom: float | None     #: the zoom ``coarse`` is for
    coarse_magnifications: tuple | None  #: the magnifications it searches (None: the metric's default)


def report_reference(image, *, coarse_zoom: float | None = 8.0, coarse_magnifications=None,
                     max_size: int = MAX_ANALYSIS_SIZE) -> ReportReference:
    """The exemplar's half of :func:`fit_report`, which needs no texture.

    Its pyramid statistics (the structural distance's floor), cross-scale
    dependence, power per octave and its own range for the search for
    magnified copies (:func:`spectex.metrics.coarse_reference`, for a view of
    its own shape at ``coarse_zoom``) are most of the report's work on the
    photo; made before or while the texture is fitted (``spectex fit`` makes
    them in a second thread while it fits), and given to
    ``fit_report(..., prepared=...)`` with the same image, ``coarse_zoom``,
    ``coarse_magnifications`` and ``max_size`` (the fit's: the photo is
    prepared as the fit prepared it, :func:`prepare_exemplar`).
    """
    from ..metrics import band_power, coarse_reference, reference_statistics

    exemplar, _ = prepare_exemplar(image, max_size=max_size)
    h, w = exemplar.shape[:2]
    if coarse_zoom is not None:
        coarse_zoom = check_float("coarse_zoom", coarse_zoom, minimum=1.0)
    try:  # an exemplar without two 32 x 32 windows (a 512 x 40 strip) has no floor: None
        statistics = reference_statistics(exemplar, max_windows=4)
    except ValueError:
        statistics = None
    coarse = None
    if coarse_zoom is not None and min(h, w) >= 192:  # coarse_copies' smallest photo
        coarse = coarse_reference(exemplar, view_shape=(h, w), zoom=coarse_zoom,
                                  **_search_kwargs(coarse_magnifications))
    return ReportReference(exemplar=exemplar, cross_scale=cross_scale(exemplar),
                           band_power_db=band_power(exemplar).power_db, statistics=statistics, coarse=coarse,
                           coarse_zoom=coarse_zoom, coarse_magnifications=_magnifications(coarse_magnifications))


def _magnifications(magnifications):
    return None if magnifications is None else tuple(float(m) for m in magnifications)


def _search_kwargs(magnifications):
    return {} if magnifications is None else {"magnifications": _magnifications(magnifications)}


def fit_report(texture, image, *, pixel_size: float = 1.0, origin=(0.0, 0.0), scale: int = 2,
               bake=None, coarse_zoom: float | None = 8.0, coarse_magnifications=None,
               prepared: ReportReference | None = None, max_size: int = MAX_ANALYSIS_SIZE) -> FitReport:
    """The fidelity numbers of a texture against an exemplar, at the exemplar's scale.

    The texture is baked over ``scale`` times the exemplar's size (each
    side) at ``pixel_size`` from ``origin`` (keep the origin a whole number
    of pixels, so that the finest layer is sampled at its texel centres as
    the fit did), and compared with the exemplar (prepared as by
    :func:`prepare_exemplar` with ``max_size``, the fit's: grey becomes RGB,
    alpha is dropped, a frame cropped, large images cropped or resampled;
    ``pixel_size`` is the fit's, ``FitResult.pixel_size``).

    With ``bake``, a bake of the texture already made (``bake(texture, ...)``
    at the exemplar's ``pixel_size``, at least the exemplar's size), that is
    compared instead, and ``origin`` and ``scale`` are not used: ``spectex
    fit`` reports on the render of 8x the area it shows this way. With
    ``prepared`` (:func:`report_reference` of the same image and
    ``coarse_zoom`` and ``coarse_magnifications``), the exemplar's half of
    the work is not done again. ``coarse_magnifications``: those the search
    for magnified copies tries (default: the metric's, 2 to 256 times);
    ``spectex fit`` gives its layers' (4, 16, 64, ... for ``ratio`` 4: a
    coarse layer that drew the photo would show it magnified that much).

    Returns
    -------
    FitReport
        ``band_power_distance_db`` (RMS over the bands the exemplar holds,
        Welch segments of the exemplar's size, :func:`spectex.metrics.band_power_distance`),
        ``band_power_exemplar_db`` and ``band_power_texture_db`` (lists),
        ``histogram_w1`` (per channel), ``cross_scale_exemplar`` and
        ``cross_scale_texture`` (the ``value`` of
        :func:`spectex.analysis.cross_scale`), ``amplitude_exemplar`` and
        ``amplitude_texture`` (its ``amplitude``), ``bake_shape``; the
        structural measures of issue 22: ``structure`` (the bake's
        exemplar-sized corner, at the photo's own place) and
        ``structure_far`` (windows spread over the whole bake), both
        :func:`spectex.metrics.structural_distance` with the exemplar's own
        floor (None for an exemplar without two 32 x 32 windows); ``clipping``
        (:func:`spectex.metrics.clipping`); ``coarse``
        (:func:`spectex.metrics.coarse_copies` on a view of the texture,
        the exemplar's shape at ``coarse_zoom`` times ``pixel_size``; None
        without ``coarse_zoom`` or for an exemplar under 192 pixels);
        ``one_off`` (:func:`spectex.metrics.one_off_repeats` of the bake:
        content the photo shows once and how often the texture shows it);
        ``lighting`` (:func:`spectex.metrics.lighting_blotches` of the bake:
        blotches at the photo's scale, such as an unevenly lit photo's
        drift repeated in every patch); ``scale``
        (:func:`spectex.metrics.scale_blotches` of the bake: a photo taken
        at an angle, its near and far grain mixed patch by patch).
    """
    from concurrent.futures import ThreadPoolExecutor

    from ..metrics import band_power, band_power_distance, clipping, histogram_w1, structural_distance

    if coarse_zoom is not None:
        coarse_zoom = check_float("coarse_zoom", coarse_zoom, minimum=1.0)
    exemplar, _ = prepare_exemplar(image, max_size=max_size)
    if prepared is None:
        prepared = report_reference(exemplar, coarse_zoom=coarse_zoom, coarse_magnifications=coarse_magnifications,
                                    max_size=max_size)
    elif (not isinstance(prepared, ReportReference) or prepared.coarse_zoom != coarse_zoom
          or prepared.coarse_magnifications != _magnifications(coarse_magnifications)
          or not np.array_equal(prepared.exemplar, exemplar)):
        raise ValueError("prepared must be report_reference() of this image with the same coarse_zoom and "
                         "coarse_magnifications")
    h, w = exemplar.shape[:2]
    from ..render.cpu import bake as bake_region  # the parameter ``bake`` hides the module's name

    if bake is None:
        scale = check_int("scale", scale, minimum=1, maximum=8)
        bake = bake_region(texture, (scale * h, scale * w), origin=origin, pixel_size=pixel_size)
    else:
        bake = check_image("bake", bake, channels=(3,))
        if bake.shape[0] < h or bake.shape[1] < w:
            raise ValueError(f"bake must be at least the exemplar's size {w}x{h}, got "
                             f"{bake.shape[1]}x{bake.shape[0]}")
    view = None
    if prepared.coarse is not None:
        view = bake_region(texture, (h, w), origin=origin, pixel_size=coarse_zoom * pixel_size)[:, :, :3]
    # the search for magnified copies (the report's longest measure: FFTs, most of them without
    # the GIL) runs in a second thread while this one makes the others
    with ThreadPoolExecutor(max_workers=1) as pool:
        coarse = None if view is None else pool.submit(_coarse, view, exemplar, coarse_zoom, prepared.coarse,
                                                       _search_kwargs(coarse_magnifications))
        ce = prepared.cross_scale
        cb = cross_scale(bake, fine=ce.fine)
        structure = structure_far = None
        if prepared.statistics is not None:
            structure = structural_distance(bake[:h, :w], exemplar, max_windows=4, prepared=prepared.statistics)
            structure_far = structural_distance(bake, exemplar, max_windows=4, prepared=prepared.statistics)
        others = dict(band_power_distance_db=band_power_distance(exemplar, bake),
                      band_power_texture_db=band_power(bake, segment=(h, w)).power_db,
                      histogram_w1=histogram_w1(exemplar, bake), clipping=clipping(bake, exemplar),
                      one_off=_one_off(bake, exemplar), lighting=_lighting(bake, exemplar),
                      scale=_scale(bake, exemplar))
        others["cells"], others["lines"], others["short"] = _cells(bake, exemplar)
        coarse = None if coarse is None else coarse.result()
    return FitReport(
        bake_shape=tuple(bake.shape[:2]),
        band_power_exemplar_db=prepared.band_power_db,
        cross_scale_exemplar=ce.value,
        cross_scale_texture=cb.value,
        amplitude_exemplar=ce.amplitude,
        amplitude_texture=cb.amplitude,
        structure=structure,
        structure_far=structure_far,
        coarse=coarse,
        **others,
    )


def _cells(bake, exemplar):
    """``(cells, lines, short)``: :func:`spectex.metrics.cell_splits` of the bake against a structured exemplar,
    for a structure along one axis :func:`spectex.metrics.line_continuity`, and
    :func:`spectex.metrics.short_cells`; None where they do not apply."""
    from ..metrics import cell_splits, lines_or_none, short_cells
    from ._structure import structure_period

    if exemplar.ndim != 3 or min(exemplar.shape[:2]) < 64 or structure_peak(exemplar) < STRUCTURED_PEAK:
        return None, None, None
    period = structure_period(exemplar)
    if period == (None, None):
        return None, None, None
    return (cell_splits(bake, exemplar, period=period), lines_or_none(bake, exemplar, period),
            short_cells(bake, exemplar, period=period))


def _lighting(bake, exemplar):
    """:func:`spectex.metrics.lighting_blotches` of the bake (at the exemplar's pixel size), None for a small
    exemplar or bake."""
    from ..metrics import lighting_blotches

    try:
        return lighting_blotches(bake, exemplar)
    except ValueError:  # an exemplar under 32 pixels, or a bake under the blotches' scale
        return None


def _scale(bake, exemplar):
    """:func:`spectex.metrics.scale_blotches` of the bake (at the exemplar's pixel size), None for a small
    exemplar or bake."""
    from ..metrics import scale_blotches

    try:
        return scale_blotches(bake, exemplar)
    except ValueError:  # an exemplar under 128 pixels, or a bake under two of its blocks
        return None


def _one_off(bake, exemplar):
    """:func:`spectex.metrics.one_off_repeats` of the bake (at the exemplar's pixel size), None for a small
    exemplar."""
    from ..metrics import one_off_repeats

    try:
        return one_off_repeats(bake, exemplar)
    except ValueError:  # an exemplar under 32 pixels, or a one-off region larger than the bake: nothing to count
        return None


def _coarse(view, exemplar, zoom, prepared, kwargs):
    """:func:`spectex.metrics.coarse_copies` of a view, None where it cannot show any magnification."""
    from ..metrics import coarse_copies

    try:
        return coarse_copies(view, exemplar, zoom=zoom, prepared=prepared, **kwargs)
    except ValueError:  # a view too small to show any magnification: nothing measured
        return None
