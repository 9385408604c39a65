"""The spectral texture file format: a TOML document and its tile PNGs.

A texture file (``ground.toml``) names its tiles (PNG files beside it) and
lists its layers, finest first::

    format = "spectex.spectral-texture"
    version = 2
    bits = 8
    tiles = ["ground.tile.png"]

    [[layers]]
    tile = 0
    size = 15.625            # metres per repeat of the tile
    offset = [0.0, 0.0]      # metres
    rotation = 0.0           # degrees, counter-clockwise
    blend = "alpha"          # alpha | detail | variance | fine | cover
    opacity = 1.0
    tiling = "stochastic"    # periodic | stochastic (version 2)
    patch = 0.5              # stochastic: triangle side in tiles
    seed = 0                 # stochastic: the grid vertices' random offsets
    snap = [7, 4]            # stochastic, optional: whole structure periods in the tile (0: off)

    [stochastic]             # only with stochastic layers: how their tables are rebuilt
    method = "histogram-preserving"
    gauss_scale = 0.1
    lut_size = 1024

:func:`save` writes it with ``tomli-w`` (the tiles as 8-bit RGBA PNGs for
``bits = 8``, 16-bit for float tiles), :func:`load` reads and checks every
field; an error names the field and the file.

Version 2 adds the layer fields ``tiling``, ``patch`` and ``seed`` and the
``[stochastic]`` table; ``snap`` (``Layer.snap``, written only where it is
not ``[0, 0]``) came later in version 2: a file with it is refused by a
spectex without it ("unknown field"), never shown with its patches unsnapped.
A stochastic layer's tables (the Gaussianised tile, the inverse look-up tables,
the decorrelation: ``spectex.shading.stochastic``) are a deterministic
function of the tile's texels and of the constants in ``[stochastic]``, so
the file stores those, not the tables; a file whose constants this spectex
does not build with is refused rather than shown differently. Version-1 files (no stochastic layers) still load.
"""

from __future__ import annotations

import numbers
import re
import tomllib
from pathlib import Path

import numpy as np

from ._validate import _show, check_relative_name
from .shading.constants import MAX_LAYERS, MAX_TILES

__all__ = ["FORMAT", "FORMAT_VERSION", "READ_VERSIONS", "save", "load", "check", "to_dict", "from_dict", "dumps",
           "named_files"]

#: File format name and version written to and required in texture files.
FORMAT = "spectex.spectral-texture"
FORMAT_VERSION = 2
#: Versions :func:`load` reads.
READ_VERSIONS = (1, 2)
#: The largest texture file :func:`load` reads (bytes), and the deepest nesting of brackets in it: a
#: texture of the most layers is about 2 kB and nests 2 deep, so these only stop hostile files early.
MAX_FILE_BYTES = 1 << 20
MAX_NESTING = 16

_HEADER = """# spectex spectral texture: layers of one tile at different scales.
# Layers are drawn in order (finest first); each later one is blended over the
# ones before by its 'blend': alpha | detail | variance | fine | cover, with alpha = opacity * tile alpha.
# size and offset are metres, rotation degrees counter-clockwise. tiling: periodic (the
# tile repeats) | stochastic (never repeats; patch: triangle side in tiles, seed: the random
# offsets, snap: [nx, ny] whole structure periods in the tile, offsets snapped to them, 0 off).
# Tiles are relative to this file.
"""

_LAYER_FIELDS = ("tile", "size", "offset", "rotation", "blend", "opacity")
_LAYER_FIELDS_V2 = _LAYER_FIELDS + ("tiling", "patch", "seed", "snap")
#: The method name of the stochastic tables this spectex builds (``[stochastic] method``).
STOCHASTIC_METHOD = "histogram-preserving"


def _stochastic_doc() -> dict:
    from .shading.constants import GAUSS_SCALE, LUT_SIZE

    return {"method": STOCHASTIC_METHOD, "gauss_scale": GAUSS_SCALE, "lut_size": LUT_SIZE}


def to_dict(texture, tile_names) -> dict:
    """The document of ``texture`` whose tiles are saved as ``tile_names``."""
    from .shading.constants import DEFAULT_PATCH

    layers = []
    for layer in texture.layers:
        entry = {"tile": layer.tile, "size": layer.size, "offset": list(layer.offset),
                 "rotation": layer.rotation, "blend": layer.blend, "opacity": layer.opacity,
                 "tiling": layer.tiling}
        # patch and seed only matter to stochastic layers; kept wherever they are set, so that a
        # texture reads back equal to itself
        if layer.tiling == "stochastic" or layer.patch != DEFAULT_PATCH:
            entry["patch"] = layer.patch
        if layer.tiling == "stochastic" or layer.seed != 0:
            entry["seed"] = layer.seed
        if layer.snap != (0, 0):
            entry["snap"] = list(layer.snap)
        layers.append(entry)
    doc = {
        "format": FORMAT,
        "version": FORMAT_VERSION,
        "bits": 8 if texture.bits == 8 else 32,
        "tiles": list(tile_names),
        "layers": layers,
    }
    if any(layer.tiling == "stochastic" for layer in texture.layers):
        doc["stochastic"] = _stochastic_doc()
    return doc


def dumps(doc: dict) -> str:
    """The document as TOML text (``tomli-w``), after a comment header."""
    import tomli_w

    return _HEADER + tomli_w.dumps(doc)


def tile_names(path: Path, n_tiles: int) -> list[str]:
    """The tile file names beside ``path``: ``ground.tile.png``, or ``ground.tile0.png``, ... for several."""
    if n_tiles == 1:
        return [f"{path.stem}.tile.png"]
    return [f"{path.stem}.tile{i}.png" for i in range(n_tiles)]


def save(texture, path) -> Path:
    """Write the texture file (TOML) and its tile PNG(s) beside it, atomically.

    ``ground.toml`` gets ``ground.tile.png`` (or ``ground.tile0.png``,
    ``ground.tile1.png``, ... for several tiles): 8-bit RGBA PNGs for
    ``bits=8``, 16-bit for float tiles. The files replace earlier ones
    only when all are complete: if anything fails, the folder is left as
    it was.

    Returns
    -------
    Path
        The texture file.
    """
    from ._output import OutputSet
    from .io import check_output_path, write_image

    path = check_output_path("output", path, (".toml",))
    names = tile_names(path, len(texture.tiles))
    text = dumps(to_dict(texture, names))
    # the tiles and the texture file replace the earlier ones together, or not at all
    with OutputSet(path.parent, names + [path.name], create=False) as stage:
        for name, tile in zip(names, texture.tiles):
            write_image(stage / name, tile, bit_depth=8 if texture.bits == 8 else 16)
        (stage / path.name).write_text(text, encoding="utf-8")
    return path


def load(path, *, texture_type):
    """Read a texture file written by :func:`save` (or by hand) as a ``texture_type``.

    Every field is checked; an error names the field and the file.
    ``texture_type`` is :class:`spectex.texture.SpectralTexture` (whose
    ``load`` calls this); this module knows the format, not the class, so
    that the import runs one way only (``texture`` -> ``texture_file``).
    """
    path, doc = _read_document(path)
    try:
        return from_dict(doc, base=path.parent, texture_type=texture_type)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"texture file '{path}': {exc}") from None


def check(path) -> None:
    """Check a texture file as :func:`load` does, up to reading its tiles: its size, its TOML, every
    field and the tile names (relative, inside its folder); the same errors. For a command that
    refuses a bad file before it imports what the work needs (``spectex bake``: dask and zarr)."""
    path, doc = _read_document(path)
    try:
        _checked_fields(doc)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"texture file '{path}': {exc}") from None


def _read_document(path):
    """``(path, doc)``: the texture file checked as an input, read (at most its limit) and parsed."""
    from ._output import check_input_file, note_input

    path = check_input_file("texture", path)
    note_input(path)  # no output of this command may replace it
    with open(path, "rb") as fh:  # read at most one byte over the limit, whatever the file's claimed size
        data = fh.read(MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES:
        raise ValueError(f"texture file '{path}' is over the limit of {MAX_FILE_BYTES} bytes "
                         f"(a texture of {MAX_LAYERS} layers takes about 2 kB)")
    try:
        text = data.decode("utf-8")
        _check_nesting(text, path)
        return path, tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"texture file '{path}' is not valid TOML: {exc}") from None
    except RecursionError:  # a nesting that _check_nesting could not see (inside an odd string): same answer
        raise ValueError(f"texture file '{path}' nests arrays or tables deeper than {MAX_NESTING}") from None


def named_files(path) -> list[Path]:
    """The texture file and the tile files it names, resolved, as far as the file can be read.

    For keeping outputs apart from inputs before anything is read in earnest:
    a file that cannot be read, or names no tiles, gives what it can (the
    loader says what is wrong with it).
    """
    inputs = [Path(path).resolve()]
    try:
        if Path(path).stat().st_size <= MAX_FILE_BYTES:  # larger: refused by the loader
            text = Path(path).read_text(encoding="utf-8")
            _check_nesting(text, path)
            doc = tomllib.loads(text)
            names = doc.get("tiles", []) if isinstance(doc, dict) else []
            names = names if isinstance(names, list) else []
            inputs += [(Path(path).parent / n).resolve() for n in names[:64] if isinstance(n, str)]
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, ValueError, RecursionError):
        pass  # the texture's own loader says what is wrong with it
    return inputs


def _check_nesting(text: str, path) -> None:
    """Refuse a document whose brackets nest deeper than :data:`MAX_NESTING` (before the recursive parser).

    Counts ``[``/``{`` against ``]``/``}`` outside quoted strings and comments;
    a texture file needs a depth of 2 (``offset = [0.0, 0.0]`` inside
    ``[[layers]]``).
    """
    depth = 0
    quote = None
    comment = False
    escaped = False
    for ch in text:
        if comment:
            comment = ch != "\n"
        elif quote is not None:
            if escaped:
                escaped = False
            elif ch == "\\" and quote == '"':
                escaped = True
            elif ch == quote or ch == "\n":
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            comment = True
        elif ch in "[{":
            depth += 1
            if depth > MAX_NESTING:
                raise ValueError(f"texture file '{path}' nests arrays or tables deeper than {MAX_NESTING}")
        elif ch in "]}":
            depth = max(depth - 1, 0)


def from_dict(doc: dict, *, base=".", texture_type):
    """A ``texture_type`` from the parsed file contents; tile paths are relative to ``base``.

    ``texture_type`` is :class:`spectex.texture.SpectralTexture`, made once
    from the tiles and the layers' tables (it makes and checks its layers;
    its errors are reworded here as the file's fields).
    """
    bits, names, layers = _checked_fields(doc)
    tiles = _read_tiles(names, base)
    try:
        return texture_type(tiles, layers, bits=8 if bits == 8 else None)
    except (ValueError, TypeError) as exc:
        raise ValueError(_field_error(str(exc))) from None


def _checked_fields(doc: dict):
    """``(bits, tile names, layer tables)`` of the parsed file, every field checked, the tile names
    relative to the file's folder; no tile read."""
    version = _check_header(doc)
    _check_stochastic_table(doc, version)
    bits = doc.get("bits", 8)
    if bits not in (8, 32) or isinstance(bits, bool):
        raise ValueError(f"field 'bits' must be 8 or 32, got {_show(bits)}")
    names = _check_tile_names(doc["tiles"])
    raw_layers = doc["layers"]
    if isinstance(raw_layers, list) and len(raw_layers) > MAX_LAYERS:  # before any tile is read
        raise ValueError(f"field 'layers' holds {len(raw_layers)} layers; a texture has at most {MAX_LAYERS}")
    layers = _layers_from_doc(doc, version)
    for i, name in enumerate(names):
        check_relative_name(f"field 'tiles[{i}]'", name)
    return bits, names, layers


_LAYER_ERROR = re.compile(r"(layers\[\d+\])(?:\.(\S+)|:) (.*)", re.S)


def _field_error(msg: str) -> str:
    """A texture's construction error as the file's field: ``layers[2].size must ...`` (the texture's
    wording) is ``field 'layers[2].size' must ...``; anything else is ``field ...``."""
    m = _LAYER_ERROR.fullmatch(msg)
    if m is None:
        return f"field {msg}"
    layer, field, rest = m.groups()
    return f"field '{layer}.{field}' {rest}" if field else f"field '{layer}' {rest}"


def _check_header(doc) -> int:
    """Check the document's fields, format and version; return the version."""
    if not isinstance(doc, dict):
        raise TypeError(f"texture must be a table, got {type(doc).__name__}")
    known = {"format", "version", "bits", "tiles", "layers", "stochastic"}
    extra = sorted(set(doc) - known)
    if extra:
        raise ValueError(f"unknown field {_show(extra[0])} (known: {', '.join(sorted(known))})")
    for key in ("format", "version", "tiles", "layers"):
        if key not in doc:
            raise ValueError(f"missing field '{key}'")
    if doc["format"] != FORMAT:
        raise ValueError(f"field 'format' must be {FORMAT!r}, got {_show(doc['format'])}")
    version = doc["version"]
    if not isinstance(version, int) or isinstance(version, bool):
        raise ValueError(f"field 'version' must be an integer, got {_show(version)}")
    if version not in READ_VERSIONS:
        raise ValueError(f"field 'version' is {version}; this spectex reads versions "
                         f"{', '.join(str(v) for v in READ_VERSIONS)}")
    return version


def _check_stochastic_table(doc, version) -> None:
    """The ``[stochastic]`` table, if there is one, must hold exactly the constants this spectex builds with."""
    if "stochastic" not in doc:
        return
    if version < 2:
        raise ValueError("unknown field 'stochastic' in a version-1 file")
    want = _stochastic_doc()
    got = doc["stochastic"]
    if not isinstance(got, dict):
        raise ValueError(f"field 'stochastic' must be a table, got {_show(got)}")
    for key in sorted(set(got) | set(want)):
        if key not in want:
            raise ValueError(f"unknown field 'stochastic.{key}' (known: {', '.join(sorted(want))})")
        if got.get(key) != want[key]:
            raise ValueError(f"field 'stochastic.{key}' is {_show(got.get(key))}; this spectex builds the "
                             f"stochastic tables with {want[key]!r}")


def _check_tile_names(names) -> list:
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise ValueError(f"field 'tiles' must be a non-empty list of file names, got {_show(names)}")
    if len(names) > MAX_TILES:
        raise ValueError(f"field 'tiles' names {len(names)} files; a texture has at most {MAX_TILES} tiles")
    return names


def _read_tiles(names, base) -> list[np.ndarray]:
    """The tile images named in the file, as RGB(A) (grey and grey-alpha widened)."""
    from .io import read_image

    tiles = []
    for i, name in enumerate(names):
        tile_path = Path(base) / check_relative_name(f"field 'tiles[{i}]'", name)
        try:
            tile = read_image(tile_path, name=f"tiles[{i}]")
        except ValueError as exc:
            raise ValueError(f"field 'tiles[{i}]': {exc}") from None
        if tile.ndim == 2:
            tile = np.repeat(tile[:, :, None], 3, axis=2)
        elif tile.shape[2] == 2:
            tile = np.concatenate([np.repeat(tile[:, :, :1], 3, axis=2), tile[:, :, 1:]], axis=2)
        tiles.append(tile)
    return tiles


def _layers_from_doc(doc, version) -> list[dict]:
    """The ``[[layers]]`` tables, their fields checked as the file holds them (known, numbers where numbers
    go); the texture checks their values when it makes its layers of them. An error names the layer and
    its field."""
    raw_layers = doc["layers"]
    if not isinstance(raw_layers, list) or not raw_layers:
        raise ValueError("field 'layers' must be a non-empty array of tables ([[layers]])")
    allowed = set(_LAYER_FIELDS if version == 1 else _LAYER_FIELDS_V2)
    for i, entry in enumerate(raw_layers):
        _check_layer_entry(i, entry, allowed, "stochastic" in doc)
    return raw_layers


def _check_layer_entry(i, entry, allowed, has_stochastic_table) -> None:
    if not isinstance(entry, dict):
        raise ValueError(f"field 'layers[{i}]' must be a table, got {_show(entry)}")
    extra = sorted(set(entry) - allowed)
    if extra:
        raise ValueError(f"unknown field 'layers[{i}].{extra[0]}' (known: {', '.join(sorted(allowed))})")
    if "size" not in entry:
        raise ValueError(f"missing field 'layers[{i}].size'")
    for key in ("size", "rotation", "opacity", "patch"):
        if key in entry and (isinstance(entry[key], bool) or not isinstance(entry[key], numbers.Real)):
            raise ValueError(f"field 'layers[{i}].{key}' must be a number, got {_show(entry[key])}")
    if entry.get("tiling") == "stochastic" and not has_stochastic_table:
        raise ValueError(f"field 'layers[{i}].tiling' is 'stochastic' but the file has no [stochastic] table")
