"""Tests of spectex.io: formats, conversions and atomic writes."""

import os
import re
import stat
import subprocess
from pathlib import Path

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


# ------------------------------------------------------------ issue 15: the output module

def _strays(folder):
    return [p.name for p in Path(folder).rglob("*") if ".part" in p.name or p.name.startswith(".spectex")]


def test_plan_output_refuses_an_input_by_inode_not_by_name(tmp_path):
    from spectex._output import plan_output

    src = tmp_path / "in.png"
    io.write_image(src, np.zeros((4, 4)))
    (tmp_path / "sub").mkdir()
    os.symlink("in.png", tmp_path / "link.png")
    os.link(src, tmp_path / "hard.png")
    for spelling in (src, tmp_path / "sub" / ".." / "in.png", tmp_path / "link.png", tmp_path / "hard.png"):
        with pytest.raises(ValueError, match=r"is the input '.*in\.png'"):
            plan_output(spelling, inputs=[src])
    # a control: another file is fine, and so is the input's name when it is not an input
    assert plan_output(tmp_path / "other.png", inputs=[src]).dest == tmp_path / "other.png"
    assert plan_output(src).dest == src
    assert _strays(tmp_path) == []


def test_session_records_every_file_read(tmp_path):
    from spectex._output import session

    path = tmp_path / "a.png"
    io.write_image(path, np.zeros((4, 4)))
    before = path.read_bytes()
    with session():
        image = io.read_image(path)
        with pytest.raises(ValueError, match="is the input"):
            io.write_image(path, image + 0.5)
    assert path.read_bytes() == before
    # outside a command, a library user may edit a file in place
    io.write_image(path, image + 0.5)
    assert path.read_bytes() != before


def test_links_are_written_through_and_kept(tmp_path):
    target = tmp_path / "target.png"
    io.write_image(target, np.zeros((4, 4)))
    os.symlink("target.png", tmp_path / "link.png")
    io.write_image(tmp_path / "link.png", np.ones((4, 4)))
    assert os.path.islink(tmp_path / "link.png") and os.readlink(tmp_path / "link.png") == "target.png"
    assert io.read_image(target).min() == 1.0
    os.symlink("new.png", tmp_path / "dangling.png")
    io.write_image(tmp_path / "dangling.png", np.ones((4, 4)))
    assert os.path.islink(tmp_path / "dangling.png") and (tmp_path / "new.png").is_file()


def test_special_files_and_folders_are_refused_unless_the_format_streams(tmp_path):
    from spectex._output import plan_output, write_text

    os.mkfifo(tmp_path / "fifo.png")
    with pytest.raises(ValueError, match="'.*fifo.png' is a pipe; this format can only be written to a file"):
        io.write_image(tmp_path / "fifo.png", np.zeros((4, 4)))
    (tmp_path / "dir.png").mkdir()
    with pytest.raises(ValueError, match="is a folder"):
        io.write_image(tmp_path / "dir.png", np.zeros((4, 4)))
    assert write_text("/dev/null", "text").stream
    assert plan_output("/dev/null", stream=True).stream
    with pytest.raises(ValueError, match="character device"):
        plan_output("/dev/null")
    assert _strays(tmp_path) == []


def test_output_set_replaces_all_or_nothing(tmp_path, monkeypatch):
    from spectex import _output
    from spectex._output import OutputSet

    out = tmp_path / "out"
    out.mkdir()
    for name in ("a.txt", "b.txt", "keep.txt"):
        (out / name).write_text(f"old {name}")
    old = {p.name: p.read_bytes() for p in out.iterdir()}

    class Boom(Exception):
        pass

    with pytest.raises(Boom):
        with OutputSet(out, ["a.txt", "b.txt"]) as stage:
            (stage / "a.txt").write_text("new a")
            raise Boom
    assert {p.name: p.read_bytes() for p in out.iterdir()} == old
    # a rename that fails half-way through the set: the files already moved are put back
    real_replace = os.replace
    calls = []

    def flaky(src, dst):
        calls.append(dst)
        if len(calls) == 4:  # two backups, one new file placed, then the second fails
            raise OSError(28, "No space left on device")
        return real_replace(src, dst)

    monkeypatch.setattr(_output.os, "replace", flaky)
    with pytest.raises(ValueError, match="could not be written: No space left on device; the earlier files"):
        with OutputSet(out, ["a.txt", "b.txt"]) as stage:
            (stage / "a.txt").write_text("new a")
            (stage / "b.txt").write_text("new b")
    monkeypatch.setattr(_output.os, "replace", real_replace)
    assert len(calls) == 6  # 4 tries, then the 2 backups put back
    assert {p.name: p.read_bytes() for p in out.iterdir()} == old
    with OutputSet(out, ["a.txt", "b.txt"]) as stage:
        (stage / "a.txt").write_text("new a")
        (stage / "b.txt").write_text("new b")
    assert (out / "a.txt").read_text() == "new a" and (out / "keep.txt").read_text() == "old keep.txt"
    assert _strays(tmp_path) == []


def test_output_set_new_folder_appears_only_when_complete(tmp_path):
    from spectex._output import OutputSet

    out = tmp_path / "new"
    with pytest.raises(KeyboardInterrupt):
        with OutputSet(out, ["a.txt"]) as stage:
            (stage / "a.txt").write_text("a")
            raise KeyboardInterrupt
    assert not out.exists() and list(tmp_path.iterdir()) == []
    with OutputSet(out, ["a.txt"]) as stage:
        (stage / "a.txt").write_text("a")
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~umask  # not mkdtemp's 0700
    assert stat.S_IMODE((out / "a.txt").stat().st_mode) == 0o666 & ~umask
    with pytest.raises(ValueError, match="must be a folder"):
        OutputSet(out / "a.txt", ["b.txt"])
    with pytest.raises(ValueError, match="the files written .* are not the files planned"):
        with OutputSet(out, ["a.txt"]) as stage:
            (stage / "b.txt").write_text("b")
    assert sorted(p.name for p in out.iterdir()) == ["a.txt"]


def test_sigterm_in_a_session_is_an_interrupt_and_held_during_renames():
    import signal

    from spectex._output import Terminated, _signals_held, session

    with session():
        with pytest.raises(Terminated):
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):  # the handler runs at the next bytecode boundary
                pass
        order = []
        with pytest.raises(Terminated):
            with _signals_held():
                os.kill(os.getpid(), signal.SIGTERM)
                for _ in range(1000):
                    pass
                order.append("held region finished")
        assert order == ["held region finished"]
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL or callable(signal.getsignal(signal.SIGTERM))


def test_sigterm_inside_a_callback_from_c_prints_no_traceback(monkeypatch):
    """numba's compiler calls back into Python through ctypes (llvmlite's object cache); a signal handled
    there cannot raise through the C frames, and Python printed the ignored exception with its traceback
    (a hostile case sending SIGTERM 2 s into a fit caught it). It is recorded and raised at the next
    check, and not passed to the unraisable hook; any other exception still is (the control)."""
    import ctypes
    import signal
    import sys

    from spectex._output import Terminated, check_interrupted, session

    passed_on = []

    def recorder(unraisable):
        passed_on.append(unraisable.exc_value)

    monkeypatch.setattr(sys, "unraisablehook", recorder)

    def signal_self():
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):  # the handler runs here, inside the callback
            pass

    def fail():
        raise ValueError("not an interrupt")

    with session():
        ctypes.CFUNCTYPE(None)(signal_self)()
        assert passed_on == []  # the interrupt: kept quiet ...
        with pytest.raises(Terminated):
            check_interrupted()  # ... and not lost
        ctypes.CFUNCTYPE(None)(fail)()
    assert len(passed_on) == 1 and isinstance(passed_on[0], ValueError)
    assert sys.unraisablehook is recorder  # the session put back the hook it found


def test_an_error_caused_by_a_signal_ends_the_run_as_the_signal():
    """SIGTERM 2 s into a fit arrived while SciPy's HiGHS extension was being imported; the handler's
    exception broke the module's initialisation, which raised ImportError("initialization failed")
    chained to it, and the command printed that traceback. After a signal, any exception leaving the
    session leaves as the signal's interrupt; without a signal it passes unchanged (the control)."""
    import ctypes
    import signal

    from spectex._output import Terminated, session

    def signal_self():
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):  # the handler runs here, inside the callback, and cannot raise out of it
            pass

    with pytest.raises(Terminated) as info:
        with session():
            ctypes.CFUNCTYPE(None)(signal_self)()
            raise ImportError("initialization failed")
    assert info.value.signum == signal.SIGTERM and isinstance(info.value.__cause__, ImportError)
    with pytest.raises(ImportError, match="initialization failed"):
        with session():
            raise ImportError("initialization failed")


def test_image_pixel_limit_is_checked_before_decoding(tmp_path, monkeypatch):
    from PIL import Image

    monkeypatch.setattr(io, "MAX_IMAGE_PIXELS", 1000)
    pil_limit = Image.MAX_IMAGE_PIXELS
    io.write_image(tmp_path / "a.png", np.zeros((40, 40)))      # 1600: over the limit, under twice it
    io.write_image(tmp_path / "b.png", np.zeros((50, 50, 3)))   # 2500: Pillow's own bomb error
    io.write_image(tmp_path / "c.png", np.zeros((40, 40)), bit_depth=16)
    np.save(tmp_path / "d.npy", np.zeros((40, 40), np.float32))
    with pytest.raises(ValueError, match=r"is 40x40 = 1600 pixels, over the limit of 1000 pixels"):
        io.read_image(tmp_path / "a.png")
    with pytest.raises(ValueError, match=r"has 2500 pixels, over the limit of 1000 pixels"):
        io.read_image(tmp_path / "b.png")
    for name in ("c.png", "d.npy"):
        with pytest.raises(ValueError, match=r"1600 pixels, over the limit of 1000"):
            io.read_image(tmp_path / name)
    assert Image.MAX_IMAGE_PIXELS == pil_limit
    monkeypatch.setattr(io, "MAX_IMAGE_PIXELS", 1600)  # the control: at the limit it reads
    assert io.read_image(tmp_path / "a.png").shape == (40, 40)


def test_inputs_that_are_not_files_say_what_they_are(tmp_path):
    with pytest.raises(ValueError, match="'/dev/null' is a character device, not a file"):
        io.read_image("/dev/null")
    with pytest.raises(ValueError, match="is a folder, not a file"):
        io.read_image(tmp_path)
    os.symlink("gone.png", tmp_path / "l.png")
    with pytest.raises(ValueError, match="symbolic link to a missing file"):
        io.read_image(tmp_path / "l.png")


def test_odd_mp4_sides_are_refused(tmp_path):
    with pytest.raises(ValueError, match="even frame sides .* got 1x1"):
        io.write_animation(tmp_path / "a.mp4", [np.zeros((1, 1))] * 2)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("channels", [None, 2, 3, 4])
def test_png16_writer_is_read_back_exactly_by_pypng(tmp_path, channels):
    # The 16-bit PNG writer (NumPy + zlib) against an independent decoder (pypng): every sample.
    import png

    shape = (37, 53) if channels is None else (37, 53, channels)
    image = np.random.default_rng(3).random(shape).astype(np.float32)
    image.flat[0], image.flat[1] = 0.0, 1.0
    path = io.write_image(tmp_path / "x.png", image, bit_depth=16)
    width, height, rows, info = png.Reader(bytes=path.read_bytes()).read()
    assert (width, height, info["bitdepth"]) == (53, 37, 16)
    planes = 1 if channels is None else channels
    assert info["planes"] == planes and info["alpha"] == (planes in (2, 4))
    got = np.vstack([np.asarray(r, dtype=np.uint16) for r in rows]).reshape(io.to_uint(image, 16).shape)
    np.testing.assert_array_equal(got, io.to_uint(image, 16))


def test_png8_compression_level_keeps_the_pixels(tmp_path):
    from PIL import Image

    image = np.random.default_rng(4).random((64, 48, 4)).astype(np.float32)
    path = io.write_image(tmp_path / "x.png", image)
    with Image.open(path) as im:
        np.testing.assert_array_equal(np.asarray(im), io.to_uint(image, 8))
