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
            "aligned": {"structure": 1.05, "repeat": 0.05, "breaks": 1.0, "splits": 1.0, "continuity": 1.0}}
    assert _auto._choose(ways, 0.0) == "aligned"
    ways["snapped"]["continuity"] = 0.95
    assert _auto._choose(ways, 0.0) == "snapped"


def test_the_aligned_way_is_chosen_only_about_as_close_as_the_others():
    """A game's boards with thin butt joints: drawn aligned they lost their joints and showed the tile's
    columns as stripes once per tile (structure 1.79), though that way alone neither repeated, broke, moved
    nor split; it is passed over for the closer ways (1.09-1.15). The control: aligned within
    ``TRIAL_MARGIN`` of them is chosen."""
    ways = {"periodic": {"structure": 1.23, "repeat": 0.54, "breaks": 1.04, "splits": 0.61, "continuity": 0.97},
            "snapped": {"structure": 1.15, "repeat": 0.20, "breaks": 2.06, "splits": np.inf, "continuity": 0.82},
            "stochastic": {"structure": 1.09, "repeat": 0.17, "breaks": 1.73, "splits": np.inf, "continuity": 0.80},
            "aligned": {"structure": 1.79, "repeat": 0.07, "breaks": 0.85, "splits": 0.63, "continuity": 1.0}}
    assert _auto._choose(ways, 0.052) != "aligned"
    ways["aligned"]["structure"] = 1.15
    assert _auto._choose(ways, 0.052) == "aligned"


@pytest.mark.slow
def test_fit_of_boards_without_joints_keeps_their_edges_in_line(monkeypatch):
    """Boards of uneven widths without joints (the tile's courses have no map, no gradient along them): drawn
    from a crop of whole periods at the photo's pixels with its columns in place, each patch shifted along
    them only (snap (1, 0)), the edges run on (continuity of a 1024 bake 1.06 of the photo's; the trial's
    ``line_breaks`` 1.05, structure 1.26). The control, without that way: snapped to whole periods, the edges
    step aside at every patch (0.97) and kink (the trial's ``line_breaks`` 4.2, structure 2.2)."""
    from spectex.render.cpu import bake

    photo = _boards()

    def edges_of(result):
        baked = np.asarray(bake(result.texture, (1024, 1024), pixel_size=result.pixel_size))
        return line_continuity(baked, photo, axis=0, length=256).ratio

    result = fit_result(photo)
    trial = result.params["trial"]
    assert trial["choice"] == "aligned" and result.params["snap"] == (1, 0)
    assert "its columns kept in line" in result.params["tile_method"]
    assert result.texture.tile_shape[0] == 470  # 10 periods of 47.03 px, not resampled
    assert trial["aligned"]["breaks"] < 1.2 < _auto.BREAK_LIMIT < trial["snapped"]["breaks"]
    aligned = edges_of(result)
    monkeypatch.setattr(_auto, "_courses_unmapped", lambda tile, snap: False)
    control = fit_result(photo)
    assert control.params["trial"]["choice"] != "aligned" and "aligned" not in control.params["trial"]
    assert aligned > 1.0 and edges_of(control) < min(0.98, aligned - 0.05)


def test_rows_of_bricks_are_not_boards():
    """The aligned way is for boards alone: their gradient runs across them (the edges), under
    ``BOARD_ALONG_SHARE`` along; flat bricks four times as long as high put 0.16 along their rows (a game's brick
    rows 0.36: drawn aligned, its bricks were merged and cut by the patches' edges)."""
    from test_cells import _running_bond

    assert _auto._along_share(_boards(), (None, 47.03)) < 0.02
    bond = np.repeat(np.repeat(_running_bond(periods=8)[0], 2, axis=0), 2, axis=1)  # courses along x, 16 px
    assert _auto._along_share(bond, (16.0, None)) > _auto.BOARD_ALONG_SHARE + 0.03
    assert _auto._along_share(_boards(), (47.03, 47.03)) == 1.0  # a lattice: not one axis


@pytest.mark.gl
@pytest.mark.slow
def test_boards_drawn_aligned_gl_matches_cpu_and_is_alias_free(gl):
    """The aligned layer (snap (1, 0): no shift across, whole texels along) in OpenGL = the CPU >= 40 dB on
    the five test views, and alias-free: >= 38 dB against 16 x 16 supersampled renders without mip-maps
    after a blur of one pixel (where aliasing shows), where the renders without mip-maps fall 3 dB lower
    but for the close-up."""
    from helpers import psnr_low, views_against_reference

    texture = fit_result(_boards()).texture
    assert texture.layers[0].snap == (1, 0)
    scores = {name: (psnr_low(c, ref), psnr_low(g, ref), psnr_low(plain, ref))
              for name, _, c, g, ref, plain in views_against_reference(texture, gl)}
    assert min(min(v[:2]) for v in scores.values()) >= 38.0, scores
    assert all(v[2] <= v[0] - 3.0 for k, v in scores.items() if k != "close"), scores


def _moved(photo, seed=0):
    """Strips of 128 rows of ``photo``, each moved across by whole mean widths (50 px)."""
    rng = np.random.default_rng(seed)
    moved = photo.copy()
    for i in range(photo.shape[0] // 128):
        rows = slice(128 * i, 128 * (i + 1))
        moved[rows] = np.roll(photo[rows], 50 * int(rng.integers(1, 9)), axis=1)
    return moved


def test_compare_measures_the_lines_of_a_structure_along_one_axis():
    """``metrics.compare`` with a period along one axis gives ``lines`` (the boards moved across 0.81); with a
    lattice, or without a period, none."""
    from spectex.metrics import compare

    photo = _boards()
    found = compare(_moved(photo), reference=photo, period=(None, 47.03)).lines
    assert found is not None and found.ratio < 0.9 and found.axis == 0
    assert compare(photo, reference=photo, period=(None, 47.03)).lines.ratio == pytest.approx(1.0)
    assert compare(photo, reference=photo, period=(47.03, 47.03)).lines is None
    assert compare(photo, reference=photo).lines is None


def test_spectex_compare_and_fit_report_say_whether_the_lines_hold(tmp_path, capsys):
    """``spectex compare`` prints the lines' continuity against a reference of boards (the period it finds
    itself): the moved strips under 0.9, the photo itself 1.00; a reference of noise, no line. ``spectex fit``
    of the boards reports it on its bake."""
    from helpers import spectex_compare_line
    from spectex import io
    from spectex.cli import main

    photo = _boards()
    io.write_image(tmp_path / "boards.png", photo)
    line = spectex_compare_line(tmp_path, capsys, _moved(photo), tmp_path / "boards.png", "lines kept")
    assert float(line.split("=")[1].split("x")[0]) < 0.9, line
    line = spectex_compare_line(tmp_path, capsys, photo, tmp_path / "boards.png", "lines kept")
    assert line.split("=")[1].strip().startswith("1.00x"), line
    noise = np.random.default_rng(0).random((256, 256, 3)).astype(np.float32)
    io.write_image(tmp_path / "noise.png", noise)
    assert main(["compare", str(tmp_path / "noise.png"), "--reference", str(tmp_path / "noise.png")]) == 0
    assert "lines kept" not in capsys.readouterr().out
    assert main(["fit", str(tmp_path / "boards.png"), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    said = [x for x in out.splitlines() if "lines along y holding their places" in x]
    assert len(said) == 1, out
    assert float(said[0].split("lines along y holding their places ")[1].split("x")[0]) >= 0.9
