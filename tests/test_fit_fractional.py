"""A structure whose period is not a whole number of pixels (a floor of 85.33-pixel tiles): the fit's
resampling does not ring by its grout, its content's repeat is read without the grout's sub-pixel drift,
and its trial measures enough periods to keep the floor (issue 22: "structure kept")."""

import numpy as np
import pytest

from helpers import floor_photo
from spectex import metrics
from spectex.fitting._core import cubic_at


def _fractional_floor(period=256, factor=3, side=512):
    """A floor of ``period / factor``-pixel tiles (85.33), area-averaged from a floor of whole periods as a
    camera would see it: the grout 2 pixels wide, its sub-pixel phase drifting from tile to tile."""
    from PIL import Image

    big = floor_photo(side * factor, period)[0]
    return np.stack([np.asarray(Image.fromarray(np.ascontiguousarray(big[:, :, c]))
                                .resize((side, side), Image.Resampling.BOX)) for c in range(3)], axis=2)


def test_cubic_at_does_not_ring_by_an_edge_and_keeps_smooth_detail():
    from scipy import ndimage

    rng = np.random.default_rng(3)
    step = np.zeros((40, 40, 1))
    step[:, 20:] = 1.0  # a sharp edge, as grout beside a floor tile
    ys, xs = np.meshgrid(np.arange(40.0), np.arange(40) * 0.987 + 0.3, indexing="ij")
    held = cubic_at(step, ys, xs)
    spline = ndimage.map_coordinates(step[:, :, 0], [ys, xs], order=3, mode="nearest")
    assert held.min() >= 0.0 and held.max() <= 1.0
    # the control: the spline alone overshoots on both sides of the edge
    assert spline.min() < -0.01 and spline.max() > 1.01, (spline.min(), spline.max())
    # smooth detail (grain of 2 pixels) read as the spline reads it, nearly
    grain = ndimage.gaussian_filter(rng.standard_normal((64, 64)), 2.0)[:, :, None]
    ys, xs = np.meshgrid(np.arange(8, 56) * 0.99 + 0.4, np.arange(8, 56) * 1.01 + 0.2, indexing="ij")
    a = cubic_at(grain, ys, xs)[:, :, 0]
    b = ndimage.map_coordinates(grain[:, :, 0], [ys, xs], order=3, mode="nearest")
    assert np.sqrt(np.mean((a - b) ** 2)) <= 0.05 * b.std(), (np.sqrt(np.mean((a - b) ** 2)), b.std())


def test_repeat_peak_of_a_floor_at_a_fractional_period_reads_its_content():
    """Random tiles at 85.33 pixels: their content repeats nowhere (measured 0.02; the lattice's mean alone
    left a line beside each grout line and read 0.35); 3 of its periods (256 pixels) repeated: >= 0.9."""
    photo = _fractional_floor()
    period = (85.333, 85.333)
    assert metrics.repeat_peak(photo, period=period) <= 0.1
    tiled = np.tile(photo[:256, :256], (2, 2, 1))  # the control: content that repeats
    assert metrics.repeat_peak(tiled, period=period) >= 0.9


@pytest.mark.slow
def test_fit_keeps_a_floor_at_a_fractional_period(monkeypatch):
    """The trial bakes measure 6 periods (512 pixels) of an 85.33-pixel floor: the snapped tile is chosen
    and the floor is drawn tile by tile (structural distance / floor over a 1024 bake measured 1.09). The
    control, the trial on 256 pixels as before (windows of 1.5 periods, reading where the grout falls in
    them): a stochastic crop was chosen, grout crosses and broken lines everywhere (1.82)."""
    from spectex.bake._block import bake_window
    from spectex.fitting import _auto, fit_result

    photo = _fractional_floor()
    ratios = {}
    for way, periods in (("now", _auto.TRIAL_PERIODS), ("control", 0)):
        monkeypatch.setattr(_auto, "TRIAL_PERIODS", periods)
        fitted = fit_result(photo)
        baked = bake_window(fitted.texture, (0, 1024, 0, 1024), pixel_size=fitted.pixel_size)
        ratios[way] = (fitted.params["trial"]["choice"], metrics.structural_distance(baked, photo).ratio)
    assert ratios["now"][0] == "snapped" and ratios["now"][1] <= 1.3, ratios
    assert ratios["control"][0] != "snapped" and ratios["control"][1] >= ratios["now"][1] + 0.5, ratios
