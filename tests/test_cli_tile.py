"""Tests for ``spectex tile`` and ``spectex spectrum``."""

import numpy as np
import pytest
from PIL import Image

from helpers import run_fails
from spectex.cli import main
from spectex.io import read_image


def run_ok(argv, capsys):
    assert main(argv) == 0
    return capsys.readouterr().out




def test_tile_writes_rgba_png_and_preview(tmp_path, capsys):
    out = tmp_path / "tile.png"
    text = run_ok(["tile", "--size", "64", "--seed", "3", "--preview", "-o", str(out)], capsys)
    assert "64x64 RGBA" in text
    img = read_image(out)
    assert img.shape == (64, 64, 4)
    with Image.open(out) as im:
        assert im.mode == "RGBA"
    prev = read_image(tmp_path / "tile_preview.png")
    assert prev.shape == (192, 2 * 192 + 4, 3)
    # colour repeated 3 x 3 on the left, alpha on the right
    np.testing.assert_allclose(prev[:64, :64], img[:, :, :3], atol=1 / 255)
    np.testing.assert_allclose(prev[64:128, 64:128], img[:, :, :3], atol=1 / 255)
    np.testing.assert_allclose(prev[:64, 196:260, 0], img[:, :, 3], atol=1 / 255)
    # the same seed gives the same file contents
    out2 = tmp_path / "again.png"
    run_ok(["tile", "--size", "64", "--seed", "3", "-o", str(out2)], capsys)
    np.testing.assert_array_equal(read_image(out2), img)


def test_tile_16_bit_and_options(tmp_path, capsys):
    out = tmp_path / "t16.png"
    run_ok(["tile", "--size", "48x32", "--method", "octaves", "--alpha", "noise", "--colormap", "moss",
            "--bit-depth", "16", "-o", str(out)], capsys)
    img = read_image(out)
    assert img.shape == (32, 48, 4)
    assert np.any(np.abs(img * 255 - np.round(img * 255)) > 0.01)  # more than 8 bits
    out = tmp_path / "none.npy"
    run_ok(["tile", "--size", "32", "--alpha", "none", "--alpha-value", "0.25", "-o", str(out)], capsys)
    assert np.all(np.load(out)[:, :, 3] == 0.25)


def test_tile_kernel(tmp_path, capsys):
    """--kernel (octaves' magnification kernel) is used; --filter is not an option of tile."""
    new, old = tmp_path / "new.npy", tmp_path / "old.npy"
    run_ok(["tile", "--size", "32", "--method", "octaves", "--kernel", "box", "-o", str(new)], capsys)
    with pytest.raises(SystemExit) as refused:
        main(["tile", "--size", "32", "--method", "octaves", "--filter", "box", "-o", str(old)])
    assert refused.value.code == 2 and "--filter" in capsys.readouterr().err
    assert not old.exists()
    capsys.readouterr()
    other = tmp_path / "other.npy"
    run_ok(["tile", "--size", "32", "--method", "octaves", "-o", str(other)], capsys)  # bspline
    assert not np.array_equal(np.load(new), np.load(other))  # the kernel was used


@pytest.fixture
def photos(tmp_path):
    from skimage import data

    rgb = data.coffee()[:200, :240]  # (200, 240, 3)
    grey = data.grass()[:128, :160]
    files = {}
    files["rgb"] = tmp_path / "rgb.jpg"
    Image.fromarray(rgb).save(files["rgb"], quality=95)
    files["palette"] = tmp_path / "palette.png"
    Image.fromarray(rgb).convert("P", palette=Image.Palette.ADAPTIVE, colors=64).save(files["palette"])
    files["grey"] = tmp_path / "grey.png"
    Image.fromarray(grey).save(files["grey"])
    files["grey16"] = tmp_path / "grey16.png"
    Image.fromarray(grey.astype(np.uint16) * 257).save(files["grey16"])
    rgba = np.dstack([rgb, np.tile(np.linspace(0, 255, 240).astype(np.uint8), (200, 1))])
    files["rgba"] = tmp_path / "rgba.png"
    Image.fromarray(rgba, mode="RGBA").save(files["rgba"])
    return files


@pytest.mark.parametrize("kind", ["rgb", "palette", "grey", "grey16", "rgba"])
def test_tile_from_photo(kind, photos, tmp_path, capsys):
    out = tmp_path / f"seamless_{kind}.png"
    run_ok(["tile", "--from", str(photos[kind]), "--size", "96", "--alpha", "emboss", "-o", str(out)], capsys)
    img = read_image(out)
    assert img.shape == (96, 96, 4)
    wrap = np.abs(img[:, 0, :3] - img[:, -1, :3]).mean()
    assert wrap < np.abs(np.diff(img[:, :, :3], axis=1)).mean() * 1.2


def test_tile_from_photo_keeps_its_alpha(photos, tmp_path, capsys):
    out = tmp_path / "kept.png"
    run_ok(["tile", "--from", str(photos["rgba"]), "--alpha", "keep", "-o", str(out)], capsys)
    img = read_image(out)
    assert img.shape == (200, 240, 4)
    assert np.abs(img[:, 0, 3] - img[:, -1, 3]).mean() < 0.05  # the ramp's seam is gone


def test_tile_bad_inputs_write_nothing(photos, tmp_path, capsys):
    out = tmp_path / "bad.png"
    prev = tmp_path / "bad_preview.png"
    junk = tmp_path / "junk.png"
    junk.write_text("not an image")
    cases = [
        (["--from", str(tmp_path / "missing.png")], "not found"),
        (["--from", str(junk)], "not a readable image"),
        (["--from", str(photos["grey"]), "--size", "256"], "smaller than the tile"),
        (["--from", str(photos["grey"]), "--alpha", "keep"], "alpha channel"),
        (["--size", "500", "--method", "octaves"], "octaves"),
        (["--alpha", "keep"], "--from"),
        (["--cutoff", "0.7"], "cutoff"),
        (["--size", "4"], "size"),
        (["--colormap", "nonesuch"], "colormap"),
        (["--strength", "-1"], "strength"),
    ]
    for extra, match in cases:
        line = run_fails(["tile", *extra, "--preview", "-o", str(out)], capsys, out, prev)
        assert match in line, (extra, line)
    run_fails(["tile", "--size", "32", "-o", str(tmp_path / "t.jpg")], capsys, tmp_path / "t.jpg")
    run_fails(["tile", "--size", "32", "--bit-depth", "16", "-o", str(tmp_path / "t.tif")], capsys,
              tmp_path / "t.tif")
    run_fails(["tile", "--size", "32", "-o", str(tmp_path / "no" / "t.png")], capsys)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [p.name for p in photos.values()] + ["junk.png"])


def test_spectrum_prints_slope_and_plots(tmp_path, capsys):
    from spectex.spectral import spectral_noise

    noise = tmp_path / "noise.npy"
    np.save(noise, spectral_noise(256, beta=2.0, rng=0))
    text = run_ok(["spectrum", str(noise), "--window", "none"], capsys)
    slope = float(text.split("slope ")[1].split()[0])
    assert abs(slope + 2.0) < 0.15
    tile = tmp_path / "tile.png"
    run_ok(["tile", "--size", "128", "-o", str(tile)], capsys)
    plot = tmp_path / "plot.png"
    text = run_ok(["spectrum", str(tile), "-o", str(plot)], capsys)
    assert "slope" in text and plot.exists()
    with Image.open(plot) as im:
        assert im.size[0] > 300


def test_spectrum_bad_inputs(tmp_path, capsys):
    flat = tmp_path / "flat.png"
    Image.fromarray(np.full((32, 32), 128, dtype=np.uint8)).save(flat)
    plot = tmp_path / "p.png"
    assert "constant" in run_fails(["spectrum", str(flat), "-o", str(plot)], capsys, plot)
    assert "not found" in run_fails(["spectrum", str(tmp_path / "none.png"), "-o", str(plot)], capsys, plot)
    tiny = tmp_path / "tiny.png"
    Image.fromarray(np.zeros((4, 4), dtype=np.uint8)).save(tiny)
    assert "8x8" in run_fails(["spectrum", str(tiny)], capsys)
    run_fails(["spectrum", str(flat), "-o", str(tmp_path / "p.jpg")], capsys, tmp_path / "p.jpg")
