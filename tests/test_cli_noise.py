"""Tests of ``spectex noise`` and of the command line's start-up cost."""

import subprocess
import sys

import numpy as np
import pytest

from spectex import io
from spectex.cli import main


def run(*args):
    return main(list(args))


def test_png_gray_and_colour(tmp_path, capsys):
    out = tmp_path / "n.png"
    assert run("noise", "fbm", "--size", "64x32", "--seed", "3", "-o", str(out)) == 0
    img = io.read_image(out)
    assert img.shape == (32, 64) and img.min() < 0.05 and img.max() > 0.95
    assert run("noise", "marble", "--size", "48x48", "--colormap", "marble", "-o", str(out)) == 0
    assert io.read_image(out).shape == (48, 48, 3)
    assert "wrote" in capsys.readouterr().out


def test_16bit_png_and_npy(tmp_path):
    png16 = tmp_path / "n16.png"
    npy = tmp_path / "n.npy"
    assert run("noise", "perlin", "--size", "40x30", "--bit-depth", "16", "-o", str(png16)) == 0
    assert run("noise", "perlin", "--size", "40x30", "-o", str(npy)) == 0
    raw = np.load(npy)
    img = io.read_image(png16)
    assert raw.dtype == np.float32 and raw.shape == (30, 40)
    # 16-bit keeps far more levels than 8 bits could
    assert len(np.unique(img)) > 600
    # the PNG is the raw field stretched to [0, 1]
    stretched = (raw - raw.min()) / (raw.max() - raw.min())
    assert np.corrcoef(stretched.ravel(), img.ravel())[0, 1] > 0.999


def test_tileable_output_is_seamless(tmp_path):
    out = tmp_path / "t.npy"
    assert run("noise", "turbulence", "--size", "64x64", "--tileable", "-o", str(out)) == 0
    a = np.load(out)
    assert np.abs(a[:, 0] - a[:, -1]).mean() < 1.1 * np.abs(np.diff(a, axis=1)).mean()


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_animation(tmp_path, suffix):
    out = tmp_path / f"a{suffix}"
    assert run("noise", "fbm", "--size", "32x24", "--frames", "6", "--colormap", "fire", "-o", str(out)) == 0
    if suffix == ".gif":
        from PIL import Image, ImageSequence

        with Image.open(out) as im:
            frames = np.stack([np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)])
    else:
        import imageio_ffmpeg

        raw = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-v", "error", "-i", str(out), "-f", "rawvideo",
                              "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout
        frames = np.frombuffer(raw, np.uint8).reshape(-1, 24, 32, 3)
    assert frames.shape[0] == 6 and frames.shape[1:3] == (24, 32)
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 1


@pytest.mark.parametrize("args,message", [
    (["noise", "fbm", "--size", "10y10"], "argument --size: expected WxH such as 512x256, got '10y10'"),
    (["noise", "fbm", "--octaves", "0"], "argument --octaves: must be >= 1, got 0"),
    (["noise", "fbm", "--scale", "nan"], "argument --scale: must be finite, got 'nan'"),
    (["noise", "fbm", "--colormap", "nope"], "colormap must be one of"),
    (["noise", "fbm", "--frames", "3"], "--frames needs a .gif or .mp4 output"),
    (["noise", "fbm", "--size", "20000x20000"], "over the limit"),
    (["noise", "wood", "--tileable"], "--tileable does not apply to wood"),
    (["noise", "plasma"], "argument kind: invalid choice: 'plasma'"),
])
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys, args, message):
    out = tmp_path / "bad.png"
    try:
        code = run(*args, "-o", str(out))
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert list(tmp_path.iterdir()) == []


def test_unwritable_folder(tmp_path, capsys):
    assert run("noise", "fbm", "-o", str(tmp_path / "missing" / "x.png")) == 2
    assert "folder that does not exist" in capsys.readouterr().err


def test_gif_needs_frames(tmp_path, capsys):
    assert run("noise", "fbm", "-o", str(tmp_path / "x.gif")) == 2
    assert capsys.readouterr().err.strip() == "spectex noise: error: --frames is needed for .gif output, got none"


def test_help_imports_nothing_heavy():
    # `spectex --help` and every subcommand's help must answer at once: no
    # NumPy, numba or Matplotlib at start-up (and so no JIT compilation).
    code = (
        "import sys\n"
        "from spectex.cli import build_parser\n"
        "p = build_parser()\n"
        "for a in p._subparsers._group_actions[0].choices.values(): a.format_help()\n"
        "heavy = [m for m in ('numpy', 'numba', 'matplotlib', 'scipy', 'moderngl', 'PIL') if m in sys.modules]\n"
        "print(','.join(heavy))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_every_subcommand_has_help():
    for cmd in ("noise",):
        proc = subprocess.run([sys.executable, "-m", "spectex", cmd, "--help"], capture_output=True, text=True)
        assert proc.returncode == 0 and "usage: spectex " + cmd in proc.stdout
