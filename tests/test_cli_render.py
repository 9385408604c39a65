"""``spectex demo``, ``spectex render`` and ``spectex view`` from the command line."""

import re

import numpy as np
import pytest
from PIL import Image

from helpers import run_fails
from spectex.cli import main
from spectex.io import read_image
from spectex.texture import SpectralTexture
from spectex.tiles import make_tile


@pytest.fixture(scope="module")
def texture_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tex")
    return SpectralTexture.paper_preset(make_tile(64, rng=1)).save(folder / "ground.toml")


@pytest.fixture
def no_gl(monkeypatch):
    import spectex.render.gl as glmod

    def unavailable(**kw):
        raise glmod.GLUnavailable("no OpenGL 3.3 context (EGL): simulated")

    monkeypatch.setattr(glmod, "create_context", unavailable)


@pytest.mark.gl
def test_cli_render_demo_writes_pictures_and_report(tmp_path, capsys, gl):
    out = tmp_path / "demo"
    assert main(["demo", "-o", str(out), "--repeat-peak"]) == 0
    text = capsys.readouterr().out
    assert "327680 x 327680" in text and "3.05 cm" in text and "2.44 mm texels under the feet" in text
    assert "1.00 MiB" in text and "300.0 GiB" in text
    assert "OpenGL" in text and "ground" in text and "aerial" in text and "haze 12000 m" in text
    # the pictures are written before the bakes behind repeat_peak (off the critical path)
    assert text.index("wrote 7 files") < text.index("repeat_peak")
    peaks = re.search(r"periodic layers ([0-9.]+), stochastic layers ([0-9.]+)", text)
    assert peaks and float(peaks.group(1)) > 0.5 and float(peaks.group(2)) <= 0.1
    for name in ("ground", "closeup", "aerial"):
        assert read_image(out / f"{name}.png").shape == (540, 960, 3)
    assert read_image(out / "tile_colour.png").shape == (512, 512, 3)
    assert read_image(out / "tile_alpha.png").shape == (512, 512)
    tex = SpectralTexture.load(out / "texture.toml")
    assert len(tex.layers) == 6 and tex.layers[-1].blend == "fine"
    assert tex.layers[:5] == SpectralTexture.paper_preset(tex.tiles[0]).layers[:5]


def test_cli_render_demo_without_gl_uses_cpu(tmp_path, capsys, no_gl, monkeypatch):
    import spectex.cli._demo as demo

    monkeypatch.setattr(demo, "DEMO_SIZE", (36, 64))
    monkeypatch.setattr(demo, "REPEAT_BAKE", (128, 16))
    out = tmp_path / "demo"
    assert main(["demo", "-o", str(out)]) == 0
    assert "repeat_peak" not in capsys.readouterr().out  # off by default: no bake kernel to compile
    assert main(["demo", "-o", str(out), "--paper", "--haze", "0"]) == 0
    captured = capsys.readouterr()
    assert "5 layers" in captured.out and "no haze" in captured.out
    assert len(SpectralTexture.load(out / "texture.toml").layers) == 5
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and "no OpenGL" in err[0] and "CPU" in err[0]
    assert "CPU reference renderer" in captured.out
    assert read_image(out / "ground.png").shape == (36, 64, 3)


@pytest.mark.gl
def test_cli_render_gl_and_cpu_agree(tmp_path, capsys, texture_file, gl):
    a, b = tmp_path / "gl.png", tmp_path / "cpu.png"
    cam = ["--camera", "3,4,2,30,-12", "--size", "160x90"]
    assert main(["render", str(texture_file), *cam, "-o", str(a), "--backend", "gl"]) == 0
    assert main(["render", str(texture_file), *cam, "-o", str(b), "--backend", "cpu"]) == 0
    out = capsys.readouterr().out
    assert "OpenGL" in out and "CPU" in out
    ga, gb = read_image(a), read_image(b)
    assert ga.shape == (90, 160, 3)
    assert 10 * np.log10(1.0 / np.mean((ga - gb) ** 2)) >= 40.0


@pytest.mark.gl
def test_cli_render_fly_over_gif(tmp_path, capsys, texture_file, gl):
    out = tmp_path / "fly.gif"
    assert main(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--to", "0,200,50,90,-30",
                 "--frames", "4", "--size", "64x36", "-o", str(out)]) == 0
    assert "4 frames" in capsys.readouterr().out
    with Image.open(out) as im:
        assert im.n_frames == 4 and im.size == (64, 36)


def test_cli_render_without_gl_falls_back(tmp_path, capsys, texture_file, no_gl):
    out = tmp_path / "cpu.png"
    assert main(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--size", "32x18", "-o", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "CPU" in err[0]
    assert read_image(out).shape == (18, 32, 3)
    run_fails(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--size", "32x18", "-o",
               str(tmp_path / "gl.png"), "--backend", "gl"], capsys, tmp_path / "gl.png")


@pytest.mark.parametrize("command", ["demo", "render"])
@pytest.mark.parametrize("cold", [(), ("render_kernel",), ("render_kernel", "render_kernel_fast")])
def test_cli_cpu_renders_say_a_first_run_compiles(tmp_path, capsys, texture_file, no_gl, monkeypatch, command,
                                                  cold):
    # without OpenGL the CPU renderer's kernel compiles on the first run (half a minute): said first, in
    # one line, when the kernel the run calls is not on disk (demo: render_kernel, its views filter
    # anisotropically) or, where the texture decides, neither kernel is (render)
    import spectex._numba_cache
    import spectex.cli._demo as demo

    monkeypatch.setattr(spectex._numba_cache, "compiled", lambda kernel: kernel.__name__ not in cold)
    monkeypatch.setattr(demo, "DEMO_SIZE", (36, 64))
    argv = (["demo", "-o", str(tmp_path / "demo")] if command == "demo" else
            ["render", str(texture_file), "--camera", "0,0,5,0,-10", "--size", "32x18", "-o", str(tmp_path / "a.png")])
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    said = [line for line in lines if line.startswith("compiling the CPU renderer")]
    expected = len(cold) == 2 or (command == "demo" and len(cold) == 1)
    assert said == ([lines[0]] if expected else [])


def test_cli_render_bad_input_one_line_nothing_written(tmp_path, capsys, texture_file):
    out = tmp_path / "out.png"
    base = ["--size", "32x18", "-o", str(out)]
    assert "not found" in run_fails(["render", str(tmp_path / "missing.toml"), "--camera", "0,0,5,0,-10", *base],
                                    capsys, out)
    bad = tmp_path / "bad.toml"
    bad.write_text("format = = 2\n")
    assert "TOML" in run_fails(["render", str(bad), "--camera", "0,0,5,0,-10", *base], capsys, out)
    wrong = texture_file.parent / "wrong.toml"
    wrong.write_text(texture_file.read_text().replace("size = 15.625", "size = -3.0"))
    assert "layers[0].size" in run_fails(["render", str(wrong), "--camera", "0,0,5,0,-10", *base], capsys, out)
    assert "z must be > 0" in run_fails(["render", str(texture_file), "--camera", "0,0,-1,0,-10", *base],
                                        capsys, out)
    assert "must be finite" in run_fails(["render", str(texture_file), "--camera", "0,0,nan,0,-10", *base], capsys, out)
    assert "budget" in run_fails(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--size", "8000x8000",
                                  "--supersample", "4", "-o", str(out)], capsys, out)
    fly = tmp_path / "fly.mp4"
    assert "budget" in run_fails(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--size", "1920x1080",
                                  "--frames", "1000", "-o", str(fly)], capsys, fly)
    assert "z must be > 0" in run_fails(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--to",
                                         "0,0,-5,0,-10", "--frames", "3", "--size", "32x18", "-o", str(fly)],
                                        capsys, fly)
    assert "output" in run_fails(["render", str(texture_file), "--camera", "0,0,5,0,-10", "--frames", "3",
                                  *base], capsys, out)
    assert list(tmp_path.glob("*.png")) == []


def test_cli_render_view_without_display(capsys, texture_file, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    err = run_fails(["view", str(texture_file)], capsys)
    assert "no display" in err and "spectex render" in err


def test_cli_render_viewer_flight_controls():
    from spectex.render import Camera
    from spectex.render.viewer import Flight

    f = Flight(Camera((0.0, 0.0, 2.0), yaw=90.0, pitch=-10.0), 5)
    f.move(1, 0, 0, 1.0)  # forward, heading east, 2 m/s at 2 m
    assert f.x == pytest.approx(4.0) and f.y == pytest.approx(0.0, abs=1e-9)
    low = f.speed
    f.z = 1000.0
    assert f.speed == pytest.approx(500 * low)  # speed scales with altitude
    f.move(0, 0, -1, 100.0)
    assert f.z == Flight.MIN_ALTITUDE  # never under the ground
    f.toggle_layer(2)
    f.toggle_layer(7)  # no such layer: ignored
    assert f.enabled == [True, True, False, True, True]
    f.look(0, 10000, 100)
    assert f.pitch == -89.0
    assert "fps" in f.status(30.0) and "12-45" in f.status(30.0)
