"""A photo that repeats itself exactly (a texture tiled two by two or three by three before it was saved) is
read as one cell of it: its copies hold nothing more, and read as content the texture drew them (issue 22:
structure kept, never repeated)."""

import numpy as np
import pytest

from helpers import floor_photo
from spectex import metrics
from spectex.fitting import _core, _structure, fit_result
from spectex.fitting._structure import repeat_cell
from spectex.render import bake


def _gravel():
    import skimage.data

    grey = skimage.data.gravel().astype(np.float64) / 255.0
    return np.stack([grey, 0.9 * grey, 0.8 * grey], axis=2)


def test_repeat_cell_finds_the_copies_of_a_tiled_texture():
    gravel = _gravel()
    for copies in (2, 3):
        side = 512 // copies
        tiled = np.tile(gravel[:side, :side], (copies, copies, 1))
        lags, scores = repeat_cell(tiled)
        assert lags == (side, side) and min(scores) > 0.999
        # saved with a little noise (a JPEG's), still copies
        noisy = np.clip(tiled + np.random.default_rng(1).normal(0.0, 0.01, tiled.shape), 0.0, 1.0)
        assert repeat_cell(noisy)[0] == (side, side)
    # a strip of copies: along one axis only
    assert repeat_cell(np.tile(gravel[:128], (3, 1, 1)))[0] == (128, None)
    # controls: the photo itself, and a smooth ramp (high correlation at every short lag, no repeat)
    assert repeat_cell(gravel[:510, :510])[0] == (None, None)
    y, x = np.mgrid[:256, :256] / 256.0
    ramp = np.stack([0.5 * x + 0.3 * y] * 3, axis=2) + np.random.default_rng(2).normal(0.0, 0.02, (256, 256, 3))
    assert repeat_cell(ramp)[0] == (None, None)


@pytest.mark.slow
def test_a_texture_tiled_three_by_three_is_fitted_from_one_cell_and_never_repeats(monkeypatch):
    """Before, the tiling read as a structure of period 170 and was drawn snapped to it: its repeat over a bake
    0.83 on a photo of dirt. The control, the rule switched off, draws the repeat again."""
    tiled = np.tile(_gravel()[:170, :170], (3, 3, 1))

    def repeat_over_a_bake(result):
        view = bake(result.texture, (768, 768), pixel_size=result.pixel_size, origin=(0.013, 0.029))
        return metrics.repeat_peak(view[:, :, :3])

    result = fit_result(tiled)
    assert result.params["repeat"]["cell"] == [170, 170]
    assert any("repeats itself exactly" in note for note in result.notes)
    assert result.params["period_px"] is None  # the cell read as what it is: gravel
    assert repeat_over_a_bake(result) <= 0.1

    monkeypatch.setattr(_structure, "REPEAT_EXACT", 1.01)
    control = fit_result(tiled)
    assert control.params["repeat"] is None
    assert repeat_over_a_bake(control) > 0.3


def test_a_tiled_wall_and_a_pattern_of_motifs_keep_the_whole_photo(monkeypatch):
    """A structure finer than the repeat (floor tiles of 48 pixels, four to a 192-pixel cell, tiled two by two)
    keeps the whole photo, its tile cut at its own period, the tiling recorded for the trial; a pattern of one
    large motif per period (a disc per 96-pixel cell) and a short exact period (tiles of 32 pixels repeating
    exactly) are the pattern's own. Controls: without the first two rules the cells are read alone."""
    floor = np.tile(floor_photo(192, period=48, spread=0.1, mottle=0.1)[0].astype(np.float64), (2, 2, 1))
    y, x = np.mgrid[:96, :96]
    disc = (np.hypot(y - 47.5, x - 47.5) < 30).astype(np.float64)
    rng = np.random.default_rng(4)
    motif = np.clip(np.stack([0.3 + 0.4 * disc] * 3, axis=2) + rng.normal(0.0, 0.05, (96, 96, 3)), 0.0, 1.0)
    motifs = np.tile(motif, (4, 4, 1))
    short = np.tile(floor_photo(128, period=32)[0].astype(np.float64), (2, 2, 1))
    for photo in (floor, motifs, short):
        assert repeat_cell(photo)[0] != (None, None)  # each repeats exactly ...
    notes = []
    whole, record = _core._one_repeat(floor, notes)  # ... the floor read whole, its tiling recorded ...
    assert whole is floor and record["whole"] and record["cell"] == [192, 192]
    assert "its structure is finer" in notes[0]
    for photo in (motifs, short):
        notes = []
        assert _core._one_repeat(photo, notes) is None and notes == []  # ... the patterns as they are
    monkeypatch.setattr(_core, "REPEAT_FINER", 0.0)
    cell, record = _core._one_repeat(floor, [])
    assert cell.shape[:2] == (192, 192) and not record["whole"]
    monkeypatch.setattr(_core, "REPEAT_MOTIF_SHARE", 1.0)
    assert _core._one_repeat(motifs, [])[1]["cell"] == [96, 96]
    assert _core._one_repeat(short, []) is None  # 32 pixels: the pattern's own period, whatever the other rules


def test_a_large_photo_of_two_copies_is_read_as_one_at_full_resolution(monkeypatch):
    """A 2048-pixel photo of a 1024-pixel texture tiled two by two: the fit analyses at most 512 pixels, and
    a crop of the photo resampled holds less than two copies (their repeat past half its side). The repeat is
    read on a preview of the whole photo and confirmed on the photo, and the photo is its top left cell from
    the first step on."""
    from scipy import ndimage

    gravel = ndimage.zoom(_gravel(), (2, 2, 1), order=1)  # 1024 pixels
    photo = np.tile(gravel, (2, 2, 1)).astype(np.float32)
    exemplar, notes, factor, source, repeat = _core._prepared_with_source(photo, 512)
    assert repeat["lags"] == [1024, 1024] and min(repeat["correlation"]) > 0.999
    assert any("every 1024 px along y and every 1024 px along x" in note for note in notes)
    if source is not None:  # the cell is the source the full-resolution tile reads
        assert source["photo"].shape[:2] == (1024, 1024)
    # the control: without the rule, the analysed crop is read, and it shows no repeat for a later step to find
    monkeypatch.setattr(_structure, "REPEAT_EXACT", 1.01)
    crop, _, _, _, none = _core._prepared_with_source(photo, 512)
    assert none is None and crop.shape[:2] == (512, 512)
    monkeypatch.undo()
    assert repeat_cell(crop)[0] == (None, None)


def test_a_tiled_structure_is_not_drawn_with_its_tiling(monkeypatch):
    """Floor tiles of 48 pixels, four to a 192-pixel copy, tiled two by two: the fit reads the whole photo, and
    its trial reads the photo's own repeat on one copy (0.11), so the periodic way, which repeats every copy,
    does not pass; the control, the repeat read on the whole (1.0, the tiling's), draws it periodic."""
    from spectex.fitting import _auto

    floor = np.tile(floor_photo(192, period=48, spread=0.1, mottle=0.1)[0].astype(np.float64), (2, 2, 1))
    result = fit_result(floor)
    assert result.params["repeat"]["whole"]
    trial = result.params["trial"]
    assert trial["choice"] != "periodic" and trial["photo_repeat"] < 0.3
    monkeypatch.setattr(_auto, "_copy_side", lambda *args: None)
    control = fit_result(floor).params["trial"]
    assert control["choice"] == "periodic" and control["photo_repeat"] > 0.9


def test_the_report_of_a_tiled_photo_says_its_one_off_content_is_in_every_copy(tmp_path, capsys):
    """The fit keeps a copy's one-off content (a red stone): the photo shows it once a copy, and the report
    says so. The control: the copy alone, its stone kept (--keep-one-off), is shown as often, and the report
    tells the user to crop it out."""
    from spectex import io
    from spectex.cli import main

    cell = _gravel()[:256, :256].copy()
    y, x = np.mgrid[:256, :256]
    cell[np.hypot(y - 60, x - 90) < 14] = (1.0, 0.2, 0.2)  # a red stone, once in the copy
    lines = []
    for name, photo, extra in (("tiled", np.tile(cell, (2, 2, 1)), []), ("cell", cell, ["--keep-one-off"])):
        path = tmp_path / f"{name}.png"
        io.write_image(path, photo.astype(np.float32))
        assert main(["fit", str(path), "-o", str(tmp_path / name)] + extra) == 0
        out = capsys.readouterr().out
        lines.append(next(x for x in out.splitlines() if x.strip().startswith("structure")))
        assert ("the photo repeats itself exactly (every 256 px along y and every 256 px along x" in out) == (
            name == "tiled")
    assert "the photo shows it once in each of its copies" in lines[0] and "crop it out" not in lines[0]
    assert "the photo shows it once in each of its copies" not in lines[1] and "crop it out" in lines[1]
