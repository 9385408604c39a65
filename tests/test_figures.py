"""spectex.figures: the labelled montages and plots that compare and fit write."""

import numpy as np
import pytest

from spectex import figures
from spectex.io import read_image


def test_montage_labels_each_image_and_keeps_the_pixels():
    a = np.zeros((20, 60), np.float32)
    b = np.random.default_rng(0).random((30, 50, 4)).astype(np.float32)
    out = figures.montage([a, b], ["left", "right"], gap=4, background=0.5)
    top = figures.LABEL_HEIGHT
    assert out.shape == (top + 30, 60 + 4 + 50, 3)
    np.testing.assert_array_equal(out[top:top + 20, :60], 0.0)
    np.testing.assert_array_equal(out[top:, 64:], b[:, :, :3])  # alpha dropped
    assert out[:top, :60].min() < 0.1 and out[:top, 64:].min() < 0.1  # dark text on each strip
    assert out[top + 20:, :60].min() == 0.5  # the canvas below the shorter image
    unlabelled = figures.montage([a, b], gap=4)
    assert unlabelled.shape == (30, 114, 3)
    np.testing.assert_array_equal(out[top:], unlabelled)


def test_montage_refuses_bad_labels():
    with pytest.raises(ValueError, match="labels must hold one label per image \\(2\\), got 1"):
        figures.montage([np.zeros((4, 4)), np.zeros((4, 4))], ["one"])
    with pytest.raises(ValueError, match="images must hold at least one image"):
        figures.montage([])


@pytest.mark.parametrize("suffix", [".png", ".svg"])
def test_plots_are_written(tmp_path, suffix):
    rng = np.random.default_rng(1)
    a = rng.random((64, 64, 3)).astype(np.float32)
    b = rng.random((96, 96, 3)).astype(np.float32) ** 2
    figures.plot_band_power(tmp_path / f"bands{suffix}", [a, b], ["a", "b"], segments=[None, (64, 64)])
    figures.plot_histograms(tmp_path / f"hist{suffix}", [a, b], ["a", "b"])
    if suffix == ".png":
        assert read_image(tmp_path / "bands.png").shape[:2] == (440, 640)
        assert read_image(tmp_path / "hist.png").shape[:2] == (320, 960)
    else:
        assert (tmp_path / "bands.svg").read_text().lstrip().startswith("<?xml")
    with pytest.raises(ValueError, match="labels must hold one label per image"):
        figures.plot_histograms(tmp_path / "x.png", [a, b], ["a"])
