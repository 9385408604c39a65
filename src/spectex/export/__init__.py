"""Take a spectral texture to engines and the web: ``spectex export``.

One folder per export, every format in it written from the same texture:

=============  ==========================================================
``web``        ``index.html``: a self-contained WebGL2 fly-over viewer
``glsl``       ``glsl/``: the layer sampler and a ground-plane example, GLSL ES 3.00 and 3.30
``godot``      ``godot/``: a Godot 4 spatial shader, its tile, a camera-anchor script
``materialx``  ``materialx/``: a MaterialX 1.39 document of standard nodes, and its tile
``hlsl``       ``hlsl/``: an include for Unity Shader Graph and Unreal custom nodes
``blender``    ``blender/``: a script that builds the material in Blender, its tile(s)
=============  ==========================================================

Every shader is the renderer's own text (:mod:`spectex.export._shader`),
with the first lines each target needs. ``docs/export.md`` says what matches
spectex exactly in each target and what differs. :mod:`spectex.export.host`
draws a ``glsl/`` export from its files alone with moderngl, the way its
README tells any OpenGL program to.

The folder is written all or nothing: into a temporary folder beside it,
moved into place when complete (:class:`spectex._output.OutputFolder`, with
the export's rule for replacing an earlier export in
:mod:`spectex.export._folder`).
"""

from __future__ import annotations

import importlib
import json
from dataclasses import dataclass
from pathlib import Path

from ._folder import check_output_dir

__all__ = ["FORMATS", "ExportResult", "check_output_dir", "export", "parse_formats"]

#: Export formats, in the order they are written; each is ``module.write_<name>(texture, folder)``.
FORMATS = ("web", "glsl", "godot", "materialx", "hlsl", "blender")


@dataclass(frozen=True)
class ExportResult:
    """What :func:`export` wrote.

    Attributes
    ----------
    folder : Path
        The export folder.
    files : dict
        Per format, the files it wrote (paths inside ``folder``).
    """

    folder: Path
    files: dict

    @property
    def formats(self) -> tuple[str, ...]:
        return tuple(self.files)


def parse_formats(formats) -> tuple[str, ...]:
    """Check a format list (names, or one comma-separated string); ``None`` means all.

    Returns the formats in :data:`FORMATS` order, each once.
    """
    if formats is None:
        return FORMATS
    if isinstance(formats, str):
        names = [part.strip() for part in formats.split(",")]
    else:
        try:
            names = list(formats)
        except TypeError:
            raise TypeError(f"formats must be a list of names or a comma-separated string, got "
                            f"{type(formats).__name__}") from None
    if not names or any(not isinstance(n, str) or not n for n in names):
        raise ValueError(f"formats must name at least one of {', '.join(FORMATS)}, got {formats!r}")
    unknown = [n for n in names if n not in FORMATS]
    if unknown:
        raise ValueError(f"formats: unknown format {unknown[0]!r} (known: {', '.join(FORMATS)})")
    return tuple(f for f in FORMATS if f in names)


def export(texture, output, *, formats=None) -> ExportResult:
    """Write ``texture`` for engines and the web into the folder ``output``.

    Parameters
    ----------
    texture : SpectralTexture
    output : str or Path
        The export folder. Its parent must exist; the folder itself must not
        exist, or be empty, or hold an earlier export (which it replaces).
    formats : sequence of str or str, optional
        Any of :data:`FORMATS` (a list, or one comma-separated string);
        all by default.

    Returns
    -------
    ExportResult
        The folder and, per format, the files written.

    Raises
    ------
    ValueError, TypeError
        For a bad texture, format list or folder; nothing is written then,
        and a failure while writing leaves ``output`` as it was.
    """
    from spectex.texture import SpectralTexture

    from .._version import __version__
    from ._folder import MANIFEST, file_hashes, output_folder

    if not isinstance(texture, SpectralTexture):
        raise TypeError(f"texture must be a SpectralTexture, got {type(texture).__name__}")
    names = parse_formats(formats)
    folder = output_folder(output)
    output = folder.path
    written = {}
    with folder as tmp:
        for name in names:
            module = importlib.import_module(f"spectex.export.{name}")
            paths = getattr(module, f"write_{name}")(texture, tmp)
            written[name] = [Path(p).relative_to(tmp) for p in paths]
        manifest = {
            "generator": f"spectex {__version__}",
            "texture": repr(texture),
            "formats": {name: [p.as_posix() for p in paths] for name, paths in written.items()},
            # what a later export checks before it replaces this folder: only files it wrote, unchanged
            "sha256": file_hashes(tmp),
        }
        (tmp / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    return ExportResult(folder=output, files={name: [output / p for p in paths] for name, paths in written.items()})
