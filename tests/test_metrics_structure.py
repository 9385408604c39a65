"""The structural measures of issue 22 (spectex.metrics): Portilla-Simoncelli statistics and their
distance with the photo's own floor, clipping, and magnified copies in a zoomed-out view.

Every measure is checked against controls made from scikit-image's photos: another part of the same
photo (at the floor), a cross-fade of two shifted copies and a random-phase version (clearly worse),
the photo magnified into a view (flagged) and a view without a magnified copy (not flagged).
"""

import numpy as np
import pytest
from scipy import ndimage

from helpers import ORANGE, with_leaves
from spectex import metrics

skimage_data = pytest.importorskip("skimage.data")


def _photo(name):
    return getattr(skimage_data, name)().astype(np.float32) / 255.0


def _random_phase(image, rng):
    """The same power spectrum with uniformly random phases (Galerne et al. 2011), mean kept."""
    f = np.fft.fft2(image)
    phase = np.angle(np.fft.fft2(rng.random(image.shape)))  # Hermitian: the result stays real
    phase[0, 0] = 0.0
    out = np.real(np.fft.ifft2(np.abs(f) * np.exp(1j * phase)))
    return np.clip(out, 0.0, 1.0).astype(np.float32)


def _down(image, f):
    h, w = image.shape[:2]
    return image[:h // f * f, :w // f * f].reshape(h // f, f, w // f, f).mean(axis=(1, 3))


def _mosaic(photo, rng, side=4096, piece=128):
    """Random pieces of the photo (flipped at random) laid on a grid: the photo's own scale
    everywhere, no magnified copy."""
    out = np.empty((side, side), dtype=np.float32)
    h, w = photo.shape
    for i in range(side // piece):
        for j in range(side // piece):
            y, x = rng.integers(0, h - piece), rng.integers(0, w - piece)
            p = photo[y:y + piece, x:x + piece]
            if rng.random() < 0.5:
                p = p[::-1]
            if rng.random() < 0.5:
                p = p[:, ::-1]
            out[i * piece:(i + 1) * piece, j * piece:(j + 1) * piece] = p
    return out


# --------------------------------------------------------------------------
# Statistics
# --------------------------------------------------------------------------

def test_texture_statistics_groups_and_colour():
    grey = _photo("gravel")[:128, :128]
    stats = metrics.texture_statistics(grey)
    assert list(stats.groups) == ["marginal", "energy", "lowpass_autocorrelation", "magnitude_autocorrelation",
                                  "cross_orientation", "cross_scale_magnitude", "cross_scale_phase", "colour"]
    for name in ("marginal", "energy", "lowpass_autocorrelation", "magnitude_autocorrelation",
                 "cross_orientation", "cross_scale_magnitude", "cross_scale_phase"):
        assert stats.groups[name].size > 0 and np.all(np.isfinite(stats.groups[name])), name
    assert stats.groups["colour"].size == 0  # grey: no colour statistics
    rgb = np.stack([grey, 0.8 * grey + 0.1, 1.0 - grey], axis=-1)
    assert metrics.texture_statistics(rgb).groups["colour"].size > 0
    # standardised by the image itself: mean 0, log sd 0
    assert abs(stats.groups["marginal"][0]) < 1e-6 and abs(stats.groups["marginal"][1]) < 1e-6
    # the statistics are those of the texture, not a constant: another photo differs in every group
    other = metrics.texture_statistics(_photo("brick")[:128, :128])
    for name in ("lowpass_autocorrelation", "magnitude_autocorrelation", "cross_scale_phase"):
        assert np.max(np.abs(other.groups[name] - stats.groups[name])) > 0.05, name


def test_texture_statistics_see_phase_structure():
    """Random phases keep the spectrum (energy) but lose the cross-scale phase structure of edges."""
    photo = _photo("brick")[:256, :256]
    rp = _random_phase(photo, np.random.default_rng(1))
    a = metrics.texture_statistics(photo)
    b = metrics.texture_statistics(rp, reference=photo)
    phase = np.sqrt(np.mean((a.groups["cross_scale_phase"] - b.groups["cross_scale_phase"]) ** 2))
    assert np.sqrt(np.mean(b.groups["cross_scale_phase"] ** 2)) < 0.1  # random phases: no coupling
    assert phase > 0.1


# --------------------------------------------------------------------------
# Structural distance with the photo's own floor
# --------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["gravel", "brick", "grass"])
def test_structural_distance_controls(name):
    photo = _photo(name)
    reference, other = photo[:, :256], photo[:, 256:]
    own = metrics.structural_distance(other, reference)
    assert 0.6 < own.ratio < 1.6, own.ratio  # another part of the photo: at its floor
    crossfade = 0.5 * (other + np.roll(other, (37, 61), axis=(0, 1)))
    ghost = metrics.structural_distance(crossfade, reference)
    rp = metrics.structural_distance(_random_phase(other, np.random.default_rng(2)), reference)
    assert ghost.ratio > 1.4 * own.ratio and ghost.ratio > 1.8, (own.ratio, ghost.ratio)
    assert rp.ratio > 1.4 * own.ratio and rp.ratio > 1.8, (own.ratio, rp.ratio)
    # the breakdown names what is off: a cross-fade flattens the bands' marginals
    assert ghost.group_ratios["marginal"] > own.group_ratios["marginal"]
    assert own.windows == (4, 4) and own.window == (256, 128)
    assert own.distance == pytest.approx(own.ratio * own.floor)


def test_structural_distance_floor_leaves_out_windows_that_are_copies():
    """A photo made of copies of one tile (four of a 256-pixel gravel crop: a tiled texture given as a photo)
    has windows that are copies of one another, whose distances are no spread of the photo's: before, another
    part of the gravel read infinitely far (the copies' floor 0). Its copies are left out
    of the floor and, all windows being copies at the default size, the windows halved: another part reads
    about 1, as for the photo untiled. The control: a photo without copies gives the same result to the bit
    (no pair is left out); a floor of random-coloured tiles on an exact grid (windows correlated 0.9) too."""
    from spectex import _texture_stats

    gravel = _photo("gravel")
    tile = gravel[:256, :256]
    tiled = np.tile(tile, (2, 2))
    other = gravel[256:, 256:]  # another part of the same gravel, in none of the copies
    copies = metrics.structural_distance(other, tiled)
    plain = metrics.structural_distance(other, gravel[:256, :])
    assert copies.window == (128, 128) and 0.6 < copies.ratio < 1.6, (copies.ratio, copies.window)
    assert copies.ratio < 1.5 * plain.ratio, (copies.ratio, plain.ratio)
    assert copies.copies > 0 and plain.copies == 0, (copies.copies, plain.copies)
    # a copy shifted along one axis only (half the windows copies): left out, the others kept
    below = gravel[256:, :256]
    half = np.concatenate([np.concatenate([tile, tile], axis=1), np.concatenate([below, below[:, ::-1]], axis=1)])
    some = metrics.structural_distance(other, half)
    assert some.window == (256, 256) and 0.6 < some.ratio < 1.6, (some.ratio, some.window)
    # with every pair kept (the rule off), the copies' floor: far from 1
    try:
        saved = _texture_stats.COPY_CORRELATION
        _texture_stats.COPY_CORRELATION = 2.0
        assert metrics.structural_distance(other, tiled).ratio > 3.0
    finally:
        _texture_stats.COPY_CORRELATION = saved
    # the controls: no copies, no change (the floor's every pair kept)
    from helpers import floor_photo

    for photo in (gravel, floor_photo(512, rng=3)[0]):
        a = metrics.structural_distance(np.roll(photo, (77, 131), axis=(0, 1)), photo)
        pairs = _texture_stats._distinct_pairs(np.asarray(photo, dtype=np.float32), a.window, 9)
        assert len(pairs) == 6 and a.window == (256, 256), (len(pairs), a.window)


def test_cli_compare_says_the_reference_repeats_itself(tmp_path, capsys):
    """spectex compare against a reference made of copies of one tile says so (and how many pairs of its
    windows it left out of the floor); against the photo itself (the control) it does not."""
    from spectex import io
    from spectex.cli import main

    gravel = _photo("gravel")
    io.write_image(tmp_path / "tiled.png", np.tile(gravel[:256, :256], (2, 2)))
    io.write_image(tmp_path / "gravel.png", gravel)
    io.write_image(tmp_path / "other.png", gravel[256:, 256:])
    assert main(["compare", str(tmp_path / "other.png"), "--reference", str(tmp_path / "tiled.png")]) == 0
    out = capsys.readouterr().out
    assert "the reference repeats itself:" in out and "128x128 windows are copies" in out, out
    assert main(["compare", str(tmp_path / "other.png"), "--reference", str(tmp_path / "gravel.png")]) == 0
    assert "repeats itself" not in capsys.readouterr().out


def test_structural_distance_is_deterministic_and_reuses_the_reference():
    photo = _photo("gravel")
    image, reference = photo[:256, 256:], photo[:, :256]
    a = metrics.structural_distance(image, reference, max_windows=4)
    b = metrics.structural_distance(image, reference, max_windows=4)
    assert a.as_dict() == b.as_dict()
    prepared = metrics.reference_statistics(reference, max_windows=4)
    c = metrics.structural_distance(image, reference, max_windows=4, prepared=prepared)
    assert c.ratio == a.ratio


def test_structural_distance_grey_against_colour_compares_luma():
    photo = _photo("gravel")
    rgb = np.repeat(photo[:, 256:, None], 3, axis=2)
    a = metrics.structural_distance(rgb, photo[:, :256])
    b = metrics.structural_distance(photo[:, 256:], photo[:, :256])
    assert a.ratio == pytest.approx(b.ratio, rel=1e-5)


def test_structural_distance_colour_group_sees_a_colour_change():
    photo = _photo("gravel")
    tint = np.stack([photo, 0.6 * photo + 0.2, 0.3 + 0.4 * photo[::-1]], axis=-1)
    reference, other = tint[:, :256], tint[:, 256:]
    own = metrics.structural_distance(other, reference)
    swapped = metrics.structural_distance(other[:, :, ::-1], reference)  # blue and red swapped
    assert swapped.group_ratios["colour"] > 3.0 * own.group_ratios["colour"]
    assert swapped.ratio > own.ratio


@pytest.mark.parametrize("kwargs, error", [
    ({"image": np.zeros((16, 16)), "reference": np.random.rand(128, 128)}, ValueError),  # image under a window
    ({"image": np.random.rand(64, 64), "reference": np.random.rand(40, 40)}, ValueError),  # no two windows
    ({"image": np.random.rand(64, 64), "reference": np.full((128, 128), 0.5)}, ValueError),  # flat
    ({"image": np.full((64, 64), np.nan), "reference": np.random.rand(128, 128)}, ValueError),
    ({"image": np.random.rand(64, 64), "reference": np.random.rand(128, 128), "window": 16}, ValueError),
    ({"image": np.random.rand(64, 64), "reference": np.random.rand(128, 128), "window": 32.0}, TypeError),
    ({"image": np.random.rand(64, 64), "reference": np.random.rand(128, 128), "max_windows": 1}, ValueError),
    ({"image": np.random.rand(64, 64, 5), "reference": np.random.rand(128, 128)}, ValueError),
    ({"image": "photo.png", "reference": np.random.rand(128, 128)}, ValueError),
])
def test_structural_distance_refuses_bad_input(kwargs, error):
    with pytest.raises(error):
        metrics.structural_distance(**kwargs)


# --------------------------------------------------------------------------
# Clipping
# --------------------------------------------------------------------------

def test_clipped_fraction_and_clipping():
    rng = np.random.default_rng(0)
    photo = rng.uniform(0.1, 0.9, (100, 100, 3)).astype(np.float32)
    assert metrics.clipped_fraction(photo) == 0.0
    clipped = photo.copy()
    clipped[:10, :, 0] = 1.0   # 1000 of 30000 values
    clipped[:5, :, 2] = 0.0    # 500 more
    assert metrics.clipped_fraction(clipped) == pytest.approx(1500 / 30000)
    # alpha is not counted; grey counts each pixel once
    rgba = np.concatenate([photo, np.ones((100, 100, 1), np.float32)], axis=2)
    assert metrics.clipped_fraction(rgba) == 0.0
    assert metrics.clipped_fraction(np.uint8([[0, 255], [128, 254]])) == pytest.approx(0.5)
    # a contrast stretch clips; the photo's own clipping plus one point is allowed
    stretched = np.clip((photo - 0.5) * 1.6 + 0.5, 0.0, 1.0)
    bad = metrics.clipping(stretched, photo)
    assert not bad.within and bad.excess > 0.1 and bad.reference == 0.0
    good = metrics.clipping(photo, clipped)
    assert good.within and good.excess < 0
    assert metrics.clipping(clipped, photo, margin=0.06).within


@pytest.mark.parametrize("call", [
    lambda: metrics.clipped_fraction(np.zeros((4, 4)), tolerance=0.6),
    lambda: metrics.clipped_fraction(np.zeros((4, 4)), tolerance=-0.1),
    lambda: metrics.clipping(np.zeros((4, 4)), np.zeros((4, 4)), margin=2.0),
    lambda: metrics.clipped_fraction(np.zeros((4, 4, 7))),
])
def test_clipping_refuses_bad_input(call):
    with pytest.raises(ValueError):
        call()


# --------------------------------------------------------------------------
# Magnified copies in a zoomed-out view
# --------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("name", ["gravel", "brick"])
def test_coarse_copies_flags_a_magnified_copy_not_a_continuation(name, monkeypatch):
    photo = _photo(name)
    # the photo at its own scale everywhere, seen from 8 times further: no magnified copy
    continuation = _down(_mosaic(photo, np.random.default_rng(3)), 8)
    # the same with the photo magnified 16 times (2 in the view), rotated, at 30 % weight
    big = ndimage.rotate(ndimage.zoom(photo, 2.0, order=1), 50.0, reshape=False, mode="reflect")[256:768, 256:768]
    copied = 0.7 * continuation + 0.3 * big
    # the photo's half of the search made once for both views (the same numbers: see the next test)
    ref = metrics.coarse_reference(photo, view_shape=continuation.shape, zoom=8)
    fine = metrics.coarse_copies(continuation, photo, zoom=8, prepared=ref)
    flagged = metrics.coarse_copies(copied, photo, zoom=8, prepared=ref)
    assert fine.within, (fine.value, fine.reference)
    assert not flagged.within and flagged.value > fine.value + 0.2, (flagged.value, fine.value)
    assert abs(fine.value) < 0.05  # no copy: chance level, whatever the view's smoothness
    # the magnification found is the copy's
    assert int(np.nanargmax(flagged.per_magnification)) == flagged.magnifications.index(16.0)
    assert fine.zoom == 8.0 and len(fine.per_magnification) == len(fine.magnifications)
    # a fainter copy (20 %) magnified 64 times (8 in the view: a 512-pixel view holds 64 of its
    # pixels, searched at the photo's full resolution; missed before, 0.01): flagged there. The
    # control: the same search without the full-resolution row sees nothing at 64.
    huge = ndimage.rotate(ndimage.zoom(photo[200:300, 200:300], 8.0, order=1), 50.0, reshape=False,
                          mode="reflect")[144:656, 144:656]
    faint = 0.8 * continuation + 0.2 * huge
    far = metrics.coarse_copies(faint, photo, zoom=8, magnifications=(16, 32, 64))
    assert not far.within and far.value > fine.value + 0.2, (far.value, fine.value)
    assert int(np.nanargmax(far.per_magnification)) == 2
    assert np.isfinite(fine.per_magnification[fine.magnifications.index(64.0)])
    import spectex._texture_stats as ts

    monkeypatch.setattr(ts, "_FULL_SCALE", ts._SEARCH_SCALES[0])  # the search as it was: no full row
    blind = metrics.coarse_copies(faint, photo, zoom=8, magnifications=(16, 32, 64))
    assert blind.within and not np.isfinite(blind.per_magnification[2]), blind.per_magnification


def test_coarse_reference_is_the_photos_half_of_coarse_copies():
    photo = _photo("gravel")[:192, :192]
    rng = np.random.default_rng(5)
    view = _down(_mosaic(photo, rng, side=512, piece=64), 4)  # 128 x 128 at zoom 4
    kwargs = dict(zoom=4, magnifications=(2, 4, 8), angles=8, pieces=4)
    alone = metrics.coarse_copies(view, photo, **kwargs)
    ref = metrics.coarse_reference(photo, view_shape=view.shape, **kwargs)
    shared = metrics.coarse_copies(view, photo, prepared=ref, **kwargs)
    assert shared.as_dict() == alone.as_dict()
    # the same prepared serves another view of that shape; a copy of the photo magnified 4 times
    # (1 in the view) is still found with it
    copy = metrics.coarse_copies(0.4 * view + 0.6 * _down(photo[:128, :128], 1), photo, prepared=ref, **kwargs)
    assert not copy.within and copy.value > alone.value + 0.2, (copy.value, alone.value)
    # refused: another photo of the same shape, another view shape, zoom or search
    other = _photo("brick")[:192, :192]
    with pytest.raises(ValueError, match="prepared"):
        metrics.coarse_copies(view, other, prepared=ref, **kwargs)
    with pytest.raises(ValueError, match="prepared"):
        metrics.coarse_copies(view[:120], photo, prepared=ref, **kwargs)
    with pytest.raises(ValueError, match="prepared"):
        metrics.coarse_copies(view, photo, prepared=ref, **{**kwargs, "zoom": 5})
    with pytest.raises(ValueError, match="prepared"):
        metrics.coarse_copies(view, photo, prepared=ref, **{**kwargs, "angles": 9})
    with pytest.raises(ValueError, match="view_shape"):
        metrics.coarse_reference(photo, view_shape=(64, 64), **kwargs)


def test_best_match_is_the_exhaustive_normalised_correlation():
    """The batched float32 FFT search against the correlation computed place by place."""
    import spectex._texture_stats as ts

    rng = np.random.default_rng(1)
    target = ts._bandpass(rng.standard_normal((64, 80)))
    pieces, mask = ts._pieces(ts._bandpass(rng.standard_normal((60, 60))), 1, 3)
    templates = pieces[0]
    t = mask.shape[0]
    wrapped = np.pad(target, ((0, t), (0, t)), mode="wrap")
    best = -1.0
    for y in range(64):
        for x in range(80):
            window = wrapped[y:y + t, x:x + t][mask]
            zero = window - window.mean()
            norm = np.sqrt(np.sum(zero * zero))
            for tpl in templates:
                best = max(best, float(np.sum(tpl[mask] * zero) / norm))
    got = ts._best_match(ts._search_targets([target], mask), templates)[0]
    assert abs(got - best) < 1e-5, (got, best)
    assert 0.1 < best < 0.9  # noise against noise: neither a match nor nothing

@pytest.mark.slow
def test_coarse_copies_judges_a_self_similar_photo_against_its_own_range(monkeypatch):
    """Moon's craters look alike at every size: the photo's own score is high and scatters between
    offsets of its zoom-out (0.15 to 0.28 at 4 times). The default fit's far view was flagged (0.25
    against 0.18) and so was the photo's own zoom-out at another offset: the measure's reference was
    one sample. Against the range over four offsets neither is; a magnified copy still is."""
    import spectex._texture_stats as ts
    from spectex.fitting import fit_result
    from spectex.render import bake

    photo = _photo("moon")
    small = ts._resample(photo.astype(np.float64), 1.0 / 8.0)
    # the photo's own zoom-out (its 64-pixel reduction repeated) at an offset none of the four takes
    rolled = np.tile(small, (9, 9))[25:25 + 512, 6:6 + 512]
    # the photo's half of the search made once for every view here (the same numbers: see
    # test_coarse_reference_is_the_photos_half_of_coarse_copies)
    ref = metrics.coarse_reference(photo, view_shape=rolled.shape, zoom=8)
    own = metrics.coarse_copies(rolled, photo, zoom=8, prepared=ref)
    assert own.within, own
    px = 1.5 / 512
    texture = fit_result(photo, pixel_size=px).texture
    view = bake(texture, (512, 512), pixel_size=8 * px)
    fit = metrics.coarse_copies(view, photo, zoom=8, prepared=ref)
    assert fit.within, fit  # measured 0.079 against its range's 0.021 at a magnification of 16
    # at a far place the fit's view (its finest layer alone scores as much: no coarse layer in it) is
    # within the photo's zoom-out laid as a mosaic (0.106 against 0.055); against the lattice of copies
    # alone (the control, the measure before the mosaics) it was flagged (0.106 against 0.040)
    far_view = bake(texture, (512, 512), pixel_size=8 * px, origin=(37.3 * 512 * px, -11.1 * 512 * px))
    far = metrics.coarse_copies(far_view, photo, zoom=8, prepared=ref)
    assert far.within, far
    # at another place the fit's view read 0.117 at 16 times, over the photo's own views as lit (at most
    # 0.055) by 0.062, until the stochastic weights followed the patch's width (2026-11-26: a cross-fade
    # of three patches over most of each triangle at this view's lambda = 3 before): moon has lighting (a
    # 5 % drift, 4 times chance), which the fit evens out, so the photo evened out is in the range too
    # (light is not the texture). The view now reads 0.101 there without the evened photo: within either
    # way, like every place tried (12 places, 0.03-0.32 against their ranges).
    lit_view = bake(texture, (512, 512), pixel_size=8 * px,
                    origin=(-35.58403873 * 512 * px, 44.86494471 * 512 * px))
    assert metrics.coarse_copies(lit_view, photo, zoom=8, prepared=ref).within
    monkeypatch.setattr(ts, "_OWN_EVENED", False)
    assert metrics.coarse_copies(lit_view, photo, zoom=8, prepared=ref).within
    monkeypatch.setattr(ts, "_OWN_MOSAICS", ())
    assert not metrics.coarse_copies(far_view, photo, zoom=8, prepared=ref).within
    # a copy magnified 16 times (2 in the view), rotated, at 30 %, over the fit's view: flagged (0.31)
    big = ndimage.rotate(ndimage.zoom(photo, 2.0, order=1), 50.0, reshape=False, mode="reflect")[256:768, 256:768]
    copied = metrics.coarse_copies(0.7 * view[:, :, 0] + 0.3 * big, photo, zoom=8, prepared=ref)
    assert not copied.within and copied.value >= fit.value + 0.2, (copied, fit)
    assert int(np.nanargmax(copied.per_magnification)) == copied.magnifications.index(16.0)
    # the control: with one offset as the reference (the measure as it was), the photo's own
    # zoom-out is flagged (measured 0.27 against 0.18); the prepared half holds the first offset only
    # (the mosaics and the evened photo are off since the far view's control above)
    monkeypatch.setattr(ts, "_OWN_ROLLS", ts._OWN_ROLLS[:1])
    assert not metrics.coarse_copies(rolled, photo, zoom=8, prepared=ref).within


def test_coarse_copies_refuses_bad_input():
    photo = _photo("gravel")[:256, :256]
    view = np.random.default_rng(0).random((128, 128)).astype(np.float32)
    with pytest.raises(ValueError):
        metrics.coarse_copies(view, photo, zoom=0.5)
    with pytest.raises(ValueError):
        metrics.coarse_copies(view[:50], photo, zoom=8)
    with pytest.raises(ValueError, match="at least 192x192"):
        metrics.coarse_copies(view, photo[:128], zoom=8)
    with pytest.raises(ValueError):
        metrics.coarse_copies(view, photo, zoom=8, magnifications=())
    with pytest.raises(ValueError):
        metrics.coarse_copies(view, photo, zoom=8, magnifications=(1.0,))
    with pytest.raises(TypeError):
        metrics.coarse_copies(view, photo, zoom=8, magnifications=("big",))
    with pytest.raises(ValueError):  # no magnification fits this view
        metrics.coarse_copies(view, photo, zoom=1, magnifications=(256,))


# --------------------------------------------------------------------------
# In compare (library and command line) and the fit report
# --------------------------------------------------------------------------

def test_compare_carries_the_structural_measures():
    photo = _photo("gravel")
    r = metrics.compare(photo[:, 256:], reference=photo[:, :256])
    assert r.structure.ratio == pytest.approx(metrics.structural_distance(photo[:, 256:], photo[:, :256]).ratio)
    assert r.clipping.within and r.coarse is None
    d = r.as_dict()
    assert d["structure"]["ratio"] == r.structure.ratio and d["clipping"]["within"] is True
    # too small or flat a reference: no floor, no structure (and no error)
    assert metrics.compare(photo[:64, :64], reference=photo[:40, :40]).structure is None
    assert metrics.compare(photo[:64, :64], reference=np.full((64, 64), 0.5)).structure is None
    with pytest.raises(ValueError, match="zoom"):
        metrics.compare(photo, reference=photo, zoom=0.5)


def test_cli_compare_prints_structure_clipping_and_copies(tmp_path, capsys):
    import json

    from PIL import Image

    from spectex.cli import main

    photo = skimage_data.brick()
    Image.fromarray(photo).save(tmp_path / "photo.png")
    Image.fromarray(photo[:, 256:]).save(tmp_path / "half.png")
    # a zoomed-out view holding the photo magnified 16 times (2 in the view)
    view = 0.6 * _down(_mosaic(_photo("brick"), np.random.default_rng(4), side=1024), 8).repeat(2, 0).repeat(2, 1) \
        + 0.4 * ndimage.zoom(_photo("brick"), 2.0, order=1)[256:512, 256:512]
    np.save(tmp_path / "view.npy", view.astype(np.float32))
    assert main(["compare", str(tmp_path / "half.png"), "--reference", str(tmp_path / "photo.png")]) == 0
    text = capsys.readouterr().out
    assert "structural distance" in text and "x the reference's own floor" in text and "clipped values" in text
    assert "magnified copies" not in text  # only with --zoom
    assert main(["compare", str(tmp_path / "view.npy"), "--reference", str(tmp_path / "photo.png"),
                 "--zoom", "8", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["coarse"]["within"] is False and data["coarse"]["zoom"] == 8.0
    assert main(["compare", str(tmp_path / "view.npy"), "--reference", str(tmp_path / "photo.png"),
                 "--zoom", "0.5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--zoom" in err[0]


@pytest.mark.slow
def test_fit_report_sees_a_magnified_coarse_layer():
    """The fit report's structural measures on two hand-made textures of one photo tile: the tile
    alone (the photo repeated: at the floor, no copies, no clipping) and the tile with a coarse
    layer 16 times larger at half opacity (the photo magnified: flagged by ``coarse``)."""
    from spectex.fitting import fit_report, report_reference
    from spectex.texture import Layer, SpectralTexture

    photo = _photo("gravel")
    tile = np.dstack([np.repeat(photo[:, :, None], 3, axis=2), np.ones((512, 512), np.float32)])
    alone = SpectralTexture(tile, [Layer(size=512.0)])
    # the photo's half of both reports made once (the same numbers: test_fit.py's report_reference test)
    prepared = report_reference(photo)
    report = fit_report(alone, photo, pixel_size=1.0, prepared=prepared)
    assert report.structure.ratio < 1.2 and report.structure_far.ratio < 1.2
    assert report.clipping.within and report.coarse.within, report.coarse
    magnified = SpectralTexture(tile, [Layer(size=512.0), Layer(size=8192.0, rotation=40.0, opacity=0.5)])
    bad = fit_report(magnified, photo, pixel_size=1.0, prepared=prepared)
    assert not bad.coarse.within and bad.coarse.value > report.coarse.value + 0.1, (bad.coarse, report.coarse)
    assert fit_report(alone, photo, pixel_size=1.0, coarse_zoom=None).coarse is None


# --------------------------------------------------------------------------
# One-off content repeated
# --------------------------------------------------------------------------

def test_one_off_repeats_sees_a_pasted_leaf_repeated():
    gravel = _photo("gravel")[:256, :256]
    leafy = with_leaves(gravel, [(150, 100, 18, ORANGE)])
    tiled = metrics.one_off_repeats(np.tile(leafy, (3, 3, 1)), leafy)
    assert tiled.rarity > tiled.threshold
    y0, x0, y1, x1 = tiled.box
    assert y0 <= 150 < y1 and x0 <= 100 < x1 and (y1 - y0) * (x1 - x0) < 0.05 * 256 * 256  # the leaf, not more
    assert tiled.copies == 9 and tiled.per_photo_area == pytest.approx(1.0) and not tiled.within
    # the photo itself shows its leaf once: within
    once = metrics.one_off_repeats(leafy, leafy)
    assert once.copies == 1 and once.within
    # a zoomed-out view (twice the pixel size) of the same tiling: the leaf at half size, found as often
    h, w = 3 * 256, 3 * 256
    far = np.tile(leafy, (3, 3, 1)).reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3))
    assert metrics.one_off_repeats(far, leafy, zoom=2.0).copies == 9
    # the control: the same tiling of the photo without the leaf holds nothing one-off
    plain = np.repeat(gravel[:, :, None], 3, axis=2)
    clean = metrics.one_off_repeats(np.tile(plain, (3, 3, 1)), plain)
    assert clean.box is None and clean.copies == 0 and clean.within and clean.rarity < clean.threshold


@pytest.mark.parametrize("name", ["gravel", "brick", "grass", "moon"])
def test_one_off_repeats_finds_nothing_in_whole_photos(name):
    """Stones, bricks, blades and craters look like many others in their photo (moon's sparse craters
    on flat ground are the closest to the threshold: 6.8 against 8)."""
    photo = _photo(name)
    r = metrics.one_off_repeats(np.tile(photo, (2, 2)), photo)
    assert r.box is None and r.within and r.rarity < r.threshold, r.rarity


def test_one_off_repeats_refuses_bad_input():
    photo = _photo("gravel")[:64, :64]
    with pytest.raises(ValueError, match="zoom"):
        metrics.one_off_repeats(photo, photo, zoom=0.5)
    with pytest.raises(ValueError, match="threshold"):
        metrics.one_off_repeats(photo, photo, threshold=0.0)
    with pytest.raises(ValueError, match="reference"):
        metrics.one_off_repeats(photo, photo[:16, :16])


def test_fit_report_and_compare_say_a_one_off_object_repeats(tmp_path, capsys):
    """A texture whose one layer is a photo with a leaf shows the leaf once per photo area: the fit
    report and ``spectex compare`` say so; the same without the leaf, nothing."""
    from spectex.cli import main
    from spectex.fitting import fit_report
    from spectex.texture import Layer, SpectralTexture

    gravel = _photo("gravel")[:256, :256]
    reports = {}
    for name, photo in (("leaf", with_leaves(gravel, [(150, 100, 18, ORANGE)])), ("plain", with_leaves(gravel, []))):
        tile = np.dstack([photo, np.ones((256, 256), np.float32)]).astype(np.float32)
        reports[name] = fit_report(SpectralTexture(tile, [Layer(size=256.0)]), photo, pixel_size=1.0,
                                   coarse_zoom=None).one_off
    assert reports["leaf"].copies == 4 and not reports["leaf"].within  # a bake of 2 x 2 photo areas
    assert reports["plain"].box is None and reports["plain"].within
    leafy = with_leaves(gravel, [(150, 100, 18, ORANGE)])
    np.save(tmp_path / "photo.npy", leafy.astype(np.float32))
    np.save(tmp_path / "tiled.npy", np.tile(leafy, (2, 2, 1)).astype(np.float32))
    assert main(["compare", str(tmp_path / "tiled.npy"), "--reference", str(tmp_path / "photo.npy")]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("one-off content"))
    assert "shown 4 times" in line and "REPEATED" in line, line
