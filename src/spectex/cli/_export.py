"""``spectex export``: a spectral texture for engines and the web."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    from spectex.export import FORMATS  # the package's top imports only the standard library

    p = subparsers.add_parser(
        "export",
        help="write a spectral texture for the web, GLSL, Godot, MaterialX and HLSL engines",
        description=(
            "Write TEXTURE (a .toml) into the folder DIR for other software: web (index.html, a "
            "self-contained WebGL2 fly-over viewer that opens by double-click), glsl (GLSL ES 3.00 "
            "and 3.30 shaders, three.js notes), godot (a Godot 4 spatial shader), materialx (a "
            "MaterialX 1.39 document) and hlsl (an include for Unity Shader Graph and Unreal). "
            "DIR is written all or nothing; an existing DIR must be empty or an earlier export, "
            "which is replaced. See docs/export.md."
        ),
    )
    p.add_argument("texture", help="texture file (.toml)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="export folder")
    p.add_argument("--format", default=None, metavar="LIST",
                   help=f"comma-separated formats, any of {','.join(FORMATS)} (default: all)")
    p.set_defaults(func=run)


def run(args) -> int:
    from spectex.export import check_output_dir, export, parse_formats
    from spectex.texture import SpectralTexture

    # Everything is checked before anything is read or written.
    formats = parse_formats(args.format)
    output = check_output_dir("output", args.output)
    texture = SpectralTexture.load(args.texture)
    result = export(texture, output, formats=formats)
    count = sum(len(files) for files in result.files.values())
    _common.report(f"wrote {output} ({', '.join(result.formats)}: {count} file{'' if count == 1 else 's'})")
    if "web" in result.files:
        _common.report(f"open {(output / 'index.html').resolve().as_uri()} in a browser")
    return 0
