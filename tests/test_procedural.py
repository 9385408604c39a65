"""Tests of spectex.procedural and spectex.color."""

import numpy as np
import pytest

from spectex import color, procedural


def _seam_ratio(kind, tileable, seeds=range(3)):
    """Mean |step| across the wrap edges over the mean |step| across interior
    cell borders (the wrap edge always lies on a lattice line, where gradient
    noise steps differ from the average, so it is compared with its peers)."""
    wrap = inner = 0.0
    borders = range(16, 256, 16)
    for seed in seeds:
        img = procedural.texture(kind, (256, 256), scale=16, seed=seed, tileable=tileable)
        wrap += np.abs(img[:, 0] - img[:, -1]).mean() + np.abs(img[0] - img[-1]).mean()
        inner += (np.mean([np.abs(img[:, k] - img[:, k - 1]).mean() for k in borders])
                  + np.mean([np.abs(img[k] - img[k - 1]).mean() for k in borders]))
    return wrap / inner


@pytest.mark.parametrize("kind", ["perlin", "value", "fbm", "turbulence", "marble", "stripes", "clouds"])
def test_tileable_textures_are_seamless(kind):
    assert 0.8 < _seam_ratio(kind, True) < 1.2
    # Control: the same texture, not tileable, has a seam.
    assert _seam_ratio(kind, False) > 1.3


@pytest.mark.parametrize("kind", ["perlin", "fbm", "turbulence"])
def test_tileable_noise_wraps_exactly(kind):
    # One pixel beyond the right edge, the periodic noise equals column 0.
    from spectex import noise

    h, w, scale = 24, 40, 5
    img = procedural.noise_image((h, w), kind=kind, scale=scale, seed=3, tileable=True)
    px, py = 5, max(1, round(scale * h / w))
    x_beyond = np.float32((w + 0.5) * px / w)
    y = ((np.arange(h) + 0.5) * py / h).astype(np.float32)
    fn = {"perlin": noise.perlin, "fbm": noise.fbm, "turbulence": noise.turbulence}[kind]
    kwargs = {} if kind == "perlin" else {"octaves": 6}
    beyond = fn(x_beyond, y, seed=3, period=(px, py), **kwargs)
    np.testing.assert_allclose(beyond, img[:, 0], atol=1e-5)


@pytest.mark.parametrize("kind", procedural.KINDS)
def test_ranges_and_shapes(kind):
    img = procedural.texture(kind, (40, 56), seed=1)
    assert img.shape == (40, 56) and img.dtype == np.float32
    lo, hi = procedural.value_range(kind)
    assert img.min() >= lo - 0.05 and img.max() <= hi + 0.05
    assert img.std() > 0.02


def test_marble_is_the_sine_of_stripes_plus_turbulence():
    shape = (32, 48)
    turb = procedural.noise_image(shape, kind="turbulence", scale=4, octaves=6, seed=5)
    u = (np.arange(48) + 0.5) / 48
    want = np.sin(2 * np.pi * (3.0 * u[None, :] + 1.2 * turb))
    np.testing.assert_allclose(procedural.marble(shape, seed=5), want, atol=2e-5)


def test_stripes_is_noise_times_sine_of_x():
    shape = (32, 64)
    n = procedural.noise_image(shape, kind="fbm", scale=4, octaves=5, seed=3)
    u = (np.arange(64) + 0.5) / 64
    want = 0.5 * (n + 1) * np.sin(2 * np.pi * 8.0 * u)[None, :]
    np.testing.assert_allclose(procedural.stripes(shape, seed=3), want, atol=2e-5)


def test_animation_moves_smoothly_through_3d_noise():
    frames = procedural.animate("fbm", (32, 32), 5, speed=0.05, seed=4)
    assert len(frames) == 5
    steps = [np.abs(a - b).mean() for a, b in zip(frames, frames[1:])]
    assert all(0 < s < 0.05 for s in steps)
    # a big jump in time gives an unrelated image
    far = procedural.texture("fbm", (32, 32), seed=4, time=50.0)
    assert np.abs(far - frames[0]).mean() > 5 * max(steps)


def test_scale_sets_the_feature_size():
    # Twice the scale: the zero crossings of single-octave noise come twice as often.
    def crossings(img):
        return np.mean(np.signbit(img[:, 1:]) != np.signbit(img[:, :-1]))
    a = crossings(procedural.noise_image((64, 512), kind="perlin", scale=8))
    b = crossings(procedural.noise_image((64, 512), kind="perlin", scale=16))
    assert 1.6 < b / a < 2.4


def test_colormaps():
    v = np.linspace(-1, 1, 11)
    grey = color.apply_colormap(v, "grey")
    np.testing.assert_allclose(grey[:, 0], (v + 1) / 2, atol=1e-6)
    assert color.apply_colormap(v, "viridis").shape == (11, 3)
    custom = color.apply_colormap(np.array([0.0, 0.5, 1.0]), [(0, (1, 0, 0)), (1, (0, 0, 1))], vmin=0, vmax=1)
    np.testing.assert_allclose(custom[1], [0.5, 0, 0.5], atol=1e-6)
    assert np.isnan(color.apply_colormap(np.array([np.nan]), "earth")).all()
    with pytest.raises(ValueError, match="^colormap must be one of .* got 'nope'$"):
        color.apply_colormap(v, "nope")
    with pytest.raises(ValueError, match=r"^vmax must be greater than vmin, got vmin=1.0, vmax=1.0$"):
        color.apply_colormap(v, "grey", vmin=1, vmax=1)
    with pytest.raises(ValueError, match="positions must be non-decreasing"):
        color.apply_colormap(v, [(1, (0, 0, 0)), (0, (1, 1, 1))])


def test_contrast_range_fills_the_ramp():
    img = procedural.texture("fbm", (64, 64), seed=1)
    rgb = procedural.colorize(img, "grey", kind="fbm")
    assert rgb.min() < 0.02 and rgb.max() > 0.98


@pytest.mark.parametrize("call,message", [
    (lambda: procedural.texture("plasma", (8, 8)), "kind must be one of"),
    (lambda: procedural.texture("fbm", (0, 8)), "shape[0] must be >= 1, got 0"),
    (lambda: procedural.texture("fbm", (8, 8), scale=-1), "scale must be > 0.0, got -1.0"),
    (lambda: procedural.animate("fbm", (8, 8), 0), "frames must be >= 1, got 0"),
    (lambda: procedural.texture("marble", (8, 8), strength=float("inf")), "strength must be finite, got inf"),
    (lambda: procedural.clouds((8, 8), cover=2), "cover must be <= 1.0, got 2.0"),
])
def test_errors(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert message in str(info.value)


def test_wood_rings_are_antialiased(monkeypatch):
    """Each pixel is the box-filtered ring profile: against an 8 x 8
    supersampled picture of the same field, the anti-aliased wood is much
    closer than point sampling (the control: the same wood with a zero
    footprint, whose ring edges are stair-stepped)."""
    from spectex import procedural as P

    kw = dict(rings=24.0, seed=3)
    truth = P.wood((1024, 1024), **kw).reshape(128, 8, 128, 8).mean(axis=(1, 3))
    aa = P.wood((128, 128), **kw)
    monkeypatch.setattr(P, "_footprint", lambda t: np.zeros_like(t))
    point = P.wood((128, 128), **kw)
    err_aa = np.sqrt(np.mean((aa - truth) ** 2))
    err_point = np.sqrt(np.mean((point - truth) ** 2))
    assert err_aa < 0.5 * err_point, (err_aa, err_point)
    assert aa.min() >= -1.0 and aa.max() <= 1.0


def test_ring_profile_box_filter_reference_values():
    from spectex.procedural import ring_profile

    # zero width: the profile itself; a whole ring: its mean, -1/2, wherever it starts
    np.testing.assert_allclose(ring_profile([0.0, 0.5, 0.999], 0.0), [-1.0, -0.75, 2 * 0.999 ** 3 - 1], atol=1e-12)
    np.testing.assert_allclose(ring_profile([0.3, 7.9, -2.2], 1.0), -0.5, atol=1e-12)
    # across an edge: half a ring of each side, the mean of 2x^3 - 1 over [0.5, 1] and [0, 0.5]
    expect = ((0.5 * 1 - 1) - (0.5 * 0.5 ** 4 - 0.5) + (0.5 * 0.5 ** 4 - 0.5)) / 1.0
    np.testing.assert_allclose(ring_profile(1.0, 1.0), expect, atol=1e-12)
