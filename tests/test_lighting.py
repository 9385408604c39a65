"""A photo's lighting (issue 22): estimated, evened out by the fit, and the blotches it leaves measured.

An unevenly lit photo (a gradient, a vignette) gives a texture whose every patch repeats the drift:
blotches at the photo's scale. ``spectex._lighting`` estimates the drift and measures the blotches
(``spectex.metrics.lighting_blotches``); the fit divides the drift out unless ``keep_lighting=True``
(the control).
"""

import numpy as np
import pytest
import skimage.data as skimage_data

from helpers import pieces, spectex_compare_line, spectex_fit_says
from spectex import metrics
from spectex._lighting import BLOTCH_EXCESS, even_out_lighting, is_lighting, lighting_drift, lighting_trend
from spectex.fitting import even_lighting, fit_result
from spectex.render import bake


def _gravel(side=256):
    grey = skimage_data.gravel()[:side, :side].astype(np.float64) / 255.0
    return np.repeat(grey[:, :, None], 3, axis=2)


def _light(shape, strength=0.3):
    """A light from the top left with a vignette: a smooth factor on the brightness, about 1."""
    h, w = shape[:2]
    y, x = np.mgrid[0:h, 0:w] / max(h, w)
    return (1.0 - strength * (0.6 * x + 0.4 * y)) * (1.0 - 0.7 * strength * ((x - 0.5) ** 2 + (y - 0.5) ** 2))


def _lit(photo, strength=0.3):
    return photo * _light(photo.shape, strength)[:, :, None]


def test_lighting_trend_finds_the_light_and_not_the_gravel():
    plain = _gravel()
    light = _light(plain.shape)
    found = lighting_trend(_lit(plain))
    truth = np.log(light) - np.log(light).mean()
    own = lighting_trend(plain)
    assert found.shape == plain.shape[:2] and abs(found.mean()) < 1e-9
    # the light, up to the gravel's own chance drift (a few per cent)
    assert np.sqrt(np.mean(own ** 2)) < 0.03
    assert np.corrcoef(found.ravel(), truth.ravel())[0, 1] > 0.97
    assert np.sqrt(np.mean((found - own - truth) ** 2)) < 0.01
    # exact on a smooth field of the model's own kind, grey or colour, any aspect
    y, x = np.mgrid[0:96, 0:160] / 160.0
    field = 0.2 * x - 0.1 * y + 0.15 * x * y
    grey = 0.4 * np.exp(field)
    assert np.allclose(lighting_trend(grey), field - field.mean(), atol=2e-3)


def test_even_out_lighting_divides_it_out_keeping_colour_and_range():
    rgb = _gravel() * np.array([1.0, 0.8, 0.6])
    lit = _lit(rgb)
    before = lit.copy()
    flat, rms = even_out_lighting(lit)
    assert np.array_equal(lit, before)  # the input is not touched
    assert rms > 0.05 and np.sqrt(np.mean(lighting_trend(flat) ** 2)) < 0.03
    # one factor per pixel on all channels: the colour's ratios kept; inside the photo's range per channel
    inside = (flat[:, :, 0] > 0.05) & (flat[:, :, 0] < lit[:, :, 0].max())
    assert np.allclose(flat[:, :, 1][inside] / flat[:, :, 0][inside], 0.8, atol=1e-6)
    assert np.all(flat >= lit.reshape(-1, 3).min(axis=0)) and np.all(flat <= lit.reshape(-1, 3).max(axis=0))
    # the fit's rule: an evenly lit photo (under 1 % RMS) is left as it is, the same array
    tiles = np.full((64, 64, 3), 0.5) + 0.1 * (np.indices((64, 64)).sum(axis=0) % 2)[:, :, None]
    same, light = even_lighting(tiles)
    assert same is tiles and light is None
    evened, light = even_lighting(lit)
    assert light["rms"] > 0.05 and light["low"] < 1.0 < light["high"]


def test_lighting_blotches_sees_a_lit_photos_pieces_and_not_an_even_ones():
    plain = _gravel()
    lit = _lit(plain)
    flat, _ = even_out_lighting(lit)
    seen = {name: metrics.lighting_blotches(pieces(photo), lit if name != "plain" else plain)
            for name, photo in (("plain", plain), ("lit", lit), ("evened", flat))}
    assert seen["lit"].excess > 2 * BLOTCH_EXCESS and not seen["lit"].within, seen
    assert seen["plain"].within and seen["evened"].within, seen
    assert seen["lit"].lighting > 0.05 and seen["plain"].lighting < 0.03
    # the plain photo's drift is chance (twice it): not divided out of its own contrast; the lit one's is light
    assert seen["lit"].significant and not seen["plain"].significant
    assert not is_lighting(0.009, 0.001) and not is_lighting(0.05, 0.02) and is_lighting(0.05, 0.01)
    # the photo's own low frequencies are not blotches: its pieces are measured against them
    assert seen["plain"].photo_contrast > 0 and seen["plain"].excess <= seen["lit"].excess / 3
    # a view at 2x the pixel size: the same pieces, halved, read alike
    half = pieces(lit)[::2, ::2]
    assert not metrics.lighting_blotches(half, lit, zoom=2.0).within
    # compare() carries it
    assert not metrics.compare(pieces(lit), reference=lit).lighting.within


def test_lighting_blotches_refuses_bad_input():
    photo = _gravel(128)
    with pytest.raises(ValueError, match="zoom"):
        metrics.lighting_blotches(photo, photo, zoom=100.0)
    with pytest.raises(ValueError, match="reference"):
        metrics.lighting_blotches(photo, photo[:20, :20])
    with pytest.raises(ValueError, match="view"):
        metrics.lighting_blotches(photo[:16, :16], photo)
    with pytest.raises(ValueError, match="threshold"):
        metrics.lighting_blotches(photo, photo, threshold=0.0)


def test_fit_evens_out_the_lighting_unless_asked_to_keep_it():
    lit = _lit(_gravel())
    side = int(round(np.sqrt(8.0) * 256))
    fits = {keep: fit_result(lit, rng=0, keep_lighting=keep) for keep in (False, True)}
    evened, kept = fits[False], fits[True]
    assert evened.params["lighting"]["rms"] > 0.05 and kept.params["lighting"] is None
    assert any("evened out the photo's lighting" in n for n in evened.notes)
    assert not any("lighting" in n for n in kept.notes)
    seen = {keep: metrics.lighting_blotches(bake(r.texture, (side, side), pixel_size=r.pixel_size), lit)
            for keep, r in fits.items()}
    assert seen[False].within and not seen[True].within, seen
    assert seen[True].excess > 2 * seen[False].excess, seen
    with pytest.raises(TypeError, match="keep_lighting"):
        fit_result(lit, keep_lighting="no")


def test_fit_of_an_evenly_lit_photo_is_unchanged():
    y, x = np.mgrid[0:128, 0:128]
    rng = np.random.default_rng(3)
    cells = rng.uniform(0.4, 0.8, (8, 8))[y // 16, x // 16]
    photo = np.repeat((np.where((y % 16 < 2) | (x % 16 < 2), 0.15, cells)
                       + 0.03 * rng.standard_normal((128, 128)))[:, :, None], 3, axis=2)
    _, rms, chance = lighting_drift(photo)
    assert rms > 0.01 and rms < 2 * chance  # 8 large cells drift by chance, not by light
    a = fit_result(photo, rng=0, iterations=1)
    b = fit_result(photo, rng=0, iterations=1, keep_lighting=True)
    assert a.params["lighting"] is None
    assert np.array_equal(a.texture.tiles[0], b.texture.tiles[0])


def test_spectex_fit_and_compare_say_it(tmp_path, capsys):
    """``spectex fit`` notes the evened lighting and reports the blotches (none); ``--keep-lighting`` reaches
    the fit; ``spectex compare`` and ``fit_report`` say the blotches of a lit photo's pieces."""
    from spectex.fitting import fit_report
    from spectex.texture import Layer, SpectralTexture

    lit = _lit(_gravel()).astype(np.float32)
    out, line, path = spectex_fit_says(tmp_path, capsys, lit, "--keep-lighting")
    assert "note: evened out the photo's lighting" in out and "--keep-lighting" in out
    assert "blotches none at the photo's scale" in line and "evened out)" in line, line
    line = spectex_compare_line(tmp_path, capsys, pieces(lit), path, "blotches")
    assert "SEEN" in line, line
    # fit_report of a texture that is the lit photo as one periodic layer: its bake repeats the light
    report = fit_report(SpectralTexture(np.dstack([lit, np.ones(lit.shape[:2], np.float32)]),
                                        [Layer(size=256.0)]), lit, pixel_size=1.0, coarse_zoom=None)
    assert not report.lighting.within and report.lighting.excess > BLOTCH_EXCESS
