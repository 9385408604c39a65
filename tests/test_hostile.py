"""Hostile inputs, table-driven across every command (issue 15).

Each case runs ``python -m spectex ...`` as a subprocess in a fresh copy of
a folder of small inputs (empty, truncated, huge on decode, NaN, links,
special files, texture files that reach outside their folder...), and
asserts:

* the expected exit status (and the words of the one-line error);
* at most one line on standard error, and no traceback;
* every file that was there before is byte-identical afterwards, links
  still links to the same place, except the outputs the case names;
* no new file except those outputs, and no temporary file anywhere;
* done within ``TIME_LIMIT`` seconds.

Interrupt cases send SIGINT or SIGTERM after a delay, or as soon as a file
appears (a staging folder or a temporary file: the moment of writing), and
additionally assert that an interrupted run changed nothing at all (or, if
the signal came during the final renames, which hold signals back, that the
whole new set is in place). A signal in the first tenths of a second reaches
Python before spectex runs (the interpreter is still importing ``site``):
SIGTERM then ends the process silently (-15), and SIGINT gives Python's own
traceback, which no program can prevent; so SIGINT delays here start at 1.5 s.

The cases run in parallel, a few subprocesses at a time; most of them fail
before any numba kernel is compiled.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
TIME_LIMIT = 120.0  # seconds per case, generous for a loaded machine
WORKERS = 4
CAMERA = ("--camera", "0,0,2,0,-10")
DEMO_FILES = ("ground.png", "closeup.png", "aerial.png", "tile_colour.png", "tile_alpha.png", "texture.tile.png",
              "texture.toml")
#: What ``spectex export tex.toml --format web,glsl`` writes (a 16 x 16 tile: five mip levels).
EXPORT_FILES = ("index.html", "spectex-export.json", "glsl/README.md", "glsl/spectex_texture.json",
                "glsl/spectex_uniforms.js", "glsl/tile.png", "glsl/spectex_layers.es300.glsl",
                "glsl/spectex_layers.330.glsl", "glsl/ground.es300.vert", "glsl/ground.es300.frag",
                "glsl/ground.330.vert", "glsl/ground.330.frag", *(f"glsl/mips/tile.level{d}.png" for d in range(5)))
FIT_FILES = ("texture.toml", "texture.tile0.png", "texture.tile1.png", "comparison.png", "band_power.png",
             "histograms.png")
TEMP = re.compile(r"\.part|^\.spectex|^\.tmp")


# ---------------------------------------------------------------- the inputs

def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _png(width, height, depth, colour_type, idat: bytes) -> bytes:
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", idat) + _chunk(b"IEND", b"")


def _make_inputs(folder: Path) -> None:
    from spectex import io
    from spectex.texture import SpectralTexture

    rng = np.random.default_rng(15)
    io.write_image(folder / "img.png", rng.random((32, 32, 3)).astype(np.float32))
    io.write_image(folder / "m.png", rng.random((32, 32, 3)).astype(np.float32))
    io.write_image(folder / "flat.png", np.full((32, 32, 3), 0.5, np.float32))
    np.save(folder / "nan.npy", np.full((16, 16, 3), np.nan, np.float32))
    inf = rng.random((16, 16)).astype(np.float32)
    inf[3, 4] = np.inf
    np.save(folder / "inf.npy", inf)
    (folder / "empty.png").write_bytes(b"")
    (folder / "trunc.png").write_bytes((folder / "img.png").read_bytes()[:200])
    (folder / "notimage.png").write_text("this is not an image\n")
    # A decompression bomb, small on disk: 12000 x 12000 1-bit grey zeros (17 kB, 144 M pixels).
    side = 12000
    rows = b"\x00" * ((1 + (side + 7) // 8) * side)
    (folder / "bomb.png").write_bytes(_png(side, side, 1, 0, zlib.compress(rows, 9)))
    # Headers only: a 16-bit PNG and a .npy claiming 100000 x 100000.
    (folder / "bomb16.png").write_bytes(_png(100000, 100000, 16, 2, zlib.compress(b"\x00" * 64)))
    with open(folder / "bomb.npy", "wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "<f4", "fortran_order": False,
                                                  "shape": (100000, 100000)})
    # Texture files: a good one, then hostile ones.
    SpectralTexture.paper_preset(tile_size=16).save(folder / "tex.toml")
    toml = (folder / "tex.toml").read_text()
    strip = np.tile(np.linspace(0, 1, 9000, dtype=np.float32)[None, :, None], (3, 1, 4))
    io.write_image(folder / "strip.tile.png", strip)  # a 3 x 9000 tile (a side over 8192)
    (folder / "strip.toml").write_text(toml.replace('"tex.tile.png"', '"strip.tile.png"'))
    (folder / "abs.toml").write_text(toml.replace('"tex.tile.png"', f'"{folder / "tex.tile.png"}"'))
    (folder / "up.toml").write_text(toml.replace('"tex.tile.png"', f'"../{folder.name}/tex.tile.png"'))
    (folder / "notile.toml").write_text(toml.replace('"tex.tile.png"', '"missing.png"'))
    (folder / "nan.toml").write_text(re.sub(r"size = [0-9.e+]+", "size = nan", toml, count=1))
    (folder / "garbage.toml").write_text("[[[ not toml\n")
    (folder / "empty.toml").write_text("")
    # Text.
    (folder / "c.txt").write_text("the cat sat on the mat and the dog sat on the log. " * 40)
    (folder / "empty.txt").write_text("")
    (folder / "nul.txt").write_bytes(b"abc\x00def")
    np.save(folder / "pickle.npy", np.array([[object()]], dtype=object), allow_pickle=True)
    data16 = folder / "img16.png"
    io.write_image(data16, rng.random((32, 32, 3)).astype(np.float32), bit_depth=16)
    (folder / "trunc16.png").write_bytes(data16.read_bytes()[:300])
    data16.unlink()
    # Links and folders.
    os.symlink("img.png", folder / "link.png")
    os.symlink("nowhere.png", folder / "dangling.png")
    os.symlink("c.txt", folder / "clink.txt")
    os.symlink(".", folder / "here")
    (folder / "sub").mkdir()
    (folder / "adir.png").mkdir()
    # Earlier outputs, which an interrupted or failed run must leave as they are.
    (folder / "prev.png").write_bytes((folder / "m.png").read_bytes())
    (folder / "prev.txt").write_text("an earlier output\n")
    for name, files in (("demo_prev", DEMO_FILES), ("fit_prev", FIT_FILES)):
        (folder / name).mkdir()
        for f in files:
            (folder / name / f).write_text(f"earlier {f}\n")


# ------------------------------------------------------------------- helpers

def _readonly_folder(folder: Path) -> str | None:
    """A folder this process cannot write into (None if there is none: root without a read-only mount)."""
    if os.geteuid() != 0:
        ro = folder / "ro"
        ro.mkdir()
        ro.chmod(0o555)
        return str(ro)
    for candidate in ("/sys", "/proc"):
        try:
            fd, probe = tempfile.mkstemp(dir=candidate)
        except OSError:
            return candidate
        os.close(fd)
        os.unlink(probe)
    return None


def _snapshot(folder: Path) -> dict:
    """relative path -> what it is: ('file', sha1, mode) | ('link', target) | ('dir', mode) | ('other', mode)."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            p = Path(root) / name
            rel = str(p.relative_to(folder))
            st = os.lstat(p)
            if stat.S_ISLNK(st.st_mode):
                out[rel] = ("link", os.readlink(p))
            elif stat.S_ISREG(st.st_mode):
                out[rel] = ("file", hashlib.sha1(p.read_bytes()).hexdigest(), stat.S_IMODE(st.st_mode))
            elif stat.S_ISDIR(st.st_mode):
                out[rel] = ("dir", stat.S_IMODE(st.st_mode))
            else:
                out[rel] = ("other", stat.S_IFMT(st.st_mode))
    return out


#: The words of a refused typed number (spectex._numbers).
_NOT_ASCII = "expected a whole number in ASCII digits"


@dataclass(frozen=True)
class Case:
    """One hostile run: ``argv`` after ``spectex`` ('{ro}' is a read-only folder)."""

    id: str
    argv: tuple
    rc: int | tuple
    err: str = ""                 # regular expression stderr must contain (an error's words)
    changes: tuple = ()           # relative paths this run may (rc 0) create or change
    setup: object = None          # f(folder) -> None, extra preparation
    signum: int | None = None     # send this signal ...
    when: object = None           # ... after this many seconds, or when this glob matches
    check: object = None          # f(folder, stdout) -> None, extra assertions
    unset: tuple = ()             # environment variables removed for this run
    stdout: str = "pipe"          # 'closed': no standard output at all; 'broken': its reader has gone
    hup: str | None = None        # SIGHUP in the run: 'default' or 'ignored' (as nohup leaves it), whatever
                                  # the test process inherited; None: inherited as it is


def _earlier_export(folder):
    """An earlier export of tex.toml in exp_prev (what an interrupted new one must leave as it was)."""
    from spectex.export import export
    from spectex.texture import SpectralTexture

    export(SpectralTexture.load(folder / "tex.toml"), folder / "exp_prev", formats="web,glsl")


def _fifo(name):
    def setup(folder):
        os.mkfifo(folder / name)
    return setup


def _hardlink(src, dst):
    def setup(folder):
        os.link(folder / src, folder / dst)
    return setup


def _sparse_huge_text(folder):
    with open(folder / "huge.txt", "wb") as fh:  # 100 MB that take no disk (made here: copies are not sparse)
        fh.truncate(100 << 20)


def _mkdir_with_photo(folder):
    (folder / "out").mkdir()
    shutil.copyfile(folder / "img.png", folder / "out" / "texture.tile0.png")


def _link_in_demo(folder):
    os.symlink("../prev.txt", folder / "demo_prev" / "texture.toml.lnk")
    os.unlink(folder / "demo_prev" / "texture.toml")
    os.symlink("../prev.txt", folder / "demo_prev" / "texture.toml")


def _no_nan(folder, stdout):
    assert not re.search(r"\bnan\b", stdout), stdout


def _stdout_has_text(folder, stdout):
    assert "the" in stdout, stdout


def _link_kept(name, target):
    def check(folder, stdout):
        assert os.readlink(folder / name) == target
        assert (folder / target).stat().st_size > 0
    return check


def _write(name, text):
    def setup(folder):
        (folder / name).write_text(text)
    return setup


def _nested(folder):  # 2 kB: 1000 nested brackets (the recursive TOML parser's depth)
    (folder / "nest.toml").write_text("a = " + "[" * 1000 + "]" * 1000 + "\n")


def _many_layers(folder):  # 100000 layers: 3 MB, refused by size before parsing
    toml = (folder / "tex.toml").read_text()
    (folder / "many.toml").write_text(toml + "\n[[layers]]\ntile = 0\nsize = 1.0\n" * 100000)


def _nine_layers(folder):  # small, parsed, refused by count before any tile is read
    toml = (folder / "tex.toml").read_text()
    (folder / "nine.toml").write_text(toml + "\n[[layers]]\ntile = 0\nsize = 1.0\n" * 9)


def _tiny_layer(folder):
    toml = (folder / "tex.toml").read_text()
    (folder / "tiny.toml").write_text(re.sub(r"size = [0-9.e+]+", "size = 1e-308", toml, count=1))


def _npy(name, array):
    def setup(folder):
        np.save(folder / name, array)
    return setup


_RNG = np.random.default_rng(26)
_BIG = (_RNG.random((32, 32, 3)) * 5 - 1).astype(np.float32)  # floats from -1 to 4
_BIG[0, 0, :2] = -1.0, 4.0
_BIG_EXEMPLAR = "big.png"


def _big_exemplar(folder):  # 4096 x 4096 grey zeros: a 16 Mpx exemplar, small on disk
    side = 4096
    rows = b"\x00" * ((1 + side) * side)
    (folder / _BIG_EXEMPLAR).write_bytes(_png(side, side, 8, 0, zlib.compress(rows, 9)))


def _user_folder_in_export(folder):
    _earlier_export(folder)
    (folder / "exp_prev" / "mine").mkdir()


def _user_file_in_manifest(folder):
    import json

    _earlier_export(folder)
    (folder / "exp_prev" / "notes.txt").write_text("a user's notes\n")
    manifest = folder / "exp_prev" / "spectex-export.json"
    doc = json.loads(manifest.read_text())
    doc["formats"]["web"].append("notes.txt")
    doc["sha256"]["notes.txt"] = "0" * 64
    manifest.write_text(json.dumps(doc))


def _finished_bake(folder):
    from spectex.bake import bake_zarr

    bake_zarr(folder / "tex.toml", folder / "b.zarr", (40, 40), pixel_size=0.1, chunk=16, shard=16)


def _bake_locked_by_live(folder):
    import json
    import socket

    _finished_bake(folder)
    (folder / "b.zarr" / "0" / "c" / "0" / "0" / "0").unlink()
    # this test process: alive while the case runs
    (folder / "b.zarr" / "spectex.lock").write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname()}))


def _bake_shard_deleted(folder):
    _finished_bake(folder)
    (folder / "b.zarr" / "0" / "c" / "0" / "1" / "1").unlink()


BAKE = ("--size", "40x40", "--pixel-size", "0.1", "--chunk", "16", "--shard", "16")
SIGINT, SIGTERM = signal.SIGINT, signal.SIGTERM
SAME = "is the input"
CASES = [
    # --- outputs that name an input: refused before any work, by inode (links, ../, hard links)
    Case("tile-from-X-o-X", ("tile", "--from", "img.png", "-o", "img.png"), 2, SAME),
    Case("tile-o-dotdot-spelling", ("tile", "--from", "img.png", "-o", "sub/../img.png"), 2, SAME),
    Case("tile-o-hard-link", ("tile", "--from", "img.png", "-o", "hard.png"), 2, SAME,
         setup=_hardlink("img.png", "hard.png")),
    Case("tile-o-through-linked-folder", ("tile", "--from", "img.png", "-o", "here/img.png"), 2, SAME),
    Case("tile-from-link-o-target", ("tile", "--from", "link.png", "-o", "img.png"), 2, SAME),
    Case("tile-preview-is-input", ("tile", "--from", "x_preview.png", "--preview", "-o", "x.png"), 2, SAME,
         setup=_hardlink("img.png", "x_preview.png")),
    Case("synth-X-o-X", ("synth", "img.png", "--method", "histogram", "-o", "img.png"), 2, SAME),
    Case("synth-X-o-link-to-X", ("synth", "img.png", "--method", "histogram", "-o", "link.png"), 2, SAME),
    Case("synth-match-o-match", ("synth", "img.png", "--method", "histogram", "--match", "m.png", "-o", "m.png"),
         2, SAME),
    Case("spectrum-X-o-X", ("spectrum", "img.png", "-o", "img.png"), 2, SAME),
    Case("compare-o-reference", ("compare", "m.png", "--reference", "img.png", "-o", "img.png"), 2, SAME),
    Case("compare-o-image", ("compare", "m.png", "--reference", "img.png", "-o", "./m.png"), 2, SAME),
    Case("text-C-o-C", ("text", "c.txt", "-o", "c.txt"), 2, SAME),
    Case("text-C-o-link-to-C", ("text", "c.txt", "-o", "clink.txt"), 2, SAME),
    Case("render-o-own-tile", ("render", "tex.toml", *CAMERA, "-o", "tex.tile.png"), 2, SAME),
    Case("fit-folder-holds-photo", ("fit", "out/texture.tile0.png", "-o", "out"), 2, SAME,
         setup=_mkdir_with_photo),
    # --- links, folders and special files as outputs
    Case("noise-o-link-writes-target", ("noise", "perlin", "--size", "16", "-o", "plink.png"), 0,
         changes=("prev.png",), setup=lambda f: os.symlink("prev.png", f / "plink.png"),
         check=_link_kept("plink.png", "prev.png")),
    Case("noise-o-dangling-link", ("noise", "perlin", "--size", "16", "-o", "dangling.png"), 0,
         changes=("nowhere.png",), check=_link_kept("dangling.png", "nowhere.png")),
    Case("noise-o-folder", ("noise", "perlin", "--size", "16", "-o", "adir.png"), 2, "is a folder"),
    Case("noise-o-fifo", ("noise", "perlin", "--size", "16", "-o", "fifo.png"), 2, "is a pipe",
         setup=_fifo("fifo.png")),
    Case("noise-o-missing-folder", ("noise", "perlin", "-o", "nofolder/x.png"), 2, "does not exist"),
    Case("noise-o-readonly-before-work", ("noise", "fbm", "--size", "8192x8192", "-o", "{ro}/x.png"), 2,
         "not writable"),
    Case("tile-o-readonly-before-work", ("tile", "--size", "8192", "-o", "{ro}/x.png"), 2, "not writable"),
    Case("demo-out-readonly", ("demo", "-o", "{ro}/demo"), 2, "not writable"),
    Case("demo-out-is-file", ("demo", "-o", "prev.txt"), 2, "must be a folder"),
    Case("demo-member-is-link", ("demo", "-o", "demo_prev"), 2, "symbolic link", setup=_link_in_demo),
    Case("fit-o-is-file", ("fit", "img.png", "-o", "prev.txt"), 2, "must be a folder"),
    Case("noise-o-name-too-long", ("noise", "perlin", "-o", "a" * 300 + ".png"), 2, "File name too long"),
    Case("noise-o-newline-in-name", ("noise", "perlin", "-o", "new\nline/x.png"), 2, "does not exist"),
    Case("fit-member-is-folder", ("fit", "img.png", "-o", "fo"), 2, "is a folder; it cannot be replaced",
         setup=lambda f: (f / "fo" / "comparison.png").mkdir(parents=True)),
    Case("demo-parent-missing", ("demo", "-o", "nope/demo"), 2, "parent folder 'nope' does not exist"),
    Case("text-o-disk-full", ("text", "c.txt", "-o", "/dev/full"), 2, "No space left on device"),
    Case("text-stdout-closed", ("text", "c.txt"), 2, "standard output is closed", stdout="closed"),
    Case("compare-stdout-closed", ("compare", "m.png", "--reference", "img.png"), 2, "standard output is closed",
         stdout="closed"),
    Case("text-stdout-reader-gone", ("text", "c.txt", "--length", "300000"), 141, stdout="broken"),
    Case("text-o-stdout-streams", ("text", "c.txt", "--length", "50", "-o", "/dev/stdout"), 0,
         check=_stdout_has_text),
    Case("text-o-devnull-streams", ("text", "c.txt", "--length", "50", "-o", "/dev/null"), 0),
    # --- inputs that are not files
    Case("text-corpus-dev-stdin", ("text", "/dev/stdin"), 2, "character device"),
    Case("spectrum-dev-stdin", ("spectrum", "/dev/stdin"), 2, "character device"),
    Case("synth-exemplar-folder", ("synth", "adir.png", "-o", "x.png"), 2, "is a folder"),
    Case("tile-from-dangling-link", ("tile", "--from", "dangling.png", "-o", "x.png"), 2, "missing file"),
    Case("compare-missing", ("compare", "nothere.png", "--reference", "img.png"), 2, "not found"),
    Case("compare-without-reference", ("compare", "img.png"), 2, "compare needs the exemplar"),
    Case("compare-three-images", ("compare", "img.png", "m.png", "--reference", "img.png"), 2,
         "one IMAGE and --reference"),
    # --- empty, truncated, not an image, NaN and infinity
    Case("synth-empty", ("synth", "empty.png", "-o", "x.png"), 2, "not a readable image"),
    Case("spectrum-truncated", ("spectrum", "trunc.png"), 2, "truncated"),
    Case("synth-truncated-16-bit", ("synth", "trunc16.png", "-o", "x.png"), 2, "not a readable PNG"),
    Case("tile-from-pickle-npy", ("tile", "--from", "pickle.npy", "-o", "x.png"), 2, "numeric array"),
    Case("noise-o-empty-name", ("noise", "perlin", "-o", ""), 2, "expected a file or folder name"),
    Case("tile-from-not-image", ("tile", "--from", "notimage.png", "-o", "x.png"), 2, "not a readable image"),
    Case("compare-nan", ("compare", "nan.npy", "--reference", "img.png"), 2, "IMAGE must hold finite values"),
    Case("synth-inf", ("synth", "inf.npy", "--method", "histogram", "-o", "x.png"), 2, "finite"),
    Case("fit-nan", ("fit", "nan.npy", "-o", "out"), 2, "finite"),
    Case("compare-flat-says-undefined", ("compare", "flat.png", "--reference", "flat.png"), 0, check=_no_nan),
    Case("text-empty-corpus", ("text", "empty.txt"), 2, "corpus"),
    Case("text-binary-corpus", ("text", "nul.txt"), 2, "NUL"),
    # --- huge: decompression bombs (small on disk) and sizes whose cost grows without bound
    Case("spectrum-bomb", ("spectrum", "bomb.png"), 2, "144000000 pixels, over the limit of 134217728"),
    Case("synth-bomb16", ("synth", "bomb16.png", "-o", "x.png"), 2, "over the limit of 134217728"),
    Case("tile-from-bomb-npy", ("tile", "--from", "bomb.npy", "-o", "x.png"), 2, "over the limit"),
    Case("fit-bomb", ("fit", "bomb.png", "-o", "out"), 2, "over the limit"),
    Case("compare-bomb", ("compare", "img.png", "--reference", "bomb.png"), 2, "over the limit"),
    Case("render-strip-tile", ("render", "strip.toml", *CAMERA, "-o", "x.png"), 2, "at most 8192"),
    Case("view-strip-tile", ("view", "strip.toml"), 2, "at most 8192"),
    Case("view-huge-window", ("view", "tex.toml", "--size", "100000x100000"), 2, "over the limit"),
    Case("tile-cutoff-tiny", ("tile", "--cutoff", "1e-12", "-o", "x.png"), 2, "cutoff must be at least"),
    Case("tile-size-huge", ("tile", "--size", "100000", "-o", "x.png"), 2, "over the limit"),
    Case("text-corpus-huge", ("text", "huge.txt"), 2, "104857600 bytes, over the limit", setup=_sparse_huge_text),
    Case("text-length-huge", ("text", "c.txt", "--length", "1000000000000"), 2, "--length must be at most"),
    Case("synth-size-huge", ("synth", "img.png", "--size", "100000x100000", "-o", "x.png"), 2, "over the limit"),
    Case("noise-size-huge", ("noise", "perlin", "--size", "100000x100000", "-o", "x.png"), 2, "over the limit"),
    Case("render-frames-budget", ("render", "tex.toml", *CAMERA, "--frames", "1000", "-o", "x.gif"), 2,
         r"1555200000 bytes .* at most 690 frames"),
    # --- values: the message says what is wrong with the value given
    Case("noise-negative-size", ("noise", "perlin", "--size", "-5x10", "-o", "x.png"), 2, ">= 1, got '-5x10'"),
    Case("noise-lacunarity-overflow", ("noise", "fbm", "--lacunarity", "1e300", "-o", "x.png"), 2,
         "--lacunarity 1e\\+300"),
    Case("noise-mp4-odd", ("noise", "perlin", "--size", "1x1", "--frames", "2", "-o", "x.mp4"), 2, "even"),
    Case("render-mp4-odd", ("render", "tex.toml", *CAMERA, "--size", "33x17", "--frames", "2", "-o", "x.mp4"), 2,
         "even"),
    Case("spectrum-fmax-over-nyquist", ("spectrum", "img.png", "--fmax", "10"), 2, "--fmax must be at most 0.5"),
    Case("fit-pixel-size-huge", ("fit", "img.png", "--pixel-size", "1e300", "-o", "out"), 2, "--pixel-size"),
    Case("fit-pixel-size-tiny", ("fit", "img.png", "--pixel-size", "1e-300", "-o", "out"), 2, "--pixel-size"),
    Case("render-absolute-tile", ("render", "abs.toml", *CAMERA, "-o", "x.png"), 2, "absolute path"),
    Case("render-dotdot-tile", ("render", "up.toml", *CAMERA, "-o", "x.png"), 2, "'\\.\\.'"),
    Case("render-missing-tile", ("render", "notile.toml", *CAMERA, "-o", "x.png"), 2, "not found"),
    Case("render-nan-layer", ("render", "nan.toml", *CAMERA, "-o", "x.png"), 2, "finite"),
    Case("render-garbage-toml", ("render", "garbage.toml", *CAMERA, "-o", "x.png"), 2, "not valid TOML"),
    Case("view-empty-toml", ("view", "empty.toml"), 2, "missing field"),
    Case("view-no-display", ("view", "tex.toml"), 2, "no display", unset=("DISPLAY", "WAYLAND_DISPLAY")),
    Case("render-empty-tile", ("render", "tex.toml", *CAMERA, "-o", "x.png"), 2, "not a readable image",
         setup=lambda f: (f / "tex.tile.png").write_bytes(b"")),
    # --- interrupts, at several moments
    Case("text-sigterm-while-working", ("text", "c.txt", "--length", "8000000", "-o", "prev.txt"), 143,
         signum=SIGTERM, when=1.5, changes=("prev.txt",)),
    Case("text-sigint-while-working", ("text", "c.txt", "--length", "8000000", "-o", "new.txt"), 130,
         signum=SIGINT, when=1.5, changes=("new.txt",)),
    # so early that Python may not have started spectex yet: then the default action ends it (-15)
    Case("text-sigterm-at-start", ("text", "c.txt", "-o", "new.txt"), (143, -15), signum=SIGTERM, when=0.05,
         changes=("new.txt",)),
    Case("demo-sigterm-new-folder", ("demo", "-o", "newdemo"), 143, signum=SIGTERM, when=0.5,
         changes=("newdemo",) + tuple(f"newdemo/{f}" for f in DEMO_FILES)),
    Case("demo-sigint-new-folder-writing", ("demo", "-o", "newdemo"), 130, signum=SIGINT,
         when=".newdemo.*", changes=("newdemo",) + tuple(f"newdemo/{f}" for f in DEMO_FILES)),
    Case("demo-sigterm-existing-writing", ("demo", "-o", "demo_prev"), 143, signum=SIGTERM,
         when="demo_prev/.spectex-stage.*", changes=tuple(f"demo_prev/{f}" for f in DEMO_FILES)),
    # early: while it starts (the demo now takes 1.5 s in all; at 2 s a loaded machine's run was ending)
    Case("demo-sigint-existing-early", ("demo", "-o", "demo_prev"), 130, signum=SIGINT, when=0.5,
         changes=tuple(f"demo_prev/{f}" for f in DEMO_FILES)),
    # SIGHUP's disposition is set for the run: a suite run under nohup (SIGHUP ignored, and inherited) must
    # test the same thing, and an ignored SIGHUP must stay ignored (the run completes, as nohup asks)
    Case("text-sighup-while-working", ("text", "c.txt", "--length", "8000000", "-o", "prev.txt"), 129,
         signum=signal.SIGHUP, when=".prev.*", changes=("prev.txt",), hup="default"),
    Case("text-sighup-ignored-under-nohup", ("text", "c.txt", "--length", "2000000", "-o", "prev.txt"), 0,
         signum=signal.SIGHUP, when=".prev.*", changes=("prev.txt",), hup="ignored", check=lambda f, out: (
             (f / "prev.txt").stat().st_size >= 2000000 or pytest.fail("the run did not complete"))),
    Case("fit-sigterm-existing", ("fit", "img.png", "-o", "fit_prev"), 143, signum=SIGTERM, when=2.0,
         changes=tuple(f"fit_prev/{f}" for f in FIT_FILES)),
    Case("noise-gif-sigint-writing", ("noise", "perlin", "--size", "256", "--frames", "60", "-o", "anim.gif"),
         130, signum=SIGINT, when=".anim.*", changes=("anim.gif",)),
    # --- the newer commands follow the same rules (export, bake)
    Case("export-o-file-input", ("export", "tex.toml", "-o", "tex.toml"), 2, "output"),
    Case("export-o-folder-holding-inputs", ("export", "tex.toml", "-o", "."), 2, ""),
    Case("export-absolute-tile", ("export", "abs.toml", "-o", "exp"), 2, "absolute path"),
    Case("export-strip-tile", ("export", "strip.toml", "-o", "exp"), 2, "at most 8192"),
    Case("export-bad-format", ("export", "tex.toml", "-o", "exp", "--format", "web,unreal5"), 2, "unreal5"),
    Case("export-missing-texture", ("export", "nope.toml", "-o", "exp"), 2, "nope.toml"),
    Case("export-sigint-new-folder-writing", ("export", "tex.toml", "-o", "newexp", "--format", "web,glsl"), 130,
         signum=SIGINT, when=".newexp.*", changes=("newexp", "newexp/glsl", "newexp/glsl/mips")
         + tuple(f"newexp/{f}" for f in EXPORT_FILES)),
    Case("export-sigterm-replacing-writing", ("export", "tex.toml", "-o", "exp_prev", "--format", "web,glsl"), 143,
         signum=SIGTERM, when=".exp_prev.*.part", changes=tuple(f"exp_prev/{f}" for f in EXPORT_FILES),
         setup=_earlier_export),
    Case("bake-o-texture", ("bake", "tex.toml", "-o", "tex.toml", "--size", "8x8", "--pixel-size", "1"), 2, ""),
    Case("bake-o-tile", ("bake", "tex.toml", "-o", "tex.tile.png", "--size", "8x8", "--pixel-size", "1"), 2, ""),
    Case("bake-absolute-tile", ("bake", "abs.toml", "-o", "b.zarr", "--size", "8x8", "--pixel-size", "1"), 2,
         "absolute path"),
    Case("bake-negative-size", ("bake", "tex.toml", "-o", "b.zarr", "--size", "-8x8", "--pixel-size", "1"), 2,
         "size"),
    Case("bake-nan-pixel-size", ("bake", "tex.toml", "-o", "b.zarr", "--size", "8x8", "--pixel-size", "nan"), 2,
         "pixel"),
    Case("bake-read-only-folder", ("bake", "tex.toml", "-o", "{ro}/b.zarr", "--size", "8x8", "--pixel-size", "1"),
         2, ""),
    # --- options that do not apply to the chosen kind, method, source or output: refused, not ignored
    Case("noise-marble-gain", ("noise", "marble", "--gain", "0.4", "-o", "x.png"), 2,
         "--gain does not apply to marble"),
    Case("noise-marble-lacunarity", ("noise", "marble", "--lacunarity", "3", "-o", "x.png"), 2,
         "--lacunarity does not apply to marble"),
    Case("noise-wood-basis", ("noise", "wood", "--basis", "value", "-o", "x.png"), 2,
         "--basis does not apply to wood"),
    Case("noise-perlin-octaves", ("noise", "perlin", "--octaves", "3", "-o", "x.png"), 2,
         "--octaves does not apply to perlin"),
    Case("noise-value-octaves", ("noise", "value", "--octaves", "3", "-o", "x.png"), 2,
         "--octaves does not apply to value"),
    Case("noise-fps-without-frames", ("noise", "fbm", "--fps", "10", "-o", "x.png"), 2,
         "--fps does not apply without --frames"),
    Case("noise-colormap-npy", ("noise", "fbm", "--colormap", "fire", "-o", "x.npy"), 2,
         "--colormap does not apply to .npy"),
    Case("noise-bit-depth-jpg", ("noise", "fbm", "--bit-depth", "8", "-o", "x.jpg"), 2,
         "--bit-depth does not apply to .jpg"),
    Case("synth-quilting-colours", ("synth", "img.png", "--colours", "per-channel", "-o", "x.png"), 2,
         "--colours does not apply to --method quilting"),
    Case("synth-histogram-block", ("synth", "img.png", "--method", "histogram", "--block", "8", "-o", "x.png"),
         2, "--block does not apply to --method histogram"),
    Case("synth-quilting-window", ("synth", "img.png", "--window", "5", "-o", "x.png"), 2,
         "--window does not apply to --method quilting"),
    Case("synth-match-size", ("synth", "img.png", "--method", "histogram", "--match", "m.png", "--size", "8",
                              "-o", "x.png"), 2, "--size does not apply with --match"),
    Case("tile-from-beta", ("tile", "--from", "img.png", "--beta", "3", "-o", "x.png"), 2,
         "--beta does not apply with --from"),
    Case("tile-seam-without-from", ("tile", "--seam", "moisan", "-o", "x.png"), 2,
         "--seam does not apply without --from"),
    Case("tile-noise-kernel", ("tile", "--method", "noise", "--kernel", "box", "-o", "x.png"), 2,
         "--kernel does not apply to --method noise"),
    Case("tile-spectral-octaves", ("tile", "--octaves", "4", "-o", "x.png"), 2,
         "--octaves does not apply to --method spectral"),
    Case("tile-luminance-azimuth", ("tile", "--alpha", "luminance", "--azimuth", "10", "-o", "x.png"), 2,
         "--azimuth does not apply to --alpha luminance"),
    Case("tile-emboss-alpha-value", ("tile", "--alpha-value", "0.3", "-o", "x.png"), 2,
         "--alpha-value does not apply to --alpha emboss"),
    Case("render-to-single-picture", ("render", "tex.toml", *CAMERA, "--to", "0,9,2,0,-10", "-o", "x.png"), 2,
         "--to does not apply to a single picture"),
    Case("compare-overlap-without-block", ("compare", "m.png", "--reference", "img.png", "--overlap", "4"), 2,
         "--overlap does not apply without --block"),
    # --- issue 26. Texture files: parsing limits, refused in one line and at once by every command
    *(Case(f"{cmd}-nested-brackets", (cmd, "nest.toml", *rest), 2, "nests arrays or tables deeper than 16",
           setup=_nested)
      for cmd, rest in (("render", (*CAMERA, "-o", "x.png")), ("export", ("-o", "exp",)),
                        ("bake", ("-o", "b.zarr", *BAKE)), ("view", ()))),
    Case("render-100000-layers", ("render", "many.toml", *CAMERA, "-o", "x.png"), 2,
         "over the limit of 1048576 bytes", setup=_many_layers),
    Case("bake-nine-layers", ("bake", "nine.toml", "-o", "b.zarr", *BAKE), 2,
         r"holds 1[0-9] layers; a texture has at most 8", setup=_nine_layers),
    Case("render-layer-size-1e-308", ("render", "tiny.toml", *CAMERA, "-o", "x.png"), 2,
         r"layers\[0\]\.size.* between 1e-06 and 1e\+09 metres", setup=_tiny_layer),
    Case("bake-layer-size-1e-308", ("bake", "tiny.toml", "-o", "b.zarr", *BAKE), 2, "between 1e-06 and 1e\\+09",
         setup=_tiny_layer),
    # --- bakes: cost, physical values, scheduler addresses, a store that checks itself, one writer
    Case("bake-pixel-size-1e300", ("bake", "tex.toml", "-o", "b.zarr", "--size", "8x8", "--pixel-size", "1e300"),
         2, "--pixel-size must be between"),
    Case("bake-size-1e9-squared", ("bake", "tex.toml", "-o", "b.zarr", "--size", "1000000000x1000000000",
                                   "--pixel-size", "1"), 2, "over the limit of 1099511627776 bytes"),
    Case("bake-shards-over-limit", ("bake", "tex.toml", "-o", "b.zarr", "--size", "20000x20000", "--pixel-size",
                                    "1", "--chunk", "16", "--shard", "16"), 2, "shards, over the limit"),
    *(Case(f"bake-scheduler-{name}", ("bake", "tex.toml", "-o", "b.zarr", *BAKE, "--scheduler", address), 2,
           "scheduler must be the network address")
      for name, address in (("inproc", "inproc://x"), ("no-port", "tcp://localhost"), ("port-99999",
                            "tcp://localhost:99999"), ("words", "not an address"))),
    Case("bake-scheduler-unreachable", ("bake", "tex.toml", "-o", "b.zarr", *BAKE, "--scheduler",
                                        "tcp://127.0.0.1:9", "--connect-timeout", "0.5"), 2,
         "cannot reach the scheduler tcp://127.0.0.1:9: nothing listens on port 9"),
    Case("bake-scheduler-no-such-host", ("bake", "tex.toml", "-o", "b.zarr", *BAKE, "--scheduler",
                                         "tcp://nosuchhost.invalid:8786"), 2, "host 'nosuchhost.invalid' not found"),
    Case("bake-connect-timeout-denormal", ("bake", "tex.toml", "-o", "b.zarr", *BAKE, "--scheduler",
                                           "tcp://127.0.0.1:9", "--connect-timeout", "1e-320"), 2,
         "--connect-timeout must be >= 0.001"),
    Case("noise-gain-overflow-one-line", ("noise", "fbm", "--gain", "1e308", "--size", "16", "-o", "x.png"), 2,
         "^spectex noise: error: gain=1e\\+308 with octaves=6 overflows"),
    Case("bake-connect-timeout-alone", ("bake", "tex.toml", "-o", "b.zarr", *BAKE, "--connect-timeout", "3"), 2,
         "--connect-timeout does not apply without --scheduler"),
    Case("bake-deleted-shard-rebaked", ("bake", "tex.toml", "-o", "b.zarr", *BAKE), 0,
         changes=("b.zarr/zarr.json", "b.zarr/0/c/0/1/1", "b.zarr/spectex-shards.json"), setup=_bake_shard_deleted,
         check=lambda f, out: "1 shards baked" in out or pytest.fail(out)),
    Case("bake-complete-control", ("bake", "tex.toml", "-o", "b.zarr", *BAKE), 0, setup=_finished_bake,
         check=lambda f, out: "complete already" in out or pytest.fail(out)),
    Case("bake-second-writer", ("bake", "tex.toml", "-o", "b.zarr", *BAKE), 2, "is being baked by process",
         setup=_bake_locked_by_live),
    # --- values, not only shapes: float images outside [0, 1], complex and signed .npy
    *(Case(f"{cmd}-float-out-of-range", argv, 2, r"holds values from -1 to 4; a float image must be in \[0, 1\]",
           setup=_npy("big.npy", _BIG))
      for cmd, argv in (("fit", ("fit", "big.npy", "-o", "out")),
                        ("synth", ("synth", "big.npy", "--method", "histogram", "-o", "x.png")),
                        ("tile", ("tile", "--from", "big.npy", "-o", "x.png")),
                        ("compare", ("compare", "big.npy", "--reference", "img.png")))),
    Case("synth-float-normalize-control", ("synth", "big.npy", "--method", "histogram", "--size", "16",
                                           "--normalize", "-o", "x.png"), 0, changes=("x.png",),
         setup=_npy("big.npy", _BIG)),
    Case("tile-normalize-without-from", ("tile", "--normalize", "-o", "x.png"), 2,
         "--normalize does not apply without --from"),
    Case("synth-complex-npy", ("synth", "c.npy", "-o", "x.png"), 2, "complex dtype complex64",
         setup=_npy("c.npy", np.ones((16, 16), np.complex64))),
    Case("synth-signed-npy", ("synth", "s.npy", "-o", "x.png"), 2, "unsigned integers or floats, got dtype int16",
         setup=_npy("s.npy", np.ones((16, 16), np.int16))),
    # --- synthesis cost: exemplar pixels (refused from the header) and estimated operations
    Case("synth-quilting-16-mpx-exemplar", ("synth", _BIG_EXEMPLAR, "--size", "64", "-o", "x.png"), 2,
         "16777216 pixels, over the limit of 4194304 pixels for quilting", setup=_big_exemplar),
    Case("synth-efros-leung-exhaustive-512", ("synth", "img.png", "--method", "efros-leung", "--exhaustive",
                                             "--window", "5", "--size", "2048", "-o", "x.png"), 2,
         "operations, over the limit of 1e\\+11"),
    # --- outputs: an export replaces only what it wrote
    Case("export-keeps-users-empty-folder", ("export", "tex.toml", "-o", "exp_prev", "--format", "web,glsl"), 2,
         "holds 'mine/', which the earlier export did not write", setup=_user_folder_in_export),
    Case("export-hand-edited-manifest", ("export", "tex.toml", "-o", "exp_prev", "--format", "web,glsl"), 2,
         "holds 'notes.txt'", setup=_user_file_in_manifest),
    Case("export-replace-control", ("export", "tex.toml", "-o", "exp_prev", "--format", "web,glsl"), 0,
         changes=("exp_prev/spectex-export.json",), setup=_earlier_export),
    # --- words: a legal long name, --seed by its name, one-frame animations
    Case("noise-o-255-byte-name", ("noise", "perlin", "--size", "8", "-o", "a" * 251 + ".png"), 0,
         changes=("a" * 251 + ".png",)),
    *(Case(f"{cmd}-seed-too-large", (cmd, *rest, "--seed", "99999999999999999999"), 2,
           "argument --seed: must be at most 9223372036854775807")
      for cmd, rest in (("noise", ("perlin", "-o", "x.png")), ("tile", ("-o", "x.png")), ("text", ("c.txt",)),
                        ("synth", ("img.png", "-o", "x.png")), ("fit", ("img.png", "-o", "out")),
                        ("demo", ("-o", "d")))),
    Case("fit-opacity-denormal", ("fit", "img.png", "--opacity", "1e-320", "-o", "out"), 2,
         "--opacity must be between 0.001 and 1"),  # found by benchmarks/fuzz_hostile.py: ran for minutes
    Case("render-one-frame-gif", ("render", "tex.toml", *CAMERA, "--size", "16x16", "--frames", "1", "-o",
                                  "x.gif"), 0, changes=("x.gif",)),
    # --- typed numbers: ASCII digits only (Python's int() and float() take any script's digits, '_',
    # spaces, 'inf'); the controls, plain ASCII (a sign, a negative zero), must run
    *(Case(f"{cmd}-{what}", (cmd, *argv), 2, words) for cmd, what, argv, words in (
        ("fit", "layers-arabic-indic-digit", ("img.png", "--layers", "٣", "-o", "out"), _NOT_ASCII),
        ("noise", "octaves-full-width-digit", ("fbm", "--octaves", "３", "-o", "x.png"), _NOT_ASCII),
        ("noise", "seed-underscores", ("perlin", "--seed", "1_000", "-o", "x.png"), _NOT_ASCII),
        ("text", "length-spaces", ("c.txt", "--length", " 3 "), _NOT_ASCII),
        ("render", "frames-float-spelling", ("tex.toml", *CAMERA, "--frames", "3.0", "-o", "x.gif"), _NOT_ASCII),
        ("bake", "chunk-5000-digits", ("tex.toml", "-o", "b.zarr", *BAKE, "--chunk", "9" * 5000),
         "at most 100 digits"),
        ("tile", "size-devanagari-digits", ("--size", "१६", "-o", "x.png"), "expected WxH"),
        ("synth", "bit-depth-arabic-indic", ("img.png", "--bit-depth", "١٦", "-o", "x.png"), _NOT_ASCII),
        ("noise", "scale-1e999", ("perlin", "--scale", "1e999", "-o", "x.png"), "must be finite"),
        ("tile", "beta-full-width", ("--beta", "１.５", "-o", "x.png"), "a number in ASCII digits"),
        ("fit", "ratio-underscores", ("img.png", "--ratio", "1_0.5", "-o", "out"), "a number in ASCII digits"),
        ("noise", "fps-infinity", ("perlin", "--frames", "2", "--fps", "infinity", "-o", "x.gif"), "must be finite"),
        ("spectrum", "fmax-hex-float", ("img.png", "--fmax", "0x1p-3"), "a number in ASCII digits"),
        ("render", "camera-full-width-digit", ("tex.toml", "--camera", "0,0,2,0,-１0", "-o", "x.png"),
         "a number in ASCII digits"),
    )),
    Case("noise-ascii-sign-control", ("noise", "fbm", "--octaves", "+3", "--seed", "-0", "--size", "8", "-o",
                                      "x.png"), 0, changes=("x.png",)),
    Case("tile-negative-zero-beta-control", ("tile", "--beta", "-0.0", "--size", "8", "-o", "x.png"), 0,
         changes=("x.png",)),
    # --- costs refused from the exemplar's header (before it is decoded or numba imported)
    Case("synth-block-over-exemplar", ("synth", "img.png", "--block", "100", "-o", "x.png"), 2,
         "exemplar of 32x32 pixels is smaller than block=100"),
    Case("synth-window-over-exemplar", ("synth", "img.png", "--method", "efros-leung", "--window", "41", "-o",
                                        "x.png"), 2, "window=41 is larger than the exemplar"),
    Case("synth-tileable-overlap", ("synth", "img.png", "--block", "16", "--overlap", "8", "--tileable", "-o",
                                    "x.png"), 2, "overlap must be smaller than block/2"),
    Case("synth-quilting-small-control", ("synth", "img.png", "--block", "16", "--size", "24", "-o", "x.png"), 0,
         changes=("x.png",)),
    Case("bake-png-pixel-size-tiny", ("bake", "tex.toml", "-o", "x.png", "--size", "8", "--pixel-size", "1e-300"),
         2, r"--pixel-size must be between 1e-06 and 1e\+09 metres"),
]


def _command(case: Case, argv: list) -> list:
    """The spectex run of ``case``, with the signal dispositions the case is about.

    SIGHUP's as the case says; SIGINT's the default a terminal gives, for a case that sends it (a
    suite started as a background job, or under nohup, hands its children an ignored SIGINT). A
    small Python sets them, then becomes the spectex run (exec keeps them).
    """
    dispositions = []
    if case.hup is not None:
        dispositions.append(f"signal.signal(signal.SIGHUP, signal.{'SIG_DFL' if case.hup == 'default' else 'SIG_IGN'})")
    if case.signum == SIGINT:
        dispositions.append("signal.signal(signal.SIGINT, signal.default_int_handler)")
    if not dispositions:
        return [sys.executable, "-m", "spectex", *argv]
    return [sys.executable, "-c", f"import os, signal, sys; {'; '.join(dispositions)}; "
            "os.execv(sys.executable, [sys.executable, *sys.argv[1:]])", "-m", "spectex", *argv]


def _run(case: Case, base: Path, work: Path) -> dict:
    folder = work / case.id
    shutil.copytree(base, folder, symlinks=True)
    if case.setup is not None:
        case.setup(folder)
    ro = None
    if any("{ro}" in a for a in case.argv):
        ro = _readonly_folder(folder)
        if ro is None:
            return {"skip": "no read-only folder available to this user"}
    argv = [a.replace("{ro}", ro or "") for a in case.argv]
    before = _snapshot(folder)
    ro_before = sorted(os.listdir(ro)) if ro else None
    env = dict(os.environ, PYTHONPATH=str(SRC), PYTHONWARNINGS="")
    for name in case.unset:
        env.pop(name, None)
    start = time.perf_counter()
    command = _command(case, argv)
    if case.stdout == "closed":
        command = ["sh", "-c", 'exec "$0" "$@" >&-', *command]
    proc = subprocess.Popen(command, cwd=folder, env=env,
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if case.stdout == "broken":
        proc.stdout.close()
        proc.stdout = None
    sent = None
    if case.signum is not None:
        deadline = start + TIME_LIMIT
        while proc.poll() is None and time.perf_counter() < deadline:
            if isinstance(case.when, (int, float)):
                if time.perf_counter() - start >= case.when:
                    break
            elif list(folder.glob(case.when)):
                break
            time.sleep(0.005)
        if proc.poll() is None:
            proc.send_signal(case.signum)
            sent = time.perf_counter() - start
    try:
        out, err = proc.communicate(timeout=TIME_LIMIT)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        return {"timeout": True, "elapsed": time.perf_counter() - start, "err": err}
    elapsed = time.perf_counter() - start
    after = _snapshot(folder)
    ro_after = sorted(os.listdir(ro)) if ro else None
    return {"rc": proc.returncode, "out": out or "", "err": err, "elapsed": elapsed, "before": before, "after": after,
            "ro": (ro_before, ro_after), "sent": sent, "folder": folder}


@pytest.fixture(scope="module")
def results(request, tmp_path_factory):
    """Run the selected cases, a few at a time; case id -> what happened."""
    wanted = {item.callspec.params["case"].id for item in request.session.items
              if item.module is request.module and hasattr(item, "callspec") and "case" in item.callspec.params}
    base = tmp_path_factory.mktemp("hostile-inputs")
    _make_inputs(base)
    work = tmp_path_factory.mktemp("hostile-runs")
    cases = [c for c in CASES if c.id in wanted]
    with ThreadPoolExecutor(max_workers=WORKERS) as pool:
        done = dict(zip((c.id for c in cases), pool.map(lambda c: _run(c, base, work), cases)))
    yield done
    for root, dirs, _ in os.walk(work):  # let pytest clean up read-only folders
        for d in dirs:
            with_write = os.stat(os.path.join(root, d)).st_mode | stat.S_IWUSR
            os.chmod(os.path.join(root, d), with_write)


def test_cases_are_distinct_and_cover_every_command():
    from spectex.cli import build_parser

    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids))
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    commands = set(sub.choices)
    covered = {c.argv[0] for c in CASES}
    assert commands <= covered, f"commands without a hostile case: {sorted(commands - covered)}"
    signalled = {c.argv[0] for c in CASES if c.signum is not None}
    assert {"demo", "fit", "text"} <= signalled


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_hostile(case, results):
    r = results[case.id]
    if "skip" in r:
        pytest.skip(r["skip"])
    assert not r.get("timeout"), f"still running after {TIME_LIMIT} s: {r['err'][-500:]}"
    assert r["elapsed"] < TIME_LIMIT
    err = r["err"]
    lines = [ln for ln in err.splitlines() if ln.strip() and "rendering on the CPU instead" not in ln]
    assert "Traceback" not in err, err
    assert len(lines) <= 1, err
    interrupted = case.signum is not None and r["sent"] is not None and r["rc"] != 0
    # An interrupt case whose run ended before the signal could be sent must be a complete run.
    expected = case.rc if isinstance(case.rc, tuple) else (case.rc,)
    if case.signum == signal.SIGINT and err.strip():
        # After its one line and its clean-up, CPython sometimes ends a process that caught a
        # KeyboardInterrupt by SIGINT itself (the shell convention for Ctrl-C): status -2.
        expected += (-signal.SIGINT,)
    expected += (0,) if case.signum is not None and r["sent"] is None else ()
    if case.hup == "ignored":
        interrupted = False  # the signal was sent, and rightly had no effect
    assert r["rc"] in expected, f"exit status {r['rc']}, stderr: {err}"
    if case.err and r["rc"] != 0:
        assert re.search(case.err, err), err
    before, after = r["before"], r["after"]
    changed = {p for p in before if after.get(p) != before[p]}
    created = set(after) - set(before)
    strays = [p for p in after if TEMP.search(Path(p).name)]
    assert not strays, f"temporary files left: {strays}"
    ro_before, ro_after = r["ro"]
    assert ro_before == ro_after
    touched = changed | created
    if interrupted and touched:
        # Signals are held back during the final renames: a signal that arrived then is acted on
        # after them, so the whole new set is in place, never a part of it.
        assert touched == set(case.changes), f"a part of the set changed: {sorted(touched)}"
    allowed = set(case.changes) if (r["rc"] == 0 or interrupted) else set()
    assert changed <= allowed, f"inputs or earlier outputs changed: {sorted(changed - allowed)}"
    assert created <= allowed, f"unexpected new files: {sorted(created - allowed)}"
    if os.environ.get("SPECTEX_HOSTILE_LOG"):
        with open(os.environ["SPECTEX_HOSTILE_LOG"], "a") as fh:
            fh.write(f"{case.id}\trc {r['rc']}\tsignal at {r['sent']}\t{r['elapsed']:.2f} s\t{err.strip()}\n")
    if case.check is not None and r["rc"] == 0:
        case.check(r["folder"], r["out"])


# ------------------------------------------------- the same bounds, from the library

def test_texture_file_tiles_stay_in_its_folder(tmp_path):
    from spectex.texture import SpectralTexture
    from spectex.texture_file import from_dict, to_dict

    tex = SpectralTexture.paper_preset(tile_size=16)
    tex.save(tmp_path / "t.toml")
    doc = to_dict(tex, ["t.tile.png"])
    assert from_dict(doc, base=tmp_path, texture_type=SpectralTexture) == tex  # the control
    (tmp_path / "sub").mkdir()
    shutil.copyfile(tmp_path / "t.tile.png", tmp_path / "sub" / "t.png")
    assert from_dict(dict(doc, tiles=["sub/t.png"]), base=tmp_path, texture_type=SpectralTexture) == tex
    for name, words in ((str(tmp_path / "t.tile.png"), "absolute path"), ("../t.tile.png", "'..'"),
                        ("sub/../t.tile.png", "'..'"), ("C:\\t.tile.png", "absolute path"), ("", "file name")):
        with pytest.raises(ValueError, match=words):
            from_dict(dict(doc, tiles=[name]), base=tmp_path / "sub", texture_type=SpectralTexture)


def test_tile_sides_are_bounded_before_any_work():
    from spectex.texture import SpectralTexture

    strip = np.zeros((3, 8193, 4), np.float32)
    with pytest.raises(ValueError, match=r"tiles\[0\] is 8193x3 texels; a tile side must be at most 8192"):
        SpectralTexture.plain(strip, 10.0)


def test_cutoff_cost_is_bounded_by_the_tile():
    from spectex.tiles import make_tile
    from spectex.tiles.from_noise import _working_factor

    start = time.perf_counter()
    assert _working_factor(512, 512, 1e-12) == 128  # the grid keeps 4 cells a side
    assert _working_factor(512, 384, 0.25) == 2
    assert time.perf_counter() - start < 1.0
    with pytest.raises(ValueError, match=r"cutoff must be at least 1/64 .* got 0.01"):
        make_tile(64, cutoff=0.01)


def test_text_length_is_bounded():
    from spectex.synthesis import generate_text, train_markov
    from spectex.synthesis._markov import MAX_TEXT_LENGTH

    model = train_markov("abcabd", order=1)
    with pytest.raises(ValueError, match=f"length must be <= {MAX_TEXT_LENGTH}"):
        generate_text(model, MAX_TEXT_LENGTH + 1)
    assert len(generate_text(model, 5)) == 5


# ------------------------------------------------- issue 26, from the library

def test_noise_refuses_a_shape_given_as_coordinates():
    from spectex import noise

    for f in (noise.fbm, noise.perlin, noise.value, noise.turbulence):
        with pytest.raises(TypeError, match="takes coordinates, not a shape|looks like a shape"):
            f((64, 64))
    # the controls: a list, or an array, of 1-D coordinates is noise at those points
    assert noise.fbm([0.5, 1.5]).shape == (2,)
    y, x = np.mgrid[0:8, 0:8] / 4.0
    assert noise.fbm(x, y).shape == (8, 8)


def test_texture_file_limits_are_fast(tmp_path):
    from spectex.texture import SpectralTexture

    load = SpectralTexture.load
    preset = SpectralTexture.paper_preset(tile_size=16)
    preset.save(tmp_path / "t.toml")
    toml = (tmp_path / "t.toml").read_text()
    assert load(tmp_path / "t.toml") == preset  # the control
    (tmp_path / "deep.toml").write_text("a = " + "[" * 1000 + "]" * 1000)
    (tmp_path / "deep_ok.toml").write_text('s = "' + "[" * 1000 + '"\n' + toml)  # brackets in a string: fine
    (tmp_path / "many.toml").write_text(toml + "\n[[layers]]\ntile = 0\nsize = 1.0\n" * 100000)
    start = time.perf_counter()
    with pytest.raises(ValueError, match="deeper than 16"):
        load(tmp_path / "deep.toml")
    with pytest.raises(ValueError, match="unknown field 's'"):
        load(tmp_path / "deep_ok.toml")
    with pytest.raises(ValueError, match="over the limit of 1048576 bytes"):
        load(tmp_path / "many.toml")
    assert time.perf_counter() - start < 5.0


def test_lengths_are_physical():
    from spectex.texture import Layer

    assert Layer(size=1e-6).size == 1e-6 and Layer(size=1e9).size == 1e9  # the controls, at the limits
    for bad in (1e-308, 1e-7, 1e10, 1e300):
        with pytest.raises(ValueError, match="size must be between 1e-06 and 1e\\+09 metres"):
            Layer(size=bad)


def test_float_images_outside_the_unit_range_are_refused_by_the_library():
    from spectex.synthesis import efros_leung, quilt, sample_histogram

    ex = np.random.default_rng(0).random((32, 32, 3)).astype(np.float32)
    assert sample_histogram(ex, (8, 8), rng=0).shape == (8, 8, 3)  # the control
    assert sample_histogram(ex * (1 + 5e-5), (8, 8), rng=0).max() <= 1.0  # rounding: clipped, taken
    for f in (lambda e: sample_histogram(e, (8, 8)), lambda e: quilt(e, (16, 16), block=8),
              lambda e: efros_leung(e, (8, 8), window=5)):
        with pytest.raises(ValueError, match=r"exemplar holds values from 0 to 2; a float image must be in \[0, 1\]"):
            f(ex * 2 / ex.max())


def test_render_returns_a_typed_result(monkeypatch):
    import dataclasses

    import spectex.render.gl as glmod
    from spectex.render import Camera, RenderResult, render
    from spectex.texture import SpectralTexture
    from spectex.tiles import make_tile

    def unavailable(**kw):
        raise glmod.GLUnavailable("no OpenGL 3.3 context (EGL): test")

    monkeypatch.setattr(glmod, "create_context", unavailable)
    result = render(SpectralTexture.plain(make_tile(16, rng=0), 4.0), Camera((0.0, 0.0, 2.0), pitch=-10.0), (6, 8))
    assert isinstance(result, RenderResult) and dataclasses.is_dataclass(result)
    assert result.image.shape == (6, 8, 3) and result.backend == "cpu"
    with pytest.raises(TypeError):  # a typed result, not the old tuple (no unpacking shim)
        _image, _backend = result


def test_a_full_disk_while_writing_a_pdf_is_one_line(tmp_path, monkeypatch, capsys):
    import errno

    import matplotlib.figure

    from spectex import io
    from spectex.cli import main

    io.write_image(tmp_path / "a.png", np.random.default_rng(1).random((32, 32, 3)).astype(np.float32))

    def full(self, *args, **kwargs):  # as matplotlib's PDF writer fails: its clean-up breaks on the OSError
        try:
            raise OSError(errno.ENOSPC, "No space left on device")
        except OSError:
            raise AttributeError("'Stream' object has no attribute 'pos'")  # noqa: B904 - the chain is the point

    assert main(["spectrum", str(tmp_path / "a.png"), "-o", str(tmp_path / "ok.pdf")]) == 0  # the control
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", full)
    assert main(["spectrum", str(tmp_path / "a.png"), "-o", str(tmp_path / "x.pdf")]) == 2
    err = capsys.readouterr().err
    assert f"output '{tmp_path / 'x.pdf'}' could not be written: No space left on device" in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "ok.pdf"]


def test_an_unwritable_numba_cache_falls_back_with_one_line(tmp_path):
    code = ("import sys; from pathlib import Path; import spectex._numba_cache as m; "
            "m._probe = lambda folder: not sys.argv[1] == 'ro'; "
            "folder = m.fall_back(Path(m.__file__).parent); print(folder); "
            "from spectex.tiles import make_tile; make_tile(16, rng=0)")
    env = dict(os.environ, PYTHONPATH=str(SRC))
    env.pop("NUMBA_CACHE_DIR", None)
    for mode in ("rw", "ro"):
        run = subprocess.run([sys.executable, "-c", code, mode], env=env, capture_output=True, text=True,
                             timeout=600)
        assert run.returncode == 0, run.stderr
        folder = run.stdout.strip().splitlines()[0]
        if mode == "rw":  # the control: a writable install says nothing
            assert folder == "None" and run.stderr == ""
        else:
            assert "compiled kernels are not kept between runs" in run.stderr
            assert run.stderr.count("\n") == 1
            assert not os.path.exists(folder)  # the private cache is removed at exit


def test_compiled_tells_a_kernel_numba_must_compile_from_one_on_disk(tmp_path):
    # the question the CLI asks before a first run's compile: False before the first call, True after it
    # in the same run and from the disk cache in the next; False again once the source changed
    module = tmp_path / "kernel_mod.py"
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import kernel_mod; "
            "from spectex._numba_cache import compiled; before = compiled(kernel_mod.f); kernel_mod.f(1.0); "
            "print(before, compiled(kernel_mod.f))")
    env = dict(os.environ, PYTHONPATH=str(SRC), NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    said = []
    for body in ("x + 1.0", None, "x * 2.0"):  # None: the same source, untouched
        if body is not None:
            module.write_text(f"import numba\n\n\n@numba.njit(cache=True)\ndef f(x):\n    return {body}\n")
            stamp = 1_700_000_000 + 10 * len(said)  # numba's stamp is the file's mtime and size: a new one
            os.utime(module, (stamp, stamp))
        run = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env=env, capture_output=True, text=True,
                             timeout=600)
        assert run.returncode == 0, run.stderr
        said.append(run.stdout.split())
    assert said == [["False", "True"], ["True", "True"], ["False", "True"]]


# ------------------------------------------------- typed numbers, in one place

@pytest.mark.parametrize("text, value", [("3", 3), ("+3", 3), ("-0", 0), ("007", 7), ("-12", -12),
                                         ("9" * 100, int("9" * 100))])
def test_parse_int_takes_ascii_whole_numbers(text, value):
    from spectex._numbers import parse_int

    assert parse_int(text) == value


@pytest.mark.parametrize("text", ["٣", "３", "१", "1_000", " 3 ", "3 ", "3.0", "1e3", "0x10", "", "+", "nan", "9" * 101,
                                  "9" * 5000, "3\n"])
def test_parse_int_refuses_what_python_int_would_take(text):
    from spectex._numbers import parse_int

    with pytest.raises(ValueError, match="ASCII digits|at most 100 digits"):
        parse_int(text)


@pytest.mark.parametrize("text, value", [("0.5", 0.5), (".5", 0.5), ("5.", 5.0), ("-1e-3", -1e-3), ("1E3", 1000.0),
                                         ("1e-320", 1e-320), ("1e308", 1e308)])
def test_parse_float_takes_ascii_decimals(text, value):
    from spectex._numbers import parse_float

    assert parse_float(text) == value


@pytest.mark.parametrize("text", ["-0", "-0.0", "-0e5"])
def test_parse_float_makes_negative_zero_plain(text):
    import math

    from spectex._numbers import parse_float

    assert math.copysign(1.0, parse_float(text)) == 1.0  # a control: float(text) keeps the sign
    assert math.copysign(1.0, float(text)) == -1.0


@pytest.mark.parametrize("text, words", [("inf", "finite"), ("-Infinity", "finite"), ("nan", "finite"),
                                         ("1e999", "finite"), ("-1e400", "finite"), ("１.５", "ASCII"),
                                         ("1_0.5", "ASCII"), (" 0.5", "ASCII"), ("0x1p3", "ASCII"), ("1e", "ASCII"),
                                         ("", "ASCII"), ("1,5", "ASCII"), ("٠.٥", "ASCII")])
def test_parse_float_refuses_what_python_float_would_take(text, words):
    from spectex._numbers import parse_float

    with pytest.raises(ValueError, match=words):
        parse_float(text)


def test_every_number_option_uses_the_one_parser():
    """No option of any command is parsed by Python's int or float themselves (they take '٣')."""
    from spectex.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    builtins = [(name, a.dest) for name, p in sub.choices.items() for a in p._actions if a.type in (int, float)]
    assert not builtins


def test_limits_from_the_environment_take_ascii_only(monkeypatch):
    from spectex._limits import limit

    monkeypatch.setenv("SPECTEX_MAX_X", "١٠٠")
    assert limit("X", 7) == 7
    monkeypatch.setenv("SPECTEX_MAX_X", "100")  # the control
    assert limit("X", 7) == 100


def test_a_float_beyond_a_double_is_a_value_error():
    from spectex._validate import check_float

    with pytest.raises(ValueError, match="must be finite"):
        check_float("gain", 10 ** 400)
    assert check_float("gain", 10 ** 300) == 1e300  # the control


# ------------------------------------------------- refusals before the heavy work

#: Refusals that need no numba: each must come before numba (or zarr, dask, moderngl) is imported.
LIGHT_REFUSALS = [
    ("synth", "img.png", "--block", "100", "-o", "x.png"),
    ("synth", "img.png", "--size", "100000x100000", "-o", "x.png"),
    ("synth", "img.png", "--method", "efros-leung", "--exhaustive", "--window", "5", "--size", "2048", "-o",
     "x.png"),
    ("synth", "img.png", "--method", "efros-leung", "--window", "4", "-o", "x.png"),
    ("synth", "img.png", "--tolerance", "-1", "-o", "x.png"),
    ("bake", "tex.toml", "-o", "b.zarr", "--size", "1000000000x1000000000", "--pixel-size", "1"),
    ("bake", "tex.toml", "-o", "b.zarr", "--size", "16", "--pixel-size", "1e300"),
    ("bake", "tex.toml", "-o", "b.zarr", "--size", "16", "--pixel-size", "1", "--chunk", "7"),
    ("bake", "tex.toml", "-o", "x.png", "--size", "100000x100000", "--pixel-size", "1"),
    ("fit", "img.png", "--layers", "99", "-o", "out"),
    ("fit", "img.png", "--ratio", "1000", "-o", "out"),
    ("tile", "--size", "100000", "-o", "x.png"),
    ("tile", "--size", "4", "-o", "x.png"),
    ("render", "tex.toml", *CAMERA, "--anisotropy", "99", "-o", "x.png"),
    ("render", "tex.toml", *CAMERA, "--size", "100000x100000", "-o", "x.png"),
    # a texture is loaded without numba (the tiles' package loads it lazily), and so are the inputs
    # that the text, tile and demo commands check
    ("render", "tex.toml", *CAMERA, "-o", "tex.tile.png"),
    ("export", "tex.toml", "-o", "tex.tile.png"),
    ("text", "c.txt", "-o", "c.txt"),
    ("text", "c.txt", "--length", "1000000000000"),
    ("tile", "--from", "tex.toml", "-o", "x.png"),
    ("demo", "-o", "tex.toml"),
    # the library's own checks, reached without its kernels: the tile's cut-off, fBm's amplitudes, a
    # texture file's tile outside its folder (checked before dask and zarr)
    ("tile", "--cutoff", "1e-12", "-o", "x.png"),
    ("noise", "fbm", "--gain", "1e308", "--size", "16", "-o", "x.png"),
    ("bake", "abs.toml", "-o", "b.zarr", "--size", "16", "--pixel-size", "1"),
]
HEAVY = ("numba", "zarr", "dask", "moderngl")


def _imports(argv, folder):
    """Exit status and the top-level modules a ``spectex`` run imported (``-X importtime``)."""
    env = dict(os.environ, PYTHONPATH=str(SRC), PYTHONWARNINGS="")
    proc = subprocess.run([sys.executable, "-X", "importtime", "-m", "spectex", *argv], cwd=folder, env=env,
                          stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=TIME_LIMIT)
    names = {line.rsplit("|", 1)[-1].strip() for line in proc.stderr.splitlines() if line.startswith("import time:")}
    return proc.returncode, names


@pytest.fixture(scope="module")
def light_folder(tmp_path_factory):
    from spectex import io
    from spectex.texture import SpectralTexture

    folder = tmp_path_factory.mktemp("light")
    io.write_image(folder / "img.png", np.random.default_rng(26).random((32, 32, 3)).astype(np.float32))
    SpectralTexture.paper_preset(tile_size=16).save(folder / "tex.toml")
    toml = (folder / "tex.toml").read_text(encoding="utf-8")
    (folder / "abs.toml").write_text(toml.replace('"tex.tile.png"', f'"{folder / "tex.tile.png"}"'), encoding="utf-8")
    (folder / "c.txt").write_text("the cat sat on the mat. " * 20, encoding="utf-8")
    return folder


@pytest.mark.parametrize("argv", LIGHT_REFUSALS, ids=[" ".join(a[:4]) for a in LIGHT_REFUSALS])
def test_refusals_come_before_the_heavy_imports(argv, light_folder):
    rc, names = _imports(argv, light_folder)
    assert rc == 2
    assert not names & set(HEAVY), sorted(names & set(HEAVY))


def test_export_of_a_periodic_texture_imports_no_numba(light_folder):
    """An export reads the texture's tiles and mip levels and writes shaders: no kernel runs, so no
    numba (the texture object of the sampler lives apart from its kernels)."""
    rc, names = _imports(("export", "tex.toml", "-o", "exp", "--format", "web,glsl,godot"), light_folder)
    assert rc == 0
    assert not names & set(HEAVY), sorted(names & set(HEAVY))
    shutil.rmtree(light_folder / "exp")


def test_heavy_imports_control(light_folder):
    """The control: the same command that does the work imports numba (so the test above can fail)."""
    rc, names = _imports(("synth", "img.png", "--block", "16", "--size", "16", "-o", "x.png"), light_folder)
    assert rc == 0 and "numba" in names
    (light_folder / "x.png").unlink()


def test_read_image_checks_the_header_before_decoding(tmp_path):
    from spectex import io

    io.write_image(tmp_path / "a.png", np.zeros((40, 24, 3), np.float32))
    data = (tmp_path / "a.png").read_bytes()
    (tmp_path / "cut.png").write_bytes(data[: len(data) // 2])  # a header, then half the pixels
    seen = []

    def refuse(shape):
        seen.append(shape)
        raise ValueError("refused from the header")

    with pytest.raises(ValueError, match="refused from the header"):  # not "not a readable image"
        io.read_image(tmp_path / "cut.png", check_header=refuse)
    assert seen == [(40, 24, 3)]
    with pytest.raises(ValueError, match="not a readable image"):  # the control: decoded, it fails
        io.read_image(tmp_path / "cut.png", check_header=seen.append)
    np.save(tmp_path / "a.npy", np.zeros((5, 6, 2), np.float32))
    io.read_image(tmp_path / "a.npy", check_header=seen.append)
    assert seen[-1] == (5, 6, 2)
