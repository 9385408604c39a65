"""``spectex bake`` from the command line: output, resuming after a kill, hostile input."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from spectex.bake import to_dtype
from spectex.cli import main
from spectex.render import bake
from spectex.texture import SpectralTexture

zarr = pytest.importorskip("zarr")


@pytest.fixture(scope="module")
def texture_file(tmp_path_factory, tile_maker):
    folder = tmp_path_factory.mktemp("tex")
    return SpectralTexture.paper_preset(tile_maker(64, 2)).save(folder / "ground.toml")


def snapshot(folder):
    return {str(f.relative_to(folder)): f.read_bytes() for f in sorted(Path(folder).rglob("*")) if f.is_file()}


def test_cli_bake_writes_the_pyramid_and_resumes_nothing_twice(texture_file, tmp_path, capsys):
    out = tmp_path / "g.zarr"
    argv = ["bake", str(texture_file), "-o", str(out), "--size", "120x90", "--pixel-size", "0.25",
            "--origin", "100,-50", "--chunk", "32", "--shard", "64", "--workers", "2"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert captured.err == ""  # no progress bar: standard error is not a terminal
    line, = captured.out.strip().splitlines()
    assert "3 levels" in line and "120x90 to 30x23 uint8" in line and "shards baked" in line
    tex = SpectralTexture.load(texture_file)
    ref = to_dtype(bake(tex, (90, 120), origin=(100.0, -50.0), pixel_size=0.25))
    assert np.array_equal(zarr.open_array(out, path="0", mode="r")[:], np.moveaxis(ref, 2, 0))
    doc = json.loads((out / "zarr.json").read_text())
    assert doc["attributes"]["spectex"]["texture_file"] == texture_file.read_text()
    before = snapshot(out)
    assert main(argv[:-2]) == 0  # the same bake on all cores: nothing to do
    assert "complete already" in capsys.readouterr().out
    assert snapshot(out) == before


def _terminal_sigint():
    """In the child: SIGINT's default, as a terminal gives it (a suite started as a background job
    or under nohup hands its children an ignored SIGINT, and the bake would never see the signal)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _run_cli(args, **kw):
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1] / "src"))
    return subprocess.Popen([sys.executable, "-m", "spectex", "bake", *args], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=_terminal_sigint, **kw)


#: A bake of 400 shards on one thread: long enough (seconds) to be stopped in the middle.
SLOW_BAKE = ("--size", "640x512", "--pixel-size", "0.05", "--chunk", "16", "--shard", "32", "--levels", "2",
             "--workers", "1")


def _finished_markers(markers) -> list:
    """The shard markers in ``markers``: whole ones only (a marker is written as ``.NAME.part``, then
    renamed; a bake killed between the two leaves the part, which is not a finished shard)."""
    return [m for m in markers.iterdir() if not m.name.startswith(".")] if markers.is_dir() else []


def _wait_for_markers(proc, markers, count, seconds=120):
    """Wait until the running bake ``proc`` has left ``count`` shard markers; it must still be running."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None:
        if len(_finished_markers(markers)) >= count:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the bake finished before it could be stopped; make it larger"


@pytest.fixture(scope="module")
def whole_slow_bake(texture_file, tmp_path_factory):
    """The files of the slow bake run from start to end without a stop: what every stopped, resumed
    or contested bake of it below must end as (made once for them all)."""
    whole = tmp_path_factory.mktemp("whole") / "t.zarr"
    proc = _run_cli([str(texture_file), *SLOW_BAKE, "-o", str(whole)])
    _, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 0, stderr
    return snapshot(whole)


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT])
def test_cli_bake_killed_and_run_again_gives_the_same_bytes(texture_file, whole_slow_bake, tmp_path, signum):
    args = [str(texture_file), *SLOW_BAKE]
    out = tmp_path / "t.zarr"
    proc = _run_cli([*args, "-o", str(out)])
    markers = out / ".spectex-progress"
    _wait_for_markers(proc, markers, 20)
    proc.send_signal(signum)
    _, stderr = proc.communicate(timeout=120)
    if signum == signal.SIGKILL:
        assert proc.returncode == -signal.SIGKILL
    else:  # a clean stop: 128 + the signal, one line, no traceback
        assert proc.returncode == 128 + signum and len(stderr.strip().splitlines()) == 1, stderr
    doc = json.loads((out / "zarr.json").read_text())
    assert doc["attributes"]["spectex"]["complete"] is False and "ome" not in doc["attributes"]
    kept = len(_finished_markers(markers))

    proc = _run_cli([*args[:-2], "-o", str(out)])  # and on all cores this time
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 0, stderr
    assert f"{kept} kept from an earlier run" in stdout
    assert snapshot(out) == whole_slow_bake


@pytest.mark.slow
def test_cli_bake_a_second_writer_while_the_first_runs_is_refused_and_the_store_exact(texture_file,
                                                                                     whole_slow_bake, tmp_path):
    """Two writers that surely overlap: once the first has written shards it is paused (SIGSTOP)
    while the second runs, so that the overlap does not hang on how fast either is on a loaded
    machine (the second, started only then, once took longer than the whole first bake); it goes on
    (SIGCONT) after the second was refused. A paused process holds its lock like a running one."""
    args = [str(texture_file), *SLOW_BAKE]
    out = tmp_path / "t.zarr"
    first = _run_cli([*args, "-o", str(out)])
    try:
        _wait_for_markers(first, out / ".spectex-progress", 5)
        first.send_signal(signal.SIGSTOP)
        lock = json.loads((out / "spectex.lock").read_text())
        assert lock["pid"] == first.pid  # the lock names its owner
        second = _run_cli([*args, "-o", str(out)])
        _, err = second.communicate(timeout=120)
        assert first.poll() is None  # paused, not ended
        assert second.returncode == 2 and f"is being baked by process {first.pid} on" in err, err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
        first.send_signal(signal.SIGCONT)
        stdout, stderr = first.communicate(timeout=300)
    finally:  # a failed assertion leaves no paused bake and no open pipes behind
        if first.poll() is None:
            first.kill()
            first.communicate()
    assert first.returncode == 0, stderr
    assert snapshot(out) == whole_slow_bake  # the refused writer changed nothing
    assert not (out / "spectex.lock").exists()


def _fails(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1 and "error" in err[0] and "Traceback" not in err[0], err
    return err[0]


@pytest.mark.parametrize("extra, word", [
    (["-o", "{tex}"], "is, or holds, the input"),
    (["-o", "{tile}"], "is, or holds, the input"),
    (["-o", "{dir}"], "is, or holds, the input"),
    (["-o", "{dir}/x.tif"], "must end in .zarr (a store) or .png"),
    (["-o", "{dir}/x.png"], "--chunk applies to a .zarr store"),
    (["-o", "{dir}/no/x.zarr"], "does not exist"),
    (["-o", "{dir}/x.zarr", "--size", "0x5"], "size"),
    (["-o", "{dir}/x.zarr", "--pixel-size", "-1"], "pixel-size"),
    (["-o", "{dir}/x.zarr", "--pixel-size", "nan"], "pixel-size"),
    (["-o", "{dir}/x.zarr", "--origin", "1"], "origin"),
    (["-o", "{dir}/x.zarr", "--chunk", "20"], "chunk"),
    (["-o", "{dir}/x.zarr", "--shard", "100"], "shard"),
    (["-o", "{dir}/x.zarr", "--levels", "0"], "levels"),
    (["-o", "{dir}/x.zarr", "--levels", "40"], "levels"),
    (["-o", "{dir}/x.zarr", "--dtype", "int8"], "dtype"),
    (["-o", "{dir}/x.zarr", "--workers", "0"], "workers"),
    (["-o", "{dir}/x.zarr", "--scheduler", "nohost"], "scheduler"),
    (["-o", "{dir}/x.zarr", "--scheduler", "tcp://127.0.0.1:9", "--workers", "2"], "workers"),
    (["-o", "{dir}/old.zarr"], "other arguments"),
    (["-o", "{dir}/junk.zarr"], "not a spectex bake"),
])
def test_cli_bake_hostile_input_one_line_exit_2_nothing_written(texture_file, tmp_path, capsys, extra, word):
    folder = tmp_path / "work"
    folder.mkdir()
    tex = folder / "ground.toml"
    tex.write_bytes(texture_file.read_bytes())
    (folder / "ground.tile.png").write_bytes((texture_file.parent / "ground.tile.png").read_bytes())
    (folder / "junk.zarr").mkdir()
    (folder / "junk.zarr" / "notes.txt").write_text("mine")
    base = ["bake", str(tex), "--size", "40x30", "--pixel-size", "0.5", "--chunk", "16", "--shard", "32"]
    assert main(base + ["-o", str(folder / "old.zarr"), "--levels", "1"]) == 0
    capsys.readouterr()
    before = snapshot(folder)
    names = {"tex": tex, "tile": folder / "ground.tile.png", "dir": folder}
    argv = base + [a.format(**names) for a in extra]
    line = _fails(argv, capsys)
    assert word in line, line
    assert snapshot(folder) == before
    assert sorted(p.name for p in folder.iterdir()) == ["ground.tile.png", "ground.toml", "junk.zarr", "old.zarr"]


def test_cli_bake_missing_texture(tmp_path, capsys):
    line = _fails(["bake", str(tmp_path / "none.toml"), "-o", str(tmp_path / "x.zarr"), "--size", "8x8",
                   "--pixel-size", "1"], capsys)
    assert "not found" in line and list(tmp_path.iterdir()) == []


def test_cli_bake_help_lists_the_options(capsys):
    with pytest.raises(SystemExit) as info:
        main(["bake", "--help"])
    assert info.value.code == 0
    text = capsys.readouterr().out
    for option in ("--size", "--pixel-size", "--origin", "--levels", "--chunk", "--shard", "--dtype",
                   "--scheduler", "--workers"):
        assert option in text


@pytest.mark.parametrize("dtype, bits", [("uint8", 8), ("uint16", 16)])
def test_cli_bake_png_is_the_same_pixels_as_the_store(texture_file, tmp_path, capsys, dtype, bits):
    """-o X.png: the region as one plain PNG, level 0 of the store bit for bit (8 or 16 bits)."""
    from spectex.io import read_image

    out = tmp_path / "ground.png"
    argv = ["bake", str(texture_file), "-o", str(out), "--size", "120x90", "--pixel-size", "0.25",
            "--origin", "100,-50", "--dtype", dtype]
    assert main(argv) == 0
    assert f"{bits}-bit RGB" in capsys.readouterr().out
    tex = SpectralTexture.load(texture_file)
    ref = to_dtype(bake(tex, (90, 120), origin=(100.0, -50.0), pixel_size=0.25), dtype)
    png = read_image(out)
    assert png.shape == (90, 120, 3)
    assert np.array_equal(np.round(png.astype(np.float64) * (2 ** bits - 1)).astype(ref.dtype), ref)
    assert [p.name for p in tmp_path.iterdir()] == ["ground.png"]  # nothing else left behind


@pytest.mark.parametrize("extra, message", [(["--levels", "2"], "--levels applies to a .zarr store"),
                                            (["--chunk", "32"], "--chunk applies to a .zarr store"),
                                            (["--workers", "1"], "--workers applies to a .zarr store"),
                                            (["--dtype", "float32"], "--dtype float32 needs a .zarr store")])
def test_cli_bake_png_refuses_the_pyramids_options(texture_file, tmp_path, capsys, extra, message):
    out = tmp_path / "ground.png"
    argv = ["bake", str(texture_file), "-o", str(out), "--size", "12x9", "--pixel-size", "0.25", *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
    assert not out.exists()
