"""Boards side by side without joints, of uneven widths (issue 22): their edges kept in line, and the measure that
sees them moved (``spectex.metrics.line_continuity``)."""

import numpy as np
import pytest
from scipy import ndimage

from spectex.fitting import _auto, fit_result
from spectex.metrics import line_continuity


def _boards(side=512, mean=50.0, spread=0.12, seed=5):
    """Boards running the photo's whole height side by side, widths ``mean`` +- ``spread`` of it (uneven: no
    shift by whole periods lines their edges up), a dark groove at each edge, a tone per board, grain
    streaks along them."""
    rng = np.random.default_rng(seed)
    edges = [0.0]
    while edges[-1] < side:
        edges.append(edges[-1] + mean * (1.0 + spread * rng.uniform(-1.0, 1.0)))
    x = np.arange(side) + 0.5
    board = np.searchsorted(edges, x) - 1
    tone = 0.55 + 0.03 * rng.standard_normal(len(edges))
    grain = ndimage.gaussian_filter(rng.standard_normal((side, side)), (24.0, 0.8))
    lum = tone[board][None, :] + 0.025 * grain / grain.std()
    groove = np.min(np.abs(x[:, None] - np.asarray(edges)[None, :]), axis=1)
    lum = lum - 0.3 * np.exp(-0.5 * (groove / 2.0) ** 2)[None, :]
    return np.clip(lum[:, :, None] * np.array([1.0, 0.85, 0.62]), 0.0, 1.0).astype(np.float32)


def test_line_continuity_sees_edges_moved_across_and_not_shifted_along():
    """Strips of 128 rows of the boards, each moved across by whole mean widths (the edges end and go on a few
    pixels aside: widths are uneven) read 0.81; moved along the boards (their edges where they were) 1.01; the
    photo against itself 1; the same transposed, with the lines along the rows, reads the same."""
    photo = _boards()
    rng = np.random.default_rng(0)
    moved, along = photo.copy(), photo.copy()
    for i in range(4):
        rows = slice(128 * i, 128 * (i + 1))
        moved[rows] = np.roll(photo[rows], 50 * int(rng.integers(1, 9)), axis=1)
        along[rows] = np.roll(photo, int(rng.integers(20, 400)), axis=0)[rows]
    assert line_continuity(photo, photo, axis=0).ratio == pytest.approx(1.0)
    found = line_continuity(moved, photo, axis=0)
    assert found.ratio < 0.9 and found.length == 256 and found.axis == 0
    assert line_continuity(along, photo, axis=0).ratio > 0.97
    turned = line_continuity(moved.transpose(1, 0, 2), photo.transpose(1, 0, 2), axis=1)
    assert turned.ratio == pytest.approx(found.ratio)


@pytest.mark.parametrize("kwargs, words", [({"axis": 2}, "axis must be <= 1, got 2"),
                                           ({"axis": 0, "length": 4}, "length must be >= 8, got 4"),
                                           ({"axis": 0, "length": 100}, "length must be at most the images' "
                                                                        "extent along the lines (64), got 100")])
def test_line_continuity_refuses_bad_input(kwargs, words):
    image = np.random.default_rng(1).random((64, 64))
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        line_continuity(image, image, **kwargs)


def test_the_choice_passes_over_a_way_that_moves_the_lines():
    """Of two ways that neither repeat nor break nor split, the one whose continuity is under
    ``CONTINUITY_LIMIT`` of the photo's is not chosen, however close its structure; the control: with its
    continuity within the limit, the snapped way is (closer, and kept when in doubt)."""
    ways = {"snapped": {"structure": 1.0, "repeat": 0.05, "breaks": 1.0, "splits": 1.0, "continuity": 0.8},
            "aligned": {"structure": 1.2, "repeat": 0.05, "breaks": 1.0, "splits": 1.0, "continuity": 1.0}}
    assert _auto._choose(ways, 0.0) == "aligned"
    ways["snapped"]["continuity"] = 0.95
    assert _auto._choose(ways, 0.0) == "snapped"


@pytest.mark.slow
def test_fit_of_boards_without_joints_keeps_their_edges_in_line(monkeypatch):
    """Boards of uneven widths without joints (the tile's courses have no map): drawn with the tile's columns in
    place, each patch shifted along them only (snap (1, 0)), the edges run on (continuity of a 1024 bake
    1.13 of the photo's). The control, without that way: snapped to whole periods, the edges step aside at
    every patch (0.97) and kink (``line_breaks`` of the trial 4.2 against 1.0)."""
    from spectex.render.cpu import bake

    photo = _boards()

    def edges_of(result):
        baked = np.asarray(bake(result.texture, (1024, 1024), pixel_size=result.pixel_size))
        return line_continuity(baked, photo, axis=0, length=256).ratio

    result = fit_result(photo)
    assert result.params["trial"]["choice"] == "aligned" and result.params["snap"] == (1, 0)
    assert "its columns kept in line" in result.params["tile_method"]
    aligned = edges_of(result)
    monkeypatch.setattr(_auto, "_courses_unmapped", lambda tile, snap: False)
    control = fit_result(photo)
    assert control.params["trial"]["choice"] != "aligned" and "aligned" not in control.params["trial"]
    assert aligned > 1.05 and edges_of(control) < aligned - 0.1
