"""spectex fit: the output folder, conversions said in the output, one-line
errors and nothing left behind."""

import numpy as np
import pytest
from PIL import Image

from helpers import error_line
from spectex.cli import main
from spectex.io import read_image, write_image
from spectex.texture import SpectralTexture

skdata = pytest.importorskip("skimage.data")

FILES = ("texture.toml", "texture.tile0.png", "texture.tile1.png", "comparison.png", "band_power.png",
         "histograms.png")


@pytest.fixture
def photos(tmp_path):
    grey = skdata.gravel()[:96, :96]
    Image.fromarray(grey).save(tmp_path / "gravel.png")
    rgb = np.stack([grey, skdata.grass()[:96, :96], grey[::-1]], axis=2)
    rgba = np.dstack([rgb, np.full((96, 96), 200, np.uint8)]).astype(np.float32) / 255.0
    write_image(tmp_path / "rgba16.png", rgba, bit_depth=16)
    grass = skdata.grass()
    strip = np.concatenate([grass[:40], grass[40:80, :88]], axis=1)  # 600 x 40: analysed on a crop
    Image.fromarray(strip).save(tmp_path / "strip.png")
    Image.fromarray(grey[:20, :20]).save(tmp_path / "tiny.png")
    Image.fromarray(np.full((64, 64, 3), 90, np.uint8)).save(tmp_path / "flat.png")
    (tmp_path / "notimage.png").write_text("hello")
    return tmp_path


def _leftovers(folder):
    return [p.name for p in folder.iterdir() if p.name.startswith(".")]




def test_cli_fit_writes_the_folder(photos, capsys):
    out = photos / "fitted"
    assert main(["fit", str(photos / "gravel.png"), "-o", str(out), "--pixel-size", "0.01"]) == 0
    text = capsys.readouterr().out
    assert "grey repeated into RGB" in text and "band power" in text and "W1" in text
    assert "on the render of 8x its area (comparison.png)" in text  # what comparison.png shows
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)
    tex = SpectralTexture.load(out / "texture.toml")
    assert tex.layers[0].size == pytest.approx(tex.tile_shape[1] * 0.01)
    comp = read_image(out / "comparison.png")
    # exemplar | render | render of 8x the area (sqrt(8) * 96 = 272 on a side, rounded to 16), labelled
    from spectex.figures import LABEL_HEIGHT

    assert comp.shape[0] == LABEL_HEIGHT + 272 and comp.shape[1] == 96 + 96 + 272 + 16
    assert comp[:LABEL_HEIGHT].min() < 0.2 and comp[:LABEL_HEIGHT].max() == 1.0  # dark labels on white
    assert read_image(out / "band_power.png").shape[2] in (3, 4)
    assert _leftovers(photos) == []


def test_cli_fit_says_the_scale_it_assumed(photos, capsys):
    # no scale given: a photo 1.5 m across, said on stdout and in texture.toml; --photo-size sets it;
    # --pixel-size and --photo-size together are refused
    out = photos / "scaled"
    assert main(["fit", str(photos / "gravel.png"), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "assumed the photo is 1.5 m across" in text
    assert "1.5 m across" in (out / "texture.toml").read_text()
    tex = SpectralTexture.load(out / "texture.toml")
    assert tex.layers[0].size == pytest.approx(tex.tile_shape[1] * 1.5 / 96)
    assert main(["fit", str(photos / "gravel.png"), "-o", str(out), "--photo-size", "0.96"]) == 0
    assert "assumed" not in capsys.readouterr().out
    tex = SpectralTexture.load(out / "texture.toml")
    assert tex.layers[0].size == pytest.approx(tex.tile_shape[1] * 0.01)
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(photos / "gravel.png"), "-o", str(out), "--photo-size", "1", "--pixel-size", "0.01"])
    assert exc.value.code == 2


@pytest.mark.parametrize("cached", [False, True])
def test_cli_fit_says_when_its_first_run_compiles(photos, capsys, monkeypatch, cached):
    # a first run after an install compiles the renderer's kernels (half a minute) before any bar moves:
    # said first, in one line; not said when numba's cache holds them (the control)
    import spectex._numba_cache

    asked = []
    monkeypatch.setattr(spectex._numba_cache, "compiled", lambda kernel: asked.append(kernel) or cached)
    assert main(["fit", str(photos / "gravel.png"), "-o", str(photos / "fitted"), "--pixel-size", "0.01"]) == 0
    lines = capsys.readouterr().out.splitlines()
    from spectex.shading.view import bake_kernel

    assert asked == [bake_kernel]
    said = [line for line in lines if line.startswith("compiling ")]
    assert said == ([] if cached else [lines[0]])


def test_cli_fit_conversions_said(photos, capsys):
    out = photos / "strip_fit"
    assert main(["fit", str(photos / "strip.png"), "-o", str(out)]) == 0
    assert "analysed on the central 512x40 crop of the 600x40 image" in capsys.readouterr().out
    assert main(["fit", str(photos / "rgba16.png"), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "alpha channel dropped" in text
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)  # files of an existing folder replaced


@pytest.mark.parametrize("photo, match", [
    ("tiny.png", "at least 32x32"),
    ("flat.png", "flat"),
    ("notimage.png", "not a readable image"),
    ("missing.png", "file not found"),
])
def test_cli_fit_bad_input_leaves_nothing(photos, capsys, photo, match):
    out = photos / "never"
    with pytest.raises(SystemExit) if photo == "missing.png" else _nothing():
        status = main(["fit", str(photos / photo), "-o", str(out)])
        assert status == 2
    assert match in error_line(capsys)
    assert not out.exists()
    assert _leftovers(photos) == []


def test_cli_fit_bad_options(photos, capsys):
    assert main(["fit", str(photos / "gravel.png"), "-o", str(photos / "o"), "--opacity", "1.5"]) == 2
    assert "--opacity must be between 0.001 and 1, got 1.5" in error_line(capsys)
    assert main(["fit", str(photos / "gravel.png"), "-o", str(photos / "gravel.png")]) == 2
    assert "must be a folder" in error_line(capsys)
    assert main(["fit", str(photos / "gravel.png"), "-o", str(photos / "no" / "such")]) == 2
    assert "does not exist" in error_line(capsys)
    assert not (photos / "o").exists() and _leftovers(photos) == []


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def test_cli_fit_searches_the_magnifications_its_layers_show():
    """The report's search for magnified copies tries ratio ** k, the magnifications of the photo a
    coarse layer would show if it drew it, those coarse_copies can search (>= 1.5)."""
    from spectex.cli._fit import _layer_magnifications

    assert _layer_magnifications(4.0, 5) == (4.0, 16.0, 64.0, 256.0)
    assert _layer_magnifications(1.3, 4) == pytest.approx((1.69, 2.197))
    assert _layer_magnifications(1.2, 3) is None  # none searchable: the metric's default
