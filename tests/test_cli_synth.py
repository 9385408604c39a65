"""spectex synth / text / compare: outputs, conversions, one-line errors, nothing left behind."""

import json

import numpy as np
import pytest
import skimage.data
from PIL import Image

from helpers import error_line
from spectex.cli import main
from spectex.io import read_image, write_image


@pytest.fixture
def folder(tmp_path):
    grey = skimage.data.gravel()[:64, :64]
    Image.fromarray(grey).save(tmp_path / "grey.png")
    rgb = np.stack([grey, skimage.data.grass()[:64, :64], grey[::-1]], axis=2)
    Image.fromarray(rgb).save(tmp_path / "rgb.png")
    Image.fromarray(rgb).convert("P", palette=Image.ADAPTIVE, colors=32).save(tmp_path / "palette.png")
    rgba = np.dstack([rgb, np.full((64, 64), 200, np.uint8)])
    Image.fromarray(rgba).save(tmp_path / "rgba.png")
    write_image(tmp_path / "deep.png", grey.astype(np.float32) / 255.0, bit_depth=16)
    (tmp_path / "corpus.txt").write_text("the cat sat on the mat and the dog sat on the log " * 5)
    (tmp_path / "empty.txt").write_text("")
    return tmp_path




@pytest.mark.parametrize("method, extra", [
    ("histogram", []),
    ("quilting", ["--block", "16", "--overlap", "3"]),
    ("efros-leung", ["--window", "7"]),
])
def test_synth_methods_write_the_requested_size(folder, capsys, method, extra):
    out = folder / f"{method}.png"
    assert main(["synth", str(folder / "rgb.png"), "--method", method, "--size", "40x30",
                 "--seed", "3", "-o", str(out), *extra]) == 0
    img = read_image(out)
    assert img.shape == (30, 40, 3)
    assert "wrote" in capsys.readouterr().out


def test_synth_histogram_match(folder, capsys):
    from spectex import metrics

    out = folder / "matched.png"
    assert main(["synth", str(folder / "rgb.png"), "--method", "histogram", "--match", str(folder / "rgba.png"),
                 "--colours", "per-channel", "-o", str(out)]) == 2  # 4 channels against 3
    assert "same number of channels" in error_line(capsys)
    assert not out.exists()
    noise = np.random.default_rng(0).integers(0, 256, (50, 70), dtype=np.uint8)
    Image.fromarray(noise).save(folder / "noise.png")
    assert main(["synth", str(folder / "grey.png"), "--method", "histogram", "--match",
                 str(folder / "noise.png"), "-o", str(out)]) == 0
    assert read_image(out).shape == (50, 70)
    assert metrics.histogram_w1(read_image(folder / "grey.png"), read_image(out))[0] < 0.002


def test_synth_tileable_quilt(folder):
    from spectex import metrics

    out = folder / "tile.png"
    assert main(["synth", str(folder / "grey.png"), "--size", "64x64", "--block", "16", "--tileable",
                 "-o", str(out)]) == 0
    assert metrics.tileability(read_image(out)) <= 2.0


def test_synth_reuse_is_the_librarys_penalty(folder):
    # --reuse reaches quilt(reuse=): the same quilt as the library's with it, another than without it
    from spectex.synthesis import quilt

    out = folder / "reuse.png"
    assert main(["synth", str(folder / "grey.png"), "--size", "96x96", "--block", "16", "--reuse", "1",
                 "--seed", "2", "-o", str(out)]) == 0
    exemplar = read_image(folder / "grey.png")
    expected = quilt(exemplar, (96, 96), block=16, rng=2, reuse=1.0)
    np.testing.assert_allclose(read_image(out), expected, atol=0.5 / 255)
    assert np.abs(quilt(exemplar, (96, 96), block=16, rng=2) - expected).max() > 0.1


@pytest.mark.parametrize("name, channels", [("palette.png", 3), ("rgba.png", 4), ("grey.png", None)])
def test_synth_documented_conversions(folder, name, channels):
    out = folder / f"out_{name}"
    assert main(["synth", str(folder / name), "--size", "32x32", "--block", "16", "-o", str(out)]) == 0
    img = read_image(out)
    assert (img.ndim == 2) if channels is None else (img.shape[2] == channels)
    if name == "rgba.png":  # alpha is synthesised like a colour: copied as it is
        np.testing.assert_allclose(img[:, :, 3], 200 / 255, atol=1e-6)


# spectex.io.read_image leaves pypng's file open for 16-bit PNGs (a ResourceWarning
# at garbage collection); reported to the io owner, ignored here until fixed.
@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
@pytest.mark.filterwarnings("ignore::ResourceWarning")
def test_synth_16_bit_in_and_out(folder):
    out = folder / "deep_out.png"
    assert main(["synth", str(folder / "deep.png"), "--size", "32x32", "--block", "16", "--bit-depth", "16",
                 "-o", str(out)]) == 0
    with Image.open(out) as im:
        assert im.mode.startswith("I;16") or im.mode == "I"


@pytest.mark.parametrize("args, message", [
    (["--method", "efros-leung", "--window", "10"], "window must be odd, got 10"),
    (["--method", "efros-leung", "--window", "99"], "window=99 is larger than the exemplar (64x64 pixels)"),
    (["--block", "80"], "exemplar of 64x64 pixels is smaller than block=80"),
    (["--block", "16", "--overlap", "16"], "overlap must be smaller than block=16, got 16"),
    (["--bit-depth", "16", "-o", "{folder}/x.jpg"], "--bit-depth 16 needs a .png output"),
    (["--reuse", "-1"], "--reuse must be >= 0.0, got -1.0"),
    (["--method", "histogram", "--reuse", "1"], "--reuse does not apply to --method histogram (only to quilting)"),
])
def test_synth_bad_input_is_one_line_exit_2_and_no_file(folder, capsys, args, message):
    args = [a.replace("{folder}", str(folder)) for a in args]
    if "-o" not in args:
        args += ["-o", str(folder / "x.png")]
    before = set(folder.iterdir())
    assert main(["synth", str(folder / "rgb.png"), "--size", "32x32", *args]) == 2
    assert message in error_line(capsys)
    assert set(folder.iterdir()) == before  # no output, no temporary file


def test_synth_missing_exemplar_is_exit_2(folder, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["synth", str(folder / "nope.png"), "-o", str(folder / "x.png")])
    assert exc.value.code == 2
    assert "file not found" in error_line(capsys)


def test_text_prints_and_writes(folder, capsys):
    assert main(["text", str(folder / "corpus.txt"), "--unit", "word", "--order", "1", "--length", "12",
                 "--seed", "4"]) == 0
    words = capsys.readouterr().out.split()
    assert len(words) == 12 and set(words) <= {"the", "cat", "sat", "on", "mat", "and", "dog", "log"}
    out = folder / "text.txt"
    assert main(["text", str(folder / "corpus.txt"), "--length", "50", "-o", str(out)]) == 0
    assert len(out.read_text().strip()) == 50


def test_text_empty_corpus_is_exit_2(folder, capsys):
    out = folder / "never.txt"
    assert main(["text", str(folder / "empty.txt"), "-o", str(out)]) == 2
    assert "corpus is empty" in error_line(capsys)
    assert not out.exists()


def test_compare_prints_measures_and_labelled_side_by_side(folder, capsys):
    quilt = folder / "q.png"
    main(["synth", str(folder / "grey.png"), "--size", "96x96", "--block", "24", "-o", str(quilt)])
    capsys.readouterr()
    sbs = folder / "sbs.png"
    assert main(["compare", str(quilt), "--reference", str(folder / "grey.png"), "--block", "24", "--overlap", "4",
                 "-o", str(sbs)]) == 0
    text = capsys.readouterr().out
    for key in ("histogram W1", "band power distance", "tileability", "verbatim copy", "repetition",
                "seam energy"):
        assert key in text
    from spectex.figures import LABEL_HEIGHT

    picture = read_image(sbs)
    assert picture.shape == (LABEL_HEIGHT + 96, 64 + 8 + 96, 3)
    strip = picture[:LABEL_HEIGHT]
    assert strip[:, :64].min() < 0.2 and strip[:, 72:].min() < 0.2  # a label over each image
    assert main(["compare", str(folder / "rgb.png"), "--reference", str(folder / "grey.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert len(data["histogram_w1"]) == 1  # grey against colour: compared on luma


def test_compare_repetition_sees_a_tiled_image(folder, capsys):
    """A tiled exemplar, slightly blurred (no exact 8-bit copies survive), reads as repeating;
    the exemplar itself does not."""
    from scipy import ndimage

    rng = np.random.default_rng(3)
    tile = ndimage.gaussian_filter(rng.random((96, 96)), 1.0, mode="wrap")
    tile = (tile - tile.min()) / (tile.max() - tile.min())
    tiled = ndimage.gaussian_filter(np.tile(tile, (3, 3)), 0.6, mode="wrap") + rng.normal(0, 0.01, (288, 288))
    np.save(folder / "tile.npy", tile.astype(np.float32))
    np.save(folder / "tiled.npy", np.clip(tiled, 0, 1).astype(np.float32))
    assert main(["compare", str(folder / "tiled.npy"), "--reference", str(folder / "tile.npy"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["exact_repetition"] < 0.05  # the old number: blind to it
    assert data["repeat_peak_image"] > 0.5
    assert data["repeat_peak_reference"] < 0.1


def test_compare_two_images_without_reference_are_refused(folder, capsys):
    # Which one is the exemplar must be said (--reference): two bare images are not guessed at.
    grey = str(folder / "grey.png")
    assert main(["compare", grey, grey, "--json"]) == 2
    assert "--reference" in error_line(capsys)
    assert main(["compare", grey, "--reference", grey, "--json"]) == 0  # the control
    assert json.loads(capsys.readouterr().out)["histogram_w1"] == [0.0]


def test_compare_flat_images_give_strict_json(folder, capsys):
    Image.fromarray(np.full((40, 40), 90, np.uint8)).save(folder / "flat.png")
    assert main(["compare", str(folder / "flat.png"), "--reference", str(folder / "flat.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tileability_image"] is None and data["histogram_w1"] == [0.0]


def test_compare_bad_output_is_exit_2(folder, capsys):
    assert main(["compare", str(folder / "rgb.png"), "--reference", str(folder / "grey.png"),
                 "-o", str(folder / "x.txt")]) == 2
    assert "output must end in one of" in error_line(capsys)
