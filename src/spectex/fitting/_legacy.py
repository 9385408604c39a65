"""The fit before issue 22 (``method="legacy"``), kept so that the benchmarks can compare with it."""

from __future__ import annotations

import math
import time

import numpy as np

from .._validate import check_choice, check_float, check_int, check_rng
from ._core import (
    FIT_TILINGS,
    MAX_ANALYSIS_SIZE,
    MAX_COARSE_SLOPE,
    STOCHASTIC_REGIONS,
    STOCHASTIC_ROUNDS,
    STRUCTURED_PEAK,
    FitResult,
    _alpha,
    _alpha_field,
    _coarse_slope,
    _layers,
    _pick_gain,
    _prepared,
    _Problem,
    _shape_spectrum,
    _with_tilings,
    finest_tile,
    structure_peak,
)


def _fit_legacy(image, *, pixel_size: float = 1.0, layers: int = 5, ratio: float = 4.0, opacity: float = 0.2,
                iterations: int = 3, tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0,
                tiling: str = "auto", patch: float | None = None, progress=None) -> FitResult:
    """The fit before issue 22 (``method="legacy"``), kept only so that benchmarks can compare."""

    start = time.perf_counter()
    pixel_size = check_float("pixel_size", pixel_size, minimum=0.0, exclusive_minimum=True)
    layers = check_int("layers", layers, minimum=2, maximum=8)
    ratio = check_float("ratio", ratio, minimum=1.0, exclusive_minimum=True, maximum=64.0)
    opacity = check_float("opacity", opacity, minimum=0.0, maximum=1.0, exclusive_minimum=True)
    iterations = check_int("iterations", iterations, minimum=1, maximum=50)
    rng = check_rng(rng)
    from ..shading.constants import DEFAULT_PATCH

    tiling = check_choice("tiling", tiling, FIT_TILINGS)
    patch = DEFAULT_PATCH if patch is None else check_float("patch", patch, minimum=0.0, exclusive_minimum=True,
                                                             maximum=4.0)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable, got {type(progress).__name__}")
    exemplar, notes, factor = _prepared(image, max_size)
    pixel_size *= factor  # given per photo pixel; the exemplar's pixel is `factor` of them
    h, w = exemplar.shape[:2]
    structure = structure_peak(exemplar)
    if tiling == "periodic":
        tilings = ["periodic"] * layers
    elif tiling == "stochastic" or structure < STRUCTURED_PEAK:
        tilings = ["stochastic"] * layers
    else:
        tilings = ["periodic"] + ["stochastic"] * (layers - 1)
    stochastic = "stochastic" in tilings
    total = 2 + 4 + 1 + 2 * (iterations + 1) + (2 * STOCHASTIC_ROUNDS if stochastic else 0)
    done = 0

    def tick():
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    tile0, n, tile_method = finest_tile(exemplar, tile_size, rng)
    tick()
    region = (min(h, 256), min(w, 256))
    from ..metrics import band_power

    slope = min(MAX_COARSE_SLOPE, _coarse_slope(band_power(exemplar, segment=region)[1]))
    q = float(np.clip(10.0 ** (slope * math.log2(ratio) / 20.0), 0.25, 1.0))
    from ..texture import Layer

    base = _layers(layers, ratio, n, pixel_size, 1.0)
    layer_list = [base[0]] + [Layer(size=lay.size, offset=lay.offset, rotation=lay.rotation,
                                    opacity=round(opacity * q ** (k - 1), 6))
                              for k, lay in enumerate(base) if k >= 1]
    problem = _Problem(exemplar, pixel_size, layer_list, n, ratio, region,
                       n_regions=2 if min(region) >= 256 else 3, continuation=slope)
    z = _alpha_field(tile0)
    tick()
    colour = tile0
    gains_db = np.zeros(len(problem.target_bands))
    history = []  # band-power errors (dB) before each band step

    def spectral_and_histogram(colour, alpha):
        err = problem.band_error(problem.bakes(colour, alpha))
        history.append(err.tolist())
        step = np.clip(0.8 * err, -6.0, 6.0)
        gains_db[:] += step
        colour = np.clip(_shape_spectrum(colour, step), 0.0, 1.0)
        tick()
        colour = problem.histogram_step(colour, problem.bakes(colour, alpha, extra=False), shift_only=True)
        tick()
        return colour

    # one round with a neutral alpha, then the alpha gain on a grid, then the rest
    colour = spectral_and_histogram(colour, _alpha(z, 0.0))
    grid = (-3.0, -1.0, 1.0, 3.0)
    values = []
    for g in grid:
        values.append(problem.cross(problem.bakes_first(colour, _alpha(z, g))))
        tick()
    gain = _pick_gain(grid, values, problem.target_cross)
    alpha = _alpha(z, gain)
    for _ in range(iterations - 1):
        colour = spectral_and_histogram(colour, alpha)
    # the steps move the dependence a little: check the gain's neighbours once more
    near = sorted({float(np.clip(gain + d, grid[0], grid[-1])) for d in (-0.75, 0.0, 0.75)})
    near_values = [problem.cross(problem.bakes_first(colour, _alpha(z, g))) for g in near]
    tick()
    best = int(np.argmin(np.abs(np.asarray(near_values) - problem.target_cross)))
    if near[best] != gain:
        gain = near[best]
        alpha = _alpha(z, gain)
        colour = spectral_and_histogram(colour, alpha)
    else:
        tick()
        tick()
    if stochastic:
        # step 5: the final layers; more regions (a stochastic texture's regions differ more than a
        # periodic one's) and STOCHASTIC_ROUNDS band and mean steps on their bakes
        problem.layers = layer_list = _with_tilings(layer_list, tilings, patch)
        problem.set_regions(STOCHASTIC_REGIONS, tile_px=n, ratio=ratio)
        for _ in range(STOCHASTIC_ROUNDS):
            colour = spectral_and_histogram(colour, alpha)
    # the exact histograms (a monotone map per channel), then a last band-power step
    colour = problem.histogram_step(colour, problem.bakes(colour, alpha, extra=False))
    err = problem.band_error(problem.bakes(colour, alpha))
    history.append(err.tolist())
    colour = np.clip(_shape_spectrum(colour, np.clip(err, -6.0, 6.0)), 0.0, 1.0)
    texture = problem.texture(colour, alpha)
    params = {"tile_px": n, "tile_method": tile_method, "layers": layers, "ratio": ratio,
              "coarse_slope_db_per_octave": slope,
              "opacities": [lay.opacity for lay in layer_list], "alpha_gain": gain,
              "alpha_grid": dict(zip(grid, values)), "band_gains_db": gains_db.tolist(),
              "band_error_history_db": history, "alpha_near": dict(zip(near, near_values)),
              "target_cross_scale": problem.target_cross, "tilings": list(tilings),
              "structure_peak": structure, "patch": patch}
    return FitResult(texture=texture, exemplar=exemplar, pixel_size=pixel_size, notes=notes, params=params,
                     seconds=time.perf_counter() - start)
