"""One-off content left out of the fit (issue 22): a leaf on gravel is filled from the rest of the photo.

The measure that finds it (``spectex.metrics.one_off_repeats``) is tested with the other structural
measures in ``test_metrics_structure.py``; here the fill (``spectex.fitting._one_off``) and the fit
that uses it, with ``keep_one_off=True`` as the control.
"""

import numpy as np
import pytest
import skimage.data as skimage_data

from helpers import ORANGE, with_leaves
from spectex._texture_stats import one_off_content
from spectex.fitting import fit_result
from spectex.fitting._one_off import remove_one_off


def _leafy(side=256, leaves=((150, 100, 18, ORANGE),)):
    """A crop of scikit-image's gravel as RGB with ``leaves`` pasted on it, and the same crop without them."""
    grey = skimage_data.gravel()[:side, :side].astype(np.float32) / 255.0
    return with_leaves(grey, leaves), with_leaves(grey, [])


def _orange(image):
    """How many pixels are a leaf's colour, orange or blue (gravel is grey)."""
    return int(np.sum(np.abs(image[..., 0] - image[..., 2]) > 0.4))


def test_remove_one_off_fills_the_leaf_from_the_photo_and_touches_nothing_else():
    photo, _ = _leafy()
    box, _, rarity = one_off_content(photo)
    assert box is not None and rarity > 8.0
    filled, source = remove_one_off(photo, box)
    assert source is not None and _orange(photo) > 100 and _orange(filled) == 0
    assert one_off_content(filled)[0] is None  # nothing one-off left
    changed = np.any(filled != photo, axis=2)
    ys, xs = np.nonzero(changed)
    y0, x0, y1, x1 = box
    # only around the region: inside its window (the box and a ring of half its larger side)
    ring = max(6, round(0.5 * max(y1 - y0, x1 - x0)))
    assert ys.min() >= y0 - ring and ys.max() < y1 + ring and xs.min() >= x0 - ring and xs.max() < x1 + ring
    # every changed pixel is the photo's own, from the window at the source, at the same offset
    wy0, wx0 = max(0, y0 - ring), max(0, x0 - ring)
    sy, sx = source
    assert np.array_equal(filled[ys, xs], photo[ys - wy0 + sy, xs - wx0 + sx])
    # the source window holds none of the leaf
    assert _orange(photo[sy:sy + (y1 + ring - wy0), sx:sx + (x1 + ring - wx0)]) == 0


def test_remove_one_off_refuses_a_region_too_large_to_fill():
    photo, _ = _leafy()
    same, source = remove_one_off(photo, (20, 20, 200, 200))
    assert source is None and same is photo


def test_fit_leaves_the_leaf_out_unless_asked_to_keep_it():
    photo, plain = _leafy()
    fitted = fit_result(photo, rng=0)
    assert len(fitted.params["one_off"]) == 1
    y0, x0, y1, x1 = fitted.params["one_off"][0]["box"]
    assert y0 <= 150 < y1 and x0 <= 100 < x1
    assert any("left out one-off content" in note for note in fitted.notes)
    assert _orange(fitted.texture.tiles[0][:, :, :3]) == 0
    kept = fit_result(photo, rng=0, keep_one_off=True)  # the control: the leaf is in the tile
    assert kept.params["one_off"] is None and _orange(kept.texture.tiles[0][:, :, :3]) > 50
    # a photo without one: the fit as before, nothing said
    clean = fit_result(plain, rng=0)
    assert clean.params["one_off"] is None and not any("one-off" in note for note in clean.notes)
    with pytest.raises(TypeError, match="keep_one_off"):
        fit_result(photo, keep_one_off="yes")


def test_fit_leaves_out_each_of_several_objects():
    """Two different objects, an orange leaf and a longer blue one: each region is found and filled in
    turn, largest first. (Objects alike mask each other, each the other's neighbour: two identical leaves
    score 4.0, an orange and a yellow one 7.2; the limit is in docs/fitting.md.)"""
    photo, _ = _leafy(leaves=((60, 60, 18, ORANGE), (190, 180, 24, (0.1, 0.3, 0.9))))
    fitted = fit_result(photo, rng=0)
    boxes = [region["box"] for region in fitted.params["one_off"]]
    assert len(boxes) == 2 and sum("left out one-off content" in note for note in fitted.notes) == 2
    for cy, cx in ((60, 60), (190, 180)):
        assert any(y0 <= cy < y1 and x0 <= cx < x1 for y0, x0, y1, x1 in boxes)
    assert _orange(fitted.texture.tiles[0][:, :, :3]) == 0


def test_spectex_fit_says_what_it_left_out(tmp_path, capsys):
    """The command's notes name the region and its source, and its report line counts the copies: 0;
    ``--keep-one-off`` reaches the fit as ``keep_one_off=True``."""
    from spectex import io
    from spectex.cli import build_parser, main

    photo, _ = _leafy()
    io.write_image(tmp_path / "leafy.png", photo)
    assert main(["fit", str(tmp_path / "leafy.png"), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "note: left out one-off content at x " in out and "--keep-one-off" in out
    line = next(x for x in out.splitlines() if x.strip().startswith("structure"))
    assert "one-off content at photo x " in line and "shown 0 times" in line
    parser, leafy = build_parser(), str(tmp_path / "leafy.png")
    assert parser.parse_args(["fit", leafy, "-o", "o", "--keep-one-off"]).keep_one_off is True
    assert parser.parse_args(["fit", leafy, "-o", "o"]).keep_one_off is False
