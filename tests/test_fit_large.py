"""A large photo of a large structure (floor tiles photographed at high resolution) is resampled until a
tile holds enough of its periods; other large photos keep their full resolution (issue 22: a fit that
looks like the photo)."""

import numpy as np
import pytest
from scipy import ndimage

from helpers import floor_photo
from spectex.fitting import _core, exemplar_scale, fit_result, prepare_exemplar


@pytest.fixture(scope="module")
def big_floor():
    """A 1536-pixel floor of 192-pixel tiles: a 512-pixel crop holds 2.7 of them."""
    return floor_photo(1536, period=192, grout=10)[0]


@pytest.mark.slow
def test_a_large_photo_of_large_tiles_is_resampled_to_hold_its_periods(big_floor, monkeypatch):
    """Resampled by 6 x 192 / 512 = 2.25 (and no more: the whole photo would be 3), said in a note, the
    pixel size given for the photo times 2.25; the fit finds the floor's period (85.3 analysed pixels)
    and cuts the tile at it. The control: cropped at full resolution as before, the fit finds no period
    and draws a seamless crop of 2.7 tiles in random patches (grout cut to pieces)."""
    assert exemplar_scale(big_floor) == pytest.approx(2.25)
    ex, notes = prepare_exemplar(big_floor)
    assert ex.shape == (512, 512, 3)
    assert any("resampled the 1536x1536 photo by 1/2.25" in n and "every 192 photo pixels" in n for n in notes)
    result = fit_result(big_floor, pixel_size=0.002)
    assert result.pixel_size == pytest.approx(0.0045)
    assert result.params["period_px"] == pytest.approx((192 / 2.25, 192 / 2.25), abs=0.5)
    assert result.params["tile_method"].startswith("cut at the structure's period")
    monkeypatch.setattr(_core, "_analysis_factor", lambda rgb, max_size: (1.0, None))
    cropped = fit_result(big_floor, pixel_size=0.002)
    assert cropped.pixel_size == pytest.approx(0.002)
    assert cropped.params["period_px"] is None and cropped.params["tile_method"] == "seamless crop"


def test_a_large_photo_without_structure_keeps_its_full_resolution():
    """Smooth noise (no period): cropped, not resampled, so its finest detail stays; the factor 1."""
    rng = np.random.default_rng(0)
    photo = np.clip(0.5 + 4.0 * ndimage.gaussian_filter(rng.random((900, 1200, 3)) - 0.5, (1.5, 1.5, 0)), 0, 1)
    assert exemplar_scale(photo) == 1.0
    ex, notes = prepare_exemplar(photo)
    np.testing.assert_allclose(ex, photo[194:706, 344:856].astype(np.float32), atol=1e-6)
    assert notes == ["analysed on the central 512x512 crop of the 1200x900 image"]


def test_small_structure_in_a_large_photo_keeps_its_full_resolution():
    """A large floor of small tiles (64 pixels: 8 in a 512 crop) is cropped at full resolution."""
    photo = floor_photo(1024, period=64)[0]
    assert exemplar_scale(photo) == 1.0
    assert prepare_exemplar(photo)[0].shape == (512, 512, 3)
