"""A large photo of a large structure (floor tiles photographed at high resolution) is resampled until a
tile holds enough of its periods, and one of large grain (gravel photographed close) until it holds enough
grains; other large photos keep their full resolution (issue 22: a fit that looks like the photo)."""

import numpy as np
import pytest
from scipy import ndimage

from helpers import floor_photo, run_fails
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


def _large_gravel(zoom):
    import skimage.data

    gravel = skimage.data.gravel().astype(np.float64) / 255.0
    big = (ndimage.zoom(gravel, zoom, order=3, mode="reflect", grid_mode=True)
           + 0.015 * np.random.default_rng(0).standard_normal((512 * zoom,) * 2))
    return gravel, np.clip(big, 0.0, 1.0).astype(np.float32)


def test_a_large_photo_of_smooth_noise_is_resampled_just_enough_for_its_grain():
    """Noise smoothed by sigma 4 (a grain of 2 x 4 x sqrt(ln 4) = 9.4 pixels) over 1536 pixels: a 512 crop holds
    54 grains, so it is resampled by 128 x 9.4 / 512 = 2.35, under the whole photo's 3, said in a note."""
    rng = np.random.default_rng(1)
    photo = np.clip(0.5 + 0.12 * ndimage.gaussian_filter(rng.standard_normal((1536, 1536)), 4.0, mode="wrap")
                    / 0.0705, 0, 1)
    factor = exemplar_scale(photo)
    assert factor == pytest.approx(128 * 2 * 4 * np.sqrt(np.log(4)) / 512, rel=0.06)
    ex, notes = prepare_exemplar(photo)
    assert ex.shape == (512, 512, 3)
    assert any(f"resampled the 1536x1536 photo by 1/{factor:.4g}" in n and "its grain is 9 photo pixels" in n
               and "must hold 128 of them" in n for n in notes)


@pytest.mark.slow
def test_a_large_photo_of_large_grain_is_drawn_whole_in_a_far_view():
    """scikit-image's gravel magnified 4 times (2048 pixels, stones of about 90): resampled to the whole photo
    (wanted 4.8, the whole photo's 4), its view of the whole photo's extent is closer to the gravel than the
    fit of the photo's 512-pixel crop at full resolution (the control, ``MIN_TILE_GRAINS`` 0: its few stones
    repeat as landmarks; structural distance / floor 1.87 against 1.24 in ``benchmarks/bench_large_photos.py``)."""
    from spectex import metrics
    from spectex.bake._block import bake_window

    gravel, big = _large_gravel(4)
    assert exemplar_scale(big) == pytest.approx(4.0)
    reference = metrics.reference_statistics(gravel)
    far = {}
    for grains in (_core.MIN_TILE_GRAINS, 0):
        monkeypatch = pytest.MonkeyPatch()
        monkeypatch.setattr(_core, "MIN_TILE_GRAINS", grains)
        try:
            result = fit_result(big, photo_size=1.5)
        finally:
            monkeypatch.undo()
        view = np.asarray(bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=1.5 / 512,
                                      origin=(0.0, 0.0)))[:, :, :3]
        far[grains] = np.mean([metrics.structural_distance(view[y:y + 512, x:x + 512], gravel,
                                                           prepared=reference).ratio
                               for y in (0, 512) for x in (0, 512)])
    assert far[_core.MIN_TILE_GRAINS] < 1.4 < 1.6 < far[0]


def test_small_structure_in_a_large_photo_keeps_its_full_resolution():
    """A large floor of small tiles (64 pixels: 8 in a 512 crop) is cropped at full resolution."""
    photo = floor_photo(1024, period=64)[0]
    assert exemplar_scale(photo) == 1.0
    assert prepare_exemplar(photo)[0].shape == (512, 512, 3)


def _noise(h, w, seed=0):
    rng = np.random.default_rng(seed)
    return np.clip(0.5 + 4.0 * ndimage.gaussian_filter(rng.random((h, w, 3)) - 0.5, (1.5, 1.5, 0)), 0, 1)


@pytest.mark.parametrize("value", ["20", "4096"])
def test_cli_fit_max_size_is_checked(tmp_path, capsys, value):
    from spectex import io

    path = tmp_path / "photo.png"
    io.write_image(path, _noise(64, 64).astype(np.float32))
    line = run_fails(["fit", str(path), "-o", str(tmp_path / "out"), "--max-size", value], capsys, tmp_path / "out")
    assert f"--max-size must be between 32 and 2048 pixels, got {value}" in line


@pytest.mark.slow
def test_cli_fit_max_size_keeps_a_larger_photo_whole(tmp_path, capsys):
    """``--max-size 600`` fits a 600-pixel photo whole, in a 600-texel tile, and reports on it as the fit
    prepared it; the control, the default, analyses its central 512 crop."""
    from spectex import io
    from spectex.cli import main

    path = tmp_path / "photo.png"
    io.write_image(path, _noise(600, 600).astype(np.float32))
    assert main(["fit", str(path), "-o", str(tmp_path / "big"), "--max-size", "600"]) == 0
    out = capsys.readouterr().out
    assert "a 600x600 tile" in out and "analysed on the central" not in out
    assert main(["fit", str(path), "-o", str(tmp_path / "default")]) == 0
    out = capsys.readouterr().out
    assert "a 512x512 tile" in out and "analysed on the central 512x512 crop of the 600x600 image" in out


def test_fit_report_prepares_the_photo_with_the_fits_max_size():
    """A report made with the fit's ``max_size`` reads the photo as the fit did (its whole 600 pixels);
    without it, a 512 crop: refused as the prepared reference of another image."""
    from spectex.fitting import report_reference

    photo = _noise(600, 600)
    whole = report_reference(photo, coarse_zoom=None, max_size=600)
    assert whole.exemplar.shape[:2] == (600, 600)
    assert report_reference(photo, coarse_zoom=None).exemplar.shape[:2] == (512, 512)
    from spectex.fitting import fit_report
    from spectex.texture import SpectralTexture

    tex = SpectralTexture.paper_preset(rng=1)
    with pytest.raises(ValueError, match="prepared must be report_reference"):
        fit_report(tex, photo, coarse_zoom=None, prepared=whole)
