"""spectex.fit on real exemplars (scikit-image's brick, grass, gravel): the
fitted texture, baked at the exemplar's pixel size, reproduces the
exemplar's power per octave, histograms and cross-scale dependence; the
unfitted default texture does not (the control)."""

import numpy as np
import pytest

import spectex
from spectex.fitting import FitResult, fit, fit_report, fit_result, prepare_exemplar
from spectex.render import bake
from spectex.texture import SpectralTexture

skdata = pytest.importorskip("skimage.data")

NAMES = ("brick", "grass", "gravel")
# the exemplar's own place and a far one that the fit never baked
ORIGINS = ((0.0, 0.0), (1000.0, 3000.0))


def _crop(name, n=128):
    return getattr(skdata, name)()[:n, :n]


@pytest.fixture(scope="module")
def fitted():
    return {name: fit_result(_crop(name), rng=0) for name in NAMES}


@pytest.fixture(scope="module")
def reports(fitted):
    # origins in exemplar pixels (whole pixels: the finest layer sampled at its texel centres)
    return {(name, o): fit_report(fitted[name].texture, _crop(name), pixel_size=fitted[name].pixel_size,
                                  origin=(o[0] * fitted[name].pixel_size, o[1] * fitted[name].pixel_size))
            for name in NAMES for o in ORIGINS}


@pytest.fixture(scope="module")
def control_reports():
    tex = SpectralTexture.paper_preset(tile_size=256)
    return {name: fit_report(tex, _crop(name)) for name in NAMES}


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("name", NAMES)
def test_fit_band_power_within_1p5_db(reports, name, origin):
    assert reports[name, origin].band_power_distance_db <= 1.5


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("name", NAMES)
def test_fit_histograms_within_w1_0p03(fitted, reports, name, origin):
    if origin == (0.0, 0.0):
        assert max(reports[name, origin].histogram_w1) <= 0.03
        return
    # far away the coarse layers (variation larger than the photo) move a region's mean by design:
    # the histogram's shape matches (W1 of the mean-removed values <= 0.03), the mean moves by
    # less than 0.06 (15/255)
    from scipy.stats import wasserstein_distance

    res = fitted[name]
    p = res.pixel_size
    baked = bake(res.texture, (256, 256), origin=(origin[0] * p, origin[1] * p), pixel_size=p)
    photo = res.exemplar
    shift = baked.mean(axis=(0, 1)) - photo.mean(axis=(0, 1))
    assert np.abs(shift).max() < 0.06
    for c in range(3):
        a, b = baked[:, :, c].ravel(), photo[:, :, c].ravel()
        assert wasserstein_distance(a - a.mean(), b - b.mean()) <= 0.03


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("name", NAMES)
def test_fit_cross_scale_dependence_sign_and_size(reports, name, origin):
    r = reports[name, origin]
    assert np.sign(r.cross_scale_texture) == np.sign(r.cross_scale_exemplar)
    assert abs(r.cross_scale_texture - r.cross_scale_exemplar) <= 0.15


@pytest.mark.parametrize("name", NAMES)
def test_fit_control_default_texture_misses(control_reports, name):
    r = control_reports[name]
    assert r.band_power_distance_db > 1.5
    assert max(r.histogram_w1) > 0.03
    same_sign = np.sign(r.cross_scale_texture) == np.sign(r.cross_scale_exemplar)
    assert not same_sign or abs(r.cross_scale_texture - r.cross_scale_exemplar) > 0.15


def test_fit_layers_start_at_the_exemplar_scale(fitted):
    res = fitted["gravel"]
    tex = res.texture
    n = res.params["tile_px"]
    assert tex.tile_shape == (n, n)
    # the assumed footprint: the photo 1.5 m across its longer side
    assert res.pixel_size == pytest.approx(1.5 / 128)
    assert tex.layers[0].size == pytest.approx(n * res.pixel_size)
    assert any("assumed the photo is 1.5 m across" in note for note in res.notes)
    sizes = np.array([layer.size for layer in tex.layers])
    np.testing.assert_allclose(sizes[1:] / sizes[:-1], 4.0)
    # coarser layers fade with the exemplar's falling spectrum
    opac = [layer.opacity for layer in tex.layers[1:]]
    assert all(a >= b for a, b in zip(opac, opac[1:]))


def test_fit_does_not_repeat_the_exemplar():
    # a small exemplar is its own tile, drawn stochastically: it does not repeat (no exact copy one
    # period away, no peak of the detail's autocorrelation at any lag); drawn periodic, the tile is
    # quilted larger than it. The control: the exemplar's own crop drawn periodic repeats (0.9997).
    from spectex.metrics import repeat_peak, repetition

    photo = _crop("gravel", 64)
    res = fit_result(photo)
    assert res.params["tile_px"] == 64 and res.params["tile_method"] == "seamless crop"
    assert res.texture.layers[0].tiling == "stochastic"
    baked = bake(res.texture, (256, 256), pixel_size=res.pixel_size)
    assert repetition(baked, (64, 64)) < 0.05
    assert repeat_peak(baked) < 0.1  # measured 0.036
    periodic = fit_result(photo, tiling="periodic")
    assert periodic.params["tile_px"] == 256 and periodic.params["tile_method"].startswith("tileable quilt")
    baked = bake(periodic.texture, (256, 256), pixel_size=periodic.pixel_size)
    assert repetition(baked, (64, 64)) < 0.05 and repeat_peak(baked) < 0.1  # 0.046
    cropped = fit_result(photo, tiling="periodic", tile_size=64)
    assert repeat_peak(bake(cropped.texture, (256, 256), pixel_size=cropped.pixel_size)) > 0.5
    # a photo longer than wide gives its central square, and the notes say so (a square one says nothing)
    assert not any("finest tile is the central" in note for note in res.notes)
    long = fit_result(skdata.gravel()[:64, :160])
    assert long.params["tile_px"] == 64
    assert any("finest tile is the central 64x64 crop of the 160x64 photo" in note for note in long.notes)


def test_small_photos_own_tile_does_not_come_back():
    # issue 22: a 256-pixel photo's tile is the photo itself (its seamless crop), drawn stochastically:
    # renders of twice its side at four places, the origin and far ones, do not repeat (repeat_peak
    # 0.043-0.059). The control: the tile quilted four times larger from it (the default until
    # 2026-11-26), whose blocks come back (0.07-0.156, over 0.1 at two of the places).
    from spectex.metrics import repeat_peak

    photo = skdata.gravel()[:256, :256]
    places = ((0.0, 0.0), (12.43, 3.7), (-30.23, 83.63), (411.5, -259.23))  # photo sides (bench_places)

    def repeats(res):
        p = res.pixel_size
        return [repeat_peak(bake(res.texture, (512, 512), origin=(round(fx * 256) * p, round(fy * 256) * p),
                                 pixel_size=p)) for fx, fy in places]

    own = fit_result(photo, rng=0)
    assert own.params["tile_px"] == 256 and own.params["tile_method"] == "seamless crop"
    assert max(repeats(own)) <= 0.1
    quilted = fit_result(photo, rng=0, tile_size=512)
    assert quilted.params["tile_method"].startswith("tileable quilt")
    assert max(repeats(quilted)) > 0.1


def test_fit_pixel_size_scales_the_layers_only():
    img = _crop("grass", 64)
    a = fit(img, pixel_size=1.0, iterations=1)
    b = fit(img, pixel_size=0.25, iterations=1)
    assert len(a.tiles) == len(b.tiles) == 2  # the photo's tile, the coarse layers' own
    np.testing.assert_array_equal(a.tiles[0], b.tiles[0])
    for la, lb in zip(a.layers, b.layers):
        assert lb.size == pytest.approx(0.25 * la.size)
        assert lb.opacity == la.opacity
    np.testing.assert_allclose(bake(a, (64, 64), pixel_size=1.0), bake(b, (64, 64), pixel_size=0.25), atol=1e-5)


def test_fit_is_deterministic_and_lazy_name():
    img = _crop("brick", 48)
    assert spectex.fit(img, rng=3, iterations=1) == fit(img, rng=3, iterations=1)


def test_fit_progress_reaches_its_total():
    calls = []
    fit(_crop("gravel", 48), iterations=1, progress=lambda d, t: calls.append((d, t)))
    assert calls and calls[-1][0] == calls[-1][1]
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_fit_conversions_grey_alpha_16bit_huge():
    grey = _crop("gravel", 64)
    ex, notes = prepare_exemplar(grey)
    assert ex.shape == (64, 64, 3) and notes == ["grey repeated into RGB"]
    np.testing.assert_allclose(ex[:, :, 1], grey / 255.0, atol=1e-6)
    rgba16 = np.dstack([grey, grey, grey, np.full_like(grey, 255)]).astype(np.uint16) * 257
    ex16, notes16 = prepare_exemplar(rgba16)
    np.testing.assert_allclose(ex16, ex, atol=1e-6)  # 16-bit scaled by 65535, alpha dropped
    assert notes16 == ["alpha channel dropped"]
    huge, notes_huge = prepare_exemplar(np.random.default_rng(0).random((40, 1500)))
    assert huge.shape == (40, 512, 3)
    assert "central 512x40 crop of the 1500x40 image" in notes_huge[-1]


@pytest.mark.parametrize("image, kwargs, match", [
    (np.random.default_rng(0).random((16, 64)), {}, "at least 32x32"),
    (np.full((64, 64, 3), 0.4), {}, "flat"),
    (np.random.default_rng(0).random((64, 64, 5)), {}, "channels"),
    (np.random.default_rng(0).random((64, 64)), {"pixel_size": 0.0}, "pixel_size must be > 0"),
    (np.random.default_rng(0).random((64, 64)), {"layers": 9}, "layers must be <= 8"),
    (np.random.default_rng(0).random((64, 64)), {"ratio": 1.0}, "ratio must be > 1"),
    (np.random.default_rng(0).random((64, 64)), {"opacity": 1.5}, "opacity must be <= 1"),
    (np.array([[np.nan] * 40] * 40), {}, "finite"),
])
def test_fit_bad_input(image, kwargs, match):
    with pytest.raises(ValueError, match=match):
        fit(image, **kwargs)


@pytest.mark.parametrize("name", NAMES)
def test_fit_coarse_layers_never_magnify_the_photo(fitted, name):
    # issue 22 (2): the coarse layers draw their own tile (tile 1), random-phase noise that holds
    # only low frequencies: under 2% of its variance above 16 cycles per tile, where the photo's
    # tile (the control) has most of its own; and they add power below the photo's lowest band
    from spectex.metrics import band_power

    res = fitted[name]
    tex = res.texture
    assert tex.layers[0].tile == 0 and all(layer.tile == 1 for layer in tex.layers[1:])

    def high_fraction(tile, cycles=16):
        lum = tile[:, :, :3].mean(axis=2)
        spec = np.abs(np.fft.fft2(lum - lum.mean())) ** 2
        n = lum.shape[0]
        u = np.hypot(*np.meshgrid(np.fft.fftfreq(n) * n, np.fft.fftfreq(n) * n))
        return spec[u > cycles].sum() / spec.sum()

    assert high_fraction(tex.tiles[1]) < 0.02
    # the control: the photo's tile has much of its variance in its fine detail (periods under 8
    # texels; brick's rectified crop gives a tile of three 31-texel columns, whose mortar lines hold
    # most of its variance under 16 cycles: 0.20 above n / 8, 0.03 above 16)
    assert high_fraction(tex.tiles[0], tex.tiles[0].shape[0] / 8) > 0.1
    # 64x the pixel size: the photo's tile has averaged out, the coarse layers carry the variation
    p = res.pixel_size
    with_coarse = band_power(bake(tex, (128, 128), pixel_size=64.0 * p))[1][1:4]
    plain = SpectralTexture(tex.tiles, tex.layers[:1])
    without = band_power(bake(plain, (128, 128), pixel_size=64.0 * p))[1][1:4]
    assert np.all(with_coarse > without)
    assert np.all(with_coarse[1:] > without[1:] + 3.0)  # the coarsest, where the photo's tile has nothing


def test_fit_never_repeats_by_default(fitted):
    # gravel (not structured): every layer stochastic; the repeat peak of the fine detail stays low
    # at the exemplar's scale and at 8 times it; the control, the same fit with periodic layers, repeats
    from spectex.fitting import STRUCTURED_PEAK
    from spectex.metrics import repeat_peak

    res = fitted["gravel"]
    p = res.pixel_size
    assert res.params["structure_peak"] < STRUCTURED_PEAK
    # the finest layer stochastic; the coarse layers' noise tile has nothing to repeat
    assert [layer.tiling for layer in res.texture.layers] == ["stochastic"] + ["periodic"] * 4
    near = bake(res.texture, (1024, 1024), pixel_size=p)
    far = bake(res.texture, (1024, 1024), pixel_size=8.0 * p)
    assert repeat_peak(near) <= 0.1 and repeat_peak(far) <= 0.1
    periodic = fit(_crop("gravel"), rng=0, tiling="periodic")
    assert all(layer.tiling == "periodic" for layer in periodic.layers)
    assert repeat_peak(bake(periodic, (1024, 1024), pixel_size=p)) > 0.5


def test_fit_cuts_a_structured_exemplar_at_its_period(fitted):
    # brick's own fine detail repeats (its structure_peak is over the threshold): plain tiling and
    # blending would break the bricks, so the finest layer's tile is cut at the structure's period
    # and drawn periodic or stochastic with its offsets snapped to whole periods (Layer.snap), as
    # the trial bakes measure (tests/test_snap.py: the snapped way keeps a wall's grid and does not repeat)
    from spectex.fitting import STRUCTURED_PEAK, structure_peak

    res = fitted["brick"]
    assert res.params["structure_peak"] >= STRUCTURED_PEAK
    assert structure_peak(res.exemplar) == res.params["structure_peak"]
    # the tile is cut at the bricks' period across (33 to 38 px in the photo: it is in perspective),
    # to a fraction of a pixel, resampled to whole columns of bricks of round(px) texels
    py, px = res.params["period_px"]
    assert px is not None and 28 <= px <= 40
    # down, the bricks' lengths are random: no period (this crop's whole-pixel estimate took a
    # spurious 31 px)
    assert py is None
    qy, qx = res.params["tile_period_px"]
    assert qx == round(px)
    layer = res.texture.layers[0]
    choice = res.params["trial"]["choice"]
    # the trial bakes decide (on this crop, with no period down, snapped 0.98 against stochastic 0.87)
    if choice != "stochastic":
        assert res.params["tile_px"] % qx == 0
    if choice == "snapped":
        assert layer.tiling == "stochastic" and layer.snap[0] == res.params["tile_px"] // qx
    else:
        assert layer.tiling == ("periodic" if choice == "periodic" else "stochastic") and layer.snap == (0, 0)
    with pytest.raises(ValueError, match="tiling"):
        fit(_crop("gravel", 48), tiling="random")


def test_fit_legacy_method_is_the_old_default():
    # method="legacy": one tile, the old 1 m pixel, every layer on the photo's tile (for the benchmark)
    img = _crop("grass", 48)
    old = fit(img, method="legacy", iterations=1)
    assert len(old.tiles) == 1 and old.layers[0].size == pytest.approx(old.tile_shape[0] * 1.0)
    with pytest.raises(ValueError, match="method"):
        fit(img, method="best")
    with pytest.raises(ValueError, match="pixel_size or photo_size"):
        fit(img, pixel_size=0.01, photo_size=2.0)
    res = fit_result(img, photo_size=0.48, iterations=1)
    assert res.pixel_size == pytest.approx(0.01) and not any("assumed" in n for n in res.notes)


def test_fit_colours_stay_in_the_photo_gamut(fitted):
    # issue 22 (4): clipped fraction at most the photo's own plus 1 point; values inside its range
    for name, res in fitted.items():
        photo = res.exemplar
        baked = bake(res.texture, (256, 256), pixel_size=res.pixel_size)
        clipped = np.mean((baked <= 0.5 / 255) | (baked >= 1 - 0.5 / 255))
        own = np.mean((photo <= 0.5 / 255) | (photo >= 1 - 0.5 / 255))
        assert clipped <= own + 0.01, name
        assert baked.min() >= photo.min() - 0.02 and baked.max() <= photo.max() + 0.02, name


def test_fit_result_is_the_fit():
    img = _crop("grass", 48)
    res = fit_result(img, iterations=1)
    assert isinstance(res, FitResult) and isinstance(res.texture, SpectralTexture)
    plain = fit(img, iterations=1)
    np.testing.assert_array_equal(plain.tiles[0], res.texture.tiles[0])  # the same fit
    with pytest.raises(TypeError, match="return_result"):  # no flag changes the return type
        fit(img, iterations=1, return_result=True)
    assert spectex.fit_result is fit_result


def test_fit_report_on_a_given_bake_is_the_same_report(fitted, reports):
    """fit_report(bake=...) (what spectex fit reports on) agrees with the report that bakes the same
    region itself; a bake smaller than the exemplar is refused."""
    tex = fitted["gravel"].texture
    own = reports["gravel", (0.0, 0.0)]
    given = fit_report(tex, _crop("gravel"), bake=bake(tex, (256, 256), pixel_size=fitted["gravel"].pixel_size))
    assert given.bake_shape == own.bake_shape == (256, 256)
    assert given.band_power_distance_db == own.band_power_distance_db
    np.testing.assert_array_equal(given.histogram_w1, own.histogram_w1)
    assert given.cross_scale_texture == own.cross_scale_texture
    with pytest.raises(ValueError, match="bake must be at least the exemplar's size 128x128, got 64x64"):
        fit_report(tex, _crop("gravel"), bake=bake(tex, (64, 64)))


def test_fit_report_with_the_photos_half_made_beforehand_is_the_same_report(fitted, reports):
    """report_reference (what spectex fit makes while it fits) gives fit_report the same numbers;
    one of another photo or zoom is refused."""
    from spectex.fitting import report_reference

    tex = fitted["gravel"].texture
    own = reports["gravel", (0.0, 0.0)]
    prepared = report_reference(_crop("gravel"))
    given = fit_report(tex, _crop("gravel"), pixel_size=fitted["gravel"].pixel_size, prepared=prepared)
    assert given.band_power_distance_db == own.band_power_distance_db
    np.testing.assert_array_equal(given.histogram_w1, own.histogram_w1)
    assert given.cross_scale_texture == own.cross_scale_texture
    assert given.clipping.image == own.clipping.image and given.coarse is own.coarse is None  # a 128-pixel photo
    assert given.structure.ratio == own.structure.ratio and given.structure_far.ratio == own.structure_far.ratio
    assert given.cross_scale_exemplar == own.cross_scale_exemplar
    with pytest.raises(ValueError, match="prepared"):
        fit_report(tex, _crop("grass"), prepared=prepared)
    with pytest.raises(ValueError, match="prepared"):
        fit_report(tex, _crop("gravel"), coarse_zoom=4, prepared=prepared)


def test_fit_coarse_layers_overlay_keeping_black_and_the_photos_extremes():
    """The coarse layers overlay the finest one: floor tiles in black grout keep it black (the alpha blend's
    veil lifted it towards the coarse colour) and the fit's tile stays inside the photo's range."""
    from helpers import floor_photo

    photo, grout = floor_photo(256, period=32, grout=3)
    photo[grout] = 0.0
    result = fit_result(photo, rng=0)
    assert {layer.blend for layer in result.texture.layers[1:]} == {"overlay"}
    near = bake(result.texture, (256, 256), pixel_size=result.pixel_size)
    assert grout.mean() > 0.05 and float(np.percentile(near, 1)) <= 0.005, np.percentile(near, 1)
    # the control: the same texture with the coarse layers alpha-blended lifts the gaps
    from dataclasses import replace

    veiled = SpectralTexture(list(result.texture.tiles), [result.texture.layers[0]]
                             + [replace(layer, blend="alpha") for layer in result.texture.layers[1:]])
    assert float(np.percentile(bake(veiled, (256, 256), pixel_size=result.pixel_size), 1)) > 0.02
    tile = np.asarray(result.texture.tiles[0])[:, :, :3]
    for c in range(3):
        assert tile[:, :, c].min() >= photo[:, :, c].min() and tile[:, :, c].max() <= photo[:, :, c].max()


def test_clip_guard_halves_the_coarse_layers_while_their_bakes_clip_more_than_the_photo():
    """``_clip_guard`` on a texture whose darkest coarse phase darkens near-black values to 0: halved until the
    bakes clip no more than the photo; a photo that clips as much (the control) keeps the layers as they are."""
    from spectex.fitting import _auto
    from spectex.texture import Layer

    fine = np.ones((8, 8, 4), dtype=np.float32)
    fine[:, :, :3] = 0.55 / 255.0  # an overlay of d = -0.1 takes it under half an 8-bit step
    coarse = np.ones((8, 8, 4), dtype=np.float32)
    coarse[:, :, :3] = 0.0  # every coarse texel at its darkest phase: d = -opacity

    class Problem:
        layers = [Layer(size=8.0), Layer(size=32.0, tile=1, blend="overlay", opacity=0.1)]

        def set_regions(self, n, *, tile_px, ratio):
            self.n = n

        def bakes(self, colour, alpha, extra=False):
            tex = SpectralTexture([fine, coarse], self.layers, bits=None)  # (float tiles: 8 bits would round them)
            return [bake(tex, (16, 16), origin=(3.0 * i, 5.0 * i), pixel_size=1.0) for i in range(self.n)]

    photo = np.full((32, 32, 3), 0.55 / 255.0, dtype=np.float32)
    problem = Problem()
    layers, depth = _auto._clip_guard(problem, None, None, photo, problem.layers, 8, 4.0)
    assert depth == 0.5 and layers[1].opacity == 0.05 and problem.n == 6  # the fit's place and 5 far ones
    assert float(np.mean([(b <= 0.5 / 255.0).mean() for b in problem.bakes(None, None)])) == 0.0
    problem = Problem()
    layers, depth = _auto._clip_guard(problem, None, None, np.zeros((32, 32, 3), np.float32), problem.layers, 8, 4.0)
    assert depth == 1.0 and layers[1].opacity == 0.1


def test_a_photo_its_seamless_crop_moves_gets_a_quilted_tile():
    # wood grain's stripes meet out of phase along the crop's wrap edges: make_seamless's smooth
    # correction took them up all along the edges and moved the photo's statistics (the tile 1.9 times
    # the photo's floor), and every patch drew that tile (a bake 1.52). A tileable quilt is weighed
    # against it and taken; gravel (the control) keeps its crop
    import sys
    from pathlib import Path

    from spectex.metrics import structural_distance

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import exemplars

    wood = exemplars.wood()
    result = fit_result(wood, rng=1)
    assert result.params["tile_method"].startswith("tileable quilt")
    assert "the seamless crop's correction" in result.params["tile_method"]
    image = bake(result.texture, (1024, 1024), pixel_size=result.pixel_size)
    s = np.mean([structural_distance(image[i:i + 512, j:j + 512], wood).ratio for i in (0, 512) for j in (0, 512)])
    assert s < 1.3
    assert fit_result(exemplars.load("gravel"), rng=1).params["tile_method"] == "seamless crop"
