"""The fit's default method (issue 22): :func:`fit_auto`, called by :func:`spectex.fitting.fit_result`.

What each layer carries, and why (``docs/fitting.md``):

* **Layer 0** shows the photo's own detail at its own scale: a seamless
  tile made from the photo (the photo's crop, or a tileable quilt of it
  with a reuse penalty), drawn stochastic with the sharpened blend weights
  of ``spectex.shading.stochastic``. A structured photo gets a tile cut at
  whole periods of its structure instead, drawn stochastic with its patch
  offsets snapped to whole periods (``Layer.snap``: the grid stays, the
  bricks in it change) or periodic, whichever way trial bakes measure best
  (:func:`_trial`, :func:`_choose`: structural distance, and the repeat of
  the content beyond the structure's lattice).
* **Layers 1 ..** carry only what the photo says about larger scales: a
  second tile of random-phase noise (Galerne et al. 2011) whose spectrum
  continues the photo's below its lowest frequency (the slope of its three
  coarsest octaves, at most ``AUTO_MAX_SLOPE``) and holds nothing above
  about two cycles across the photo, coloured along the main axis of the
  photo's low-passed colours. The photo itself is never magnified.
* **Colours** end with the rounds' shift of the means (the bakes' means
  to the photo's) and the tile clipped to the photo's range per channel; not the exact
  histogram step, which fitted a few bake regions' pooled histogram and
  stretched a non-stationary photo's flat parts (see the last step in
  :func:`fit_auto`).
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._validate import check_choice, check_float, check_int, check_rng
from ..render.cpu import bake
from ._core import (
    FIT_TILINGS,
    MAX_ANALYSIS_SIZE,
    MIN_SIZE,
    STRUCTURED_PEAK,
    FitResult,
    _coarse_slope,
    _Problem,
    _shape_spectrum,
    prepare_exemplar,
    structure_peak,
)

#: The photo's assumed width (its longer side), metres, when neither ``pixel_size`` nor
#: ``photo_size`` is given: a photo of ground taken standing, about 1.5 m across.
DEFAULT_PHOTO_SIZE = 1.5
#: Autocorrelation a lag must reach to count as the structure's period (:func:`structure_period`).
PERIOD_MIN_CORRELATION = 0.15
#: Most power per octave the coarse layers' continuation may keep towards coarser scales (dB per
#: octave): a stationary texture of independent objects has a flat 2-D spectrum beyond its objects'
#: size (-6 dB per octave band); -3 leaves room for the slow variation of real ground, where the
#: legacy fit's -1.5 made blotches larger than anything in the photo.
AUTO_MAX_SLOPE = -3.0
#: The drift across the axis :func:`structure_period` allows per pixel of lag (about 6 degrees).
TILT = 0.1
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
#: Side of the trial's far bake (pixels, at twice the photo's pixel size).
TRIAL_FAR = 512
#: Default opacity of the first coarse layer (method "auto"): low, so that the coarse layers veil
#: the photo's detail little (0.25 over four layers took 5 dB of its power, which the band step put
#: back by raising the tile's contrast into clipping).
AUTO_OPACITY = 0.1
#: How the coarse layers go over the finer ones: the alpha blend, a convex combination, so the
#: colours never leave the photo's range. The variance-preserving blend kept the detail's contrast
#: but amplified the extremes: 9% of the deep-field photo's values clipped at 0 (the photo's 0.8%),
#: against 0.0% with the alpha blend at opacity 0.1, for a structural distance 0.87 instead of 0.85.
COARSE_BLEND = "alpha"
#: Default band-power rounds (method "auto").
AUTO_ITERATIONS = 2
#: The coarse tile holds up to this many cycles per tile, times ``ratio`` (a Gaussian roll-off):
#: at 2 and ratio 4, layer 1 reaches two cycles across the finest tile, the photo's lowest octave.
COARSE_CYCLES = 2.0


def structure_period(exemplar, *, min_lag: int = 8):
    """The period of a structured exemplar along its columns and rows, from its autocorrelation.

    The luma's circular autocorrelation (mean removed, divided by its value
    at lag 0) is read along the y axis (lag ``(dy, 0)``) and the x axis
    (``(0, dx)``), lags ``min_lag`` to half the side, each lag ``d`` taking
    the best over a drift of ``TILT d`` across the axis (a photo a few
    degrees off the structure's axes). On each axis the highest local
    maximum wins, unless a shorter lag reaches 90% of it (a multiple of the
    true period is as high as the period itself).

    Returns
    -------
    (py, px) : tuple of int or None
        Pixels; an entry is None where that axis has no lag with
        correlation :data:`PERIOD_MIN_CORRELATION` or more (no period
        shorter than half the side).
    """
    from ._core import _luma

    lum = _luma(exemplar)
    lum = lum - lum.mean()
    spec = np.fft.rfft2(lum)
    acf = np.fft.irfft2(np.abs(spec) ** 2, s=lum.shape)
    acf /= acf[0, 0]
    out = []
    for a in (acf, acf.T):
        half = a.shape[0] // 2
        line = np.array([max(a[d, e % a.shape[1]] for e in range(-int(math.ceil(TILT * d)),
                                                                  int(math.ceil(TILT * d)) + 1))
                         for d in range(half)])
        v = line[min_lag:half]
        peaks = [i for i in range(1, len(v) - 1) if v[i] >= v[i - 1] and v[i] >= v[i + 1]]
        best = max(peaks, key=lambda i: v[i]) if peaks else None
        if best is None or v[best] < PERIOD_MIN_CORRELATION:
            out.append(None)
            continue
        first = next(i for i in peaks if v[i] >= 0.9 * v[best])
        out.append(int(first + min_lag))
    return out[0], out[1]


def _best_cut(lines, span):
    """Start of the ``span`` lines (axis 0) whose wrap edge shows least: line ``start + span`` (the one
    after the cut) closest to line ``start`` in mean squared difference."""
    n = lines.shape[0]
    if span >= n:
        return 0
    costs = [float(np.mean((lines[y] - lines[y + span]) ** 2)) for y in range(n - span)]
    return int(np.argmin(costs))


def _period_tile(exemplar, period):
    """A square tile of whole periods, cut where its wrap edges show least; or None.

    ``period = (py, px)``, either may be None (no period along that axis).
    The side ``L`` is as many whole periods as fit (near square when both
    are known, then resampled along y by ``L / (ky py)``, within 12%); the
    crop's place along each axis is the one whose wrap edge differs least
    (:func:`_best_cut`). Returns ``(tile (L, L, 3) float64, L, (ky, kx))``.
    """
    from scipy import ndimage

    h, w = exemplar.shape[:2]
    py, px = period
    if py is None and px is None:
        return None
    choice = None
    if px is not None and py is not None:
        for kx in range(w // px, 0, -1):
            side = kx * px
            ky = max(1, round(side / py))
            if ky * py <= h - 1 and side <= w - 1 and side >= MIN_SIZE and abs(ky * py / side - 1.0) <= 0.12:
                choice = (ky * py, side, ky, kx)
                break
    elif px is not None:
        kx = (min(h, w) - 1) // px
        choice = (kx * px, kx * px, 0, kx)
    else:
        ky = (min(h, w) - 1) // py
        choice = (ky * py, ky * py, ky, 0)
    if choice is None or min(choice[:2]) < MIN_SIZE:
        return None
    ch, cw, ky, kx = choice
    x0 = _best_cut(np.moveaxis(exemplar, 1, 0), cw)
    y0 = _best_cut(exemplar[:, x0:x0 + cw], ch)
    crop = exemplar[y0:y0 + ch, x0:x0 + cw].astype(np.float64)
    if ch != cw:
        # periodic along y: wrap-mode resampling keeps the crop seamless
        crop = ndimage.zoom(crop, (cw / ch, 1.0, 1.0), order=1, mode="grid-wrap", grid_mode=True)[:cw]
    return crop, cw, (ky, kx)


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


def _trial(exemplar, pixel_size, candidates, patch, period):
    """The finest layer alone, each way, measured: ``{label: {"structure": ratio, "repeat": peak}}``.

    ``candidates``: ``(label, tiling, tile, snap)``. ``structure``:
    structural distance / floor (:func:`spectex.metrics.structural_distance`)
    of a bake of the photo's size (at most 256) at its pixel size, against
    the photo's central crop of that size (4 windows each). ``repeat``:
    :func:`spectex.metrics.repeat_peak` with the structure's lattice removed
    (``period``, pixels; the content's repeat beyond the structure's own) of
    a 512 x 512 bake at twice the pixel size (at least two tiles across).
    """
    from ..metrics import reference_statistics, repeat_peak, structural_distance
    from ..texture import Layer, SpectralTexture

    h, w = exemplar.shape[:2]
    m = min(h, w, 256)
    y0, x0 = (h - m) // 2, (w - m) // 2
    reference = exemplar[y0:y0 + m, x0:x0 + m]
    prepared = reference_statistics(reference, max_windows=4)
    half = tuple(None if p is None else p / 2.0 for p in period)
    out = {}
    for label, tiling, tile, snap in candidates:
        rgba = np.ones(tile.shape[:2] + (4,), dtype=np.float32)
        rgba[:, :, :3] = np.clip(tile, 0.0, 1.0)
        layer = Layer(size=tile.shape[0] * pixel_size, tiling=tiling, patch=patch, snap=snap)
        texture = SpectralTexture(rgba, [layer])
        baked = bake(texture, (m, m), pixel_size=pixel_size)
        far = bake(texture, (TRIAL_FAR, TRIAL_FAR), pixel_size=2.0 * pixel_size)
        out[label] = {"structure": structural_distance(baked, reference, prepared=prepared, max_windows=4).ratio,
                      "repeat": repeat_peak(far, period=half)}
    return out


def _choose(trial, own_repeat):
    """The finest layer's way from :func:`_trial`: the closest structure among the ways that do not
    repeat (content repeat at most ``max(REPEAT_LIMIT, own_repeat + REPEAT_MARGIN)``, all of them
    if none), the snapped one kept while within ``TRIAL_MARGIN`` of it (structure kept when in
    doubt)."""
    limit = max(REPEAT_LIMIT, own_repeat + REPEAT_MARGIN)
    allowed = [k for k, v in trial.items() if v["repeat"] <= limit] or list(trial)
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


def _resolve_scale(pixel_size, photo_size, full_side, notes):
    """The fit's pixel size (metres) and the report's words for it; an assumed scale is noted in ``notes``."""
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
    return pixel_size, scale


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


def fit_auto(image, *, pixel_size=None, photo_size=None, layers=5, ratio=4.0, opacity=None, iterations=None,
             tile_size=None, max_size=MAX_ANALYSIS_SIZE, rng=0, tiling="auto", patch=None, progress=None) -> FitResult:
    """Issue 22's fit (see the module's docstring and :func:`spectex.fit`)."""
    start = time.perf_counter()
    layers, ratio, opacity, iterations, rng, tiling, patch = check_options(
        layers=layers, ratio=ratio, opacity=opacity, iterations=iterations, rng=rng, tiling=tiling, patch=patch,
        progress=progress)
    from ..metrics import band_power
    from ..texture import Layer, layer_placement
    from ..tiles import make_seamless

    exemplar, notes = prepare_exemplar(image, max_size=max_size)
    full_side = max(np.shape(image)[:2])
    pixel_size, scale = _resolve_scale(pixel_size, photo_size, full_side, notes)
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
    period = structure_period(exemplar) if structure >= STRUCTURED_PEAK else None
    if period is not None and period == (None, None):
        period = None
    cut = _period_tile(exemplar, period) if period is not None and tiling != "stochastic" else None
    if tile_size is None:
        tile_size = max(min(h, w), min(512, 4 * min(h, w)))
    n = check_int("tile_size", tile_size, minimum=MIN_SIZE, maximum=4096)
    if n <= min(h, w):
        tile0 = make_seamless(exemplar, shape=(n, n))[:, :, :3].astype(np.float64)
        tile_method = "seamless crop"
    else:
        from ..synthesis import quilt

        block = int(np.clip(min(h, w) // 4, 16, 64))
        tile0 = quilt(exemplar, (n, n), block=block, tileable=True, rng=rng, reuse=1.0).astype(np.float64)
        tile_method = f"tileable quilt (block {block}, reuse penalty 1)"
    tilings0 = "periodic" if tiling == "periodic" else "stochastic"
    snap0 = (0, 0)
    trial = None
    if cut is not None:
        crop, side, counts = cut
        # the crop as it is: cut where its wrap edges differ least, at whole periods, it is seamless as a
        # structure; make_seamless's smooth correction takes up every brick's colour step along the wrap
        # edges and spreads them into blotches (up to 0.66 on a 240-pixel wall tile; its structural
        # distance 1.98 against 0.86 for the crop itself)
        cut_tile = np.clip(crop, 0.0, 1.0).astype(np.float64)
        cut_method = (f"cut at the structure's period (x {period[1]}, y {period[0]} px; {counts[1]} x "
                      f"{counts[0]} periods, 0 where none) where its wrap edges show least")
        if tiling == "periodic" or min(h, w) < 64:  # (too small for two windows of the measure)
            tile0, n, tile_method, tilings0 = cut_tile, side, cut_method, "periodic"
        else:
            # the trial bakes: the finest layer alone, each way, measured by the structural distance
            # and by the repeat of its content beyond the structure's lattice
            snap = (counts[1], counts[0])
            trial = _trial(exemplar, pixel_size, [("periodic", "periodic", cut_tile, (0, 0)),
                                                  ("snapped", "stochastic", cut_tile, snap),
                                                  ("stochastic", "stochastic", tile0, (0, 0))], patch, period)
            from ..metrics import repeat_peak

            own = repeat_peak(exemplar, period=period)
            trial["photo_repeat"] = own
            choice = _choose({k: v for k, v in trial.items() if k != "photo_repeat"}, own)
            trial["choice"] = choice
            if choice == "periodic":
                tile0, n, tile_method, tilings0 = cut_tile, side, cut_method, "periodic"
            elif choice == "snapped":
                tile0, n, tilings0, snap0 = cut_tile, side, "stochastic", snap
                tile_method = cut_method + f", drawn stochastically with offsets snapped to whole periods (snap {snap})"
    tick()
    # --- the coarse layers' own tile
    region = (min(h, 256), min(w, 256))
    slope = min(AUTO_MAX_SLOPE, _coarse_slope(band_power(exemplar, segment=region)[1]))
    mean, axis, noise = _coarse_tile(exemplar, n, ratio, slope, rng)
    lo = np.quantile(exemplar.reshape(-1, 3), 0.005, axis=0)
    hi = np.quantile(exemplar.reshape(-1, 3), 0.995, axis=0)

    def coarse(g):
        rgba = np.ones((n, n, 4), dtype=np.float32)
        rgba[:, :, :3] = np.clip(mean + g * noise[:, :, None] * axis, lo, hi)
        return rgba

    q = float(np.clip(10.0 ** (slope * math.log2(ratio) / 20.0), 0.25, 1.0))
    finest = n * pixel_size
    layer_list = [Layer(size=finest, tile=0, tiling=tilings0, patch=patch, snap=snap0)]
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
    for _ in range(iterations):
        # one set of bakes per round: the band step (a radial gain, mean kept) and the means' shift
        # both read it
        bakes = problem.bakes(colour, alpha)
        err = problem.band_error(bakes)
        history.append(err.tolist())
        fine_err = err[:-n_cont]
        shaped = _shape_spectrum(colour, np.concatenate([np.clip(0.8 * fine_err, -6.0, 6.0), [0.0, 0.0]]))
        colour = problem.histogram_step(shaped, bakes, shift_only=True)
        if len(history) == 1:
            # the coarse tile's contrast, once (its stochastic tables are then made once more only):
            # its power follows gain^2 until the photo's range clips it
            gain = float(np.clip(gain * 10.0 ** (float(np.mean(err[-n_cont:])) / 20.0), 0.1, 8.0))
            problem.coarse_tile = coarse(gain)
        tick()
    # the tile inside the photo's range per channel (no colour the photo lacks); the means are the
    # rounds' (a further shift on fresh bakes moved them by 0.01-0.17 of an 8-bit step on gravel, moon,
    # tissue and deep field: not worth a third set of bakes and stochastic tables, a third of the time).
    # Not the exact histogram step (the bakes' histograms mapped to the photo's) that was here: a few
    # bake regions of a non-stationary photo (moon's flat maria beside its craters) pool local contrasts
    # 10 dB apart, and the quantile map fitted to that sample stretched the tile's flat parts, raising
    # moon's finest bands by 3 dB with a speckle of grain (structural distance 1.15 against 1.04 without
    # it; tissue 0.88 against 0.81; within 0.03 on the others, docs/fitting.md)
    colour = np.clip(colour, exemplar.reshape(-1, 3).min(axis=0), exemplar.reshape(-1, 3).max(axis=0))
    tick()
    texture = problem.texture(colour, alpha)
    params = {"method": "auto", "tile_px": n, "tile_method": tile_method, "layers": layers, "ratio": ratio,
              "coarse_slope_db_per_octave": slope, "coarse_gain": gain,
              "opacities": [lay.opacity for lay in layer_list], "alpha_gain": 0.0,
              "band_error_history_db": history, "tilings": [lay.tiling for lay in layer_list],
              "structure_peak": structure, "period_px": period, "trial": trial, "snap": snap0, "patch": patch,
              "scale": scale}
    return FitResult(texture=texture, exemplar=exemplar, pixel_size=pixel_size, notes=notes, params=params,
                     seconds=time.perf_counter() - start)
