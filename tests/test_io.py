"""Tests of spectex.io: formats, conversions and atomic writes."""

import re
import subprocess

import numpy as np
import pytest
from PIL import Image

from spectex import io


def test_roundtrip_8_and_16_bit(tmp_path):
    rng = np.random.default_rng(0)
    img = rng.random((20, 30, 3)).astype(np.float32)
    io.write_image(tmp_path / "a.png", img)
    io.write_image(tmp_path / "b.png", img, bit_depth=16)
    a = io.read_image(tmp_path / "a.png")
    b = io.read_image(tmp_path / "b.png")
    assert np.max(np.abs(a - img)) <= 0.5 / 255 + 1e-6
    assert np.max(np.abs(b - img)) <= 0.5 / 65535 + 1e-6
    rgba = rng.random((8, 9, 4)).astype(np.float32)
    io.write_image(tmp_path / "c.png", rgba, bit_depth=16)
    assert io.read_image(tmp_path / "c.png").shape == (8, 9, 4)


def test_conversions(tmp_path):
    grey = (np.arange(64, dtype=np.uint8).reshape(8, 8) * 4)
    Image.fromarray(grey).convert("P").save(tmp_path / "p.png")
    p = io.read_image(tmp_path / "p.png")
    assert p.shape == (8, 8, 3)
    Image.fromarray(grey).save(tmp_path / "g.png")
    assert io.read_image(tmp_path / "g.png").shape == (8, 8)
    Image.fromarray((grey.astype(np.uint16) * 257)).save(tmp_path / "g16.png")
    g16 = io.read_image(tmp_path / "g16.png")
    np.testing.assert_allclose(g16, grey / 255.0, atol=1e-6)


def test_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "x.png"
    with pytest.raises(ValueError):
        io.write_image(target, np.zeros((4, 4, 7)))
    assert list(tmp_path.iterdir()) == []

    class Boom(Exception):
        pass

    with pytest.raises(Boom):
        with io.atomic_path(target) as tmp:
            tmp.write_bytes(b"half")
            raise Boom
    assert list(tmp_path.iterdir()) == []
    # a previous complete file survives a failed rewrite
    io.write_image(target, np.zeros((4, 4)))
    before = target.read_bytes()
    with pytest.raises(Boom):
        with io.atomic_path(target) as tmp:
            tmp.write_bytes(b"half")
            raise Boom
    assert target.read_bytes() == before


@pytest.mark.parametrize("content,message", [
    (None, "image file not found"),
    (b"not an image", "image is not a readable image"),
])
def test_read_errors(tmp_path, content, message):
    path = tmp_path / "x.png"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(ValueError, match=message):
        io.read_image(path)


def test_output_suffix_checked(tmp_path):
    with pytest.raises(ValueError, match=r"^output must end in one of .*got '.*x\.xyz'$"):
        io.write_image(tmp_path / "x.xyz", np.zeros((2, 2)))
    with pytest.raises(ValueError, match="bit_depth=16 needs a .png output"):
        io.write_image(tmp_path / "x.jpg", np.zeros((2, 2)), bit_depth=16)


def test_mp4_is_quiet_and_reads_back(tmp_path, capfd):
    pytest.importorskip("imageio")
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    levels = np.linspace(0.1, 0.9, 5, dtype=np.float32)
    frames = [np.full((24, 32, 3), v, np.float32) for v in levels]
    out = io.write_animation(tmp_path / "a.mp4", frames, fps=10)
    err = capfd.readouterr().err
    assert "pix_fmt" not in err
    assert err == ""
    ffmpeg = imageio_ffmpeg.get_ffmpeg_exe()
    # `ffmpeg -i` alone describes the streams on stderr and exits with status 1.
    info = subprocess.run([ffmpeg, "-hide_banner", "-i", str(out)], capture_output=True, text=True).stderr
    stream = re.search(r"Video: (\w+).*?, (yuv\w+).*?, (\d+)x(\d+)", info)
    assert stream is not None, info
    assert stream.group(1, 2, 3, 4) == ("h264", "yuv420p", "32", "24")
    raw = subprocess.run([ffmpeg, "-v", "error", "-i", str(out), "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         capture_output=True, check=True).stdout
    assert len(raw) == 5 * 24 * 32 * 3
    got = np.frombuffer(raw, np.uint8).reshape(5, 24, 32, 3)
    np.testing.assert_allclose(got.mean(axis=(1, 2, 3)) / 255.0, levels, atol=0.02)
