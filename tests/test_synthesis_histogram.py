"""Independent sampling and exact histogram matching."""

import numpy as np
import pytest
import skimage.data

from spectex import metrics
from spectex.synthesis import match_histogram, sample_histogram


@pytest.fixture(scope="module")
def grass():
    return (skimage.data.grass()[:64, :64] / 255.0).astype(np.float32)


@pytest.fixture(scope="module")
def colour():
    g = skimage.data.gravel()[:48, :48] / 255.0
    # strongly correlated channels: a brown-grey ramp
    return np.stack([0.2 + 0.7 * g, 0.15 + 0.5 * g, 0.1 + 0.3 * g ** 2], axis=2).astype(np.float32)


def test_sampling_keeps_the_histogram_not_the_structure(grass):
    out = sample_histogram(grass, (80, 96), rng=0)
    assert out.shape == (80, 96) and out.dtype == np.float32
    assert metrics.histogram_w1(grass, out)[0] <= 0.03
    assert metrics.band_power_distance(grass, out) > 1.5  # white noise: the bad control


def test_joint_sampling_keeps_colours_per_channel_does_not(colour):
    colours = {tuple(p) for p in colour.reshape(-1, 3)}
    joint = sample_histogram(colour, (32, 32), rng=1)
    assert all(tuple(p) in colours for p in joint.reshape(-1, 3))
    split = sample_histogram(colour, (32, 32), joint=False, rng=1)
    assert np.all(metrics.histogram_w1(colour, split) <= 0.03)
    assert np.mean([tuple(p) in colours for p in split.reshape(-1, 3)]) < 0.2


def test_sampling_is_deterministic(grass):
    np.testing.assert_array_equal(sample_histogram(grass, 16, rng=3), sample_histogram(grass, 16, rng=3))
    assert not np.array_equal(sample_histogram(grass, 16, rng=3), sample_histogram(grass, 16, rng=4))


def test_matching_is_exact_and_keeps_the_order(grass):
    rng = np.random.default_rng(0)
    image = rng.random(grass.shape).astype(np.float32)
    out = match_histogram(image, grass)
    np.testing.assert_array_equal(np.sort(out.ravel()), np.sort(grass.ravel()))
    assert metrics.histogram_w1(grass, out)[0] == 0.0
    # the image's order is kept: ranks of distinct inputs are monotone in the output
    order = np.argsort(image.ravel())
    assert np.all(np.diff(out.ravel()[order]) >= 0)


def test_matching_different_sizes_uses_quantiles(grass):
    image = np.linspace(0, 1, 30 * 20, dtype=np.float32).reshape(30, 20)
    out = match_histogram(image, grass)
    assert out.shape == (30, 20)
    assert metrics.histogram_w1(grass, out)[0] < 0.01


def test_flat_image_gets_the_whole_histogram(grass):
    out = match_histogram(np.full(grass.shape, 0.5, np.float32), grass, rng=0)
    np.testing.assert_array_equal(np.sort(out.ravel()), np.sort(grass.ravel()))


def test_joint_matching_moves_the_joint_distribution(colour):
    # Independent channels have none of the exemplar's correlation; per-channel
    # matching keeps them independent, joint matching brings the correlation in.
    rng = np.random.default_rng(2)
    image = rng.random(colour.shape).astype(np.float32)
    per = match_histogram(image, colour)
    joint = match_histogram(image, colour, joint=True, rng=0)
    corr = lambda im: np.corrcoef(im[:, :, 0].ravel(), im[:, :, 1].ravel())[0, 1]  # noqa: E731
    assert corr(colour) > 0.99
    assert abs(corr(per)) < 0.1
    assert corr(joint) > 0.9
    np.testing.assert_allclose(metrics.histogram_w1(colour, joint), 0.0, atol=1e-7)  # marginals exact too


def test_channel_mismatch_is_an_error(grass, colour):
    with pytest.raises(ValueError, match="same number of channels"):
        match_histogram(grass, colour)
    with pytest.raises(ValueError, match="iterations must be >= 1, got 0"):
        match_histogram(colour, colour, joint=True, iterations=0)
