"""``spectex export`` and ``spectex.export.export``: formats, the folder written all or nothing,
one-line errors with exit status 2."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

import spectex.export as ex
from helpers import make_test_tile
from spectex.cli import main
from spectex.export import FORMATS, ExportResult, export, parse_formats
from spectex.export._folder import MANIFEST
from spectex.texture import SpectralTexture


@pytest.fixture(scope="module")
def texture():
    return SpectralTexture.paper_preset(tile=make_test_tile(32, 0))


@pytest.fixture(scope="module")
def texture_file(tmp_path_factory, texture):
    return texture.save(tmp_path_factory.mktemp("tex") / "ground.toml")


def snapshot(folder: Path) -> dict:
    """Every file under ``folder`` (hidden ones too) and its bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_formats_are_the_six_targets():
    assert FORMATS == ("web", "glsl", "godot", "materialx", "hlsl", "blender")


@pytest.mark.parametrize("value, expected", [
    (None, FORMATS),
    ("web", ("web",)),
    ("materialx, web", ("web", "materialx")),
    (["materialx", "web", "web"], ("web", "materialx")),
])
def test_parse_formats(value, expected):
    assert parse_formats(value) == expected


@pytest.mark.parametrize("value, error", [
    ("", ValueError), ("web,", ValueError), ("png", ValueError), ([], ValueError), (["web", 3], ValueError),
    (3, TypeError),
])
def test_parse_formats_refuses(value, error):
    with pytest.raises(error, match="format"):
        parse_formats(value)


def test_export_writes_every_format_and_a_manifest(tmp_path, texture):
    result = export(texture, tmp_path / "out")
    assert isinstance(result, ExportResult) and result.folder == tmp_path / "out"
    assert result.formats == FORMATS
    written = {p for files in result.files.values() for p in files}
    assert all(p.is_file() and p.stat().st_size > 0 for p in written)
    assert (tmp_path / "out" / "index.html") in written
    manifest = json.loads((tmp_path / "out" / MANIFEST).read_text())
    assert list(manifest["formats"]) == list(FORMATS)
    on_disk = {p for p in (tmp_path / "out").rglob("*") if p.is_file()}
    assert on_disk == written | {tmp_path / "out" / MANIFEST}
    assert not [p for p in tmp_path.iterdir() if p.name != "out"]  # no staging folder left
    assert oct((tmp_path / "out").stat().st_mode & 0o777) == oct(0o777 & ~_umask())


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_export_replaces_an_earlier_export(tmp_path, texture):
    export(texture, tmp_path / "out")
    result = export(texture, tmp_path / "out", formats="web")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["index.html", MANIFEST]
    assert result.formats == ("web",)
    assert not [p for p in tmp_path.iterdir() if p.name != "out"]


def test_export_into_an_empty_folder(tmp_path, texture):
    (tmp_path / "out").mkdir()
    export(texture, tmp_path / "out", formats=["web"])
    assert (tmp_path / "out" / "index.html").is_file()


def test_export_refuses_an_earlier_export_with_files_added(tmp_path, texture):
    export(texture, tmp_path / "out", formats="web,godot")
    (tmp_path / "out" / "godot" / "my_scene.tscn").write_text("mine")
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match="godot/my_scene.tscn"):
        export(texture, tmp_path / "out", formats="web")
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("make, message", [
    (lambda p: (p / "out").mkdir() or (p / "out" / "mine.txt").write_text("keep"), "not written by spectex export"),
    (lambda p: (p / "out").write_text("a file"), "not a folder"),
    (lambda p: None, "does not exist"),
])
def test_export_refuses_folders_it_must_not_touch(tmp_path, texture, make, message):
    make(tmp_path)
    target = tmp_path / "out" if message != "does not exist" else tmp_path / "missing" / "out"
    before = snapshot(tmp_path)
    with pytest.raises(ValueError, match=message):
        export(texture, target, formats="web")
    assert snapshot(tmp_path) == before


def test_export_refuses_a_non_texture(tmp_path):
    with pytest.raises(TypeError, match="texture must be a SpectralTexture"):
        export("ground.toml", tmp_path / "out")
    assert not list(tmp_path.iterdir())


def test_a_failing_writer_leaves_nothing_new(tmp_path, texture, monkeypatch):
    import spectex.export.materialx as mtlx

    def broken(texture, folder):
        (folder / "materialx").mkdir()
        (folder / "materialx" / "half.mtlx").write_text("<materialx")
        raise OSError("disk full (simulated)")

    monkeypatch.setattr(mtlx, "write_materialx", broken)
    with pytest.raises(OSError, match="simulated"):
        export(texture, tmp_path / "out", formats="web,materialx")
    assert not list(tmp_path.iterdir())
    # and an earlier export stays as it was
    monkeypatch.undo()
    export(texture, tmp_path / "out", formats="web")
    before = snapshot(tmp_path)
    monkeypatch.setattr(mtlx, "write_materialx", broken)
    with pytest.raises(OSError, match="simulated"):
        export(texture, tmp_path / "out", formats="materialx")
    assert snapshot(tmp_path) == before


def test_an_interrupt_leaves_the_earlier_export(tmp_path, texture, monkeypatch):
    """Ctrl-C (or SIGTERM, raised the same way) while writing: no stage left, the earlier export intact."""
    import spectex.export.materialx as mtlx

    export(texture, tmp_path / "out", formats="web")
    before = snapshot(tmp_path)

    def interrupted(texture, folder):
        (folder / "materialx").mkdir()
        raise KeyboardInterrupt

    monkeypatch.setattr(mtlx, "write_materialx", interrupted)
    with pytest.raises(KeyboardInterrupt):
        export(texture, tmp_path / "out", formats="web,materialx")
    assert snapshot(tmp_path) == before and sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_export_refuses_to_replace_a_folder_holding_an_input(tmp_path, texture):
    """An earlier export whose tile a command has read (an input of the session) is not replaced."""
    from spectex._output import note_input, session

    export(texture, tmp_path / "out", formats="godot")
    before = snapshot(tmp_path)
    with session():
        note_input(tmp_path / "out" / "godot" / "tile.png")
        with pytest.raises(ValueError, match="holds the input .*tile.png"):
            export(texture, tmp_path / "out", formats="godot")
    assert snapshot(tmp_path) == before
    export(texture, tmp_path / "out", formats="godot")  # control: outside that session it is replaced


# ------------------------------------------------------------------------------------- CLI
def run_cli(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_export_all(tmp_path, texture_file, capsys):
    code, out, err = run_cli(["export", str(texture_file), "-o", str(tmp_path / "out")], capsys)
    assert code == 0, err
    assert "wrote" in out and "index.html" in out
    manifest = json.loads((tmp_path / "out" / MANIFEST).read_text())
    assert list(manifest["formats"]) == list(FORMATS)


def test_cli_export_one_format(tmp_path, texture_file, capsys):
    code, out, err = run_cli(["export", str(texture_file), "-o", str(tmp_path / "out"), "--format", "materialx"],
                             capsys)
    assert code == 0, err
    assert not (tmp_path / "out" / "index.html").exists()
    assert (tmp_path / "out" / "materialx" / "spectex_ground.mtlx").is_file()


@pytest.mark.parametrize("args, fragment", [
    (["--format", "png"], "unknown format 'png'"),
    (["--format", ""], "formats must name"),
    ([], "the following arguments are required: -o/--output"),
    (["-o", "{tmp}/no/such/folder"], "does not exist"),
    (["-o", "{tmp}/taken"], "not written by spectex export"),
    (["-o", "{tmp}/afile"], "not a folder"),
    (["--texture-is", "{tmp}/missing.toml"], "texture file not found"),
    (["--texture-is", "{tmp}/broken.toml"], "not valid TOML"),
])
def test_cli_export_errors_are_one_line_exit_2_and_write_nothing(tmp_path, texture_file, capsys, args, fragment):
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "notes.txt").write_text("mine")
    (tmp_path / "afile").write_text("a file")
    (tmp_path / "broken.toml").write_text("format = [")
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    source = str(texture_file)
    if args[:1] == ["--texture-is"]:
        source, args = args[1], []
    if "-o" not in args and "--output" not in args and fragment != "the following arguments are required: -o/--output":
        args = args + ["-o", str(tmp_path / "out")]
    before = snapshot(tmp_path)
    texture_before = Path(texture_file).read_bytes()
    code, out, err = run_cli(["export", source, *args], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "error" in lines[0] and fragment in lines[0], err
    assert "Traceback" not in err
    assert snapshot(tmp_path) == before
    assert Path(texture_file).read_bytes() == texture_before


def test_cli_help_names_every_format(capsys):
    code, out, _ = run_cli(["export", "--help"], capsys)
    assert code == 0
    for name in FORMATS:
        assert name in out


def test_package_imports_only_the_standard_library_at_top():
    import subprocess

    code = ("import sys; import spectex.export; "
            "heavy = [m for m in ('numpy', 'numba', 'PIL', 'MaterialX', 'playwright') if m in sys.modules]; "
            "print(','.join(heavy))")
    env = dict(os.environ, PYTHONPATH=str(Path(ex.__file__).parents[2]))
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert run.returncode == 0 and run.stdout.strip() == "", run.stdout + run.stderr
