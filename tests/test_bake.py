"""Bakes to a sharded OME-Zarr pyramid: exact pixels, metadata an independent reader accepts, resuming."""

import json
import math
import tomllib

import numpy as np
import pytest

from spectex import texture_file
from spectex.bake import bake_window, bake_zarr, level_shapes, to_dtype
from spectex.render import bake
from spectex.texture import SpectralTexture

zarr = pytest.importorskip("zarr")
pytest.importorskip("dask")

SHAPE = (150, 230)
ORIGIN = (12345.678, -9876.54321)  # far from the world origin: the anchors' rounding matters here
P = 0.0625


@pytest.fixture(scope="module")
def texture(tile_maker):
    return SpectralTexture.paper_preset(tile_maker(64, 3))


def reference(texture, shape=SHAPE, *, origin=ORIGIN, pixel_size=P, dtype="uint8"):
    """The pixels a level must hold: spectex.render.bake, converted, channels first."""
    return np.moveaxis(to_dtype(bake(texture, shape, origin=origin, pixel_size=pixel_size), dtype), 2, 0)


def read_ome(path):
    """The image through ome-zarr-py, an independent OME-NGFF reader: (node metadata, [levels])."""
    from ome_zarr.io import parse_url
    from ome_zarr.reader import Reader

    location = parse_url(str(path))
    assert location is not None, f"ome-zarr does not open {path}"
    nodes = list(Reader(location)())
    assert nodes, f"ome-zarr finds no image in {path}"
    return nodes[0].metadata, [np.asarray(level) for level in nodes[0].data]


def store_bytes(path):
    """Every file of a store, by relative path."""
    return {str(f.relative_to(path)): f.read_bytes() for f in sorted(path.rglob("*")) if f.is_file()}


# ------------------------------------------------------------------ windows
@pytest.mark.parametrize("blend", ["alpha", "variance", "detail", "overlay"])
def test_bake_window_is_the_window_of_the_whole_bake_to_the_bit(tile_maker, blend):
    tex = SpectralTexture.paper_preset(tile_maker(64, 1), blend=blend)
    whole = bake(tex, (300, 410), origin=ORIGIN, pixel_size=0.1)
    for r0, r1, c0, c1 in [(0, 300, 0, 410), (17, 170, 233, 410), (299, 300, 0, 1), (64, 128, 128, 256)]:
        window = bake_window(tex, (r0, r1, c0, c1), origin=ORIGIN, pixel_size=0.1)
        assert window.dtype == np.float32 and window.shape == (r1 - r0, c1 - c0, 3)
        assert np.array_equal(window, whole[r0:r1, c0:c1]), (r0, r1, c0, c1)


def test_a_bake_at_a_shifted_origin_is_not_the_window(texture):
    """The control that bake_window exists for: a block baked on its own rounds its anchors elsewhere."""
    whole = bake(texture, (300, 410), origin=ORIGIN, pixel_size=0.1)
    r0, c0 = 100, 200
    shifted = bake(texture, (200, 210), origin=(ORIGIN[0] + c0 * 0.1, ORIGIN[1] + r0 * 0.1), pixel_size=0.1)
    assert not np.array_equal(shifted, whole[r0:, c0:])
    assert np.abs(shifted - whole[r0:, c0:]).max() < 1e-5  # the same picture, other last bits


def test_bake_window_rejects_bad_windows(texture):
    for window, err in [((0, 0, 0, 5), ValueError), ((5, 2, 0, 5), ValueError), ((0, 5, 0), ValueError),
                        ((-1, 5, 0, 5), ValueError), ((0, 5.0, 0, 5), TypeError)]:
        with pytest.raises(err, match="window"):
            bake_window(texture, window, pixel_size=1.0)
    with pytest.raises(ValueError, match="pixel_size"):
        bake_window(texture, (0, 4, 0, 4), pixel_size=0.0)


# --------------------------------------------------------------- conversion
def test_to_dtype_reference_values():
    v = np.array([0.0, 1.0, 0.5, 0.25, 0.1, 2.0 / 255.0], dtype=np.float32)
    assert to_dtype(v, "uint8").tolist() == [0, 255, 128, 64, 26, 2]  # 127.5 rounds to even: 128
    assert to_dtype(v, "uint16").tolist() == [0, 65535, 32768, 16384, 6554, 514]  # 32767.5 -> 32768
    assert to_dtype(v, "uint8").dtype == np.uint8 and to_dtype(v, "uint16").dtype == np.uint16
    assert np.array_equal(to_dtype(v, "float32"), v)
    with pytest.raises(ValueError, match="dtype"):
        to_dtype(v, "int8")


# ------------------------------------------------------------ bake to zarr
def test_bake_zarr_every_level_is_the_bake_at_its_pixel_size_read_by_ome_zarr(texture, tmp_path):
    out = tmp_path / "region.zarr"
    result = bake_zarr(texture, out, SHAPE, pixel_size=P, origin=ORIGIN, chunk=32, shard=64)
    assert result.shapes == level_shapes(SHAPE, 4) == [(150, 230), (75, 115), (38, 58), (19, 29)]
    assert result.pixel_sizes == [P, 2 * P, 4 * P, 8 * P]
    assert result.baked == result.shards == 3 * 4 + 2 * 2 + 1 + 1 and result.resumed == 0
    assert result.pixels == sum(h * w for h, w in result.shapes)

    meta, levels = read_ome(out)
    assert [a["name"] for a in meta["axes"]] == ["c", "y", "x"]
    assert [a["type"] for a in meta["axes"]] == ["channel", "space", "space"]
    assert meta["axes"][1]["unit"] == meta["axes"][2]["unit"] == "meter"
    assert meta["channel_names"] == ["red", "green", "blue"]
    assert meta["contrast_limits"] == [[0, 255]] * 3
    assert len(levels) == 4
    for k, (level, transforms) in enumerate(zip(levels, meta["coordinateTransformations"])):
        size = P * 2 ** k
        assert level.dtype == np.uint8 and level.shape == (3,) + result.shapes[k]
        assert np.array_equal(level, reference(texture, result.shapes[k], pixel_size=size)), k
        scale = next(t["scale"] for t in transforms if t["type"] == "scale")
        shift = next(t["translation"] for t in transforms if t["type"] == "translation")
        assert scale == [1.0, size, size]
        # OME-NGFF places pixel centres at scale * index + translation; bake samples at the centres.
        assert shift == [0.0, ORIGIN[1] + size / 2, ORIGIN[0] + size / 2]

    doc = json.loads((out / "zarr.json").read_text())
    assert doc["zarr_format"] == 3 and doc["attributes"]["ome"]["version"] == "0.5"
    ours = doc["attributes"]["spectex"]
    assert ours["complete"] is True
    assert ours["bake"]["shape"] == list(SHAPE) and ours["bake"]["origin"] == list(ORIGIN)
    assert ours["bake"]["pixel_size"] == P and ours["bake"]["levels"] == 4 and ours["bake"]["dtype"] == "uint8"
    assert tomllib.loads(ours["texture_file"])["layers"] == texture_file.to_dict(texture, [])["layers"]
    assert "[[layers]]" in ours["texture_file"] and f"size = {texture.layers[0].size!r}" in ours["texture_file"]
    array = zarr.open_array(out, path="0", mode="r")
    assert array.chunks == (3, 32, 32) and array.shards == (3, 64, 64)
    assert array.metadata.dimension_names == ("c", "y", "x")
    assert not (out / ".spectex-progress").exists()


@pytest.mark.parametrize("dtype", ["uint16", "float32"])
def test_bake_zarr_other_types_hold_the_converted_bake(texture, tmp_path, dtype):
    out = tmp_path / "t.zarr"
    bake_zarr(texture, out, SHAPE, pixel_size=P, origin=ORIGIN, levels=2, chunk=64, shard=128, dtype=dtype)
    meta, levels = read_ome(out)
    assert levels[0].dtype == np.dtype(dtype)
    assert np.array_equal(levels[0], reference(texture, dtype=dtype))
    assert np.array_equal(levels[1], reference(texture, level_shapes(SHAPE, 2)[1], pixel_size=2 * P, dtype=dtype))
    assert meta["contrast_limits"][0] == [0, 65535 if dtype == "uint16" else 1.0]


def test_bake_zarr_same_pixels_whatever_chunk_shard_and_threads(texture, tmp_path):
    ref = [reference(texture, s, pixel_size=P * 2 ** k) for k, s in enumerate(level_shapes(SHAPE, 3))]
    for n, (chunk, shard, workers) in enumerate([(16, 16, 1), (16, 48, 2), (32, 96, 3), (128, 256, 2)]):
        out = tmp_path / f"v{n}.zarr"
        result = bake_zarr(texture, out, SHAPE, pixel_size=P, origin=ORIGIN, levels=3, chunk=chunk, shard=shard,
                           workers=workers)
        assert result.shards == sum(math.ceil(h / shard) * math.ceil(w / shard) for h, w in result.shapes)
        for k in range(3):
            assert np.array_equal(zarr.open_array(out, path=str(k), mode="r")[:], ref[k]), (chunk, shard, k)


def test_bake_zarr_from_a_texture_file_keeps_its_text(texture, tmp_path):
    path = texture.save(tmp_path / "ground.toml")
    out = tmp_path / "g.zarr"
    bake_zarr(path, out, (40, 50), pixel_size=0.5, chunk=16, shard=32)
    doc = json.loads((out / "zarr.json").read_text())
    assert doc["attributes"]["spectex"]["texture_file"] == path.read_text()
    assert np.array_equal(zarr.open_array(out, path="0")[:], reference(texture, (40, 50), origin=(0.0, 0.0),
                                                                      pixel_size=0.5))


# ------------------------------------------------------------------ resuming
class Stop(Exception):
    pass


def test_interrupted_bake_resumes_to_the_same_bytes(texture, tmp_path):
    kw = dict(pixel_size=P, origin=ORIGIN, levels=3, chunk=16, shard=32, workers=1)
    whole = tmp_path / "a" / "t.zarr"
    whole.parent.mkdir()
    bake_zarr(texture, whole, SHAPE, **kw)

    out = tmp_path / "b" / "t.zarr"
    out.parent.mkdir()
    calls = []

    def stop_after_three(done, total):
        calls.append(done)
        if len(calls) == 3:
            raise Stop

    with pytest.raises(Stop):
        bake_zarr(texture, out, SHAPE, progress=stop_after_three, **kw)
    # Unfinished: no image for a reader, not marked complete.
    doc = json.loads((out / "zarr.json").read_text())
    assert "ome" not in doc["attributes"] and doc["attributes"]["spectex"]["complete"] is False
    from ome_zarr.io import parse_url
    from ome_zarr.reader import Reader

    assert not any(node.data for node in Reader(parse_url(str(out)))())
    markers = {f.name for f in (out / ".spectex-progress").iterdir()}
    assert 3 <= len(markers) < 26
    # A worker killed mid-write: a garbage shard without a marker, and zarr's temporary file.
    shard = out / "0" / "c" / "0" / "4" / "6"
    assert "0.4.6" not in markers
    shard.parent.mkdir(parents=True, exist_ok=True)
    shard.write_bytes(b"half a shard")
    (shard.parent / ("6." + "0" * 32 + ".partial")).write_bytes(b"temp")

    result = bake_zarr(texture, out, SHAPE, **kw)
    assert result.resumed == len(markers) and result.baked == result.shards - len(markers)
    assert store_bytes(out) == store_bytes(whole)
    again = bake_zarr(texture, out, SHAPE, **kw)
    assert again.baked == 0 and again.resumed == again.shards


def test_resume_ignores_threads_but_refuses_other_arguments(texture, tmp_path):
    out = tmp_path / "t.zarr"
    kw = dict(pixel_size=P, origin=ORIGIN, levels=2, chunk=16, shard=32)
    bake_zarr(texture, out, SHAPE, workers=1, **kw)
    before = store_bytes(out)
    assert bake_zarr(texture, out, SHAPE, workers=2, **kw).baked == 0
    changes = [dict(shape=(150, 231)), dict(pixel_size=0.06), dict(origin=(0.0, 0.0)), dict(levels=3),
               dict(chunk=32), dict(shard=64), dict(dtype="uint16")]
    for change in changes:
        args = kw | {"shape": SHAPE} | change
        shape = args.pop("shape")
        with pytest.raises(ValueError, match="other arguments") as info:
            bake_zarr(texture, out, shape, **args)
        assert next(iter(change)) in str(info.value)
    other = SpectralTexture.paper_preset(texture.tiles[0], opacity=0.5)
    with pytest.raises(ValueError, match="other arguments.*layers"):
        bake_zarr(other, out, SHAPE, **kw)
    assert store_bytes(out) == before


def test_bake_zarr_refuses_paths_that_are_not_its_own(texture, tmp_path):
    (tmp_path / "file.zarr").write_text("not a store")
    (tmp_path / "dir.zarr").mkdir()
    (tmp_path / "dir.zarr" / "data.txt").write_text("keep me")
    zarr.create_group(store=str(tmp_path / "other.zarr"), attributes={"ome": {"version": "0.5"}})
    for name in ("file.zarr", "dir.zarr", "other.zarr"):
        before = store_bytes(tmp_path)
        with pytest.raises(ValueError, match="is not a spectex bake"):
            bake_zarr(texture, tmp_path / name, (20, 20), pixel_size=1.0, chunk=16, shard=16)
        assert store_bytes(tmp_path) == before


@pytest.mark.parametrize("kwargs, err, word", [
    (dict(shape=(0, 5)), ValueError, "shape"),
    (dict(pixel_size=0.0), ValueError, "pixel_size"),
    (dict(pixel_size=float("nan")), ValueError, "pixel_size"),
    (dict(origin=(0.0,)), ValueError, "origin"),
    (dict(origin=(0.0, float("inf"))), ValueError, "origin"),
    (dict(chunk=8), ValueError, "chunk"),
    (dict(chunk=24), ValueError, "chunk"),
    (dict(shard=48), ValueError, "shard"),
    (dict(chunk=16, shard=16384), ValueError, "shard"),
    (dict(levels=0), ValueError, "levels"),
    (dict(levels=9), ValueError, "levels"),
    (dict(dtype="int8"), ValueError, "dtype"),
    (dict(workers=0), ValueError, "workers"),
    (dict(scheduler="localhost:8786"), ValueError, "scheduler"),
    (dict(scheduler="inproc://x"), ValueError, "scheduler"),  # issue 26: in-process, never a cluster
    (dict(scheduler="tcp://host:99999"), ValueError, "scheduler"),
    (dict(scheduler="tcp://host"), ValueError, "scheduler"),
    (dict(connect_timeout=0.0), ValueError, "connect_timeout"),
    (dict(connect_timeout=1e-320), ValueError, "connect_timeout must be >= 0.001"),
    (dict(pixel_size=1e300), ValueError, "pixel_size"),
    (dict(pixel_size=1e-300), ValueError, "pixel_size"),
    (dict(origin=(1e300, 0.0)), ValueError, "origin"),
    (dict(shape=(10**9, 10**9)), ValueError, r"shape 1000000000x1000000000 .* over the limit .*BAKE_BYTES"),
    (dict(shape=(20000, 20000), chunk=16, shard=16), ValueError, r"shards, over the limit .*BAKE_SHARDS"),
    (dict(scheduler="tcp://127.0.0.1:9", workers=2), ValueError, "workers"),
    (dict(path="out.png"), ValueError, "path"),
    (dict(path="missing/out.zarr"), ValueError, "path"),
    (dict(texture="nope.toml"), ValueError, "texture"),
    (dict(texture=np.zeros((4, 4, 4))), TypeError, "texture"),
])
def test_bake_zarr_rejects_bad_input_before_writing(texture, tmp_path, monkeypatch, kwargs, err, word):
    monkeypatch.chdir(tmp_path)
    args = dict(texture=texture, path="out.zarr", shape=(100, 100), pixel_size=1.0, chunk=32, shard=64)
    args.update(kwargs)
    with pytest.raises(err, match=word):
        bake_zarr(args.pop("texture"), args.pop("path"), args.pop("shape"), **args)
    assert list(tmp_path.iterdir()) == []


def test_unreachable_scheduler_writes_nothing(texture, tmp_path):
    import socket
    import time

    # nothing listens: refused at once (dask.distributed alone would retry until its timeout)
    start = time.perf_counter()
    with pytest.raises(OSError, match="tcp://127.0.0.1:9: nothing listens on port 9 of 127.0.0.1"):
        bake_zarr(texture, tmp_path / "t.zarr", (20, 20), pixel_size=1.0, chunk=16, shard=16,
                  scheduler="tcp://127.0.0.1:9", connect_timeout=30)
    assert time.perf_counter() - start < 30  # not the timeout
    # something listens but never answers as a scheduler: the timeout says so
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen()
        address = f"tcp://127.0.0.1:{silent.getsockname()[1]}"
        with pytest.raises(OSError, match=f"cannot reach the scheduler {address} within 0.5 s"):
            bake_zarr(texture, tmp_path / "t.zarr", (20, 20), pixel_size=1.0, chunk=16, shard=16,
                      scheduler=address, connect_timeout=0.5)
    assert list(tmp_path.iterdir()) == []


def test_bake_limits_come_from_the_environment(monkeypatch):
    from spectex._limits import limit

    monkeypatch.setenv("SPECTEX_MAX_BAKE_BYTES", str(1 << 44))
    assert limit("BAKE_BYTES", 1 << 40) == 1 << 44
    for bad in ("", "lots", "-5", "0"):  # a typo never lifts a limit
        monkeypatch.setenv("SPECTEX_MAX_BAKE_BYTES", bad)
        assert limit("BAKE_BYTES", 1 << 40) == 1 << 40


KW = dict(pixel_size=P, origin=ORIGIN, levels=2, chunk=16, shard=32)


def test_a_deleted_or_damaged_shard_is_baked_again_to_the_same_bytes(texture, tmp_path):
    out = tmp_path / "t.zarr"
    bake_zarr(texture, out, SHAPE, **KW)
    whole = store_bytes(out)
    shards = [f for f in whole if f.startswith("0/c/")]
    (out / shards[3]).unlink()
    damaged = out / shards[5]
    damaged.write_bytes(damaged.read_bytes()[:-7])  # truncated: its recorded size no longer matches
    result = bake_zarr(texture, out, SHAPE, **KW)
    assert (result.baked, result.resumed) == (2, result.shards - 2)
    assert store_bytes(out) == whole
    # the control: an intact store is complete, nothing baked
    assert bake_zarr(texture, out, SHAPE, **KW).baked == 0


def test_a_second_writer_is_refused_and_a_stale_lock_taken_over(texture, tmp_path):
    import socket
    import subprocess
    import sys

    out = tmp_path / "t.zarr"
    bake_zarr(texture, out, SHAPE, **KW)
    whole = store_bytes(out)
    (out / "0" / "c" / "0" / "0" / "0").unlink()
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        lock = {"pid": live.pid, "host": socket.gethostname()}
        (out / "spectex.lock").write_text(json.dumps(lock))
        with pytest.raises(ValueError, match=f"is being baked by process {live.pid} on"):
            bake_zarr(texture, out, SHAPE, **KW)
        assert (out / "spectex.lock").exists()  # the other writer's lock is left alone
        (out / "spectex.lock").write_text(json.dumps(dict(lock, host="elsewhere")))
        with pytest.raises(ValueError, match="on elsewhere"):  # another host: cannot be checked, refused
            bake_zarr(texture, out, SHAPE, **KW)
    finally:
        live.kill()
        live.wait()
    # the same process, now dead: its lock is stale and taken over
    (out / "spectex.lock").write_text(json.dumps(lock))
    assert bake_zarr(texture, out, SHAPE, **KW).baked == 1
    assert not (out / "spectex.lock").exists()
    assert store_bytes(out) == whole


def test_two_bakes_at_once_one_refused_the_store_exact(texture, tmp_path):
    import subprocess
    import sys

    out = tmp_path / "t.zarr"
    reference_store = tmp_path / "ref.zarr"
    bake_zarr(texture, reference_store, SHAPE, **KW)
    texture.save(tmp_path / "tex.toml")
    argv = [sys.executable, "-m", "spectex", "bake", str(tmp_path / "tex.toml"), "-o", str(out), "--size",
            f"{SHAPE[1]}x{SHAPE[0]}", "--pixel-size", str(P), "--origin", f"{ORIGIN[0]},{ORIGIN[1]}",
            "--levels", "2", "--chunk", "16", "--shard", "32", "--workers", "1"]
    runs = [subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    done = []
    for run in runs:
        _, err = run.communicate(timeout=300)
        done.append((run.returncode, err))
    codes = sorted(rc for rc, _ in done)
    assert codes in ([0, 0], [0, 2]), done  # both finished one after the other, or one refused
    refused = [err for rc, err in done if rc == 2]
    assert all("is being baked by process" in err and err.count("\n") == 1 for err in refused), refused
    shards = {k: v for k, v in store_bytes(out).items() if "/c/" in k}
    assert shards == {k: v for k, v in store_bytes(reference_store).items() if "/c/" in k}
    assert json.loads((out / "zarr.json").read_text())["attributes"]["spectex"]["complete"] is True
    assert not (out / "spectex.lock").exists()


def test_leftovers_of_a_killed_run_are_cleaned_by_the_next(texture, tmp_path):
    out = tmp_path / "t.zarr"
    bake_zarr(texture, out, SHAPE, **KW)
    whole = store_bytes(out)
    (out / ".spectex-progress").mkdir()
    (out / ".spectex-progress" / ".0.0.0.part").write_text("1")
    (out / ".spectex-shards.json.part").write_text("{")
    (out / "0" / ".stray.part").mkdir()
    (out / "0" / ".stray.part" / "x").write_text("x")
    (out / "user.txt").write_text("keep")  # not ours: kept
    bake_zarr(texture, out, SHAPE, **KW)
    assert store_bytes(out) == whole | {"user.txt": b"keep"}
    assert not (out / "0" / ".stray.part").exists() and not (out / ".spectex-progress").exists()


# --------------------------------------------------------------- a cluster
def test_bake_on_a_local_cluster_of_two_processes_equals_the_local_bake(texture, tmp_path):
    distributed = pytest.importorskip("distributed")
    kw = dict(pixel_size=P, origin=ORIGIN, levels=2, chunk=16, shard=64)
    local = tmp_path / "local" / "t.zarr"
    local.parent.mkdir()
    bake_zarr(texture, local, SHAPE, **kw)
    remote = tmp_path / "cluster" / "t.zarr"
    remote.parent.mkdir()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=50) as cluster:
        with distributed.Client(cluster, set_as_default=False) as client, \
                distributed.get_task_stream(client) as stream:
            result = bake_zarr(texture, remote, SHAPE, scheduler=cluster.scheduler_address, **kw)
    workers = {task["worker"] for task in stream.data if "spectex-bake" in str(task["key"])}
    assert len(workers) == 2  # both processes baked shards
    assert result.baked == result.shards == 3 * 4 + 2 * 2
    assert store_bytes(remote) == store_bytes(local)


def test_each_level_agrees_with_the_box_filtered_level_below(texture, tmp_path):
    """Two routes to a coarser level: the sampler's mip-mapping at 2x the pixel size, and a 2 x 2 box of level 0.

    On the paper's composite, which the 2/255 was set for (the preset's variance blend keeps about 3x
    the contrast, and the two routes' difference grows with it: 3.4/255 at level 2)."""
    texture = SpectralTexture.paper_preset(texture.tiles[0], blend="alpha", detail=False)
    out = tmp_path / "t.zarr"
    bake_zarr(texture, out, (256, 384), pixel_size=0.5, origin=ORIGIN, levels=3, chunk=64, shard=128)
    for k in (1, 2):
        fine = zarr.open_array(out, path=str(k - 1), mode="r")[:].astype(np.float64)
        coarse = zarr.open_array(out, path=str(k), mode="r")[:].astype(np.float64)
        h, w = coarse.shape[1:]
        box = fine.reshape(3, h, 2, w, 2).mean(axis=(2, 4))
        assert np.abs(box - coarse).mean() < 2.0, k  # of 255
        assert min(np.corrcoef(box[c].ravel(), coarse[c].ravel())[0, 1] for c in range(3)) > 0.98, k
        # control: the same comparison off by 3 pixels fails
        off = np.roll(coarse, 3, axis=2)
        assert min(np.corrcoef(box[c].ravel(), off[c].ravel())[0, 1] for c in range(3)) < 0.9, k


def test_docs_python_examples_run(tmp_path, monkeypatch):
    """docs/bake.md's Python blocks that bake and check 'example.zarr' run as written."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "bake.md").read_text()
    blocks = [b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "example.zarr" in b]
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs"}
    for code in blocks:
        exec(compile(code, "docs/bake.md", "exec"), namespace)
    assert namespace["result"].shapes[0] == (300, 400)


def test_a_bake_larger_than_the_free_disk_is_refused_before_writing(texture, tmp_path, monkeypatch):
    import collections

    import spectex.bake._zarr as bz

    usage = collections.namedtuple("usage", "total used free")
    need = sum(3 * h * w for h, w in bz.level_shapes(SHAPE, 2))  # uint8, two levels
    out = tmp_path / "t.zarr"
    monkeypatch.setattr(bz.shutil, "disk_usage", lambda p: usage(10 ** 12, 0, need - 1))
    words = f"makes 2 levels that need {need} bytes uncompressed, more than the {need - 1} bytes free"
    with pytest.raises(ValueError, match=words):
        bake_zarr(texture, out, SHAPE, **KW)
    assert not out.exists()
    monkeypatch.setattr(bz.shutil, "disk_usage", lambda p: usage(10 ** 12, 0, need))  # the control
    assert bake_zarr(texture, out, SHAPE, **KW).baked > 0
    # a resumed bake counts what is there already: the rest of the bytes free is enough
    written = sum(f.stat().st_size for f in out.rglob("*") if f.is_file())
    monkeypatch.setattr(bz.shutil, "disk_usage", lambda p: usage(10 ** 12, 0, need - written))
    assert bake_zarr(texture, out, SHAPE, **KW).baked == 0
