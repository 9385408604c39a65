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
            # the analysed tile (512 texels, its texels on the view's pixels: the crop's choice alone; the
            # default's tile at full resolution is read from its mip-maps here, and measured below)
            result = fit_result(big, photo_size=1.5, tile_size=512)
        finally:
            monkeypatch.undo()
        view = np.asarray(bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=1.5 / 512,
                                      origin=(0.0, 0.0)))[:, :, :3]
        far[grains] = np.mean([metrics.structural_distance(view[y:y + 512, x:x + 512], gravel,
                                                           prepared=reference).ratio
                               for y in (0, 512) for x in (0, 512)])
    assert far[_core.MIN_TILE_GRAINS] < 1.4 < 1.6 < far[0]


def _rippled_sand(ripples, side=1024, wavelength=200.0, seed=3):
    """Fine sand (a grain of a pixel) with faint ripples ``wavelength`` pixels apart, turned 35 degrees and
    meandering: 5 across the photo, 2.5 across a 512 crop (a beach photographed from above)."""
    rng = np.random.default_rng(seed)
    grain = ndimage.gaussian_filter(rng.standard_normal((side, side)), 0.8)
    y, x = np.mgrid[0:side, 0:side].astype(np.float64)
    meander = ndimage.gaussian_filter(rng.standard_normal((side, side)), 48.0)
    turn = np.radians(35.0)
    wave = np.sin(2.0 * np.pi * (x * np.cos(turn) + y * np.sin(turn) + 14.0 * meander / meander.std()) / wavelength)
    lum = 0.6 + 0.07 * grain / grain.std() + ripples * wave
    return np.clip(lum[:, :, None] * np.array([1.0, 0.9, 0.72]), 0.0, 1.0).astype(np.float32)


def _ripple_correlation(view, wavelength, turn=35.0):
    """How the ripples of a view hold together: the autocorrelation of its luma blurred by 6 pixels (the grain
    left out), a wavelength apart across the crests (1 for a perfect wave, about 0 for fragments)."""
    lum = ndimage.gaussian_filter(view[:, :, :3].mean(axis=2).astype(np.float64), 6.0)
    lum -= lum.mean()
    f = np.fft.fft2(lum)
    ac = np.fft.fftshift(np.real(np.fft.ifft2(np.abs(f) ** 2)))
    cy, cx = ac.shape[0] // 2, ac.shape[1] // 2
    t = np.radians(turn)
    value = ndimage.map_coordinates(ac, [[cy + wavelength * np.sin(t)], [cx + wavelength * np.cos(t)]], order=1)[0]
    return float(value / ac[cy, cx])


def test_a_large_photo_of_fine_grain_and_large_ripples_is_resampled_to_hold_them():
    """Fine sand with faint ripples 200 pixels apart (1024 pixels): its grain alone would keep the full
    resolution (a 512 crop holds 2.5 ripples, which the coarse layers cannot draw: they continue the crop's
    spectrum without gaining power), but the band of the ripples beyond the crop is 10 dB over the coarsest
    the crop holds (``COARSE_EXCESS_DB`` 6), so the photo is resampled until the crop holds 4 of its
    wavelengths, here the whole photo, said in a note. The controls: the same sand without ripples keeps its
    full resolution; with the rule off, the ripples' photo does too."""
    rippled = _rippled_sand(0.03)
    assert exemplar_scale(_rippled_sand(0.0)) == 1.0
    assert exemplar_scale(rippled) == pytest.approx(2.0)
    notes = prepare_exemplar(rippled)[1]
    assert any("resampled the 1024x1024 photo by 1/2" in n and "features of 128-256 photo pixels" in n for n in notes)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(_core, "COARSE_EXCESS_DB", np.inf)
        assert exemplar_scale(rippled) == 1.0


@pytest.mark.slow
def test_a_large_photo_of_large_ripples_keeps_them_in_a_far_view():
    """The rippled sand's fit viewed over the whole photo (512 pixels across): its ripples hold together a
    wavelength apart (correlation 0.40, the photo's own 0.66), where the fit of the full-resolution crop
    drew fragments of them (0.17: the control, the rule off)."""
    from spectex.bake._block import bake_window

    rippled = _rippled_sand(0.03)
    found = {}
    for excess in (_core.COARSE_EXCESS_DB, np.inf):
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(_core, "COARSE_EXCESS_DB", excess)
            result = fit_result(rippled, photo_size=1.5)
        view = np.asarray(bake_window(result.texture, (0, 512, 0, 512), pixel_size=1.5 / 512,
                                      origin=(0.013, 0.029)))
        found[excess] = _ripple_correlation(view, 100.0)
    photo = _core._resampled(rippled, 512, 512)
    assert _ripple_correlation(photo, 100.0) > 0.6  # the measure sees the photo's ripples
    assert found[_core.COARSE_EXCESS_DB] > 0.3 > 0.25 > found[np.inf], found


def test_small_structure_in_a_large_photo_keeps_its_full_resolution():
    """A large floor of small tiles (64 pixels: 8 in a 512 crop) is cropped at full resolution."""
    photo = floor_photo(1024, period=64)[0]
    assert exemplar_scale(photo) == 1.0
    assert prepare_exemplar(photo)[0].shape == (512, 512, 3)


def _noise(h, w, seed=0):
    rng = np.random.default_rng(seed)
    return np.clip(0.5 + 4.0 * ndimage.gaussian_filter(rng.random((h, w, 3)) - 0.5, (1.5, 1.5, 0)), 0, 1)


@pytest.mark.parametrize("option, value, words", [("--max-size", "20", "32 and 2048 pixels"),
                                                   ("--max-size", "4096", "32 and 2048 pixels"),
                                                   ("--tile-size", "20", "32 and 2048 texels"),
                                                   ("--tile-size", "4096", "32 and 2048 texels")])
def test_cli_fit_sizes_are_checked(tmp_path, capsys, option, value, words):
    from spectex import io

    path = tmp_path / "photo.png"
    io.write_image(path, _noise(64, 64).astype(np.float32))
    line = run_fails(["fit", str(path), "-o", str(tmp_path / "out"), option, value], capsys, tmp_path / "out")
    assert f"{option} must be between {words}, got {value}" in line


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


@pytest.fixture(scope="module")
def gravel_x2_fits():
    """scikit-image's gravel magnified twice (1024 pixels, a grain of 1.5 % noise of its own): the default fit
    and the control with ``tile_size=512`` (the tile the fit analysed, as before the full-resolution tile)."""
    gravel, big = _large_gravel(2)
    return big, fit_result(big, photo_size=1.5), fit_result(big, photo_size=1.5, tile_size=512)


@pytest.mark.slow
def test_a_resampled_photo_keeps_its_own_detail_in_a_tile_at_full_resolution(gravel_x2_fits):
    """Resampled by 1/2 for its grain, the fit's finest tile is at the photo's resolution, 1024 texels: the
    analysed tile with the photo's finer detail put back where it came from. Registered: area-averaged
    by 2 it is the analysed tile (the control's) to 0.003 on average (measured 0.001), where the same shifted
    by one analysed texel is 10 times as far (0.05); its detail is the photo's there (correlation of the two
    high passes over 0.9, measured 0.9997, against under 0.1 for the photo's detail beside it, -0.05)."""
    big, full, control = gravel_x2_fits
    assert full.texture.tile_shape == (1024, 1024) and control.texture.tile_shape == (512, 512)
    assert full.params["full_resolution"] == 1024 and full.params["analysis_px"] == 512
    assert control.params["full_resolution"] is None
    assert any("the finest tile holds the photo's own detail: 1024x1024 texels, a texel one photo pixel" in n
               and "tile_size=512" in n for n in full.notes)
    assert full.pixel_size == control.pixel_size and full.texture.texel_size == pytest.approx(
        control.texture.texel_size / 2)
    tile = full.texture.tiles[0][:, :, :3].astype(np.float64)
    small = tile.reshape(512, 2, 512, 2, 3).mean(axis=(1, 3))
    analysed = control.texture.tiles[0][:, :, :3].astype(np.float64)
    near = float(np.mean(np.abs(small - analysed)))
    shifted = float(np.mean(np.abs(np.roll(small, 1, axis=1) - analysed)))
    assert near < 0.003 and shifted > 10 * near, (near, shifted)

    def high(a):
        g = a.mean(axis=2) if a.ndim == 3 else a
        return (g - ndimage.gaussian_filter(g, 2.0))[64:-64, 64:-64].ravel()

    photo = big if big.ndim == 2 else big.mean(axis=2)
    here = np.corrcoef(high(tile), high(photo))[0, 1]
    beside = np.corrcoef(high(tile), high(np.roll(photo, 7, axis=0)))[0, 1]
    assert here > 0.9 and abs(beside) < 0.1, (here, beside)


@pytest.mark.slow
def test_the_close_view_of_a_resampled_photo_is_as_sharp_as_the_photo(gravel_x2_fits):
    """At the photo's own pixel size the full-resolution tile's view is closer to the photo (structural
    distance / floor over four windows) than the analysed tile magnified (the control: its texels 2 photo
    pixels, the photo's grain gone), and a view at 4.3 times the photo's pixel size (mip-maps, not the
    finest texels) as close as the control's, within 0.1."""
    from spectex import metrics
    from spectex.bake._block import bake_window

    big, full, control = gravel_x2_fits
    px = 1.5 / 1024
    reference = metrics.reference_statistics(big[256:768, 256:768])
    from PIL import Image

    side = round(1024 / 4.3)
    far_photo = np.asarray(Image.fromarray(big).resize((side, side), Image.Resampling.BOX))  # area-averaged
    far_reference = metrics.reference_statistics(far_photo)

    def views(result):
        close = np.asarray(bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=px, origin=(0.0, 0.0)))
        far = np.asarray(bake_window(result.texture, (0, 512, 0, 512), pixel_size=4.3 * px, origin=(0.013, 0.029)))
        near = np.mean([metrics.structural_distance(close[y:y + 512, x:x + 512, :3], big[256:768, 256:768],
                                                    prepared=reference).ratio for y in (0, 512) for x in (0, 512)])
        return near, np.mean([metrics.structural_distance(far[y:y + side, x:x + side, :3], far_photo,
                                                          prepared=far_reference).ratio
                              for y in (0, 512 - side) for x in (0, 512 - side)])

    (near_full, far_full), (near_control, far_control) = views(full), views(control)
    assert near_full < 0.8 * near_control, (near_full, near_control)
    assert far_full <= far_control + 0.1, (far_full, far_control)


@pytest.mark.slow
def test_cli_fit_draws_a_resampled_photo_at_full_resolution_unless_told_a_tile_size(tmp_path, capsys):
    """``spectex fit`` of gravel magnified twice writes a 1024-texel tile and says why (and that its report's
    render reads the finer tile's mip-maps); ``--tile-size 512`` the analysed tile (the control: no note of
    the photo's own detail, no such clause)."""
    from spectex import io
    from spectex.cli import main

    path = tmp_path / "gravel.png"
    io.write_image(path, _large_gravel(2)[1])
    assert main(["fit", str(path), "-o", str(tmp_path / "full")]) == 0
    out = capsys.readouterr().out
    assert "a 1024x1024 tile" in out and "the finest tile holds the photo's own detail" in out
    # the report's render reads the finer tile's mip-maps: said, with the measure on both halved
    assert "the finest tile 2 times finer than the photo as analysed" in out and "with both halved" in out
    assert io.read_image(tmp_path / "full" / "texture.tile0.png").shape[:2] == (1024, 1024)
    assert main(["fit", str(path), "-o", str(tmp_path / "small"), "--tile-size", "512"]) == 0
    out = capsys.readouterr().out
    assert "a 512x512 tile" in out and "the finest tile holds" not in out and "times finer" not in out


@pytest.mark.slow
def test_one_off_content_leaves_no_detail_in_the_full_resolution_tile(monkeypatch):
    """An orange leaf on gravel magnified twice is filled from elsewhere (``keep_one_off``'s default), and the
    photo's detail there is taken from the same place: no edge of the leaf in the full-resolution tile (the
    tile's chroma, red less blue, less its blur, at most 0.2 in the leaf's box; measured 0.08). The control:
    the detail left where it was, the leaf's outline comes back (0.55)."""
    from helpers import ORANGE, with_leaves
    from spectex.fitting import _full

    leafy = with_leaves(_large_gravel(2)[1], [(600, 400, 40.0, ORANGE)])

    def outline(result):
        assert result.texture.tile_shape == (1024, 1024) and result.params["one_off"]
        y0, x0, y1, x1 = result.params["one_off"][0]["box"]
        tile = result.texture.tiles[0].astype(np.float64)
        chroma = tile[:, :, 0] - tile[:, :, 2]
        return float(np.abs(chroma - ndimage.gaussian_filter(chroma, 2.0))[2 * y0:2 * y1, 2 * x0:2 * x1].max())

    moved = outline(fit_result(leafy, photo_size=1.5))
    unmoved = _full.full_resolution
    monkeypatch.setattr(_full, "full_resolution", lambda *a, moves=(), **k: unmoved(*a, moves=(), **k))
    left = outline(fit_result(leafy, photo_size=1.5))
    assert moved < 0.2 < 0.4 < left, (moved, left)


@pytest.mark.gl
@pytest.mark.slow
def test_a_full_resolution_tile_renders_alike_on_gl_and_cpu_and_alias_free(gl, gravel_x2_fits):
    """A fit whose tiles are at the photo's resolution (1024 texels; the free-cell map of a tile that large
    read at 512): GL = CPU >= 40 dB on every view (asserted by the helper), and alias-free: CPU and GL
    within 40 dB of 16 x 16 supersampled renders without mip-maps, low-passed (a Gaussian of one pixel,
    where aliasing shows; measured 46-53 dB); the control, one sample per pixel without mip-maps, 3 dB
    worse or more away from the close view. (Full-band the views score 35.4-43.1 dB, the analysed tile's
    35.8-43.3: gravel with a white grain of its own, the trilinear filter's shape against the box over the
    pixel, as "A small tile is seen minified sooner" in docs/fitting.md says.)"""
    from helpers import psnr_low, views_against_reference

    texture = gravel_x2_fits[1].texture
    assert texture.tile_shape == (1024, 1024)
    scores = {name: (psnr_low(c, ref), psnr_low(g, ref), psnr_low(plain, ref))
              for name, _, c, g, ref, plain in views_against_reference(texture, gl)}
    assert min(min(v[:2]) for v in scores.values()) >= 40.0, scores
    assert all(v[2] <= v[0] - 3.0 for k, v in scores.items() if k != "close"), scores
